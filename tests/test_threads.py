"""Thread budgets: BLAS limits are applied and restored; worker counts are checked."""

import pytest
from threadpoolctl import threadpool_info

from hippo._threads import blas_threads, n_workers, single_threaded_blas


def _blas_threads() -> list[int]:
    return [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]


def test_blas_limits_apply_and_restore():
    before = _blas_threads()
    assert before, "numpy's BLAS should be visible to threadpoolctl"
    with single_threaded_blas():
        assert _blas_threads() == [1] * len(before)
        with blas_threads(2):
            assert _blas_threads() == [2] * len(before)
        assert _blas_threads() == [1] * len(before)
    with blas_threads(None):
        assert _blas_threads() == before
    assert _blas_threads() == before


def test_n_workers():
    assert n_workers(3) == 3
    assert n_workers() >= 1
    with pytest.raises(ValueError, match="workers"):
        n_workers(0)


def test_parallel_map_keeps_order_and_does_not_nest():
    import threading

    from hippo._threads import parallel_map

    seen: list[str] = []

    def inner(x: int) -> int:
        seen.append(threading.current_thread().name)
        return x * x

    def outer(x: int) -> list[int]:
        return parallel_map(inner, range(x), workers=2)

    assert parallel_map(lambda x: x + 1, range(7), workers=2) == list(range(1, 8))
    out = parallel_map(outer, [3, 4], workers=2)
    assert out == [[0, 1, 4], [0, 1, 4, 9]]
    # the inner maps ran on the outer workers themselves: no pool inside a pool
    assert len(set(seen)) <= 2 and all(not n.startswith("MainThread") for n in seen)
    assert parallel_map(inner, [], workers=2) == []


def test_free_cores_follow_the_load():
    from hippo._threads import blas_budget, free_cores, usable_cores

    cores = usable_cores()
    assert free_cores(load=0.0) == cores      # a quiet machine: every core
    assert free_cores(load=1.0) == cores      # only this process runs
    assert free_cores(load=cores + 5.0) == 1  # busy: one worker, never oversubscribed
    if cores >= 2:
        assert free_cores(load=2.0) == cores - 1
    assert 1 <= free_cores() <= cores
    assert blas_budget(2, cores=2) == 1 and blas_budget(1, cores=4) == 4


def test_sfa_gives_the_same_bits_on_one_or_two_blas_threads():
    # the free cores (so the BLAS threads of a fit) follow the machine's load; the eigensolvers
    # sum in another order on two threads, so SFA solves on one: same data, same bits
    import numpy as np

    from hippo.perception.sfa import SFA

    rng = np.random.default_rng(0)
    t = np.arange(4000)
    slow = np.sin(2 * np.pi * t / 800)[:, None]
    X = np.tanh(slow @ rng.standard_normal((1, 400)) + 0.3 * rng.standard_normal((4000, 400)))
    X = np.cumsum(X, axis=0) * 0.01 + X            # correlated, reservoir-like columns
    fits = []
    for n in (1, 2, 1, 2):
        with blas_threads(n):
            fits.append(SFA(n_components=4).fit(X).W_)
    assert all(np.array_equal(fits[0], w) for w in fits[1:])
