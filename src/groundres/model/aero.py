"""The rotor in air: the ``[aero]`` table's parameters, checked, and what follows from them.

A rotor with an :class:`Aero` carries quasi-steady strip-theory loads over the
lifting span (``docs/theory.md``, "The rotor in air"): the blades keep their
mass, static moment, inertia, hinge, springs and dampers; the air adds a lift
slope, a profile drag, a chord and the span it lifts over, a collective pitch
and a linear twist, and the pitch-flap and pitch-lag couplings. Without one the
rotor is in vacuum and nothing of this module is used.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import ParameterError
from .validate import finite, non_negative, positive

#: Inflow models: momentum-theory uniform inflow frozen at its trim value, or
#: Pitt-Peters dynamic inflow.
INFLOWS = ("uniform", "dynamic")
#: Largest pitch [deg] anywhere on the span: strip theory here takes small angles.
MAX_PITCH_DEG = 30.0
#: Largest value of each size of the air and the blade's section: far beyond any rotor, and
#: small enough that the loads (which grow as R^5) stay within floating point.
LARGEST = {"air_density": 1e4, "lift_slope": 100.0, "chord": 1e4, "tip_radius": 1e4, "root_cutout": 1e4}
LARGEST_UNITS = {
    "air_density": "kg/m^3",
    "lift_slope": "1/rad",
    "chord": "m",
    "tip_radius": "m",
    "root_cutout": "m",
}
#: Largest magnitude of K_Pbeta and K_Pzeta (tan 80 deg is 5.7).
MAX_COUPLING = 6.0


@dataclass(frozen=True)
class Aero:
    """Aerodynamic parameters of the blades (every blade the same), in SI.

    Parameters
    ----------
    air_density : float
        rho [kg/m^3] (0: no air, the vacuum's equations about a trim at rest).
    lift_slope : float
        a [1/rad].
    chord : float
        c [m].
    tip_radius : float
        R [m], from the shaft.
    root_cutout : float
        Where the lift starts [m], from the shaft; at or beyond every hinge.
    drag_coefficient : float
        Profile drag cd0 [-].
    collective, twist : float
        Pitch theta = collective + twist r/R [rad] (r from the shaft).
    pitch_flap : float
        K_Pbeta = tan(delta3): the pitch changes by -K_Pbeta x flap (flap up).
    pitch_lag : float
        K_Pzeta: the pitch changes by -K_Pzeta x lag (lag against the rotation).
    inflow : str
        "uniform" or "dynamic" (INFLOWS).
    lock_given : bool
        Whether the case gave the Lock number (``air_density`` was derived from it).
    """

    air_density: float
    lift_slope: float
    chord: float
    tip_radius: float
    root_cutout: float
    drag_coefficient: float = 0.0
    collective: float = 0.0
    twist: float = 0.0
    pitch_flap: float = 0.0
    pitch_lag: float = 0.0
    inflow: str = "uniform"
    lock_given: bool = False

    def __post_init__(self):
        non_negative(self, "air_density", "root_cutout", "drag_coefficient")
        positive(self, "lift_slope", "chord", "tip_radius")
        for key, largest in LARGEST.items():
            if getattr(self, key) > largest:
                raise ParameterError(
                    key, getattr(self, key), f"must be at most {largest:g} {LARGEST_UNITS[key]}"
                )
        if self.tip_radius <= self.root_cutout:
            raise ParameterError(
                "tip_radius",
                self.tip_radius,
                f"must be beyond root_cutout ({self.root_cutout:g} m): the blade lifts from the root "
                "cutout to the tip",
            )
        if self.drag_coefficient >= 1:
            raise ParameterError(
                "drag_coefficient", self.drag_coefficient, "must be a profile drag from 0 to below 1"
            )
        for key in ("collective", "twist", "pitch_flap", "pitch_lag"):
            if not finite(getattr(self, key)):
                raise ParameterError(key, getattr(self, key), "must be a finite number")
        limit = math.radians(MAX_PITCH_DEG)
        for where, pitch in (
            ("root cutout", self.pitch_at(self.root_cutout)),
            ("tip", self.pitch_at(self.tip_radius)),
        ):
            if abs(pitch) > limit:
                key = "collective" if abs(self.collective) > limit or not self.twist else "twist"
                raise ParameterError(
                    key,
                    math.degrees(getattr(self, key)),
                    f"gives a pitch of {math.degrees(pitch):.4g} deg at the {where}; strip theory here "
                    f"takes small angles, |pitch| <= {MAX_PITCH_DEG:g} deg over the span",
                )
        for key in ("pitch_flap", "pitch_lag"):
            if abs(getattr(self, key)) > MAX_COUPLING:
                raise ParameterError(key, getattr(self, key), f"must be within +-{MAX_COUPLING:g}")
        if self.inflow not in INFLOWS:
            raise ParameterError("inflow", self.inflow, f"must be one of {list(INFLOWS)}")
        if self.inflow == "dynamic" and self.air_density == 0:
            raise ParameterError(
                "inflow",
                self.inflow,
                "needs air: the inflow's apparent mass is the air's; with no air (a zero air density or "
                'Lock number) use "uniform"',
            )

    def pitch_at(self, radius: float) -> float:
        """The trim pitch [rad] at ``radius`` from the shaft, before the couplings."""
        return self.collective + self.twist * radius / self.tip_radius

    def lock_number(self, blade_inertia: float) -> float:
        """gamma = rho a c R^4 / I [-] of a blade of inertia ``blade_inertia`` about its hinge."""
        return self.air_density * self.lift_slope * self.chord * self.tip_radius**4 / blade_inertia

    def solidity(self, n_blades: int) -> float:
        """sigma = N c / (pi R) [-]."""
        return n_blades * self.chord / (math.pi * self.tip_radius)

    def disk_area(self) -> float:
        """pi R^2 [m^2]."""
        return math.pi * self.tip_radius**2

    def check_hinges(self, offsets) -> None:
        """The lifting span must lie beyond every hinge (the blade is rigid beyond it)."""
        outer = max(offsets)
        if self.root_cutout < outer * (1 - 1e-12):
            raise ParameterError(
                "root_cutout",
                self.root_cutout,
                f"must be at or beyond the hinge offset ({outer:g} m): only the blade beyond its hinge lifts",
            )
        if self.tip_radius <= outer:
            raise ParameterError(
                "tip_radius", self.tip_radius, f"must be beyond the hinge offset ({outer:g} m)"
            )

    @staticmethod
    def density_for_lock(
        lock_number: float, lift_slope: float, chord: float, tip_radius: float, inertia: float
    ):
        """rho [kg/m^3] that gives ``lock_number`` (the case gave it instead of the density)."""
        return lock_number * inertia / (lift_slope * chord * tip_radius**4)


#: The [aero] keys in degrees in a case file (radians inside).
DEGREE_KEYS = ("collective", "twist")
