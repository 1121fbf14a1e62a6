"""The Brain's own rules (:mod:`hippo.brain`) on known answers: a brain whose map, state layer,
drives and odometry are set by hand, one method called and its answer checked against one
worked out by hand (rewards and run-ups, learning a transition, the lesson on another goal,
the tick's move limit, lifts, proprioception, occlusion, direction sectors)."""

import math

import numpy as np
import pytest

from hippo.brain import Brain, BrainParams
from hippo.cognitive_map import Action, DriveParams
from hippo.cognitive_map.localise import LocaliserParams
from hippo.perception.states import StateLayerParams
from hippo.seeds import Seeds
from hippo.timing import NonOccurrenceParams, SpectralParams
from hippo.types import Mode, Observation, StateKind

DT = 0.2


class NoPlaces:
    kind, n_units = "stub", 1


class Stub:
    """A place source reporting the place it is told; counts its lifts and the readings seen."""

    kind, n_units = "stub", 3

    def __init__(self) -> None:
        self.where, self.lifts, self.seen = 0, 0, []

    def step(self, obs, truth=None):
        self.seen.append(np.array(obs.ir, dtype=float))
        return np.eye(3)[self.where]

    def lifted(self) -> None:
        self.lifts += 1


def brain(drives: str = "ab", **params) -> Brain:
    return Brain(NoPlaces(), drives={n: DriveParams() for n in drives},
                 params=BrainParams(**params))


def stub_brain(**params) -> tuple[Brain, Stub]:
    src = Stub()
    params.setdefault("settle_time", 0.0)
    p = BrainParams(states=StateLayerParams(normalize="fixed", place_scale=0.5,
                                            context_time=1.0), **params)
    return Brain(src, drives={"sound": DriveParams()}, params=p), src


def obs(k: int, *, odo=(0.0, 0.0, 0.0), moving: bool = True, ir: float = 0.5,
        sound: bool = False) -> Observation:
    return Observation(round(k * DT, 9), k, np.full(8, ir), 0, sound, np.array(odo, float),
                       moving)


def stop(b: Brain, place: int) -> tuple[int, int]:
    """``still@place`` and ``moving@place``."""
    return b.layer.recruit("still", context=place), b.layer.recruit("moving", context=place)


# -- a new brain -------------------------------------------------------------------------------
def test_a_new_brain_is_built_from_its_params_and_starts_at_rest():
    p = BrainParams(spectral=SpectralParams(n_cells=64), relocalise=LocaliserParams(n_known=2),
                    non_occurrence=NonOccurrenceParams(min_peak=0.3))
    b = Brain(Stub(), params=p)
    assert b.spectral.params.n_cells == 64 and b.nonocc.params.min_peak == 0.3
    assert b.planner.params is p.planner and b.planner.params.w == 0.9
    assert b.localiser is not None and b.localiser.params.n_known == 2
    assert b.layer._n_place0 == 3                       # the source's 3 units, one sector
    assert Brain().layer._n_place0 == 0                 # no place source: no place units
    assert b.drives.names == ["sound"]                  # the default drive
    assert b.odometer == 0.0 and b.t == 0.0 and b.entered_at == 0.0
    assert b._clear_view is None and b._moving is True and b._flip == 0
    assert b._settle_until == -math.inf
    # the brain's stream of the run's seed (default 0) and the planner seeded with it
    assert b.rng.random() == Seeds(0).generator("brain").random()
    assert b.planner.rng.random() == np.random.default_rng(0).random()
    c = Brain(Stub(), seed=5)
    assert c.rng.random() == Seeds(5).generator("brain").random()
    assert c.planner.rng.random() == np.random.default_rng(5).random()


# -- rewards and run-ups ------------------------------------------------------------------------
def test_a_reward_of_an_unknown_drive_is_refused_naming_the_known_ones():
    b = brain()
    with pytest.raises(KeyError, match=r"unknown drive 'x'; known: a, b"):
        b.reward("x")
    assert b._pending_rewards == [] and b._rewarded_at is None


def test_a_reward_teaches_the_run_since_the_reward_before_if_near_the_run_up_taught():
    b = brain(runup_window=30.0)
    b.odometer = 100.0
    b.reward("a")                      # the first reward only anchors
    assert b.runups == {} and b.runup_after == {}
    assert b._rewarded_at == b.wait_ended_at == 100.0
    assert b._rewarded_drive == b.last_wait_drive == "a"
    assert b._pending_rewards == ["a"]
    b.odometer = 180.0
    b.reward("b")                      # 80 cm after a: b's run-up, after a
    assert b.runups == {"b": 80.0} and b.runup_after == {"b": "a"}
    b.odometer = 260.0
    b.reward("a")                      # 80 cm after b
    assert b.runups == {"b": 80.0, "a": 80.0} and b.runup_after == {"b": "a", "a": "b"}
    b.odometer = 370.0
    b.reward("b")                      # 110 cm: |110 - 80| = 30 = the window: replaces it
    assert b.runups["b"] == 110.0
    b.odometer = 481.0
    b.reward("a")                      # 111 cm: |111 - 80| = 31 > 30: a block after hours
    assert b.runups["a"] == 80.0       # keeps the run-up taught ...
    assert b.wait_ended_at == b._rewarded_at == 481.0   # ... and anchors the next one
    b.odometer = 400.0
    b._rewarded_at = 481.0
    b.reward("b")                      # 81 cm back (-81): |-81 - 110| far out of the window
    assert b.runups["b"] == 110.0
    assert b._pending_rewards == ["a", "b", "a", "b", "a", "b"]


def test_a_reward_after_a_detour_or_with_no_drive_before_teaches_no_run_up():
    b = brain(runup_window=30.0)
    b._rewarded_at, b._rewarded_drive, b.odometer = 0.0, "a", 50.0
    b.reward("b", runup=False)         # led back from a detour: no run-up, but anchors
    assert b.runups == {} and b._rewarded_at == b.wait_ended_at == 50.0
    assert b.last_wait_drive == b._rewarded_drive == "b"
    b.odometer = 90.0
    b.reward("a")                      # the run since that anchor counts: 40 cm after b
    assert b.runups == {"a": 40.0} and b.runup_after == {"a": "b"}
    c = brain()
    c._rewarded_at, c.odometer = 0.0, 50.0   # an anchor with no drive rewarded at it
    c.reward("a")
    assert c.runups == {} and c._rewarded_drive == "a"


# -- the lesson repeated on another drive's goal ------------------------------------------------
def goal_map() -> tuple[Brain, int, int, int]:
    """Place p with its stop ``still@p -> moving@p``, drive a's goal; b's goal elsewhere."""
    b = brain()
    p = b.layer.recruit("place", 0)
    q = b.layer.recruit("place", 1)
    still, moving = stop(b, p)
    b.graph.add_transition(still, moving, Action.wait(), 5.0)
    b.drives.link("a", (still, moving))
    qs, qm = stop(b, q)
    b.drives.link("b", (qs, qm))
    return b, p, still, moving


def test_a_lesson_on_another_drives_goal_only_when_every_rewarded_drive_has_its_own():
    b, p, still, moving = goal_map()
    assert not b._lesson_on_another_goal(still, moving)        # nothing pending
    b._pending_rewards = ["b"]
    assert b._lesson_on_another_goal(still, moving)            # b has its own goal
    assert not b._lesson_on_another_goal(None, moving)
    assert not b._lesson_on_another_goal(p, still)             # not a wait out of a stop
    assert not b._lesson_on_another_goal(moving, still)        # not a goal at all
    b.drives.link("a", (p, still))
    assert not b._lesson_on_another_goal(p, still)             # a's goal, but no wait
    b._pending_rewards = ["b", "a"]
    assert not b._lesson_on_another_goal(still, moving)        # a lesson for a's own goal
    b._pending_rewards = ["b"]
    b.drives.unlink("b", next(iter(b.drives.links("b"))))
    assert not b._lesson_on_another_goal(still, moving)        # b has no goal yet: learn


def test_a_lesson_on_another_goal_satisfies_its_drive_and_learns_nothing():
    b, _p, still, moving = goal_map()
    b.drives.set_level("b", 0.7)
    b._pending_rewards = ["b"]
    n = len(b.graph)
    b._learn(still, moving, 24.0, b.pi.pose)
    assert b.drives.level("b") == 0.0 and b._pending_rewards == []
    assert len(b.graph) == n and b.graph.delay((still, moving)) == 5.0
    assert b.last_transition is None
    assert set(b.drives.links("b")) != {(still, moving)}


# -- learning a transition ----------------------------------------------------------------------
def test_a_move_is_learned_with_the_heading_and_distance_run_since_entering():
    b = brain()
    p, q = b.layer.recruit("place", 0), b.layer.recruit("place", 1)
    b.pi.reset((4.0, 6.0, 0.0))
    b.t = 7.0
    b._learn(p, q, 2.5, (1.0, 2.0, 1.0))          # from (1, 2) to (4, 6): 5 cm at atan2(4, 3)
    act = b.graph.action((p, q))
    assert not act.is_wait and act.distance == pytest.approx(5.0)
    assert act.heading == pytest.approx(math.atan2(4.0, 3.0))
    assert b.graph.delay((p, q)) == 2.5 and b.graph.count((p, q)) == 1
    assert b.graph.attributes((p, q))["last_used"] == 7.0
    assert b.graph.position(q) == (4.0, 6.0) and b.last_transition == (p, q)
    assert (q, p) not in b.graph                    # infer_reverse off by default


def test_a_change_of_place_without_moving_is_learned_as_a_wait():
    b = brain()
    p, q, r = (b.layer.recruit("place", i) for i in range(3))
    b.pi.reset((1.0, 1.0, 0.0))
    b._learn(p, q, 1.0, (1.0, 1.0 + 0.9e-6, 0.0))    # 0.9e-6 cm < 1e-6: no move
    assert b.graph.action((p, q)).is_wait
    b._learn(p, r, 1.0, (1.0, 1.0 + 2e-6, 0.0))      # 2e-6 cm: a (tiny) move due south
    act = b.graph.action((p, r))
    assert not act.is_wait and act.heading == pytest.approx(-math.pi / 2)
    s = b.layer.recruit("place", 3)
    b.pi.reset((1e-6, 0.0, 0.0))
    b._learn(p, s, 1.0, (0.0, 0.0, 0.0))             # exactly 1e-6 cm: already a move
    assert not b.graph.action((p, s)).is_wait


def test_a_stop_a_resume_and_the_sound_are_waits_however_far_the_robot_went():
    b = brain("a")
    p = b.layer.recruit("place", 0)
    still, moving = stop(b, p)
    sound = b.layer.recruit("sound")
    b.pi.reset((50.0, 0.0, 0.0))
    far = (0.0, 0.0, 0.0)
    b._learn(p, still, 1.0, far)                     # into a stop
    b._learn(still, moving, 1.0, far)                # out of a stop
    b._learn(still, sound, 1.0, far)                 # the sound
    for tr in ((p, still), (still, moving), (still, sound)):
        assert b.graph.action(tr).is_wait, tr
    b._learn(moving, p, 1.0, far)                    # moving@p -> p: a move
    assert not b.graph.action((moving, p)).is_wait


def test_the_sound_rewards_the_sound_drive_and_pending_rewards_link_the_transition():
    b = Brain(NoPlaces(), drives={"sound": DriveParams(), "a": DriveParams()})
    p = b.layer.recruit("place", 0)
    still, _ = stop(b, p)
    sound = b.layer.recruit("sound")
    b.drives.set_level("sound", 0.8)
    b.drives.set_level("a", 0.6)
    b._pending_rewards = ["a"]
    b._learn(still, sound, 2.0, b.pi.pose)
    assert b.drives.level("sound") == 0.0 and (still, sound) in b.drives.links("sound")
    assert b.drives.level("a") == 0.0 and (still, sound) in b.drives.links("a")
    assert b._pending_rewards == []
    b.drives.set_level("sound", 0.8)
    b._learn(p, still, 1.0, b.pi.pose)               # not the sound: the drive not rewarded
    assert b.drives.level("sound") == 0.8 and (p, still) not in b.drives.links("sound")
    nosound = brain("a")                            # no drive "sound": the sound links nothing
    q = nosound.layer.recruit("place", 0)
    s2 = nosound.layer.recruit("sound")
    nosound._learn(q, s2, 1.0, nosound.pi.pose)
    assert nosound.drives.links("a") == {}


def test_infer_reverse_adds_the_way_back_only_of_a_first_move_between_contexts():
    b = brain(infer_reverse=True)
    p, q, r = (b.layer.recruit("place", i) for i in range(3))
    _still, moving = stop(b, p)
    b.pi.reset((10.0, 0.0, 0.0))
    b._learn(p, q, 1.0, (0.0, 0.0, 0.0))
    assert (q, p) in b.graph and b.graph.inferred((q, p))
    assert b.graph.attributes((q, p))["last_used"] == b.t == 0.0
    b.graph.remove_transition((q, p))
    b.graph.remove_transition((p, q))
    b.t = 3.0
    b._learn(p, q, 1.0, (0.0, 0.0, 0.0))
    assert b.graph.attributes((q, p))["last_used"] == 3.0    # inferred now
    b.graph.remove_transition((q, p))
    b._learn(p, q, 1.0, (0.0, 0.0, 0.0))            # a repeat (count 2): nothing inferred
    assert b.graph.count((p, q)) == 2 and (q, p) not in b.graph
    b._learn(moving, r, 1.0, (0.0, 0.0, 0.0))       # from a resume: not between contexts
    assert (r, moving) not in b.graph
    off = brain()
    x, y = off.layer.recruit("place", 0), off.layer.recruit("place", 1)
    off.pi.reset((10.0, 0.0, 0.0))
    off._learn(x, y, 1.0, (0.0, 0.0, 0.0))
    assert (y, x) not in off.graph


def test_forgetting_decays_the_map_and_prunes_the_links_to_what_it_dropped():
    b = brain(forget=0.5)
    p, q, r = (b.layer.recruit("place", i) for i in range(3))
    b.graph.add_transition(p, q, Action.wait(), 1.0)
    b.drives.link("a", (p, q))
    b._learn(q, r, 1.0, b.pi.pose)   # strength 1 -> 0.5: kept, the link with it
    assert (p, q) in b.graph and (p, q) in b.drives.links("a")
    for _ in range(4):               # 0.5^5 = 0.03 < 0.05: dropped, and a's link with it
        b._learn(q, r, 1.0, b.pi.pose)
    assert (p, q) not in b.graph and b.drives.links("a") == {}
    keep = brain()                   # forget 1.0: nothing decays
    x, y, z = (keep.layer.recruit("place", i) for i in range(3))
    keep.graph.add_transition(x, y, Action.wait(), 1.0)
    keep.graph._g.nodes[(x, y)]["strength"] = 0.01   # weak (a map kept from a forgetful run)
    for _ in range(3):
        keep._learn(y, z, 1.0, keep.pi.pose)
    assert (x, y) in keep.graph and keep.graph.attributes((x, y))["strength"] == 0.01


# -- the tick's move limit, abandoning a move ---------------------------------------------------
def test_a_move_may_take_move_timeout_times_its_delay_plus_move_margin():
    b = brain(move_timeout=3.0, move_margin=5.0, default_delay=4.0)
    d = b.decide
    p, q = b.layer.recruit("place", 0), b.layer.recruit("place", 1)
    b.graph.add_transition(p, q, Action.move(0.0, 10.0), 2.0)
    b.graph.add_transition(q, p, Action.move(0.0, 10.0), None)
    b.t, b.state, d.current_since = 9.0, p, 8.0
    b.pi.heading = 0.25
    d.mode, d.heading, d.current = Mode.MOVE, 0.5, (p, q)
    tick = b._tick(True, novel=True)
    assert tick.move_limit == 3.0 * 2.0 + 5.0                  # the learned delay
    assert (tick.t, tick.winner, tick.event, tick.mode, tick.transition) == (
        9.0, p, True, Mode.MOVE, (p, q))
    assert (tick.target_heading, tick.heading, tick.move_since) == (0.5, 0.25, 8.0)
    assert tick.settling is False and tick.novel is True and tick.omitted == ()
    d.mode, d.current = Mode.APPROACH, (q, p)                  # no delay learned: the default
    assert b._tick(False).move_limit == 3.0 * 4.0 + 5.0
    d.current = None                                           # keeping a heading: the default
    assert b._tick(False).move_limit == 3.0 * 4.0 + 5.0
    assert b._tick(False, settling=True).move_limit is None
    d.heading = None
    assert b._tick(False).move_limit is None
    d.heading = 0.5
    for mode in (Mode.WAIT, Mode.EXPLORE):
        d.mode = mode
        assert b._tick(False).move_limit is None
    b.non_occurrence = [(p, q)]
    t = b._tick(False, settling=True)
    assert t.omitted == ((p, q),) and t.settling is True and t.event is False
    assert t.novel is False


def test_abandoning_a_move_explores_with_no_transition():
    b = brain()
    b.decide.mode, b.decide.current = Mode.MOVE, (0, 1)
    b.abandon()
    assert b.mode == Mode.EXPLORE and b.current is None


# -- lifts --------------------------------------------------------------------------------------
def test_a_lift_turns_the_heading_estimate_restarts_the_episode_and_settles():
    b, src = stub_brain(settle_time=6.0)
    b.t, b.pi.heading = 10.0, 3.0
    b.state, b._ctx_now, b._rewarded_at = 1, 1, 5.0
    b.lifted(0.5)                                   # 3.5 rad wraps to 3.5 - 2 pi
    assert b.pi.heading == pytest.approx(3.5 - 2.0 * math.pi)
    assert src.lifts == 1 and b.state is None and b._ctx_now is None
    assert b._rewarded_at is None and b._settle_until == 16.0
    b.lifted(moved=False)                           # put back where it was: no re-anchoring
    assert src.lifts == 1 and b._settle_until == 16.0


def test_a_lift_keeps_the_drives_a_wait_holds_only_when_asked():
    b = brain()
    d = b.decide
    p = b.layer.recruit("place", 0)
    b.drives.inhibit("a")
    d._inhibited = {"a": p}
    b.pi.reset((7.0, 8.0, 0.0))
    b.lifted(keep_drives=True)
    assert d.inhibitions() == {"a": p} and b.drives.is_inhibited("a")
    assert d._inhibited_at["a"] == (7.0, 8.0)
    b.lifted()
    assert d.inhibitions() == {} and not b.drives.is_inhibited("a")


def test_a_lift_resets_the_direction_sectors():
    b = Brain(NoPlaces(), params=BrainParams(heading_sectors=4))
    assert b.sectors is not None and b.sectors.n == 4
    b.sectors.sector = 2
    b.lifted()
    assert b.sectors.sector is None
    assert brain().sectors is None                   # one sector: no split
    assert Brain(NoPlaces(), params=BrainParams(heading_sectors=2)).layer._n_place0 == 2


# -- the tick: odometry, proprioception, occlusion ----------------------------------------------
def test_the_odometer_sums_the_distance_run():
    b, _ = stub_brain()
    b.step(obs(1, odo=(3.0, 4.0, 0.0)))
    b.step(obs(2, odo=(-6.0, 8.0, 0.0)))
    assert b.odometer == 15.0 and b.pi.pose[:2] != (0.0, 0.0)
    assert b.t == 0.4


def test_moving_flips_only_after_proprio_ticks_ticks_in_a_row():
    b, _ = stub_brain(proprio_ticks=3)
    assert b._moving is True
    b.step(obs(1, moving=False))
    b.step(obs(2, moving=False))
    assert b._moving is True and b._flip == 2
    b.step(obs(3, moving=True))                     # one moving tick: the count starts over
    assert b._flip == 0
    for k in range(4, 6):
        b.step(obs(k, moving=False))
    assert b._moving is True
    b.step(obs(6, moving=False))                    # the third still tick in a row
    assert b._moving is False and b._flip == 0


def test_a_turn_on_the_spot_faster_than_still_turn_counts_as_moving():
    b, _ = stub_brain(proprio_ticks=1, still_turn=0.5)   # bound: 0.5 rad/s x 0.2 s = 0.1 rad
    b.step(obs(1, moving=False, odo=(0.0, 0.0, 0.1)))    # exactly the bound: still
    assert b._moving is False
    b.step(obs(2, moving=False, odo=(0.0, 0.0, -0.1001)))  # just past it (either way): moving
    assert b._moving is True


def test_the_place_cells_hear_the_last_clear_view_while_the_robot_is_boxed_in():
    class Box:
        def __init__(self) -> None:
            self.on = False

        def boxed_in(self, o) -> bool:
            return self.on

    box = Box()
    b, src = stub_brain()
    b.occlusion = box
    box.on = True
    b.step(obs(1, ir=0.9))             # boxed in from the start: no clear view yet, hears it
    box.on = False
    b.step(obs(2, ir=0.3))
    box.on = True
    b.step(obs(3, ir=0.8))
    assert [float(s[0]) for s in src.seen] == [0.9, 0.3, 0.3]
    assert float(b._clear_view[0]) == 0.3


def test_the_place_states_split_by_the_heading_sector():
    b, _src = stub_brain(heading_sectors=2)
    b.step(obs(1, odo=(1.0, 0.0, 0.0)))     # heading 0: sector 0
    east = b.state
    assert b.layer._n_place0 == 6 and b.kind(east) == StateKind.PLACE
    b.lifted(math.pi, moved=False)          # turned round: heading pi, sector 1
    b.step(obs(2, odo=(1.0, 0.0, 0.0)))
    b.step(obs(3, odo=(1.0, 0.0, 0.0)))
    assert b.state is not None and b.state != east
    # place 0's units interleave the sectors: unit 0 heading east, unit 1 heading west
    assert (b.layer.key(east).index, b.layer.key(b.state).index) == (0, 1)


# -- introspection ------------------------------------------------------------------------------
def test_entered_since_describe_and_kind():
    b = brain()
    p = b.layer.recruit("place", 2)
    still, _ = stop(b, p)
    assert b.entered_since(p) is None
    b._entries[p] = (4.5, (0.0, 0.0, 0.0))
    assert b.entered_since(p) == 4.5
    assert b.describe(None) == "none" and b.describe(still) == "still@place 2"
    assert b.kind(still) == StateKind.STILL and b.kind(p) == StateKind.PLACE


def test_a_snapshot_reads_the_current_transitions_prediction_and_the_sounds():
    class R:
        def __init__(self, prediction: float) -> None:
            self.prediction = prediction

    b = brain("ab")
    p, q = b.layer.recruit("place", 0), b.layer.recruit("place", 1)
    still, _ = stop(b, p)
    sound = b.layer.recruit("sound")
    snap = b.snapshot()                              # a new brain: nothing under way
    assert snap == {"sound_prediction": 0.0, "sound_non_occurrence": False, "winner": -1,
                    "mode": int(Mode.EXPLORE), "transition_a": -1, "transition_b": -1,
                    "prediction": 0.0, "non_occurrence": False, "drives": [0.0, 0.0],
                    "wait_drive": -1}
    b.readouts = {(p, q): R(0.25), (still, sound): R(0.5), (q, sound): R(0.75)}
    b.non_occurrence = [(p, q)]
    b.state, b.decide.mode, b.decide.current = q, Mode.MOVE, (p, q)
    b.drives.set_level("b", 0.5)
    snap = b.snapshot()
    assert snap["sound_prediction"] == 0.75          # the largest prediction of the sound
    assert snap["prediction"] == 0.25 and snap["non_occurrence"] is True
    assert snap["sound_non_occurrence"] is False     # the omitted event is no sound
    assert (snap["winner"], snap["transition_a"], snap["transition_b"]) == (q, p, q)
    assert snap["mode"] == int(Mode.MOVE) and snap["drives"] == [0.0, 0.5]
    b.non_occurrence = [(q, sound)]
    b.decide.current = (q, p)                        # no readout for it
    snap = b.snapshot()
    assert snap["sound_non_occurrence"] is True and snap["prediction"] == 0.0


# -- a sensory event ----------------------------------------------------------------------------
def test_an_event_learns_the_transition_timed_from_entering_and_moves_the_context():
    b = brain()
    p, q = b.layer.recruit("place", 0), b.layer.recruit("place", 1)
    still, moving = stop(b, q)
    b.state, b.entered_at, b._entry_pose, b._ctx_now = p, 1.0, (0.0, 0.0, 0.0), p
    b.t = 3.5
    b.pi.reset((10.0, 0.0, 0.0))
    b._on_event(q)                                  # 2.5 s and 10 cm east after entering p
    assert b.graph.delay((p, q)) == 2.5 and b.graph.action((p, q)).distance == 10.0
    assert (b.state, b.entered_at, b._entry_pose) == (q, 3.5, (10.0, 0.0, 0.0))
    assert b._entries == {q: (3.5, (10.0, 0.0, 0.0))}
    assert (b._ctx_now, b._ctx_before, b.came_from) == (q, p, p)
    b.t = 5.0
    b._on_event(still)                              # a stop: no context, the entries stay
    assert b.graph.delay((q, still)) == 1.5 and b.graph.action((q, still)).is_wait
    assert b._entries.keys() == {q} and (b._ctx_now, b._ctx_before) == (q, p)
    assert (b.state, b.entered_at) == (still, 5.0)
    b.t = 8.0
    b._on_event(moving)                             # the wait: 3 s after the stop
    assert b.graph.delay((still, moving)) == 3.0 and b.last_transition == (still, moving)


def test_resuming_without_a_stop_before_it_and_a_stay_begun_unseen_time_nothing():
    b = brain()
    p, q = b.layer.recruit("place", 0), b.layer.recruit("place", 1)
    _, moving = stop(b, p)
    b.state, b.entered_at, b.t = p, 0.0, 2.0
    b._on_event(moving)                             # moving@p straight after p (e.g. a lift)
    assert len(b.graph) == 0 and b.state == moving and b.entered_at == 2.0
    b.state, b.entry_unseen, b.t = p, True, 4.0
    b._on_event(q)                                  # re-anchored inside p: no p -> q
    assert len(b.graph) == 0 and b.entry_unseen is False and b.state == q


def test_a_stop_the_decider_did_not_time_is_learned_without_a_delay():
    b = brain()
    p = b.layer.recruit("place", 0)
    still, _ = stop(b, p)
    b.state, b.entered_at, b.t = p, 1.0, 4.0
    b.decide.mode, b.decide.stop_untimed = Mode.WAIT, True
    b._on_event(still)
    assert (p, still) in b.graph and b.graph.delay((p, still)) is None


def test_an_inferred_way_back_that_led_elsewhere_is_forgotten():
    b = brain()
    p, q, r = (b.layer.recruit("place", i) for i in range(3))
    b.graph.add_transition(p, q, Action.move(0.0, 10.0), 2.0)
    back = b.graph.infer_reverse((p, q))
    assert back == (q, p)
    b.state, b.entered_at, b.t = q, 0.0, 2.0
    b.decide.current = (q, p)
    b._on_event(r)                                  # took the way back, came to r
    assert (q, p) not in b.graph and (q, r) in b.graph
    b.graph.infer_reverse((p, q))
    b.state, b.decide.current = q, (q, p)
    b._on_event(p)                                  # it led where it said: confirmed
    assert (q, p) in b.graph and not b.graph.inferred((q, p))
    b.graph.add_transition(r, p, Action.move(1.0, 5.0), 1.0)   # a real move that led elsewhere
    b.state, b.decide.current = r, (r, p)
    b._on_event(q)
    assert (r, p) in b.graph


def test_settling_after_a_lift_lasts_settle_time_exactly_then_restarts_without_a_transition():
    b, _src = stub_brain(settle_time=0.4)
    b.t = 0.4
    b.lifted(moved=False)                           # settles until 0.8
    t1 = b.step(obs(3, odo=(2.0, 0.0, 0.0)))        # t = 0.6
    assert t1.settling and t1.mode == Mode.EXPLORE and b.state is None
    t2 = b.step(obs(4, odo=(2.0, 0.0, 0.0)))        # t = 0.8: decides
    assert not t2.settling and b.state is not None
    w = b.state
    assert (b.entered_at, b._entry_pose) == (0.8, (4.0, 0.0, 0.0))
    assert b._entries == {w: (0.8, (4.0, 0.0, 0.0))}
    assert (b._ctx_now, b._ctx_before) == (w, None) and len(b.graph) == 0
    assert b.entry_unseen is False


def test_a_stop_right_after_a_brief_place_binds_to_the_place_before_only_below_context_time():
    # p won at 4.0 (or 4.1); the stop at 5.0 in q's context; context_time 1.0 s: p held 1.0 s
    # (exactly context_time: p was a context) or 0.9 s (not: the stop is q's, timed from 1.0)
    got = {}
    for entered in (4.0, 4.1):
        b = Brain(NoPlaces(), params=BrainParams(states=StateLayerParams(context_time=1.0)))
        p, q = b.layer.recruit("place", 0), b.layer.recruit("place", 1)
        still, _ = stop(b, q)
        b._ctx_before, b._ctx_now, b._entries = q, p, {q: (1.0, (0.0, 0.0, 0.0))}
        b.state, b.entered_at, b.t = p, entered, 5.0
        b._on_event(still)
        got[entered] = sorted((tr, b.graph.delay(tr)) for tr in b.graph)
        got[entered] = [(tr == (p, still), tr == (q, still), d) for tr, d in got[entered]]
    assert got[4.0] == [(True, False, 1.0)]
    assert got[4.1] == [(False, True, 4.0)]


def test_a_stop_made_for_a_stop_recognised_softly_is_learned_from_its_place():
    b = brain()
    p, q = b.layer.recruit("place", 0), b.layer.recruit("place", 1)
    still, _ = stop(b, q)
    d = b.decide
    d._waiting_on, d.mode, d._approach_t0 = (q, still), Mode.WAIT, 2.0
    b.state, b.entered_at, b.t = p, 4.0, 5.0       # p won; the robot stopped for q's stop
    b._on_event(still)
    assert list(b.graph) == [(q, still)] and b.graph.delay((q, still)) == 3.0


def test_entering_a_place_too_often_from_another_explores_a_while():
    b = brain("a", cycle_visits=1, cycle_explore=20.0)
    p, q, r = (b.layer.recruit("place", i) for i in range(3))
    b.graph.add_transition(q, r, Action.move(0.0, 10.0), 2.0)
    b.drives.link("a", (q, r))
    b.drives.set_level("a", 1.0)
    b.state, b.t = p, 3.0
    b._on_event(q)                        # came from a place, the first visit of q: cycling
    assert b.mode == Mode.EXPLORE and b.current is None
    assert b.decide._explore_until == 23.0
    c = brain("a", cycle_visits=1, cycle_explore=20.0)
    p, q, r = (c.layer.recruit("place", i) for i in range(3))
    c.graph.add_transition(q, r, Action.move(0.0, 10.0), 2.0)
    c.drives.link("a", (q, r))
    c.drives.set_level("a", 1.0)
    c.state, c.entry_unseen, c.t = p, True, 3.0
    c._on_event(q)                        # no place before it (re-anchored): no cycling
    assert c.mode == Mode.MOVE and c.current == (q, r)


def test_a_lift_forgets_the_episodes_anchors_and_entries():
    b = brain()
    b.t = 12.0
    b.pi.reset((5.0, 6.0, 0.5))
    b.entered_at, b._entry_pose, b._entries = 1.0, (0.0, 0.0, 0.0), {3: (1.0, (0.0, 0.0, 0.0))}
    b._ctx_now, b._ctx_before, b.entry_unseen = 3, 2, True
    b.wait_ended_at, b._rewarded_at, b._rewarded_drive, b.last_wait_drive = 1.0, 2.0, "a", "b"
    b.last_transition, b.non_occurrence, b._pending_rewards = (2, 3), [(2, 3)], ["a"]
    b.lifted()
    assert b.state is None and b.entry_unseen is False and b._entries == {}
    assert b._ctx_now is None and b._ctx_before is None
    assert b.wait_ended_at is None and b._rewarded_at is None
    assert b._rewarded_drive is None and b.last_wait_drive is None
    assert b.entered_at == 12.0 and b._entry_pose == (5.0, 6.0, 0.5)
    assert b.last_transition is None and b.non_occurrence == [] and b._pending_rewards == []
    assert b.readouts == {}


def test_errors_name_what_was_wrong():
    with pytest.raises(ValueError, match=r"^this Brain has no place source: use perceive\(\), "
                                         r"or pass places$"):
        Brain().step(obs(1))
    b, _ = stub_brain()
    with pytest.raises(ValueError, match=r"^sensor readings "):
        b.step(obs(1, ir=math.nan))
    with pytest.raises(ValueError, match=r"^odometry "):
        b.step(obs(1, odo=(0.0, math.inf, 0.0)))
    with pytest.raises(ValueError, match=r"^heading_change must be finite"):
        b.lifted(math.nan)


def test_only_the_place_source_receives_the_ground_truth():
    class Truthful(Stub):
        def step(self, obs, truth=None):
            self.truth = truth
            return super().step(obs, truth)

    src = Truthful()
    b = Brain(src, params=BrainParams(settle_time=0.0))
    truth = object()
    b.step(obs(1), truth)                  # any object: the brain only passes it on
    assert src.truth is truth


def test_a_tick_says_whether_a_sensory_event_happened_while_settling_and_after():
    b, src = stub_brain(settle_time=0.4)
    b.t = 0.4
    b.lifted(moved=False)
    assert b.step(obs(3)).event is True         # settling: place 0 wins afresh
    assert b.step(obs(4)).event is False        # decides: still place 0
    src.where = 1
    ticks = [b.step(obs(k)) for k in range(5, 12)]
    assert any(t.event for t in ticks) and ticks[-1].event is False
    assert b.state == b.layer.find("place", 1)


def test_a_sidestep_counts_toward_the_sectors_min_step():
    b, _ = stub_brain(heading_sectors=2, proprio_ticks=1)
    b.step(obs(1, odo=(1.0, 0.0, 0.0)))         # heading east: sector 0
    b.step(obs(2, odo=(0.0, 0.0, math.pi)))     # turned round on the spot: 0 cm, sector kept
    assert b.sectors.sector == 0
    b.step(obs(3, odo=(0.0, 1.0, 0.0)))         # 1 cm sideways (dx 0) heading west: sector 1
    assert b.sectors.sector == 1


def test_a_floor_colour_ends_settling_without_asking_the_localiser():
    b, _ = stub_brain(relocalise=LocaliserParams(max_time=0.2))
    b.lifted(moved=False)                       # at t 0: the localiser's clock starts
    tick = b.step(Observation(0.2, 1, np.full(8, 0.5), 1, False, np.zeros(3), True))
    assert b.kind(tick.winner) == StateKind.COLOUR and not tick.settling
    assert b.localiser.localised is False       # max_time passed, but nobody asked it
