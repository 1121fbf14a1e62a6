"""The fault injection's rules on hand-worked cases: the noise drawn from the seed (an
independent numpy generator reproduces every draw, the default seed 0 included), no draw at
all without sensor noise, the online injector's single stream across ticks and its float
readings, with_faults passing each argument through, the index bound exactly at the sensor
count, and every refusal word for word."""

from __future__ import annotations

import re

import numpy as np
import pytest

from hippo.sim.faults import FaultInjector, SensorFaults, with_faults
from hippo.sim.record import Recording


def _U(T: int = 12, n: int = 4, seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).uniform(0.1, 0.9, (T, n))


def _rec(U: np.ndarray) -> Recording:
    T = U.shape[0]
    return Recording("a", "ir8", 0.2, 0, np.arange(T) * 0.2, U, np.zeros(T), np.ones(T),
                     np.zeros(T), np.zeros(T), np.zeros(T, np.int16), np.zeros(T, np.int16),
                     np.zeros(T, np.int16), ["r"])


def test_a_noise_sensor_without_sensor_noise_draws_only_its_uniforms():
    # sensor_noise = 0: no Gaussian draw before the dead sensor's uniform ones, so the column
    # is the seed's first T uniforms (an independent generator gives them)
    U = _U()
    V = SensorFaults.of({1: "noise"}).apply(U, seed=4)
    assert np.array_equal(V[:, 1], np.random.default_rng(4).uniform(0.0, 1.0, 12))
    assert np.array_equal(np.delete(V, 1, axis=1), np.delete(U, 1, axis=1))
    # the default seed is 0
    W = SensorFaults.of({1: "noise"}).apply(U)
    assert np.array_equal(W[:, 1], np.random.default_rng(0).uniform(0.0, 1.0, 12))
    # readings outside [0, 1] are not clipped when no noise is added
    big = np.full((3, 2), 1.5)
    assert np.array_equal(SensorFaults.of().apply(big), big)


def test_the_online_injector_draws_from_one_stream():
    # tick by tick, each reading's noise continues the same generator: the i-th faulty tick
    # gets the generator's i-th uniform (a new generator per tick would repeat the first)
    inj = FaultInjector(SensorFaults.of({0: "noise"}, start=2), seed=5)
    out = [inj(np.array([0.5, 0.25])) for _ in range(5)]
    rng = np.random.default_rng(5)
    want = [0.5, 0.5] + [rng.uniform(0.0, 1.0, 1)[0] for _ in range(3)]
    assert [o[0] for o in out] == want and all(o[1] == 0.25 for o in out)
    assert inj.tick == 5
    # the default seed is 0
    d = FaultInjector(SensorFaults.of({0: "noise"}))
    assert d(np.array([0.5]))[0] == np.random.default_rng(0).uniform(0.0, 1.0, 1)[0]
    # integer readings come back as floats, before the start as after it
    late = FaultInjector(SensorFaults.of(start=1))
    assert late(np.array([0, 1])).dtype == np.float64
    assert late(np.array([0, 1])).dtype == np.float64


def test_with_faults_passes_every_argument_on():
    U = _U(20)
    rec = _rec(U)
    # the defaults: no extra noise, from tick 0, seed 0 (a noise sensor shows the seed)
    bad = with_faults(rec, {2: "noise"})
    want = U.copy()
    want[:, 2] = np.random.default_rng(0).uniform(0.0, 1.0, 20)
    assert np.array_equal(bad.sensors, want)
    # sensor_noise, start and seed as given: the Gaussian draw on ticks >= start, clipped,
    # then the dead sensor's uniforms, from seed 9
    bad = with_faults(rec, {2: "stuck1"}, sensor_noise=0.05, start=6, seed=9)
    rng = np.random.default_rng(9)
    want = U.copy()
    want[6:] = np.clip(want[6:] + rng.normal(0.0, 0.05, (14, 4)), 0.0, 1.0)
    want[6:, 2] = 1.0
    assert np.array_equal(bad.sensors, want)


def test_the_index_bound_is_the_sensor_count():
    U = _U(5, 4)
    assert np.all(SensorFaults.of([3]).apply(U)[:, 3] == 0.0)   # the last sensor
    with pytest.raises(ValueError, match=re.escape(
            "dead sensor(s) [4] out of range for 4 sensors")):
        SensorFaults.of([4, 1]).apply(U)


def test_refusals_word_for_word():
    cases = [
        (lambda: SensorFaults.of({0: "broken"}),
         "dead sensor mode for sensor 0 must be one of stuck0, stuck1, noise; got 'broken'"),
        (lambda: SensorFaults.of("012"),
         "dead_sensors must be {index: mode}, a sequence of (index, mode) pairs or a sequence "
         "of indices, got '012'"),
        (lambda: SensorFaults.of(sensor_noise=np.nan), "sensor_noise must be finite, got nan"),
        (lambda: SensorFaults(sensor_noise=np.inf), "sensor_noise must be finite, got inf"),
        (lambda: SensorFaults(sensor_noise=-0.5),
         "sensor_noise must be a finite s.d. >= 0, got -0.5"),
        (lambda: SensorFaults.of(start=-1), "start must be an integer >= 0, got -1"),
        (lambda: SensorFaults(start=-2), "start must be an integer >= 0, got -2"),
        (lambda: SensorFaults(dead=[(1, "stuck0")]),
         "dead must be a tuple of (index, mode) pairs, got [(1, 'stuck0')]"),
        (lambda: SensorFaults.of([1]).apply(np.ones(4)),
         "sensor matrix U must be (T, n_sensors), got shape (4,)"),
        (lambda: SensorFaults.of([1]).apply(np.array([[np.nan, 1.0]])),
         "sensor matrix U contains 1 non-finite value(s) (NaN or inf)"),
        (lambda: FaultInjector(SensorFaults.of())(np.ones((2, 2))),
         "a reading must be a 1-D sensor vector, got shape (2, 2)"),
    ]
    for call, text in cases:
        with pytest.raises(ValueError, match=f"^{re.escape(text)}$"):
            call()
    with pytest.raises(TypeError, match="^" + re.escape(
            "faults must be SensorFaults (e.g. SensorFaults.of({1: 'stuck0'})), got dict") + "$"):
        FaultInjector({1: "stuck0"})


def test_a_non_finite_reading_is_refused_before_the_start_tick_too_and_counts_no_tick():
    inj = FaultInjector(SensorFaults.of({0: "stuck0"}, start=2), seed=0)
    bad = np.array([0.5, np.nan, 0.2])
    for _ in range(2):   # before the start tick as after it, and the tick does not move
        with pytest.raises(ValueError, match=re.escape(
                "sensor matrix U contains 1 non-finite value(s) (NaN or inf)")):
            inj(bad)
    assert inj.tick == 0
    u = np.array([0.5, 0.4, 0.2])
    np.testing.assert_array_equal(inj(u), u)          # tick 0, 1: before the fault starts
    np.testing.assert_array_equal(inj(u), u)
    assert inj(u)[0] == 0.0                           # tick 2: sensor 0 stuck at 0
