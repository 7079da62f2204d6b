"""Animated mode shape: top view of the body and the blades, in both frames."""

from __future__ import annotations

import numpy as np


def mode_animation(
    shape, frames: int = 60, cycles: float = 2.0, exaggeration_deg: float = 18.0, speed_text: str = ""
):
    """An animation of a :class:`~groundres.results.shapes.ModeShape` seen from above.

    Left: nonrotating axes (the rotor turns); right: rotating axes (the blades
    stay, the hub moves). Lag and hub motion are exaggerated by one factor
    chosen so that the largest lag angle of the first cycle shows as
    ``exaggeration_deg``; flap shows as the size of the blade-tip marker. The
    rotor's centre of mass leaves a trace. A growing mode grows on screen.
    ``speed_text`` names the speed in the case's unit (default: rad/s).

    Returns
    -------
    matplotlib.animation.FuncAnimation (its figure is ``.fig``)
    """
    from matplotlib.animation import FuncAnimation
    from matplotlib.figure import Figure

    w = shape.rotor_speed
    freq = abs(shape.eigenvalue.imag)
    period = 2 * np.pi / freq if freq > 0.05 * w else 2 * np.pi / w
    t = np.linspace(0.0, cycles * period, frames)
    mot = shape.motion(t)
    first = t <= period
    lag = mot.get("lag", np.zeros_like(mot["azimuth"]))
    flap = mot.get("flap")
    ref_lag = np.abs(lag[first]).max()
    # hub: 1 m of hub motion shown like 1 rad of lag on a unit blade (consistent scale)
    ref = max(ref_lag, np.abs(mot["hub"][first]).max(), 1e-300)
    k = np.radians(exaggeration_deg) / ref
    hub = k * mot["hub"]
    lag = k * lag
    flap_scale = (
        (np.radians(exaggeration_deg) / np.abs(flap[first]).max())
        if flap is not None and np.abs(flap).max() > 0
        else 0.0
    )

    fig = Figure(figsize=(10, 5.4), layout="constrained")
    axes = fig.subplots(1, 2)
    titles = ("nonrotating axes", "rotating axes (turning with the rotor)")
    artists = []
    for ax, title in zip(axes, titles):
        ax.set_aspect("equal")
        ax.set_xlim(-1.5, 1.5)
        ax.set_ylim(-1.5, 1.5)
        ax.set_title(title, fontsize=10)
        ax.set_xticks([])
        ax.set_yticks([])
        ax.add_patch(_circle())
        ax.annotate("x", xy=(0, 1.42), ha="center", fontsize=8, color="0.4")
        ax.annotate("y", xy=(-1.42, 0), va="center", fontsize=8, color="0.4")
        blades = [ax.plot([], [], lw=3, color="tab:red")[0] for _ in range(shape.n_blades)]
        tips = ax.scatter(np.zeros(shape.n_blades), np.zeros(shape.n_blades), s=20, color="tab:red", zorder=3)
        body = ax.plot([], [], "s", ms=16, color="0.3")[0]
        trace = ax.plot([], [], "-", lw=1, color="tab:blue")[0]
        cg = ax.plot([], [], "o", ms=5, color="tab:blue")[0]
        artists.append((blades, tips, body, trace, cg))
    cg_path = [[], []]
    speed = speed_text or f"{w:.4g} rad/s"
    flag = "unstable, growing" if shape.unstable else ("neutral" if shape.neutral else "stable, decaying")
    status = fig.suptitle("", fontsize=10)

    def screen(x, y):
        return -y, x  # x forward is up, y left is left

    def draw(i):
        if i == 0:
            cg_path[0].clear()
            cg_path[1].clear()
        out = []
        for panel, (blades, tips, body, trace, cg) in enumerate(artists):
            if panel == 0:
                hx, hy = hub[i]
                psi = mot["azimuth"][i] - lag[i]
            else:
                c, s = np.cos(w * t[i]), np.sin(w * t[i])
                hx, hy = c * hub[i, 0] + s * hub[i, 1], -s * hub[i, 0] + c * hub[i, 1]
                psi = mot["azimuth"][0] - lag[i]
            ends = []
            for b, line in enumerate(blades):
                xb, yb = hx + np.cos(psi[b]), hy + np.sin(psi[b])
                line.set_data(*zip(screen(hx, hy), screen(xb, yb)))
                ends.append(screen(xb, yb))
            tips.set_offsets(np.array(ends))
            if flap is not None:
                tips.set_sizes(20 * (1 + 3 * np.clip(flap_scale * flap[i], -0.9, 3)) ** 2)
            body.set_data(*[[v] for v in screen(hx, hy)])
            mid = np.mean([(hx + 0.5 * np.cos(p), hy + 0.5 * np.sin(p)) for p in psi], axis=0)
            cg_path[panel].append(screen(*mid))
            trace.set_data(*zip(*cg_path[panel]))
            cg.set_data([cg_path[panel][-1][0]], [cg_path[panel][-1][1]])
            out += [*blades, tips, body, trace, cg]
        status.set_text(
            f"{shape.label} at {speed} ({flag}); t = {t[i]:.2f} s; lag and hub motion exaggerated; "
            f"blue: rotor centre of mass"
        )
        return out

    anim = FuncAnimation(fig, draw, frames=frames, blit=False)
    anim.fig = fig
    return anim


def _circle():
    from matplotlib.patches import Circle

    return Circle((0, 0), 1.0, fill=False, ls=":", color="0.75")
