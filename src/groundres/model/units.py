"""Numbers as people read them: speeds and frequencies in the case's unit, with the ratio to the
reference speed, and values to the digits their accuracy supports.

Data files stay SI (rad/s); what a person reads, on the terminal or on a page,
is in the case's ``[sweep] unit`` (rpm, Hz or rad/s; frequencies of an rpm
case in cycles/min) with "ref", the ratio to the case's reference speed.
"""

from __future__ import annotations

import math

from .params import FREQUENCY_UNITS, SPEED_UNITS


def fmt_speed(w, sweep, digits: int = 5, ref: bool = True, unit: bool = True, sep: str = " "):
    """A speed [rad/s] in the case's unit (``unit``: its name too), with its ratio
    to the reference ("ref") after ``sep``."""
    text = f"{w / SPEED_UNITS[sweep.unit]:.{digits}g}" + (f" {sweep.unit}" if unit else "")
    if ref and sweep.reference:
        text += f"{sep}({w / sweep.reference:.4g} ref)"
    return text


def fmt_frequency(w, sweep, digits: int = 4):
    """A frequency [rad/s] in the case's unit (cycles/min for rpm), rad/s beside it."""
    text = f"{w / SPEED_UNITS[sweep.unit]:.{digits}g} {FREQUENCY_UNITS[sweep.unit]}"
    return text if sweep.unit == "rad/s" else f"{text} ({w:.{digits}g} rad/s)"


def ref_note(sweep) -> str | None:
    """The line that explains "ref" once, or None without a reference speed."""
    if not sweep.reference:
        return None
    return f"ref: rotor speed / the case's reference speed, {fmt_speed(sweep.reference, sweep, ref=False)}."


def significant(value: float, rtol: float) -> str:
    """``value`` to the digits its relative tolerance ``rtol`` supports (1e-4: 4 significant digits)."""
    return f"{value:.{max(1, round(-math.log10(rtol)))}g}"
