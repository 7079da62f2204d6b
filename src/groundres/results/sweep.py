"""Result of a sweep: arrays with documented shapes plus metadata.

Compute returns data; plotting and files consume it (``.plot()``,
``.to_xarray()``, ``.summary()``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..assess.margins import Margins
from ..assess.stability import Stability, growth_threshold
from ..methods import Method
from ..model.params import Case
from ..model.trim import Trim
from ..modes.identify import Modes


@dataclass
class SweepResult:
    """Modes and stability of one case over its rotor-speed sweep.

    Attributes
    ----------
    case : Case
    method : Method
        The analysis (:class:`groundres.methods.Method`, a str: "multiblade-eigen",
        "rotating-eigen" or "floquet"); ``method.option`` repeats it.
    frame : str
        Frame of ``frequency``: "nonrotating" or "rotating".
    rotor_speed : ndarray (n_s,)
        [rad/s].
    modes : Modes
        Labelled modes (see :class:`groundres.modes.identify.Modes`).
    stability : Stability
    deutsch : list of DeutschEntry
    exact_lag_damping : float or None
        Smallest lag damping (all blades) that makes the sweep stable [N m s/rad],
        found from the roots; None if no value up to a large cap does, or if
        the sweep is unstable where lag damping decides nothing.
    no_exact_lag_damping : tuple or None
        Why ``exact_lag_damping`` is None: ("cap", largest damping tried
        [N m s/rad]), ("below", speed [rad/s] below which the sweep is
        unstable and the search does not look: half the lowest body frequency)
        or ("skipped", None) where the search was not asked for, or ("afforded",
        strongest damper a Floquet scan can follow [N m s/rad]).
    coordinates : list of Coordinate
        Nonrotating coordinates of the mode shapes (``modes.shape``).
    weights : ndarray (n_s, n)
        Kinetic weight (mass-matrix diagonal) of each coordinate [kg, kg m^2];
        only their ratios are used (mode-shape normalisation), and where the
        SI values would overflow they are given in the computation's mass unit.
    accuracy : dict, optional
        How the roots were found and how accurately (solver, tolerances, step
        counts, growth threshold), JSON-ready; output folders record it.
    margins : Margins, optional
        The damping each mode keeps over the operating range and the run-up,
        against the requirement (:class:`groundres.assess.margins.Margins`).
    between : dict, optional
        (start, end) -> {label: root} of the modes that grow at the peak of each unstable range
        that holds none of the sweep's speeds (the modes identified there on their own:
        interpolating the sweep's across such a range could name the wrong ones).
    trim : Trim, optional
        The hover trim at every speed of a rotor in air (:class:`groundres.model.trim.Trim`);
        None in vacuum.
    """

    case: Case
    method: Method
    frame: str
    rotor_speed: np.ndarray
    modes: Modes
    stability: Stability
    deutsch: list
    exact_lag_damping: float | None
    coordinates: list
    weights: np.ndarray | None = None
    no_exact_lag_damping: tuple | None = None
    accuracy: dict | None = None
    margins: Margins | None = None
    between: dict | None = None
    trim: Trim | None = None

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
        if not inside.any() and self.between and (start, end) in self.between:
            return list(self.between[(start, end)])
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
            Phasors, whirl decomposition and motion (see :mod:`groundres.results.shapes`).

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
            hub_x=self.case.body.hub_x,
            hub_y=self.case.body.hub_y,
            rotating_frequency=float(m.frequency_rotating[i, j]),
        )

    def _mode_at(self, speed: float, values) -> str:
        for labels in self._between_at(speed):  # (a growing mode between the sweep's speeds)
            return labels[0]
        i = int(np.argmin(np.abs(self.rotor_speed - speed)))
        return self.labels[int(np.nanargmax(values[i]))]

    def _between_at(self, speed: float) -> list:
        """The growing modes of the unstable range between the sweep's speeds holding ``speed``."""
        return [list(roots) for (a, b), roots in (self.between or {}).items() if a <= speed <= b and roots]

    def summary(self) -> dict:
        """The summary.json content (see :mod:`groundres.results.summary` and docs/case-files.md)."""
        from .summary import summary

        return summary(self)

    def dataset(self):
        """The sweep as plain arrays: ``(coords, variables, attrs)``.

        ``coords`` and ``variables`` map names to ``(dims, values, attrs)``; this
        is the single description behind :meth:`to_xarray` and ``modes.nc``
        (CF conventions, see :mod:`groundres.results.dataset`).
        """
        from .dataset import dataset

        return dataset(self)

    def __repr__(self) -> str:
        from .display import sweep_text

        return sweep_text(self)

    def _repr_html_(self) -> str:
        from .display import sweep_html

        return sweep_html(self)

    def to_dataframe(self):
        """The sweep as tidy rows (a pandas DataFrame): speed, mode, frequency, real part,
        damping ratio, in the case's unit (:mod:`groundres.results.rows`).

        Examples
        --------
        >>> df = result.to_dataframe()  # doctest: +SKIP
        >>> df[df["mode"] == "regressive lag"].plot(x="speed", y="damping_ratio")  # doctest: +SKIP
        """
        from .rows import to_dataframe

        return to_dataframe(self)

    def to_xarray(self):
        """The sweep as an xarray Dataset (dims ``speed``, ``mode``)."""
        import xarray as xr

        coords, variables, attrs = self.dataset()
        return xr.Dataset(variables, coords=coords, attrs=attrs)

    def plot(
        self,
        fig=None,
        show_damping_ratio: bool = False,
        *,
        speed_axis: str = "auto",
        frequency_limits=None,
        real_limits=None,
        modes=None,
        ax=None,
    ):
        """Coleman diagram (a matplotlib Figure).

        Parameters
        ----------
        fig : matplotlib Figure or SubFigure, optional
            An empty figure or subfigure to draw in; a new figure if None.
        show_damping_ratio : bool
            Damping ratio [-] instead of the real part [1/s] in the lower panel.
        speed_axis : {"auto", "unit", "normalised"}
            Speeds in the case's unit, or divided by its reference speed
            ("auto": normalised where the case has a reference).
        frequency_limits, real_limits : (float, float), optional
            Ranges of the frequency axis (in its units as shown) and of the
            lower panel (1/s, or the damping ratio).
        modes : sequence of str, optional
            Labels of the modes to draw; the unstable ranges show regardless.
        ax : matplotlib Axes, or two of them, optional
            Instead of ``fig``: axes of your own, the frequencies in the first, the real
            part (or damping ratio) in the second where two are given.

        See Also
        --------
        groundres.plotting.coleman.coleman_diagram

        Examples
        --------
        >>> result.plot(modes=["regressive lag"], real_limits=(-0.5, 0.1))  # doctest: +SKIP
        >>> fig, (left, right) = plt.subplots(1, 2, layout="constrained")  # doctest: +SKIP
        >>> result.plot(ax=left)  # the frequencies beside a picture of your own  # doctest: +SKIP
        """
        from ..plotting.coleman import coleman_diagram

        return coleman_diagram(
            self,
            fig,
            show_damping_ratio,
            speed_axis=speed_axis,
            frequency_limits=frequency_limits,
            real_limits=real_limits,
            modes=modes,
            ax=ax,
        )
