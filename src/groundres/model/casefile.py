"""Reading a case: a file name or a shipped case's name to its text, and the text to TOML data.

Everything a case file can be before it is a case is checked here, with a
message naming the file: missing, a folder, too large, not UTF-8, keys
nested too deep for the TOML reader, invalid TOML, a number too long to
read. What the data may hold is :mod:`groundres.model.schema`'s concern.
"""

from __future__ import annotations

import difflib
import re
import sys
import tomllib
from importlib import resources
from pathlib import Path

from ..errors import CaseError, shown

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


def case_text(path_or_name: str | Path) -> tuple[str, str]:
    """(text, source) of a case file, or of a shipped case by name; CaseError where there is none."""
    path = Path(path_or_name)
    try:
        is_file = path.is_file()
    except (OSError, ValueError) as err:  # a name too long, a NUL byte
        reason = getattr(err, "strerror", None) or err
        raise CaseError(f"case {shown(str(path_or_name))}: not a usable file name ({reason})") from None
    if is_file:
        return _read_text(path), str(path)
    shipped = shipped_cases()
    name = str(path_or_name).removesuffix(".toml")
    if name not in shipped:
        near = difflib.get_close_matches(name, shipped, n=1, cutoff=0.5)
        hint = f"; did you mean the shipped case '{near[0]}'?" if near else "; see `groundres cases`"
        what = "a folder, not a case file" if path.is_dir() else "no such file or shipped case"
        raise CaseError(f"case {shown(str(path_or_name))}: {what}{hint}")
    return shipped[name], name


def toml_data(text: str, source: str) -> dict:
    """The TOML data of a case's text; CaseError naming ``source`` where it cannot be read."""
    long_key = _LONG_KEY.search(text)
    if long_key:  # (the TOML reader takes a time quadratic in the parts of a key)
        line = text.count("\n", 0, long_key.start()) + 1
        raise CaseError(f"{source}: the key on line {line} has over {MAX_KEY_PARTS} dotted parts")
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
_KEY_PART = r"""(?:[A-Za-z0-9_-]+|"(?:[^"\\\n]|\\.)*"|'[^'\n]*')"""
_LONG_KEY = re.compile(
    rf"^[ \t]*\[{{0,2}}[ \t]*(?:{_KEY_PART}[ \t]*\.[ \t]*){{{MAX_KEY_PARTS},}}", re.MULTILINE
)

_UNICODE_MARKS = {
    b"\xff\xfe\x00\x00": "UTF-32",
    b"\x00\x00\xfe\xff": "UTF-32",
    b"\xff\xfe": "UTF-16",
    b"\xfe\xff": "UTF-16",
}


def _read_text(path: Path) -> str:
    """The text of a case file: UTF-8 (a leading byte-order mark is dropped), at most MAX_CASE_BYTES."""
    try:
        with path.open("rb") as f:
            raw = f.read(MAX_CASE_BYTES + 1)
    except OSError as err:
        raise CaseError(f"{path}: cannot be read ({err.strerror or err})") from None
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
