"""Design studies: stability measures of a case over a grid of its keys, and of its failures.

A designer's question is rarely one sweep: how much lag and landing-gear
damping does the helicopter need over its rotor-speed range, and what margin
is left when any one damper fails? :func:`study` answers it with one full
speed sweep per grid point (:mod:`groundres.studies.grid` says which keys
vary, :mod:`groundres.studies.run` computes, here or on a Dask cluster, and
:mod:`groundres.studies.store` keeps the results chunk by chunk so that an
interrupted study resumes where it stopped).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from .._version import __version__
from ..errors import StudyError
from .grid import FAILURE, Grid, canonical, make_grid, raw
from .measures import ERROR, MEASURES
from .run import compute, map_batches
from .store import DONE, load, template, write_netcdf

__all__ = ["study", "boundary", "plot", "write_netcdf", "canonical", "StudyError", "Grid", "make_grid"]

#: Zarr store and NetCDF file of a study in its output folder.
ZARR, NETCDF = "study.zarr", "study.nc"


def units_of(case, keys) -> dict:
    """Units of the varied keys' values: the case file's (speeds in its sweep unit)."""
    out = {}
    for key in keys:
        name = key.rpartition(".")[2]
        if key in ("sweep.start", "sweep.stop", "sweep.reference"):
            out[key] = case.sweep.unit
        elif key.startswith("rotor.damper["):  # (a rod: along it)
            out[key] = {"damping": "N s/m", "stiffness": "N/m"}.get(name, "m")
        elif name.startswith(("position_", "centre_")):
            out[key] = "m"
        elif name in _UNITS:
            out[key] = _UNITS[name]
        else:  # body keys: mass_x, stiffness_pitch, damping_roll, ... ("" for a key unknown here)
            kind, _, dof = name.partition("_")
            out[key] = _BODY_UNITS.get(kind, ("", ""))[dof in ("x", "y", "z")]
    return out


#: Units of the rotor's and the sweep's keys (docs/case-files.md).
_UNITS = {
    "blades": "1",
    "points": "1",
    "hinge_offset": "m",
    "blade_mass": "kg",
    "blade_static_moment": "kg m",
    "blade_inertia": "kg m^2",
    "hub_height": "m",
    "hub_x": "m",
    "hub_y": "m",
    "mass": "kg",
    "lag_stiffness": "N m/rad",
    "lag_damping": "N m s/rad",
    "flap_stiffness": "N m/rad",
    "flap_damping": "N m s/rad",
}
#: Units of the body's keys: (rotation, translation).
_BODY_UNITS = {
    "mass": ("kg", "kg"),
    "inertia": ("kg m^2", "kg m^2"),
    "stiffness": ("N m/rad", "N/m"),
    "damping": ("N m s/rad", "N s/m"),
}


def study(case, vary: dict, failures: str | None = None, client=None, out=None, progress=None) -> xr.Dataset:
    """Stability measures of ``case`` at every point of a grid of its keys.

    Parameters
    ----------
    case : Case
        With its text (a case file or a shipped case).
    vary : dict
        Dotted key -> ``"START:STOP:COUNT[:log]"`` or a sequence of values,
        in the case's units (``{"rotor.lag_damping": "0:8000:9",
        "body.damping_x": [2e4, 5e4]}``); one dimension each, in order.
    failures : "single" or None
        Add a dimension ``failure``: "none" and one entry per blade whose lag
        damper is put out of action ("blade k"), and per working damper rod
        ("<kind> rod k": the rod starting at blade k, without damping).
    client : dask.distributed.Client, optional
        Compute on that cluster; None: in this process.
    out : path, optional
        Folder for ``study.zarr`` (written chunk by chunk; a study started
        there before with the same case and grid resumes) and ``study.nc``.
    progress : callable, optional
        ``progress(done, total)`` in grid points.

    Returns
    -------
    xarray.Dataset
        One dimension per varied key (and ``failure``), coordinates in the
        case's units; variables ``max_real_part`` [1/s], ``min_damping_ratio``
        [-], ``unstable_width`` [rad/s], ``first_unstable_speed`` [rad/s],
        ``stable`` and ``error`` (why a point has no measures); attributes
        ``case_text`` and ``groundres_version``.

    Raises
    ------
    StudyError
        A key that is no number key of a case, a bad range or count, a store
        made for another case or grid.
    """
    grid = make_grid(case, vary, failures)
    fresh = template(grid, case, units_of(case, grid.keys))
    data, source = raw(case), case.source
    if out is None:
        values = compute(data, source, grid, client=client, progress=progress)
        ds = fresh.drop_vars(DONE)
        for name in (*MEASURES, ERROR):
            ds[name].values[...] = values[name].reshape(grid.shape)
        return ds
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    compute(data, source, grid, out / ZARR, fresh, client=client, progress=progress)
    ds = load(out / ZARR)
    write_netcdf(ds, out / NETCDF)
    return ds


def worst_over_failures(ds: xr.Dataset) -> xr.Dataset:
    """The study with the failure dimension reduced to its worst entry at each point."""
    if FAILURE not in ds.dims:
        return ds
    return xr.Dataset(
        {
            "max_real_part": ds.max_real_part.max(FAILURE),
            "min_damping_ratio": ds.min_damping_ratio.min(FAILURE),
            "unstable_width": ds.unstable_width.max(FAILURE),
            "first_unstable_speed": ds.first_unstable_speed.min(FAILURE),
            "stable": ds.stable.all(FAILURE),
        },
        attrs=ds.attrs,
    )


def design_point(case, grid: Grid) -> dict:
    """The case's own value of each varied key (where the case file gives it)."""
    from .grid import _tables, entry_of

    data, out = raw(case), {}
    for key in grid.keys:
        entry = entry_of(key)
        if entry and entry[0] == "rotor.blade":
            table = next((b for b in data["rotor"].get("blade", []) if b.get("index") == entry[1]), {})
            value = table.get(entry[2], data["rotor"].get(entry[2]))
        elif entry:
            value = _tables(data, entry[0])[entry[1] - 1].get(entry[2])
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
    from ..assess.deutsch import deutsch
    from ..errors import CaseError
    from .grid import varied_case

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

    design, deutsch = design_point(case, grid), deutsch_curve(case, grid)
    if "boundary_key" in ds.attrs:
        title = f"Stability boundary along {ds.attrs['boundary_key']}: {case.title}"
        return boundary_map(ds, list(grid.keys), design, deutsch, title)
    return study_map(ds, design, deutsch, f"Study: {case.title}")


#: Lines of a boundary search per task (each about ten sweeps).
LINES_PER_TASK = 2


def boundary(
    case, vary: dict, key: str, failures: str | None = None, client=None, progress=None
) -> xr.Dataset:
    """The stability boundary along ``key`` for every value of the other varied keys.

    ``vary`` as for :func:`study`; ``key`` one of its keys, whose range is
    searched by root finding (:mod:`groundres.studies.study.boundary`) instead of
    sampled. Returns a data set over the other keys (and ``failure``):
    ``boundary`` [the key's units], ``stable_at_start``, ``evaluations`` and
    ``error``.
    """
    from . import search

    grid = make_grid(case, vary, failures)
    key = canonical(key)
    if key not in grid.keys:
        raise StudyError(f"--boundary {key}: must be one of the varied keys ({', '.join(grid.keys)})")
    i = grid.keys.index(key)
    along = grid.values[i]
    if len(along) < 2 or along[0] == along[-1]:
        raise StudyError(
            f"--boundary {key}: its range needs two different ends (START:STOP:COUNT, COUNT >= 2)"
        )
    others = Grid(grid.keys[:i] + grid.keys[i + 1 :], grid.values[:i] + grid.values[i + 1 :], grid.failures)
    span = (float(along[0]), float(along[-1]), float(np.abs(np.diff(along)).min()))
    flats = np.arange(others.size)
    per = max(LINES_PER_TASK, len(others.failures))  # (a line's failures in one task: see search.lines)
    batches = [
        (raw(case), case.source, others, key, span, flats[j : j + per]) for j in range(0, others.size, per)
    ]
    found = [
        r
        for part in map_batches(
            search.lines, batches, client, progress, lambda i, r: len(r), (0, others.size)
        )
        for r in part
    ]
    units = units_of(case, grid.keys)
    coords = {k: (k, np.asarray(v, float), {"units": units[k]}) for k, v in zip(others.keys, others.values)}
    if others.failures:
        coords[FAILURE] = (FAILURE, np.array(others.failures, dtype=object))
    data = {}
    for name, (dtype, long_name) in search.VARIABLES.items():
        attrs = {
            "long_name": long_name.replace("the key", key),
            "units": units[key] if name == "boundary" else "1",
        }
        data[name] = (
            others.dims,
            np.array([r[name] for r in found], dtype=dtype).reshape(others.shape),
            attrs,
        )
    data[ERROR] = (others.dims, np.array([r["error"] for r in found], dtype=object).reshape(others.shape))
    attrs = {
        "title": f"groundres stability boundary of {case.title}",
        "boundary_key": key,
        "boundary_range": [span[0], span[1]],
        "case_text": case.text,
        "groundres_version": __version__,
    }
    return xr.Dataset(data, coords=coords, attrs=attrs)
