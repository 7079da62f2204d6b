"""A quantity scanned over rotor speed: internal grids, peaks, sign changes.

Range detection and the damping search look at the largest real part of
the roots as a function of rotor speed. The sweep's own grid may be coarse
(two points), so both evaluate that function on an internal grid as well:
uniform over the sweep and dense around the speeds where the regressive lag
mode meets a body mode (the tuning speeds Omega (1 - nu) = omega_b), where
ground resonance lives. A range narrower than the grid still shows as a
local maximum of the function, which :func:`zoom_max` refines; the ends of
a range come from root finding (:func:`crossing`), never from the grid.
Every function here takes ``fun(speeds) -> values`` on arrays, so that a
batch of speeds costs one call (one batched integration for Floquet).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

#: Internal grid (uniform points, points around each tuning speed) of an eigen-analysis
#: (False) and a periodic one (True); a Floquet sweep of n points adds max(0, 48 - n/2) uniform ones (a
#: sweep that fine needs no more) and 24 around each tuning speed (8 beyond 100 points).
GRID = {False: (1000, 200), True: (48, 24)}
#: Tuning clusters span [t / CLUSTER_WIDTH, t * CLUSTER_WIDTH], geometrically spaced.
CLUSTER_WIDTH = 1.5
#: Relative accuracy of a refined peak's speed (eigen, periodic).
PEAK_XTOL = {False: 1e-7, True: 1e-4}


def probe_speeds(speeds, tuning=(), periodic: bool = False) -> np.ndarray:
    """Internal speeds [rad/s] over the sweep, beside (not including) the sweep's own.

    Parameters
    ----------
    speeds : ndarray
        The sweep, increasing [rad/s].
    tuning : iterable of float
        Tuning speeds [rad/s]; those inside the sweep get a dense cluster.
    periodic : bool
        A periodic (Floquet) analysis, whose every speed costs an integration;
        it sets the grid size (:data:`GRID`).

    Notes
    -----
    For a Floquet analysis no probe of the even grid lies below half the first
    speed that turns (a periodic analysis just above rest is the costliest of
    the sweep); a range open there is followed down within a work budget
    (:func:`groundres.assess.stability.find_ranges`). The clusters at the tuning
    speeds are kept whatever the sweep's spacing: a sweep from rest in steps
    wider than the resonances (0 to 1e7 rpm in 400 speeds) would otherwise see
    no speed where the rotor grows.
    """
    speeds = np.asarray(speeds, dtype=float)
    lo, hi = speeds[0], speeds[-1]
    uniform, cluster = GRID[periodic]
    if periodic:  # every Floquet speed is an integration: what the sweep lacks
        uniform, cluster = max(0, uniform - len(speeds) // 2), (cluster if len(speeds) < 100 else 8)
    even = np.linspace(lo, hi, uniform) if uniform > 1 else np.zeros(0)
    moving = speeds[speeds > 0]
    if periodic and len(moving):
        even = even[even >= 0.5 * moving.min()]
    parts = [even]
    for t in tuning:  # (kept whatever the sweep's spacing: a resonance is where the rotor may grow)
        if t is not None and lo < t < hi:
            a, b = max(lo, t / CLUSTER_WIDTH), min(hi, t * CLUSTER_WIDTH)
            parts.append(np.geomspace(max(a, 1e-300), b, cluster))
    probe = np.unique(np.concatenate(parts))
    probe = probe[(probe > lo) & (probe < hi)]
    return np.setdiff1d(probe, speeds)


def local_maxima(values, count: int) -> np.ndarray:
    """Indices of the ``count`` largest local maxima of a sampled function (ends included)."""
    v = np.asarray(values, dtype=float)
    if len(v) == 1:
        return np.array([0])
    left = np.r_[True, v[1:] >= v[:-1]]
    right = np.r_[v[:-1] >= v[1:], True]
    idx = np.flatnonzero(left & right)
    # of a flat run keep one
    idx = idx[np.r_[True, np.diff(idx) > 1]] if len(idx) else idx
    return idx[np.argsort(-v[idx], kind="stable")][:count]


def zoom_max(fun, lo: float, hi: float, xtol: float, points: int = 9, rounds: int = 40):
    """Largest value of ``fun`` on [lo, hi] and where: (value, speed) (:func:`zoom_many`)."""
    return zoom_many(fun, [(lo, hi)], xtol, points, rounds)[0]


def zoom_many(
    fun, spans, xtol: float, points: int = 9, rounds: int = 40, rough=None
) -> list[tuple[float, float]]:
    """Largest value of ``fun`` on each bracket [lo, hi] of ``spans`` and where: [(value, speed)].

    In each bracket: evaluates ``points`` speeds, keeps the neighbourhood of
    the best and repeats (the bracket shrinks by (points - 1) / 2 each round)
    until it is narrower than ``xtol`` relative to ``hi``; then a parabola
    through the best three gives the peak, kept if it is higher. Where the
    best of a round is an end of the bracket itself, that end is the answer.
    The brackets advance together: one call of ``fun`` per round for all.

    With ``rough`` (``rough(speeds) -> values``: ``fun`` at a looser accuracy,
    cheaper), the rounds look with it and ``fun`` is evaluated once, at the
    point each bracket ends on and at its parabola's vertex (one call for
    all): every value returned is ``fun``'s.
    """
    look = fun if rough is None else rough
    # lo, hi, best, at, open, and the bracket's own ends
    state = [[float(lo), float(hi), -np.inf, float(lo), True, float(lo), float(hi)] for lo, hi in spans]
    vertex = []  # (bracket, speed) of the final parabolas
    for _ in range(rounds):
        active = [st for st in state if st[4]]
        if not active:
            break
        w = np.concatenate([np.linspace(st[0], st[1], points) for st in active])
        v = np.asarray(look(w), dtype=float).reshape(len(active), points)
        w = w.reshape(len(active), points)
        for st, wk, vk in zip(active, w, v):
            i = int(np.argmax(vk))
            if vk[i] > st[2]:
                st[2], st[3] = float(vk[i]), float(wk[i])
            if (i == 0 and wk[0] == st[5]) or (i == points - 1 and wk[-1] == st[6]):
                st[4] = False  # (the largest at an end of the bracket: there it stays)
                continue
            step = wk[1] - wk[0]
            if step <= xtol * max(abs(st[1]), 1e-300):
                st[4] = False
                if 0 < i < points - 1:
                    denom = vk[i - 1] - 2 * vk[i] + vk[i + 1]
                    if denom < 0:
                        vertex.append((st, wk[i] + 0.5 * step * (vk[i - 1] - vk[i + 1]) / denom))
                continue
            st[0], st[1] = max(st[0], st[3] - step), min(st[1], st[3] + step)
    if rough is not None:  # the values at fun's accuracy: where each ended, and its vertex
        ends = [(st, st[3]) for st in state]
        values = np.asarray(fun(np.array([x for _, x in ends + vertex])), dtype=float)
        for st in state:
            st[2] = -np.inf
        for (st, x), vx in zip(ends + vertex, values):
            if vx > st[2]:
                st[2], st[3] = float(vx), float(x)
    elif vertex:
        values = np.asarray(fun(np.array([x for _, x in vertex])), dtype=float)
        for (st, x), vx in zip(vertex, values):
            if vx > st[2]:
                st[2], st[3] = float(vx), float(x)
    return [(st[2], st[3]) for st in state]


#: Half-width, relative, of the bracket a rough look at a crossing leaves for ``fun``.
ROUGH_BRACKET = 1e-6


def crossing(fun, lo: float, hi: float, rough=None) -> float:
    """Where ``fun`` (on arrays of speeds) changes sign in [lo, hi], to 1e-10 relative.

    With ``rough`` (``rough(speeds) -> (values, lower, upper)``, ``fun`` at a
    looser accuracy, :class:`PeakWatch`), the crossing is first found with
    it, and ``fun`` searches only within :data:`ROUGH_BRACKET` of there
    where its values at both ends of that bracket differ in sign (else in
    [lo, hi]).
    """
    known = {}

    def f(w):
        if w not in known:
            known[w] = float(fun(np.array([w]))[0])
        return known[w]

    if rough is not None:
        ends = np.asarray(rough(np.array([lo, hi]))[0], float)
        if ends[0] * ends[1] < 0:
            near = brentq(lambda w: float(rough(np.array([w]))[0][0]), lo, hi, xtol=1e-12, rtol=1e-8)
            a, b = max(lo, near * (1 - ROUGH_BRACKET)), min(hi, near * (1 + ROUGH_BRACKET))
            va, vb = (float(v) for v in fun(np.array([a, b])))
            known[a], known[b] = va, vb
            if va * vb <= 0:
                lo, hi = a, b
    return float(brentq(f, lo, hi, xtol=1e-12, rtol=1e-10))


def bracket(grid, i):
    """Neighbours of grid point i (never below half the first speed that turns)."""
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]
    if lo <= 0 < grid[i]:
        lo = 0.5 * grid[i]
    return lo, hi


class PeakWatch:
    """The largest value of ``fun(parameter, speeds)`` over speed, for one parameter after another.

    A full scan evaluates the grid and refines its largest local maxima; the
    peaks found are kept with their grid brackets, so that the next
    parameter (the next lag damping of a search) looks there first: the
    worst speed moves little from one damping to the next, and only a full
    scan can show that no peak is positive.

    With ``rough`` (``rough(parameter, speeds) -> (values, lower, upper)``:
    ``fun`` at a looser accuracy and bounds of ``fun`` given it), scans and
    refinements look with it, and ``fun`` decides: at the refined peaks, and
    at every speed whose bounds do not settle the sign (a last peak whose
    lower bound is positive is positive).
    """

    def __init__(self, fun, grid, periodic, seeds=(), peaks=None, rough=None):
        self.fun, self.grid, self.periodic, self.rough = fun, np.asarray(grid, float), periodic, rough
        self.xtol = PEAK_XTOL[periodic]
        self.peaks = peaks or (3 if periodic else 8)
        self.brackets = [self._around(w) for w in seeds]
        self.scanned = None  # the parameter of the last full scan

    def _around(self, w):
        i = int(np.clip(np.searchsorted(self.grid, w), 0, len(self.grid) - 1))
        lo, hi = bracket(self.grid, i)
        return [min(lo, w), max(hi, w), w, False]

    def _refine(self, p, spans):
        """Peaks in watched spans [lo, hi, last peak, settled] (the grid brackets they
        came from: a peak that leaves its bracket is found again by the next full
        scan), refined together. A span is settled where its largest value lay on
        an end of the bracket (the peak left it, or another root rose above it
        there): refining it again cannot help, and its last peak is kept, where
        the mode that peaked there is looked at again. Returns the refined values."""
        rough = None if self.rough is None else (lambda w: self.rough(p, w)[0])
        found = zoom_many(
            lambda w: self.fun(p, w), [(span[0], span[1]) for span in spans], self.xtol, rough=rough
        )
        for span, (_, at) in zip(spans, found):
            span[3] = min(at - span[0], span[1] - at) <= self.xtol * abs(span[1])
            if not span[3]:
                span[2] = at
        return [top for top, _ in found]

    def watched(self, p):
        """Largest value over the watched peaks (-inf if none).

        The last peaks are tried first, in one call: where one is still
        positive the verdict needs no refinement; else those not settled
        (:meth:`_refine`) are refined together.
        """
        if not self.brackets:
            return -np.inf
        at = np.array([span[2] for span in self.brackets])
        if self.rough is None:
            last = np.asarray(self.fun(p, at), float)
            if last.max() > 0:
                return float(last.max())
        else:
            last, lower, upper = (np.asarray(v, float) for v in self.rough(p, at))
            if lower.max() > 0:  # (positive whatever the rough look's error)
                return float(lower.max())
        live = [k for k, span in enumerate(self.brackets) if not span[3]]
        tops = self._refine(p, [self.brackets[k] for k in live]) if live else []
        if self.rough is not None:  # the settled peaks' values at fun's accuracy where they may be positive
            doubt = [k for k in range(len(at)) if k not in live and upper[k] > 0]
            last = np.where(upper > 0, -np.inf, last)
            if doubt:
                last[doubt] = np.asarray(self.fun(p, at[doubt]), float)
        return max(tops + [float(last.max())])

    def full(self, p):
        """Largest value from a full scan; the scan's peaks are watched from now on.

        The highest local maximum is refined, and the others where they could
        rise above zero by four times what refining gained on it. A rough
        scan's value counts only where ``fun`` confirms it: the grid speeds
        that its bound leaves possibly positive are evaluated again.
        """
        self.scanned = p
        if self.rough is None:
            values = upper = np.asarray(self.fun(p, self.grid), float)
            best = float(values.max())
        else:
            values, _, upper = (np.asarray(v, float) for v in self.rough(p, self.grid))
            best = -np.inf
        gain, spans, refined = None, [], []
        for i in local_maxima(values, self.peaks):
            lo, hi = bracket(self.grid, i)
            span = [lo, hi, self.grid[i], False]
            if hi > lo and (gain is None or upper[i] + 4 * gain > 0):
                (top,) = self._refine(p, [span])
                best = max(best, top)
                gain = max(gain or 0.0, top - values[i])
                refined.append(i)
            if all(abs(span[2] - t[2]) > 4 * self.xtol * abs(t[2]) for t in spans):
                spans.append(span)
        if self.rough is not None:
            doubt = np.setdiff1d(np.flatnonzero(upper > 0), refined)
            if not refined:  # (no bracket to refine: the grid's best decides)
                doubt = np.union1d(doubt, [int(np.argmax(values))])
            if len(doubt):
                best = max(best, float(np.max(self.fun(p, self.grid[doubt]))))
        kept = [b for b in self.brackets if all(abs(b[2] - s[2]) > 4 * self.xtol * abs(s[2]) for s in spans)]
        self.brackets = (spans + kept)[: 2 * self.peaks]
        return best
