"""The helicopter as a whole: body pitch and roll with flapping and lagging blades."""

import numpy as np
import pytest

from conftest import PITCH_ROLL, make_case
from groundres import analyze

N, M_BLADE, INERTIA, OFFSET = 4, 94.9, 1084.7, 0.3048


def test_without_blade_coupling_translation_frequencies_are_sqrt_k_over_m():
    """S = 0: the blades' mass moves with the hub but nothing couples; omega = sqrt(K / (M + N m))."""
    case = make_case(
        blade=dict(blade_static_moment=0.0), body=dict(damping_x=0.0, damping_y=0.0), sweep=(5.0, 40.0, 8)
    )
    result = analyze(case)
    f = dict(zip(result.labels, result.frequency.T))
    b = case.body
    np.testing.assert_allclose(f["body x"], np.sqrt(b.stiffness_x / (b.mass_x + N * M_BLADE)), rtol=1e-12)
    np.testing.assert_allclose(f["body y"], np.sqrt(b.stiffness_y / (b.mass_y + N * M_BLADE)), rtol=1e-12)


def test_without_blade_coupling_pitch_and_roll_are_a_gyroscopic_pair():
    """S = 0, no flap: pitch and roll with the rotor's inertia J_r = N (m h^2 + (I + m e^2)/2)
    and the rotor's angular momentum: (K_p - J_p w^2)(K_r - J_r w^2) = (G w)^2 with
    G = N Omega (I + m e^2) (at Omega = 0 simply sqrt(K/J))."""
    body = {**PITCH_ROLL, "damping_pitch": 0.0, "damping_roll": 0.0}
    case = make_case(
        dofs=("pitch", "roll"), body=body, blade=dict(blade_static_moment=0.0), sweep=(0.0, 30.0, 7)
    )
    result = analyze(case)
    h = PITCH_ROLL["hub_height"]
    j_rotor = N * (M_BLADE * h**2 + (INERTIA + M_BLADE * OFFSET**2) / 2)
    jp, jr = PITCH_ROLL["inertia_pitch"] + j_rotor, PITCH_ROLL["inertia_roll"] + j_rotor
    kp, kr = PITCH_ROLL["stiffness_pitch"], PITCH_ROLL["stiffness_roll"]
    for i, w in enumerate(result.rotor_speed):
        g = N * w * (INERTIA + M_BLADE * OFFSET**2)
        # in w^2: jp jr x^2 - (kp jr + kr jp + g^2) x + kp kr = 0
        x = np.roots([jp * jr, -(kp * jr + kr * jp + g**2), kp * kr])
        expected = np.sort(np.sqrt(x.real))
        got = np.sort([result.frequency[i, result.labels.index(k)] for k in ("body pitch", "body roll")])
        np.testing.assert_allclose(got, expected, rtol=1e-10)


def test_rigid_body_gives_rotating_blade_frequencies_seen_at_nu_omega_plus_minus_omega():
    """A body too stiff and heavy to move: coning nu_beta W, collective lag nu W, cyclic
    flap |nu_beta -+ 1| W, cyclic lag |1 -+ nu| W (Johnson 2013, multiblade coordinates)."""
    big = dict(
        inertia_pitch=1e12,
        inertia_roll=1e12,
        stiffness_pitch=1e16,
        stiffness_roll=1e16,
        damping_pitch=0.0,
        damping_roll=0.0,
        hub_height=1.5,
    )
    case = make_case(
        dofs=("pitch", "roll"),
        flap=True,
        body=big,
        sweep=(10.0, 40.0, 5),
        blade=dict(lag_stiffness=2e5, lag_damping=0.0, flap_stiffness=1e5),
    )
    result = analyze(case)
    w = result.rotor_speed
    blade = case.rotor.blades[0]
    nu, nb = blade.lag_frequency(w), blade.flap_frequency(w)
    f = dict(zip(result.labels, result.frequency.T))
    expected = {
        "coning": nb * w,
        "collective lag": nu * w,
        "differential lag": nu * w,
        "differential flap": nb * w,
        "regressive flap": np.abs(nb - 1) * w,
        "progressive flap": (nb + 1) * w,
        "regressive lag": np.abs(1 - nu) * w,
        "progressive lag": (1 + nu) * w,
    }
    for label, value in expected.items():
        np.testing.assert_allclose(f[label], value, rtol=1e-6, err_msg=label)


@pytest.mark.parametrize("name", ["stiff-inplane", "soft-inplane-damped"])
def test_stable_shipped_cases(name):
    from groundres import load_case

    result = analyze(load_case(name))
    assert result.stability.stable


def test_undamped_stable_modes_sit_at_zero():
    """No damping anywhere: outside any coalescence every root is neutral."""
    from groundres import load_case

    result = analyze(load_case("stiff-inplane"))
    assert np.abs(result.real_part).max() < 1e-9 * result.rotor_speed.max()


def test_soft_in_plane_has_one_unstable_range_and_damping_removes_it():
    from groundres import load_case

    soft = analyze(load_case("soft-inplane"))
    assert len(soft.stability.unstable_ranges) == 1
    damped = analyze(load_case("soft-inplane-damped"))
    assert damped.stability.stable
    installed = damped.case.rotor.blades[0].lag_damping
    assert damped.exact_lag_damping < installed
    pitch_roll = analyze(load_case("soft-inplane-pitch-roll"))
    # the ground-resonance range, and a narrow lag-flap coalescence below it
    # (between two grid points: see test_edges_numeric.py for its provenance)
    narrow, wide = pitch_roll.stability.unstable_ranges
    assert wide[0] > soft.rotor_speed[0]
    assert narrow[1] - narrow[0] < 0.02 and narrow[1] < wide[0]


def test_pitch_roll_floquet_equals_multiblade():
    case = make_case(
        dofs=("pitch", "roll"),
        flap=True,
        body=PITCH_ROLL,
        sweep=(4.0, 40.0, 40),
        blade=dict(lag_stiffness=1e5, flap_stiffness=5e4),
    )
    eigen = analyze(case)
    flq = analyze(case, method="floquet")
    np.testing.assert_allclose(flq.real_part, eigen.real_part, rtol=0, atol=1e-8)
    np.testing.assert_allclose(flq.frequency, eigen.frequency, rtol=1e-8, atol=1e-8)


def test_full_body_unstable_range_matches_between_methods():
    """x, y, pitch and roll at once, one damper out: Floquet; identical blades: multiblade."""
    body = {**PITCH_ROLL}
    case = make_case(
        dofs=("x", "y", "pitch", "roll"),
        flap=True,
        body=body,
        sweep=(5.0, 40.0, 60),
        blade=dict(lag_damping=500.0),
    )
    a = analyze(case)
    b = analyze(case, method="floquet")
    assert a.method == "multiblade-eigen"
    np.testing.assert_allclose(b.stability.unstable_ranges, a.stability.unstable_ranges, rtol=1e-7)


def test_the_hub_s_in_plane_motion_per_body_coordinate_is_the_derived_geometry_s():
    """The hub centre's in-plane displacement per unit body coordinate (what a cycle's hub
    frequency is read from) against a second route: the symbolic geometry the equations are derived
    from (:func:`groundres.symbolic.derive.blade_geometry`, hinge at the hub centre), differentiated
    at rest. Exact: both are the same linear map, up to round-off."""
    import sympy as sp

    from groundres.model.body import BODY_DOFS, Body
    from groundres.symbolic.derive import BLADE_SYMBOLS, COORDS, blade_geometry

    hinge, _, _ = blade_geometry()
    values = {"hub_height": 1.7, "hub_x": 0.3, "hub_y": -0.2, "hinge_offset": 0.0}
    subs = {BLADE_SYMBOLS[k]: v for k, v in values.items()}
    rest = dict.fromkeys(COORDS, 0)
    by_name = dict(zip(("x", "y", "z", "pitch", "roll", "yaw"), COORDS[:6]))
    unit = {f"mass_{d}": 1.0 for d in "xyz"} | {f"inertia_{d}": 1.0 for d in ("pitch", "roll", "yaw")}
    unit |= {f"stiffness_{d}": 1.0 for d in BODY_DOFS}
    body = Body(dofs=BODY_DOFS, **{k: values[k] for k in ("hub_height", "hub_x", "hub_y")}, **unit)
    got = body.hub_in_plane()
    for j, name in enumerate(body.dofs):
        for i in range(2):
            derived = sp.diff(hinge[i], by_name[name]).subs(rest).subs(subs)
            derived = float(sp.simplify(derived.subs(sp.Symbol("psi", real=True), 0)))
            assert got[i, j] == pytest.approx(derived, abs=1e-14), (name, i)
