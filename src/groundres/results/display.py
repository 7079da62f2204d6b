"""How results read in a notebook or at a prompt: a short text and an HTML table.

``repr(result)`` is a few lines (what was analysed, the verdict, the unstable
ranges and the margins), never the arrays; ``_repr_html_`` is the same as a
small page fragment that Jupyter shows. Every number comes from the result's
summary (:mod:`groundres.results.summary`), in the case's unit, so it reads as
the terminal and the report do.
"""

from __future__ import annotations

from html import escape

from ..model.units import fmt_speed

#: The colour of each verdict in HTML (the report's).
_COLOUR = {
    "meets the requirement": "#1a7f37",
    "stable": "#1a7f37",
    "stable but below it": "#9a6700",
    "unstable": "#cf222e",
}


def _ratio(least: dict | None) -> str:
    if least is None:
        return "-"
    return "0 (neutral)" if least["neutral"] else f"{100 * least['value']:.3g} %"


def _where(least: dict | None, sweep) -> str:
    return "" if least is None or least["neutral"] else fmt_speed(least["speed"], sweep, digits=4)


def _ranges(summary: dict, sweep) -> list[str]:
    lines = []
    for r in summary["unstable_ranges"]:
        start = fmt_speed(r["start"], sweep, digits=4, ref=False)
        end = fmt_speed(r["end"], sweep, digits=4, ref=False)
        opens = [s for s, k in (("start", "open_start"), ("end", "open_end")) if r.get(k)]
        text = f"{start} to {end}" + (f" (open at the sweep's {' and '.join(opens)})" if opens else "")
        lines.append(f"{text}: {', '.join(r['modes'])}")
    return lines


def _lines(summary: dict, sweep) -> list[tuple[str, str]]:
    """(heading, text) pairs: the facts both forms show."""
    m = summary["margins"]
    span = (
        f"{fmt_speed(summary['sweep']['start'], sweep, digits=4, ref=False)} to "
        f"{fmt_speed(summary['sweep']['stop'], sweep, digits=4, ref=False)}"
    )
    out = [
        ("analysis", f"{summary['method']}, {summary['frame']} frame"),
        ("sweep", f"{summary['sweep']['points']} speeds, {span}; {len(summary['modes'])} modes"),
        ("verdict", m["verdict"]),
    ]
    ranges = _ranges(summary, sweep)
    out += [("unstable", text) for text in ranges] or [("unstable", "nowhere in the sweep")]
    least = m["least_damping_ratio"]
    where = "operating range" if m["operating_range"]["given"] else "sweep"
    if least is not None:
        text = f"{_ratio(least)} ({least['mode']}"
        text += ")" if least["neutral"] else f", at {_where(least, sweep)})"
        if m["required_damping_ratio"] is not None:
            text += f"; required {100 * m['required_damping_ratio']:.3g} %"
        out.append((f"least damping ratio over the {where}", text))
    growth = m["growth_margin"]
    if growth is not None:
        value = "neutral" if growth["neutral"] else f"{growth['value']:.4g} 1/s"
        at = "" if growth["neutral"] else f", at {fmt_speed(growth['speed'], sweep, digits=4)}"
        out.append(("growth margin", f"{value} ({growth['mode']}{at})"))
    return out


def sweep_text(result) -> str:
    """``repr`` of a :class:`~groundres.results.sweep.SweepResult`: a few lines."""
    summary, sweep = result.summary(), result.case.sweep
    lines = [f"<SweepResult: {summary['title']}"]
    lines += [f"  {heading}: {text}" for heading, text in _lines(summary, sweep)]
    return "\n".join(lines) + ">"


def sweep_html(result) -> str:
    """``_repr_html_`` of a :class:`~groundres.results.sweep.SweepResult`: the facts, then one
    row per mode (least damping ratio over the operating range and the run-up, the margin to
    the requirement, the verdict)."""
    summary, sweep = result.summary(), result.case.sweep
    m = summary["margins"]
    facts = "".join(
        f"<tr><th style='text-align:left'>{escape(h)}</th><td style='text-align:left'>"
        + (_verdict_html(t) if h == "verdict" else escape(t))
        + "</td></tr>"
        for h, t in _lines(summary, sweep)
    )
    run_up = m["run_up"] is not None
    head = ["mode", "least damping ratio", "at"] + (["run-up", "at"] if run_up else [])
    head += ["margin", "largest real part [1/s]", "verdict"]
    rows = []
    for row in m["modes"]:
        cells = [escape(row["mode"]), _ratio(row["least_damping_ratio"])]
        cells.append(escape(_where(row["least_damping_ratio"], sweep)))
        if run_up:
            up = row["least_damping_ratio_run_up"]
            cells += [_ratio(up), escape(_where(up, sweep))]
        cells.append("-" if row["margin"] is None else f"{100 * row['margin']:+.3g} %")
        largest = row.get("largest_real_part")
        cells.append("-" if largest is None else f"{largest['value']:.4g}")
        cells.append(_verdict_html(row["verdict"]))
        rows.append("<tr>" + "".join(f"<td style='text-align:left'>{c}</td>" for c in cells) + "</tr>")
    header = "".join(f"<th style='text-align:left'>{escape(h)}</th>" for h in head)
    note = (
        "- : the mode does not vibrate there (neutral at rest, overdamped); "
        "damping ratios seen from nonrotating axes."
    )
    return (
        f"<div><strong>{escape(summary['title'])}</strong>"
        f"<table>{facts}</table>"
        f"<table><thead><tr>{header}</tr></thead><tbody>{''.join(rows)}</tbody></table>"
        f"<small>{escape(note)}</small></div>"
    )


def _verdict_html(verdict: str) -> str:
    return f"<span style='color:{_COLOUR[verdict]};font-weight:600'>{escape(verdict)}</span>"


def _table(title: str, pairs: list[tuple[str, str]]) -> str:
    rows = "".join(
        f"<tr><th style='text-align:left'>{escape(h)}</th><td style='text-align:left'>{escape(t)}</td></tr>"
        for h, t in pairs
    )
    return f"<div><strong>{escape(title)}</strong><table>{rows}</table></div>"


def _simulation_lines(sim) -> list[tuple[str, str]]:
    from ..solve.simulate import initial_text

    sweep = sim.case.sweep
    t = sim.time
    return [
        ("rotor speed", fmt_speed(sim.rotor_speed, sweep)),
        ("time", f"{t[-1] - t[0]:.4g} s, {len(t)} instants, {len(sim.coordinates)} coordinates"),
        ("initial disturbance", initial_text(sim.initial)),
        ("growth rate", f"{sim.growth_rate():.4g} 1/s measured over the second half"),
        ("predicted", f"{sim.predicted_growth:.4g} 1/s, the largest real part ({sim.method})"),
        ("model", "linear: amplitudes scale with the initial disturbance, only their growth matters"),
    ]


def simulation_text(sim) -> str:
    """``repr`` of a :class:`~groundres.results.simulation.Simulation`."""
    lines = [f"<Simulation: {sim.case.title}"] + [f"  {h}: {t}" for h, t in _simulation_lines(sim)]
    return "\n".join(lines) + ">"


def simulation_html(sim) -> str:
    """``_repr_html_`` of a :class:`~groundres.results.simulation.Simulation`."""
    return _table(sim.case.title, _simulation_lines(sim))


def _comparison_lines(comparison) -> list[tuple[str, str]]:
    out = []
    for e in comparison.entries:
        summary, sweep = e.result.summary(), e.result.case.sweep
        ranges = "; ".join(_ranges(summary, sweep)) or "stable over the sweep"
        out.append((f"entry {e.number}", f"{e.name}, {e.result.method}: {ranges}"))
    rows = comparison.differences()
    beyond = [r for r in rows if r["within_round_off"] is False]
    names = sorted({r["quantity"] for r in beyond})
    out.append(
        (
            "differences",
            f"{len(rows)} against entry 1, {len(beyond)} beyond round-off"
            + (f" ({', '.join(names)})" if names else ""),
        )
    )
    return out


def comparison_text(comparison) -> str:
    """``repr`` of a :class:`~groundres.results.comparison.Comparison`."""
    lines = [f"<Comparison of {len(comparison.entries)} entries (entry 1 the baseline)"]
    lines += [f"  {h}: {t}" for h, t in _comparison_lines(comparison)]
    return "\n".join(lines) + ">"


def comparison_html(comparison) -> str:
    """``_repr_html_`` of a :class:`~groundres.results.comparison.Comparison`."""
    return _table(f"Comparison of {len(comparison.entries)} entries", _comparison_lines(comparison))
