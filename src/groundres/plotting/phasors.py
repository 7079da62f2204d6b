"""Phasor diagrams of a mode: every coordinate and its rate as arrows in the complex plane.

One panel per kind of coordinate, each with its unit: body translations [m],
body rotations [rad], lag [rad], flap [rad]; nonrotating axes above, rotating
axes below. The mode is normalised so that its reference coordinate's
displacement is 1 (:meth:`groundres.results.shapes.ModeShape.phasors`).

Two scales (``scale``): "panel" draws each panel to its own largest
displacement, to read phases; "common" draws every panel to one physical
scale (metres and radians as they are), to compare sizes: hub motion against
lag amplitude. An arrow too short to draw or to label is named in the
panel's note with its amplitude, never as a label piled on the origin.
"""

from __future__ import annotations

import numpy as np

from ..model.body import TRANSLATIONS

#: Scales of the panels (module docstring).
SCALES = ("panel", "common")
#: Arrows shorter than this share of the panel's radius are named in its note, not drawn.
SMALL = 0.04
#: Amplitudes up to this share of the mode's largest are round-off: the coordinate does not move.
ZERO = 1e-9
#: Labels closer in direction than this [deg] (at similar lengths) are moved apart outwards.
CROWDED = 14.0


def _group(p) -> str:
    if p.kind != "body":
        return p.kind
    return "body translation" if p.name.split("_")[0] in TRANSLATIONS else "body rotation"


_ORDER = ("body translation", "body rotation", "lag", "flap", "inflow")
_UNITS = {"body translation": "m", "body rotation": "rad", "lag": "rad", "flap": "rad", "inflow": "m"}
#: What a panel's arrows are, where the words for the other panels do not say it.
_TITLES = {"inflow": "inflow (dashed: velocity)"}


def phasor_diagram(shape, fig=None, speed_text="", scale="panel"):
    """Draw the phasors of a :class:`~groundres.results.shapes.ModeShape` in both frames.

    Top row: nonrotating axes (body and multiblade coordinates); bottom row:
    rotating axes (each blade; body in rotating axes). One panel per group
    (body translations, body rotations, lag, flap). Displacements are solid
    arrows, rates hollow dashed arrows of the same colour, scaled by
    1/``abs(lambda)`` so that a neutral mode shows them equally long and 90
    degrees ahead. ``speed_text`` names the speed in the case's unit (default:
    rad/s); a real part within the growth threshold of zero shows as 0
    (neutral). ``scale``: "panel" or "common" (:data:`SCALES`, module docstring).

    Returns
    -------
    matplotlib Figure
    """
    if scale not in SCALES:
        raise ValueError(f"scale={scale!r}: must be one of {', '.join(SCALES)}")
    frames = ("nonrotating", "rotating")
    table = {f: shape.phasors(f) for f in frames}
    groups = [g for g in _ORDER if any(_group(p) == g for p in table["nonrotating"])]
    if fig is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(3.6 + 3.5 * len(groups), 9.4), layout="constrained")
    axes = fig.subplots(2, len(groups), squeeze=False)
    lam = shape.eigenvalue
    size = abs(lam) or 1.0  # (a root at the origin has no rates: nothing to scale them by)
    common = max((abs(p.displacement) for f in frames for p in table[f]), default=1.0) or 1.0
    for r, frame in enumerate(frames):
        for c, group in enumerate(groups):
            rows = [p for p in table[frame] if _group(p) == group]
            radius = (
                common
                if scale == "common"
                else (max((abs(p.displacement) for p in rows), default=1.0) or 1.0)
            )
            unit = _UNITS[group]
            if not rows:  # (the inflow states have no rotating form: the air does not turn)
                axes[r, c].text(0.5, 0.5, f"{group}: nonrotating only (above)", ha="center", va="center")
                axes[r, c].set_axis_off()
                continue
            _panel(axes[r, c], rows, radius, size, unit, ZERO * common)
            axes[r, c].set_xlabel(f"real part [{unit}]")
            axes[r, c].set_ylabel(f"imaginary part [{unit}]")
            axes[r, c].set_title(f"{_TITLES.get(group, group)}, {frame} axes [{unit}]", fontsize=10)
    ratio = -lam.real / abs(lam) if abs(lam) > 0 else float("nan")
    flag = "UNSTABLE" if shape.unstable else ("neutral" if shape.neutral else "stable")
    lead = np.mean([p.rate_lead for p in table["nonrotating"] if abs(p.displacement) > 1e-3])
    if shape.neutral:  # round-off, not a result: the real part within the growth threshold of zero
        real, ratio_text = "0", "0"
    else:
        real, ratio_text = f"{lam.real:.4g}", f"{ratio:.3g}"
    how = (
        "one physical scale in every panel (m, rad)"
        if scale == "common"
        else "each panel to its largest displacement"
    )
    fig.suptitle(
        f"{shape.label} at {speed_text or f'{shape.rotor_speed:.4g} rad/s'}: {flag}, "
        f"lambda = {real} + {lam.imag:.4g}i 1/s, damping ratio {ratio_text}\n"
        f"solid: displacement; dashed: rate / |lambda|; {how}; the reference coordinate's displacement is 1\n"
        f"rates lead displacements by {lead:.2f} deg (90 for a neutral mode; less when growing, more when "
        "decaying)",
        fontsize=10,
        color="#b00000" if shape.unstable else "black",
    )
    return fig


def _panel(ax, rows, radius, size, unit, zero) -> None:
    """The arrows of one panel, drawn to ``radius`` (the panel's edge at 1.45 of it); amplitudes
    up to ``zero`` are round-off (the coordinate does not move)."""
    from matplotlib.patches import Circle

    ax.add_patch(Circle((0, 0), radius, fill=False, ls=":", color="0.6"))
    small, still, placed = [], [], []
    for i, p in enumerate(rows):
        d, v = p.displacement, p.rate / size
        colour = f"C{i % 10}"
        if abs(d) < SMALL * radius:
            (small if abs(d) > zero else still).append(p.name if abs(d) <= zero else f"{p.name} {abs(d):.2g}")
            continue
        ax.annotate(
            "", xy=(d.real, d.imag), xytext=(0, 0), arrowprops=dict(arrowstyle="-|>", color=colour, lw=2.0)
        )
        ax.annotate(
            "",
            xy=(v.real, v.imag),
            xytext=(0, 0),
            arrowprops=dict(arrowstyle="-|>", color=colour, lw=1.2, ls="--", fill=False),
        )
        angle = np.degrees(np.angle(d))
        out = 1.08
        for a, length in placed:  # (labels of arrows alike in direction and length: moved apart)
            if abs((angle - a + 180) % 360 - 180) < CROWDED and abs(abs(d) - length) < 0.25 * radius:
                out += 0.14 * radius / abs(d)
        placed.append((angle, abs(d)))
        ax.text(
            out * d.real,
            out * d.imag,
            p.name,
            color=colour,
            fontsize=9,
            ha="left" if d.real >= 0 else "right",
            va="bottom" if d.imag >= 0 else "top",
        )
    notes = ([f"too small to draw [{unit}]: " + ", ".join(small)] if small else []) + (
        ["not moving: " + ", ".join(still)] if still else []
    )
    if notes:
        ax.text(
            0.02,
            0.02,
            "\n".join(notes),
            transform=ax.transAxes,
            fontsize=8,
            color="0.35",
            va="bottom",
            wrap=True,
        )
    ax.axhline(0, color="0.8", lw=0.6)
    ax.axvline(0, color="0.8", lw=0.6)
    ax.set_xlim(-1.45 * radius, 1.45 * radius)
    ax.set_ylim(-1.3 * radius, 1.3 * radius)
    ax.set_aspect("equal")
