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
from dataclasses import dataclass

import numpy as np

from .refine import Least, Refiner
from .stability import growth_threshold

#: Relative accuracy of a refined extreme's speed (eigen-analysis, periodic).
XTOL = {False: 1e-6, True: 1e-4}
#: A mode does not vibrate where its frequency seen from rotating axes is below this
#: fraction of its root's size (or of the rotor speed): an overdamped pair, real in the blades' axes.
STILL = 1e-2
#: The verdicts, from best to worst.
VERDICTS = ("meets the requirement", "stable", "stable but below it", "unstable")


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
    carries it exceeds :data:`STILL` of the root's size (or of the rotor speed). A
    root that is zero (within the growth threshold: the attitude of a body free in
    pitch or roll) counts nowhere.

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
    # A zero root (a free body's attitude, hovering) is no vibration, whichever frame sees it
    # turn: it neither vibrates nor grows.
    zero = np.abs(modes.root_eigenvalue) <= growth_threshold(speeds)[:, None]
    return (~creeps[None, :] | started) & ~zero, stillness


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
        ratio or growth margin (:data:`groundres.assess.refine.NEAR`), the others' taken at the sweep's speeds
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
    refine = Refiner(roots_at, modes, speeds, unique, XTOL[periodic], every, by_root, stillness, floor)
    least_op = refine.least(ratio, counts, operating)
    least_up = refine.least(ratio, counts, run_up) if run_up else [None] * len(modes.labels)
    largest = refine.largest(real, counts)
    growing, between = set(), []
    for start, end in result.stability.unstable_ranges:
        labels = result.unstable_modes(start, end)
        growing.update(labels)
        if not ((speeds >= start) & (speeds <= end)).any():  # (each mode's root there, where known)
            roots = (getattr(result, "between", None) or {}).get((start, end), {})
            between.append((start, end, {label: roots.get(label) for label in labels}))
    # a range that falls between the sweep's speeds: its modes' extremes are searched inside it,
    # so that a mode that grows there shows a negative damping ratio and a positive real part
    refine.within(least_op, counts, operating, between, "ratio", sign=1.0)
    if run_up:
        refine.within(least_up, counts, run_up, between, "ratio", sign=1.0)
    refine.within(largest, counts, (speeds[0], speeds[-1]), between, "real", sign=-1.0)
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
        "growth": _larger(refine.growth(rows), rows),
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


def _larger(growth, rows):
    """The growth margin, or a mode's own largest real part where that is larger (found
    inside an unstable range between the sweep's speeds, which the margin's search, near
    the sweep's largest, does not visit)."""
    own = [(m.largest_real_part, m.mode) for m in rows if m.largest_real_part]
    best = max(((x.value, x.speed, mode) for x, mode in own), default=None)
    if growth is None or (best is not None and best[0] > growth[0]):
        return best
    return growth


def _verdict(grows: bool, operating: Least | None, required: float | None) -> str:
    if grows:
        return "unstable"
    if required is None:
        return "stable"
    if operating is None or operating.value >= required:  # (a mode that only creeps there vibrates not)
        return "meets the requirement"
    return "stable but below it"
