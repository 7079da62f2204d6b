"""Checks of parameter values: the error that names the key, the value and what is allowed."""

from __future__ import annotations

import math

from ..errors import ParameterError


def finite(value) -> bool:
    """Whether ``value`` is a number (not a bool) that a float holds finitely."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return False
    try:
        return math.isfinite(value)
    except OverflowError:  # a whole number beyond the float range
        return False


def positive(obj, *names):
    for name in names:
        value = getattr(obj, name)
        if not (finite(value) and value > 0):
            raise ParameterError(name, value, "must be a finite number > 0")


def non_negative(obj, *names):
    for name in names:
        value = getattr(obj, name)
        if not (finite(value) and value >= 0):
            raise ParameterError(name, value, "must be a finite number >= 0")


#: Largest length [m] a position of the geometry (damper rod ends, gear legs, the centre of
#: mass, the hub) may have: beyond it squares of lengths overflow in the derived matrices.
MAX_LENGTH = 1e100


def lengths(obj, *names):
    """Each of ``names`` a finite length within +-:data:`MAX_LENGTH` [m]; ParameterError otherwise."""
    for name in names:
        value = getattr(obj, name)
        if not (finite(value) and abs(value) <= MAX_LENGTH):
            raise ParameterError(name, value, f"must be a finite length, |value| <= {MAX_LENGTH:.0e} [m]")
