"""Nonlinear blade lag dampers: the laws a ``[rotor.lag_damper]`` table names.

A law gives the moment M [N m] a blade's lag damper exerts against the lag
angle theta [rad] and rate v = theta' [rad/s] (lag positive against the
rotation, as everywhere in groundres); the blade's equation gets -M:

* ``linear``: M = K theta + c v.
* ``bilinear`` (a hydraulic damper with a relief valve): M = K theta + g(v),
  g = c1 v up to the knee abs(v) = v_r = M_r / c1, then sign(v) (M_r + c2 (abs(v) - v_r)).
  c2 < c1 is a relief valve; c2 > c1 a progressive damper (or free play).
* ``friction``: M = K theta + c_v v + F tanh(v / v_eps): Coulomb friction F,
  regularised over v_eps, beside a viscous part c_v.
* ``tanh``: M = K theta + f tanh(alpha v).
* ``friction-link`` (a Jenkins element, elastomer-like): a spring k_l in series
  with a slider of break-out moment F, beside c_v and K. The link's moment is
  m = k_l (theta - s), s the slider's angle, which moves only while abs(m) > F:
  s' = sign(m) (abs(m) - F) / c_reg (regularised by c_reg: the ideal slider as
  c_reg -> 0). M = K theta + c_v v + m.
* ``table`` (an elastomer's measured properties): storage and loss stiffness
  K'(A), K''(A) against amplitude A at a reference frequency. It describes
  sinusoidal motion only: it enters predictions (:mod:`groundres.model.describing`),
  never a time simulation.

Every law is odd in (theta, v) and continuous. Its small-motion linearisation
(:meth:`DamperLaw.small_motion`) is what every linear analysis of the case
uses: for small motion a friction damper is its regularisation's slope and a
friction link is stuck (a spring k_l, no damping from the slider).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from .validate import finite

LAWS = ("linear", "bilinear", "friction", "tanh", "friction-link", "table")

#: Each law's keys: (required, optional) besides ``law``.
LAW_KEYS = {
    "linear": (("damping",), ("stiffness",)),
    "bilinear": (("damping", "relief_moment", "damping_after_relief"), ("stiffness",)),
    "friction": (("friction_moment", "regularisation_velocity"), ("damping", "stiffness")),
    "tanh": (("tanh_moment", "tanh_rate"), ("stiffness",)),
    "friction-link": (
        ("friction_moment", "link_stiffness", "regularisation_damping"),
        ("damping", "stiffness"),
    ),
    "table": (("amplitudes", "storage_stiffness", "loss_stiffness", "reference_frequency"), ()),
}
#: Every number a law may hold, with its unit (the table's lists in their own units).
UNITS = {
    "damping": "N m s/rad",
    "relief_moment": "N m",
    "damping_after_relief": "N m s/rad",
    "friction_moment": "N m",
    "regularisation_velocity": "rad/s",
    "tanh_moment": "N m",
    "tanh_rate": "s/rad",
    "link_stiffness": "N m/rad",
    "regularisation_damping": "N m s/rad",
    "stiffness": "N m/rad",
    "amplitudes": "deg",
    "storage_stiffness": "N m/rad",
    "loss_stiffness": "N m/rad",
    "reference_frequency": "Hz",
}
#: Largest number a law may hold (damping, moment, stiffness, rate: far beyond any damper's; the
#: describing functions square products of them).
LARGEST = 1e12
#: Largest amplitude a table may list [deg].
LARGEST_AMPLITUDE = 90.0
#: The keys that hold lists (the table law's), and the most entries a list may have.
LIST_KEYS = ("amplitudes", "storage_stiffness", "loss_stiffness")
MAX_TABLE = 200
#: Keys that must be > 0 where given (the rest must be >= 0).
_POSITIVE = (
    "relief_moment",
    "friction_moment",
    "regularisation_velocity",
    "tanh_moment",
    "tanh_rate",
    "link_stiffness",
    "regularisation_damping",
    "reference_frequency",
)


@dataclass(frozen=True)
class DamperLaw:
    """One blade's lag damper law (module docstring), parameters in SI (the table's amplitudes
    in rad, its reference frequency in rad/s: :meth:`from_keys` converts the case file's)."""

    law: str
    damping: float = 0.0
    stiffness: float = 0.0
    relief_moment: float = 0.0
    damping_after_relief: float = 0.0
    friction_moment: float = 0.0
    regularisation_velocity: float = 0.0
    tanh_moment: float = 0.0
    tanh_rate: float = 0.0
    link_stiffness: float = 0.0
    regularisation_damping: float = 0.0
    amplitudes: tuple = ()
    storage_stiffness: tuple = ()
    loss_stiffness: tuple = ()
    reference_frequency: float = 0.0

    @classmethod
    def from_keys(cls, keys: dict) -> DamperLaw:
        """The law of a case file's table ``keys`` (``law`` and its keys, the case file's units:
        amplitudes in deg, the reference frequency in Hz); ParameterError naming the key."""
        law = keys.get("law")
        if law not in LAWS:
            raise ParameterError("law", law, f"must be one of {list(LAWS)}")
        required, optional = LAW_KEYS[law]
        for key in keys:
            if key != "law" and key not in required + optional:
                raise ParameterError(
                    key,
                    keys[key],
                    f"does not apply to law {law!r} (its keys: {', '.join(required + optional)})",
                )
        for key in required:
            if key not in keys:
                raise ParameterError(key, None, f"is required by law {law!r}")
        values = {}
        for key, value in keys.items():
            if key == "law":
                continue
            if key in LIST_KEYS:
                values[key] = _numbers(key, value)
            else:
                values[key] = _number(key, value)
        if law == "table":
            hertz = values["reference_frequency"]
            if not 0 < hertz <= LARGEST:  # (judged in the file's unit, before it becomes rad/s)
                raise ParameterError(
                    "reference_frequency", hertz, f"must be > 0 and at most {LARGEST:.0e} [Hz]"
                )
            values["amplitudes"] = tuple(math.radians(a) for a in values["amplitudes"])
            values["reference_frequency"] = 2 * math.pi * values["reference_frequency"]
        return cls(law=law, **values)

    def __post_init__(self):
        if self.law not in LAWS:
            raise ParameterError("law", self.law, f"must be one of {list(LAWS)}")
        for key in UNITS:
            values = getattr(self, key) if key in LIST_KEYS else (getattr(self, key),)
            for value in values:
                if not finite(value) or value < 0:
                    raise ParameterError(key, value, "must be a finite number >= 0")
                if value > LARGEST:
                    raise ParameterError(key, value, f"must be at most {LARGEST:.0e}")
        required, _ = LAW_KEYS[self.law]
        for key in required:
            if key in _POSITIVE and key not in LIST_KEYS and not getattr(self, key) > 0:
                raise ParameterError(key, getattr(self, key), f"must be > 0 for law {self.law!r}")
        if self.law == "bilinear" and not self.damping > 0:
            raise ParameterError(
                "damping", self.damping, "must be > 0 for law 'bilinear' (the slope up to the knee)"
            )
        if self.law == "table":
            self._check_table()
        damping, stiffness = self.small_motion()
        if not (damping <= LARGEST and stiffness <= LARGEST):
            key = {"friction": "regularisation_velocity", "tanh": "tanh_rate", "table": "reference_frequency"}
            name = key.get(self.law, "damping")
            raise ParameterError(
                name,
                getattr(self, name)
                if name != "reference_frequency"
                else self.reference_frequency / (2 * math.pi),
                f"gives a slope at rest of {damping:.3g} N m s/rad, beyond {LARGEST:.0e}",
            )

    def _check_table(self):
        a, k1, k2 = self.amplitudes, self.storage_stiffness, self.loss_stiffness
        if not 2 <= len(a) <= MAX_TABLE:
            raise ParameterError(
                "amplitudes",
                [round(math.degrees(x), 12) for x in a],
                f"must list 2 to {MAX_TABLE} amplitudes",
            )
        if len(k1) != len(a) or len(k2) != len(a):
            raise ParameterError(
                "storage_stiffness" if len(k1) != len(a) else "loss_stiffness",
                len(k1) if len(k1) != len(a) else len(k2),
                f"must list one value per amplitude ({len(a)})",
            )
        if not a[-1] <= math.radians(LARGEST_AMPLITUDE):
            raise ParameterError(
                "amplitudes",
                [round(math.degrees(x), 12) for x in a],
                f"must be at most {LARGEST_AMPLITUDE} deg",
            )
        if not (a[0] > 0 and all(y > x for x, y in zip(a, a[1:]))):
            raise ParameterError(
                "amplitudes", [round(math.degrees(x), 12) for x in a], "must be > 0 and increasing"
            )
        for key in ("storage_stiffness", "loss_stiffness"):
            if any(v < 0 for v in getattr(self, key)):
                raise ParameterError(key, list(getattr(self, key)), "must all be >= 0")

    # -- what the law does ------------------------------------------------------------

    @property
    def has_slider(self) -> bool:
        """Whether the law carries a state of its own (the friction link's slider angle)."""
        return self.law == "friction-link"

    @property
    def simulable(self) -> bool:
        """Whether the law gives a moment in time (all but the table of measured properties)."""
        return self.law != "table"

    @property
    def relief_rate(self) -> float:
        """The bilinear knee v_r = M_r / c1 [rad/s]."""
        return self.relief_moment / self.damping

    def moment(self, angle, rate, slider=0.0):
        """The damper's moment M [N m] at lag ``angle`` [rad] and ``rate`` [rad/s] (arrays
        broadcast), and ``slider`` [rad] for the friction link."""
        angle, rate = np.asarray(angle, dtype=float), np.asarray(rate, dtype=float)
        spring = self.stiffness * angle
        if self.law == "linear":
            return spring + self.damping * rate
        if self.law == "bilinear":
            return spring + self.rate_moment(rate)
        if self.law == "friction":
            return (
                spring
                + self.damping * rate
                + self.friction_moment * np.tanh(rate / self.regularisation_velocity)
            )
        if self.law == "tanh":
            return spring + self.tanh_moment * np.tanh(self.tanh_rate * rate)
        if self.law == "friction-link":
            return spring + self.damping * rate + self.link_stiffness * (angle - slider)
        raise ValueError("a table of measured properties gives no moment in time (use a friction link)")

    def rate_moment(self, rate):
        """The bilinear law's g(v) [N m]."""
        rate = np.asarray(rate, dtype=float)
        knee, c1, c2 = self.relief_rate, self.damping, self.damping_after_relief
        beyond = np.sign(rate) * (self.relief_moment + c2 * (np.abs(rate) - knee))
        return np.where(np.abs(rate) <= knee, c1 * rate, beyond)

    def slider_rate(self, angle, slider):
        """The friction link's slider rate s' [rad/s] at lag ``angle`` and ``slider`` [rad]."""
        link = self.link_stiffness * (np.asarray(angle, dtype=float) - slider)
        return (
            np.sign(link) * np.maximum(np.abs(link) - self.friction_moment, 0.0) / self.regularisation_damping
        )

    def slopes(self, angle, rate, slider=0.0) -> tuple:
        """(dM/dtheta, dM/dv, dM/ds) at ``angle``, ``rate`` and ``slider`` (floats): the law's
        Jacobian, for an implicit integration."""
        if self.law == "friction-link":
            return self.stiffness + self.link_stiffness, self.damping, -self.link_stiffness
        if self.law == "bilinear":
            return (
                self.stiffness,
                self.damping if abs(rate) <= self.relief_rate else self.damping_after_relief,
                0.0,
            )
        if self.law == "friction":
            sech = 1.0 / math.cosh(min(abs(rate) / self.regularisation_velocity, 350.0))
            slope = self.damping + self.friction_moment / self.regularisation_velocity * sech * sech
            return self.stiffness, slope, 0.0
        if self.law == "tanh":
            sech = 1.0 / math.cosh(min(abs(self.tanh_rate * rate), 350.0))
            return self.stiffness, self.tanh_moment * self.tanh_rate * sech * sech, 0.0
        return self.stiffness, self.damping, 0.0

    def slider_slopes(self, angle, slider) -> tuple:
        """(ds'/dtheta, ds'/ds) of the friction link's slider (zero while it sticks)."""
        link = self.link_stiffness * (angle - slider)
        rate = self.link_stiffness / self.regularisation_damping if abs(link) > self.friction_moment else 0.0
        return rate, -rate

    def cycle(self, amplitude: float, frequency: float, points: int = 721):
        """The law over one steady cycle of theta = A cos(w t): (angle, rate, moment), each
        (points,), at ``amplitude`` [rad] and ``frequency`` [rad/s]. The friction link's
        slider is followed over a cycle before (implicit Euler, 64 steps per point: the
        slider's time constant c_reg / k_l may be far below the step)."""
        phase = np.linspace(0.0, 2 * np.pi, points)
        angle = amplitude * np.cos(phase)
        rate = -amplitude * frequency * np.sin(phase)
        if not self.has_slider:
            return angle, rate, self.moment(angle, rate)
        fine = np.linspace(-2 * np.pi, 2 * np.pi, 2 * 64 * (points - 1) + 1)
        dt = (fine[1] - fine[0]) / abs(frequency)
        k, force, c = self.link_stiffness, self.friction_moment, self.regularisation_damping
        slider, s = np.empty(fine.size), 0.0
        for i, theta in enumerate(amplitude * np.cos(fine)):  # (bounded: 2 x 64 x points steps)
            link = k * (theta - s)
            if abs(link) > force:
                s += math.copysign(dt * (abs(link) - force) / (c + dt * k), link)
            slider[i] = s
        return angle, rate, self.moment(angle, rate, slider[64 * (points - 1) :: 64])  # (phase 0 on)

    def small_motion(self) -> tuple[float, float]:
        """(damping [N m s/rad], stiffness [N m/rad]) of the law for small motion: its slope at
        rest (the friction link stuck; the table at its smallest amplitude, its loss taken at
        the reference frequency)."""
        if self.law == "linear":
            return self.damping, self.stiffness
        if self.law == "bilinear":
            return self.damping, self.stiffness
        if self.law == "friction":
            return self.damping + self.friction_moment / self.regularisation_velocity, self.stiffness
        if self.law == "tanh":
            return self.tanh_moment * self.tanh_rate, self.stiffness
        if self.law == "friction-link":
            return self.damping, self.stiffness + self.link_stiffness
        return self.loss_stiffness[0] / self.reference_frequency, self.storage_stiffness[0]


@dataclass(frozen=True)
class BladeDamper:
    """A blade's lag damper law and the blade's own root spring [N m/rad] beside it (the blade's
    ``lag_stiffness`` is the root spring plus the law's stiffness at the amplitude considered)."""

    law: DamperLaw
    root_stiffness: float

    def linear(self, damping: float, stiffness: float) -> dict:
        """The blade's ``lag_damping`` and ``lag_stiffness`` for an equivalent linear damper."""
        return {"lag_damping": float(damping), "lag_stiffness": self.root_stiffness + float(stiffness)}


def _number(key, value) -> float:
    if not finite(value):
        raise ParameterError(key, value, "must be a finite number")
    return float(value)


def _numbers(key, value) -> tuple:
    if not isinstance(value, (list, tuple)) or not value:
        raise ParameterError(key, value, "must be a list of numbers")
    if len(value) > MAX_TABLE:
        raise ParameterError(key, len(value), f"must list at most {MAX_TABLE} values")
    return tuple(_number(key, v) for v in value)
