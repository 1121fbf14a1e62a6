"""The decider's rules (:mod:`hippo.decision`) on known answers: a brain whose map, state layer
and drives are set by hand, one decider method called and its answer checked.

The activity of a transition is the drive's link weight to its goal (one link: W = 0.5) times
``w`` = 0.9 per hop back from it (PlannerParams), so a move one hop closer to a goal has the
higher activity; the robot runs east (heading 0) unless a test turns it."""

import dataclasses
import math

import numpy as np
import pytest

from hippo.brain import Brain, BrainParams
from hippo.cognitive_map import Action, DriveParams, PlannerParams
from hippo.types import Mode, StateKind, wrap_angle

EAST, WEST = 0.0, math.pi


class NoPlaces:
    kind, n_units = "stub", 1


def brain(drives: str = "ab", *, seed: int = 0, rng=None, **params) -> Brain:
    return Brain(NoPlaces(), drives={n: DriveParams() for n in drives},
                 params=BrainParams(**params), seed=seed, rng=rng)


def places(b: Brain, n: int) -> list[int]:
    return [b.layer.recruit("place", i) for i in range(n)]


def stop(b: Brain, place: int, drive: str | None = None) -> tuple[int, int]:
    """``place -> still@place -> moving@place`` (waits); ``drive`` (made active) wants the wait
    after the stop. Returns the stop ``(place, still@place)`` (activity 0.9 x the wait's)."""
    still = b.layer.recruit("still", context=place)
    moving = b.layer.recruit("moving", context=place)
    b.graph.add_transition(place, still, Action.wait(), 3.0)
    b.graph.add_transition(still, moving, Action.wait(), 10.0)
    if drive is not None:
        b.drives.link(drive, (still, moving))
        b.drives.set_level(drive, 1.0)
    return place, still


def move(b: Brain, a: int, c: int, heading: float = EAST) -> tuple[int, int]:
    b.graph.add_transition(a, c, Action.move(heading, 20.0), 2.0)
    return a, c


def moving_robot(d, heading: float = EAST) -> None:
    d.mode, d.heading = Mode.MOVE, heading


# -- reset, and where the map knows nothing -----------------------------------------------------
def test_a_new_episode_starts_exploring_with_nothing_under_way_timed_from_now():
    b = brain()
    d = b.decide
    p, q = places(b, 2)
    b.t = 5.0
    d.mode, d.current, d.heading = Mode.WAIT, (p, q), 1.0
    d.current_since = d._approach_t0 = d._wait_since = 1.0
    d._waiting_on, d._stopped_at = (p, q), 3.0
    d._omitted_early = d._runup_fired = d._by_companion = d._stop_by_runup = True
    d._entry_timed = d.stop_untimed = True
    d._inhibited, d._inhibited_at = {"a": p}, {"a": (1.0, 2.0)}
    d.reset_episode()
    assert d.mode == Mode.EXPLORE and d.current is None and d.heading is None
    assert d.current_since == d._approach_t0 == d._wait_since == 5.0
    assert d._waiting_on is None and d._stopped_at is None
    assert d._inhibited == {} and d._inhibited_at == {}
    for flag in ("_omitted_early", "_runup_fired", "_by_companion", "_stop_by_runup",
                 "_entry_timed", "stop_untimed"):
        assert getattr(d, flag) is False, flag


def test_a_state_the_map_does_not_know_keeps_a_moving_robot_on_its_heading_else_explores():
    b = brain()
    d = b.decide
    (p,) = places(b, 1)
    b.t = 2.0
    moving_robot(d, 0.4)
    d._runup_fired = d._by_companion = True
    d.choose(p)                                   # p is not in the map
    assert d.mode == Mode.MOVE and d.current is None and d.current_since == 2.0
    assert d._runup_fired is False and d._by_companion is False
    d.mode = Mode.EXPLORE                         # exploring, a heading kept from before
    d.choose(p)
    assert d.mode == Mode.EXPLORE
    d.mode, d.heading = Mode.MOVE, None           # moving with no heading: nothing to keep
    d.choose(p)
    assert d.mode == Mode.EXPLORE


def test_with_only_a_stop_out_of_a_place_moving_on_after_a_wait_is_lost():
    b = brain()
    d = b.decide
    (p,) = places(b, 1)
    stop(b, p, "a")
    moving_robot(d)
    d.choose(p, exclude_wait=True)               # no move out of p: keep the heading
    assert d.mode == Mode.MOVE and d.current is None
    d.mode, d.heading = Mode.WAIT, None
    d.choose(p, exclude_wait=True)
    assert d.mode == Mode.EXPLORE and d.current is None


def test_an_active_drive_with_no_reachable_goal_explores_with_the_wall_follower():
    b = brain()
    d = b.decide
    p, q, x, y = places(b, 4)
    move(b, p, q)
    move(b, x, y)
    b.drives.link("a", (x, y))                    # a's goal: not reachable from p
    b.drives.set_level("a", 1.0)
    moving_robot(d)
    d.choose(p)
    assert d.mode == Mode.EXPLORE and d.current is None


def test_with_no_drive_the_robot_explores_by_moving_never_by_stopping():
    b = brain()
    d = b.decide
    p, q = places(b, 2)
    stop(b, p)                                    # no drive linked, none active
    for seed in range(6):
        b.rng = np.random.default_rng(seed)
        moving_robot(d, 0.3)
        d.choose(p)                               # only the stop: no known move
        assert d.mode == Mode.MOVE and d.current is None and d.heading == 0.3
    move(b, p, q, 0.8)
    for seed in range(6):
        b.rng = np.random.default_rng(seed)
        d.mode = Mode.EXPLORE
        d.choose(p)
        assert d.current == (p, q) and d.mode == Mode.MOVE and d.heading == 0.8


# -- motor continuity ---------------------------------------------------------------------------
def test_a_move_turns_the_robot_round_only_past_turn_limit_from_its_own_heading():
    b = brain()
    d = b.decide
    p, q, r = places(b, 3)
    ahead, back = move(b, p, q, 1.2), move(b, p, r, 1.2 + 2.0)
    b.pi.reset((0.0, 0.0, 1.0))                   # the robot heads 1.0 rad
    assert not d._turns(ahead)                    # 0.2 rad off its heading
    assert d._turns(back)                         # 2.2 rad off: more than 1.75
    edge = abs(wrap_angle(d._direction(back) - 1.0))   # the turn, as the robot measures it
    b.p = dataclasses.replace(b.p, turn_limit=edge)
    assert not d._turns(back)                     # exactly turn_limit: no turn round
    b.p = dataclasses.replace(b.p, turn_limit=math.nextafter(edge, 0.0))
    assert d._turns(back)
    (s,) = stop(b, q)[1:]
    assert not d._turns((q, s))                   # a wait has no direction


def continuity(**params):
    """p with a move west one hop from drive a's stop (activity 0.9^2 W = 0.405) and a move
    east two hops from drive b's (0.9^3 W = 0.3645); the robot heads east."""
    b = brain(**params)
    p, w, e, f = places(b, 4)
    west, east = move(b, p, w, WEST), move(b, p, e, EAST)
    move(b, e, f)
    stop(b, w, "a")
    stop(b, f, "b")
    assert b.decide._activity(west) > b.decide._activity(east) > 0.5 * b.decide._activity(west)
    return b, p, west, east


def test_a_move_that_would_turn_a_moving_robot_round_is_discounted():
    # discounted, the move west has 0.5 x 0.405 = 0.2025 < 0.3645: the robot keeps east (and
    # the pick is the most active one, whatever the random stream)
    b, p, west, east = continuity()
    d = b.decide
    for seed in range(8):
        b.rng = np.random.default_rng(seed)
        moving_robot(d)
        d.choose(p)
        assert d.current == east and d.mode == Mode.MOVE and d.heading == EAST
    d.mode, d.heading = Mode.EXPLORE, None        # not moving: no heading to keep, west wins
    d.choose(p)
    assert d.current == west and d.heading == pytest.approx(WEST)
    d.mode = Mode.WAIT                            # moving on after a wait it still faces east
    b.pi.reset((0.0, 0.0, EAST))
    d.choose(p, exclude_wait=True)
    assert d.current == east


def test_a_mild_turn_discount_leaves_a_much_stronger_move_round_ahead():
    b, p, west, _ = continuity(turn_discount=0.95)
    d = b.decide
    moving_robot(d)
    d.choose(p)
    assert d.current == west                      # 0.95 x 0.405 = 0.385 > 0.3645


@pytest.mark.parametrize("own", [True, False])
def test_with_no_activity_left_after_the_stop_is_excluded_a_move_is_picked_at_random(own):
    # the planner picks the stop (the only active way); moving on after the wait excludes it,
    # and neither move out has activity: a random one, each for some seed (own_stops_only
    # draws it among the moves, else among all the transitions left)
    b = brain(own_stops_only=own)
    d = b.decide
    p, q, r, f = places(b, 4)
    stop(b, p, "a")
    one, two = move(b, p, q), move(b, p, r)
    picks = set()
    for seed in range(12):
        b.rng = np.random.default_rng(seed)
        d.mode = Mode.WAIT
        d.choose(p, exclude_wait=True)
        picks.add(d.current)
    assert picks == {one, two}
    move(b, r, f)                                 # now r leads to b's stop: two hops, 0.3645
    stop(b, f, "b")
    for seed in range(8):
        b.rng = np.random.default_rng(seed)
        d.mode = Mode.WAIT
        d.choose(p, exclude_wait=True)
        assert d.current == two                   # the most active move, every time


def test_on_a_tie_the_planners_pick_from_the_brains_random_stream_stands():
    # two moves of equal activity (each one hop before a stop), no planner noise: the planner
    # picks one at random from the brain's stream, and the decider keeps that pick: both come
    # up over the seeds, and two brains on the same stream (planner seeds apart) agree
    def picks(seed: int, stream: int) -> list:
        b = brain(seed=seed, rng=np.random.default_rng(stream),
                  planner=PlannerParams(noise=0.0))
        d = b.decide
        p, q, r = places(b, 3)
        move(b, p, q, 0.5)
        move(b, p, r, -0.5)
        stop(b, q, "a")
        stop(b, r, "b")
        out = []
        for _ in range(16):
            d.mode = Mode.EXPLORE
            d.choose(p)
            out.append(d.current)
        return out

    first = picks(1, 5)
    assert len(set(first)) == 2
    assert picks(2, 5) == first


# -- a stop only for a drive that wants it ------------------------------------------------------
def unwanted_stop():
    """p's stop serves drive a, held by a finished wait; past it the map leads to b's stop (so
    the planner prefers p's stop), and a move p -> q leads nowhere."""
    b = brain()
    p, q, r = places(b, 3)
    s = stop(b, p)
    b.drives.link("a", (s[1], b.layer.find("moving", context=p)))
    b.drives.inhibit("a")
    move(b, b.layer.find("moving", context=p), r)
    stop(b, r, "b")
    return b, p, q, s


def test_a_stop_no_free_drive_wants_is_no_way_on_and_the_robot_moves_instead():
    b, p, q, s = unwanted_stop()
    d = b.decide
    assert b.planner.decide(b.graph, b.drives, p, b.rng).transition == s
    d.mode = Mode.EXPLORE
    d.choose(p)                                   # only the stop out: no move to take
    assert d.mode == Mode.EXPLORE and d.current is None
    moving_robot(d)
    d.choose(p)
    assert d.mode == Mode.MOVE and d.current is None
    on = move(b, p, q)                            # a move with no activity: it is taken
    for seed in range(4):
        b.rng = np.random.default_rng(seed)
        d.mode = Mode.EXPLORE
        d.choose(p)
        assert d.current == on and d.mode == Mode.MOVE
    b.drives.release("a")                         # a free again and active: p's stop serves it
    b.drives.set_level("a", 1.0)
    d.mode = Mode.EXPLORE
    d.choose(p)
    assert d.current == s and d.mode == Mode.APPROACH
    b.drives.inhibit("a")
    b.p = dataclasses.replace(b.p, own_stops_only=False)   # without the rule: the short cut
    d.mode = Mode.EXPLORE
    d.choose(p)
    assert d.current == s


def test_a_stop_wanted_needs_a_free_active_drive_linked_to_the_wait_after_it():
    b = brain()
    d = b.decide
    p, q = places(b, 2)
    _, still = stop(b, p, "a")
    assert d._stop_wanted(still)
    b.drives.set_level("a", b.p.planner.exploration_threshold)   # at the threshold: active
    assert d._wanted("a") and d._stop_wanted(still) and d._drive_active()
    b.drives.set_level("a", 0.04)
    assert not d._wanted("a") and not d._stop_wanted(still) and not d._drive_active()
    b.drives.set_level("a", 1.0)
    b.drives.inhibit("a")
    assert not d._wanted("a") and not d._stop_wanted(still)
    unknown = b.layer.recruit("still", context=q)  # a stop the map does not hold
    assert not d._stop_wanted(unknown)


def test_an_untimely_stop_is_passed_by_a_robot_choosing_afresh_on_a_move_out_of_its_place():
    # the stop p would approach is an alias of one farther on (_untimely): not moving with a
    # heading, the robot chooses again without the stop, and takes the move out of p
    b = brain()
    d = b.decide
    p, q = places(b, 2)
    s = stop(b, p, "a")
    on = move(b, p, q)
    d._untimely = lambda tr: tr == s
    b.state = None                                # choose(p) asks about p, not the brain's
    d.mode = Mode.EXPLORE
    d.choose(p)
    assert d.current == on and d.mode == Mode.MOVE
    moving_robot(d, 0.3)                          # moving: it drives on as it goes
    d.choose(p)
    assert d.current is None and d.mode == Mode.MOVE and d.heading == 0.3
    d._untimely = lambda tr: False
    d.choose(p)
    assert d.current == s and d.mode == Mode.APPROACH


# -- at a sensory event -------------------------------------------------------------------------
def test_an_approach_goes_on_through_a_place_unless_that_place_knows_the_stop():
    b = brain()
    d = b.decide
    p, e, k = places(b, 3)
    s = stop(b, p, "a")
    move(b, e, p)
    b.graph.add_transition(k, s[1], Action.wait(), 2.0)   # k knows p's stop (an alias)
    d.mode, d.current = Mode.APPROACH, s
    b.state = e
    d.on_event(e, StateKind.PLACE, p)             # e does not: the approach goes on
    assert d.mode == Mode.APPROACH and d.current == s
    b.state = k
    d.on_event(k, StateKind.PLACE, p)             # k does: the robot chooses there
    assert d.mode == Mode.APPROACH and d.current == (k, s[1])
    # re-entering the stop's own place chooses afresh: a stop the map forgot meanwhile (the
    # map's decay, ``forget``) is not approached any longer: a's goal is out of reach, the
    # robot explores
    b.graph.remove_transition((k, s[1]))
    b.graph.remove_transition(s)
    d.mode, d.current = Mode.APPROACH, s
    b.state = p
    d.on_event(p, StateKind.PLACE, e)
    assert d.mode == Mode.EXPLORE and d.current is None


def test_a_place_winning_while_the_robot_brakes_for_its_stop_is_ignored_for_still_grace():
    b = brain()
    d = b.decide
    p, e = places(b, 2)
    s = stop(b, p, "a")
    move(b, e, p)
    grace = d.still_grace                         # (2 + 2) x 0.2 s
    assert grace == pytest.approx(0.8)
    d.mode, d._waiting_on, d._wait_since = Mode.WAIT, s, 0.0
    b.t, b.state = grace, e                       # exactly the grace: still braking
    d.on_event(e, StateKind.PLACE, p)
    assert d.mode == Mode.WAIT and d._waiting_on == s
    b.t = math.nextafter(grace, 1.0)              # past it: e is where the robot is
    d.on_event(e, StateKind.PLACE, p)
    assert d._waiting_on is None and d.current == (e, p) and d.mode == Mode.MOVE


def moving_on():
    """c's stop (drive a active) with its wait; c -> f a move with no activity."""
    b = brain()
    c, f, x = places(b, 3)
    s = stop(b, c, "a")
    on = move(b, c, f)
    b.state = b.layer.find("moving", context=c)   # the brain is in moving@c (no way out)
    return b, c, x, s, on


def test_moving_again_keeps_the_move_chosen_when_the_wait_ended_else_chooses_from_the_place():
    b, c, x, s, on = moving_on()
    d = b.decide
    new = b.state
    kept = (c, x)                                 # chosen when the wait ended
    d.mode, d.current = Mode.MOVE, kept
    d.on_event(new, StateKind.MOVING, s[1])
    assert d.current == kept and d.mode == Mode.MOVE
    d.mode, d.current = Mode.MOVE, None           # no move chosen: from c, never its stop
    d.on_event(new, StateKind.MOVING, s[1])
    assert d.current == on and d.mode == Mode.MOVE
    d.mode, d.current = Mode.EXPLORE, kept        # not moving: choose
    d.on_event(new, StateKind.MOVING, s[1])
    assert d.current == on


def habituating(**params):
    """p -> q -> q's stop for drive a: entering p the robot moves to q."""
    b = brain(cycle_visits=3, cycle_window=10.0, cycle_explore=20.0, **params)
    p, q, r = places(b, 3)
    on = move(b, p, q)
    stop(b, q, "a")
    b.state = p
    return b, p, r, on


def test_entering_a_place_cycle_visits_times_in_cycle_window_explores_for_cycle_explore():
    b, p, r, on = habituating()
    d = b.decide
    for t in (100.0, 101.0):
        b.t = t
        d.on_event(p, StateKind.PLACE, r)
        assert d.current == on and d.mode == Mode.MOVE
    b.t = 102.0
    d.on_event(p, StateKind.PLACE, r)             # the third entry within 10 s
    assert d.mode == Mode.EXPLORE and d.current is None
    b.t = 121.9                                   # explores until 102 + 20 ...
    d.on_event(p, StateKind.PLACE, r)
    assert d.mode == Mode.EXPLORE
    d._visits.clear()
    b.t = 122.0                                   # ... and chooses again at 122
    d.on_event(p, StateKind.PLACE, r)
    assert d.current == on and d.mode == Mode.MOVE


def test_only_entering_a_place_from_a_place_counts_towards_habituation():
    b, p, r, on = habituating()
    d = b.decide
    s = b.layer.recruit("still", context=r)
    for t in (100.0, 101.0, 102.0):               # entered from a stop, or as the first state
        b.t = t
        d.on_event(p, StateKind.PLACE, s if t < 102.0 else None)
    assert d.current == on and d.mode == Mode.MOVE
    b, p, r, on = habituating()
    d = b.decide
    still = b.layer.find("still", context=b.layer.find("place", 1))
    for t in (100.0, 101.0, 102.0):               # a stillness is no place entered
        b.t = t
        b.state = still
        d.on_event(still, StateKind.STILL, p)
    assert d._explore_until == -math.inf


def test_habituation_counts_one_place_in_the_window_and_only_while_a_drive_is_active():
    b, p, r, _ = habituating()
    d = b.decide
    b.t = 100.0
    assert not d._cycling(p)                      # one entry
    b.t = 110.0                                   # the first exactly cycle_window ago: counts
    assert not d._cycling(p)
    b.t = 110.0
    assert d._cycling(p)                          # three entries
    b, p, r, _ = habituating()
    d = b.decide
    for t in (100.0, 105.0):
        b.t = t
        assert not d._cycling(r)                  # another place, twice
    b.t = 110.5                                   # 100 is past the window, 105 is not
    assert not d._cycling(p) and not d._cycling(p)
    assert d._cycling(p)                          # p three times (r's entries do not count)
    b, p, r, _ = habituating()
    d = b.decide
    b.drives.set_level("a", 0.0)                  # no drive active: no habituation
    assert not any(d._cycling(p) for _ in range(5))


# -- the source of a stop recognised softly, and releasing held drives --------------------------
def test_a_stop_made_while_another_place_won_is_the_stop_it_waited_for_timed_from_then():
    # waiting (braking) for c's stop, recognised at t = 3; the stillness comes while place k
    # wins (entered at t = 7): what the robot did is c -> still@c, timed from 3
    b = brain()
    d = b.decide
    c, k, x = places(b, 3)
    _, still = stop(b, c)
    other = b.layer.recruit("still", context=x)
    d.mode, d._waiting_on, d._approach_t0 = Mode.WAIT, (c, still), 3.0
    src = d.intended_source
    assert src(still, StateKind.STILL, k, 7.0) == (c, 3.0)
    assert src(still, StateKind.STILL, c, 7.0) == (c, 7.0)          # c itself won: as it is
    assert src(still, StateKind.STILL, None, 7.0) == (None, 7.0)    # no transition
    assert src(other, StateKind.STILL, k, 7.0) == (k, 7.0)          # another stop
    assert src(still, StateKind.MOVING, k, 7.0) == (k, 7.0)         # not a stillness
    d.mode = Mode.APPROACH                                          # not (yet) waiting for it
    assert src(still, StateKind.STILL, k, 7.0) == (k, 7.0)
    d.mode, d._waiting_on = Mode.WAIT, None
    assert src(still, StateKind.STILL, k, 7.0) == (k, 7.0)


def held(release_distance: float = 60.0):
    """Drive a held by a wait at c's stop, which ended at (0, 100); from q the map stops at c
    (q -> still@c), from r it does not."""
    b = brain(release_distance=release_distance)
    d = b.decide
    c, q, r = places(b, 3)
    _, still = stop(b, c, "a")
    b.graph.add_transition(q, still, Action.wait(), 2.0)
    move(b, c, r)
    b.drives.inhibit("a")
    d._inhibited, d._inhibited_at = {"a": c}, {"a": (0.0, 100.0)}
    return b, d, c, q, r


def test_a_held_drive_is_released_at_release_distance_from_a_place_that_does_not_stop_there():
    b, d, c, q, r = held()
    b.pi.reset((0.0, 100.0, 0.0))                 # where the wait ended
    d.release_away_from(r)
    assert b.drives.is_inhibited("a")
    b.pi.reset((0.0, 160.0 - 1e-9, 0.0))          # just short of 60 cm (north)
    d.release_away_from(r)
    assert b.drives.is_inhibited("a")
    b.pi.reset((0.0, 160.0, 0.0))                 # 60 cm north: far enough, in r
    for place in (c, q):                          # c itself, or a place that stops at c
        d.release_away_from(place)
        assert b.drives.is_inhibited("a")
    d.release_away_from(r)
    assert not b.drives.is_inhibited("a") and d._inhibited == {} and d._inhibited_at == {}
    b, d, c, q, r = held()
    b.pi.reset((60.0, 100.0, 0.0))                # 60 cm east
    d.release_away_from(r)
    assert not b.drives.is_inhibited("a")


def test_a_held_drive_with_no_place_of_release_recorded_counts_from_where_the_robot_is():
    b, d, _, _, r = held(release_distance=0.0)
    del d._inhibited_at["a"]
    d.release_away_from(r)
    assert not b.drives.is_inhibited("a") and d._inhibited == {}
    b, d, _, _, r = held()
    del d._inhibited_at["a"]
    b.pi.reset((500.0, 0.0, 0.0))
    d.release_away_from(r)
    assert b.drives.is_inhibited("a")
