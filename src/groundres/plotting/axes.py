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
