"""The report of one case: what a colleague needs to judge it, in one printable HTML file.

Sections: the verdict and unstable ranges with the mode that grows, the
Coleman diagram, derived quantities (lag frequency at the reference speed,
body frequencies with the rotor's mass, the Deutsch requirement per body mode
at its tuning speed), the lag damping (installed, exact minimum), the
phasors of the worst mode at the worst speed, a study's map where given, the
case text, and the method with its accuracy figures. Every number that
summary.json holds is shown from summary.json (see :mod:`groundres.pages`).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..model.units import fmt_frequency, fmt_speed
from ..results.air import shown_rows
from .page import number, paragraphs, picture, render


def speed(value, key: str, sweep):
    """A speed [rad/s] from summary.json, shown in the case's unit with its ratio to the reference."""
    if value is None:
        return number(None, key)
    return number(value, key, fmt_speed(value, sweep))


def frequency(value, key: str, sweep):
    """A frequency [rad/s] from summary.json in the case's unit (cycles/min for rpm) and rad/s."""
    if value is None:
        return number(None, key)
    return number(value, key, fmt_frequency(value, sweep))


def worst_point(result, summary: dict):
    """(speed [rad/s], mode label, why) where the phasors are shown, or None (no roots).

    Where a root grows: the largest real part. Otherwise the regressive lag
    mode at the tuning speed of the body mode with the largest Deutsch
    requirement (where it meets that mode), or, without one in the sweep, at
    the least damped speed of the regressive lag mode (the least damped mode
    where there is none), among speeds above rest and roots off the origin,
    which have no phase to show; where that mode is neutral over the whole
    sweep (nothing damps it), at the reference speed.
    """
    from ..assess.stability import growth_threshold

    mr = summary["max_real_part"]
    if mr["value"] is not None and not mr["neutral"] and mr["value"] > 0:
        return mr["speed"], mr["mode"], "the largest real part (fastest growth) of the sweep"
    tunings = [
        e
        for e in summary["lag_damping"]["deutsch"]
        if e["tuning_speed"] is not None and e["tuning_in_sweep"] and e["required_lag_damping"] is not None
    ]
    if tunings and "regressive lag" in result.labels:
        tight = max(tunings, key=lambda e: e["required_lag_damping"])
        return (
            tight["tuning_speed"],
            "regressive lag",
            f"the tuning speed of body mode {tight['body_mode']}, where the regressive lag mode meets it "
            "(the largest Deutsch requirement; no root grows)",
        )
    speeds = result.rotor_speed
    ratio = np.where(
        (speeds[:, None] > 0) & (np.abs(result.modes.eigenvalue) > 0), result.damping_ratio, np.nan
    )
    if not np.isfinite(ratio).any():
        return None
    lag = result.labels.index("regressive lag") if "regressive lag" in result.labels else None
    if lag is not None and np.isfinite(ratio[:, lag]).any():
        j, why = lag, "the smallest damping ratio of the regressive lag mode (no root grows)"
    else:
        j = int(np.nanargmin(np.nanmin(ratio, axis=0)))
        why = "the smallest damping ratio of the sweep (no root grows)"
    if np.all(np.abs(result.real_part[:, j]) <= growth_threshold(speeds)):  # neutral: no least damped
        ref = result.case.sweep.reference
        w = ref if ref and speeds[0] <= ref <= speeds[-1] else 0.5 * (speeds[0] + speeds[-1])
        where = "the reference speed" if w == ref else "the middle of the sweep"
        return (
            float(w),
            result.labels[j],
            f"{where} (the mode is neutral over the whole sweep: nothing damps it)",
        )
    i = int(np.nanargmin(ratio[:, j]))
    return float(speeds[i]), result.labels[j], why


def at_speed(result, w: float):
    """The result itself where ``w`` [rad/s] is one of its speeds, else the same analysis with ``w`` added."""
    if np.any(result.rotor_speed == w):
        return result
    from ..analysis import analyze

    return analyze(
        result.case,
        frame=result.frame,
        method=result.method.option,
        speeds=np.union1d(result.rotor_speed, [w]),
        lag_damping_search=False,
    )


def phasor_section(result, summary: dict, fmt: str) -> dict | None:
    """The phasor diagram of the worst mode at the worst speed, and its coordinates' phases."""
    from ..plotting.phasors import phasor_diagram

    point = worst_point(result, summary)
    if point is None:
        return None
    w, label, why = point
    sweep = result.case.sweep
    shape = at_speed(result, w).mode(label, w)
    text = fmt_speed(shape.rotor_speed, sweep)
    rows = [
        {
            "frame": frame,
            "name": p.name,
            "unit": p.unit,
            "amplitude": f"{abs(p.displacement):.3g}",
            "phase": f"{round(float(np.degrees(np.angle(p.displacement))), 1) + 0.0:.1f}",
        }
        for frame in ("nonrotating", "rotating")
        for p in shape.phasors(frame)
        if abs(p.displacement) > 1e-3
    ]
    lam = shape.eigenvalue
    return {
        "label": label,
        "why": why,
        "speed": text,
        "state": shape.state,
        "lead": "90" if shape.neutral else f"{np.degrees(np.angle(lam)):.2f}",
        "picture": picture(phasor_diagram(shape, speed_text=text), fmt),
        "rows": rows,
    }


#: Speeds a report's limit-cycle table shows at most.
CYCLE_ROWS = 10


def cycle_section(found, fmt: str) -> dict:
    """The limit cycles of a case with nonlinear lag dampers (a
    :class:`~groundres.results.limit_cycles.LimitCycleResult`): the diagram, the smallest
    threshold and the largest stable cycle in words, the verdict at a few speeds, and the notes."""
    from ..results.damper_laws import SMALL_MOTION_NOTE

    p, sweep = found.prediction, found.case.sweep
    shown = np.unique(np.linspace(0, len(p.speeds) - 1, min(CYCLE_ROWS, len(p.speeds))).round().astype(int))
    worst, largest = found.smallest_threshold(), found.largest_stable()
    linear = SMALL_MOTION_NOTE.replace("this analysis is linear", "The other sections are linear")
    notes = [linear + "; this section takes the laws as they are, through their describing functions"]
    poor = [c for c in p.cycles if c.poor]
    if poor:
        notes.append(
            f"At {len(poor)} of the cycles the single-harmonic approximation is poor (a second frequency "
            "component above 0.2 of the first): read them as estimates"
        )
    if any(c.large for c in p.cycles):
        notes.append(
            "Some cycles exceed 10 deg, beyond the small angles the structure holds: there, and wherever the "
            "motion grows without bound, read 'until something not modelled stops it'"
        )
    if found.regularised():
        notes.append(
            "The friction link's regularisation moves some cycles by more than 5 % (limit_cycles.json)"
        )
    return {
        "picture": picture(found.plot(), fmt),
        "threshold": found.threshold_words(worst) if worst is not None else None,
        "unbounded": found.unbounded_words(),
        "below": found.below_words(),
        "settles_below": found.stable_below_words(),
        "stable": found.stable_words(largest) if largest is not None else None,
        "rows": [
            {
                "speed": fmt_speed(p.speeds[i], sweep),
                "verdict": p.verdict(int(i)),
                "thresholds": _amplitudes(p.at(float(p.speeds[i])), stable=False),
                "stable": _amplitudes(p.at(float(p.speeds[i])), stable=True),
            }
            for i in shown
        ],
        "method": found.method,
        "notes": notes,
        "confirmations": [found.confirmation_words(e) for e in found.confirmations],
    }


def _amplitudes(cycles, stable: bool) -> str:
    """'2.38' or '0.914, 4.77' [deg]: the cycles of one stability at a speed, smallest first."""
    return ", ".join(
        f"{np.degrees(c.amplitude):.3g}"
        for c in sorted(cycles, key=lambda c: c.amplitude)
        if c.stable is stable
    )


#: How the accuracy record's entries read on a page (name with its unit); others by their key.
ACCURACY_NAMES = {
    "roots": "roots",
    "transition_tolerance": "transition-matrix tolerance [-]",
    "transition_tolerance_note": "transition-matrix tolerance, meaning",
    "harmonics": "harmonics for frequency identification",
    "interval_rad": "symmetry interval of the equations [rad of rotor turn]",
    "steps_per_interval min": "integration steps per interval, fewest",
    "steps_per_interval max": "integration steps per interval, most",
    "lifted_speeds": "speeds integrated by lifting (slow rotor)",
    "growth_threshold per_radian": "growth threshold, per rad/s of rotor speed [1/s]",
    "growth_threshold floor": "growth threshold, floor [1/s]",
    "growth_threshold unit": None,
    "growth_threshold note": "growth threshold, meaning",
}


def accuracy_rows(accuracy: dict | None, prefix: str = "") -> list[tuple[str, str]]:
    """The accuracy record flattened into (name, text) rows, named as :data:`ACCURACY_NAMES` says."""
    rows = []
    for key, value in (accuracy or {}).items():
        if isinstance(value, dict):
            rows += accuracy_rows(value, f"{prefix}{key} ")
            continue
        name = ACCURACY_NAMES.get(f"{prefix}{key}", f"{prefix}{key}".replace("_", " "))
        if name is None:
            continue
        rows.append((name, f"{value:.6g}" if isinstance(value, float) else str(value)))
    return rows


def _span(values, units: str = "") -> str:
    """A numeric array's finite range as text, with its unit."""
    finite = values[np.isfinite(values)] if np.issubdtype(values.dtype, np.number) else values
    if not np.issubdtype(values.dtype, np.number):
        return ", ".join(str(v) for v in values.ravel()[:8]) + (" ..." if values.size > 8 else "")
    if not finite.size:
        return "no finite value"
    unit = f" {units}" if units else ""
    return f"{finite.min():.4g} to {finite.max():.4g}{unit} ({values.size} values)"


def study_section(folder: Path, case_text: str) -> dict:
    """A study folder's map (embedded as the study wrote it), what it varied and what it found.

    ``case_text``: the reported case's text; a study of another case is said so.
    """
    import xarray as xr

    from .page import data_uri

    maps = sorted(folder.glob("map.*"))
    shown = [p for p in maps if p.suffix[1:] in ("png", "svg")]
    record = {}
    provenance = folder / "provenance.json"
    if provenance.is_file():
        record = json.loads(provenance.read_text(encoding="utf-8"))
    notes, facts = [], []
    study_case = folder / "case.toml"
    if study_case.is_file() and study_case.read_text(encoding="utf-8") != case_text:
        notes.append(
            "The study's case.toml is not the case reported above: the map is of the study's own case."
        )
    if maps and not shown:
        notes.append(
            f"The study's map is {maps[0].name}, which a page cannot embed; run the study with --format png "
            "(or svg) to have it here."
        )
    for name in ("study.nc", "boundary.nc"):
        if (folder / name).is_file():
            with xr.open_dataset(folder / name) as ds:
                for dim in ds.sizes:
                    if dim in ds.coords and ds.coords[dim].size:
                        facts.append(
                            (
                                f"varied: {dim}",
                                _span(ds.coords[dim].values, ds.coords[dim].attrs.get("units", "")),
                            )
                        )
                if "stable" in ds:
                    stable = ds["stable"].values
                    facts.append(("stable points", f"{int(np.sum(stable == 1))} of {stable.size}"))
                if "error" in ds:
                    failed = int(sum(bool(str(e)) for e in np.ravel(ds["error"].values)))
                    if failed:
                        facts.append(("points that failed", f"{failed} (see the study's error variable)"))
                if name == "boundary.nc":
                    for var in ds.data_vars:
                        values = ds[var].values
                        if values.dtype.kind in "fi":  # (flags and messages are not results to show)
                            facts.append((f"found: {var}", _span(values, ds[var].attrs.get("units", ""))))
            break
    return {
        "folder": str(folder),
        "command_line": record.get("command_line", ""),
        "uri": data_uri(shown[0].read_bytes(), shown[0].suffix[1:]) if shown else None,
        "facts": facts,
        "notes": notes,
    }


def deutsch_rows(summary: dict, sweep) -> list[dict]:
    """The Deutsch requirement per body mode, every number from summary.json.

    A requirement where the criterion does not apply is shown as such (its value
    is for the average blade); a tuning speed outside the sweep is marked; and
    where the criterion is met but the analysis finds growth at the tuning speed
    the row says that the criterion's assumptions do not hold there.
    """
    ranges = [(r["start"], r["end"]) for r in summary["unstable_ranges"]]
    rows = []
    for i, e in enumerate(summary["lag_damping"]["deutsch"]):
        key = f"lag_damping.deutsch.{i}"
        if e["satisfied"] is None:
            verdict = e["satisfied_reason"]
        else:
            verdict = "met by the installed damping" if e["satisfied"] else "NOT met by the installed damping"
        tuning, required = e["tuning_speed"], e["required_lag_damping"]
        caveat = ""
        if e["satisfied"] and tuning is not None and any(s <= tuning <= t for s, t in ranges):
            caveat = (
                "yet the analysis finds growth at this tuning speed: the criterion's assumptions (light "
                "damping, one body mode at a time on its own, identical blades) do not hold here"
            )
        if required is None:
            shown = number(None, f"{key}.required_lag_damping", e.get("required_lag_damping_reason", "none"))
        elif not e["applies"]:
            shown = number(required, f"{key}.required_lag_damping", f"({required:.4g})")
        else:
            shown = number(required, f"{key}.required_lag_damping")
        nu = e["lag_frequency_per_rev"]
        rows.append(
            {
                "mode": e["body_mode"],
                "form": e["form"],
                "frequency": frequency(e["body_frequency"], f"{key}.body_frequency", sweep),
                "tuning": speed(tuning, f"{key}.tuning_speed", sweep),
                "outside": tuning is not None and e["tuning_in_sweep"] is False,
                "nu": number(nu, f"{key}.lag_frequency_per_rev", None if nu is not None else "no tuning"),
                "required": shown,
                "verdict": verdict,
                "satisfied": e["satisfied"],
                "caveat": caveat,
            }
        )
    return rows


def margin_rows(summary: dict, sweep) -> list[dict]:
    """The margins table of the page: per mode, its least damping ratio over the operating range
    and the run-up [%] with where, the margin to the requirement and the verdict."""

    def percent(least, key):
        if least is None:
            return number(None, key + ".value", "-")
        text = "0 (neutral)" if least["neutral"] else f"{100 * least['value']:.3g} %"
        return number(least["value"], key + ".value", text)

    def where(least, key):
        return "" if least is None or least["neutral"] else speed(least["speed"], key + ".speed", sweep)

    rows = []
    for i, m in enumerate(summary["margins"]["modes"]):
        key = f"margins.modes.{i}"
        margin = m["margin"]
        rows.append(
            {
                "mode": m["mode"],
                "least": percent(m["least_damping_ratio"], key + ".least_damping_ratio"),
                "at": where(m["least_damping_ratio"], key + ".least_damping_ratio"),
                "run_up": percent(m["least_damping_ratio_run_up"], key + ".least_damping_ratio_run_up"),
                "run_up_at": where(m["least_damping_ratio_run_up"], key + ".least_damping_ratio_run_up"),
                "margin": number(
                    margin, key + ".margin", "-" if margin is None else f"{100 * margin:+.3g} %"
                ),
                "verdict": m["verdict"],
            }
        )
    return rows


def air_rows(summary: dict, sweep) -> list[dict] | None:
    """The trim table of a rotor in air at a few speeds spread over the sweep
    (:func:`groundres.results.air.shown_rows`); None in vacuum."""
    if "trim" not in summary:
        return None
    trim = summary["trim"]
    out = []
    for i, row in shown_rows(trim):
        cells = [
            number(value, f"trim.{name}.{i}" + (".0" if isinstance(trim[name][i], list) else ""))
            for name, value in row.items()
        ]
        out.append({"speed": speed(trim["rotor_speed"][i], f"trim.rotor_speed.{i}", sweep), "cells": cells})
    return out


def report_page(
    result,
    *,
    fmt: str = "png",
    study: str | Path | None = None,
    command_line: str = "",
    plot: dict | None = None,
    summary: dict | None = None,
    cycles=None,
) -> tuple[str, dict[str, bytes]]:
    """The HTML report of a :class:`~groundres.results.sweep.SweepResult`, and the pictures to
    write beside it.

    Returns ``(html, files)``: ``files`` maps file names (``coleman.<fmt>``,
    ``phasors.<fmt>``) to their bytes. The page embeds the pictures itself.
    ``plot``: keyword arguments of :meth:`~groundres.results.sweep.SweepResult.plot`
    for the Coleman diagram (speed axis, limits, modes); ``summary``: the result's
    :meth:`~groundres.results.sweep.SweepResult.summary`, where the caller has it; ``cycles``: the
    case's limit cycles (:func:`groundres.analysis.limit_cycles`, a case with nonlinear lag
    dampers), drawn in a section of their own (``limit_cycles.<fmt>``).
    """
    case = result.case
    sweep = case.sweep
    summary = result.summary() if summary is None else summary
    coleman = picture(result.plot(**(plot or {})), fmt)
    phasors = phasor_section(result, summary, fmt)
    files = {f"coleman.{fmt}": coleman["bytes"]}
    if phasors is not None:
        files[f"phasors.{fmt}"] = phasors["picture"]["bytes"]
    limit = cycle_section(cycles, fmt) if cycles is not None else None
    if limit is not None:
        files[f"limit_cycles.{fmt}"] = limit["picture"]["bytes"]
    ranges = [
        {
            "start": speed(r["start"], f"unstable_ranges.{i}.start", sweep),
            "end": speed(r["end"], f"unstable_ranges.{i}.end", sweep),
            "open_start": r.get("open_start", False),
            "open_end": r.get("open_end", False),
            "modes": ", ".join(r["modes"]),
            "note": "; ".join(n for n in (r.get("start_note"), r.get("end_note")) if n),
        }
        for i, r in enumerate(summary["unstable_ranges"])
    ]
    lag = summary["lag_damping"]
    reference = fmt_speed(sweep.reference, sweep, ref=False) if sweep.reference else ""
    context = {
        "title": f"groundres report: {case.title}",
        "case": case,
        "summary": summary,
        "sweep": sweep,
        "description": paragraphs(case.description or ""),
        "ranges": ranges,
        "speed": lambda value, key: speed(value, key, sweep),
        "deutsch": deutsch_rows(summary, sweep),
        "air": air_rows(summary, sweep),
        "margins": margin_rows(summary, sweep) if "margins" in summary else None,
        "lag": lag,
        "coleman": coleman,
        "phasors": phasors,
        "cycles": limit,
        "study": study_section(Path(study), case.text) if study is not None else None,
        "accuracy": accuracy_rows(result.accuracy),
        "command_line": command_line,
        "unit_note": (
            f"Speeds in {sweep.unit}"
            + (f", with their ratio to the reference speed {reference} (ref)" if sweep.reference else "")
            + "; the sweep's numbers are also in summary.json beside this page, in SI units."
        ),
    }
    return render("report.html", **context), files
