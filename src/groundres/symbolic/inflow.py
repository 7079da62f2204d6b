"""What Pitt-Peters dynamic inflow adds to one blade's equations in air (derived).

The blade's trim, kinematics and strip-theory loads are those of
:mod:`groundres.symbolic.aero`; here the air at the section gains three
inflow states down the shaft, and the blade's share of the inflow's forcing
(its thrust and the first moments of its shaft-normal load) is linearised
about the trim like its own generalised forces (``docs/theory.md``,
"Dynamic inflow"). The inflow's own apparent mass and damping are added
numerically by :mod:`groundres.model.inflow`.
"""

from __future__ import annotations

import sympy as sp

from .aero import (
    _RING,
    BLADE_SYMBOLS,
    COORDS,
    HARMONICS,
    LOCAL_DOFS,
    Terms,
    _at_trim,
    _dot,
    _harmonic_split,
    _kinematics,
    _span_integral,
    _terms,
    _Trim,
)
from .derive import blade_geometry


def _arms():
    """The section's distances forward and to the left of the hub centre, in the body's axes,
    as functions of the coordinates (the first-moment arms, before division by the tip radius)."""
    _, _, body = blade_geometry()
    p = BLADE_SYMBOLS
    point = _kinematics()[0]
    hub = sp.Matrix(COORDS[:3]) + body * sp.Matrix([p["hub_x"], p["hub_y"], p["hub_height"]])
    return [(point - hub).dot(body[:, k]) for k in (0, 1)]


def derive_inflow_coupling() -> Terms:
    """What dynamic inflow adds to one blade's equations, as Terms of shape (2, 5, 11, 11):
    [damping, stiffness] x HARMONICS x (LOCAL_DOFS + the inflow states of
    :data:`groundres.symbolic.codegen.INFLOW_STATES`)^2.

    The inflow states enter as velocities v_m (the rates of coordinates that appear
    nowhere else): the air at the section comes down the shaft at ``lambda Omega R
    + v_0 + v_1 X/R + v_2 Y/R``, X and Y the section's trim position forward and
    to the left of the hub. Rows 0-7 get the blade's generalised forces per unit
    v_m (damping columns 8-10). Rows 8-10 are minus this blade's share of the
    inflow's forcing: its thrust ``int F . s`` and the first moments ``int (X/R)
    F . s`` and ``int (Y/R) F . s`` of its shaft-normal load at the deflected
    section positions, per unit change of each coordinate, rate and inflow
    state. The inflow's own apparent mass and damping are added numerically
    (:mod:`groundres.model.inflow`).
    """
    trim = _Trim()
    shaft = _kinematics()[3]
    arms = _arms()
    arm0 = [_RING.one] + [_at_trim(x) for x in arms]  # (the weights of the inflow states)
    n, k = len(LOCAL_DOFS), len(arm0)
    arm_q = [[_RING.zero] * n] + [[_at_trim(x.diff(q)) for q in COORDS] for x in arms]
    ds_q = [_at_trim(shaft.diff(q)) for q in COORDS]
    load = _dot(trim.force, trim.shaft)
    per_inflow = [trim.force_change_in([w * c for c in trim.shaft]) for w in arm0]
    polys, per_tip = {}, {}

    def put(g, i, j, poly):  # (an arm in row or column: divided by the tip radius)
        for h, part in enumerate(_harmonic_split(_span_integral(poly))):
            if part:
                polys[(g, h, i, j)] = -part
                per_tip[(g, h, i, j)] = (i > n) + (j > n)

    for m, force in enumerate(per_inflow):
        for i in range(n):
            put(0, i, n + m, _dot(force, trim.partial[i]))
        for r in range(k):
            put(0, n + r, n + m, arm0[r] * _dot(force, trim.shaft))
    for j in range(n):
        moved = _dot(trim.force_change(j, rate=False), trim.shaft) + _dot(trim.force, ds_q[j])
        pushed = _dot(trim.force_change(j, rate=True), trim.shaft)
        for r in range(k):
            put(1, n + r, j, arm_q[r][j] * load + arm0[r] * moved)
            put(0, n + r, j, arm0[r] * pushed)
    return _terms(polys, (2, len(HARMONICS), n + k, n + k), per_tip)
