"""The limit-cycle diagram: blade lag amplitude of every cycle against rotor speed.

Stable cycles solid, unstable ones (thresholds) dashed; the background shaded
where the motion grows (red) or decays (green) at that amplitude, from the
scan the cycles were found in (at the amplitude of the blade that moves most);
where the blades differ (a failed damper) every blade's amplitude thin and
numbered; the hub's amplitude along each cycle on a twin axis (thin, grey).
Beside it, the Coleman diagram of the linear analysis (the laws at small motion).
"""

from __future__ import annotations

import math

import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.ticker import ScalarFormatter

from ..assess.cycle_shapes import LARGE
from ..model.mbc import unit_of
from ..model.units import SPEED_UNITS
from .titles import figure_title

GROWS, DECAYS = "#f4c7c3", "#d5ecd4"


def limit_cycle_figure(result, fig=None):
    """Draw :class:`groundres.results.limit_cycles.LimitCycleResult` ``result``."""
    if fig is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(15, 6) if result.linear is not None else (9, 6), layout="constrained")
    if result.linear is not None:
        left, right = fig.subfigures(1, 2, width_ratios=[1.1, 1])
        result.linear.plot(fig=right)
    else:
        left = fig
    ax = left.subplots()
    sweep = result.case.sweep
    factor, unit = (sweep.reference, "-") if sweep.reference else (SPEED_UNITS[sweep.unit], sweep.unit)
    p = result.prediction
    x = p.speeds / factor
    degrees = np.degrees(p.amplitudes)
    if len(x) > 1:
        ax.pcolormesh(
            _edges(x),
            _edges(degrees, log=True),
            (p.growth.T > 0).astype(float),
            cmap=ListedColormap([DECAYS, GROWS]),
            vmin=0,
            vmax=1,
            shading="flat",
            rasterized=True,
        )
    twin = ax.twinx()
    translations = [d for d in result.case.body.dofs if unit_of("body", d) == "m"]
    dissimilar = False
    for stable, branch in result.branches():
        w = np.array([c.speed for c in branch]) / factor
        a = np.degrees([c.amplitude for c in branch])
        style = "-" if stable else "--"
        color = "C0" if stable else "C3"
        ax.plot(w, a, style, color=color, lw=2.0, marker="o" if len(w) == 1 else None)
        if any(c.dissimilar for c in branch):  # (every blade, thin, named at the branch's end)
            dissimilar = True
            _each_blade(ax, branch, w, style, color)
        if translations:
            hub = [1e3 * max(c.hub[d] for d in translations) for c in branch]
            twin.plot(w, hub, style, color="0.45", lw=0.9)
    ax.plot([], [], "-", color="C0", lw=2, label="stable cycle (motion settles on it)")
    ax.plot([], [], "--", color="C3", lw=2, label="unstable cycle: a threshold (above it, motion grows)")
    if dissimilar:
        ax.plot(
            [], [], "-", color="0.3", lw=0.8, label="each blade (numbered); thick: the blade that moves most"
        )
    ax.fill_between([], [], color=GROWS, label="grows at this amplitude")
    ax.fill_between([], [], color=DECAYS, label="decays at this amplitude")
    if translations:
        ax.plot(
            [], [], "-", color="0.45", lw=0.9, label=f"hub, largest of {', '.join(translations)} (right axis)"
        )
        twin.set_ylabel("hub amplitude along the cycle [mm]")
        twin.set_yscale("log")
        twin.yaxis.set_major_formatter(ScalarFormatter())
        twin.yaxis.set_minor_formatter(ScalarFormatter())
    else:
        twin.set_axis_off()
    ax.set_yscale("log")
    ax.set_ylim(degrees[0], degrees[-1])
    ax.set_xlim(x[0], x[-1]) if len(x) > 1 else None
    ax.set_xlabel("rotor speed / reference speed [-]" if unit == "-" else f"rotor speed [{unit}]")
    ax.set_ylabel(
        "blade lag amplitude A [deg]"
        if not dissimilar
        else "lag amplitude of the blade that moves most [deg]"
    )
    if p.cycles and max(c.amplitude for c in p.cycles) > LARGE:
        ax.axhline(
            math.degrees(LARGE), color="0.3", lw=0.8, ls=":", label="beyond: angles too large for the model"
        )
    ax.legend(fontsize=8, loc="lower left", framealpha=0.9)
    beside = "; beside: the linear analysis, dampers at small motion" if result.linear is not None else ""
    ax.set_title(f"Limit cycles (describing functions){beside}", fontsize=10)
    left.suptitle(figure_title(result.case.title), fontsize=11)
    return fig


def _each_blade(ax, branch, w, style, color):
    """Every blade's amplitude along ``branch``, thin; blades that move alike (mirror images
    about a failed one) share a line and its label."""
    amplitudes = np.degrees([[b.amplitude for b in c.blades] for c in branch])  # (points, blades)
    groups = []
    for k in range(amplitudes.shape[1]):
        for group in groups:
            if np.allclose(amplitudes[:, k], amplitudes[:, group[0]], rtol=1e-6, atol=0):
                group.append(k)
                break
        else:
            groups.append([k])
    for group in groups:
        each = amplitudes[:, group[0]]
        ax.plot(w, each, style, color=color, lw=0.8, alpha=0.8, marker="." if len(w) == 1 else None)
        ax.annotate(
            ", ".join(str(k + 1) for k in group),
            (w[-1], each[-1]),
            xytext=(3, 0),
            textcoords="offset points",
            fontsize=7,
            color=color,
            va="center",
        )


def _edges(values, log=False):
    """Cell edges around ``values`` (sorted): midpoints, the ends extended by half a step."""
    v = np.log(values) if log else np.asarray(values, float)
    mid = 0.5 * (v[1:] + v[:-1])
    edges = np.concatenate([[v[0] - (mid[0] - v[0])], mid, [v[-1] + (v[-1] - mid[-1])]])
    return np.exp(edges) if log else edges
