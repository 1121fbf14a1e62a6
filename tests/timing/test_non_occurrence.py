"""Non-occurrence: fires soon after an omitted event, never when the event comes on time."""

import numpy as np
import pytest
from timing_helpers import DT, make, trial

from hippo.timing import NonOccurrence, NonOccurrenceParams


@pytest.mark.parametrize("delay", [2.0, 7.0, 24.1, 45.0])
def test_omitted_event_fires_after_the_delay_and_not_long_after(delay):
    timing, cells, nonocc, rng = make(3)
    for _ in range(4):
        trial(timing, cells, 0, 1, delay, rng=rng, nonocc=nonocc)
    ext = trial(timing, cells, 0, 1, None, rng=rng, nonocc=nonocc, t_max=2 * delay)
    assert len(ext.fired) == 1  # fires once, then stays latched
    t_fire = ext.fired[0]
    p = nonocc.params
    tolerance = max(p.rel_tolerance * delay, p.abs_tolerance)
    assert delay < t_fire <= delay + tolerance + 2 * DT
    if delay == 7.0:  # the place-preference extinction trial: resume within 2 s
        assert t_fire - delay < 2.0


def test_signal_stays_on_until_the_prediction_ends():
    timing, cells, nonocc, rng = make(4)
    for _ in range(3):
        trial(timing, cells, 0, 1, 7.0, rng=rng)
    cells.step(timing.step(0, DT), DT)
    nonocc.step(cells.readouts, DT)
    on = []
    for _ in range(60):  # 12 s in state 0, no event
        nonocc.step(cells.step(timing.step(0, DT), DT), DT)
        on.append((0, 1) in nonocc.active)
    on = np.array(on)
    assert not on[:34].any() and on[40:].all()
    nonocc.step(cells.step(timing.step(2, DT), DT), DT)  # state 0 ends: the signal stops
    assert not nonocc.active


def test_on_time_events_never_fire_over_many_trials():
    timing, cells, nonocc, rng = make(5)
    pairs = {2.0: (0, 1), 7.0: (2, 3), 15.0: (4, 5)}  # three transitions, interleaved
    fired = []
    for delay in rng.permutation(np.repeat(list(pairs), 10)):
        a, b = pairs[delay]  # jittered ticks: the event comes at the tick nearest the delay
        fired += trial(timing, cells, a, b, delay, rng=rng, nonocc=nonocc).fired
    for delay in rng.permutation(np.repeat(list(pairs), 6)):
        a, b = pairs[delay]  # the agent's own reproductions (patrol), learned again
        fired += trial(timing, cells, a, b, None, rng=rng, nonocc=nonocc, self_end=True,
                       t_max=3 * delay).fired
    assert fired == []
    # ... while an omission among them is caught
    ext = trial(timing, cells, 2, 3, None, rng=rng, nonocc=nonocc, t_max=10.0)
    assert len(ext.fired) == 1


def test_hirel_rule_on_plain_predictions():
    nonocc = NonOccurrence(NonOccurrenceParams(min_peak=0.2, fall_fraction=0.5))
    tau = np.arange(0.0, 14.0, DT)
    bell = 0.8 * np.exp(-0.5 * ((tau - 7.0) / 0.7) ** 2)
    fired_at = [t for t, x in zip(tau, bell) if nonocc.step({"sound": x}, DT)]
    # half maximum on the falling side: 7 + 0.7 * sqrt(2 ln 2) = 7.82 s
    assert len(fired_at) == 1 and fired_at[0] == pytest.approx(8.0, abs=DT / 2)
    assert nonocc.peak["sound"] == pytest.approx(0.8, rel=1e-3)
    nonocc.reset()
    weak = [nonocc.step({"sound": 0.1 * x}, DT) for x in bell]  # never predicted: silent
    assert not any(weak)
    # the event arrives before the fall (the key disappears): silent
    nonocc.reset()
    early = [nonocc.step({"sound": x} if t < 7.4 else {}, DT) for t, x in zip(tau, bell)]
    assert not any(early)


def test_bad_input_is_named():
    nonocc = NonOccurrence()
    with pytest.raises(ValueError, match="non-finite"):
        nonocc.step({(0, 1): float("nan")}, DT)
    with pytest.raises(ValueError, match="dt"):
        nonocc.step({}, -DT)
    with pytest.raises(ValueError, match="mapping"):
        nonocc.step([0.5], DT)
    with pytest.raises(ValueError, match="fall_fraction"):
        NonOccurrenceParams(fall_fraction=1.5)


def test_the_timed_rule_fires_once_after_the_tolerance_and_says_so_in_fired():
    # N = [tau_hat / T_hat >= 1 + max(r, a / T_hat)]: T_hat = 10 s, r = 0.05, a = 0.6 s ->
    # fires at the first elapsed fraction >= 1.06, once; ``fired`` lists it at that tick only
    from hippo.timing.transition_params import TransitionReadout

    nonocc = NonOccurrence(NonOccurrenceParams(rel_tolerance=0.05, abs_tolerance=0.6))

    def ro(frac, delay=10.0):
        return {(0, 1): TransitionReadout((0, 1), 0.5, 0.8, delay, frac, frac >= 1.0)}

    assert nonocc.step(ro(1.05), DT) == [] and nonocc.fired == []
    assert nonocc.step(ro(1.06), DT) == [(0, 1)] and nonocc.fired == [(0, 1)]
    assert nonocc.step(ro(1.5), DT) == [] and nonocc.fired == []
    assert nonocc.active == {(0, 1)}
    # no stored delay (0): nothing to be late for, never fires
    nonocc.reset()
    assert all(nonocc.step(ro(f, delay=0.0), DT) == [] for f in (1.0, 2.0, 50.0))


def test_bad_input_names_the_argument_and_the_type():
    nonocc = NonOccurrence()
    with pytest.raises(ValueError, match=r"^dt\b"):
        nonocc.step({}, 0.0)
    with pytest.raises(ValueError, match="got list"):
        nonocc.step([0.5], DT)


@pytest.mark.parametrize("bad", ["0.5", b"0.5", True, np.bool_(False)])
def test_a_prediction_that_is_no_number_is_refused(bad):
    """float() would take a numeric string or a bool; a prediction is a number."""
    nonocc = NonOccurrence()
    with pytest.raises(ValueError, match=r"^prediction of \(0, 1\) must be a number, got "):
        nonocc.step({(0, 1): bad}, DT)
    assert nonocc.peak == {}
    assert nonocc.step({(0, 1): np.float32(0.5), (1, 2): 1}, DT) == []  # numbers of any type
    assert nonocc.peak == {(0, 1): 0.5, (1, 2): 1.0}
