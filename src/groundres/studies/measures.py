"""What a study records at each grid point: stability measures and margins of one speed sweep.

The measures are those of ``groundres run`` on the same case (its
``summary.json``): the margins (:mod:`groundres.assess.margins`: the growth
margin and the least damping ratios of the vibrating modes, which move with
the design on both sides of the stability boundary and are continuous across
it, so that a map can draw the boundary between its points), the unstable
ranges (ends to 1e-10 relative) and the refined worst values of every root,
all from :func:`groundres.analyze`, without the exact lag-damping search,
which a study's own grid replaces. A case whose lag dampers follow a nonlinear
law also records its limit cycles (:func:`groundres.assess.limit_cycles.predict`
over ``[limit_cycle]``): the smallest threshold and the largest stable cycle,
each with its speed, so that a study maps them against the law's keys.
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis import analyze
from ..assess.limit_cycles import predict
from ..errors import CaseError, MethodError, ModelRangeError, SpeedRangeError

#: name -> (dtype, units, long_name): the data variables of a study.
MEASURES = {
    "growth_margin": (
        "f8",
        "1/s",
        "largest real part of the vibrating modes over the sweep (positive grows)",
    ),
    "least_damping_ratio": ("f8", "1", "least damping ratio of the vibrating modes over the operating range"),
    "least_damping_ratio_run_up": ("f8", "1", "least damping ratio over the run-up (NaN without one)"),
    "margin": ("f8", "1", "least damping ratio over the operating range minus the required one (or zero)"),
    "max_real_part": ("f8", "1/s", "largest real part of the roots over the sweep"),
    "min_damping_ratio": ("f8", "1", "smallest damping ratio of the roots over the sweep"),
    "unstable_width": ("f8", "rad/s", "total width of the unstable rotor-speed ranges"),
    "first_unstable_speed": ("f8", "rad/s", "lowest rotor speed of an unstable range (NaN if stable)"),
    "stable": ("bool", "1", "no root grows anywhere in the sweep"),
    "smallest_threshold": (
        "f8",
        "rad",
        "least lag amplitude above which a disturbance grows (an unstable limit cycle), over the limit-cycle "
        "speeds; 0 where at some speed any disturbance grows without bound; where a threshold lies below the "
        "amplitudes searched (below_searched_speed_count), the amplitude the growth starts at (amplitude_min "
        "or above): an upper bound; NaN: none, or no nonlinear lag damper law",
    ),
    "smallest_threshold_speed": (
        "f8",
        "rad/s",
        "rotor speed of the smallest threshold (where it is 0: the first speed at which any disturbance "
        "grows)",
    ),
    "unbounded_speed_count": (
        "f8",
        "1",
        "number of limit-cycle speeds at which any disturbance grows without bound (small motion grows, no "
        "threshold there); NaN: no nonlinear lag damper law",
    ),
    "below_searched_speed_count": (
        "f8",
        "1",
        "number of limit-cycle speeds at which small motion does not grow but the smallest amplitude "
        "searched does (a threshold lies below amplitude_min); NaN: no nonlinear lag damper law",
    ),
    "stable_below_searched_speed_count": (
        "f8",
        "1",
        "number of limit-cycle speeds at which small motion grows but the amplitudes searched decay (a "
        "stable cycle lies below amplitude_min); NaN: no nonlinear lag damper law",
    ),
    "largest_stable_cycle": (
        "f8",
        "rad",
        "largest lag amplitude of a stable limit cycle over the limit-cycle speeds (where one lies below the "
        "amplitudes searched, the amplitude its decay starts at: an upper bound); NaN: none, or no nonlinear "
        "lag damper law",
    ),
    "largest_stable_cycle_speed": ("f8", "rad/s", "rotor speed of the largest stable cycle"),
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
    """The measures of one case (scalars; :func:`groundres.analyze` without the damping search)."""
    result = analyze(case, lag_damping_search=False, margins_of_every_mode=False)
    stability, margins = result.stability, result.margins
    ranges = stability.unstable_ranges
    growth, least, run_up = margins.growth_margin, margins.least("operating"), margins.least("run_up")
    return {
        "growth_margin": math.nan if growth is None else float(growth[0]),
        "least_damping_ratio": math.nan if least is None else float(least[0]),
        "least_damping_ratio_run_up": math.nan if run_up is None else float(run_up[0]),
        "margin": math.nan if margins.margin is None else float(margins.margin),
        "max_real_part": float(stability.max_real_part[0]),
        "min_damping_ratio": float(stability.min_damping_ratio[0]),
        "unstable_width": float(sum(b - a for a, b in ranges)),
        "first_unstable_speed": float(ranges[0][0]) if ranges else math.nan,
        "stable": bool(stability.stable),
        **cycle_measures(case),
    }


def cycle_measures(case) -> dict:
    """The smallest threshold and the largest stable limit cycle of a case with a nonlinear lag damper
    law over ``[limit_cycle]``'s speeds and amplitudes (amplitudes of the blade that moves most, rad);
    NaN without a law or without such a cycle. Where at some speed any disturbance grows without
    bound (:meth:`groundres.assess.limit_cycles.LimitCycles.unbounded`) the smallest threshold is
    0 at the first such speed: a threshold elsewhere would flatter the design. Else, where a
    threshold lies below the amplitudes searched
    (:meth:`groundres.assess.limit_cycles.LimitCycles.below_searched`) it is at most the amplitude
    the growth starts at, recorded as such where no threshold found is smaller; likewise a stable
    cycle below them bounds the largest stable cycle by the amplitude the decay starts at.
    ``unbounded_speed_count`` and ``below_searched_speed_count`` count those speeds."""
    names = (
        "smallest_threshold",
        "smallest_threshold_speed",
        "unbounded_speed_count",
        "below_searched_speed_count",
        "stable_below_searched_speed_count",
        "largest_stable_cycle",
        "largest_stable_cycle_speed",
    )
    out = dict.fromkeys(names, math.nan)
    if not case.rotor.nonlinear:
        return out
    options = case.limit_cycle
    speeds = np.linspace(case.sweep.start, case.sweep.stop, options.points)
    found = predict(case, speeds, searched=options.searched)
    cycles, unbounded, below = found.cycles, found.unbounded(), found.below_searched()
    thresholds, stable = [c for c in cycles if not c.stable], [c for c in cycles if c.stable]
    out["unbounded_speed_count"], out["below_searched_speed_count"] = float(len(unbounded)), float(len(below))
    at = found.speeds  # (the speeds predicted: a sweep's speed at rest is left out)
    candidates = [(c.amplitude, c.speed) for c in thresholds]
    candidates += [(found.lead(i)[1], float(at[i])) for i in below]  # (upper bounds)
    if unbounded:
        out["smallest_threshold"], out["smallest_threshold_speed"] = 0.0, float(at[unbounded[0]])
    elif candidates:
        out["smallest_threshold"], out["smallest_threshold_speed"] = min(candidates)
    sizes = [(c.amplitude, c.speed) for c in stable]
    settles = found.stable_below_searched()
    out["stable_below_searched_speed_count"] = float(len(settles))
    sizes += [(found.lead(i)[1], float(at[i])) for i in settles]  # (upper bounds)
    if sizes:
        out["largest_stable_cycle"], out["largest_stable_cycle_speed"] = max(sizes)
    return out


def failed(err: Exception) -> str:
    """The reason a grid point failed, one line."""
    text = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
    return text if isinstance(err, CaseError) else f"{type(err).__name__}: {text}"
