"""Floquet diagram: the characteristic multipliers of a periodic analysis over the sweep.

A Floquet analysis finds, at each rotor speed, the eigenvalues of the
transition matrix over the equations' period; the Floquet exponents lambda
follow, defined up to multiples of i Omega (groundres picks the harmonic at
which each mode's content moves). Over one revolution, T = 2 pi / Omega, the
multiplier z = exp(lambda T) is the same whichever harmonic was picked: it
is an eigenvalue of the transition matrix over one revolution, and a root
grows when it lies outside the unit circle. The diagram draws each labelled
mode's multipliers over the sweep in the complex plane (left) and ``|z|``
against rotor speed (right), so the crossing of the unit circle reads
directly.
"""

from __future__ import annotations

import numpy as np

from .axes import speed_scale
from .coleman import label_colour, line_style, root_lines
from .titles import figure_title


def multipliers(result) -> np.ndarray:
    """The multipliers over one revolution, z = exp(2 pi lambda / Omega): (n_s, n_m)."""
    return np.exp(result.modes.eigenvalue * (2 * np.pi / result.rotor_speed)[:, None])


def multiplier_diagram(result, fig=None):
    """Draw the Floquet diagram of a Floquet :class:`~groundres.results.sweep.SweepResult`.

    Returns
    -------
    matplotlib Figure
    """
    if fig is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(11, 5), layout="constrained")
    z = multipliers(result)
    factor, unit = speed_scale(result)
    w = result.rotor_speed / factor
    ax_z, ax_m = fig.subplots(1, 2, width_ratios=[1, 1.3])
    t = np.linspace(0, 2 * np.pi, 361)
    ax_z.plot(np.cos(t), np.sin(t), color="0.5", lw=0.9, ls=":", label="unit circle")
    colours = [label_colour(label, i) for i, label in enumerate(result.labels)]
    for i, label in enumerate(result.labels):
        ax_z.plot(z[:, i].real, z[:, i].imag, ".", ms=2.5, color=colours[i])
        ax_z.plot(z[:, i].real, -z[:, i].imag, ".", ms=1.5, color=colours[i], alpha=0.35)
        ax_m.plot([], [], color=colours[i], lw=1.5, label=label)
    # |z| of every tracked root, continuous, coloured by its mode's label (as the Coleman real parts)
    modes = result.modes
    size = np.exp(modes.root_real_part * (2 * np.pi / result.rotor_speed)[:, None])
    styles = [line_style(label) for label in result.labels]
    marks = root_lines(
        ax_m, w, size, modes.root_label, styles, colours, float(np.ptp(size)) if size.size else 1.0
    )
    if marks:
        mx, my = np.array(marks).T
        ax_m.plot(
            mx, my, "o", ms=4, mfc="white", mec="0.2", mew=0.8, zorder=5, label="branches exchange labels"
        )
    for s, e in result.stability.unstable_ranges:
        ax_m.axvspan(s / factor, e / factor, color="#d62728", alpha=0.12, lw=0)
    ax_m.axhline(1.0, color="0.3", lw=0.8)
    ax_z.set_aspect("equal")
    ax_z.set_xlabel("Re z")
    ax_z.set_ylabel("Im z")
    ax_z.set_title("multipliers z over the sweep (pale: conjugates)", fontsize=10)
    ax_m.set_ylabel("|z| [-]  (above 1: grows)")
    ax_m.set_xlabel("rotor speed / reference [-]" if unit == "-" else f"rotor speed [{unit}]")
    ax_m.set_title("|z| against rotor speed; z = exp(2 pi lambda / Omega), over one revolution", fontsize=10)
    for ax in (ax_z, ax_m):
        ax.grid(True, color="0.9", lw=0.6)
    ax_m.legend(loc="best", fontsize=8, frameon=False)
    fig.suptitle(f"{figure_title(result.case.title)}\nFloquet diagram ({result.method})", fontsize=10)
    return fig
