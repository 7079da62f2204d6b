"""A run of the nonlinear equations (the lag dampers' laws themselves) at one rotor speed.

:class:`NonlinearRun` holds the time history, what its end shows
(:class:`groundres.assess.confirm.Measured`: each blade's settled lag and the
hub's, in the two frames, and whether the motion still grows, decays or has
settled) and the cycles predicted at that speed beside it; ``to_dict()`` is
nonlinear.json, ``words()`` the verdict as a designer reads it, ``plot()`` the
time history with the predicted cycles.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..assess.confirm import RESOLVED
from ..model.mbc import unit_of
from ..model.units import fmt_speed
from ..solve.nonlinear import LIMIT
from .simulation import coordinate_unit

#: Said with every nonlinear run.
NOTES = (
    "blade amplitudes are each blade's lag components in the rotating frame (a blade turns with the rotor), "
    "hub amplitudes each body coordinate's in the nonrotating frame; both are the two largest components "
    "over the last window (FFT peaks refined by least squares), the largest being the measure the limit-"
    "cycle prediction uses",
    "verdict: the largest component of the blade that moves most over the last window against the window "
    "before it: settled within 2 %, else grows or decays",
    "stopped: where a blade's lag passed 90 deg and the run ended (null: it ran its course); the windows "
    "then end there",
    "resolved false: the motion at the end is below a thousand times the integration's absolute tolerance, "
    "so its amplitudes are the integration's error and are given as null",
    "the structure is linear (small angles): motion that grows means growth until something not modelled "
    "stops it",
)


@dataclass
class NonlinearRun:
    """A run of the nonlinear equations (module docstring).

    Attributes
    ----------
    case : Case
    rotor_speed : float
        [rad/s].
    start : str
        How the run started, in words (the disturbance given).
    measured : Measured
    predicted : list of Cycle
        The limit cycles predicted at ``rotor_speed`` (empty: none, or none predicted for this case).
    """

    case: object
    rotor_speed: float
    start: str
    measured: object
    predicted: list

    @property
    def history(self):
        """The time history (:class:`groundres.solve.nonlinear.NonlinearHistory`)."""
        return self.measured.history

    @property
    def time(self):
        return self.history.time

    @property
    def displacement(self):
        return self.history.displacement

    def column_names(self) -> list[str]:
        """A name with its unit for each coordinate: "x [m]", "lag1 [rad]"."""
        return [f"{c.short} [{coordinate_unit(c)}]" for c in self.history.coordinates]

    @property
    def resolved(self) -> bool:
        """Whether the motion at the end is above the integration's resolution (a thousand times its
        absolute tolerance): below it the amplitudes are the integration's error, not a result."""
        return bool(self.measured.amplitude > RESOLVED * self.history.atol)

    def words(self) -> str:
        """'at 260 rpm the motion settled on a lag cycle of 6.2 deg (blade 1) ...'."""
        m = self.measured
        where = fmt_speed(self.rotor_speed, self.case.sweep)
        if self.history.stopped is not None:
            return (
                f"at {where} the motion grew until a blade's lag passed {math.degrees(LIMIT):g} deg at "
                f"{self.history.stopped:.3g} s, where the run stopped (far beyond the small angles the model "
                "holds)"
            )
        if self.resolved is False:
            return f"at {where} the motion decayed to the integration's resolution by the end of the run"
        sizes = [parts[0][1] for parts in m.blades]
        alike = max(sizes) - min(sizes) <= 0.01 * max(sizes)
        amplitude = f"{math.degrees(m.amplitude):.3g} deg " + (
            "(every blade)" if alike else f"(blade {m.lead})"
        )
        if m.verdict == "settled":
            return f"at {where} the motion settled on a lag cycle of {amplitude}"
        rate = "still growing" if m.verdict == "grows" else "still decaying"
        return f"at {where} the motion is {rate} at the end of the run: {amplitude} over its last window"

    def to_dict(self) -> dict:
        """nonlinear.json: the run, its end in both frames, and the predicted cycles beside it."""
        m, h = self.measured, self.history
        hub_units = {name: unit_of("body", name) for name in m.hub}
        return {
            "speed": self.rotor_speed,
            "speed_unit": "rad/s",
            "amplitude_unit": "deg",
            "frequency_unit": "rad/s",
            "hub_units": hub_units,
            "start": self.start,
            "duration": float(h.time[-1]),
            "window": m.window,
            "integrator": h.method,
            "evaluations": h.evaluations,
            "verdict": m.verdict,
            "stopped": self.history.stopped,
            "resolved": self.resolved,
            "words": self.words(),
            "blade": m.lead,
            "amplitude": math.degrees(m.amplitude) if self.resolved else None,
            "blades": [
                {
                    "blade": k + 1,
                    "amplitude": math.degrees(parts[0][1]),
                    "frequency_rotating": parts[0][0],
                    "second_amplitude": math.degrees(parts[1][1]),
                    "second_frequency_rotating": parts[1][0],
                }
                for k, parts in enumerate(m.blades)
            ]
            if self.resolved
            else None,
            "hub": {
                name: {
                    "amplitude": parts[0][1],
                    "frequency_nonrotating": parts[0][0],
                    "second_amplitude": parts[1][1],
                    "second_frequency_nonrotating": parts[1][0],
                }
                for name, parts in m.hub.items()
            }
            if self.resolved
            else None,
            "predicted": [
                {
                    "stable": c.stable,
                    "amplitude": math.degrees(c.amplitude),
                    "frequency_rotating": c.frequency,
                    "frequency_nonrotating": c.nonrotating_frequency,
                    "second_frequency_nonrotating": c.nonrotating_second,
                    "blades": [math.degrees(b.amplitude) for b in c.blades],
                    "hub": c.hub,
                }
                for c in self.predicted
            ],
            "notes": list(NOTES),
        }

    def plot(self, fig=None):
        """Every blade's lag [deg] and the hub's motion against time, the predicted cycles (the
        blade that moves most) as dashed levels."""
        from ..plotting.nonlinear_run import nonlinear_run_figure

        return nonlinear_run_figure(self, fig)

    def __repr__(self) -> str:
        return f"NonlinearRun({self.words()})"


def hub_text(measured) -> str:
    """'x 2.2 mm at 25.1 rad/s, y 7.4 mm at 25.1 rad/s' (translations in mm, angles in deg)."""
    parts = []
    for name, ((w, a), _) in measured.hub.items():
        value = f"{1e3 * a:.3g} mm" if unit_of("body", name) == "m" else f"{np.degrees(a):.3g} deg"
        parts.append(f"{name} {value} at {w:.4g} rad/s")
    return ", ".join(parts)
