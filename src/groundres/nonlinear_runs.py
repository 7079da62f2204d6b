"""Runs of the nonlinear equations (the lag dampers' laws themselves) for a user: at one speed
from a disturbance, and the threshold search.

:func:`run_nonlinear` integrates the periodic blade equations with each law's
moment and measures the end of the run as the limit-cycle prediction measures a
cycle; :func:`search_threshold` brackets a predicted threshold by bisection on
the disturbance. Both start from ``[simulation]`` where the call leaves a choice.
"""

from __future__ import annotations

import math

import numpy as np

from .assess import confirm as confirming
from .assess.limit_cycles import disturbance, predict
from .errors import CaseError, ParameterError
from .model.params import Case, SimulationOptions
from .model.units import SPEED_UNITS
from .results.nonlinear_run import NonlinearRun
from .solve import nonlinear
from .solve.simulate import default_initial, initial_state, initial_text


def _checked(case: Case, speed) -> None:
    if not case.rotor.nonlinear:
        raise CaseError(
            "[rotor.lag_damper]: a nonlinear run needs a nonlinear lag damper law (none is given)"
        )
    bad = (
        isinstance(speed, bool)
        or not isinstance(speed, (int, float))
        or not (np.isfinite(speed) and speed > 0)
    )
    if bad:
        raise ParameterError("speed", speed, "must be a finite number > 0 [rad/s]")
    table = case.rotor.unsimulable_blade
    if table is not None:
        raise CaseError(
            f'blade {table + 1}\'s lag damper, law = "table": a table of measured properties gives no moment '
            "in time, so it cannot be simulated (fit a friction-link law to it)"
        )


def _cycles(case: Case, speed: float) -> list:
    """The cycles predicted at ``speed`` over the amplitudes ``[limit_cycle]`` searches."""
    return predict(case, [speed], searched=case.limit_cycle.searched).cycles


def _along(cycles: list, factor: float):
    """The cycle a run along a predicted cycle follows: the threshold of least amplitude, else the
    stable cycle of least amplitude."""
    ranked = sorted(cycles, key=lambda c: (c.stable, c.amplitude))
    if not ranked:
        raise ParameterError(
            "along_cycle", factor, "no limit cycle is predicted at this speed to start along"
        )
    return ranked[0]


def run_nonlinear(
    case: Case,
    speed: float,
    *,
    duration: float | None = None,
    window: float | None = None,
    initial: dict | None = None,
    along_cycle: float | None = None,
    progress=None,
) -> NonlinearRun:
    """Integrate the periodic blade equations with the lag dampers' laws at ``speed`` [rad/s].

    The run starts from ``initial`` (displacements [m, rad] and rates by coordinate name, as
    :func:`groundres.analysis.simulate`) or ``along_cycle`` times the predicted cycle at that speed
    (the threshold of least amplitude, else the stable cycle), else from ``[simulation]``, else from
    0.01 on every body coordinate and on lag1. ``duration`` [s] defaults to ``[simulation]`` or 120
    periods of the motion; ``window`` [s] to ``[simulation]`` or a fifth of the run. Its end is
    measured as the prediction measures a cycle (:mod:`groundres.assess.confirm`), in both frames,
    with the predicted cycles beside it.

    Examples
    --------
    >>> run = run_nonlinear(load_case("hammond-relief-valve"), 27.7, along_cycle=1.1)  # doctest: +SKIP
    >>> run.measured.verdict, run.words()  # doctest: +SKIP
    """
    _checked(case, speed)
    options = case.simulation
    given = SimulationOptions(
        duration=duration if duration is not None else options.duration,
        window=window if window is not None else options.window,
        along_cycle=along_cycle if along_cycle is not None or initial else options.along_cycle,
        initial=tuple((initial or {}).items()) or (() if along_cycle is not None else options.initial),
    )
    predicted = _cycles(case, speed)
    system = nonlinear.structure(case)
    if given.along_cycle is not None:
        cycle = _along(predicted, given.along_cycle)
        start = disturbance(system, cycle, given.along_cycle)
        kind = "stable cycle" if cycle.stable else "threshold"
        words = f"{given.along_cycle:g} times the predicted {kind} of {math.degrees(cycle.amplitude):.3g} deg"
        frequency = cycle.frequency
    else:
        values = dict(given.initial) or default_initial(system)  # (bounded by SimulationOptions)
        start = initial_state(system, values)
        words = initial_text(values)
        blade = case.rotor.blades[0]
        frequency = float(blade.lag_frequency(np.array([speed]))[0]) * speed
    run_for, measured_over = confirming.run_length(case, speed, frequency, given.duration, given.window)
    history = nonlinear.integrate(case, speed, run_for, start, progress=progress)
    return NonlinearRun(case, speed, words, confirming.measure(history, measured_over), predicted)


def search_threshold(
    case: Case, speed: float, *, steps: int = 4, duration: float | None = None, progress=None
):
    """Bracket the predicted threshold of least amplitude at ``speed`` [rad/s] by simulation: runs
    started along it at factors of it, bisected ``steps`` times between one that stays below it
    and one that heads beyond it (:func:`groundres.assess.confirm.bracket_threshold`).

    Returns (cycle, (below, beyond)): the predicted threshold and the factors of it that bracket
    the simulated one: the largest whose run stays below it (decays, or settles on a stable cycle
    below it) and the least whose run heads beyond it (an end is None where it did not behave as
    its side).
    """
    _checked(case, speed)
    if isinstance(steps, bool) or not isinstance(steps, int) or not 0 <= steps <= 12:
        raise ParameterError("steps", steps, "must be a whole number from 0 to 12")
    cycles = _cycles(case, speed)
    thresholds = [c for c in cycles if not c.stable]
    if not thresholds:
        unit = case.sweep.unit
        raise ParameterError(
            "speed",
            speed,
            f"no threshold is predicted at {speed / SPEED_UNITS[unit]:g} {unit} (groundres cycles)",
        )
    cycle = min(thresholds, key=lambda c: c.amplitude)
    run_for = duration if duration is not None else case.simulation.duration
    run_for = SimulationOptions(duration=run_for).duration  # (checked: finite, 0 to MAX_DURATION)
    others = [c for c in cycles if c is not cycle]
    bracket = confirming.bracket_threshold(
        case, cycle, steps=steps, duration=run_for, progress=progress, others=others
    )
    return cycle, bracket
