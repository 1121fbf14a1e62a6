"""SensorGuard: flags exactly the dead sensors, imputes from correlated live ones."""

import numpy as np
import pytest

from hippo.perception.sensor_guard import SensorGuard, SensorGuardParams
from hippo.sim.faults import SensorFaults


def _readings(T=3000, seed=0):
    """8 smooth sensor signals driven by 3 slow latent sources (neighbours correlated), with
    the e-puck's reading noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(T)
    z = np.column_stack([np.sin(t / 40.0), np.cos(t / 65.0), np.sin(t / 23.0 + 1)])
    mix = rng.normal(size=(3, 8))
    U = 0.5 + 0.15 * z @ mix + rng.normal(0, 0.02, (T, 8))
    return np.clip(U, 0, 1)


def test_no_flags_on_healthy_or_uniformly_noisier_sensors():
    U = _readings()
    g = SensorGuard().fit(U[:2000])
    assert not g.flags(U).any()
    assert np.array_equal(g.clean(U), U)                       # passes through untouched
    noisy = SensorFaults.of(sensor_noise=0.1).apply(U, seed=1)
    assert g.flags(noisy).mean() < 0.01                        # noise on all is not "dead"


def test_flags_dead_sensors_after_one_window_and_imputes():
    U = _readings()
    g = SensorGuard(SensorGuardParams(window=25)).fit(U[:2000])
    F = SensorFaults.of({1: "stuck0", 4: "noise", 6: "stuck1"}, start=2000)
    V = F.apply(U, seed=2)
    fl = g.flags(V)
    assert not fl[:2000].any()
    after = fl[2000 + 25:]
    assert after[:, [1, 4, 6]].all() and not after[:, [0, 2, 3, 5, 7]].any()
    C = g.clean(V)
    err_raw = np.abs(V[2025:, [1, 4, 6]] - U[2025:, [1, 4, 6]]).mean()
    err_imp = np.abs(C[2025:, [1, 4, 6]] - U[2025:, [1, 4, 6]]).mean()
    assert err_imp < 0.25 * err_raw                            # much closer to the truth
    assert np.array_equal(C[:, [0, 2, 3, 5, 7]], V[:, [0, 2, 3, 5, 7]])


def test_conditional_mean_is_exact_for_a_linear_copy():
    rng = np.random.default_rng(0)
    a = rng.uniform(0.2, 0.8, 2000)
    U = np.column_stack([a, rng.uniform(0.2, 0.8, 2000), 0.5 * a + 0.2])
    g = SensorGuard(SensorGuardParams(ridge=0.0)).fit(U)
    flags = np.zeros_like(U, bool)
    flags[:, 2] = True
    assert np.allclose(g.impute(U, flags)[:, 2], U[:, 2], atol=1e-9)


def test_step_matches_clean_and_errors():
    U = _readings(400)
    V = SensorFaults.of({3: "stuck1"}, start=100).apply(U)
    g = SensorGuard().fit(U[:300])
    online = np.array([g.step(u) for u in V])
    assert np.allclose(online, g.clean(V))
    with pytest.raises(RuntimeError, match="fit"):
        SensorGuard().clean(U)
    with pytest.raises(ValueError, match="sensors"):
        g.clean(U[:, :5])
    with pytest.raises(ValueError, match="window"):
        SensorGuardParams(window=1)


def test_params_are_checked_field_by_field():
    for field, bad in (("window", 2.5), ("window", np.nan), ("window", True), ("max_dead", 1.7),
                       ("stuck_tol", "x"), ("noise_ratio", np.inf), ("ridge", None)):
        with pytest.raises(ValueError, match=f"SensorGuardParams.{field} must be"):
            SensorGuardParams(**{field: bad})
    for field, bad in (("window", 10**12), ("window", 1), ("max_dead", -1),
                       ("noise_floor", -0.1)):
        with pytest.raises(ValueError, match=field):
            SensorGuardParams(**{field: bad})
    assert SensorGuardParams(window=100_000).window == 100_000
    with pytest.raises(TypeError, match="params must be SensorGuardParams"):
        SensorGuard(params={"window": 3})
    with pytest.raises(ValueError, match="at least 1 sensor"):
        SensorGuard().fit(np.zeros((10, 0)))
