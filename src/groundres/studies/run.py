"""Computing a study's grid: in this process, or on a Dask cluster, chunk by chunk.

Tasks are chunks of grid points (:func:`groundres.studies.store.chunk_shape`),
each a full speed sweep per point. On a cluster every task runs on one core
(groundres' own threads and BLAS held to one: the workers share the cores);
results come back as tasks finish and are written to the store at once, so
an interrupted study loses at most the chunks in flight. Here too: the
clusters, the local one started (on this machine only) and an existing one
connected to (:mod:`groundres.studies.handshake` first). Only studies/ knows Dask.
"""

from __future__ import annotations

import contextlib
import os
import signal
import uuid
from pathlib import Path

import numpy as np

from ..solve import parallel
from .grid import NO_FAILURE, Grid, varied_case
from .measures import ERROR, MEASURES, POINT_ERRORS, empty, failed, of_case
from .store import chunk_shape, chunks, flat_indices, open_store, write_chunk

#: Most points of a task (a Floquet point takes about 0.1-1 s: a task of a few
#: seconds makes the scheduler's milliseconds negligible).
CHUNK_POINTS = 32
#: Tasks wanted for a study, at least (load balance over a cluster's workers).
CHUNK_COUNT = 64
#: The class of a single failure of alike blades: any of them is the same rotor turned.
ANY_BLADE = "any blade"


def study_chunk(grid: Grid) -> tuple:
    """The chunk shape of a study: a function of its grid only (a resume finds the same).

    The failure dimension is never split: a chunk computes the single failures
    of alike blades once (:func:`compute_points`).
    """
    target = max(len(grid.failures) or 1, min(CHUNK_POINTS, grid.size // CHUNK_COUNT))
    return chunk_shape(grid.shape, target)


def compute_points(data: dict, source: str, grid: Grid, flats) -> dict:
    """Measures of the grid points ``flats`` (flat indices), in order: arrays.

    A point whose case is invalid, or that the model cannot analyse, has NaN
    measures and its reason in ``error``; the others go on. Where the blades
    are alike but for the failed damper, every single failure is the same
    rotor seen from another blade (the azimuth origin moved by 2 pi (k - 1)/N):
    its measures over the sweep are those of the first failure, computed once.
    """
    out = empty(len(flats))
    seen = {}  # (values, failure or ANY_BLADE) -> measures or error
    for j, flat in enumerate(flats):
        values, failure = grid.point(int(flat))
        key = (tuple(values.items()), failure_class(data, values, failure, source))
        if key not in seen:
            try:
                seen[key] = of_case(varied_case(data, values, failure, source))
            except POINT_ERRORS as err:  # (recorded with its reason; the study goes on)
                seen[key] = failed(err)
        if isinstance(seen[key], str):
            out[ERROR][j] = seen[key]
            continue
        for name in MEASURES:
            out[name][j] = seen[key][name]
    return out


def failure_class(data, values, failure, source) -> str:
    """``failure``, or :data:`ANY_BLADE` where the point's rotor looks the same from every blade
    (blades and damper rods alike: so any single failure is the same rotor turned)."""
    if failure == NO_FAILURE:
        return failure
    try:
        rotor = varied_case(data, values, NO_FAILURE, source).rotor
    except POINT_ERRORS:  # (the point itself says what is wrong)
        return failure
    if not rotor.identical:
        return failure
    return ANY_BLADE if failure.startswith("blade ") else f"any {failure.rpartition(' rod ')[0]} rod"


def compute(data, source, grid, store: Path | None = None, fresh=None, client=None, progress=None):
    """Measures of every grid point, chunk by chunk: a dict of arrays shaped as the grid.

    Parameters
    ----------
    data : dict
        The case's TOML tables (:func:`groundres.studies.grid.raw`).
    source : str
        The case's name, for messages.
    grid : Grid
    store : Path, optional
        Zarr store: finished chunks are written there as they come, and the
        chunks found done there are not computed again.
    fresh : xarray.Dataset
        The store's template (:func:`groundres.studies.store.template`), with ``store``.
    client : dask.distributed.Client, optional
        Where to compute; None: in this process.
    progress : callable, optional
        ``progress(done, total)`` in grid points.
    """
    chunk = study_chunk(grid)
    done = open_store(store, fresh, chunk) if store is not None else np.zeros(grid.shape, bool)
    values = empty(grid.size)
    todo = [where for where in chunks(grid.shape, chunk) if not done[where].all()]
    batches = [(data, source, grid, flat_indices(grid.shape, where)) for where in todo]
    finished = grid.size - sum(len(b[3]) for b in batches)

    def take(i, got):
        flats = batches[i][3]
        for name in values:
            values[name][flats] = got[name]
        if store is not None:
            write_chunk(store, grid, todo[i], got)
        return len(flats)

    map_batches(compute_points, batches, client, progress, take, (finished, grid.size))
    return values


def map_batches(fn, batches, client=None, progress=None, take=None, count=None):
    """``fn(*batch)`` for each batch, in this process or on ``client`` (on a worker's one
    core), results handed to ``take(index, result)`` as they come (in any order on a
    cluster); ``take`` returns how many items the batch held (1 without ``take``).
    ``progress(done, total)`` counts items from ``count`` = (done before, total).

    Returns the results in the batches' order.
    """
    report = progress or (lambda done, total: None)
    done, total = count if count is not None else (0, len(batches))
    out = [None] * len(batches)
    report(done, total)

    def taken(i, result):
        nonlocal done
        out[i] = result
        done += take(i, result) if take is not None else 1
        report(done, total)

    if client is None:
        for i, batch in enumerate(batches):
            taken(i, fn(*batch))
        return out
    from distributed import as_completed

    token = uuid.uuid4().hex  # (keys named after the work and the batch: compute_points-<token>-<i>)
    futures = {
        client.submit(_in_place, fn, *batch, key=f"{fn.__name__}-{token}-{i}"): i
        for i, batch in enumerate(batches)
    }
    # (results gathered by as_completed in the client's own loop: this thread only waits, so an
    # interrupt here leaves no gather of Dask's cut half-way; each result let go once taken, so
    # a worker lost later has nothing of it to compute again)
    for future, result in as_completed(futures, with_results=True):
        i = futures.pop(future)
        future.release()
        taken(i, result)
    return out


def _in_place(fn, *args):
    """A task on a cluster's worker: one core (see the module's note)."""
    with parallel.in_place():
        return fn(*args)


#: Most memory a worker of a local cluster may hold [bytes]: a grid point's analysis needs a
#: few hundred MB at most (a sweep's matrices are bounded, :data:`groundres.model.params.MAX_SWEEP_VALUES`);
#: a worker above 80 % of it pauses, and one above 95 % is restarted (its task computed again).
WORKER_MEMORY = 4 * 2**30


def worker_memory(workers: int) -> int:
    """The memory limit of each of ``workers`` local workers [bytes]: the machine's memory
    shared between them, at most :data:`WORKER_MEMORY`."""
    from distributed.system import MEMORY_LIMIT

    return int(min(MEMORY_LIMIT / max(workers, 1), WORKER_MEMORY))


def memory_of(client) -> list[tuple[int, int]]:
    """(peak resident memory, memory limit) of each worker of ``client`` [bytes]; the limit 0
    where the cluster sets none."""
    info = client.scheduler_info().get("workers", {})
    peaks = client.run(_peak_memory)
    return [(int(peaks.get(address, 0)), int(w.get("memory_limit") or 0)) for address, w in info.items()]


def _peak_memory() -> int:
    """This process's peak resident memory [bytes] (Linux and macOS report it differently)."""
    import resource
    import sys

    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return int(peak if sys.platform == "darwin" else peak * 1024)


#: Where a local cluster listens: this machine only.
LOOPBACK = "127.0.0.1"
#: How long an existing cluster's scheduler has to answer [s] (:func:`remote_client`).
CONNECT_SECONDS = 10.0


def local_client(workers: int, dashboard: bool = False, quiet: bool = True):
    """A Dask cluster on this machine, for this machine only: ``workers`` processes of one
    thread each, each held to :func:`worker_memory`.

    Parameters
    ----------
    workers : int
    dashboard : bool
        Serve Dask's dashboard (on 127.0.0.1, a free port: ``client.dashboard_link``;
        it needs bokeh: :func:`dashboard_missing`).
    quiet : bool
        Keep Dask's log lines off the terminal: the study reports what fails (a
        failed task raises in this process), and a cluster closed while its
        workers compute logs races of its own (a worker's heartbeat cut by its
        own closing) as errors.

    Notes
    -----
    Scheduler, nannies and workers listen on 127.0.0.1. Dask's scheduler and
    workers always open a web server as well: on 127.0.0.1 too, serving nothing
    but the dashboard where asked.

    The cluster's processes import nothing from the folder this one was started
    in. They start as ``python -c ...``, which puts the current folder first on
    ``sys.path`` (a ``weakref.py`` there would run in every worker); Python's
    safe path (PYTHONSAFEPATH=1, Python >= 3.11) in their environment keeps it
    out. It is set while the cluster starts (the multiprocessing resource tracker
    starts then, with the first worker) and in the nannies' environment for
    workers started later (a worker restarted past its memory limit).

    Its workers keep glibc's default memory trimming: Dask sets
    ``MALLOC_TRIM_THRESHOLD_`` = 64 kB in its workers, which hands the many
    small NumPy arrays of an analysis back to the system and costs a grid
    point 1.5x its time (0.32 against 0.21 s, measured on the Hammond
    one-damper case with 100 speeds).
    """
    import logging

    import dask
    from distributed import Client, LocalCluster

    environ = dict(dask.config.get("distributed.nanny.pre-spawn-environ", {}))
    environ.pop("MALLOC_TRIM_THRESHOLD_", None)
    environ[SAFE_PATH] = "1"
    settings = {"distributed.nanny.pre-spawn-environ": environ, "distributed.worker.http.routes": []}
    if not dashboard:
        settings["distributed.scheduler.http.routes"] = []
    cluster = client = None
    try:
        with dask.config.set(settings), _environ({SAFE_PATH: "1"}), _starting():
            cluster = LocalCluster(
                n_workers=workers,
                threads_per_worker=1,
                processes=True,
                host=LOOPBACK,
                # (a free port: studies side by side must not collide on Dask's 8787)
                dashboard_address=f"{LOOPBACK}:0",
                scheduler_kwargs={"dashboard": dashboard},
                silence_logs=logging.CRITICAL if quiet else logging.ERROR,
                memory_limit=worker_memory(workers),
            )
            client = Client(cluster)
    except BaseException:  # (SIGTERM held while it started, or a failure: nothing left running)
        close(client if client is not None else cluster)
        raise
    return client


def dashboard_missing() -> str | None:
    """Why Dask cannot serve its dashboard here (bokeh missing or too old), or None."""
    import warnings

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # (distributed warns as well as raising)
            import distributed.dashboard.scheduler  # noqa: F401
    except ImportError as err:
        from distributed.versions import BOKEH_REQUIREMENT

        return f'Dask needs {BOKEH_REQUIREMENT} for its dashboard ({err}): pip install "{BOKEH_REQUIREMENT}"'
    return None


def remote_client(address: str, seconds: float | None = None):
    """A client of the Dask cluster whose scheduler listens at ``address`` (e.g.
    tcp://host:8786), once the scheduler has answered as one within ``seconds``
    (:data:`CONNECT_SECONDS`; :func:`groundres.studies.handshake.check_scheduler`).

    Raises ConnectionError, TimeoutError or ValueError, saying in words why no
    scheduler answers there: nothing listens, something else does, or it is silent.
    """
    from distributed import Client

    from .handshake import check_scheduler

    left = check_scheduler(address, CONNECT_SECONDS if seconds is None else seconds)
    try:
        return Client(address, timeout=max(left, 1.0))
    except (OSError, TimeoutError, ValueError) as err:
        raise ConnectionError(f"no Dask scheduler reached there ({type(err).__name__}: {err})") from err


def close(client_or_cluster) -> None:
    """Close a client, and the local cluster it was made with (:func:`local_client`); an
    existing cluster (:func:`remote_client`) is its owner's and keeps running."""
    if client_or_cluster is None:
        return
    cluster = getattr(client_or_cluster, "cluster", None)
    client_or_cluster.close()
    if cluster is not None:
        cluster.close()


#: Python's safe path (>= 3.11): neither the script's folder nor, for ``-c``, the current
#: folder is put on ``sys.path``.
SAFE_PATH = "PYTHONSAFEPATH"


@contextlib.contextmanager
def _environ(values: dict):
    """``values`` in this process's environment inside the block (processes started there
    inherit them), the environment as it was after."""
    before = {key: os.environ.get(key) for key in values}
    os.environ.update(values)
    try:
        yield
    finally:
        for key, value in before.items():
            if value is None:
                os.environ.pop(key, None)
            else:
                os.environ[key] = value


@contextlib.contextmanager
def _starting():
    """While a local cluster starts: processes started with SIGINT ignored, and SIGTERM held.

    Ctrl-C at a terminal reaches the whole process group, and the workers would
    each print a traceback. A Python started with SIGINT ignored keeps ignoring
    it: this process alone is interrupted, and closes them (the study resumes).
    A Ctrl-C in the second or two the cluster takes to start is ignored by this
    process too: only an ignored SIGINT passes to the processes it starts, and a
    signal's handling is the whole process's. (Blocking SIGINT meanwhile does not
    hold it: BLAS's own threads, which do not block it, take it and discard it.)

    SIGTERM meanwhile is held and handled once the cluster is up (then closed
    whole): handled at once, it would leave a cluster half started, which Dask's
    own exit handler then fails to close, with a traceback.
    """
    try:
        interrupt = signal.signal(signal.SIGINT, signal.SIG_IGN)
    except ValueError:  # (not the main thread: nothing to change)
        yield
        return
    held = []
    terminate = signal.signal(signal.SIGTERM, lambda signum, frame: held.append(signum))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, interrupt)
        signal.signal(signal.SIGTERM, terminate if terminate is not None else signal.SIG_DFL)
        if held:
            signal.raise_signal(signal.SIGTERM)  # (handled now, as it would have been)
