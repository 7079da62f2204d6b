"""What a study records at each grid point: stability measures of one speed sweep.

The measures are those of ``groundres run`` on the same case (its
``summary.json``): the unstable ranges (ends to 1e-10 relative) and the
refined worst values of :func:`groundres.analyze`, without the exact
lag-damping search, which a study's own grid replaces.
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis import analyze
from ..errors import CaseError, MethodError, ModelRangeError, SpeedRangeError

#: name -> (dtype, units, long_name): the data variables of a study.
MEASURES = {
    "max_real_part": ("f8", "1/s", "largest real part of the roots over the sweep"),
    "min_damping_ratio": ("f8", "1", "smallest damping ratio of the roots over the sweep"),
    "unstable_width": ("f8", "rad/s", "total width of the unstable rotor-speed ranges"),
    "first_unstable_speed": ("f8", "rad/s", "lowest rotor speed of an unstable range (NaN if stable)"),
    "stable": ("bool", "1", "no root grows anywhere in the sweep"),
}
#: Why a grid point has no measures ("" where it has).
ERROR = "error"
#: Exceptions that make a grid point fail (recorded, the study goes on): a case
#: made invalid by its values, or one the model cannot analyse. Anything else
#: (a lost worker, memory, a fault) fails the task: it is not marked done, so a
#: resume computes it again.
POINT_ERRORS = (CaseError, MethodError, ModelRangeError, SpeedRangeError)


def empty(n: int) -> dict:
    """Measures of ``n`` points before any is computed (NaN, False, no error)."""
    out = {
        name: np.full(n, np.nan) if dtype == "f8" else np.zeros(n, bool)
        for name, (dtype, *_) in MEASURES.items()
    }
    out[ERROR] = np.full(n, "", dtype=object)
    return out


def stability_of(case):
    """The case's :class:`groundres.assess.stability.Stability`: :func:`groundres.analyze` without the
    damping search."""
    return analyze(case, lag_damping_search=False).stability


def of_case(case) -> dict:
    """The measures of one case (scalars, :func:`stability_of`)."""
    stability = stability_of(case)
    ranges = stability.unstable_ranges
    return {
        "max_real_part": float(stability.max_real_part[0]),
        "min_damping_ratio": float(stability.min_damping_ratio[0]),
        "unstable_width": float(sum(b - a for a, b in ranges)),
        "first_unstable_speed": float(ranges[0][0]) if ranges else math.nan,
        "stable": bool(stability.stable),
    }


def failed(err: Exception) -> str:
    """The reason a grid point failed, one line."""
    text = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
    return text if isinstance(err, CaseError) else f"{type(err).__name__}: {text}"
