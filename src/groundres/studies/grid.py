"""The grid of a design study: which case keys vary, over which values, and the failures.

A varied key is any number key of the case file in dotted form, as the case
file nests it: ``rotor.lag_damping``, ``body.damping_x``, ``sweep.stop``; in a
repeated table, ``rotor.blade[k].<key>`` for blade k (1-based, the ``index``
of a ``[[rotor.blade]]`` table, which is added where the case has none), and
``rotor.damper[k].<key>``, ``body.gear[k].<key>`` for the k-th such table of
the case file (1-based, in the file's order). The keys
and their types come from the case-file schema (:data:`groundres.model.keys.SCHEMA`),
so a key added to the format later is variable without code here. Values are
in the case's own units (``sweep.stop`` in the sweep's unit).

A failure is a single lag damper out of action: blade k's ``lag_damping`` set
to 0. ``failures="single"`` adds one entry per blade with a working damper,
besides "none".
"""

from __future__ import annotations

import copy
import difflib
import hashlib
import json
import math
import re
import tomllib
from dataclasses import dataclass

import numpy as np

from .._version import __version__
from ..errors import InputError, StudyError, shown
from ..model.casefile import table_lines
from ..model.keys import SCHEMA
from ..model.params import Case
from ..model.schema import parse_case

#: Most grid points of one study (a study beyond it is refused before any work).
MAX_POINTS = 1_000_000
#: Name of the failure dimension and of its entry with every damper working.
FAILURE, NO_FAILURE = "failure", "none"

#: Repeated tables ([[...]]) of the format, found in its schema.
REPEATED = tuple(
    t
    for t in SCHEMA
    if "." in t and SCHEMA[t.rpartition(".")[0]].get(t.rpartition(".")[2]) == "an array of tables"
)
#: A key of one entry of a repeated table: (table, k, key).
_ENTRY = re.compile(rf"^({'|'.join(re.escape(t) for t in REPEATED)})\[([0-9]+)\]\.([a-z_]+)$", re.ASCII)
#: The key that names an entry of a repeated table (others are named by their place).
_NAMED_BY = {t: "index" for t in REPEATED if SCHEMA[t].get("index") == "a whole number"}
#: Keys of repeated tables that say which blade an entry belongs to: no design values.
_WHICH = {"index", "blade"}


def numeric_keys() -> list[str]:
    """Every varied key the case format has (a repeated table's shown with [k])."""
    out = []
    for table, keys in SCHEMA.items():
        for key, kind in keys.items():
            if kind not in ("a number", "a whole number") or (table in REPEATED and key in _WHICH):
                continue
            if table in REPEATED:
                out.append(f"{table}[k].{key}")
            else:
                out.append(f"{table}.{key}" if table else key)
    return out


def key_kind(key: str) -> str:
    """ "a number" or "a whole number" for a variable key; StudyError naming it otherwise."""
    entry = _ENTRY.match(key)
    if entry:
        table, name = entry[1], entry[3]
    else:
        table, _, name = key.rpartition(".")
    kind = SCHEMA.get(table, {}).get(name)
    if entry is None and table in REPEATED or (entry and name in _WHICH):
        kind = None  # (an entry's keys need its number; the number names it, it is no design value)
    if kind not in ("a number", "a whole number"):
        near = difflib.get_close_matches(key, numeric_keys(), n=1, cutoff=0.6)
        hint = f"; did you mean '{near[0]}'?" if near else "; see the case-file keys (docs/case-files.md)"
        what = (
            f"is {kind}, not a number" if kind and "number" not in kind else "is no number key of a case file"
        )
        raise StudyError(f"--vary {shown(key)}: {what}{hint}")
    return kind


def canonical(key: str) -> str:
    """A varied key as the study names it (``rotor.blade[02].x`` is ``rotor.blade[2].x``)."""
    key = key.strip()
    entry = _ENTRY.match(key)
    return f"{entry[1]}[{int(entry[2])}].{entry[3]}" if entry else key


def entry_of(key: str):
    """(table, k, name) of a key of one entry of a repeated table, or None."""
    entry = _ENTRY.match(key)
    return (entry[1], int(entry[2]), entry[3]) if entry else None


def parse_values(key: str, spec) -> np.ndarray:
    """The values of a varied key: ``"START:STOP:COUNT[:log]"`` or a sequence of numbers."""
    kind = key_kind(key)
    if isinstance(spec, str):
        parts = spec.split(":")
        if len(parts) not in (3, 4) or (len(parts) == 4 and parts[3] != "log"):
            raise StudyError(f"--vary {key}={shown(spec)}: must be START:STOP:COUNT or START:STOP:COUNT:log")
        try:
            start, stop = float(parts[0]), float(parts[1])
        except ValueError:
            raise StudyError(f"--vary {key}={shown(spec)}: START and STOP must be numbers") from None
        try:
            count = int(parts[2])
        except ValueError:
            raise StudyError(f"--vary {key}={shown(spec)}: COUNT must be a whole number") from None
        if not (math.isfinite(start) and math.isfinite(stop)):
            raise StudyError(f"--vary {key}={shown(spec)}: START and STOP must be finite")
        if not 1 <= count <= MAX_POINTS:
            raise StudyError(f"--vary {key}={shown(spec)}: COUNT = {count} must be from 1 to {MAX_POINTS}")
        if start == stop and count > 1:
            raise StudyError(f"--vary {key}={shown(spec)}: START equals STOP, so COUNT must be 1")
        if len(parts) == 4:
            if start <= 0 or stop <= 0:
                raise StudyError(f"--vary {key}={shown(spec)}: a log range needs START and STOP > 0")
            values = np.geomspace(start, stop, count)
        else:
            with np.errstate(over="ignore", invalid="ignore"):
                values = np.linspace(start, stop, count)
        if not np.isfinite(values).all():
            raise StudyError(f"--vary {key}={shown(spec)}: the range is too wide for a float")
    else:
        try:
            values = np.atleast_1d(np.asarray(spec, dtype=float))
        except (TypeError, ValueError):
            values = np.array([np.nan])
        if values.ndim != 1 or not len(values) or not np.isfinite(values).all():
            raise StudyError(f"vary {key} = {shown(spec)}: must be a non-empty list of finite numbers")
    if kind == "a whole number":
        if not np.all(values == np.round(values)):
            raise StudyError(
                f"--vary {key}: {key} is a whole number; the range gives {shown(values.tolist())}"
            )
        values = np.round(values)
    return values


@dataclass(frozen=True)
class Grid:
    """The points of a study: the product of the varied keys' values (and failures).

    Attributes
    ----------
    keys : tuple of str
        Varied keys, in order (the study's first dimensions).
    values : tuple of ndarray
        Their values, in the case's units.
    failures : tuple of str
        "none" and "blade k" entries (empty without a failure dimension).
    """

    keys: tuple
    values: tuple
    failures: tuple = ()

    @property
    def dims(self) -> tuple:
        return self.keys + ((FAILURE,) if self.failures else ())

    @property
    def shape(self) -> tuple:
        return tuple(len(v) for v in self.values) + ((len(self.failures),) if self.failures else ())

    @property
    def size(self) -> int:
        return int(np.prod(self.shape))

    def point(self, flat: int) -> tuple[dict, str]:
        """The values of each key and the failure at a flat (C-order) index."""
        where = np.unravel_index(flat, self.shape)
        values = {k: float(v[i]) for k, v, i in zip(self.keys, self.values, where)}
        return values, (self.failures[where[-1]] if self.failures else NO_FAILURE)

    def fingerprint(self, case_text: str) -> str:
        """A hash of the case text and the grid: a store made for another is refused."""
        grid = {
            "keys": list(self.keys),
            "values": [np.asarray(v).tolist() for v in self.values],
            "failures": list(self.failures),
        }
        # (and the version: a study resumed by another groundres would mix two versions' results)
        text = f"{case_text}\n{json.dumps(grid, sort_keys=True)}\n{__version__}"
        return hashlib.sha256(text.encode()).hexdigest()


def make_grid(case: Case, vary: dict, failures: str | None = None) -> Grid:
    """The grid of a study of ``case`` (``vary``: key -> spec, :func:`parse_values`)."""
    if not vary:
        raise StudyError("--vary: at least one key must vary (KEY=START:STOP:COUNT)")
    keys = tuple(canonical(k) for k in vary)
    for k, given in zip(keys, vary):
        if keys.count(k) > 1:
            raise StudyError(f"--vary {given.strip()}: given twice (as {k})")
    values = tuple(parse_values(k, vary[given]) for k, given in zip(keys, vary))
    data = raw(case)
    for key in keys:
        entry = entry_of(key)
        if entry and entry[0] in _NAMED_BY:
            if not 1 <= entry[1] <= data["rotor"]["blades"]:
                raise StudyError(
                    f"--vary {key}: blade {entry[1]} does not exist (blades = {data['rotor']['blades']})"
                )
        elif entry:
            count = len(table_of(data, entry[0]))
            if not 1 <= entry[1] <= count:
                raise StudyError(
                    f"--vary {key}: the case has {count} [[{entry[0]}]] table{'s' if count != 1 else ''}, "
                    f"so k is 1 to {count}"
                    if count
                    else f"--vary {key}: the case has no [[{entry[0]}]] table"
                )
    names = ()
    if failures is not None:
        if failures != "single":
            raise StudyError(f"--failures {shown(failures)}: must be 'single'")
        if "rotor.blades" in keys:
            raise StudyError(
                "--failures single: not with rotor.blades varied (which blade fails would change)"
            )
        overrides = {b["index"]: b for b in data["rotor"].get("blade", []) if "index" in b}
        working = [
            i + 1
            for i, b in enumerate(case.rotor.blades)
            # (working in the case, or given a damper by a varied key)
            if b.lag_damping > 0
            or f"rotor.blade[{i + 1}].lag_damping" in keys
            or ("rotor.lag_damping" in keys and "lag_damping" not in overrides.get(i + 1, {}))
        ]
        # (damper rods: each working one fails in turn, besides the blades' own dampers)
        rods = [f"{d.kind} rod {d.blade}" for d in case.rotor.dampers if d.damping > 0]
        if not working and not rods:
            raise StudyError(
                "--failures single: no blade of the study has a working lag damper to fail (nor a damper rod)"
            )
        names = (NO_FAILURE, *(f"blade {k}" for k in working), *rods)
    grid = Grid(keys, values, names)
    if grid.size > MAX_POINTS:
        raise StudyError(f"--vary: the grid has {grid.size} points, more than {MAX_POINTS}")
    return grid


def raw(case: Case) -> dict:
    """The case's TOML tables, to be varied."""
    return tomllib.loads(raw_text(case))


def varied_case(data: dict, values: dict, failure: str = NO_FAILURE, source: str = "") -> Case:
    """The case with each key set to its value and the failure applied (CaseError if invalid)."""
    data = copy.deepcopy(data)
    for key, value in values.items():
        kind = key_kind(key)
        number = int(round(value)) if kind == "a whole number" else float(value)
        entry = entry_of(key)
        if entry and entry[0] in _NAMED_BY:
            _blade_table(data, entry[1])[entry[2]] = number
        elif entry:
            table_of(data, entry[0])[entry[1] - 1][entry[2]] = number
        else:
            table, _, name = key.rpartition(".")
            inner = data
            for part in table.split(".") if table else ():  # (a table inside a table: rotor.lag_damper)
                inner = inner.setdefault(part, {})
            inner[name] = number
    if failure.startswith("blade "):
        blade = _blade_table(data, int(failure.split()[-1]))
        if "lag_damper" in data["rotor"] or "lag_damper" in blade:  # (a law: the damper fails whole)
            blade.pop("lag_damping", None)
            blade["lag_damper"] = "failed"
        else:
            blade["lag_damping"] = 0.0
    elif failure != NO_FAILURE:  # (a damper rod: "<kind> rod <k>", overridden with no damping)
        kind, _, blade = failure.rpartition(" rod ")
        tables = data["rotor"].setdefault("damper", [])
        entry = next((t for t in tables if t.get("kind") == kind and t.get("blade") == int(blade)), None)
        if entry is None:
            tables.append({"kind": kind, "blade": int(blade), "damping": 0.0})
        else:
            entry["damping"] = 0.0
    return parse_case(data, source)


def table_of(data: dict, table: str) -> list:
    """The case's entries of a repeated table (a list, empty where it has none)."""
    parent, _, name = table.rpartition(".")
    return data.get(parent, {}).get(name, [])


def _blade_table(data: dict, index: int) -> dict:
    """The ``[[rotor.blade]]`` table of blade ``index`` (added if the case has none)."""
    tables = data["rotor"].setdefault("blade", [])
    for entry in tables:
        if entry.get("index") == index:
            return entry
    entry = {"index": index}
    tables.append(entry)
    return entry


def with_points(case: Case, points: int | None) -> Case:
    """The case with ``points`` speeds in its sweep (its text edited, so that a study's store
    and folder record it), or the case itself where ``points`` is None.

    Raises
    ------
    StudyError
        A number of points the case format does not allow, or a case whose ``[sweep]``
        table is not written as one (an inline table).
    """
    if points is None:
        return case
    if isinstance(points, bool) or not isinstance(points, int):
        raise StudyError(f"--points {shown(points)}: must be a whole number")
    lines = raw_text(case).splitlines()
    span = table_lines(lines, "sweep")
    if span is None:
        raise StudyError("--points: the case has no [sweep] table to set it in; set points in the case file")
    start, end = span
    entry = f"points = {points}"
    at = next((i for i in range(start + 1, end) if re.match(r"\s*points\s*=", lines[i])), None)
    if at is None:
        lines.insert(start + 1, entry)
    else:
        lines[at] = entry
    text = "\n".join(lines) + "\n"
    try:
        return parse_case(tomllib.loads(text), case.source, text)
    except InputError as err:  # (the case format says what is allowed)
        raise StudyError(f"--points {points}: {err}") from None


def raw_text(case: Case) -> str:
    """The case's text (StudyError where it has none)."""
    if not case.text:
        raise StudyError("the case has no text to vary: give a case file or a shipped case")
    return case.text
