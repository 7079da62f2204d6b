"""Margins a designer acts on: the damping each mode keeps over the operating range and run-up.

The question is not only whether some root grows, but how much damping every
mode keeps where the rotor runs, against the damping the design must show:

* the **operating range** (``[sweep] operating_start``, ``operating_stop``;
  the whole sweep where not given) and the **run-up**, the sweep below it,
  which the rotor passes through on its way up and down;
* for every mode, its **least damping ratio** over each (refined between the
  sweep's speeds, so not tied to their spacing) and where;
* the **margin** to ``[sweep] required_damping_ratio`` (to zero, the
  stability boundary, where none is required), and a verdict: "meets the
  requirement", "stable but below it" or "unstable" (a mode that grows
  anywhere in the sweep, run-up included);
* the **growth margin**: the largest real part of the vibration modes over
  the sweep [1/s], negative where every one decays. Unlike the largest real
  part of all roots, it moves with the design on the stable side too, and
  is continuous across the stability boundary.

**Roots neutral at rest.** An articulated blade without a lag spring has no
stiffness at rest: its lag roots are zero there, and at low speed, where its
damper makes the lag motion overdamped, one root of each lag mode creeps
towards zero as the rotor slows (the centrifugal stiffness vanishes). Such a
root neither vibrates nor grows; its real part is tiny and its damping ratio,
seen from nonrotating axes, is small only because the axes turn. So a mode
that is neutral at rest (its root at rest within the growth threshold of
zero) counts for the margins only where it vibrates (its frequency seen from
rotating axes is not zero); while it creeps it is left out, and the
summary's ``neutral_at_rest`` names such modes. The largest real part of
all roots (:class:`groundres.assess.stability.Stability`) keeps them, and
every verdict of growth counts every root.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ..modes.identify import damping_ratio
from .stability import continuing_roots, growth_threshold, interpolated

#: Relative accuracy of a refined extreme's speed (eigen-analysis, periodic).
XTOL = {False: 1e-6, True: 1e-4}
#: A mode does not vibrate where its frequency seen from rotating axes is below this
#: fraction of its root's size (or of the rotor speed): an overdamped pair, real in the blades' axes.
STILL = 1e-2
#: The verdicts, from best to worst.
VERDICTS = ("meets the requirement", "stable", "stable but below it", "unstable")


@dataclass(frozen=True)
class Least:
    """An extreme of a mode over a range: ``value`` (a damping ratio [-], or a real part
    [1/s]) at ``speed`` [rad/s]; ``neutral`` where its real part there is within the growth
    threshold of zero (round-off: neither growth nor decay; a damping ratio is then 0)."""

    value: float
    speed: float
    neutral: bool = False


@dataclass(frozen=True)
class ModeMargin:
    """One mode's margins.

    Attributes
    ----------
    mode : str
        The label.
    operating, run_up : Least or None
        Its least damping ratio over the operating range and over the run-up;
        None where it is nowhere a vibration there, or there is no run-up.
    largest_real_part : Least or None
        Its largest real part over the sweep where it vibrates (``value`` [1/s]).
    grows : bool
        It grows somewhere in the sweep (run-up included).
    verdict : str
        One of :data:`VERDICTS` ("stable": no requirement given).
    """

    mode: str
    operating: Least | None
    run_up: Least | None
    largest_real_part: Least | None
    grows: bool
    verdict: str

    def margin(self, required: float | None) -> float | None:
        """Least damping ratio over the operating range minus the requirement (or zero)."""
        return None if self.operating is None else self.operating.value - (required or 0.0)


@dataclass(frozen=True)
class Margins:
    """The margins of a sweep (:func:`margins`).

    Attributes
    ----------
    operating_range : (float, float)
        [rad/s]; the whole sweep where the case gives none.
    operating_given : bool
        Whether the case gives the operating range.
    run_up : (float, float) or None
        [rad/s]: the sweep below the operating range.
    required_damping_ratio : float or None
    modes : tuple of ModeMargin
    neutral_at_rest : tuple of str
        The modes whose roots are zero at rest (counted only where they vibrate).
    verdict : str
        The worst of the modes' verdicts (:data:`VERDICTS`).
    vibrating : ndarray (n_s, n_m) bool
        Where each mode counts (:func:`vibrating`), at the sweep's speeds.
    overall : dict
        "operating", "run_up" (least damping ratio) and "growth" (growth margin): (value,
        speed, mode) over every vibrating root, refined between the sweep's speeds whatever
        label a root carries (a label that moves to another branch at a veering cannot be
        followed between the speeds, the roots can); None where no mode vibrates there.
    """

    operating_range: tuple
    operating_given: bool
    run_up: tuple | None
    required_damping_ratio: float | None
    modes: tuple
    neutral_at_rest: tuple
    verdict: str
    vibrating: np.ndarray
    overall: dict

    def least(self, where: str = "operating") -> tuple[float, float, str] | None:
        """(damping ratio, speed, mode) of the least damped vibrating root over ``where``
        ("operating" or "run_up"), or None where no mode vibrates there."""
        return self.overall[where]

    @property
    def margin(self) -> float | None:
        """The least damping ratio over the operating range minus the requirement (or zero) [-]."""
        least = self.least("operating")
        return None if least is None else least[0] - (self.required_damping_ratio or 0.0)

    @property
    def growth_margin(self) -> tuple[float, float, str] | None:
        """(real part [1/s], speed [rad/s], mode): the largest real part of the vibration modes
        over the sweep; None where no mode vibrates."""
        return self.overall["growth"]


def vibrating(modes, speeds, rest) -> np.ndarray:
    """(n_s, n_m) bool: where each mode counts for the margins (module docstring): where the
    root that carries its label (``modes.branch``) counts (:func:`root_counts`)."""
    counts, _ = root_counts(modes, speeds, rest)
    return counts[np.arange(len(speeds))[:, None], modes.branch]


def root_counts(modes, speeds, rest) -> tuple[np.ndarray, np.ndarray]:
    """Where each tracked root counts for the margins, and how still it is.

    A root creeps from rest when it starts, at the sweep's first speed, as the
    less damped root of a mode neutral at rest (``rest`` (n_m,) bool); it
    counts from the first speed where it vibrates on, whatever label it carries
    by then (labels move between roots at veerings; a root does not). It
    vibrates where the frequency seen from rotating axes of the mode that
    carries it exceeds :data:`STILL` of the root's size (or of the rotor speed).

    Returns
    -------
    counts : bool ndarray (n_s, n_e)
    stillness : ndarray (n_s, n_e)
        How far each root is from vibrating, negative where it vibrates;
        interpolated between the sweep's speeds it places where a creeping
        root starts to vibrate.
    """
    speeds = np.asarray(speeds, float)
    rows = np.arange(len(speeds))[:, None]
    label = modes.root_label
    size = np.maximum(np.abs(modes.root_eigenvalue), speeds[:, None])
    stillness = STILL * np.maximum(size, 1e-300) - np.abs(modes.frequency_rotating[rows, label])
    first = modes.eigenvalue[0, label[0]].real  # (the representative: the less damped of two real roots)
    tiny = 1e-9 * max(float(np.abs(modes.root_eigenvalue[0]).max()), 1e-300)
    creeps = np.asarray(rest, bool)[label[0]] & (modes.root_real_part[0] >= first - tiny)
    started = np.logical_or.accumulate(stillness < 0, axis=0)
    return ~creeps[None, :] | started, stillness


def neutral_at_rest(rest_modes) -> np.ndarray:
    """(n_m,) bool: the modes whose root at rest (``rest_modes``, the analysis at speed 0) is
    zero to within the growth threshold there."""
    lam = rest_modes.eigenvalue[0]
    scale = max(float(np.abs(lam).max()), 1.0)
    return np.abs(lam) <= growth_threshold(0.0) + 1e-12 * scale


def margins(
    result, roots_at, rest, unique: bool, periodic: bool, every: bool = True, floor: float = 0.0
) -> Margins:
    """The margins of a sweep's result.

    Parameters
    ----------
    result : SweepResult-like
        With ``case``, ``rotor_speed``, ``modes``, ``labels`` and
        ``stability`` (its ranges say which modes grow).
    roots_at : callable
        ``roots_at(speeds) -> (k, r)``: every root at each speed (batched).
    rest : ndarray (n_m,) bool
        The modes neutral at rest (:func:`neutral_at_rest`).
    unique : bool
        Frequencies are unique (a multiblade eigen-analysis): every root is taken
        as it is (:func:`groundres.assess.stability.continuing_roots`).
    periodic : bool
        A periodic analysis: its refinements are looser (:data:`XTOL`).
    every : bool
        Refine every mode's extremes between the sweep's speeds (the per-mode table);
        otherwise only those of the modes that can hold the overall least damping
        ratio or growth margin (:data:`NEAR`), the others' taken at the sweep's speeds
        (what a study needs, at a fraction of the cost for a periodic analysis).
    floor : float
        The lowest speed [rad/s] a refinement may solve at (a periodic analysis' lowest
        affordable speed, :func:`groundres.solve.floquet.cost.lowest_periodic_speed`).
    """
    sweep = result.case.sweep
    speeds = np.asarray(result.rotor_speed, float)
    modes = result.modes
    by_root, stillness = root_counts(modes, speeds, rest)
    counts = by_root[np.arange(len(speeds))[:, None], modes.branch]
    neutral = np.abs(modes.eigenvalue.real) <= growth_threshold(speeds)[:, None]
    ratio = np.where(counts, np.where(neutral, 0.0, modes.damping_ratio), np.nan)
    real = np.where(counts, modes.eigenvalue.real, np.nan)
    operating, run_up = sweep.operating_range, sweep.run_up
    refine = _Refiner(roots_at, modes, speeds, unique, XTOL[periodic], every, by_root, stillness, floor)
    least_op = refine.least(ratio, counts, operating)
    least_up = refine.least(ratio, counts, run_up) if run_up else [None] * len(modes.labels)
    largest = refine.largest(real, counts)
    growing = set()
    for start, end in result.stability.unstable_ranges:
        growing.update(result.unstable_modes(start, end))
    required = sweep.required_damping_ratio
    rows = []
    for j, label in enumerate(modes.labels):
        grows = label in growing
        rows.append(
            ModeMargin(
                label, least_op[j], least_up[j], largest[j], grows, _verdict(grows, least_op[j], required)
            )
        )
    overall = {
        "operating": refine.overall(rows, "operating", ratio, counts, operating),
        "run_up": refine.overall(rows, "run_up", ratio, counts, run_up) if run_up else None,
        "growth": refine.growth(rows),
    }
    least = overall["operating"]
    if required is not None and least is not None and not any(m.grows for m in rows):
        # (the least over every root, refined across veerings, may lie below each mode's own)
        worst = "meets the requirement" if least[0] >= required else "stable but below it"
        rows = [
            dataclasses.replace(m, verdict=worst) if m.mode == least[2] and worst != m.verdict else m
            for m in rows
        ]
    verdict = (
        "unstable" if result.stability.unstable_ranges else max((m.verdict for m in rows), key=VERDICTS.index)
    )
    return Margins(
        operating_range=operating,
        operating_given=sweep.operating_start is not None or sweep.operating_stop is not None,
        run_up=run_up,
        required_damping_ratio=required,
        modes=tuple(rows),
        neutral_at_rest=tuple(label for label, r in zip(modes.labels, rest) if r),
        verdict=verdict,
        vibrating=counts,
        overall=overall,
    )


def _verdict(grows: bool, operating: Least | None, required: float | None) -> str:
    if grows:
        return "unstable"
    if required is None:
        return "stable"
    if operating is None or operating.value >= required:  # (a mode that only creeps there vibrates not)
        return "meets the requirement"
    return "stable but below it"


#: Without ``every`` (:func:`margins`), the modes refined: those whose extreme at the sweep's
#: speeds lies within this share of the overall one (plus the growth threshold, or 1e-3 of
#: damping ratio) of it; a refinement moves an extreme by far less between the sweep's speeds.
NEAR = 0.25


class _Refiner:
    """Extremes of each mode's damping ratio or real part between the sweep's speeds."""

    def __init__(self, roots_at, modes, speeds, unique, xtol, every, by_root, stillness, floor=0.0):
        self.roots_at, self.modes, self.speeds, self.unique, self.xtol = roots_at, modes, speeds, unique, xtol
        self.every, self.by_root, self.stillness, self.floor = every, by_root, stillness, floor

    def _edge(self, i: int, k: int, e: int) -> float:
        """Where root ``e`` starts vibrating between speeds ``i`` (where it counts) and its
        neighbour ``k`` (where it creeps), its stillness interpolated linearly."""
        s, w = self.stillness[:, e], self.speeds
        return float(w[i] + (w[k] - w[i]) * s[i] / (s[i] - s[k]))

    def growth(self, rows):
        """(value, speed, mode): the growth margin, the largest real part of the counting
        roots over the sweep, refined along the root that holds it at the sweep's speeds (up to
        where it starts vibrating): a root goes on across a veering, where labels move."""
        modes, speeds = self.modes, self.speeds
        real = np.where(self.by_root, modes.root_real_part, -np.inf)
        if not np.isfinite(real).any():
            return None
        i, e = np.unravel_index(int(np.argmax(real)), real.shape)
        value, at = float(real[i, e]), float(speeds[i])
        mode = modes.labels[int(modes.root_label[i, e])]
        ends = []
        for k in (i - 1, i + 1):
            if not 0 <= k < len(speeds):
                ends.append(float(speeds[i]))
            else:
                ends.append(float(speeds[k]) if self.by_root[k, e] else self._edge(i, k, e))
        a, b = max(ends[0], self.floor), ends[1]
        if b > a and speeds[i] > 0:
            near = [k for k in (i - 1, i, i + 1) if 0 <= k < len(speeds)]
            w, lam = speeds[near], modes.root_eigenvalue[near, e]
            if not self.unique:  # (a frequency known modulo the rotor speed: unwrapped between neighbours)
                cycles = np.divide(lam.imag - lam.imag[0], w, out=np.zeros(len(w)), where=w > 0)
                turn = np.angle(np.exp(2j * np.pi * cycles))
                lam = lam.real + 1j * (lam.imag[0] + turn * w / (2 * np.pi))

            def fun(x):
                target = np.interp(x, w, lam.real) + 1j * np.abs(np.interp(x, w, lam.imag))
                roots = np.asarray(self.roots_at(x)).reshape(len(x), -1)
                return -continuing_roots(roots, target, x, self.unique)[0].real

            refined, where = _golden(fun, np.array([a]), np.array([b]), self.xtol)
            if -refined[0] > value:
                value, at = -float(refined[0]), float(where[0])
        return value, at, mode

    def _values(self, w, columns, what):
        """Damping ratio or real part of each column's mode at its speed ``w`` (batched)."""
        roots = np.asarray(self.roots_at(w))
        roots = roots.reshape(len(w), -1)
        best, cand = continuing_roots(
            roots, interpolated(self.modes, self.speeds, w, columns), w, self.unique
        )
        if what == "real":
            return best.real
        ratio = damping_ratio(best, scale=np.abs(cand).max(axis=1))
        return np.where(np.abs(best.real) <= growth_threshold(w), 0.0, ratio)  # (neutral: round-off)

    def overall(self, rows, field, ratio, counts, span):
        """(value, speed, mode): the least damping ratio over ``span`` of every vibrating
        root, from the modes' own (``rows``, their ``field``) and refined over every root
        between the sweep's speeds around the grid's least, where every mode counts there
        (across a veering, where labels move, the roots go on)."""
        best = [(getattr(m, field).value, getattr(m, field).speed, m.mode) for m in rows if getattr(m, field)]
        if not best:
            return None
        value, at, mode = min(best)
        speeds = self.speeds
        lo, hi = span
        inside = (speeds >= lo) & (speeds <= hi)
        grid = np.where(inside[:, None] & counts, ratio, np.inf)
        i = int(np.argmin(np.nanmin(grid, axis=1)))
        a, b = max(speeds[max(i - 1, 0)], lo, self.floor), min(speeds[min(i + 1, len(speeds) - 1)], hi)
        ends = [int(np.argmin(np.abs(speeds - x))) for x in (a, b)]
        if not (b > a and speeds[i] > 0) or not all(counts[k].all() for k in ends):
            return value, at, mode  # (a creeping root near: the modes' own extremes stand)

        def fun(w):
            roots = np.asarray(self.roots_at(w)).reshape(len(w), -1)
            return np.array([self._least_ratio_at(r, x) for r, x in zip(roots, w)])

        refined, where = _golden(fun, np.array([a]), np.array([b]), self.xtol)
        if refined[0] < value:
            value, at = float(refined[0]), float(where[0])
        return value, at, mode

    def _least_ratio_at(self, roots, w: float) -> float:
        """The least damping ratio at ``w`` [rad/s] over the roots that continue the modes
        (every root where frequencies are unique), a neutral root's as 0."""
        if self.unique:
            cand = roots.real + 1j * np.abs(roots.imag)
            scale = np.abs(cand).max()
        else:
            targets = interpolated(self.modes, self.speeds, w)
            k = len(targets)
            cand, every = continuing_roots(
                np.broadcast_to(roots, (k, len(roots))), targets, np.full(k, w), False
            )
            scale = np.abs(every).max()
        ratio = damping_ratio(cand, scale=scale)
        return float(np.where(np.abs(cand.real) <= growth_threshold(w), 0.0, ratio).min())

    def least(self, ratio, counts, span) -> list:
        """Per mode, its least damping ratio over ``span`` [rad/s] (Least, or None)."""
        return self._extreme(ratio, counts, span, "ratio", sign=1.0)

    def largest(self, real, counts) -> list:
        """Per mode, its largest real part over the sweep (Least, or None)."""
        return self._extreme(real, counts, (self.speeds[0], self.speeds[-1]), "real", sign=-1.0)

    def _extreme(self, values, counts, span, what, sign) -> list:
        lo, hi = span
        speeds = self.speeds
        inside = (speeds >= lo) & (speeds <= hi)
        out = [None] * values.shape[1]
        columns, brackets, found = [], [], {}
        for j in range(values.shape[1]):
            ok = inside & counts[:, j] & np.isfinite(values[:, j])
            if not ok.any():
                continue
            i = int(np.flatnonzero(ok)[np.argmin(sign * values[ok, j])])
            found[j] = (float(values[i, j]), float(speeds[i]))
            # the bracket: the neighbours where the mode counts too and its label stays on
            # its branch (a label that moves to another branch has no root to follow between)
            moved = self.modes.exchange[:, j]
            a = b = speeds[i]
            if i > 0 and not moved[i]:  # (towards a neighbour where the mode is still: up to where it starts)
                a = speeds[i - 1] if counts[i - 1, j] else self._edge(i, i - 1, self.modes.branch[i, j])
            if i + 1 < len(speeds) and not moved[i + 1]:
                b = speeds[i + 1] if counts[i + 1, j] else self._edge(i, i + 1, self.modes.branch[i, j])
            a, b = max(a, lo, self.floor), min(b, hi)
            if b > a and speeds[i] > 0:
                columns.append(j)
                brackets.append((a, b))
        if found and not self.every:  # only the modes that can hold the overall extreme
            best = min(sign * v for v, _ in found.values())
            slack = NEAR * abs(best) + (1e-3 if what == "ratio" else float(growth_threshold(speeds[-1])))
            chosen = {j for j, (v, _) in found.items() if sign * v <= best + slack}
            kept = [(j, ab) for j, ab in zip(columns, brackets) if j in chosen]
            columns, brackets = [j for j, _ in kept], [ab for _, ab in kept]
        else:
            chosen = set(range(values.shape[1]))
        if columns:
            a, b = (np.array(x, float) for x in zip(*brackets))
            refined = _golden(lambda w: sign * self._values(w, columns, what), a, b, self.xtol)
            for j, value, at in zip(columns, *refined):
                if value < sign * found[j][0]:  # (the refined extreme beats the sweep's)
                    found[j] = (sign * float(value), float(at))
        # the span's ends themselves, where they fall between the sweep's speeds (a search only
        # nears an end, and the extreme over a span may lie at an end no bracket reaches)
        ends = []
        for j in range(values.shape[1]):
            if found and j not in chosen:
                continue
            for end in (lo, hi):
                i = int(np.argmin(np.abs(speeds - end)))
                near = self.modes.exchange[max(i, 1) : i + 2, j].any() if len(speeds) > 1 else False
                if end not in speeds and end > max(self.floor, 0.0) and counts[i, j] and not near:
                    ends.append((j, end))
        if ends:
            cols, w = zip(*ends)
            for j, value, at in zip(cols, sign * self._values(np.array(w, float), list(cols), what), w):
                if j not in found or value < sign * found[j][0]:
                    found[j] = (sign * float(value), float(at))
        for j, (value, at) in found.items():
            neutral = value == 0.0 if what == "ratio" else bool(abs(value) <= growth_threshold(at))
            out[j] = Least(float(value), float(at), neutral)
        return out


def _golden(fun, a, b, xtol, most: int = 60):
    """Minima of ``fun`` (batched: ``fun(x)`` for an array of k points, one per bracket) over
    the brackets [a, b] (k,), by golden-section search to ``xtol`` of the speed; the value
    and where, (k,) each, the better of the last two points."""
    g = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = a.copy(), b.copy()
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = fun(c), fun(d)
    for _ in range(most):
        if np.all(b - a <= xtol * np.maximum(np.abs(b), 1e-300)):
            break
        left = fc <= fd
        b = np.where(left, d, b)
        a = np.where(left, a, c)
        d_new = np.where(left, c, a + g * (b - a))
        c_new = np.where(left, b - g * (b - a), d)
        x = np.where(left, c_new, d_new)
        fx = fun(x)
        fc, fd = np.where(left, fx, fd), np.where(left, fc, fx)
        c, d = c_new, d_new
    first = fc <= fd
    return np.where(first, fc, fd), np.where(first, c, d)
