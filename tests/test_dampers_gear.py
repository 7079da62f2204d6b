"""Damper rods and a body on gear legs (issue 12): their matrices, against hand derivations.

Provenance of every reference value: derived by hand in the test from the geometry
(rod lengths, leg displacements, a rigid body's kinetic energy), in NumPy, with no
groundres code in the reference. Tolerances: 1e-12 relative where both sides are
a few products of the same numbers (round-off, ~1e-15, with margin); eigenvalues
of 6 x 6 or 14 x 14 problems 1e-9 relative (LAPACK's backward error times the
problems' condition, ~1e-12 here).
"""

import math
import tomllib
from dataclasses import replace

import numpy as np
import pytest
from click.testing import CliRunner

from conftest import HAMMOND_TOML
from groundres import analyze, load_case, parse_case
from groundres.cli import main
from groundres.model.body import Body, Leg
from groundres.model.dampers import Damper
from groundres.model.params import Rotor
from groundres.model.system import System

E = 0.3048  # [m] Hammond's hinge offset


def case_from(text):
    return parse_case(tomllib.loads(text), "test", text)


def lag_block(system, which=1):
    """The blades' lag block of the damping (1) or stiffness (2) matrix at azimuth 0."""
    n_body, n = system.n_body, system.n_blades
    return system.matrices(np.array([10.0]))[which, 0][n_body : n_body + n, n_body : n_body + n]


def rods_only(n_blades, **rod):
    """Hammond's blades without their own dampers, with one rod layout, on its hub."""
    base = load_case("hammond-1974")
    blades = tuple(replace(b, lag_damping=0.0) for b in base.rotor.blades[:1]) * n_blades
    rods = tuple(Damper(blade=k, **rod) for k in range(1, n_blades + 1))
    return System(Rotor(blades, dampers=rods), base.body)


def test_an_inter_blade_rod_gradient_equals_the_hand_derived_rod_length():
    """Points a outboard of each hinge on the span axes of blades delta apart:
    l = 2 (e + a) sin(delta/2) at rest; lagging blade k by zeta moves its point by
    a zeta against the rotation, so dl/dzeta_k = a cos(delta/2) and dl/dzeta_k+1 = -a cos(delta/2)."""
    for n, kind, j in ((4, "blade-to-blade", 1), (5, "blade-to-next-but-one", 2), (3, "blade-to-blade", 1)):
        a, c = 0.4, 1.0e4
        system = rods_only(n, kind=kind, damping=c, start_x=a, end_x=a)
        delta = 2 * math.pi * j / n
        g = a * math.cos(delta / 2)
        damper = system.rotor.dampers[0]
        assert damper.length([E] * n, n) == pytest.approx(2 * (E + a) * math.sin(delta / 2), rel=1e-14)
        hand = np.zeros((n, n))
        for k in range(n):
            m = (k + j) % n
            for p, gp in ((k, g), (m, -g)):
                for q, gq in ((k, g), (m, -g)):
                    hand[p, q] += c * gp * gq
        np.testing.assert_allclose(
            lag_block(system),
            lag_block(rods_only(n, kind=kind, damping=0.0, start_x=a, end_x=a)) + hand,
            rtol=1e-12,
            atol=1e-9 * c,
        )


@pytest.mark.parametrize("n, j", [(3, 1), (4, 1), (5, 2), (6, 2), (4, 2)])
def test_a_relative_lag_rod_leaves_collective_undamped_and_damps_cyclic_order_n_by_2_1_minus_cos(n, j):
    """Mirror-image attachments: the rods' lag damping block is circulant with eigenvalues
    2 (1 - cos(2 pi n j / N)) c g^2 on cyclic order n (0 on collective lag, n = 0)."""
    kind = {1: "blade-to-blade", 2: "blade-to-next-but-one"}[j]
    c = 2.0e4
    system = rods_only(n, kind=kind, damping=c, start_x=0.35, start_y=0.1, end_x=0.35, end_y=-0.1)
    g = system.rotor.dampers[0].gradient([E] * n, n)[0]
    rods = system.rod_matrices[0][system.n_body : system.n_body + n, system.n_body : system.n_body + n]
    for order in range(n):
        v = np.exp(2j * np.pi * order * np.arange(n) / n)  # (the circulant's eigenvectors)
        expected = 2 * (1 - math.cos(2 * math.pi * order * j / n)) * c * g * g
        np.testing.assert_allclose(rods @ v, expected * v, atol=1e-10 * c * g * g)
    # and in the roots: the collective lag mode keeps its undamped frequency Omega sqrt(e S / I)
    case = load_case("hammond-interblade")
    w = 20.0
    roots = analyze(case, speeds=[w], lag_damping_search=False).modes.eigenvalue[0]
    b = case.rotor.blades[0]
    nu_w = w * math.sqrt(b.hinge_offset * b.blade_static_moment / b.blade_inertia)
    assert np.min(np.abs(roots - 1j * nu_w)) < 1e-9 * nu_w


def test_a_rod_attached_at_different_distances_adds_a_small_collective_part():
    """Both blades lagging by zeta turn the rotor (no length change) and move each hinge
    sideways: the collective eigenvalue is c (g_a + g_b)^2, nonzero and small."""
    c, n = 2.0e4, 4
    system = rods_only(n, kind="blade-to-blade", damping=c, start_x=0.30, start_y=0.1, end_x=0.45, end_y=-0.1)
    g_a, _, g_b, _ = system.rotor.dampers[0].gradient([E] * n, n)
    rods = system.rod_matrices[0][system.n_body : system.n_body + n, system.n_body : system.n_body + n]
    collective = np.ones(n) @ rods @ np.ones(n) / n
    assert collective == pytest.approx(c * (g_a + g_b) ** 2, rel=1e-12)
    cyclic = (
        np.real(np.conj(np.exp(0.5j * np.pi * np.arange(n))) @ rods @ np.exp(0.5j * np.pi * np.arange(n))) / n
    )
    assert 0 < collective < 0.05 * cyclic


def test_blade_to_hub_rods_equal_the_rotational_lag_damper_keys():
    """A blade-to-hub rod of coefficient c and length gradient g is a rotational damper c g^2
    (and a rod spring k one of k g^2): the same equations as the old keys."""
    rod = dict(
        kind="blade-to-hub", damping=3.0e4, stiffness=2.0e5, start_x=0.5, start_y=0.15, end_x=0.2, end_y=0.6
    )
    with_rods = rods_only(4, **rod)
    g = with_rods.rotor.dampers[0].gradient([E] * 4, 4)[0]
    base = load_case("hammond-1974")
    blade = replace(base.rotor.blades[0], lag_damping=3.0e4 * g * g, lag_stiffness=2.0e5 * g * g)
    old = System(Rotor((blade,) * 4), base.body)
    speeds, psi = np.array([5.0, 20.0, 35.0]), np.array([[0.0], [0.9]])
    np.testing.assert_allclose(
        with_rods.matrices(speeds, psi), old.matrices(speeds, psi), rtol=1e-13, atol=1e-9
    )


def legs_at(positions, k=(1e5, 2e5, 3e5), c=(1e3, 2e3, 3e3)):
    return tuple(
        Leg(
            *p,
            stiffness_x=k[0],
            stiffness_y=k[1],
            stiffness_z=k[2],
            damping_x=c[0],
            damping_y=c[1],
            damping_z=c[2],
        )
        for p in positions
    )


def test_symmetric_legs_with_the_centre_of_mass_at_the_pivot_are_the_diagonal_modal_body():
    dofs = ("x", "y", "z", "pitch", "roll", "yaw")
    px, py = 1.2, 0.8
    legs = legs_at([(sx * px, sy * py, 0.0) for sx in (1, -1) for sy in (1, -1)])
    rigid = Body(
        dofs=dofs,
        mass=900.0,
        inertia_xx=400.0,
        inertia_yy=1500.0,
        inertia_zz=1300.0,
        hub_height=1.7,
        gear=legs,
    )
    kx, ky, kz = 4e5, 8e5, 12e5  # (four legs each)
    cx, cy, cz = 4e3, 8e3, 12e3
    modal = Body(
        dofs=dofs,
        mass_x=900.0, mass_y=900.0, mass_z=900.0,
        inertia_pitch=1500.0, inertia_roll=400.0, inertia_yaw=1300.0,
        stiffness_x=kx, stiffness_y=ky, stiffness_z=kz,
        stiffness_pitch=kz * px**2, stiffness_roll=kz * py**2, stiffness_yaw=kx * py**2 + ky * px**2,
        damping_x=cx, damping_y=cy, damping_z=cz,
        damping_pitch=cz * px**2, damping_roll=cz * py**2, damping_yaw=cx * py**2 + cy * px**2,
        hub_height=1.7,
    )  # fmt: skip
    np.testing.assert_allclose(rigid.matrices(), modal.matrices(), rtol=1e-14, atol=1e-9)
    rotor = load_case("hammond-1974").rotor
    speeds, psi = np.array([5.0, 20.0]), np.array([[0.0], [1.3]])
    np.testing.assert_allclose(
        System(rotor, rigid).matrices(speeds, psi),
        System(rotor, modal).matrices(speeds, psi),
        rtol=1e-14,
        atol=1e-9,
    )


def hand_rigid_body(m, j, centre, legs):
    """Mass and stiffness on (x, y, z, pitch, roll, yaw) by hand: in rotation-vector
    coordinates (t, r) a point p of the body moves by t + r x p, so
    T = 1/2 m |t' + r' x c|^2 + 1/2 r'.J r' and V = 1/2 sum_legs (t + r x p).diag(k)(t + r x p);
    pitch is -r_y, roll r_x, yaw r_z."""

    def cross(v):
        return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])

    def moved(p):  # displacement = A q, q in (t, r)
        return np.hstack([np.eye(3), -cross(p)])

    a = moved(centre)
    mass = m * a.T @ a
    mass[3:, 3:] += j
    stiffness = sum(moved(p).T @ np.diag(k) @ moved(p) for p, k in legs)
    to_ours = np.zeros((6, 6))  # q_rv = S q_ours
    to_ours[:3, :3] = np.eye(3)
    to_ours[3, 4] = 1.0  # r_x = roll
    to_ours[4, 3] = -1.0  # r_y = -pitch
    to_ours[5, 5] = 1.0  # r_z = yaw
    return to_ours.T @ mass @ to_ours, to_ours.T @ stiffness @ to_ours


def test_rigid_body_on_legs_has_the_frequencies_of_a_hand_built_six_dof_model():
    from scipy.linalg import eigh

    j = np.array([[600.0, -30.0, 45.0], [-30.0, 1900.0, 12.0], [45.0, 12.0, 1700.0]])
    centre = np.array([0.15, -0.05, 1.1])
    positions = [(1.3, 0.9, -0.2), (1.1, -1.0, -0.1), (-1.6, 0.8, 0.0), (-1.4, -0.9, 0.1), (0.2, 0.0, 0.5)]
    ks = [(1e5, 6e4, 3e5), (1.2e5, 5e4, 2.8e5), (9e4, 7e4, 3.2e5), (1e5, 5.5e4, 2.9e5), (2e4, 2e4, 0.0)]
    legs = tuple(Leg(*p, stiffness_x=k[0], stiffness_y=k[1], stiffness_z=k[2]) for p, k in zip(positions, ks))
    body = Body(
        dofs=("x", "y", "z", "pitch", "roll", "yaw"), mass=1200.0,
        inertia_xx=j[0, 0], inertia_yy=j[1, 1], inertia_zz=j[2, 2],
        inertia_xy=j[0, 1], inertia_xz=j[0, 2], inertia_yz=j[1, 2],
        centre_x=centre[0], centre_y=centre[1], centre_z=centre[2], hub_height=2.3, gear=legs,
    )  # fmt: skip
    mass, stiffness = hand_rigid_body(1200.0, j, centre, list(zip(positions, ks)))
    ours = body.matrices()
    np.testing.assert_allclose(ours[0], mass, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(ours[2], stiffness, rtol=1e-12, atol=1e-6)
    np.testing.assert_allclose(
        eigh(ours[2], ours[0], eigvals_only=True), eigh(stiffness, mass, eigvals_only=True), rtol=1e-9
    )


def test_heave_couples_with_coning_and_yaw_with_collective_lag():
    """Multiblade form of identical blades: z meets the coning (collective flap) through S,
    yaw meets collective lag through the blades' inertia about the shaft."""
    text = (
        HAMMOND_TOML.replace('dofs = ["x", "y"]', 'dofs = ["x", "y", "z", "yaw"]')
        .replace(
            "[body]", "[body]\nmass_z = 5000.0\nstiffness_z = 1e6\ninertia_yaw = 9000.0\nstiffness_yaw = 2e6"
        )
        .replace("lag_stiffness = 0.0", "lag_stiffness = 0.0\nflap = true\nflap_stiffness = 1e4")
    )
    system = System(*[getattr(case_from(text), k) for k in ("rotor", "body")])
    names = [f"{c.kind} {c.name}" for c in system.multiblade_coordinates()]
    m = system.multiblade(np.array([20.0]))[0, 0]
    blade = system.rotor.blades[0]
    assert m[names.index("body z"), names.index("flap 0")] == pytest.approx(
        4 * blade.blade_static_moment, rel=1e-12
    )
    shaft = blade.blade_inertia + blade.hinge_offset * blade.blade_static_moment
    assert abs(m[names.index("body yaw"), names.index("lag 0")]) == pytest.approx(4 * shaft, rel=1e-12)


def test_multiblade_eigenvalues_equal_floquet_exponents_for_rods_and_gear():
    """The time-invariant forms of the new cases against Floquet theory of the blade
    coordinates: largest real parts to 1e-8 1/s (the Floquet tolerance's)."""
    for name in ("hammond-interblade", "light-helicopter-skids"):
        case = load_case(name)
        speeds = np.linspace(case.sweep.stop * 0.1, case.sweep.stop, 7)
        eig = analyze(case, speeds=speeds, lag_damping_search=False)
        flq = analyze(case, speeds=speeds, method="floquet", lag_damping_search=False)
        assert eig.method == "multiblade-eigen" and flq.method == "floquet"
        np.testing.assert_allclose(flq.modes.real_part.max(-1), eig.modes.real_part.max(-1), atol=1e-8)


RIGID = """
[rotor]
blades = 3
hinge_offset = 0.25
blade_mass = 25.0
blade_static_moment = 60.0
blade_inertia = 200.0
lag_damping = 1000.0
[body]
dofs = ["x", "y", "pitch", "roll"]
mass = 1100.0
inertia_xx = 700.0
inertia_yy = 2500.0
hub_height = 2.5
[[body.gear]]
position_x = 1.0
position_y = 1.0
position_z = 0.0
stiffness_z = 2e5
stiffness_y = 5e4
stiffness_x = 1e5
[[body.gear]]
position_x = -1.0
position_y = -1.0
position_z = 0.0
stiffness_z = 2e5
stiffness_y = 5e4
stiffness_x = 1e5
[sweep]
start = 1.0
stop = 40.0
"""
ROD = '[[rotor.damper]]\nkind = "blade-to-blade"\ndamping = 2e4\n'
INTER = HAMMOND_TOML.replace(
    "[body]", ROD + "start_x = 0.3\nstart_y = 0.1\nend_x = 0.3\nend_y = -0.1\n\n[body]"
)
#: One leg, at the centre of mass: no stiffness against pitch or roll.
ONE_LEG = RIGID[: RIGID.index("[[body.gear]]")] + RIGID[RIGID.rindex("[[body.gear]]") :].replace(
    "position_x = -1.0\nposition_y = -1.0", "position_x = 0.0\nposition_y = 0.0"
)


@pytest.mark.parametrize(
    "text, words",
    [
        (
            INTER.replace("end_x = 0.3\nend_y = -0.1", "end_x = -0.2\nend_y = 0.1"),
            None,
        ),  # (valid: another rod)
        (
            INTER.replace(
                "start_x = 0.3\nstart_y = 0.1\nend_x = 0.3\nend_y = -0.1",
                "start_x = 0.0\nstart_y = 0.0\nend_x = 0.3048\nend_y = 0.0",
            )
            .replace("blades = 4", "blades = 2")
            .replace('"blade-to-blade"', '"blade-to-hub"'),
            ["coincide", "end_x"],
        ),
        (
            INTER.replace('kind = "blade-to-blade"', 'kind = "blade-to-blade"\nblade = 5'),
            ["blade = 5", "1 to 4"],
        ),
        (
            INTER.replace('"blade-to-blade"', '"blade-to-next-but-one"').replace("blades = 4", "blades = 2"),
            ["itself", "2 blades"],
        ),
        (INTER.replace('"blade-to-blade"', '"blade-to-bladee"'), ["kind", "blade-to-blade"]),
        (INTER.replace("damping = 2e4", "damping = -1.0"), ["damping", ">= 0"]),
        (ONE_LEG, ["dofs", "pitch"]),
        (INTER.replace("start_x = 0.3", "start_x = 1e155"), ["start_x", "1e+100"]),
        (RIGID.replace("hub_height = 2.5", "hub_height = 2.5\ncentre_z = -1e120"), ["centre_z", "1e+100"]),
        (
            load_case("hammond-1974-one-damper").text.replace("start = 30.0", "start = 1e-200"),
            ["too close to zero", "1e-100 rad/s"],
        ),
        (RIGID.replace("mass = 1100.0", "mass = 1100.0\nmass_x = 1100.0"), ["mass_x", "exclusive"]),
        (RIGID.replace("inertia_yy = 2500.0\n", ""), ["inertia_yy"]),
        (
            RIGID.replace("inertia_xx = 700.0", "inertia_xx = 700.0\ninertia_xy = 2000.0"),
            ["inertia_xx, inertia_yy, inertia_xy", "positive definite"],
        ),
        (RIGID.replace("inertia_yy = 2500.0", "inertia_yy = 0.0"), ["inertia_yy = 0.0", "pitch is in dofs"]),
        (RIGID.replace("position_z = 0.0\n", "", 1), ["position_z"]),
    ],
)
def test_bad_geometry_exits_2_naming_the_key(tmp_path, text, words):
    path = tmp_path / "case.toml"
    path.write_text(text)
    result = CliRunner().invoke(main, ["run", str(path), "--out", str(tmp_path / "out")])
    if words is None:
        assert result.exit_code == 0, result.output
        return
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output
    for word in words:
        assert word in result.output, (word, result.output)
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_a_time_simulation_grows_at_the_largest_floquet_exponent_with_a_failed_rod(tmp_path):
    """Simulation vs Floquet on the periodic inter-blade case (at its worst speed, 0.13 1/s): the
    default duration runs until the growing root outgrows the next by e^8 over the measured
    half, so the slope is the root's to well under 1 % (measured 0.006 %)."""
    import json

    out = tmp_path / "sim"
    result = CliRunner().invoke(
        main, ["simulate", "hammond-interblade-one-failed", "--speed", "256", "--out", str(out)]
    )
    assert result.exit_code == 0, result.output
    text = result.output.replace("\n", " ")
    measured = float(text.split("Measured growth rate ")[1].split()[0])
    predicted = float(text.split("largest real part (floquet) ")[1].split()[0])
    assert predicted > 0.1 and measured == pytest.approx(predicted, rel=0.01)
    assert json.loads((out / "provenance.json").read_text())["duration"]["value"] > 40 * 60 / 256


def test_rods_without_damping_leave_the_search_on_the_blade_dampers():
    """Stiffness-only rods on a rotor with blade dampers: the exact search sizes the blade dampers."""
    text = HAMMOND_TOML.replace(
        "[body]",
        ROD.replace("2e4", "0.0")
        + "stiffness = 1000.0\nstart_x = 0.3\nstart_y = 0.1\nend_x = 0.3\nend_y = -0.1\n\n[body]",
    )
    result = analyze(case_from(text))
    summary = result.summary()["lag_damping"]
    assert summary["exact_minimum_searched"] == "blade lag dampers"
    assert summary["exact_minimum_unit"] == "N m s/rad"
    assert 1000.0 < summary["exact_minimum"] < 4067.5  # (hub dampers: 2982.5 without the rods' springs)


def test_single_failures_of_different_kinds_are_not_shared():
    """Blade dampers and rods on one rotor: a blade's failure and a rod's are different rotors."""
    from groundres.studies.study import study

    text = load_case("hammond-interblade").text.replace("lag_damping = 0.0 ", "lag_damping = 3000.0 ")
    text = text.replace("points = 400", "points = 12").replace("start = 30.0", "start = 200.0")
    assert "lag_damping = 3000.0" in text
    ds = study(case_from(text), {"body.damping_x": [51078.7]}, failures="single")
    blade = float(ds.max_real_part.sel(failure="blade 1")[0])
    rod = float(ds.max_real_part.sel(failure="blade-to-blade rod 1")[0])
    assert blade != rod
    assert float(ds.max_real_part.sel(failure="blade 3")[0]) == blade  # (alike: the same rotor turned)


def test_rotating_phasors_keep_heave_and_yaw_and_heave_is_in_metres():
    from groundres.results.dataset import coordinate_unit

    text = HAMMOND_TOML.replace('dofs = ["x", "y"]', 'dofs = ["x", "y", "z", "yaw"]').replace(
        "[body]", "[body]\nmass_z = 5000.0\nstiffness_z = 1e6\ninertia_yaw = 9000.0\nstiffness_yaw = 2e6"
    )
    result = analyze(case_from(text), speeds=[20.0, 21.0], lag_damping_search=False)
    units = {c.name: coordinate_unit(c) for c in result.coordinates if c.kind == "body"}
    assert units == {"x": "m", "y": "m", "z": "m", "yaw": "rad"}
    rotating = {p.name for p in result.mode("body yaw", 20.0).phasors("rotating")}
    assert {"z", "yaw", "x_r", "y_r"} <= rotating


@pytest.mark.parametrize(
    "text, words",
    [
        (INTER.replace('kind = "blade-to-blade"', f'kind = "{"x" * 5000}"'), ["kind", "..."]),
        (INTER.replace("[body]", '[body]\n"bad\\nkey" = 1.0'), ["unknown key", "'bad\\nkey'"]),
        (INTER.replace("[body]", f"[body]\n{'k' * 5000} = 1.0"), ["unknown key", "..."]),
    ],
)
def test_long_or_multiline_names_in_messages_are_shortened_to_one_line(tmp_path, text, words):
    """A message stays one short line whatever the user typed: texts are shortened, newlines escaped."""
    path = tmp_path / "case.toml"
    path.write_text(text)
    result = CliRunner().invoke(main, ["run", str(path), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2
    message = result.output.strip()
    assert "\n" not in message and len(message) < 600, message[:200]
    for word in words:
        assert word in message
