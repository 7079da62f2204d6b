"""`groundres compare`: Coleman diagrams of several analyses overlaid, and how they differ."""

from __future__ import annotations

from pathlib import Path

import click

from .common import (
    FORMAT,
    Steps,
    check_out,
    fail_user,
    fmt_speed,
    invocation,
    load,
    make_console,
    out_option,
    output_dir,
    plain,
    ref_note,
)
from .plotoptions import check_modes, check_reference, check_scale, parse_limits, plot_options
from .run import STAGES, warm_plotting

#: The columns of differences.csv (speeds in rad/s, real parts in 1/s).
CSV_HEADER = ["entry", "name", "quantity", "range", "unit", "baseline", "value", "difference", "note"]


@click.command("compare")
@click.argument("cases", nargs=-1, required=True, metavar="CASE...")
@out_option("groundres-out/<first case name>-compare")
@click.option(
    "--method",
    "methods",
    multiple=True,
    type=click.Choice(["auto", "eigen", "floquet"]),
    help="Analysis method, repeatable: every CASE is analysed by each [default: each case's own].",
)
@click.option(
    "--frame",
    type=click.Choice(["nonrotating", "rotating"]),
    default=None,
    help="Frame of the frequencies, for every entry (overrides the cases).",
)
@click.option("--damping-ratio", is_flag=True, help="Plot damping ratio instead of real part.")
@plot_options(
    "Rotor-speed axis: the first case's unit, or divided by the first case's [sweep] reference; "
    "auto normalises where every case has that same reference."
)
@FORMAT
def command(cases, out, methods, frame, damping_ratio, speed_axis, frequency_limits, real_limits, modes, fmt):
    """Overlay the Coleman diagrams of two or more analyses and tabulate their differences.

    CASE is a TOML file or a shipped case name; the entries are every CASE by
    every --method, and entry 1 is the baseline: e.g. two cases, or one case
    by two methods (groundres compare hammond-one-damper-isotropic --method
    eigen --method floquet). Prints, and writes as differences.csv and
    differences.json, how each entry's unstable ranges and largest real part
    differ from the baseline's (data files in rad/s and 1/s; the table in the
    first case's unit). Also writes compare.<format> (png unless --format
    says), summary-<n>.json for entry n, case.toml (the first case),
    case-<k>.toml (the k-th CASE) and provenance.json into --out, replacing
    the folder whole.
    """
    from .. import folders, io
    from ..comparison import compare

    console = make_console()
    plot = {
        "show_damping_ratio": damping_ratio,
        "speed_axis": speed_axis,
        "frequency_limits": parse_limits(frequency_limits, "--frequency-limits"),
        "real_limits": parse_limits(real_limits, "--real-limits"),
    }
    methods = list(methods) or [None]
    if len(cases) * len(methods) < 2:
        fail_user(
            f"{len(cases)} case and {len(methods)} method make one entry: compare needs two or more; "
            "give two or more CASEs, or --method twice (e.g. --method eigen --method floquet)"
        )
    loaded = [load(case) for case in cases]
    check_reference(loaded[0], speed_axis, "the first case")
    out_dir = output_dir(cases[0], out, "compare")
    check_out(out_dir)
    warm = warm_plotting()
    asked = [f"{Path(case).stem}" + (f" --method {m}" if m else "") for case in cases for m in methods]

    with Steps(console) as steps:

        def progress(number, stage, done, total):
            steps(f"Entry {number} ({asked[number - 1]}): {STAGES.get(stage, stage).lower()}", done, total)

        comparison = compare(loaded, methods, frame, progress=steps.callback and progress)
        plot["modes"] = check_modes(modes, comparison.labels, "a mode of any entry")
        check_scale(*(e.result for e in comparison.entries), speed_axis=speed_axis)
        rows = comparison.differences()
        with steps.step("Writing results"), folders.output_folder(out_dir) as folder:
            for entry in comparison.entries:
                io.write_summary(entry.result, folder / f"summary-{entry.number}.json")
            io.write_csv(folder / "differences.csv", CSV_HEADER, [_csv_row(r) for r in rows])
            io.write_json(folder / "differences.json", _json(comparison, rows))
            warm.join()
            io.write_figure(comparison.plot(**plot), folder / f"compare.{fmt}")
            for k, case in enumerate(loaded[1:], start=2):
                with io.atomic_path(folder / f"case-{k}.toml") as tmp:
                    tmp.write_bytes(case.text.encode("utf-8"))
            folders.write_provenance(
                folder,
                loaded[0],
                command="compare",
                entries=[_entry_record(e, cases) for e in comparison.entries],
                **invocation(),
            )
    _print(console, comparison, rows, out_dir, fmt)


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


def _csv_row(row: dict) -> list:
    """A row of differences.csv: numbers in full (repr), empty cells where there is none."""

    def cell(v):
        if v is None:
            return ""
        return repr(v + 0.0) if isinstance(v, float) else v

    return [cell(row[key]) for key in CSV_HEADER]


def _json(comparison, rows) -> dict:
    from ..comparison import PAIRING_NOTE, QUANTITIES

    return {
        "baseline": 1,
        "entries": [
            {"entry": e.number, "name": e.name, "case": e.case.source, "title": e.case.title}
            | {"method": e.result.method, "frame": e.result.frame, "summary": f"summary-{e.number}.json"}
            for e in comparison.entries
        ],
        "quantities": {key: {"meaning": m, "unit": u} for key, (m, u) in QUANTITIES.items()},
        "note": PAIRING_NOTE,
        "differences": [
            {k: v for k, v in r.items() if v is not None or k not in ("range", "note")} for r in rows
        ],
    }


def _quantity(row: dict, unit: str) -> str:
    q, k = row["quantity"], row["range"]
    return {
        "unstable_range_count": "unstable ranges",
        "unstable_width": f"unstable width [{unit}]",
        "range_start": f"range {k} start [{unit}]",
        "range_end": f"range {k} end [{unit}]",
        "max_real_part": "largest real part [1/s]",
        "max_real_part_speed": f"  at [{unit}]",
    }[q]


def _cells(row: dict, sweep) -> tuple[str, str, str]:
    """Baseline, entry and difference as the table shows them (speeds in the first case's unit)."""
    from ..params import SPEED_UNITS

    speed = row["unit"] == "rad/s"
    width = row["quantity"] == "unstable_width"

    def value(v):
        if v is None:
            return "-"
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
    else:
        diff = f"{d / SPEED_UNITS[sweep.unit] if speed else d:+.3g}"
    return value(row["baseline"]), value(row["value"]), diff


def _print(console, comparison, rows, out_dir, fmt) -> None:
    from .printout import simple_table

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
    last = None
    for row in rows:
        if last is not None and row["entry"] != last:
            table.add_section()
        last = row["entry"]
        cells = (_quantity(row, sweep.unit), *_cells(row, sweep))
        table.add_row(str(row["entry"]), *(plain(c) for c in cells))
    console.print(table)
    units = {e.case.sweep.unit for e in entries}
    notes = [
        f"Speeds in {sweep.unit}, the first case's unit"
        + (" (the cases' own units differ)" if len(units) > 1 else "")
        + "; ranges are paired where they overlap, in speed order.",
    ]
    if ref_note(sweep):
        notes.append(ref_note(sweep))
    for line in notes:
        console.print(plain(line))
    files = [f"summary-{e.number}.json" for e in entries] + ["case.toml"]
    files += [f"case-{k}.toml" for k in range(2, 1 + len({e.case_index for e in entries}))]
    console.print(
        f"Wrote {plain(out_dir)}/compare.{fmt}, differences.csv, differences.json, {', '.join(files)}, "
        "provenance.json"
    )
