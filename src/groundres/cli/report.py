"""`groundres report`: one case as a self-contained, printable HTML page."""

from __future__ import annotations

import os
import shlex
import stat
from pathlib import Path

import click

from ..errors import shown, shown_path
from ..methods import OPTIONS
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

#: Files a study folder holds that the report reads (one of them, with case.toml).
STUDY_DATA = ("study.nc", "boundary.nc")
#: The provenance of a study, and the largest read [bytes].
PROVENANCE, MAX_PROVENANCE_BYTES = "provenance.json", 16_000_000


def study_folder(path: str) -> tuple[Path, str | None]:
    """A study folder given to --study and the text of its case.toml (None: it has none).

    It must be a readable folder holding study.nc or boundary.nc and the provenance.json of a
    study; every file of it the report reads (those, case.toml and the map) must be a regular
    file that can be read: each is checked here, before any work, and none is waited on (a FIFO).
    """
    import json

    import xarray as xr

    from ..errors import CaseError, shown_path
    from ..model.casefile import MAX_CASE_BYTES, file_type, path_problem, read_file

    label = f"--study {shown_path(path)}"
    study = "give the --out folder of a groundres study"
    folder = Path(path)
    try:
        mode = os.stat(folder).st_mode
    except (OSError, ValueError) as err:
        if isinstance(err, FileNotFoundError) and not os.path.lexists(folder):
            fail_user(f"{label}: not a folder; {study}")
        fail_user(f"{label}: {path_problem(folder, err)}; {study}")
    if not stat.S_ISDIR(mode):
        fail_user(f"{label}: not a folder ({file_type(mode)}); {study}")
    if not os.access(folder, os.R_OK | os.X_OK):
        fail_user(f"{label}: cannot be read (permission denied); {study}")
    present = [folder / name for name in STUDY_DATA if os.path.lexists(folder / name)]
    if not present:
        fail_user(f"{label}: holds neither study.nc nor boundary.nc; {study}")

    def read(name: str, limit: int) -> bytes:
        try:
            return read_file(folder / name, f"{label}: {name}", limit)
        except CaseError as err:
            fail_user(str(err))

    for data in present:
        read(data.name, 0)  # (a regular file that opens; its content is read below)
    if not os.path.lexists(folder / PROVENANCE):
        fail_user(f"{label}: not the --out folder of a groundres study (it has no {PROVENANCE})")
    try:
        record = json.loads(read(PROVENANCE, MAX_PROVENANCE_BYTES).decode("utf-8"))
        ours = record.get("generator") == "groundres" and record.get("command") == "study"
    except (ValueError, AttributeError):
        ours = False
    if not ours:
        fail_user(f"{label}: not the --out folder of a groundres study (its {PROVENANCE} does not say so)")
    try:
        xr.open_dataset(present[0]).close()
    except Exception as err:  # noqa: BLE001 - any unreadable file is the user's to fix
        first = str(err).strip().splitlines()[0] if str(err).strip() else ""
        fail_user(f"{label}: {present[0].name} cannot be read ({type(err).__name__}: {shown(first)})")
    for name in sorted(os.listdir(folder)):
        if name.startswith("map.") and name.rsplit(".", 1)[-1] in ("png", "svg"):
            read(name, 0)  # (the page embeds it)
    if not os.path.lexists(folder / "case.toml"):
        return folder, None
    raw = read("case.toml", MAX_CASE_BYTES)
    if len(raw) > MAX_CASE_BYTES:
        fail_user(f"{label}: case.toml is larger than {MAX_CASE_BYTES} bytes, which no case file needs")
    try:
        return folder, raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        fail_user(f"{label}: case.toml is not UTF-8 text")


@click.command("report")
@click.argument("case", required=False)
@out_option("groundres-out/<case name>-report")
@FORMAT
@click.option(
    "--study",
    "study",
    metavar="FOLDER",
    default=None,
    help="A study's --out folder: its map and what it varied join the report "
    "(with no CASE, the study's own case.toml is reported).",
)
@click.option(
    "--frame",
    type=click.Choice(["nonrotating", "rotating"]),
    default=None,
    help="Frame of the frequencies (overrides the case).",
)
@click.option(
    "--method",
    type=click.Choice(OPTIONS),
    default=None,
    help="Analysis method (overrides the case).",
)
@plot_options(
    "Rotor-speed axis of the Coleman diagram: the case's unit, or divided by its [sweep] reference; "
    "auto normalises where the case has a reference."
)
def command(case, out, fmt, study, frame, method, speed_axis, frequency_limits, real_limits, modes):
    """Analyse CASE and write a self-contained HTML report of it (index.html).

    The page holds the verdict and unstable ranges with the modes that grow,
    the Coleman diagram, derived quantities (lag frequency at the reference
    speed, body frequencies with the rotor's mass, the Deutsch requirement per
    body mode and its tuning speed), the lag damping, the phasors of the worst
    mode at the worst speed, the case text, and the method with its accuracy
    figures; with --study, the study's map. Pictures are embedded (the page
    opens offline and prints cleanly) and also written beside it in --format;
    summary.json holds the sweep's numbers the page shows (the phasor
    table is of the eigenvector at the speed shown; a study's figures are its folder's).
    """
    console = make_console()
    plot = {
        "speed_axis": speed_axis,
        "frequency_limits": parse_limits(frequency_limits, "--frequency-limits"),
        "real_limits": parse_limits(real_limits, "--real-limits"),
    }
    study_dir, study_text = study_folder(study) if study is not None else (None, None)
    if case is None and study_dir is not None:
        if study_text is None:
            fail_user(f"--study {shown_path(study)}: holds no case.toml; name the CASE to report")
        case = str(study_dir / "case.toml")
        name = study_dir.name
    else:
        name = case
        if case is None:
            console.print("No case given: reporting the built-in default case [bold]hammond-undamped[/bold].")
    the_case = load(case)
    check_reference(the_case, speed_axis)
    if study_text is not None and study_text != the_case.text:
        console.print(
            "Note: the study's case.toml is not this case; the report shows the study's map as it is."
        )
    out_dir = output_dir(name, out, "report")
    check_out(out_dir, out)
    warm = warm_plotting()
    from ..analysis import analyze
    from ..results import files, folders

    with Steps(console, {**STAGES, "limit cycles": "Limit cycles", "page": "Writing the report"}) as steps:
        with method_named():
            result = analyze(the_case, frame=frame, method=method, progress=steps.callback)
        plot["modes"] = check_modes(modes, result.labels)
        check_scale(result, speed_axis=speed_axis)
        cycles = None
        if the_case.rotor.nonlinear:  # (a section of their own: the laws as they are)
            from ..analysis import limit_cycles

            cycles = limit_cycles(the_case, linear=False, progress=steps.callback)
        with steps.step("page"), folders.output_folder(out_dir, out_name(out)) as folder:
            warm.join()
            from ..pages.report import report_page

            meta = invocation()
            summary = result.summary()  # (once: on the page and in summary.json)
            html, pictures = report_page(
                result,
                summary=summary,
                fmt=fmt,
                study=study_dir,
                command_line=shlex.join(["groundres", *meta["argv"]]),
                plot=plot,
                cycles=cycles,
            )
            files.write_json(folder / "summary.json", summary)
            for file_name, data in pictures.items():
                files.write_bytes(folder / file_name, data)
            files.write_text(folder / "index.html", html)
            folders.write_provenance(
                folder,
                the_case,
                command="report",
                method=result.method,
                frame=result.frame,
                accuracy=result.accuracy,
                **meta,
            )
    verdict = "stable over the sweep" if result.stability.stable else "unstable"
    console.print(f"{plain(the_case.title)}: {verdict}.")
    console.print(
        f"Wrote {plain(out_dir)}/index.html ({', '.join(pictures)}, summary.json, case.toml, provenance.json)"
    )
