"""Re-localisation in the map: known place changes, Weber timing, the time limit."""

from __future__ import annotations

import math

import pytest

from hippo.cognitive_map import Action, TransitionGraph
from hippo.cognitive_map.localise import LocaliserParams, MapLocaliser


def corridor() -> TransitionGraph:
    """1 -> 2 -> 3 -> 4, each stay 4 s."""
    g = TransitionGraph()
    for a in (1, 2, 3):
        g.add_transition(a, a + 1, Action.move(0.0, 20.0), delay=4.0)
    return g


def test_one_known_change_localises_and_unknown_ones_do_not():
    g, loc = corridor(), MapLocaliser()
    loc.reset(100.0)
    assert not loc.observe(3, 101.0, g)        # the stale winner: nothing to check
    assert not loc.observe(1, 102.0, g)        # 3 -> 1 is not in the map
    assert loc.observe(2, 104.0, g)            # 1 -> 2 is
    assert loc.time_to_localise == pytest.approx(4.0)
    assert loc.events == 3


def test_timing_counts_from_the_second_change_with_weber_tolerance():
    g = corridor()
    loc = MapLocaliser(LocaliserParams(n_known=2, delay_tolerance=0.5))
    loc.reset(0.0)
    loc.observe(1, 0.5, g)
    assert not loc.observe(2, 1.0, g)          # first change: known, timing not checked
    assert not loc.observe(3, 1.5, g)          # 0.5 s in 2 against a learned 4 s: too fast
    assert not loc.observe(4, 5.5, g)          # a known 4 s, but the run restarted at 3
    loc.reset(10.0)
    loc.observe(1, 11.0, g)
    loc.observe(2, 12.0, g)
    # within x1.5 of the learned 4 s: 4 * 1.4 = 5.6 s passes, 4 * 1.6 = 6.4 s would not
    assert loc.observe(3, 12.0 + 5.6, g)


def test_weber_bound_is_symmetric_in_log_time():
    g = corridor()
    for stay, want in ((4.0 / 1.49, True), (4.0 / 1.51, False), (4.0 * 1.49, True),
                       (4.0 * 1.51, False)):
        loc = MapLocaliser(LocaliserParams(n_known=2))
        loc.reset(0.0)
        loc.observe(1, 1.0, g)
        loc.observe(2, 2.0, g)
        assert loc.observe(3, 2.0 + stay, g) is want, stay


def test_max_time_gives_up_waiting():
    g, loc = corridor(), MapLocaliser(LocaliserParams(max_time=30.0))
    loc.reset(0.0)
    loc.observe(4, 1.0, g)
    assert not loc.check(29.0)
    assert loc.check(30.0) and loc.time_to_localise == pytest.approx(30.0)


def test_bad_input_is_named():
    with pytest.raises(ValueError, match="n_known"):
        LocaliserParams(n_known=0)
    with pytest.raises(ValueError, match="max_time"):
        LocaliserParams(max_time=-1)
    loc = MapLocaliser()
    loc.reset(5.0)
    with pytest.raises(ValueError, match="finite time"):
        loc.observe(1, math.nan, corridor())
    with pytest.raises(ValueError, match="finite time"):
        loc.observe(1, 1.0, corridor())


@pytest.mark.parametrize("bad", [math.nan, math.inf, "5", True])
def test_a_lift_or_anchor_time_that_is_no_finite_number_is_refused(bad):
    """reset(nan) used to be taken, and check() then never gave up (nan - t0 >= max_time is
    never true)."""
    loc = MapLocaliser(LocaliserParams(max_time=30.0))
    loc.reset(2.0)
    with pytest.raises(ValueError, match=r"^t must be (a real number|finite), got "):
        loc.reset(bad)
    with pytest.raises(ValueError, match=r"^t must be (a real number|finite), got "):
        loc.anchor(bad)
    assert loc.t0 == 2.0 and loc.check(32.0)  # the last good lift still times out


def test_the_weber_bound_itself_is_inside():
    # |ln(6 / 4)| = ln(1 + 0.5) exactly: a stay of 1.5 x the learned delay still matches
    g = corridor()
    loc = MapLocaliser(LocaliserParams(n_known=2, delay_tolerance=0.5))
    loc.reset(0.0)
    loc.observe(1, 1.0, g)
    loc.observe(2, 2.0, g)
    assert loc.observe(3, 8.0, g)


def test_a_short_learned_delay_is_timed_too():
    # a learned 0.5 s: a 2 s stay (x4) does not match it (the run restarts), a 0.6 s one does
    g = TransitionGraph()
    for a in (1, 2, 3, 4):
        g.add_transition(a, a + 1, Action.move(0.0, 20.0), delay=0.5)
    loc = MapLocaliser(LocaliserParams(n_known=2))
    loc.reset(0.0)
    loc.observe(1, 1.0, g)
    loc.observe(2, 2.0, g)
    assert not loc.observe(3, 4.0, g)
    assert not loc.observe(4, 4.5, g)
    assert loc.observe(5, 5.1, g)


def test_changes_without_a_measurable_timing_are_not_timed():
    # a transition with no learned delay (None) or a zero one, or a stay of zero seconds:
    # known is enough (a log-ratio of the times would be undefined)
    g = TransitionGraph()
    g.add_transition(1, 2, Action.move(0.0, 20.0))             # no delay
    g.add_transition(2, 3, Action.move(0.0, 20.0))
    g.add_transition(3, 4, Action.move(0.0, 20.0), delay=0.0)  # a zero delay
    g.add_transition(4, 5, Action.move(0.0, 20.0), delay=4.0)
    loc = MapLocaliser(LocaliserParams(n_known=4))
    loc.reset(0.0)
    loc.observe(1, 1.0, g)
    assert not loc.observe(2, 2.0, g)
    assert not loc.observe(3, 9.0, g)     # 7 s against no delay: fine
    assert not loc.observe(4, 10.0, g)    # 1 s against a zero delay: fine
    assert loc.observe(5, 10.0, g)        # 0 s in 4 against 4 s: not timed
    assert loc.time_to_localise == 10.0


def test_the_same_winner_again_neither_breaks_nor_extends_a_run():
    # a repeated winner (at the same instant, allowed) is not a change: the run of known
    # changes goes on, and the stay is timed from the repeat
    g = corridor()
    loc = MapLocaliser(LocaliserParams(n_known=2))
    loc.reset(0.0)
    loc.observe(1, 1.0, g)
    assert not loc.observe(2, 2.0, g)
    assert not loc.observe(2, 2.0, g)
    assert loc.events == 3 and loc.time_to_localise is None
    assert loc.observe(3, 6.0, g)


def test_once_localised_it_stays_localised_until_the_next_lift():
    g = corridor()
    loc = MapLocaliser()  # a new localiser counts from t = 0
    assert loc.localised_at is None and loc.time_to_localise is None
    assert not loc.check(59.0) and loc.check(60.0)
    assert loc.observe(3, 61.0, g) and loc.observe(1, 62.0, g)  # even an unknown change
    assert loc.time_to_localise == 60.0
    loc.reset(100.0)
    assert not loc.localised and loc.time_to_localise is None


def test_params_of_the_wrong_type_are_named():
    with pytest.raises(TypeError, match="params must be LocaliserParams"):
        MapLocaliser({"n_known": 2})


def test_after_the_place_code_is_re_anchored_the_next_change_localises():
    g, loc = corridor(), MapLocaliser()
    loc.reset(0.0)
    assert not loc.observe(3, 1.0, g)          # stale
    loc.anchor(2.0)
    assert not loc.localised                   # the anchor alone does not localise ...
    assert loc.observe(1, 2.2, g)              # ... the next change does, known or not
    assert loc.by_anchor and loc.time_to_localise == pytest.approx(2.2)
    loc.reset(5.0)                             # a new lift forgets the anchor
    assert not loc.by_anchor
    assert not loc.observe(3, 6.0, g)
    assert not loc.observe(1, 7.0, g)
    assert loc.observe(2, 8.0, g) and not loc.by_anchor   # known: localised the map's way


def test_anchor_settle_lets_the_jump_switch_pass():
    g, loc = corridor(), MapLocaliser(LocaliserParams(anchor_settle=1.0))
    loc.reset(0.0)
    loc.anchor(2.0)
    assert not loc.observe(1, 2.4, g)          # the jump's own switch, within 1 s
    assert loc.observe(4, 3.5, g) and loc.by_anchor


def test_a_negative_anchor_settle_is_refused():
    with pytest.raises(ValueError):
        LocaliserParams(anchor_settle=-1.0)
