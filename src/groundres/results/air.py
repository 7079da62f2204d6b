"""What a result of a rotor in air reports beside its roots: the air and the hover trim.

The ``aero`` block (the Lock number and solidity, the air's parameters and
which of density and Lock number the case gave) and the trim table over the
sweep (inflow ratio, thrust coefficient and blade loading, coning and trim
lag, thrust and torque), as ``summary.json`` holds them and as variables of
``modes.nc``; and the note the Deutsch criterion needs in air.
"""

from __future__ import annotations

import math

import numpy as np

from ..model.units import AERO_UNITS

#: Said wherever the Deutsch criterion appears beside a rotor in air.
DEUTSCH_IN_AIR = (
    "the Deutsch criterion has no aerodynamics: it weighs the blades' structural lag dampers and the "
    "body's dampers only, while the roots include the air's damping of flap and lag"
)
#: The trim table's columns: name -> (unit, long name).
TRIM_COLUMNS = {
    "inflow_ratio": ("1", "inflow ratio lambda = v / (Omega R), positive down through the disk"),
    "thrust_coefficient": ("1", "thrust coefficient C_T = T / (rho pi R^2 (Omega R)^2)"),
    "blade_loading": ("1", "blade loading C_T / sigma"),
    "coning": ("deg", "coning angle at the trim"),
    "trim_lag": ("deg", "lag angle at the trim (against the rotation)"),
    "thrust": ("N", "rotor thrust along the shaft"),
    "torque": ("N m", "torque the rotor asks of the shaft"),
}


def aero_block(case) -> dict:
    """The ``aero`` block of summary.json: the air's parameters and what follows from them."""
    aero, rotor = case.rotor.aero, case.rotor
    inertia = rotor.blades[0].blade_inertia
    return {
        "lock_number": aero.lock_number(inertia),
        "lock_number_note": "gamma = rho a c R^4 / I, I the inertia of blade 1 about its hinge",
        "given": "lock_number" if aero.lock_given else "air_density",
        "solidity": aero.solidity(rotor.n_blades),
        "air_density": aero.air_density,
        "lift_slope": aero.lift_slope,
        "drag_coefficient": aero.drag_coefficient,
        "chord": aero.chord,
        "tip_radius": aero.tip_radius,
        "root_cutout": aero.root_cutout,
        "collective": math.degrees(aero.collective),
        "twist": math.degrees(aero.twist),
        "pitch_flap": aero.pitch_flap,
        "pitch_lag": aero.pitch_lag,
        "inflow": aero.inflow,
        "units": {k: u for k, u in AERO_UNITS.items() if u != "1"},
    }


def trim_columns(trim, alike: bool) -> dict:
    """name -> values over the sweep (n_s,), or per blade (n_s, N) for coning and trim lag where
    the blades differ (``alike`` False)."""
    pick = (lambda a: a[:, 0]) if alike else (lambda a: a)
    return {
        "inflow_ratio": trim.inflow_ratio,
        "thrust_coefficient": trim.thrust_coefficient,
        "blade_loading": trim.loading,
        "coning": np.degrees(pick(trim.coning)),
        "trim_lag": np.degrees(pick(trim.trim_lag)),
        "thrust": trim.thrust,
        "torque": trim.torque,
    }


def trim_block(result) -> dict:
    """The ``trim`` block of summary.json: the hover trim at every speed of the sweep."""
    alike = result.case.rotor.blades_alike
    columns = trim_columns(result.trim, alike)
    out = {
        "rotor_speed": [float(w) for w in result.rotor_speed],
        "units": {name: unit for name, (unit, _) in TRIM_COLUMNS.items()} | {"rotor_speed": "rad/s"},
        "note": (
            "The body at rest, each blade still in the hub's axes at its coning and trim lag, uniform "
            "inflow from momentum theory (C_T = 2 lambda |lambda|)"
            + ("" if alike else "; coning and trim_lag per blade (rows: speeds, columns: blades)")
        ),
    }
    for name, values in columns.items():
        out[name] = np.asarray(values, dtype=float).tolist()
    return out


#: Rows of the trim table the terminal and the report show (summary.json and modes.nc hold
#: every speed).
SHOWN_ROWS = 6


def shown_rows(trim: dict) -> list[tuple[int, dict]]:
    """The rows of summary.json's ``trim`` block (``trim``) that the terminal and the report
    show: a few speeds spread over the sweep, each as (index, name -> value), blade 1's coning
    and trim lag where they are per blade."""
    n = len(trim["rotor_speed"])
    rows = sorted({round(i * (n - 1) / (SHOWN_ROWS - 1)) for i in range(SHOWN_ROWS)})

    def first(value):
        return value[0] if isinstance(value, list) else value

    return [(i, {name: first(trim[name][i]) for name in TRIM_COLUMNS}) for i in rows]


def trim_variables(result) -> dict:
    """Variables of modes.nc for the trim: name -> (dims, values, attrs)."""
    alike = result.case.rotor.blades_alike
    out = {}
    for name, values in trim_columns(result.trim, alike).items():
        unit, long_name = TRIM_COLUMNS[name]
        dims = ("speed",) if np.ndim(values) == 1 else ("speed", "blade")
        out[f"trim_{name}"] = (dims, np.asarray(values, dtype=float), {"units": unit, "long_name": long_name})
    return out
