"""`groundres study`: stability measures over a grid of case keys, on Dask."""

from __future__ import annotations

import os
import stat
import time
from pathlib import Path

import click

from ..errors import shown
from .common import FIGURE_FORMATS, FORMAT, fail_user, invocation, load, make_console, plain

#: The map in each format --format offers.
MAP_FILES = {f"map.{fmt}" for fmt in FIGURE_FORMATS}
#: What a study folder may hold: a folder with anything else is refused.
#: The lock a study holds on its folder while it writes there (two at once would mix).
LOCK = ".groundres-study.lock"
STUDY_FILES = {"study.zarr", "study.nc", "boundary.nc", *MAP_FILES, "case.toml", "provenance.json", LOCK}


def parse_vary(items) -> dict:
    """``KEY=SPEC`` options into {key: spec}, naming the option that is wrong."""
    out = {}
    for item in items:
        key, eq, spec = item.partition("=")
        key, spec = key.strip(), spec.strip()
        if not eq or not key or not spec:
            fail_user(
                f"--vary {shown(item)}: must be KEY=START:STOP:COUNT[:log], e.g. rotor.lag_damping=0:8000:17"
            )
        if key in out:
            fail_user(f"--vary {key}: given twice")
        out[key] = spec
    return out


def check_study_folder(out: Path, case_text: str, boundary: bool) -> None:
    """Refuse, before any cluster starts, a folder a study cannot write (a name too long, a parent
    that is a file, a folder that is not writable, an unreadable file in it) or one that holds
    files a study did not write, or another study's (nothing is mixed in)."""
    from ..errors import CaseError, OutputFolderError, shown_path
    from ..model.casefile import MAX_CASE_BYTES, read_file
    from ..results.folders import check_folder

    label = f"--out {shown_path(out)}"
    try:
        exists = check_folder(out, "--out", replace=False)
    except OutputFolderError as err:
        fail_user(str(err))
    if not exists:
        return
    copy = out / "case.toml"
    if os.path.lexists(copy):
        try:
            text = read_file(copy, f"{label}: its case.toml", MAX_CASE_BYTES).decode(
                "utf-8", errors="replace"
            )
        except CaseError as err:
            fail_user(f"{err}; give another folder")
        if text != case_text:
            fail_user(f"{label}: holds a study of another case; give another folder")
    other = "study.zarr" if boundary else "boundary.nc"
    if os.path.lexists(out / other):
        kind = "grid study" if boundary else "boundary search"
        fail_user(f"{label}: holds a {kind}; give another folder for this one")
    for name in ("study.nc", *sorted(MAP_FILES), "boundary.nc", "case.toml", "provenance.json"):
        if (out / name).is_dir():
            fail_user(f"{label}: {name} there is a folder; give another folder")
    strangers = sorted(
        p.name
        for p in out.iterdir()
        if p.name not in STUDY_FILES
        and not p.name.endswith(".partial")
        and not p.name.startswith(".study.nc.")
    )
    if strangers:
        fail_user(f"{label}: holds files no study wrote ({', '.join(strangers[:3])}); give another folder")
    _check_store(out / "study.zarr", label)


def _check_store(store: Path, label: str) -> None:
    """Refuse a study's store that a resumed study could not read and write: not a folder, or a
    folder of its top two levels (the store and its arrays) not readable, writable and searchable."""
    from ..model.casefile import file_type

    if not os.path.lexists(store):
        return
    folders = [store]
    if store.is_dir() and os.access(store, os.R_OK | os.X_OK):
        folders += sorted(p for p in store.iterdir() if p.is_dir() and not p.is_symlink())
    for folder in folders:
        try:
            mode = os.stat(folder).st_mode
        except OSError as err:
            fail_user(f"{label}: {folder.name} cannot be read ({err.strerror or err}); give another folder")
        if not stat.S_ISDIR(mode):
            fail_user(f"{label}: {folder.name} there is {file_type(mode)}, not a folder (a study's store)")
        if not os.access(folder, os.R_OK | os.W_OK | os.X_OK):
            where = "study.zarr" if folder == store else f"study.zarr/{folder.name}"
            fail_user(
                f"{label}: {where} there is not writable (a resumed study writes into it); make it "
                "writable or give another folder"
            )


@click.command("study")
@click.argument("case")
@click.option(
    "--vary",
    "vary",
    multiple=True,
    required=True,
    metavar="KEY=START:STOP:COUNT[:log]",
    help="A case key to vary (dotted, e.g. rotor.lag_damping, body.damping_x, "
    "rotor.blade[2].lag_damping, sweep.stop), in the case's units; repeat for more keys.",
)
@click.option(
    "--failures",
    type=click.Choice(["single"]),
    default=None,
    help="Add a dimension 'failure': all dampers working, and each lag damper out of action in turn.",
)
@click.option(
    "--out",
    "out",
    required=True,
    type=click.Path(file_okay=False),
    help="Study folder: study.zarr (kept chunk by chunk: the same command resumes an interrupted "
    "study), study.nc and map.<format>; refused before any work if it cannot be written.",
)
@click.option(
    "--workers",
    type=click.IntRange(1, 512),
    default=None,
    help="Worker processes of the local Dask cluster [default: the cores of this machine].",
)
@click.option(
    "--scheduler",
    default=None,
    metavar="ADDRESS",
    help="Run on an existing Dask cluster (e.g. tcp://host:8786); its scheduler must answer as "
    "one within 10 s.",
)
@click.option(
    "--dashboard",
    is_flag=True,
    help="Serve Dask's dashboard of the local cluster on 127.0.0.1 (a free port) and print its "
    "address (needs bokeh). Without it the cluster serves no web page; it listens on 127.0.0.1 only.",
)
@click.option(
    "--boundary",
    default=None,
    metavar="KEY",
    help="Instead of the grid: find where the stability changes along this varied key, by root "
    "finding, for every value of the others (boundary.nc, map.<format>).",
)
@click.option(
    "--points",
    type=click.IntRange(2, None),
    default=None,
    metavar="N",
    help="Speeds of the sweep at every grid point [default: the case's [sweep] points]. The "
    "measures are refined between speeds, so fewer cost less and change them little "
    "(docs/studies.md).",
)
@click.option(
    "--max-hours",
    type=click.FloatRange(0, None, min_open=True),
    default=4.0,
    show_default=True,
    metavar="H",
    help="Refuse a study estimated to take longer than H hours of wall-clock time (one sweep "
    "timed here, times the sweeps to make, shared between the workers).",
)
@FORMAT
def command(case, vary, failures, out, workers, scheduler, dashboard, boundary, points, max_hours, fmt):
    """Stability of CASE over a grid of its keys (and single lag-damper failures).

    Each grid point is a full speed sweep of the case. Writes study.zarr and
    study.nc (measures per point: growth_margin, least_damping_ratio,
    least_damping_ratio_run_up, margin, max_real_part, min_damping_ratio,
    unstable_width, first_unstable_speed, stable, and with a nonlinear lag damper law
    smallest_threshold (0 where some speed grows from any disturbance; an upper bound where a
    threshold lies below the amplitudes searched) and largest_stable_cycle with their speeds,
    unbounded_speed_count, below_searched_speed_count and stable_below_searched_speed_count;
    error) and map.<format>
    (png unless --format says) into --out. Runs on a local Dask cluster unless --scheduler names one.
    """
    from ..results import files, folders
    from ..studies import figure, store, study
    from ..studies.grid import canonical, make_grid, with_points

    console = make_console()
    the_case = with_points(load(case), points)
    grid = make_grid(the_case, parse_vary(vary), failures)
    if not out.strip():
        fail_user(f"--out {out!r}: empty; give a folder, e.g. --out study")
    out_dir = Path(out)
    if boundary is not None and canonical(boundary) not in grid.keys:
        fail_user(f"--boundary {shown(boundary)}: must be one of the --vary keys ({', '.join(grid.keys)})")
    boundary = study.boundary_key(grid, boundary) if boundary is not None else None  # (before any work)
    if scheduler is not None and workers is not None:
        fail_user("--workers: only for the local cluster; an existing cluster (--scheduler) has its own")
    if workers is not None and workers > most_workers():
        fail_user(
            f"--workers {workers}: at most {most_workers()} on this machine ({os.cpu_count()} cores; each "
            "worker is a process computing on one core, so more only share them); use --scheduler for more"
        )
    if scheduler is not None and dashboard:
        fail_user("--dashboard: only for the local cluster; an existing cluster (--scheduler) has its own")
    check_study_folder(out_dir, the_case.text, boundary is not None)
    values = dict(zip(grid.keys, grid.values))
    left = grid.size if boundary is not None else study.remaining(the_case, values, failures, out_dir)
    client = None  # (finished: no cluster to start)
    if left:
        client = _started(the_case, grid, left, boundary, scheduler, workers, dashboard, max_hours)
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        _close(client)
        fail_user(f"--out {str(out_dir)!r}: cannot be made ({err.strerror or err})")
    _hold(out_dir, client)  # (held until the command ends)
    if client is not None and dashboard:
        console.print(f"Dask dashboard: {client.dashboard_link}", markup=False)
    started = time.perf_counter()
    memory = []
    try:
        with _Progress(console, "Boundary lines" if boundary else "Grid points") as progress:
            if boundary is None:
                ds = study.study(the_case, values, failures, client, out_dir, progress)
            else:
                ds = study.boundary(the_case, values, boundary, failures, client, progress)
        memory = _memory(client)
    finally:
        _close(client)
    out_dir.mkdir(parents=True, exist_ok=True)
    if boundary is not None:
        store.write_netcdf(ds, out_dir / "boundary.nc")
    files.write_figure(figure.plot(ds, the_case, grid), out_dir / f"map.{fmt}")
    for stale in MAP_FILES - {f"map.{fmt}"}:  # (a map of an earlier run in another format: not this study's)
        (out_dir / stale).unlink(missing_ok=True)
    folders.write_provenance(out_dir, the_case, command="study", **invocation())
    seconds = time.perf_counter() - started
    if boundary is None:
        _report(console, ds, grid, out_dir, seconds, progress.first or 0, fmt)
    else:
        _report_boundary(console, ds, grid, out_dir, seconds, fmt)
    if memory:
        console.print(_memory_text(memory))


def _hold(out_dir: Path, client):
    """An exclusive lock on the study's folder (its open file), or exit 2 where another study
    writes there now: two studies into one folder at once would mix their files."""
    try:
        import fcntl
    except ImportError:  # (no flock: Windows)
        return None
    try:
        fd = os.open(out_dir / LOCK, os.O_RDWR | os.O_CREAT | os.O_NONBLOCK, 0o600)
    except OSError as err:
        _close(client)
        fail_user(f"--out {shown(str(out_dir))}: its lock {LOCK} cannot be opened ({err.strerror or err})")
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        os.close(fd)
        _close(client)
        fail_user(
            f"--out {shown(str(out_dir))}: another study is writing there now; wait for it to end "
            "(this one then resumes from its store) or choose another folder"
        )
    click.get_current_context().call_on_close(lambda: os.close(fd))  # (released as the command ends)
    return fd


def most_workers() -> int:
    """The most local workers a study may start: four per core of this machine (at least 2)."""
    return max(2, 4 * (os.cpu_count() or 1))


def _started(the_case, grid, left, boundary, scheduler, workers, dashboard, max_hours):
    """The study's client, after its cost is estimated and found within ``max_hours`` (the local
    cluster's, before it starts; an existing cluster's, on its threads, once reached)."""
    import dataclasses

    from ..solve.parallel import CORES
    from ..studies import cost

    estimated = cost.estimate(the_case, grid, left, workers or CORES, boundary)
    if scheduler is None:
        cost.check(estimated, max_hours)
    client = _client(scheduler, workers or CORES, dashboard)
    if scheduler is not None:
        threads = sum(w.get("nthreads", 1) for w in client.scheduler_info().get("workers", {}).values())
        estimated = dataclasses.replace(estimated, workers=max(threads, 1))
        try:
            cost.check(estimated, max_hours)
        except Exception:
            _close(client)
            raise
    make_console().print(f"Estimated: {estimated.text()}.")
    return client


def _client(scheduler, workers, dashboard=False):
    import os

    from ..studies import run

    if scheduler is None:
        missing = run.dashboard_missing() if dashboard else None
        if missing:
            fail_user(f"--dashboard: {missing}")
        return run.local_client(workers, dashboard, quiet=not os.environ.get("GROUNDRES_DEBUG"))
    try:
        return run.remote_client(scheduler)
    except (OSError, TimeoutError, ValueError) as err:  # (each says why, in words)
        fail_user(f"--scheduler {shown(scheduler)}: {err}")


def _memory(client) -> list:
    """(peak, limit) of each worker [bytes], or nothing where there is no cluster or it cannot say."""
    if client is None:
        return []
    from ..studies.run import memory_of

    try:
        return memory_of(client)
    except Exception:  # noqa: BLE001 - a report only: a cluster that cannot answer says nothing
        return []


def _memory_text(memory: list) -> str:
    gib = 2**30
    peaks = ", ".join(f"{peak / gib:.2g}" for peak, _ in memory)
    limits = {limit for _, limit in memory}
    limit = (
        f"limit {limits.pop() / gib:.3g} GiB each"
        if len(limits) == 1 and 0 not in limits
        else "limits set by the cluster"
    )
    return f"Workers: {len(memory)} ({limit}); peak memory {peaks} GiB."


def _close(client):
    from ..studies.run import close

    close(client)  # (None: a finished study, for which none was started)


class _Progress:
    """Points done, rate and time left, on a terminal."""

    def __init__(self, console, what):
        self.console, self.what, self.bar, self.task = console, what, None, None
        self.first = None  # (points found done in the store when the study started)

    def __enter__(self):
        if self.console.is_terminal:
            from rich.progress import (
                BarColumn,
                MofNCompleteColumn,
                Progress,
                TextColumn,
                TimeElapsedColumn,
                TimeRemainingColumn,
            )

            self.bar = Progress(
                TextColumn(self.what),
                BarColumn(),
                MofNCompleteColumn(),
                TextColumn("{task.fields[rate]}"),
                TimeElapsedColumn(),
                TextColumn("left"),
                TimeRemainingColumn(),
                console=self.console,
                transient=True,
            )
            self.bar.start()
        self.started = time.perf_counter()
        return self

    def __call__(self, done, total):
        if self.first is None:
            self.first = done
        if self.bar is None:
            return
        if self.task is None:
            self.task = self.bar.add_task("study", total=total, rate="")
        elapsed = time.perf_counter() - self.started
        rate = f"{(done - self.first) / elapsed:.2f}/s" if elapsed > 0 and done > self.first else ""
        self.bar.update(self.task, completed=done, total=total, rate=rate)

    def __exit__(self, *exc):
        if self.bar is not None:
            self.bar.stop()


def _report(console, ds, grid, out_dir, seconds, reused=0, fmt="png"):
    import numpy as np

    failed = int((ds.error.values != "").sum())
    stable = int(ds.stable.values.sum())
    console.print(
        f"Study of {grid.size} grid points ({' x '.join(map(str, grid.shape))}: {', '.join(grid.dims)}) "
        f"in {seconds:.1f} s: {stable} stable, {grid.size - stable - failed} unstable, {failed} failed."
    )
    if reused:
        console.print(f"{reused} of them were found done in the store (an earlier run of this study).")
    if failed:
        first = ds.error.values.ravel()[np.flatnonzero(ds.error.values.ravel() != "")[0]]
        console.print(f"A failed point's reason: {first}", markup=False)
    console.print(f"Wrote {plain(str(out_dir))}/study.zarr, study.nc, map.{fmt}, case.toml, provenance.json")


def _report_boundary(console, ds, grid, out_dir, seconds, fmt="png"):
    import numpy as np

    key = ds.attrs["boundary_key"]
    lines = ds.boundary.size
    found = int(np.isfinite(ds.boundary.values).sum())
    failed = int((ds.error.values != "").sum())
    sweeps = int(ds.evaluations.values.sum())
    console.print(
        f"Stability boundary along {key}: {lines} line(s) in {seconds:.1f} s, {sweeps} speed sweeps "
        f"(a grid would take {grid.size}); boundary found on {found}, none in the range on "
        f"{lines - found - failed}, {failed} failed."
    )
    console.print(f"Wrote {plain(str(out_dir))}/boundary.nc, map.{fmt}, case.toml, provenance.json")
