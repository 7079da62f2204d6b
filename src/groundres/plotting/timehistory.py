"""Time history of a simulation: body motion and blade motion against time."""

from __future__ import annotations

import numpy as np

_UNITS = {"x": ("m", 1.0), "y": ("m", 1.0), "pitch": ("deg", 180 / np.pi), "roll": ("deg", 180 / np.pi)}


def time_history(sim, fig=None, title="", growth=None, predicted=None):
    """Plot a :class:`~groundres.simulate.Simulation`.

    Parameters
    ----------
    sim : Simulation
    fig : matplotlib Figure, optional
    title : str
    growth, predicted : float, optional
        Measured growth rate and the largest Floquet/eigen real part [1/s],
        shown in the title and as an envelope.

    Returns
    -------
    matplotlib Figure
    """
    if fig is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(10, 7.5), layout="constrained")
    body = [i for i, c in enumerate(sim.coordinates) if c.kind == "body"]
    kinds = sorted({c.kind for c in sim.coordinates if c.kind != "body"}, key=["lag", "flap"].index)
    axes = fig.subplots(2 + len(kinds), 1, sharex=True, height_ratios=[2] * (1 + len(kinds)) + [1.4])
    log_ax, axes = axes[-1], axes[:-1]
    t = sim.time
    ax = axes[0]
    trans = [i for i in body if sim.coordinates[i].name in ("x", "y")]
    tilt = [i for i in body if sim.coordinates[i].name in ("pitch", "roll")]
    for i in trans:
        ax.plot(t, sim.displacement[:, i], lw=1.0, label=f"body {sim.coordinates[i].name} [m]")
    ax.set_ylabel("body translation [m]" if trans else "")
    if tilt:
        ax2 = ax.twinx() if trans else ax
        for i in tilt:
            ax2.plot(
                t,
                np.degrees(sim.displacement[:, i]),
                lw=1.0,
                ls="--",
                label=f"body {sim.coordinates[i].name} [deg]",
            )
        ax2.set_ylabel("body rotation [deg]")
        if ax2 is not ax:
            ax2.legend(loc="upper right", fontsize=8)
    ax.legend(loc="upper left", fontsize=8)
    for ax, kind in zip(axes[1:], kinds):
        for i, c in enumerate(sim.coordinates):
            if c.kind == kind:
                ax.plot(t, np.degrees(sim.displacement[:, i]), lw=0.9, label=f"blade {c.name}")
        ax.set_ylabel(f"{kind} angle [deg]")
        ax.legend(loc="upper left", fontsize=8, ncol=4)
    state = np.hstack([sim.displacement, sim.velocity])
    norm = np.linalg.norm(state / np.maximum(np.abs(state).max(0), 1e-300), axis=1)
    log_ax.semilogy(t, norm / norm[0], color="C0", lw=0.9, label="state norm (each coordinate scaled)")
    if predicted is not None:
        anchor = norm[-1] / norm[0]
        log_ax.semilogy(
            t,
            anchor * np.exp(predicted * (t - t[-1])),
            ":",
            color="0.3",
            label=f"slope of the largest real part, {predicted:.4g} 1/s",
        )
    log_ax.set_ylabel("amplitude / initial [-]")
    log_ax.legend(loc="upper left", fontsize=8)
    for ax in (*axes, log_ax):
        ax.grid(True, color="0.9", lw=0.6)
    log_ax.set_xlabel("time [s]")
    text = f"linear model at rotor speed {sim.rotor_speed:.4g} rad/s"
    if growth is not None:
        text += f"; measured growth {growth:.4g} 1/s"
    if predicted is not None:
        text += f", largest real part {predicted:.4g} 1/s (dotted: its slope)"
    fig.suptitle(f"{title}\n{text}", fontsize=10)
    return fig
