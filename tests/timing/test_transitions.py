"""Transition cells: timed predictions of the next state, Weber widths, re-learning."""

import math

import numpy as np
import pytest
from timing_helpers import DT, make, trial

from hippo.timing import BatteryState, SpectralTiming, TransitionCells, TransitionParams
from hippo.timing.trials import reproduce

DELAYS = (2.0, 7.0, 20.0, 45.0)


def learned(delay: float, pairings: int = 4, seed: int = 0):
    timing, cells, nonocc, rng = make(seed)
    for _ in range(pairings):
        trial(timing, cells, 0, 1, delay, rng=rng)
    return timing, cells, nonocc, rng


def test_one_event_is_one_euler_step_of_eq1_by_hand():
    timing = SpectralTiming()
    cells = TransitionCells(timing)
    p = cells.params.nlms
    cells.step(timing.step(0, DT), DT)
    for _ in range(9):
        cells.step(timing.step(0, DT), DT)
    ev = timing.step(1, DT)  # 0 -> 1 after 2.0 s
    cells.step(ev, DT)
    x = timing.tuning(2.0)
    # m_1 = gamma*0 + (1-gamma)*1, eta = |1 - m_1| + sigma2 = gamma; W was 0 so X = 0
    eta = p.gamma + p.sigma2
    expected = DT * p.alpha * eta * (1.0 - 0.0) * x / (x @ x + p.sigma1)
    assert np.allclose(cells.weights((0, 1)), expected, rtol=1e-12, atol=1e-15)
    assert cells.transitions == [(0, 1)]


@pytest.mark.parametrize("delay", DELAYS)
def test_prediction_peaks_at_or_just_before_the_learned_delay(delay):
    timing, cells, _, _ = learned(delay)
    probe = trial(timing, cells, 0, 1, None, jitter=0.0, t_max=2 * delay)
    t_peak = probe.tau[np.argmax(probe.prediction)]
    assert delay - max(0.1 * delay, DT) - 1e-6 <= t_peak <= delay + 1e-6
    # bell shaped: rises before the peak, falls after it, silent at the start
    assert probe.prediction[0] < 0.01 * probe.prediction.max()
    assert probe.prediction[-1] < 0.05 * probe.prediction.max()
    assert 0.6 < probe.prediction.max() < 1.05


def test_prediction_width_grows_with_the_delay_weber():
    widths = []
    for delay in DELAYS:
        _, cells, _, _ = learned(delay)
        tau = np.linspace(0.01, 2.5 * delay, 20001)
        x = cells.expected(0, tau)[(0, 1)]
        above = tau[x >= 0.5 * x.max()]
        widths.append(above[-1] - above[0])
    relative = np.array(widths) / np.array(DELAYS)
    assert np.all(np.diff(widths) > 0)
    assert relative.max() / relative.min() < 1.1  # width proportional to delay
    assert 0.2 < relative.mean() < 0.5


def test_never_seen_transition_predicts_nothing():
    timing, cells, _, _ = learned(7.0)
    cells.step(timing.step(2, DT), DT)  # state 2 is known, but never followed 0
    ro = cells.step(timing.step(0, DT), DT)
    assert set(ro) == {(0, 1)}
    for _ in range(35):  # 7 s in state 0
        ro = cells.step(timing.step(0, DT), DT)
    assert cells.prediction((0, 2)) == 0.0
    assert not cells.delay_over((0, 2)) and cells.elapsed_fraction((0, 2)) == 0.0
    assert math.isnan(cells.learned_delay((0, 2))) and cells.strength((0, 2)) == 0.0
    assert not np.any(cells.weights((0, 2)))
    assert cells.prediction((0, 1)) > 0.5
    assert cells.successors(0) == [1] and cells.successors(2) == [0]
    # and a state that never had a successor has no readouts at all
    assert cells.step(timing.step(5, DT), DT) == {}


@pytest.mark.parametrize(("old", "new"), [(7.0, 12.0), (12.0, 7.0)])
def test_changed_delay_is_relearned_within_a_few_trials(old, new):
    timing, cells, _, rng = learned(old, pairings=5)
    assert cells.learned_delay((0, 1)) == pytest.approx(old, rel=0.03)
    for _ in range(3):
        trial(timing, cells, 0, 1, new, rng=rng)
    tau = np.arange(DT, 2 * max(old, new), DT)
    x = cells.expected(0, tau)[(0, 1)]
    assert tau[np.argmax(x)] == pytest.approx(new, rel=0.05)
    assert cells.learned_delay((0, 1)) == pytest.approx(new, rel=0.03)


@pytest.mark.parametrize("delay", [2.0, 7.0, 24.1, 60.0])
def test_delay_over_lands_on_the_learned_delay(delay):
    timing, cells, _, _ = learned(delay, seed=1)
    lead = cells.params.anticipation + cells.params.latency
    probe = trial(timing, cells, 0, 1, None, jitter=0.0, t_max=1.5 * delay)
    first = probe.tau[np.argmax(probe.delay_over)]
    assert probe.delay_over.any() and np.all(probe.delay_over[np.argmax(probe.delay_over):])
    # the flag rises one tick (the latency) before the tick nearest the delay
    assert abs(first + cells.params.latency - delay) <= DT / 2 + 0.03 * delay
    # elapsed fraction = population readout of the elapsed time / learned delay
    t_hat = cells.learned_delay((0, 1))
    assert probe.elapsed_fraction == pytest.approx(probe.tau / t_hat, rel=0.01, abs=0.02)
    assert lead == pytest.approx(0.3)


@pytest.mark.parametrize("delay", [2.0, 11.6, 45.0])
def test_closed_loop_reproduction_is_precise(delay):
    """The agent leaves when delay_over rises and the leaving is learned again (patrol)."""
    timing, cells, _, rng = learned(delay, seed=2)
    ends = [trial(timing, cells, 0, 1, None, rng=rng, self_end=True, t_max=3 * delay).end
            for _ in range(5)]
    err = np.array(ends) / delay - 1.0
    assert abs(err.mean()) < 0.03
    assert np.abs(err).max() < max(0.03, 0.11 / delay)  # tick quantisation at short delays


def test_bad_input_is_named():
    timing, cells, _, _ = learned(2.0, pairings=1)
    with pytest.raises(ValueError, match="unknown state id 57"):
        cells.prediction((0, 57))
    with pytest.raises(ValueError, match="unknown state id 57"):
        cells.successors(57)
    with pytest.raises(ValueError, match="tuple"):
        cells.delay_over(3)
    with pytest.raises(ValueError, match="state id"):
        cells.learned_delay((-1, 0))
    with pytest.raises(ValueError, match="BatteryState"):
        cells.step(np.zeros(timing.n_cells), DT)
    with pytest.raises(ValueError, match="dt"):
        cells.step(timing.step(0, DT), -DT)
    bad = BatteryState(0, 0.0, np.zeros(5), False)
    with pytest.raises(ValueError, match="shape"):
        cells.step(bad, DT)
    with pytest.raises(ValueError, match="unstable"):
        cells.step(timing.step(0, DT), 1.0)
    with pytest.raises(ValueError, match="min_strength"):
        TransitionParams(min_strength=-1.0)


def test_reset_keeps_or_forgets_weights():
    _, cells, _, _ = learned(7.0, pairings=2)
    w = cells.weights((0, 1))
    cells.reset(keep_weights=True)
    assert np.array_equal(cells.weights((0, 1)), w) and cells.readouts == {}
    cells.reset()
    assert cells.transitions == []


def test_same_seed_same_result_and_long_waits_stay_over():
    a, b = reproduce(7.0, seed=3, loops=2), reproduce(7.0, seed=3, loops=2)
    assert a.waits == b.waits and a.learned == b.learned
    assert reproduce(7.0, seed=4, loops=2).waits != a.waits
    timing, cells, _, _ = learned(2.0)
    cells.step(timing.step(0, DT), DT)
    for _ in range(5000):  # 1000 s: far beyond the battery, the delay stays over
        ro = cells.step(timing.step(0, DT), DT)
    assert ro[(0, 1)].delay_over and cells.elapsed == math.inf


def test_settled_ticks_skip_learning_with_the_same_numbers():
    """Between events m^US is exactly one-hot at the winner and eta = 0 on every row: the
    step skips the learning there. Weights, delays and readouts equal those of a run that
    takes the learning step on every tick, bit for bit."""
    rng = np.random.default_rng(7)
    states = np.repeat(rng.integers(0, 4, 60), rng.integers(1, 80, 60))  # dwell 0.2-16 s
    runs = []
    for skip in (True, False):
        timing = SpectralTiming()
        cells = TransitionCells(timing)
        cells._skip_settled = skip
        reads = []
        for s in states:
            reads.append(cells.step(timing.step(int(s), DT), DT))
        runs.append((cells, reads))
    (a, ra), (b, rb) = runs
    assert a.transitions == b.transitions and len(a.transitions) >= 6
    for key in a.transitions:
        np.testing.assert_array_equal(a.weights(key), b.weights(key))
    assert ra == rb


def test_reproduce_reports_the_closed_loop_waits_the_stored_delay_and_the_lag():
    # HIREL Table I in miniature: 3 teacher trials at 7 s, then 5 waits the system ends itself
    # (each within ~1.5 ticks of 7 s), the stored delay within 2 %, and the non-occurrence
    # neuron firing after the omitted event's time, within a fifth of the delay (Weber)
    r = reproduce(7.0, seed=0)
    assert r.delay == 7.0 and len(r.waits) == 5
    assert all(abs(w - 7.0) < 0.3 for w in r.waits), r.waits
    assert abs(r.learned - 7.0) < 0.14
    assert 0.0 < r.non_occurrence_lag < 0.2 * 7.0


def test_more_states_than_the_first_allocation_are_learned_alike():
    # a ring of 20 states (the per-state arrays start with room for 8 and grow), 2 s in each:
    # every transition of the ring stores 2 s, the last as well as the first
    timing = SpectralTiming()
    cells = TransitionCells(timing)
    for _ in range(3):
        for s in range(20):
            for _ in range(10):
                cells.step(timing.step(s, DT), DT)
    assert len(cells.transitions) == 20
    for key in [(0, 1), (8, 9), (18, 19), (19, 0)]:
        assert cells.learned_delay(key) == pytest.approx(2.0, rel=0.05), key


def test_the_readout_depends_on_the_battery_pattern_only():
    import dataclasses

    timing, cells, _, _ = learned(5.0)
    twin_timing, twin, _, _ = learned(5.0)
    for _ in range(12):
        battery = timing.step(0, DT)
        copy = dataclasses.replace(twin_timing.step(0, DT),
                                   activity=battery.activity.copy())  # not the battery's own
        assert twin.step(copy, DT) == cells.step(battery, DT)
    assert cells.elapsed == twin.elapsed > 2.0


def test_the_teacher_comes_at_the_earlier_of_two_equally_near_ticks():
    # dt = 0.25 (exact in binary), delay 1.125: ticks at 1.0 and 1.25 are equally near; the
    # rule "tau >= delay - dt/2" takes 1.0
    from hippo.timing.chain import TimingChain
    from hippo.timing.trials import run_trial

    assert run_trial(TimingChain(), 0, 1, 1.125, dt=0.25, jitter=0.0).end == 1.0


def test_a_negative_transition_source_is_named():
    _, cells, _, _ = learned(3.0, pairings=1)
    with pytest.raises(ValueError, match=r"^transition source\b"):
        cells.learned_delay((-1, 1))


def test_a_delay_beyond_the_battery_says_how_to_time_it():
    from hippo.timing import DelayRangeWarning, SpectralParams

    timing = SpectralTiming(SpectralParams(mu_max=10.0))
    cells = TransitionCells(timing)
    for _ in range(80):  # 16 s in state 0, beyond mu_max = 10 s
        cells.step(timing.step(0, DT), DT)
    with pytest.warns(DelayRangeWarning, match=r"Harmless for a stay no task times.*raise "
                                               r"SpectralParams.mu_max$"):
        cells.step(timing.step(1, DT), DT)


def test_an_event_marked_unmeasured_teaches_no_delay_but_is_recruited():
    # 0 -> 1 learned at 7 s; then 0 -> 1 after only 3 s (a stop the agent made by other
    # means than its timing), marked as no measurement
    def event(target: int, learn_event: bool) -> tuple[TransitionCells, np.ndarray, float]:
        timing, cells, _, _ = learned(7.0)
        w, delay = cells.weights((0, 1)).copy(), cells.learned_delay((0, 1))
        for _ in range(15):                                  # 3 s in state 0
            cells.step(timing.step(0, DT), DT)
        cells.step(timing.step(target, DT), DT, learn_event=learn_event)
        return cells, w, delay

    cells, w, delay = event(1, learn_event=False)
    # the stay in state 0 learns only m^US's 1e-18 tail (the trial's end state 99 -> 0)
    assert np.allclose(cells.weights((0, 1)), w, rtol=0.0, atol=1e-12)
    assert cells.learned_delay((0, 1)) == pytest.approx(delay, abs=1e-9)
    cells, w, delay = event(1, learn_event=True)   # measured: one event re-times it at once
    assert np.abs(cells.weights((0, 1)) - w).max() > 0.1
    assert cells.learned_delay((0, 1)) == pytest.approx(3.0, abs=0.2)
    cells, _, _ = event(2, learn_event=False)      # a new transition: known, not timed
    assert (0, 2) in cells.transitions and not cells.weights((0, 2)).any()
