"""The sensor guard's rules on designed readings with known answers: a sensor stuck when its
window's range is below ``stuck_tol`` (exactly at it: live), noise-only when its mean squared
change exceeds ``noise_ratio`` times the tick's median and ``noise_floor`` (exactly at either:
live), the first flag exactly at the first full window, the per-tick median, the ``max_dead``
most suspect sensors kept (ties to the lowest index), the conditional mean with its ridge and
its clip to [0, 1], the online step, and the exact texts of its errors.

Readings alternate between two dyadic values, so every range and mean squared change below is
exact in floating point and worked out by hand: ``0.5, 0.5 + a, 0.5, ...`` has range ``a`` and
mean squared change ``a**2``."""

from __future__ import annotations

import numpy as np
import pytest

from hippo.perception.sensor_guard import SensorGuard, SensorGuardParams


def _exactly(exc: type[Exception], text: str):
    """``pytest.raises`` matching the whole message, word for word."""
    import re

    return pytest.raises(exc, match="^" + re.escape(text) + "$")


def _alternating(T: int, amp: float, base: float = 0.5) -> np.ndarray:
    """base, base + amp, base, ...: range amp, every change +-amp, mean squared change amp**2."""
    return base + amp * (np.arange(T) % 2)


def _fitted(n: int, params: SensorGuardParams | None = None, seed: int = 0) -> SensorGuard:
    """A guard fitted on random clean readings of ``n`` sensors (detection does not use them)."""
    U = np.random.default_rng(seed).uniform(0.2, 0.8, (200, n))
    return SensorGuard(params).fit(U)


# ------------------------------------------------------------------ parameters
def test_parameter_edges_are_inclusive_and_named_word_for_word():
    assert SensorGuardParams(window=2).window == 2                       # lo = 2 allowed
    with _exactly(ValueError, "window must be an integer in [2, 100000], got 1"):
        SensorGuardParams(window=1)
    with _exactly(ValueError, "window must be an integer in [2, 100000], got 100001"):
        SensorGuardParams(window=100_001)
    assert SensorGuardParams(max_dead=0).max_dead == 0                   # lo = 0 allowed
    with _exactly(ValueError, "max_dead must be an integer >= 0, got -1"):
        SensorGuardParams(max_dead=-1)
    for name in ("stuck_tol", "noise_ratio", "noise_floor", "ridge"):
        assert getattr(SensorGuardParams(**{name: 0.0}), name) == 0.0   # 0 allowed
        with _exactly(ValueError, f"{name} must be finite and >= 0, got -0.5"):
            SensorGuardParams(**{name: -0.5})
    with _exactly(TypeError, "params must be SensorGuardParams, got dict"):
        SensorGuard(params={"window": 3})  # type: ignore[arg-type]


# ------------------------------------------------------------------ fit and checks
def test_fit_learns_the_mean_and_the_ridged_covariance():
    rng = np.random.default_rng(3)
    U = rng.uniform(0.0, 1.0, (50, 3))
    g = SensorGuard(SensorGuardParams(ridge=0.5)).fit(U)
    # numpy's unbiased covariance of the columns, plus 0.5 on the diagonal
    np.testing.assert_allclose(g.mean_, U.sum(axis=0) / 50, rtol=1e-12)
    centred = U - U.mean(axis=0)
    np.testing.assert_allclose(g.cov_, centred.T @ centred / 49 + 0.5 * np.eye(3), rtol=1e-12)
    assert g.n_sensors_ == 3
    # the fewest readings (2) and sensors (1): a (1, 1) covariance, (a - b)^2 / 2 + ridge
    one = SensorGuard(SensorGuardParams(ridge=0.25)).fit(np.array([[0.25], [0.75]]))
    np.testing.assert_allclose(one.cov_, [[0.125 + 0.25]], rtol=1e-15)
    np.testing.assert_array_equal(one.mean_, [0.5])


def test_fit_clean_and_step_refuse_bad_input_word_for_word():
    with _exactly(ValueError, "SensorGuard.fit needs at least 2 readings"):
        SensorGuard().fit(np.zeros((1, 3)))
    with _exactly(ValueError, "SensorGuard.fit needs at least 1 sensor, got U of shape (10, 0)"):
        SensorGuard().fit(np.zeros((10, 0)))
    with _exactly(ValueError, "sensor matrix U must be (T, n_sensors), got shape (5,)"):
        SensorGuard().fit(np.zeros(5))
    bad = np.full((4, 3), 0.5)
    bad[2, 1] = np.nan
    with _exactly(ValueError, "sensor matrix U contains 1 non-finite value(s) (NaN or inf)"):
        SensorGuard().fit(bad)
    not_fitted = "SensorGuard is not fitted yet; call fit(U) first"
    with _exactly(RuntimeError, not_fitted):
        SensorGuard().clean(np.zeros((5, 3)))
    with _exactly(RuntimeError, not_fitted):
        SensorGuard().step(np.zeros(3))
    g = _fitted(3)
    with _exactly(ValueError, "sensor matrix U contains 1 non-finite value(s) (NaN or inf)"):
        g.clean(bad)
    with _exactly(ValueError, "U has 2 sensors, the guard was fitted on 3"):
        g.flags(np.zeros((5, 2)))
    with _exactly(ValueError, "reading must have shape (3,), got (2,)"):
        g.step(np.zeros(2))
    with _exactly(ValueError, "flags must have shape (4, 3), got (4, 2)"):
        g.impute(np.zeros((4, 3)), np.zeros((4, 2), bool))


# ------------------------------------------------------------------ detection
def test_stuck_is_a_range_below_stuck_tol_from_the_first_full_window():
    """Window 4, stuck_tol 0.25 (noise detection off: floor 100). Ranges 0.25 (exactly the
    tolerance: live), 0.125 (stuck) and 0.5 (live). With T == window only the last row has a
    full window; it alone is flagged."""
    p = SensorGuardParams(window=4, stuck_tol=0.25, noise_floor=100.0)
    g = _fitted(3, p)
    U = np.column_stack([_alternating(4, 0.25), _alternating(4, 0.125), _alternating(4, 0.5)])
    want = np.zeros((4, 3), bool)
    want[3, 1] = True
    np.testing.assert_array_equal(g.flags(U), want)
    # one reading short of a window: nothing flagged, a boolean (T, n) array
    short = g.flags(U[:3])
    assert short.dtype == bool and short.shape == (3, 3) and not short.any()
    # one tick later the stuck sensor is still flagged, and at row 3 too
    U5 = np.column_stack([_alternating(5, 0.25), _alternating(5, 0.125), _alternating(5, 0.5)])
    np.testing.assert_array_equal(g.flags(U5)[:, 1], [False, False, False, True, True])


def test_noise_is_strictly_above_ratio_times_median_and_the_floor():
    """Mean squared changes 1/16, 1/64, 1/256: the tick's median is 1/64. With noise_ratio 4
    the first sensor's 1/16 is exactly 4 x the median (live); with 3.75 it is above (noisy).
    With noise_ratio 2 a floor of exactly 1/16 keeps it live, a floor just under flags it."""
    U = np.column_stack([_alternating(6, 0.25), _alternating(6, 0.125),
                         _alternating(6, 0.0625)])
    full = np.arange(6) >= 4

    def flagged(ratio: float, floor: float) -> np.ndarray:
        g = _fitted(3, SensorGuardParams(window=5, stuck_tol=0.0, noise_ratio=ratio,
                                         noise_floor=floor))
        return g.flags(U)

    assert not flagged(4.0, 0.0).any()
    np.testing.assert_array_equal(flagged(3.75, 0.0)[:, 0], full)
    assert not flagged(3.75, 0.0)[:, 1:].any()
    assert not flagged(2.0, 1 / 16).any()
    np.testing.assert_array_equal(flagged(2.0, np.nextafter(1 / 16, 0))[:, 0], full)


def test_the_median_is_the_ticks_own():
    """Every sensor's noise rises together half-way: each tick's median rises with it, so no
    sensor is flagged (a median over the whole recording, calm for most of it, would flag all
    four sensors once they are noisy: 1/16 > 8 x 1/4096 and > 0.02)."""
    calm = np.column_stack([_alternating(60, 1 / 64)] * 4)
    loud = np.column_stack([_alternating(20, 0.25)] * 4)
    g = _fitted(4, SensorGuardParams(window=3))
    assert not g.flags(np.vstack([calm, loud])).any()


def test_max_dead_keeps_the_most_suspect_sensors():
    """Sensor 0 stuck (score 1), sensors 1 and 2 noisy (mean squared changes 1/16 and 1/4,
    scores 1 + those), five calm sensors (1/4096, the median). With max_dead = 2 the two
    noisiest are kept; with max_dead = 3 all three; with 0 none."""
    calm = [_alternating(8, 1 / 64)] * 5
    U = np.column_stack([np.full(8, 0.3), _alternating(8, 0.25), _alternating(8, 0.5), *calm])
    full = np.arange(8) >= 4
    for max_dead, dead in ((2, [1, 2]), (3, [0, 1, 2]), (0, [])):
        g = _fitted(8, SensorGuardParams(window=5, noise_ratio=4.0, noise_floor=0.0,
                                         max_dead=max_dead))
        want = np.zeros((8, 8), bool)
        want[np.ix_(full, dead)] = True
        np.testing.assert_array_equal(g.flags(U), want)


def test_max_dead_breaks_ties_to_the_lowest_sensor():
    """Sensors 4-7 stuck at different values (each score 1, a tie), 0-3 live and calm: with
    max_dead = 2 the stable order keeps sensors 4 and 5, never a live one."""
    live = [_alternating(6, 1 / 64)] * 4
    stuck = [np.full(6, v) for v in (0.1, 0.2, 0.3, 0.4)]
    g = _fitted(8, SensorGuardParams(window=5, max_dead=2))
    fl = g.flags(np.column_stack(live + stuck))
    want = np.zeros((6, 8), bool)
    want[4:, [4, 5]] = True
    np.testing.assert_array_equal(fl, want)


# ------------------------------------------------------------------ imputation
def test_imputation_is_the_conditional_mean_for_each_pattern_of_dead_sensors():
    """û_D = μ_D + (u_A - μ_A) Σ_AA⁻¹ Σ_AD, computed here with an explicit inverse of numpy's
    covariance plus the ridge, for three patterns in one call; all sensors dead: μ."""
    rng = np.random.default_rng(5)
    z = rng.uniform(0.3, 0.7, 300)
    U = np.column_stack([z, 0.8 * z + 0.05 * rng.uniform(0, 1, 300),
                         0.5 - 0.3 * (z - 0.5) + 0.05 * rng.uniform(0, 1, 300)])
    ridge = 1e-3
    g = SensorGuard(SensorGuardParams(ridge=ridge)).fit(U)
    mu, S = U.mean(axis=0), np.cov(U.T) + ridge * np.eye(3)
    V = rng.uniform(0.35, 0.65, (5, 3))
    flags = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 1], [1, 1, 1], [1, 0, 0]], bool)
    want = V.copy()
    for r, dead in ((1, [0]), (2, [1, 2]), (4, [0])):
        live = [i for i in range(3) if i not in dead]
        gain = np.linalg.inv(S[np.ix_(live, live)]) @ S[np.ix_(live, dead)]
        want[r, dead] = mu[dead] + (V[r, live] - mu[live]) @ gain
    want[3] = mu
    assert np.all((want >= 0) & (want <= 1))
    np.testing.assert_allclose(g.impute(V, flags), want, rtol=1e-10)
    np.testing.assert_array_equal(g.impute(V, np.zeros((5, 3), bool)), V)


def test_imputed_readings_are_clipped_to_the_unit_interval():
    """Trained on u1 = 1.5 u0 - 0.25 exactly (ridge 0): u0 = 0.9 predicts 1.1 (clipped to 1),
    u0 = 0.1 predicts -0.1 (clipped to 0), u0 = 0.5 predicts 0.5."""
    u0 = np.linspace(0.2, 0.8, 101)
    g = SensorGuard(SensorGuardParams(ridge=0.0)).fit(np.column_stack([u0, 1.5 * u0 - 0.25]))
    V = np.array([[0.9, 0.3], [0.1, 0.3], [0.5, 0.3]])
    out = g.impute(V, np.array([[False, True]] * 3))
    np.testing.assert_array_equal(out[:, 0], V[:, 0])
    assert out[0, 1] == 1.0 and out[1, 1] == 0.0
    assert out[2, 1] == pytest.approx(0.5, abs=1e-12)


# ------------------------------------------------------------------ online
def test_step_flags_from_its_own_window_and_copies_the_reading():
    """A stuck-at-0 sensor and a noisy one among two calm ones, fed through one reused buffer
    (as a robot's driver fills it): from the fifth reading on, sensors 0 and 1 are imputed
    exactly as impute() does with those flags (range 0; 1/16 > 8 x the median 1/4096 and
    > 0.02); before that, the reading passes through as a new float array."""
    g = _fitted(4, SensorGuardParams(window=5))
    T = 9
    V = np.column_stack([np.zeros(T), _alternating(T, 0.25), _alternating(T, 1 / 64, 0.3),
                         _alternating(T, 1 / 64, 0.6)])
    want_flags = np.zeros((T, 4), bool)
    want_flags[4:, :2] = True
    want = g.impute(V, want_flags)
    assert not np.array_equal(want[4:, :2], V[4:, :2])
    buf = np.empty(4)
    out = []
    for row in V:
        buf[:] = row
        out.append(g.step(buf))
    np.testing.assert_array_equal(np.array(out), want)
    np.testing.assert_array_equal(np.array(out), g.clean(V))
    g.reset()
    first = g.step([0, 1, 1, 0])                       # integers in, floats out
    assert first.dtype == np.float64 and first.tolist() == [0.0, 1.0, 1.0, 0.0]


def test_step_refuses_a_non_finite_reading_as_clean_does():
    """step is clean row by row: a NaN or inf reading is refused with the same words (it used
    to pass through and sit in the window's history, its range and change NaN, for ``window``
    ticks), and a refused reading is not kept: the next readings are guarded as if it never
    came."""
    g = _fitted(3, SensorGuardParams(window=2))
    with _exactly(ValueError, "sensor matrix U contains 1 non-finite value(s) (NaN or inf)"):
        g.clean(np.array([[np.nan, 0.5, 0.5]]))
    V = np.array([[0.25, 0.5, 0.75], [0.25, 0.625, 0.5]])     # sensor 0 stuck over 2 ticks
    first = g.step(V[0])
    with _exactly(ValueError, "reading contains 1 non-finite value(s) (NaN or inf)"):
        g.step(np.array([np.nan, 0.5, 0.5]))
    with _exactly(ValueError, "reading contains 2 non-finite value(s) (NaN or inf)"):
        g.step([0.5, np.inf, np.nan])
    second = g.step(V[1])
    np.testing.assert_array_equal(np.array([first, second]), g.clean(V))
    assert second[0] != 0.25                                     # imputed: the window was full
