"""The stability boundary along one key, for every value of the others, by root finding.

Instead of a full grid, each line of the study (the other keys and the
failure held) is searched along the boundary key between its range's ends:
where the sweep's verdict differs at the two ends, Brent's method finds the
value where it changes, on the largest real part less the growth threshold
at its speed (continuous, its sign the sweep's verdict), to a tenth of the
grid spacing the key's COUNT would give. A line whose ends agree has no
boundary in the range (NaN; ``stable_at_start`` says on which side the whole
line lies). A line costs about ten sweeps instead of COUNT.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from ..assess.stability import growth_threshold
from .grid import Grid, varied_case
from .measures import POINT_ERRORS, failed, stability_of

#: Boundary tolerance, in grid spacings of the key.
XTOL = 0.1
#: name -> (dtype, long_name) of a boundary study's variables (units: the key's, for ``boundary``).
VARIABLES = {
    "boundary": ("f8", "value of the key where the sweep's stability changes (NaN: none in the range)"),
    "stable_at_start": ("bool", "the sweep is stable at the start of the key's range"),
    "evaluations": ("i8", "speed sweeps the search took (0: another line's answer, the same rotor turned)"),
}


def signed_excess(case) -> float:
    """Largest real part less the growth threshold at its speed [1/s], signed by the verdict."""
    stability = stability_of(case)
    value, speed = stability.max_real_part
    excess = float(value - growth_threshold(np.array([speed]))[0])
    return -abs(excess) if stability.stable else abs(excess)


def line(data, source, others: Grid, key: str, span: tuple, flat: int) -> dict:
    """The boundary along ``key`` over ``span`` (start, stop, the grid's smallest spacing) of one
    line of ``others``."""
    values, failure = others.point(flat)
    lo, hi, spacing = span
    evaluations = 0

    def f(v):
        nonlocal evaluations
        evaluations += 1
        return signed_excess(varied_case(data, {**values, key: float(v)}, failure, source))

    try:
        f_lo, f_hi = f(lo), f(hi)
        at = math.nan
        if (f_lo > 0) != (f_hi > 0):
            at = brentq(f, min(lo, hi), max(lo, hi), xtol=XTOL * spacing, rtol=1e-12)
        return {"boundary": at, "stable_at_start": f_lo <= 0, "evaluations": evaluations, "error": ""}
    except POINT_ERRORS as err:  # (recorded with its reason; the study goes on)
        return {
            "boundary": math.nan,
            "stable_at_start": False,
            "evaluations": evaluations,
            "error": failed(err),
        }


def lines(data, source, others, key, span, flats) -> list[dict]:
    """:func:`line` for each of ``flats`` (the single failures of alike blades searched once:
    :func:`groundres.studies.run.compute_points`)."""
    from .run import failure_class

    seen, out = {}, []
    for i in flats:
        values, failure = others.point(int(i))
        # (alike all along the line: at both ends of a rotor-wide key, whose blade overrides, if
        # any, stay put while it moves; a key of one blade, rod or leg makes them differ)
        ends = [{**values, key: v} for v in span[:2]]
        classes = {failure_class(data, end, failure, source) for end in ends}
        alike = "[" not in key and len(classes) == 1 and failure not in classes
        ident = (tuple(values.items()), classes.pop() if alike else failure)
        if ident in seen:  # (no sweep of its own: another line turned)
            out.append({**seen[ident], "evaluations": 0})
            continue
        seen[ident] = line(data, source, others, key, span, int(i))
        out.append(seen[ident])
    return out
