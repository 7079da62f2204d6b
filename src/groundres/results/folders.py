"""Output folders: each command's folder is one unit, put in place whole, with its provenance.

A command writes all its files into a fresh hidden folder beside the target
and then, under a lock on the parent, moves the old folder aside, the new one
into place and removes the old one: an interrupted run leaves the old folder
or nothing, and two runs into one folder cannot mix (the later one wins).
The folder holds the case text that produced it and ``provenance.json``
(:func:`write_provenance`), which also marks it as groundres output.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil
import signal
import tempfile
import threading
from pathlib import Path

from ..errors import OutputFolderError
from .files import current_umask, strict, write_bytes, write_json

#: The file that marks a folder as groundres output (and lists its files).
PROVENANCE = "provenance.json"
#: The case text that produced the folder.
CASE_COPY = "case.toml"
_HIDDEN = ".groundres-"
_LOCK = ".groundres.lock"
#: Hidden folders of a run in progress: new (being written) and old (being replaced).
_STAGING = re.compile(r"\.groundres-(new|old)-(\d+)-[a-z0-9_]+-.*")
#: What commands wrote before folders carried provenance.json (these may be replaced too).
_OLDER_OUTPUTS = re.compile(
    r"summary\.json|modes\.csv|modes\.nc|coleman\.png|simulation\.(png|csv)|phasors\.(csv|json)"
    r"|phasors_.+\.png|mode_.+\.gif|\..+\.part(\..+)?"
)


def foreign_entries(path: str | Path) -> list[str]:
    """Entries of an existing folder that groundres did not write (none: it may be replaced).

    A groundres folder lists its files in ``provenance.json``; a folder without
    one counts as groundres output only if every entry has the name of a file
    an earlier version wrote. Anything but a regular file is foreign.
    """
    path = Path(path)
    entries = {e.name: e.is_file(follow_symlinks=False) for e in os.scandir(path)}
    ours = None
    if entries.get(PROVENANCE):
        with contextlib.suppress(OSError, ValueError, AttributeError, TypeError):
            record = json.loads((path / PROVENANCE).read_text(encoding="utf-8"))
            if record.get("generator") == "groundres":
                ours = {str(name) for name in record["files"]} | {PROVENANCE}
    if ours is None:
        return sorted(n for n, regular in entries.items() if not (regular and _OLDER_OUTPUTS.fullmatch(n)))
    return sorted(n for n, regular in entries.items() if not (regular and n in ours))


def check_output_folder(path: str | Path) -> None:
    """Raise OutputFolderError unless ``path`` can become (or be replaced by) an output folder.

    It may be missing (its first existing parent must be a folder), empty, or a
    folder groundres wrote that holds nothing else.
    """
    given, path = path, Path(os.path.realpath(path))
    if path == Path(os.path.realpath(os.getcwd())):
        raise OutputFolderError(
            f"output folder {given}: is the current folder, which a run would replace whole; "
            "choose a folder inside it, e.g. --out results"
        )
    if path.exists() and not path.is_dir():
        raise OutputFolderError(f"output folder {given}: exists and is not a folder")
    if not path.exists():
        parent = path.parent
        while not parent.exists():
            parent = parent.parent
        if not parent.is_dir():
            raise OutputFolderError(f"output folder {given}: {parent} is not a folder")
        _check_writable(given, parent)
        return
    _check_writable(given, path.parent)
    foreign = foreign_entries(path)
    if foreign:
        shown = ", ".join(foreign[:5]) + (f" and {len(foreign) - 5} more" if len(foreign) > 5 else "")
        raise OutputFolderError(
            f"output folder {given}: not a groundres output folder (it holds {shown}, which groundres "
            "did not write), so it is not replaced; choose a new or empty folder with --out"
        )


def _check_writable(given, folder: Path) -> None:
    """Raise OutputFolderError unless a folder can be made (and removed) in ``folder``,
    where the fresh output folder will be made."""
    try:
        os.rmdir(tempfile.mkdtemp(dir=folder, prefix=f"{_HIDDEN}probe-"))
    except OSError as err:
        raise _unwritable(given, folder, err) from None


def _unwritable(given, folder, err: OSError) -> OutputFolderError:
    return OutputFolderError(
        f"output folder {given}: cannot write in {folder} ({err.strerror}); choose another --out"
    )


@contextlib.contextmanager
def output_folder(path: str | Path):
    """Yield a fresh hidden folder beside ``path``; on success it replaces ``path`` whole.

    On any exception (an interrupt included) the fresh folder is removed and
    ``path`` is left as it was. Stale folders of runs that were killed are
    removed by the next run into the same parent.

    Raises
    ------
    OutputFolderError
        If ``path`` holds files groundres did not write (see :func:`check_output_folder`).
    """
    check_output_folder(path)
    target = Path(os.path.realpath(path))
    fresh = None
    try:
        with _signals_deferred():  # an interrupt now still finds the name to remove
            try:
                target.parent.mkdir(parents=True, exist_ok=True)
                fresh = Path(
                    tempfile.mkdtemp(
                        dir=target.parent, prefix=f"{_HIDDEN}new-{os.getpid()}-", suffix=f"-{target.name}"
                    )
                )
            except OSError as err:
                raise _unwritable(path, target.parent, err) from None
        yield fresh
        os.chmod(fresh, 0o777 & ~current_umask())
        with _signals_deferred(), _locked(target.parent):
            _remove_stale(target.parent)
            _swap(fresh, target, path)
    finally:
        if fresh is not None and fresh.exists():
            with _signals_deferred():
                shutil.rmtree(fresh, ignore_errors=True)


def _swap(fresh: Path, target: Path, given) -> None:
    """Put ``fresh`` in place of ``target`` (which is re-checked: it may have changed meanwhile)."""
    if not (target.exists() or target.is_symlink()):
        os.rename(fresh, target)
        return
    if target.is_symlink() or not target.is_dir():
        raise OutputFolderError(f"output folder {given}: exists and is not a folder")
    check_output_folder(given)
    aside = tempfile.mkdtemp(
        dir=target.parent, prefix=f"{_HIDDEN}old-{os.getpid()}-", suffix=f"-{target.name}"
    )
    try:
        os.rename(target, aside)  # (onto the empty folder just made: a unique name)
    except OSError as err:  # a mount point, an immutable folder: it cannot be moved aside
        os.rmdir(aside)
        raise OutputFolderError(
            f"output folder {given}: cannot be replaced ({err.strerror or err}; a mount point or a "
            "folder that may not be moved): give a folder inside it, e.g. --out "
            f"{os.path.join(str(given), 'results')}"
        ) from None
    try:
        os.rename(fresh, target)
    except BaseException:
        os.rename(aside, target)
        raise
    shutil.rmtree(aside, ignore_errors=True)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _remove_stale(parent: Path) -> None:
    """Remove the hidden folders of runs into ``parent`` whose process is gone."""
    for entry in os.scandir(parent):
        match = _STAGING.fullmatch(entry.name)
        if match and entry.is_dir(follow_symlinks=False) and not _alive(int(match[2])):
            shutil.rmtree(entry.path, ignore_errors=True)


@contextlib.contextmanager
def _locked(parent: Path):
    """An exclusive lock for swapping folders in ``parent`` (a lock file, removed after)."""
    try:
        import fcntl
    except ImportError:  # no flock (Windows): swaps are not serialised
        yield
        return
    lock = parent / _LOCK
    while True:
        fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o666)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)
            try:
                same = os.stat(lock).st_ino == os.fstat(fd).st_ino
            except FileNotFoundError:
                same = False
            if same:
                break  # (else the holder before removed the file: lock the new one)
        except BaseException:
            os.close(fd)
            raise
        os.close(fd)
    try:
        yield
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(lock)
        os.close(fd)


@contextlib.contextmanager
def _signals_deferred():
    """Hold SIGINT and SIGTERM until the block is done, then deliver the first that came."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught = []
    previous = {}
    for sig in (signal.SIGINT, signal.SIGTERM):
        handler = signal.getsignal(sig)
        if handler is not None and handler is not signal.SIG_IGN:
            previous[sig] = signal.signal(sig, lambda number, frame: caught.append(number))
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        if caught:
            signal.raise_signal(caught[0])


def write_provenance(
    folder: str | Path,
    case,
    *,
    command: str,
    argv=(),
    started: str = "",
    method: str | None = None,
    frame: str | None = None,
    accuracy: dict | None = None,
    **extra,
) -> dict:
    """Write ``case.toml`` (the case text exactly as read) and ``provenance.json`` into ``folder``.

    Call it last: ``provenance.json`` lists every file of the folder (itself
    included), which is how a later run knows it may replace the folder.
    Returns the record written (see docs/case-files.md).
    """
    import hashlib
    import platform
    import shlex
    from datetime import UTC, datetime
    from importlib import metadata

    from .._version import __version__

    folder = Path(folder)
    data = case.text.encode("utf-8")
    if case.text:
        write_bytes(folder / CASE_COPY, data)

    def version(name):
        try:
            return metadata.version(name)
        except metadata.PackageNotFoundError:
            return None

    record = {
        "generator": "groundres",
        "groundres_version": __version__,
        "command": command,
        "command_line": shlex.join(["groundres", *argv]),
        "argv": ["groundres", *argv],
        "started": started,
        "finished": datetime.now(UTC).isoformat(timespec="seconds"),
        "case": {
            "title": case.title,
            "source": case.source,
            "file": CASE_COPY if case.text else None,
            "sha256": hashlib.sha256(data).hexdigest() if case.text else None,
        },
        "method": method,
        "frame": frame,
        "accuracy": accuracy or {},
        **extra,
        "software": {
            "python": platform.python_version(),
            **{name: version(name) for name in ("numpy", "scipy", "sympy", "matplotlib", "netCDF4")},
            "platform": platform.platform(),
        },
    }
    record["files"] = sorted({*os.listdir(folder), PROVENANCE})
    record = strict(record)
    write_json(folder / PROVENANCE, record)
    return record
