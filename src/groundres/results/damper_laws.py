"""What a result reports of a rotor whose lag dampers follow laws (:mod:`groundres.model.damper_laws`).

The ``lag_dampers`` block of summary.json: each blade's law, its parameters
(SI; a table's amplitudes in deg and reference frequency in Hz, as the case
file gives them) and the small-motion values the linear analysis used, with
the note that says so.
"""

from __future__ import annotations

import math
from dataclasses import fields

from ..model.damper_laws import LAW_KEYS, UNITS

#: Said wherever a linear analysis meets nonlinear lag dampers.
SMALL_MOTION_NOTE = (
    "this analysis is linear: each nonlinear lag damper enters at its small-motion values (its "
    "slope at rest: a bilinear damper's first slope, a friction damper's regularisation, a friction "
    "link stuck, a table's smallest amplitude with its loss at the reference frequency); how it "
    "behaves at larger amplitudes is what its describing function (groundres damper) and its limit "
    "cycles (groundres cycles) tell"
)


def laws_block(case) -> dict:
    """The ``lag_dampers`` block of summary.json (module docstring)."""
    blades = []
    for k, entry in enumerate(case.rotor.lag_laws):
        blade = case.rotor.blades[k]
        if entry is None:
            blades.append({"blade": k + 1, "law": None, "lag_damping": blade.lag_damping})
            continue
        law = entry.law
        required, optional = LAW_KEYS[law.law]
        values = {}
        for f in fields(law):
            if f.name in required + optional:
                values[f.name] = getattr(law, f.name)
        if law.law == "table":
            values["amplitudes"] = [math.degrees(a) for a in law.amplitudes]
            values["reference_frequency"] = law.reference_frequency / (2 * math.pi)
        c0, k0 = law.small_motion()
        blades.append(
            {
                "blade": k + 1,
                "law": law.law,
                "parameters": values,
                "small_motion": {"damping": c0, "stiffness": k0},
                "root_stiffness": entry.root_stiffness,
            }
        )
    return {
        "blades": blades,
        "units": {**UNITS, "small_motion.damping": "N m s/rad", "small_motion.stiffness": "N m/rad"},
        "note": SMALL_MOTION_NOTE if case.rotor.nonlinear else "every law is linear",
    }
