"""Several analyses side by side: cases by methods, each against the first.

An entry is one case analysed by one method (and the frame asked for). The
first entry is the baseline; :meth:`Comparison.differences` gives, for every
other entry, how its unstable rotor-speed ranges and its largest real part
differ from the baseline's (:meth:`Comparison.differences_table` and
:meth:`Comparison.differences_record` are its files). Every number comes
from :func:`groundres.analysis.analyze` and
:class:`groundres.assess.stability.Stability`; :func:`groundres.analysis.compare`
makes a comparison.

Speeds are in rad/s and real parts in 1/s here (SI, the data contract); the
command line and the figure speak the first case's unit.

Round-off is never a result: every difference carries the tolerance below
which it is round-off (:data:`ROUND_OFF`), derived from how each quantity is
computed. The numbers stay as computed; the command line prints a difference
within its tolerance as "0 (round-off)".
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..assess.stability import GROWTH_FLOOR, GROWTH_PER_RADIAN, growth_threshold, is_neutral
from ..model.params import Case
from .sweep import SweepResult

#: What each quantity of :meth:`Comparison.differences` is, and its unit.
QUANTITIES = {
    "unstable_range_count": ("number of unstable ranges", "1"),
    "unstable_width": ("total width of the unstable ranges", "rad/s"),
    "range_start": ("start of an unstable range", "rad/s"),
    "range_end": ("end of an unstable range", "rad/s"),
    "growth_margin": ("growth margin: largest real part of the vibrating modes over the sweep", "1/s"),
    "growth_margin_speed": ("rotor speed of the growth margin", "rad/s"),
    "least_damping_ratio": ("least damping ratio of the vibrating modes over the operating range", "1"),
    "least_damping_ratio_speed": ("rotor speed of the least damping ratio", "rad/s"),
}

#: Round-off of a range end, relative to the speed [-]. An end is the root of
#: (largest real part - growth threshold) in speed, found by Brent's method to
#: 1e-12 rad/s + 1e-10 of the speed (:func:`groundres.assess.scan.crossing`). An error e
#: in the real part moves the end by e / slope: with roots accurate to ~1e-9 of
#: their size ``abs(eigenvalue)`` (Floquet, transition tolerance 5e-11 per entry,
#: :mod:`groundres.solve.floquet.transition`; eigen-analysis better) and the slopes at the ends
#: of the shipped cases (0.02 to 2 1/s per rad/s), at most ~6e-8 of the speed.
#: Measured: eigen and Floquet ends of hammond-one-damper-isotropic agree to 4e-12.
SPEED_ROUND_OFF = 1e-7
#: Round-off of the speed of the largest real part, relative [-]: the argument of
#: a flat maximum, found by bounded Brent to 1e-6 of the bracket's upper speed
#: (:mod:`groundres.assess.stability`); a value error d moves it by a further
#: ``sqrt(2 d / abs(f''))``. Ten times the search tolerance.
PEAK_SPEED_ROUND_OFF = 1e-5
#: Round-off of the speed of a margin (the growth margin's, the least damping ratio's),
#: relative [-] to the top of the bracket it was refined in (the sweep's next speed): found by
#: golden-section search to 1e-4 of that for a periodic analysis (1e-6 eigen,
#: :data:`groundres.assess.margins.XTOL`); ten times that.
MARGIN_SPEED_ROUND_OFF = 1e-3
#: Round-off of a least damping ratio [-]: a smooth minimum found to 1e-4 of its speed
#: moves by ~f'' (1e-4 w)^2 / 2, under 1e-8 on the shipped cases; where the minimum lies
#: at a label's exchange of branches, at the sweep's own speeds; with roots accurate to
#: ~1e-9 of their size. Measured: eigen and Floquet least damping ratios of
#: hammond-one-damper-isotropic agree to 3e-9.
DAMPING_RATIO_ROUND_OFF = 1e-6

#: The tolerance of each quantity, as differences.json states it.
ROUND_OFF = {
    "unstable_range_count": "0 (a count)",
    "unstable_width": f"{SPEED_ROUND_OFF:g} x the sum of the ends of the ranges (the larger of the two sums)",
    "range_start": f"{SPEED_ROUND_OFF:g} x the larger of the two speeds",
    "range_end": f"{SPEED_ROUND_OFF:g} x the larger of the two speeds",
    "growth_margin": (
        f"the growth threshold at the larger of the two speeds: {GROWTH_PER_RADIAN:g} 1/s per rad/s "
        f"+ {GROWTH_FLOOR:g} 1/s (below it a real part is neutral, round-off; where both are neutral "
        "the difference is round-off whatever its size)"
    ),
    "growth_margin_speed": (
        f"{MARGIN_SPEED_ROUND_OFF:g} x the sweep's next speed above the two (the argument of a flat maximum, "
        "found to 1e-4 of its bracket's upper speed, the sweep's next); where a growth margin is neutral its "
        "speed is no result"
    ),
    "least_damping_ratio": (
        f"{DAMPING_RATIO_ROUND_OFF:g} (a damping ratio refined between the sweep's speeds)"
    ),
    "least_damping_ratio_speed": (
        f"{MARGIN_SPEED_ROUND_OFF:g} x the sweep's next speed above the two (the argument of a flat "
        "minimum); where a least damping ratio is neutral its speed is no result"
    ),
}

#: The columns of differences.csv (speeds in rad/s, real parts in 1/s; tolerance in the row's unit).
CSV_HEADER = [
    "entry",
    "name",
    "quantity",
    "range",
    "unit",
    "baseline",
    "value",
    "difference",
    "note",
    "tolerance",
    "within_round_off",
]

#: What differences.json says of the tolerances.
ROUND_OFF_NOTE = (
    "within_round_off is true where |difference| <= tolerance (in the row's unit): the difference "
    "is round-off of the computation, not a result; the numbers are kept as computed"
)

#: How ranges are paired, as the notes of the differences say.
PAIRING_NOTE = (
    "difference = entry - baseline; an entry's unstable ranges are paired with the baseline's "
    "in speed order where they overlap; a range without a partner has no difference"
)


@dataclass(frozen=True)
class Entry:
    """One analysis of a comparison.

    Attributes
    ----------
    number : int
        1-based; entry 1 is the baseline.
    case_name : str
        The case's name: its file's stem, the shipped name, or its title.
    detail : str
        The method and frame where the entries differ ("" where they do not).
    case_index : int
        0-based index of the entry's case among the cases compared.
    method : str or None
        The method asked for ("auto", "eigen", "floquet"; None: the case's own).
    result : SweepResult
    """

    number: int
    case_name: str
    detail: str
    case_index: int
    method: str | None
    result: SweepResult

    @property
    def case(self) -> Case:
        return self.result.case

    @property
    def name(self) -> str:
        """The case's name, with the method and frame in brackets where the entries differ."""
        return f"{self.case_name} ({self.detail})" if self.detail else self.case_name


@dataclass(frozen=True)
class Comparison:
    """Entries (cases by methods) analysed for comparison; the first is the baseline."""

    entries: tuple[Entry, ...]

    @property
    def labels(self) -> list[str]:
        """Every mode label of the entries, in order of first appearance."""
        return list(dict.fromkeys(label for e in self.entries for label in e.result.labels))

    def differences(self) -> list[dict]:
        """Each entry against the baseline: a row per quantity.

        Returns
        -------
        list of dict
            Keys ``entry`` (number), ``name``, ``quantity`` (a key of
            :data:`QUANTITIES`), ``range`` (1-based pair number for
            ``range_start`` and ``range_end``, else None), ``unit``,
            ``baseline``, ``value``, ``difference`` (value - baseline;
            None where either is missing, with the reason in ``note``),
            ``tolerance`` (the difference's round-off, in ``unit``:
            :data:`ROUND_OFF`) and ``within_round_off`` (bool; None without
            a difference). An entry identical to the baseline gives
            differences of exactly 0.
        """
        base = self.entries[0].result
        rows = []
        for entry in self.entries[1:]:
            rows += _rows(entry, base, entry.result)
        return rows

    def differences_table(self, rows=None) -> tuple[list[str], list[list]]:
        """differences.csv: its header (:data:`CSV_HEADER`) and a row per difference, numbers
        in full (repr), empty cells where there is none (``rows``: :meth:`differences`)."""

        def cell(v):
            if v is None:
                return ""
            if isinstance(v, bool):
                return "true" if v else "false"
            return repr(v + 0.0) if isinstance(v, float) else v

        rows = self.differences() if rows is None else rows
        return CSV_HEADER, [[cell(row[key]) for key in CSV_HEADER] for row in rows]

    def differences_record(self, rows=None) -> dict:
        """differences.json: the entries, what each quantity is, the round-off tolerances and
        the differences (``rows``: :meth:`differences`)."""
        rows = self.differences() if rows is None else rows
        return {
            "baseline": 1,
            "entries": [
                {"entry": e.number, "name": e.name, "case": e.case.source, "title": e.case.title}
                | {
                    "method": e.result.method.value,
                    "frame": e.result.frame,
                    "summary": f"summary-{e.number}.json",
                }
                for e in self.entries
            ],
            "quantities": {key: {"meaning": m, "unit": u} for key, (m, u) in QUANTITIES.items()},
            "note": PAIRING_NOTE,
            "round_off": {
                "note": ROUND_OFF_NOTE,
                "tolerance": dict(ROUND_OFF),
                "speed_relative": SPEED_ROUND_OFF,
                "peak_speed_relative": PEAK_SPEED_ROUND_OFF,
                "growth_threshold_per_radian": GROWTH_PER_RADIAN,
                "growth_threshold_floor": GROWTH_FLOOR,
            },
            "differences": [
                {k: v for k, v in r.items() if v is not None or k not in ("range", "note")} for r in rows
            ],
        }

    def __repr__(self) -> str:
        from .display import comparison_text

        return comparison_text(self)

    def _repr_html_(self) -> str:
        from .display import comparison_html

        return comparison_html(self)

    def plot(
        self,
        fig=None,
        show_damping_ratio: bool = False,
        *,
        speed_axis: str = "auto",
        frequency_limits=None,
        real_limits=None,
        modes=None,
        ax=None,
    ):
        """The entries' Coleman diagrams overlaid (a matplotlib Figure).

        Options (``fig`` an empty figure or subfigure, or ``ax`` axes of your own) as
        :meth:`groundres.results.sweep.SweepResult.plot`; see
        :func:`groundres.plotting.overlay.overlay_diagram`.
        """
        from ..plotting.overlay import overlay_diagram

        return overlay_diagram(
            self,
            fig,
            show_damping_ratio,
            speed_axis=speed_axis,
            frequency_limits=frequency_limits,
            real_limits=real_limits,
            modes=modes,
            ax=ax,
        )


def case_name(case: Case) -> str:
    """A short name of a case: its file's stem, the shipped case's name, or its title (with how
    it differs from its file: "in vacuum")."""
    name = Path(case.source).stem if case.source else case.title
    return f"{name} ({case.variant})" if case.variant and case.source else name


def entry_details(results) -> list[str]:
    """What tells the entries apart beyond their case: method and frame, where they differ."""
    methods = {r.method for r in results}
    frames = {r.frame for r in results}
    return [
        ", ".join(
            ([r.method] if len(methods) > 1 else []) + ([f"{r.frame} frame"] if len(frames) > 1 else [])
        )
        for r in results
    ]


def _value(x):
    """A count (int) or a float, or None where it is missing or not finite."""
    if isinstance(x, int) or x is None:
        return x
    return float(x) if math.isfinite(x) else None


def neutral_max(result: SweepResult) -> bool:
    """Whether the growth margin of ``result`` is neutral: within the growth threshold of zero
    at its speed (round-off, neither growth nor decay), or there is none."""
    growth = result.margins.growth_margin
    return growth is None or bool(is_neutral(growth[0], growth[1]))


def _row(entry, quantity, baseline, value, tolerance, number=None, note=None, round_off=False) -> dict:
    """A row of the differences; ``round_off``: the difference is round-off whatever its size."""
    baseline, value = _value(baseline), _value(value)
    difference = None if baseline is None or value is None else value - baseline
    row = {
        "entry": entry.number,
        "name": entry.name,
        "quantity": quantity,
        "range": number,
        "unit": QUANTITIES[quantity][1],
        "baseline": baseline,
        "value": value,
        "difference": difference,
        "tolerance": None if difference is None else tolerance,
        "within_round_off": None if difference is None else bool(round_off or abs(difference) <= tolerance),
        "note": note,
    }
    if difference is None and note is None:
        row["note"] = "no finite value in the " + ("baseline" if baseline is None else "entry")
    return row


def _largest(*speeds) -> float:
    """The largest finite speed given (0 for none)."""
    return max((abs(w) for w in speeds if w is not None and math.isfinite(w)), default=0.0)


def overlaps(a: tuple, b: tuple) -> bool:
    """Whether two ranges (start, end) share speeds."""
    return a[0] <= b[1] and b[0] <= a[1]


def pair_ranges(first, second):
    """Pairs of overlapping ranges, in speed order: [(a or None, b or None), ...].

    ``first`` and ``second`` are sorted lists of disjoint (start, end); a
    range that overlaps none of the other list is paired with None.
    """
    pairs, i, j = [], 0, 0
    while i < len(first) or j < len(second):
        a = first[i] if i < len(first) else None
        b = second[j] if j < len(second) else None
        if a is not None and b is not None and overlaps(a, b):
            pairs.append((a, b))
            i, j = i + 1, j + 1
        elif b is None or (a is not None and a[1] < b[0]):
            pairs.append((a, None))
            i += 1
        else:
            pairs.append((None, b))
            j += 1
    return pairs


def _rows(entry, base: SweepResult, other: SweepResult) -> list[dict]:
    ranges_a, ranges_b = base.stability.unstable_ranges, other.stability.unstable_ranges
    ends = max(sum(abs(s) + abs(e) for s, e in ranges) for ranges in (ranges_a, ranges_b))  # (width's ends)
    rows = [
        _row(entry, "unstable_range_count", len(ranges_a), len(ranges_b), 0),
        _row(
            entry,
            "unstable_width",
            sum((e - s for s, e in ranges_a), 0.0),
            sum((e - s for s, e in ranges_b), 0.0),
            SPEED_ROUND_OFF * ends,
        ),
    ]
    for k, (a, b) in enumerate(pair_ranges(ranges_a, ranges_b), start=1):
        note = None if a and b else ("only in the baseline" if a else "only in this entry")
        for i, quantity in enumerate(("range_start", "range_end")):
            wa, wb = a[i] if a else None, b[i] if b else None
            tol = SPEED_ROUND_OFF * _largest(wa, wb)
            rows.append(_row(entry, quantity, wa, wb, tol, number=k, note=note))
    (va, wa), (vb, wb) = ((r.margins.growth_margin or (None, None))[:2] for r in (base, other))
    neutral = neutral_max(base), neutral_max(other)
    threshold = float(growth_threshold(_largest(wa, wb)))
    grids = (base.rotor_speed, other.rotor_speed)
    rows += _extreme_rows(
        entry, "growth_margin", (va, wa), (vb, wb), threshold, neutral, "growth margin", grids
    )
    (za, xa), (zb, xb) = ((r.margins.least("operating") or (None, None))[:2] for r in (base, other))
    zero = za == 0.0, zb == 0.0  # (a neutral least: round-off, where it lies is no result)
    rows.append(_row(entry, "least_damping_ratio", za, zb, DAMPING_RATIO_ROUND_OFF))
    rows.append(_speed_row(entry, "least_damping_ratio", xa, xb, zero, "least damping ratio", grids))
    return rows


def _extreme_rows(entry, name, a, b, round_off, neutral, what, grids) -> list:
    """The rows of an extreme and of where it lies, ``a`` and ``b`` (value, speed) each."""
    return [
        _row(entry, name, a[0], b[0], round_off, round_off=all(neutral)),
        _speed_row(entry, name, a[1], b[1], neutral, what, grids),
    ]


def _bracket_top(speed, grids) -> float:
    """The top of the bracket a margin was refined in, whose share the refinement's tolerance is:
    each sweep's ``grids`` next speed at or above ``speed``, the larger of the two (the looser
    tolerance; ``speed`` past them)."""
    above = [float(g[g >= speed].min()) for g in map(np.asarray, grids) if (g >= speed).any()]
    return max(above, default=speed)


def _speed_row(entry, name, wa, wb, neutral, what, grids):
    """The row of where an extreme lies (``name``_speed), no result where both are round-off."""
    larger = _largest(wa, wb)
    return _row(
        entry,
        f"{name}_speed",
        wa,
        wb,
        MARGIN_SPEED_ROUND_OFF * _bracket_top(larger, grids),
        note=_neutral_note(neutral, what),
        round_off=all(neutral),
    )


def _neutral_note(neutral, what: str) -> str | None:
    """What a pair of neutral flags (baseline, entry) makes of where ``what`` lies."""
    if all(neutral):
        return f"both {what}s are neutral (round-off): where they lie is no result"
    if any(neutral):
        which = "the baseline's" if neutral[0] else "this entry's"
        return f"{which} {what} is neutral (round-off): where it lies is no result"
    return None
