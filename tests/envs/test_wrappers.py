"""HippoCells: hippo's place and time cells added to the observation."""

from __future__ import annotations

import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import hippo.envs  # noqa: F401
from hippo.envs import HippoCells
from hippo.perception import RCSFAICA, PlacePrototypes, PrototypeParams
from hippo.sim import record


@pytest.fixture(scope="module")
def fitted():
    rec = record("two-rooms", 3000, seed=0, progress=False)
    model = RCSFAICA(n_reservoir=60, n_sfa=4, n_ica=4, ica_restarts=2, seed=0)
    Y = model.fit_transform(rec.sensors)
    protos = PlacePrototypes(PrototypeParams(n_prototypes=8, seed=0)).fit(Y)
    return model, protos


def test_wrapper_passes_check_env_and_adds_cells(fitted):
    model, protos = fitted
    env = HippoCells(gym.make("hippo/TwoRooms-v0").unwrapped, model, protos)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        # the one expected remark: a wrapped env is checked (that is the point here)
        warnings.filterwarnings("ignore", message=".*different from the unwrapped")
        check_env(env)
    obs, info = env.reset(seed=1)
    assert set(obs) == {"ir", "floor", "sound", "moving", "odometry", "place", "time"}
    assert obs["place"].shape == (protos.n_units,) and obs["time"].shape == (128,)
    assert env.observation_space.contains(obs)
    assert info["hippo_event"]  # the first tick is an event


def test_place_key_is_the_models_own_step(fitted):
    model, _ = fitted
    env = HippoCells(gym.make("hippo/TwoRooms-v0"), model)  # raw ICA units
    obs, _ = env.reset(seed=3)
    irs, places = [obs["ir"]], [obs["place"]]
    for _ in range(30):
        obs, *_ = env.step(np.array([0.7, 0.7], np.float32))
        irs.append(obs["ir"])
        places.append(obs["place"])
    model.reset_state()
    direct = np.array([model.step(u) for u in irs])
    np.testing.assert_allclose(np.array(places), direct, rtol=1e-5, atol=1e-5)


def test_time_cells_restart_at_each_event_and_track_elapsed_time(fitted):
    model, protos = fitted
    env = HippoCells(gym.make("hippo/TwoRooms-v0"), model, protos)
    obs, info = env.reset(seed=2)
    since = 0.0
    timing = env.timing
    for _ in range(60):
        obs, _, _, _, info = env.step(np.array([0.6, 0.5], np.float32))
        since = 0.0 if info["hippo_event"] else since + env.dt
        # the time cells encode the seconds since the last sensory event
        np.testing.assert_allclose(obs["time"], timing.tuning(since), atol=1e-6)
    assert isinstance(env.describe(info["hippo_state"]), str)


def test_wrapper_refuses_what_it_cannot_serve(fitted):
    model, _ = fitted
    base = gym.make("hippo/TwoRooms-v0")
    with pytest.raises(ValueError, match="fitted"):
        HippoCells(base, RCSFAICA())
    with pytest.raises(ValueError, match="recruit"):
        grow = PlacePrototypes(PrototypeParams(n_prototypes=4, recruit_threshold=0.2))
        HippoCells(base, model, grow.fit(np.random.default_rng(0).normal(size=(50, 4))))
    with pytest.raises(ValueError, match="17"):
        m17 = RCSFAICA(n_inputs=17, n_reservoir=20, n_sfa=2, n_ica=2, ica_restarts=1)
        m17.fit(np.random.default_rng(0).uniform(size=(400, 17)))
        HippoCells(base, m17)
