"""`groundres cycles`: limit cycles of a rotor with nonlinear lag dampers."""

from __future__ import annotations

import click

from .common import (
    FORMAT,
    Steps,
    check_out,
    invocation,
    load,
    make_console,
    out_name,
    out_option,
    output_dir,
    plain,
)
from .run import STAGES as RUN_STAGES

STAGES = {
    "limit cycles": "Limit cycles (describing functions)",
    "confirm": "Confirming cycles by simulation [cycles]",
    **RUN_STAGES,
}
#: Speeds the terminal's table shows at most.
ROWS = 12


@click.command("cycles")
@click.argument("case", required=False)
@out_option("groundres-out/<case name>-cycles")
@FORMAT
def command(case, out, fmt):
    """Limit cycles of CASE, whose lag dampers follow nonlinear laws ([rotor.lag_damper]).

    At each speed ([limit_cycle] points over the sweep), the blade lag amplitudes at which the
    equivalent linear system (each law's describing function) has a neutral root: stable cycles,
    on which the motion settles, and unstable ones, thresholds above which a disturbance grows.
    Writes limit_cycles.<format> (the limit-cycle diagram beside the Coleman diagram of the
    linear analysis; png unless --format says), limit_cycles.json, limit_cycles.nc (the scan and
    the cycles with their branches), case.toml and provenance.json.
    """
    from ..analysis import limit_cycles
    from ..results import files, folders

    console = make_console()
    the_case = load(case)
    out_dir = output_dir(case, out, "cycles")
    check_out(out_dir, out)
    with Steps(console, STAGES) as steps:
        found = limit_cycles(the_case, progress=steps.callback)
        with folders.output_folder(out_dir, out_name(out)) as folder:
            with steps.step("write"):
                files.write_figure(found.plot(), folder / f"limit_cycles.{fmt}")
            files.write_json(folder / "limit_cycles.json", found.to_dict())
            files.write_netcdf(found, folder / "limit_cycles.nc")
            folders.write_provenance(folder, the_case, command="cycles", **invocation())
    _print(console, found)
    console.print(f"Wrote {plain(str(out_dir))}/ (limit_cycles.{fmt}, limit_cycles.json, limit_cycles.nc)")


def _print(console, found) -> None:
    """The verdict at a few speeds, the smallest threshold and the largest stable cycle in words."""
    import numpy as np

    from ..model.units import fmt_speed

    p, sweep = found.prediction, found.case.sweep
    console.print(f"[bold]{plain(found.case.title)}[/bold]: limit cycles (describing functions)")
    shown = np.unique(np.linspace(0, len(p.speeds) - 1, min(ROWS, len(p.speeds))).round().astype(int))
    for i in shown:
        console.print(f"  {plain(fmt_speed(p.speeds[i], sweep))}: {p.verdict(int(i))}")
    if len(shown) < len(p.speeds):
        console.print(
            f"  ({len(shown)} of the {len(p.speeds)} speeds; limit_cycles.json gives every one's verdict)"
        )
    worst, largest = found.smallest_threshold(), found.largest_stable()
    unbounded = found.unbounded_words()
    if unbounded is not None:
        console.print(plain(f"Grows from any disturbance: {unbounded}."))
    below, settles = found.below_words(), found.stable_below_words()
    if below is not None:
        console.print(plain(f"Threshold below the amplitudes searched: {below}."))
    if settles is not None:
        console.print(plain(f"Stable cycle below the amplitudes searched: {settles}."))
    if worst is not None:
        elsewhere = " (of those found)" if below else " (where there is one)" if unbounded else ""
        console.print(plain(f"Smallest threshold{elsewhere}: {found.threshold_words(worst)}."))
    if largest is not None:
        console.print(plain(f"Largest stable cycle: {found.stable_words(largest)}."))
    if all(x is None for x in (worst, largest, unbounded, below, settles)):
        console.print("No limit cycle within the amplitudes searched.")
    for entry in found.confirmations:
        console.print(plain(f"Simulation: {found.confirmation_words(entry)}."))
    loose = found.regularised()
    if loose:
        console.print(
            plain(
                f"Note: at {len(loose)} of the cycles the friction link's regularisation is above 0.05 "
                "(c_reg A w / F): its slider slips that far above the ideal one the prediction assumes "
                "(limit_cycles.json, link_regularisation)."
            )
        )
    poor = [c for c in p.cycles if c.poor]
    if poor:
        console.print(
            plain(
                f"Note: at {len(poor)} of the cycles the single-harmonic approximation is poor (a second "
                "frequency component above 0.2 of the first; limit_cycles.json, poor_approximation)."
            )
        )
