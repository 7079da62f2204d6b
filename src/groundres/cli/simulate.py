"""`groundres simulate`: time history of the periodic equations at one speed."""

from __future__ import annotations

from pathlib import Path

import click

from .common import DEFAULT_CASE, OUT, case_at_speed, fail_user, make_console, plain, status


@click.command("simulate")
@click.argument("case", required=False)
@click.option("--speed", type=float, required=True, help="Rotor speed, in the case's sweep unit.")
@click.option("--time", "duration", type=float, default=None, help="Duration [s] [default: 40 revolutions].")
@click.option(
    "--initial",
    multiple=True,
    metavar="NAME=VALUE",
    help="Initial displacement (m, rad) or rate (NAME_rate), e.g. x=0.01, lag1=0.02; repeatable "
    "[default: x, y, pitch, roll present = 0.01 and lag1 = 0.01].",
)
@OUT
def command(case, speed, duration, initial, out):
    """Integrate the periodic equations of CASE in time at one rotor speed.

    Writes simulation.png (body and blade motion) and simulation.csv, and
    compares the measured growth rate with the largest real part from the
    eigen- or Floquet analysis.
    """
    import numpy as np

    from .. import io
    from .. import simulate as sim_module
    from ..analysis import choose_method, root_solver
    from ..dataset import coordinate_unit
    from ..plotting.timehistory import time_history
    from ..stability import growth_threshold
    from ..system import System

    console = make_console()
    the_case, w = case_at_speed(case, speed)
    duration = duration or 40 * 2 * np.pi / w
    if not duration > 0:
        fail_user(f"--time = {duration!r}: must be > 0 [s]")
    system = System(the_case.rotor, the_case.body)
    values = {}
    for item in initial:
        key, sep, value = item.partition("=")
        try:
            values[key.strip()] = float(value)
        except ValueError:
            fail_user(f"--initial {item!r}: expected NAME=NUMBER, e.g. x=0.01")
        if not sep:
            fail_user(f"--initial {item!r}: expected NAME=NUMBER, e.g. x=0.01")
    if not values:
        values = {d: 0.01 for d in the_case.body.dofs} | {"lag1": 0.01}
    try:
        q0, v0 = sim_module.initial_state(system, values)
    except KeyError as err:
        fail_user(f"--initial {err.args[0]}")
    name = Path(case).stem if case else DEFAULT_CASE
    out_dir = Path(out) if out else Path("groundres-out") / name
    with status(console, f"Simulating {duration:.4g} s at {speed:g} {the_case.sweep.unit}..."):
        sim = sim_module.simulate(system, w, duration, (q0, v0))
        growth = sim.growth_rate()
        method = choose_method(the_case)
        predicted = float(root_solver(the_case, method).roots(w).real.max())
    fig = time_history(sim, title=the_case.title, growth=growth, predicted=predicted)
    io.write_figure(fig, out_dir / "simulation.png")
    header = ["time [s]"] + [
        f"{c.symbol if c.kind == 'body' else f'{c.kind}{c.name}'} [{coordinate_unit(c)}]"
        for c in sim.coordinates
    ]
    io.write_csv(out_dir / "simulation.csv", header, np.column_stack([sim.time, sim.displacement]))
    if abs(predicted) <= growth_threshold(w):  # round-off: the analysis says neutral
        console.print(
            f"Measured growth rate {growth:.6g} 1/s; largest real part ({method}) 0 1/s (neutral: "
            "within the growth threshold of zero)."
        )
    else:
        console.print(
            f"Measured growth rate {growth:.6g} 1/s; largest real part ({method}) {predicted:.6g} 1/s"
            f" ({100 * (growth - predicted) / abs(predicted):+.3f} %)."
        )
    console.print(f"Wrote {plain(out_dir)}/simulation.png, simulation.csv")
