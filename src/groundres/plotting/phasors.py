"""Phasor diagrams of a mode: every coordinate and its rate as arrows in the complex plane."""

from __future__ import annotations

import numpy as np

_GROUPS = (("body", "body"), ("lag", "lag"), ("flap", "flap"))


def phasor_diagram(shape, fig=None, speed_text=""):
    """Draw the phasors of a :class:`~groundres.results.shapes.ModeShape` in both frames.

    Top row: nonrotating axes (body and multiblade coordinates); bottom row:
    rotating axes (each blade; body in rotating axes). One panel per group
    (body, lag, flap), each scaled to its largest displacement. Displacements
    are solid arrows, rates hollow dashed arrows of the same colour, scaled by
    1/``abs(lambda)`` so that a neutral mode shows them equally long and 90 degrees
    ahead. ``speed_text`` names the speed in the case's unit (default: rad/s);
    a real part within the growth threshold of zero shows as 0 (neutral).

    Returns
    -------
    matplotlib Figure
    """
    if fig is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(13, 8.6), layout="constrained")
    frames = ("nonrotating", "rotating")
    table = {f: shape.phasors(f) for f in frames}
    groups = [g for g, _ in _GROUPS if any(p.kind == g for p in table["nonrotating"])]
    axes = fig.subplots(2, len(groups), squeeze=False)
    colours = [f"C{i}" for i in range(10)]
    for r, frame in enumerate(frames):
        for c, group in enumerate(groups):
            ax = axes[r, c]
            rows = [p for p in table[frame] if p.kind == group]
            scale = max((abs(p.displacement) for p in rows), default=1.0) or 1.0
            # (a root at the origin has no rates: nothing to scale them by)
            root = (
                max((abs(p.rate) / abs(p.displacement) for p in rows if abs(p.displacement) > 0), default=1.0)
                or 1.0
            )
            ax.add_patch(_circle())
            for i, p in enumerate(rows):
                d = p.displacement / scale
                v = p.rate / (scale * root)
                colour = colours[i % 10]
                if abs(d) < 1e-3:
                    continue
                ax.annotate(
                    "",
                    xy=(d.real, d.imag),
                    xytext=(0, 0),
                    arrowprops=dict(arrowstyle="-|>", color=colour, lw=2.0),
                )
                ax.annotate(
                    "",
                    xy=(v.real, v.imag),
                    xytext=(0, 0),
                    arrowprops=dict(arrowstyle="-|>", color=colour, lw=1.2, ls="--", fill=False),
                )
                ax.text(
                    1.08 * d.real,
                    1.08 * d.imag,
                    p.name,
                    color=colour,
                    fontsize=8,
                    ha="left" if d.real >= 0 else "right",
                    va="bottom" if d.imag >= 0 else "top",
                )
            ax.axhline(0, color="0.8", lw=0.6)
            ax.axvline(0, color="0.8", lw=0.6)
            ax.set_xlim(-1.45, 1.45)
            ax.set_ylim(-1.3, 1.3)
            ax.set_aspect("equal")
            ax.set_xlabel("real part (normalised)")
            ax.set_ylabel("imaginary part (normalised)")
            unit = " [m, rad]" if group == "body" else " [rad]"
            ax.set_title(f"{group}, {frame} axes{unit if group == 'body' else ''}", fontsize=10)
    lam = shape.eigenvalue
    ratio = -lam.real / abs(lam) if abs(lam) > 0 else float("nan")
    flag = "UNSTABLE" if shape.unstable else ("neutral" if shape.neutral else "stable")
    lead = np.mean([p.rate_lead for p in table["nonrotating"] if abs(p.displacement) > 1e-3])
    if shape.neutral:  # round-off, not a result: the real part within the growth threshold of zero
        real, ratio_text = "0", "0"
    else:
        real, ratio_text = f"{lam.real:.4g}", f"{ratio:.3g}"
    fig.suptitle(
        f"{shape.label} at {speed_text or f'{shape.rotor_speed:.4g} rad/s'}: {flag}, "
        f"lambda = {real} + {lam.imag:.4g}i 1/s, damping ratio {ratio_text}\n"
        f"solid: displacement; dashed: rate / |lambda|; rates lead displacements by {lead:.2f} deg "
        f"(90 for a neutral mode; less when growing, more when decaying)",
        fontsize=10,
        color="#b00000" if shape.unstable else "black",
    )
    return fig


def _circle():
    from matplotlib.patches import Circle

    return Circle((0, 0), 1.0, fill=False, ls=":", color="0.6")
