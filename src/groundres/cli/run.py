"""`groundres run`: analyse a case over its sweep and write its results."""

from __future__ import annotations

import sys
from pathlib import Path

import click

from .common import DEFAULT_CASE, OUT, load, make_console, output_dir, status


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

    Writes summary.json, modes.csv, modes.nc and coleman.png into --out. With
    no CASE, runs the built-in default, the shipped case 'hammond-undamped'.
    """
    console = make_console()
    if case is None:
        console.print(f"No case given: running the built-in default case [bold]{DEFAULT_CASE}[/bold].")
    the_case = load(case)
    out_dir = output_dir(case, out)
    pool = _picture_process()
    try:
        from ..analysis import analyze

        with status(console, f"Analysing {the_case.title}..."):
            result = analyze(the_case, frame=frame, method=method)
        with status(console, "Writing results..."):
            _write_all(result, out_dir, damping_ratio, pool)
    finally:
        pool.shutdown(cancel_futures=True)
    _print_result(console, result, out_dir)


def _warm_plotting() -> None:
    """Import the plotting stack (runs in the picture process while the analysis runs)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.backends.backend_agg  # noqa: F401
    import matplotlib.figure  # noqa: F401

    from ..plotting import coleman  # noqa: F401


def _render_coleman(result, path: Path, damping_ratio: bool) -> None:
    from .. import io

    io.write_figure(result.plot(show_damping_ratio=damping_ratio), path)


def _picture_process():
    """A one-worker pool that starts importing matplotlib at once."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    context = multiprocessing.get_context("fork") if sys.platform.startswith("linux") else None
    pool = ProcessPoolExecutor(max_workers=1, mp_context=context)
    pool.submit(_warm_plotting)
    return pool


def _write_all(result, out_dir: Path, damping_ratio: bool, pool=None):
    """Write the four outputs; the picture renders in the picture process meanwhile."""
    from .. import io

    picture = pool.submit(_render_coleman, result, out_dir / "coleman.png", damping_ratio) if pool else None
    io.write_summary(result, out_dir / "summary.json")
    io.write_modes_csv(result, out_dir / "modes.csv")
    io.write_modes_netcdf(result, out_dir / "modes.nc")
    if picture is None:
        _render_coleman(result, out_dir / "coleman.png", damping_ratio)
    else:
        picture.result()


def _print_result(console, result, out_dir):
    from .report import print_result

    print_result(console, result, out_dir)
