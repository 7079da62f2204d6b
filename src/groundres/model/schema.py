"""Read a case file (TOML) into a :class:`~groundres.model.params.Case`.

The format is documented in ``docs/case-files.md``. Every mistake raises
:class:`CaseError` with one readable line naming the key, the value and what
is allowed; unknown keys get the nearest valid key suggested.
"""

from __future__ import annotations

import difflib
import math
from pathlib import Path

from ..errors import CaseError, ParameterError, shown
from .aero import DEGREE_KEYS, INFLOWS, Aero
from .body import BODY_DOFS, MODAL_KEYS, RIGID_KEYS, Body, Leg
from .casefile import LARGEST_NUMBER_TEXT, case_text, toml_data
from .damper_laws import BladeDamper, DamperLaw
from .dampers import GEOMETRY, KINDS, Damper
from .keys import (
    BOOL,
    FAILED_OR_TABLE,
    INT,
    NUMBER,
    NUMLIST,
    REQUIRED,
    SCHEMA,
    STR,
    STRLIST,
    TABLE,
    TABLES,
    key_text,
)
from .params import BLADE_KEYS, Blade, Case, LimitCycleOptions, Rotor, SimulationOptions, Sweep
from .units import SPEED_UNITS
from .validate import finite

_DEFAULT_DOFS = ["x", "y"]


def _check_type(table: str, key: str, value, kind: str, where: str = "") -> None:
    """``value`` of ``key`` is of ``kind`` (CaseError naming it, as ``where`` + key if given)."""
    name = f"{where}{key}" if where else key_text(table, key)
    ok = {
        NUMBER: isinstance(value, (int, float)) and not isinstance(value, bool),
        INT: isinstance(value, int) and not isinstance(value, bool),
        BOOL: isinstance(value, bool),
        STR: isinstance(value, str),
        STRLIST: isinstance(value, list) and all(isinstance(v, str) for v in value),
        TABLE: isinstance(value, dict),
        TABLES: isinstance(value, list) and all(isinstance(v, dict) for v in value),
        NUMLIST: isinstance(value, list)
        and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value),
        FAILED_OR_TABLE: isinstance(value, dict) or value == "failed",
    }[kind]
    if not ok:
        text = type(value).__name__ if isinstance(value, (dict, list)) else shown(value)
        raise CaseError(f"{name} = {text}: must be {kind}")
    numbers = [value] if kind == NUMBER else value if kind == NUMLIST else []
    if not all(finite(v) for v in numbers):
        what = "finite numbers" if kind == NUMLIST else "a finite number"
        raise CaseError(f"{name} = {shown(value)}: must be {what}, |value| <= {LARGEST_NUMBER_TEXT}")


def _check_table(table: str, data: dict, where: str = "") -> None:
    """``data`` holds only ``table``'s keys, of their kinds, and its required ones; messages name
    the table as the file writes it, or as ``where`` (a table inside a repeated one)."""
    schema = SCHEMA[table]
    for key, value in data.items():
        if key not in schema:
            near = difflib.get_close_matches(key, schema, n=1, cutoff=0.5)
            hint = f"; did you mean '{near[0]}'?" if near else f"; allowed keys: {', '.join(schema)}"
            inside = where.rstrip(". ") or (("[" + table + "]") if table else "the case file")
            raise CaseError(f"unknown key {shown(key)} in {inside}{hint}")
        _check_type(table, key, value, schema[key], where)
    for key in REQUIRED.get(table, ()):
        if key not in data:
            raise CaseError(f"missing key {key_text(table, key)}: it is required")


def _build(prefix: str, factory, **kwargs):
    try:
        return factory(**kwargs)
    except ParameterError as err:
        key = err.key
        if "." in key and prefix.startswith("["):  # ("[simulation] initial.x" is "[simulation.initial] x")
            inner, _, key = key.partition(".")
            prefix = f"{prefix.rstrip()[:-1]}.{inner}] "
        raise CaseError(f"{prefix}{key} = {shown(err.value)}: {err.allowed}") from None


def _rotor(data: dict) -> Rotor:
    _check_table("rotor", data)
    blade_data = {k: float(data[k]) for k in BLADE_KEYS if k in data}
    blade = _build("[rotor] ", Blade, **blade_data)
    flap = data.get("flap", False)
    rotor = _build("[rotor] ", Rotor.uniform, n_blades=data["blades"], blade=blade, flap=flap)
    layout = data.get("lag_damper")
    if layout is not None:
        _check_table("rotor.lag_damper", layout)
        if "lag_damping" in data:
            raise CaseError(
                f"[rotor] lag_damping = {shown(data['lag_damping'])}: a [rotor.lag_damper] law replaces it; "
                "give one of the two"
            )
        _law("[rotor.lag_damper] ", layout)
    laws = [layout] * rotor.n_blades
    seen = set()
    for entry in data.get("blade", []):
        _check_table("rotor.blade", entry)
        index = entry["index"]
        if not 1 <= index <= rotor.n_blades:
            raise CaseError(
                f"[[rotor.blade]] index = {shown(index)}: must be from 1 to blades ({rotor.n_blades})"
            )
        if index in seen:
            raise CaseError(f"[[rotor.blade]] index = {index}: each blade may be overridden once")
        seen.add(index)
        own = entry.get("lag_damper")
        if own is not None or layout is not None:
            laws[index - 1] = _blade_law(index, own, layout, entry)
        changes = {k: float(v) for k, v in entry.items() if k not in ("index", "lag_damper")}
        merged = {**blade_data, **changes}
        _build(f"[[rotor.blade]] index = {index}: ", Blade, **merged)
        rotor = rotor.with_blade(index, **changes)
    rotor = _with_laws(rotor, laws)
    dampers = _dampers(data.get("damper", []), rotor.n_blades)
    return _build(
        "[[rotor.damper]] ",
        Rotor,
        blades=rotor.blades,
        flap=rotor.flap,
        dampers=dampers,
        lag_laws=rotor.lag_laws,
    )


def _law(prefix: str, keys: dict) -> DamperLaw:
    """The law of a lag damper table (CaseError naming the key)."""
    try:
        return DamperLaw.from_keys(keys)
    except ParameterError as err:
        shown_value = "(missing)" if err.value is None else shown(err.value)
        raise CaseError(f"{prefix}{err.key} = {shown_value}: {err.allowed}") from None


def _blade_law(index: int, own, layout, entry: dict):
    """Blade ``index``'s lag damper table ("failed": no damper), from its ``lag_damper``
    (``"failed"``, or a table: with ``law``, a law of its own; without, keys overriding the
    rotor's ``layout``)."""
    where = f"[[rotor.blade]] index = {index}:"
    if "lag_damping" in entry and (layout is not None or own is not None):
        raise CaseError(
            f"{where} lag_damping = {shown(entry['lag_damping'])}: the blades' dampers follow "
            '[rotor.lag_damper]; a failed one is lag_damper = "failed", another law a lag_damper table'
        )
    if own == "failed":
        return "failed"
    if own is None:
        return layout
    _check_table("rotor.lag_damper", own, f"{where} lag_damper.")
    if "law" not in own and layout is None:
        raise CaseError(f"{where} lag_damper has no law: name one (law = ...), or give [rotor.lag_damper]")
    keys = own if "law" in own else {**layout, **own}
    _law(f"{where} lag_damper.", keys)
    return keys


def _with_laws(rotor: Rotor, laws: list) -> Rotor:
    """The rotor whose blades carry their lag damper laws (``laws``: per blade a law's keys, None
    for the blade's own linear ``lag_damping``, or "failed": no damper at all)."""
    if all(keys is None for keys in laws):
        return rotor
    entries = []
    for index, keys in enumerate(laws, start=1):
        if keys == "failed":
            rotor = rotor.with_blade(index, lag_damping=0.0)
        root = rotor.blades[index - 1].lag_stiffness
        entries.append(None if keys in (None, "failed") else BladeDamper(DamperLaw.from_keys(keys), root))
    return rotor.with_lag_laws(tuple(entries)) if any(entries) else rotor


def _dampers(entries: list, n_blades: int) -> tuple:
    """The damper rods of ``[[rotor.damper]]`` tables: an entry without ``blade`` is a layout
    (one rod starting at every blade); an entry with ``blade = k`` overrides the keys it
    gives of the layout's rod of its kind starting at blade k (``damping = 0.0``: a failed
    damper), or is a rod of its own where its kind has no layout."""
    layouts, overrides = {}, {}
    for entry in entries:
        _check_table("rotor.damper", entry)
        kind = entry["kind"]
        if kind not in KINDS:
            near = difflib.get_close_matches(kind, KINDS, n=1, cutoff=0.5)
            hint = f" (did you mean '{near[0]}'?)" if near else ""
            raise CaseError(f"[[rotor.damper]] kind = {shown(kind)}: must be one of {list(KINDS)}{hint}")
        values = {k: float(v) for k, v in entry.items() if k not in ("kind", "blade")}
        if "blade" not in entry:
            if kind in layouts:
                raise CaseError(
                    f"[[rotor.damper]] kind = {shown(kind)}: a layout (an entry without blade) may be "
                    "given once "
                    "per kind; override single rods with blade = k"
                )
            layouts[kind] = values
            continue
        blade = entry["blade"]
        if not 1 <= blade <= n_blades:
            raise CaseError(
                f"[[rotor.damper]] blade = {shown(blade)}: must be a blade of the rotor, 1 to {n_blades}"
            )
        if (kind, blade) in overrides:
            raise CaseError(f"[[rotor.damper]] kind = {shown(kind)}, blade = {blade}: given twice")
        overrides[(kind, blade)] = values
    rods = []
    for kind, values in layouts.items():
        for blade in range(1, n_blades + 1):
            rods.append((kind, blade, {**values, **overrides.pop((kind, blade), {})}))
    rods += [(kind, blade, values) for (kind, blade), values in overrides.items()]
    out = []
    for kind, blade, values in rods:
        missing = [k for k in GEOMETRY[:2] + GEOMETRY[3:5] + ("damping",) if k not in values]
        if missing:
            raise CaseError(
                f"missing key [[rotor.damper]] {missing[0]} (kind = {shown(kind)}, blade = {blade}): "
                "a rod needs damping and both ends (start_x, start_y, end_x, end_y; z defaults to 0)"
            )
        out.append(
            _build(
                f"[[rotor.damper]] kind = {shown(kind)}, blade = {blade}: ",
                Damper,
                blade=blade,
                kind=kind,
                **values,
            )
        )
    return tuple(out)


def _body(data: dict) -> Body:
    _check_table("body", data)
    dofs = data.get("dofs", _DEFAULT_DOFS)
    for d in dofs:
        if d not in BODY_DOFS:
            near = difflib.get_close_matches(d, BODY_DOFS, n=1, cutoff=0.5)
            hint = f" (did you mean '{near[0]}'?)" if near else ""
            raise CaseError(f"[body] dofs = {shown(dofs)}: {shown(d)} is not one of {list(BODY_DOFS)}{hint}")
    modal = [k for k in MODAL_KEYS if k in data]
    rigid = [k for k in (*RIGID_KEYS, "gear") if k in data]
    if modal and rigid:
        raise CaseError(
            f"[body] {modal[0]} and {rigid[0]}: the modal form (mass_x, stiffness_x, ...) and the rigid "
            "form (mass, inertia_xx, ..., [[body.gear]]) are exclusive; give one"
        )
    if rigid:
        required = ["mass", "hub_height", "gear"]
        required += [f"inertia_{a}{a}" for d, a in (("roll", "x"), ("pitch", "y"), ("yaw", "z")) if d in dofs]
        for key in required:
            if key not in data:
                why = (
                    "a body on gear legs needs it"
                    if key != "gear"
                    else "a rigid body stands on [[body.gear]] legs"
                )
                raise CaseError(f"missing key [body] {key}: {why}")
    else:
        for d in dofs:
            for key in (Body.inertia_key(d), f"stiffness_{d}"):
                if key not in data:
                    raise CaseError(f"missing key [body] {key}: required because dofs includes '{d}'")
        if {"pitch", "roll"} & set(dofs) and "hub_height" not in data:
            raise CaseError("missing key [body] hub_height: required with pitch or roll in dofs")
    legs = []
    for i, entry in enumerate(data.get("gear", []), start=1):
        _check_table("body.gear", entry)
        legs.append(_build(f"[[body.gear]] {i}: ", Leg, **{k: float(v) for k, v in entry.items()}))
    values = {k: float(v) for k, v in data.items() if k not in ("dofs", "gear")}
    try:
        return Body(dofs=tuple(dofs), gear=tuple(legs), **values)
    except ParameterError as err:  # (a leg's key, "gear[2].stiffness_x", as the file writes it)
        leg, _, key = err.key.partition("].")
        where = f"[[body.gear]] {leg.removeprefix('gear[')}: {key}" if key else f"[body] {err.key}"
        raise CaseError(f"{where} = {shown(err.value)}: {err.allowed}") from None


#: The [sweep] keys that hold speeds (in the case's unit).
_SPEED_KEYS = ("start", "stop", "reference", "operating_start", "operating_stop")


def _sweep(data: dict) -> Sweep:
    _check_table("sweep", data)
    unit = data.get("unit", "rad/s")
    if unit not in SPEED_UNITS:
        raise CaseError(f"[sweep] unit = {shown(unit)}: must be one of {list(SPEED_UNITS)}")
    factor = SPEED_UNITS[unit]
    kwargs = {k: data[k] for k in ("points", "frame", "method") if k in data}
    if "required_damping_ratio" in data:
        kwargs["required_damping_ratio"] = float(data["required_damping_ratio"])
    for key in _SPEED_KEYS:
        if key in data:
            kwargs[key] = float(data[key]) * factor
    for key in _SPEED_KEYS:
        if key in kwargs and not finite(kwargs[key]):
            raise CaseError(
                f"[sweep] {key} = {shown(data[key])}: too large to hold in rad/s ({unit} x {factor:.6g})"
            )
    try:
        return Sweep(unit=unit, **kwargs)
    except ParameterError as err:
        value = data.get(err.key, err.value)  # as written, in the case's unit
        allowed = err.allowed
        if err.key == "start" and "below stop" in allowed:
            allowed = f"must be below stop ({shown(data['stop'])})"
        if "inside the sweep" in allowed:
            ends = f"from start ({shown(data['start'])}) to stop ({shown(data['stop'])}) {unit}"
            allowed = f"must be a speed inside the sweep, {ends}"
        raise CaseError(f"[sweep] {err.key} = {shown(value)}: {allowed}") from None


def _aero(data: dict, rotor: Rotor) -> Rotor:
    """``rotor`` in the air of the ``[aero]`` table (its Lock number, if given, turned into the
    air density with the inertia of the ``[rotor]`` blade)."""
    _check_table("aero", data)
    given = [k for k in ("air_density", "lock_number") if k in data]
    if len(given) != 1:
        what = "both are given" if given else "neither is given"
        raise CaseError(
            f"[aero] {' and '.join(given) or 'air_density'}: give the air density or the Lock number, "
            f"one of the two ({what}; the other is derived)"
        )
    inflow = data.get("inflow", "uniform")
    if inflow not in INFLOWS:
        near = difflib.get_close_matches(inflow, INFLOWS, n=1, cutoff=0.5)
        hint = f" (did you mean '{near[0]}'?)" if near else ""
        raise CaseError(f"[aero] inflow = {shown(inflow)}: must be one of {list(INFLOWS)}{hint}")
    values = {k: float(v) for k, v in data.items() if k not in ("inflow", "lock_number")}
    for key in DEGREE_KEYS:
        if key in values:
            values[key] = math.radians(values[key])
    values.setdefault("root_cutout", max(b.hinge_offset for b in rotor.blades))
    if "lock_number" in data:
        lock = float(data["lock_number"])
        if not (finite(lock) and lock >= 0):
            raise CaseError(
                f"[aero] lock_number = {shown(data['lock_number'])}: must be a finite number >= 0"
            )
        for key in ("lift_slope", "chord", "tip_radius"):
            if not values[key] > 0:
                raise CaseError(f"[aero] {key} = {shown(data[key])}: must be a finite number > 0")
        inertia = rotor.blades[0].blade_inertia
        values["air_density"] = Aero.density_for_lock(
            lock, values["lift_slope"], values["chord"], values["tip_radius"], inertia
        )
        if not finite(values["air_density"]):
            raise CaseError(f"[aero] lock_number = {shown(data['lock_number'])}: too large for this blade")
    try:
        aero = Aero(inflow=inflow, lock_given="lock_number" in data, **values)
    except ParameterError as err:
        if err.key == "air_density" and "lock_number" in data:  # (the density derived from it)
            raise CaseError(
                f"[aero] lock_number = {shown(data['lock_number'])}: gives an air density of "
                f"{err.value:.6g} kg/m^3 with this blade, which {err.allowed}"
            ) from None
        value = data.get(err.key, err.value)
        raise CaseError(f"[aero] {err.key} = {shown(value)}: {err.allowed}") from None
    try:
        return Rotor(
            blades=rotor.blades, flap=rotor.flap, dampers=rotor.dampers, aero=aero, lag_laws=rotor.lag_laws
        )
    except ParameterError as err:
        value = data.get(err.key, err.value)
        raise CaseError(f"[aero] {err.key} = {shown(value)}: {err.allowed}") from None


def parse_case(data: dict, source: str = "", text: str = "") -> Case:
    """Build a Case from the parsed TOML tables (``text``: the file they came from).

    Raises
    ------
    CaseError
        With a one-line message naming the key, the value and what is allowed.
    """
    _check_table("", data)
    rotor = _rotor(data["rotor"])
    if "aero" in data:
        rotor = _aero(data["aero"], rotor)
    limit_cycle = _limit_cycle(data.get("limit_cycle", {}), data["sweep"])
    table = rotor.unsimulable_blade
    if limit_cycle.confirm and table is not None:  # (known now: refused before any work)
        raise CaseError(
            f"[limit_cycle] confirm = {shown(data['limit_cycle']['confirm'])}: confirming runs simulate the "
            f'laws, and blade {table + 1}\'s law = "table" gives no moment in time; leave confirm out, or '
            "fit a friction-link law to the table"
        )
    return _build(
        "[sweep] ",  # the one check of the whole case is the size of the sweep
        Case,
        rotor=rotor,
        body=_body(data["body"]),
        sweep=_sweep(data["sweep"]),
        limit_cycle=limit_cycle,
        simulation=_simulation(data.get("simulation", {})),
        title=data.get("title", Path(source).stem if source else "groundres case"),
        description=data.get("description", ""),
        source=source,
        text=text,
    )


def _limit_cycle(data: dict, sweep: dict) -> LimitCycleOptions:
    _check_table("limit_cycle", data)
    values = {k: (v if k == "points" else float(v)) for k, v in data.items() if k != "confirm"}
    if "confirm" in data:  # (speeds in the sweep's unit, checked as written)
        _build("[limit_cycle] ", LimitCycleOptions, confirm=tuple(data["confirm"]))
        factor = SPEED_UNITS.get(sweep.get("unit", "rad/s"), 1.0)
        values["confirm"] = tuple(float(v) * factor for v in data["confirm"])
    high = values.get("amplitude_max")
    if "amplitude_min" not in values and high is not None and finite(high) and 0 < high <= 0.001:
        raise CaseError(
            f"[limit_cycle] amplitude_max = {shown(data['amplitude_max'])}: must be above amplitude_min "
            "(0.001 deg unless given)"
        )
    return _build("[limit_cycle] ", LimitCycleOptions, **values)


def _simulation(data: dict) -> SimulationOptions:
    _check_table("simulation", data)
    initial = data.get("initial", {})
    for name, value in initial.items():
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise CaseError(
                f"[simulation.initial] {name} = {shown(value)}: must be a number (m, rad; m/s, rad/s for "
                "NAME_rate)"
            )
    values = {k: float(v) for k, v in data.items() if k != "initial"}
    values["initial"] = tuple((str(k), float(v)) for k, v in initial.items())
    return _build("[simulation] ", SimulationOptions, **values)


def load_case(path_or_name: str | Path) -> Case:
    """Read a case file, or a shipped case by name (see ``groundres cases``).

    Raises
    ------
    CaseError
        If the file is missing, is not valid TOML, or breaks the format.
    """
    text, source = case_text(path_or_name)
    data = toml_data(text, source)
    try:
        return parse_case(data, source, text)
    except RecursionError:
        raise CaseError(f"{source}: arrays or tables nested too deeply to read") from None
