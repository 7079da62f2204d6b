"""Animated mode shape: the rotor and body seen from above in both frames, and from the side.

Panels: the plan view in nonrotating axes (the rotor turns), the plan view in
rotating axes (the blades stay, the hub moves), and, where the body pitches
or rolls, a side view (pitch) and a rear view (roll) with the mast and the
rotor disc. Lag, hub and body motion are exaggerated by one factor, chosen so
that the largest lag angle (or hub motion, 1 m shown like 1 rad of lag on a
unit blade) of the first cycle shows as ``exaggeration_deg``; flap shows as
the size of the blade-tip marker. The rotor's centre of mass is a bright
marker drawn above everything, with its trace. Lengths are not to scale (a
unit rotor radius, a mast of :data:`MAST`); a growing mode grows on screen.

The GIF is rendered by blitting (the still parts drawn once, only the
moving ones each frame) and written with Pillow: about 0.02 s a frame.
"""

from __future__ import annotations

import numpy as np

#: Figure height [in], width [in] with two panels (plan views) and with three or four
#: (side views too), and resolution [dots per inch]: 1100 or 1400 pixels wide.
HEIGHT, WIDTH, WIDE, DPI = 5.0, 11.0, 14.0, 100
#: Mast height and fuselage half-length in the side and rear views, in rotor radii.
MAST, FUSELAGE = 0.6, 0.9
#: Colours: blades, rotor centre of mass, body.
BLADE, CENTRE, BODY = "tab:red", "#ff9f1c", "0.25"


def mode_animation(
    shape, frames: int = 40, cycles: float = 2.0, exaggeration_deg: float = 18.0, speed_text: str = ""
):
    """An animation of a :class:`~groundres.results.shapes.ModeShape` (module docstring).

    ``speed_text`` names the speed in the case's unit (default: rad/s).

    Returns
    -------
    matplotlib.animation.FuncAnimation
        Its figure is ``.fig``; :func:`write_gif` writes it fast.
    """
    from matplotlib.animation import FuncAnimation

    scene = _Scene(shape, frames, cycles, exaggeration_deg, speed_text)
    anim = FuncAnimation(scene.fig, scene.draw, frames=frames, blit=False)
    anim.fig, anim.scene = scene.fig, scene
    return anim


def write_gif(anim, path, fps: float = 15.0, progress=None) -> None:
    """Write ``anim`` (from :func:`mode_animation`) to ``path`` as a looping GIF, by blitting.

    ``progress(done, total)`` is called after each frame.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from PIL import Image

    scene = anim.scene
    fig = scene.fig
    canvas = FigureCanvasAgg(fig)
    scene.hide(True)
    canvas.draw()
    background = canvas.copy_from_bbox(fig.bbox)
    scene.hide(False)
    images = []
    for i in range(scene.frames):
        canvas.restore_region(background)
        for artist in scene.draw(i):
            fig.draw_artist(artist)
        images.append(
            Image.frombuffer("RGBA", canvas.get_width_height(), canvas.buffer_rgba()).convert("RGB")
        )
        if progress is not None:
            progress(i + 1, scene.frames)
    palette = images[0].quantize(colors=64, method=Image.Quantize.MEDIANCUT)
    frames = [palette] + [im.quantize(palette=palette, dither=Image.Dither.NONE) for im in images[1:]]
    frames[0].save(
        path, format="GIF", save_all=True, append_images=frames[1:], duration=int(1000 / fps), loop=0
    )


class _Scene:
    """The figure and its moving artists; ``draw(i)`` sets them to frame ``i``."""

    def __init__(self, shape, frames, cycles, exaggeration_deg, speed_text):
        from matplotlib.figure import Figure

        self.shape, self.frames = shape, frames
        w = shape.rotor_speed
        freq = abs(shape.eigenvalue.imag)
        period = 2 * np.pi / freq if freq > 0.05 * w else 2 * np.pi / w
        self.t = np.linspace(0.0, cycles * period, frames)
        mot = shape.motion(self.t)
        first = self.t <= period
        lag = mot.get("lag", np.zeros_like(mot["azimuth"]))
        flap = mot.get("flap")
        ref = max(np.abs(lag[first]).max(), np.abs(mot["hub"][first]).max(), 1e-300)
        k = np.radians(exaggeration_deg) / ref  # (one factor for lag, hub and body motion)
        self.mot, self.k = mot, k
        self.hub, self.lag = k * mot["hub"], k * lag
        self.flap = flap
        self.flap_scale = (
            np.radians(exaggeration_deg) / np.abs(flap[first]).max()
            if flap is not None and np.abs(flap).max() > 0
            else 0.0
        )
        body = mot.get("body", {})
        self.tilts = [(name, k * body[name]) for name in ("pitch", "roll") if name in body]
        self.translation = {d: k * body[d] for d in ("x", "y") if d in body}
        n_panels = 2 + len(self.tilts)
        width = WIDTH if n_panels == 2 else WIDE
        self.fig = Figure(figsize=(width, HEIGHT + (n_panels > 2) * 0.3), dpi=DPI, layout="constrained")
        axes = self.fig.subplots(1, n_panels)
        titles = _PLAN_TITLES if n_panels == 2 else [t.split(" (")[0] for t in _PLAN_TITLES]
        self.plan = [self._plan(ax, title) for ax, title in zip(axes[:2], titles)]
        self.side = [self._side(ax, name) for ax, (name, _) in zip(axes[2:], self.tilts)]
        self.paths = [[], []]
        speed = speed_text or f"{w:.4g} rad/s"
        flag = "unstable, growing" if shape.unstable else ("neutral" if shape.neutral else "stable, decaying")
        self.head = f"{shape.label} at {speed} ({flag})"
        self.status = self.fig.suptitle(self._status(0), fontsize=12)  # (its size, for the layout)
        self.fig.get_layout_engine().execute(self.fig)  # (laid out once: the frames are blitted)
        self.fig.set_layout_engine("none")

    def _plan(self, ax, title):
        n = self.shape.n_blades
        _frame(ax, title)
        ax.annotate("x (forward)", xy=(0, 1.42), ha="center", fontsize=10, color="0.4")
        ax.annotate("y", xy=(-1.42, 0), va="center", fontsize=10, color="0.4")
        blades = [ax.plot([], [], lw=3.5, color=BLADE, zorder=2)[0] for _ in range(n)]
        tips = ax.scatter(np.zeros(n), np.zeros(n), s=30, color=BLADE, zorder=3)
        hub = ax.plot([], [], "s", ms=11, color=BODY, alpha=0.6, zorder=1)[0]
        trace = ax.plot([], [], "-", lw=1.4, color=CENTRE, zorder=4)[0]
        centre = ax.plot([], [], "o", ms=10, color=CENTRE, mec="black", mew=1.2, zorder=5)[0]
        return blades, tips, hub, trace, centre

    def _side(self, ax, name):
        _frame(ax, "side view (pitch)" if name == "pitch" else "rear view (roll)", circle=False)
        ax.set_ylim(-0.9, 2.1)
        ax.axhline(0.0, color="0.85", lw=1.0, zorder=0)
        ax.annotate(
            "x (forward) \u2192" if name == "pitch" else "\u2190 y", xy=(0, -0.8), ha="center", fontsize=10
        )
        ax.annotate("not to scale", xy=(1.45, 2.0), ha="right", va="top", fontsize=9, color="0.5")
        body = ax.plot([], [], lw=7, color=BODY, solid_capstyle="round", zorder=1)[0]
        mast = ax.plot([], [], lw=2.5, color="0.45", zorder=1)[0]
        disc = ax.plot([], [], lw=3, color=BLADE, alpha=0.8, zorder=2)[0]
        centre = ax.plot([], [], "o", ms=10, color=CENTRE, mec="black", mew=1.2, zorder=5)[0]
        return body, mast, disc, centre

    def hide(self, hidden: bool) -> None:
        """Hide the moving artists (to draw the still background) or show them again."""
        for artist in self._moving():
            artist.set_visible(not hidden)

    def _moving(self):
        for blades, tips, hub, trace, centre in self.plan:
            yield from (*blades, tips, hub, trace, centre)
        for parts in self.side:
            yield from parts
        yield self.status

    def draw(self, i: int) -> list:
        """Set the artists to frame ``i``; the ones that moved."""
        w, t = self.shape.rotor_speed, self.t
        if i == 0:
            self.paths = [[], []]
        for panel, (blades, tips, hub_mark, trace, centre) in enumerate(self.plan):
            if panel == 0:
                hx, hy = self.hub[i]
                psi = self.mot["azimuth"][i] - self.lag[i]
            else:
                c, s = np.cos(w * t[i]), np.sin(w * t[i])
                hx, hy = c * self.hub[i, 0] + s * self.hub[i, 1], -s * self.hub[i, 0] + c * self.hub[i, 1]
                psi = self.mot["azimuth"][0] - self.lag[i]
            ends = []
            for b, line in enumerate(blades):
                xb, yb = hx + np.cos(psi[b]), hy + np.sin(psi[b])
                line.set_data(*zip(_screen(hx, hy), _screen(xb, yb)))
                ends.append(_screen(xb, yb))
            tips.set_offsets(np.array(ends))
            if self.flap is not None:
                tips.set_sizes(30 * (1 + 3 * np.clip(self.flap_scale * self.flap[i], -0.9, 3)) ** 2)
            hub_mark.set_data(*[[v] for v in _screen(hx, hy)])
            mid = np.mean([(hx + 0.5 * np.cos(p), hy + 0.5 * np.sin(p)) for p in psi], axis=0)
            self.paths[panel].append(_screen(*mid))
            trace.set_data(*zip(*self.paths[panel]))
            centre.set_data([self.paths[panel][-1][0]], [self.paths[panel][-1][1]])
        for (name, angle), (body, mast, disc, centre) in zip(self.tilts, self.side):
            a = float(angle[i])
            if name == "pitch":  # (x to the right; the mast tilts aft, the nose up, for pitch > 0)
                base = self.translation["x"][i] if "x" in self.translation else 0.0
                lean = (-np.sin(a), np.cos(a))
            else:  # (seen from behind: y to the left; the mast leans to -y for roll > 0)
                base = -self.translation["y"][i] if "y" in self.translation else 0.0
                lean = (np.sin(a), np.cos(a))
            across = (lean[1], -lean[0])
            top = (base + MAST * lean[0], MAST * lean[1])
            body.set_data(
                [base - FUSELAGE * across[0], base + FUSELAGE * across[0]],
                [
                    -FUSELAGE * across[1],
                    FUSELAGE * across[1],
                ],
            )
            mast.set_data([base, top[0]], [0.0, top[1]])
            disc.set_data([top[0] - across[0], top[0] + across[0]], [top[1] - across[1], top[1] + across[1]])
            centre.set_data([top[0]], [top[1]])
        self.status.set_text(self._status(i))
        return list(self._moving())

    def _status(self, i: int) -> str:
        return (
            f"{self.head}; t = {self.t[i]:.2f} s\nlag, hub and body motion exaggerated (one factor); "
            "orange: the rotor's centre of mass and its path"
        )


_PLAN_TITLES = ("from above, nonrotating axes", "from above, rotating axes (turning with the rotor)")


def _frame(ax, title, circle=True) -> None:
    from matplotlib.patches import Circle

    ax.set_aspect("equal")
    ax.set_xlim(-1.5, 1.5)
    ax.set_ylim(-1.5, 1.5)
    ax.set_title(title, fontsize=12)
    ax.set_xticks([])
    ax.set_yticks([])
    if circle:
        ax.add_patch(Circle((0, 0), 1.0, fill=False, ls=":", color="0.75"))


def _screen(x, y):
    return -y, x  # x forward is up, y left is left
