"""Result files and output folders.

Each file is written atomically (a temporary file renamed into place); the
folder they go into is put in place whole by :mod:`groundres.results.folders`. The
result files:

* ``summary.json``: see docs/case-files.md; strict JSON (no NaN or Infinity
  tokens: a number that is not finite is written as null, with a
  ``<name>_reason`` beside it);
* ``modes.csv``: one row per (speed, mode), the unit in each header:
  ``speed [rad/s]``, ``mode``, ``frequency [rad/s]`` (in the result's frame),
  ``real_part [1/s]``, ``damping_ratio [-]``;
* ``modes.nc``: the same as a NetCDF-4 data set (CF conventions) with dims
  ``speed``, ``mode`` (see :mod:`groundres.results.dataset`);
* ``simulation.csv``: a time history, one row per instant;
* ``differences.csv`` and ``differences.json``: how the entries of a comparison differ.
"""

from __future__ import annotations

import contextlib
import csv
import io as _io
import json
import os
import tempfile
from pathlib import Path

import numpy as np


def current_umask() -> int:
    """The process's umask (read without changing it for longer than the call)."""
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _file_mode() -> int:
    """Permissions of a newly created file under the current umask."""
    return 0o666 & ~current_umask()


@contextlib.contextmanager
def atomic_path(path: str | Path):
    """Yield a temporary path beside ``path``; rename it into place on success."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".part" + path.suffix)
    os.close(fd)
    try:
        os.chmod(tmp, 0o600)  # (writable by its writer whatever the umask; its mode is set below)
        yield Path(tmp)
        os.chmod(tmp, _file_mode())
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def write_text(path: str | Path, text: str) -> None:
    """Write text atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")


def write_bytes(path: str | Path, data: bytes) -> None:
    """Write bytes atomically (a picture made in memory, a case text as read)."""
    with atomic_path(path) as tmp:
        tmp.write_bytes(data)


def strict(obj):
    """``obj`` with every NaN or infinity replaced by None.

    In a dict, a replaced value gets a ``<key>_reason`` beside it (unless one
    is there already) saying which value it was.
    """
    if isinstance(obj, dict):
        out = {}
        for key, value in obj.items():
            clean = strict(value)
            out[key] = clean
            if clean is None and _not_finite(value) and f"{key}_reason" not in obj:
                out[f"{key}_reason"] = f"not a finite number ({float(value)!r})"
        return out
    if isinstance(obj, (list, tuple)):
        return [strict(v) for v in obj]
    if _not_finite(obj):
        return None
    if isinstance(obj, np.generic):
        return obj.item()
    return obj


def _not_finite(value) -> bool:
    return isinstance(value, (float, np.floating)) and not np.isfinite(value)


def json_text(obj) -> str:
    """Strict JSON (RFC 8259: no NaN or Infinity tokens), indented, see :func:`strict`."""
    return json.dumps(strict(obj), indent=2, allow_nan=False) + "\n"


def write_json(path: str | Path, obj) -> None:
    """Write ``obj`` as strict JSON atomically."""
    write_text(path, json_text(obj))


def csv_text(header, rows) -> str:
    """CSV text; floats with ten significant digits (-0 written as 0)."""
    buf = _io.StringIO()
    out = csv.writer(buf, lineterminator="\n")
    out.writerow(header)
    for row in rows:
        out.writerow([f"{float(v) + 0.0:.10g}" if isinstance(v, (float, np.floating)) else v for v in row])
    return buf.getvalue()


def write_csv(path: str | Path, header, rows) -> None:
    """Write rows as CSV atomically."""
    write_text(path, csv_text(header, rows))


#: modes.csv columns, each numeric one with its unit.
MODES_CSV_HEADER = ["speed [rad/s]", "mode", "frequency [rad/s]", "real_part [1/s]", "damping_ratio [-]"]


def write_modes_csv(result, path: str | Path) -> None:
    """modes.csv: one row per (speed, mode)."""
    freq, real, ratio = result.frequency, result.real_part, result.damping_ratio
    rows = (
        [w, label, freq[i, j], real[i, j], ratio[i, j]]
        for i, w in enumerate(result.rotor_speed)
        for j, label in enumerate(result.labels)
    )
    write_csv(path, MODES_CSV_HEADER, rows)


def write_simulation_csv(simulation, path: str | Path) -> None:
    """simulation.csv: ``time [s]`` and each coordinate's displacement, its unit in the header
    (:meth:`groundres.results.simulation.Simulation.column_names`)."""
    rows = np.column_stack([simulation.time, simulation.displacement])
    write_csv(path, ["time [s]", *simulation.column_names()], rows)


def write_differences(comparison, folder: str | Path, rows=None) -> None:
    """differences.csv and differences.json of a comparison
    (:meth:`groundres.results.comparison.Comparison.differences_table` and ``differences_record``)."""
    rows = comparison.differences() if rows is None else rows
    write_csv(Path(folder) / "differences.csv", *comparison.differences_table(rows))
    write_json(Path(folder) / "differences.json", comparison.differences_record(rows))


def write_netcdf(result, path: str | Path) -> None:
    """Write ``result.dataset()`` as NetCDF-4 (readable by xarray.open_dataset): modes.nc of a
    sweep, limit_cycles.nc of a limit-cycle analysis.

    netCDF4 is used directly rather than through xarray: the file is the same
    and the command line starts half a second faster.
    """
    import netCDF4

    coords, variables, attrs = result.dataset()
    every = {**coords, **variables}
    sizes = {}
    for dims, values, _ in every.values():
        sizes.update(zip(dims, np.shape(values)))
    with atomic_path(path) as tmp:
        with netCDF4.Dataset(tmp, "w", format="NETCDF4") as nc:
            for name, size in sizes.items():
                nc.createDimension(name, size)  # size 0 (no unstable range): unlimited
            for name, (dims, values, var_attrs) in every.items():
                dtype = str if values.dtype == object else values.dtype
                var = nc.createVariable(name, dtype, dims)
                if dtype is str:
                    for i, v in enumerate(values):
                        var[i] = v
                else:
                    var[:] = values
                var.setncatts(var_attrs)
            nc.setncatts(attrs)


def write_figure(fig, path: str | Path, dpi: int = 130) -> None:
    """Save a matplotlib figure atomically (format from the file suffix)."""
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi, format=path.suffix.lstrip(".") or "png")
