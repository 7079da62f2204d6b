"""The lock runs share beside their output folders: swaps of folders in one parent one at a time.

A lock file (:data:`LOCK`) in the parent, locked with ``flock`` while a run swaps its
folder into place and removed after; :func:`check` finds, before any work, a lock
that cannot serve (a folder, a file that cannot be written).
"""

from __future__ import annotations

import contextlib
import os
import stat
from pathlib import Path

from ..errors import OutputFolderError, shown_path

#: The lock file's name, in the parent of the folders it serialises.
LOCK = ".groundres.lock"


def _problem(lock: Path, err: OSError) -> str:
    return (
        f"the lock file {shown_path(lock)} that runs writing beside each other share cannot be opened "
        f"({err.strerror or err}); remove it or choose another --out"
    )


def check(parent: Path) -> None:
    """OutputFolderError where the lock file in ``parent`` exists but cannot serve (a folder, a
    file that cannot be written), found before any work."""
    lock = parent / LOCK
    if not os.path.lexists(lock):
        return
    try:
        status = os.stat(lock)
    except OSError as err:
        raise OutputFolderError(_problem(lock, err)) from None
    if not stat.S_ISREG(status.st_mode):
        raise OutputFolderError(_problem(lock, IsADirectoryError(0, "not a regular file")))
    if not os.access(lock, os.W_OK):
        raise OutputFolderError(_problem(lock, PermissionError(0, "not writable")))


@contextlib.contextmanager
def locked(parent: Path):
    """An exclusive lock for swapping folders in ``parent`` (a lock file, removed after)."""
    try:
        import fcntl
    except ImportError:  # no flock (Windows): swaps are not serialised
        yield
        return
    lock = parent / LOCK
    while True:
        try:
            fd = os.open(lock, os.O_RDWR | os.O_CREAT | os.O_NONBLOCK, 0o666)
        except OSError as err:  # (a folder, a file made immutable, another's file there)
            raise OutputFolderError(_problem(lock, err)) from None
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
