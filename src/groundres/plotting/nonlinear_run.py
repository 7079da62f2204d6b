"""A run of the nonlinear equations: every blade's lag and the hub's motion against time.

Unlike a linear run, whose amplitude only scales its start, the size of the
motion is the result here: the top panel shows each blade's lag angle in
degrees, with the predicted limit cycles (the largest component of the blade
that moves most) as dashed levels, stable blue and thresholds red; the panel
below shows the hub's translations in millimetres (or its angles in degrees).
The window the verdict was measured over is shaded.
"""

from __future__ import annotations

import numpy as np

from ..model.mbc import unit_of
from .titles import figure_title


def nonlinear_run_figure(run, fig=None):
    """Draw :class:`groundres.results.nonlinear_run.NonlinearRun` ``run``."""
    if fig is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(10, 7), layout="constrained")
    top, bottom = fig.subplots(2, 1, sharex=True)
    h, m = run.history, run.measured
    t = h.time
    for k in range(len(m.blades)):
        top.plot(t, np.degrees(h.lag(k + 1)), lw=0.7, label=f"blade {k + 1} lag")
    shown = set()
    for c in run.predicted:
        level = np.degrees(c.amplitude)
        color, kind = ("C0", "stable cycle") if c.stable else ("C3", "threshold")
        label = None if kind in shown else f"predicted {kind} (blade that moves most)"
        shown.add(kind)
        for sign in (1, -1):
            top.axhline(sign * level, color=color, ls="--", lw=1.2, label=label if sign > 0 else None)
    top.set_ylabel("blade lag [deg]")
    top.legend(fontsize=8, loc="upper right", ncols=2)
    names = [c.short for c in h.coordinates]
    for name in m.hub:
        values = h.displacement[:, names.index(name)]
        metres = unit_of("body", name) == "m"
        bottom.plot(t, 1e3 * values if metres else np.degrees(values), lw=0.8, label=name)
    bottom.set_ylabel("hub [mm; deg for angles]")
    bottom.set_xlabel("time [s]")
    if m.hub:
        bottom.legend(fontsize=8, loc="upper right")
    for ax in (top, bottom):
        ax.axvspan(t[-1] - m.window, t[-1], color="0.92", zorder=0)
        ax.grid(True, lw=0.3)
    top.set_title(f"{run.words()} (measured over the shaded window)", fontsize=9)
    fig.suptitle(figure_title(run.case.title), fontsize=11)
    return fig
