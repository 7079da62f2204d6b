"""Options of the Coleman diagram, shared by `groundres run` and `groundres compare`.

Each option is checked where its answer is known, before anything is written:
the limits and the speed axis's reference as the command starts, the mode
labels once the analysis has named them. A bad value is one line naming the
option, the value and what is allowed (exit 2).
"""

from __future__ import annotations

import click

from ..errors import shown
from .common import fail_user

#: --speed-axis choices (as groundres.plotting.axes.SPEED_AXES, not imported: the CLI starts light).
SPEED_AXES = ("auto", "unit", "normalised")

#: What each limits option is in, for its messages.
_LIMITS_UNITS = {
    "--frequency-limits": "in the frequency axis's units as shown: per reference speed where the axis "
    "is normalised, else the case's frequency unit (cycles/min for rpm), e.g. 0:2",
    "--real-limits": "in 1/s, or of the damping ratio [-] with --damping-ratio, e.g. -0.5:0.1",
}


def plot_options(speed_help: str):
    """The four options as one decorator (``speed_help``: what "auto" means for the command)."""

    def decorate(f):
        for option in reversed(
            (
                click.option(
                    "--speed-axis",
                    type=click.Choice(SPEED_AXES),
                    default="auto",
                    show_default=True,
                    help=speed_help,
                ),
                click.option(
                    "--frequency-limits",
                    metavar="LOW:HIGH",
                    default=None,
                    help="Range of the frequency axis, in its units as shown.",
                ),
                click.option(
                    "--real-limits",
                    metavar="LOW:HIGH",
                    default=None,
                    help="Range of the lower panel: real part [1/s], or damping ratio with --damping-ratio.",
                ),
                click.option(
                    "--modes",
                    "modes",
                    multiple=True,
                    metavar="LABEL",
                    help="Draw only this mode (repeatable); the unstable ranges show regardless.",
                ),
            )
        ):
            f = option(f)
        return f

    return decorate


def parse_limits(text: str | None, option: str):
    """``LOW:HIGH`` as (low, high), or None if not given; a one-line error otherwise."""
    if text is None:
        return None
    allowed = f"give LOW:HIGH, two finite numbers with LOW < HIGH, {_LIMITS_UNITS[option]}"
    low, sep, high = text.partition(":")
    try:
        values = (float(low), float(high))
    except ValueError:
        values = None
    if not sep or values is None:
        fail_user(f"{option} {shown(text)}: not two numbers; {allowed}")
    from ..plotting.axes import checked_limits  # (the same rules as from Python)

    try:
        return checked_limits(values, option)
    except ValueError as err:  # (its reason, after the name and value it repeats)
        fail_user(f"{option} {shown(text)}: {str(err).split(': ', 1)[1]}; {allowed}")


def check_reference(case, speed_axis: str, name: str = "the case") -> None:
    """Refuse --speed-axis normalised for a case without a reference speed (before any work)."""
    if speed_axis == "normalised" and not case.sweep.reference:
        fail_user(
            f"--speed-axis normalised: {name} has no [sweep] reference speed to divide by; "
            "choose --speed-axis auto or unit, or give the case a reference"
        )


def check_modes(modes, labels, what: str = "a mode of this case") -> list[str] | None:
    """The --modes labels (None: all), each one of ``labels``; a one-line error otherwise."""
    for label in modes:
        if label not in labels:
            fail_user(f"--modes {shown(label)}: not {what}; choose from {', '.join(labels)}")
    return list(dict.fromkeys(modes)) or None


def check_scale(*results, speed_axis: str) -> None:
    """The speed axis can be drawn (a reference too small to divide by is refused here)."""
    from ..plotting.axes import speed_scale

    try:
        speed_scale(*results, kind=speed_axis)
    except ValueError as err:
        fail_user(f"--speed-axis {speed_axis}: {str(err).split(': ', 1)[-1]}")
