"""A second, independent derivation of the generated matrices: one blade's linearised equations on a
moving body, a rigid body's mass matrix, a gear leg's stiffness matrix and the damper rods' length
gradients, compared with the generated code.

What is derived
    1. The linearised equations M(psi) q'' + C(psi) q' + K(psi) q = 0 of ONE blade on a moving body, for
       q = [x, y, z, theta, phi, chi, zeta, beta] (pivot translation, pitch nose up, roll right side
       down, yaw nose left, lag against the rotation, flap up), as exact SymPy functions of the azimuth
       psi, the rotor speed Omega and the blade and hub parameters (hub centre anywhere relative to the
       pivot). Only the blade's contribution is kept: no body mass, springs or dampers, no gravity, no
       aerodynamics; forcing-only terms (independent of q) are dropped.
    2. The 6 x 6 mass matrix of a rigid body (mass, inertia tensor about its centre of mass in body axes,
       centre of mass anywhere) on the body coordinates [x, y, z, theta, phi, chi].
    3. The 6 x 6 stiffness matrix of a gear leg: a body point tied to the ground by springs along the
       fixed x, y, z axes.
    4. The gradients of a damper rod's length at rest with respect to the lag and flap angles of the
       blade(s) it joins: blade to hub, and blade to another blade ``spacing`` ahead.

How
    1. With :mod:`sympy.physics.mechanics`: reference frames for the body (R_z(chi) R_x(phi) R_y(-theta),
       mechanics' body-fixed "ZXY" rotation), the hub (about the body's z axis by the prescribed azimuth
       psi(t), with psi' = Omega) and the blade span (R_z(-zeta) R_y(-beta) in the hub frame), points for
       the pivot, the hinge and the blade, and the blade itself either as a ``RigidBody`` (mass m, centre
       of mass at S/m along the span, central inertia I - S^2/m about the two axes perpendicular to the
       span and zero about it) or as two ``Particle`` objects on the span axis. The kinetic energy comes
       from mechanics; its exact second-order Taylor part about q = q' = 0 is taken (constant and linear
       parts only force), the root springs are added as a potential, ``LagrangesMethod`` forms
       d/dt dL/dq' - dL/dq for this quadratic Lagrangian with the explicit time dependence
       psi = Omega t + psi0, and the root dampers enter through the Rayleigh function
       D = (C_zeta zeta'^2 + C_beta beta'^2)/2. M, C, K are then the Jacobians with respect to q'', q', q.
    2. The Hessian, with respect to the speeds, of a mechanics ``RigidBody``'s kinetic energy on the same
       body frame; and by hand, T = 1/2 M |v + w x c|^2 + 1/2 w.J w with w = (phi', -theta', chi').
    3. The Hessian of V = 1/2 sum_a k_a u_a^2 with u the displacement of a mechanics ``Point`` fixed in
       the body frame; and by hand, u = (x, y, z) + a x p with the small rotation a = (phi, -theta, chi).
    4. The exact SymPy derivative of the rod length written with mechanics frames for the two blades'
       hub and span axes, and independently central differences at 50 digits (mpmath) of the length
       written with explicit rotation matrices.

Why it is independent
    Nothing is imported from ``groundres.symbolic.derive``; the kinematics are built from mechanics'
    frames and points rather than from hand-written position vectors, the blade is a rigid body (or
    two particles) rather than a line integral, and the equations come from ``LagrangesMethod``. Only
    the generated NumPy functions (``blade_function`` and ``generated``) are compared, entry by entry,
    at several random physically valid parameter sets (hub centre on either side of the pivot in x, y
    and z) and azimuths. The derivation is also checked against results worked out by hand: the
    rotating lag and flap frequencies, the gyroscopic pitch-roll coupling, the translation rows as the
    second time derivative of the blade's first moment of mass (Newton for its centre of mass, which
    gives the heave-flap coupling S and the centrifugal force turning with yaw), the yaw-lag inertia
    I + e S and the yaw inertia about the pivot; the rigid body's and the legs' matrices in simple
    configurations; and the rods' symmetries.

Tolerance
    Both sides evaluate, in double precision, different but algebraically equal expressions whose terms
    are at most of the size of the entry's natural scale s_i s_j Omega^g (s_i^2 the largest diagonal
    mass entry of coordinate i over the azimuth; g = 0, 1, 2 for M, C, K; times the largest such
    dimensionless entry of that matrix, to allow for the springs and dampers). Rounding then gives
    differences of a few ulps times a few tens of terms, ~1e-15 of that scale; an error in a derivation
    (a wrong sign, a missing term) shows at the size of a term, which for these random parameters is at
    least ~1e-4 of the scale. 1e-12 of the scale separates the two by orders of magnitude on either side.
    The scale is per entry and dimensionally consistent, so an entry in kg is not judged against one in
    kg m^2.
"""

import functools
import itertools

import mpmath
import numpy as np
import pytest
import sympy as sp
from sympy.physics import mechanics as me

from groundres.symbolic.codegen import blade_function, generated

COORDS = ("x", "y", "z", "pitch", "roll", "yaw", "lag", "flap")
GROUPS = ("M", "C", "K")
HARMONICS = ("1", "cos psi", "sin psi", "cos 2psi", "sin 2psi")
X, Y, Z, PITCH, ROLL, YAW, LAG, FLAP = range(len(COORDS))

OMEGA, PSI, PSI0 = sp.symbols("Omega psi psi0", real=True)
MASS, STATIC, INERTIA, OFFSET, HEIGHT, HUB_X, HUB_Y = sp.symbols("m S I e h h_x h_y", real=True)
K_LAG, C_LAG, K_FLAP, C_FLAP = sp.symbols("K_zeta C_zeta K_beta C_beta", real=True)
#: Same order as the arguments of the generated blade function.
ARGUMENTS = (OMEGA, MASS, STATIC, INERTIA, OFFSET, HEIGHT, HUB_X, HUB_Y, K_LAG, C_LAG, K_FLAP, C_FLAP)
#: Two-particle model: masses m1, m2 at r1, r2 from the hinge on the span axis.
PARTICLES = sp.symbols("m1 m2 r1 r2", positive=True)

T = me.dynamicsymbols._t
Q = me.dynamicsymbols("x y z theta phi chi zeta beta")
AZIMUTH = me.dynamicsymbols("psi_t")  # psi(t), prescribed: psi' = Omega, psi'' = 0

TOLERANCE = 1e-12  # of each entry's scale (module docstring)


def body_kinematics(coordinates):
    """Inertial frame, body frame R_z(chi) R_x(phi) R_y(-theta), fixed origin and the moving pivot."""
    x, y, z, theta, phi, chi = coordinates
    inertial = me.ReferenceFrame("N")
    body = inertial.orientnew("B", "Body", (chi, phi, -theta), "ZXY")  # R_z(chi) R_x(phi) R_y(-theta)
    origin = me.Point("O")
    origin.set_vel(inertial, 0)
    pivot = origin.locatenew("pivot", x * inertial.x + y * inertial.y + z * inertial.z)
    return inertial, body, origin, pivot


def kinematics():
    """Frames and points: body, hub, blade span; the hinge point; the inertial origin."""
    *_, zeta, beta = Q
    inertial, body, origin, pivot = body_kinematics(Q[:6])
    hub = body.orientnew("H", "Axis", (AZIMUTH, body.z))  # counter-clockwise seen from above
    span = hub.orientnew("L", "Body", (-zeta, -beta, 0), "ZYX")  # lag against rotation, flap up
    centre = pivot.locatenew("hub", HUB_X * body.x + HUB_Y * body.y + HEIGHT * body.z)
    hinge = centre.locatenew("hinge", OFFSET * hub.x)
    return inertial, body, hub, span, origin, hinge


def blade_bodies(model, inertial, span, origin, hinge):
    """The blade as mechanics bodies: a rigid line mass, or two particles on the span axis."""

    def moving_point(name, radius):
        point = hinge.locatenew(name, radius * span.x)
        point.set_vel(inertial, point.pos_from(origin).dt(inertial))
        return point

    if model == "line":
        centre = moving_point("G", STATIC / MASS)
        central = (INERTIA - STATIC**2 / MASS) * (me.outer(span.y, span.y) + me.outer(span.z, span.z))
        return [me.RigidBody("blade", centre, span, MASS, (central, centre))]
    m1, m2, r1, r2 = PARTICLES
    return [me.Particle("p1", moving_point("P1", r1), m1), me.Particle("p2", moving_point("P2", r2), m2)]


def quadratic_part(expr, variables):
    """The exact second-order Taylor term of ``expr`` about ``variables`` = 0.

    Variables not involved in a second derivative are set to zero before differentiating, which
    keeps the expressions small.
    """
    out = sp.S.Zero
    rest = expr
    for i, zi in enumerate(variables):
        first = rest.diff(zi)
        for zj in variables[i:]:
            others = {v: 0 for v in variables if v != zj}
            second = first.xreplace(others).diff(zj).xreplace({zj: 0})
            out += second * zi * zj * (sp.Rational(1, 2) if zj == zi else 1)
        rest = rest.xreplace({zi: 0})
    return out


@functools.cache
def derive(model="line"):
    """Linearised blade equations (M, C, K) as SymPy matrices in psi, Omega and the parameters."""
    inertial, _, _, span, origin, hinge = kinematics()
    kinetic = sum(b.kinetic_energy(inertial) for b in blade_bodies(model, inertial, span, origin, hinge))

    # plain symbols for the expansion; the rotor speed is constant
    n = len(Q)
    qs = sp.symbols(f"q0:{n}")
    us = sp.symbols(f"u0:{n}")
    speeds = [v.diff(T) for v in Q]
    kinetic = kinetic.subs(AZIMUTH.diff(T), OMEGA)
    kinetic = kinetic.xreplace(dict(zip(speeds, us))).xreplace(dict(zip(Q, qs))).xreplace({AZIMUTH: PSI})
    assert not kinetic.atoms(sp.Derivative) and not kinetic.atoms(sp.core.function.AppliedUndef)
    quadratic = quadratic_part(kinetic, qs + us)

    # back to functions of time, psi = Omega t + psi0, and Lagrange's equations of the quadratic Lagrangian
    potential = (K_LAG * qs[LAG] ** 2 + K_FLAP * qs[FLAP] ** 2) / 2
    lagrangian = (quadratic - potential).xreplace(dict(zip(us, speeds))).xreplace(dict(zip(qs, Q)))
    lagrangian = lagrangian.xreplace({PSI: OMEGA * T + PSI0})
    method = me.LagrangesMethod(lagrangian, Q)
    equations = method.form_lagranges_equations()  # d/dt dL/dq' - dL/dq
    dissipation = (C_LAG * speeds[LAG] ** 2 + C_FLAP * speeds[FLAP] ** 2) / 2
    equations += sp.Matrix([dissipation.diff(v) for v in speeds])

    accelerations = sp.symbols(f"a0:{n}")
    equations = me.msubs(equations, dict(zip([v.diff(T) for v in speeds], accelerations)))
    equations = me.msubs(equations, dict(zip(speeds, us)))
    equations = me.msubs(equations, dict(zip(Q, qs)))
    equations = equations.subs(PSI0, PSI - OMEGA * T)
    matrices = [equations.jacobian(v) for v in (accelerations, us, qs)]
    # linear: nothing may depend on the coordinates or on time any more
    allowed = set(ARGUMENTS) | set(PARTICLES) | {PSI}
    assert all(mat.free_symbols <= allowed for mat in matrices)
    return matrices


@functools.cache
def numeric(model="line"):
    return sp.lambdify((PSI, *ARGUMENTS, *PARTICLES), derive(model), "numpy")


def evaluate(psi, values, model="line", particles=(np.nan,) * 4):
    """My (3, 8, 8) array [M, C, K] at azimuth psi (the particles' m1, m2, r1, r2 for that model)."""
    return np.array(numeric(model)(psi, *values, *particles), dtype=float)


def parameter_sets(n=6, seed=20240917):
    """Physically valid random parameters (SI-like magnitudes), in ARGUMENTS order.

    The hub centre lies on either side of the pivot: hub_x, hub_y and hub_height take every sign
    combination among the sets (the last set has the hub on the pivot's vertical, hub_height < 0)."""
    rng = np.random.default_rng(seed)
    sets = []
    for k in range(n):
        omega = rng.uniform(5.0, 50.0)
        mass = rng.uniform(5.0, 200.0)
        inertia = mass * rng.uniform(1.0, 40.0) ** 2 / 3
        static = rng.uniform(0.3, 0.97) * np.sqrt(mass * inertia)
        offset = 0.0 if k == 0 else rng.uniform(0.0, 1.5)
        height = (-1.0) ** (k // 4) * rng.uniform(0.2, 3.0)
        hub = np.array([(-1.0) ** k, (-1.0) ** (k // 2)]) * rng.uniform(0.1, 2.0, 2) * (k != n - 1)
        springs = rng.uniform(0.0, 1.0, 2) * inertia * omega**2 * (k != 1)
        dampers = rng.uniform(0.0, 0.5, 2) * inertia * omega * (k != 1)
        blade = (mass, static, inertia, offset, height, *hub)
        sets.append((omega, *blade, springs[0], dampers[0], springs[1], dampers[1]))
    return sets


AZIMUTHS = 0.1 + 2 * np.pi * np.arange(8) / 8
TRIG = np.array([np.ones_like(AZIMUTHS), *(f(k * AZIMUTHS) for k in (1, 2) for f in (np.cos, np.sin))])


def entry_scales(matrices, omega):
    """The natural scale of every entry, shape (3, n, n), from one parameter set's (azimuths, 3, n, n).

    s_i = sqrt(max over azimuths of M_ii) (kg^(1/2), or kg^(1/2) m for a rotation), so s_i s_j Omega^g
    has the entry's units; times the largest dimensionless entry of that matrix (springs, dampers)."""
    s = np.sqrt(np.abs(np.diagonal(matrices[:, 0], axis1=1, axis2=2)).max(axis=0))
    units = np.array([np.outer(s, s) * omega**g for g in range(3)])
    largest = (np.abs(matrices) / units).max(axis=(0, 2, 3))
    return units * largest[:, None, None]


@pytest.fixture(scope="module")
def comparison():
    """Mine and the project's matrices, shape (sets, azimuths, 3, 8, 8), the project's harmonics and
    the entries' scales (sets, 1, 3, 8, 8)."""
    f = blade_function()
    mine, theirs, harmonics, scales = [], [], [], []
    for values in parameter_sets():
        arr = f(*values)
        harmonics.append(arr)
        theirs.append(np.einsum("ghij,hp->pgij", arr, TRIG))
        mine.append([evaluate(p, values) for p in AZIMUTHS])
        scales.append(entry_scales(np.array(mine[-1]), values[0])[None])
    return np.array(mine), np.array(theirs), np.array(harmonics), np.array(scales)


def test_generated_blade_function_shape():
    values = parameter_sets()[0]
    assert blade_function()(*values).shape == (3, 5, 8, 8)
    keywords = dict(zip(("rotor_speed", "blade_mass", "blade_static_moment"), values[:3]))
    rest = ("blade_inertia", "hinge_offset", "hub_height", "hub_x", "hub_y")
    rest += ("lag_stiffness", "lag_damping", "flap_stiffness", "flap_damping")
    keywords.update(zip(rest, values[3:]))
    np.testing.assert_array_equal(blade_function()(**keywords), blade_function()(*values))


ENTRIES = [(g, i, j) for g in range(3) for i in range(8) for j in range(8)]


@pytest.mark.parametrize(
    ("g", "i", "j"), ENTRIES, ids=[f"{GROUPS[g]}[{COORDS[i]},{COORDS[j]}]" for g, i, j in ENTRIES]
)
def test_entry_matches_generated_code(comparison, g, i, j):
    mine, theirs, harmonics, scales = comparison
    a, b = mine[:, :, g, i, j], theirs[:, :, g, i, j]
    scale = scales[:, :, g, i, j]  # per parameter set, this entry
    error = np.abs(a - b)
    ok = error <= TOLERANCE * scale
    if not ok.all():
        s, p = np.unravel_index(np.argmax(error / scale), error.shape)
        mine_h = np.linalg.lstsq(TRIG.T, a[s], rcond=None)[0]
        pytest.fail(
            f"{GROUPS[g]}[{COORDS[i]}, {COORDS[j]}] differs: parameter set {s}, psi = {AZIMUTHS[p]:.4f}: "
            f"mine {a[s, p]!r}, generated {b[s, p]!r}, "
            f"|diff|/entry scale = {error[s, p] / scale[s, 0]:.3e}\n"
            f"harmonics {HARMONICS}:\n  mine      {mine_h}\n  generated {harmonics[s, g, :, i, j]}"
        )


def test_overall_agreement(comparison):
    """One summary number: the largest difference relative to each entry's scale."""
    mine, theirs, _, scales = comparison
    assert (np.abs(mine - theirs) / scales).max() < TOLERANCE


def test_conventions_of_my_kinematics():
    """The frames follow the conventions: body R_z(chi) R_x(phi) R_y(-theta), span (cb cz, -cb sz, sb)."""
    x, y, z, theta, phi, chi, zeta, beta = Q
    inertial, body, hub, span, _, _ = kinematics()
    c, s = sp.cos, sp.sin
    rz = sp.Matrix([[c(chi), -s(chi), 0], [s(chi), c(chi), 0], [0, 0, 1]])
    rx = sp.Matrix([[1, 0, 0], [0, c(phi), -s(phi)], [0, s(phi), c(phi)]])
    ry = sp.Matrix([[c(-theta), 0, s(-theta)], [0, 1, 0], [-s(-theta), 0, c(-theta)]])
    assert sp.simplify(inertial.dcm(body) - rz * rx * ry) == sp.zeros(3, 3)
    expected = sp.Matrix([c(beta) * c(zeta), -c(beta) * s(zeta), s(beta)])
    assert sp.simplify(span.x.to_matrix(hub) - expected) == sp.zeros(3, 1)
    # the hub x axis at azimuth psi, body undisturbed: (cos psi, sin psi, 0), counter-clockwise from above
    axis = hub.x.to_matrix(inertial).subs({theta: 0, phi: 0, chi: 0})
    assert sp.simplify(axis - sp.Matrix([c(AZIMUTH), s(AZIMUTH), 0])) == sp.zeros(3, 1)
    # nose up, right side down, nose left
    nose = body.x.to_matrix(inertial).subs({phi: 0, chi: 0})
    right = (-body.y).to_matrix(inertial).subs({theta: 0, chi: 0})
    nose_left = body.x.to_matrix(inertial).subs({theta: 0, phi: 0})
    assert nose[2] == s(theta) and right[2] == -s(phi) and nose_left[1] == s(chi)


def test_my_model_is_consistent():
    """Mass matrix symmetric, positive semi-definite, definite on the blade rows; harmonics 0-2 only."""
    mass, _, _ = derive()
    assert (mass - mass.T).applyfunc(sp.expand) == sp.zeros(8, 8)
    psis = 2 * np.pi * np.arange(16) / 16
    for values in parameter_sets():
        samples = np.array([evaluate(p, values) for p in psis])
        for p in range(len(psis)):
            m = samples[p, 0]
            assert np.linalg.eigvalsh(m).min() > -1e-10 * np.abs(m).max()
            assert np.linalg.eigvalsh(m[LAG:, LAG:]).min() > 0
        spectrum = np.abs(np.fft.rfft(samples, axis=0)) / len(psis)
        assert spectrum[3:].max() < 1e-12 * np.abs(samples).max()


def test_line_mass_equals_two_particles():
    """The rigid-body line mass and two particles with the same m, S, I give the same equations."""
    rng = np.random.default_rng(7)
    for _ in range(3):
        m1, m2 = rng.uniform(1.0, 50.0, 2)
        r1, r2 = rng.uniform(0.0, 8.0, 2)
        omega, offset = rng.uniform(5.0, 40.0), rng.uniform(0.0, 1.0)
        hub = rng.uniform(-2.0, 2.0, 3)  # height, x, y
        springs = rng.uniform(0.0, 1e4, 4)
        blade = (m1 + m2, m1 * r1 + m2 * r2, m1 * r1**2 + m2 * r2**2)
        values = (omega, *blade, offset, *hub, *springs)
        for psi in (0.0, 0.7, 2.5):
            line = evaluate(psi, values)
            pair = evaluate(psi, values, "particles", (m1, m2, r1, r2))
            np.testing.assert_allclose(pair, line, rtol=1e-12, atol=1e-12 * np.abs(line).max())


def test_rotating_lag_and_flap_frequencies():
    """nu_lag^2 = e S/I + K_zeta/(I Omega^2), nu_flap^2 = 1 + e S/I + K_beta/(I Omega^2), at any azimuth."""
    mass, damping, stiffness = derive()
    nu_lag = stiffness[LAG, LAG] / (mass[LAG, LAG] * OMEGA**2)
    nu_flap = stiffness[FLAP, FLAP] / (mass[FLAP, FLAP] * OMEGA**2)
    assert sp.simplify(nu_lag - (OFFSET * STATIC / INERTIA + K_LAG / (INERTIA * OMEGA**2))) == 0
    assert sp.simplify(nu_flap - (1 + OFFSET * STATIC / INERTIA + K_FLAP / (INERTIA * OMEGA**2))) == 0
    assert sp.simplify(damping[LAG, LAG] - C_LAG) == 0 and sp.simplify(damping[FLAP, FLAP] - C_FLAP) == 0
    # with the body held still, lag and flap decouple from each other
    assert mass[LAG, FLAP] == mass[FLAP, LAG] == damping[LAG, FLAP] == damping[FLAP, LAG] == 0
    assert stiffness[LAG, FLAP] == stiffness[FLAP, LAG] == 0


def azimuth_mean(expr):
    """Exact azimuth mean of a trigonometric polynomial of degree <= 2 in psi (four samples suffice:
    cos psi, sin psi, cos 2psi, sin 2psi all sum to zero over psi = 0, pi/2, pi, 3pi/2)."""
    return sum(expr.xreplace({PSI: k * sp.pi / 2}) for k in range(4)) / 4


def test_gyroscopic_pitch_roll_coupling():
    """Azimuth mean of the pitch-roll damping terms = +-Omega (I + 2 S e + m e^2), the polar moment.

    The hub's offset from the pivot does not enter: every Omega term of T is bilinear in the blade's
    position from the hub centre, so the offset appears only with the first harmonic of that position."""
    _, damping, _ = derive()
    polar = INERTIA + 2 * STATIC * OFFSET + MASS * OFFSET**2
    assert sp.simplify(azimuth_mean(damping[PITCH, ROLL]) - OMEGA * polar) == 0
    assert sp.simplify(azimuth_mean(damping[ROLL, PITCH]) + OMEGA * polar) == 0
    assert sp.simplify(azimuth_mean(damping[PITCH, PITCH])) == 0
    assert sp.simplify(azimuth_mean(damping[ROLL, ROLL])) == 0
    # and the generated code's constant harmonic agrees
    for values in parameter_sets():
        omega, m, s, inertia, e = values[:5]
        constant = blade_function()(*values)[1, 0]
        expected = omega * (inertia + 2 * s * e + m * e**2)
        np.testing.assert_allclose(constant[PITCH, ROLL], expected, rtol=1e-12)
        np.testing.assert_allclose(constant[ROLL, PITCH], -expected, rtol=1e-12)


def translation_rows_by_hand():
    """The x, y, z rows of (M, C, K), shape (3, 3, 8), worked out by hand.

    A translation's generalised force is the rate of the blade's momentum, so its row of the linear
    equations is d^2/dt^2 of the linear part of the blade's first moment of mass F = int p dm (p the
    position of dm), with psi = Omega t. To first order, in body axes the element at r from the hinge is
    at h + (e + r) u + r (-zeta t + beta z) (hub centre h = (h_x, h_y, h), u = (cos psi, sin psi, 0),
    t = (-sin psi, cos psi, 0): lag against the rotation, flap up), and the body adds the pivot's
    (x, y, z) and the small rotation a x (.) with a = (phi, -theta, chi). With
    F0 = m h + (m e + S) u at rest:
        F = m (x, y, z) + S (-zeta t + beta z) + a x F0,
    a x F0 = (-theta m h - chi F0_y,  chi F0_x - phi m h,  phi F0_y + theta F0_x).
    So the heave row is m z'' + S beta'' + d^2/dt^2 (theta F0_x + phi F0_y): the heave-flap mass
    coupling is +S (flap up raises the blade's first moment as heave does), and a constant yaw gives
    the x, y rows the stiffness d^2/dt^2 of (-chi F0_y, chi F0_x): the centrifugal force
    (m e + S) Omega^2 u turning with the yaw.
    """
    x, y, z, theta, phi, chi, zeta, beta = qs = sp.symbols("q0:8")
    psi = OMEGA * T
    u = sp.Matrix([sp.cos(psi), sp.sin(psi), 0])
    tangent = sp.Matrix([-sp.sin(psi), sp.cos(psi), 0])
    up = sp.Matrix([0, 0, 1])
    f0 = MASS * sp.Matrix([HUB_X, HUB_Y, HEIGHT]) + (MASS * OFFSET + STATIC) * u
    a = sp.Matrix([phi, -theta, chi])
    moment = MASS * sp.Matrix([x, y, z]) + STATIC * (-zeta * tangent + beta * up) + a.cross(f0)
    rows = []
    for k in range(3):
        # F_k = sum_j c_j(t) q_j: F_k'' = c q'' + 2 c' q' + c'' q
        c = [moment[k].diff(q) for q in qs]
        rows.append([c, [2 * cj.diff(T) for cj in c], [cj.diff(T, 2) for cj in c]])
    return sp.Matrix(
        [[rows[k][g][j].subs(T, PSI / OMEGA) for j in range(8)] for g in range(3) for k in range(3)]
    )


def test_translation_rows_are_newton_for_the_blade_centre_of_mass():
    """The x, y, z rows of M, C, K equal the hand derivation (translation_rows_by_hand), exactly in my
    derivation and within the tolerance in the generated code."""
    hand = translation_rows_by_hand()  # rows: (M x, M y, M z, C x, ..., K z)
    mine = sp.Matrix.vstack(*(matrix[:3, :] for matrix in derive()))
    assert (mine - hand).applyfunc(sp.expand) == sp.zeros(9, 8)
    # the heave row alone, as in the brief: heave-flap mass coupling +S, nothing on lag or yaw
    mass = derive()[0]
    assert sp.expand(mass[Z, FLAP] - STATIC) == 0 and sp.expand(mass[Z, Z] - MASS) == 0
    assert mass[Z, LAG] == mass[Z, YAW] == 0
    f = sp.lambdify((PSI, *ARGUMENTS), hand, "numpy")
    for values in parameter_sets():
        generated_rows = np.einsum("ghij,hp->pgij", blade_function()(*values), TRIG)[:, :, :3, :]
        mine_rows = np.array([evaluate(p, values) for p in AZIMUTHS])
        scale = entry_scales(mine_rows, values[0])[None, :, :3, :]
        by_hand = np.array([np.reshape(np.array(f(p, *values), dtype=float), (3, 3, 8)) for p in AZIMUTHS])
        assert (np.abs(generated_rows - by_hand) <= TOLERANCE * scale).all()


def test_yaw_lag_and_yaw_inertia():
    """Mass entries of yaw with lag and with itself, worked out by hand.

    At rest the element at r from the hinge is at p = h + (e + r) u from the pivot (h = (h_x, h_y, h),
    u = (cos psi, sin psi, 0), t = z x u). A yaw rate moves it by chi' z x p = chi' ((-h_y, h_x, 0) +
    (e + r) t); a lag rate (against the rotation) by -zeta' r t. So
        T = 1/2 int |chi' z x p - zeta' r t|^2 dm
          = 1/2 chi'^2 int |z x p|^2 dm - chi' zeta' int r (e + r + h_x cos psi + h_y sin psi) dm + ...
    M[yaw, lag] = -(I + e S) - S (h_x cos psi + h_y sin psi): a yaw rate acts on the blade like a
    lag rate of the opposite sign, with the blade's lag inertia about the shaft I + e S; and
    M[yaw, yaw] = int |z x p|^2 dm = I + 2 e S + m e^2 + m (h_x^2 + h_y^2)
                  + 2 (m e + S)(h_x cos psi + h_y sin psi), the polar moment about the pivot's vertical.
    """
    mass = derive()[0]
    cos, sin = sp.cos(PSI), sp.sin(PSI)
    yaw_lag = -(INERTIA + OFFSET * STATIC) - STATIC * (HUB_X * cos + HUB_Y * sin)
    polar = INERTIA + 2 * OFFSET * STATIC + MASS * OFFSET**2
    yaw_yaw = (
        polar + MASS * (HUB_X**2 + HUB_Y**2) + 2 * (MASS * OFFSET + STATIC) * (HUB_X * cos + HUB_Y * sin)
    )
    assert sp.expand(mass[YAW, LAG] - yaw_lag) == 0 and sp.expand(mass[LAG, YAW] - yaw_lag) == 0
    assert sp.expand(mass[YAW, YAW] - yaw_yaw) == 0
    # the generated harmonics (1, cos psi, sin psi, ...)
    for values in parameter_sets():
        omega, m, s, inertia, e, _, hx, hy = values[:8]
        arr = blade_function()(*values)[0]
        scale = inertia + m * (e**2 + hx**2 + hy**2)
        expected = np.array([-(inertia + e * s), -s * hx, -s * hy, 0.0, 0.0])
        np.testing.assert_allclose(arr[:, YAW, LAG], expected, rtol=0, atol=TOLERANCE * scale)
        np.testing.assert_allclose(arr[:, LAG, YAW], expected, rtol=0, atol=TOLERANCE * scale)
        expected = [
            inertia + 2 * e * s + m * e**2 + m * (hx**2 + hy**2),
            2 * (m * e + s) * hx,
            2 * (m * e + s) * hy,
            0.0,
            0.0,
        ]
        np.testing.assert_allclose(arr[:, YAW, YAW], expected, rtol=0, atol=TOLERANCE * scale)


# ---------------------------------------------------------------------------------------------------
# 2. The rigid body's mass matrix

RIGID = sp.symbols("M J_xx J_yy J_zz J_xy J_xz J_yz c_x c_y c_z", real=True)
RIGID_NAMES = (
    "mass",
    "inertia_xx",
    "inertia_yy",
    "inertia_zz",
    "inertia_xy",
    "inertia_xz",
    "inertia_yz",
    "centre_x",
    "centre_y",
    "centre_z",
)


def speeds_and_coordinates():
    """Plain symbols for the six body coordinates and their speeds, and the replacement that puts them
    in place of mechanics' functions of time."""
    coordinates = me.dynamicsymbols("x y z theta phi chi")
    qs, us = sp.symbols("q0:6"), sp.symbols("u0:6")
    speeds = [v.diff(T) for v in coordinates]
    return coordinates, qs, us, {**dict(zip(speeds, us)), **dict(zip(coordinates, qs))}


@functools.cache
def derive_rigid_body():
    """Mass matrix of the rigid body: Hessian of mechanics' kinetic energy in the speeds, at rest."""
    mass, jxx, jyy, jzz, jxy, jxz, jyz, cx, cy, cz = RIGID
    coordinates, qs, us, plain = speeds_and_coordinates()
    inertial, body, origin, pivot = body_kinematics(coordinates)
    centre = pivot.locatenew("C", cx * body.x + cy * body.y + cz * body.z)
    centre.set_vel(inertial, centre.pos_from(origin).dt(inertial))
    tensor = me.inertia(body, jxx, jyy, jzz, jxy, jyz, jxz)
    # the arguments are the tensor's entries (whatever sign convention for products of inertia)
    assert tensor.to_matrix(body) == sp.Matrix([[jxx, jxy, jxz], [jxy, jyy, jyz], [jxz, jyz, jzz]])
    rigid = me.RigidBody("body", centre, body, mass, (tensor, centre))
    kinetic = me.msubs(rigid.kinetic_energy(inertial), plain)
    hessian = sp.hessian(kinetic, us).xreplace(dict.fromkeys(qs, 0))
    return hessian.applyfunc(sp.expand)


def cross_matrix(v):
    """[v]x, the matrix of w -> v x w."""
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


#: w = ROTATION @ (x', y', z', theta', phi', chi'): roll about +x, pitch about -y, yaw about +z
ROTATION = np.array([[0, 0, 0, 0, 1, 0], [0, 0, 0, -1, 0, 0], [0, 0, 0, 0, 0, 1]], dtype=float)


def point_motion(p):
    """(3, 6): the first-order motion of the body point p (from the pivot) per body coordinate,
    v = (x', y', z') + w x p = (x', y', z') - p x w."""
    return np.hstack([np.eye(3), np.zeros((3, 3))]) - cross_matrix(p) @ ROTATION


def rigid_body_by_hand(mass, jxx, jyy, jzz, jxy, jxz, jyz, cx, cy, cz):
    """T = 1/2 M |v_c|^2 + 1/2 w.J w: mass matrix A' M A + G' J G (A: centre motion, G: ROTATION)."""
    tensor = np.array([[jxx, jxy, jxz], [jxy, jyy, jyz], [jxz, jyz, jzz]])
    motion = point_motion(np.array([cx, cy, cz]))
    return mass * motion.T @ motion + ROTATION.T @ tensor @ ROTATION


def rigid_parameter_sets(n=5, seed=31):
    """Physically valid rigid bodies: positive mass, a positive definite inertia tensor obeying the
    triangle inequalities (principal moments of a real mass distribution, turned), centre anywhere."""
    rng = np.random.default_rng(seed)
    sets = []
    for _ in range(n):
        mass = rng.uniform(500.0, 1e4)
        second = rng.uniform(0.2, 2.0, 3) ** 2 * mass  # int x^2 dm, ... along principal axes
        principal = second.sum() - second  # J_1 = int (y^2 + z^2) dm, ...
        turn, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        j = turn @ np.diag(principal) @ turn.T
        centre = rng.uniform(-2.0, 2.0, 3)
        sets.append((mass, j[0, 0], j[1, 1], j[2, 2], j[0, 1], j[0, 2], j[1, 2], *centre))
    return sets


def test_rigid_body_mass_matches_generated_code():
    mine = sp.lambdify(RIGID, derive_rigid_body(), "numpy")
    for values in rigid_parameter_sets():
        theirs = generated("rigid_body_mass")(**dict(zip(RIGID_NAMES, values)))
        assert theirs.shape == (6, 6)
        ours = np.array(mine(*values), dtype=float)
        np.testing.assert_allclose(rigid_body_by_hand(*values), ours, rtol=0, atol=1e-13 * np.abs(ours).max())
        # per-entry scale sqrt(M_ii M_jj) (positive definite: |M_ij| <= it)
        d = np.sqrt(np.diag(ours))
        assert (np.abs(theirs - ours) <= TOLERANCE * np.outer(d, d)).all(), (
            f"rigid body: mine\n{ours}\ngenerated\n{theirs}"
        )
        assert np.linalg.eigvalsh(theirs).min() > 0


def test_rigid_body_simple_cases():
    """By hand: centre at the pivot, principal axes = body axes: diag(M, M, M, J_yy, J_xx, J_zz) (pitch is
    about y, roll about x); a product J_xy gives M[pitch, roll] = -J_xy (w_y = -theta'); a point mass M at
    c = (c_x, 0, c_z): pitch inertia M (c_x^2 + c_z^2), x-pitch coupling -M c_z (nose up moves a centre
    above the pivot backwards), z-pitch M c_x (and the nose forwards up)."""
    f = generated("rigid_body_mass")
    zero = dict.fromkeys(RIGID_NAMES, 0.0)
    got = f(**{**zero, "mass": 3.0, "inertia_xx": 5.0, "inertia_yy": 7.0, "inertia_zz": 11.0})
    np.testing.assert_array_equal(got, np.diag([3.0, 3.0, 3.0, 7.0, 5.0, 11.0]))
    got = f(**{**zero, "inertia_xx": 5.0, "inertia_yy": 7.0, "inertia_xy": 2.0})
    assert got[PITCH, ROLL] == got[ROLL, PITCH] == -2.0
    got = f(**{**zero, "mass": 3.0, "centre_x": 2.0, "centre_z": 0.5})
    assert got[PITCH, PITCH] == 3.0 * (4.0 + 0.25) and got[X, PITCH] == -1.5 and got[Z, PITCH] == 6.0
    assert got[ROLL, ROLL] == 3.0 * 0.25 and got[YAW, YAW] == 3.0 * 4.0 and got[Y, YAW] == 6.0


# ---------------------------------------------------------------------------------------------------
# 3. A gear leg's stiffness matrix

LEG = sp.symbols("p_x p_y p_z k_x k_y k_z", real=True)
LEG_NAMES = ("position_x", "position_y", "position_z", "along_x", "along_y", "along_z")


@functools.cache
def derive_leg():
    """Hessian, at rest, of V = 1/2 sum k_a u_a^2, u the displacement of a mechanics point of the body."""
    px, py, pz, kx, ky, kz = LEG
    coordinates, qs, _, plain = speeds_and_coordinates()
    inertial, body, origin, pivot = body_kinematics(coordinates)
    point = pivot.locatenew("P", px * body.x + py * body.y + pz * body.z)
    rest = px * inertial.x + py * inertial.y + pz * inertial.z
    displacement = point.pos_from(origin) - rest
    potential = sum(k * displacement.dot(a) ** 2 for k, a in zip((kx, ky, kz), inertial)) / 2
    potential = me.msubs(potential, plain)
    return sp.hessian(potential, qs).xreplace(dict.fromkeys(qs, 0)).applyfunc(sp.expand)


def leg_by_hand(px, py, pz, kx, ky, kz):
    """u = A q to first order (A = point_motion(p)), V = 1/2 q' A' diag(k) A q."""
    motion = point_motion(np.array([px, py, pz]))
    return motion.T @ np.diag([kx, ky, kz]) @ motion


def test_leg_matrix_matches_generated_code():
    mine = sp.lambdify(LEG, derive_leg(), "numpy")
    rng = np.random.default_rng(5)
    for _ in range(6):
        position = rng.uniform(-4.0, 4.0, 3)
        springs = rng.uniform(1e4, 1e6, 3)
        values = (*position, *springs)
        theirs = generated("leg_matrix")(**dict(zip(LEG_NAMES, values)))
        assert theirs.shape == (6, 6)
        ours = np.array(mine(*values), dtype=float)
        # diagonal scale: |K_ij| <= sqrt(K_ii K_jj) for this positive semi-definite matrix, but a
        # diagonal entry may vanish, so the scale is max(k) * (1 or |p|) per coordinate
        d = np.sqrt(springs.max()) * np.array([1.0] * 3 + [np.linalg.norm(position)] * 3)
        np.testing.assert_allclose(leg_by_hand(*values), ours, rtol=0, atol=1e-13 * np.abs(ours).max())
        assert (np.abs(theirs - ours) <= TOLERANCE * np.outer(d, d)).all(), (
            f"leg: mine\n{ours}\ngenerated\n{theirs}"
        )


def test_symmetric_legs():
    """By hand, four equal legs at (+-a, +-b, -c) (c below the pivot): nose up by theta moves a foot by
    theta (c, 0, x_i) (-theta y x p = theta (-p_z, 0, p_x)), right side down by phi by phi (0, c, y_i), yaw by
    chi by chi (-y_i, x_i, 0). Summed over the legs every term odd in x_i or y_i cancels:
        K = 4 [[k_x, ., ., k_x c, ., .], [., k_y, ., ., k_y c, .], [., ., k_z, ., ., .],
               [k_x c, ., ., k_x c^2 + k_z a^2, ., .], [., k_y c, ., ., k_y c^2 + k_z b^2, .],
               [., ., ., ., ., k_x b^2 + k_y a^2]]
    and with the feet level with the pivot (c = 0) it is diagonal."""
    f = generated("leg_matrix")
    a, b, c = 1.7, 1.1, 0.9
    kx, ky, kz = 2e5, 3e5, 7e5
    for depth in (c, 0.0):
        total = sum(
            f(position_x=sx * a, position_y=sy * b, position_z=-depth, along_x=kx, along_y=ky, along_z=kz)
            for sx, sy in itertools.product((-1, 1), repeat=2)
        )
        expected = np.diag(
            [kx, ky, kz, kx * depth**2 + kz * a**2, ky * depth**2 + kz * b**2, kx * b**2 + ky * a**2]
        )
        expected[X, PITCH] = expected[PITCH, X] = kx * depth
        expected[Y, ROLL] = expected[ROLL, Y] = ky * depth
        np.testing.assert_allclose(total, 4 * expected, rtol=1e-14, atol=1e-14 * kz * a**2)
    assert np.count_nonzero(total - np.diag(np.diag(total))) == 0


# ---------------------------------------------------------------------------------------------------
# 4. Damper rods: gradients of the length at rest

ROD = sp.symbols("e e_m s s_x s_y s_z t_x t_y t_z", real=True)
ROD_TO_HUB_NAMES = ("hinge_offset", "start_x", "start_y", "start_z", "end_x", "end_y", "end_z")
ROD_TO_BLADE_NAMES = ("hinge_offset", "end_hinge_offset", "spacing", *ROD_TO_HUB_NAMES[1:])


@functools.cache
def derive_rods():
    """Exact gradients of my rod lengths: (to the hub: (lag, flap)), (to blade m: (lag_k, flap_k, lag_m,
    flap_m)), at rest, from mechanics frames: blade k's hub axes, blade m's (``spacing`` ahead,
    counter-clockwise), and each blade's own axes (span, leading edge, up) turned by lag and flap like
    the span (R_z(-zeta) R_y(-beta))."""
    offset, end_offset, spacing, sx, sy, sz, tx, ty, tz = ROD
    angles = sp.symbols("zeta_k beta_k zeta_m beta_m", real=True)
    hub_k = me.ReferenceFrame("Hk")
    hub_m = hub_k.orientnew("Hm", "Axis", (spacing, hub_k.z))
    blade_k = hub_k.orientnew("Lk", "Body", (-angles[0], -angles[1], 0), "ZYX")
    blade_m = hub_m.orientnew("Lm", "Body", (-angles[2], -angles[3], 0), "ZYX")
    centre = me.Point("rotor centre")
    start = centre.locatenew("start", offset * hub_k.x + sx * blade_k.x + sy * blade_k.y + sz * blade_k.z)
    on_hub = centre.locatenew("on hub", tx * hub_k.x + ty * hub_k.y + tz * hub_k.z)
    on_blade = centre.locatenew(
        "on blade", end_offset * hub_m.x + tx * blade_m.x + ty * blade_m.y + tz * blade_m.z
    )
    rest = dict.fromkeys(angles, 0)
    to_hub = start.pos_from(on_hub).magnitude()
    to_blade = start.pos_from(on_blade).magnitude()
    return (
        sp.Matrix([to_hub.diff(v).xreplace(rest) for v in angles[:2]]),
        sp.Matrix([to_blade.diff(v).xreplace(rest) for v in angles]),
    )


def rod_by_differences(offset, end_offset, spacing, start, end, to_hub):
    """The gradient by central differences at 50 digits of the length written with explicit rotation
    matrices (position of a blade point: R_z(azimuth) ((hinge, 0, 0) + R_z(-lag) R_y(-flap) r))."""
    mp = mpmath

    def rz(a):
        return mp.matrix([[mp.cos(a), -mp.sin(a), 0], [mp.sin(a), mp.cos(a), 0], [0, 0, 1]])

    def ry(a):
        return mp.matrix([[mp.cos(a), 0, mp.sin(a)], [0, 1, 0], [-mp.sin(a), 0, mp.cos(a)]])

    def on_blade(azimuth, hinge, lag, flap, r):
        r = mp.matrix([mp.mpf(float(v)) for v in r])
        return rz(azimuth) * (mp.matrix([mp.mpf(float(hinge)), 0, 0]) + rz(-lag) * ry(-flap) * r)

    def length(angles):
        a = on_blade(0, offset, angles[0], angles[1], start)
        if to_hub:
            b = mp.matrix([mp.mpf(float(v)) for v in end])
        else:
            b = on_blade(mp.mpf(float(spacing)), end_offset, angles[2], angles[3], end)
        return mp.norm(a - b)

    n = 2 if to_hub else 4
    out = []
    with mp.workdps(50):
        step = mp.mpf("1e-20")
        for i in range(n):
            delta = [step if k == i else 0 for k in range(n)]
            out.append((length(delta) - length([-d for d in delta])) / (2 * step))
    return np.array([float(v) for v in out])


def rod_geometries(n=6, seed=11):
    """Random rod geometry: hinge offsets, blade spacing, points on the blades and the hub (m)."""
    rng = np.random.default_rng(seed)
    for _ in range(n):
        offsets = rng.uniform(0.0, 0.6, 2)
        spacing = 2 * np.pi / rng.integers(2, 7)
        start = rng.uniform(-0.4, 0.4, 3) + [rng.uniform(0.1, 1.0), 0.0, 0.0]
        end = rng.uniform(-0.4, 0.4, 3) + [rng.uniform(0.1, 1.0), 0.0, 0.0]
        yield offsets, spacing, start, end


def test_rod_gradients_match_generated_code():
    to_hub, to_blade = (sp.lambdify(ROD, g, "numpy") for g in derive_rods())
    for (offset, end_offset), spacing, start, end in rod_geometries():
        values = (offset, end_offset, spacing, *start, *end)
        hub_end = np.array(end) + [offset + 0.5, 0.0, 0.0]  # a hub point a little further out
        hub_values = (offset, end_offset, spacing, *start, *hub_end)
        mine_hub = np.array(to_hub(*hub_values), dtype=float).ravel()
        mine_blade = np.array(to_blade(*values), dtype=float).ravel()
        theirs_hub = generated("rod_to_hub")(**dict(zip(ROD_TO_HUB_NAMES, (offset, *start, *hub_end))))
        theirs_blade = generated("rod_to_blade")(**dict(zip(ROD_TO_BLADE_NAMES, values)))
        assert theirs_hub.shape == (2,) and theirs_blade.shape == (4,)
        # the gradient is a lever arm: its scale is the distance of the attachment points from the hinges
        scale = np.linalg.norm(start) + np.linalg.norm(end) + offset + end_offset
        differences_hub = rod_by_differences(offset, end_offset, spacing, start, hub_end, to_hub=True)
        differences_blade = rod_by_differences(offset, end_offset, spacing, start, end, to_hub=False)
        np.testing.assert_allclose(mine_hub, differences_hub, rtol=0, atol=1e-14 * scale)
        np.testing.assert_allclose(mine_blade, differences_blade, rtol=0, atol=1e-14 * scale)
        np.testing.assert_allclose(theirs_hub, mine_hub, rtol=0, atol=TOLERANCE * scale)
        np.testing.assert_allclose(theirs_blade, mine_blade, rtol=0, atol=TOLERANCE * scale)


def test_rod_symmetries():
    """By hand.

    Mirror-symmetric rod between two blades (equal hinge offsets, the same distance along, opposite
    leading-edge offsets, the same height): the mirror in the plane bisecting the blades swaps them, maps
    blade k's leading edge to blade m's trailing edge, so lag_k to -lag_m and flap_k to flap_m: the lag
    gradients are equal and opposite (a purely differential lag motion), the flap gradients equal.

    Collective part: both blades lagging by zeta turn about their hinges H by -zeta, which is a rigid turn
    about the shaft (length unchanged) plus a shift zeta z x H of each blade. So the sum of the lag
    gradients is d . (z x (H_k - H_m)), d the unit vector from blade m's point to blade k's. It vanishes
    for the mirror-symmetric rod (d and H_k - H_m both normal to the mirror plane), for zero hinge offsets,
    and whenever the rod is parallel to the hinges' chord (two blades, spacing pi, points at opposite
    leading-edge offsets); different distances along otherwise give a nonzero sum.

    An in-plane rod (all heights zero) has zero flap gradients: flap moves the points vertically, square
    to the rod. A rod from a blade point at r along the span to the hub point r further out from the
    hinge's radius but d behind (-d in y: tangential) shortens by r per unit lag (lag moves the point by
    -r zeta in y): (-r, 0).
    """
    to_blade, to_hub = generated("rod_to_blade"), generated("rod_to_hub")
    rng = np.random.default_rng(3)
    for _ in range(5):
        offset, along = rng.uniform(0.1, 0.5), rng.uniform(0.1, 1.0)
        edge, height = rng.uniform(0.02, 0.3), rng.uniform(-0.2, 0.2)
        spacing = 2 * np.pi / rng.integers(3, 7)
        common = dict(hinge_offset=offset, end_hinge_offset=offset, spacing=spacing)
        scale = along + offset
        for sign in (1, -1):
            g = to_blade(
                **common,
                start_x=along,
                start_y=sign * edge,
                start_z=height,
                end_x=along,
                end_y=-sign * edge,
                end_z=height,
            )
            assert abs(g[0] + g[2]) <= 1e-14 * scale and abs(g[1] - g[3]) <= 1e-14 * scale
            assert abs(g[0]) > 1e-3 * scale
        # different distances along: a collective part, d . (z x (H_k - H_m))
        for end_offset, farther in ((offset, 1.5 * along), (0.5 * offset, along)):
            start, end = np.array([along, edge, height]), np.array([farther, -edge, height])
            turn = np.array(
                [[np.cos(spacing), -np.sin(spacing), 0], [np.sin(spacing), np.cos(spacing), 0], [0, 0, 1]]
            )
            hinge_k, hinge_m = np.array([offset, 0.0, 0.0]), turn @ [end_offset, 0.0, 0.0]
            rod = hinge_k + start - (hinge_m + turn @ end)
            collective = rod @ np.cross([0.0, 0.0, 1.0], hinge_k - hinge_m) / np.linalg.norm(rod)
            g = to_blade(
                hinge_offset=offset,
                end_hinge_offset=end_offset,
                spacing=spacing,
                **dict(zip(("start_x", "start_y", "start_z"), start)),
                **dict(zip(("end_x", "end_y", "end_z"), end)),
            )
            assert abs(g[0] + g[2] - collective) <= 1e-14 * scale
            assert abs(collective) > 1e-3 * scale
        # in plane: no flap gradient, to a blade or to the hub
        start = dict(start_x=along, start_y=edge, start_z=0.0)
        g = to_blade(**common, **start, end_x=rng.uniform(0.1, 1.0), end_y=rng.uniform(-0.3, 0.3), end_z=0.0)
        assert abs(g[1]) <= 1e-14 * scale and abs(g[3]) <= 1e-14 * scale
        g = to_hub(hinge_offset=offset, **start, end_x=offset + 2 * along, end_y=-edge, end_z=0.0)
        assert abs(g[1]) <= 1e-14 * scale
        # tangential rod to the hub
        g = to_hub(
            hinge_offset=offset,
            start_x=along,
            start_y=0.0,
            start_z=0.0,
            end_x=offset + along,
            end_y=-edge,
            end_z=0.0,
        )
        np.testing.assert_allclose(g, [-along, 0.0], rtol=1e-14, atol=1e-14 * scale)
