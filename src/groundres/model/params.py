"""Physical description of a case: blades, rotor, body and speed sweep, in SI.

Every class is a frozen dataclass validated on construction; a bad value raises
:class:`ParameterError`, which names the key, the value and what is allowed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace

import numpy as np

from ..errors import ParameterError
from ..methods import OPTIONS
from .aero import Aero
from .body import Body
from .units import SPEED_UNITS
from .validate import finite, non_negative, positive

FRAMES = ("nonrotating", "rotating")

#: Most blades a rotor may have (docs/case-files.md, "Limits").
MAX_BLADES = 32
#: Most speeds a sweep may have.
MAX_POINTS = 100_000
#: Most speeds a limit-cycle analysis may have.
MAX_CYCLE_POINTS = 2000
#: Most speeds [limit_cycle] confirm lists (each costs a few nonlinear runs).
MAX_CONFIRM = 8
#: Longest nonlinear run [s], and the largest disturbance it starts from [m, rad; m/s, rad/s].
MAX_DURATION = 3600.0
MAX_DISTURBANCE = 1.0
#: Most values points x (2 n)^2 of a sweep's state matrices (n coordinates):
#: an eigen-analysis holds about 60 bytes per value, so this bounds it near 1.2 GB.
MAX_SWEEP_VALUES = 20_000_000


@dataclass(frozen=True)
class Blade:
    """One rigid blade, described about its hinge.

    Parameters
    ----------
    blade_mass : float
        Mass beyond the hinge [kg].
    blade_static_moment : float
        First moment of mass about the hinge, S [kg m].
    blade_inertia : float
        Second moment of mass about the hinge, I [kg m^2].
    hinge_offset : float
        Distance from the shaft axis to the lag and flap hinge, e [m].
    lag_stiffness, flap_stiffness : float
        Root springs [N m/rad].
    lag_damping, flap_damping : float
        Blade-to-hub dampers [N m s/rad].
    """

    blade_mass: float
    blade_static_moment: float
    blade_inertia: float
    hinge_offset: float
    lag_stiffness: float = 0.0
    lag_damping: float = 0.0
    flap_stiffness: float = 0.0
    flap_damping: float = 0.0

    def __post_init__(self):
        positive(self, "blade_mass", "blade_inertia")
        non_negative(
            self,
            "blade_static_moment",
            "hinge_offset",
            "lag_stiffness",
            "lag_damping",
            "flap_stiffness",
            "flap_damping",
        )
        s, m, i = self.blade_static_moment, self.blade_mass, self.blade_inertia
        # S^2 <= m I, compared in logarithms so that no product over- or underflows
        if s > 0 and 2 * math.log(s) > math.log(m) + math.log(i) + 1e-12:
            raise ParameterError(
                "blade_static_moment",
                s,
                f"S^2 <= blade_mass * blade_inertia must hold for a real blade "
                f"(here S^2 = {float(s) * float(s):.6g} > m I = {float(m) * float(i):.6g})",
            )

    def lag_frequency(self, rotor_speed):
        """Rotating lag frequency nu [per rev]: nu^2 = K/(I Omega^2) + e S / I."""
        w = np.asarray(rotor_speed, dtype=float)
        with np.errstate(divide="ignore"):
            return np.sqrt(
                self.lag_stiffness / (self.blade_inertia * w**2)
                + self.hinge_offset * self.blade_static_moment / self.blade_inertia
            )

    def flap_frequency(self, rotor_speed):
        """Rotating flap frequency [per rev]: nu^2 = 1 + e S / I + K/(I Omega^2)."""
        w = np.asarray(rotor_speed, dtype=float)
        with np.errstate(divide="ignore"):
            return np.sqrt(
                1.0
                + self.hinge_offset * self.blade_static_moment / self.blade_inertia
                + self.flap_stiffness / (self.blade_inertia * w**2)
            )


BLADE_KEYS = tuple(f.name for f in fields(Blade))


@dataclass(frozen=True)
class Rotor:
    """N blades at equal azimuth spacing; blade k sits at Omega t + 2 pi (k-1)/N.

    Parameters
    ----------
    blades : tuple of Blade
        One entry per blade, blade 1 first.
    flap : bool
        Whether each blade has a flap degree of freedom.
    dampers : tuple of Damper
        Lag damper rods (:mod:`groundres.model.dampers`), besides each blade's own
        rotational ``lag_damping``.
    aero : Aero or None
        The blades' aerodynamics (:mod:`groundres.model.aero`): the rotor in air,
        linearised about its hover trim; None (the default): in vacuum.
    lag_laws : tuple of BladeDamper or None
        Nonlinear lag damper laws (:mod:`groundres.model.damper_laws`), one entry per blade
        (None: the blade's own linear ``lag_damping``), or empty (no laws). The blades then
        hold each law's small-motion values (:meth:`with_lag_laws`), which every linear
        analysis uses; :meth:`equivalent` gives the rotor at other amplitudes.
    """

    blades: tuple
    flap: bool = False
    dampers: tuple = ()
    aero: Aero | None = None
    lag_laws: tuple = ()

    def __post_init__(self):
        if not 2 <= len(self.blades) <= MAX_BLADES:
            raise ParameterError("blades", len(self.blades), f"a rotor needs 2 to {MAX_BLADES} blades")
        object.__setattr__(self, "dampers", tuple(self.dampers))
        object.__setattr__(self, "lag_laws", tuple(self.lag_laws))
        if self.lag_laws and len(self.lag_laws) != len(self.blades):
            raise ParameterError(
                "lag_laws", len(self.lag_laws), f"must give one entry per blade ({len(self.blades)})"
            )
        offsets = [b.hinge_offset for b in self.blades]
        for damper in self.dampers:
            damper.check(offsets, len(self.blades))
        if self.aero is not None:
            self.aero.check_hinges(offsets)

    @classmethod
    def uniform(cls, n_blades: int, blade: Blade, flap: bool = False) -> Rotor:
        """A rotor of ``n_blades`` identical blades (2 to ``MAX_BLADES``)."""
        if isinstance(n_blades, bool) or not isinstance(n_blades, int) or not 2 <= n_blades <= MAX_BLADES:
            raise ParameterError("blades", n_blades, f"must be a whole number from 2 to {MAX_BLADES}")
        return cls((blade,) * n_blades, flap)

    @property
    def n_blades(self) -> int:
        return len(self.blades)

    def inertia_about_pivot(self, h: float, dof: str = "pitch") -> float:
        """Inertia [kg m^2] of the blades about a pivot ``h`` [m] below the hub, averaged
        over azimuth: in pitch or roll sum of m h^2 + (I + 2 S e + m e^2) / 2, in yaw
        (about the shaft) sum of I + 2 S e + m e^2."""
        shaft = sum(
            b.blade_inertia + 2 * b.blade_static_moment * b.hinge_offset + b.blade_mass * b.hinge_offset**2
            for b in self.blades
        )
        if dof == "yaw":
            return shaft
        return sum(b.blade_mass * h * h for b in self.blades) + 0.5 * shaft

    @property
    def blades_alike(self) -> bool:
        """True when every blade has the same properties (damper rods aside)."""
        return all(b == self.blades[0] for b in self.blades[1:])

    @property
    def identical(self) -> bool:
        """True when the rotor looks the same from every blade: blades alike and the damper
        rods repeating from blade to blade (a failed rod among working ones breaks it)."""
        return self.repeats(1)

    def repeats(self, shift: int) -> bool:
        """Whether blade k + ``shift`` takes blade k's place exactly (its properties and the
        rods it starts)."""
        n = self.n_blades
        if not all(self.blades[k] == self.blades[(k + shift) % n] for k in range(n)):
            return False
        turned = sorted((d.turned(shift, n) for d in self.dampers), key=repr)
        return turned == sorted(self.dampers, key=repr)

    @property
    def nonlinear(self) -> bool:
        """Whether any blade's lag damper follows a law other than a linear one."""
        return any(d is not None and d.law.law != "linear" for d in self.lag_laws)

    @property
    def unsimulable_blade(self) -> int | None:
        """The first blade (0-based) whose law cannot be simulated (a table of measured properties
        gives no moment in time), None where every law can."""
        return next((k for k, d in enumerate(self.lag_laws) if d is not None and not d.law.simulable), None)

    def with_lag_laws(self, laws: tuple) -> Rotor:
        """A copy whose blades carry ``laws`` (per blade a BladeDamper or None), each such blade at
        its law's small-motion damping and stiffness."""
        blades = list(self.blades)
        for k, entry in enumerate(laws):
            if entry is not None:
                blades[k] = replace(blades[k], **entry.linear(*entry.law.small_motion()))
        return replace(self, blades=tuple(blades), lag_laws=tuple(laws))

    def equivalent(self, damping, stiffness) -> Rotor:
        """A copy whose blades with laws have equivalent linear dampers: ``damping`` [N m s/rad]
        and ``stiffness`` [N m/rad] per blade (sequences; the entries of blades without a law
        are not read)."""
        blades = list(self.blades)
        for k, entry in enumerate(self.lag_laws):
            if entry is not None:
                blades[k] = replace(blades[k], **entry.linear(damping[k], stiffness[k]))
        return replace(self, blades=tuple(blades))

    def with_blade(self, index: int, **changes) -> Rotor:
        """A copy in which blade ``index`` (1-based) has some properties changed."""
        blades = list(self.blades)
        blades[index - 1] = replace(blades[index - 1], **changes)
        return replace(self, blades=tuple(blades))


@dataclass(frozen=True)
class Sweep:
    """Rotor speeds to analyse, with reporting choices.

    Parameters
    ----------
    start, stop : float
        Rotor speed range [rad/s], 0 <= start < stop.
    points : int
        Number of equally spaced speeds, 2 to ``MAX_POINTS``.
    unit : str
        Unit used in the case file and on plot axes ("rad/s", "rpm", "Hz").
    reference : float or None
        Reference speed [rad/s]; plots show speed / reference.
    frame : str
        "nonrotating" or "rotating": the axes frequencies are seen from.
    method : str
        "auto", "eigen" or "floquet".
    operating_start, operating_stop : float or None
        The operating range of rotor speed [rad/s], inside the sweep; the
        sweep below it is the run-up. Either may be left out (None): the
        range then starts at the sweep's start or stops at its stop.
    required_damping_ratio : float or None
        The damping ratio every mode must keep over the operating range [-]
        (:mod:`groundres.assess.margins`); None: none required beyond stability.
    """

    start: float
    stop: float
    points: int = 200
    unit: str = "rad/s"
    reference: float | None = None
    frame: str = "nonrotating"
    method: str = "auto"
    operating_start: float | None = None
    operating_stop: float | None = None
    required_damping_ratio: float | None = None

    def __post_init__(self):
        non_negative(self, "start")
        positive(self, "stop")
        if self.start >= self.stop:
            raise ParameterError("start", self.start, f"must be below stop ({self.stop})")
        p = self.points
        if isinstance(p, bool) or not isinstance(p, int) or not 2 <= p <= MAX_POINTS:
            raise ParameterError("points", p, f"must be a whole number from 2 to {MAX_POINTS}")
        for key, allowed in (("unit", SPEED_UNITS), ("frame", FRAMES), ("method", OPTIONS)):
            if getattr(self, key) not in allowed:
                raise ParameterError(key, getattr(self, key), f"must be one of {list(allowed)}")
        if self.reference is not None:
            positive(self, "reference")
        for key in ("operating_start", "operating_stop"):
            value = getattr(self, key)
            if value is not None and not (finite(value) and self.start <= value <= self.stop):
                raise ParameterError(key, value, "must be a speed inside the sweep, from start to stop")
        low, high = self.operating_range
        if low >= high:
            if self.operating_start is None:
                raise ParameterError("operating_stop", high, "must be above the sweep's start")
            if self.operating_stop is None:
                raise ParameterError("operating_start", low, "must be below the sweep's stop")
            raise ParameterError("operating_start", low, "must be below operating_stop")
        ratio = self.required_damping_ratio
        if ratio is not None and not (finite(ratio) and 0 <= ratio < 1):
            raise ParameterError("required_damping_ratio", ratio, "must be a damping ratio from 0 to below 1")

    @property
    def speeds(self) -> np.ndarray:
        """The rotor speeds [rad/s], shape (points,)."""
        return np.linspace(self.start, self.stop, self.points)

    @property
    def operating_range(self) -> tuple[float, float]:
        """The operating range [rad/s]: (operating_start, operating_stop), the sweep's
        ends where they are not given."""
        low = self.start if self.operating_start is None else self.operating_start
        high = self.stop if self.operating_stop is None else self.operating_stop
        return float(low), float(high)

    @property
    def run_up(self) -> tuple[float, float] | None:
        """The run-up [rad/s]: the sweep below the operating range, or None where the range
        starts at the sweep's start."""
        low = self.operating_range[0]
        return (float(self.start), low) if low > self.start else None

    @property
    def unit_factor(self) -> float:
        """rad/s per unit of ``unit``."""
        return SPEED_UNITS[self.unit]


@dataclass(frozen=True)
class LimitCycleOptions:
    """What a limit-cycle analysis searches (``[limit_cycle]``): blade lag amplitudes from
    ``amplitude_min`` to ``amplitude_max`` [deg], at ``points`` speeds spread over the sweep."""

    amplitude_min: float = 0.001
    amplitude_max: float = 30.0
    points: int = 100
    #: Speeds [rad/s] at which ``groundres cycles`` confirms the predicted cycles by simulation.
    confirm: tuple = ()

    def __post_init__(self):
        for key in ("amplitude_max", "amplitude_min"):
            value = getattr(self, key)
            if not (finite(value) and 1e-6 <= value <= 90.0):
                raise ParameterError(key, value, "must be a finite number from 1e-6 to 90 [deg]")
        if not self.amplitude_min < self.amplitude_max:
            raise ParameterError(
                "amplitude_min", self.amplitude_min, f"must be below amplitude_max ({self.amplitude_max})"
            )
        p = self.points
        if isinstance(p, bool) or not isinstance(p, int) or not 2 <= p <= MAX_CYCLE_POINTS:
            raise ParameterError("points", p, f"must be a whole number from 2 to {MAX_CYCLE_POINTS}")
        if len(self.confirm) > MAX_CONFIRM:
            raise ParameterError("confirm", list(self.confirm), f"must list at most {MAX_CONFIRM} speeds")
        for w in self.confirm:
            if not (finite(w) and w > 0):
                raise ParameterError("confirm", list(self.confirm), "each speed must be a finite number > 0")
        if len(set(self.confirm)) != len(self.confirm):
            raise ParameterError("confirm", list(self.confirm), "must list each speed once")

    @property
    def searched(self) -> tuple[float, float]:
        """The amplitudes searched [rad]."""
        return math.radians(self.amplitude_min), math.radians(self.amplitude_max)


@dataclass(frozen=True)
class SimulationOptions:
    """How a run of the nonlinear equations goes (``[simulation]``): ``duration`` and the
    measuring ``window`` at its end [s] (None: from the motion's frequency), and its start:
    ``along_cycle`` times the predicted cycle at the speed, or the ``initial`` displacements
    [m, rad] and rates [m/s, rad/s] by coordinate name (``NAME_rate``), as (name, value) pairs."""

    duration: float | None = None
    window: float | None = None
    along_cycle: float | None = None
    initial: tuple = ()

    def __post_init__(self):
        if self.duration is not None and not (finite(self.duration) and 0 < self.duration <= MAX_DURATION):
            raise ParameterError(
                "duration", self.duration, f"must be a finite number > 0 and at most {MAX_DURATION:g} [s]"
            )
        if self.window is not None:
            top = self.duration / 2 if self.duration is not None else MAX_DURATION / 2
            if not (finite(self.window) and 0 < self.window <= top):
                half = (
                    f"{top:g} [s], half the duration given (the verdict compares two windows)"
                    if self.duration is not None
                    else f"half the run's length (at most {top:g} s: the verdict compares two windows)"
                )
                raise ParameterError("window", self.window, f"must be a finite number > 0 and at most {half}")
        if self.along_cycle is not None and not (finite(self.along_cycle) and 0 < self.along_cycle <= 100):
            raise ParameterError(
                "along_cycle", self.along_cycle, "must be a finite number > 0 and at most 100"
            )
        if self.along_cycle is not None and self.initial:
            raise ParameterError(
                "along_cycle", self.along_cycle, "give either along_cycle or [simulation.initial]"
            )
        for name, value in self.initial:
            if not (finite(value) and abs(value) <= MAX_DISTURBANCE):
                raise ParameterError(
                    f"initial.{name}",
                    value,
                    f"must be a finite number within +-{MAX_DISTURBANCE:g} [m, rad; "
                    "m/s, rad/s]: the structure holds small angles",
                )


@dataclass(frozen=True)
class Case:
    """Everything one analysis needs.

    ``source`` names where the case came from (a path or a shipped case's
    name) and ``text`` is the case file's text exactly as read, which output
    folders keep beside the results (both empty for a case built in Python);
    ``variant`` says how the case differs from its file ("in vacuum":
    :meth:`in_vacuum`), "" where it does not.
    """

    rotor: Rotor
    body: Body
    sweep: Sweep
    title: str = "groundres case"
    description: str = ""
    source: str = field(default="", compare=False)
    text: str = field(default="", compare=False, repr=False)
    variant: str = ""
    limit_cycle: LimitCycleOptions = field(default_factory=LimitCycleOptions)
    simulation: SimulationOptions = field(default_factory=SimulationOptions)

    def in_vacuum(self) -> Case:
        """The same case without its ``[aero]`` table: the rotor in vacuum (the case itself
        where it has none); its title says so and its text has the table commented out."""
        if self.rotor.aero is None:
            return self
        from .casefile import without_table

        text = (
            without_table(self.text, "aero", "in vacuum: the [aero] table below is left out")
            if self.text
            else ""
        )
        return replace(
            self,
            rotor=replace(self.rotor, aero=None),
            title=f"{self.title} (in vacuum)",
            text=text,
            variant="in vacuum",
        )

    def __post_init__(self):
        n = len(self.body.dofs) + self.rotor.n_blades * (2 if self.rotor.flap else 1)
        limit = MAX_SWEEP_VALUES // (2 * n) ** 2
        if self.sweep.points > limit:
            raise ParameterError(
                "points",
                self.sweep.points,
                f"at most {limit} speeds for this model ({n} coordinates; a sweep holds "
                f"points x (2 x {n})^2 <= {MAX_SWEEP_VALUES:.0e} values, about 1.2 GB)",
            )
