"""The rotor in air: the derived aerodynamic and trim matrices against a second route and closed forms.

The second route (:class:`NumericBlade`) is written here from the physics alone, in NumPy:
the section's position from rotation matrices, its velocity from a central difference of
the position in the coordinates and the azimuth, the strip-theory loads, Gauss-Legendre
quadrature over the span (exact: the integrand is a polynomial of low degree in the radius),
and the linearisation by complex-step derivatives. It shares no code with the symbolic
derivation (groundres.symbolic.aero) beyond the definitions in docs/theory.md.

Closed forms (hover, uniform inflow; Johnson, Rotorcraft Aeromechanics, 2013, chapters on
hover and flap dynamics, rederived in docs/theory.md): the isolated flapping blade's roots
s/Omega = -gamma J/4 +- i sqrt(nu_beta^2 + gamma K_Pbeta A1/2 - (gamma J/4)^2), the lag
damping of a blade with collective and profile drag, and the trim inflow of an untwisted rotor.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from groundres.errors import CaseError
from groundres.model.aero import Aero
from groundres.model.body import Body
from groundres.model.params import Blade, Rotor
from groundres.model.schema import parse_case
from groundres.model.system import System
from groundres.model.trim import solve_trim
from groundres.symbolic.codegen import air_coefficients, air_values, blade_function


def rot_x(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]], dtype=complex)


def rot_y(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]], dtype=complex)


def rot_z(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]], dtype=complex)


class NumericBlade:
    """One blade's aerodynamic generalised forces Q(q, q') by numbers alone (module docstring)."""

    def __init__(self, p: dict, speed: float, psi: float):
        self.p, self.speed, self.psi = p, speed, psi
        nodes, weights = np.polynomial.legendre.leggauss(12)
        low, high = p["root_cutout"], p["tip_radius"]
        self.radii = (high - low) / 2 * nodes + (high + low) / 2
        self.weights = (high - low) / 2 * weights

    def frames(self, q, psi):
        x, y, z, theta, phi, chi, zeta, beta = q
        body = rot_z(chi) @ rot_x(phi) @ rot_y(-theta)
        axes = body @ rot_z(psi) @ rot_z(-zeta) @ rot_y(-beta)
        return body, axes

    def point(self, q, psi, radius):
        p = self.p
        body, axes = self.frames(q, psi)
        hub = np.array([p["hub_x"], p["hub_y"], p["hub_height"]])
        hinge = np.array(q[:3]) + body @ hub + body @ rot_z(psi) @ np.array([p["hinge_offset"], 0, 0])
        return hinge + (radius - p["hinge_offset"]) * axes[:, 0]

    def velocity(self, q, qd, radius, h=1e-6):
        """dP/dt = sum dP/dq_i q'_i + Omega dP/dpsi, by central differences (fourth order)."""

        def d(f):
            return (8 * (f(h) - f(-h)) - (f(2 * h) - f(-2 * h))) / (12 * h)

        v = self.speed * d(lambda e: self.point(q, self.psi + e, radius))
        return v + d(lambda e: self.point(q + e * qd, self.psi, radius))

    def section_force(self, q, qd, radius, inflow):
        """The section's force (3,) per unit span, the air coming down the shaft at ``inflow`` [m/s]."""
        p = self.p
        body, axes = self.frames(q, self.psi)
        lead, normal = axes[:, 1], axes[:, 2]
        k_lift = p["air_density"] * p["chord"] * p["lift_slope"] / 2
        k_drag = p["air_density"] * p["chord"] * p["drag_coefficient"] / 2
        w = self.velocity(q, qd, radius) + inflow * body[:, 2]
        u_t, u_p = w @ lead, w @ normal
        theta = (
            p["collective"]
            + p["twist"] * radius / p["tip_radius"]
            - p["pitch_flap"] * q[7]
            - p["pitch_lag"] * q[6]
        )
        f_n = k_lift * (u_t**2 * theta - u_p * u_t)
        f_x = k_lift * (u_p * u_t * theta - u_p**2) + k_drag * u_t**2
        return f_n * normal - f_x * lead

    def partials(self, q, radius):
        """The partial velocities dP/dq_i of the section (8, 3), by central differences."""
        out = []
        for i in range(8):
            e = np.zeros(8)
            e[i] = 1e-6
            out.append((self.point(q + e, self.psi, radius) - self.point(q - e, self.psi, radius)) / 2e-6)
        return np.array(out)

    def forces(self, q, qd):
        """The generalised forces on the eight coordinates."""
        p = self.p
        q, qd = np.asarray(q, dtype=complex), np.asarray(qd, dtype=complex)
        inflow = p["inflow_ratio"] * self.speed * p["tip_radius"]
        return sum(
            weight * (self.partials(q, radius) @ self.section_force(q, qd, radius, inflow))
            for radius, weight in zip(self.radii, self.weights)
        )

    def linearised(self, trim):
        """(-dQ/dq, -dQ/dq') at the trim, by complex steps."""
        q0 = np.array([0, 0, 0, 0, 0, 0, trim["trim_lag"], trim["coning"]], dtype=float)
        stiffness, damping = np.zeros((8, 8)), np.zeros((8, 8))
        h = 1e-30
        for j in range(8):
            e = np.zeros(8)
            e[j] = 1.0
            stiffness[:, j] = -self.forces(q0 + 1j * h * e, np.zeros(8)).imag / h
            damping[:, j] = -self.forces(q0, 1j * h * e).imag / h
        return stiffness, damping


def random_parameters(rng):
    e = rng.uniform(0.1, 0.6)
    return dict(
        blade_mass=rng.uniform(20, 80),
        blade_static_moment=rng.uniform(50, 120),
        blade_inertia=rng.uniform(300, 600),
        hinge_offset=e,
        hub_height=rng.uniform(-2, 2),
        hub_x=rng.uniform(-0.5, 0.5),
        hub_y=rng.uniform(-0.5, 0.5),
        lag_stiffness=rng.uniform(0, 1e5),
        lag_damping=rng.uniform(0, 1e3),
        flap_stiffness=rng.uniform(0, 1e5),
        flap_damping=rng.uniform(0, 1e3),
        air_density=rng.uniform(0.8, 1.3),
        lift_slope=rng.uniform(5, 6.3),
        drag_coefficient=rng.uniform(0.005, 0.02),
        chord=rng.uniform(0.2, 0.5),
        tip_radius=rng.uniform(4, 6),
        root_cutout=e + rng.uniform(0, 0.5),
        collective=rng.uniform(-0.1, 0.2),
        twist=rng.uniform(-0.2, 0.05),
        pitch_flap=rng.uniform(-0.5, 0.5),
        pitch_lag=rng.uniform(-0.5, 0.5),
        inflow_ratio=rng.uniform(-0.02, 0.08),
        coning=rng.uniform(-0.1, 0.15),
        trim_lag=rng.uniform(-0.05, 0.1),
    )


def span_moments(p):
    low, high = p["root_cutout"] - p["hinge_offset"], p["tip_radius"] - p["hinge_offset"]
    return {f"span_moment_{k}": (high ** (k + 1) - low ** (k + 1)) / (k + 1) for k in range(5)}


def blade_in_air(speed, p):
    """The generated blade in air (its coefficients, then its monomials) at one speed: (3, 5, 8, 8, 1)."""
    state = ("inflow_ratio", "coning", "trim_lag")
    coefficients = air_coefficients(
        "blade_in_air", **{k: v for k, v in p.items() if k not in state}, **span_moments(p)
    )
    return air_values("blade_in_air", coefficients, np.array([speed]), *(np.array([p[k]]) for k in state))


def at_azimuth(harmonics, psi):
    weights = np.array([1, np.cos(psi), np.sin(psi), np.cos(2 * psi), np.sin(2 * psi)])
    return np.einsum("h,ghij->gij", weights, harmonics)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_air_matrices_equal_a_numeric_linearisation_of_the_section_loads(seed):
    """The symbolic aerodynamic stiffness and damping (the blade in air minus the same blade in
    no air, both about the same trim) against the second route, at a random blade, trim,
    coupling and azimuth; the body's six coordinates included (follower thrust, hub offsets)."""
    rng = np.random.default_rng(seed)
    p = random_parameters(rng)
    speed, psi = rng.uniform(10, 40), rng.uniform(0, 2 * np.pi)
    air = blade_in_air(speed, p)[..., 0]
    still = blade_in_air(speed, {**p, "air_density": 0.0})[..., 0]
    _, damping, stiffness = at_azimuth(air - still, psi)
    ref_k, ref_c = NumericBlade(p, speed, psi).linearised(p)
    for mine, ref in ((stiffness, ref_k), (damping, ref_c)):
        scale = np.abs(ref).max()
        np.testing.assert_allclose(mine, ref, rtol=0, atol=2e-8 * scale)


def test_no_air_about_zero_trim_is_the_vacuum_blade():
    """With no air and the trim at zero, the blade in air is the vacuum's blade (structure
    linearised about a trim reduces to the structure about zero)."""
    rng = np.random.default_rng(4)
    p = random_parameters(rng)
    p.update(air_density=0.0, coning=0.0, trim_lag=0.0)
    structural = {k: p[k] for k in blade_function().__code__.co_varnames[1:12]}
    vacuum = blade_function()(np.array([17.0]), **structural)
    air = blade_in_air(17.0, p)
    np.testing.assert_allclose(air, vacuum, rtol=0, atol=1e-12 * np.abs(vacuum).max())


def rotor_in_air(blade, aero, n=4, flap=True):
    return Rotor((blade,) * n, flap=flap, aero=aero)


HUB = Body(dofs=("x", "y"), mass_x=2000.0, mass_y=2000.0, stiffness_x=1e6, stiffness_y=1e6)


@pytest.mark.parametrize("offset, pitch_flap", [(0.0, 0.0), (0.4, 0.0), (0.4, 0.7)])
def test_isolated_flapping_blade_roots(offset, pitch_flap):
    """Flap roots s/Omega = -gamma J/4 +- i sqrt(nu_beta^2 + gamma K_P A1/2 - (gamma J/4)^2) at
    zero collective (no coning, no inflow), lift from the hinge (Johnson 2013, hover flap
    dynamics; J = int x (x - e/R)^2 dx, A1 = int x^2 (x - e/R) dx over e/R..1)."""
    inertia, radius, rho, a, chord, speed = 400.0, 5.0, 1.225, 5.7, 0.35, 30.0
    blade = Blade(90.0, 110.0, inertia, offset, lag_stiffness=1e9, flap_stiffness=8000.0)
    aero = Aero(rho, a, chord, radius, root_cutout=offset, pitch_flap=pitch_flap)
    system = System(rotor_in_air(blade, aero), HUB)
    m, c, k = system.matrices(np.array([speed]))[:, 0]
    i = 2 + 4  # the first blade's flap, after the hub's x, y and four lags
    roots = np.roots([m[i, i], c[i, i], k[i, i]]) / speed
    gamma, eb = rho * a * chord * radius**4 / inertia, offset / radius
    j = (1 - eb) ** 4 / 4 + eb * (1 - eb) ** 3 / 3
    a1 = 1 / 4 - eb / 3 + eb**4 / 12
    nu2 = 1 + offset * 110.0 / inertia + 8000.0 / (inertia * speed**2) + gamma * pitch_flap * a1 / 2
    expected = -gamma * j / 4 + 1j * math.sqrt(nu2 - (gamma * j / 4) ** 2)
    np.testing.assert_allclose(sorted(roots, key=lambda r: r.imag)[-1], expected, rtol=1e-12)


def test_lag_damping_of_a_blade_with_collective_and_profile_drag():
    """C_lag / (I Omega) = gamma [lambda theta (1 - e/R)^3 / 6 + (cd0/a) J] for an untwisted blade
    lifting from its hinge, flap locked (the in-plane force's change with the lag rate)."""
    inertia, radius, rho, a, chord, cd0, theta, speed = 400.0, 5.0, 1.225, 5.7, 0.35, 0.012, 0.14, 30.0
    offset = 0.3
    blade = Blade(90.0, 110.0, inertia, offset, lag_stiffness=1e12)
    aero = Aero(rho, a, chord, radius, root_cutout=offset, drag_coefficient=cd0, collective=theta)
    system = System(rotor_in_air(blade, aero, flap=False), HUB)
    lam = system.trim(np.array([speed])).inflow_ratio[0]
    c = system.matrices(np.array([speed]))[1, 0]
    gamma, eb = rho * a * chord * radius**4 / inertia, offset / radius
    j = (1 - eb) ** 4 / 4 + eb * (1 - eb) ** 3 / 3
    expected = gamma * (lam * theta * (1 - eb) ** 3 / 6 + cd0 / a * j) * inertia * speed
    assert c[2, 2] == pytest.approx(expected, rel=1e-9)  # (trim lag 1e-7 rad: its effect is below)


def test_trim_inflow_of_an_untwisted_rotor():
    """lambda = (sigma a/16)(sqrt(1 + 64 theta/(3 sigma a)) - 1) (zero offset, no cutout, no
    coning: blades held stiff), and the torque C_Q = sigma cd0/8 + lambda C_T."""
    blade = Blade(10.0, 25.0, 83.3, 0.0, lag_stiffness=1e12, flap_stiffness=1e12)
    aero = Aero(1.225, 5.7, 0.3, 5.0, root_cutout=0.0, collective=math.radians(8), drag_coefficient=0.01)
    rotor = rotor_in_air(blade, aero)
    trim = solve_trim(rotor, HUB, np.array([0.0, 10.0, 30.0]))
    sigma, a, theta = aero.solidity(4), 5.7, math.radians(8)
    lam = sigma * a / 16 * (math.sqrt(1 + 64 * theta / (3 * sigma * a)) - 1)
    np.testing.assert_allclose(trim.inflow_ratio, [0.0, lam, lam], rtol=0, atol=1e-14)
    c_q = sigma * 0.01 / 8 + lam * 2 * lam**2
    expected = c_q * 1.225 * math.pi * 25.0 * (30.0 * 5.0) ** 2 * 5.0
    assert trim.torque[2] == pytest.approx(expected, rel=1e-9)
    assert trim.thrust[2] == pytest.approx(2 * lam**2 * 1.225 * math.pi * 25.0 * (150.0) ** 2, rel=1e-9)


def test_trim_at_zero_collective_has_no_inflow_and_no_thrust():
    blade = Blade(60.0, 132.0, 406.0, 0.5, lag_stiffness=21119.0, flap_stiffness=5074.0)
    aero = Aero(1.225, 5.7, 0.35, 5.0, root_cutout=0.5, drag_coefficient=0.01)
    trim = solve_trim(rotor_in_air(blade, aero, n=3), HUB, np.linspace(0, 40, 5))
    np.testing.assert_array_equal(trim.inflow_ratio, 0.0)
    np.testing.assert_allclose(trim.coning, 0.0, atol=1e-15)
    assert (trim.trim_lag[1:] > 0).all()  # profile drag lags the blades


CASE = """
[rotor]
blades = 3
hinge_offset = 0.5
blade_mass = 60.0
blade_static_moment = 132.0
blade_inertia = 406.0
lag_stiffness = 21119.0
flap = true
flap_stiffness = 5074.0

[body]
dofs = ["pitch", "roll"]
inertia_pitch = 2500.0
inertia_roll = 800.0
stiffness_pitch = 379030.0
stiffness_roll = 102425.0
hub_height = 1.6

[sweep]
start = 30.0
stop = 300.0
points = 12
unit = "rpm"
"""


def case_in_air(**aero):
    import tomllib

    data = tomllib.loads(CASE)
    if aero:
        data["aero"] = {"lift_slope": 5.7, "chord": 0.35, "tip_radius": 5.0, **aero}
    return parse_case(data)


def roots(case):
    from groundres.methods import choose_method
    from groundres.solve.solvers import solver_for

    values = solver_for(case, choose_method(case)).roots(case.sweep.speeds)
    # each speed's roots by frequency, then real part (round-off aside: rounded keys)
    order = np.lexsort((np.round(values.real, 6), np.round(values.imag, 6)), axis=-1)
    return np.take_along_axis(values, order, -1)


def test_zero_lock_number_is_the_vacuum():
    vacuum = roots(case_in_air())
    still = roots(case_in_air(lock_number=0.0, collective=5.0, drag_coefficient=0.01))
    np.testing.assert_allclose(still, vacuum, rtol=1e-12, atol=1e-12 * np.abs(vacuum).max())


def test_at_zero_collective_the_roots_depend_on_the_lock_number_and_cd0_over_a():
    """Same gamma and cd0/a, different air density and chord (and lift slope): the same roots."""
    one = roots(case_in_air(air_density=1.225, drag_coefficient=0.01))
    gamma = 1.225 * 5.7 * 0.35 * 5.0**4 / 406.0
    chord = 0.5
    other = case_in_air(lock_number=gamma, drag_coefficient=0.01 * 6.0 / 5.7, lift_slope=6.0, chord=chord)
    assert other.rotor.aero.air_density == pytest.approx(1.225 * 5.7 * 0.35 / (6.0 * chord), rel=1e-14)
    np.testing.assert_allclose(roots(other), one, rtol=1e-10, atol=1e-10 * np.abs(one).max())


def test_air_damps_the_regressive_flap_instability_of_the_vacuum_rotor():
    """In vacuum the undamped soft in-plane rotor has a flap-lag coalescence near 88.9 rpm
    (0.1 rpm wide); the blades' aerodynamic flap damping removes it."""
    import tomllib

    data = tomllib.loads(CASE)
    data["sweep"].update(start=88.85, stop=89.05, points=41)
    vacuum = parse_case(data)
    assert roots(vacuum).real.max() > 1e-3
    data["aero"] = {
        "lift_slope": 5.7,
        "chord": 0.35,
        "tip_radius": 5.0,
        "air_density": 1.225,
        "drag_coefficient": 0.01,
    }
    # the flap roots are strongly damped in air, the lag ones by the profile drag: every root decays
    assert roots(parse_case(data)).real.max() < -1e-3


@pytest.mark.parametrize(
    "aero, words",
    [
        ({"air_density": 1.2, "lock_number": 5.0}, "one of the two"),
        ({"lift_slope": 5.7}, "one of the two (neither"),
        ({"air_density": 1.2, "tip_radius": 0.4}, "[aero] tip_radius = 0.4"),
        ({"air_density": 1.2, "root_cutout": 0.2}, "at or beyond the hinge offset"),
        ({"air_density": 1.2, "collective": 40.0}, "[aero] collective = 40"),
        ({"air_density": -1.0}, "[aero] air_density = -1.0"),
        ({"air_density": 1.2, "inflow": "dynamik"}, "did you mean 'dynamic'"),
        ({"air_density": 1.2, "drag_coefficient": 1.5}, "[aero] drag_coefficient = 1.5"),
        ({"air_density": 1.2, "tip_radius": 1e300}, "[aero] tip_radius = 1e+300: must be at most"),
        ({"lock_number": 1e6}, "[aero] lock_number = 1000000.0: gives an air density"),
    ],
)
def test_bad_aero_values_name_the_key(aero, words):
    with pytest.raises(CaseError) as err:
        case_in_air(**aero)
    assert words in str(err.value)


def test_the_span_moments_keep_one_set_of_names():
    from groundres.symbolic.aero import SPAN_SYMBOLS
    from groundres.symbolic.codegen import SPAN_ARGUMENTS

    assert tuple(SPAN_SYMBOLS) == SPAN_ARGUMENTS


@pytest.mark.parametrize("inflow", ["uniform", "dynamic"])
def test_floquet_of_the_blade_equations_equals_multiblade_eigen_in_air(inflow):
    """Identical blades in air (collective, pitch-lag coupling: coning and trim lag enter):
    the Floquet exponents of the untransformed blade equations, each speed on its own trim,
    equal the multiblade eigenvalues (real parts; frequencies modulo the rotor speed), with
    uniform and with dynamic inflow (three more roots, the same by both routes)."""
    from groundres.solve.solvers import Floquet, Multiblade

    case = case_in_air(
        air_density=1.225, drag_coefficient=0.01, collective=8.0, pitch_lag=-0.3, inflow=inflow
    )
    system = System.in_mass_unit(case.rotor, case.body)
    speeds = case.sweep.speeds
    eigen, floquet = Multiblade(system).roots(speeds), Floquet(system).roots(speeds)
    scale = np.abs(eigen.real).max()
    np.testing.assert_allclose(np.sort(floquet.real, -1), np.sort(eigen.real, -1), rtol=0, atol=1e-9 * scale)
    # every exponent is an eigenvalue shifted by a whole number of rotor speeds
    for w, f_roots, e_roots in zip(speeds, floquet, eigen):
        for root in f_roots:
            shifts = (root.imag - e_roots.imag) / w
            near = np.abs(e_roots.real - root.real) < 1e-8 * scale
            assert (near & (np.abs(shifts - np.round(shifts)) < 1e-8)).any()


@pytest.mark.parametrize("inflow", ["uniform", "dynamic"])
def test_rotating_axes_equal_multiblade_in_air_on_an_isotropic_hub(inflow):
    """With dynamic inflow its first-harmonic pair turns with the hub, as velocities."""
    from groundres.solve.solvers import Multiblade, Rotating

    blade = Blade(60.0, 132.0, 406.0, 0.5, lag_stiffness=21119.0, flap_stiffness=5074.0)
    aero = Aero(
        1.225, 5.7, 0.35, 5.0, root_cutout=0.6, collective=0.1, twist=-0.12, pitch_flap=0.3, inflow=inflow
    )
    system = System(rotor_in_air(blade, aero, n=3), HUB)
    speeds = np.linspace(5.0, 40.0, 8)
    one, other = Multiblade(system).roots(speeds), Rotating(system).roots(speeds)
    scale = np.abs(one.real).max()
    np.testing.assert_allclose(np.sort(other.real, -1), np.sort(one.real, -1), rtol=0, atol=1e-9 * scale)


def test_steady_flapping_per_unit_body_pitch_and_roll_rate():
    """A centrally hinged rotor without spring, zero collective, the hub at the pivot: turning
    the body at a steady rate tilts the rotor behind the shaft. Per unit q/Omega (pitch rate,
    nose up) beta_1c = -16/gamma and beta_1s = -1; per unit p/Omega (roll rate, right side
    down) beta_1c = 1 and beta_1s = -16/gamma (Johnson 2013, flapping due to shaft rotation,
    in groundres's azimuth from the nose). The body's angles themselves load nothing."""
    inertia, radius, rho, a, chord, speed = 400.0, 5.0, 1.225, 5.7, 0.35, 30.0
    blade = Blade(90.0, 110.0, inertia, 0.0, lag_stiffness=1e9)
    body = Body(
        dofs=("pitch", "roll"),
        inertia_pitch=1000.0,
        inertia_roll=1000.0,
        stiffness_pitch=1e5,
        stiffness_roll=1e5,
        hub_height=0.0,
    )
    system = System(rotor_in_air(blade, Aero(rho, a, chord, radius, root_cutout=0.0)), body)
    m, c, k = system.multiblade(np.array([speed]))[:, 0]
    names = [(x.kind, x.name) for x in system.multiblade_coordinates()]
    blades = list(range(2, system.size))
    assert np.abs(k[np.ix_(blades, [0, 1])]).max() == 0.0
    response = np.linalg.solve(k[np.ix_(blades, blades)], -c[np.ix_(blades, [0, 1])]) * speed
    flap = {name: response[names.index(("flap", name)) - 2] for name in ("1c", "1s")}
    gamma = rho * a * chord * radius**4 / inertia
    np.testing.assert_allclose(flap["1c"], [-16 / gamma, 1.0], rtol=1e-12)
    np.testing.assert_allclose(flap["1s"], [-1.0, -16 / gamma], rtol=1e-12)


def test_a_collective_sweep_is_a_study_of_aero_collective():
    """A study varies [aero] keys like any other: each point equals the case with that value
    written into its [aero] table (serial study; the cluster path is tested in test_study.py)."""
    from groundres import analyze
    from groundres.studies.study import study

    air = "air_density = 1.225\nlift_slope = 5.7\nchord = 0.35\ntip_radius = 5.0\ncollective = 2.0\n"
    text = CASE + "\n[aero]\n" + air
    import tomllib

    case = parse_case(tomllib.loads(text), "air", text)
    grid = study(case, {"aero.collective": [0.0, 6.0], "aero.pitch_lag": [0.0, -0.3]})
    assert grid["aero.collective"].attrs["units"] == "deg"
    for collective, pitch_lag in [(0.0, 0.0), (6.0, -0.3)]:
        written = text.replace("collective = 2.0", f"collective = {collective}\npitch_lag = {pitch_lag}")
        stability = analyze(
            parse_case(tomllib.loads(written), "air", written), lag_damping_search=False
        ).stability
        point = grid.sel({"aero.collective": collective, "aero.pitch_lag": pitch_lag})
        assert float(point.max_real_part) == pytest.approx(stability.max_real_part[0], rel=1e-9, abs=1e-12)


def test_compare_vacuum_puts_the_case_in_vacuum_beside_it_in_one_command(tmp_path):
    from click.testing import CliRunner

    from groundres.cli import main

    out = tmp_path / "cmp"
    import json

    result = CliRunner().invoke(main, ["compare", "model-rotor-hover-0deg", "--vacuum", "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "(in" in result.output and "vacuum)" in result.output  # (the table may wrap it)
    record = json.loads((out / "provenance.json").read_text())["entries"][0]
    assert record["name"] == "model-rotor-hover-0deg (in vacuum)"
    first, second = (json.loads((out / f"summary-{k}.json").read_text()) for k in (1, 2))
    assert "aero" not in first and second["aero"]["lock_number"] == pytest.approx(6.9, abs=0.01)
    assert "# [aero]" in (out / "case.toml").read_text()
    refused = CliRunner().invoke(main, ["compare", "hammond-1974", "--vacuum", "--out", str(tmp_path / "x")])
    assert refused.exit_code == 2 and "no CASE has an [aero] table" in refused.output
