"""What every command shares: user errors, loading a case, the console, speed text."""

from __future__ import annotations

import contextlib
from pathlib import Path

import click

from ..errors import printable, shown

DEFAULT_CASE = "hammond-undamped"


class UserError(click.ClickException):
    """A mistake the user can mend: ``error: <message>`` on stderr, exit status 2; the message
    has its control characters escaped (:func:`groundres.errors.printable`)."""

    exit_code = 2

    def __init__(self, message: str):
        super().__init__(printable(message))

    def show(self, file=None):
        click.echo(f"error: {self.message}", err=True)


def fail_user(message: str):
    raise UserError(message)


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread so that cleanup runs as for Ctrl-C."""


#: Set when SIGTERM arrives: a Terminated raised inside a weak-reference callback or a
#: destructor is swallowed by Python, so the block it interrupted raises it again at its end.
_TERMINATED = []


def _terminate(signum, frame):
    _TERMINATED.append(signum)
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
    _TERMINATED.clear()
    try:
        yield
        if _TERMINATED:  # (the Terminated raised was swallowed where it landed)
            raise Terminated()
    finally:
        signal.signal(signal.SIGTERM, previous if previous is not None else signal.SIG_DFL)


def matplotlib_folder() -> None:
    """Give matplotlib a private configuration and cache folder where its own is not writable
    (a read-only or missing HOME), before it is imported: it would otherwise make a
    temporary one itself and say so on every run. The folder is made by
    :func:`tempfile.mkdtemp` (mode 0700: no other account can put a matplotlibrc or a
    font cache in it) and removed at exit; MPLCONFIGDIR, if set, is left as it is.
    """
    import os
    import sys

    if os.environ.get("MPLCONFIGDIR") or "matplotlib" in sys.modules or sys.platform == "win32":
        return
    try:
        home = Path.home()
    except RuntimeError:  # (no HOME and no account entry)
        home = None
    if sys.platform.startswith(("linux", "freebsd")):
        bases = [
            os.environ.get("XDG_CONFIG_HOME") or (home and home / ".config"),
            os.environ.get("XDG_CACHE_HOME") or (home and home / ".cache"),
        ]
        folders = [base and Path(base) / "matplotlib" for base in bases]
    else:
        folders = [home and home / ".matplotlib"]
    if all(folder and _writable_folder(folder) for folder in folders):
        return
    import atexit
    import shutil
    import tempfile

    private = tempfile.mkdtemp(prefix="groundres-matplotlib-")
    atexit.register(shutil.rmtree, private, ignore_errors=True)
    os.environ["MPLCONFIGDIR"] = private


def _writable_folder(folder: Path) -> bool:
    """Whether ``folder`` is, or can be made, a writable folder (as matplotlib tries its own)."""
    import os

    try:
        folder = folder.resolve()
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        return False
    return folder.is_dir() and os.access(folder, os.W_OK)


def output_dir(case: str | None, out, command: str = "run") -> Path:
    """--out, or groundres-out/<case name> for run and groundres-out/<case name>-<command> otherwise.

    Each command's folder is replaced whole, so commands never share a default.
    """
    if out is not None:
        if not out.strip():
            fail_user(f"--out {shown(out)}: empty; give a folder, e.g. --out results")
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


@contextlib.contextmanager
def method_named():
    """A method the block's analysis cannot use named as the command line gave it: ``--method
    eigen`` where the option asked for it, the case's ``[sweep] method`` otherwise."""
    from ..errors import MethodError

    try:
        yield
    except MethodError as err:
        if err.key != "method":  # (the case's own: its message names the key)
            raise
        fail_user(err.named(f"--method {err.value}"))


def invocation() -> dict:
    """The command line and start time of this run (for provenance.json)."""
    from ..model.casefile import source_name

    meta = click.get_current_context().meta
    # (an argument the file system gave as bytes that are no UTF-8: its bytes escaped, as every
    # output takes only valid Unicode)
    argv = [source_name(arg) for arg in meta.get("groundres.argv", [])]
    return {"argv": argv, "started": meta.get("groundres.started", "")}


def case_at_speed(case: str | None, speed: float):
    """The case and a --speed (in the case's unit) in rad/s."""
    import math

    from ..model.units import SPEED_UNITS

    the_case = load(case)
    unit = the_case.sweep.unit
    if not (math.isfinite(speed) and speed > 0):
        fail_user(f"--speed = {shown(speed)}: must be a finite number > 0 (in {unit}, the case's unit)")
    w = speed * SPEED_UNITS[unit]
    if not (math.isfinite(w) and w > 0):
        fail_user(f"--speed = {shown(speed)} {unit}: outside the floating-point range in rad/s")
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
    from ..errors import CaseError
    from ..model.schema import load_case

    if case is not None and not case.strip():
        default = "" if named else " (none: the default case)"
        fail_user(f"CASE {shown(case)}: empty; give a case file or a shipped case name{default}")
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


def make_console(**options):
    """The console commands print to (stdout; ``options`` of rich's Console): no highlighting,
    and no control character of printed text reaches the terminal (:class:`_Printable`),
    whatever the command printed."""
    from rich.console import Console

    console = Console(**{"stderr": False, "highlight": False, **options})
    console.push_render_hook(_Printable())
    return console


class _Printable:
    """A rich render hook: every printed renderable with control characters in its text
    escaped (rich's own styles and cursor moves are control segments, kept). Text
    is escaped before layout where it is made (:func:`plain`); this holds for the rest."""

    def process_renderables(self, renderables):
        return [_Escaped(r) for r in renderables]


class _Escaped:
    def __init__(self, renderable):
        self.renderable = renderable

    def __rich_console__(self, console, options):
        from rich.segment import Segment

        for segment in console.render(self.renderable, options):
            text, style, control = segment
            yield segment if control else Segment(printable(text), style, control)


def status(console, text):
    """A spinner while something slow runs (only on a terminal), its text shown literally."""
    if console.is_terminal:
        from rich.text import Text

        return console.status(Text(plain_text(text)))  # plain text: a title's brackets are not markup
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
            label = plain_text(self.labels.get(stage, stage))  # (a case's name in it, escaped)
            self._tasks[stage] = self._progress.add_task(label, total=total)
        self._progress.update(self._tasks[stage], completed=done, total=total)

    def step(self, stage: str):
        """A spinner with elapsed time around a block (completed when it ends)."""

        @contextlib.contextmanager
        def block():
            self(stage, 0, None)
            yield
            self(stage, 1, 1)

        return block()


def plain_text(text) -> str:
    """User text (a title, a path) as printed: every control character but a line end escaped
    (``\\x1b``: an escape sequence in a title must not drive the terminal)."""
    return printable(text)


def plain(text) -> str:
    """User text (a title, a label) made safe to print through rich as markup: as
    :func:`plain_text`, and its markup shown literally."""
    from rich.markup import escape

    return escape(plain_text(text))
