"""Floquet analysis of a rotor in air: each speed on the equations frozen at its own trim.

The periodic machinery (node matrices on fixed azimuth grids shared by every
speed, :mod:`groundres.solve.floquet.coefficients`) rests on the equations being
polynomials in the rotor speed: mass constant, damping linear, stiffness
quadratic. In air the hover trim (coning, trim lag, inflow) changes with the
speed, so they are not; with the trim held they are again, and they equal the
true equations at the speed whose trim is held. So a sweep in air is solved
speed by speed, each on its own frozen system, and the solutions joined.
"""

from __future__ import annotations

import numpy as np

from .coefficients import per_speed

#: The fields of a Floquet solution that run over the speeds (the others are shared).
_PER_SPEED = (
    "exponent",
    "multiplier",
    "vector",
    "harmonics",
    "steps",
    "lifted",
    "key",
    "real_lower",
    "real_upper",
)


def in_air(solve, system, speeds, damping=None, progress=None, **options):
    """``solve`` (:func:`groundres.solve.floquet.exponents.solve`) of a rotor in air at ``speeds``:
    speed by speed, each on ``system`` frozen at that speed's trim
    (:meth:`groundres.model.system.System.frozen`), the solutions joined into one.

    ``damping`` (per speed along the system's damping directions) and ``options`` are
    ``solve``'s; ``progress(done, total)`` is called after each speed.
    """
    damping = per_speed(damping, len(speeds))
    if not len(speeds):  # (nothing to solve: the shapes, from the system frozen at rest)
        return solve(system.frozen(0.0), speeds, damping=damping, **options)
    parts = []
    for i, w in enumerate(speeds):
        each = None if damping is None else damping[i : i + 1]
        parts.append(solve(system.frozen(w), speeds[i : i + 1], damping=each, **options))
        if progress is not None:
            progress(i + 1, len(speeds))
    joined = {}
    for name in _PER_SPEED:
        values = [getattr(p, name) for p in parts]
        joined[name] = None if values[0] is None else np.concatenate(values)
    first = parts[0]
    return type(first)(orders=first.orders, symmetry=first.symmetry, speeds=speeds, **joined)
