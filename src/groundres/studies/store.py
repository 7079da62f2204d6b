"""A study's results on disk: a Zarr store written chunk by chunk, so that nothing is lost.

The store holds every measure (:data:`groundres.studies.measures.MEASURES`),
the reason a point failed (``error``) and whether each point is done
(``done``), all chunked as the study's tasks are. A finished chunk's values
are written first and its ``done`` flags after them: a chunk cut short by an
interruption is computed again on resume, and one whose flags are set is
complete. The store's attributes keep the case text, the grid and their
hash (:meth:`groundres.studies.grid.Grid.fingerprint`); a study resumed into
a store made for another case or grid is refused, saying what differs.
"""

from __future__ import annotations

import itertools
import json
import math
import warnings
from pathlib import Path

import numpy as np
import xarray as xr

from .._version import __version__
from ..errors import StudyError
from .grid import FAILURE, Grid
from .measures import ERROR, MEASURES, empty

DONE = "done"
#: Chunks are written into the store without touching its metadata, which the store holds
#: consolidated from the start (a study's arrays never change shape): ``xarray.open_zarr``
#: opens it at once and without a warning (:func:`_create`, :func:`_open`).
_ZARR = {"consolidated": False}


def _create(fresh: xr.Dataset, path: Path, encoding: dict) -> None:
    """Write the empty store with consolidated metadata (an extension of Zarr v3 that
    zarr-python and xarray read; zarr warns that the specification lacks it)."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="Consolidated metadata", category=UserWarning)
        fresh.to_zarr(path, mode="w", encoding=encoding, consolidated=True)


def _open(path: Path) -> xr.Dataset:
    """The store, by its consolidated metadata (a store written before them: without)."""
    try:
        return xr.open_zarr(path, consolidated=True)
    except (KeyError, ValueError, FileNotFoundError):
        return xr.open_zarr(path, consolidated=False)


def chunk_shape(shape: tuple, target: int) -> tuple:
    """A chunk of about ``target`` points: the trailing dimensions kept whole first."""
    chunk = list(shape)
    for d in range(len(shape)):
        while math.prod(chunk) > target and chunk[d] > 1:
            chunk[d] = -(-chunk[d] // 2)
    return tuple(chunk)


def chunks(shape: tuple, chunk: tuple) -> list[tuple]:
    """The chunks of a grid, as tuples of slices (C order)."""
    starts = [range(0, n, c) for n, c in zip(shape, chunk)]
    return [
        tuple(slice(s, min(s + c, n)) for s, c, n in zip(corner, chunk, shape))
        for corner in itertools.product(*starts)
    ]


def flat_indices(shape: tuple, where: tuple) -> np.ndarray:
    """Flat (C-order) indices of the points of a chunk, in C order within it."""
    return np.ravel_multi_index(
        np.meshgrid(*[np.arange(s.start, s.stop) for s in where], indexing="ij"), shape
    ).ravel()


def template(grid: Grid, case, units: dict) -> xr.Dataset:
    """The study's data set with nothing computed (NaN, False, no error, nothing done)."""
    coords = {
        k: (k, np.asarray(v, float), {"units": units.get(k, "")}) for k, v in zip(grid.keys, grid.values)
    }
    if grid.failures:
        coords[FAILURE] = (
            FAILURE,
            np.array(grid.failures, dtype=object),
            {"long_name": "lag damper out of action"},
        )
    values = empty(grid.size)
    data = {}
    for name, (_, unit, long_name) in MEASURES.items():
        data[name] = (grid.dims, values[name].reshape(grid.shape), {"units": unit, "long_name": long_name})
    data[ERROR] = (
        grid.dims,
        values[ERROR].reshape(grid.shape),
        {"long_name": "why the point has no measures"},
    )
    data[DONE] = (grid.dims, np.zeros(grid.shape, bool), {"long_name": "point computed"})
    attrs = {
        "title": f"groundres study of {case.title}",
        "case_text": case.text,
        "grid": json.dumps({"keys": list(grid.keys), "failures": list(grid.failures)}),
        "fingerprint": grid.fingerprint(case.text),
        "groundres_version": __version__,
    }
    if case.sweep.required_damping_ratio is not None:  # (the margin's reference: drawn on the map)
        attrs["required_damping_ratio"] = float(case.sweep.required_damping_ratio)
    return xr.Dataset(data, coords=coords, attrs=attrs)


def open_store(path: Path, fresh: xr.Dataset, chunk: tuple) -> np.ndarray:
    """Create the store (or open the one there for a resume); the points already done."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise StudyError(f"{path}: exists and is not a study store; give another --out or remove it")
    if not (path / "zarr.json").exists():
        if path.exists() and any(path.iterdir()):
            raise StudyError(f"{path}: exists and is not a study store; give another --out or remove it")
        encoding = {name: {"chunks": chunk} for name in fresh.data_vars}
        _create(fresh, path, encoding)
        return np.zeros(fresh[DONE].shape, bool)
    try:
        stored = _open(path)
    except Exception as err:  # noqa: BLE001 - any unreadable store is the user's to remove
        raise StudyError(f"{path}: not a readable study store ({type(err).__name__}: {err})") from None
    if stored.attrs.get("fingerprint") != fresh.attrs["fingerprint"]:
        raise StudyError(f"{path}: made for {_difference(stored, fresh)}; give another --out or remove it")
    if set(stored.data_vars) != set(fresh.data_vars):  # (an earlier groundres kept other measures)
        raise StudyError(
            f"{path}: its measures ({', '.join(sorted(stored.data_vars))}) are not this groundres' "
            f"({', '.join(sorted(fresh.data_vars))}); give another --out or remove it"
        )
    return np.asarray(stored[DONE].values, bool)


def finished(path: Path, fresh: xr.Dataset) -> bool:
    """Whether the store at ``path`` holds this study (``fresh``: its template) complete: then it
    answers without computing, and so without a cluster."""
    return done_points(path, fresh) == fresh[DONE].size


def done_points(path: Path, fresh: xr.Dataset) -> int:
    """Points of this study (``fresh``: its template) the store at ``path`` holds computed (0
    where there is no store, or one of another study: :func:`open_store` says why)."""
    if not (Path(path) / "zarr.json").exists():
        return 0
    try:
        with _open(Path(path)) as stored:
            same = stored.attrs.get("fingerprint") == fresh.attrs["fingerprint"]
            if not (same and set(stored.data_vars) == set(fresh.data_vars)):
                return 0
            return int(np.count_nonzero(stored[DONE].values))
    except Exception:  # noqa: BLE001 - not readable: nothing done (open_store says why)
        return 0


def _difference(stored: xr.Dataset, fresh: xr.Dataset) -> str:
    """What a store was made for that this study is not, in words."""
    if stored.attrs.get("groundres_version") != fresh.attrs["groundres_version"]:
        return (
            f"groundres {stored.attrs.get('groundres_version')} (this is {fresh.attrs['groundres_version']})"
        )
    if stored.attrs.get("case_text") != fresh.attrs["case_text"]:
        return "another case (its case text differs)"
    if stored.attrs.get("grid") != fresh.attrs["grid"]:
        return f"another grid ({stored.attrs.get('grid')} there, {fresh.attrs['grid']} here)"
    for key in fresh.coords:
        if key in stored.coords and not np.array_equal(np.asarray(stored[key]), np.asarray(fresh[key])):
            return f"another grid (the values of {key} differ)"
    return "another grid (the values of a varied key differ)"


def write_chunk(path: Path, grid: Grid, where: tuple, values: dict) -> None:
    """Write one finished chunk: its values, then its ``done`` flags."""
    shape = tuple(s.stop - s.start for s in where)
    region = dict(zip(grid.dims, where))
    part = {name: (grid.dims, np.asarray(values[name]).reshape(shape)) for name in (*MEASURES, ERROR)}
    xr.Dataset(part).to_zarr(path, region=region, **_ZARR)
    xr.Dataset({DONE: (grid.dims, np.ones(shape, bool))}).to_zarr(path, region=region, **_ZARR)


def load(path: Path) -> xr.Dataset:
    """The whole study from its store, in memory (without the ``done`` flags)."""
    with _open(path) as ds:
        out = ds.load()
    return out.drop_vars(DONE)


def write_netcdf(ds: xr.Dataset, path: Path) -> None:
    """The study as NetCDF, whole or not at all (written beside, then renamed)."""
    from ..results.files import atomic_path

    with atomic_path(path) as partial:  # (a name of its own: two studies at once never share it)
        ds.to_netcdf(partial)
