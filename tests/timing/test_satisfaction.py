"""HIREL eq. 4-5: satisfaction prediction from transitions, one Euler step by hand."""

import numpy as np
import pytest

from hippo.timing import Satisfaction, SatisfactionParams

P = SatisfactionParams(alpha=2.5, gamma=0.02, theta=0.2)


def test_two_euler_steps_by_hand():
    sat = Satisfaction(1, P)
    xp = sat.step({(3, 4): 1.0}, [1.0], 0.2)
    assert xp[0] == pytest.approx(-0.2)  # X^P = 0 * 1 - theta
    # dW/dt = 2.5 (1 - 0) 1 1 - 0.02 * 1 = 2.48 -> W = 0.496
    assert sat.weights[0, 0] == pytest.approx(0.496)
    xp = sat.step({(3, 4): 1.0}, [1.0], 0.2)
    assert xp[0] == pytest.approx(0.496 - 0.2)
    # dW/dt = 2.5 (1 - 0.496) - 0.02 = 1.24 -> W = 0.744
    assert sat.weights[0, 0] == pytest.approx(0.744)


def test_active_transition_without_satisfaction_decays():
    sat = Satisfaction(2, P)
    sat.step({(0, 1): 1.0, (1, 2): 0.5}, [1.0, 0.0], 0.2)
    w = sat.weights.copy()
    # drive 0 satisfied: W[0] grows for both transitions (scaled by X^T); drive 1 stays 0
    assert w[0, 0] == pytest.approx(0.2 * (2.5 - 0.02))
    assert w[0, 1] == pytest.approx(0.2 * (2.5 * 0.5 - 0.02 * 0.5))
    assert np.all(w[1] == 0.0)
    sat.step({(0, 1): 0.5}, [0.0, 0.0], 0.2)  # no satisfaction: -gamma X^T dt
    assert sat.weights[0, 0] == pytest.approx(w[0, 0] - 0.2 * 0.02 * 0.5)
    assert sat.weights[0, 1] == pytest.approx(w[0, 1])  # inactive transition: unchanged
    assert sat.keys == [(0, 1), (1, 2)]


def test_prediction_after_learning_and_unknown_keys():
    sat = Satisfaction(1, P)
    for _ in range(20):
        sat.step({"a": 1.0}, [1.0], 0.2)
    assert sat.predict({"a": 1.0})[0] == pytest.approx(1.0 - 0.02 / 2.5 - 0.2, abs=1e-3)
    assert sat.predict({"b": 1.0})[0] == pytest.approx(-0.2)  # never seen: nothing
    for _ in range(10000):
        sat.step({"a": 1.0}, [0.0], 0.2)
    assert sat.weights[0, 0] == 0.0  # decays, never below 0
    sat.reset(keep_weights=True)
    assert sat.keys == ["a"]
    sat.reset()
    assert sat.keys == [] and sat.weights.shape == (1, 0)


def test_bad_input_is_named():
    sat = Satisfaction(2)
    with pytest.raises(ValueError, match="satisfaction"):
        sat.step({}, [np.nan, 0.0], 0.2)
    with pytest.raises(ValueError, match="2 value"):
        sat.step({}, [1.0], 0.2)
    with pytest.raises(ValueError, match="dt"):
        sat.step({}, [1.0, 0.0], -0.2)
    with pytest.raises(ValueError, match="activity of transition"):
        sat.step({(0, 1): float("inf")}, [1.0, 0.0], 0.2)
    with pytest.raises(ValueError, match="n_drives"):
        Satisfaction(0)
