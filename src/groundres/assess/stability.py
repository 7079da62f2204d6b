"""Stability over a speed sweep: the growth threshold, unstable ranges, worst values.

A real part counts as positive above ``GROWTH_PER_RADIAN * Omega`` (growth of
more than one millionth per radian of rotor rotation) plus ``GROWTH_FLOOR``
(1e-9 1/s, for the rotor at rest), so that neutral modes of undamped cases
and near-repeated eigenvalues do not turn into instabilities through
round-off. Unstable ranges come from the largest real part on the sweep and
on an internal grid (:mod:`groundres.assess.scan`), with the local maxima refined
(ranges narrower than the grid) and, for eigen-analyses, the places where two
roots meet (undamped coalescences); their ends come from root finding, not
from the grid spacing. A range open at the first speed that turns is followed
down towards rest (:func:`_start_above_rest`), a periodic analysis only as
far as its cost allows (:func:`groundres.solve.floquet.cost.lowest_periodic_speed`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize_scalar

from ..modes.identify import damping_ratio
from ..solve.floquet.cost import REST_HALVINGS
from . import scan

GROWTH_PER_RADIAN = 1e-6
#: [1/s] added to the threshold: at rest the neutral roots sit at round-off.
GROWTH_FLOOR = 1e-9


def growth_threshold(speeds):
    """Real part [1/s] above which a root counts as unstable at each speed."""
    return GROWTH_PER_RADIAN * np.asarray(speeds, dtype=float) + GROWTH_FLOOR


def is_neutral(real_part, speeds):
    """Whether real parts [1/s] at ``speeds`` [rad/s] are round-off: ``|real part|``
    at or below the growth threshold (neither growth nor decay)."""
    return np.abs(real_part) <= growth_threshold(speeds)


#: Real parts within this fraction of the growth threshold of zero are a neutral
#: root's (an undamped flap, a blade whose damper failed): round-off far below it.
NEUTRAL_BAND = 1e-3


def largest_real_part(real, speeds, neutral: bool = True, bound=None) -> np.ndarray:
    """Largest of real parts (n_s, k) [1/s] at each speed; without ``neutral``, over the
    roots not within :data:`NEUTRAL_BAND` of the growth threshold of zero (0 if none).

    A neutral root never grows, so leaving it out changes no verdict, but it
    would flatten the largest real part where every other root decays and hide
    the peak of the mode that decides (the damping search follows that peak).
    With ``bound`` (n_s, k), lower or upper bounds of the real parts, the
    largest of those over the same roots: a lower or an upper bound of it.
    """
    real = np.asarray(real, dtype=float)
    value = real if bound is None else np.asarray(bound, dtype=float)
    if neutral:
        return value.max(-1)
    band = NEUTRAL_BAND * growth_threshold(speeds)[:, None]
    masked = np.where(np.abs(real) <= band, -np.inf, value).max(-1)
    return np.where(np.isfinite(masked) | (masked > 0), masked, 0.0)


def growth_of(solver):
    """``growth(speeds, neutral=True)``: the largest real part [1/s] of ``solver``'s roots at
    any speeds (:meth:`groundres.solve.solvers.Solver.real_parts`, :func:`largest_real_part`)."""

    def growth(speeds, neutral=True):
        speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
        return largest_real_part(solver.real_parts(speeds), speeds, neutral)

    return growth


def rough_growth_of(solver):
    """``rough_growth(speeds, neutral=True) -> (value, lower, upper)``: :func:`growth_of` at the
    solver's looser scan accuracy, with bounds of the exact value; None where the solver
    has no cheaper scan (:attr:`groundres.solve.solvers.Solver.rough_real_parts`)."""
    if solver.rough_real_parts is None:
        return None

    def rough_growth(speeds, neutral=True):
        speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
        real, lower, upper = solver.rough_real_parts(speeds)
        return tuple(largest_real_part(real, speeds, neutral, bound) for bound in (None, lower, upper))

    return rough_growth


def continuing_roots(roots, targets, w, unique: bool) -> tuple[np.ndarray, np.ndarray]:
    """The root that continues each target eigenvalue at its speed, frequency made positive,
    and every candidate (k, r) it was chosen among.

    ``roots`` (k, r) are every root at the speeds ``w`` (k,) [rad/s] and
    ``targets`` (k,) the eigenvalues expected there (interpolated from a
    sweep, frequency >= 0). Where frequencies are ``unique`` (a multiblade
    eigen-analysis) the nearest root is taken as it is; otherwise (a root
    known modulo the rotor speed, or seen from other axes) its frequency is
    first shifted by the multiple of the rotor speed that brings it nearest.
    """
    roots, targets = np.asarray(roots), np.asarray(targets)
    w = np.asarray(w, float)[:, None]
    if unique:
        cand = roots.real + 1j * np.abs(roots.imag)
    else:
        m = np.rint((targets.imag[:, None] - roots.imag) / w)
        cand = roots.real + 1j * np.abs(roots.imag + m * w)
    return cand[np.arange(len(targets)), np.argmin(np.abs(cand - targets[:, None]), axis=1)], cand


def interpolated(modes, speeds, w, columns=None) -> np.ndarray:
    """The modes' eigenvalues interpolated at speeds ``w`` [rad/s] (one per column, or per
    mode in ``columns``)."""
    lam = modes.eigenvalue
    columns = range(lam.shape[1]) if columns is None else columns
    w = np.broadcast_to(np.asarray(w, float), (len(columns),))
    return np.array(
        [
            complex(np.interp(x, speeds, lam[:, k].real), np.interp(x, speeds, lam[:, k].imag))
            for x, k in zip(w, columns)
        ]
    )


def smallest_damping_ratio_at(roots, modes, speeds, w: float, unique: bool) -> float:
    """Smallest damping ratio [-] at speed ``w`` [rad/s] over the roots that continue the modes.

    ``roots`` are every root at ``w``; ``modes`` the sweep's
    (:class:`groundres.modes.identify.Modes`) at ``speeds``. Where frequencies
    are ``unique`` (a multiblade eigen-analysis) every root counts; otherwise
    each mode's root is the one that continues it (:func:`continuing_roots`).
    """
    roots = np.asarray(roots)
    if unique:
        cand = roots.real + 1j * np.abs(roots.imag)
        return float(damping_ratio(cand, scale=np.abs(cand).max()).min())
    targets = interpolated(modes, speeds, w)
    k = len(targets)
    best, cand = continuing_roots(np.broadcast_to(roots, (k, len(roots))), targets, np.full(k, w), unique)
    return float(damping_ratio(best, scale=np.abs(cand).max()).min())


@dataclass(frozen=True)
class Stability:
    """Stability of a sweep.

    Attributes
    ----------
    unstable_ranges : list of (float, float)
        Rotor-speed intervals [rad/s] where some root has a positive real part.
    max_real_part : (float, float)
        Largest real part [1/s] over the sweep and the speed [rad/s] where it occurs.
    min_damping_ratio : (float, float)
        Smallest damping ratio [-] over the sweep and its speed [rad/s].
    peak_speeds : tuple of float
        Speed [rad/s] of the largest real part inside each unstable range.
    open_below : float or None
        Where the first range begins at the lowest speed the analysis reaches
        above rest (a periodic analysis costs more the slower the rotor: see
        :func:`groundres.solve.floquet.cost.lowest_periodic_speed`), that speed [rad/s]:
        the range may begin lower. None otherwise.
    """

    unstable_ranges: list
    max_real_part: tuple
    min_damping_ratio: tuple
    peak_speeds: tuple = ()
    open_below: float | None = None

    @property
    def stable(self) -> bool:
        return not self.unstable_ranges


def _refine_max(fun, speeds, values, i, xtol=1e-6):
    """Maximise fun near grid point i (bounded by its neighbours; never between
    the rotor at rest and the first speed that turns: the value at rest is exact
    and a periodic analysis just above it is the costliest of the sweep)."""
    if speeds[i] <= 0:
        return float(values[i]), float(speeds[i])
    lo, hi = speeds[max(i - 1, 0)], speeds[min(i + 1, len(speeds) - 1)]
    if lo <= 0:
        lo = speeds[i]
    if hi <= lo:
        return values[i], speeds[i]
    top, at = _maximise(fun, lo, hi, xtol)
    if top > values[i]:
        return top, at
    return float(values[i]), float(speeds[i])


def _maximise(fun, lo: float, hi: float, xtol: float) -> tuple[float, float]:
    """Largest value of ``fun`` on [lo, hi] and where (bounded Brent, to ``xtol`` relative to hi)."""
    res = minimize_scalar(lambda w: -fun(w), bounds=(lo, hi), method="bounded", options={"xatol": xtol * hi})
    return float(-res.fun), float(res.x)


def find_ranges(grid, values, excess, periodic=False, peaks=8, closeness=None, floor=0.0, rough=None):
    """Intervals where ``excess`` (largest real part minus the growth threshold) is positive.

    Parameters
    ----------
    grid : ndarray (n,)
        Speeds [rad/s], increasing: the sweep's and an internal grid
        (:func:`groundres.assess.scan.probe_speeds`).
    values : ndarray (n,)
        ``excess`` on the grid [1/s].
    excess : callable
        ``excess(speeds) -> values`` at any speeds (arrays).
    periodic : bool
        A periodic (Floquet) analysis: sets the accuracy of the refined peaks
        (:data:`groundres.assess.scan.PEAK_XTOL`).
    peaks : int
        Local maxima of the grid values refined to find ranges narrower than
        the grid (the largest first).
    closeness : callable, optional
        ``closeness(speeds)``: nearest approach of two roots
        (:func:`groundres.solve.modal.closest_pair`). An undamped coalescence range
        has no bump outside it (its roots are neutral until they meet), but
        its roots approach: the deepest local minima of the closeness are
        refined to where the roots meet, and the growth is probed beside it.
    floor : float
        Lowest speed [rad/s] analysed between rest and the grid's first turning
        speed (:func:`_start_above_rest`); 0 for no limit but round-off.
    rough : callable, optional
        ``rough(speeds) -> (values, lower, upper)``: ``excess`` at a looser
        accuracy, for crossings and peaks to be looked for with
        (:func:`groundres.assess.scan.crossing`, :func:`groundres.assess.scan.zoom_many`).

    Returns
    -------
    ranges : list of (float, float)
        Interior ends to 1e-10 relative; ranges open at an end of the grid report that end.
    peak_speeds : list of float
        Speed of the largest excess inside each range.
    open_below : float or None
        The first range's start where it grows at the lowest speed tried above
        rest (``floor``): the range may begin lower.
    """
    grid, values = np.asarray(grid, float), np.asarray(values, float)
    n = len(grid)
    found = []  # (start, end, peak speed, peak value)
    open_at = None
    i = 0
    while i < n:
        if values[i] <= 0:
            i += 1
            continue
        j = i
        while j + 1 < n and values[j + 1] > 0:
            j += 1
        if i == 0:
            start = grid[0]
        elif grid[i - 1] <= 0:  # the range begins somewhere between rest and grid[i]
            start, open_at = _start_above_rest(excess, grid[i], floor, rough)
        else:
            start = _end(excess, grid[i - 1], grid[i], rough)
        end = grid[-1] if j == n - 1 else scan.crossing(excess, grid[j], grid[j + 1], rough)
        k = i + int(np.argmax(values[i : j + 1]))
        found.append([float(start), float(end), float(grid[k]), float(values[k])])
        i = j + 1
    spans = [scan.bracket(grid, i) for i in scan.local_maxima(values, peaks) if values[i] <= 0 < grid[i]]
    spans = [(lo, hi) for lo, hi in spans if hi > lo]
    # (refined together: one call of ``excess`` per round for all of them)
    look = None if rough is None else (lambda w: rough(w)[0])
    for (lo, hi), (top, at) in zip(
        spans, scan.zoom_many(excess, spans, scan.PEAK_XTOL[periodic], rough=look)
    ):
        if top <= 0 or any(a <= at <= b for a, b, _, _ in found):
            continue
        # a range narrower than the grid: its ends on either side of the peak
        found.append([float(_end(excess, lo, at, rough)), float(_fall(excess, at, hi, rough)), at, top])
    if closeness is not None:
        near = np.asarray(closeness(grid), float)
        for i in scan.local_maxima(-near, peaks):
            lo, hi = scan.bracket(grid, i)
            if grid[i] <= 0 or hi <= lo:
                continue
            _, meet = scan.zoom_max(lambda w: -np.asarray(closeness(w)), lo, hi, 1e-12)
            if any(a * (1 - 1e-6) <= meet <= b * (1 + 1e-6) for a, b, _, _ in found):
                continue  # the meeting point of a range already found (one of its ends)
            side = meet * 10.0 ** -np.arange(10.0, 3.0, -1.0)
            probe = np.clip(np.concatenate([meet - side, meet + side]), lo, hi)
            v = np.asarray(excess(probe), float)
            if v.max() <= 0:
                continue
            at = float(probe[int(np.argmax(v))])
            found.append(
                [float(_end(excess, lo, at, rough)), float(_fall(excess, at, hi, rough)), at, float(v.max())]
            )
    ranges, peaks = _merged(found)
    return ranges, peaks, (open_at if ranges and open_at is not None and ranges[0][0] == open_at else None)


def _merged(found):
    """Ranges (start, end, peak speed, peak value) sorted, overlapping ones joined."""
    out = []
    for a, b, w, v in sorted(found):
        if out and a <= out[-1][1] * (1 + 1e-9):
            last = out[-1]
            last[1] = max(last[1], b)
            if v > last[3]:
                last[2], last[3] = w, v
        else:
            out.append([a, b, w, v])
    return [(a, b) for a, b, _, _ in out], [w for _, _, w, _ in out]


def _start_above_rest(excess, first, floor, rough=None):
    """Where a range that is open at ``first`` (the grid's first speed above
    rest) begins: the speeds first / 2, first / 4, ... down to ``floor`` are
    tried in one call, then the crossing refined between the last stable one
    and the next. A range still growing at the lowest speed tried starts there
    (:attr:`Stability.open_below` says so).

    Returns
    -------
    (start, open_at) : (float, float or None)
        ``open_at`` is ``start`` where the range is still open there.
    """
    floor = max(floor, first * 2.0**-REST_HALVINGS)
    if floor > 0.5 * first:  # no slower speed affordable: the range is open at the first
        return float(first), float(first)
    count = int(np.floor(np.log2(first / floor)))
    w = first * 2.0 ** -np.arange(1, count + 1)
    v = np.asarray(excess(w), float)
    calm = np.flatnonzero(v <= 0)
    if not len(calm):
        return float(w[-1]), float(w[-1])
    j = int(calm[0])
    return scan.crossing(excess, float(w[j]), float(first if j == 0 else w[j - 1]), rough), None


def _end(excess, lo, hi, rough=None):
    """The rising crossing in [lo, hi], or lo if excess is already positive there."""
    if float(excess(np.array([lo]))[0]) > 0:
        return lo
    return scan.crossing(excess, lo, hi, rough)


def _fall(excess, lo, hi, rough=None):
    """The falling crossing in [lo, hi], or hi if excess is still positive there."""
    if float(excess(np.array([hi]))[0]) > 0:
        return hi
    return scan.crossing(excess, lo, hi, rough)


def _probed(excess, rough, probe):
    """``excess`` on the internal grid: with a rough look where its bounds settle the
    sign, and ``excess`` itself where they do not."""
    if not len(probe):
        return np.zeros(0)
    if rough is None:
        return np.asarray(excess(probe, neutral=True), float)
    value, lower, upper = (np.asarray(v, float) for v in rough(probe, neutral=True))
    open_ = (lower <= 0) & (upper > 0)
    if open_.any():
        value[open_] = excess(probe[open_], neutral=True)
    return value


def assess(
    speeds,
    max_real,
    min_damping,
    growth,
    max_real_at,
    min_damping_at,
    probe=None,
    periodic=False,
    closeness=None,
    floor=0.0,
    rough_growth=None,
):
    """Unstable ranges and refined worst values for a sweep.

    Parameters
    ----------
    speeds : ndarray (n_s,)
        The sweep [rad/s].
    max_real, min_damping : ndarray (n_s,)
        Largest real part [1/s] and smallest damping ratio [-] at each sweep speed.
    growth : callable
        ``growth(speeds, neutral=True) -> largest real part`` at any speeds
        (arrays, roots only); without ``neutral``, of the roots that are not
        neutral (:func:`largest_real_part`).
    max_real_at, min_damping_at : callable
        The same quantities at one speed, as accurate as the sweep's (to refine the worst values).
    probe : ndarray, optional
        Internal speeds between the sweep's (:func:`groundres.assess.scan.probe_speeds`).
    periodic : bool
        A periodic (Floquet) analysis, whose roots are known modulo the rotor speed.
    closeness : callable, optional
        Nearest approach of two roots at given speeds (:func:`find_ranges`).
    floor : float
        Lowest speed [rad/s] analysed above rest (:func:`find_ranges`).
    rough_growth : callable, optional
        ``rough_growth(speeds, neutral=True) -> (value, lower, upper)``:
        ``growth`` at a looser accuracy, for the internal grid and the
        searches to look with; ``growth`` decides every sign that its bounds
        leave open.

    The crossings and narrow ranges are searched on the largest real part of
    the roots that are not neutral: it has the sign of the whole one
    everywhere (a neutral root never grows), and no corner where a decaying
    root rises through a neutral one just before it crosses the threshold.
    """
    speeds = np.asarray(speeds, float)
    probe = np.zeros(0) if probe is None else np.asarray(probe, float)

    def excess(w, neutral=False):
        w = np.asarray(w, float)
        return growth(w, neutral=neutral) - growth_threshold(w)

    rough = None
    if rough_growth is not None:

        def rough(w, neutral=False):
            w = np.asarray(w, float)
            return tuple(v - growth_threshold(w) for v in rough_growth(w, neutral=neutral))

    grid = np.concatenate([speeds, probe])
    values = np.concatenate([max_real - growth_threshold(speeds), _probed(excess, rough, probe)])
    order = np.argsort(grid, kind="stable")
    grid, values = grid[order], values[order]
    ranges, peak_speeds, open_below = find_ranges(
        grid, values, excess, periodic, closeness=closeness, floor=floor, rough=rough
    )
    i = int(np.argmax(values))
    sweep_i = int(np.argmin(np.abs(speeds - grid[i])))
    xtol = 1e-6
    if grid[i] in speeds:
        worst = _refine_max(max_real_at, speeds, max_real, sweep_i, xtol)
    else:  # the worst speed lies between the sweep's: refine there
        worst = _maximise(max_real_at, *scan.bracket(grid, i), xtol)
    at = worst[1]
    if worst[0] > growth_threshold(at) and not any(a <= at <= b for a, b in ranges):
        # the refined worst value grows where no range was found: its range, narrower than the grid
        lo, hi = scan.bracket(grid, i)
        lo, hi = min(lo, at), max(hi, at)
        start = _end(excess, lo, at) if float(excess(np.array([at]))[0]) > 0 else at
        end = hi if start == at else _fall(excess, at, hi)
        ranges, peak_speeds = zip(*sorted(list(zip(ranges, peak_speeds)) + [((start, end), at)]))
        ranges, peak_speeds = list(ranges), list(peak_speeds)
    j = int(np.nanargmin(min_damping))
    low = _refine_max(lambda w: -min_damping_at(w), speeds, -min_damping, j, xtol)
    # the sweep's grid alone may miss where the damping ratio is smallest (a coarse
    # sweep): the worst speeds of the real part, found on the internal grid, are
    # looked at too, and the smallest refined between its grid neighbours
    for w in sorted({float(at), *map(float, peak_speeds)} - {float(low[1])}):
        if w <= 0:
            continue
        ratio = float(min_damping_at(w))
        if ratio < -low[0]:
            low = (-ratio, w)
            if not periodic:
                k = int(np.argmin(np.abs(grid - w)))
                lo, hi = scan.bracket(grid, k)
                top, where = _maximise(lambda x: -min_damping_at(x), min(lo, w), max(hi, w), xtol)
                if top > -ratio:
                    low = (top, where)
    return Stability(
        unstable_ranges=ranges,
        max_real_part=worst,
        min_damping_ratio=(-low[0], low[1]),
        peak_speeds=tuple(peak_speeds),
        open_below=open_below,  # (no range is added below it: it starts at the lowest speed)
    )
