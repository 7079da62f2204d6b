"""`groundres simulate`: time history of the periodic equations at one speed."""

from __future__ import annotations

import click

from ..errors import shown
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
    help="Initial displacement (m, rad) or rate (NAME_rate), e.g. x=0.01, lag1=0.02; repeatable; "
    "|VALUE| <= 1e150 (the equations are linear: the size only scales the motion) "
    "[default: every body dof present = 0.01 and lag1 = 0.01].",
)
@click.option(
    "--along",
    type=float,
    default=None,
    metavar="FACTOR",
    help="Nonlinear lag dampers: start at FACTOR times the predicted limit cycle at this speed (the "
    "threshold of least amplitude, else the stable cycle) [default: [simulation] along_cycle].",
)
@click.option(
    "--window",
    type=float,
    default=None,
    help="Nonlinear lag dampers: the measuring window at the end of the run [s] [default: [simulation] "
    "window, or a fifth of the run].",
)
@click.option(
    "--threshold",
    is_flag=True,
    help="Nonlinear lag dampers: bracket the predicted threshold at this speed by runs started along it, "
    "bisected --steps times between one that stays below it and one that heads beyond it.",
)
@click.option("--steps", type=int, default=None, help="Bisections of --threshold [default: 4].")
@out_option("groundres-out/<case name>-simulate")
@FORMAT
def command(case, speed, duration, initial, along, window, threshold, steps, out, fmt):
    """Integrate the periodic equations of CASE in time at one rotor speed.

    Writes simulation.<format> (body and blade motion; png unless --format
    says) and simulation.csv (with case.toml and provenance.json), and
    compares the measured growth rate with the largest real part from the
    eigen- or Floquet analysis.

    With nonlinear lag dampers ([rotor.lag_damper]) the equations carry the laws themselves:
    the run starts from --initial, or --along a predicted limit cycle, and nonlinear.json says
    how it ends (each blade's settled lag in the rotating frame, the hub's in the nonrotating
    frame) beside the predicted cycles; --threshold brackets a predicted threshold instead.
    """
    from ..analysis import simulate
    from ..assess.stability import is_neutral
    from ..errors import ParameterError
    from ..results import files, folders

    console = make_console()
    values = _initial_values(initial)
    the_case, w = case_at_speed(case, speed)
    out_dir = output_dir(case, out, "simulate")
    if the_case.rotor.nonlinear:
        from .nonlinear_run import run

        return run(
            console, the_case, w, speed, duration, values, along, window, threshold, steps, out, out_dir, fmt
        )
    if along is not None or window is not None or threshold or steps is not None:
        fail_user(
            "--along, --window, --threshold and --steps need nonlinear lag dampers ([rotor.lag_damper])"
        )
    check_out(out_dir, out)
    unit = the_case.sweep.unit
    labels = {"integrate": f"Simulating at {speed:g} {unit} [s simulated]", "write": "Writing results"}
    given = {
        "speed": f"{shown(speed)} {unit}",
        "duration": repr(duration) if duration is not None else "(the default)",
    }
    with Steps(console, labels) as steps:
        report = steps.callback and (lambda done, total: steps("integrate", done, total))
        try:
            sim = simulate(the_case, w, duration=duration, initial=values or None, progress=report)
        except ParameterError as err:  # (named as the command line's options)
            key, _, name = err.key.partition(".")
            if key == "initial":  # (as given: --initial x=1e+308)
                given_as = f"{name}={err.value!r}" if name else _initial_text(err.value)
                fail_user(f"--initial {given_as}{'' if initial else ' (the default)'}: {err.allowed}")
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


def _initial_text(value) -> str:
    """The --initial values an error names, NAME=VALUE as given."""
    return " ".join(f"{shown(k)[1:-1] if isinstance(k, str) else shown(k)}={v!r}" for k, v in value.items())


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
            fail_user(f"--initial {shown(item)}: expected NAME=NUMBER, e.g. x=0.01")
        if not math.isfinite(number):
            fail_user(f"--initial {shown(item)}: the value must be a finite number")
        values[key.strip()] = number
    if values and not any(values.values()):
        fail_user(f"--initial {shown(' '.join(items))}: every value is zero, so nothing would move")
    return values
