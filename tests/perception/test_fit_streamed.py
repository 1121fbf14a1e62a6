"""A streamed fit (constant memory) equals the fit that holds the whole state sequence."""

from __future__ import annotations

import numpy as np
import pytest

import hippo.perception.ica as ica_module
import hippo.perception.place_cells as pc
from hippo.perception.place_cells import RCSFAICA


def sensors(T: int, n: int = 8, seed: int = 0) -> np.ndarray:
    """A smooth multi-sensor signal with slow structure (a robot's IR seen from afar)."""
    rng = np.random.default_rng(seed)
    t = np.arange(T)[:, None]
    slow = np.sin(2 * np.pi * t / rng.uniform(300, 900, n) + rng.uniform(0, 6, n))
    return np.clip(0.5 + 0.4 * slow + 0.05 * rng.standard_normal((T, n)), 0.0, 1.0)


@pytest.mark.parametrize("overrides", [
    {},                                        # SMC09 settings, fixed cutoff
    {"sfa_cutoff": "auto", "washout": 100},    # held-out split, washout inside the first chunk
    {"downsample": 3, "washout": 10},          # down-sampled input
])
def test_streamed_fit_equals_the_held_fit(monkeypatch, overrides):
    monkeypatch.setattr(pc, "_HARVEST_CHUNK", 700)  # many chunks on a short recording
    U = sensors(6000)
    kw = dict(n_reservoir=80, ica_restarts=2, seed=3, **overrides)
    held = RCSFAICA(**kw).fit(U, stream=False)
    streamed = RCSFAICA(**kw).fit(U, stream=True)
    np.testing.assert_allclose(streamed.sfa_.W_, held.sfa_.W_, rtol=1e-6, atol=1e-8)
    np.testing.assert_allclose(streamed.sfa_.slowness_, held.sfa_.slowness_, rtol=1e-8)
    assert streamed.sfa_.cutoff_ == held.sfa_.cutoff_
    np.testing.assert_allclose(streamed.ica_.components_, held.ica_.components_,
                               rtol=1e-5, atol=1e-7)
    np.testing.assert_allclose(streamed.output_peak_, held.output_peak_, rtol=1e-5)
    V = sensors(1500, seed=1)
    np.testing.assert_allclose(streamed.transform(V), held.transform(V), rtol=1e-5, atol=1e-5)


def test_default_streams_only_beyond_the_memory_budget(monkeypatch):
    calls = []
    real = RCSFAICA._fit_streamed
    monkeypatch.setattr(RCSFAICA, "_fit_streamed",
                        lambda self, Ud: calls.append(Ud.shape) or real(self, Ud))
    U = sensors(3000)
    RCSFAICA(n_reservoir=40, ica_restarts=1).fit(U)
    assert calls == []
    monkeypatch.setattr(pc, "_HOLD_BYTES", 3000 * 48 * 4 - 1)  # states just over the budget
    RCSFAICA(n_reservoir=40, ica_restarts=1).fit(U)
    assert calls == [(3000, 8)]


def test_streamed_fit_with_chunked_ica_equals_the_held_fit(monkeypatch):
    """The whole streamed path at small chunk sizes: float32 ICA input (the only array of
    length T), ICA expectations, SFA signs and output statistics summed chunk by chunk."""
    import hippo.perception.ica as ica_mod

    monkeypatch.setattr(pc, "_HARVEST_CHUNK", 700)  # the same SFA moments both ways
    U = sensors(6000)
    kw = dict(n_reservoir=80, ica_restarts=2, seed=3)
    held = RCSFAICA(**kw).fit(U, stream=False)
    monkeypatch.setattr(ica_mod, "_CHUNK", 900)
    streamed = RCSFAICA(**kw).fit(U, stream=True)
    np.testing.assert_allclose(streamed.sfa_.W_, held.sfa_.W_, rtol=1e-6, atol=1e-8)
    np.testing.assert_allclose(streamed.ica_.components_, held.ica_.components_,
                               rtol=1e-4, atol=1e-6)
    np.testing.assert_allclose(streamed.output_std_, held.output_std_, rtol=1e-5)
    np.testing.assert_allclose(streamed.output_peak_, held.output_peak_, rtol=1e-4)


def test_output_stats_equal_those_of_the_whole_output(monkeypatch):
    U = sensors(4000)
    m = RCSFAICA(n_reservoir=40, ica_restarts=1).fit(U, stream=False)
    X = m.features(U)
    Y = m.sfa_.transform(X)
    S = m.ica_.transform(Y)
    monkeypatch.setattr(ica_module, "_OUT_CHUNK", 333)
    std, peak = ica_module.output_stats(m.ica_, Y.astype(np.float32))
    np.testing.assert_allclose(std, S.std(axis=0), rtol=1e-5)
    np.testing.assert_allclose(peak, np.percentile(S, 99.9, axis=0), rtol=1e-5)
