"""`groundres simulate`: time history of the periodic equations at one speed."""

from __future__ import annotations

import click

from .common import (
    Steps,
    case_at_speed,
    check_out,
    fail_user,
    fmt_speed,
    invocation,
    make_console,
    out_option,
    output_dir,
    plain,
)


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
@out_option("groundres-out/<case name>-simulate")
def command(case, speed, duration, initial, out):
    """Integrate the periodic equations of CASE in time at one rotor speed.

    Writes simulation.png (body and blade motion) and simulation.csv (with
    case.toml and provenance.json), and compares the measured growth rate
    with the largest real part from the eigen- or Floquet analysis.
    """
    import numpy as np

    from .. import io
    from .. import simulate as sim_module
    from ..analysis import METHOD_NAMES, choose_method, root_solver
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
    out_dir = output_dir(case, out, "simulate")
    check_out(out_dir)
    labels = {
        "integrate": f"Simulating {duration:.4g} s at {speed:g} {the_case.sweep.unit} [s simulated]",
        "roots": "Largest real part at that speed",
        "write": "Writing results",
    }
    with Steps(console, labels) as steps:
        report = steps.callback and (lambda done, total: steps("integrate", done, total))
        sim = sim_module.simulate(system, w, duration, (q0, v0), progress=report)
        steps("integrate", duration, duration)
        growth = sim.growth_rate()
        method = choose_method(the_case)
        with steps.step("roots"):
            predicted = float(root_solver(the_case, method).roots(w).real.max())
        with steps.step("write"), io.output_folder(out_dir) as folder:
            fig = time_history(
                sim,
                title=the_case.title,
                growth=growth,
                predicted=predicted,
                speed_text=fmt_speed(w, the_case.sweep),
            )
            io.write_figure(fig, folder / "simulation.png")
            header = ["time [s]"] + [
                f"{c.symbol if c.kind == 'body' else f'{c.kind}{c.name}'} [{coordinate_unit(c)}]"
                for c in sim.coordinates
            ]
            io.write_csv(folder / "simulation.csv", header, np.column_stack([sim.time, sim.displacement]))
            io.write_provenance(
                folder,
                the_case,
                command="simulate",
                method="time-integration",
                prediction_method=METHOD_NAMES[method],
                frame="blade coordinates, body axes nonrotating",
                accuracy={
                    "integrator": "DOP853 (scipy.integrate.solve_ivp), dense output",
                    "rtol": sim.rtol,
                    "atol": sim.atol,
                    "output_points": len(sim.time),
                    "growth_rate": "slope of the log state norm, sampled once per revolution, "
                    "over the second half of the run",
                },
                rotor_speed={"value": w, "unit": "rad/s"},
                duration={"value": float(sim.time[-1]), "unit": "s"},
                initial=dict(values),
                **invocation(),
            )
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
    console.print(f"Wrote {plain(out_dir)}/simulation.png, simulation.csv, case.toml, provenance.json")
