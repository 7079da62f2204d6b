"""The lag damper laws of a rotor: each law's moment, and its equivalent damping and stiffness
against amplitude (:mod:`groundres.model.describing`).

One row per distinct law. Left, the law itself: the moment against the lag
rate for the rate laws, the moment against the lag angle over steady cycles
for the friction link (its loops), and the measured points for a table.
Middle and right, c_eq(A) and k_eq(A) at the frequency given, with the
small-motion values every linear analysis uses dashed.
"""

from __future__ import annotations

import math

import numpy as np

from ..model import describing
from .titles import figure_title

#: Amplitudes of the friction link's loops, as multiples of the amplitude at which it slips.
LOOPS = (0.8, 2.0, 6.0)


def damper_figure(entries, frequency: float, amplitudes, title: str, fig=None):
    """Draw the laws ``entries`` [(label, DamperLaw)] at ``frequency`` [rad/s] over ``amplitudes``
    [rad] (sorted, > 0).

    Returns
    -------
    matplotlib Figure
    """
    if fig is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(13, 3.6 * len(entries) + 0.6), layout="constrained")
    axes = np.atleast_2d(fig.subplots(len(entries), 3, squeeze=False))
    degrees = np.degrees(amplitudes)
    for row, (label, law) in zip(axes, entries):
        _law_panel(row[0], law, frequency, amplitudes, label)
        c_eq, k_eq = describing.equivalent(law, amplitudes, frequency)
        c0, k0 = law.small_motion()
        for ax, values, small, name, unit in (
            (row[1], c_eq, c0, "equivalent damping c_eq", "N m s/rad"),
            (row[2], k_eq, k0, "equivalent stiffness k_eq", "N m/rad"),
        ):
            ax.plot(degrees, values, color="C0", lw=1.6, label=name)
            ax.axhline(small, color="0.4", ls="--", lw=1.0, label="small motion (the linear analysis)")
            outside = describing.outside_table(law, amplitudes)
            if outside.any():
                ax.plot(
                    degrees[outside], values[outside], ".", color="C3", ms=3, label="held beyond the table"
                )
            ax.set_xscale("log")
            ax.set_xlabel("lag amplitude A [deg]")
            ax.set_ylabel(f"{name.split(' ')[1]} [{unit}]")
            ax.set_title(f"{name} at {frequency:.4g} rad/s", fontsize=10)
            ax.grid(True, which="both", alpha=0.3)
            if np.all(values == small):  # (a constant: the law has none of it, or one fixed value)
                ax.set_ylim(small - max(1.0, abs(small)), small + max(1.0, abs(small)))
            else:
                ax.set_ylim(bottom=min(0.0, float(np.min(values))))
            ax.legend(fontsize=8)
    fig.suptitle(figure_title(title), fontsize=11)
    return fig


def _law_panel(ax, law, frequency, amplitudes, label):
    """The law itself (module docstring)."""
    ax.set_title(f"{label}: law {law.law!r}", fontsize=10)
    ax.grid(True, alpha=0.3)
    if law.law == "table":
        a = np.degrees(law.amplitudes)
        ax.plot(a, law.storage_stiffness, "o-", color="C1", label="storage stiffness K'")
        ax.plot(a, law.loss_stiffness, "s-", color="C2", label="loss stiffness K''")
        ax.set_xlabel("amplitude [deg]")
        ax.set_ylabel("[N m/rad]")
        ax.legend(fontsize=8, title=f"measured at {law.reference_frequency / (2 * math.pi):.4g} Hz")
        return
    if law.has_slider:
        slip = law.friction_moment / law.link_stiffness
        for i, factor in enumerate(LOOPS):
            angle, _, moment = law.cycle(factor * slip, frequency)
            ax.plot(
                np.degrees(angle),
                moment,
                color=f"C{i}",
                lw=1.3,
                label=f"A = {math.degrees(factor * slip):.3g} deg",
            )
        ax.set_xlabel("lag angle [deg]")
        ax.set_ylabel("moment M [N m]")
        ax.legend(fontsize=8, title=f"steady cycles at {frequency:.4g} rad/s")
        return
    top = float(amplitudes[-1]) * abs(frequency)
    # (the rate over which the law turns: its knee, or its regularisation's width)
    turn = None
    if law.law == "bilinear":
        turn = law.relief_rate
    elif law.law == "friction":
        turn = law.regularisation_velocity
    elif law.law == "tanh":
        turn = 1.0 / law.tanh_rate
    top = min(top, 5 * turn) if turn else top
    rate = np.linspace(-top, top, 1201)
    ax.plot(rate, law.moment(0.0, rate), color="C0", lw=1.6, label="M(0, v)")
    if law.law == "bilinear":
        for v in (-law.relief_rate, law.relief_rate):
            ax.axvline(v, color="0.5", ls=":", lw=0.9)
    ax.set_xlabel("lag rate v [rad/s]")
    ax.set_ylabel("moment M [N m]")
    ax.legend(fontsize=8, title="at zero lag angle")
