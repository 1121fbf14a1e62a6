"""Thread budgets for work that runs on both cores at once.

The one rule: at every stage, ``workers x BLAS threads <= free cores`` (:func:`blas_budget`,
:func:`free_cores`). A stage that runs one thing (a batched harvest) gives it all free cores as
BLAS threads; a stage that runs several side by side (fits, ICA restarts, sweep cells) gives each
one BLAS thread. Free cores are the usable ones minus the load other processes put on them, so
on busy cores the default falls back to one worker instead of oversubscribing.

The fitting code runs two things side by side (a reservoir harvest beside the SFA moments, or
one leak configuration per core). Each must then use single-threaded BLAS, or the BLAS thread
pools of the two would fight over the cores. ``threadpoolctl`` sets the thread count of whichever
BLAS numpy and scipy loaded (OpenBLAS, MKL, BLIS) at run time; doing that by hand means ctypes
calls into each library's own setter.
"""

from __future__ import annotations

import os
import threading
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from typing import Any, TypeVar

import numpy as np  # noqa: F401  (loads the BLAS that threadpoolctl then finds)
from threadpoolctl import ThreadpoolController

_controller: ThreadpoolController | None = None
_local = threading.local()
T = TypeVar("T")


def _get_controller() -> ThreadpoolController:
    global _controller
    if _controller is None:
        _controller = ThreadpoolController()
    return _controller


@contextmanager
def blas_threads(n: int | None) -> Iterator[None]:
    """BLAS calls made inside use ``n`` threads each (restored on exit; ``None``: unchanged)."""
    if n is None:
        yield
        return
    with _get_controller().limit(limits=int(n), user_api="blas"):
        yield


def single_threaded_blas():
    """BLAS calls made inside run on one thread each (restored on exit)."""
    return blas_threads(1)


def usable_cores() -> int:
    """Cores this process may run on (its CPU affinity)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not on Linux
        return max(1, os.cpu_count() or 1)


def free_cores(load: float | None = None) -> int:
    """Usable cores that other processes leave free: ``cores - (load - 1)``, in [1, cores].

    ``load`` defaults to the 1-minute load average, which counts this process too (the one
    runnable thread calling this). On a quiet machine all cores are free; when other work keeps
    the cores busy, starting more threads than are free only makes them wait for each other (and
    BLAS threads spin while they wait), so the side-by-side stages fall back to one worker.
    """
    cores = usable_cores()
    if load is None:
        try:
            load = os.getloadavg()[0]
        except (AttributeError, OSError):  # pragma: no cover - no load average
            return cores
    return int(min(cores, max(1, cores - round(max(0.0, float(load) - 1.0)))))


def n_workers(requested: int | None = None) -> int:
    """Worker threads for side-by-side work: ``requested``, else :func:`free_cores`."""
    if requested is not None:
        if int(requested) < 1:
            raise ValueError(f"workers must be >= 1, got {requested}")
        return int(requested)
    return free_cores()


def blas_budget(workers: int, *, cores: int | None = None) -> int:
    """BLAS threads each of ``workers`` side-by-side workers may use: the one rule for threads,
    ``workers x BLAS threads <= cores`` (at least 1; ``cores`` default: :func:`free_cores`)."""
    if int(workers) < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    return max(1, int(cores if cores is not None else free_cores()) // int(workers))


def parallel_map(fn: Callable[[Any], T], items: Iterable[Any], workers: int | None = None
                 ) -> list[T]:
    """``[fn(x) for x in items]`` on up to ``workers`` threads (default: the usable cores), each
    with single-threaded BLAS; results in the order of ``items``.

    The numbers do not depend on ``workers``: with one worker, or when called from inside
    another ``parallel_map`` (no nested pools), the items run one after the other, also with
    single-threaded BLAS.
    """
    items = list(items)
    k = min(n_workers(workers), len(items))
    if k <= 1 or getattr(_local, "worker", False):
        with single_threaded_blas():
            return [fn(x) for x in items]

    def run(x: Any) -> T:
        _local.worker = True
        return fn(x)

    with single_threaded_blas(), ThreadPoolExecutor(k) as pool:
        return list(pool.map(run, items))
