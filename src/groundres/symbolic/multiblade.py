"""Exact symbolic multiblade equations for N identical blades.

Each blade's coefficients are trigonometric polynomials in its azimuth
psi_k = psi + 2 pi (k-1)/N. Writing z_k = exp(i psi_k) and w = exp(i psi), a
sum over the blades of z_k^a is N w^a when N divides a and zero otherwise, so
the multiblade matrices follow exactly, without trigonometric simplification.
Rows are premultiplied by T' as in :mod:`groundres.model.mbc` (cyclic blade rows are
N/2 times the averaged equations). The result is free of w (time-invariant)
for N >= 3; for N = 2 the periodic terms remain, written with psi.
"""

from __future__ import annotations

import sympy as sp

from .derive import BODY_DOFS, BODY_SYMBOLS, LOCAL_DOFS, TRANSLATIONS, BladeEquations, azimuth, rotor_speed

_z, _w = sp.symbols("z w")


def _laurent_trig(n):
    """cos(n psi_k), sin(n psi_k) as Laurent polynomials in z."""
    return (_z**n + _z**-n) / 2, (_z**n - _z**-n) / (2 * sp.I)


def _blade_laurent(group):
    """Harmonic matrices -> one matrix of Laurent polynomials in z."""
    c1, s1 = _laurent_trig(1)
    c2, s2 = _laurent_trig(2)
    weights = (1, c1, s1, c2, s2)
    n = len(LOCAL_DOFS)
    return sum((wgt * mat for wgt, mat in zip(weights, group)), sp.zeros(n, n))


def _ddt(expr):
    """Time derivative: psi_k and psi both advance at Omega."""
    return sp.expand(sp.I * rotor_speed * (_z * sp.diff(expr, _z) + _w * sp.diff(expr, _w)))


def _blade_sum(expr, n_blades):
    """Sum over k of expr(z_k), z_k = w exp(2 pi i (k-1)/N)."""
    total = 0
    for term in sp.Add.make_args(sp.expand(expr)):
        coeff, powers = term.as_coeff_mul()
        a = sp.Integer(0)
        rest = coeff
        for factor in powers:
            base, exp = factor.as_base_exp()
            if base == _z:
                a += exp
            else:
                rest *= factor
        if a % n_blades == 0:
            total += n_blades * rest * _w**a
    return total


def _to_real(expr):
    """Laurent polynomial in w -> expression in cos/sin of the azimuth psi."""
    expr = sp.expand(expr)
    if not expr.has(_w):
        return sp.simplify(expr)
    expr = expr.subs(_w, sp.exp(sp.I * azimuth))
    return sp.simplify(sp.expand_complex(sp.expand(expr)).rewrite(sp.cos))


def multiblade_names(n_blades):
    names = ["0"] + [f"{n}{p}" for n in range(1, (n_blades - 1) // 2 + 1) for p in "cs"]
    return names + (["d"] if n_blades % 2 == 0 else [])


def multiblade_equations(equations: BladeEquations, n_blades: int, body_dofs, flap: bool):
    """Symbolic multiblade mass, damping and stiffness matrices.

    Parameters
    ----------
    equations : BladeEquations
    n_blades : int
    body_dofs : sequence of str
    flap : bool

    Returns
    -------
    names : list of str
        Coordinate names: body dofs, then ``lag_0``, ``lag_1c``, ..., then flap.
    mass, damping, stiffness : sympy.Matrix
    """
    kinds = ("lag", "flap") if flap else ("lag",)
    mb = multiblade_names(n_blades)
    basis = {"0": sp.Integer(1)}
    for name in mb[1:]:
        if name == "d":
            half = n_blades // 2
            basis[name] = ((_z / _w) ** half + (_w / _z) ** half) / 2
        else:
            n = int(name[:-1])
            basis[name] = _laurent_trig(n)[0 if name.endswith("c") else 1]
    columns = [(d, LOCAL_DOFS.index(d), sp.Integer(1)) for d in body_dofs]
    columns += [(f"{k}_{n}", LOCAL_DOFS.index(k), basis[n]) for k in kinds for n in mb]
    mb_mass, mb_damp, mb_stiff = (
        _blade_laurent(g) for g in (equations.mass, equations.damping, equations.stiffness)
    )
    b = BODY_SYMBOLS
    body = {
        "mass": {d: b[("mass_" if d in TRANSLATIONS else "inertia_") + d] for d in BODY_DOFS},
        "damping": {d: b[f"damping_{d}"] for d in BODY_DOFS},
        "stiffness": {d: b[f"stiffness_{d}"] for d in BODY_DOFS},
    }
    size = len(columns)
    out = [sp.zeros(size, size) for _ in range(3)]
    for i, (name_i, li, row) in enumerate(columns):
        for j, (_, lj, col) in enumerate(columns):
            d1 = _ddt(col)
            d2 = _ddt(d1)
            m_ij, c_ij, k_ij = mb_mass[li, lj], mb_damp[li, lj], mb_stiff[li, lj]
            terms = (
                row * m_ij * col,
                row * (2 * m_ij * d1 + c_ij * col),
                row * (m_ij * d2 + c_ij * d1 + k_ij * col),
            )
            for g, term in enumerate(terms):
                value = _to_real(_blade_sum(term, n_blades))
                if i == j and name_i in BODY_DOFS:
                    value += body[("mass", "damping", "stiffness")[g]][name_i]
                out[g][i, j] = value
    return [c[0] for c in columns], out[0], out[1], out[2]
