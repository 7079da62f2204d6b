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

from ..cli.common import fmt_speed
from ..params import FREQUENCY_UNITS, SPEED_UNITS
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
    text = f"{value / SPEED_UNITS[sweep.unit]:.4g} {FREQUENCY_UNITS[sweep.unit]}"
    if sweep.unit != "rad/s":
        text += f" ({value:.4g} rad/s)"
    return number(value, key, text)


def worst_point(result, summary: dict):
    """(speed [rad/s], mode label, why) where the phasors are shown, or None (no roots).

    Where a root grows: the largest real part. Otherwise the regressive lag
    mode at the tuning speed of the body mode with the largest Deutsch
    requirement (where it meets that mode), or, without one in the sweep, at
    the least damped speed of the regressive lag mode (the least damped mode
    where there is none), among speeds above rest and roots off the origin,
    which have no phase to show.
    """
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
    ratio = np.where(
        (result.rotor_speed[:, None] > 0) & (np.abs(result.modes.eigenvalue) > 0),
        result.damping_ratio,
        np.nan,
    )
    if not np.isfinite(ratio).any():
        return None
    if (
        "regressive lag" in result.labels
        and np.isfinite(ratio[:, result.labels.index("regressive lag")]).any()
    ):
        j = result.labels.index("regressive lag")
        why = "the smallest damping ratio of the regressive lag mode (no root grows)"
    else:
        j = int(np.nanargmin(np.nanmin(ratio, axis=0)))
        why = "the smallest damping ratio of the sweep (no root grows)"
    i = int(np.nanargmin(ratio[:, j]))
    return float(result.rotor_speed[i]), result.labels[j], why


def phasor_section(result, summary: dict, fmt: str) -> dict | None:
    """The phasor diagram and the rate phases of the worst mode at the sweep speed nearest the worst."""
    from ..plotting.phasors import phasor_diagram

    point = worst_point(result, summary)
    if point is None:
        return None
    w, label, why = point
    sweep = result.case.sweep
    shape = result.mode(label, w)
    text = fmt_speed(shape.rotor_speed, sweep)
    rows = [
        {
            "frame": frame,
            "name": p.name,
            "unit": p.unit,
            "amplitude": f"{abs(p.displacement):.3g}",
            "lead": f"{p.rate_lead:.2f}",
            "in_phase": f"{p.in_phase:+.3f}",
        }
        for frame in ("nonrotating", "rotating")
        for p in shape.phasors(frame)
        if abs(p.displacement) > 1e-3
    ]
    return {
        "label": label,
        "why": why,
        "speed": text,
        "exact": shape.rotor_speed == w,
        "worst_speed": fmt_speed(w, sweep),
        "state": "growing" if shape.unstable else ("neutral" if shape.neutral else "decaying"),
        "picture": picture(phasor_diagram(shape, speed_text=text), fmt),
        "rows": rows,
    }


def accuracy_rows(accuracy: dict | None, prefix: str = "") -> list[tuple[str, str]]:
    """The accuracy record flattened into (name, text) rows."""
    rows = []
    for key, value in (accuracy or {}).items():
        name = f"{prefix}{key}".replace("_", " ")
        if isinstance(value, dict):
            rows += accuracy_rows(value, f"{prefix}{key} ")
        elif isinstance(value, float):
            rows.append((name, f"{value:.6g}"))
        else:
            rows.append((name, str(value)))
    return rows


def study_section(folder: Path, fmt: str) -> dict:
    """A study folder's map (embedded as written) and what it varied."""
    from .page import data_uri

    maps = sorted(p for p in folder.glob("map.*") if p.suffix[1:] in ("png", "svg"))
    record = {}
    provenance = folder / "provenance.json"
    if provenance.is_file():
        record = json.loads(provenance.read_text(encoding="utf-8"))
    facts = []
    for name in ("study.nc", "boundary.nc"):
        if (folder / name).is_file():
            import xarray as xr

            with xr.open_dataset(folder / name) as ds:
                for dim in ds.sizes:
                    if dim in ds.coords and ds.coords[dim].size:
                        values = ds.coords[dim].values
                        if np.issubdtype(values.dtype, np.number):
                            facts.append(
                                (dim, f"{values.min():.4g} to {values.max():.4g} ({values.size} values)")
                            )
                        else:
                            facts.append((dim, ", ".join(str(v) for v in values[:8])))
                if "stable" in ds:
                    stable = ds["stable"].values
                    facts.append(("stable points", f"{int(np.sum(stable == 1))} of {stable.size}"))
            break
    return {
        "folder": str(folder),
        "command_line": record.get("command_line", ""),
        "uri": data_uri(maps[0].read_bytes(), maps[0].suffix[1:]) if maps else None,
        "facts": facts,
    }


def deutsch_rows(summary: dict, sweep) -> list[dict]:
    """The Deutsch requirement per body mode, every number from summary.json."""
    rows = []
    for i, e in enumerate(summary["lag_damping"]["deutsch"]):
        key = f"lag_damping.deutsch.{i}"
        if e["satisfied"] is None:
            verdict = e["satisfied_reason"]
        else:
            verdict = "met by the installed damping" if e["satisfied"] else "NOT met by the installed damping"
        rows.append(
            {
                "mode": e["body_mode"],
                "form": e["form"],
                "frequency": frequency(e["body_frequency"], f"{key}.body_frequency", sweep),
                "tuning": speed(e["tuning_speed"], f"{key}.tuning_speed", sweep),
                "nu": number(e["lag_frequency_per_rev"], f"{key}.lag_frequency_per_rev", None)
                if e["lag_frequency_per_rev"] is not None
                else number(None, f"{key}.lag_frequency_per_rev", "no tuning"),
                "required": number(e["required_lag_damping"], f"{key}.required_lag_damping")
                if e["required_lag_damping"] is not None
                else number(
                    None, f"{key}.required_lag_damping", e.get("required_lag_damping_reason", "none")
                ),
                "verdict": verdict,
                "satisfied": e["satisfied"],
            }
        )
    return rows


def report_page(
    result, *, fmt: str = "png", study: str | Path | None = None, command_line: str = ""
) -> tuple[str, dict[str, bytes]]:
    """The HTML report of a :class:`~groundres.results.SweepResult`, and the pictures to write beside it.

    Returns ``(html, files)``: ``files`` maps file names (``coleman.<fmt>``,
    ``phasors.<fmt>``) to their bytes. The page embeds the pictures itself.
    """
    case = result.case
    sweep = case.sweep
    summary = result.summary()
    coleman = picture(result.plot(), fmt)
    phasors = phasor_section(result, summary, fmt)
    files = {f"coleman.{fmt}": coleman["bytes"]}
    if phasors is not None:
        files[f"phasors.{fmt}"] = phasors["picture"]["bytes"]
    ranges = [
        {
            "start": speed(r["start"], f"unstable_ranges.{i}.start", sweep),
            "end": speed(r["end"], f"unstable_ranges.{i}.end", sweep),
            "modes": ", ".join(r["modes"]),
            "note": r.get("start_note") or r.get("end_note") or "",
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
        "lag": lag,
        "coleman": coleman,
        "phasors": phasors,
        "study": study_section(Path(study), fmt) if study is not None else None,
        "accuracy": accuracy_rows(result.accuracy),
        "command_line": command_line,
        "unit_note": (
            f"Speeds in {sweep.unit}"
            + (f", with their ratio to the reference speed {reference} (ref)" if sweep.reference else "")
            + "; every number is also in summary.json beside this page, in SI units."
        ),
    }
    return render("report.html", **context), files
