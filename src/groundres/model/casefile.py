"""Reading a case: a file name or a shipped case's name to its text, and the text to TOML data.

Everything a case file can be before it is a case is checked here, with a
message naming the file: missing, a folder or another file that is no
regular file (a FIFO, a device), a loop of symbolic links, unreadable, too
large, not UTF-8, keys of too many dotted parts for the TOML reader, invalid
TOML, a number too long to read. What the data may hold is
:mod:`groundres.model.schema`'s concern. :func:`read_file` reads any small
file a command takes (a study's case.toml, its provenance) the same way:
never blocking, never past its limit.
"""

from __future__ import annotations

import difflib
import errno
import os
import re
import stat
import sys
import tomllib
from importlib import resources
from pathlib import Path

from ..errors import CaseError, shown, shown_path

#: Largest case file read [bytes]; a case is a few kB of text.
MAX_CASE_BYTES = 1_000_000
#: Largest number a number key may hold: the float range.
LARGEST_NUMBER = sys.float_info.max
#: LARGEST_NUMBER as messages write it (rounded down: 1.798e308 is no float).
LARGEST_NUMBER_TEXT = "1.797e308"


def shipped_cases() -> dict[str, str]:
    """Names of the shipped cases and their TOML text."""
    root = resources.files("groundres") / "cases"
    return {
        p.name.removesuffix(".toml"): p.read_text(encoding="utf-8")
        for p in sorted(root.iterdir(), key=lambda p: p.name)
        if p.name.endswith(".toml")
    }


def source_name(path) -> str:
    """A file's name as text every output can hold: bytes that are no UTF-8 (a name the file
    system gave as such) written as their escapes (``\\xff``), since NetCDF attributes, JSON
    and TOML take only valid Unicode."""
    return os.fsencode(path).decode("utf-8", "backslashreplace")


def case_text(path_or_name: str | Path) -> tuple[str, str]:
    """(text, source) of a case file, or of a shipped case by name; CaseError where there is none.

    A path that names a regular file is read; any other path (missing, a folder, a FIFO) may
    still be a shipped case's name, and is otherwise refused with what it is.
    """
    given = os.fspath(path_or_name)
    try:
        mode = os.stat(given).st_mode
    except (OSError, ValueError) as err:
        mode, problem = None, err
    if mode is not None and stat.S_ISREG(mode):
        return _read_text(Path(given)), source_name(given)
    shipped = shipped_cases()
    name = given.removesuffix(".toml")
    if name in shipped:
        return shipped[name], name
    if mode is not None:
        what = "a folder, not a case file" if stat.S_ISDIR(mode) else not_regular(mode)
    elif isinstance(problem, OSError) and problem.errno == errno.ENOENT and not os.path.lexists(given):
        what = "no such file or shipped case"
    else:
        what = path_problem(given, problem)
    near = difflib.get_close_matches(name, shipped, n=1, cutoff=0.5)
    missing = mode is None and what == "no such file or shipped case"
    hint = (
        f"; did you mean the shipped case '{near[0]}'?"
        if near
        else "; see `groundres cases`"
        if missing or (mode is not None and stat.S_ISDIR(mode))
        else ""
    )
    raise CaseError(f"case {shown(given)}: {what}{hint}")


#: What a path is, by its type.
_FILE_TYPES = {
    stat.S_IFREG: "a regular file",
    stat.S_IFDIR: "a folder",
    stat.S_IFIFO: "a FIFO",
    stat.S_IFCHR: "a character device",
    stat.S_IFBLK: "a block device",
    stat.S_IFSOCK: "a socket",
}


def file_type(mode: int) -> str:
    """What a file of ``mode`` (an ``st_mode``) is, in words: "a FIFO", "a folder"."""
    return _FILE_TYPES.get(stat.S_IFMT(mode), "a file of an unknown type")


def not_regular(mode: int) -> str:
    """The words for a file of ``mode`` (an ``st_mode``) that is no regular file."""
    return f"not a regular file ({file_type(mode)})"


def path_problem(path, err: OSError | ValueError) -> str:
    """What ``err``, raised by ``os.stat`` or ``os.open`` on ``path``, says about it, in words."""
    if not isinstance(err, OSError):
        return "not a usable file name (it holds a NUL character)"
    if err.errno == errno.ENOENT and os.path.lexists(path):
        try:
            return f"a symbolic link to {shown_path(os.readlink(path))}, which does not exist"
        except (OSError, ValueError):
            pass
    return {
        errno.ENOENT: "no such file",
        errno.ELOOP: "a loop of symbolic links (or too many in a row)",
        errno.ENOTDIR: "a part of it is not a folder",
        errno.ENAMETOOLONG: "not a usable file name (File name too long)",
        errno.EACCES: "cannot be read (permission denied)",
        errno.EPERM: "cannot be read (operation not permitted)",
    }.get(err.errno, f"cannot be read ({err.strerror or err})")


def read_file(path: str | Path, label: str, limit: int) -> bytes:
    """The bytes of the regular file ``path``, up to ``limit`` and one more (a caller sees it is
    larger); CaseError, its message starting with ``label``, where there is none to read.

    The file's type is checked before it is opened, and it is opened without blocking: a
    FIFO or a device is refused, never waited on (nor one put in its place meanwhile).
    """
    flags = os.O_RDONLY
    for flag in ("O_NONBLOCK", "O_NOCTTY", "O_CLOEXEC", "O_BINARY"):
        flags |= getattr(os, flag, 0)
    try:
        mode = os.stat(path).st_mode
        fd = os.open(path, flags) if stat.S_ISREG(mode) else None
    except (OSError, ValueError) as err:
        raise CaseError(f"{label}: {path_problem(path, err)}") from None
    if fd is None:
        raise CaseError(f"{label}: {not_regular(mode)}")
    with open(fd, "rb") as f:
        try:
            mode = os.fstat(fd).st_mode
            if not stat.S_ISREG(mode):  # (swapped since the check)
                raise CaseError(f"{label}: {not_regular(mode)}")
            return f.read(limit + 1)
        except OSError as err:
            raise CaseError(f"{label}: cannot be read ({err.strerror or err})") from None


def toml_data(text: str, source: str) -> dict:
    """The TOML data of a case's text; CaseError naming ``source`` where it cannot be read."""
    long_key = _long_key(text)
    if long_key:  # (the TOML reader takes a time quadratic in the parts of a key)
        key, line, parts = long_key
        raise CaseError(
            f"{source}: the key {shown(key)} on line {line} has over {MAX_KEY_PARTS} dotted parts ({parts})"
        )
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise CaseError(f"{source}: not valid TOML: {err}") from None
    except RecursionError:
        raise CaseError(f"{source}: arrays or tables nested too deeply to read") from None
    except ValueError:  # a whole number too long to convert (over 4300 digits)
        raise CaseError(f"{source}: {_too_long_number(text)}") from None


#: Most dotted parts of a key or table name (the format needs two: rotor.blade).
MAX_KEY_PARTS = 32
#: A part of a key: bare, or a basic or literal string on one line.
_KEY_PART = r"""(?:[A-Za-z0-9_-]+|"(?:[^"\\\n]|\\[^\n])*"|'[^'\n]*')"""
#: The TOML text as tokens, each matched in one pass and none ever failing: strings (whose
#: content is skipped), dotted runs of key parts (every key, wherever it stands: at the start
#: of a line, in a table header, in an inline table; a value is one or two parts), comments
#: and anything else. Each alternative matches in linear time.
_TOKENS = re.compile(
    r"""(?P<skip>"{3}(?:[^\\"]|\\(?s:.)?|"(?!""))*(?:"{3}"{0,2}|\Z)"""
    r"""|'{3}(?:[^']|'(?!''))*(?:'{3}'{0,2}|\Z)"""
    r"|#[^\n]*)"
    rf"|(?P<run>{_KEY_PART}(?:[ \t]*\.[ \t]*{_KEY_PART})*)"
    r"""|"(?:[^"\\\n]|\\[^\n])*|'[^'\n]*|[^A-Za-z0-9_"'#-]+"""
)


def _long_key(text: str):
    """(key, line, parts) of the first key of over MAX_KEY_PARTS dotted parts, or None.

    Linear in the text: strings and comments are skipped whole (a description may hold
    "a.b.c..."), every other run of parts joined by dots is counted.
    """
    for match in _TOKENS.finditer(text):
        run = match["run"]
        if run is None or run.count(".") < MAX_KEY_PARTS:
            continue
        parts = run.count(".") + 1 if "'" not in run and '"' not in run else len(re.findall(_KEY_PART, run))
        if parts > MAX_KEY_PARTS:
            return run, text.count("\n", 0, match.start()) + 1, parts
    return None


_UNICODE_MARKS = {
    b"\xff\xfe\x00\x00": "UTF-32",
    b"\x00\x00\xfe\xff": "UTF-32",
    b"\xff\xfe": "UTF-16",
    b"\xfe\xff": "UTF-16",
}


def _read_text(path: Path) -> str:
    """The text of a case file: UTF-8 (a leading byte-order mark is dropped), at most MAX_CASE_BYTES."""
    raw = read_file(path, str(path), MAX_CASE_BYTES)
    if len(raw) > MAX_CASE_BYTES:
        raise CaseError(f"{path}: larger than {MAX_CASE_BYTES} bytes, which no case file needs")
    not_text = f"{path}: not a UTF-8 TOML text file"
    for mark, name in _UNICODE_MARKS.items():
        if raw.startswith(mark):
            raise CaseError(f"{not_text} (it is {name}; save it as UTF-8)")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as err:
        line = raw[: err.start].count(b"\n") + 1
        raise CaseError(f"{not_text} (byte 0x{raw[err.start]:02x} on line {line} is not UTF-8)") from None
    if "\x00" in text:
        raise CaseError(f"{not_text} (it holds NUL bytes: a binary file?)")
    return text


def _too_long_number(text: str) -> str:
    """The message for a whole number too long for Python to read, naming its key if it can."""
    found = re.search(r"^\s*([\w.\"'-]+)\s*=\s*[+-]?\d[\d_]{4000,}", text, re.MULTILINE)
    where = f"{found.group(1)} = " if found else "a value "
    return (
        f"{where}<a whole number of over 4000 digits>: must be a finite number, "
        f"|value| <= {LARGEST_NUMBER_TEXT}"
    )


#: A table header line of a case file (``[sweep]``, ``[[rotor.blade]]``).
_TABLE_HEADER = re.compile(r"^\s*\[")


def table_lines(lines: list[str], table: str) -> tuple[int, int] | None:
    """(first, end) of the lines of ``[table]`` in a case file's ``lines`` (its header line and
    the lines up to the next header), or None where it is not written under its own header."""
    start = next((i for i, line in enumerate(lines) if line.strip() == f"[{table}]"), None)
    if start is None:
        return None
    end = next((i for i in range(start + 1, len(lines)) if _TABLE_HEADER.match(lines[i])), len(lines))
    return start, end


def without_table(text: str, table: str, why: str) -> str:
    """A case file's ``text`` with its ``[table]`` commented out line by line, under a comment
    saying ``why`` (the text as it is, with that comment on top, where the table is not
    written under its own header)."""
    lines = text.splitlines()
    span = table_lines(lines, table)
    if span is None:
        return f"# {why}\n{text}"
    start, end = span
    lines[start:end] = [f"# {why}"] + [f"# {line}" if line else "#" for line in lines[start:end]]
    return "\n".join(lines) + "\n"
