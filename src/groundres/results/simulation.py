"""A simulation of a case: the time history at one rotor speed, and what the analysis predicts.

Compute returns data; ``.plot()`` and ``.to_xarray()`` consume it, as for a
sweep (:class:`groundres.results.sweep.SweepResult`). The equations are
linear, so amplitudes only scale the initial disturbance: what a simulation
tells is whether and how fast the motion grows, and its measured growth rate
(:meth:`Simulation.growth_rate`) checks the largest real part of the
eigen- or Floquet analysis independently.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..methods import Method
from ..model.params import Case
from ..model.units import fmt_speed
from ..solve.simulate import TimeHistory
from .dataset import coordinate_unit


@dataclass
class Simulation:
    """The time history of a case at one rotor speed (:func:`groundres.analysis.simulate`).

    Attributes
    ----------
    case : Case
    history : TimeHistory
        The integrated motion (:class:`groundres.solve.simulate.TimeHistory`):
        ``time`` [s], ``displacement`` and ``velocity`` (n_t, n) in SI (m, rad;
        m/s, rad/s) of ``coordinates`` (blade coordinates, body axes nonrotating).
    initial : dict
        The initial displacements and rates given, by name ("x", "lag1", "roll_rate").
    method : Method
        The analysis whose roots predict the growth (:class:`groundres.methods.Method`).
    predicted_growth : float
        Largest real part of that analysis' roots at the rotor speed [1/s].
    """

    case: Case
    history: TimeHistory
    initial: dict
    method: Method
    predicted_growth: float

    @property
    def rotor_speed(self) -> float:
        """[rad/s]."""
        return self.history.rotor_speed

    @property
    def time(self) -> np.ndarray:
        """Instants [s], (n_t,)."""
        return self.history.time

    @property
    def displacement(self) -> np.ndarray:
        """Coordinates at each instant (n_t, n) [m, rad]."""
        return self.history.displacement

    @property
    def velocity(self) -> np.ndarray:
        """Their rates (n_t, n) [m/s, rad/s]."""
        return self.history.velocity

    @property
    def coordinates(self) -> list:
        """The coordinates (:class:`groundres.model.mbc.Coordinate`): body, then each blade's lag, flap."""
        return self.history.coordinates

    def growth_rate(self, start_fraction: float = 0.5) -> float:
        """Measured growth rate [1/s] (:meth:`groundres.solve.simulate.TimeHistory.growth_rate`)."""
        return self.history.growth_rate(start_fraction)

    def column_names(self) -> list[str]:
        """A name with its unit for each coordinate: "x [m]", "lag1 [rad]"."""
        return [f"{c.short} [{coordinate_unit(c)}]" for c in self.coordinates]

    def __repr__(self) -> str:
        from .display import simulation_text

        return simulation_text(self)

    def _repr_html_(self) -> str:
        from .display import simulation_html

        return simulation_html(self)

    def plot(self, fig=None, *, ax=None):
        """The time history (a matplotlib Figure): the growth on a log scale, then body and
        blade motion, relative to the initial disturbance, with the measured growth rate and
        the predicted one (:func:`groundres.plotting.timehistory.time_history`).

        Parameters
        ----------
        fig : matplotlib Figure or SubFigure, optional
            An empty figure or subfigure to draw in; a new figure if None.
        ax : matplotlib Axes, optional
            Instead of ``fig``: axes of your own for the amplitude envelopes alone.
        """
        from ..plotting.timehistory import time_history

        return time_history(
            self.history,
            fig,
            title=self.case.title,
            growth=self.growth_rate(),
            predicted=self.predicted_growth,
            speed_text=fmt_speed(self.rotor_speed, self.case.sweep),
            initial=self.initial,
            ax=ax,
        )

    def to_xarray(self):
        """The time history as an xarray Dataset: ``displacement`` and ``velocity`` over
        dims ``time`` [s] and ``coordinate`` (each with its unit in ``unit``)."""
        import xarray as xr

        names = [c.short for c in self.coordinates]
        units = [coordinate_unit(c) for c in self.coordinates]
        return xr.Dataset(
            {
                "displacement": (("time", "coordinate"), self.displacement, {"long_name": "displacement"}),
                "velocity": (("time", "coordinate"), self.velocity, {"long_name": "rate (per second)"}),
            },
            coords={
                "time": ("time", self.time, {"units": "s"}),
                "coordinate": ("coordinate", names),
                "unit": ("coordinate", units, {"long_name": "unit of the displacement (per s: of the rate)"}),
            },
            attrs={
                "title": f"groundres time simulation of {self.case.title}",
                "rotor_speed": self.rotor_speed,
                "rotor_speed_units": "rad/s",
                "growth_rate": self.growth_rate(),
                "predicted_growth": self.predicted_growth,
                "growth_units": "1/s",
                "prediction_method": self.method.value,
                "rtol": self.history.rtol,
                "atol": self.history.atol,
            },
        )
