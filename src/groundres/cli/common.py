"""What every command shares: user errors, loading a case, the console, speed text."""

from __future__ import annotations

from pathlib import Path

import click

DEFAULT_CASE = "hammond-undamped"


class UserError(click.ClickException):
    exit_code = 2

    def show(self, file=None):
        click.echo(f"error: {self.message}", err=True)


def fail_user(message: str):
    raise UserError(message)


def output_dir(case: str | None, out) -> Path:
    """--out, or groundres-out/<case name>."""
    return Path(out) if out else Path("groundres-out") / (Path(case).stem if case else DEFAULT_CASE)


def case_at_speed(case: str | None, speed: float):
    """The case and a --speed (in the case's unit) in rad/s."""
    from ..params import SPEED_UNITS

    the_case = load(case)
    if not speed > 0:
        fail_user(f"--speed = {speed!r}: must be > 0 (in {the_case.sweep.unit})")
    return the_case, speed * SPEED_UNITS[the_case.sweep.unit]


def load(case: str | None):
    from ..config import CaseError, load_case

    try:
        return load_case(case or DEFAULT_CASE)
    except CaseError as err:
        fail_user(str(err))


OUT = click.option(
    "--out",
    "out",
    type=click.Path(file_okay=False),
    default=None,
    help="Output directory [default: groundres-out/<case name>].",
)


def make_console():
    from rich.console import Console

    return Console(stderr=False, highlight=False)


def status(console, text):
    """A spinner while something slow runs (only on a terminal)."""
    import contextlib

    if console.is_terminal:
        from rich.text import Text

        return console.status(Text(text))  # plain text: a title's brackets are not markup
    return contextlib.nullcontext()


def fmt_speed(w, sweep, digits: int = 5, ref: bool = True):
    """A speed [rad/s] in the case's unit, with its ratio to the reference ("ref")."""
    from ..params import SPEED_UNITS

    text = f"{w / SPEED_UNITS[sweep.unit]:.{digits}g} {sweep.unit}"
    if ref and sweep.reference:
        text += f" ({w / sweep.reference:.4g} ref)"
    return text


#: How a frequency reads in a case whose speeds are in each unit (as on the Coleman diagram).
FREQUENCY_UNITS = {"rad/s": "rad/s", "rpm": "cycles/min", "Hz": "Hz"}


def fmt_frequency(w, sweep, digits: int = 4):
    """A frequency [rad/s] in the case's unit (cycles/min for rpm), rad/s beside it."""
    from ..params import SPEED_UNITS

    text = f"{w / SPEED_UNITS[sweep.unit]:.{digits}g} {FREQUENCY_UNITS[sweep.unit]}"
    return text if sweep.unit == "rad/s" else f"{text} ({w:.{digits}g} rad/s)"


def ref_note(sweep) -> str | None:
    """The line that explains "ref" once, or None without a reference speed."""
    if not sweep.reference:
        return None
    return f"ref: rotor speed / the case's reference speed, {fmt_speed(sweep.reference, sweep, ref=False)}."


def plain(text) -> str:
    """User text (a title, a label) made safe to print through rich: markup shown literally."""
    from rich.markup import escape

    return escape(str(text))
