"""A second, independent derivation of one blade's linearised equations, compared with the generated code.

What is derived
    The linearised equations M(psi) q'' + C(psi) q' + K(psi) q = 0 of ONE blade on a moving body, for
    q = [x, y, theta, phi, zeta, beta] (hub translation, pitch nose up, roll right side down, lag against
    the rotation, flap up), as exact SymPy functions of the azimuth psi, the rotor speed Omega and the
    blade parameters. Only the blade's contribution is kept: no body mass, springs or dampers, no
    gravity, no aerodynamics; forcing-only terms (independent of q) are dropped.

How
    With :mod:`sympy.physics.mechanics`: reference frames for the body (R_x(phi) R_y(-theta)), the hub
    (about the body's z axis by the prescribed azimuth psi(t), with psi' = Omega) and the blade span
    (R_z(-zeta) R_y(-beta) in the hub frame), points for the hinge and the blade, and the blade itself
    either as a ``RigidBody`` (mass m, centre of mass at S/m along the span, central inertia I - S^2/m
    about the two axes perpendicular to the span and zero about it) or as two ``Particle`` objects on the
    span axis. The kinetic energy comes from mechanics; its exact second-order Taylor part about
    q = q' = 0 is taken (constant and linear parts only force), the root springs are added as a
    potential, ``LagrangesMethod`` forms d/dt dL/dq' - dL/dq for this quadratic Lagrangian with the
    explicit time dependence psi = Omega t + psi0, and the root dampers enter through the Rayleigh
    function D = (C_zeta zeta'^2 + C_beta beta'^2)/2. M, C, K are then the Jacobians with respect to
    q'', q', q.

Why it is independent
    Nothing is imported from ``groundres.symbolic.derive``; the kinematics are built from mechanics'
    frames and points rather than from hand-written position vectors, the blade is a rigid body (or
    two particles) rather than a line integral, and the equations come from ``LagrangesMethod``. Only
    the generated NumPy function (``blade_function``) is compared, entry by entry, at several random
    physically valid parameter sets and azimuths. The derivation is also checked against textbook
    results: the rotating lag and flap frequencies and the gyroscopic pitch-roll coupling.
"""

import functools

import numpy as np
import pytest
import sympy as sp
from sympy.physics import mechanics as me

from groundres.symbolic.codegen import blade_function

COORDS = ("x", "y", "theta", "phi", "zeta", "beta")
GROUPS = ("M", "C", "K")
HARMONICS = ("1", "cos psi", "sin psi", "cos 2psi", "sin 2psi")

OMEGA, PSI, PSI0 = sp.symbols("Omega psi psi0", real=True)
MASS, STATIC, INERTIA, OFFSET, HEIGHT, K_LAG, C_LAG, K_FLAP, C_FLAP = sp.symbols(
    "m S I e h K_zeta C_zeta K_beta C_beta", real=True
)
#: Same order as the arguments of the generated blade function.
ARGUMENTS = (OMEGA, MASS, STATIC, INERTIA, OFFSET, HEIGHT, K_LAG, C_LAG, K_FLAP, C_FLAP)
#: Two-particle model: masses m1, m2 at r1, r2 from the hinge on the span axis.
PARTICLES = sp.symbols("m1 m2 r1 r2", positive=True)

T = me.dynamicsymbols._t
Q = me.dynamicsymbols(" ".join(COORDS))
AZIMUTH = me.dynamicsymbols("psi_t")  # psi(t), prescribed: psi' = Omega, psi'' = 0


def kinematics():
    """Frames and points: body, hub, blade span; the hinge point; the inertial origin."""
    x, y, theta, phi, zeta, beta = Q
    inertial = me.ReferenceFrame("N")
    body = inertial.orientnew("B", "Body", (phi, -theta, 0), "XYZ")  # R_x(phi) R_y(-theta)
    hub = body.orientnew("H", "Axis", (AZIMUTH, body.z))  # counter-clockwise seen from above
    span = hub.orientnew("L", "Body", (-zeta, -beta, 0), "ZYX")  # lag against rotation, flap up
    origin = me.Point("O")
    origin.set_vel(inertial, 0)
    hinge = origin.locatenew("hinge", x * inertial.x + y * inertial.y + HEIGHT * body.z + OFFSET * hub.x)
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
    qs = sp.symbols("q0:6")
    us = sp.symbols("u0:6")
    speeds = [v.diff(T) for v in Q]
    kinetic = kinetic.subs(AZIMUTH.diff(T), OMEGA)
    kinetic = kinetic.xreplace(dict(zip(speeds, us))).xreplace(dict(zip(Q, qs))).xreplace({AZIMUTH: PSI})
    assert not kinetic.atoms(sp.Derivative) and not kinetic.atoms(sp.core.function.AppliedUndef)
    quadratic = quadratic_part(kinetic, qs + us)

    # back to functions of time, psi = Omega t + psi0, and Lagrange's equations of the quadratic Lagrangian
    potential = (K_LAG * qs[4] ** 2 + K_FLAP * qs[5] ** 2) / 2
    lagrangian = (quadratic - potential).xreplace(dict(zip(us, speeds))).xreplace(dict(zip(qs, Q)))
    lagrangian = lagrangian.xreplace({PSI: OMEGA * T + PSI0})
    method = me.LagrangesMethod(lagrangian, Q)
    equations = method.form_lagranges_equations()  # d/dt dL/dq' - dL/dq
    dissipation = (C_LAG * speeds[4] ** 2 + C_FLAP * speeds[5] ** 2) / 2
    equations += sp.Matrix([dissipation.diff(v) for v in speeds])

    accelerations = sp.symbols("a0:6")
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
    """My (3, 6, 6) array [M, C, K] at azimuth psi (the particles' m1, m2, r1, r2 for that model)."""
    return np.array(numeric(model)(psi, *values, *particles), dtype=float)


def parameter_sets(n=4, seed=20240917):
    """Physically valid random parameters (SI-like magnitudes), in ARGUMENTS order."""
    rng = np.random.default_rng(seed)
    sets = []
    for k in range(n):
        omega = rng.uniform(5.0, 50.0)
        mass = rng.uniform(5.0, 200.0)
        inertia = mass * rng.uniform(1.0, 40.0) ** 2 / 3
        static = rng.uniform(0.3, 0.97) * np.sqrt(mass * inertia)
        offset = 0.0 if k == 0 else rng.uniform(0.0, 1.5)
        height = rng.uniform(-3.0, 3.0)
        springs = rng.uniform(0.0, 1.0, 2) * inertia * omega**2 * (k != 1)
        dampers = rng.uniform(0.0, 0.5, 2) * inertia * omega * (k != 1)
        blade = (mass, static, inertia, offset, height)
        sets.append((omega, *blade, springs[0], dampers[0], springs[1], dampers[1]))
    return sets


AZIMUTHS = 0.1 + 2 * np.pi * np.arange(8) / 8
TRIG = np.array([np.ones_like(AZIMUTHS), *(f(k * AZIMUTHS) for k in (1, 2) for f in (np.cos, np.sin))])


@pytest.fixture(scope="module")
def comparison():
    """Mine and the project's matrices, shape (sets, azimuths, 3, 6, 6), and the project's harmonics."""
    f = blade_function()
    mine, theirs, harmonics = [], [], []
    for values in parameter_sets():
        arr = f(*values)
        harmonics.append(arr)
        theirs.append(np.einsum("ghij,hp->pgij", arr, TRIG))
        mine.append([evaluate(p, values) for p in AZIMUTHS])
    return np.array(mine), np.array(theirs), np.array(harmonics)


ENTRIES = [(g, i, j) for g in range(3) for i in range(6) for j in range(6)]


@pytest.mark.parametrize(
    ("g", "i", "j"), ENTRIES, ids=[f"{GROUPS[g]}[{COORDS[i]},{COORDS[j]}]" for g, i, j in ENTRIES]
)
def test_entry_matches_generated_code(comparison, g, i, j):
    mine, theirs, harmonics = comparison
    a, b = mine[:, :, g, i, j], theirs[:, :, g, i, j]
    scale = np.abs(mine[:, :, g]).max(axis=(1, 2, 3))[:, None]  # per parameter set, this matrix
    error = np.abs(a - b)
    ok = error <= 1e-10 * np.abs(a) + 1e-12 * scale
    if not ok.all():
        s, p = np.unravel_index(np.argmax(error / scale), error.shape)
        mine_h = np.linalg.lstsq(TRIG.T, a[s], rcond=None)[0]
        pytest.fail(
            f"{GROUPS[g]}[{COORDS[i]}, {COORDS[j]}] differs: parameter set {s}, psi = {AZIMUTHS[p]:.4f}: "
            f"mine {a[s, p]!r}, generated {b[s, p]!r}, "
            f"|diff|/matrix scale = {error[s, p] / scale[s, 0]:.3e}\n"
            f"harmonics {HARMONICS}:\n  mine      {mine_h}\n  generated {harmonics[s, g, :, i, j]}"
        )


def test_overall_agreement(comparison):
    """One summary number: the largest difference relative to each matrix's scale."""
    mine, theirs, _ = comparison
    scale = np.abs(mine).max(axis=(1, 3, 4))[:, None, :, None, None]
    assert (np.abs(mine - theirs) / scale).max() < 1e-12


def test_conventions_of_my_kinematics():
    """The frames follow the brief: body R_x(phi) R_y(-theta), span (cb cz, -cb sz, sb) in the hub."""
    x, y, theta, phi, zeta, beta = Q
    inertial, body, hub, span, _, _ = kinematics()
    c, s = sp.cos, sp.sin
    rx = sp.Matrix([[1, 0, 0], [0, c(phi), -s(phi)], [0, s(phi), c(phi)]])
    ry = sp.Matrix([[c(-theta), 0, s(-theta)], [0, 1, 0], [-s(-theta), 0, c(-theta)]])
    assert sp.simplify(inertial.dcm(body) - rx * ry) == sp.zeros(3, 3)
    expected = sp.Matrix([c(beta) * c(zeta), -c(beta) * s(zeta), s(beta)])
    assert sp.simplify(span.x.to_matrix(hub) - expected) == sp.zeros(3, 1)
    # the hub x axis at azimuth psi, body undisturbed: (cos psi, sin psi, 0), counter-clockwise from above
    axis = hub.x.to_matrix(inertial).subs({theta: 0, phi: 0})
    assert sp.simplify(axis - sp.Matrix([c(AZIMUTH), s(AZIMUTH), 0])) == sp.zeros(3, 1)
    # nose up and right side down
    nose = body.x.to_matrix(inertial).subs(phi, 0)
    right = (-body.y).to_matrix(inertial).subs(theta, 0)
    assert nose[2] == s(theta) and right[2] == -s(phi)


def test_my_model_is_consistent():
    """Mass matrix symmetric, positive semi-definite, definite on the blade rows; harmonics 0-2 only."""
    mass, _, _ = derive()
    assert sp.simplify(mass - mass.T) == sp.zeros(6, 6)
    psis = 2 * np.pi * np.arange(16) / 16
    for values in parameter_sets():
        samples = np.array([evaluate(p, values) for p in psis])
        for p in range(len(psis)):
            m = samples[p, 0]
            assert np.linalg.eigvalsh(m).min() > -1e-10 * np.abs(m).max()
            assert np.linalg.eigvalsh(m[4:, 4:]).min() > 0
        spectrum = np.abs(np.fft.rfft(samples, axis=0)) / len(psis)
        assert spectrum[3:].max() < 1e-12 * np.abs(samples).max()


def test_line_mass_equals_two_particles():
    """The rigid-body line mass and two particles with the same m, S, I give the same equations."""
    rng = np.random.default_rng(7)
    for _ in range(3):
        m1, m2 = rng.uniform(1.0, 50.0, 2)
        r1, r2 = rng.uniform(0.0, 8.0, 2)
        omega, offset, height = rng.uniform(5.0, 40.0), rng.uniform(0.0, 1.0), rng.uniform(-2.0, 2.0)
        springs = rng.uniform(0.0, 1e4, 4)
        blade = (m1 + m2, m1 * r1 + m2 * r2, m1 * r1**2 + m2 * r2**2)
        values = (omega, *blade, offset, height, *springs)
        for psi in (0.0, 0.7, 2.5):
            line = evaluate(psi, values)
            pair = evaluate(psi, values, "particles", (m1, m2, r1, r2))
            np.testing.assert_allclose(pair, line, rtol=1e-12, atol=1e-12 * np.abs(line).max())


def test_rotating_lag_and_flap_frequencies():
    """nu_lag^2 = e S/I + K_zeta/(I Omega^2), nu_flap^2 = 1 + e S/I + K_beta/(I Omega^2), at any azimuth."""
    mass, damping, stiffness = derive()
    lag, flap = 4, 5
    nu_lag = stiffness[lag, lag] / (mass[lag, lag] * OMEGA**2)
    nu_flap = stiffness[flap, flap] / (mass[flap, flap] * OMEGA**2)
    assert sp.simplify(nu_lag - (OFFSET * STATIC / INERTIA + K_LAG / (INERTIA * OMEGA**2))) == 0
    assert sp.simplify(nu_flap - (1 + OFFSET * STATIC / INERTIA + K_FLAP / (INERTIA * OMEGA**2))) == 0
    assert sp.simplify(damping[lag, lag] - C_LAG) == 0 and sp.simplify(damping[flap, flap] - C_FLAP) == 0
    # with the body held still, lag and flap decouple from each other
    assert mass[lag, flap] == mass[flap, lag] == damping[lag, flap] == damping[flap, lag] == 0
    assert stiffness[lag, flap] == stiffness[flap, lag] == 0


def test_gyroscopic_pitch_roll_coupling():
    """Azimuth mean of the pitch-roll damping terms = +-Omega (I + 2 S e + m e^2), the polar moment."""
    _, damping, _ = derive()
    polar = INERTIA + 2 * STATIC * OFFSET + MASS * OFFSET**2
    theta, phi = COORDS.index("theta"), COORDS.index("phi")

    def mean(expr):
        return sp.integrate(expr, (PSI, 0, 2 * sp.pi)) / (2 * sp.pi)

    assert sp.simplify(mean(damping[theta, phi]) - OMEGA * polar) == 0
    assert sp.simplify(mean(damping[phi, theta]) + OMEGA * polar) == 0
    assert sp.simplify(mean(damping[theta, theta])) == 0 and sp.simplify(mean(damping[phi, phi])) == 0
    # and the generated code's constant harmonic agrees
    for values in parameter_sets():
        omega, m, s, inertia, e = values[:5]
        constant = blade_function()(*values)[1, 0]
        expected = omega * (inertia + 2 * s * e + m * e**2)
        np.testing.assert_allclose(constant[theta, phi], expected, rtol=1e-12)
        np.testing.assert_allclose(constant[phi, theta], -expected, rtol=1e-12)
