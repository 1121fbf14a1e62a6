"""Fault injection: each mode does exactly what its spec says."""

import numpy as np
import pytest

from hippo.sim.faults import FaultInjector, SensorFaults, with_faults
from hippo.sim.record import Recording


def _U(T=200, n=8, seed=0):
    return np.random.default_rng(seed).uniform(0.1, 0.9, (T, n))


def test_dead_modes_and_start():
    U = _U()
    F = SensorFaults.of({1: "stuck0", 3: "stuck1", 5: "noise"}, start=50)
    V = F.apply(U, seed=3)
    assert np.array_equal(V[:50], U[:50])                      # healthy before the start
    assert np.all(V[50:, 1] == 0.0) and np.all(V[50:, 3] == 1.0)
    live = [0, 2, 4, 6, 7]
    assert np.array_equal(V[:, live], U[:, live])              # others untouched (no noise)
    noise = V[50:, 5]
    assert 0.0 <= noise.min() and noise.max() <= 1.0
    assert abs(noise.mean() - 0.5) < 0.06 and abs(noise.var() - 1 / 12) < 0.02
    assert abs(np.corrcoef(noise, U[50:, 5])[0, 1]) < 0.25     # carries no signal
    assert np.array_equal(F.apply(U, seed=3), V)               # same seed, same faults
    assert F.indices == [1, 3, 5]


def test_sensor_noise_sd_and_clip():
    U = np.full((20000, 2), 0.5)
    V = SensorFaults.of(sensor_noise=0.1).apply(U, seed=1)
    assert abs((V - U).std() - 0.1) < 0.003 and abs((V - U).mean()) < 0.003
    W = SensorFaults.of(sensor_noise=0.5).apply(np.zeros((1000, 2)), seed=1)
    assert W.min() == 0.0 and W.max() <= 1.0 and (W > 0).mean() > 0.4


def test_index_forms_and_errors():
    assert SensorFaults.of([2, 0]).dead == ((0, "stuck0"), (2, "stuck0"))
    assert SensorFaults.of([(4, "noise")]).dead == ((4, "noise"),)
    with pytest.raises(ValueError, match="mode"):
        SensorFaults.of({0: "broken"})
    with pytest.raises(ValueError, match="twice"):
        SensorFaults.of([(1, "stuck0"), (1, "stuck1")])
    with pytest.raises(ValueError, match="sensor_noise"):
        SensorFaults.of(sensor_noise=-0.1)
    with pytest.raises(ValueError, match="out of range"):
        SensorFaults.of([9]).apply(_U())


def test_online_injector_matches_its_spec():
    U = _U(60)
    inj = FaultInjector(SensorFaults.of({0: "stuck1"}, sensor_noise=0.0, start=10), seed=0)
    V = np.array([inj(u) for u in U])
    assert np.array_equal(V[:10], U[:10]) and np.all(V[10:, 0] == 1.0)
    assert np.array_equal(V[:, 1:], U[:, 1:])


def test_with_faults_keeps_the_ground_truth():
    T = 30
    rec = Recording("a", "ir8", 0.2, 0, np.arange(T) * 0.2, _U(T), np.zeros(T), np.ones(T),
                    np.zeros(T), np.zeros(T), np.zeros(T, np.int16), np.zeros(T, np.int16),
                    np.zeros(T, np.int16), ["r"])
    bad = with_faults(rec, {2: "stuck0"}, seed=0)
    assert np.all(bad.sensors[:, 2] == 0) and np.array_equal(bad.y, rec.y)
    assert np.array_equal(rec.sensors, _U(T))                  # the original is unchanged


def test_fault_specs_are_checked_not_coerced():
    bad = {
        "dead sensor index must be an integer": [[1.7], [True], [(2.0, "noise")], {1.5: "stuck0"},
                                                 ["1"]],
        "dead sensor index must be an integer >= 0": [[-1]],
        "dead_sensors must be": ["012", 3],
        r"dead_sensors entries must be \(index, mode\)": [[(2, "noise", "x")], [(2,)]],
        "mode for sensor 1": [[(1, 0)], {1: None}],
    }
    for match, specs in bad.items():
        for spec in specs:
            with pytest.raises(ValueError, match=match):
                SensorFaults.of(spec)
    for noise in (True, "0.1", np.nan, -0.1):
        with pytest.raises(ValueError, match="sensor_noise"):
            SensorFaults.of(sensor_noise=noise)
    for start in (2.5, np.nan, "3", -1, True):
        with pytest.raises(ValueError, match="start"):
            SensorFaults.of(start=start)
        with pytest.raises(ValueError, match="start"):
            SensorFaults(start=start)
    with pytest.raises(ValueError, match="index must be an integer"):
        SensorFaults(dead=((True, "stuck0"),))
    with pytest.raises(ValueError, match=r"entries must be \(index, mode\) tuples"):
        SensorFaults(dead=([1, "stuck0"],))
    with pytest.raises(TypeError, match="faults must be SensorFaults"):
        FaultInjector({1: "stuck0"})
    # the accepted forms, numpy integers and [index, mode] lists included
    F = SensorFaults.of([np.int64(3), [1, "noise"]], sensor_noise=np.float64(0.1), start=np.int8(2))
    assert F.dead == ((1, "noise"), (3, "stuck0")) and type(F.dead[1][0]) is int
    assert F.sensor_noise == 0.1 and F.start == 2


@pytest.mark.parametrize(("seed", "match"), [
    (-1, r"^seed must be an integer in \[0, "), (1.5, r"^seed must be an integer, got 1.5"),
])
def test_a_bad_fault_seed_is_named(seed, match):
    # fifth fuzzing pass: numpy's SeedSequence message, naming no argument
    F, U = SensorFaults.of({1: "noise"}, sensor_noise=0.1), np.full((20, 3), 0.5)
    with pytest.raises(ValueError, match=match):
        F.apply(U, seed=seed)
    with pytest.raises(ValueError, match=match):
        FaultInjector(F, seed=seed)
    # an integer seed and a generator seed the noise as before
    assert np.array_equal(F.apply(U, seed=7), F.apply(U, np.random.default_rng(7)))
    rng = np.random.default_rng(7)
    want = np.clip(U + rng.normal(0.0, 0.1, U.shape), 0.0, 1.0)
    want[:, 1] = rng.uniform(0.0, 1.0, 20)
    assert np.array_equal(F.apply(U, seed=7), want)
