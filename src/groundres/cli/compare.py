"""`groundres compare`: Coleman diagrams of several analyses overlaid, and how they differ."""

from __future__ import annotations

from pathlib import Path

import click

from ..methods import OPTIONS
from ..model.units import fmt_speed
from .common import (
    FORMAT,
    Steps,
    check_out,
    fail_user,
    invocation,
    load,
    make_console,
    method_named,
    out_name,
    out_option,
    output_dir,
    plain,
)
from .plotoptions import check_modes, check_reference, check_scale, parse_limits, plot_options
from .run import STAGES, warm_plotting


@click.command("compare")
@click.argument("cases", nargs=-1, required=True, metavar="CASE...")
@out_option("groundres-out/<first case name>-compare")
@click.option(
    "--method",
    "methods",
    multiple=True,
    type=click.Choice(OPTIONS),
    help="Analysis method, repeatable: every CASE is analysed by each [default: each case's own].",
)
@click.option(
    "--frame",
    type=click.Choice(["nonrotating", "rotating"]),
    default=None,
    help="Frame of the frequencies, for every entry (overrides the cases).",
)
@click.option(
    "--vacuum",
    is_flag=True,
    help="Also analyse every CASE in air without its [aero] table, as the entry just before it "
    "(so one case and --vacuum compare the rotor in vacuum, the baseline, with it in air).",
)
@click.option("--damping-ratio", is_flag=True, help="Plot damping ratio instead of real part.")
@plot_options(
    "Rotor-speed axis: the first case's unit, or divided by the first case's [sweep] reference; "
    "auto normalises where every case has that same reference."
)
@FORMAT
def command(
    cases, out, methods, frame, vacuum, damping_ratio, speed_axis, frequency_limits, real_limits, modes, fmt
):
    """Overlay the Coleman diagrams of two or more analyses and tabulate their differences.

    CASE is a TOML file or a shipped case name; the entries are every CASE by
    every --method, and entry 1 is the baseline: e.g. two cases, or one case
    by two methods (groundres compare hammond-one-damper-isotropic --method
    eigen --method floquet). Prints, and writes as differences.csv and
    differences.json, how each entry's unstable ranges, growth margin and least damping ratio
    differ from the baseline's (data files in rad/s and 1/s, as computed, with
    each difference's round-off tolerance; the table in the first case's unit,
    a difference within its tolerance as "0 (round-off)"). Also writes
    compare.<format> (png unless --format says), summary-<n>.json for entry n,
    case.toml (the first case), case-<k>.toml (the k-th CASE) and
    provenance.json into --out, replacing the folder whole.
    """
    from ..analysis import compare
    from ..results import files, folders

    console = make_console()
    plot = {
        "show_damping_ratio": damping_ratio,
        "speed_axis": speed_axis,
        "frequency_limits": parse_limits(frequency_limits, "--frequency-limits"),
        "real_limits": parse_limits(real_limits, "--real-limits"),
    }
    methods = list(methods) or [None]
    loaded = [load(case, named=True) for case in cases]
    if vacuum:
        if not any(c.rotor.aero is not None for c in loaded):
            fail_user("--vacuum: no CASE has an [aero] table; every one is in vacuum already")
        loaded, cases = _with_twins(loaded, cases)
    if len(cases) * len(methods) < 2:
        fail_user(
            f"{len(cases)} case and {len(methods)} method make one entry: compare needs two or more; "
            "give two or more CASEs, or --method twice (e.g. --method eigen --method floquet)"
        )
    check_reference(loaded[0], speed_axis, "the first case")
    out_dir = output_dir(cases[0], out, "compare")
    check_out(out_dir, out)
    warm = warm_plotting()
    asked = [f"{Path(case).stem}" + (f" --method {m}" if m else "") for case in cases for m in methods]

    with Steps(console) as steps:

        def progress(number, stage, done, total):
            steps(f"Entry {number} ({asked[number - 1]}): {STAGES.get(stage, stage).lower()}", done, total)

        with method_named():
            comparison = compare(loaded, methods, frame, progress=steps.callback and progress)
        plot["modes"] = check_modes(modes, comparison.labels, "a mode of any entry")
        check_scale(*(e.result for e in comparison.entries), speed_axis=speed_axis)
        rows = comparison.differences()
        with steps.step("Writing results"), folders.output_folder(out_dir, out_name(out)) as folder:
            for entry in comparison.entries:
                files.write_json(folder / f"summary-{entry.number}.json", entry.result.summary())
            files.write_differences(comparison, folder, rows)
            warm.join()
            files.write_figure(comparison.plot(**plot), folder / f"compare.{fmt}")
            for k, case in enumerate(loaded[1:], start=2):
                files.write_bytes(folder / f"case-{k}.toml", case.text.encode("utf-8"))
            folders.write_provenance(
                folder,
                loaded[0],
                command="compare",
                entries=[_entry_record(e, cases) for e in comparison.entries],
                **invocation(),
            )
    _print(console, comparison, rows, out_dir, fmt)


def _with_twins(loaded, cases):
    """The cases with each one in air preceded by itself in vacuum (:meth:`Case.in_vacuum`),
    and the arguments that name them."""
    cases_out, names = [], []
    for case, argument in zip(loaded, cases):
        if case.rotor.aero is not None:
            cases_out.append(case.in_vacuum())
            names.append(f"{argument} (in vacuum)")
        cases_out.append(case)
        names.append(argument)
    return cases_out, names


def _entry_record(entry, cases) -> dict:
    """An entry as provenance.json and differences.json name it."""
    return {
        "entry": entry.number,
        "name": entry.name,
        "case": {
            "source": entry.case.source,
            "title": entry.case.title,
            "file": "case.toml" if entry.case_index == 0 else f"case-{entry.case_index + 1}.toml",
            "argument": cases[entry.case_index],
        },
        "method_asked": entry.method or "the case's own",
        "method": entry.result.method,
        "frame": entry.result.frame,
        "summary": f"summary-{entry.number}.json",
        "accuracy": entry.result.accuracy or {},
    }


def _quantity(row: dict, unit: str) -> str:
    q, k = row["quantity"], row["range"]
    return {
        "unstable_range_count": "unstable ranges",
        "unstable_width": f"unstable width [{unit}]",
        "range_start": f"range {k} start [{unit}]",
        "range_end": f"range {k} end [{unit}]",
        "growth_margin": "growth margin [1/s]",
        "growth_margin_speed": f"  at [{unit}]",
        "least_damping_ratio": "least damping ratio [-]",
        "least_damping_ratio_speed": f"  at [{unit}]",
    }[q]


#: A difference within its round-off tolerance, as the table shows it.
ROUND_OFF_TEXT = "0 (round-off)"


def _cells(row: dict, sweep, neutral: dict) -> tuple[str, str, str]:
    """Baseline, entry and difference as the table shows them (speeds in the first case's
    unit): round-off never as a number. ``neutral``: entry number -> whether its growth
    margin is neutral (within the growth threshold of zero)."""
    from ..model.units import SPEED_UNITS

    speed = row["unit"] == "rad/s"
    width = row["quantity"] == "unstable_width"
    peak = row["quantity"] in ("growth_margin", "growth_margin_speed")

    def value(v, number):
        if v is None:
            return "-"
        if peak and neutral[number]:  # round-off: a neutral growth margin, and where it peaks
            return "neutral" if row["quantity"] == "growth_margin" else "-"
        if isinstance(v, int):
            return str(v)
        if speed and not width:
            return fmt_speed(v, sweep, digits=6, unit=False, sep="\n")
        return f"{v / SPEED_UNITS[sweep.unit] if speed else v:.6g}"

    d = row["difference"]
    if d is None:
        diff = row["note"] or "-"
    elif d == 0:
        diff = "0"
    elif row["quantity"] == "growth_margin_speed" and (neutral[1] or neutral[row["entry"]]):
        diff = "- (neutral)"
    elif row["within_round_off"]:
        diff = ROUND_OFF_TEXT
    else:
        diff = f"{d / SPEED_UNITS[sweep.unit] if speed else d:+.3g}"
    return value(row["baseline"], 1), value(row["value"], row["entry"]), diff


def _print(console, comparison, rows, out_dir, fmt) -> None:
    from ..results.comparison import neutral_max
    from .printout import simple_table, threshold_text

    entries = comparison.entries
    sweep = entries[0].case.sweep
    table = simple_table("Entries (entry 1 is the baseline)")
    for header in ("#", "case", "method", "frame", "verdict"):
        table.add_column(header)
    for e in entries:
        verdict = (
            "stable" if e.result.stability.stable else f"unstable ({len(e.result.stability.unstable_ranges)})"
        )
        table.add_row(str(e.number), plain(e.case_name), e.result.method, e.result.frame, plain(verdict))
    console.print(table)
    console.print()
    table = simple_table("Differences from the baseline (entry - entry 1)")
    for header in ("#", "quantity", "baseline", "entry", "difference"):
        table.add_column(header)
    neutral = {e.number: neutral_max(e.result) for e in entries}
    last, shown = None, set()
    for row in rows:
        if last is not None and row["entry"] != last:
            table.add_section()
        last = row["entry"]
        cells = (_quantity(row, sweep.unit), *_cells(row, sweep, neutral))
        shown.update(cells[1:])
        table.add_row(str(row["entry"]), *(plain(c) for c in cells))
    console.print(table)
    units = {e.case.sweep.unit for e in entries}
    notes = [
        f"Speeds in {sweep.unit}, the first case's unit"
        + (" (the cases' own units differ)" if len(units) > 1 else "")
        + "; ranges are paired where they overlap, in speed order.",
    ]
    if ROUND_OFF_TEXT in shown:
        notes.append(
            f"{ROUND_OFF_TEXT}: a difference within the round-off of the computation (its tolerance, "
            "and the difference as computed, in differences.json)."
        )
    if "neutral" in shown:
        notes.append(
            f"neutral: the growth margin within the growth threshold of zero ({threshold_text()}): "
            "round-off, not growth; where it peaks is no result."
        )
    if sweep.reference:
        refs = {e.case.sweep.reference for e in entries}
        notes.append(
            "ref: rotor speed / the first case's reference speed, "
            + fmt_speed(sweep.reference, sweep, ref=False)
            + (", for every entry (the cases' own references differ)." if len(refs) > 1 else ".")
        )
    for line in notes:
        console.print(plain(line))
    files = [f"summary-{e.number}.json" for e in entries] + ["case.toml"]
    files += [f"case-{k}.toml" for k in range(2, 1 + len({e.case_index for e in entries}))]
    console.print(
        f"Wrote {plain(out_dir)}/compare.{fmt}, differences.csv, differences.json, {', '.join(files)}, "
        "provenance.json"
    )
