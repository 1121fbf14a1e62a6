"""hippo's Gymnasium environments: the API contract, seeding, rewards, rendering."""

from __future__ import annotations

import math
import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import hippo.envs
from hippo.envs import ENVIRONMENTS

IDS = list(ENVIRONMENTS)


@pytest.mark.parametrize("env_id", IDS)
def test_check_env_passes_without_warnings(env_id):
    env = gym.make(env_id, render_mode="rgb_array")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # any checker warning fails the test
        check_env(env.unwrapped)
    env.close()


@pytest.mark.parametrize("env_id", IDS)
def test_observation_is_the_robots_senses_only(env_id):
    env = gym.make(env_id)
    obs, info = env.reset(seed=0)
    assert set(obs) == {"ir", "floor", "sound", "moving", "odometry"}
    assert env.observation_space.contains(obs)
    # ground truth is in info, never in the observation
    assert {"pose", "speed", "region", "location", "t"} <= set(info)
    assert env.spec.max_episode_steps == ENVIRONMENTS[env_id][1]


@pytest.mark.parametrize("env_id", IDS)
def test_seeding_follows_gymnasium(env_id):
    env = gym.make(env_id)
    a = env.reset(seed=7)
    steps_a = [env.step(np.array([0.8, 0.5], np.float32))[0]["ir"] for _ in range(5)]
    after_a = env.reset()  # no seed: continues the stream
    b = env.reset(seed=7)
    steps_b = [env.step(np.array([0.8, 0.5], np.float32))[0]["ir"] for _ in range(5)]
    after_b = env.reset()
    np.testing.assert_array_equal(a[0]["ir"], b[0]["ir"])
    np.testing.assert_array_equal(a[1]["pose"], b[1]["pose"])
    np.testing.assert_array_equal(np.array(steps_a), np.array(steps_b))
    np.testing.assert_array_equal(after_a[0]["ir"], after_b[0]["ir"])
    # the unseeded reset drew new sensor noise from np_random
    assert not np.array_equal(after_a[0]["ir"], a[0]["ir"])


def test_different_seeds_start_differently():
    env = gym.make("hippo/TwoRooms-v0")
    poses = {tuple(np.round(env.reset(seed=s)[1]["pose"], 6)) for s in range(5)}
    assert len(poses) == 5  # random free start poses


def test_action_is_normalised_wheel_speed_and_clipped():
    env = gym.make("hippo/TwoRooms-v0").unwrapped
    env.reset(seed=0, options={"pose": (60.0, 45.0, 0.0)})  # corridor, facing +x
    _, _, _, _, info = env.step(np.array([1.0, 1.0], np.float32))
    vmax, dt = env.world.robot.speed_max, env.world.dt
    assert info["pose"][0] - 60.0 == pytest.approx(vmax * dt, rel=1e-3)
    assert info["speed"] == pytest.approx(vmax, rel=1e-3)
    env.reset(seed=0, options={"pose": (60.0, 45.0, 0.0)})
    _, _, _, _, info2 = env.step(np.array([5.0, 5.0]))  # outside the box: clipped to 1
    assert info2["pose"][0] == pytest.approx(info["pose"][0])
    env.reset(seed=0, options={"pose": (60.0, 45.0, 0.0)})
    obs, *_ = env.step(np.array([-1.0, 1.0], np.float32))  # turn in place, CCW
    assert obs["odometry"][2] == pytest.approx(2 * vmax / env.world.robot.axle * dt, rel=1e-3)
    with pytest.raises(ValueError, match="action"):
        env.step(np.array([np.nan, 0.0]))
    with pytest.raises(ValueError, match="reset option"):
        env.reset(options={"start": 1})


@pytest.mark.parametrize("env_id", IDS)
def test_a_reset_pose_that_is_not_three_finite_numbers_is_refused_by_name(env_id):
    """The fourth fuzzing pass: a pose with an infinite heading was taken, and the reset failed
    with "math domain error" from the ray casting."""
    env = gym.make(env_id).unwrapped
    for pose in ((60.0, 45.0, math.inf), (60.0, 45.0, math.nan), (math.inf, 45.0, 0.0),
                 (60.0, 45.0), ("a", 45.0, 0.0), 3.0):
        with pytest.raises(ValueError, match=r"options\['pose'\] must be three finite numbers"):
            env.reset(seed=0, options={"pose": pose})
    x, y, _ = env.task.arena.start_pose
    _, info = env.reset(seed=0, options={"pose": (x, y, 0.5)})
    assert info["pose"][2] == pytest.approx(0.5)


def test_place_preference_pays_after_the_delay_still_in_the_goal():
    env = gym.make("hippo/PlacePreference-v0", delay=2.0).unwrapped
    gx, gy = env.task.arena.landmarks["goal"]
    obs, _ = env.reset(seed=0, options={"pose": (gx, gy, math.pi / 2)})
    assert obs["floor"] == 1
    rewards, sounds = [], []
    for _ in range(15):
        obs, r, term, trunc, _ = env.step(np.zeros(2, np.float32))
        rewards.append(r)
        sounds.append(int(obs["sound"]))
        if term:
            break
    # still for 2.0 s = 10 ticks, the sound is heard on the next tick with the reward
    assert rewards[-1] == 1.0 and sum(rewards) == 1.0 and term and not trunc
    assert sounds[-1] == 1 and sum(sounds) == 1
    assert len(rewards) == 11
    # moving through the zone pays nothing
    env.reset(seed=0, options={"pose": (gx, gy - 5, math.pi / 2)})
    total = sum(env.step(np.array([0.3, 0.3], np.float32))[1] for _ in range(40))
    assert total == 0.0


def test_patrol_pays_each_checkpoint_in_turn():
    env = gym.make("hippo/Patrol-v0", waits=(1.0, 1.0, 1.0)).unwrapped
    c1 = env.task.arena.landmarks["checkpoint-1"]
    _, info = env.reset(seed=0, options={"pose": (*c1, 0.0)})
    assert info["checkpoint"] == 1
    rewards = [env.step(np.zeros(2, np.float32))[1] for _ in range(30)]
    # served once (1 s still = 5 ticks, paid on the 6th); checkpoint 2 is due now, so
    # waiting on at checkpoint 1 earns nothing more
    assert rewards.index(1.0) == 5 and sum(rewards) == 1.0
    _, _, _, _, info = env.step(np.zeros(2, np.float32))
    assert info["checkpoint"] == 2 and info["served"] == 1


def test_two_rooms_pays_for_reaching_the_other_room():
    env = gym.make("hippo/TwoRooms-v0").unwrapped
    _, info = env.reset(seed=0, options={"pose": (15.0, 45.0, 0.0)})
    assert info["region"] == "room_a" and info["target"] == "room_b"
    env.world.place_robot(90.0, 45.0, 0.0)
    _, r, _, _, info = env.step(np.zeros(2, np.float32))
    assert r == 1.0 and info["target"] == "room_a" and info["visits"] == 1
    _, r, _, _, _ = env.step(np.zeros(2, np.float32))
    assert r == 0.0  # staying in room B pays nothing


def test_render_draws_the_robot_where_it_is():
    env = gym.make("hippo/TwoRooms-v0", render_mode="rgb_array")
    env.reset(seed=0, options={"pose": (15.0, 45.0, 0.0)})
    a = env.render()
    env.unwrapped.world.place_robot(90.0, 45.0, 0.0)
    b = env.render()
    assert a.dtype == np.uint8 and a.ndim == 3 and a.shape[2] == 3
    assert a.shape == b.shape and not np.array_equal(a, b)
    env.close()
    env.close()  # closing twice is allowed
    plain = gym.make("hippo/TwoRooms-v0")
    plain.reset(seed=0)
    with pytest.warns(UserWarning, match="render_mode"):
        assert plain.render() is None  # no render mode: nothing, and a warning


def test_bad_render_mode_and_registration_is_idempotent():
    with pytest.raises(ValueError, match="render_mode"):
        hippo.envs.TwoRoomsEnv(render_mode="human")
    hippo.envs.register_envs()  # no error on a second registration
    with pytest.raises(ValueError, match="delay"):
        hippo.envs.PlacePreferenceEnv(delay=0)
    with pytest.raises(ValueError, match="waits"):
        hippo.envs.PatrolEnv(waits=(1.0, 2.0))
