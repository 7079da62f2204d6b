"""Pitt-Peters dynamic inflow in hover: a second route, closed forms, and every method alike.

The second route (:class:`InflowBlade`) extends the numeric blade of tests/test_aero.py
(NumPy rotations, Gauss quadrature, complex-step derivatives; no code shared with the
derivation): the air at each section gains ``v_0 + v_1 X/R + v_2 Y/R`` down the shaft, X and
Y the section's position forward and to the left of the hub centre in the body's axes, and
the blade's share of the inflow's forcing is its thrust ``int F . s`` and first moments
``int (X/R) F . s``, ``int (Y/R) F . s`` at the deflected positions.

Closed forms (docs/theory.md, "Dynamic inflow"): with rigid blades (no flap, no lag
motion) and no coning the inflow roots in hover are, per radian of azimuth,

    s_0 = -(4 lambda + sigma a (1 - x0^2) / 4) / M0,   s_1 = -(lambda + sigma a (1 - x0^4) / 16) / M1

(M0 = 128/(75 pi), M1 = 16/(45 pi), x0 the root cutout over the tip radius; the second a
double root), which with M0 gives the -(75 pi/32)(lambda + sigma a/16) of Chen and
Hindson (1986, NASA TM 88327) at x0 = 0.
"""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest

from groundres.errors import CaseError
from groundres.model.aero import Aero
from groundres.model.body import Body
from groundres.model.inflow import APPARENT_MASS
from groundres.model.params import Blade, Rotor
from groundres.model.schema import parse_case
from groundres.model.system import System
from groundres.symbolic.codegen import air_coefficients, air_values
from test_aero import CASE, NumericBlade, random_parameters, roots, span_moments


class InflowBlade(NumericBlade):
    """The numeric blade with the three inflow states (module docstring)."""

    def arms(self, q, radius):
        p = self.p
        body, _ = self.frames(q, self.psi)
        hub = np.array(q[:3]) + body @ np.array([p["hub_x"], p["hub_y"], p["hub_height"]])
        arm = self.point(q, self.psi, radius) - hub
        return arm @ body[:, 0] / p["tip_radius"], arm @ body[:, 1] / p["tip_radius"]

    def loads(self, q, qd, v):
        """Generalised forces on the eight coordinates, and the forcing (thrust, moments / R)."""
        p = self.p
        q, qd, v = (np.asarray(x, dtype=complex) for x in (q, qd, v))
        shaft = self.frames(q, self.psi)[0][:, 2]
        forces, forcing = np.zeros(8, dtype=complex), np.zeros(3, dtype=complex)
        for radius, weight in zip(self.radii, self.weights):
            fwd, left = self.arms(q, radius)
            inflow = p["inflow_ratio"] * self.speed * p["tip_radius"] + v[0] + v[1] * fwd + v[2] * left
            force = self.section_force(q, qd, radius, inflow)
            forces += weight * (self.partials(q, radius) @ force)
            along = force @ shaft
            forcing += weight * np.array([along, fwd * along, left * along])
        return forces, forcing

    def linearised(self, trim):
        """(damping, stiffness) of the 11 x 11 equations that the inflow adds (rows 8-10:
        minus the forcing), by complex steps."""
        q0 = np.array([0, 0, 0, 0, 0, 0, trim["trim_lag"], trim["coning"]], dtype=float)
        damping, stiffness = np.zeros((11, 11)), np.zeros((11, 11))
        h = 1e-30
        zero8, zero3 = np.zeros(8), np.zeros(3)
        for j in range(8):
            e = np.zeros(8)
            e[j] = h
            stiffness[8:, j] = self.loads(q0 + 1j * e, zero8, zero3)[1].imag / h
            damping[8:, j] = self.loads(q0, 1j * e, zero3)[1].imag / h
        for m in range(3):
            e = np.zeros(3)
            e[m] = h
            forces, forcing = self.loads(q0, zero8, 1j * e)
            damping[:8, 8 + m] = forces.imag / h
            damping[8:, 8 + m] = forcing.imag / h
        return -damping, -stiffness


def inflow_in_air(speed, p):
    """The generated inflow coupling at one speed: (2, 5, 11, 11)."""
    state = ("inflow_ratio", "coning", "trim_lag")
    coefficients = air_coefficients(
        "inflow_in_air", **{k: v for k, v in p.items() if k not in state}, **span_moments(p)
    )
    values = air_values("inflow_in_air", coefficients, np.array([speed]), *(np.array([p[k]]) for k in state))
    return values[..., 0]


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_inflow_coupling_equals_a_numeric_linearisation(seed):
    """The derived loads per unit inflow state and the blade's share of the inflow's forcing,
    against the second route at a random blade, trim, hub offset and azimuth."""
    rng = np.random.default_rng(seed)
    p = random_parameters(rng)
    speed, psi = rng.uniform(10, 40), rng.uniform(0, 2 * np.pi)
    weights = np.array([1, np.cos(psi), np.sin(psi), np.cos(2 * psi), np.sin(2 * psi)])
    damping, stiffness = np.einsum("h,ghij->gij", weights, inflow_in_air(speed, p))
    ref_c, ref_k = InflowBlade(p, speed, psi).linearised(p)
    assert np.abs(ref_k[8:, 6:8]).max() > 0 and np.abs(ref_c[8:, 8:]).max() > 0  # (not vacuous)
    for mine, ref in ((damping, ref_c), (stiffness, ref_k)):
        for rows in (slice(0, 8), slice(8, 11)):  # (forces and forcing have their own sizes)
            scale = np.abs(ref[rows]).max()
            np.testing.assert_allclose(mine[rows], ref[rows], rtol=0, atol=2e-8 * scale)
    # and only there: the 8 x 8 block is the blade in air's
    assert not damping[:8, :8].any() and not stiffness[:8, :8].any()


def rigid_case(**aero):
    data = tomllib.loads(CASE)
    data["rotor"].update(flap=False, lag_stiffness=1e13)
    data["body"].update(stiffness_pitch=1e15, stiffness_roll=1e15)  # (held: no body rates)
    data["aero"] = {"lift_slope": 5.7, "chord": 0.35, "tip_radius": 5.0, "air_density": 1.225, **aero}
    return parse_case(data)


@pytest.mark.parametrize("collective, cutout", [(8.0, 0.5), (0.0, 0.5), (12.0, 1.5)])
def test_inflow_roots_with_rigid_blades(collective, cutout):
    """Three of the roots are the closed forms (module docstring), to the coupling left by the stiff
    lag and body; at zero collective lambda = 0 (no division by it)."""
    case = rigid_case(collective=collective, root_cutout=cutout, inflow="dynamic")
    system = System.in_mass_unit(case.rotor, case.body)
    speeds = case.sweep.speeds
    lam = system.trim(speeds).inflow_ratio
    aero = case.rotor.aero
    sigma_a = aero.solidity(case.rotor.n_blades) * aero.lift_slope
    x0 = aero.root_cutout / aero.tip_radius
    s0 = -(4 * lam + sigma_a * (1 - x0**2) / 4) / APPARENT_MASS[0] * speeds
    s1 = -(lam + sigma_a * (1 - x0**4) / 16) / APPARENT_MASS[1] * speeds
    found = roots(case)
    assert found.shape[-1] == 2 * system.size - 3
    for expected in (s0, s1):
        near = np.abs(found - expected[:, None]).min(-1)
        np.testing.assert_array_less(near, 1e-7 * np.abs(expected))
    # the double root: two roots at s1
    assert ((np.abs(found - s1[:, None]) < 1e-6 * np.abs(s1[:, None])).sum(-1) == 2).all()
    if collective == 0.0:
        np.testing.assert_array_equal(lam, 0.0)


def test_dropping_the_inflow_positions_removes_only_zero_roots():
    """The full second-order system (the inflow states' positions kept) has the same roots and
    three more at zero: the positions are no motion."""
    from groundres.solve import modal

    data = tomllib.loads(CASE)
    data["aero"] = {"lift_slope": 5.7, "chord": 0.35, "tip_radius": 5.0, "air_density": 1.225}
    data["aero"].update(collective=8.0, inflow="dynamic", pitch_lag=-0.2)
    case = parse_case(data)
    system = System.in_mass_unit(case.rotor, case.body)
    m, c, k = system.multiblade(np.array([25.0]))
    full = np.sort_complex(np.linalg.eigvals(modal.state_matrix(m, c, k))[0])
    kept = np.linalg.eigvals(modal.state_matrix(m, c, k, system.integrals))[0]
    scale = np.abs(full).max()
    zeros = np.abs(full) < 1e-9 * scale
    assert zeros.sum() == 3
    np.testing.assert_allclose(np.sort_complex(kept), full[~zeros], rtol=0, atol=1e-9 * scale)


def test_a_whisper_of_air_is_the_vacuum_with_the_inflow_roots_beside_it():
    """Lock number 1e-9 with dynamic inflow: the vacuum's roots, and three inflow roots."""
    vacuum = roots(parse_case(tomllib.loads(CASE)))
    data = tomllib.loads(CASE)
    data["aero"] = {"lift_slope": 5.7, "chord": 0.35, "tip_radius": 5.0, "lock_number": 1e-9}
    data["aero"].update(collective=6.0, inflow="dynamic")
    whisper = roots(parse_case(data))
    assert whisper.shape[-1] == vacuum.shape[-1] + 3
    scale = np.abs(vacuum).max()
    for speed_roots, own in zip(whisper, vacuum):
        distance = np.abs(speed_roots[:, None] - own[None, :]).min(0)
        np.testing.assert_array_less(distance, 1e-6 * scale)


def test_dynamic_inflow_needs_air():
    data = tomllib.loads(CASE)
    data["aero"] = {"lift_slope": 5.7, "chord": 0.35, "tip_radius": 5.0, "air_density": 0.0}
    data["aero"]["inflow"] = "dynamic"
    with pytest.raises(CaseError, match="needs air"):
        parse_case(data)


def test_a_tilting_body_in_air_is_not_isotropic():
    """On an isotropic pitch-roll gimbal the rotor's torque along the tilted shaft couples roll
    to pitch only (the gimbal's axis order: roll outside, pitch inside), so no turn about the
    shaft leaves the equations alike: rotating axes are no time-invariant form in air, and
    dissimilar blades there go to Floquet analysis."""
    from groundres.methods import Method, choose_method

    blade = Blade(60.0, 132.0, 406.0, 0.5, lag_stiffness=21119.0, flap_stiffness=5074.0)
    body = Body(
        dofs=("pitch", "roll"),
        inertia_pitch=2000.0,
        inertia_roll=2000.0,
        stiffness_pitch=3e5,
        stiffness_roll=3e5,
        hub_height=1.5,
    )
    aero = Aero(1.225, 5.7, 0.35, 5.0, root_cutout=0.6, collective=0.14, drag_coefficient=0.01)
    system = System(Rotor((blade,) * 4, flap=True, aero=aero), body)
    _, _, k = system.multiblade(np.array([20.0]))[:, 0, :2, :2]
    torque = system.trim(np.array([20.0])).torque[0]
    assert k[0, 1] == 0.0 and k[1, 0] == pytest.approx(-torque, rel=1e-9)  # (roll row, pitch column)
    case_data = tomllib.loads(CASE)
    case_data["body"].update(inertia_roll=2500.0, stiffness_roll=379030.0)
    case_data["rotor"]["blade"] = [{"index": 1, "lag_damping": 100.0}]
    case_data["aero"] = {"lift_slope": 5.7, "chord": 0.35, "tip_radius": 5.0, "air_density": 1.225}
    assert choose_method(parse_case(case_data)) is Method.FLOQUET
    del case_data["aero"]
    assert choose_method(parse_case(case_data)) is Method.ROTATING


def test_the_inflow_modes_are_labelled_by_content():
    """The Coleman labels: uniform inflow (one real root) and cyclic inflow, beside the flap,
    lag and body modes, named alike by the eigen and the Floquet analyses."""
    from groundres.analysis import analyze

    data = tomllib.loads(CASE)
    data["aero"] = {"lift_slope": 5.7, "chord": 0.35, "tip_radius": 5.0, "air_density": 1.225}
    data["aero"].update(collective=8.0, inflow="dynamic")
    case = parse_case(data)
    eigen, floquet = analyze(case), analyze(case, method="floquet")
    assert "uniform inflow" in eigen.modes.labels and "cyclic inflow" in eigen.modes.labels
    assert eigen.modes.labels == floquet.modes.labels
    j = eigen.modes.labels.index("uniform inflow")
    assert (eigen.modes.energy[:, j, j] > 0.5).all()
    scale = np.abs(eigen.modes.real_part).max()
    np.testing.assert_allclose(floquet.modes.real_part, eigen.modes.real_part, rtol=0, atol=1e-8 * scale)
    assert math.isfinite(float(np.abs(eigen.modes.shape).max()))


@pytest.mark.parametrize(
    "inflow, blades, dofs",
    [
        ("uniform", "alike", ("pitch", "roll")),
        ("dynamic", "alike", ("pitch", "roll")),
        ("dynamic", "one", ("x", "y")),
    ],
)
def test_the_form_from_monomials_equals_the_assembled_one(inflow, blades, dofs):
    """groundres.model.airform: the time-invariant form summed over monomials of the trim state
    equals the one assembled from the blades' matrices, to round-off, over three bands of
    speeds (multiblade for identical blades; rotating axes for a dissimilar one on a body that
    only translates)."""
    from groundres.model.airform import AirForm

    blade = Blade(60.0, 132.0, 406.0, 0.5, lag_stiffness=21119.0, flap_stiffness=5074.0, lag_damping=300.0)
    other = Blade(64.0, 132.0, 420.0, 0.5, lag_stiffness=21119.0, flap_stiffness=5074.0, lag_damping=0.0)
    if dofs == ("x", "y"):
        body = Body(dofs=dofs, mass_x=2000.0, mass_y=2000.0, stiffness_x=1e6, stiffness_y=1e6, hub_height=1.2)
    else:
        body = Body(
            dofs=dofs, inertia_pitch=2000.0, inertia_roll=900.0, stiffness_pitch=3e5, stiffness_roll=2e5
        )
    aero = Aero(1.225, 5.7, 0.35, 5.0, root_cutout=0.6, collective=0.12, pitch_lag=-0.3, inflow=inflow)
    rotor = Rotor((blade,) * 3 + ((blade,) if blades == "alike" else (other,)), flap=True, aero=aero)
    system = System(rotor, body)
    transform = system.multiblade if blades == "alike" else system.rotating_axes
    form = AirForm(system, lambda w, h: transform(w, harmonics=h))
    speeds = np.array([0.0, 3.0, 11.0, 17.0, 40.0, 90.0])
    got, want = form(speeds), transform(speeds)
    scale = np.abs(want).max(axis=(2, 3), keepdims=True)
    assert (np.abs(got - want) <= 1e-13 * scale).all(), np.abs(got - want).max()


def test_labels_agree_between_methods_from_rest_with_dynamic_inflow():
    """A sweep from rest: the uniform inflow's one root is chosen at each speed by content, so
    the eigen and the Floquet analyses name every root alike, at rest too (where a cyclic
    pair's regressive and progressive halves are a matter of convention: their two
    frequencies are compared as a pair there)."""
    from groundres.analysis import analyze

    data = tomllib.loads(CASE)
    data["sweep"].update(start=0.0, points=8)
    data["aero"] = {"lift_slope": 5.7, "chord": 0.35, "tip_radius": 5.0, "air_density": 1.225}
    data["aero"].update(collective=8.0, inflow="dynamic")
    case = parse_case(data)
    eigen, floquet = analyze(case), analyze(case, method="floquet")
    assert eigen.modes.labels == floquet.modes.labels
    scale = np.abs(eigen.modes.eigenvalue).max()
    np.testing.assert_allclose(floquet.modes.real_part, eigen.modes.real_part, rtol=0, atol=1e-8 * scale)
    ours, theirs = floquet.modes.frequency_nonrotating, eigen.modes.frequency_nonrotating
    np.testing.assert_allclose(ours[1:], theirs[1:], rtol=0, atol=1e-8 * scale)
    labels = eigen.modes.labels
    for j, label in enumerate(labels):
        if label.startswith("regressive"):
            pair = [j, labels.index(label.replace("regressive", "progressive"))]
            np.testing.assert_allclose(np.sort(ours[0, pair]), np.sort(theirs[0, pair]), atol=1e-8 * scale)
        elif not label.startswith("progressive"):
            assert abs(ours[0, j] - theirs[0, j]) <= 1e-8 * scale, label


def test_rotating_axes_see_the_inflow_pair_from_nonrotating_axes():
    """Dissimilar blades (one lag damper failed) on a body that translates, with dynamic inflow:
    rotating axes (the inflow pair turned as velocities, then seen from nonrotating axes) give
    the Floquet analysis' labels, real parts and nonrotating frequencies."""
    from groundres.analysis import analyze

    data = tomllib.loads(CASE)
    data["body"] = {
        "dofs": ["x", "y"],
        "mass_x": 2000.0,
        "mass_y": 2000.0,
        "stiffness_x": 1e6,
        "stiffness_y": 1e6,
        "damping_x": 4e3,
        "damping_y": 4e3,
        "hub_height": 1.2,
    }
    data["rotor"].update(lag_damping=3000.0, blade=[{"index": 1, "lag_damping": 0.0}])
    data["sweep"].update(points=6)
    data["aero"] = {"lift_slope": 5.7, "chord": 0.35, "tip_radius": 5.0, "air_density": 1.225}
    data["aero"].update(collective=8.0, inflow="dynamic")
    case = parse_case(data)
    rotating, floquet = analyze(case), analyze(case, method="floquet")
    assert rotating.method.value == "rotating-eigen"
    assert rotating.modes.labels == floquet.modes.labels
    scale = np.abs(rotating.modes.eigenvalue).max()
    for what in ("real_part", "frequency_nonrotating"):
        np.testing.assert_allclose(
            getattr(floquet.modes, what), getattr(rotating.modes, what), rtol=0, atol=1e-7 * scale
        )


def test_roots_asked_at_rest_first_do_not_fix_the_coupling_blocks():
    """The multiblade solver finds its coupling blocks once; asked at rest first (where the
    couplings that grow with the speed vanish) it keeps none, so later speeds are right."""
    from groundres.solve.solvers import Multiblade

    data = tomllib.loads(CASE)
    data["aero"] = {"lift_slope": 5.7, "chord": 0.35, "tip_radius": 5.0, "air_density": 1.225}
    data["aero"].update(collective=8.0, inflow="dynamic")
    case = parse_case(data)
    system = System.in_mass_unit(case.rotor, case.body)
    first_at_rest = Multiblade(system)
    first_at_rest.roots(np.zeros(1))
    speeds = case.sweep.speeds[[3, 9]]
    fresh = np.sort_complex(Multiblade(system).roots(speeds))
    later = np.sort_complex(first_at_rest.roots(speeds))
    np.testing.assert_allclose(later, fresh, rtol=0, atol=1e-9 * np.abs(fresh).max())


def test_simulate_takes_inflow_rates_not_positions():
    from groundres.analysis import simulate
    from groundres.errors import ParameterError

    data = tomllib.loads(CASE)
    data["aero"] = {"lift_slope": 5.7, "chord": 0.35, "tip_radius": 5.0, "air_density": 1.225}
    data["aero"].update(collective=8.0, inflow="dynamic")
    case = parse_case(data)
    with pytest.raises(ParameterError, match="inflow_uniform_rate"):
        simulate(case, 20.0, initial={"inflow_uniform": 0.1})
    sim = simulate(case, 20.0, duration=2.0, initial={"inflow_forward_rate": 0.1, "lag1": 0.01})
    assert np.isfinite(sim.growth_rate())
