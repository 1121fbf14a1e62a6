"""Thread budgets by hand (hippo._threads): the usable cores from the CPU affinity (or the CPU
count), the free cores from a given load (rounded half to even) and from the 1-minute load
average, the worker count and the BLAS threads each may use (floor division, at least 1), and
parallel_map's threads: one worker or one item runs on the caller's thread, a pool never runs
more than its workers at once, a nested map runs on its outer worker, every call with
single-threaded BLAS, the results in order."""

from __future__ import annotations

import os
import threading
import time

import pytest
from threadpoolctl import ThreadpoolController, threadpool_info

from hippo import _threads
from hippo._threads import (
    _get_controller,
    blas_budget,
    free_cores,
    n_workers,
    parallel_map,
    usable_cores,
)


def _blas() -> list[int]:
    return [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]


# ------------------------------------------------------------------------------------ cores
def test_the_controller_is_made_once(monkeypatch):
    monkeypatch.setattr(_threads, "_controller", None)
    first = _get_controller()
    assert isinstance(first, ThreadpoolController)
    assert _get_controller() is first and _threads._controller is first


def test_usable_cores_are_the_affinity(monkeypatch):
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 3, 5})
    assert usable_cores() == 3
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: set())
    assert usable_cores() == 1          # at least one


@pytest.mark.parametrize("count, cores", [(4, 4), (1, 1), (None, 1), (0, 1)])
def test_usable_cores_without_an_affinity_are_the_cpu_count(monkeypatch, count, cores):
    monkeypatch.delattr(os, "sched_getaffinity")
    monkeypatch.setattr(os, "cpu_count", lambda: count)
    assert usable_cores() == cores


@pytest.mark.parametrize("load, free", [
    (0.0, 4), (1.0, 4), (1.5, 4),      # round(0.5) = 0: half to even
    (1.6, 3), (2.0, 3), (2.4, 3), (2.5, 2), (3.5, 2), (4.0, 1), (4.5, 1), (5.0, 1), (99.0, 1),
    (-3.0, 4)])
def test_free_cores_are_the_cores_less_the_others_load(monkeypatch, load, free):
    monkeypatch.setattr(_threads, "usable_cores", lambda: 4)
    assert free_cores(load) == free and type(free_cores(load)) is int


def test_free_cores_read_the_one_minute_load(monkeypatch):
    monkeypatch.setattr(_threads, "usable_cores", lambda: 4)
    monkeypatch.setattr(os, "getloadavg", lambda: (3.0, 0.0, 9.0))
    assert free_cores() == 2                # 4 - (3 - 1), not the 5- or 15-minute figure

    def no_load() -> tuple[float, float, float]:
        raise OSError("no load average")

    monkeypatch.setattr(os, "getloadavg", no_load)
    assert free_cores() == 4                # unknown load: every core


# ---------------------------------------------------------------------------------- budgets
def test_workers_as_asked_or_the_free_cores(monkeypatch):
    monkeypatch.setattr(_threads, "free_cores", lambda: 3)
    assert n_workers() == 3 and n_workers(None) == 3
    assert n_workers(1) == 1 and n_workers(5) == 5 and n_workers(2.7) == 2
    for bad in (0, -1):
        with pytest.raises(ValueError) as e:
            n_workers(bad)
        assert str(e.value) == f"workers must be >= 1, got {bad}"


@pytest.mark.parametrize("workers, cores, budget", [
    (1, 4, 4), (2, 4, 2), (3, 4, 1), (2, 3, 1), (3, 8, 2), (4, 2, 1), (1, 1, 1), (2, 0, 1)])
def test_the_blas_budget_is_the_cores_shared_out(workers, cores, budget):
    got = blas_budget(workers, cores=cores)
    assert got == budget and type(got) is int


def test_the_blas_budget_defaults_to_the_free_cores(monkeypatch):
    monkeypatch.setattr(_threads, "free_cores", lambda: 6)
    assert blas_budget(2) == 3 and blas_budget(4) == 1 and blas_budget(1) == 6
    assert blas_budget(2, cores=2) == 1                # given cores win
    for bad in (0, -2):
        with pytest.raises(ValueError) as e:
            blas_budget(bad, cores=4)
        assert str(e.value) == f"workers must be >= 1, got {bad}"


# --------------------------------------------------------------------------------- the pool
def test_one_worker_or_one_item_runs_on_the_callers_thread():
    me = threading.get_ident()

    def where(x: int) -> tuple[int, int, list[int]]:
        return x * 10, threading.get_ident(), _blas()

    for items, workers in (([1, 2, 3], 1), ([4], 2), ([5], None)):
        out = parallel_map(where, items, workers=workers)
        assert [v for v, _, _ in out] == [10 * x for x in items]
        assert all(t == me for _, t, _ in out)
        assert all(b and set(b) == {1} for _, _, b in out)   # single-threaded BLAS
    assert parallel_map(where, [], workers=3) == []


def test_a_pool_runs_at_most_its_workers_at_once():
    lock = threading.Lock()
    active, most, threads = [0], [0], set()

    def work(x: int) -> tuple[int, list[int]]:
        with lock:
            active[0] += 1
            most[0] = max(most[0], active[0])
            threads.add(threading.get_ident())
        time.sleep(0.05)
        with lock:
            active[0] -= 1
        return x + 1, _blas()

    out = parallel_map(work, range(6), workers=2)
    assert [v for v, _ in out] == [1, 2, 3, 4, 5, 6]          # in the order of the items
    assert most[0] == 2 and len(threads) == 2 and threading.get_ident() not in threads
    assert all(b and set(b) == {1} for _, b in out)


def test_a_nested_map_runs_on_its_outer_worker():
    def inner(y: int) -> tuple[int, int]:
        return y * y, threading.get_ident()

    def outer(x: int) -> tuple[list[int], bool]:
        me = threading.get_ident()
        res = parallel_map(inner, range(x), workers=2)
        return [v for v, _ in res], all(t == me for _, t in res)

    out = parallel_map(outer, [3, 4, 2], workers=2)
    assert out == [([0, 1, 4], True), ([0, 1, 4, 9], True), ([0, 1], True)]
    # the caller's thread is no worker: its own maps still use a pool
    assert not getattr(_threads._local, "worker", False)
