"""What every command shares: user errors, loading a case, the console, speed text."""

from __future__ import annotations

import contextlib
from pathlib import Path

import click

DEFAULT_CASE = "hammond-undamped"


class UserError(click.ClickException):
    exit_code = 2

    def show(self, file=None):
        click.echo(f"error: {self.message}", err=True)


def fail_user(message: str):
    raise UserError(message)


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread so that cleanup runs as for Ctrl-C."""


def _terminate(signum, frame):
    raise Terminated()


@contextlib.contextmanager
def interrupts():
    """SIGTERM raises Terminated while the block runs (Ctrl-C raises KeyboardInterrupt)."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, _terminate)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous if previous is not None else signal.SIG_DFL)


def output_dir(case: str | None, out, command: str = "run") -> Path:
    """--out, or groundres-out/<case name> for run and groundres-out/<case name>-<command> otherwise.

    Each command's folder is replaced whole, so commands never share a default.
    """
    if out is not None:
        if not out.strip():
            fail_user(f"--out {out!r}: empty; give a folder, e.g. --out results")
        return Path(out)
    name = Path(case).stem if case else DEFAULT_CASE
    return Path("groundres-out") / (name if command == "run" else f"{name}-{command}")


def out_name(out) -> str:
    """What messages call an output folder: --out, or the default one (when --out was not given)."""
    return "--out" if out is not None else "the default output folder (choose one with --out)"


def check_out(path: Path, out=None) -> None:
    """Refuse, before any work, an output folder that cannot be made or replaced (a name too long,
    a parent that is a file, a folder that is not writable) or holds files groundres did not
    write. ``out``: the --out given (None: ``path`` is the default)."""
    from ..errors import OutputFolderError
    from ..results.folders import check_output_folder

    try:
        check_output_folder(path, out_name(out))
    except OutputFolderError as err:
        fail_user(str(err))


def invocation() -> dict:
    """The command line and start time of this run (for provenance.json)."""
    meta = click.get_current_context().meta
    return {"argv": meta.get("groundres.argv", []), "started": meta.get("groundres.started", "")}


def case_at_speed(case: str | None, speed: float):
    """The case and a --speed (in the case's unit) in rad/s."""
    import math

    from ..model.units import SPEED_UNITS

    the_case = load(case)
    unit = the_case.sweep.unit
    if not (math.isfinite(speed) and speed > 0):
        fail_user(f"--speed = {speed!r}: must be a finite number > 0 (in {unit}, the case's unit)")
    w = speed * SPEED_UNITS[unit]
    if not (math.isfinite(w) and w > 0):
        fail_user(f"--speed = {speed!r} {unit}: outside the floating-point range in rad/s")
    from ..assess.resolution import check_representable
    from ..model.system import System

    # (an error here is a ModelRangeError, which the command line turns into exit 2)
    system = System.in_mass_unit(the_case.rotor, the_case.body)
    check_representable(system, w, "--speed", (unit, SPEED_UNITS[unit]))
    return the_case, w


def load(case: str | None, named: bool = False):
    """The CASE argument as a case (None: the default case); a bad one is a one-line error, exit 2.

    ``named``: the message names the argument (for commands that read several cases).
    """
    from ..errors import CaseError, shown
    from ..model.schema import load_case

    if case is not None and not case.strip():
        default = "" if named else " (none: the default case)"
        fail_user(f"CASE {case!r}: empty; give a case file or a shipped case name{default}")
    try:
        return load_case(case if case is not None else DEFAULT_CASE)
    except CaseError as err:
        message = str(err)
        fail_user(f"CASE {shown(case)}: {message}" if named and case not in message else message)


def out_option(default: str):
    """--out, replaced whole by each run (see docs/case-files.md, outputs)."""
    return click.option(
        "--out",
        "out",
        type=click.Path(file_okay=False),
        default=None,
        help=f"Output folder, replaced whole by this run; refused before any work if it holds other "
        f"files or cannot be written or replaced [default: {default}].",
    )


OUT = out_option("groundres-out/<case name>")

#: File formats of pictures (matplotlib writes each; animations stay GIF).
FIGURE_FORMATS = ("png", "svg", "pdf")

#: --format, for every command that draws a picture.
FORMAT = click.option(
    "--format",
    "fmt",
    type=click.Choice(FIGURE_FORMATS),
    default="png",
    show_default=True,
    help="File format of the pictures written.",
)


def make_console():
    from rich.console import Console

    return Console(stderr=False, highlight=False)


def status(console, text):
    """A spinner while something slow runs (only on a terminal), its text shown literally."""
    if console.is_terminal:
        from rich.text import Text

        return console.status(Text(text))  # plain text: a title's brackets are not markup
    return contextlib.nullcontext()


class Steps:
    """Rich progress of a command's slow steps, on a terminal only (transient).

    Call it as ``steps(stage, done, total)`` (``total`` None for a spinner);
    ``steps.callback`` is the same callable on a terminal and None elsewhere,
    for library functions that take a ``progress`` argument.
    """

    def __init__(self, console, labels=None):
        self.console = console
        self.labels = labels or {}
        self._progress = None
        self._tasks = {}

    def __enter__(self):
        if self.console.is_terminal:
            from rich.progress import (
                BarColumn,
                Progress,
                SpinnerColumn,
                TaskProgressColumn,
                TextColumn,
                TimeElapsedColumn,
            )

            self._progress = Progress(
                SpinnerColumn(),
                TextColumn("{task.description}", markup=False),
                BarColumn(),
                TaskProgressColumn(),
                TimeElapsedColumn(),
                console=self.console,
                transient=True,
            )
            self._progress.start()
        return self

    def __exit__(self, *exc):
        if self._progress is not None:
            self._progress.stop()
            self._progress = None

    @property
    def callback(self):
        return self if self._progress is not None else None

    def __call__(self, stage: str, done: float, total: float | None = None) -> None:
        if self._progress is None:
            return
        if stage not in self._tasks:
            self._tasks[stage] = self._progress.add_task(self.labels.get(stage, stage), total=total)
        self._progress.update(self._tasks[stage], completed=done, total=total)

    def step(self, stage: str):
        """A spinner with elapsed time around a block (completed when it ends)."""

        @contextlib.contextmanager
        def block():
            self(stage, 0, None)
            yield
            self(stage, 1, 1)

        return block()


def plain(text) -> str:
    """User text (a title, a label) made safe to print through rich: markup shown literally, and no
    control character but line ends and tabs (an escape sequence in a title must not drive the terminal)."""
    import unicodedata

    from rich.markup import escape

    text = "".join(ch for ch in str(text) if ch in "\n\t" or unicodedata.category(ch) != "Cc")
    return escape(text)
