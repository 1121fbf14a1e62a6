"""RobotEnv's rules, each against an answer worked out by hand or a twin World stepped directly.

The spaces come from the documented formulas: the odometry bound is 2 speed_max dt (the
e-puck's 5.08 cm/s over 0.2 s: 2.032 cm) and pi, the floor has colours + 1 values (goal-arena
has one zone of colour 1, two-rooms none), the frame rate round(1 / dt). Seeding follows
Gymnasium: np_random is numpy's default_rng(seed), from which an episode draws its start pose
and then the world's seed as integers(0, 2**63 - 1); a World seeded by hand with that draw
and stepped with the wheel speeds clip(action, -1, 1) speed_max senses the same numbers.
two-rooms' (20, 44) lies in room_a, nearest to location 5 = (21, 45).
"""

from __future__ import annotations

import math
import re
import warnings
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from hippo.envs.rewards import ShuttleTask
from hippo.envs.robot import PatrolEnv, PlacePreferenceEnv, RobotEnv, TwoRoomsEnv
from hippo.sim import arenas
from hippo.sim.robot import RobotParams
from hippo.sim.world import World


def refused(message: str, kind: type[Exception] = ValueError):
    return pytest.raises(kind, match="^" + re.escape(message) + "$")


def test_the_spaces_follow_the_robot_the_arena_and_dt():
    env = TwoRoomsEnv()
    b = np.float32(2 * 5.08 * 0.2)
    space = env.observation_space
    assert set(space.spaces) == {"ir", "floor", "sound", "moving", "odometry"}
    np.testing.assert_array_equal(space["odometry"].high, [b, b, np.float32(math.pi)])
    np.testing.assert_array_equal(space["odometry"].low, [-b, -b, -np.float32(math.pi)])
    assert space["odometry"].dtype == np.float32 and space["ir"].dtype == np.float32
    assert space["ir"].shape == (8,)
    assert (space["ir"].low.min(), space["ir"].high.max()) == (0.0, 1.0)
    assert space["floor"].n == 1 and space["sound"].n == 2 and space["moving"].n == 2
    a = env.action_space
    assert a.shape == (2,) and a.dtype == np.float32
    np.testing.assert_array_equal(a.low, [-1, -1])
    np.testing.assert_array_equal(a.high, [1, 1])
    assert env.metadata == {"render_modes": ["rgb_array"], "render_fps": 5}
    assert env.render_mode is None

    slow = PlacePreferenceEnv(sensors="ray17", dt=0.25,
                              robot=RobotParams(speed_max=4.0))
    assert slow.observation_space["floor"].n == 2
    assert slow.observation_space["ir"].shape == (17,)
    np.testing.assert_array_equal(slow.observation_space["odometry"].high,
                                  np.array([2.0, 2.0, math.pi], np.float32))
    assert slow.metadata["render_fps"] == 4
    assert RobotEnv.metadata["render_fps"] == 5     # the class's own dict is left alone
    assert PlacePreferenceEnv(dt=0.4).metadata["render_fps"] == 2   # round(2.5): even


def test_each_environment_builds_its_task_from_its_arguments():
    assert isinstance(TwoRoomsEnv().task, ShuttleTask)
    assert PlacePreferenceEnv().task.delay == 7.0
    assert PlacePreferenceEnv(delay=3.5).task.delay == 3.5
    p = PatrolEnv()
    assert tuple(p.task.waits) == (24.1, 19.1, 11.6) and p.task.radius == 12.0
    p = PatrolEnv(waits=(1.0, 2.0, 3.0), radius=20.0)
    assert tuple(p.task.waits) == (1.0, 2.0, 3.0) and p.task.radius == 20.0
    assert TwoRoomsEnv(dt=0.5).world.dt == 0.5


def test_a_render_mode_must_be_known():
    with refused("render_mode must be None or one of ['rgb_array'], got 'human'"):
        TwoRoomsEnv(render_mode="human")
    assert TwoRoomsEnv(render_mode="rgb_array").render_mode == "rgb_array"


def _twin(env: RobotEnv, seed: int, pose: tuple[float, float, float] | None
          ) -> tuple[World, Any, tuple[float, float, float]]:
    """A World seeded by hand the way reset draws it from default_rng(seed)."""
    rng = np.random.default_rng(seed)
    start = env.task.start_pose(rng) if pose is None else pose
    world = World(env.task.arena, seed=None)
    obs = world.reset(int(rng.integers(0, 2**63 - 1)), pose=start)
    return world, obs, start


@pytest.mark.parametrize("pose", [None, (20.0, 44.0, 0.5)])
def test_reset_draws_the_start_and_then_the_worlds_seed(pose):
    env = TwoRoomsEnv()
    options = None if pose is None else {"pose": pose}
    obs, info = env.reset(seed=11, options=options)
    world, wobs, start = _twin(env, 11, pose)
    np.testing.assert_array_equal(obs["ir"], np.asarray(wobs.ir, np.float32))
    np.testing.assert_allclose(info["pose"], start, atol=1e-12)
    # the next step's noise follows the same stream
    obs, *_ = env.step([0.5, -0.25])
    wobs = world.step(np.array([0.5, -0.25]) * 5.08)
    np.testing.assert_array_equal(obs["ir"], np.asarray(wobs.ir, np.float32))


def test_the_action_is_clipped_then_scaled_by_the_top_speed():
    env = TwoRoomsEnv()
    env.reset(seed=2, options={"pose": (20.0, 44.0, 0.0)})
    world, _, _ = _twin(env, 2, (20.0, 44.0, 0.0))
    for action, wheels in (([2.0, -0.5], [5.08, -0.5 * 5.08]), ([-3.0, 0.25], [-5.08, 1.27]),
                           ([1.0, -1.0], [5.08, -5.08])):
        obs, reward, terminated, truncated, info = env.step(np.array(action))
        wobs = world.step(np.array(wheels))
        np.testing.assert_array_equal(obs["ir"], np.asarray(wobs.ir, np.float32))
        np.testing.assert_array_equal(info["pose"], world.truth.pose)
        assert info["speed"] == world.truth.speed and info["t"] == wobs.t
        assert type(reward) is float and reward == 0.0
        assert terminated is False and truncated is False


def test_the_truth_goes_to_info_with_the_tasks_bookkeeping():
    env = TwoRoomsEnv()
    obs, info = env.reset(seed=0, options={"pose": (20.0, 44.0, 0.5)})
    assert set(info) == {"t", "pose", "speed", "region", "location", "target", "visits"}
    assert info["t"] == 0.0 and info["speed"] == 0.0
    np.testing.assert_array_equal(info["pose"], [20.0, 44.0, 0.5])
    assert info["region"] == "room_a"
    assert info["location"] == 5 and type(info["location"]) is int
    assert info["target"] == "room_b" and info["visits"] == 0
    assert obs["floor"] == 0 and obs["sound"] == 0 and obs["moving"] == 0
    for k in ("floor", "sound", "moving"):
        assert type(obs[k]) is np.int64
    np.testing.assert_array_equal(obs["odometry"], [0, 0, 0])
    _, _, _, _, info = env.step([0.0, 0.0])
    assert info["t"] == 0.2 and info["region"] == "room_a"


def test_the_observation_converts_and_clips_what_the_world_sensed():
    env = TwoRoomsEnv()
    b = np.float32(2.032)
    fake = SimpleNamespace(ir=np.array([0.25, 1.0]), floor=3, sound=True, moving=False,
                           odometry=np.array([10.0, -10.0, 4.0]))
    out = env._observation(fake)  # type: ignore[arg-type]
    np.testing.assert_array_equal(out["odometry"], [b, -b, np.float32(math.pi)])
    assert out["odometry"].dtype == np.float32 and out["ir"].dtype == np.float32
    np.testing.assert_array_equal(out["ir"], [0.25, 1.0])
    assert (out["floor"], out["sound"], out["moving"]) == (3, 1, 0)
    fake.odometry = np.array([2.0, -2.0, -3.0])          # inside the bound: as it is
    np.testing.assert_array_equal(env._observation(fake)["odometry"],   # type: ignore[arg-type]
                                  np.array([2.0, -2.0, -3.0], np.float32))


def test_step_needs_a_reset_and_two_finite_wheel_speeds():
    env = TwoRoomsEnv()
    with refused("call reset() before step()", RuntimeError):
        env.step([0.0, 0.0])
    env.reset(seed=0)
    for action, shown in (([0.0, 0.0, 0.0], "[0.0, 0.0, 0.0]"), ([np.nan, 0.0], "[nan, 0.0]"),
                          ([0.0, np.inf], "[0.0, inf]"), ("ab", "'ab'"),
                          ({"left": 1}, "{'left': 1}"), ([1j, 0.0], "[1j, 0.0]"),
                          (0.5, "0.5")):
        with refused("action must be two finite wheel speeds (in [-1, 1]; beyond it they are "
                     f"clipped), got {shown}"):
            env.step(action)
    with refused("action must be two finite wheel speeds (in [-1, 1]; beyond it they are "
                 f"clipped), got {'[' + ', '.join(['0.0'] * 30)[:79]}"):
        env.step([0.0] * 30)
    env.step([[0.5], [0.5]])   # any shape of two numbers


def test_reset_options_are_checked_word_for_word():
    env = TwoRoomsEnv()
    with refused("unknown reset option(s) ['speed', 'start']; allowed: 'pose'"):
        env.reset(seed=0, options={"start": 1, "speed": 2, "pose": (20.0, 44.0, 0.0)})
    with refused("options['pose'] must be three finite numbers (x, y, heading), got (1.0, 2.0)"):
        env.reset(seed=0, options={"pose": (1.0, 2.0)})
    with refused("options['pose'] must be three finite numbers (x, y, heading), got 'abc'"):
        env.reset(seed=0, options={"pose": "abc"})
    with refused("options['pose'] must be three finite numbers (x, y, heading), got "
                 "(20.0, 44.0, nan)"):
        env.reset(seed=0, options={"pose": (20.0, 44.0, math.nan)})
    # options that are no dict used to fail with "'list' object has no attribute 'get'"
    with refused("options must be a dict, got ['pose', (20.0, 44.0, 0.0)]"):
        env.reset(seed=0, options=["pose", (20.0, 44.0, 0.0)])  # type: ignore[arg-type]
    with refused("options must be a dict, got 'pose'"):
        env.reset(seed=0, options="pose")  # type: ignore[arg-type]
    _, info = env.reset(seed=0, options={"pose": [20, 44, 0]})   # integers are numbers
    np.testing.assert_array_equal(info["pose"], [20.0, 44.0, 0.0])
    _, info = env.reset(seed=0, options={})
    _, _, start = _twin(env, 0, None)
    np.testing.assert_allclose(info["pose"], start, atol=1e-12)


def test_a_reset_without_a_seed_continues_the_stream():
    env = TwoRoomsEnv()
    env.reset(seed=5)
    _, second = env.reset()
    rng = np.random.default_rng(5)
    env.task.start_pose(rng)
    rng.integers(0, 2**63 - 1)
    start = env.task.start_pose(rng)
    np.testing.assert_allclose(second["pose"], start, atol=1e-12)


def test_render_needs_a_mode_and_close_can_be_called_twice():
    env = TwoRoomsEnv()
    env.reset(seed=0)
    with pytest.warns(UserWarning, match=re.escape(
            "render() called without a render_mode; make the environment with "
            "render_mode='rgb_array'")):
        assert env.render() is None
    drawn = TwoRoomsEnv(render_mode="rgb_array")
    drawn.reset(seed=0, options={"pose": (20.0, 44.0, 0.0)})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        frame = drawn.render()
    assert frame is not None and frame.dtype == np.uint8 and frame.shape[2] == 3
    renderer = drawn._renderer
    assert renderer is not None
    np.testing.assert_array_equal(drawn.render(), frame)   # the same figure, drawn again
    assert drawn._renderer is renderer
    drawn.close()
    assert drawn._renderer is None
    drawn.close()


def test_the_frame_shows_the_tasks_marks_and_the_robots_body():
    """A renderer built by hand with the task's checkpoints and the robot's radius draws the
    same frame."""
    from hippo.envs.render import ArenaRenderer

    env = PatrolEnv(render_mode="rgb_array", robot=RobotParams(radius=5.0))
    env.reset(seed=0, options={"pose": (60.0, 60.0, 0.0)})
    assert set(env.task.marks) == {"checkpoint-1", "checkpoint-2", "checkpoint-3"}
    by_hand = ArenaRenderer(arenas.get("patrol-course"), 5.0, marks=env.task.marks)
    np.testing.assert_array_equal(env.render(), by_hand.frame((60.0, 60.0, 0.0)))
    bare = ArenaRenderer(arenas.get("patrol-course"), 5.0)
    assert not np.array_equal(env.render(), bare.frame((60.0, 60.0, 0.0)))
    by_hand.close()
    bare.close()
    env.close()


class _Watching(ShuttleTask):
    """two-rooms' shuttle, remembering the observations it is handed."""

    def __init__(self) -> None:
        super().__init__()
        self.handed: list[Any] = []

    def reset(self, world: World, obs: Any) -> dict[str, Any]:
        self.handed.append(obs)
        return super().reset(world, obs)

    def step(self, world: World, obs: Any) -> tuple[float, bool, dict[str, Any]]:
        self.handed.append(obs)
        return super().step(world, obs)


def test_the_task_is_handed_the_observation_of_the_tick():
    task = _Watching()
    env = RobotEnv(task)
    obs, _ = env.reset(seed=0, options={"pose": (20.0, 44.0, 0.0)})
    after, *_ = env.step([0.5, 0.5])
    first, second = task.handed
    assert first.t == 0.0 and second.t == 0.2
    np.testing.assert_array_equal(np.asarray(first.ir, np.float32), obs["ir"])
    np.testing.assert_array_equal(np.asarray(second.ir, np.float32), after["ir"])
