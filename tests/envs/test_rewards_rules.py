"""The Gymnasium tasks' reward rules on stand-in worlds: the robot is put where each case needs
(the task reads only the true pose, the tick length and the observation's floor, sound and
motion), and every answer is worked out by hand from the rules in hippo/envs/rewards.py.

Ticks of 0.5 s (exact in binary) make each stillness a sum of halves, so the 1e-9 s tolerance
on a wait is tested exactly: 2**-30 s (9.3e-10) over two ticks still pays, 2**-29 s
(1.9e-9) does not. The arenas' coordinates come from their definitions: two-rooms' room_a is
x < 30, room_b x > 60 and the corridor in between; goal-arena's goal zone is colour 1;
patrol-course's checkpoints are (80, 11), (140, 56), (50, 105) and its start (14, 60, -pi/2).
"""

from __future__ import annotations

import math
import re
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from hippo.envs.rewards import GoalWaitTask, PatrolTask, ShuttleTask, Task, _StillTimer

NEAR_1S = 1.0 + 2.0**-30   # a wait 9.3e-10 s over two ticks of 0.5 s: within the tolerance
FAR_1S = 1.0 + 2.0**-29    # 1.9e-9 s over: beyond it
EDGE_1S = 1.0 + 1e-9       # exactly on it: EDGE_1S - 1e-9 == 1.0 in floating point


class _World:
    """The parts of a World a task reads: the true pose, dt, and the sound it asks for."""

    def __init__(self, x: float, y: float, heading: float = 0.0, dt: float = 0.5) -> None:
        self.truth = SimpleNamespace(pose=(x, y, heading))
        self.dt = dt
        self.sounds = 0

    def put(self, x: float, y: float, heading: float = 0.0) -> None:
        self.truth.pose = (x, y, heading)

    def emit_sound(self) -> None:
        self.sounds += 1


def _obs(*, floor: int = 0, moving: bool = False, sound: bool = False) -> Any:
    return SimpleNamespace(floor=floor, moving=moving, sound=sound)


def refused(message: str):
    return pytest.raises(ValueError, match="^" + re.escape(message) + "$")


def test_the_base_task_leaves_every_rule_to_its_subclass():
    w, o = _World(0, 0), _obs()
    for call in (lambda: Task().start_pose(np.random.default_rng(0)),
                 lambda: Task().reset(w, o), lambda: Task().step(w, o)):
        with pytest.raises(NotImplementedError):
            call()


def test_the_still_timer_adds_dt_while_still_inside_and_restarts_otherwise():
    t = _StillTimer()
    assert t.still == 0.0
    assert t.update(True, _obs(), 0.5) == 0.5
    assert t.update(True, _obs(), 0.25) == 0.75
    assert t.update(True, _obs(moving=True), 0.5) == 0.0   # it moved
    assert t.update(True, _obs(), 0.5) == 0.5
    assert t.update(False, _obs(), 0.5) == 0.0             # it left
    assert t.still == 0.0


# --- two rooms


def test_shuttle_the_first_room_to_pay_is_the_one_the_robot_is_not_in():
    task = ShuttleTask()
    assert task.ROOMS == ("room_a", "room_b") and task.marks == {}
    assert task.arena.name == "two-rooms"
    for x, target in ((15.0, "room_b"), (90.0, "room_a")):
        assert task.reset(_World(x, 45.0), _obs()) == {"target": target, "visits": 0}
        assert task.target == target and task.visits == 0
    # in the corridor (x 30-60): the room it faces pays first: +x faces room_b, -x room_a
    for heading, target in ((0.0, "room_b"), (0.3, "room_b"), (math.pi, "room_a"),
                            (2.0, "room_a")):
        assert task.reset(_World(45.0, 45.0, heading), _obs())["target"] == target


def test_shuttle_pays_each_entry_into_the_target_room_and_then_wants_the_other():
    task, w = ShuttleTask(), _World(15.0, 45.0)
    task.reset(w, _obs())
    assert task.step(w, _obs()) == (0.0, False, {"target": "room_b", "visits": 0})
    w.put(45.0, 45.0)                                   # the corridor pays nothing
    assert task.step(w, _obs()) == (0.0, False, {"target": "room_b", "visits": 0})
    w.put(90.0, 45.0)
    assert task.step(w, _obs()) == (1.0, False, {"target": "room_a", "visits": 1})
    assert task.step(w, _obs()) == (0.0, False, {"target": "room_a", "visits": 1})
    w.put(15.0, 45.0)
    assert task.step(w, _obs()) == (1.0, False, {"target": "room_b", "visits": 2})
    assert w.sounds == 0   # two rooms pays without the sound


def test_shuttle_starts_at_the_arenas_random_free_pose():
    task = ShuttleTask()
    got = task.start_pose(np.random.default_rng(3))
    assert got == task.arena.sample_free_pose(np.random.default_rng(3))
    assert task.arena.is_free(got[0], got[1], 3.7 + 2.0)


# --- place preference


def test_goal_wait_refuses_a_delay_that_is_no_positive_time():
    for bad in (0, 0.0, -1.0, math.inf, math.nan):
        with refused(f"delay must be finite and > 0, got {bad!r}"):
            GoalWaitTask(bad)
    for bad in ("7", True, None):     # "7" and True had been read as 7 and 1 s
        with refused(f"delay must be a number, got {bad!r}"):
            GoalWaitTask(bad)   # type: ignore[arg-type]
    assert GoalWaitTask().delay == 7.0 and GoalWaitTask(2).delay == 2.0


def test_goal_wait_marks_the_goal_and_starts_at_one_of_the_four_corridor_places():
    task = GoalWaitTask()
    assert task.marks == {"goal": (12.0, 76.0)} and task.colour == 1
    asked = []

    def pick(k: int) -> Any:
        def integers(n: int) -> np.int64:
            asked.append(n)
            return np.int64(k)
        return SimpleNamespace(integers=integers)

    starts = [task.start_pose(pick(k)) for k in range(4)]   # type: ignore[arg-type]
    assert asked == [4, 4, 4, 4]
    assert starts == [(85.0, 15.0, 0.0), (132.0, 100.0, math.pi / 2),
                      (60.0, 136.0, math.pi), (12.0, 105.0, -math.pi / 2)]


def test_goal_wait_pays_once_still_in_the_zone_for_the_delay_then_ends():
    task, w = GoalWaitTask(NEAR_1S), _World(12.0, 76.0)
    assert task.reset(w, _obs(floor=1)) == {"still_in_goal_s": 0.0}
    assert task.step(w, _obs(floor=1)) == (0.0, False, {"still_in_goal_s": 0.5})
    assert w.sounds == 0
    # 1.0 s still >= (1 + 2**-30) - 1e-9: the sound is asked for now ...
    assert task.step(w, _obs(floor=1)) == (0.0, False, {"still_in_goal_s": 1.0})
    assert w.sounds == 1 and task.sounded
    # ... once only, however long it stays
    assert task.step(w, _obs(floor=1)) == (0.0, False, {"still_in_goal_s": 1.5})
    assert w.sounds == 1
    # and heard on a later tick: +1 and the episode ends (the timer is not moved on)
    assert task.step(w, _obs(floor=1, sound=True)) == (1.0, True, {"still_in_goal_s": 1.5})


def test_goal_wait_the_tolerance_is_1e_9_s():
    assert EDGE_1S - 1e-9 == 1.0
    task, w = GoalWaitTask(EDGE_1S), _World(12.0, 76.0)
    task.reset(w, _obs())
    task.step(w, _obs(floor=1))
    task.step(w, _obs(floor=1))
    assert w.sounds == 1            # 1.0 s >= EDGE_1S - 1e-9, on the edge
    task, w = GoalWaitTask(FAR_1S), _World(12.0, 76.0)
    task.reset(w, _obs())
    task.step(w, _obs(floor=1))
    task.step(w, _obs(floor=1))
    assert w.sounds == 0            # 1.0 s < (1 + 2**-29) - 1e-9
    task.step(w, _obs(floor=1))
    assert w.sounds == 1


def test_goal_wait_restarts_the_stop_when_the_robot_moves_or_is_off_the_goal():
    task, w = GoalWaitTask(1.0), _World(12.0, 76.0)
    task.reset(w, _obs())
    assert task.step(w, _obs(floor=1))[2] == {"still_in_goal_s": 0.5}
    assert task.step(w, _obs(floor=1, moving=True))[2] == {"still_in_goal_s": 0.0}
    assert task.step(w, _obs(floor=1))[2] == {"still_in_goal_s": 0.5}
    assert task.step(w, _obs(floor=0))[2] == {"still_in_goal_s": 0.0}   # another colour
    assert task.step(w, _obs(floor=2))[2] == {"still_in_goal_s": 0.0}
    assert w.sounds == 0
    # a reset forgets the stop and the sound
    task.step(w, _obs(floor=1))
    task.step(w, _obs(floor=1))
    assert w.sounds == 1
    task.reset(w, _obs())
    assert task.timer.still == 0.0 and task.sounded is False
    task.step(w, _obs(floor=1))
    task.step(w, _obs(floor=1))
    assert w.sounds == 2


# --- the patrol


def test_patrol_refuses_waits_and_radius_word_for_word():
    for bad in (5, None, "abc", (None, 2, 3)):
        with refused(f"waits must be three waits in s, one per checkpoint, got {bad!r}"):
            PatrolTask(waits=bad)   # type: ignore[arg-type]
    with refused("waits must give one wait per checkpoint (3), got (1.0, 2.0)"):
        PatrolTask(waits=(1, 2))
    with refused("waits must give one wait per checkpoint (3), got (1.0, 2.0, 3.0, 4.0)"):
        PatrolTask(waits=(1, 2, 3, 4))
    for bad in (0.0, -1.0, math.inf, math.nan):
        with refused(f"waits must be finite and > 0, got {bad!r}"):
            PatrolTask(waits=(1.0, 2.0, bad))
    for bad in (0.0, -2.0, math.nan):
        with refused(f"radius must be finite and > 0, got {bad!r}"):
            PatrolTask(radius=bad)
    # numpy waits and an integer radius are numbers
    t = PatrolTask(waits=np.array([1, 2, 3]), radius=5)
    assert t.waits == (1.0, 2.0, 3.0) and type(t.waits[0]) is float and t.radius == 5.0


def test_patrol_a_string_of_digits_is_no_three_waits_nor_are_strings_and_bools():
    # "123" is three characters that float() reads as 1, 2 and 3 s: refused, as "abc" is;
    # so are waits float() reads from text, and True (1 s)
    for bad in ("123", b"123", ("24.1", "19.1", "11.6"), (True, 2.0, 3.0),
                [1.0, np.bool_(True), 3.0]):
        with refused(f"waits must be three waits in s, one per checkpoint, got {bad!r}"):
            PatrolTask(waits=bad)   # type: ignore[arg-type]
    # any iterable of three numbers, read once
    assert PatrolTask(waits=iter([1, 2.5, np.float32(3.0)])).waits == (1.0, 2.5, 3.0)


def test_patrol_checkpoints_marks_and_start():
    task = PatrolTask()
    assert task.waits == (24.1, 19.1, 11.6) and task.radius == 12.0
    assert task.checkpoints == [(80.0, 11.0), (140.0, 56.0), (50.0, 105.0)]
    assert task.marks == {"checkpoint-1": (80.0, 11.0), "checkpoint-2": (140.0, 56.0),
                          "checkpoint-3": (50.0, 105.0)}
    # the course's own start, whatever the generator
    assert task.start_pose(np.random.default_rng(0)) == (14.0, 60.0, -math.pi / 2)
    assert task.start_pose(None) == task.arena.start_pose   # type: ignore[arg-type]


def _served(task: PatrolTask, w: _World, ticks: int) -> list[float]:
    return [task.step(w, _obs())[0] for _ in range(ticks)]


def test_patrol_pays_each_checkpoint_in_turn_after_its_own_wait():
    task, w = PatrolTask(waits=(1.0, 0.5, 1.5)), _World(80.0, 11.0)
    assert task.reset(w, _obs()) == {"checkpoint": 1, "still_s": 0.0, "served": 0}
    # checkpoint 1: 2 ticks still (1.0 s) ask for the sound, heard on the 3rd: +1
    assert task.step(w, _obs()) == (0.0, False, {"checkpoint": 1, "still_s": 0.5, "served": 0})
    assert task.step(w, _obs()) == (0.0, False, {"checkpoint": 1, "still_s": 1.0, "served": 0})
    assert w.sounds == 1
    assert task.step(w, _obs()) == (0.0, False, {"checkpoint": 1, "still_s": 1.5, "served": 0})
    assert w.sounds == 1      # asked for once
    assert task.step(w, _obs(sound=True)) == (
        1.0, False, {"checkpoint": 2, "still_s": 0.0, "served": 1})
    # waiting on at checkpoint 1 earns nothing: checkpoint 2 is due
    assert _served(task, w, 6) == [0.0] * 6 and w.sounds == 1
    w.put(140.0, 56.0)        # checkpoint 2: 0.5 s, one tick
    assert _served(task, w, 1) == [0.0] and w.sounds == 2
    assert task.step(w, _obs(sound=True)) == (
        1.0, False, {"checkpoint": 3, "still_s": 0.0, "served": 2})
    w.put(50.0, 105.0)        # checkpoint 3: 1.5 s, three ticks
    assert _served(task, w, 2) == [0.0, 0.0] and w.sounds == 2
    assert _served(task, w, 1) == [0.0] and w.sounds == 3
    assert task.step(w, _obs(sound=True))[::2] == (
        1.0, {"checkpoint": 1, "still_s": 0.0, "served": 3})
    w.put(80.0, 11.0)         # and round again: checkpoint 1
    assert _served(task, w, 2) == [0.0, 0.0] and w.sounds == 4
    assert task.step(w, _obs(sound=True))[2]["checkpoint"] == 2


def test_patrol_a_sound_it_did_not_ask_for_pays_nothing():
    task, w = PatrolTask(waits=(1.0, 1.0, 1.0)), _World(80.0, 11.0)
    task.reset(w, _obs())
    assert task.step(w, _obs(sound=True)) == (
        0.0, False, {"checkpoint": 1, "still_s": 0.5, "served": 0})


def test_patrol_near_is_within_the_radius_inclusive():
    # 12 cm from checkpoint 1 exactly: near
    task, w = PatrolTask(waits=(1.0, 1.0, 1.0)), _World(80.0 + 12.0, 11.0)
    task.reset(w, _obs())
    assert task.step(w, _obs())[2]["still_s"] == 0.5
    w.put(80.0 + 12.0 + 2.0**-40, 11.0)                  # just past it: not near
    assert task.step(w, _obs())[2]["still_s"] == 0.0
    task = PatrolTask(waits=(1.0, 1.0, 1.0), radius=20.0)  # a wider radius takes it
    task.reset(w, _obs())
    assert task.step(w, _obs())[2]["still_s"] == 0.5
    w.put(80.0 + 12.0, 11.0 + 16.0)                       # 20 cm (3-4-5 times 4) exactly
    assert task.step(w, _obs())[2]["still_s"] == 1.0
    w.put(80.0 + 12.0, 11.0 + 16.5)
    assert task.step(w, _obs())[2]["still_s"] == 0.0


def test_patrol_the_wait_tolerance_is_1e_9_s_and_motion_restarts_the_stop():
    task, w = PatrolTask(waits=(FAR_1S, NEAR_1S, EDGE_1S)), _World(80.0, 11.0)
    task.reset(w, _obs())
    assert _served(task, w, 2) == [0.0, 0.0] and w.sounds == 0   # 1.0 < (1 + 2**-29) - 1e-9
    assert task.step(w, _obs(moving=True))[2]["still_s"] == 0.0
    _served(task, w, 2)
    assert w.sounds == 0
    _served(task, w, 1)
    assert w.sounds == 1
    task.step(w, _obs(sound=True))
    w.put(140.0, 56.0)
    _served(task, w, 2)
    assert w.sounds == 2                                       # 1.0 >= (1 + 2**-30) - 1e-9
    task.step(w, _obs(sound=True))
    w.put(50.0, 105.0)
    _served(task, w, 2)
    assert w.sounds == 3                                       # 1.0 >= EDGE_1S - 1e-9
    # a reset starts the round again at checkpoint 1, nothing served, no sound pending
    assert task.reset(w, _obs()) == {"checkpoint": 1, "still_s": 0.0, "served": 0}
    assert task.sounded is False
