"""The isolated blade's flap-lag problem in hover, derived a second way, against the rotor in air.

The classical problem (Ormiston and Hodges 1972, "Linear flap-lag dynamics of hingeless helicopter
rotor blades in hover", Journal of the American Helicopter Society 17(2); Johnson 2013, Rotorcraft
Aeromechanics, Cambridge University Press, the chapters on flap-lag dynamics)
is set up here from scratch, with the model of ``docs/theory.md`` ("The rotor in air") but without
the small-angle simplifications of the classical papers, and solved in this file alone.

What is derived
    One rigid blade, a line mass beyond its hinge (static moment S, inertia I about the hinge; its mass
    m does not enter with the hub at rest), hinged at e from the shaft: lag zeta about the shaft axis
    (positive against the rotation), then flap beta about the lagged in-plane axis (positive up), root
    springs and dampers on both. The hub turns at Omega and is otherwise at rest, which is what the
    COLLECTIVE multiblade coordinates of N >= 3 identical blades see: they do not couple with the body's
    x and y. The air loads are the quasi-steady strip loads of the theory page, lift from
    ``root_cutout`` to ``tip_radius``, with the pitch theta = collective + twist r/R - K_Pbeta beta -
    K_Pzeta zeta on the total angles and the uniform inflow lambda frozen at its momentum-theory trim
    value.

How (Newton-Euler, not energies)
    In the hub's rotating axes, the absolute acceleration of the point rho along the span is
    a = rho b'' + 2 Omega z x rho b' + Omega z x (Omega z x (H + rho b)), H = (e, 0, 0) the hinge and b
    the unit vector along the span. Moment equilibrium about the hinge point (which itself
    accelerates; taking a absolute makes that exact) of the blade's mass distribution and the air
    loads,

        I b x b'' + 2 Omega I b x (z x b') + Omega^2 [S b x (z x (z x H)) + I b x (z x (z x b))]
            = M_air + (hinge moments),  M_air = int rho b x F drho,

    is projected on the two hinge axes: the lag hinge axis -z (positive lag) and the flap hinge axis
    f = (-sin zeta, -cos zeta, 0) (positive flap), which carry only the springs and dampers. Nothing
    here writes an energy or uses Lagrange's equations; the section loads are written as forces along
    the blade's normal n and leading-edge direction t and the moments taken by cross products. The span
    integrals are exact: every integrand is a polynomial of degree <= 4 in rho (velocities linear in
    rho, pitch linear in rho), and three-point Gauss-Legendre quadrature is exact to degree 5. SymPy
    differentiates the nonlinear hinge equations exactly; the hover trim (coning beta0, trim lag
    zeta0, inflow lambda from T = rho pi R^2 (Omega R)^2 2 lambda |lambda|, T = N int F . z drho along
    the shaft) is solved by Newton's method on those exact derivatives, and M, C, K are the Jacobians
    with respect to the accelerations, rates and angles at the trim, with lambda held.

Dynamic inflow
    With Pitt-Peters dynamic inflow the collective also carries the uniform inflow state. Its
    equation is written here from Pitt and Peters (1981) and momentum theory alone (apparent mass
    128/(75 pi), gain 4 abs(lambda), forced by the rotor's thrust change, the air's velocity
    entering the loads as lambda Omega R does), on the same exact hinge equations, and the five
    roots of the (lag 0, flap 0, inflow) block must be the project's: found within 2.4e-15 Omega
    over zero, positive and negative collective, both couplings and a model rotor, while the inflow
    state moves them from the frozen inflow's by 0.047 Omega or more.

Why it is independent
    Nothing is imported from ``groundres.symbolic`` or ``groundres.model.trim``. The project's side is
    built from its public API only (``Blade``, ``Rotor``, ``Aero``, ``Body``, ``System``,
    ``Multiblade``): its trim (``System.trim``) and the 2 x 2 collective block (lag 0, flap 0) of its
    multiblade form (``System.multiblade``), whose four roots must be the isolated blade's four roots
    in the rotating frame.

Tolerance
    Both sides are exact linearisations of the same nonlinear equations about the same trim, evaluated
    in double precision; the trims converge to ~1e-15 rad. The roots of a 2 x 2 quadratic eigenproblem
    with well separated roots then agree to a modest multiple of the round-off in the matrices, a few
    1e-14 of Omega; the cases avoid coalescing roots (where a double root would turn a 1e-16 error into
    1e-8). 1e-9 of Omega for the roots and 1e-10 (relative, or of the natural scale for angles and
    inflow) for the trim leave orders of magnitude for round-off (the agreement found is ~2e-15 of
    Omega for the roots and ~1e-16 rad, ~1e-15 relative for the trim), while a wrong or missing term
    shows at the size of that term. The smallest effect checked is the trim lag's exact geometry:
    linearising about zero trim lag instead moves the roots by 5e-5 to 5e-3 of Omega in these cases,
    and about zero coning by 1.5e-3 to 3e-2 (``test_the_cases_are_not_vacuous`` holds each above
    1e-5 of Omega, 1e4 times the tolerance).
"""

import functools
import math

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import linear_sum_assignment

from groundres.model.aero import Aero
from groundres.model.body import Body
from groundres.model.params import Blade, Rotor
from groundres.model.system import System
from groundres.solve.solvers import Multiblade

#: Relative tolerances (see the module docstring).
ROOT_TOLERANCE = 1e-9
TRIM_TOLERANCE = 1e-10

# ---------------------------------------------------------------------------------------------------
# The isolated blade, by moment equilibrium about its hinges

LAG, FLAP = sp.symbols("zeta beta", real=True)
LAG_RATE, FLAP_RATE = sp.symbols("zeta_dot beta_dot", real=True)
LAG_ACC, FLAP_ACC = sp.symbols("zeta_ddot beta_ddot", real=True)
OMEGA, INFLOW = sp.symbols("Omega lambda", real=True)
#: The parameters, in the order the numeric functions take them.
PARAMETERS = sp.symbols(
    "m S I e K_lag C_lag K_flap C_flap rho_air a c cd0 theta0 theta_tw R r_c K_Pbeta K_Pzeta", real=True
)
NAMES = [str(p) for p in PARAMETERS]
#: Three-point Gauss-Legendre nodes and weights on [-1, 1]: exact for polynomials of degree <= 5.
GAUSS = (
    (-sp.sqrt(sp.Rational(3, 5)), sp.Rational(5, 9)),
    (0, sp.Rational(8, 9)),
    (sp.sqrt(sp.Rational(3, 5)), sp.Rational(5, 9)),
)


def vec(x, y, z):
    return sp.Matrix([x, y, z])


def rates_of(expression, q, qd, qdd=None):
    """d/dt of a vector function of q(t) (q' = qd, q'' = qdd)."""
    first = expression.jacobian(q) * qd
    if qdd is None:
        return first
    return expression.jacobian(q) * qdd + first.jacobian(q) * qd


@functools.cache
def blade_equations():
    """The hinge equations, thrust and torque of one blade, differentiated, as NumPy functions."""
    m, s, i, e, k_lag, c_lag, k_flap, c_flap, rho_air, a, c, cd0, th0, th_tw, tip, cutout, kpb, kpz = (
        PARAMETERS
    )
    q, qd, qdd = sp.Matrix([LAG, FLAP]), sp.Matrix([LAG_RATE, FLAP_RATE]), sp.Matrix([LAG_ACC, FLAP_ACC])
    cz, sz, cb, sb = sp.cos(LAG), sp.sin(LAG), sp.cos(FLAP), sp.sin(FLAP)
    z = vec(0, 0, 1)
    spin = OMEGA * z
    hinge = vec(e, 0, 0)
    # blade axes: span b, leading edge t, normal n; lag about -z then flap about f = -(lagged y)
    b = vec(cb * cz, -cb * sz, sb)
    t = vec(sz, cz, 0)
    n = vec(-sb * cz, sb * sz, cb)
    lag_axis, flap_axis = -z, vec(-sz, -cz, 0)
    b_dot, b_ddot = rates_of(b, q, qd), rates_of(b, q, qd, qdd)

    # rate of change of the angular momentum about the (accelerating) hinge, integrated over the mass
    inertial = (
        i * b.cross(b_ddot)
        + 2 * i * b.cross(spin.cross(b_dot))
        + s * b.cross(spin.cross(spin.cross(hinge)))
        + i * b.cross(spin.cross(spin.cross(b)))
    )

    # air loads on the section at rho from the hinge (r = e + rho from the shaft)
    def section(rho):
        position = hinge + rho * b
        w = spin.cross(position) + rho * b_dot + INFLOW * OMEGA * tip * z
        u_t, u_p = w.dot(t), w.dot(n)
        pitch = th0 + th_tw * (e + rho) / tip - kpb * FLAP - kpz * LAG
        f_n = rho_air * c * a / 2 * (u_t**2 * pitch - u_p * u_t)
        f_x = rho_air * c * a / 2 * (u_p * u_t * pitch - u_p**2) + rho_air * c * cd0 / 2 * u_t**2
        force = f_n * n - f_x * t
        return force, rho * b.cross(force), position.cross(force)

    lo, hi = cutout - e, tip - e
    moment, thrust, torque = sp.zeros(3, 1), 0, 0
    for node, weight in GAUSS:
        force, arm_moment, shaft_moment = section((lo + hi) / 2 + (hi - lo) / 2 * node)
        moment += weight * (hi - lo) / 2 * arm_moment
        thrust += weight * (hi - lo) / 2 * force.dot(z)
        torque -= weight * (hi - lo) / 2 * shaft_moment.dot(z)

    residual = sp.Matrix(
        [
            lag_axis.dot(inertial - moment) + k_lag * LAG + c_lag * LAG_RATE,
            flap_axis.dot(inertial - moment) + k_flap * FLAP + c_flap * FLAP_RATE,
        ]
    )
    still = {LAG_RATE: 0, FLAP_RATE: 0, LAG_ACC: 0, FLAP_ACC: 0}
    angles = [LAG, FLAP]
    outputs = {
        "residual": residual,
        "stiffness": residual.jacobian(angles),
        "damping": residual.jacobian(qd),
        "mass": residual.jacobian(qdd),
        "d_inflow": residual.diff(INFLOW),
        "thrust": sp.Matrix([thrust]),
        "d_thrust": sp.Matrix([thrust]).jacobian(angles + [INFLOW]),
        "d_thrust_rates": sp.Matrix([thrust]).jacobian(qd),
        "torque": sp.Matrix([torque]),
    }
    arguments = [LAG, FLAP, OMEGA, INFLOW, *PARAMETERS]
    keys = list(outputs)
    function = sp.lambdify(arguments, [outputs[k].xreplace(still) for k in keys], modules="numpy", cse=True)

    def evaluate(lag, flap, speed, inflow, params):
        values = function(lag, flap, speed, inflow, *(params[name] for name in NAMES))
        return {k: np.array(v, dtype=float) for k, v in zip(keys, values)}

    return evaluate, (inertial, b, b_dot, lag_axis, flap_axis)


def own_trim(params, n_blades, speed):
    """(trim lag, coning, inflow ratio, thrust, torque) by Newton's method on the exact equations."""
    evaluate, _ = blade_equations()
    tip, sigma = params["R"], n_blades * params["c"] / (math.pi * params["R"])
    area_speed = params["rho_air"] * math.pi * tip**2 * (speed * tip) ** 2
    pitch = params["theta0"] + 0.75 * params["theta_tw"]
    # the untwisted rotor's inflow as the first guess (any sign of the pitch)
    guess = sigma * params["a"] / 16 * (math.sqrt(1 + 64 * abs(pitch) / (3 * sigma * params["a"])) - 1)
    x = np.array([0.0, 0.0, math.copysign(guess, pitch)])
    for _ in range(60):
        v = evaluate(x[0], x[1], speed, x[2], params)
        lam = x[2]
        residual = np.concatenate(
            [v["residual"][:, 0], [n_blades * v["thrust"][0, 0] - area_speed * 2 * lam * abs(lam)]]
        )
        jacobian = np.zeros((3, 3))
        jacobian[:2, :2] = v["stiffness"]
        jacobian[:2, 2] = v["d_inflow"][:, 0]
        jacobian[2] = n_blades * v["d_thrust"][0]
        jacobian[2, 2] -= area_speed * 4 * abs(lam)
        step = np.linalg.solve(jacobian, -residual)
        x = x + step
        if np.max(np.abs(step)) < 1e-15:
            break
    else:  # pragma: no cover - a failure to converge is a failure of the test
        raise AssertionError(f"own trim did not converge: last step {step}")
    v = evaluate(x[0], x[1], speed, x[2], params)
    return x[0], x[1], x[2], n_blades * v["thrust"][0, 0], n_blades * v["torque"][0, 0]


def own_roots(params, trim, speed):
    """The four roots [1/s] of the isolated blade linearised about its trim (lambda held)."""
    evaluate, _ = blade_equations()
    v = evaluate(trim[0], trim[1], speed, trim[2], params)
    return quadratic_roots(v["mass"], v["damping"], v["stiffness"])


#: Pitt-Peters' apparent mass of the uniform inflow (Pitt and Peters 1981, "Theoretical prediction
#: of dynamic-inflow derivatives", Vertica 5).
UNIFORM_APPARENT_MASS = 128 / (75 * math.pi)


def own_roots_dynamic_inflow(params, n_blades, trim, speed):
    """The five roots [1/s] of the collective flap-lag problem with the uniform inflow state of
    Pitt-Peters dynamic inflow (momentum theory perturbed: M0 nu' + 4 abs(lambda) nu = dC_T,
    ' = d/dpsi, nu = v / (Omega R)), written here from those equations alone: the air comes
    down at lambda Omega R + v, so the blade's loads and thrust change with v as with lambda
    over Omega R; the equation in v times rho pi R^4 Omega^2 reads
    rho pi R^3 (M0 v_dot + 4 abs(lambda) Omega v) = N dT. With v the rate of a coordinate xi
    that appears nowhere else, the 3 x 3 problem in (zeta, beta, xi) has the five roots and
    one at zero (xi's position), which is dropped."""
    evaluate, _ = blade_equations()
    v = evaluate(trim[0], trim[1], speed, trim[2], params)
    tip = params["R"]
    per_v = 1.0 / (speed * tip)  # (d/dv = d/dlambda / (Omega R))
    air = params["rho_air"] * math.pi * tip**3
    mass, damping, stiffness = np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((3, 3))
    mass[:2, :2], damping[:2, :2], stiffness[:2, :2] = v["mass"], v["damping"], v["stiffness"]
    damping[:2, 2] = v["d_inflow"][:, 0] * per_v
    mass[2, 2] = air * UNIFORM_APPARENT_MASS
    damping[2, 2] = air * 4 * abs(trim[2]) * speed - n_blades * v["d_thrust"][0, 2] * per_v
    damping[2, :2] = -n_blades * v["d_thrust_rates"][0]
    stiffness[2, :2] = -n_blades * v["d_thrust"][0, :2]
    roots = quadratic_roots(mass, damping, stiffness)
    return np.delete(roots, np.argmin(np.abs(roots)))


def quadratic_roots(mass, damping, stiffness):
    """Roots s of det(M s^2 + C s + K) = 0 from the first-order form."""
    size = len(mass)
    inverse = np.linalg.inv(mass)
    state = np.block([[np.zeros((size, size)), np.eye(size)], [-inverse @ stiffness, -inverse @ damping]])
    return np.linalg.eigvals(state)


# ---------------------------------------------------------------------------------------------------
# The project's answer, from its public API

BASE = dict(
    m=30.0,
    S=80.0,
    I=290.0,
    e=0.25,
    K_lag=0.0,
    C_lag=4000.0,
    K_flap=0.0,
    C_flap=0.0,
    rho_air=1.225,
    a=5.7,
    c=0.35,
    cd0=0.0,
    theta0=0.0,
    theta_tw=0.0,
    R=5.5,
    r_c=0.25,
    K_Pbeta=0.0,
    K_Pzeta=0.0,
)

#: The cases: (id, number of blades, rotor speeds [rad/s], changes to BASE; angles in degrees).
CASES = [
    ("articulated-zero-collective", 4, (15.0, 25.0, 35.0), dict()),
    ("articulated-6deg-drag", 4, (15.0, 25.0, 35.0), dict(theta0=6.0, cd0=0.01)),
    ("12deg-twist-cutout", 4, (20.0, 30.0), dict(theta0=12.0, theta_tw=-8.0, cd0=0.012, r_c=1.1)),
    ("zero-collective-twist", 3, (20.0, 32.0), dict(theta_tw=-10.0, cd0=0.008, r_c=0.8)),
    ("negative-collective", 5, (18.0, 30.0), dict(theta0=-6.0, cd0=0.01)),
    ("pitch-flap-positive", 4, (20.0, 30.0), dict(theta0=8.0, cd0=0.01, K_Pbeta=0.5)),
    ("pitch-flap-negative", 4, (20.0, 30.0), dict(theta0=8.0, cd0=0.01, K_Pbeta=-0.5)),
    (
        "soft-inplane-pitch-lag-positive",
        4,
        (20.0, 30.0, 40.0),
        dict(theta0=9.0, cd0=0.01, e=0.5, r_c=0.9, K_lag=9.0e4, C_lag=300.0, K_flap=3.0e4, K_Pzeta=0.4),
    ),
    (
        "soft-inplane-pitch-lag-negative",
        4,
        (20.0, 30.0, 40.0),
        dict(theta0=9.0, cd0=0.01, e=0.5, r_c=0.9, K_lag=9.0e4, C_lag=300.0, K_flap=3.0e4, K_Pzeta=-0.4),
    ),
    (
        "stiff-inplane-both-couplings",
        3,
        (25.0, 35.0),
        dict(
            theta0=10.0,
            theta_tw=-6.0,
            cd0=0.011,
            e=0.4,
            r_c=1.0,
            K_lag=5.0e5,
            C_lag=0.0,
            K_flap=8.0e4,
            C_flap=500.0,
            K_Pbeta=0.3,
            K_Pzeta=-0.25,
        ),
    ),
    (
        "stiff-flap-soft-lag-opposite-couplings",
        6,
        (22.0, 33.0),
        dict(
            theta0=12.0,
            cd0=0.01,
            e=0.3,
            r_c=0.6,
            K_lag=2.0e4,
            C_lag=1500.0,
            K_flap=4.0e5,
            C_flap=2000.0,
            K_Pbeta=-0.4,
            K_Pzeta=0.5,
        ),
    ),
    (
        "model-rotor",
        4,
        (60.0, 90.0, 120.0),
        dict(
            m=0.4,
            S=0.16,
            I=0.085,
            e=0.06,
            r_c=0.12,
            R=1.0,
            c=0.06,
            a=6.0,
            theta0=7.0,
            theta_tw=-5.0,
            cd0=0.009,
            K_lag=60.0,
            C_lag=0.05,
            K_flap=15.0,
            C_flap=0.01,
            K_Pbeta=0.2,
            K_Pzeta=0.3,
        ),
    ),
]

DEGREES = ("theta0", "theta_tw")


def case_params(changes):
    params = dict(BASE, **changes)
    for key in DEGREES:
        params[key] = math.radians(params[key])
    return params


def project_system(params, n_blades):
    blade = Blade(
        params["m"],
        params["S"],
        params["I"],
        params["e"],
        lag_stiffness=params["K_lag"],
        lag_damping=params["C_lag"],
        flap_stiffness=params["K_flap"],
        flap_damping=params["C_flap"],
    )
    aero = Aero(
        params["rho_air"],
        params["a"],
        params["c"],
        params["R"],
        root_cutout=params["r_c"],
        drag_coefficient=params["cd0"],
        collective=params["theta0"],
        twist=params["theta_tw"],
        pitch_flap=params["K_Pbeta"],
        pitch_lag=params["K_Pzeta"],
    )
    rotor = Rotor((blade,) * n_blades, flap=True, aero=aero)
    body = Body(dofs=("x", "y"), mass_x=2000.0, mass_y=1500.0, stiffness_x=4.0e5, stiffness_y=3.0e5)
    return System(rotor, body)


def collective_block(system, speeds, keys=(("lag", "0"), ("flap", "0"))):
    """The block of the multiblade mass, damping, stiffness on the coordinates ``keys`` ((kind,
    name) each: lag 0, flap 0 by default), and the largest coupling of those coordinates with
    the others relative to the block's own entries."""
    mats = system.multiblade(np.asarray(speeds))
    coords = system.multiblade_coordinates()
    index = [next(j for j, c in enumerate(coords) if (c.kind, c.name) == key) for key in keys]
    others = [j for j in range(len(coords)) if j not in index]
    block = mats[:, :, index][:, :, :, index]
    coupling = np.concatenate(
        [mats[:, :, index][:, :, :, others].ravel(), mats[:, :, others][:, :, :, index].ravel()]
    )
    return block, np.max(np.abs(coupling)) / np.max(np.abs(block))


def matched_difference(ours, theirs):
    """Largest |difference| between two root sets, matched one to one."""
    cost = np.abs(ours[:, None] - theirs[None, :])
    rows, cols = linear_sum_assignment(cost)
    return cost[rows, cols].max()


# ---------------------------------------------------------------------------------------------------
# The checks


@functools.cache
def comparison(case_id):
    """Both sides' trims and roots for one case (computed once, shared by the tests)."""
    _, n_blades, speeds, changes = next(c for c in CASES if c[0] == case_id)
    params = case_params(changes)
    system = project_system(params, n_blades)
    trim = system.trim(np.asarray(speeds))
    block, coupling = collective_block(system, speeds)
    full = Multiblade(system).roots(np.asarray(speeds))
    rows = []
    for j, speed in enumerate(speeds):
        mine = own_trim(params, n_blades, speed)
        rows.append(
            dict(
                speed=speed,
                own_trim=mine,
                own_roots=own_roots(params, mine, speed),
                project_roots=quadratic_roots(*block[:, j]),
                full_roots=full[j],
            )
        )
    return params, n_blades, trim, coupling, rows


IDS = [c[0] for c in CASES]


@pytest.mark.parametrize("case_id", IDS)
def test_hover_trim_equals_the_isolated_blade_trim(case_id):
    """Coning, trim lag (every blade), inflow ratio, thrust along the shaft and torque agree to 1e-10
    (angles and inflow: of 1 rad and of the inflow's scale 0.1; thrust and torque: relative, against
    the rotor's natural scale rho pi R^2 (Omega R)^2 times 1e-3 and that times R)."""
    params, n_blades, trim, _, rows = comparison(case_id)
    for j, row in enumerate(rows):
        lag0, flap0, lam, thrust, torque = row["own_trim"]
        scale = params["rho_air"] * math.pi * params["R"] ** 2 * (row["speed"] * params["R"]) ** 2
        assert np.all(np.abs(trim.trim_lag[j] - lag0) <= TRIM_TOLERANCE), (trim.trim_lag[j], lag0)
        assert np.all(np.abs(trim.coning[j] - flap0) <= TRIM_TOLERANCE), (trim.coning[j], flap0)
        assert abs(trim.inflow_ratio[j] - lam) <= 0.1 * TRIM_TOLERANCE, (trim.inflow_ratio[j], lam)
        assert abs(trim.thrust[j] - thrust) <= TRIM_TOLERANCE * max(abs(thrust), 1e-3 * scale), (
            trim.thrust[j],
            thrust,
        )
        assert abs(trim.torque[j] - torque) <= TRIM_TOLERANCE * max(
            abs(torque), 1e-3 * scale * params["R"]
        ), (trim.torque[j], torque)


@pytest.mark.parametrize("case_id", IDS)
def test_collective_multiblade_roots_equal_the_isolated_blade_roots(case_id):
    """The four roots of the collective (lag 0, flap 0) block equal the isolated blade's to 1e-9 Omega,
    the block does not couple with the body or the cyclic coordinates (to 1e-12 of its entries), and
    the four roots are among the whole system's multiblade roots."""
    _, _, _, coupling, rows = comparison(case_id)
    assert coupling <= 1e-12
    for row in rows:
        ours, theirs = row["own_roots"], row["project_roots"]
        assert matched_difference(ours, theirs) <= ROOT_TOLERANCE * row["speed"], (ours, theirs)
        # each of ours is one of the whole system's roots
        nearest = np.min(np.abs(ours[:, None] - row["full_roots"][None, :]), axis=1)
        assert np.all(nearest <= ROOT_TOLERANCE * row["speed"]), (ours, row["full_roots"])


@pytest.mark.parametrize("case_id", IDS[1:])
def test_the_cases_are_not_vacuous(case_id):
    """Every case with thrust has coning and trim lag that matter: the isolated blade linearised about
    zero trim lag (coning kept), or about zero coning (trim lag kept), has roots more than 1e-5 Omega
    (1e4 times the tolerance) from the true ones, so the agreement above tests the exact geometry of
    the trim; the inflow has the sign of the thrust."""
    evaluate, _ = blade_equations()
    params, _, _, _, rows = comparison(case_id)
    for row in rows:
        lag0, flap0, lam, thrust, _ = row["own_trim"]
        assert abs(thrust) > 0 and np.sign(lam) == np.sign(thrust)
        for lag, flap in ((0.0, flap0), (lag0, 0.0)):
            v = evaluate(lag, flap, row["speed"], lam, params)
            moved = quadratic_roots(v["mass"], v["damping"], v["stiffness"])
            assert matched_difference(moved, row["own_roots"]) > 1e-5 * row["speed"]


def test_the_couplings_move_the_roots():
    """Pitch-flap and pitch-lag coupling each move the roots by far more than the tolerance (and the
    zero-collective case trims at zero angles and zero inflow)."""
    params, n_blades, _, _, rows = comparison("stiff-flap-soft-lag-opposite-couplings")
    speed = rows[0]["speed"]
    for key in ("K_Pbeta", "K_Pzeta"):
        held = dict(params, **{key: 0.0})
        moved = own_roots(held, own_trim(held, n_blades, speed), speed)
        assert matched_difference(moved, rows[0]["own_roots"]) > 1e-3 * speed
    _, _, _, _, rows_zero = comparison("articulated-zero-collective")
    assert rows_zero[0]["own_trim"][:3] == pytest.approx((0.0, 0.0, 0.0), abs=1e-14)


def test_the_hinge_axes_are_those_of_the_angles():
    """The projections are onto the right axes: d b / d zeta = (-z) x b and d b / d beta = f x b, so the
    hinge moments are the generalised forces of zeta and beta (the classical small-angle equations
    follow: I beta'' + (I + e S) Omega^2 beta + ... and I zeta'' + e S Omega^2 zeta + ...)."""
    _, (inertial, b, _, lag_axis, flap_axis) = blade_equations()
    for axis, angle in ((lag_axis, LAG), (flap_axis, FLAP)):
        assert sp.simplify(b.diff(angle) - axis.cross(b)) == sp.zeros(3, 1)
    # in vacuum, about zero angles: the rotating lag and flap frequencies of the theory page
    m, s, i, e = PARAMETERS[:4]
    zero = {LAG: 0, FLAP: 0, LAG_RATE: 0, FLAP_RATE: 0, LAG_ACC: 0, FLAP_ACC: 0}
    rows = sp.Matrix([lag_axis.dot(inertial), flap_axis.dot(inertial)])
    stiffness = rows.jacobian([LAG, FLAP]).subs(zero)
    assert sp.simplify(stiffness - sp.diag(e * s * OMEGA**2, (i + e * s) * OMEGA**2)) == sp.zeros(2, 2)
    assert sp.simplify(rows.jacobian([LAG_ACC, FLAP_ACC]).subs(zero) - sp.diag(i, i)) == sp.zeros(2, 2)


#: Cases for dynamic inflow (ids of CASES): zero, positive and negative collective, both couplings,
#: a model rotor.
DYNAMIC_IDS = [
    "articulated-zero-collective",
    "12deg-twist-cutout",
    "negative-collective",
    "soft-inplane-pitch-lag-negative",
    "stiff-flap-soft-lag-opposite-couplings",
    "model-rotor",
]


@pytest.mark.parametrize("case_id", DYNAMIC_IDS)
def test_collective_roots_with_dynamic_inflow_equal_the_isolated_blade_with_its_inflow(case_id):
    """With Pitt-Peters dynamic inflow the collective block (lag 0, flap 0, uniform inflow) of the
    project's multiblade form has the five roots of the isolated blade with the uniform inflow
    state (:func:`own_roots_dynamic_inflow`) to 1e-9 Omega, is coupled with nothing else, and
    differs from the frozen inflow's roots by far more than that (the inflow state matters)."""
    import dataclasses

    _, n_blades, speeds, changes = next(c for c in CASES if c[0] == case_id)
    params = case_params(changes)
    frozen = project_system(params, n_blades)
    rotor = dataclasses.replace(frozen.rotor, aero=dataclasses.replace(frozen.rotor.aero, inflow="dynamic"))
    system = System(rotor, frozen.body)
    block, coupling = collective_block(system, speeds, (("lag", "0"), ("flap", "0"), ("inflow", "uniform")))
    assert coupling <= 1e-12
    full = Multiblade(system).roots(np.asarray(speeds))
    for j, speed in enumerate(speeds):
        trim = own_trim(params, n_blades, speed)
        theirs = own_roots_dynamic_inflow(params, n_blades, trim, speed)
        m, c, k = block[:, j]
        ours = quadratic_roots(m, c, k)
        ours = np.delete(ours, np.argmin(np.abs(ours)))  # (the inflow position's root at zero)
        assert matched_difference(ours, theirs) <= ROOT_TOLERANCE * speed, (ours, theirs)
        nearest = np.min(np.abs(theirs[:, None] - full[j][None, :]), axis=1)
        assert np.all(nearest <= ROOT_TOLERANCE * speed), (theirs, full[j])
        frozen_roots = own_roots(params, trim, speed)
        assert np.min(np.abs(theirs[:, None] - frozen_roots[None, :]), axis=0).max() > 1e-4 * speed
