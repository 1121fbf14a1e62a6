"""The decimator's rules on hand-worked cases: the taps (a Hamming-windowed sinc written out
with numpy, unit DC gain, 2·factor + 1 of them), the group delay, the decimation instants
``factor-1, 2·factor-1, ...`` offline and online for several factors, the convolution
``y[k] = Σ_j h[j] u[t_k - j]`` as an explicit loop, the zero-order hold, and every refusal
word for word."""

from __future__ import annotations

import re

import numpy as np
import pytest

from hippo.perception.resample import Decimator, antialias_taps, hold


def _hand_taps(n: int, factor: int) -> np.ndarray:
    """A Hamming-windowed sinc low-pass with cut-off 1/factor of Nyquist, written out (not
    scipy): h[m] = c·sinc(c·(m - (n-1)/2))·hamming[m], scaled to sum 1."""
    c = 1.0 / factor
    m = np.arange(n) - (n - 1) / 2
    h = c * np.sinc(c * m) * np.hamming(n)
    return h / h.sum()


def _hand_decimate(U: np.ndarray, h: np.ndarray, factor: int) -> np.ndarray:
    """y[k] = Σ_j h[j] u[t_k - j], t_k = (k+1)·factor - 1, u[t] = 0 for t < 0: a plain loop."""
    T, n = U.shape
    out = np.zeros((T // factor, n))
    for k in range(T // factor):
        t = (k + 1) * factor - 1
        for j in range(h.size):
            if t - j >= 0:
                out[k] += h[j] * U[t - j]
    return out


def test_taps_are_the_windowed_sinc_with_2_factor_plus_1_taps():
    assert antialias_taps(1).shape == (1,) and antialias_taps(1)[0] == 1.0
    for factor in (2, 3, 5):
        taps = antialias_taps(factor)
        assert taps.shape == (2 * factor + 1,)
        np.testing.assert_allclose(taps, _hand_taps(2 * factor + 1, factor), rtol=0,
                                   atol=1e-15)
        assert abs(taps.sum() - 1.0) < 1e-14                # unit DC gain
    # an explicit tap count, the smallest (1) included
    np.testing.assert_allclose(antialias_taps(3, numtaps=9), _hand_taps(9, 3), atol=1e-15)
    assert antialias_taps(2, numtaps=1).tolist() == [1.0]
    d = Decimator(3, numtaps=9)
    assert d.taps.shape == (9,) and d.delay == 4.0       # (9 - 1) / 2
    # default: 2·factor + 1 taps, group delay factor ticks
    for factor in (2, 3, 4):
        d = Decimator(factor)
        assert d.taps.size == 2 * factor + 1 and d.delay == float(factor)
    assert Decimator(1).delay == 0.0


def test_offline_and_online_follow_the_convolution_and_the_instants():
    U = np.random.default_rng(3).uniform(size=(17, 2))
    for factor in (2, 3, 4):
        d = Decimator(factor)
        want = _hand_decimate(U, _hand_taps(2 * factor + 1, factor), factor)
        np.testing.assert_allclose(d.offline(U), want, rtol=0, atol=1e-14)
        got = [(t, y) for t, y in enumerate(d.push(u) for u in U) if y is not None]
        # an output after each block of factor inputs: ticks factor-1, 2·factor-1, ...
        assert [t for t, _ in got] == list(range(factor - 1, 17, factor))
        assert [t for t, _ in got] == d.sample_ticks(17).tolist()
        np.testing.assert_allclose([y for _, y in got], want, rtol=0, atol=1e-14)
    # factor 1: the identity, a copy
    V = Decimator(1).offline(U)
    assert np.array_equal(V, U) and V is not U


def test_sample_ticks_by_hand():
    assert Decimator(3).sample_ticks(10).tolist() == [2, 5, 8]
    assert Decimator(3).sample_ticks(9).tolist() == [2, 5, 8]
    assert Decimator(3).sample_ticks(2).tolist() == []
    assert Decimator(4).sample_ticks(13).tolist() == [3, 7, 11]
    assert Decimator(1).sample_ticks(3).tolist() == [0, 1, 2]


def test_reset_forgets_the_history():
    d = Decimator(2)
    for u in np.ones((3, 1)):
        d.push(u)
    d.reset()
    # after a reset the first output is taken at the second push, from zeros before it
    assert d.push(np.array([1.0])) is None
    y = d.push(np.array([1.0]))
    h = _hand_taps(5, 2)
    np.testing.assert_allclose(y, [h[0] + h[1]], rtol=0, atol=1e-15)


def test_hold_by_hand():
    Y = np.array([[1.0], [2.0], [3.0]], dtype=np.float32)
    init = np.array([9.0])
    # factor 3: tick t holds output (t+1)//3 - 1; ticks 0, 1 hold the initial value; the
    # last output is held past its own block (ticks 11, 12)
    out = hold(Y, 13, 3, init)
    assert out[:, 0].tolist() == [9, 9, 1, 1, 1, 2, 2, 2, 3, 3, 3, 3, 3]
    assert out.dtype == np.float32
    out2 = hold(np.array([[1.0, -1.0], [2.0, -2.0]]), 5, 2, np.zeros(2))
    assert out2.tolist() == [[0, 0], [1, -1], [1, -1], [2, -2], [2, -2]]
    Z = np.arange(6.0)[:, None]
    one = hold(Z, 4, 1, np.zeros(1))
    assert one[:, 0].tolist() == [0, 1, 2, 3] and not np.shares_memory(one, Z)


def test_refusals_word_for_word():
    for call in (lambda: antialias_taps(0), lambda: Decimator(0), lambda: Decimator(-2)):
        with pytest.raises(ValueError, match=r"^downsample factor must be an integer >= 1, "
                                             r"got -?\d$"):
            call()
    for call in (lambda: antialias_taps(2, numtaps=0), lambda: Decimator(2, numtaps=0)):
        with pytest.raises(ValueError, match=r"^numtaps must be an integer >= 1, got 0$"):
            call()
    with pytest.raises(ValueError, match=r"^numtaps must be an integer, got 4.5 \(float\)$"):
        antialias_taps(2, numtaps=4.5)
    d = Decimator(2)
    with pytest.raises(ValueError, match=re.escape(
            "input U must be (T, n) (one row a tick), got shape (10,)")):
        d.offline(np.ones(10))
    with pytest.raises(ValueError, match=re.escape("reading u must be 1-D, got shape (2, 2)")):
        d.push(np.ones((2, 2)))


def test_hold_refuses_a_factor_below_one():
    for bad in (0, -2):
        with pytest.raises(ValueError, match="factor"):
            hold(np.zeros((3, 2)), 6, bad, np.zeros(2))
    # factor 2 over 6 ticks: instants at ticks 1, 3, 5 (k = (t + 1) // 2 - 1), tick 0 initial
    out = hold(np.arange(6.0).reshape(3, 2), 6, 2, np.array([-1.0, -1.0]))
    np.testing.assert_array_equal(out[:, 0], [-1, 0, 0, 2, 2, 4])
