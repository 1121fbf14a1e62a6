"""The torch backend (for CUDA) gives the numpy path's states, wherever torch is installed."""

from __future__ import annotations

import numpy as np
import pytest

from hippo.perception.place_cells import RCSFAICA
from hippo.perception.reservoir import Reservoir, ReservoirParams

torch = pytest.importorskip("torch")


def params(**kw) -> ReservoirParams:
    return ReservoirParams(**{"n_inputs": 8, "n_neurons": 80, "seed": 5, **kw})


def inputs(T: int = 400, seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).random((T, 8))


def test_float32_states_agree_with_numpy():
    r = Reservoir(params())
    U = inputs()
    a, b = r.run(U), r.run(U, backend="torch")
    assert a.dtype == b.dtype == np.float32 and a.shape == b.shape
    np.testing.assert_allclose(b, a, atol=2e-5)  # float32 rounding, not drift


def test_chunked_runs_continue_identically():
    r = Reservoir(params(), dtype="float64")
    U = inputs()
    whole = r.run(U, backend="torch")
    first = r.run(U[:150], backend="torch")
    rest = r.run(U[150:], x0=first[-1], backend="torch")
    np.testing.assert_allclose(np.concatenate([first, rest]), whole, atol=1e-12)
    np.testing.assert_allclose(whole, r.run(U), atol=1e-12)


def test_batched_streams_agree_with_numpy():
    r = Reservoir(params(), dtype="float64")
    U = np.stack([inputs(seed=s) for s in range(3)])       # (B, T, n_u)
    x0 = np.random.default_rng(1).uniform(-0.5, 0.5, (3, 80))
    np.testing.assert_allclose(r.run(U, x0=x0, backend="torch"), r.run(U, x0=x0), atol=1e-12)


@pytest.mark.skipif(not torch.cuda.is_available(), reason="needs a CUDA device")
def test_cuda_fit_matches_the_cpu_fit():  # pragma: no cover - no GPU on the CI machines
    U = np.clip(0.5 + 0.3 * np.sin(np.arange(4000)[:, None] / [50, 70, 90, 110, 130, 150, 170,
                                                               190]), 0, 1)
    cpu = RCSFAICA(n_reservoir=100, ica_restarts=2, dtype="float64").fit(U)
    gpu = RCSFAICA(n_reservoir=100, ica_restarts=2, dtype="float64", device="cuda").fit(U)
    np.testing.assert_allclose(gpu.transform(U), cpu.transform(U), atol=1e-6)
