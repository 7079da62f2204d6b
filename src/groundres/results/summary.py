"""The summary.json content of a sweep: verdicts, worst values, damping requirements.

Every speed is in rad/s and every number is SI (the data contract; the case's
own unit is in ``sweep.unit_in_case``). Every number is a finite number or
null, and a null always has a ``<name>_reason`` string beside it.
"""

from __future__ import annotations

import math

import numpy as np

from .._version import __version__
from ..assess.damping_search import RTOL
from ..assess.deutsch import DeutschEntry, installed_lag_damping, lag_frequency_per_rev
from ..assess.stability import GROWTH_FLOOR, GROWTH_PER_RADIAN, growth_threshold, is_neutral
from ..model.system import searched, searched_unit
from ..model.units import ROD_UNITS
from .air import DEUTSCH_IN_AIR, aero_block, trim_block
from .damper_laws import laws_block

#: Units of the quantities in summary.json.
UNITS = {
    "speed": "rad/s",
    "frequency": "rad/s",
    "real_part": "1/s",
    "damping_ratio": "1",
    "lag_damping": "N m s/rad",
    "body_damping": "N s/m (pitch and roll referred to the hub)",
    "lag_frequency": "per rev",
}

DEUTSCH_NOTE = (
    "Deutsch criterion at exact tuning Omega (1 - nu) = omega_b, light damping: "
    "planar C_b C_lag >= (N/4) S^2 omega_b^2 (1-nu)/nu; isotropic "
    "C_h C_lag >= (N/2) S^2 omega_h^2 (1-nu)/nu; omega_b includes the rotor mass; "
    "nu is the rotating lag frequency [per rev] at the tuning speed; the verdict "
    "compares the smallest working damper with the requirement and is null where "
    "the criterion does not apply (dissimilar blades, two blades) or there is no tuning"
)


#: What the Deutsch rows of an unstable sweep must not be read as.
DEUTSCH_UNSTABLE = (
    "the analysis finds the rotor unstable (unstable_ranges): the criterion's verdicts below "
    "are per body mode, at light damping and exact tuning, and do not make it stable"
)

MARGINS_NOTE = (
    "damping ratios seen from nonrotating axes; least over the operating range and over the "
    "run-up (the sweep below it), refined between the sweep's speeds; margin = least over the "
    "operating range - required_damping_ratio (0 where none is required); a mode neutral at rest "
    "(neutral_at_rest) counts only where it vibrates (its frequency seen from rotating axes is not "
    "zero); growth_margin: the largest real part of the vibrating modes over the sweep"
)


def num(x):
    """A JSON-safe float (None for None, NaN or infinity)."""
    if x is None:
        return None
    x = float(x)
    return x if math.isfinite(x) else None


def put(out: dict, key: str, value, reason: str) -> dict:
    """``out[key] = num(value)``; where that is null, ``out[key + "_reason"] = reason``."""
    out[key] = num(value)
    if out[key] is None:
        out[f"{key}_reason"] = reason
    return out


def open_below_note(speed_text: str) -> str:
    """What a range open at the lowest speed the analysis reaches above rest means."""
    return (
        f"still growing at {speed_text}, the lowest speed above rest the analysis looks at "
        "(a Floquet analysis costs more the slower the rotor): the range may begin lower"
    )


#: What a range that reaches an end of the sweep means.
SWEEP_END_NOTE = "the sweep's stop: still growing there, the range may continue above it"
SWEEP_START_NOTE = "the sweep's start: already growing there, the range may begin below it"


def open_ends(result, start, end) -> tuple[bool, bool]:
    """Whether a range [start, end] [rad/s] reaches the sweep's first (moving) speed and its
    last: growth there may go on beyond the sweep."""
    speeds = result.rotor_speed
    first = float(speeds[0])
    return bool(first > 0 and start <= first), bool(end >= speeds[-1])


def _range(result, start, end) -> dict:
    out = {"start": start, "end": end, "modes": result.unstable_modes(start, end)}
    at_start, at_stop = open_ends(result, start, end)
    if result.stability.open_below is not None and start == result.stability.open_below:
        out["start_note"] = open_below_note(f"{start:.6g} rad/s")
    elif at_start:
        out["start_note"] = SWEEP_START_NOTE
    out["open_start"] = at_start or "start_note" in out
    out["open_end"] = at_stop
    if at_stop:
        out["end_note"] = SWEEP_END_NOTE
    return out


def no_exact_reason(result, speed) -> str:
    """Why a result has no exact minimum lag damping, ``speed(w)`` writing a speed [rad/s]."""
    kind, value = result.no_exact_lag_damping or ("cap", None)
    if kind == "skipped":
        return "the search for it was not run"
    if kind == "below":
        return (
            f"the sweep is unstable below {speed(value)} (half the lowest body frequency), where the "
            "regressive lag mode meets no body mode: lag damping does not decide stability there"
        )
    unit = searched_unit(result.case.rotor)
    upto = f" {value:.4g} {unit}" if value is not None else " the largest tried"
    if kind == "afforded":
        return (
            f"no lag damping up to{upto} makes the sweep stable, and the Floquet analysis cannot "
            "follow a stronger damper within its work limit (the periodic equations grow stiff as "
            "the damper decays faster, most at the search's lowest speeds)"
        )
    speeds = result.rotor_speed
    undamped = [
        e.body_mode
        for e in result.deutsch
        if e.required_lag_damping is not None
        and math.isinf(e.required_lag_damping)
        and e.tuning_speed is not None
        and speeds[0] <= e.tuning_speed <= speeds[-1]
    ]
    if undamped:
        return (
            f"no lag damping up to{upto} makes the sweep stable: the body mode {', '.join(undamped)} "
            "meets the regressive lag mode inside the sweep with no body damping, and the Deutsch "
            "criterion needs some (no lag damper suffices without it)"
        )
    return (
        f"no lag damping up to{upto} (the largest the search tries: many times the Deutsch value "
        "and the installed damper) makes the sweep stable with the installed body damping"
    )


def _lag_frequency_at(rotor, speed) -> dict:
    """The rotating cyclic lag frequency [per rev] at the reference speed (summary.json's block)."""
    entry = {
        "unit": "per rev",
        "note": "nu = sqrt((K_lag + rods' cyclic stiffness) / (I Omega^2) + e S / I) of the average "
        "blade at the reference speed: below 1 soft in plane (ground resonance possible), above 1 stiff",
    }
    put(entry, "speed", speed, "no reference speed in the case")
    if not speed:
        return put(entry, "value", None, "no reference speed in the case")
    return put(
        entry,
        "value",
        lag_frequency_per_rev(rotor, speed),
        "the reference speed is too small: the lag spring's share K_lag / (I Omega^2) overflows",
    )


def summary(result) -> dict:
    """The summary.json content of a :class:`~groundres.results.sweep.SweepResult`."""
    st = result.stability
    case = result.case
    sweep = case.sweep
    installed, failed = installed_lag_damping(case.rotor)
    speeds = result.rotor_speed
    out = {
        "title": case.title,
        "groundres_version": __version__,
        "method": result.method.value,
        "frame": result.frame,
        "speed_unit": "rad/s",
        "units": dict(UNITS),
        "stable": st.stable,
        "unstable_ranges": [_range(result, s, e) for s, e in st.unstable_ranges],
        "max_real_part": _max_real_part(result),
        "min_damping_ratio": _min_damping_ratio(result),
        "growth_threshold_per_radian": GROWTH_PER_RADIAN,
        "growth_threshold_floor": GROWTH_FLOOR,
        "growth_threshold_note": (
            "a root grows when its real part exceeds growth_threshold_per_radian * rotor speed "
            "+ growth_threshold_floor [1/s]; values within that of zero are neutral (round-off)"
        ),
        "case": {
            "source": case.source,
            "blades": case.rotor.n_blades,
            "flap": case.rotor.flap,
            "body_dofs": list(case.body.dofs),
            "identical_blades": case.rotor.identical,
            "blades_alike": case.rotor.blades_alike,
            "isotropic_body": case.body.isotropic,
        },
        "sweep": {
            "start": float(speeds[0]),
            "stop": float(speeds[-1]),
            "points": int(len(speeds)),
            "unit_in_case": sweep.unit,
        },
        "modes": list(result.labels),
    }
    put(out["sweep"], "reference", sweep.reference, "no reference speed in the case")
    out["lag_frequency_at_reference"] = _lag_frequency_at(case.rotor, sweep.reference)
    lag = {
        "unit": "N m s/rad",
        "installed": installed,
        "installed_note": (
            "the smallest working lag damper: the blades' damper when they are identical; "
            "with dissimilar blades the smallest non-zero one (a failed damper, 0, is "
            "counted in failed_dampers)"
        ),
        "per_blade": [float(b.lag_damping) for b in case.rotor.blades],
        "failed_dampers": failed,
    }
    rods = case.rotor.dampers
    if rods:
        lag["installed_note"] = (
            "the cyclic (order 1) lag damping per blade: the smallest working blade-to-hub "
            "rotational damper, plus the damper rods' c (g_a^2 + g_b^2 + 2 g_a g_b cos(2 pi j / N)) "
            "averaged over the blades (g: the rod's length change per radian of lag of each blade it joins)"
        )
        lag["rods"] = [
            {"kind": d.kind, "blade": d.blade, "damping": float(d.damping), "stiffness": float(d.stiffness)}
            for d in rods
        ]
        lag["rods_unit"] = dict(ROD_UNITS)
    on_rods = searched(case.rotor) == "rods"
    lag["exact_minimum_searched"] = "damper rods" if on_rods else "blade lag dampers"
    lag["exact_minimum_unit"] = searched_unit(case.rotor)
    put(lag, "exact_minimum", result.exact_lag_damping, no_exact_reason(result, lambda w: f"{w:.6g} rad/s"))
    lag["exact_minimum_relative_tolerance"] = RTOL[result.method.option]
    lag["exact_minimum_note"] = (
        "smallest damping, set on every working damper of the kind searched (the damper rods' "
        "damping along the rod where the case has rods, else each blade's lag damper; on every "
        "one when none has damping), for which no root grows anywhere in the sweep (body "
        "damping as installed)"
    )
    lag["deutsch"] = [deutsch_entry(e, speeds) for e in result.deutsch]
    lag["deutsch_note"] = DEUTSCH_NOTE + ("; " + DEUTSCH_IN_AIR if case.rotor.aero is not None else "")
    if not st.stable:
        lag["deutsch_overall"] = DEUTSCH_UNSTABLE
    out["lag_damping"] = lag
    if result.margins is not None:
        out["margins"] = margins_block(result)
    if case.rotor.aero is not None:
        out["aero"] = aero_block(case)
        out["trim"] = trim_block(result)
    if case.rotor.lag_laws:
        out["lag_dampers"] = laws_block(case)
    return out


def _max_real_part(result) -> dict:
    value, at = result.stability.max_real_part
    out = put({}, "value", value, "no finite real part in the sweep")
    put(out, "speed", at, "no finite real part in the sweep")
    out["mode"] = result._mode_at(at, result.real_part)
    out["growth_threshold"] = float(growth_threshold(at))
    out["neutral"] = math.isfinite(value) and bool(is_neutral(value, at))
    _vibrating(out, result, at)
    return out


def _vibrating(out: dict, result, at) -> None:
    """Whether the mode of a worst value vibrates at its speed (a mode neutral at rest that
    creeps while overdamped does not: :mod:`groundres.assess.margins`)."""
    if result.margins is None:
        return
    i = int(np.argmin(np.abs(result.rotor_speed - at)))
    grows_there = any(out["mode"] in labels for labels in result._between_at(at))  # (grows: vibrates)
    out["vibrating"] = grows_there or bool(result.margins.vibrating[i, result.labels.index(out["mode"])])
    if not out["vibrating"]:
        out["vibrating_note"] = (
            "a root of a mode neutral at rest that does not vibrate there (overdamped at low speed, it "
            "creeps back to rest): no margin; see margins for the vibrating modes"
        )


def _min_damping_ratio(result) -> dict:
    value, at = result.stability.min_damping_ratio
    reason = "every root sits at the origin: no damping ratio"
    out = put({}, "value", value, reason)
    put(out, "speed", at, reason)
    ratios = -np.nan_to_num(result.damping_ratio, nan=np.inf)
    out["mode"] = result._mode_at(at, ratios)
    # neutral: the root's real part, -ratio |lambda|, within the growth threshold
    i = int(np.argmin(np.abs(result.rotor_speed - at)))
    size = abs(result.modes.eigenvalue[i, result.labels.index(out["mode"])])
    for (a, b), roots in (result.between or {}).items():  # (a root between the sweep's speeds)
        if a <= at <= b and out["mode"] in roots:
            size = abs(roots[out["mode"]])
    out["neutral"] = math.isfinite(value) and bool(is_neutral(value * size, at))
    _vibrating(out, result, at)
    return out


def deutsch_entry(e: DeutschEntry, speeds) -> dict:
    """One Deutsch row of summary.json (see docs/case-files.md)."""
    no_tuning = "no tuning: the regressive lag mode never reaches the body frequency (nu >= 1)"
    out = {"body_mode": e.body_mode, "form": e.form}
    put(out, "body_frequency", e.body_frequency, "no body stiffness")
    put(out, "tuning_speed", e.tuning_speed, no_tuning)
    if e.tuning_speed is None:
        out["tuning_in_sweep"] = None
        out["tuning_in_sweep_reason"] = no_tuning
    else:
        out["tuning_in_sweep"] = bool(speeds[0] <= e.tuning_speed <= speeds[-1])
    put(out, "lag_frequency_per_rev", e.lag_frequency, no_tuning)
    put(out, "body_damping", e.body_damping, "not finite")
    if e.required_lag_damping is None:
        out["required_lag_damping"] = None
        out["required_lag_damping_reason"] = no_tuning
    elif math.isinf(e.required_lag_damping):
        out["required_lag_damping"] = None
        out["required_lag_damping_reason"] = "body undamped: no finite lag damping suffices"
    else:
        out["required_lag_damping"] = float(e.required_lag_damping)
    out["installed_lag_damping"] = float(e.installed_lag_damping)
    out["failed_lag_dampers"] = e.failed_dampers
    out["applies"] = e.applies
    if not e.applies:
        out["limitation"] = e.limitation
    out["satisfied"] = e.satisfied
    out["satisfied_reason"] = e.reason
    return out


def _least(least) -> dict | None:
    """A Least (:class:`groundres.assess.refine.Least`) as summary.json writes it."""
    return (
        None
        if least is None
        else {"value": num(least.value), "speed": num(least.speed), "neutral": least.neutral}
    )


def margins_block(result) -> dict:
    """The ``margins`` block of summary.json (:mod:`groundres.assess.margins`)."""
    m = result.margins
    lo, hi = m.operating_range
    out = {
        "operating_range": {"start": lo, "stop": hi, "given": m.operating_given},
        "required_damping_ratio": num(m.required_damping_ratio),
        "verdict": m.verdict,
    }
    if not m.operating_given:
        out["operating_range"]["note"] = "the case gives none: the whole sweep"
    if m.required_damping_ratio is None:
        out["required_damping_ratio_reason"] = "none required: margins are to zero, the stability boundary"
    out["run_up"] = {"start": m.run_up[0], "stop": m.run_up[1]} if m.run_up else None
    if m.run_up is None:
        out["run_up_reason"] = "the operating range starts at the sweep's start"
    for key, where in (("least_damping_ratio", "operating"), ("least_damping_ratio_run_up", "run_up")):
        least = m.least(where)
        out[key] = None if least is None else {"value": least[0], "speed": least[1], "mode": least[2]}
        if least is not None:
            out[key]["neutral"] = least[0] == 0.0
        if least is None:
            out[f"{key}_reason"] = (
                "no run-up" if m.run_up is None and where == "run_up" else "no mode vibrates there"
            )
    put(out, "margin", m.margin, "no mode vibrates in the operating range")
    growth = m.growth_margin
    out["growth_margin"] = (
        None
        if growth is None
        else {
            "value": growth[0],
            "speed": growth[1],
            "mode": growth[2],
            "neutral": bool(is_neutral(growth[0], growth[1])),
        }
    )
    if growth is None:
        out["growth_margin_reason"] = "no mode vibrates in the sweep"
    out["neutral_at_rest"] = list(m.neutral_at_rest)
    rows = []
    for mode in m.modes:
        row = {"mode": mode.mode}
        for key, least in (
            ("least_damping_ratio", mode.operating),
            ("least_damping_ratio_run_up", mode.run_up),
            ("largest_real_part", mode.largest_real_part),
        ):
            row[key] = _least(least)
            if least is None:
                row[f"{key}_reason"] = (
                    "no run-up"
                    if key.endswith("run_up") and m.run_up is None
                    else "it does not vibrate there"
                )
        put(
            row, "margin", mode.margin(m.required_damping_ratio), "it does not vibrate in the operating range"
        )
        row["grows"] = mode.grows
        row["verdict"] = mode.verdict
        rows.append(row)
    out["modes"] = rows
    out["units"] = {"damping_ratio": "1", "speed": "rad/s", "real_part": "1/s"}
    out["note"] = MARGINS_NOTE
    return out
