"""The slow pool's rules with known answers: the time constant's edges and exact error texts,
the pool run in float64 from a given state (float32 input and state included), the empty
recording, and the online pool's float64 update. The expected pools are the module
docstring's recurrence m(t) = (1 - 1/tau) m(t-1) + (1/tau) z(t), written out here as a loop in
float64."""

from __future__ import annotations

import re

import numpy as np
import pytest

from hippo.perception.slow_pool import SlowPool, check_slow_pool, with_pool


def _exactly(exc: type[Exception], text: str):
    return pytest.raises(exc, match="^" + re.escape(text) + "$")


def _recurrence(Z: np.ndarray, tau: float, m0: np.ndarray) -> np.ndarray:
    """The pool equation as a float64 loop from m(-1) = m0."""
    beta = 1.0 / tau
    m = np.asarray(m0, dtype=np.float64).copy()
    out = np.empty(Z.shape, dtype=np.float64)
    for t, z in enumerate(np.asarray(Z, dtype=np.float64)):
        m = (1.0 - beta) * m + beta * z
        out[t] = m
    return out


def test_time_constant_edges_and_messages():
    for ok in (1, 1.0, np.int64(1), np.float32(1.0), 0, 0.0):
        v = check_slow_pool(ok)
        assert type(v) is float and v == float(ok)
    with _exactly(ValueError, "slow_pool must be 0 (off) or a time constant >= 1 tick, "
                              "got 0.9999999999999999"):
        check_slow_pool(float(np.nextafter(1.0, 0.0)))  # one step below 1
    with _exactly(ValueError, "slow_pool must be a number of ticks (0 = off), got '100'"):
        check_slow_pool("100")
    # a numpy scalar is shown as the number it holds, not as np.float64(0.5)
    with _exactly(ValueError, "slow_pool must be 0 (off) or a time constant >= 1 tick, "
                              "got 0.5"):
        check_slow_pool(np.float64(0.5))
    with _exactly(ValueError, "tau must be 0 (off) or a time constant >= 1 tick, got -2"):
        with_pool(np.ones((3, 2)), -2)
    with _exactly(ValueError, "slow_pool: an online pool needs a time constant >= 1 tick, "
                              "got 0"):
        SlowPool(0, 3)
    with _exactly(ValueError, "slow_pool must be 0 (off) or a time constant >= 1 tick, "
                              "got 0.5"):
        SlowPool(0.5, 3)


def test_pool_from_a_float32_state_is_computed_in_float64():
    """A float32 state: the pool is the float64 recurrence from the float64 value of the state
    (a float32 product (1 - 1/3) m0 would be off by ~1e-8 in the first rows). float32
    features: the pool is returned in float32 next to the unchanged features; the last state
    is float64."""
    rng = np.random.default_rng(7)
    Z = rng.standard_normal((40, 3))
    m0 = np.array([0.1, 0.7, -0.3], dtype=np.float32)
    want = _recurrence(Z, 3.0, m0)
    # the first row by hand: (2/3) m0 + (1/3) z(0)
    np.testing.assert_allclose(want[0], (2 / 3) * m0.astype(float) + Z[0] / 3, rtol=1e-14)
    F, last = with_pool(Z, 3.0, m0)
    assert F.dtype == np.float64 and F.shape == (40, 6)
    np.testing.assert_array_equal(F[:, :3], Z)
    np.testing.assert_allclose(F[:, 3:], want, rtol=1e-13, atol=1e-15)
    Z32 = Z.astype(np.float32)
    F, last = with_pool(Z32, 3.0, m0)
    assert F.dtype == np.float32 and last.dtype == np.float64
    np.testing.assert_array_equal(F[:, :3], Z32)
    want32 = _recurrence(Z32, 3.0, m0)
    np.testing.assert_allclose(F[:, 3:], want32, rtol=1e-6, atol=1e-7)     # float32's rounding
    np.testing.assert_allclose(last, want32[-1], rtol=1e-13, atol=1e-15)


def test_an_empty_recording_leaves_the_state_where_it_was():
    Z = np.zeros((0, 3))
    F, last = with_pool(Z, 5.0)
    assert F.shape == (0, 6)
    np.testing.assert_array_equal(last, np.zeros(3))
    m0 = np.array([0.25, -1.5, 3.0], dtype=np.float32)
    F, last = with_pool(Z, 5.0, m0)
    assert F.shape == (0, 6) and last.dtype == np.float64
    np.testing.assert_array_equal(last, [0.25, -1.5, 3.0])
    last[0] = 9.0                                        # a copy: the caller's state is kept
    assert m0[0] == 0.25


def test_online_pool_updates_in_float64():
    """float32 readings into the online pool: m = (1 - 1/3) m + (1/3) z in float64 (a float32
    product (1/3) z would differ by ~1e-9)."""
    rng = np.random.default_rng(8)
    Z = rng.standard_normal((30, 4)).astype(np.float32)
    pool = SlowPool(3.0, 4)
    got = np.array([pool.step(z).copy() for z in Z])
    assert pool.m.dtype == np.float64
    np.testing.assert_allclose(got, _recurrence(Z, 3.0, np.zeros(4)), rtol=1e-13, atol=1e-15)
