"""Time history of a simulation: growth on a log scale first, then body and blade motion.

The equations are linear, so amplitudes only scale the initial disturbance:
what a reader takes from a simulation is whether and how fast the motion
grows, not how large it gets (a linear model grows without bound where the
real aircraft would be limited by its gear, dampers and structure). So every
panel shows the motion relative to the initial disturbance d, the largest
initial displacement given (in m for a translation, rad for an angle: a
translation of d metres and an angle of d radians both read 1). The first
panel shows the amplitude envelope of every body coordinate and of the
largest lag angle on a log scale, where growth at a rate sigma is a straight
line exp(sigma t) from the first second on; the linear panels below show the
motion itself, translations and rotations of the body on axes of their own.
"""

from __future__ import annotations

import textwrap

import numpy as np

from .axes import canvas
from .titles import TITLE_LINE, figure_title

_ANGLES = ("pitch", "roll", "yaw")


def envelope(time, values) -> np.ndarray:
    """Amplitude envelope of an oscillating signal, through the peaks of its magnitude.

    The peaks are the samples that are the largest within a window of half a
    period of the signal (estimated from its zero crossings, at least five
    samples): the magnitude peaks twice a period, and a wider window would let
    the next, larger peak of a fast-growing signal hide each one (or the last,
    of a fast-decaying one). Between them the envelope is interpolated on a log scale,
    so it does not dip between peaks and growth at a constant rate is a
    straight line on a log axis.

    Parameters
    ----------
    time : ndarray (n_t,)
        Equally spaced instants [s].
    values : ndarray (n_t,)

    Returns
    -------
    ndarray (n_t,)
    """
    from scipy.ndimage import maximum_filter1d

    magnitude = np.abs(values)
    crossings = np.count_nonzero(np.diff(np.signbit(values)))
    span = time[-1] - time[0]
    dt = span / max(len(time) - 1, 1)
    period = 2 * span / crossings if crossings else span
    size = int(np.clip(0.5 * period / dt, 5, len(time)))
    peaks = np.flatnonzero(magnitude >= maximum_filter1d(magnitude, size=size, mode="nearest"))
    peaks = np.unique(np.r_[0, peaks, len(time) - 1])
    level = np.log(np.maximum(magnitude[peaks], np.finfo(float).tiny))
    return np.exp(np.interp(time, time[peaks], level))


def _fitted_line(time, amplitude, rate):
    """exp(c + rate t) through ``amplitude`` over the second half of the run."""
    late = time >= time[0] + 0.5 * (time[-1] - time[0])
    keep = late & (amplitude > 0)
    if not keep.any():
        return None
    offset = np.median(np.log(amplitude[keep]) - rate * time[keep])
    return np.exp(offset + rate * time)


def disturbance(initial: dict) -> tuple[float, str]:
    """The scale d of an initial state (the largest displacement given, or, with rates only,
    the largest rate times 1 s) and how the pictures name it."""
    shown = {k: abs(float(v)) for k, v in initial.items() if not k.endswith("_rate") and v}
    if shown:
        return max(shown.values()), "the largest initial displacement [m or rad]"
    rates = [abs(float(v)) for v in initial.values() if v]
    return (max(rates) if rates else 1.0), "the largest initial rate x 1 s [m or rad]"


def time_history(
    sim, fig=None, title="", growth=None, predicted=None, speed_text=None, initial=None, ax=None
):
    """Plot a time history (:class:`~groundres.solve.simulate.TimeHistory`), its motion
    relative to the initial disturbance (module docstring).

    Parameters
    ----------
    sim : TimeHistory
    fig : matplotlib Figure or SubFigure, optional
        An empty figure or subfigure to draw in; a new figure if None.
    title : str
    growth, predicted : float, optional
        Measured growth rate and the largest Floquet/eigen real part [1/s];
        the measured one is drawn as exp(growth t) on the log panel.
    speed_text : str, optional
        The rotor speed as the reader knows it (e.g. "255 rpm (1.645 ref)");
        [rad/s] by default.
    initial : dict, optional
        The initial state by coordinate name (:func:`groundres.solve.simulate.initial_text`);
        without it the motion is shown relative to its largest value at the start.
    ax : matplotlib Axes, optional
        Instead of ``fig``: axes of your own for the log panel (the envelopes) alone.

    Returns
    -------
    matplotlib Figure
    """
    from ..solve.simulate import initial_text

    given = canvas(fig, ax, (1,))
    coords = sim.coordinates
    if initial:
        scale, what = disturbance(initial)
        told = f"d = {scale:.3g}, {what}: {initial_text(initial)}"
    else:
        scale = float(np.abs(sim.displacement[0]).max()) or 1.0
        told = f"d = {scale:.3g}, the largest displacement at the start [m or rad]"
    shown = sim.displacement / scale
    body = [i for i, c in enumerate(coords) if c.kind == "body"]
    kinds = sorted({c.kind for c in coords if c.kind in ("lag", "flap")}, key=["lag", "flap"].index)
    inflow = [i for i, c in enumerate(coords) if c.kind == "inflow"]
    t = sim.time

    def name(i):
        c = coords[i]
        return f"body {c.name}" if c.kind == "body" else f"{c.kind}, blade {c.name}"

    if given is not None:
        _log_panel(given[0], t, shown, body, coords, name, growth, predicted)
        given[0].set_xlabel("time [s]")
        return given[0].figure
    if fig is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(10, 9), layout="constrained")
    axes = fig.subplots(2 + len(kinds) + bool(inflow), 1, sharex=True)
    log_ax, body_ax, blade_axes = axes[0], axes[1], axes[2 : 2 + len(kinds)]
    if inflow:  # (the inflow states' rates are the inflow velocities)
        for i in inflow:
            axes[-1].plot(t, sim.velocity[:, i] / scale, lw=0.9, label=coords[i].name)
        axes[-1].set_ylabel("inflow velocity / d\n[m/s per unit d]")
        axes[-1].legend(loc="upper left", fontsize=8, ncol=3)
    _log_panel(log_ax, t, shown, body, coords, name, growth, predicted)
    trans = [i for i in body if coords[i].name not in _ANGLES]
    tilt = [i for i in body if coords[i].name in _ANGLES]
    for i in trans:
        body_ax.plot(t, shown[:, i], lw=1.0, label=f"{name(i)}")
    body_ax.set_ylabel("body translation / d [-]" if trans else "")
    if tilt:
        ax2 = body_ax.twinx() if trans else body_ax
        for n, i in enumerate(tilt):
            ax2.plot(t, shown[:, i], lw=1.0, ls="--", color=f"C{len(trans) + n}", label=f"{name(i)}")
        ax2.set_ylabel("body rotation / d [-]")
        if ax2 is not body_ax:
            ax2.legend(loc="upper right", fontsize=8)
    body_ax.legend(loc="upper left", fontsize=8)
    for panel, kind in zip(blade_axes, kinds):
        for i, c in enumerate(coords):
            if c.kind == kind:
                panel.plot(t, shown[:, i], lw=0.9, label=f"blade {c.name}")
        panel.set_ylabel(f"{kind} angle / d [-]")
        panel.legend(loc="upper left", fontsize=8, ncol=4)
    for panel in axes:
        panel.grid(True, color="0.9", lw=0.6)
    axes[-1].set_xlabel("time [s]")
    text = f"rotor speed {speed_text or f'{sim.rotor_speed:.4g} rad/s'}"
    if growth is not None:
        text += f"; measured growth rate {growth:.4g} 1/s"
    if predicted is not None:
        text += f", largest real part {predicted:.4g} 1/s"
    note = textwrap.fill(
        f"Linear model: motion relative to the initial disturbance, {told}. Only its growth is "
        "meaningful, not its size.",
        TITLE_LINE + 20,
    )
    fig.suptitle(f"{figure_title(title)}\n{text}\n{note}", fontsize=10)
    return fig


def _log_panel(ax, t, shown, body, coords, name, growth, predicted):
    """Envelopes of the body coordinates and of the largest lag angle (relative to d), log
    scale, with exp(sigma t)."""
    lag = [i for i, c in enumerate(coords) if c.kind == "lag"]
    envelopes = {i: envelope(t, shown[:, i]) for i in body + lag}
    if lag:
        largest = max(lag, key=lambda i: envelopes[i][-1])
        picked = body + [largest]
    else:
        largest, picked = None, body
    top = max(envelopes[i].max() for i in picked)
    floor = 1e-12 * top if top > 0 else 1e-300
    for n, i in enumerate(picked):
        label = name(i) + (" (largest lag)" if i == largest and len(lag) > 1 else "")
        ax.semilogy(t, np.maximum(envelopes[i], floor), lw=1.1, color=f"C{n}", label=label)
    rate = growth if growth is not None else predicted
    if rate is not None and picked:
        anchor = max(picked, key=lambda i: envelopes[i][-1])
        line = _fitted_line(t, envelopes[anchor], rate)
        if line is not None:
            what = "measured" if growth is not None else "largest real part"
            ax.semilogy(
                t, line, ":", color="0.15", lw=1.4, label=f"exp(sigma t), sigma = {rate:.4g} 1/s ({what})"
            )
    ax.set_ylabel("amplitude / d [-]")
    ax.set_title(
        "Amplitude envelopes relative to the initial disturbance d, log scale",
        fontsize=9,
        loc="left",
    )
    ax.legend(loc="best", fontsize=8, ncol=2)
