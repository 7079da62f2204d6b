"""What a limit-cycle analysis hands back: the cycles over the speeds, in numbers and in words.

:class:`LimitCycleResult` holds the prediction (:class:`groundres.assess.limit_cycles.LimitCycles`)
with its case and the linear analysis beside it; ``to_dict()`` is limit_cycles.json,
``threshold_words`` and ``stable_words`` say a threshold or a cycle as a designer reads it,
``plot()`` draws the limit-cycle diagram beside the Coleman diagram.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..assess.confirm import run_words
from ..assess.cycle_shapes import LARGE, POOR
from ..assess.limit_cycles import multiblade_applies
from ..model.describing import link_regularisation
from ..model.mbc import unit_of
from ..model.units import fmt_speed
from .damper_laws import laws_block

#: Ranges of speeds named in words before the rest are counted.
RANGES = 4
#: A friction link's regularisation (c_reg A w / F) beyond which its cycles are flagged.
REGULARISED = 0.05

#: Said with every limit-cycle result.
NOTES = (
    "amplitudes are of a blade's lag in the rotating frame, its largest frequency component (the one "
    "the damper law is evaluated at); peak is the sum of all its components (half peak-to-peak)",
    "a cycle's amplitude, peak, frequencies and second_component are those of the blade that moves most "
    "(blade); blades lists every blade's, each blade's law taken at its own amplitude and frequency "
    "(equivalent_damping null: a blade without a damper law); hub amplitudes are each body coordinate's "
    "largest frequency component",
    f"second_component is the next largest component over the largest: beyond {POOR} the single-harmonic "
    "approximation of the describing function is poor there (poor_approximation)",
    "a friction link's describing function is the ideal slider's: link_regularisation, c_reg A w / F, "
    "bounds how far the regularised law's may differ (relative)",
    "the structure is linear (small angles): a cycle beyond "
    f"{math.degrees(LARGE):g} deg (large) and any growth 'without bound' mean 'until something not modelled "
    "stops it'",
)


@dataclass
class LimitCycleResult:
    """Limit cycles of a case (module docstring).

    Attributes
    ----------
    case : Case
    prediction : LimitCycles
    linear : SweepResult or None
        The linear analysis (the laws at small motion) drawn beside the cycles.
    """

    case: object
    prediction: object
    linear: object = None
    #: The cycles at ``[limit_cycle] confirm`` speeds set against runs of the nonlinear equations
    #: (:func:`groundres.assess.confirm.confirm`).
    confirmations: list = field(default_factory=list)

    @property
    def thresholds(self) -> list:
        """The unstable cycles: a lag disturbance above one grows."""
        return [c for c in self.prediction.cycles if not c.stable]

    @property
    def stable(self) -> list:
        """The stable cycles: motion settles on them."""
        return [c for c in self.prediction.cycles if c.stable]

    def smallest_threshold(self):
        """The unstable cycle of least amplitude (None: none)."""
        return min(self.thresholds, key=lambda c: c.amplitude, default=None)

    def largest_stable(self):
        """The stable cycle of largest amplitude (None: none)."""
        return max(self.stable, key=lambda c: c.amplitude, default=None)

    def _hub(self, cycle) -> str:
        parts = []
        for name, value in cycle.hub.items():
            if unit_of("body", name) == "m":
                parts.append(f"{name} {1e3 * value:.3g} mm")
            else:
                parts.append(f"{name} {math.degrees(value):.3g} deg")
        return ", ".join(parts)

    def _lag(self, cycle) -> str:
        """'2.4 deg' on identical blades; 'blade 1 3.4 deg (blades 2-4: 2.1, 2.4, 2.1 deg)' on
        blades that differ."""
        if not cycle.dissimilar:
            return f"{math.degrees(cycle.amplitude):.3g} deg"
        lead = max(range(len(cycle.blades)), key=lambda k: cycle.blades[k].amplitude)
        others = [k for k in range(len(cycle.blades)) if k != lead]
        listed = ", ".join(f"{math.degrees(cycle.blades[k].amplitude):.3g}" for k in others)
        names = ", ".join(str(k + 1) for k in others)
        return f"{math.degrees(cycle.amplitude):.3g} deg of blade {lead + 1} (blades {names}: {listed} deg)"

    def _where(self, found) -> str:
        """'at 12 of the 100 speeds, from 300 to 400 rpm' (each run of neighbouring speeds its own
        range: 'from 200 to 250 rpm and from 300 to 400 rpm')."""
        p, sweep = self.prediction, self.case.sweep
        runs, start = [], 0
        for k in range(1, len(found) + 1):
            if k == len(found) or found[k] != found[k - 1] + 1:
                runs.append((found[start], found[k - 1]))
                start = k
        parts = [
            f"at {fmt_speed(p.speeds[a], sweep)}"
            if a == b
            else f"from {fmt_speed(p.speeds[a], sweep)} to {fmt_speed(p.speeds[b], sweep)}"
            for a, b in runs[:RANGES]
        ]
        more = f" and {len(runs) - RANGES} more ranges" if len(runs) > RANGES else ""
        listed = (
            ", ".join(parts[:-1]) + " and " + parts[-1] if len(parts) > 1 and not more else ", ".join(parts)
        )
        return f"at {len(found)} of the {len(p.speeds)} speeds, {listed}{more}"

    def unbounded_words(self) -> str | None:
        """'at 12 of the 100 speeds, from 300 to 400 rpm, any disturbance grows without bound (small
        motion grows, and so does every amplitude searched ...)', or None where there is none."""
        found = self.prediction.unbounded()
        if not found:
            return None
        where, smallest = self._where(found), math.degrees(self.prediction.amplitudes[0])
        return (
            f"{where}, any disturbance grows without bound (small motion grows, and so does every amplitude "
            f"searched from {smallest:.3g} deg: no threshold there)"
        )

    def _starts(self, found) -> str:
        """The amplitudes at which the motion leaves neutral at speeds ``found``, in words."""
        p = self.prediction
        starts = sorted({p.lead(i)[1] for i in found})
        low, high = (f"{math.degrees(a):.3g}" for a in (starts[0], starts[-1]))
        said = f"{low} deg" if low == high else f"{low} to {high} deg"
        return said + (" (the smallest amplitude searched)" if starts[-1] == p.amplitudes[0] else "")

    def below_words(self) -> str | None:
        """Where small motion does not grow but the amplitudes searched do, in words (a threshold
        lies below them), or None where there is no such speed."""
        return self._below(self.prediction.below_searched(), "does not grow", "does", "a threshold lies")

    def stable_below_words(self) -> str | None:
        """Where small motion grows but the amplitudes searched decay, in words (a stable cycle
        lies below them), or None where there is no such speed."""
        found = self.prediction.stable_below_searched()
        return self._below(found, "grows", "decays", "the motion settles on a stable cycle")

    def _below(self, found, small: str, searched: str, cycle: str) -> str | None:
        if not found:
            return None
        return (
            f"{self._where(found)}, small motion {small} but a disturbance of {self._starts(found)} "
            f"{searched}: {cycle} below it (lower [limit_cycle] amplitude_min to find it)"
        )

    def threshold_words(self, cycle) -> str:
        """'at 260 rpm a lag disturbance above 0.88 deg (hub x 1.6 mm, y 6.5 mm) grows' ..."""
        beyond = [c for c in self.prediction.at(cycle.speed) if c.amplitude > cycle.amplitude]
        fate = "grows to a larger stable cycle" if any(c.stable for c in beyond) else "grows without bound"
        speed = fmt_speed(cycle.speed, self.case.sweep)
        return f"at {speed} a lag disturbance above {self._lag(cycle)} (hub {self._hub(cycle)}) {fate}"

    def stable_words(self, cycle) -> str:
        """'at 260 rpm the blades settle on a lag cycle of 6.2 deg (hub x 11 mm, y 46 mm)' ..."""
        large = " (large: beyond the small angles the model holds)" if cycle.large else ""
        return (
            f"at {fmt_speed(cycle.speed, self.case.sweep)} the motion settles on a lag cycle of "
            f"{self._lag(cycle)} (hub {self._hub(cycle)}){large}"
        )

    @property
    def method(self) -> str:
        """How the cycles were found, in words."""
        if multiblade_applies(self.case):
            return "describing functions; multiblade eigen-analysis of the equivalent linear system"
        return (
            "describing functions, each blade's law at its own amplitude and frequency; Floquet analysis "
            "of the equivalent periodic system"
        )

    def to_dict(self) -> dict:
        """limit_cycles.json: the cycles with their units, each speed's verdict, and the notes."""
        p = self.prediction
        return {
            "speed_unit": "rad/s",
            "amplitude_unit": "deg",
            "frequency_unit": "rad/s",
            "hub_units": {
                name: "m" if unit_of("body", name) == "m" else "rad" for name in self.case.body.dofs
            },
            "damping_unit": "N m s/rad",
            "stiffness_unit": "N m/rad",
            "growth_unit": "1/s",
            "searched": [math.degrees(a) for a in (p.amplitudes[0], p.amplitudes[-1])],
            "method": self.method,
            "lag_dampers": laws_block(self.case),
            "speeds": [float(w) for w in p.speeds],
            "verdicts": [p.verdict(i) for i in range(len(p.speeds))],
            "unbounded_speeds": [float(p.speeds[i]) for i in p.unbounded()],
            "threshold_below_searched_speeds": [float(p.speeds[i]) for i in p.below_searched()],
            "stable_cycle_below_searched_speeds": [float(p.speeds[i]) for i in p.stable_below_searched()],
            "small_motion_growth": [float(g) for g in p.small_growth],
            "cycles": [
                {
                    "speed": c.speed,
                    "stable": c.stable,
                    "amplitude": math.degrees(c.amplitude),
                    "peak": math.degrees(c.peak),
                    "frequency_rotating": c.frequency,
                    "frequency_nonrotating": c.nonrotating_frequency,
                    "second_frequency_nonrotating": c.nonrotating_second,
                    "blade": 1 + max(range(len(c.blades)), key=lambda k: c.blades[k].amplitude),
                    "hub": c.hub,
                    "second_component": c.second_component,
                    "poor_approximation": c.poor,
                    "large": c.large,
                    "equivalent_damping": c.equivalent_damping,
                    "equivalent_stiffness": c.equivalent_stiffness,
                    **self._regularisation(c),
                    "blades": [_blade(b) for b in c.blades],
                }
                for c in p.cycles
            ],
            "confirmations": self.confirmations,
            "notes": list(NOTES),
        }

    def confirmation_words(self, entry: dict) -> str:
        """A confirmation in words: 'at 264 rpm the threshold of 2.38 deg is confirmed: 0.8 times it
        decays, 1.25 times it grows'."""
        where = fmt_speed(entry["speed"], self.case.sweep)
        if entry["predicted"] is None:
            return f"at {where} no cycle is predicted ({entry['verdict']}): nothing to confirm"
        runs = {r["factor"]: r for r in entry["runs"]}
        said = "confirmed" if entry["confirmed"] else "not confirmed"
        if entry["stable"]:
            (run,) = runs.values()
            words = (
                f"at {where} the stable cycle of {entry['predicted']:.3g} deg is {said}: from "
                f"{run['factor']:g} times it the run {run_words(run)}"
            )
            if run.get("stopped") is not None:  # (nothing settled to set against the prediction)
                return words
            end = "" if run["verdict"] == "settled" else f", {run['amplitude']:.3g} deg at its end"
            return f"{words}{end} ({100 * entry['error']:+.2g} %)"
        below, above = (runs[f] for f in sorted(runs))

        def did(run):
            side = (
                "" if run.get("undecided") else " (heads beyond it)" if run["beyond"] else " (stays below it)"
            )
            return f"{run['factor']:g} times it {run_words(run)}{side}"

        predicted = f"{entry['predicted']:.3g} deg"
        return f"at {where} the threshold of {predicted} is {said}: {did(below)}, {did(above)}"

    def _regularisation(self, cycle) -> dict:
        """A friction link's regularisation at ``cycle``: c_reg A w / F, by which its describing
        function (the ideal slider's) may be off, relative (absent for other laws)."""
        law = next((e.law for e in self.case.rotor.lag_laws if e is not None), None)
        if law is None or not law.has_slider:
            return {}
        return {"link_regularisation": float(link_regularisation(law, cycle.amplitude, cycle.frequency))}

    def regularised(self) -> list:
        """The cycles of a friction link whose regularisation exceeds :data:`REGULARISED`."""
        return [
            c
            for c in self.prediction.cycles
            if self._regularisation(c).get("link_regularisation", 0) > REGULARISED
        ]

    def branches(self) -> list:
        """The cycles joined over neighbouring speeds: [(stable, [cycles])], each branch the cycles
        of one stability and one rank (by amplitude, among that stability's) at speed after speed."""
        p = self.prediction
        open_ = {}
        out = []
        for i, w in enumerate(p.speeds):
            ranked = {}
            for c in sorted(p.at(float(w)), key=lambda c: c.amplitude):
                ranked.setdefault(c.stable, []).append(c)
            seen = set()
            for stable, cycles in ranked.items():
                for rank, c in enumerate(cycles):
                    key = (stable, rank)
                    seen.add(key)
                    if key in open_ and open_[key][0] == i - 1:
                        open_[key][1].append(c)
                        open_[key] = (i, open_[key][1])
                    else:
                        branch = [c]
                        out.append((stable, branch))
                        open_[key] = (i, branch)
            for key in list(open_):
                if key not in seen:
                    del open_[key]
        return out

    def dataset(self):
        """The cycles as plain arrays, ``(coords, variables, attrs)`` as a sweep's
        (:meth:`groundres.results.sweep.SweepResult.dataset`): behind :meth:`to_xarray` and
        limit_cycles.nc. Dimensions ``speed`` and ``amplitude`` (the scan: ``growth``), ``cycle``
        (every cycle, with its ``branch``; ``hub_x`` ... each body coordinate's) and ``blade``; SI units."""
        return cycle_dataset(self)

    def to_xarray(self):
        """:meth:`dataset` as an xarray Dataset."""
        import xarray as xr

        coords, variables, attrs = self.dataset()
        return xr.Dataset(
            {k: (d, v, a) for k, (d, v, a) in variables.items()},
            coords={k: (d, v, a) for k, (d, v, a) in coords.items()},
            attrs=attrs,
        )

    def plot(self, fig=None):
        """The limit-cycle diagram beside the Coleman diagram (a matplotlib Figure)."""
        from ..plotting.limit_cycles import limit_cycle_figure

        return limit_cycle_figure(self, fig)


def _blade(blade) -> dict:
    """One blade's entry in a cycle of limit_cycles.json."""
    return {
        "amplitude": math.degrees(blade.amplitude),
        "peak": math.degrees(blade.peak),
        "frequency_rotating": blade.frequency,
        "second_component": blade.second_component,
        "equivalent_damping": blade.damping,
        "equivalent_stiffness": blade.stiffness,
    }


def cycle_dataset(result) -> tuple:
    """(coords, variables, attrs) of :meth:`LimitCycleResult.dataset`."""
    p, case = result.prediction, result.case
    cycles = p.cycles
    branch = np.full(len(cycles), -1)
    index = {id(c): i for i, c in enumerate(cycles)}
    for b, (_, members) in enumerate(result.branches()):
        for c in members:
            branch[index[id(c)]] = b
    dofs = list(case.body.dofs)
    n_b = case.rotor.n_blades

    def column(get, dtype=float):
        return np.array([get(c) for c in cycles], dtype=dtype).reshape(len(cycles))

    def per_blade(get):
        return np.array([[get(b) for b in c.blades] for c in cycles], float).reshape(len(cycles), n_b)

    coords = {
        "speed": (("speed",), np.asarray(p.speeds, float), {"units": "rad/s", "long_name": "rotor speed"}),
        "amplitude": (
            ("amplitude",),
            np.asarray(p.amplitudes, float),
            {"units": "rad", "long_name": "lag amplitude of the blade that moves most, as scanned"},
        ),
        "blade": (("blade",), np.arange(1, n_b + 1), {"long_name": "blade index"}),
    }
    nan = float("nan")
    variables = {
        "growth": (
            ("speed", "amplitude"),
            np.asarray(p.growth, float),
            {
                "units": "1/s",
                "long_name": "largest real part of a root with lag motion of the equivalent system",
            },
        ),
        "small_motion_growth": (
            ("speed",),
            np.asarray(p.small_growth, float),
            {
                "units": "1/s",
                "long_name": "largest real part of a root with lag motion, each law at its slope at rest",
            },
        ),
        "cycle_speed": (
            ("cycle",),
            column(lambda c: c.speed),
            {"units": "rad/s", "long_name": "rotor speed"},
        ),
        "cycle_amplitude": (
            ("cycle",),
            column(lambda c: c.amplitude),
            {"units": "rad", "long_name": "largest lag component of the blade that moves most"},
        ),
        "cycle_peak": (
            ("cycle",),
            column(lambda c: c.peak),
            {"units": "rad", "long_name": "half peak-to-peak"},
        ),
        "stable": (
            ("cycle",),
            column(lambda c: c.stable, np.int8),
            {"long_name": "1 stable cycle, 0 threshold"},
        ),
        "branch": (("cycle",), branch, {"long_name": "branch of neighbouring speeds the cycle lies on"}),
        "frequency_rotating": (
            ("cycle",),
            column(lambda c: c.frequency),
            {"units": "rad/s", "long_name": "the cycle's frequency in the rotating frame"},
        ),
        "frequency_nonrotating": (
            ("cycle",),
            column(lambda c: c.nonrotating_frequency),
            {"units": "rad/s", "long_name": "frequency of the hub's largest component (nonrotating frame)"},
        ),
        "second_frequency_nonrotating": (
            ("cycle",),
            column(lambda c: math.nan if c.nonrotating_second is None else c.nonrotating_second),
            {
                "units": "rad/s",
                "long_name": "frequency of the hub's second component where it holds 0.2 of the first "
                "(NaN: less)",
            },
        ),
        "second_component": (
            ("cycle",),
            column(lambda c: c.second_component),
            {"units": "1", "long_name": "second lag component over the largest"},
        ),
        "blade_amplitude": (
            ("cycle", "blade"),
            per_blade(lambda b: b.amplitude),
            {"units": "rad", "long_name": "each blade's largest lag component"},
        ),
        "blade_equivalent_damping": (
            ("cycle", "blade"),
            per_blade(lambda b: nan if b.damping is None else b.damping),
            {"units": "N m s/rad", "long_name": "each blade's equivalent lag damper (NaN: no law)"},
        ),
    }
    for d in dofs:  # (each body coordinate in its own unit)
        variables[f"hub_{d}"] = (
            ("cycle",),
            column(lambda c, d=d: c.hub.get(d, nan)),
            {"units": unit_of("body", d), "long_name": f"hub {d}: its largest component on the cycle"},
        )
    attrs = {
        "title": case.title,
        "method": result.method,
        "Conventions": "CF-1.8",
        "notes": " | ".join(NOTES),
    }
    return coords, variables, attrs
