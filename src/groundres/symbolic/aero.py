"""One blade in air: its equations linearised about the hover trim, and the trim loads.

The structure is that of :func:`groundres.symbolic.derive.derive_blade`,
linearised about the trim instead of about zero: the blade coned by
``coning`` and lagged by ``trim_lag`` (both exact in the kinematics), the
body at rest. The air adds quasi-steady strip-theory loads (see
``docs/theory.md``, "The rotor in air"):

* a section at radius ``r`` along the blade (``r - e`` from the hinge), from
  ``root_cutout`` to ``tip_radius``, moves with velocity ``V`` (the body's
  translation and rotation, the rotor's turning, the blade's lag and flap,
  all exact); the air comes down the shaft at ``lambda Omega R``;
* with ``W = V + lambda Omega R s`` (``s`` the shaft axis), the section sees
  ``U_T = W . t`` and ``U_P = W . n`` (``t`` towards the leading edge, ``n``
  the blade's normal, both turning with the blade); radial flow is ignored;
* pitch ``theta = collective + twist r/R - K_Pbeta beta - K_Pzeta zeta``;
* normal force ``F_n = 1/2 rho c a (U_T^2 theta - U_P U_T)``, in-plane force
  (against the rotation) ``F_x = 1/2 rho c a (U_P U_T theta - U_P^2) + 1/2 rho
  c cd0 U_T^2``; the section force is ``F = F_n n - F_x t``;
* the generalised force on coordinate ``q_i`` is ``int F . dP/dq_i dr``.

Linearised consistently, ``dQ_i = int (dF . P_i + F . dP_i) dr``: the change
of the force along the unchanged partial velocity, and the trim force along
the change of the partial velocity. The second term makes the thrust a
follower force: about a pivot on the shaft it gives no stiffness in pitch or
roll, while the torque along the tilted shaft couples them. The inflow
``lambda`` is frozen at its trim value (uniform momentum inflow).

Every coefficient is a trigonometric polynomial in the azimuth of degree at
most two, split into the harmonics of :data:`groundres.symbolic.derive.HARMONICS`
like the structure's. The trim loads (the flap and lag moments left over at a
trial trim, the blade's thrust and torque, and their derivatives in coning,
trim lag and inflow) let the numeric core find the trim by Newton's method.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .derive import (
    BLADE_SYMBOLS,
    COORDS,
    HARMONICS,
    LOCAL_DOFS,
    RATES,
    _time_derivative,
    azimuth,
    blade_geometry,
    blade_kinetic,
    rotor_speed,
)

#: The air's and the blade's aerodynamic parameters, and the trim the equations are
#: linearised about (angles in radians, the inflow ratio lambda = v / (Omega R)).
AERO_SYMBOLS = dict(
    air_density=sp.Symbol("rho", nonnegative=True),
    lift_slope=sp.Symbol("a", nonnegative=True),
    drag_coefficient=sp.Symbol("c_d0", nonnegative=True),
    chord=sp.Symbol("c", positive=True),
    tip_radius=sp.Symbol("R", positive=True),
    root_cutout=sp.Symbol("r_0", nonnegative=True),
    collective=sp.Symbol("theta_0", real=True),
    twist=sp.Symbol("theta_tw", real=True),
    pitch_flap=sp.Symbol("K_Pbeta", real=True),
    pitch_lag=sp.Symbol("K_Pzeta", real=True),
    inflow_ratio=sp.Symbol("lambda", real=True),
    coning=sp.Symbol("beta_0", real=True),
    trim_lag=sp.Symbol("zeta_0", real=True),
)
#: The span's moments int rho^k d rho, rho the distance from the hinge along the blade,
#: over the lifting span (rho from root_cutout - e to tip_radius - e): the generated
#: functions take them ready made (:func:`groundres.model.trim.moments`), which keeps them short.
#: (Their names are codegen.SPAN_ARGUMENTS, which the numeric core uses without SymPy.)
SPAN_SYMBOLS = {f"span_moment_{k}": sp.Symbol(f"M_{k}", real=True) for k in range(5)}
#: The trim unknowns, in the order of the trim Jacobian's columns.
TRIM_UNKNOWNS = ("coning", "trim_lag", "inflow_ratio")
#: The trim loads of one blade, in order (:func:`derive_trim`).
TRIM_LOADS = ("flap_residual", "lag_residual", "thrust", "torque")

_radius = sp.Symbol("rho_s", real=True)  # distance from the hinge along the blade
# Cosines and sines as plain symbols while the algebra is polynomial; each pair
# obeys c^2 + s^2 = 1, which :func:`_reduced` applies.
_PAIRS = tuple(
    (angle, sp.Symbol(f"c_{name}", real=True), sp.Symbol(f"s_{name}", real=True))
    for angle, name in (
        (azimuth, "psi"),
        (AERO_SYMBOLS["coning"], "beta"),
        (AERO_SYMBOLS["trim_lag"], "zeta"),
    )
)
_TRIG = {f(angle): sym for angle, c, s in _PAIRS for f, sym in ((sp.cos, c), (sp.sin, s))}


def _kinematics():
    """Section position, leading-edge and normal axes, and the shaft axis, as functions of the
    coordinates (the structure's geometry, :func:`groundres.symbolic.derive.blade_geometry`)."""
    hinge, axes, body = blade_geometry()
    return hinge + _radius * axes[:, 0], axes[:, 1], axes[:, 2], body[:, 2]


def _trim_values():
    a = AERO_SYMBOLS
    values = {q: 0 for q in COORDS + RATES}
    values[COORDS[6]], values[COORDS[7]] = a["trim_lag"], a["coning"]
    return values


# The algebra about the trim is done on sparse polynomials (SymPy's polynomial
# rings: far faster than expression trees). The twist enters as the twist rate
# twist / tip_radius, so that every quantity is a polynomial.
_TWIST_RATE = sp.Symbol("g_tw", real=True)
_RING_SYMBOLS = (
    rotor_speed,
    *BLADE_SYMBOLS.values(),
    *(v for k, v in AERO_SYMBOLS.items() if k != "twist"),
    *SPAN_SYMBOLS.values(),
    _TWIST_RATE,
    _radius,
    *(sym for _, c, s in _PAIRS for sym in (c, s)),
)
_RING = sp.ring(_RING_SYMBOLS, sp.QQ)[0]
_INDEX = {sym: i for i, sym in enumerate(_RING_SYMBOLS)}


def _at_trim(expr):
    """An expression (or a 3-vector) at the trim as a polynomial (a list for a vector)."""
    a = AERO_SYMBOLS
    out = expr.xreplace(_trim_values()).xreplace(_TRIG).xreplace({a["twist"]: _TWIST_RATE * a["tip_radius"]})
    if isinstance(out, sp.MatrixBase):
        return [_reduced(_RING(sp.expand(v))) for v in out]
    return _reduced(_RING(sp.expand(out)))


def _reduced(poly):
    """A polynomial reduced by c^2 + s^2 = 1 of each cosine-sine pair (every sine to
    degree one at most): a canonical form, so that equal quantities look equal."""
    for _, c, s in _PAIRS:
        ic, js = _INDEX[c], _INDEX[s]
        if all(monom[js] < 2 for monom in poly.keys()):
            continue
        out = _RING.zero
        cos2 = _RING.gens[ic] ** 2
        for monom, coeff in poly.terms():
            k, odd = divmod(monom[js], 2)
            rest = list(monom)
            rest[js] = odd
            out += _RING({tuple(rest): coeff}) * (1 - cos2) ** k
        poly = out
    return poly


def _dot(u, v):
    return _reduced(sum((a * b for a, b in zip(u, v)), _RING.zero))


def _cross(u, v):
    return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]


def _combine(*terms):
    """sum of scalar x vector products, as one vector."""
    return [_reduced(sum((k * v[i] for k, v in terms), _RING.zero)) for i in range(3)]


def _as_expr(poly):
    """A polynomial back as an expression: cosines and sines, the twist itself."""
    a = AERO_SYMBOLS
    back = {sym: f(angle) for angle, c, s in _PAIRS for f, sym in ((sp.cos, c), (sp.sin, s))}
    back[_TWIST_RATE] = a["twist"] / a["tip_radius"]
    return sp.expand(poly.as_expr().xreplace(back))


def _harmonic_split(poly):
    """The HARMONICS coefficients (polynomials without the azimuth) of a polynomial in
    cos psi, sin psi of degree two at most."""
    _, c, s = _PAIRS[0]
    ic, js = _INDEX[c], _INDEX[s]
    parts = {}
    for monom, coeff in _reduced(poly).terms():
        key = (monom[ic], monom[js])
        rest = list(monom)
        rest[ic] = rest[js] = 0
        parts[key] = parts.get(key, _RING.zero) + _RING({tuple(rest): coeff})
    if any(i + j > 2 for i, j in parts):
        raise ValueError("harmonic above the second in a blade coefficient")
    get = lambda i, j: parts.get((i, j), _RING.zero)  # noqa: E731
    return (get(0, 0) + get(2, 0) / 2, get(1, 0), get(0, 1), get(2, 0) / 2, get(1, 1) / 2)


def _span_integral(poly):
    """The integral over the lifting span of a polynomial in the distance from the hinge,
    in the span's moments (SPAN_SYMBOLS)."""
    ir = _INDEX[_radius]
    moments = [_RING(v) for v in SPAN_SYMBOLS.values()]
    out = _RING.zero
    for monom, coeff in poly.terms():
        rest = list(monom)
        rest[ir] = 0
        out += _RING({tuple(rest): coeff}) * moments[monom[ir]]
    return out


def _pitch():
    a = AERO_SYMBOLS
    return (
        a["collective"]
        + a["twist"] * (BLADE_SYMBOLS["hinge_offset"] + _radius) / a["tip_radius"]
        - a["pitch_flap"] * COORDS[7]
        - a["pitch_lag"] * COORDS[6]
    )


def _relative_air(point, shaft):
    """W: the section's velocity through the air (its own, plus the inflow's, down the shaft)."""
    a = AERO_SYMBOLS
    velocity = point.applyfunc(_time_derivative)
    return velocity + a["inflow_ratio"] * rotor_speed * a["tip_radius"] * shaft


class _Trim:
    """The section's kinematics and loads at the trim, and their first derivatives (polynomials)."""

    def __init__(self):
        point, lead, normal, shaft = _kinematics()
        air = _relative_air(point, shaft)
        pitch = _pitch()
        self.position, self.shaft = _at_trim(point), _at_trim(shaft)
        self.partial = [_at_trim(point.diff(q)) for q in COORDS]
        self.second = [[_at_trim(point.diff(q, p)) for p in COORDS] for q in COORDS]
        self.w0, self.lead, self.normal = _at_trim(air), _at_trim(lead), _at_trim(normal)
        u_t, u_p, theta = _dot(self.w0, self.lead), _dot(self.w0, self.normal), _at_trim(pitch)
        k = {name: _RING(v) for name, v in AERO_SYMBOLS.items() if v in _INDEX}
        k_lift = k["air_density"] * k["chord"] * k["lift_slope"] / 2
        k_drag = k["air_density"] * k["chord"] * k["drag_coefficient"] / 2
        self.fn = _reduced(k_lift * (u_t**2 * theta - u_p * u_t))
        self.fx = _reduced(k_lift * (u_p * u_t * theta - u_p**2) + k_drag * u_t**2)
        self.force = _combine((self.fn, self.normal), (-self.fx, self.lead))
        # dF_n and dF_x per unit change of U_T, U_P and theta at the trim
        self.dfn = [k_lift * (2 * u_t * theta - u_p), -k_lift * u_t, k_lift * u_t**2]
        self.dfx = [
            k_lift * u_p * theta + 2 * k_drag * u_t,
            k_lift * (u_t * theta - 2 * u_p),
            k_lift * u_p * u_t,
        ]
        # the changes of W, t, n and theta per unit change of each coordinate and rate
        self.dw_q = [_at_trim(air.diff(q)) for q in COORDS]
        self.dw_r = [_at_trim(air.diff(r)) for r in RATES]
        self.dt_q = [_at_trim(lead.diff(q)) for q in COORDS]
        self.dn_q = [_at_trim(normal.diff(q)) for q in COORDS]
        self.dtheta_q = [_at_trim(pitch.diff(q)) for q in COORDS]

    def force_change(self, j: int, rate: bool):
        """dF per unit change of coordinate j (or of its rate)."""
        if rate:
            return self.force_change_in(self.dw_r[j])
        return self.force_change_in(self.dw_q[j], self.dt_q[j], self.dn_q[j], self.dtheta_q[j])

    def force_change_in(self, dw, dt=None, dn=None, dtheta=None):
        """dF per unit change of the relative air dw, the axes dt and dn and the pitch dtheta."""
        zero = [_RING.zero] * 3
        dt, dn, dtheta = dt or zero, dn or zero, dtheta or _RING.zero
        du_t = _dot(dw, self.lead) + _dot(self.w0, dt)
        du_p = _dot(dw, self.normal) + _dot(self.w0, dn)
        dfn = self.dfn[0] * du_t + self.dfn[1] * du_p + self.dfn[2] * dtheta
        dfx = self.dfx[0] * du_t + self.dfx[1] * du_p + self.dfx[2] * dtheta
        return _combine((dfn, self.normal), (self.fn, dn), (-dfx, self.lead), (-self.fx, dt))


def derive_air_loads():
    """The linearised aerodynamic generalised forces of one blade about the trim.

    Returns
    -------
    (stiffness, damping) : two 8 x 8 nested lists of polynomials
        ``-dQ/dq`` and ``-dQ/dq'`` (LOCAL_DOFS order): what the air adds to the
        blade's stiffness and damping matrices.
    """
    trim = _Trim()
    n = len(LOCAL_DOFS)
    stiffness = [[None] * n for _ in range(n)]
    damping = [[None] * n for _ in range(n)]
    for j in range(n):
        moved, pushed = trim.force_change(j, rate=False), trim.force_change(j, rate=True)
        for i in range(n):
            change = _dot(moved, trim.partial[i]) + _dot(trim.force, trim.second[i][j])
            stiffness[i][j] = -_span_integral(change)
            damping[i][j] = -_span_integral(_dot(pushed, trim.partial[i]))
    return stiffness, damping


def _structure():
    """The blade's inertial mass, damping and stiffness about the trim (8 x 8 nested lists of
    polynomials, before the harmonic split), springs and dampers included."""
    p = BLADE_SYMBOLS
    kinetic = blade_kinetic()
    n = len(LOCAL_DOFS)
    grad_q = [kinetic.diff(q) for q in COORDS]
    grad_qd = [kinetic.diff(qd) for qd in RATES]

    def hess(grads, variables):
        return [[_at_trim(grads[i].diff(variables[j])) for j in range(n)] for i in range(n)]

    m_t, b_t, k_t = hess(grad_qd, RATES), hess(grad_qd, COORDS), hess(grad_q, COORDS)
    c_psi, s_psi = (_RING.gens[_INDEX[v]] for v in _PAIRS[0][1:])

    def d_psi(e):  # d/dpsi of a polynomial in cos psi, sin psi
        return _reduced(-s_psi * e.diff(c_psi) + c_psi * e.diff(s_psi))

    omega = _RING(rotor_speed)
    own = {6: ("lag_damping", "lag_stiffness"), 7: ("flap_damping", "flap_stiffness")}
    damping = [[omega * d_psi(m_t[i][j]) + b_t[i][j] - b_t[j][i] for j in range(n)] for i in range(n)]
    stiffness = [[omega * d_psi(b_t[i][j]) - k_t[i][j] for j in range(n)] for i in range(n)]
    for i, (c, k) in own.items():
        damping[i][i] += _RING(p[c])
        stiffness[i][i] += _RING(p[k])
    return m_t, damping, stiffness


@dataclass(frozen=True)
class Terms:
    """A derived array split into monomials of the trim state (:data:`groundres.symbolic.codegen.AIR_STATE`).

    ``value[index] = sum_k monomial_k(state) * entries[(k,) + index]``, with
    ``monomial_k = prod_j state_j ** monomials[k][j]``: every entry is a
    polynomial in the rotor speed, the inflow ratio, the coning and trim lag
    and their cosines and sines, whose coefficients depend on the blade, the
    body and the air only. The numeric core evaluates the coefficients once
    per rotor and the monomials at every speed: a product, not the long
    expressions, per speed.

    Attributes
    ----------
    entries : dict
        ``(k,) + index`` -> SymPy expression in the remaining arguments.
    monomials : tuple of tuple of int
        The exponents of each monomial over the trim state.
    array_shape : tuple
        The array's shape (without the monomials' axis).
    """

    entries: dict
    monomials: tuple
    array_shape: tuple

    @property
    def full_shape(self) -> tuple:
        """(K,) + array_shape: the generated function's array."""
        return (len(self.monomials),) + self.array_shape


def _state_gens():
    """The trim state's symbols, in the order of the monomials' exponents: codegen.AIR_STATE
    (rotor_speed, inflow_ratio, coning, trim_lag, and the cosines and sines of the angles)."""
    a = AERO_SYMBOLS
    trig = [sym for _, c, s in _PAIRS[1:] for sym in (c, s)]
    return [rotor_speed, a["inflow_ratio"], a["coning"], a["trim_lag"], *trig]


def _terms(polys: dict, shape: tuple, per_tip=None) -> Terms:
    """Split polynomials (index -> polynomial) into Terms over the trim state (an entry of
    ``per_tip``, index -> k, divided by the tip radius to the power k)."""
    gens = [_INDEX[g] for g in _state_gens()]
    grouped = {}
    for index, poly in polys.items():
        for monom, coeff in _reduced(poly).terms():
            key = tuple(monom[g] for g in gens)
            rest = list(monom)
            for g in gens:
                rest[g] = 0
            part = _RING({tuple(rest): coeff})
            grouped[(key, index)] = grouped.get((key, index), _RING.zero) + part
    order = sorted({key for key, _ in grouped})
    number = {key: k for k, key in enumerate(order)}
    tip = AERO_SYMBOLS["tip_radius"]
    per_tip = per_tip or {}
    entries = {
        (number[key],) + index: _as_expr(v) / tip ** per_tip.get(index, 0)
        for (key, index), v in grouped.items()
        if v
    }
    return Terms(dict(sorted(entries.items())), tuple(order), shape)


def derive_blade_in_air() -> Terms:
    """One blade's linear equations in air, about its hover trim, as Terms of shape
    (3, 5, 8, 8): [mass, damping, stiffness] x HARMONICS x LOCAL_DOFS x LOCAL_DOFS.

    The structure linearised about the trim (the coning and trim lag exact in
    its kinematics) plus the air's stiffness and damping (:func:`derive_air_loads`).
    """
    mass, damping, stiffness = _structure()
    air_k, air_c = derive_air_loads()
    n = len(LOCAL_DOFS)
    total_c = [[damping[i][j] + air_c[i][j] for j in range(n)] for i in range(n)]
    total_k = [[stiffness[i][j] + air_k[i][j] for j in range(n)] for i in range(n)]
    polys = {}
    for g, matrix in enumerate((mass, total_c, total_k)):
        for i in range(n):
            for j in range(n):
                for h, part in enumerate(_harmonic_split(matrix[i][j])):
                    if part:
                        polys[(g, h, i, j)] = part
    return _terms(polys, (3, len(HARMONICS), n, n))


def derive_trim() -> Terms:
    """The trim loads of one blade and their derivatives, as Terms of shape (4, 4).

    Column 0 holds, at a trial trim (coning, trim lag, inflow ratio; body at
    rest, blade still in the hub's axes): the flap and the lag residual
    (structural minus aerodynamic generalised force; zero at the trim), the
    blade's thrust along the shaft [N] and the torque it asks of the shaft
    [N m]. Columns 1-3 are their derivatives in TRIM_UNKNOWNS.
    """
    a, p = AERO_SYMBOLS, BLADE_SYMBOLS
    trim = _Trim()
    kinetic = blade_kinetic()
    loads = []
    for index, spring in ((7, "flap_stiffness"), (6, "lag_stiffness")):
        q, qd = COORDS[index], RATES[index]
        # Lagrange's d/dt(dT/dq') - dT/dq of the blade held still, plus its root spring
        held = _at_trim(_time_derivative(kinetic.diff(qd)) - kinetic.diff(q))
        angle = _RING(a["coning"] if index == 7 else a["trim_lag"])
        aero = _span_integral(_dot(trim.force, trim.partial[index]))
        loads.append(held + _RING(p[spring]) * angle - aero)
    loads.append(_span_integral(_dot(trim.force, trim.shaft)))
    hub = [_RING(BLADE_SYMBOLS[k]) for k in ("hub_x", "hub_y", "hub_height")]
    moment = _cross([x - h for x, h in zip(trim.position, hub)], trim.force)  # about the hub centre
    loads.append(-_span_integral(_dot(moment, trim.shaft)))
    ic, js = _INDEX[_PAIRS[0][1]], _INDEX[_PAIRS[0][2]]
    gen = {sym: _RING.gens[_INDEX[sym]] for _, c, s in _PAIRS[1:] for sym in (c, s)}
    (_, c_beta, s_beta), (_, c_zeta, s_zeta) = _PAIRS[1:]

    def d_angle(poly, angle, c, s):  # d/d(angle) with its cosine and sine
        bare = _RING.gens[_INDEX[angle]]
        return _reduced(poly.diff(bare) - gen[s] * poly.diff(gen[c]) + gen[c] * poly.diff(gen[s]))

    polys = {}
    for row, value in enumerate(loads):
        value = _reduced(value)
        if any(m[ic] or m[js] for m in value.keys()):
            raise ValueError("a trim load depends on the azimuth")
        columns = (
            value,
            d_angle(value, a["coning"], c_beta, s_beta),
            d_angle(value, a["trim_lag"], c_zeta, s_zeta),
            _reduced(value.diff(_RING.gens[_INDEX[a["inflow_ratio"]]])),
        )
        for col, part in enumerate(columns):
            if part:
                polys[(row, col)] = part
    return _terms(polys, (len(TRIM_LOADS), 1 + len(TRIM_UNKNOWNS)))
