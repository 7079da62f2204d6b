"""Read a case file (TOML) into a :class:`~groundres.params.Case`.

The format is documented in ``docs/case-files.md``. Every mistake raises
:class:`CaseError` with one readable line naming the key, the value and what
is allowed; unknown keys get the nearest valid key suggested.
"""

from __future__ import annotations

import difflib
import tomllib
from importlib import resources
from pathlib import Path

from .params import (
    BLADE_KEYS,
    BODY_DOFS,
    SPEED_UNITS,
    Blade,
    Body,
    Case,
    ParameterError,
    Rotor,
    Sweep,
)


class CaseError(ValueError):
    """A case file that cannot be used, with a message fit for the user."""


_NUMBER, _INT, _BOOL, _STR, _STRLIST, _TABLE, _TABLES = (
    "a number",
    "a whole number",
    "true or false",
    "a string",
    "a list of strings",
    "a table",
    "an array of tables",
)

SCHEMA = {
    "": {
        "title": _STR,
        "description": _STR,
        "rotor": _TABLE,
        "body": _TABLE,
        "sweep": _TABLE,
    },
    "rotor": {
        "blades": _INT,
        "hinge_offset": _NUMBER,
        "blade_mass": _NUMBER,
        "blade_static_moment": _NUMBER,
        "blade_inertia": _NUMBER,
        "lag_stiffness": _NUMBER,
        "lag_damping": _NUMBER,
        "flap": _BOOL,
        "flap_stiffness": _NUMBER,
        "flap_damping": _NUMBER,
        "blade": _TABLES,
    },
    "rotor.blade": {"index": _INT, **{k: _NUMBER for k in BLADE_KEYS}},
    "body": {
        "dofs": _STRLIST,
        "hub_height": _NUMBER,
        **{
            f"{kind}_{d}": _NUMBER
            for d in BODY_DOFS
            for kind in (("mass" if d in ("x", "y") else "inertia"), "stiffness", "damping")
        },
    },
    "sweep": {
        "start": _NUMBER,
        "stop": _NUMBER,
        "points": _INT,
        "unit": _STR,
        "reference": _NUMBER,
        "frame": _STR,
        "method": _STR,
    },
}
REQUIRED = {
    "": ("rotor", "body", "sweep"),
    "rotor": ("blades", "hinge_offset", "blade_mass", "blade_static_moment", "blade_inertia"),
    "rotor.blade": ("index",),
    "sweep": ("start", "stop"),
}
_DEFAULT_DOFS = ["x", "y"]


def _where(table: str, key: str) -> str:
    return f"[{table}] {key}" if table else key


def _check_type(table: str, key: str, value, kind: str) -> None:
    ok = {
        _NUMBER: isinstance(value, (int, float)) and not isinstance(value, bool),
        _INT: isinstance(value, int) and not isinstance(value, bool),
        _BOOL: isinstance(value, bool),
        _STR: isinstance(value, str),
        _STRLIST: isinstance(value, list) and all(isinstance(v, str) for v in value),
        _TABLE: isinstance(value, dict),
        _TABLES: isinstance(value, list) and all(isinstance(v, dict) for v in value),
    }[kind]
    if not ok:
        shown = value if not isinstance(value, (dict, list)) or len(str(value)) < 60 else type(value).__name__
        raise CaseError(f"{_where(table, key)} = {shown!r}: must be {kind}")


def _check_table(table: str, data: dict) -> None:
    schema = SCHEMA[table]
    for key, value in data.items():
        if key not in schema:
            near = difflib.get_close_matches(key, schema, n=1, cutoff=0.5)
            hint = f"; did you mean '{near[0]}'?" if near else f"; allowed keys: {', '.join(schema)}"
            raise CaseError(
                f"unknown key '{key}' in {('[' + table + ']') if table else 'the case file'}{hint}"
            )
        _check_type(table, key, value, schema[key])
    for key in REQUIRED.get(table, ()):
        if key not in data:
            raise CaseError(f"missing key {_where(table, key)}: it is required")


def _build(prefix: str, factory, **kwargs):
    try:
        return factory(**kwargs)
    except ParameterError as err:
        raise CaseError(f"{prefix}{err.key} = {err.value!r}: {err.allowed}") from None


def _rotor(data: dict) -> Rotor:
    _check_table("rotor", data)
    blade_data = {k: float(data[k]) for k in BLADE_KEYS if k in data}
    blade = _build("[rotor] ", Blade, **blade_data)
    flap = data.get("flap", False)
    rotor = _build("[rotor] ", Rotor.uniform, n_blades=data["blades"], blade=blade, flap=flap)
    seen = set()
    for entry in data.get("blade", []):
        _check_table("rotor.blade", entry)
        index = entry["index"]
        if not 1 <= index <= rotor.n_blades:
            raise CaseError(f"[[rotor.blade]] index = {index!r}: must be from 1 to blades ({rotor.n_blades})")
        if index in seen:
            raise CaseError(f"[[rotor.blade]] index = {index!r}: each blade may be overridden once")
        seen.add(index)
        changes = {k: float(v) for k, v in entry.items() if k != "index"}
        merged = {**blade_data, **changes}
        _build(f"[[rotor.blade]] index = {index}: ", Blade, **merged)
        rotor = rotor.with_blade(index, **changes)
    return rotor


def _body(data: dict) -> Body:
    _check_table("body", data)
    dofs = data.get("dofs", _DEFAULT_DOFS)
    for d in dofs:
        if d not in BODY_DOFS:
            near = difflib.get_close_matches(d, BODY_DOFS, n=1, cutoff=0.5)
            hint = f" (did you mean '{near[0]}'?)" if near else ""
            raise CaseError(f"[body] dofs = {dofs!r}: '{d}' is not one of {list(BODY_DOFS)}{hint}")
    for d in dofs:
        for key in (Body.inertia_key(d), f"stiffness_{d}"):
            if key not in data:
                raise CaseError(f"missing key [body] {key}: required because dofs includes '{d}'")
    if {"pitch", "roll"} & set(dofs) and "hub_height" not in data:
        raise CaseError("missing key [body] hub_height: required with pitch or roll in dofs")
    values = {k: float(v) for k, v in data.items() if k != "dofs"}
    return _build("[body] ", Body, dofs=tuple(dofs), **values)


def _sweep(data: dict) -> Sweep:
    _check_table("sweep", data)
    unit = data.get("unit", "rad/s")
    if unit not in SPEED_UNITS:
        raise CaseError(f"[sweep] unit = {unit!r}: must be one of {list(SPEED_UNITS)}")
    factor = SPEED_UNITS[unit]
    kwargs = {k: data[k] for k in ("points", "frame", "method") if k in data}
    for key in ("start", "stop", "reference"):
        if key in data:
            kwargs[key] = float(data[key]) * factor
    try:
        return Sweep(unit=unit, **kwargs)
    except ParameterError as err:
        value = err.value / factor if err.key in ("start", "stop", "reference") else err.value
        allowed = err.allowed
        if err.key == "start" and "below stop" in allowed:
            allowed = f"must be below stop ({data['stop']!r})"
        raise CaseError(f"[sweep] {err.key} = {value!r}: {allowed}") from None


def parse_case(data: dict, source: str = "", text: str = "") -> Case:
    """Build a Case from the parsed TOML tables (``text``: the file they came from).

    Raises
    ------
    CaseError
        With a one-line message naming the key, the value and what is allowed.
    """
    _check_table("", data)
    return Case(
        rotor=_rotor(data["rotor"]),
        body=_body(data["body"]),
        sweep=_sweep(data["sweep"]),
        title=data.get("title", Path(source).stem if source else "groundres case"),
        description=data.get("description", ""),
        source=source,
        text=text,
    )


def shipped_cases() -> dict[str, str]:
    """Names of the shipped cases and their TOML text."""
    root = resources.files("groundres") / "cases"
    return {
        p.name.removesuffix(".toml"): p.read_text(encoding="utf-8")
        for p in sorted(root.iterdir(), key=lambda p: p.name)
        if p.name.endswith(".toml")
    }


def load_case(path_or_name: str | Path) -> Case:
    """Read a case file, or a shipped case by name (see ``groundres cases``).

    Raises
    ------
    CaseError
        If the file is missing, is not valid TOML, or breaks the format.
    """
    path = Path(path_or_name)
    if path.is_file():
        # bytes decoded as they are (no newline translation): outputs keep the exact text
        text, source = path.read_bytes().decode("utf-8"), str(path)
    else:
        shipped = shipped_cases()
        name = str(path_or_name).removesuffix(".toml")
        if name not in shipped:
            near = difflib.get_close_matches(name, shipped, n=1, cutoff=0.5)
            hint = f"; did you mean the shipped case '{near[0]}'?" if near else "; see `groundres cases`"
            raise CaseError(f"case {str(path_or_name)!r}: no such file or shipped case{hint}")
        text, source = shipped[name], name
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise CaseError(f"{source}: not valid TOML: {err}") from None
    return parse_case(data, source, text)
