"""What a study's map shows beside its measures: the case's design point and the Deutsch requirement.

:func:`plot` draws a study or a boundary search
(:mod:`groundres.plotting.study_map`) with the case's own value of each
varied key (:func:`design_point`) and, on a two-key map with the lag damping,
the lag damping the Deutsch criterion asks for (:func:`deutsch_curve`).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..assess.deutsch import deutsch
from ..errors import CaseError
from .grid import Grid, entry_of, raw, table_of, varied_case


def design_point(case, grid: Grid) -> dict:
    """The case's own value of each varied key (where the case file gives it)."""
    data, out = raw(case), {}
    for key in grid.keys:
        entry = entry_of(key)
        if entry and entry[0] == "rotor.blade":
            table = next((b for b in data["rotor"].get("blade", []) if b.get("index") == entry[1]), {})
            value = table.get(entry[2], data["rotor"].get(entry[2]))
        elif entry:
            value = table_of(data, entry[0])[entry[1] - 1].get(entry[2])
        else:
            table, _, name = key.rpartition(".")
            value = data.get(table, {}).get(name)
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            out[key] = float(value)
    return out


def deutsch_curve(case, grid: Grid):
    """The Deutsch requirement over a two-key map with a lag-damping key, where it applies.

    Returns (lag_key, other_key, other_values, required [N m s/rad]) with
    NaN where no body mode is tuned inside the sweep; a str saying why the
    criterion does not apply; or None (no lag-damping key, or not two keys).
    """
    if len(grid.keys) != 2:
        return None
    # (the criterion sizes every blade's damper at once: not drawn against one blade's)
    lags = [k for k in grid.keys if k == "rotor.lag_damping"]
    if len(lags) != 1:
        return None
    lag = lags[0]
    other = next(k for k in grid.keys if k != lag)
    data, values, required, why = raw(case), np.asarray(grid.values[grid.keys.index(other)]), [], set()
    for v in values:
        try:
            c = varied_case(data, {other: float(v)})
        except CaseError:  # (the point fails in the study too: it says why)
            required.append(np.nan)
            continue
        need = []
        for e in deutsch(c.rotor, c.body):
            if e.limitation is not None:
                why.add(e.limitation)
            elif e.tuning_speed is not None and c.sweep.start <= e.tuning_speed <= c.sweep.stop:
                need.append(e.required_lag_damping)
        required.append(max(need) if need else np.nan)
    if why and not np.isfinite(required).any():
        return "does not apply (" + "; ".join(sorted(why)) + ")"
    return lag, other, values, np.asarray(required, float)


def plot(ds: xr.Dataset, case, grid: Grid):
    """The figure of a study or of a boundary search (:mod:`groundres.plotting.study_map`)."""
    from ..plotting.study_map import boundary_map, study_map

    design, curve = design_point(case, grid), deutsch_curve(case, grid)
    if "boundary_key" in ds.attrs:
        title = f"Stability boundary along {ds.attrs['boundary_key']}: {case.title}"
        return boundary_map(ds, list(grid.keys), design, curve, title)
    return study_map(ds, design, curve, f"Study: {case.title}")
