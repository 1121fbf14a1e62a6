"""HIREL eq. 1-3: one Euler step by hand, and the rule's behaviour."""

import numpy as np
import pytest

from hippo.timing import NLMS, NLMSParams, learning_modulation, nlms_update, sliding_mean

P = NLMSParams(alpha=2.0, sigma1=0.5, sigma2=0.1, gamma=0.8, leak=0.0)


def test_eq3_sliding_mean_and_eq2_modulation_by_hand():
    m = sliding_mean(np.array([0.2]), np.array([1.0]), 0.8)
    assert m[0] == pytest.approx(0.8 * 0.2 + 0.2 * 1.0)  # 0.36
    eta = learning_modulation(np.array([1.0]), m, 0.1)
    assert eta[0] == pytest.approx(abs(1.0 - 0.36) + 0.1)  # 0.74


def test_eq1_one_euler_step_by_hand():
    w = np.array([[0.1, 0.2, 0.0]])
    cs = np.array([1.0, 0.5, 0.0])
    # X = 0.1 + 0.1 = 0.2; error 0.8; sum cs^2 + sigma1 = 1.75
    # dW = alpha*eta*err*cs/1.75 = 2*0.74*0.8/1.75 * cs = 0.676571.. * cs; dt = 0.1
    w_new, x = nlms_update(w, cs, np.array([1.0]), np.array([0.74]), P, 0.1)
    assert x[0] == pytest.approx(0.2)
    assert w_new[0] == pytest.approx([0.16765714285714, 0.23382857142857, 0.0], abs=1e-12)


def test_leak_term_by_hand():
    p = NLMSParams(alpha=2.0, sigma1=0.5, sigma2=0.1, gamma=0.8, leak=0.5)
    w = np.array([[0.1, 0.2, 0.0]])
    cs = np.array([1.0, 0.5, 0.0])
    # extra term: -alpha*eta*leak*US*W*dt = -2*0.74*0.5*1*0.1 W = -0.074 W
    w_new, _ = nlms_update(w, cs, np.array([1.0]), np.array([0.74]), p, 0.1)
    assert w_new[0] == pytest.approx([0.1 - 0.0074 + 0.06765714285714,
                                      0.2 - 0.0148 + 0.03382857142857, 0.0], abs=1e-12)
    # the leak is gated by the US: no decay when the predicted state is absent
    w0, _ = nlms_update(w, np.zeros(3), np.array([0.0]), np.array([0.74]), p, 0.1)
    assert np.array_equal(w0, w)


def test_layer_step_chains_eq3_eq2_eq1():
    layer = NLMS(1, 3, P)
    layer.weights[:] = [[0.1, 0.2, 0.0]]
    layer.m_us[:] = 0.2
    x = layer.step(np.array([1.0, 0.5, 0.0]), np.array([1.0]), 0.1)
    assert x[0] == pytest.approx(0.2)
    assert layer.m_us[0] == pytest.approx(0.36) and layer.eta[0] == pytest.approx(0.74)
    assert layer.weights[0] == pytest.approx([0.16765714285714, 0.23382857142857, 0.0])


def test_learns_the_us_and_only_from_active_inputs():
    rng = np.random.default_rng(0)
    layer = NLMS(2, 5, NLMSParams(alpha=5.0, sigma2=0.2, gamma=0.5, leak=0.0))
    cs = rng.uniform(0, 1, 5)
    cs[4] = 0.0
    for _ in range(200):
        layer.step(cs, np.array([1.0, 0.3]), 0.2)
    assert layer.predict(cs) == pytest.approx([1.0, 0.3], abs=1e-3)
    assert np.all(layer.weights[:, 4] == 0.0)  # a silent input never learns
    layer.reset()
    assert not np.any(layer.weights)


def test_bad_input_is_named():
    layer = NLMS(1, 3)
    with pytest.raises(ValueError, match="cs"):
        layer.step(np.array([1.0, np.nan, 0.0]), np.array([1.0]), 0.2)
    with pytest.raises(ValueError, match="us"):
        layer.step(np.ones(3), np.array([np.inf]), 0.2)
    with pytest.raises(ValueError, match="dt"):
        layer.step(np.ones(3), np.ones(1), -0.2)
    with pytest.raises(ValueError, match="shape"):
        layer.step(np.ones(4), np.ones(1), 0.2)
    with pytest.raises(ValueError, match="gamma"):
        NLMSParams(gamma=1.0)
    with pytest.raises(ValueError, match="alpha"):
        NLMSParams(alpha=-1.0)


def test_unstable_step_and_wrong_params_are_refused():
    layer = NLMS(1, 2)  # alpha = 10, gamma = 0.5: alpha*dt*eta reaches 2 at dt = 0.4
    with pytest.raises(ValueError, match=r"alpha\*dt\*eta = 5 >= 2 is unstable"):
        layer.step(np.ones(2), np.array([1.0]), 1.0)
    assert not np.any(layer.weights) and not np.any(layer.m_us)  # nothing changed
    for i in range(60):  # a stable dt learns the alternating target without diverging
        layer.step(np.ones(2), np.array([float(i % 2)]), 0.2)
    assert np.all(np.abs(layer.weights) < 1.0)
    with pytest.raises(TypeError, match="params must be NLMSParams"):
        NLMS(1, 2, params="abc")
