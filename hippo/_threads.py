"""Thread budgets for work that runs on both cores at once.

The fitting code runs two things side by side (a reservoir harvest beside the SFA moments, or
one leak configuration per core). Each must then use single-threaded BLAS, or the BLAS thread
pools of the two would fight over the cores. ``threadpoolctl`` sets the thread count of whichever
BLAS numpy and scipy loaded (OpenBLAS, MKL, BLIS) at run time; doing that by hand means ctypes
calls into each library's own setter.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np  # noqa: F401  (loads the BLAS that threadpoolctl then finds)
from threadpoolctl import ThreadpoolController

_controller: ThreadpoolController | None = None


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


def n_workers(requested: int | None = None) -> int:
    """Worker threads for side-by-side work: ``requested``, else the cores this process may use."""
    if requested is not None:
        if int(requested) < 1:
            raise ValueError(f"workers must be >= 1, got {requested}")
        return int(requested)
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not on Linux
        cores = os.cpu_count() or 1
    return max(1, cores)
