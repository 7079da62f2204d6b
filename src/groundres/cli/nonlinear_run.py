"""`groundres simulate` on a case with nonlinear lag dampers: a run of the equations with the laws,
or the threshold search."""

from __future__ import annotations

import math

from ..errors import shown
from .common import Steps, check_out, fail_user, invocation, out_name, plain

#: The options that give the nonlinear runs' arguments.
OPTIONS = {
    "speed": "--speed",
    "duration": "--time",
    "along_cycle": "--along",
    "window": "--window",
    "steps": "--steps",
}


def run(console, the_case, w, speed, duration, values, along, window, threshold, steps, out, out_dir, fmt):
    """The nonlinear path of ``groundres simulate`` (its options as given; ``w`` [rad/s]; ``out_dir``
    the folder ``out`` names)."""
    from ..errors import ParameterError
    from ..model.units import fmt_speed
    from ..nonlinear_runs import run_nonlinear, search_threshold
    from ..results import files, folders

    check_out(out_dir, out)
    unit = the_case.sweep.unit
    if steps is not None and not threshold:
        fail_user(
            f"--steps {steps}: counts the bisections of --threshold; give --threshold, or leave --steps out"
        )
    steps = 4 if steps is None else steps
    given = {"speed": f"{shown(speed)} {unit}", "duration": repr(duration), "steps": repr(steps)}
    if threshold and (along is not None or values or window is not None):
        fail_user(
            "--threshold starts its own runs along the predicted threshold: leave out --along, --initial "
            "and --window"
        )
    labels = {
        "integrate": f"Simulating at {speed:g} {unit} with the damper laws [s simulated]",
        "threshold": f"Bracketing the threshold at {speed:g} {unit} [runs]",
        "write": "Writing results",
    }
    with Steps(console, labels) as steps_bar:
        try:
            if threshold:
                report = steps_bar.callback and (lambda d, t: steps_bar("threshold", d, t))
                cycle, bracket = search_threshold(
                    the_case, w, steps=steps, duration=duration, progress=report
                )
            else:
                report = steps_bar.callback and (lambda d, t: steps_bar("integrate", d, t))
                found = run_nonlinear(
                    the_case,
                    w,
                    duration=duration,
                    window=window,
                    initial=values or None,
                    along_cycle=along,
                    progress=report,
                )
        except ParameterError as err:  # (named where the value came from: an option, or the case file)
            on_line = {
                "duration": duration is not None,
                "window": window is not None,
                "along_cycle": along is not None,
                "initial": bool(values),
            }
            key, _, name = err.key.partition(".")
            if key == "window" and duration is not None:  # (the run's length is the option's)
                err.allowed = err.allowed.replace("the duration given", f"--time = {duration!r}")
            if key in on_line and not on_line[key]:
                table = "[simulation.initial]" if key == "initial" else "[simulation]"
                fail_user(f"{table} {name or key} = {shown(err.value)}: {err.allowed}")
            if key == "initial":  # (as given: --initial x=3)
                fail_user(
                    f"--initial {name}={err.value!r}: {err.allowed}" if name else f"--initial: {err.allowed}"
                )
            option = OPTIONS.get(err.key, err.key)
            fail_user(f"{option} = {given.get(err.key) or shown(err.value)}: {err.allowed}")
        with steps_bar.step("write"), folders.output_folder(out_dir, out_name(out)) as folder:
            if threshold:
                record = _threshold_record(cycle, bracket)
                files.write_json(folder / "threshold.json", record)
            else:
                files.write_figure(found.plot(), folder / f"simulation.{fmt}")
                files.write_simulation_csv(found, folder / "simulation.csv")
                files.write_json(folder / "nonlinear.json", found.to_dict())
            folders.write_provenance(
                folder,
                the_case,
                command="simulate",
                method="time-integration with the lag damper laws",
                rotor_speed={"value": w, "unit": "rad/s"},
                **invocation(),
            )
    where = fmt_speed(w, the_case.sweep)
    if threshold:
        below, beyond = bracket
        predicted = math.degrees(cycle.amplitude)
        if below is None or beyond is None:
            started, missed = ("below", "stay below it") if below is None else ("above", "head beyond it")
            console.print(
                plain(
                    f"At {where} the predicted threshold of {predicted:.3g} deg is not bracketed: the run "
                    f"started {started} it does not {missed} (the prediction is off by more than the "
                    "bracket, 0.8 to 1.25 times it)."
                )
            )
        else:
            console.print(
                plain(
                    f"At {where} the simulated threshold lies between {below:.4g} and {beyond:.4g} times the "
                    f"predicted {predicted:.3g} deg: {below * predicted:.3g} to {beyond * predicted:.3g} deg "
                    f"(blade {record['blade']})."
                )
            )
        console.print(f"Wrote {plain(out_dir)}/threshold.json, case.toml, provenance.json")
        return
    from ..results.nonlinear_run import hub_text

    words = found.words()
    hub = f"; hub {hub_text(found.measured)}" if found.resolved and found.history.stopped is None else ""
    console.print(plain(f"{words[0].upper()}{words[1:]}{hub}."))
    for c in found.predicted:
        kind = "stable cycle" if c.stable else "threshold"
        console.print(plain(f"  predicted {kind}: {math.degrees(c.amplitude):.3g} deg"))
    h = found.history
    console.print(f"Integrator {h.method}: {h.evaluations} evaluations of the equations.")
    console.print(
        f"Wrote {plain(out_dir)}/simulation.{fmt}, simulation.csv, nonlinear.json, case.toml, provenance.json"
    )


def _threshold_record(cycle, bracket) -> dict:
    """threshold.json: the predicted threshold and the factors of it the runs bracket."""
    below, beyond = bracket
    blade = 1 + max(range(len(cycle.blades)), key=lambda k: cycle.blades[k].amplitude)
    return {
        "speed": cycle.speed,
        "speed_unit": "rad/s",
        "amplitude_unit": "deg",
        "predicted": math.degrees(cycle.amplitude),
        "blade": blade,
        "below_at": below,
        "beyond_at": beyond,
        "bracket": [None if f is None else f * math.degrees(cycle.amplitude) for f in bracket],
        "notes": [
            "runs start along the predicted threshold's motion at factors of it; below_at is the largest "
            "factor whose run stays below the threshold (decays, or settles on a stable cycle below it), "
            "beyond_at the least whose run heads beyond it (grows, or settles on a stable cycle above "
            "it); null: that end did not behave as its side",
            "each run is measured on the blade that moves most, over its last two fifths (the same "
            "measure as a confirming run's)",
        ],
    }
