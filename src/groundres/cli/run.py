"""`groundres run`: analyse a case over its sweep and write its results."""

from __future__ import annotations

import threading
from pathlib import Path

import click

from ..methods import OPTIONS
from .common import (
    DEFAULT_CASE,
    FORMAT,
    OUT,
    Steps,
    check_out,
    invocation,
    load,
    make_console,
    method_named,
    out_name,
    output_dir,
)
from .plotoptions import check_modes, check_reference, check_scale, parse_limits, plot_options

#: What the progress display calls the analysis stages.
STAGES = {
    "sweep": "Sweep over the rotor speeds",
    "range ends": "Ends of the unstable ranges",
    "lag damping": "Minimum lag damping",
    "margins": "Margins of each mode",
    "write": "Writing results",
}


@click.command("run")
@click.argument("case", required=False)
@OUT
@click.option(
    "--frame",
    type=click.Choice(["nonrotating", "rotating"]),
    default=None,
    help="Frame of the reported frequencies (overrides the case).",
)
@click.option(
    "--method",
    type=click.Choice(OPTIONS),
    default=None,
    help="Analysis method (overrides the case).",
)
@click.option("--damping-ratio", is_flag=True, help="Plot damping ratio instead of real part.")
@plot_options(
    "Rotor-speed axis: the case's unit, or divided by its [sweep] reference; auto normalises "
    "where the case has a reference."
)
@FORMAT
def command(case, out, frame, method, damping_ratio, speed_axis, frequency_limits, real_limits, modes, fmt):
    """Analyse CASE (a TOML file or a shipped case name) over its speed sweep.

    Writes summary.json, modes.csv, modes.nc, coleman.<format> (the Coleman
    diagram; png unless --format says), case.toml and provenance.json into
    --out, replacing the folder whole. With no CASE, runs the built-in
    default, the shipped case 'hammond-undamped'.
    """
    console = make_console()
    plot = {
        "show_damping_ratio": damping_ratio,
        "speed_axis": speed_axis,
        "frequency_limits": parse_limits(frequency_limits, "--frequency-limits"),
        "real_limits": parse_limits(real_limits, "--real-limits"),
    }
    if case is None:
        console.print(f"No case given: running the built-in default case [bold]{DEFAULT_CASE}[/bold].")
    the_case = load(case)
    check_reference(the_case, speed_axis)
    out_dir = output_dir(case, out)
    check_out(out_dir, out)
    warm = warm_plotting()
    from ..analysis import analyze
    from ..results import folders
    from .printout import print_result

    with Steps(console, STAGES) as steps:
        with method_named():
            result = analyze(the_case, frame=frame, method=method, progress=steps.callback)
        plot["modes"] = check_modes(modes, result.labels)
        check_scale(result, speed_axis=speed_axis)
        with steps.step("write"), folders.output_folder(out_dir, out_name(out)) as folder:
            summary = result.summary()  # (once: written, and printed below)
            _write_all(result, summary, folder, plot, warm, fmt)
            folders.write_provenance(
                folder,
                the_case,
                command="run",
                method=result.method,
                frame=result.frame,
                accuracy=result.accuracy,
                **invocation(),
            )
    print_result(console, result, summary, out_dir, fmt)


def _import_plotting() -> None:
    """Import the plotting stack (in a background thread while the analysis runs).

    A failure is left to the main thread, which imports the same modules again
    when it plots and reports the error there.
    """
    try:
        import matplotlib.backends.backend_agg  # noqa: F401  (figures are saved through Agg)
        import matplotlib.figure  # noqa: F401

        from ..plotting import coleman  # noqa: F401
    except Exception:  # noqa: BLE001, S110 - reported by the main thread's own import
        pass


def warm_plotting() -> threading.Thread:
    """Start importing matplotlib in a daemon thread (it cannot outlive the process).

    Join it before plotting: importing the same modules from two threads at
    once is safe, but joining keeps the order of imports simple.
    """
    thread = threading.Thread(target=_import_plotting, name="groundres-import-plotting", daemon=True)
    thread.start()
    return thread


def _write_all(
    result, summary: dict, out_dir: Path, plot: dict, warm: threading.Thread | None = None, fmt: str = "png"
) -> None:
    """Write the four result files into ``out_dir`` (the picture last: its imports finish meanwhile).

    ``summary``: the result's :meth:`~groundres.results.sweep.SweepResult.summary`, computed once.
    ``plot``: keyword arguments of :meth:`~groundres.results.sweep.SweepResult.plot`; ``fmt``: the
    picture's format (png, svg or pdf).
    """
    from ..results import files

    files.write_json(out_dir / "summary.json", summary)
    files.write_modes_csv(result, out_dir / "modes.csv")
    files.write_netcdf(result, out_dir / "modes.nc")
    if warm is not None:
        warm.join()
    files.write_figure(result.plot(**plot), out_dir / f"coleman.{fmt}")
