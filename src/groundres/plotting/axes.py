"""The options the Coleman diagrams share: speed axis, axis limits, modes drawn.

Each check raises ValueError naming the keyword argument, the value and what
is allowed; the command line checks its options itself first, naming them.
"""

from __future__ import annotations

import math

import numpy as np

from ..model.units import SPEED_UNITS

#: Choices of ``speed_axis``: the case's reference where it has one, its unit, or the reference.
SPEED_AXES = ("auto", "unit", "normalised")


def speed_scale(*results, kind: str = "auto"):
    """Factor dividing rad/s for plot axes, and the axis-unit text ("-": normalised).

    The first result's case decides: "unit" is its ``[sweep] unit``;
    "normalised" divides by its reference speed (ValueError without one);
    "auto" normalises when that case has a reference that every other result's
    case shares, and otherwise uses the unit.
    """
    if kind not in SPEED_AXES:
        raise ValueError(f"speed_axis={kind!r}: must be one of {', '.join(SPEED_AXES)}")
    sweep = results[0].case.sweep
    top = max((float(np.max(r.rotor_speed)) for r in results if len(r.rotor_speed)), default=0.0)
    # (a reference so small that the ratios leave floating point: the case's unit instead)
    usable = bool(sweep.reference) and top / 1e300 < sweep.reference
    if kind == "normalised":
        if not usable:
            raise ValueError(
                f"speed_axis='normalised': {_no_reference(sweep)}; choose 'auto' or 'unit', "
                "or give the case a [sweep] reference"
            )
        return sweep.reference, "-"
    shared = all(r.case.sweep.reference == sweep.reference for r in results)
    if kind == "auto" and usable and shared:
        return sweep.reference, "-"
    return SPEED_UNITS[sweep.unit], sweep.unit


def _no_reference(sweep) -> str:
    if not sweep.reference:
        return "the case has no [sweep] reference speed"
    return f"the case's reference speed ({sweep.reference:g} rad/s) is too small to divide by"


#: Largest size of an axis limit, and the inverse of the smallest span: far beyond any axis of the
#: model (its rates stay below about 1e10 1/s) and well inside what the plotting library can tick.
LIMIT_SIZE = 1e100


def checked_limits(value, name: str):
    """``value`` (LOW, HIGH) as two floats, LOW < HIGH, both finite; ValueError naming ``name``."""
    try:
        low, high = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}={value!r}: must be two numbers (LOW, HIGH)") from None
    if not (math.isfinite(low) and math.isfinite(high)):
        raise ValueError(f"{name}={value!r}: both numbers must be finite")
    if not low < high:
        raise ValueError(f"{name}={value!r}: LOW must be below HIGH")
    if max(abs(low), abs(high)) > LIMIT_SIZE or high - low < 1 / LIMIT_SIZE:
        raise ValueError(
            f"{name}={value!r}: the numbers must lie within +-{LIMIT_SIZE:g} and HIGH - LOW be at "
            f"least {1 / LIMIT_SIZE:g}"
        )
    return low, high


def checked_modes(modes, labels) -> list[str]:
    """The mode labels asked for (all of ``labels`` if None); ValueError for one not there."""
    if modes is None:
        return list(labels)
    modes = [modes] if isinstance(modes, str) else list(modes)
    for label in modes:
        if label not in labels:
            raise ValueError(f"modes: {label!r} is not a mode here; choose from {', '.join(labels)}")
    if not modes:
        raise ValueError(f"modes: empty; choose from {', '.join(labels)}")
    return modes


def canvas(fig, ax, counts: tuple) -> list | None:
    """Where a picture draws: None for a figure (``fig``, new where None), or the caller's
    axes (``ax``: one Axes or a sequence of ``counts`` of them). ValueError for both given,
    a wrong number of axes, or a ``fig`` (figure or subfigure) that already holds axes (a
    picture adds its own and would draw over them)."""
    from matplotlib.axes import Axes

    if ax is not None:
        if fig is not None:
            raise ValueError("fig and ax: pass one of them (ax draws into the axes given)")
        axes = [ax] if isinstance(ax, Axes) else list(np.ravel(np.asarray(ax, dtype=object)))
        if len(axes) not in counts or not all(isinstance(a, Axes) for a in axes):
            allowed = " or ".join(str(c) for c in counts)
            raise ValueError(f"ax={ax!r}: must be {allowed} matplotlib Axes")
        return axes
    if fig is not None and fig.axes:
        raise ValueError(
            f"fig holds {len(fig.axes)} axes already: pass an empty figure or subfigure "
            "(fig.subfigures(...)), or ax= to draw into axes of your own"
        )
    return None


def legend(fig, ax, given, handles, labels, fontsize: float = 9) -> None:
    """The legend: right of the figure where the picture made its axes in a figure laid out
    by constraints, beside ``ax`` otherwise (the caller's axes, or a figure without them)."""
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    if given is None and isinstance(root_figure(fig).get_layout_engine(), ConstrainedLayoutEngine):
        fig.legend(handles, labels, loc="outside right center", fontsize=fontsize, frameon=False)
    else:
        beside = {"loc": "upper left", "bbox_to_anchor": (1.01, 1.0), "frameon": False}
        ax.legend(handles, labels, fontsize=fontsize - 1, **beside)


def root_figure(artist):
    """The figure at the top of an artist's (an Axes', a subfigure's) parents."""
    root = artist
    for _ in range(100):  # (a subfigure's parents, up to the figure)
        if getattr(root, "figure", root) is root or root.figure is None:
            break
        root = root.figure
    return root


#: Width a legend beside the axes takes from them once laid out [in].
LEGEND_WIDTH = 2.0


def title_line(ax, fontsize: float, legend: bool = True) -> int:
    """Characters of a title line that fit the width of ``ax`` at ``fontsize`` [pt], less
    that of a legend beside it (positions before the layout: the axes span their cell)."""
    parent = ax.figure  # (a subfigure, or the figure: positions before the layout are relative to it)
    width = ax.get_position().width * parent.bbox.width / root_figure(ax).dpi  # [in]
    width -= LEGEND_WIDTH if legend else 0.0
    return max(20, int(width * 72 / (0.55 * fontsize)))
