"""The torch backend (for CUDA) gives the numpy path's states, wherever torch is installed."""

from __future__ import annotations

import numpy as np
import pytest

from hippo.perception.place_cells import RCSFAICA
from hippo.perception.reservoir import Reservoir
from hippo.perception.reservoir_params import ReservoirParams

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


def test_the_backend_choice_and_the_torch_thread_count(monkeypatch):
    # backend="torch" runs the tick loop in torch, on `threads` CPU threads, and gives torch
    # its own thread count back; "auto" and "numpy" on the CPU never call torch
    r = Reservoir(params())
    U = inputs(30)
    real_tanh, seen = torch.tanh, []

    def tanh(*args, **kw):
        seen.append(torch.get_num_threads())
        return real_tanh(*args, **kw)

    monkeypatch.setattr(torch, "tanh", tanh)
    before = torch.get_num_threads()
    torch.set_num_threads(2)
    try:
        for leak in (None, np.array([[0.05, 0.15], [0.3, 0.3]])):
            seen.clear()
            r.run(U, leak=leak, backend="torch", threads=1)
            assert seen == [1] * 30 and torch.get_num_threads() == 2
            seen.clear()
            r.run(U, leak=leak)
            r.run(U, leak=leak, backend="numpy")
            assert seen == []
    finally:
        torch.set_num_threads(before)


def test_the_states_stay_on_the_reservoir_device_whatever_torch_s_default():
    # a program that set torch's default device elsewhere ("meta" here: tensors without data)
    # does not move a CPU reservoir's loop off the CPU
    r = Reservoir(params(), dtype="float64")
    U = inputs(60)
    x0 = np.random.default_rng(2).uniform(-0.5, 0.5, 80)
    want = r.run(U, x0=x0)
    leaks = np.array([[0.05, 0.15], [0.3, 0.3]])
    want_sweep = r.run(U, leak=leaks)
    old = torch.get_default_device()
    torch.set_default_device("meta")
    try:
        got = r.run(U, x0=x0, backend="torch")
        got_sweep = r.run(U, leak=leaks, backend="torch")
    finally:
        torch.set_default_device(old)
    np.testing.assert_allclose(got, want, atol=1e-12)
    np.testing.assert_allclose(got_sweep, want_sweep, atol=1e-12)


def test_torch_tensors_that_require_grad_are_accepted():
    # U and x0 may be torch tensors, also ones that are part of an autograd graph
    r = Reservoir(params(), dtype="float64")
    U = inputs(40)
    x0 = np.random.default_rng(3).uniform(-0.5, 0.5, 80)
    Ut = torch.tensor(U, requires_grad=True)
    x0t = torch.tensor(x0, requires_grad=True)
    np.testing.assert_array_equal(r.run(Ut, x0=x0t), r.run(U, x0=x0))


def test_on_a_cuda_device_auto_is_torch_and_numpy_is_refused(monkeypatch):
    # the choice comes before any CUDA work, so a CUDA device is pretended here and the torch
    # loop replaced by a recorder
    monkeypatch.setattr(torch.cuda, "is_available", lambda: True)
    r = Reservoir(params(), device="cuda")
    with pytest.raises(ValueError, match=r"^backend='numpy' runs on the CPU, but device='cuda'"):
        r.run(inputs(5), backend="numpy")
    used = []
    monkeypatch.setattr(r, "_run_torch", lambda U, A, x, threads: used.append(U.shape)
                        or np.zeros((1, U.shape[1], 80), np.float32))
    r.run(inputs(5))
    r.run(inputs(5), backend="torch")
    assert used == [(1, 5, 8), (1, 5, 8)]
