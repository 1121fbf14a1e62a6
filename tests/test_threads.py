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
