"""`groundres simulate`: time history of the periodic equations at one speed."""

from __future__ import annotations

import click

from .common import (
    FORMAT,
    Steps,
    case_at_speed,
    check_out,
    fail_user,
    invocation,
    make_console,
    out_name,
    out_option,
    output_dir,
    plain,
)


@click.command("simulate")
@click.argument("case", required=False)
@click.option("--speed", type=float, required=True, help="Rotor speed, in the case's sweep unit.")
@click.option(
    "--time",
    "duration",
    type=float,
    default=None,
    help="Duration [s] [default: 40 revolutions, or longer (up to 400) until the least stable root "
    "outgrows the next one by e^8].",
)
@click.option(
    "--initial",
    multiple=True,
    metavar="NAME=VALUE",
    help="Initial displacement (m, rad) or rate (NAME_rate), e.g. x=0.01, lag1=0.02; repeatable "
    "[default: every body dof present = 0.01 and lag1 = 0.01].",
)
@out_option("groundres-out/<case name>-simulate")
@FORMAT
def command(case, speed, duration, initial, out, fmt):
    """Integrate the periodic equations of CASE in time at one rotor speed.

    Writes simulation.<format> (body and blade motion; png unless --format
    says) and simulation.csv (with case.toml and provenance.json), and
    compares the measured growth rate with the largest real part from the
    eigen- or Floquet analysis.
    """
    from ..analysis import simulate
    from ..assess.stability import is_neutral
    from ..errors import ParameterError, shown
    from ..results import files, folders

    console = make_console()
    values = _initial_values(initial)
    the_case, w = case_at_speed(case, speed)
    out_dir = output_dir(case, out, "simulate")
    check_out(out_dir, out)
    unit = the_case.sweep.unit
    labels = {"integrate": f"Simulating at {speed:g} {unit} [s simulated]", "write": "Writing results"}
    given = {
        "speed": f"{speed!r} {unit}",
        "duration": repr(duration) if duration is not None else "(the default)",
    }
    with Steps(console, labels) as steps:
        report = steps.callback and (lambda done, total: steps("integrate", done, total))
        try:
            sim = simulate(the_case, w, duration=duration, initial=values or None, progress=report)
        except ParameterError as err:  # (named as the command line's options)
            option = OPTIONS.get(err.key, err.key)
            fail_user(f"{option} = {given.get(err.key) or shown(err.value)}: {err.allowed}")
        steps("integrate", sim.time[-1], sim.time[-1])
        growth = sim.growth_rate()
        with steps.step("write"), folders.output_folder(out_dir, out_name(out)) as folder:
            files.write_figure(sim.plot(), folder / f"simulation.{fmt}")
            files.write_simulation_csv(sim, folder / "simulation.csv")
            folders.write_provenance(
                folder,
                the_case,
                command="simulate",
                method="time-integration",
                prediction_method=sim.method.value,
                frame="blade coordinates, body axes nonrotating",
                accuracy={
                    "integrator": "DOP853 (scipy.integrate.solve_ivp), dense output",
                    "rtol": sim.history.rtol,
                    "atol": sim.history.atol,
                    "output_points": len(sim.time),
                    "growth_rate": "slope of the log state norm, sampled once per revolution, "
                    "over the second half of the run",
                },
                rotor_speed={"value": w, "unit": "rad/s"},
                duration={"value": float(sim.time[-1]), "unit": "s"},
                initial=dict(values),
                **invocation(),
            )
    predicted, method = sim.predicted_growth, sim.method
    if is_neutral(predicted, w):  # round-off: the analysis says neutral
        console.print(
            f"Measured growth rate {growth:.6g} 1/s; largest real part ({method}) 0 1/s (neutral: "
            "within the growth threshold of zero)."
        )
    else:
        console.print(
            f"Measured growth rate {growth:.6g} 1/s; largest real part ({method}) {predicted:.6g} 1/s"
            f" ({100 * (growth - predicted) / abs(predicted):+.3f} %)."
        )
    console.print(f"Wrote {plain(out_dir)}/simulation.{fmt}, simulation.csv, case.toml, provenance.json")


#: The options that give simulate()'s arguments.
OPTIONS = {"speed": "--speed", "duration": "--time", "initial": "--initial"}


def _initial_values(items) -> dict:
    """--initial NAME=VALUE options as a dict; names are checked against the model later."""
    import math

    values = {}
    for item in items:
        key, sep, value = item.partition("=")
        try:
            number = float(value)
        except ValueError:
            number = None
        if not sep or not key.strip() or number is None:
            fail_user(f"--initial {item!r}: expected NAME=NUMBER, e.g. x=0.01")
        if not math.isfinite(number):
            fail_user(f"--initial {item!r}: the value must be a finite number")
        values[key.strip()] = number
    if values and not any(values.values()):
        fail_user(f"--initial {' '.join(items)!r}: every value is zero, so nothing would move")
    return values
