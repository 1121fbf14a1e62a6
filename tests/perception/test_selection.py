"""Held-out slowness: the analytic value on a sine, and the right choice on a synthetic slow
source."""

import numpy as np
import pytest

from hippo.perception import RCSFAICA
from hippo.perception.selection import (
    heldout_slowness,
    normalised_slowness,
    rank_correlation,
    select_leak,
)


def test_normalised_slowness_analytic():
    P = 400
    t = np.arange(40 * P)
    y = np.column_stack([np.sin(2 * np.pi * t / P), np.random.default_rng(0).normal(size=t.size)])
    d = normalised_slowness(y)
    assert d[0] == pytest.approx(2 * (1 - np.cos(2 * np.pi / P)), rel=1e-3)
    assert d[1] == pytest.approx(2.0, rel=0.03)
    with pytest.raises(ValueError):
        normalised_slowness(np.zeros((2, 1)))


def _slow_source(T=6000, seed=0):
    """8 inputs: a slow square-ish source (switching every ~300 ticks, like a room) seen only
    through fast sign-flipping carriers, plus noise. A reservoir that integrates over ~tens of
    ticks recovers it; one with leak 1 (no memory) cannot."""
    rng = np.random.default_rng(seed)
    s = np.repeat(rng.integers(0, 2, T // 300 + 1), 300)[:T] * 2 - 1.0
    carrier = np.sign(rng.normal(size=(T, 1)))
    U = 0.5 + 0.2 * np.column_stack([s[:, None] * carrier * (1 + 0.1 * k) for k in range(4)]
                                    + [carrier * (1 - 0.1 * k) for k in range(4)])
    return np.clip(U + rng.normal(0, 0.02, U.shape), 0, 1), s


def test_select_leak_prefers_memory_on_a_slow_source():
    U, s = _slow_source()
    sel = select_leak(U, [1.0, 0.05], n_reservoir=80, n_sfa=2, n_ica=2, ica_restarts=1,
                      seed=0, input_weight=1.0, input_prob=0.3)
    assert sel.best_candidate == 0.05 and sel.scores[1] < sel.scores[0]
    # and the chosen model's slowest feature does carry the source
    Y = sel.models[1].transform(U, return_sfa=True)[1]
    assert abs(np.corrcoef(Y[1000:, 0], s[1000:])[0, 1]) > 0.7


def test_heldout_slowness_and_rank_correlation_checks():
    U, _ = _slow_source(1200)
    m = RCSFAICA.smc09(n_reservoir=30, n_sfa=2, n_ica=2, ica_restarts=1).fit(U[:1000])
    assert np.isfinite(heldout_slowness(m, U, 1000))
    with pytest.raises(ValueError, match="n_fit"):
        heldout_slowness(m, U, 1199)
    assert rank_correlation([3, 2, 1], [0.1, 0.2, 0.3]) == pytest.approx(1.0)
    assert rank_correlation([1, 2, 3], [0.1, 0.2, 0.3]) == pytest.approx(-1.0)
    with pytest.raises(ValueError):
        rank_correlation([1, 2], [1, 2])
