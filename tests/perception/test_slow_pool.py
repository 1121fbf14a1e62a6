"""The slow pool (``slow_pool``): a leaky running mean of the SFA input, appended to it."""

from __future__ import annotations

import json

import numpy as np
import pytest

import hippo.perception.place_cells as pc
from hippo.io import CorruptFileError, load_npz, save_npz
from hippo.perception import RCSFAICA, fit_leak_sweep
from hippo.perception.place_cell_params import RCSFAICAParams
from hippo.perception.slow_pool import SlowPool, check_slow_pool, with_pool


def sensors(T: int, n: int = 8, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    t = np.arange(T)[:, None]
    slow = np.sin(2 * np.pi * t / rng.uniform(300, 900, n) + rng.uniform(0, 6, n))
    return np.clip(0.5 + 0.4 * slow + 0.05 * rng.standard_normal((T, n)), 0.0, 1.0)


@pytest.mark.parametrize("tau", [1.0, 7.0, 100.0, 333.3])
def test_pool_on_a_step_is_the_leaky_integrator(tau):
    """A step z = c from t = 0: m(t) = c (1 - (1 - 1/tau)^(t+1)); after tau ticks 1 - 1/e of
    the way for large tau."""
    c = np.array([0.3, -2.0, 1.0])
    T = 1000
    F, last = with_pool(np.tile(c, (T, 1)), tau)
    t = np.arange(T)[:, None]
    want = c * (1.0 - (1.0 - 1.0 / tau) ** (t + 1))
    np.testing.assert_array_equal(F[:, :3], np.tile(c, (T, 1)))
    np.testing.assert_allclose(F[:, 3:], want, rtol=1e-12, atol=1e-14)
    np.testing.assert_array_equal(last, F[-1, 3:])
    if tau == 100.0:
        np.testing.assert_allclose(F[99, 3:], c * (1 - 0.99 ** 100), rtol=1e-12)
        assert abs(F[99, 3] / c[0] - (1 - np.exp(-1))) < 0.01


def test_pool_continues_across_chunks_and_online():
    Z = np.random.default_rng(1).standard_normal((500, 4))
    whole, _ = with_pool(Z, 30.0)
    a, m = with_pool(Z[:123], 30.0)
    b, _ = with_pool(Z[123:], 30.0, m)
    np.testing.assert_allclose(np.vstack([a, b]), whole, rtol=1e-12, atol=1e-14)
    pool = SlowPool(30.0, 4)
    online = np.array([pool.step(z).copy() for z in Z])
    np.testing.assert_allclose(online, whole[:, 4:], rtol=1e-10, atol=1e-13)
    pool.reset()
    np.testing.assert_array_equal(pool.m, 0.0)


def test_pool_off_is_the_input_itself():
    Z = np.ones((5, 2), dtype=np.float32)
    F, last = with_pool(Z, 0.0)
    assert F is Z and last is None


@pytest.mark.parametrize("bad", [-1, 0.5, 0.999, float("nan"), float("inf"), "100", True,
                                 None])
def test_bad_slow_pool_names_the_argument(bad):
    with pytest.raises(ValueError, match="slow_pool"):
        check_slow_pool(bad)
    with pytest.raises(ValueError, match="slow_pool"):
        RCSFAICAParams(slow_pool=bad)
    with pytest.raises(ValueError, match="slow_pool"):
        RCSFAICA.smc09(slow_pool=bad)


@pytest.mark.parametrize("bad", [0.5, -1, float("nan"), float("inf"), True, "50"])
def test_with_pool_refuses_a_time_constant_that_oscillates_or_diverges(bad):
    with pytest.raises(ValueError, match="tau must be"):
        with_pool(np.ones((5, 2)), bad)


def test_slow_pool_zero_is_todays_model():
    """slow_pool = 0: the SFA input is exactly [u; x] and step/transform give exactly what a
    model without the field gives (default 0)."""
    U = sensors(1500)
    off = RCSFAICA(n_reservoir=40, ica_restarts=1, seed=2, slow_pool=0).fit(U)
    default = RCSFAICA(n_reservoir=40, ica_restarts=1, seed=2).fit(U)
    X = off.features(U)
    np.testing.assert_array_equal(X, np.concatenate(
        [U.astype(np.float32), off.reservoir_.run(U)], axis=1))
    assert off.sfa_.n_features_in_ == 48
    np.testing.assert_array_equal(off.transform(U), default.transform(U))


@pytest.fixture(scope="module")
def pooled():
    U = sensors(4000)
    return RCSFAICA(n_reservoir=60, ica_restarts=2, seed=4, slow_pool=50).fit(U), U


def test_pool_widens_the_sfa_input(pooled):
    model, U = pooled
    X = model.features(U)
    assert X.shape == (len(U), 2 * 68) and model.sfa_.n_features_in_ == 2 * 68
    Z = np.concatenate([U.astype(np.float32), model.reservoir_.run(U)], axis=1)
    np.testing.assert_allclose(X[:, 68:], with_pool(Z, 50.0)[0][:, 68:], rtol=0, atol=0)


def test_step_equals_transform_with_a_pool(pooled):
    model, U = pooled
    Y = model.transform(U[:800])
    model.reset_state()
    S = np.array([model.step(u) for u in U[:800]])
    np.testing.assert_allclose(S, Y, atol=1e-4 * np.abs(Y).max())
    model.reset_state()  # the pool's state is cleared: the same outputs again
    np.testing.assert_allclose(np.array([model.step(u) for u in U[:50]]), S[:50], atol=1e-12)


def test_step_equals_transform_with_a_pool_and_no_reservoir():
    U = sensors(1500)
    model = RCSFAICA(use_reservoir=False, n_sfa=4, n_ica=2, ica_restarts=1,
                     slow_pool=20).fit(U)
    assert model.sfa_.n_features_in_ == 16
    Y = model.transform(U[:300])
    np.testing.assert_allclose(np.array([model.step(u) for u in U[:300]]), Y, atol=1e-9)


def test_streamed_fit_with_a_pool_equals_the_held_fit(monkeypatch):
    monkeypatch.setattr(pc, "_HARVEST_CHUNK", 700)  # the pool is carried across many chunks
    U = sensors(5000)
    kw = dict(n_reservoir=50, ica_restarts=2, seed=3, slow_pool=80, washout=100)
    held = RCSFAICA(**kw).fit(U, stream=False)
    streamed = RCSFAICA(**kw).fit(U, stream=True)
    # the same features, chunk by chunk, to float32's last bit (BLAS may round a block of
    # ticks by its size: 1 ulp in 2 % of the values on an AMD EPYC, bit for bit before)
    np.testing.assert_allclose(held._harvest_summarised(held._decimator().offline(U))[0],
                               held.features(U), rtol=0, atol=4 * np.finfo(np.float32).eps)
    np.testing.assert_allclose(streamed.sfa_.slowness_, held.sfa_.slowness_, rtol=1e-6)
    V = sensors(1000, seed=1)
    np.testing.assert_allclose(streamed.transform(V), held.transform(V), rtol=1e-4, atol=1e-4)


def test_save_load_round_trip_with_a_pool(pooled, tmp_path):
    model, U = pooled
    path = model.save(tmp_path / "m.npz")
    loaded = RCSFAICA.load(path)
    assert loaded.params.slow_pool == 50.0
    np.testing.assert_array_equal(loaded.transform(U[:300]), model.transform(U[:300]))
    model.reset_state()
    np.testing.assert_array_equal(np.array([loaded.step(u) for u in U[:20]]),
                                  np.array([model.step(u) for u in U[:20]]))
    # a file whose parameters lose the pool no longer fits its SFA arrays: refused
    a = load_npz(path)
    raw = json.loads(str(a["params"]))
    raw["slow_pool"] = 0
    a["params"] = np.array(json.dumps(raw))
    save_npz(tmp_path / "bad.npz", a)
    with pytest.raises(CorruptFileError, match="sfa_"):
        RCSFAICA.load(tmp_path / "bad.npz")
    raw["slow_pool"] = -3
    a["params"] = np.array(json.dumps(raw))
    save_npz(tmp_path / "bad2.npz", a)
    with pytest.raises(CorruptFileError, match="slow_pool"):
        RCSFAICA.load(tmp_path / "bad2.npz")


def test_leak_sweep_carries_the_pool():
    U = sensors(2000)
    kw = dict(n_reservoir=40, ica_restarts=1, seed=5, slow_pool=40)
    swept = fit_leak_sweep(U, [0.1, (0.05, 0.15)], RCSFAICAParams(**kw), workers=1)
    single = RCSFAICA(leak=(0.05, 0.15), **kw).fit(U)
    assert swept[1].sfa_.n_features_in_ == 96
    np.testing.assert_allclose(swept[1].sfa_slowness_, single.sfa_slowness_, rtol=1e-4)
