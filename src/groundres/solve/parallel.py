"""Threads for batches of small linear algebra, without oversubscribing the cores.

NumPy's matrix products and LAPACK calls release the GIL, so a batch split
over a few threads runs in parallel. Inside those threads the BLAS library
must not start threads of its own (OpenBLAS and MKL use every core by
default): cores x BLAS threads oversubscribe the machine, 1.4x slower on a
quiet one and 3.7-4.9x under load (measured on two cores). While the pool
works, BLAS is limited to one thread with threadpoolctl; outside it, BLAS
keeps its own setting (a single large eigenproblem uses every core).
"""

from __future__ import annotations

import contextlib
import os
import threading
from concurrent.futures import ThreadPoolExecutor

#: Threads of the pool: the cores this process may run on, at most 4 (the
#: batches are small; more threads only add overhead).
CORES = min(len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1), 4)

_POOL = None
_CONTROLLER = None
#: ``inside`` is set in the pool's threads: a batch split again there runs in place
#: (the pool's threads waiting on tasks queued behind themselves would never return).
_LOCAL = threading.local()


def _controller():
    """threadpoolctl's view of the loaded BLAS libraries (found once)."""
    global _CONTROLLER
    if _CONTROLLER is None:
        from threadpoolctl import ThreadpoolController

        _CONTROLLER = ThreadpoolController()
    return _CONTROLLER


def map_threads(fn, items) -> list:
    """``[fn(x) for x in items]``, over the pool's threads with BLAS single-threaded."""
    global _POOL
    items = list(items)
    if len(items) < 2 or CORES < 2 or getattr(_LOCAL, "inside", False):
        return [fn(x) for x in items]
    if _POOL is None:
        _POOL = ThreadPoolExecutor(CORES, initializer=_mark_inside)
    with _controller().limit(limits=1, user_api="blas"):
        return list(_POOL.map(fn, items))


def _mark_inside():
    _LOCAL.inside = True


@contextlib.contextmanager
def serial_blas():
    """BLAS single-threaded inside the block: for batches of small products outside the pool
    (OpenBLAS wakes its threads for a long product of small matrices, gaining little; they
    then spin for a while and take the cores from the pool's next batch)."""
    with _controller().limit(limits=1, user_api="blas"):
        yield


@contextlib.contextmanager
def in_place():
    """Batches run in the calling thread and BLAS single-threaded, inside the block: for a
    process that shares the cores with others (a Dask worker, one core each)."""
    before = getattr(_LOCAL, "inside", False)
    _LOCAL.inside = True
    try:
        with serial_blas():
            yield
    finally:
        _LOCAL.inside = before
