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
nonrotating frame.

:func:`confirm` sets a predicted cycle against runs started along its motion:
a stable cycle from :data:`ABOVE` times it, or nearer where a threshold lies
close above it (:func:`stable_start`; settling back to it), a threshold
between :data:`BELOW` (decays) and :data:`ABOVE` (grows) times it
(:func:`groundres.assess.limit_cycles.bracket_threshold`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

#: Change of the largest component over one window within which a run has settled (relative).
SETTLED = 0.02
#: Factors of a predicted cycle the confirming runs start at.
BELOW, ABOVE = 0.8, 1.25
#: Default run: periods of the cycle's (or the blade's) rotating-frame frequency, and the part of
#: the run each of the two measuring windows takes.
PERIODS, WINDOW_SHARE = 120, 0.2


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
    if history.stopped is not None or now > (1 + SETTLED) * was:
        verdict = "grows"
    elif now < (1 - SETTLED) * was:
        verdict = "decays"
    else:
        verdict = "settled"
    return Measured(blades, hub, float(was), verdict, float(window), history)


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
    cycle of ``others``, those at its speed, lies close), its settled amplitude (the blade that
    moves most) against the predicted. A threshold: runs from :data:`BELOW` and :data:`ABOVE` times
    it, which should decay and grow. Returns a dict for limit_cycles.json (angles in deg).
    """
    from ..solve import nonlinear
    from .limit_cycles import disturbance

    duration = default_duration(cycle.frequency) if duration is None else duration
    window = WINDOW_SHARE * duration if window is None else min(window, duration / 2)
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
        }
        for f, m in runs.items()
    ]
    if cycle.stable:
        (settled,) = runs.values()
        out["confirmed"] = settled.verdict == "settled"
        out["settled"] = math.degrees(settled.amplitude)
        out["error"] = settled.amplitude / cycle.amplitude - 1
    else:
        out["confirmed"] = runs[BELOW].verdict == "decays" and runs[ABOVE].verdict == "grows"
    out["duration"], out["window"] = duration, window
    return out
