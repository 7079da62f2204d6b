"""The thread pool keeps BLAS single-threaded inside it (issue 10, item 1)."""

import numpy as np
import pytest
from threadpoolctl import threadpool_info

from groundres.solve import parallel


def _blas_threads():
    return [i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"]


@pytest.mark.skipif(parallel.CORES < 2, reason="one core: the pool is not used")
def test_blas_is_single_threaded_inside_the_pool_and_restored_after():
    before = _blas_threads()
    seen = parallel.map_threads(lambda a: (_blas_threads(), np.linalg.eigvals(a).shape), [np.eye(4)] * 4)
    assert all(threads and set(threads) == {1} for threads, _ in seen)
    assert [shape for _, shape in seen] == [(4,)] * 4
    assert _blas_threads() == before


def test_results_keep_the_order_of_the_items():
    assert parallel.map_threads(lambda x: x * x, range(10)) == [x * x for x in range(10)]
    assert parallel.map_threads(lambda x: -x, [3]) == [-3]


def test_a_batch_split_again_inside_the_pool_runs_in_place():
    """(A pool thread waiting on tasks queued behind itself would never return: a grid
    of node matrices is built over the pool, and may be asked for from inside it.)"""
    import concurrent.futures

    def inner(x):
        return x + 1

    def outer(x):
        return parallel.map_threads(inner, [x, 10 * x])

    with concurrent.futures.ThreadPoolExecutor(1) as watchdog:
        got = watchdog.submit(parallel.map_threads, outer, range(4)).result(timeout=30)
    assert got == [[x + 1, 10 * x + 1] for x in range(4)]


def test_serial_blas_keeps_blas_single_threaded_inside_and_restores_it():
    """(A long product of small matrices outside the pool must not wake BLAS threads that then
    spin through the pool's next batch.)"""
    before = _blas_threads()
    with parallel.serial_blas():
        assert set(_blas_threads()) == {1}
    assert _blas_threads() == before
