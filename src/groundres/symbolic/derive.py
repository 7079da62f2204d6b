"""Linearised equations of motion of one blade on a moving body, from its energies.

The model (see ``docs/conventions.md``): a body whose reference point (the
pivot) translates in x, y and z and which pitches, rolls and yaws about it;
the hub centre is at (``hub_x``, ``hub_y``, ``hub_height``) from the pivot in
body axes; a rigid blade hinged at ``hinge_offset`` from the shaft lags (positive
against the rotation) and flaps (positive up) about that hinge, with root
springs and dampers. All blade mass lies on its span axis beyond the hinge, so
the blade enters through its mass ``m``, static moment ``S`` and inertia ``I``
about the hinge. Constant rotor speed, no aerodynamics, no gravity.

The kinetic energy of the blade is exact for a rigid line mass::

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

#: Local coordinates of one blade's equations: the six body coordinates,
#: then the blade's own lag and flap angles.
LOCAL_DOFS = ("x", "y", "z", "pitch", "roll", "yaw", "lag", "flap")
BODY_DOFS = LOCAL_DOFS[:6]
#: Body coordinates that translate (their inertia is a mass).
TRANSLATIONS = ("x", "y", "z")
#: Harmonics of the blade azimuth, in the order of the coefficient arrays.
HARMONICS = ("0", "c1", "s1", "c2", "s2")

rotor_speed, azimuth = sp.symbols("Omega psi", real=True)
BLADE_SYMBOLS = dict(
    blade_mass=sp.Symbol("m", positive=True),
    blade_static_moment=sp.Symbol("S", nonnegative=True),
    blade_inertia=sp.Symbol("I", positive=True),
    hinge_offset=sp.Symbol("e", nonnegative=True),
    hub_height=sp.Symbol("h", real=True),
    hub_x=sp.Symbol("h_x", real=True),
    hub_y=sp.Symbol("h_y", real=True),
    lag_stiffness=sp.Symbol("K_zeta", nonnegative=True),
    lag_damping=sp.Symbol("C_zeta", nonnegative=True),
    flap_stiffness=sp.Symbol("K_beta", nonnegative=True),
    flap_damping=sp.Symbol("C_beta", nonnegative=True),
)
BODY_SYMBOLS = {
    f"{kind}_{dof}": sp.Symbol(f"{letter}_{dof}", **assume)
    for dof in BODY_DOFS
    for kind, letter, assume in (
        (
            "mass" if dof in TRANSLATIONS else "inertia",
            "M" if dof in TRANSLATIONS else "J",
            {"positive": True},
        ),
        ("stiffness", "K", {"nonnegative": True}),
        ("damping", "C", {"nonnegative": True}),
    )
}
#: Coordinate symbols (q) and rate symbols (qd), in LOCAL_DOFS order.
COORDS = sp.symbols("x y z theta phi chi zeta beta", real=True)
RATES = sp.symbols("xd yd zd thetad phid chid zetad betad", real=True)


@dataclass(frozen=True)
class BladeEquations:
    """Harmonic coefficient matrices of one blade's linear equations.

    ``mass[h]``, ``damping[h]``, ``stiffness[h]`` are 8 x 8 SymPy matrices in
    LOCAL_DOFS order for harmonic ``h`` of HARMONICS; the blade's contribution
    at azimuth psi is ``sum_h X[h] * trig_h(psi)``.
    """

    mass: tuple
    damping: tuple
    stiffness: tuple

    def at_azimuth(self, psi=azimuth):
        """The three 8 x 8 matrices as functions of the azimuth ``psi``."""
        trig = (1, sp.cos(psi), sp.sin(psi), sp.cos(2 * psi), sp.sin(2 * psi))
        n = len(LOCAL_DOFS)

        def combine(group):
            return sp.Matrix(n, n, lambda i, j: sp.expand(sum(c * X[i, j] for c, X in zip(trig, group))))

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


def blade_geometry():
    """The blade's hinge position, its axes and the body's rotation, as functions of the coordinates.

    Returns ``(hinge, axes, body)``: the hinge point (from the pivot, in ground axes); the blade's
    axes (columns: along the span, towards the leading edge, its normal), turned by the body,
    the azimuth, the lag (against the rotation) and the flap (up); the body's rotation matrix.
    """
    x, y, z, theta, phi, chi, zeta, beta = COORDS
    p = BLADE_SYMBOLS
    # Yaw about +z (nose left, with the rotor), then roll about +x (right side
    # down), then pitch nose up (about -y).
    body = _rot_z(chi) * _rot_x(phi) * _rot_y(-theta)
    hub_frame = body * _rot_z(azimuth)
    hub = sp.Matrix([p["hub_x"], p["hub_y"], p["hub_height"]])
    hinge = sp.Matrix([x, y, z]) + body * hub + hub_frame * (p["hinge_offset"] * sp.Matrix([1, 0, 0]))
    # Lag against the rotation, flap up; the order of the two hinges changes
    # only terms of third order in the coordinates.
    axes = hub_frame * _rot_z(-zeta) * _rot_y(-beta)
    return hinge, axes, body


def blade_kinetic():
    """The exact kinetic energy of one rigid blade on the moving body (module docstring)."""
    p = BLADE_SYMBOLS
    hinge, axes, _ = blade_geometry()
    a_dot = hinge.applyfunc(_time_derivative)
    b_dot = axes[:, 0].applyfunc(_time_derivative)
    return (
        p["blade_mass"] * a_dot.dot(a_dot) / 2
        + p["blade_static_moment"] * a_dot.dot(b_dot)
        + p["blade_inertia"] * b_dot.dot(b_dot) / 2
    )


def derive_blade() -> BladeEquations:
    """Derive one blade's linear equations of motion with its body coupling.

    Returns
    -------
    BladeEquations
        Harmonic coefficient matrices of mass, damping and stiffness.
    """
    p = BLADE_SYMBOLS
    kinetic = blade_kinetic()
    zero = {s: 0 for s in COORDS + RATES}
    grad_q = [kinetic.diff(q) for q in COORDS]
    grad_qd = [kinetic.diff(qd) for qd in RATES]

    n = len(LOCAL_DOFS)

    def hess(grads, variables):
        return sp.Matrix(n, n, lambda i, j: sp.expand(sp.simplify(grads[i].diff(variables[j]).subs(zero))))

    m_t = hess(grad_qd, RATES)  # d2T/dqd dqd
    b_t = hess(grad_qd, COORDS)  # T contains qd' b_t q
    k_t = hess(grad_q, COORDS)
    c_d = sp.diag(*[0] * len(BODY_DOFS), p["lag_damping"], p["flap_damping"])
    k_v = sp.diag(*[0] * len(BODY_DOFS), p["lag_stiffness"], p["flap_stiffness"])
    mass = m_t
    damping = m_t.diff(azimuth) * rotor_speed + b_t - b_t.T + c_d
    stiffness = b_t.diff(azimuth) * rotor_speed - k_t + k_v

    def split(matrix):
        entries = [_harmonics(matrix[i, j]) for i in range(n) for j in range(n)]
        return tuple(sp.Matrix(n, n, [e[h] for e in entries]) for h in range(len(HARMONICS)))

    return BladeEquations(split(mass), split(damping), split(stiffness))


def body_matrices():
    """Mass, damping and stiffness of the modal body alone (6 x 6, BODY_DOFS order).

    The body's kinetic energy is 1/2 sum M_i qd_i^2 (the pivot is its centre of
    mass), its potential energy 1/2 sum K_i q_i^2 and its dissipation function
    1/2 sum C_i qd_i^2; blades are not included.
    """
    b = BODY_SYMBOLS
    names = [("mass" if d in TRANSLATIONS else "inertia") + f"_{d}" for d in BODY_DOFS]
    return (
        sp.diag(*[b[n] for n in names]),
        sp.diag(*[b[f"damping_{d}"] for d in BODY_DOFS]),
        sp.diag(*[b[f"stiffness_{d}"] for d in BODY_DOFS]),
    )


# -- the body as a rigid helicopter on gear legs, and damper rods ------------------

#: The rigid body: mass, inertia tensor about its centre of mass (body axes), and
#: the centre of mass from the pivot (the reference point of the body coordinates).
RIGID_SYMBOLS = dict(
    mass=sp.Symbol("M_b", positive=True),
    inertia_xx=sp.Symbol("J_xx", real=True),
    inertia_yy=sp.Symbol("J_yy", real=True),
    inertia_zz=sp.Symbol("J_zz", real=True),
    inertia_xy=sp.Symbol("J_xy", real=True),
    inertia_xz=sp.Symbol("J_xz", real=True),
    inertia_yz=sp.Symbol("J_yz", real=True),
    centre_x=sp.Symbol("c_x", real=True),
    centre_y=sp.Symbol("c_y", real=True),
    centre_z=sp.Symbol("c_z", real=True),
)
#: A gear leg: where it meets the body (from the pivot), and a coefficient along each
#: ground axis (a stiffness, or a damping: the matrices have the same form).
LEG_SYMBOLS = dict(
    position_x=sp.Symbol("p_x", real=True),
    position_y=sp.Symbol("p_y", real=True),
    position_z=sp.Symbol("p_z", real=True),
    along_x=sp.Symbol("k_x", real=True),
    along_y=sp.Symbol("k_y", real=True),
    along_z=sp.Symbol("k_z", real=True),
)
#: A damper rod: its end on blade k (from the hinge, in the blade's axes: along the
#: span, towards the leading edge, up), its other end (on blade k + j from that
#: blade's hinge in its axes, or on the hub from the rotor centre in blade k's axes
#: at rest), the hinge offsets of the two blades and their azimuth spacing 2 pi j / N.
ROD_SYMBOLS = dict(
    hinge_offset=BLADE_SYMBOLS["hinge_offset"],
    end_hinge_offset=sp.Symbol("e_b", nonnegative=True),
    spacing=sp.Symbol("delta", real=True),
    start_x=sp.Symbol("a_x", real=True),
    start_y=sp.Symbol("a_y", real=True),
    start_z=sp.Symbol("a_z", real=True),
    end_x=sp.Symbol("b_x", real=True),
    end_y=sp.Symbol("b_y", real=True),
    end_z=sp.Symbol("b_z", real=True),
)


def _body_rotation():
    """The body's rotation and its six coordinates (as in :func:`derive_blade`)."""
    x, y, z, theta, phi, chi = COORDS[:6]
    return sp.Matrix([x, y, z]), _rot_z(chi) * _rot_x(phi) * _rot_y(-theta)


def _body_dt(expr):
    """d/dt of an expression in the body coordinates (nothing turns at Omega)."""
    return sum(expr.diff(q) * qd for q, qd in zip(COORDS[:6], RATES[:6]))


def _hessian_at_rest(expr, variables):
    zero = {s: 0 for s in COORDS + RATES}
    n = len(variables)
    return sp.Matrix(
        n, n, lambda i, j: sp.expand(sp.simplify(expr.diff(variables[i], variables[j]).subs(zero)))
    )


def derive_rigid_body() -> sp.Matrix:
    """Mass matrix (6 x 6, BODY_DOFS order) of a rigid body, blades excluded.

    T = 1/2 M ``|v_c|^2`` + 1/2 w' J w, with v_c the velocity of the centre of
    mass (at ``centre`` from the pivot, turning with the body) and w the
    body's angular velocity in its own axes (R' dR/dt = [w x]); at rest its
    Hessian in the rates is the (constant) mass matrix.
    """
    p = RIGID_SYMBOLS
    translation, rotation = _body_rotation()
    centre = translation + rotation * sp.Matrix([p["centre_x"], p["centre_y"], p["centre_z"]])
    v_c = centre.applyfunc(_body_dt)
    spin = rotation.T * rotation.applyfunc(_body_dt)
    w = sp.Matrix([spin[2, 1], spin[0, 2], spin[1, 0]])
    j = sp.Matrix(
        [
            [p["inertia_xx"], p["inertia_xy"], p["inertia_xz"]],
            [p["inertia_xy"], p["inertia_yy"], p["inertia_yz"]],
            [p["inertia_xz"], p["inertia_yz"], p["inertia_zz"]],
        ]
    )
    kinetic = p["mass"] * v_c.dot(v_c) / 2 + (w.T * j * w)[0, 0] / 2
    return _hessian_at_rest(kinetic, RATES[:6])


def derive_leg() -> sp.Matrix:
    """Stiffness (or damping) matrix (6 x 6, BODY_DOFS order) of one gear leg.

    The leg's point on the body moves by u = (its position now) - (at rest);
    springs along the ground axes store V = 1/2 sum_a k_a u_a^2 (dampers
    dissipate 1/2 sum_a c_a u_a'^2, the same form in the rates). At rest the
    Hessian of V is the leg's stiffness matrix: T' diag(k) T with T the linear
    map from the body coordinates to u (translation plus rotation x position).
    """
    p = LEG_SYMBOLS
    translation, rotation = _body_rotation()
    position = sp.Matrix([p["position_x"], p["position_y"], p["position_z"]])
    u = translation + rotation * position - position
    potential = sum(k * u[a] ** 2 for a, k in enumerate((p["along_x"], p["along_y"], p["along_z"]))) / 2
    return _hessian_at_rest(potential, COORDS[:6])


def _blade_point(offset, lag, flap, point):
    """A point fixed on a blade (``point`` from its hinge, hinge ``offset`` from the shaft,
    in the blade's axes), in its hub axes."""
    return offset * sp.Matrix([1, 0, 0]) + _rot_z(-lag) * _rot_y(-flap) * point


def derive_rod(to_hub: bool) -> sp.Matrix:
    """Gradient of a damper rod's length at rest with respect to the lag and flap of the
    blades it joins: (lag_k, flap_k, lag_k+j, flap_k+j), or (lag_k, flap_k) ``to_hub``.

    A damper of coefficient c along the rod dissipates 1/2 c l'^2, so it adds
    c g g' to the damping matrix (and a rod spring k adds k g g' to the
    stiffness), g this gradient. Both ends turn with the rotor and move with
    the body together, so only the blades' own angles change the length.
    """
    p = ROD_SYMBOLS
    zeta, beta, zeta2, beta2 = sp.symbols("zeta_a beta_a zeta_b beta_b", real=True)
    start = _blade_point(p["hinge_offset"], zeta, beta, sp.Matrix([p["start_x"], p["start_y"], p["start_z"]]))
    end_point = sp.Matrix([p["end_x"], p["end_y"], p["end_z"]])
    angles = (zeta, beta) if to_hub else (zeta, beta, zeta2, beta2)
    end = (
        end_point
        if to_hub
        else _rot_z(p["spacing"]) * _blade_point(p["end_hinge_offset"], zeta2, beta2, end_point)
    )
    half_square = (start - end).dot(start - end) / 2
    rest = {a: 0 for a in (zeta, beta, zeta2, beta2)}
    length = sp.sqrt(2 * half_square.subs(rest))
    return sp.Matrix([sp.simplify(half_square.diff(a).subs(rest)) for a in angles]) / length
