"""Coleman diagram: modal frequency and real part against rotor speed."""

from __future__ import annotations

import numpy as np

from ..params import SPEED_UNITS
from ..stability import growth_threshold

_FREQ_UNIT = {"rad/s": "rad/s", "rpm": "cycles/min", "Hz": "Hz"}
_COLOURS = {
    "body x": "#222222",
    "body y": "#7f7f7f",
    "body pitch": "#8c564b",
    "body roll": "#bcbd22",
    "body forward whirl": "#222222",
    "body backward whirl": "#7f7f7f",
    "body forward tilt": "#8c564b",
    "body backward tilt": "#bcbd22",
    "regressive lag": "#d62728",
    "progressive lag": "#1f77b4",
    "collective lag": "#2ca02c",
    "differential lag": "#9467bd",
    "regressive flap": "#ff7f0e",
    "progressive flap": "#17becf",
    "coning": "#e377c2",
    "differential flap": "#aec7e8",
}
_EXTRA = ["#ff9896", "#98df8a", "#c5b0d5", "#c49c94", "#f7b6d2", "#dbdb8d", "#9edae5", "#ffbb78"]


def label_colour(label: str, i: int = 0) -> str:
    """A stable colour for a mode label."""
    return _COLOURS.get(label, _EXTRA[i % len(_EXTRA)])


def speed_axis(result):
    """Factor dividing rad/s for plot axes, and the axis-unit text."""
    sweep = result.case.sweep
    if sweep.reference:
        return sweep.reference, "-"
    return SPEED_UNITS[sweep.unit], sweep.unit


def _broken(x, y, branch, jump=None):
    """Insert gaps where a label moves to another branch, or (periodic systems)
    where its identified frequency jumps by a harmonic (no vertical joins)."""
    cut = branch[1:] != branch[:-1]
    if jump is not None:
        cut |= np.abs(np.diff(y)) > jump[1:]
    cut = np.flatnonzero(cut) + 1
    return np.insert(x.astype(float), cut, np.nan), np.insert(y.astype(float), cut, np.nan)


def coleman_diagram(result, fig=None, show_damping_ratio=False):
    """Draw the Coleman diagram of a sweep result.

    Parameters
    ----------
    result : SweepResult
    fig : matplotlib Figure, optional
        Figure to draw in (two axes are added); a new one if None.
    show_damping_ratio : bool
        Plot the damping ratio instead of the real part in the lower panel.

    Returns
    -------
    matplotlib Figure
    """
    if fig is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(10, 8), layout="constrained")
    ax_f, ax_d = fig.subplots(2, 1, sharex=True, height_ratios=[3, 2])
    factor, unit = speed_axis(result)
    w = result.rotor_speed / factor
    freq = result.frequency / factor
    lower = result.damping_ratio if show_damping_ratio else result.real_part
    normalised = unit == "-"
    f_unit = "-" if normalised else _FREQ_UNIT[unit]

    for s, e in result.stability.unstable_ranges:
        for ax in (ax_f, ax_d):
            ax.axvspan(s / factor, e / factor, color="#d62728", alpha=0.12, lw=0)
    grows = result.real_part > growth_threshold(result.rotor_speed)[:, None]
    branch = result.modes.branch
    jump = 0.4 * w if len(result.modes.orders) > 1 else None  # a harmonic is Omega
    for i, label in enumerate(result.labels):
        colour = label_colour(label, i)
        style = "--" if "flap" in label or label == "coning" else "-"
        ax_f.plot(*_broken(w, freq[:, i], branch[:, i], jump), style, color=colour, lw=1.6, label=label)
        ax_d.plot(*_broken(w, lower[:, i], branch[:, i]), style, color=colour, lw=1.6)
        if grows[:, i].any():
            hot = np.where(grows[:, i], freq[:, i], np.nan)
            ax_f.plot(*_broken(w, hot, branch[:, i], jump), "-", color=colour, lw=4.0, alpha=0.5)
    # 1/rev (and 2/rev) references
    speeds = np.array([w[0], w[-1]])
    ax_f.plot(speeds, speeds, ":", color="0.45", lw=1.0, label="1/rev")
    ax_f.plot(speeds, 2 * speeds, ":", color="0.75", lw=1.0, label="2/rev")
    ax_d.axhline(0.0, color="0.3", lw=0.8)
    if not show_damping_ratio:
        # neutral roots of undamped cases sit at zero up to round-off: keep a visible scale
        span = np.nanmax(np.abs(lower)) if np.isfinite(lower).any() else 0.0
        floor = 0.02 * max(np.nanmax(result.frequency), 1e-12)
        if span < floor:
            ax_d.set_ylim(-floor, floor)
    top = np.nanmax(freq) if np.isfinite(freq).any() else 1.0
    ax_f.set_ylim(0, 1.05 * top)
    ax_f.set_xlim(w[0], w[-1])
    frame = "nonrotating" if result.frame == "nonrotating" else "rotating"
    ax_f.set_ylabel(
        f"modal frequency, {frame} frame / reference [-]"
        if normalised
        else f"modal frequency, {frame} frame [{f_unit}]"
    )
    if show_damping_ratio:
        ax_d.set_ylabel("damping ratio [-]")
    else:
        ax_d.set_ylabel("real part (modal damping) [1/s]")
    if normalised:
        ref = result.case.sweep.reference / SPEED_UNITS[result.case.sweep.unit]
        ax_d.set_xlabel(f"rotor speed / reference [-]  (reference {ref:g} {result.case.sweep.unit})")
    else:
        ax_d.set_xlabel(f"rotor speed [{unit}]")
    for ax in (ax_f, ax_d):
        ax.grid(True, color="0.9", lw=0.6)
    ranges = result.stability.unstable_ranges
    if ranges:
        text = "unstable: " + ", ".join(f"{s / factor:.4g} to {e / factor:.4g}" for s, e in ranges)
        text += " [-]" if normalised else f" {unit}"
    else:
        text = "stable over the whole sweep"
    ax_f.set_title(f"{result.case.title}\n{result.method}, {frame} frame; {text}", fontsize=10)
    handles, labels = ax_f.get_legend_handles_labels()
    if ranges:
        from matplotlib.patches import Patch

        handles.append(Patch(color="#d62728", alpha=0.12))
        labels.append("unstable range")
    fig.legend(handles, labels, loc="outside right center", fontsize=9, frameon=False)
    return fig
