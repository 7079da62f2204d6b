"""`groundres run`: analyse a case over its sweep and write its results."""

from __future__ import annotations

import threading
from pathlib import Path

import click

from .common import (
    DEFAULT_CASE,
    OUT,
    Steps,
    check_out,
    invocation,
    load,
    make_console,
    output_dir,
)

#: What the progress display calls the analysis stages.
STAGES = {
    "sweep": "Sweep over the rotor speeds",
    "range ends": "Ends of the unstable ranges",
    "lag damping": "Minimum lag damping",
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
    type=click.Choice(["auto", "eigen", "floquet"]),
    default=None,
    help="Analysis method (overrides the case).",
)
@click.option("--damping-ratio", is_flag=True, help="Plot damping ratio instead of real part.")
def command(case, out, frame, method, damping_ratio):
    """Analyse CASE (a TOML file or a shipped case name) over its speed sweep.

    Writes summary.json, modes.csv, modes.nc, coleman.png, case.toml and
    provenance.json into --out, replacing the folder whole. With no CASE, runs
    the built-in default, the shipped case 'hammond-undamped'.
    """
    console = make_console()
    if case is None:
        console.print(f"No case given: running the built-in default case [bold]{DEFAULT_CASE}[/bold].")
    the_case = load(case)
    out_dir = output_dir(case, out)
    check_out(out_dir)
    warm = warm_plotting()
    from .. import folders
    from ..analysis import analyze
    from .printout import print_result

    with Steps(console, STAGES) as steps:
        result = analyze(the_case, frame=frame, method=method, progress=steps.callback)
        with steps.step("write"), folders.output_folder(out_dir) as folder:
            _write_all(result, folder, damping_ratio, warm)
            folders.write_provenance(
                folder,
                the_case,
                command="run",
                method=result.method,
                frame=result.frame,
                accuracy=result.accuracy,
                **invocation(),
            )
    print_result(console, result, out_dir)


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


def _write_all(result, out_dir: Path, damping_ratio: bool, warm: threading.Thread | None = None):
    """Write the four result files into ``out_dir`` (the picture last: its imports finish meanwhile)."""
    from .. import io

    io.write_summary(result, out_dir / "summary.json")
    io.write_modes_csv(result, out_dir / "modes.csv")
    io.write_modes_netcdf(result, out_dir / "modes.nc")
    if warm is not None:
        warm.join()
    io.write_figure(result.plot(show_damping_ratio=damping_ratio), out_dir / "coleman.png")
