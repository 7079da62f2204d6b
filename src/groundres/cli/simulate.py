"""`groundres simulate`: time history of the periodic equations at one speed."""

from __future__ import annotations

import click

from ..model.units import fmt_speed
from .common import (
    FORMAT,
    Steps,
    case_at_speed,
    check_out,
    fail_user,
    invocation,
    make_console,
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
    import math

    import numpy as np

    from ..assess.stability import is_neutral
    from ..methods import choose_method
    from ..model.system import System
    from ..plotting.timehistory import time_history
    from ..results import files, folders
    from ..results.dataset import coordinate_unit
    from ..solve import simulate as sim_module
    from ..solve.solvers import solver_for

    console = make_console()
    if duration is not None and not (math.isfinite(duration) and duration > 0):
        fail_user(f"--time = {duration!r}: must be a finite number > 0 [s]")
    values = _initial_values(initial)
    the_case, w = case_at_speed(case, speed)
    system = System(the_case.rotor, the_case.body)
    try:
        q0, v0 = sim_module.initial_state(system, values or _default_initial(the_case))
    except KeyError as err:
        fail_user(f"--initial {err.args[0]}")
    given = duration
    duration = _checked_duration(system, the_case.sweep.unit, speed, w, given)
    method = choose_method(the_case)
    roots = np.asarray(solver_for(the_case, method).roots(w)).ravel()
    predicted = float(roots.real.max())
    if given is None:  # (longer where the least stable root stands out slowly)
        duration = _checked_duration(system, the_case.sweep.unit, speed, w, None, _settling(roots))
    out_dir = output_dir(case, out, "simulate")
    check_out(out_dir)
    labels = {
        "integrate": f"Simulating {duration:.4g} s at {speed:g} {the_case.sweep.unit} [s simulated]",
        "write": "Writing results",
    }
    with Steps(console, labels) as steps:
        report = steps.callback and (lambda done, total: steps("integrate", done, total))
        sim = sim_module.simulate(
            system, w, duration, (q0, v0), progress=report, speed_text=f"{speed:g} {the_case.sweep.unit}"
        )
        steps("integrate", duration, duration)
        growth = sim.growth_rate()
        with steps.step("write"), folders.output_folder(out_dir) as folder:
            fig = time_history(
                sim,
                title=the_case.title,
                growth=growth,
                predicted=predicted,
                speed_text=fmt_speed(w, the_case.sweep),
            )
            files.write_figure(fig, folder / f"simulation.{fmt}")
            header = ["time [s]"] + [
                f"{c.symbol if c.kind == 'body' else f'{c.kind}{c.name}'} [{coordinate_unit(c)}]"
                for c in sim.coordinates
            ]
            files.write_csv(folder / "simulation.csv", header, np.column_stack([sim.time, sim.displacement]))
            folders.write_provenance(
                folder,
                the_case,
                command="simulate",
                method="time-integration",
                prediction_method=method.value,
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


def _default_initial(case) -> dict:
    return {d: 0.01 for d in case.body.dofs} | {"lag1": 0.01}


#: Default duration: at least this many revolutions, at most MOST_REVOLUTIONS.
LEAST_REVOLUTIONS, MOST_REVOLUTIONS = 40, 400
#: e-folds by which the least stable root outgrows the next over the second half of a default run.
SETTLE = 8.0


def _settling(roots) -> float:
    """Time [s] over which the least stable root outgrows the next distinct one by e^SETTLE
    (the growth rate is measured over the run's second half: twice that); inf if they tie."""
    import numpy as np

    real = np.sort(np.asarray(roots).real)[::-1]
    scale = max(np.abs(real).max(), 1e-300)
    below = real[real < real[0] - 1e-9 * scale]
    return 2 * SETTLE / (real[0] - below[0]) if len(below) else float("inf")


def _checked_duration(system, unit: str, speed: float, w: float, duration: float | None, settle=0.0) -> float:
    """--time (None: LEAST_REVOLUTIONS, or up to MOST_REVOLUTIONS where the least stable root takes
    ``settle`` [s] to stand out, :func:`_settling`) once it is long enough to measure growth and
    short enough to run.

    The integration steps are estimated before integrating (:func:`groundres.solve.simulate.estimate_steps`)
    and a run over :data:`groundres.solve.simulate.MAX_STEPS` is refused, saying what to change.
    """
    import math

    from ..solve import simulate as sim_module

    revolution = 2 * math.pi / w
    at_speed = f"at {speed:g} {unit}"
    if not math.isfinite(40 * revolution):
        fail_user(f"--speed = {speed!r}: too slow to simulate (a revolution would last {revolution:.3g} s)")
    shortest = sim_module.MIN_REVOLUTIONS * revolution
    if duration is not None and duration < shortest:
        fail_user(
            f"--time = {duration!r}: must be at least {sim_module.MIN_REVOLUTIONS} revolutions "
            f"({shortest:.4g} s {at_speed}), over whose second half the growth rate is measured"
        )
    default = duration is None
    if default:
        duration = min(max(LEAST_REVOLUTIONS * revolution, settle), MOST_REVOLUTIONS * revolution)
    rate = sim_module.fastest_rate(system, w)
    if not math.isfinite(rate):
        fail_user(
            f"--speed = {speed!r} {unit}: too fast to simulate: the equations' coefficients, which "
            f"grow as the speed squared, exceed {sim_module.LARGEST_COEFFICIENT:.0e} (the integration "
            "squares them)"
        )
    per_second = rate / (2 * math.pi) * sim_module.STEPS_PER_PERIOD
    steps = sim_module.estimate_steps(system, w, duration)
    if default and steps > sim_module.MAX_STEPS and duration > LEAST_REVOLUTIONS * revolution:
        # (a longer default than 40 revolutions only as far as the step limit allows)
        duration = max(LEAST_REVOLUTIONS * revolution, duration * sim_module.MAX_STEPS / steps)
        steps = sim_module.estimate_steps(system, w, duration)
    if steps > sim_module.MAX_STEPS:
        longest = sim_module.MAX_STEPS / per_second
        if longest >= shortest:
            advice = f"choose --time of at most {longest:.4g} s"
        else:
            advice = (
                f"no --time fits {at_speed}: even the shortest run that measures a growth rate "
                f"({sim_module.MIN_REVOLUTIONS} revolutions, {shortest:.4g} s) is too long; "
                "choose a higher --speed"
            )
        fail_user(
            f"--time = {duration:.4g} s"
            f"{f' (the default, {duration / revolution:.0f} revolutions)' if default else ''} {at_speed}: "
            f"the simulation would take about {steps:.2g} integration steps (fastest motion "
            f"{rate:.4g} rad/s, about {sim_module.STEPS_PER_PERIOD} steps a period), over the limit "
            f"of {sim_module.MAX_STEPS}; {advice}"
        )
    return duration


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
