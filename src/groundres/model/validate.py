"""Checks of parameter values: the error that names the key, the value and what is allowed."""

from __future__ import annotations

import math


def shown(value) -> str:
    """``repr(value)`` fit for a one-line message: long whole numbers and texts shortened."""
    if isinstance(value, int) and not isinstance(value, bool):
        digits = math.floor(abs(value).bit_length() * math.log10(2)) + 1 if value else 1
        if digits > 20:
            if digits > 4000:  # too long to convert to text at all
                return f"{'-' if value < 0 else ''}<a whole number of about {digits} digits>"
            text = str(value)
            return f"{text[:8]}...{text[-4:]} ({len(text.lstrip('-'))} digits)"
        return repr(value)
    text = repr(value)
    return text if len(text) <= 60 else f"{text[:40]}...{text[-12:]}"


def finite(value) -> bool:
    """Whether ``value`` is a number (not a bool) that a float holds finitely."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return False
    try:
        return math.isfinite(value)
    except OverflowError:  # a whole number beyond the float range
        return False


class ParameterError(ValueError):
    """A parameter value outside what the model allows.

    Attributes
    ----------
    key : str
        Name of the parameter (dotted path once the case reader adds its table).
    value : object
        The offending value.
    allowed : str
        What is allowed, in words.
    """

    def __init__(self, key: str, value, allowed: str):
        self.key, self.value, self.allowed = key, value, allowed
        super().__init__(f"{key} = {shown(value)}: {allowed}")

    def under(self, prefix: str) -> ParameterError:
        """The same error with its key placed under a table name."""
        return ParameterError(f"{prefix}.{self.key}" if prefix else self.key, self.value, self.allowed)


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
