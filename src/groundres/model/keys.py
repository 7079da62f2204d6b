"""The case file's tables, the keys each holds and the kind of value each key takes.

:data:`SCHEMA` maps a table's dotted name ("" for the top level, "rotor.lag_damper")
to its keys and their kinds; :data:`REQUIRED` lists the keys a table must have;
:func:`key_text` names a key as the file writes it. The reader
(:mod:`groundres.model.schema`) checks a file against them, and design studies
(:mod:`groundres.studies.grid`) find the keys they may vary there.
"""

from __future__ import annotations

from .body import LEG_KEYS, MODAL_KEYS, RIGID_KEYS
from .damper_laws import LIST_KEYS
from .damper_laws import UNITS as LAW_UNITS
from .dampers import DAMPER_KEYS
from .params import BLADE_KEYS
from .units import AERO_UNITS

NUMBER, INT, BOOL, STR, STRLIST, TABLE, TABLES, NUMLIST, FAILED_OR_TABLE = (
    "a number",
    "a whole number",
    "true or false",
    "a string",
    "a list of strings",
    "a table",
    "an array of tables",
    "a list of numbers",
    'a table or "failed"',
)

SCHEMA = {
    "": {
        "title": STR,
        "description": STR,
        "rotor": TABLE,
        "body": TABLE,
        "sweep": TABLE,
        "aero": TABLE,
        "limit_cycle": TABLE,
        "simulation": TABLE,
    },
    "rotor": {
        "blades": INT,
        "hinge_offset": NUMBER,
        "blade_mass": NUMBER,
        "blade_static_moment": NUMBER,
        "blade_inertia": NUMBER,
        "lag_stiffness": NUMBER,
        "lag_damping": NUMBER,
        "flap": BOOL,
        "flap_stiffness": NUMBER,
        "flap_damping": NUMBER,
        "blade": TABLES,
        "damper": TABLES,
        "lag_damper": TABLE,
    },
    "rotor.blade": {"index": INT, **{k: NUMBER for k in BLADE_KEYS}, "lag_damper": FAILED_OR_TABLE},
    "rotor.lag_damper": {"law": STR, **{k: NUMLIST if k in LIST_KEYS else NUMBER for k in LAW_UNITS}},
    "rotor.damper": {"kind": STR, "blade": INT, **{k: NUMBER for k in DAMPER_KEYS if k != "kind"}},
    "body": {
        "dofs": STRLIST,
        "hub_height": NUMBER,
        "hub_x": NUMBER,
        "hub_y": NUMBER,
        **{k: NUMBER for k in MODAL_KEYS},
        **{k: NUMBER for k in RIGID_KEYS},
        "gear": TABLES,
    },
    "body.gear": {k: NUMBER for k in LEG_KEYS},
    "aero": {**{k: NUMBER for k in AERO_UNITS}, "inflow": STR},
    "limit_cycle": {"amplitude_min": NUMBER, "amplitude_max": NUMBER, "points": INT, "confirm": NUMLIST},
    "simulation": {"duration": NUMBER, "window": NUMBER, "along_cycle": NUMBER, "initial": TABLE},
    "sweep": {
        "start": NUMBER,
        "stop": NUMBER,
        "points": INT,
        "unit": STR,
        "reference": NUMBER,
        "frame": STR,
        "method": STR,
        "operating_start": NUMBER,
        "operating_stop": NUMBER,
        "required_damping_ratio": NUMBER,
    },
}
REQUIRED = {
    "": ("rotor", "body", "sweep"),
    "rotor": ("blades", "hinge_offset", "blade_mass", "blade_static_moment", "blade_inertia"),
    "rotor.blade": ("index",),
    "rotor.damper": ("kind",),
    "body.gear": ("position_x", "position_y", "position_z"),
    "sweep": ("start", "stop"),
    "aero": ("lift_slope", "chord", "tip_radius"),
}


def key_text(table: str, key: str = "") -> str:
    """How a message names ``key`` of a case file's ``table`` (as the file writes it):
    ``[sweep] stop``, ``[[body.gear]] damping`` (an array of tables), ``[rotor]``."""
    if not table:
        return key
    parent, _, name = table.rpartition(".")
    array = SCHEMA.get(parent, {}).get(name) == TABLES
    where = f"[[{table}]]" if array else f"[{table}]"
    return f"{where} {key}" if key else where
