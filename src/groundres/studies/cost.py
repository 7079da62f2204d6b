"""What a study costs, estimated before it runs, and the limit beyond which it is refused.

A study's time is the number of analyses it makes times the time of one,
shared between its workers. The time of one is measured, not modelled: the
case as written is analysed once in this process, on one thread, as a
worker analyses a grid point; with failures its first failure is analysed
too (a failed damper turns a rotor of identical blades from a multiblade
eigen-analysis into a Floquet one, tens of times dearer). The number of
analyses counts the points not yet in the store, each failure of alike blades
once (:func:`groundres.studies.run.failure_class`), and for a boundary study
:data:`SWEEPS_PER_LINE` sweeps a line. A study estimated above ``hours`` of
wall-clock time is refused before any cluster starts, with the estimate and
what to change (:func:`check`).

The estimate assumes every point costs what the case costs; a grid that
varies the sweep itself (its start, its points) or takes the rotor much
slower or stiffer can cost more, which the progress bar's time left shows
as the study goes.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

from ..errors import StudyError
from .grid import NO_FAILURE, Grid, raw, varied_case
from .measures import POINT_ERRORS, of_case
from .run import failure_class

#: The wall-clock limit of a study [h] unless the caller gives another (``--max-hours``).
MAX_HOURS = 4.0
#: Sweeps a boundary line costs, about (:mod:`groundres.studies.search`: its two ends and
#: Brent's method to a tenth of the grid's spacing).
SWEEPS_PER_LINE = 12


@dataclass(frozen=True)
class Estimate:
    """A study's cost: ``analyses`` sweeps of ``seconds`` each (the mean of the measured
    ones, weighted by how many of each the study makes), on ``workers`` workers."""

    analyses: int
    seconds: float
    workers: int

    @property
    def hours(self) -> float:
        """Wall-clock hours, the work shared evenly between the workers."""
        return self.analyses * self.seconds / max(self.workers, 1) / 3600.0

    def text(self) -> str:
        wall = self.hours * 3600.0
        if wall < 120:
            when = f"{wall:.0f} s"
        else:
            when = f"{wall / 60:.0f} min" if wall < 7200 else f"{wall / 3600:.3g} h"
        return (
            f"about {when} ({self.analyses} sweeps of about {self.seconds:.2g} s on "
            f"{self.workers} worker{'s' if self.workers != 1 else ''})"
        )


def sweep_seconds(case, failure: str = NO_FAILURE) -> float:
    """Seconds one sweep of ``case`` (with ``failure``) takes in this process on one thread, as
    a grid point does (a case the model refuses costs the time until its refusal)."""
    from ..solve import parallel

    data = raw(case)
    started = time.perf_counter()
    with parallel.in_place():
        try:
            of_case(varied_case(data, {}, failure, case.source))
        except POINT_ERRORS:  # (a point that fails costs what its refusal took)
            pass
    return time.perf_counter() - started


def estimate(case, grid: Grid, remaining: int, workers: int, boundary: str | None = None) -> Estimate:
    """The cost of computing ``remaining`` of the points of ``grid`` (or, for a ``boundary``
    study, all its lines) on ``workers`` workers."""
    if remaining <= 0:
        return Estimate(0, 0.0, workers)
    kinds = [NO_FAILURE]
    if grid.failures:
        data = raw(case)
        kinds += sorted({failure_class(data, {}, f, case.source) for f in grid.failures[1:]})
    seconds = {NO_FAILURE: sweep_seconds(case)}
    if len(kinds) > 1:
        seconds["failed"] = sweep_seconds(case, grid.failures[1])
    per_point = seconds[NO_FAILURE] + (len(kinds) - 1) * seconds.get("failed", 0.0)
    share = remaining / grid.size  # (the points still to compute, of every failure alike)
    points = math.prod(len(v) for v in grid.values)
    if boundary is not None:
        lines = points // max(len(grid.values[grid.keys.index(boundary)]), 1)
        analyses_per_point, points = SWEEPS_PER_LINE, lines
    else:
        analyses_per_point = 1
    analyses = max(1, round(share * points * len(kinds) * analyses_per_point))
    mean = per_point / len(kinds)
    return Estimate(analyses, mean, workers)


def check(estimated: Estimate, hours: float = MAX_HOURS) -> None:
    """Refuse a study estimated above ``hours`` of wall-clock time, saying what to change."""
    if estimated.hours <= hours:
        return
    raise StudyError(
        f"the study would take {estimated.text()}, more than --max-hours {hours:g}: use fewer "
        "points (a smaller COUNT in --vary), fewer speeds a sweep (--points), --boundary KEY "
        "instead of a grid along KEY, more workers (--scheduler), or a larger --max-hours"
    )
