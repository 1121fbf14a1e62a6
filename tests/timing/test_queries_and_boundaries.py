"""Queries of the timing modules against their definitions, and their boundaries (the mutation
survivors of hippo/timing: each test here failed on at least one surviving mutant)."""

import math

import numpy as np
import pytest
from timing_helpers import DT, make, trial

from hippo.timing import NLMS, NLMSParams, SpectralTiming


def _learned_7s():
    timing, cells, _nonocc, _rng = make(0)
    for _ in range(4):
        trial(timing, cells, 0, 1, 7.0)
    return timing, cells


def test_transition_queries_follow_their_definitions():
    timing, cells = _learned_7s()
    assert cells.successors(0) == [1]
    assert cells.successors(1) == [99]  # each trial ends in state 99 (timing_helpers.trial)
    w = cells.weights((0, 1))
    T = cells.learned_delay((0, 1))
    assert T == pytest.approx(7.0, abs=0.3)
    # strength: the prediction the weights give at the learned delay
    assert cells.strength((0, 1)) == pytest.approx(float(w @ timing.tuning(T)), rel=1e-9)
    assert 0.5 < cells.strength((0, 1)) <= 1.0
    assert cells.strength((1, 0)) == 0.0 and math.isnan(cells.learned_delay((1, 0)))
    # in state 0 for 3.5 s: about half the learned delay has elapsed
    cells.step(timing.step(0, DT), DT)
    for _ in range(round(3.5 / DT) - 1):
        cells.step(timing.step(0, DT), DT)
    frac = cells.elapsed_fraction((0, 1))
    assert frac == pytest.approx(3.5 / T, abs=0.05)
    assert cells.prediction((0, 1)) == pytest.approx(float(w @ timing.activity), rel=1e-9)
    assert cells.prediction((0, 1)) > 0
    assert not cells.delay_over((0, 1))
    assert cells.elapsed_fraction((1, 0)) == 0.0  # not a transition out of the winner


def test_transition_query_errors_name_the_argument():
    _timing, cells = _learned_7s()
    with pytest.raises(ValueError, match="state must be"):
        cells.successors(-1)
    with pytest.raises(ValueError, match="unknown state id 5"):
        cells.successors(5)
    with pytest.raises(ValueError, match="transition key"):
        cells.strength((0, 1, 2))
    with pytest.raises(ValueError, match="transition target"):
        cells.elapsed_fraction((0, 1.5))
    with pytest.raises(ValueError, match="state must be"):
        SpectralTiming().battery(-2)
    assert np.array_equal(SpectralTiming().battery(3), np.zeros(SpectralTiming().n_cells))


def test_nlms_layer_shapes_and_messages():
    layer = NLMS(1, 1)
    assert layer.weights.shape == (1, 1) and layer.m_us.shape == (1,) and layer.eta.shape == (1,)
    assert layer.predict(np.ones(1)) == pytest.approx([0.0])
    x = layer.step(np.ones(1), np.ones(1), DT)
    assert x == pytest.approx([0.0]) and layer.weights[0, 0] > 0
    assert layer.predict(np.ones(1))[0] == pytest.approx(layer.weights[0, 0])
    layer.reset()
    assert not layer.weights.any() and not layer.m_us.any() and not layer.eta.any()
    for bad in ((0, 1), (1, 0), (2.5, 1), (1, 1.5)):
        with pytest.raises(ValueError, match="n_out and n_in"):
            NLMS(*bad)
    layer = NLMS(2, 3)
    with pytest.raises(ValueError, match=r"cs must have shape \(3,\)"):
        layer.predict(np.ones(2))
    with pytest.raises(ValueError, match="cs contains"):
        layer.predict(np.array([np.nan, 0, 0]))
    with pytest.raises(ValueError, match="us contains"):
        layer.step(np.ones(3), np.array([np.inf, 0]), DT)
    with pytest.raises(ValueError, match="cs contains"):
        layer.step(np.array([np.nan, 0, 0]), np.zeros(2), DT)
    with pytest.raises(ValueError, match="dt must be"):
        layer.step(np.ones(3), np.zeros(2), -DT)
    with pytest.raises(ValueError, match=r"us must have shape \(2,\)"):
        layer.step(np.ones(3), np.zeros(3), DT)


def test_nlms_params_bounds():
    NLMSParams(sigma2=0.0, gamma=0.0, leak=0.0)  # the exact paper rule, no averaging
    for kw, name in (({"alpha": 0.0}, "alpha"), ({"sigma1": 0.0}, "sigma1"),
                     ({"sigma2": -1e-3}, "sigma2"), ({"gamma": 1.0}, "gamma"),
                     ({"leak": -0.1}, "leak")):
        with pytest.raises(ValueError, match=name):
            NLMSParams(**kw)


def test_expected_of_a_state_without_successors_is_empty_and_names_bad_ids():
    _timing, cells = _learned_7s()
    assert set(cells.expected(0, [1.0, 7.0])) == {(0, 1)}
    t2 = SpectralTiming()
    c2 = type(cells)(t2)
    c2.step(t2.step(0, DT), DT)
    c2.step(t2.step(1, DT), DT)  # 0 -> 1 learned; 1 has no successor yet
    assert c2.expected(1, [1.0]) == {}
    with pytest.raises(ValueError, match="state must be"):
        cells.expected(-1, [1.0])
    with pytest.raises(ValueError, match="transition source"):
        cells.strength((-1, 1))


def test_non_occurrence_fires_at_the_boundaries():
    """HIREL's rule fires once a prediction that peaked at (not only above) min_peak falls below
    fall_fraction of its peak; the timed rule fires once the elapsed fraction reaches (not only
    passes) 1 + tolerance."""
    from hippo.timing import NonOccurrence, NonOccurrenceParams, TransitionReadout

    p = NonOccurrenceParams(min_peak=0.25, fall_fraction=0.5)
    no = NonOccurrence(p)
    for x in (0.1, 0.25):  # rises exactly to min_peak
        assert no.step({"k": x}, DT) == []
    assert no.step({"k": 0.125}, DT) == []  # exactly half: not below
    assert no.step({"k": 0.12}, DT) == ["k"]
    T = 10.0
    edge = 1.0 + max(p.rel_tolerance, p.abs_tolerance / T)
    no = NonOccurrence(p)

    def ro(frac):
        return TransitionReadout((0, 1), 0.3, p.min_peak, T, frac, False)

    assert no.step({(0, 1): ro(math.nextafter(edge, 0.0))}, DT) == []
    assert no.step({(0, 1): ro(edge)}, DT) == [(0, 1)]
    no = NonOccurrence(p)
    weak = TransitionReadout((0, 1), 0.3, math.nextafter(p.min_peak, 0.0), T, 2.0, False)
    assert no.step({(0, 1): weak}, DT) == []  # never strongly predicted: silent


def test_run_trial_names_a_bad_delay():
    from hippo.timing.chain import TimingChain
    from hippo.timing.trials import run_trial

    with pytest.raises(ValueError, match="delay"):
        run_trial(TimingChain(), 0, 1, -1.0, dt=DT, jitter=0.0)
    # a NaN or negative t_max ended the trial at once, silently (end None)
    for bad in (float("nan"), -1.0, 0.0):
        with pytest.raises(ValueError, match="t_max"):
            run_trial(TimingChain(), 0, 1, None, dt=DT, jitter=0.0, self_end=True, t_max=bad)
    with pytest.raises(ValueError, match="after"):
        run_trial(TimingChain(), 0, 1, 2.0, dt=DT, jitter=0.0, after=-1.0)


def test_a_chain_wires_its_parts_with_the_given_params():
    from hippo.timing import NonOccurrenceParams, SpectralParams, TransitionParams
    from hippo.timing.chain import TimingChain

    chain = TimingChain(SpectralParams(n_cells=16), TransitionParams(min_strength=0.5),
                        NonOccurrenceParams(min_peak=0.3))
    assert chain.step(0, DT).battery.activity.shape == (16,)
    assert chain.cells.timing is chain.spectral
    assert chain.cells.params.min_strength == 0.5 and chain.nonocc.params.min_peak == 0.3


def test_a_chain_of_parts_that_do_not_fit_is_refused():
    from hippo.timing import TransitionCells
    from hippo.timing.chain import TimingChain

    with pytest.raises(ValueError, match=r"^cells must read the batteries of spectral"):
        TimingChain.of(SpectralTiming(), TransitionCells(SpectralTiming()))


def test_run_trial_stays_after_s_in_b_and_takes_the_modules_one_by_one():
    from hippo.timing import NonOccurrence, TransitionCells
    from hippo.timing.chain import TimingChain
    from hippo.timing.trials import run_trial

    chain = TimingChain()
    trace = run_trial(chain, 0, 1, 3.0, jitter=0.0)
    assert trace.end == pytest.approx(3.0) and chain.state == 1
    assert chain.spectral.tau == pytest.approx(4.0)  # b lasts ``after`` = 4 s by default
    run_trial(chain, 2, 3, 1.0, jitter=0.0, after=1.0)
    assert chain.spectral.tau == pytest.approx(1.0)
    # the same trial through the modules one by one teaches the same delay
    timing = SpectralTiming()
    cells = TransitionCells(timing)
    run_trial(timing, cells, 0, 1, 3.0, jitter=0.0)
    assert cells.learned_delay((0, 1)) == chain.cells.learned_delay((0, 1))
    with pytest.raises(ValueError, match=r"^nonocc goes with run_trial"):
        run_trial(TimingChain(), 0, 1, 3.0, jitter=0.0, nonocc=NonOccurrence())
    with pytest.raises(TypeError, match=r"takes a, b and delay"):
        run_trial(TimingChain(), 0, 1, jitter=0.0)
    with pytest.raises(ValueError, match="jitter > 0 needs rng"):
        run_trial(TimingChain(), 0, 1, 3.0, jitter=0.1)
