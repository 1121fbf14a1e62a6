"""The washout of the start from rest: ``RCSFAICAParams.transient_updates`` and what it buys."""

import warnings
from dataclasses import replace

import numpy as np
import pytest

from hippo.perception import ICANN09, RCSFAICA, SMC09
from hippo.perception.ica import ICAConvergenceWarning
from hippo.perception.reservoir import Reservoir


def test_transient_updates_known_values():
    # ICANN09 down-sampled by 25: r = 1 - 0.6 + 0.6 * 0.9 = 0.94, ln(1e-3) / ln(0.94) = 111.6
    # -> 112, plus 2 updates of the anti-aliasing filter's zero history
    assert replace(ICANN09, downsample=25).transient_updates() == 114
    # SMC09: the slower leak 0.05 counts, r = 0.9995 -> 13,812.2 -> 13,813 (no filter)
    assert SMC09.transient_updates() == 13813
    # leak 1 (a plain ESN): r = ρ = 0.9 -> ln(1e-3) / ln(0.9) = 65.6 -> 66
    assert replace(ICANN09, leak=1.0, downsample=1).transient_updates() == 66
    assert replace(ICANN09, leak=1.0, downsample=1).transient_updates(0.1) == 22
    # no reservoir: only the filter
    assert replace(ICANN09, use_reservoir=False, downsample=25).transient_updates() == 2
    assert replace(ICANN09, use_reservoir=False, downsample=1).transient_updates() == 0


@pytest.mark.parametrize("n", [50, 400])
def test_the_start_is_forgotten_within_the_bound(n):
    """Two runs from different states on the same input agree to ``tol`` of their initial
    distance after ``transient_updates(tol)`` updates (tanh only speeds the contraction), and
    not after a tenth of them: the washout is neither too short nor absurdly long."""
    p = replace(ICANN09, n_reservoir=n, downsample=1, seed=3)
    k = p.transient_updates(1e-3)
    res = Reservoir(p.reservoir_params(), dtype="float64")
    rng = np.random.default_rng(0)
    U = rng.uniform(0, 1, (k + 5, 17))
    x0 = rng.uniform(-1, 1, n)
    d = np.linalg.norm(res.run(U) - res.run(U, x0=x0), axis=1) / np.linalg.norm(x0)
    assert d[k - 1] < 1e-3
    assert d[k // 10] > 1e-3


@pytest.mark.parametrize("bad", [0.0, 1.0, -0.5, 2.0])
def test_bad_tol(bad):
    with pytest.raises(ValueError, match="tol"):
        ICANN09.transient_updates(bad)


def test_no_fading_memory_is_refused():
    with pytest.raises(ValueError, match="spectral_radius"):
        replace(ICANN09, spectral_radius=1.05).transient_updates()


def test_washout_frees_the_units_spent_on_the_start():
    """A tour of 120 updates repeated 25 times. Fitted from rest without a washout, ICA spends
    units on the start-up transient: they carry their unit variance in the first updates and are
    nearly silent afterwards (s.d. 0.41 and 0.24 over the rest). With the washout every unit
    keeps its variance on the tours (s.d. >= 0.99)."""
    rng = np.random.default_rng(0)
    P = 120
    t = np.arange(P)
    tour = np.stack([0.5 + 0.4 * np.sin(2 * np.pi * (k % 3 + 1) * t / P + rng.uniform(0, 6.3))
                     for k in range(17)], axis=1)
    U = np.clip(np.tile(tour, (25, 1)) + rng.normal(0, 0.01, (25 * P, 17)), 0, 1)
    sd = {}
    for washout in (0, "auto"):
        m = RCSFAICA.icann09(downsample=1, n_reservoir=100, n_sfa=12, n_ica=12,
                             ica_restarts=1, seed=1)
        if washout == "auto":
            m = RCSFAICA(m.params, washout=m.params.transient_updates())
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ICAConvergenceWarning)
            sd[washout] = m.fit(U).transform(U)[P:].std(axis=0)
    assert sd[0].min() < 0.6
    assert sd["auto"].min() > 0.9
