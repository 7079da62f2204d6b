"""Output folders: each command's folder is one unit, put in place whole, with its provenance.

A command writes all its files into a fresh hidden folder beside the target
and then, under a lock on the parent, moves the old folder aside, the new one
into place and removes the old one: an interrupted run leaves the old folder
or nothing, and two runs into one folder cannot mix (the later one wins).
The folder holds the case text that produced it and ``provenance.json``
(:func:`write_provenance`), which also marks it as groundres output.

Before any work, :func:`check_folder` refuses a folder that cannot be made
or replaced: a name or path too long for the file system, a parent that is a
file or cannot be searched, a parent or folder that is not writable (whose
old files could not be removed), a mount point. Nothing a failed run made is
left beside the folder (the hidden folders' names are ``.groundres-*``).
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import re
import shutil
import signal
import stat
import tempfile
import threading
from pathlib import Path

from ..errors import OutputFolderError, shown, shown_path
from ..model.casefile import file_type, read_file
from . import lock
from .files import current_umask, strict, write_bytes, write_json

#: The file that marks a folder as groundres output (and lists its files).
PROVENANCE = "provenance.json"
#: The case text that produced the folder.
CASE_COPY = "case.toml"
#: The longest name and path [bytes] where the file system does not say (POSIX's usual values).
NAME_MAX, PATH_MAX = 255, 4096
#: Bytes of a path kept for what a command puts inside its folder: the hidden folder's longer
#: name, the files' names and their temporary names.
ROOM = 256
#: Largest provenance.json read [bytes]; it lists a folder's files and the software.
MAX_PROVENANCE_BYTES = 16_000_000
_HIDDEN = ".groundres-"
#: Hidden folders of a run in progress: new (being written), old (being replaced) and the probe
#: of whether a parent is writable.
_STAGING = re.compile(r"\.groundres-(new|old|probe)-(\d+)-[a-z0-9_]+(-.*)?", re.DOTALL)
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
            raw = read_file(path / PROVENANCE, PROVENANCE, MAX_PROVENANCE_BYTES)
            record = json.loads(raw.decode("utf-8")) if len(raw) <= MAX_PROVENANCE_BYTES else {}
            if record.get("generator") == "groundres":
                ours = {str(name) for name in record["files"]} | {PROVENANCE}
    if ours is None:
        return sorted(n for n, regular in entries.items() if not (regular and _OLDER_OUTPUTS.fullmatch(n)))
    return sorted(n for n, regular in entries.items() if not (regular and n in ours))


def check_output_folder(path: str | Path, name: str = "output folder") -> None:
    """Raise OutputFolderError unless ``path`` can become (or be replaced by) an output folder.

    It may be missing (see :func:`check_folder`), empty, or a folder groundres
    wrote that holds nothing else. ``name``: what messages call it (``--out``).
    """
    if not check_folder(path, name):
        return
    foreign = foreign_entries(os.path.realpath(path))
    if foreign:
        listed = ", ".join(shown(n) for n in foreign[:5]) + (
            f" and {len(foreign) - 5} more" if len(foreign) > 5 else ""
        )
        raise OutputFolderError(
            f"{name} {shown_path(path)}: not a groundres output folder (it holds {listed}, which "
            "groundres did not write), so it is not replaced; choose a new or empty folder with --out"
        )


def check_folder(path: str | Path, name: str = "output folder", *, replace: bool = True) -> bool:
    """Raise OutputFolderError unless a command can write the folder ``path``; whether it exists.

    Checked without writing anything there: names within the file system's
    NAME_MAX and the whole real path within its PATH_MAX less :data:`ROOM`;
    every part on the way reachable; a missing folder's nearest existing parent
    a folder in which one can be made. An existing folder must be readable,
    writable and searchable; one that is ``replace``-d whole (moved aside and
    removed) must also not be the current folder or a mount point, and its
    parent must be writable (and, if that parent has the sticky bit, one of
    the two must be the user's). ``name``: what messages call the folder.
    """
    label = f"{name} {shown_path(path)}"
    text = os.fspath(path)
    if "\0" in text:
        raise OutputFolderError(f"{label}: not a usable folder name (it holds a NUL character)")
    if _size(text) > FAR * PATH_MAX:  # (no file system takes it; resolving it costs its length squared)
        raise OutputFolderError(
            f"{label}: its path is {_size(text)} bytes long, far over the {PATH_MAX} a path may have "
            "(PATH_MAX); choose a shorter one"
        )
    try:
        real = Path(os.path.realpath(text))
    except FileNotFoundError:  # (a relative path, from a current folder since removed)
        raise OutputFolderError(f"{label}: the current folder no longer exists; give a full path") from None
    nearest, status = _nearest(real, label)
    name_max, path_max = _limits(nearest)
    for part in real.parts[1:]:
        if _size(part) > name_max:
            raise OutputFolderError(
                f"{label}: the name {shown(part)} is {_size(part)} bytes long, over the {name_max} a "
                f"name may have in {shown_path(nearest)} (NAME_MAX); choose a shorter one"
            )
    if _size(str(real)) > path_max - ROOM:
        raise OutputFolderError(
            f"{label}: its full path is {_size(str(real))} bytes long, over the {path_max - ROOM} a "
            f"folder may have here (PATH_MAX {path_max} less {ROOM} for the files inside); choose a "
            "shorter one"
        )
    if nearest != real:
        if not stat.S_ISDIR(status.st_mode):
            raise OutputFolderError(f"{label}: cannot be made: {shown_path(nearest)} is {_kind(status)}")
        _check_writable(label, nearest, "cannot be made: ")
        if nearest == real.parent:
            lock.check(nearest)
        return False
    if not stat.S_ISDIR(status.st_mode):
        raise OutputFolderError(f"{label}: exists and is {_kind(status)}")
    if replace and real == Path(os.path.realpath(os.getcwd())):
        raise OutputFolderError(
            f"{label}: is the current folder, which a run would replace whole; "
            "choose a folder inside it, e.g. --out results"
        )
    if not _access(real, os.R_OK | os.X_OK):
        raise OutputFolderError(f"{label}: cannot be read (permission denied); choose another --out")
    if not _access(real, os.W_OK):
        what = (
            "cannot be replaced: not writable (its files could not be removed)" if replace else "not writable"
        )
        raise OutputFolderError(f"{label}: {what}; make it writable (chmod u+w) or choose another --out")
    if replace:
        inside = shown_path(os.path.join(text, "results"))
        if os.path.ismount(real):
            raise OutputFolderError(
                f"{label}: cannot be replaced: a mount point, which cannot be moved; give a folder "
                f"inside it, e.g. --out {inside}"
            )
        _check_writable(label, real.parent, "cannot be replaced: ")
        lock.check(real.parent)
        _check_sticky(label, real, status)
    return True


#: A path this many times :data:`PATH_MAX` long is refused before it is resolved.
FAR = 4


def _size(text: str) -> int:
    """Bytes of a name as the file system takes it."""
    try:
        return len(os.fsencode(text))
    except UnicodeError:  # (a lone surrogate: no file system takes it, and it fails there)
        return len(text.encode("utf-8", "surrogatepass"))


def _limits(folder: Path) -> tuple[int, int]:
    """(NAME_MAX, PATH_MAX) of the file system of ``folder`` [bytes], or the usual values."""
    found = []
    for key, usual in (("PC_NAME_MAX", NAME_MAX), ("PC_PATH_MAX", PATH_MAX)):
        try:
            value = os.pathconf(folder, key)
        except (OSError, ValueError, AttributeError):  # (no pathconf: Windows)
            value = -1
        found.append(value if value > 0 else usual)
    return found[0], found[1]


def _nearest(real: Path, label: str) -> tuple[Path, os.stat_result]:
    """The nearest existing path of ``real`` and its parents, and its status; OutputFolderError
    where the way to it is barred (a folder that cannot be searched, a loop of symbolic links)."""
    barred = None  # (the first error on the way up, and the last path it barred)
    for candidate in (real, *real.parents):
        try:
            status = os.stat(candidate)
        except OSError as err:
            if err.errno in (errno.EACCES, errno.ELOOP):
                barred = (barred[0] if barred else err.errno, candidate)
            elif err.errno not in (errno.ENOENT, errno.ENOTDIR, errno.ENAMETOOLONG):
                raise OutputFolderError(
                    f"{label}: cannot reach {shown_path(candidate)} ({err.strerror or err}); "
                    "choose another --out"
                ) from None
            continue  # (a name over NAME_MAX is said by the caller)
        if barred and barred[0] == errno.EACCES:
            raise OutputFolderError(
                f"{label}: cannot be reached: {shown_path(candidate)} cannot be searched (permission "
                "denied); choose another --out"
            )
        if barred:
            raise OutputFolderError(
                f"{label}: cannot be reached: {shown_path(barred[1])} is a loop of symbolic links; "
                "choose another --out"
            )
        return candidate, status
    raise OutputFolderError(f"{label}: no part of it exists")  # (the root always does)


def _kind(status: os.stat_result) -> str:
    return f"not a folder ({file_type(status.st_mode)})"


def _access(path: Path, mode: int) -> bool:
    """Whether this process may use ``path`` so (by its effective ids where the system tells)."""
    if os.access in os.supports_effective_ids:
        return os.access(path, mode, effective_ids=True)
    return os.access(path, mode)


def _check_writable(label: str, folder: Path, what: str) -> None:
    """Raise OutputFolderError unless a folder can be made (and removed) in ``folder``, where the
    fresh output folder will be made (a probe: permissions, a read-only file system, quotas)."""
    try:
        with _signals_deferred():  # (an interrupt still finds the probe to remove)
            os.rmdir(tempfile.mkdtemp(dir=folder, prefix=f"{_HIDDEN}probe-{os.getpid()}-"))
    except OSError as err:
        raise _unwritable(label, folder, err, what) from None


def _check_sticky(label: str, real: Path, status: os.stat_result) -> None:
    """Refuse a folder that cannot be moved aside: in a parent with the sticky bit (such as
    /tmp), a folder that neither it nor its parent is the user's."""
    if not hasattr(os, "geteuid") or os.geteuid() == 0:
        return
    parent = os.stat(real.parent)
    if parent.st_mode & stat.S_ISVTX and os.geteuid() not in (status.st_uid, parent.st_uid):
        raise OutputFolderError(
            f"{label}: cannot be replaced: it is another user's, in {shown_path(real.parent)}, where only "
            "its owner may move it; choose another --out"
        )


def _unwritable(label: str, folder, err: OSError, what: str = "") -> OutputFolderError:
    return OutputFolderError(
        f"{label}: {what}cannot write in {shown_path(folder)} ({err.strerror or err}); choose another --out"
    )


def _hidden_name(kind: str, target: Path) -> tuple[str, str]:
    """(prefix, suffix) of a hidden folder beside ``target`` (mkdtemp puts 8 characters between
    them): the target's name shortened so that the whole is within NAME_MAX."""
    prefix = f"{_HIDDEN}{kind}-{os.getpid()}-"
    room = _limits(target.parent)[0] - len(prefix) - 8 - 1
    name = target.name
    while name and _size(name) > room:
        name = name[: max(0, min(len(name) - 1, room))]
    return prefix, f"-{name}" if name else ""


@contextlib.contextmanager
def output_folder(path: str | Path, name: str = "output folder"):
    """Yield a fresh hidden folder beside ``path``; on success it replaces ``path`` whole.

    On any exception (an interrupt included) the fresh folder is removed and
    ``path`` is left as it was. Stale folders of runs that were killed are
    removed by the next run into the same parent. ``name``: what messages call
    the folder (``--out``).

    Raises
    ------
    OutputFolderError
        If ``path`` holds files groundres did not write, or cannot be made or
        replaced (see :func:`check_output_folder`).
    """
    check_output_folder(path, name)
    target = Path(os.path.realpath(path))
    fresh, made, done = None, [p for p in target.parents if not os.path.lexists(p)], False
    try:
        with _signals_deferred():  # an interrupt now still finds the name to remove
            try:
                target.parent.mkdir(parents=True, exist_ok=True)
                prefix, suffix = _hidden_name("new", target)
                fresh = Path(tempfile.mkdtemp(dir=target.parent, prefix=prefix, suffix=suffix))
                os.chmod(fresh, stat.S_IRWXU)  # (writable while written, whatever the umask)
            except OSError as err:
                raise _unwritable(f"{name} {shown_path(path)}", target.parent, err) from None
        yield fresh
        os.chmod(fresh, 0o777 & ~current_umask())
        with _signals_deferred(), lock.locked(target.parent):
            _remove_stale(target.parent)
            _swap(fresh, target, path, name)
        done = True
    finally:
        with _signals_deferred():
            if fresh is not None and fresh.exists():
                _remove(fresh)
            for parent in made if not done else ():  # (the parents this run made, if still empty)
                with contextlib.suppress(OSError):
                    os.rmdir(parent)


def _swap(fresh: Path, target: Path, given, name: str) -> None:
    """Put ``fresh`` in place of ``target`` (which is re-checked: it may have changed meanwhile)."""
    if not (target.exists() or target.is_symlink()):
        os.rename(fresh, target)
        return
    label = f"{name} {shown_path(given)}"
    if target.is_symlink() or not target.is_dir():
        raise OutputFolderError(f"{label}: exists and is not a folder")
    check_output_folder(given, name)
    prefix, suffix = _hidden_name("old", target)
    aside = tempfile.mkdtemp(dir=target.parent, prefix=prefix, suffix=suffix)
    try:
        os.rename(target, aside)  # (onto the empty folder just made: a unique name)
    except OSError as err:  # a mount point, an immutable folder: it cannot be moved aside
        os.rmdir(aside)
        raise OutputFolderError(
            f"{label}: cannot be replaced ({err.strerror or err}; a mount point or a "
            "folder that may not be moved): give a folder inside it, e.g. --out "
            f"{shown_path(os.path.join(str(given), 'results'))}"
        ) from None
    try:
        os.rename(fresh, target)
    except BaseException:
        os.rename(aside, target)
        raise
    _remove(Path(aside))


def _remove(folder: Path) -> None:
    """Remove a hidden folder of groundres's (it holds files only) whatever its permissions: an
    old output folder made read-only after the check, a fresh one made under a umask that
    takes the owner's write permission."""
    with contextlib.suppress(OSError):
        os.chmod(folder, stat.S_IRWXU)
    shutil.rmtree(folder, ignore_errors=True)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _remove_stale(parent: Path) -> None:
    """Remove the hidden folders of runs into ``parent`` whose process is gone (where it can be
    listed: a parent one may write in but not read keeps them)."""
    try:
        entries = list(os.scandir(parent))
    except OSError:
        return
    for entry in entries:
        match = _STAGING.fullmatch(entry.name)
        if match and entry.is_dir(follow_symlinks=False) and not _alive(int(match[2])):
            _remove(Path(entry.path))


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
