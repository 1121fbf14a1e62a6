"""The decider's run-up rules (:mod:`hippo.runups`) on known answers: a loop of three taught
stops a -> b -> c -> a whose run-ups are set by hand, and the robot's run since its last wait.

The walk of ``_due_walk`` sums the taught run-ups backwards from a drive to the drive of the
last wait: with run-ups b 50 (after a), c 70 (after b), a 150 (after c) and the last wait for
a, drive c's stop is first due 70 + 50 = 120 cm on, and again every lap of 270 cm."""

import math

import pytest

from hippo.brain import Brain, BrainParams
from hippo.cognitive_map import Action, DriveParams
from hippo.runups import _context_adjacency
from hippo.types import Mode

RUNUPS = {"b": 50.0, "c": 70.0, "a": 150.0}
AFTER = {"b": "a", "c": "b", "a": "c"}


class NoPlaces:
    kind, n_units = "stub", 1


def loop(window: float = 20.0, *, last: str | None = "a", ran: float = 0.0,
         runups: dict | None = None, **params) -> Brain:
    """A brain whose last wait (for ``last``) ended 1000 cm into the run, ``ran`` cm ago."""
    brain = Brain(NoPlaces(), drives={n: DriveParams() for n in "abc"},
                  params=BrainParams(runup_window=window, **params))
    brain.runups = dict(RUNUPS if runups is None else runups)
    brain.runup_after = dict(AFTER)
    brain.wait_ended_at, brain.last_wait_drive = 1000.0, last
    brain.odometer = 1000.0 + ran
    return brain


def at(brain: Brain, ran: float) -> Brain:
    brain.odometer = brain.wait_ended_at + ran
    return brain


def test_the_walk_sums_the_run_ups_back_to_the_last_wait():
    d = loop().decide
    assert d._due_walk("c") == (120.0, 270.0, True)     # c after b after a: 70 + 50
    assert d._due_walk("b") == (50.0, 270.0, True)      # b right after a
    assert d._due_walk("a") == (270.0, 270.0, True)     # a again: a whole lap
    # a drive without a run-up ends the walk: no lap closed, the first point stands
    d = loop(runups={"b": 50.0, "c": 70.0}).decide
    assert d._due_walk("c") == (120.0, 120.0, False)
    d = loop(runups={"b": 50.0, "c": 70.0, "x": 5.0}).decide   # the walk stops at a
    assert d._due_walk("c") == (120.0, 120.0, False)
    # no bound: the last wait's drive is not in the chain, no anchor, or no window
    assert loop(last="x").decide._due_walk("c") is None
    assert loop(last=None).decide._due_walk("c") is None
    b = loop()
    b.wait_ended_at = None
    assert b.decide._due_walk("c") is None
    assert loop(window=0.0).decide._due_walk("c") is None
    assert loop(window=0.5).decide._due_walk("c") == (120.0, 270.0, True)


def test_a_lap_counts_only_when_it_is_longer_than_two_windows():
    assert loop(ran=10.0).decide._walked("c") == (120.0, 270.0, 10.0, 20.0)
    assert loop(window=135.0).decide._walked("c")[1] == 0.0      # 270 = 2 x 135: no lap
    assert loop(window=134.0).decide._walked("c")[1] == 270.0
    assert loop(last="x").decide._walked("c") is None


@pytest.mark.parametrize(("ran", "not_due", "due", "ahead"), [
    (90.0, True, False, False),      # more than the window before the first point
    (99.0, True, False, False),      # 21 cm before it: clearly early
    (100.0, False, True, True),      # the window's edge, ahead by exactly the window
    (120.0, False, True, True),      # where it is due
    (140.0, False, True, False),     # 20 cm past: due, no longer ahead
    (141.0, True, False, False),     # 21 cm past: clearly not due
    (200.0, True, False, False),
    (380.0, False, True, True),      # a lap on: due again at 390, 10 cm ahead
    (390.0, False, True, True),
    (411.0, True, False, False),
])
def test_where_the_run_ups_say_a_stop_is_due(ran, not_due, due, ahead):
    d = loop(ran=ran).decide
    assert d._not_due("c") is not_due
    assert d._due("c") is due
    assert d._due_ahead("c") is ahead


def test_without_a_closed_lap_nothing_bounds_the_run_past_the_first_point():
    d = at(loop(window=135.0), 300.0).decide      # lap 270 = 2 windows: not counted
    assert not d._not_due("c")                     # no bound past 120
    assert not d._due("c")                         # 180 cm past 120: not due
    assert not d._due_ahead("c")
    assert at(loop(window=135.0), 100.0).decide._due_ahead("c")   # 20 cm ahead
    assert at(loop(window=135.0), -10.0).decide._not_due("c") is False  # 130 < window
    assert at(loop(window=135.0), -16.0).decide._not_due("c") is True
    for rule in ("_not_due", "_due", "_due_ahead"):
        assert getattr(loop(last="x").decide, rule)("c") is False  # no anchor in the chain


def test_the_gate_holds_an_approach_only_between_window_and_tolerance_before_the_run_up():
    brain = loop(window=20.0, runup_tolerance=5.0)
    d = brain.decide
    d.wait_drive = lambda: 1                      # approaching for b (run-up 50 cm)
    held = {ran: at(brain, ran).decide._before_runup() for ran in (29.0, 30.0, 31.0, 44.9,
                                                                   45.0, 50.0)}
    assert held == {29.0: False, 30.0: False, 31.0: True, 44.9: True, 45.0: False, 50.0: False}
    at(brain, 40.0)
    assert d._before_runup()
    d.wait_drive = lambda: -1                     # no drive's approach
    assert not d._before_runup()
    d.wait_drive = lambda: 1
    brain.runups.pop("b")                         # no run-up taught for b
    assert not d._before_runup()
    brain = at(loop(window=1.0, runup_tolerance=0.5), 49.2)   # a narrow window still gates
    brain.decide.wait_drive = lambda: 1
    assert brain.decide._before_runup()
    brain.wait_ended_at = None
    assert not brain.decide._before_runup()


def test_the_odometric_stop_is_due_from_run_up_plus_runup_stop_to_the_window():
    brain = loop(window=20.0, runup_stop=0.0, last="c")
    d = brain.decide
    d.wait_drive = lambda: 0                      # approaching for a (run-up 150 after c)
    passed = {ran: at(brain, ran).decide._past_runup() for ran in (149.9, 150.0, 169.9, 170.0)}
    assert passed == {149.9: False, 150.0: True, 169.9: True, 170.0: False}
    brain = at(loop(window=20.0, runup_stop=10.0, last="c"), 159.0)
    brain.decide.wait_drive = lambda: 0
    assert not brain.decide._past_runup()
    assert at(brain, 160.0).decide._past_runup()
    brain = at(loop(window=20.0, runup_stop=-1.0, last="c"), 160.0)   # disabled
    brain.decide.wait_drive = lambda: 0
    assert not brain.decide._past_runup()
    assert not at(loop(last="b", runup_stop=0.0), 150.0).decide._runup_passed("a")  # not in order


def test_a_run_up_counts_in_order_only_from_the_drive_taught_before_it():
    brain = loop(ran=33.0)
    d = brain.decide
    assert d._in_order("b") == (50.0, 33.0)
    assert d._in_order("c") is None               # c counts from b, the last wait was a
    brain.runups.pop("b")
    assert d._in_order("b") is None               # in order, but no run-up taught
    brain.wait_ended_at = None
    assert d._in_order("c") is None


def test_an_anchor_is_stale_past_the_longest_run_up_and_a_window():
    d = at(loop(window=20.0), 170.0).decide       # 150 + 20: not yet
    assert not d._stale()
    assert at(loop(window=20.0), 170.5).decide._stale()
    assert loop(runups={}).decide._stale()
    b = loop()
    b.wait_ended_at = None
    assert b.decide._stale()
    # a wait within the window of its run-up anchors; at the window's edge too
    assert at(loop(window=20.0), 70.0).decide._anchors("b")
    assert not at(loop(window=20.0), 70.5).decide._anchors("b")


def test_two_stops_by_place_well_short_of_the_run_up_replace_it():
    # b's run-up is 300 cm after a's wait (a detour in the lesson); the window is 100 cm
    brain = loop(window=100.0, runups={"b": 300.0, "c": 70.0, "a": 150.0})
    d = brain.decide

    def stop(ran: float, *, by_runup: bool = False) -> None:
        d._stopped_at, d._stop_by_runup = brain.wait_ended_at + ran, by_runup
        d._correct_runup("b")

    stop(120.0)                                   # 180 short: recorded, not yet believed
    assert brain.runups["b"] == 300.0 and brain.runup_early == {"b": 120.0}
    stop(170.0)                                   # 50 from the first (window / 2): the mean
    assert brain.runups["b"] == 145.0 and brain.runup_early == {}
    brain.runups["b"] = 300.0
    stop(120.0)
    stop(171.0)                                   # 51 apart: the later one is kept instead
    assert brain.runups["b"] == 300.0 and brain.runup_early == {"b": 171.0}
    stop(200.0)                                   # at the window's edge: in its place, clears
    assert brain.runup_early == {} and brain.runups["b"] == 300.0
    stop(250.0)                                   # in its place with nothing to clear
    assert brain.runup_early == {} and brain.runups["b"] == 300.0
    stop(120.0, by_runup=True)                    # a stop made by the run-up proves nothing
    assert brain.runup_early == {}
    brain.last_wait_drive = "c"                   # not after the drive taught before b
    stop(120.0)
    assert brain.runup_early == {}
    brain.last_wait_drive = "a"
    d._stopped_at = None
    d._correct_runup("b")
    assert brain.runup_early == {}
    brain.runups.pop("b")
    stop(120.0)
    assert brain.runup_early == {} and "b" not in brain.runups


def test_the_odometric_stop_takes_the_taught_stop_timed_as_if_its_place_had_been_entered():
    # a's stop is still@A after place A, 3.5 s into A; the robot runs on in place B, one
    # transition from A, past a's run-up + runup_stop: it approaches a's stop, over at once
    brain = loop(window=20.0, runup_stop=10.0, last="c")
    a_place = brain.layer.recruit("place", 0)
    b_place = brain.layer.recruit("place", 1)
    still = brain.layer.recruit("still", context=a_place)
    moving = brain.layer.recruit("moving", context=a_place)
    brain.graph.add_transition(a_place, still, Action.wait(), 3.5)
    brain.graph.add_transition(still, moving, Action.wait(), 8.0)
    brain.graph.add_transition(b_place, a_place, Action.move(0.0, 30.0), 6.0)
    brain.drives.link("a", (still, moving))     # a drive is linked to its wait
    brain.drives.set_level("a", 1.0)
    brain._ctx_now = b_place
    brain.t = 100.0
    d = brain.decide
    d.mode = Mode.MOVE
    at(brain, 155.0)
    assert not d._runup_due()                     # 150 + 10 not yet run
    at(brain, 160.0)
    assert d._runup_due()
    assert d.mode == Mode.APPROACH and d.current == (a_place, still)
    assert d._approach_t0 == pytest.approx(100.0 - 3.5) and d.current_since == 100.0
    assert d._runup_fired is True and d._by_companion is False and d._entry_timed is False
    d.mode = Mode.WAIT                            # only a robot on a move is stopped so
    assert not d._runup_due()
    assert not loop(runup_stop=-1.0).decide._runup_due()


def test_the_odometric_stop_looks_past_drives_whose_run_up_has_not_passed():
    # the last wait was for b: a (first of the drives) is wanted but due 120 + 150 cm on;
    # c's run-up (70 cm after b) has passed: c's stop, which the map gives no delay, is taken
    brain = loop(window=20.0, runup_stop=10.0, last="b")
    c_place = brain.layer.recruit("place", 0)
    still = brain.layer.recruit("still", context=c_place)
    moving = brain.layer.recruit("moving", context=c_place)
    brain.graph.add_transition(c_place, still, Action.wait(), None)
    brain.graph.add_transition(still, moving, Action.wait(), 8.0)
    brain.drives.link("c", (still, moving))
    brain.drives.set_level("a", 1.0)
    brain.drives.set_level("c", 1.0)
    brain._ctx_now, brain.t = c_place, 50.0
    d = brain.decide
    d.mode = Mode.MOVE
    assert at(brain, 80.0).decide._runup_due()
    assert d.current == (c_place, still) and d._approach_t0 == 50.0   # no delay: over now


def test_within_hops_in_the_map_a_stop_and_its_move_on_stand_for_their_place():
    brain = loop()
    ids = [brain.layer.recruit("place", k) for k in range(4)]
    p0, p1, p2, p3 = ids
    still1 = brain.layer.recruit("still", context=p1)
    moving1 = brain.layer.recruit("moving", context=p1)
    g = brain.graph
    g.add_transition(p0, p1, Action.move(0.0, 10.0))
    g.add_transition(p1, still1, Action.wait())
    g.add_transition(still1, moving1, Action.wait())
    g.add_transition(moving1, p2, Action.move(0.0, 10.0))
    ctx = brain.layer.key
    adj = _context_adjacency(g, lambda s: ctx(s).context if ctx(s).context is not None else s)
    assert adj == {p0: {p1}, p1: {p0, p2}, p2: {p1}}
    d = brain.decide
    brain._ctx_now = p0
    assert d._near_in_map(p0, 0) and not d._near_in_map(p1, 0)
    assert d._near_in_map(p1, 1) and not d._near_in_map(p2, 1)
    assert d._near_in_map(p2, 2) and d._near_in_map(p1, 2)
    assert not d._near_in_map(p3, 5)              # never linked: never near
    brain._ctx_now = still1                       # at the stop: it stands for p1
    assert d._near_in_map(p2, 1) and d._near_in_map(p0, 1)
    brain._ctx_now = p3                           # a place the map has no link from
    assert not d._near_in_map(p0, 3)
    brain._ctx_now = None
    assert not d._near_in_map(p0, 3)


def test_a_held_stop_passed_after_a_lift_re_anchors_when_it_is_due():
    brain = loop()
    a_place = brain.layer.recruit("place", 0)
    still = brain.layer.recruit("still", context=a_place)
    moving = brain.layer.recruit("moving", context=a_place)
    brain.graph.add_transition(a_place, still, Action.wait(), 2.0)
    brain.graph.add_transition(still, moving, Action.wait(), 8.0)
    brain.drives.link("b", (still, moving))
    brain.drives.inhibit("b")                     # held (a, first of the drives, is not)
    d = brain.decide
    brain.wait_ended_at = None
    d.lifted_with_drives()
    assert d.reanchoring()
    brain.t = 10.0
    d.passed_held_stop(a_place)
    assert d._due_anchor == ("b", 12.0)
    brain.odometer, brain.t = 1234.0, 12.0 - 1e-9
    d.reanchor()
    assert brain.wait_ended_at is None            # not yet due
    brain.t = 12.0
    d.reanchor()
    assert brain.wait_ended_at == 1234.0 and brain.last_wait_drive == "b"
    assert d._reanchor is False and d._due_anchor is None
    # a robot already waiting keeps its own anchor
    brain.wait_ended_at = None
    d.lifted_with_drives()
    d._due_anchor, d.mode = ("b", 0.0), Mode.WAIT
    d.reanchor()
    assert brain.wait_ended_at is None and d._reanchor is True
    assert not math.isnan(brain.t)


def test_a_place_win_is_an_alias_only_when_its_stop_is_not_due_and_another_is_just_ahead():
    # due_first: a stop taught only for a (due 270 cm after a's own wait) while c's stop is
    # due 20 cm ahead (at 120): the win is untimely. A stop no wanted drive is taught: not
    brain = loop(window=20.0, ran=100.0, due_first=True)
    a_place, x_place = brain.layer.recruit("place", 0), brain.layer.recruit("place", 1)
    stops = {}
    for place in (a_place, x_place):
        still = brain.layer.recruit("still", context=place)
        moving = brain.layer.recruit("moving", context=place)
        brain.graph.add_transition(place, still, Action.wait(), 2.0)
        brain.graph.add_transition(still, moving, Action.wait(), 8.0)
        stops[place] = (place, still), (still, moving)
    brain.drives.link("a", stops[a_place][1])
    for n in "ac":
        brain.drives.set_level(n, 1.0)
    d = brain.decide
    assert d._untimely(stops[a_place][0])
    assert not d._untimely(stops[x_place][0])     # no wanted drive is taught this stop
    brain.drives.set_level("c", 0.0)
    assert not d._untimely(stops[a_place][0])     # no other wanted drive due ahead


def test_only_a_stop_and_its_move_on_stand_for_their_place_in_the_map():
    # a sound bound to place p0 (a conjunctive kind by choice) is a state of its own: p2,
    # reached through it, is two transitions from p0
    from hippo.perception.states import StateLayerParams
    brain = loop(states=StateLayerParams(conjunctive=("still", "moving", "sound")))
    p0, p2 = brain.layer.recruit("place", 0), brain.layer.recruit("place", 2)
    heard = brain.layer.recruit("sound", context=p0)
    brain.graph.add_transition(p0, heard, Action.wait())
    brain.graph.add_transition(heard, p2, Action.move(0.0, 10.0))
    brain._ctx_now = p0
    assert not brain.decide._near_in_map(p2, 1) and brain.decide._near_in_map(p2, 2)
