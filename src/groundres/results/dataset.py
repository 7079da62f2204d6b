"""The sweep as a self-describing data set (CF conventions): behind modes.nc and to_xarray().

Every numeric variable has ``units`` (UDUNITS strings, "1" for dimensionless
numbers, flags and indices) and ``long_name``; string variables (labels) have
a ``long_name``. The case is flattened into global attributes ``rotor_<key>``,
``body_<key>``, ``sweep_<key>``, each number with a ``<name>_units`` beside it
(blade keys hold one value per blade, blade 1 first); speeds are in rad/s.
"""

from __future__ import annotations

import numpy as np

from .._version import __version__
from ..assess.stability import GROWTH_FLOOR, GROWTH_PER_RADIAN
from ..model.body import TRANSLATIONS
from ..model.units import BLADE_UNITS, BODY_UNITS, ROD_UNITS, udunits
from .air import trim_variables
from .summary import open_below_note

CONVENTIONS = "CF-1.10"


def coordinate_unit(coordinate) -> str:
    """Unit of a coordinate (:func:`groundres.model.mbc.unit_of`)."""
    return coordinate.unit


def case_attributes(case) -> dict:
    """The case as flat global attributes (numbers SI, speeds rad/s, each with its units)."""
    out = {}

    def put(name, value, units=None):
        out[name] = value
        if units:
            out[f"{name}_units"] = units

    rotor, body, sweep = case.rotor, case.body, case.sweep
    put("case_title", case.title)
    if case.description:
        put("case_description", case.description.strip())
    if case.source:
        put("case_source", case.source)
    put("rotor_blades", np.int32(rotor.n_blades))
    put("rotor_flap", "true" if rotor.flap else "false")
    put("rotor_identical_blades", "true" if rotor.identical else "false")
    for key, units in BLADE_UNITS.items():
        if key.startswith("flap") and not rotor.flap:
            continue
        put(f"rotor_{key}", np.array([getattr(b, key) for b in rotor.blades], float), udunits(units))
    put("body_dofs", " ".join(body.dofs))
    put("body_form", body.form)
    if body.form == "modal":
        for dof in body.dofs:
            key = body.inertia_key(dof)
            turns = dof not in TRANSLATIONS
            put(f"body_{key}", float(getattr(body, key)), udunits(BODY_UNITS[key.split("_")[0]][turns]))
            for kind in ("stiffness", "damping"):
                put(
                    f"body_{kind}_{dof}",
                    float(getattr(body, f"{kind}_{dof}")),
                    udunits(BODY_UNITS[kind][turns]),
                )
    else:
        put("body_mass", float(body.mass), "kg")
        put("body_inertia_tensor", body.inertia_tensor().ravel(), "kg m2")
        put("body_centre_of_mass", np.array([body.centre_x, body.centre_y, body.centre_z]), "m")
        for kind, units in (
            ("position", "m"),
            ("stiffness", BODY_UNITS["stiffness"][0]),
            ("damping", BODY_UNITS["damping"][0]),
        ):
            values = [[getattr(leg, f"{kind}_{a}") for a in "xyz"] for leg in body.gear]
            put(f"body_gear_{kind}", np.array(values, float).ravel(), units)
    put("body_hub", np.array([body.hub_x, body.hub_y, body.hub_height], float), "m")
    if {"pitch", "roll"} & set(body.dofs):
        put("body_hub_height", float(body.hub_height), "m")
    if rotor.dampers:
        put("rotor_damper_kind", " ".join(d.kind for d in rotor.dampers))
        put("rotor_damper_blade", np.array([d.blade for d in rotor.dampers], np.int32))
        put("rotor_damper_damping", np.array([d.damping for d in rotor.dampers], float), ROD_UNITS["damping"])
        put(
            "rotor_damper_stiffness",
            np.array([d.stiffness for d in rotor.dampers], float),
            ROD_UNITS["stiffness"],
        )
        for end in ("start", "end"):
            values = [[getattr(d, f"{end}_{a}") for a in "xyz"] for d in rotor.dampers]
            put(f"rotor_damper_{end}", np.array(values, float).ravel(), "m")
    put("sweep_start", float(sweep.start), "rad/s")
    put("sweep_stop", float(sweep.stop), "rad/s")
    put("sweep_points", np.int32(sweep.points))
    put("sweep_unit", sweep.unit)
    if sweep.reference:
        put("sweep_reference", float(sweep.reference), "rad/s")
    put("sweep_frame", sweep.frame)
    put("sweep_method", sweep.method)
    return out


def _flag(dims, values, long_name, meanings):
    """A 0/1 variable with CF flag attributes."""
    return (
        dims,
        np.asarray(values).astype(np.int8),
        {
            "long_name": long_name,
            "units": "1",
            "flag_values": np.array([0, 1], np.int8),
            "flag_meanings": meanings,
        },
    )


def dataset(result):
    """``(coords, variables, attrs)`` of a :class:`~groundres.results.sweep.SweepResult`.

    ``coords`` and ``variables`` map names to ``(dims, values, attrs)``.
    """
    speed = result.rotor_speed
    modes = result.modes
    st = result.stability
    unstable = np.zeros(len(speed), np.int8)
    for s, e in st.unstable_ranges:
        unstable[(speed >= s) & (speed <= e)] = 1
    coords = {
        "speed": (("speed",), speed, {"units": "rad/s", "long_name": "rotor speed"}),
        "mode": (("mode",), np.array(result.labels, dtype=object), {"long_name": "mode label"}),
        "coordinate": (
            ("coordinate",),
            np.array([c.symbol for c in result.coordinates], dtype=object),
            {"long_name": "nonrotating coordinate of the mode shapes (body, multiblade)"},
        ),
        "harmonic": (
            ("harmonic",),
            np.asarray(modes.harmonic_orders, dtype=np.int32),
            {
                "units": "1",
                "long_name": "harmonic order m: frequency offset m * rotor speed from the mode's frequency",
            },
        ),
        "root": (
            ("root",),
            np.arange(modes.root_label.shape[1], dtype=np.int32),
            {"units": "1", "long_name": "tracked root: one continuous branch of the sweep"},
        ),
        "end": (("end",), np.array(["start", "stop"], dtype=object), {"long_name": "end of a range"}),
    }
    both = ("speed", "mode")
    shape_note = (
        "an eigenvector: its scale and phase are arbitrary, only ratios and phase differences "
        "between coordinates mean something; each coordinate in its own unit (coordinate_units: "
        "m for body translations, rad for angles)"
    )
    variables = {
        "frequency": (
            both,
            result.frequency,
            {"units": "rad/s", "long_name": f"modal frequency, {result.frame} frame"},
        ),
        "frequency_nonrotating": (
            both,
            modes.frequency_nonrotating,
            {"units": "rad/s", "long_name": "modal frequency, nonrotating frame"},
        ),
        "frequency_rotating": (
            both,
            modes.frequency_rotating,
            {"units": "rad/s", "long_name": "modal frequency, rotating frame"},
        ),
        "real_part": (
            both,
            result.real_part,
            {"units": "1/s", "long_name": "largest real part of the mode"},
        ),
        "damping_ratio": (both, result.damping_ratio, {"units": "1", "long_name": "damping ratio"}),
        "shape_real": (
            both + ("coordinate",),
            np.moveaxis(modes.shape, 1, 2).real,
            {"units": "1", "long_name": "mode shape (nonrotating axes), real part", "comment": shape_note},
        ),
        "shape_imag": (
            both + ("coordinate",),
            np.moveaxis(modes.shape, 1, 2).imag,
            {
                "units": "1",
                "long_name": "mode shape (nonrotating axes), imaginary part",
                "comment": shape_note,
            },
        ),
        "coordinate_units": (
            ("coordinate",),
            np.array([coordinate_unit(c) for c in result.coordinates], dtype=object),
            {"long_name": "unit of each coordinate of the mode shapes"},
        ),
        "participation": (
            both + ("harmonic",),
            modes.participation,
            {"units": "1", "long_name": "share of each harmonic in the mode, nonrotating frame"},
        ),
        "exchange": _flag(
            both,
            modes.exchange,
            "the label moved to another branch since the previous speed (veering)",
            "same_branch exchanged",
        ),
        "harmonic_change": _flag(
            both,
            modes.harmonic_change,
            "the nonrotating frequency moved to another harmonic of its root since "
            "the previous speed (that harmonic holds clearly more of the label's content)",
            "continuous moved",
        ),
        "harmonic_change_rotating": _flag(
            both,
            modes.harmonic_change_rotating,
            "the same for the rotating-frame frequency",
            "continuous moved",
        ),
        "root_mode": (
            ("speed", "root"),
            modes.root_label.astype(np.int32),
            {"units": "1", "long_name": "index (into mode) of the mode the root belongs to"},
        ),
        "root_real_part": (
            ("speed", "root"),
            modes.root_real_part,
            {"units": "1/s", "long_name": "real part of the root"},
        ),
        "unstable": _flag(("speed",), unstable, "speed lies in an unstable range", "stable unstable"),
        "unstable_range": (
            ("range", "end"),
            np.array(st.unstable_ranges, float).reshape(-1, 2),
            {"units": "rad/s", "long_name": "rotor-speed range in which some root grows"}
            | (
                {}
                if st.open_below is None
                else {"comment": "first range: " + open_below_note(f"{st.open_below:.6g} rad/s")}
            ),
        ),
        "unstable_range_modes": (
            ("range",),
            np.array([", ".join(result.unstable_modes(s, e)) for s, e in st.unstable_ranges], dtype=object),
            {"long_name": "modes with a growing root in the range"},
        ),
    }
    if result.trim is not None:
        variables.update(trim_variables(result))
    attrs = {
        "Conventions": CONVENTIONS,
        "title": result.case.title,
        "source": f"groundres {__version__}, {result.method.value} analysis",
        "groundres_version": __version__,
        "method": result.method.value,
        "frame": result.frame,
        "comment": (
            "speeds and frequencies in rad/s, real parts in 1/s (SI; the case's own speed unit "
            "is sweep_unit); a real part counts as growth above growth_threshold_per_radian * "
            "rotor speed + growth_threshold_floor"
        ),
        "growth_threshold_per_radian": GROWTH_PER_RADIAN,
        "growth_threshold_floor": GROWTH_FLOOR,
        "growth_threshold_floor_units": "1/s",
        **case_attributes(result.case),
    }
    return coords, variables, attrs
