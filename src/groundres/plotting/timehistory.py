"""Time history of a simulation: growth on a log scale first, then body and blade motion.

The equations are linear, so amplitudes only scale the initial disturbance:
what a reader takes from a simulation is whether and how fast the motion
grows. The first panel shows the amplitude envelope of every body coordinate
and of the largest lag angle on a log scale, where growth at a rate sigma is a
straight line exp(sigma t) from the first second on; the linear panels below
show the motion itself.
"""

from __future__ import annotations

import numpy as np

from .titles import figure_title

_ANGLES = ("pitch", "roll", "yaw")


def envelope(time, values) -> np.ndarray:
    """Amplitude envelope of an oscillating signal, through the peaks of its magnitude.

    The peaks are the samples that are the largest within a window of just
    over one period of the signal (estimated from its zero crossings, at least
    five samples); between them the envelope is interpolated on a log scale,
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
    size = int(np.clip(1.1 * period / dt, 5, len(time)))
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


def time_history(sim, fig=None, title="", growth=None, predicted=None, speed_text=None):
    """Plot a time history (:class:`~groundres.solve.simulate.TimeHistory`).

    Parameters
    ----------
    sim : TimeHistory
    fig : matplotlib Figure, optional
    title : str
    growth, predicted : float, optional
        Measured growth rate and the largest Floquet/eigen real part [1/s];
        the measured one is drawn as exp(growth t) on the log panel.
    speed_text : str, optional
        The rotor speed as the reader knows it (e.g. "255 rpm (1.645 ref)");
        [rad/s] by default.

    Returns
    -------
    matplotlib Figure
    """
    if fig is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(10, 9), layout="constrained")
    coords = sim.coordinates
    body = [i for i, c in enumerate(coords) if c.kind == "body"]
    kinds = sorted({c.kind for c in coords if c.kind != "body"}, key=["lag", "flap"].index)
    axes = fig.subplots(2 + len(kinds), 1, sharex=True)
    log_ax, body_ax, blade_axes = axes[0], axes[1], axes[2:]
    t = sim.time
    shown = sim.displacement.copy()
    for i, c in enumerate(coords):
        if c.kind != "body" or c.name in _ANGLES:
            shown[:, i] = np.degrees(shown[:, i])

    def unit(i):
        return "m" if coords[i].kind == "body" and coords[i].name not in _ANGLES else "deg"

    def name(i):
        c = coords[i]
        return f"body {c.name}" if c.kind == "body" else f"{c.kind}, blade {c.name}"

    _log_panel(log_ax, t, shown, body, coords, unit, name, growth, predicted)

    trans = [i for i in body if unit(i) == "m"]
    tilt = [i for i in body if unit(i) == "deg"]
    for i in trans:
        body_ax.plot(t, shown[:, i], lw=1.0, label=f"{name(i)} [m]")
    body_ax.set_ylabel("body translation [m]" if trans else "")
    if tilt:
        ax2 = body_ax.twinx() if trans else body_ax
        for i in tilt:
            ax2.plot(t, shown[:, i], lw=1.0, ls="--", label=f"{name(i)} [deg]")
        ax2.set_ylabel("body rotation [deg]")
        if ax2 is not body_ax:
            ax2.legend(loc="upper right", fontsize=8)
    body_ax.legend(loc="upper left", fontsize=8)
    for ax, kind in zip(blade_axes, kinds):
        for i, c in enumerate(coords):
            if c.kind == kind:
                ax.plot(t, shown[:, i], lw=0.9, label=f"blade {c.name}")
        ax.set_ylabel(f"{kind} angle [deg]")
        ax.legend(loc="upper left", fontsize=8, ncol=4)
    for ax in axes:
        ax.grid(True, color="0.9", lw=0.6)
    axes[-1].set_xlabel("time [s]")
    text = f"rotor speed {speed_text or f'{sim.rotor_speed:.4g} rad/s'}"
    if growth is not None:
        text += f"; measured growth rate {growth:.4g} 1/s"
    if predicted is not None:
        text += f", largest real part {predicted:.4g} 1/s"
    fig.suptitle(f"{figure_title(title)}\n{text}", fontsize=10)
    return fig


def _log_panel(ax, t, shown, body, coords, unit, name, growth, predicted):
    """Envelopes of the body coordinates and of the largest lag angle, log scale, with exp(sigma t)."""
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
        label = f"{name(i)} [{unit(i)}]" + (" (largest lag)" if i == largest and len(lag) > 1 else "")
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
    ax.set_ylabel("amplitude [m or deg]")
    ax.set_title(
        "Amplitude envelopes, log scale. The model is linear: amplitudes scale with the initial "
        "disturbance, only their growth matters.",
        fontsize=9,
        loc="left",
    )
    ax.legend(loc="best", fontsize=8, ncol=2)
