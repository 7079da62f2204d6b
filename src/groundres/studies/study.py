"""A design study: stability measures of a case at every point of a grid of its keys.

A designer's question is rarely one sweep: how much lag and landing-gear
damping does the helicopter need over its rotor-speed range, and what margin
is left when any one damper fails? :func:`study` answers it with one full
speed sweep per grid point; :func:`boundary` finds, instead of sampling, where
the stability changes along one key for every value of the others. The grid
is :mod:`groundres.studies.grid`'s, the computing (here or on a Dask cluster)
:mod:`groundres.studies.run`'s, the store that lets an interrupted study
resume :mod:`groundres.studies.store`'s, and the map :mod:`groundres.studies.figure`'s.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from .._version import __version__
from ..errors import StudyError
from ..model.units import key_unit
from .grid import FAILURE, Grid, canonical, make_grid, raw, with_points
from .measures import ERROR, MEASURES
from .run import compute, map_batches
from .store import DONE, done_points, load, template, write_netcdf

#: Zarr store and NetCDF file of a study in its output folder.
ZARR, NETCDF = "study.zarr", "study.nc"


def study(
    case, vary: dict, failures: str | None = None, client=None, out=None, progress=None, points=None
) -> xr.Dataset:
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
    points : int, optional
        Speeds of the sweep at every grid point instead of the case's ``[sweep] points``
        (:func:`groundres.studies.grid.with_points`): the measures are refined between the
        sweep's speeds, so a coarser sweep changes them little and costs less (docs/studies.md).

    Returns
    -------
    xarray.Dataset
        One dimension per varied key (and ``failure``), coordinates in the
        case's units; variables ``growth_margin`` [1/s], ``least_damping_ratio``
        and ``least_damping_ratio_run_up`` [-], ``margin`` [-] (the margins:
        :mod:`groundres.assess.margins`), ``max_real_part`` [1/s],
        ``min_damping_ratio`` [-], ``unstable_width`` [rad/s], ``first_unstable_speed`` [rad/s],
        ``stable`` and ``error`` (why a point has no measures); attributes
        ``case_text`` and ``groundres_version``.

    Raises
    ------
    StudyError
        A key that is no number key of a case, a bad range or count, a store
        made for another case or grid.
    """
    case = with_points(case, points)
    grid = make_grid(case, vary, failures)
    fresh = template(grid, case, _units(case, grid.keys))
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


#: Lines of a boundary search per task (each about ten sweeps).
LINES_PER_TASK = 2


def boundary(
    case, vary: dict, key: str, failures: str | None = None, client=None, progress=None, points=None
) -> xr.Dataset:
    """The stability boundary along ``key`` for every value of the other varied keys.

    ``vary`` as for :func:`study`; ``key`` one of its keys, whose range is
    searched by root finding (:mod:`groundres.studies.search`) instead of
    sampled. Returns a data set over the other keys (and ``failure``):
    ``boundary`` [the key's units], ``stable_at_start``, ``evaluations`` and
    ``error``; ``points`` as for :func:`study`.
    """
    from . import search

    case = with_points(case, points)
    grid = make_grid(case, vary, failures)
    key = boundary_key(grid, key)
    i = grid.keys.index(key)
    along = grid.values[i]
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
    units = _units(case, grid.keys)
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


def boundary_key(grid: Grid, key: str) -> str:
    """``key`` as the grid names it, where a boundary can be searched along it (StudyError
    otherwise: not a varied key, or a range without two different ends)."""
    key = canonical(key)
    if key not in grid.keys:
        raise StudyError(f"--boundary {key}: must be one of the varied keys ({', '.join(grid.keys)})")
    along = grid.values[grid.keys.index(key)]
    if len(along) < 2 or along[0] == along[-1]:
        raise StudyError(
            f"--boundary {key}: its range needs two different ends (START:STOP:COUNT, COUNT >= 2)"
        )
    return key


def finished(case, vary: dict, failures: str | None, out, points=None) -> bool:
    """Whether the study's folder ``out`` already holds it whole (:func:`study` would compute
    nothing): a caller need start no cluster."""
    return remaining(case, vary, failures, out, points) == 0


def remaining(case, vary: dict, failures: str | None, out, points=None) -> int:
    """Grid points of the study that its folder ``out`` does not yet hold computed."""
    case = with_points(case, points)
    grid = make_grid(case, vary, failures)
    fresh = template(grid, case, _units(case, grid.keys))
    return grid.size - done_points(Path(out) / ZARR, fresh)


def _units(case, keys) -> dict:
    """Units of the varied keys' values: the case file's (speeds in its sweep unit)."""
    return {key: key_unit(key, case.sweep.unit) for key in keys}
