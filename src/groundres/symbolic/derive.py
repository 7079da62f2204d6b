"""Linearised equations of motion of one blade on a moving body, from its energies.

The model (see ``docs/conventions.md``): a body whose pivot translates in x and
y and which pitches and rolls about that pivot; the hub is ``hub_height`` above
the pivot; a rigid blade hinged at ``hinge_offset`` from the shaft lags (positive
against the rotation) and flaps (positive up) about that hinge, with root
springs and dampers. All blade mass lies on its span axis beyond the hinge, so
the blade enters through its mass ``m``, static moment ``S`` and inertia ``I``
about the hinge. Constant rotor speed, no aerodynamics, no gravity.

The kinetic energy of the blade is exact for a rigid line mass,

    T = 1/2 m |dA/dt|^2 + S dA/dt . dB/dt + 1/2 I |dB/dt|^2,

with ``A`` the hinge position and ``B`` the unit vector along the blade. Its
second-order Taylor part about the equilibrium (all coordinates zero),

    T2 = 1/2 qd' Mt qd + qd' Bt q + 1/2 q' Kt q,

gives through Lagrange's equations the exact linear equations

    Mt q'' + (dMt/dt + Bt - Bt' + Cd) q' + (dBt/dt - Kt + Kv) q = 0,

where ``Kv`` and ``Cd`` come from the springs and the Rayleigh dissipation
function. Terms of T linear in the coordinates only force the system (a rotor
out of balance) and do not affect stability; they are dropped.

Every coefficient is a trigonometric polynomial in the blade azimuth ``psi``
of degree at most two. The derivation returns the harmonic coefficient
matrices (constant, cos psi, sin psi, cos 2 psi, sin 2 psi), which is what the
numeric core needs for any number of blades, any blade properties and any
instant of time.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

#: Local coordinates of one blade's equations: the four body coordinates,
#: then the blade's own lag and flap angles.
LOCAL_DOFS = ("x", "y", "pitch", "roll", "lag", "flap")
BODY_DOFS = LOCAL_DOFS[:4]
#: Harmonics of the blade azimuth, in the order of the coefficient arrays.
HARMONICS = ("0", "c1", "s1", "c2", "s2")

rotor_speed, azimuth = sp.symbols("Omega psi", real=True)
BLADE_SYMBOLS = dict(
    blade_mass=sp.Symbol("m", positive=True),
    blade_static_moment=sp.Symbol("S", nonnegative=True),
    blade_inertia=sp.Symbol("I", positive=True),
    hinge_offset=sp.Symbol("e", nonnegative=True),
    hub_height=sp.Symbol("h", real=True),
    lag_stiffness=sp.Symbol("K_zeta", nonnegative=True),
    lag_damping=sp.Symbol("C_zeta", nonnegative=True),
    flap_stiffness=sp.Symbol("K_beta", nonnegative=True),
    flap_damping=sp.Symbol("C_beta", nonnegative=True),
)
BODY_SYMBOLS = {
    f"{kind}_{dof}": sp.Symbol(f"{letter}_{dof}", **assume)
    for dof in BODY_DOFS
    for kind, letter, assume in (
        ("mass" if dof in ("x", "y") else "inertia", "M" if dof in ("x", "y") else "J", {"positive": True}),
        ("stiffness", "K", {"nonnegative": True}),
        ("damping", "C", {"nonnegative": True}),
    )
}
#: Coordinate symbols (q) and rate symbols (qd), in LOCAL_DOFS order.
COORDS = sp.symbols("x y theta phi zeta beta", real=True)
RATES = sp.symbols("xd yd thetad phid zetad betad", real=True)


@dataclass(frozen=True)
class BladeEquations:
    """Harmonic coefficient matrices of one blade's linear equations.

    ``mass[h]``, ``damping[h]``, ``stiffness[h]`` are 6 x 6 SymPy matrices in
    LOCAL_DOFS order for harmonic ``h`` of HARMONICS; the blade's contribution
    at azimuth psi is ``sum_h X[h] * trig_h(psi)``.
    """

    mass: tuple
    damping: tuple
    stiffness: tuple

    def at_azimuth(self, psi=azimuth):
        """The three 6 x 6 matrices as functions of the azimuth ``psi``."""
        trig = (1, sp.cos(psi), sp.sin(psi), sp.cos(2 * psi), sp.sin(2 * psi))

        def combine(group):
            return sp.Matrix(6, 6, lambda i, j: sp.expand(sum(c * X[i, j] for c, X in zip(trig, group))))

        return tuple(combine(group) for group in (self.mass, self.damping, self.stiffness))


def _rot_x(a):
    return sp.Matrix([[1, 0, 0], [0, sp.cos(a), -sp.sin(a)], [0, sp.sin(a), sp.cos(a)]])


def _rot_y(a):
    return sp.Matrix([[sp.cos(a), 0, sp.sin(a)], [0, 1, 0], [-sp.sin(a), 0, sp.cos(a)]])


def _rot_z(a):
    return sp.Matrix([[sp.cos(a), -sp.sin(a), 0], [sp.sin(a), sp.cos(a), 0], [0, 0, 1]])


def _time_derivative(expr, coords=COORDS, rates=RATES):
    """d/dt of an expression in the coordinates and the azimuth (psi' = Omega)."""
    return sum(expr.diff(q) * qd for q, qd in zip(coords, rates)) + rotor_speed * expr.diff(azimuth)


def _harmonics(expr):
    """Split a trigonometric polynomial in psi (degree <= 2) into HARMONICS.

    Cosines and sines are written with w = exp(i psi); the coefficient of w^k is
    read off exactly. Raises if the expression has harmonics above the second.
    """
    w = sp.Symbol("w")
    laurent = sp.expand(
        sp.expand_trig(expr).subs(
            {sp.cos(azimuth): (w + 1 / w) / 2, sp.sin(azimuth): (w - 1 / w) / (2 * sp.I)}
        )
    )
    coeffs = {}
    for term in sp.Add.make_args(laurent):
        c, k = term.as_coeff_exponent(w)
        if c.has(w):
            raise ValueError(f"not a polynomial in exp(i psi): {term}")
        coeffs[int(k)] = coeffs.get(int(k), 0) + c
    if any(abs(k) > 2 for k, c in coeffs.items() if sp.simplify(c) != 0):
        raise ValueError("harmonic above the second in a blade coefficient")
    get = lambda k: coeffs.get(k, 0)  # noqa: E731
    return tuple(
        sp.simplify(sp.expand(v))
        for v in (
            get(0),
            get(1) + get(-1),
            sp.I * (get(1) - get(-1)),
            get(2) + get(-2),
            sp.I * (get(2) - get(-2)),
        )
    )


def derive_blade() -> BladeEquations:
    """Derive one blade's linear equations of motion with its body coupling.

    Returns
    -------
    BladeEquations
        Harmonic coefficient matrices of mass, damping and stiffness.
    """
    x, y, theta, phi, zeta, beta = COORDS
    p = BLADE_SYMBOLS
    ez = sp.Matrix([0, 0, 1])
    ex = sp.Matrix([1, 0, 0])
    # Roll about +x (right side down), pitch nose up (about -y).
    body = _rot_x(phi) * _rot_y(-theta)
    hub_frame = body * _rot_z(azimuth)
    hinge = sp.Matrix([x, y, 0]) + body * (p["hub_height"] * ez) + hub_frame * (p["hinge_offset"] * ex)
    # Lag against the rotation, flap up; the order of the two hinges changes
    # only terms of third order in the coordinates.
    span = hub_frame * sp.Matrix([sp.cos(beta) * sp.cos(zeta), -sp.cos(beta) * sp.sin(zeta), sp.sin(beta)])
    a_dot = hinge.applyfunc(_time_derivative)
    b_dot = span.applyfunc(_time_derivative)
    kinetic = (
        p["blade_mass"] * a_dot.dot(a_dot) / 2
        + p["blade_static_moment"] * a_dot.dot(b_dot)
        + p["blade_inertia"] * b_dot.dot(b_dot) / 2
    )
    zero = {s: 0 for s in COORDS + RATES}
    grad_q = [kinetic.diff(q) for q in COORDS]
    grad_qd = [kinetic.diff(qd) for qd in RATES]

    def hess(grads, variables):
        return sp.Matrix(6, 6, lambda i, j: sp.expand(sp.simplify(grads[i].diff(variables[j]).subs(zero))))

    m_t = hess(grad_qd, RATES)  # d2T/dqd dqd
    b_t = hess(grad_qd, COORDS)  # T contains qd' b_t q
    k_t = hess(grad_q, COORDS)
    c_d = sp.diag(0, 0, 0, 0, p["lag_damping"], p["flap_damping"])
    k_v = sp.diag(0, 0, 0, 0, p["lag_stiffness"], p["flap_stiffness"])
    mass = m_t
    damping = m_t.diff(azimuth) * rotor_speed + b_t - b_t.T + c_d
    stiffness = b_t.diff(azimuth) * rotor_speed - k_t + k_v

    def split(matrix):
        entries = [_harmonics(matrix[i, j]) for i in range(6) for j in range(6)]
        return tuple(sp.Matrix(6, 6, [e[h] for e in entries]) for h in range(len(HARMONICS)))

    return BladeEquations(split(mass), split(damping), split(stiffness))


def body_matrices():
    """Mass, damping and stiffness of the body alone (4 x 4, BODY_DOFS order).

    The body's kinetic energy is 1/2 sum M_i qd_i^2 (the pivot is its centre of
    mass), its potential energy 1/2 sum K_i q_i^2 and its dissipation function
    1/2 sum C_i qd_i^2; blades are not included.
    """
    b = BODY_SYMBOLS
    names = [("mass" if d in ("x", "y") else "inertia") + f"_{d}" for d in BODY_DOFS]
    return (
        sp.diag(*[b[n] for n in names]),
        sp.diag(*[b[f"damping_{d}"] for d in BODY_DOFS]),
        sp.diag(*[b[f"stiffness_{d}"] for d in BODY_DOFS]),
    )
