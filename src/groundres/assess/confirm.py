"""What a run of the nonlinear equations shows, measured as the prediction measures a cycle.

A run (:func:`groundres.solve.nonlinear.integrate`) is judged on two windows
at its end, each ``window`` long: every blade's lag and every body coordinate
are split into their two largest frequency components
(:func:`groundres.solve.nonlinear.components`: FFT peaks refined by least
squares, so that a dissimilar rotor's several frequencies are told apart); the
largest component of the blade that moves most, in the last window against
the one before, says whether the motion still grows, decays, or has settled
(within :data:`SETTLED` a window). The blades' components are in the rotating
frame (a blade coordinate turns with the rotor) and the body's in the
nonrotating frame. Each window is at most half the run.

Where a run heads (:func:`destination`) says which side of a threshold it
started on: a run that settled stays where it is, one still growing heads to the
nearest stable cycle above it (or without bound), one still decaying to the
nearest below it (or rest). A run started just below a threshold with a stable
cycle beneath it settles on that cycle: it stays below the threshold as surely
as one that decays.

:func:`confirm` sets a predicted cycle against runs started along its motion:
a stable cycle from :data:`ABOVE` times it, or nearer where a threshold lies
close above it (:func:`stable_start`; settling back to it), a threshold
between :data:`BELOW` (stays below) and :data:`ABOVE` (heads beyond) times it
(:func:`bracket_threshold` bisects between such
runs).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

#: Change of the largest component over one window within which a run has settled (relative).
SETTLED = 0.02
#: Motion below this many times the integration's absolute tolerance is not a result: a run whose
#: motion ends below it has decayed (to the integration's resolution).
RESOLVED = 1000.0
#: Factors of a predicted cycle the confirming runs start at.
BELOW, ABOVE = 0.8, 1.25
#: Default run: periods of the cycle's (or the blade's) rotating-frame frequency, and the part of
#: the run each of the two measuring windows takes.
PERIODS, WINDOW_SHARE = 120, 0.2
#: Shortest run, in periods of its motion, and shortest measuring window (two fifths of a run of
#: ten periods): fewer and a window holds too little of the motion for its amplitude.
MIN_PERIODS, WINDOW_PERIODS = 10, 2
#: A run settles on a predicted stable cycle when its level lies within this factor of it; one that
#: settles farther from every stable cycle only changes too slowly to tell (undecided).
NEAR_CYCLE = 1.25


@dataclass
class Measured:
    """A run's end (module docstring); SI, angles in rad, frequencies in rad/s.

    Attributes
    ----------
    blades : list of [(frequency, amplitude), (frequency, amplitude)]
        Each blade's two largest lag components in the rotating frame over the last window.
    hub : dict
        Each body coordinate's two largest components in the nonrotating frame.
    before : float
        The largest component of the blade that moves most, over the window before the last.
    verdict : str
        "grows", "decays" or "settled".
    """

    blades: list
    hub: dict
    before: float
    verdict: str
    window: float
    history: object = field(default=None, repr=False)

    @property
    def lead(self) -> int:
        """The blade that moves most (1-based)."""
        return 1 + int(np.argmax([parts[0][1] for parts in self.blades]))

    @property
    def amplitude(self) -> float:
        """The largest component of the blade that moves most, over the last window [rad]."""
        return self.blades[self.lead - 1][0][1]


def measure(history, window: float) -> Measured:
    """Measure the end of ``history`` over two windows of ``window`` [s] (module docstring)."""
    time = history.time
    window = min(window, (time[-1] - time[0]) / 2)  # (an empty window before would read as growth)
    last = time >= time[-1] - window
    before = (time >= time[-1] - 2 * window) & ~last
    blades = [
        _two(nonlinear_components(time[last], history.lag(k)[last]))
        for k in range(1, 1 + sum(c.kind == "lag" for c in history.coordinates))
    ]
    names = [c.short for c in history.coordinates]
    hub = {
        c.short: _two(nonlinear_components(time[last], history.displacement[last, names.index(c.short)]))
        for c in history.coordinates
        if c.kind == "body"
    }
    lead = int(np.argmax([parts[0][1] for parts in blades]))
    earlier = nonlinear_components(time[before], history.lag(lead + 1)[before], 1)
    was = earlier[0][1] if earlier else 0.0
    now = blades[lead][0][1]
    if history.stopped is not None or now > max((1 + SETTLED) * was, RESOLVED * history.atol):
        verdict = "grows"
    elif now < (1 - SETTLED) * was or now <= RESOLVED * history.atol:
        verdict = "decays"
    else:
        verdict = "settled"
    return Measured(blades, hub, float(was), verdict, float(window), history)


def destination(measured: Measured, stable=()) -> float:
    """Where a run is heading, as the amplitude of the blade that moves most [rad] (module
    docstring): where it settled; for one still growing (or stopped past 90 deg) the nearest of
    the ``stable`` cycles' amplitudes above it, else inf; for one still decaying the nearest
    below it, else 0."""
    now = measured.amplitude
    history = getattr(measured, "history", None)
    if history is not None and history.stopped is not None:  # (passed 90 deg: without bound)
        return math.inf
    if measured.verdict == "settled":
        return now
    if measured.verdict == "grows":
        return min((a for a in stable if a > now), default=math.inf)
    return max((a for a in stable if a < now), default=0.0)


def beyond(measured: Measured, threshold: float, stable=()) -> bool:
    """Whether a run heads beyond ``threshold`` [rad] (:func:`destination`)."""
    return destination(measured, stable) > threshold


def undecided(measured: Measured, stable) -> bool:
    """Whether a run that settled did so far from every ``stable`` cycle's amplitude [rad] (by more
    than a factor :data:`NEAR_CYCLE`): it changes too slowly to tell where it heads in this run."""
    if measured.verdict != "settled" or not measured.amplitude > 0:
        return False
    return not any(abs(math.log(measured.amplitude / a)) <= math.log(NEAR_CYCLE) for a in stable if a > 0)


def run_words(run: dict) -> str:
    """What a run did, from its entry in limit_cycles.json: 'decays', 'grows', 'settles at
    1.21 deg', 'grows past 90 deg, where it stopped at 3.2 s'."""
    if run.get("stopped") is not None:
        return f"grows past 90 deg, where it stopped at {run['stopped']:.3g} s"
    if run.get("undecided"):
        return (
            f"barely changes, {run['amplitude']:.3g} deg at its end with no stable cycle predicted near: too "
            "slow to tell in this run (lengthen [simulation] duration)"
        )
    if run["verdict"] == "settled":
        return f"settles at {run['amplitude']:.3g} deg"
    return run["verdict"]


def nonlinear_components(time, signal, count: int = 2):
    """:func:`groundres.solve.nonlinear.components`, none for a signal that does not move."""
    from ..solve.nonlinear import components

    if len(time) < 8 or not np.ptp(signal) > 0:
        return []
    return components(time, signal, count)


def _two(parts):
    """Two (frequency, amplitude) pairs, zeros where a signal holds fewer."""
    parts = list(parts) + [(0.0, 0.0)] * 2
    return parts[:2]


def check_length(duration: float, window: float, frequency: float, where: str, default: bool = False) -> None:
    """Refuse a run of ``duration`` [s] measured over windows of ``window`` [s] that does not fit
    its motion at ``frequency`` [rad/s, rotating frame] ``where`` ('at 264.34 rpm'): a window
    beyond half the run, or a run or window too short for the motion; a ParameterError naming
    duration or window. ``default``: the run's length is the default at that speed."""
    from ..errors import ParameterError
    from ..model.params import MAX_DURATION

    period = 2 * math.pi / max(frequency, 1e-3)
    shortest = min(MIN_PERIODS * period, MAX_DURATION)
    motion = f"the motion {where}, of {period:.3g} s each"
    if duration < shortest:
        raise ParameterError(
            "duration",
            duration,
            f"must be at least {shortest:.3g} [s]: {MIN_PERIODS} periods of {motion}, so that each of the "
            "two measuring windows holds a few",
        )
    if window > duration / 2:
        length = "the default " + where if default else "the duration given"
        raise ParameterError(
            "window",
            window,
            f"must be at most half the run, {duration / 2:.3g} [s]: the run lasts {duration:.3g} s, {length}",
        )
    if window < min(WINDOW_PERIODS * period, shortest / 5):
        raise ParameterError(
            "window",
            window,
            f"must be at least {WINDOW_PERIODS * period:.3g} [s]: {WINDOW_PERIODS} periods of {motion}, for "
            "its amplitude to be measured",
        )


def run_length(case, speed, frequency, duration=None, window=None) -> tuple[float, float]:
    """The (duration, window) [s] of a run of ``case`` at ``speed`` [rad/s] whose motion is at
    ``frequency`` [rad/s, rotating frame]: those given, or the defaults (:func:`default_duration`,
    :data:`WINDOW_SHARE` of it), checked (:func:`check_length`)."""
    from ..model.units import fmt_speed

    default = duration is None
    duration = default_duration(frequency) if default else duration
    window = WINDOW_SHARE * duration if window is None else window
    check_length(duration, window, frequency, f"at {fmt_speed(speed, case.sweep)}", default)
    return duration, window


def default_duration(frequency: float) -> float:
    """A run's length [s] for motion at ``frequency`` [rad/s] in the rotating frame, at most
    :data:`groundres.model.params.MAX_DURATION`."""
    from ..model.params import MAX_DURATION

    return min(PERIODS * 2 * math.pi / max(frequency, 1e-3), MAX_DURATION)


def stable_start(cycle, others=()) -> float:
    """The factor of a stable ``cycle`` a confirming run starts at: :data:`ABOVE`, or halfway (on a
    log scale) to the next cycle above at its speed where that is nearer (a threshold there: a run
    beyond it would grow, not return), or from below where the cycle above is very near."""
    above = [c.amplitude / cycle.amplitude for c in others if c.amplitude > cycle.amplitude * (1 + 1e-9)]
    below = [c.amplitude / cycle.amplitude for c in others if c.amplitude < cycle.amplitude * (1 - 1e-9)]
    up = min([ABOVE] + [math.sqrt(r) for r in above])
    if up >= 1.05:
        return up
    return max([BELOW] + [math.sqrt(r) for r in below])


def confirm(
    case, cycle, duration: float | None = None, window: float | None = None, progress=None, others=()
) -> dict:
    """Set ``cycle`` against runs of the nonlinear equations started along its motion.

    A stable cycle: a run from :func:`stable_start` times it (:data:`ABOVE`, nearer where another
    cycle of ``others``, those at its speed, lies close), which should settle nearer it than any
    other cycle; its settled amplitude (the blade that moves most) against the predicted. A
    threshold: runs from :data:`BELOW` and :data:`ABOVE` times it, which should stay below it and
    head beyond it (:func:`beyond`, each run's ``beyond``). Returns a dict for
    limit_cycles.json (angles in deg).
    """
    from ..solve import nonlinear
    from .limit_cycles import disturbance

    duration, window = run_length(case, cycle.speed, cycle.frequency, duration, window)
    stable = [c.amplitude for c in others if c.stable]
    system = nonlinear.structure(case)
    factors = (stable_start(cycle, others),) if cycle.stable else (BELOW, ABOVE)
    runs = {}
    for i, factor in enumerate(factors):
        report = progress and (lambda done, total, i=i: progress(i * total + done, len(factors) * total))
        history = nonlinear.integrate(
            case, cycle.speed, duration, disturbance(system, cycle, factor), progress=report
        )
        runs[factor] = measure(history, window)
    out = {"speed": cycle.speed, "stable": cycle.stable, "predicted": math.degrees(cycle.amplitude)}
    out["runs"] = [
        {
            "factor": f,
            "verdict": m.verdict,
            "amplitude": math.degrees(m.amplitude),
            "blade": m.lead,
            "evaluations": m.history.evaluations,
            "method": m.history.method,
            "stopped": m.history.stopped,
            "undecided": undecided(m, stable + ([cycle.amplitude] if cycle.stable else [])),
            **({} if cycle.stable else {"beyond": beyond(m, cycle.amplitude, stable)}),
        }
        for f, m in runs.items()
    ]
    if cycle.stable:
        (settled,) = runs.values()
        levels = [c.amplitude for c in others] + [cycle.amplitude]
        size = max(settled.amplitude, 1e-300)  # (a run stopped at once measures nothing)
        nearest = min(levels, key=lambda a: abs(math.log(size / a)))
        out["confirmed"] = settled.verdict == "settled" and nearest == cycle.amplitude
        out["settled"] = math.degrees(settled.amplitude)
        out["error"] = settled.amplitude / cycle.amplitude - 1
    else:
        out["confirmed"] = not out["runs"][0]["beyond"] and out["runs"][1]["beyond"]
    out["confirmed"] = out["confirmed"] and not any(r["undecided"] for r in out["runs"])
    out["duration"], out["window"] = duration, runs[factors[0]].window
    return out


def bracket_threshold(
    case,
    cycle,
    low: float = 0.8,
    high: float = 1.25,
    steps: int = 4,
    duration=None,
    progress=None,
    others=(),
):
    """Bracket an unstable cycle (a threshold) by simulation: start the nonlinear equations
    (:func:`groundres.solve.nonlinear.integrate`) along ``cycle``'s motion at factors of it and
    bisect the factor between one that stays below the threshold and one that heads beyond it,
    ``steps`` times.

    Each run lasts ``duration`` [s] (default 60 periods of the cycle's rotating-frame frequency)
    and is measured over its last two fifths as a confirming run is
    (:func:`groundres.assess.confirm.measure`); where it heads (:func:`groundres.assess.confirm.beyond`,
    the stable cycles among ``others``, the cycles at its speed, its destinations) says its
    side: a run that settles on a stable cycle below the threshold stays below it. Returns
    (below, beyond): the factors bracketing the threshold, or None for an end that did not
    behave as its side (the prediction is then off by more than the bracket).
    ``progress(done, total)`` counts the runs.
    """
    from ..solve import nonlinear
    from .limit_cycles import disturbance

    system = nonlinear.structure(case)
    duration = 120 * math.pi / cycle.frequency if duration is None else duration
    duration, _ = run_length(case, cycle.speed, cycle.frequency, duration)
    stable = [c.amplitude for c in others if c.stable]

    runs = [0]

    def grows(factor: float) -> bool:
        runs[0] += 1
        if progress is not None:
            progress(runs[0] - 1, steps + 2)
        history = nonlinear.integrate(
            case, cycle.speed, duration, disturbance(system, cycle, factor), points=4000
        )
        return beyond(measure(history, duration / 5), cycle.amplitude, stable)

    low_grows, high_grows = grows(low), grows(high)
    if low_grows or not high_grows:
        return (None if low_grows else low), (high if high_grows else None)
    for _ in range(steps):
        mid = math.sqrt(low * high)
        low, high = (low, mid) if grows(mid) else (mid, high)
    if progress is not None:
        progress(steps + 2, steps + 2)
    return low, high
