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
    import math

    from ..params import SPEED_UNITS

    the_case = load(case)
    unit = the_case.sweep.unit
    if not (math.isfinite(speed) and speed > 0):
        fail_user(f"--speed = {speed!r}: must be a finite number > 0 (in {unit}, the case's unit)")
    w = speed * SPEED_UNITS[unit]
    if not (math.isfinite(w) and w > 0):
        fail_user(f"--speed = {speed!r} {unit}: outside the floating-point range in rad/s")
    return the_case, w


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
        return console.status(text)
    return contextlib.nullcontext()


def first_run() -> bool:
    from ..symbolic import codegen

    return not codegen._paths()[0].exists()


def fmt_speed(w, sweep):
    """A speed [rad/s] in the case's unit, with its ratio to the reference."""
    from ..params import SPEED_UNITS

    text = f"{w / SPEED_UNITS[sweep.unit]:.5g} {sweep.unit}"
    if sweep.reference:
        text += f" ({w / sweep.reference:.4g} ref)"
    return text
