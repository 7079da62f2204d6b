"""Result of a sweep: arrays with documented shapes plus metadata.

Compute returns data; plotting and files consume it (``.plot()``,
``.to_xarray()``, ``.summary()``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._version import __version__
from .identify import Modes
from .params import Case
from .stability import GROWTH_PER_RADIAN, DeutschEntry, Stability, growth_threshold


def _num(x):
    """A JSON-safe float (None for NaN or infinity)."""
    if x is None:
        return None
    x = float(x)
    return x if math.isfinite(x) else None


@dataclass
class SweepResult:
    """Modes and stability of one case over its rotor-speed sweep.

    Attributes
    ----------
    case : Case
    method : str
        "multiblade-eigen", "rotating-eigen" or "floquet".
    frame : str
        Frame of ``frequency``: "nonrotating" or "rotating".
    rotor_speed : ndarray (n_s,)
        [rad/s].
    modes : Modes
        Labelled modes (see :class:`groundres.identify.Modes`).
    stability : Stability
    deutsch : list of DeutschEntry
    exact_lag_damping : float or None
        Smallest lag damping (all blades) that makes the sweep stable [N m s/rad],
        found from the eigenvalues; None if no value up to a large cap does.
    coordinates : list of Coordinate
        Nonrotating coordinates of the mode shapes (``modes.shape``).
    weights : ndarray (n_s, n)
        Kinetic weight (mass-matrix diagonal) of each coordinate.
    accuracy : dict, optional
        How the roots were found and how accurately (solver, tolerances, step
        counts, growth threshold), JSON-ready; output folders record it.
    """

    case: Case
    method: str
    frame: str
    rotor_speed: np.ndarray
    modes: Modes
    stability: Stability
    deutsch: list
    exact_lag_damping: float | None
    coordinates: list
    weights: np.ndarray | None = None
    accuracy: dict | None = None

    @property
    def labels(self) -> list[str]:
        return self.modes.labels

    @property
    def frequency(self) -> np.ndarray:
        """Modal frequency [rad/s] in the result's frame, shape (n_s, n_m)."""
        if self.frame == "rotating":
            return self.modes.frequency_rotating
        return self.modes.frequency_nonrotating

    @property
    def real_part(self) -> np.ndarray:
        """Largest real part of each mode [1/s], shape (n_s, n_m)."""
        return self.modes.real_part

    @property
    def damping_ratio(self) -> np.ndarray:
        """Damping ratio of each mode [-], shape (n_s, n_m)."""
        return self.modes.damping_ratio

    def unstable_modes(self, start: float, end: float) -> list[str]:
        """Labels of the modes that grow somewhere in [start, end] [rad/s]."""
        w = self.rotor_speed
        inside = (w >= start) & (w <= end)
        if not inside.any():
            inside = np.abs(w - 0.5 * (start + end)) == np.abs(w - 0.5 * (start + end)).min()
        grows = (self.real_part[inside] > growth_threshold(w[inside])[:, None]).any(0)
        if not grows.any():
            grows = self.real_part[inside].max(0) == self.real_part[inside].max()
        return [lab for lab, g in zip(self.labels, grows) if g]

    def mode(self, label: str, speed: float):
        """The mode ``label`` at the sweep speed nearest ``speed`` [rad/s].

        Returns
        -------
        ModeShape
            Phasors, whirl decomposition and motion (see :mod:`groundres.shapes`).

        Examples
        --------
        >>> result.mode("regressive lag", speed=26.0).whirl()["centre_of_mass"]  # doctest: +SKIP
        """
        from .shapes import ModeShape

        if label not in self.labels:
            raise KeyError(f"mode {label!r}: not a mode of this case; choose one of {', '.join(self.labels)}")
        i = int(np.argmin(np.abs(self.rotor_speed - speed)))
        j = self.labels.index(label)
        m = self.modes
        blades = self.case.rotor.blades
        return ModeShape(
            label=label,
            rotor_speed=float(self.rotor_speed[i]),
            eigenvalue=complex(m.eigenvalue[i, j]),
            coordinates=self.coordinates,
            harmonics=m.harmonics[i, :, :, j],
            orders=m.harmonic_orders,
            weights=self.weights[i],
            n_blades=len(blades),
            cg_arm=float(np.mean([b.blade_static_moment / b.blade_mass for b in blades])),
            hub_height=self.case.body.hub_height,
            rotating_frequency=float(m.frequency_rotating[i, j]),
        )

    def _mode_at(self, speed: float, values) -> str:
        i = int(np.argmin(np.abs(self.rotor_speed - speed)))
        return self.labels[int(np.nanargmax(values[i]))]

    def summary(self) -> dict:
        """The summary.json content (see docs/case-files.md)."""
        st = self.stability
        blades = self.case.rotor.blades
        installed = min(b.lag_damping for b in blades)
        return {
            "title": self.case.title,
            "groundres_version": __version__,
            "method": self.method,
            "frame": self.frame,
            "speed_unit": "rad/s",
            "stable": st.stable,
            "unstable_ranges": [
                {"start": s, "end": e, "modes": self.unstable_modes(s, e)} for s, e in st.unstable_ranges
            ],
            "max_real_part": {
                "value": _num(st.max_real_part[0]),
                "speed": _num(st.max_real_part[1]),
                "mode": self._mode_at(st.max_real_part[1], self.real_part),
            },
            "min_damping_ratio": {
                "value": _num(st.min_damping_ratio[0]),
                "speed": _num(st.min_damping_ratio[1]),
                "mode": self._mode_at(
                    st.min_damping_ratio[1], -np.nan_to_num(self.damping_ratio, nan=np.inf)
                ),
            },
            "growth_threshold_per_radian": GROWTH_PER_RADIAN,
            "case": {
                "source": self.case.source,
                "blades": self.case.rotor.n_blades,
                "flap": self.case.rotor.flap,
                "body_dofs": list(self.case.body.dofs),
                "identical_blades": self.case.rotor.identical,
                "isotropic_body": self.case.body.isotropic,
            },
            "sweep": {
                "start": float(self.rotor_speed[0]),
                "stop": float(self.rotor_speed[-1]),
                "points": int(len(self.rotor_speed)),
                "unit_in_case": self.case.sweep.unit,
                "reference": _num(self.case.sweep.reference),
            },
            "modes": list(self.labels),
            "lag_damping": {
                "unit": "N m s/rad",
                "installed": installed,
                "exact_minimum": _num(self.exact_lag_damping),
                "exact_minimum_note": (
                    "smallest lag damping, the same on every blade, for which no root grows "
                    "anywhere in the sweep (eigenvalues; body damping as installed)"
                ),
                "deutsch": [_deutsch_entry(e) for e in self.deutsch],
                "deutsch_note": (
                    "Deutsch criterion at exact tuning Omega (1 - nu) = omega_b, light damping: "
                    "planar C_b C_lag >= (N/4) S^2 omega_b^2 (1-nu)/nu; isotropic "
                    "C_h C_lag >= (N/2) S^2 omega_h^2 (1-nu)/nu; omega_b includes the rotor mass"
                ),
            },
        }

    def dataset(self):
        """The sweep as plain arrays: ``(coords, variables, attrs)``.

        ``coords`` and ``variables`` map names to ``(dims, values, attrs)``; this
        is the single description behind :meth:`to_xarray` and ``modes.nc``.
        """
        speed = self.rotor_speed
        unstable = np.zeros(len(speed), np.int8)
        for s, e in self.stability.unstable_ranges:
            unstable[(speed >= s) & (speed <= e)] = 1
        coords = {
            "speed": (("speed",), speed, {"units": "rad/s", "long_name": "rotor speed"}),
            "mode": (("mode",), np.array(self.labels, dtype=object), {"long_name": "mode label"}),
            "coordinate": (
                ("coordinate",),
                np.array([c.symbol for c in self.coordinates], dtype=object),
                {"long_name": "nonrotating coordinate of the mode shapes (body, multiblade)"},
            ),
            "harmonic": (
                ("harmonic",),
                np.asarray(self.modes.harmonic_orders, dtype=np.int32),
                {"long_name": "harmonic order m: frequency offset m * rotor speed from the mode's frequency"},
            ),
            "root": (
                ("root",),
                np.arange(self.modes.root_label.shape[1], dtype=np.int32),
                {"long_name": "tracked root: one continuous branch of the sweep"},
            ),
        }
        both = ("speed", "mode")
        variables = {
            "frequency": (
                both,
                self.frequency,
                {"units": "rad/s", "long_name": f"modal frequency, {self.frame} frame"},
            ),
            "frequency_nonrotating": (
                both,
                self.modes.frequency_nonrotating,
                {"units": "rad/s", "long_name": "modal frequency, nonrotating frame"},
            ),
            "frequency_rotating": (
                both,
                self.modes.frequency_rotating,
                {"units": "rad/s", "long_name": "modal frequency, rotating frame"},
            ),
            "real_part": (
                both,
                self.real_part,
                {"units": "1/s", "long_name": "largest real part of the mode"},
            ),
            "damping_ratio": (both, self.damping_ratio, {"units": "1", "long_name": "damping ratio"}),
            "shape_real": (
                both + ("coordinate",),
                np.moveaxis(self.modes.shape, 1, 2).real,
                {"long_name": "mode shape (nonrotating), real part; m for x y, rad for angles"},
            ),
            "shape_imag": (
                both + ("coordinate",),
                np.moveaxis(self.modes.shape, 1, 2).imag,
                {"long_name": "mode shape (nonrotating), imaginary part"},
            ),
            "participation": (
                both + ("harmonic",),
                self.modes.participation,
                {"units": "1", "long_name": "share of each harmonic in the mode, nonrotating frame"},
            ),
            "exchange": _flag(
                both,
                self.modes.exchange,
                "the label moved to another branch since the previous speed (veering)",
                "same_branch exchanged",
            ),
            "harmonic_change": _flag(
                both,
                self.modes.harmonic_change,
                "the nonrotating frequency moved to another harmonic of its root since "
                "the previous speed (that harmonic holds clearly more of the label's content)",
                "continuous moved",
            ),
            "harmonic_change_rotating": _flag(
                both,
                self.modes.harmonic_change_rotating,
                "the same for the rotating-frame frequency",
                "continuous moved",
            ),
            "root_mode": (
                ("speed", "root"),
                self.modes.root_label.astype(np.int32),
                {"long_name": "index (into mode) of the mode the root belongs to"},
            ),
            "root_real_part": (
                ("speed", "root"),
                self.modes.root_real_part,
                {"units": "1/s", "long_name": "real part of the root"},
            ),
            "unstable": _flag(("speed",), unstable, "speed lies in an unstable range", "stable unstable"),
        }
        attrs = {
            "title": self.case.title,
            "groundres_version": __version__,
            "method": self.method,
            "frame": self.frame,
            "unstable_ranges_rad_per_s": np.array(self.stability.unstable_ranges, float).ravel(),
        }
        return coords, variables, attrs

    def to_xarray(self):
        """The sweep as an xarray Dataset (dims ``speed``, ``mode``)."""
        import xarray as xr

        coords, variables, attrs = self.dataset()
        return xr.Dataset(variables, coords=coords, attrs=attrs)

    def plot(self, **kwargs):
        """Coleman diagram (see :func:`groundres.plotting.coleman.coleman_diagram`)."""
        from .plotting.coleman import coleman_diagram

        return coleman_diagram(self, **kwargs)


def _flag(dims, values, long_name, meanings):
    """A 0/1 variable of the data set, with CF flag attributes."""
    return (
        dims,
        np.asarray(values).astype(np.int8),
        {"long_name": long_name, "flag_values": np.array([0, 1], np.int8), "flag_meanings": meanings},
    )


def _deutsch_entry(e: DeutschEntry) -> dict:
    return {
        "body_mode": e.body_mode,
        "form": e.form,
        "body_frequency": _num(e.body_frequency),
        "tuning_speed": _num(e.tuning_speed),
        "lag_frequency_per_rev": _num(e.lag_frequency),
        "body_damping": _num(e.body_damping),
        "required_lag_damping": None
        if e.required_lag_damping is None
        else ("infinite" if math.isinf(e.required_lag_damping) else e.required_lag_damping),
        "installed_lag_damping": e.installed_lag_damping,
        "satisfied": e.satisfied,
    }
