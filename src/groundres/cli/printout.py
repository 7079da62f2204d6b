"""What `groundres run` prints: verdict, worst values, the Deutsch table, at 80 columns.

Speeds are in the case's unit (with their ratio to the reference speed, "ref");
values within the growth threshold of zero print as neutral, not as numbers
(they are round-off; the data files keep them as computed). User text
(titles) is printed literally, never as rich markup.
"""

from __future__ import annotations

from ..model.units import FREQUENCY_UNITS, fmt_speed, ref_note, significant
from ..results.air import DEUTSCH_IN_AIR, shown_rows
from ..results.summary import SWEEP_END_NOTE, SWEEP_START_NOTE, no_exact_reason, open_below_note
from .common import plain

#: How the terminal names each inflow model.
INFLOW_WORDS = {"uniform": "uniform", "dynamic": "Pitt-Peters dynamic"}


def simple_table(title: str):
    """A table that fits 80 columns: a rule under the header, two spaces between columns."""
    from rich import box
    from rich.table import Table

    return Table(
        title=title, title_justify="left", box=box.SIMPLE_HEAD, show_edge=False, padding=(0, 1, 0, 0)
    )


def threshold_text() -> str:
    from ..assess.stability import GROWTH_FLOOR, GROWTH_PER_RADIAN

    return f"{GROWTH_PER_RADIAN:g} 1/s per rad/s of rotor speed + {GROWTH_FLOOR:g} 1/s"


def worst_values(summary: dict, sweep) -> str:
    """The largest real part and smallest damping ratio, neutral where they are round-off."""
    mr, md = summary["max_real_part"], summary["min_damping_ratio"]
    if mr["value"] is None:
        first = f"Largest real part: none ({mr['value_reason']})"
    elif mr["neutral"]:
        first = (
            f"Largest real part: neutral (below the growth threshold, {threshold_text()}, "
            "over the sweep: round-off, not growth)"
        )
    else:
        at = fmt_speed(mr["speed"], sweep)
        first = f"Largest real part {mr['value']:.4g} 1/s ({plain(mr['mode'])}{_creeps(mr)}) at {at}"
    if md["value"] is None:
        second = f"smallest damping ratio: none ({md['value_reason']})"
    elif md["neutral"]:
        second = "smallest damping ratio 0 (neutral)"
    else:
        at = fmt_speed(md["speed"], sweep)
        second = f"smallest damping ratio {md['value']:.4g} ({plain(md['mode'])}{_creeps(md)}) at {at}"
    return f"{first}; {second}."


def _creeps(worst: dict) -> str:
    """Words for a worst value that comes from a mode that does not vibrate there."""
    return "" if worst.get("vibrating", True) else ", not vibrating: neutral at rest, overdamped"


def unstable_table(summary: dict, sweep):
    unit = sweep.unit
    table = simple_table("Unstable rotor-speed ranges")
    for header in (f"from [{unit}]", f"to [{unit}]", "growing modes"):
        table.add_column(plain(header))
    for r in summary["unstable_ranges"]:
        modes = plain(", ".join(r["modes"]))
        start = ("<= " if "start_note" in r else "") + _speed_cell(r["start"], sweep)
        end = (">= " if r.get("open_end") else "") + _speed_cell(r["end"], sweep)
        table.add_row(start, end, modes)
    return table


def range_notes(summary: dict, sweep) -> list[str]:
    """Lines explaining a range whose start is only a bound
    (:func:`groundres.results.summary.open_below_note`)."""
    out = []
    for r in summary["unstable_ranges"]:
        if r.get("start_note") == SWEEP_START_NOTE:
            out.append(f"<= {fmt_speed(r['start'], sweep)}: {SWEEP_START_NOTE}.")
        elif "start_note" in r:
            out.append(f"<= {fmt_speed(r['start'], sweep)}: {open_below_note(fmt_speed(r['start'], sweep))}.")
        if r.get("open_end"):
            out.append(f">= {fmt_speed(r['end'], sweep)}: {SWEEP_END_NOTE}.")
    return out


def _speed_cell(w, sweep, digits=5, sep=" ") -> str:
    """A speed in a column headed with the unit: the number, and its ratio to the reference."""
    return fmt_speed(w, sweep, digits, unit=False, sep=sep)


def _verdict(e: dict) -> str:
    if not e["applies"]:
        return f"does not apply:\n{e['limitation']}"
    if e["tuning_speed"] is None:
        return "none needed:\nno tuning"
    if e["required_lag_damping"] is None:
        return "[red]no[/red]: body undamped"
    return "[green]yes[/green]" if e["satisfied"] else "[red]no[/red]"


def _tuning_cell(e: dict, sweep) -> str:
    if e["tuning_speed"] is None:
        return "none"
    text = _speed_cell(e["tuning_speed"], sweep, digits=4, sep="\n")
    return text if e["tuning_in_sweep"] else f"{text}\n{_side(e, sweep)}"


def _side(e: dict, sweep) -> str:
    return "beyond sweep" if e["tuning_speed"] > sweep.stop else "below sweep"


def _installed(lag: dict) -> str:
    if lag["installed"] == 0:
        return "no lag damper"
    text = f"{lag['installed']:.5g} N m s/rad"
    return text + (f", {lag['failed_dampers']} failed" if lag["failed_dampers"] else "")


def deutsch_table(summary: dict, sweep):
    """One row per body mode: tuning, requirement and the verdict on the installed damper."""
    from ..model.units import SPEED_UNITS

    lag = summary["lag_damping"]
    unit = sweep.unit
    table = simple_table("Lag damping by the Deutsch criterion, per body mode")
    for header in (
        "body mode",
        f"omega_b\n[{FREQUENCY_UNITS[unit]}]",
        f"tuning\n[{unit}]",
        "nu\n[/rev]",
        "needs\n[N m s/rad]",
        "verdict",
    ):
        name, _, units = header.partition("\n")
        table.add_column(plain(header), min_width=max(len(name), len(units)))
    for e in lag["deutsch"]:
        need = e["required_lag_damping"]
        if e["tuning_speed"] is None:
            need_text = "-"
        else:
            need_text = "infinite" if need is None else f"{need:.5g}"
        table.add_row(
            e["body_mode"],
            f"{e['body_frequency'] / SPEED_UNITS[unit]:.4g}",
            _tuning_cell(e, sweep),
            "-" if e["lag_frequency_per_rev"] is None else f"{e['lag_frequency_per_rev']:.4g}",
            need_text,
            _verdict(e),
        )
    return table


def deutsch_notes(summary: dict, sweep) -> list[str]:
    """The lines under the Deutsch table: every symbol explained once."""
    rows = summary["lag_damping"]["deutsch"]
    forms = {e["form"] for e in rows}
    text = (
        "omega_b: body frequency, rotor mass included; tuning: rotor speed where the regressive "
        "lag frequency Omega (1 - nu) meets omega_b; nu: rotating lag frequency at that speed "
        "[per rev]"
    )
    if "isotropic" in forms:
        text += "; x-y, pitch-roll: isotropic form (both directions alike)"
    if "planar" in forms:
        coupled = any(e["body_mode"].startswith("mode ") for e in rows)
        text += (
            "; mode k: a mode of the body on its gear (rotor mass and inertia included), named by the "
            "coordinate that moves most, referred to the hub's motion in the rotor plane; planar form"
            if coupled
            else "; x, y, pitch, roll: planar form"
        )
    lag = summary["lag_damping"]
    if lag["installed"] == 0:
        installed = "Installed lag damping: none."
    elif "rods" in lag:
        installed = (
            f"Installed: {lag['installed']:.5g} N m s/rad of cyclic lag damping per blade, from the blades' "
            "own dampers and the damper rods (a rod between mirror-image points of blades j apart gives "
            "c g^2 (2 - 2 cos(2 pi j / N)))."
        )
    else:
        failed = f" ({lag['failed_dampers']} failed)" if lag["failed_dampers"] else ""
        installed = f"Installed: {lag['installed']:.5g} N m s/rad, the smallest working lag damper{failed}."
    notes = [installed, text + "."]
    outside = {_side(e, sweep) for e in rows if e["tuning_in_sweep"] is False}
    if outside:
        notes.append(
            f"{' / '.join(sorted(outside))}: the tuning speed lies outside the sweep "
            f"({fmt_speed(sweep.start, sweep, ref=False)} to {fmt_speed(sweep.stop, sweep, ref=False)}), "
            "so the sweep does not reach that resonance."
        )
    ref = ref_note(sweep)
    if ref:
        notes.append(ref)
    limits = {e.get("limitation") for e in rows} - {None}
    if "damper rods differ" in limits:
        notes.append(
            "Damper rods differ: the criterion assumes every blade alike with its rods; its 'needs' is "
            "for the rotor's average rod, which can miss what a failed rod does. The exact minimum "
            "below governs."
        )
    if "blades differ" in limits:
        notes.append(
            "Blades differ: the criterion assumes identical blades; its 'needs' is for the "
            "average blade (smeared damper), which can miss what a failed damper does. The "
            "exact minimum below governs."
        )
    if "two blades" in limits:
        notes.append(
            "Two blades: the criterion assumes N >= 3 blades; a two-bladed rotor has periodic "
            "coefficients in every frame. Its 'needs' is indicative only; the exact minimum "
            "below governs."
        )
    if "aero" in summary:
        notes.append(f"In air: {DEUTSCH_IN_AIR}; the exact minimum below includes the air.")
    return [plain(n) for n in notes]


def air_header(summary: dict) -> str:
    """One line on the air: the Lock number and solidity (which one the case gave), the pitch."""
    a = summary["aero"]
    lock = f"Lock number {a['lock_number']:.4g}" + (" (given)" if a["given"] == "lock_number" else "")
    density = f"air density {a['air_density']:.4g} kg/m^3" + (
        " (given)" if a["given"] == "air_density" else ""
    )
    couplings = ", ".join(
        f"{name} {a[key]:+.3g}"
        for key, name in (("pitch_flap", "K_Pbeta"), ("pitch_lag", "K_Pzeta"))
        if a[key]
    )
    return (
        f"In air: {lock}, {density}, solidity {a['solidity']:.4g}; collective {a['collective']:.4g} deg, "
        f"twist {a['twist']:.4g} deg{', ' + couplings if couplings else ''}; "
        f"{INFLOW_WORDS[a['inflow']]} inflow."
    )


def trim_table(summary: dict, sweep):
    """The hover trim at a few speeds spread over the sweep (:func:`groundres.results.air.shown_rows`)."""
    table = simple_table("Hover trim (every speed in summary.json and modes.nc)")
    for head in (
        "speed",
        "lambda",
        "C_T",
        "C_T/sigma",
        "coning\n[deg]",
        "trim lag\n[deg]",
        "thrust\n[N]",
        "torque\n[N m]",
    ):
        table.add_column(head, justify="right")
    for i, row in shown_rows(summary["trim"]):
        digits = {"thrust": 5, "torque": 5}
        table.add_row(
            _speed_cell(summary["trim"]["rotor_speed"][i], sweep),
            *(f"{value:.{digits.get(name, 4)}g}" for name, value in row.items()),
        )
    return table


def print_result(console, result, summary: dict, out_dir, fmt: str = "png") -> None:
    """The terminal's account of a run: verdict, ranges, worst values, the lag damping
    (``summary``: the result's :meth:`~groundres.results.sweep.SweepResult.summary`)."""
    sweep = result.case.sweep
    console.print(
        f"[bold]{plain(result.case.title)}[/bold]  "
        f"({summary['method']}, frequencies in the {result.frame} frame)"
    )
    if "aero" in summary:
        console.print(plain(air_header(summary)))
        console.print(trim_table(summary, sweep))
        if not result.case.rotor.blades_alike:
            console.print("Coning and trim lag of blade 1 (the blades differ: each blade's in summary.json).")
    if result.case.rotor.nonlinear:
        console.print(plain(f"Nonlinear lag dampers: {summary['lag_dampers']['note']}."))
    if summary["stable"]:
        console.print(
            "[green]Stable[/green] over the whole sweep "
            f"{fmt_speed(result.rotor_speed[0], sweep)} to {fmt_speed(result.rotor_speed[-1], sweep)}."
        )
    else:
        console.print()
        console.print(unstable_table(summary, sweep))
        for line in range_notes(summary, sweep):
            console.print(plain(line))
    console.print(worst_values(summary, sweep))
    if "margins" in summary:
        console.print()
        console.print(margins_table(summary, sweep))
        for line in margins_notes(summary, sweep):
            console.print(plain(line))
    console.print()
    if "deutsch_overall" in summary["lag_damping"]:
        console.print(plain(f"Note: {summary['lag_damping']['deutsch_overall']}."))
    console.print(deutsch_table(summary, sweep))
    for line in deutsch_notes(summary, sweep):
        console.print(line)
    lag = summary["lag_damping"]
    exact = lag["exact_minimum"]
    unit = lag["exact_minimum_unit"]
    if lag["exact_minimum_searched"] == "damper rods":
        what = "damper-rod damping"
        which = "every rod" if result.case.rotor.identical else "every working rod"
        values = sorted({r["damping"] for r in lag["rods"] if r["damping"] > 0})
        installed = "installed: " + (
            "no rod damping"
            if not values
            else f"{values[0]:.5g} N s/m"
            if len(values) == 1
            else f"rods differ, the smallest working {values[0]:.5g} N s/m"
        )
    else:
        what = "lag damping"
        which = "every blade" if result.case.rotor.identical else "every working damper"
        installed = f"installed: {_installed(lag)}"
    if exact is None:
        why = no_exact_reason(result, lambda w: fmt_speed(w, sweep))
        console.print(f"Exact minimum {what} (on {which}): none: {why} ({installed}).")
    elif exact == 0:
        console.print(f"Exact minimum {what}: 0, the sweep is stable without it ({installed}).")
    else:
        shown = significant(exact, lag["exact_minimum_relative_tolerance"])
        console.print(f"Exact minimum {what} (on {which}, from the roots): {shown} {unit} ({installed}).")
    console.print(
        f"Wrote {plain(out_dir)}/summary.json, modes.csv, modes.nc, coleman.{fmt}, case.toml, provenance.json"
    )


def _percent(least: dict | None) -> str:
    """A damping ratio in per cent, or why there is none."""
    if least is None:
        return "-"
    return "0 (neutral)" if least["neutral"] else f"{100 * least['value']:.3g}"


def _at(least: dict | None, sweep) -> str:
    return "" if least is None or least["neutral"] else _speed_cell(least["speed"], sweep, digits=4, sep="\n")


_VERDICT_STYLE = {
    "meets the requirement": "green",
    "stable": "green",
    "stable but below it": "yellow",
    "unstable": "red",
}


def margins_table(summary: dict, sweep):
    """One row per mode: its least damping ratio over the operating range and the run-up,
    the margin to the requirement and the verdict (:mod:`groundres.assess.margins`)."""
    m = summary["margins"]
    unit = sweep.unit
    where = "operating range" if m["operating_range"]["given"] else "sweep"
    title = f"Damping of each mode over the {where}"
    if m["required_damping_ratio"] is not None:
        title += f", against {100 * m['required_damping_ratio']:.3g} % required"
    table = simple_table(title)
    headers = ["mode", "least\n[%]", f"at\n[{unit}]"]
    if m["run_up"] is not None:
        headers += ["run-up\n[%]", f"at\n[{unit}]"]
    headers += ["margin\n[%]", "verdict"]
    for header in headers:
        name, _, units = header.partition("\n")
        table.add_column(plain(header), min_width=max(len(name), len(units)))
    for row in m["modes"]:
        cells = [
            plain(row["mode"]),
            _percent(row["least_damping_ratio"]),
            _at(row["least_damping_ratio"], sweep),
        ]
        if m["run_up"] is not None:
            run_up = row["least_damping_ratio_run_up"]
            cells += [_percent(run_up), _at(run_up, sweep)]
        margin = row["margin"]
        cells.append("-" if margin is None else f"{100 * margin:+.3g}")
        style = _VERDICT_STYLE[row["verdict"]]
        cells.append(f"[{style}]{row['verdict']}[/{style}]")
        table.add_row(*cells)
    return table


def margins_notes(summary: dict, sweep) -> list[str]:
    """The verdict over the operating range, and the lines under the margins table."""
    m = summary["margins"]
    lo, hi = m["operating_range"]["start"], m["operating_range"]["stop"]
    span = f"{fmt_speed(lo, sweep, ref=False)} to {fmt_speed(hi, sweep, ref=False)}"
    where = (
        f"operating range {span}"
        if m["operating_range"]["given"]
        else f"whole sweep {span} (no operating range given)"
    )
    least = m["least_damping_ratio"]
    verdict = m["verdict"]
    if least is None:
        text = f"Margins over the {where}: no mode vibrates there."
    else:
        value = "0 (neutral)" if least["neutral"] else f"{100 * least['value']:.3g} %"
        text = f"Verdict: {verdict}. Least damping ratio over the {where}: {value} ({least['mode']}"
        text += ")" if least["neutral"] else f", at {fmt_speed(least['speed'], sweep)})"
        if m["required_damping_ratio"] is not None:
            text += f"; required {100 * m['required_damping_ratio']:.3g} %"
        text += "."
    notes = [text]
    if m["run_up"] is not None:
        start, stop = (fmt_speed(m["run_up"][k], sweep, ref=False) for k in ("start", "stop"))
        notes.append(
            f"Run-up: the sweep below the operating range, {start} to {stop}; it must be stable, the "
            "requirement applies over the operating range."
        )
    growth = m["growth_margin"]
    if growth is not None:
        shown = "neutral" if growth["neutral"] else f"{growth['value']:.4g} 1/s"
        notes.append(
            f"Growth margin (largest real part of the vibrating modes): {shown} ({growth['mode']}"
            + (")." if growth["neutral"] else f", at {fmt_speed(growth['speed'], sweep)}).")
        )
    if m["neutral_at_rest"]:
        notes.append(
            f"Neutral at rest ({', '.join(m['neutral_at_rest'])}): no stiffness with the rotor stopped; "
            "counted only where they vibrate (not while overdamped at low speed)."
        )
    notes.append(
        "-: the mode does not vibrate there; neutral: within the growth threshold of zero (round-off)."
    )
    return notes
