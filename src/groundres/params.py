"""Physical description of a case: blades, rotor, body and speed sweep, in SI.

Every class is a frozen dataclass validated on construction; a bad value raises
:class:`ParameterError`, which names the key, the value and what is allowed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace

import numpy as np

BODY_DOFS = ("x", "y", "pitch", "roll")
SPEED_UNITS = {"rad/s": 1.0, "rpm": 2.0 * math.pi / 60.0, "Hz": 2.0 * math.pi}
#: How a frequency reads in a case whose speeds are in each unit (rpm: cycles/min).
FREQUENCY_UNITS = {"rad/s": "rad/s", "rpm": "cycles/min", "Hz": "Hz"}
FRAMES = ("nonrotating", "rotating")
METHODS = ("auto", "eigen", "floquet")

#: Most blades a rotor may have (docs/case-files.md, "Limits").
MAX_BLADES = 32
#: Most speeds a sweep may have.
MAX_POINTS = 100_000
#: Most values points x (2 n)^2 of a sweep's state matrices (n coordinates):
#: an eigen-analysis holds about 60 bytes per value, so this bounds it near 1.2 GB.
MAX_SWEEP_VALUES = 20_000_000


def shown(value) -> str:
    """``repr(value)`` fit for a one-line message: long whole numbers and texts shortened."""
    if isinstance(value, int) and not isinstance(value, bool):
        digits = math.floor(abs(value).bit_length() * math.log10(2)) + 1 if value else 1
        if digits > 20:
            if digits > 4000:  # too long to convert to text at all
                return f"{'-' if value < 0 else ''}<a whole number of about {digits} digits>"
            text = str(value)
            return f"{text[:8]}...{text[-4:]} ({len(text.lstrip('-'))} digits)"
        return repr(value)
    text = repr(value)
    return text if len(text) <= 60 else f"{text[:40]}...{text[-12:]}"


def finite(value) -> bool:
    """Whether ``value`` is a number (not a bool) that a float holds finitely."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return False
    try:
        return math.isfinite(value)
    except OverflowError:  # a whole number beyond the float range
        return False


class ParameterError(ValueError):
    """A parameter value outside what the model allows.

    Attributes
    ----------
    key : str
        Name of the parameter (dotted path once the case reader adds its table).
    value : object
        The offending value.
    allowed : str
        What is allowed, in words.
    """

    def __init__(self, key: str, value, allowed: str):
        self.key, self.value, self.allowed = key, value, allowed
        super().__init__(f"{key} = {shown(value)}: {allowed}")

    def under(self, prefix: str) -> ParameterError:
        """The same error with its key placed under a table name."""
        return ParameterError(f"{prefix}.{self.key}" if prefix else self.key, self.value, self.allowed)


def _positive(obj, *names):
    for name in names:
        value = getattr(obj, name)
        if not (finite(value) and value > 0):
            raise ParameterError(name, value, "must be a finite number > 0")


def _non_negative(obj, *names):
    for name in names:
        value = getattr(obj, name)
        if not (finite(value) and value >= 0):
            raise ParameterError(name, value, "must be a finite number >= 0")


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
        _positive(self, "blade_mass", "blade_inertia")
        _non_negative(
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
    """

    blades: tuple
    flap: bool = False

    def __post_init__(self):
        if not 2 <= len(self.blades) <= MAX_BLADES:
            raise ParameterError("blades", len(self.blades), f"a rotor needs 2 to {MAX_BLADES} blades")

    @classmethod
    def uniform(cls, n_blades: int, blade: Blade, flap: bool = False) -> Rotor:
        """A rotor of ``n_blades`` identical blades (2 to ``MAX_BLADES``)."""
        if isinstance(n_blades, bool) or not isinstance(n_blades, int) or not 2 <= n_blades <= MAX_BLADES:
            raise ParameterError("blades", n_blades, f"must be a whole number from 2 to {MAX_BLADES}")
        return cls((blade,) * n_blades, flap)

    @property
    def n_blades(self) -> int:
        return len(self.blades)

    def inertia_about_pivot(self, h: float) -> float:
        """Pitch or roll inertia [kg m^2] of the blades about a pivot ``h`` [m] below
        the hub, averaged over azimuth: sum of m h^2 + (I + 2 S e + m e^2) / 2."""
        return sum(
            b.blade_mass * h * h
            + 0.5
            * (
                b.blade_inertia
                + 2 * b.blade_static_moment * b.hinge_offset
                + b.blade_mass * b.hinge_offset**2
            )
            for b in self.blades
        )

    @property
    def identical(self) -> bool:
        """True when every blade has the same properties."""
        return all(b == self.blades[0] for b in self.blades[1:])

    def with_blade(self, index: int, **changes) -> Rotor:
        """A copy in which blade ``index`` (1-based) has some properties changed."""
        blades = list(self.blades)
        blades[index - 1] = replace(blades[index - 1], **changes)
        return replace(self, blades=tuple(blades))


@dataclass(frozen=True)
class Body:
    """The helicopter on its landing gear: any subset of x, y, pitch, roll.

    Masses and inertias EXCLUDE the blades. x, y move the pivot (and the hub
    with it); pitch (nose up) and roll (right side down) turn the body about the
    pivot, which is ``hub_height`` below the hub and is the body's centre of mass.

    Parameters
    ----------
    dofs : tuple of str
        Body degrees of freedom, a subset of ("x", "y", "pitch", "roll"), in any
        order; stored in that order of BODY_DOFS (the model's coordinates).
    mass_x, mass_y : float
        Translating masses [kg].
    inertia_pitch, inertia_roll : float
        Inertias about the pivot [kg m^2].
    stiffness_x, stiffness_y : float
        [N/m]; stiffness_pitch, stiffness_roll [N m/rad].
    damping_x, damping_y : float
        [N s/m]; damping_pitch, damping_roll [N m s/rad].
    hub_height : float
        Hub centre above the pivot [m].
    """

    dofs: tuple = ("x", "y")
    mass_x: float = 0.0
    mass_y: float = 0.0
    inertia_pitch: float = 0.0
    inertia_roll: float = 0.0
    stiffness_x: float = 0.0
    stiffness_y: float = 0.0
    stiffness_pitch: float = 0.0
    stiffness_roll: float = 0.0
    damping_x: float = 0.0
    damping_y: float = 0.0
    damping_pitch: float = 0.0
    damping_roll: float = 0.0
    hub_height: float = 0.0

    def __post_init__(self):
        dofs = tuple(self.dofs)
        object.__setattr__(self, "dofs", dofs)
        if not dofs:
            raise ParameterError("dofs", list(dofs), f"needs at least one of {list(BODY_DOFS)}")
        for d in dofs:
            if d not in BODY_DOFS:
                raise ParameterError("dofs", list(dofs), f"each entry must be one of {list(BODY_DOFS)}")
        if len(set(dofs)) != len(dofs):
            raise ParameterError("dofs", list(dofs), "each degree of freedom may appear once")
        # a subset: its order carries no meaning, the model's coordinates follow BODY_DOFS
        object.__setattr__(self, "dofs", tuple(d for d in BODY_DOFS if d in dofs))
        for d in dofs:
            _positive(self, self.inertia_key(d))
            _non_negative(self, f"stiffness_{d}", f"damping_{d}")
        if {"pitch", "roll"} & set(dofs):
            h = self.hub_height
            if not finite(h):
                raise ParameterError("hub_height", h, "must be a finite number [m]")

    @staticmethod
    def inertia_key(dof: str) -> str:
        """Name of the mass or inertia parameter of a body degree of freedom."""
        return f"mass_{dof}" if dof in ("x", "y") else f"inertia_{dof}"

    def value(self, kind: str, dof: str) -> float:
        """``kind`` is "inertia" (mass or inertia), "stiffness" or "damping"."""
        key = self.inertia_key(dof) if kind == "inertia" else f"{kind}_{dof}"
        return getattr(self, key)

    def pair_isotropic(self, a: str, b: str) -> bool:
        """Whether two body dofs are both present with equal inertia, stiffness and damping."""
        if a not in self.dofs or b not in self.dofs:
            return False
        return all(
            math.isclose(self.value(k, a), self.value(k, b), rel_tol=1e-12, abs_tol=0.0)
            for k in ("inertia", "stiffness", "damping")
        )

    @property
    def isotropic(self) -> bool:
        """True when the support looks the same in every direction of the rotor plane.

        Translation needs x and y both present and identical (or both absent);
        likewise pitch and roll.
        """
        ok = True
        for a, b in (("x", "y"), ("pitch", "roll")):
            present = (a in self.dofs) + (b in self.dofs)
            ok &= present == 0 or self.pair_isotropic(a, b)
        return ok


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
    """

    start: float
    stop: float
    points: int = 200
    unit: str = "rad/s"
    reference: float | None = None
    frame: str = "nonrotating"
    method: str = "auto"

    def __post_init__(self):
        _non_negative(self, "start")
        _positive(self, "stop")
        if self.start >= self.stop:
            raise ParameterError("start", self.start, f"must be below stop ({self.stop})")
        p = self.points
        if isinstance(p, bool) or not isinstance(p, int) or not 2 <= p <= MAX_POINTS:
            raise ParameterError("points", p, f"must be a whole number from 2 to {MAX_POINTS}")
        for key, allowed in (("unit", SPEED_UNITS), ("frame", FRAMES), ("method", METHODS)):
            if getattr(self, key) not in allowed:
                raise ParameterError(key, getattr(self, key), f"must be one of {list(allowed)}")
        if self.reference is not None:
            _positive(self, "reference")

    @property
    def speeds(self) -> np.ndarray:
        """The rotor speeds [rad/s], shape (points,)."""
        return np.linspace(self.start, self.stop, self.points)

    @property
    def unit_factor(self) -> float:
        """rad/s per unit of ``unit``."""
        return SPEED_UNITS[self.unit]


@dataclass(frozen=True)
class Case:
    """Everything one analysis needs.

    ``source`` names where the case came from (a path or a shipped case's
    name) and ``text`` is the case file's text exactly as read, which output
    folders keep beside the results (both empty for a case built in Python).
    """

    rotor: Rotor
    body: Body
    sweep: Sweep
    title: str = "groundres case"
    description: str = ""
    source: str = field(default="", compare=False)
    text: str = field(default="", compare=False, repr=False)

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
