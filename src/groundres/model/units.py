"""Units: of the rotor speed and how a speed reads in it, of every case key, and the mass unit.

**SI inside.** Every number groundres computes with is SI, speeds in rad/s.
A case file gives its speeds in its ``[sweep] unit`` (:data:`SPEED_UNITS`);
what a person reads, on the terminal or on a page, is in that unit too (a
frequency of an rpm case in cycles/min), with "ref", the ratio to the case's
reference speed (:func:`fmt_speed`). Data files stay SI.

**Case keys.** :func:`key_unit` gives the unit of any number key of a case
file, in the case file's notation (``kg m^2``); :func:`udunits` writes it as
the CF conventions of NetCDF files do (``kg m2``).

**The mass unit.** Every coefficient of the equations is linear in the
masses, static moments, inertias, springs and dampers, so dividing all of
them by one mass unit changes no root and no mode shape. Where the inertias
of a case lie outside 2^+-:data:`MASS_RANGE` kg (kg m^2), its equations are
computed in a :class:`MassUnit` that is a power of two near the largest one:
exact in floating point, so that their products cannot overflow or
underflow. Lengths and speeds are used as given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np

from .damper_laws import UNITS as LAW_UNITS

#: rad/s per unit of rotor speed a case file may use.
SPEED_UNITS = {"rad/s": 1.0, "rpm": 2.0 * math.pi / 60.0, "Hz": 2.0 * math.pi}
#: How a frequency reads in a case whose speeds are in each unit (rpm: cycles/min).
FREQUENCY_UNITS = {"rad/s": "rad/s", "rpm": "cycles/min", "Hz": "Hz"}

# -- how numbers read ---------------------------------------------------------------


def fmt_speed(w, sweep, digits: int = 5, ref: bool = True, unit: bool = True, sep: str = " "):
    """A speed [rad/s] in the case's unit (``unit``: its name too), with its ratio
    to the reference ("ref") after ``sep``."""
    text = f"{w / SPEED_UNITS[sweep.unit]:.{digits}g}" + (f" {sweep.unit}" if unit else "")
    if ref and sweep.reference:
        text += f"{sep}({w / sweep.reference:.4g} ref)"
    return text


def fmt_frequency(w, sweep, digits: int = 4):
    """A frequency [rad/s] in the case's unit (cycles/min for rpm), rad/s beside it."""
    text = f"{w / SPEED_UNITS[sweep.unit]:.{digits}g} {FREQUENCY_UNITS[sweep.unit]}"
    return text if sweep.unit == "rad/s" else f"{text} ({w:.{digits}g} rad/s)"


def speed_text(w: float, speed_unit=("rad/s", 1.0)) -> str:
    """A speed [rad/s] in a case's unit (name, rad/s per unit), with rad/s beside it."""
    name, factor = speed_unit
    return f"{w:.4g} rad/s" if factor == 1.0 else f"{w / factor:.4g} {name} ({w:.4g} rad/s)"


def ref_note(sweep) -> str | None:
    """The line that explains "ref" once, or None without a reference speed."""
    if not sweep.reference:
        return None
    return f"ref: rotor speed / the case's reference speed, {fmt_speed(sweep.reference, sweep, ref=False)}."


def significant(value: float, rtol: float) -> str:
    """``value`` to the digits its relative tolerance ``rtol`` supports (1e-4: 4 significant digits)."""
    return f"{value:.{max(1, round(-math.log10(rtol)))}g}"


# -- units of case keys -------------------------------------------------------------

#: Units of the blades' keys (``[rotor]`` and ``[[rotor.blade]]``).
BLADE_UNITS = {
    "blade_mass": "kg",
    "blade_static_moment": "kg m",
    "blade_inertia": "kg m^2",
    "hinge_offset": "m",
    "lag_stiffness": "N m/rad",
    "lag_damping": "N m s/rad",
    "flap_stiffness": "N m/rad",
    "flap_damping": "N m s/rad",
}
#: Units of the body's keys by kind (``<kind>_<dof>``, a leg's ``<kind>_<axis>``):
#: (along a translation, about a rotation).
BODY_UNITS = {
    "mass": ("kg", "kg"),
    "inertia": ("kg m^2", "kg m^2"),
    "stiffness": ("N/m", "N m/rad"),
    "damping": ("N s/m", "N m s/rad"),
}
#: Units of a damper rod's keys (``[[rotor.damper]]``): along the rod; its ends in m.
ROD_UNITS = {"damping": "N s/m", "stiffness": "N/m"}
#: Units of the other number keys.
OTHER_UNITS = {
    "blades": "1",
    "points": "1",
    "hub_height": "m",
    "hub_x": "m",
    "hub_y": "m",
    "mass": "kg",
}
#: Units of the ``[aero]`` keys.
AERO_UNITS = {
    "air_density": "kg/m^3",
    "lock_number": "1",
    "lift_slope": "1/rad",
    "drag_coefficient": "1",
    "chord": "m",
    "tip_radius": "m",
    "root_cutout": "m",
    "collective": "deg",
    "twist": "deg",
    "pitch_flap": "1",
    "pitch_lag": "1",
}
_TRANSLATIONS = ("x", "y", "z")


def key_unit(key: str, sweep_unit: str = "rad/s") -> str:
    """The unit of a dotted case key (``rotor.lag_damping``, ``body.gear[2].stiffness_z``,
    ``sweep.stop``), in the case file's notation; a speed is in ``sweep_unit``; "" for a
    key that holds no number."""
    name = key.rpartition(".")[2]
    if key in ("sweep.start", "sweep.stop", "sweep.reference"):
        return sweep_unit
    if key.startswith("rotor.damper"):
        return ROD_UNITS.get(name, "m")
    if ".lag_damper." in key or key.startswith("rotor.lag_damper."):  # (a law's keys)
        return LAW_UNITS.get(name, "")
    if key.startswith("aero."):
        return AERO_UNITS.get(name, "")
    if name.startswith(("position_", "centre_", "start_", "end_")):
        return "m"
    if name in BLADE_UNITS:
        return BLADE_UNITS[name]
    if name in OTHER_UNITS:
        return OTHER_UNITS[name]
    kind, _, axis = name.partition("_")  # mass_x, stiffness_pitch, damping_roll, inertia_xy
    if kind not in BODY_UNITS:
        return ""
    return BODY_UNITS[kind][0 if axis in _TRANSLATIONS or kind in ("mass", "inertia") else 1]


def udunits(unit: str) -> str:
    """A unit as the CF conventions write it (UDUNITS: ``kg m^2`` -> ``kg m2``)."""
    return unit.replace("^", "")


# -- the mass unit ------------------------------------------------------------------

#: Inertias inside 2^+-MASS_RANGE are used as given; outside, a mass unit is used.
MASS_RANGE = 200
_BODY_KINDS = ("mass", "inertia_", "stiffness_", "damping_")
_BY_MASS = ("stiffness", "damping")  # (of a leg or a damper rod: scale with the mass unit)


@dataclass(frozen=True)
class MassUnit:
    """The mass unit a case's equations are computed in (module docstring).

    Parameters
    ----------
    kg : float
        Its size [kg]: 1, or a power of two (exact in floating point).
    """

    kg: float = 1.0

    @classmethod
    def of(cls, rotor, body) -> MassUnit:
        """1 kg unless the inertias of ``rotor`` and ``body`` lie outside 2^+-MASS_RANGE,
        else the power of two nearest the largest."""
        big = max(_inertias(rotor, body))
        if 2.0**-MASS_RANGE <= big <= 2.0**MASS_RANGE:
            return cls()
        return cls(math.ldexp(1.0, min(round(math.log2(big)), 1023)))  # (2^1024 is no float)

    @property
    def si(self) -> bool:
        """Whether this is the kilogram itself (the equations are SI)."""
        return self.kg == 1.0

    def scale(self, rotor, body):
        """Rotor and body with every mass-like parameter (masses, static moments,
        inertias, springs, dampers) in this unit: divided by :attr:`kg`, exactly."""
        if self.si:
            return rotor, body
        blades = tuple(replace(b, **_divided(b, self.kg, _blade_mass_like(b))) for b in rotor.blades)
        body_keys = [f.name for f in fields(body) if f.name.startswith(_BODY_KINDS) and getattr(body, f.name)]
        changes = _divided(body, self.kg, body_keys)
        changes["gear"] = tuple(_by_mass(leg, self.kg) for leg in body.gear)
        dampers = tuple(_by_mass(d, self.kg) for d in rotor.dampers)
        air = rotor.aero and replace(rotor.aero, air_density=rotor.aero.air_density / self.kg)
        return replace(rotor, blades=blades, dampers=dampers, aero=air), replace(body, **changes)

    def from_si(self, value):
        """A mass-like value [SI] in this unit."""
        return value if self.si else value / self.kg

    def to_si(self, value):
        """A mass-like value in this unit back in SI (None stays None; beyond the float
        range it is infinite)."""
        if value is None or self.si:
            return value
        with np.errstate(over="ignore"):
            return value * self.kg


#: The kilogram: equations in SI.
SI = MassUnit()


def _inertias(rotor, body) -> list[float]:
    values = [v for b in rotor.blades for v in (b.blade_mass, b.blade_inertia, b.blade_static_moment)]
    if body.form == "rigid":
        values += [body.mass, *np.abs(np.linalg.eigvalsh(body.inertia_tensor()))]
    else:
        values += [body.value("inertia", d) for d in body.dofs]
    return [v for v in values if v > 0]


def _blade_mass_like(blade) -> list[str]:
    return [f.name for f in fields(blade) if f.name != "hinge_offset"]


def _divided(part, kg: float, names) -> dict:
    return {name: getattr(part, name) / kg for name in names}


def _by_mass(part, kg: float):
    """A leg or damper rod with its stiffnesses and dampings divided by ``kg``."""
    return replace(part, **_divided(part, kg, [f.name for f in fields(part) if f.name.startswith(_BY_MASS)]))
