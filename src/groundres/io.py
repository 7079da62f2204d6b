"""Result files and output folders.

Each file is written atomically (a temporary file renamed into place); each
command's output folder is put in place whole (:func:`output_folder`) and
holds its provenance (:func:`write_provenance`). The result files:

* ``summary.json``: see docs/case-files.md; strict JSON (no NaN or Infinity
  tokens: a number that is not finite is written as null, with a
  ``<name>_reason`` beside it);
* ``modes.csv``: one row per (speed, mode), the unit in each header:
  ``speed [rad/s]``, ``mode``, ``frequency [rad/s]`` (in the result's frame),
  ``real_part [1/s]``, ``damping_ratio [-]``;
* ``modes.nc``: the same as a NetCDF-4 data set (CF conventions) with dims
  ``speed``, ``mode`` (see :mod:`groundres.dataset`).
"""

from __future__ import annotations

import contextlib
import csv
import io as _io
import json
import os
import re
import shutil
import signal
import tempfile
import threading
from pathlib import Path

import numpy as np


def _file_mode() -> int:
    """Permissions of a newly created file under the current umask."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


@contextlib.contextmanager
def atomic_path(path: str | Path):
    """Yield a temporary path beside ``path``; rename it into place on success."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".part" + path.suffix)
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, _file_mode())
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def write_text(path: str | Path, text: str) -> None:
    """Write text atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")


def strict(obj):
    """``obj`` with every NaN or infinity replaced by None.

    In a dict, a replaced value gets a ``<key>_reason`` beside it (unless one
    is there already) saying which value it was.
    """
    if isinstance(obj, dict):
        out = {}
        for key, value in obj.items():
            clean = strict(value)
            out[key] = clean
            if clean is None and _not_finite(value) and f"{key}_reason" not in obj:
                out[f"{key}_reason"] = f"not a finite number ({float(value)!r})"
        return out
    if isinstance(obj, (list, tuple)):
        return [strict(v) for v in obj]
    if _not_finite(obj):
        return None
    if isinstance(obj, np.generic):
        return obj.item()
    return obj


def _not_finite(value) -> bool:
    return isinstance(value, (float, np.floating)) and not np.isfinite(value)


def json_text(obj) -> str:
    """Strict JSON (RFC 8259: no NaN or Infinity tokens), indented, see :func:`strict`."""
    return json.dumps(strict(obj), indent=2, allow_nan=False) + "\n"


def write_json(path: str | Path, obj) -> None:
    """Write ``obj`` as strict JSON atomically."""
    write_text(path, json_text(obj))


def write_summary(result, path: str | Path) -> None:
    write_json(path, result.summary())


def csv_text(header, rows) -> str:
    """CSV text; floats with ten significant digits (-0 written as 0)."""
    buf = _io.StringIO()
    out = csv.writer(buf, lineterminator="\n")
    out.writerow(header)
    for row in rows:
        out.writerow([f"{float(v) + 0.0:.10g}" if isinstance(v, (float, np.floating)) else v for v in row])
    return buf.getvalue()


def write_csv(path: str | Path, header, rows) -> None:
    """Write rows as CSV atomically."""
    write_text(path, csv_text(header, rows))


#: modes.csv columns, each numeric one with its unit.
MODES_CSV_HEADER = ["speed [rad/s]", "mode", "frequency [rad/s]", "real_part [1/s]", "damping_ratio [-]"]


def write_modes_csv(result, path: str | Path) -> None:
    """modes.csv: one row per (speed, mode)."""
    freq, real, ratio = result.frequency, result.real_part, result.damping_ratio
    rows = (
        [w, label, freq[i, j], real[i, j], ratio[i, j]]
        for i, w in enumerate(result.rotor_speed)
        for j, label in enumerate(result.labels)
    )
    write_csv(path, MODES_CSV_HEADER, rows)


def write_modes_netcdf(result, path: str | Path) -> None:
    """Write ``result.dataset()`` as NetCDF-4 (readable by xarray.open_dataset).

    netCDF4 is used directly rather than through xarray: the file is the same
    and the command line starts half a second faster.
    """
    import netCDF4

    coords, variables, attrs = result.dataset()
    every = {**coords, **variables}
    sizes = {}
    for dims, values, _ in every.values():
        sizes.update(zip(dims, np.shape(values)))
    with atomic_path(path) as tmp:
        with netCDF4.Dataset(tmp, "w", format="NETCDF4") as nc:
            for name, size in sizes.items():
                nc.createDimension(name, size)  # size 0 (no unstable range): unlimited
            for name, (dims, values, var_attrs) in every.items():
                dtype = str if values.dtype == object else values.dtype
                var = nc.createVariable(name, dtype, dims)
                if dtype is str:
                    for i, v in enumerate(values):
                        var[i] = v
                else:
                    var[:] = values
                var.setncatts(var_attrs)
            nc.setncatts(attrs)


def write_figure(fig, path: str | Path, dpi: int = 130) -> None:
    """Save a matplotlib figure atomically (format from the file suffix)."""
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi, format=path.suffix.lstrip(".") or "png")


# -- Output folders: one unit, put in place whole ---------------------------------------------
#
# A command writes all its files into a fresh hidden folder beside the target
# and then, under a lock on the parent, moves the old folder aside, the new one
# into place and removes the old one: an interrupted run leaves the old folder
# or nothing, and two runs into one folder cannot mix (the later one wins).

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


class OutputFolderError(ValueError):
    """An output folder groundres will not replace: it holds files groundres did not write."""


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
        return
    foreign = foreign_entries(path)
    if foreign:
        shown = ", ".join(foreign[:5]) + (f" and {len(foreign) - 5} more" if len(foreign) > 5 else "")
        raise OutputFolderError(
            f"output folder {given}: not a groundres output folder (it holds {shown}, which groundres "
            "did not write), so it is not replaced; choose a new or empty folder with --out"
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
    target.parent.mkdir(parents=True, exist_ok=True)
    fresh = None
    try:
        with _signals_deferred():  # an interrupt now still finds the name to remove
            fresh = Path(
                tempfile.mkdtemp(
                    dir=target.parent, prefix=f"{_HIDDEN}new-{os.getpid()}-", suffix=f"-{target.name}"
                )
            )
        yield fresh
        os.chmod(fresh, 0o777 & ~_umask())
        with _signals_deferred(), _locked(target.parent):
            _remove_stale(target.parent)
            _swap(fresh, target, path)
    finally:
        if fresh is not None and fresh.exists():
            with _signals_deferred():
                shutil.rmtree(fresh, ignore_errors=True)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


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
    os.rename(target, aside)  # (onto the empty folder just made: a unique name)
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

    from ._version import __version__

    folder = Path(folder)
    data = case.text.encode("utf-8")
    if case.text:
        with atomic_path(folder / CASE_COPY) as tmp:
            tmp.write_bytes(data)

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
    record = _strict_json(record)
    write_text(folder / PROVENANCE, json.dumps(record, indent=2, allow_nan=False) + "\n")
    return record


def _strict_json(value):
    """The value with NumPy scalars as Python numbers and NaN or infinity as None."""
    if isinstance(value, dict):
        return {str(k): _strict_json(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_strict_json(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not np.isfinite(value):
        return None
    return value
