"""HippoCells' rules on stand-in place cells whose outputs are known by hand.

The stand-in model's step returns 2 ir[:2] - 1 (its two "ICA units"), the stand-in prototypes'
step 1 - |y| / 2 clipped to [0, 1] per unit plus a third constant unit of 0.25: the ``place``
key must be exactly those numbers (float32). The ``time`` key and the state in ``info`` must
be what a Brain built with the documented parameters (PROTOTYPE_STATES with prototypes, the
layer's defaults without; SpectralParams by default) gives for the same places, floor, sound
and motion, tick by tick; every refusal is checked word for word.
"""

from __future__ import annotations

import re
from types import SimpleNamespace
from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from gymnasium import spaces

from hippo.brain import Brain, BrainParams
from hippo.envs.robot import PlacePreferenceEnv, TwoRoomsEnv
from hippo.envs.wrappers import PROTOTYPE_STATES, HippoCells
from hippo.perception.states import StateLayerParams
from hippo.tasks.explore import PLACE_STATES
from hippo.timing.spectral import SpectralParams


class _Model:
    """A fitted-looking RCSFAICA: two units, 2 ir[:2] - 1; counts its resets."""

    def __init__(self, n_in: int = 8) -> None:
        self.ica_ = object()
        self.n_features_in_ = n_in
        self.params = SimpleNamespace(n_ica=2)
        self.resets = 0
        self.steps = 0
        self.seen: list[np.ndarray] = []

    def step(self, ir: np.ndarray) -> np.ndarray:
        self.steps += 1
        self.seen.append(ir)
        return 2.0 * np.asarray(ir[:2], float) - 1.0

    def reset_state(self) -> None:
        self.resets += 1


class _Protos:
    def __init__(self, recruit: float = 0.0) -> None:
        self.centres_ = np.zeros((3, 2))
        self.params = SimpleNamespace(recruit_threshold=recruit)
        self.n_units = 3
        self.steps = 0
        self.seen: list[np.ndarray] = []

    def step(self, y: np.ndarray) -> np.ndarray:
        self.steps += 1
        self.seen.append(y)
        return np.concatenate([np.clip(1.0 - np.abs(y) / 2.0, 0.0, 1.0), [0.25]])


def refused(message: str):
    return pytest.raises(ValueError, match="^" + re.escape(message) + "$")


class _DictEnv(gym.Env):
    def __init__(self, space: spaces.Space) -> None:
        self.observation_space = space
        self.action_space = spaces.Discrete(1)


def test_the_environment_and_the_model_are_checked_word_for_word():
    box = spaces.Box(0, 1, (3,))
    with refused("HippoCells needs an environment with hippo's Dict observation (keys ir, "
                 f"floor, sound, moving), got {box}"):
        HippoCells(_DictEnv(box), _Model())  # type: ignore[arg-type]
    no_ir = spaces.Dict({"floor": spaces.Discrete(2)})
    with refused("HippoCells needs an environment with hippo's Dict observation (keys ir, "
                 f"floor, sound, moving), got {no_ir}"):
        HippoCells(_DictEnv(no_ir), _Model())  # type: ignore[arg-type]
    for key in ("place", "time"):
        taken = spaces.Dict({"ir": spaces.Box(0, 1, (8,)), key: spaces.Discrete(2)})
        with refused(f"the observation already has a key {key!r}"):
            HippoCells(_DictEnv(taken), _Model())  # type: ignore[arg-type]
    env = TwoRoomsEnv()
    unfitted = _Model()
    unfitted.ica_ = None  # type: ignore[assignment]
    with refused("place_cells must be a fitted RCSFAICA (call fit first)"):
        HippoCells(env, unfitted)  # type: ignore[arg-type]
    with refused("place_cells were fitted on 17 sensors, the environment has 8"):
        HippoCells(env, _Model(17))  # type: ignore[arg-type]
    bare = _Protos()
    bare.centres_ = None  # type: ignore[assignment]
    with refused("prototypes must be fitted PlacePrototypes (call fit first)"):
        HippoCells(env, _Model(), bare)  # type: ignore[arg-type]
    del bare.centres_
    with refused("prototypes must be fitted PlacePrototypes (call fit first)"):
        HippoCells(env, _Model(), bare)  # type: ignore[arg-type]
    plain = _Model()
    del plain.ica_
    with refused("place_cells must be a fitted RCSFAICA (call fit first)"):
        HippoCells(env, plain)  # type: ignore[arg-type]
    with refused("prototypes that recruit new cells online (recruit_threshold > 0) would change "
                 "the size of the observation; use recruit_threshold=0"):
        HippoCells(env, _Model(), _Protos(recruit=1e-9))  # type: ignore[arg-type]
    HippoCells(env, _Model(), _Protos(recruit=0.0))  # type: ignore[arg-type]


def test_the_spaces_and_parameters_with_and_without_prototypes():
    env = TwoRoomsEnv()
    raw = HippoCells(env, _Model())  # type: ignore[arg-type]
    place, time = raw.observation_space["place"], raw.observation_space["time"]
    assert place.shape == (2,) and place.dtype == np.float32
    assert np.all(place.low == -np.inf) and np.all(place.high == np.inf)
    assert time.shape == (128,) and time.dtype == np.float32
    assert (time.low.min(), time.high.max()) == (0.0, 1.0)
    assert set(raw.observation_space.spaces) == {"ir", "floor", "sound", "moving", "odometry",
                                                 "place", "time"}
    assert raw.observation_space["ir"] is env.observation_space["ir"]
    assert raw.brain.p.states == StateLayerParams() and raw.brain.p.spectral == SpectralParams()
    assert raw.layer is raw.brain.layer and raw.timing is raw.brain.spectral
    assert raw.dt == 0.2 and type(raw.dt) is float

    protos = HippoCells(TwoRoomsEnv(dt=0.5), _Model(), _Protos())  # type: ignore[arg-type]
    place = protos.observation_space["place"]
    assert place.shape == (3,)
    assert (place.low.min(), place.high.max()) == (0.0, 1.0)
    assert PROTOTYPE_STATES is PLACE_STATES and protos.brain.p.states == PLACE_STATES
    assert protos.dt == 0.5

    mine = StateLayerParams(place_scale=0.3)
    timing = SpectralParams(n_cells=16)
    own = HippoCells(TwoRoomsEnv(), _Model(), _Protos(), states=mine,  # type: ignore[arg-type]
                     timing=timing)
    assert own.brain.p.states == mine and own.brain.p.spectral == timing
    assert own.observation_space["time"].shape == (16,)
    assert HippoCells(TwoRoomsEnv(), _Model(), states=mine  # type: ignore[arg-type]
                      ).brain.p.states == mine


def test_the_wrapper_steps_its_own_copies():
    model, protos = _Model(), _Protos()
    env = HippoCells(TwoRoomsEnv(), model, protos)  # type: ignore[arg-type]
    assert env.place_cells is not model and env.prototypes is not protos
    env.reset(seed=0)
    env.step([0.3, 0.3])
    assert (model.steps, model.resets, protos.steps) == (0, 0, 0)
    assert model.seen == [] and protos.seen == []       # nothing shared, even lists
    assert (env.place_cells.steps, env.place_cells.resets, env.prototypes.steps) == (2, 1, 2)


@pytest.mark.parametrize("with_protos", [False, True])
def test_place_time_and_state_are_the_brains_on_the_stand_in_places(with_protos):
    protos = _Protos() if with_protos else None
    env = HippoCells(TwoRoomsEnv(), _Model(), protos)  # type: ignore[arg-type]
    twin = Brain(params=BrainParams(states=PLACE_STATES if with_protos else StateLayerParams(),
                                    spectral=SpectralParams()))
    obs, info = env.reset(seed=4, options={"pose": (20.0, 44.0, 0.0)})
    actions = [[0.8, 0.8]] * 6 + [[-0.5, 0.5]] * 4 + [[0.0, 0.0]] * 3
    for k in range(len(actions) + 1):
        ir = obs["ir"].astype(float)
        y = 2.0 * ir[:2] - 1.0
        place = np.concatenate([np.clip(1.0 - np.abs(y) / 2.0, 0, 1), [0.25]]) \
            if with_protos else y
        assert obs["place"].dtype == np.float32 and obs["time"].dtype == np.float32
        np.testing.assert_array_equal(obs["place"], place.astype(np.float32))
        seen = twin.perceive(place, colour=int(obs["floor"]), sound=bool(obs["sound"]),
                             moving=bool(obs["moving"]), dt=0.2)
        np.testing.assert_array_equal(obs["time"],
                                      seen.timing.battery.activity.astype(np.float32))
        assert info["hippo_state"] == seen.event.winner
        assert info["hippo_event"] is bool(seen.event.changed)
        assert env.describe(info["hippo_state"]) == twin.layer.describe(seen.event.winner)
        assert "pose" in info and "target" in info          # the environment's info is kept
        if k == 0:
            assert info["hippo_event"] is True              # the first tick is an event
        if k < len(actions):
            obs, reward, _, truncated, info = env.step(actions[k])
            assert isinstance(reward, float) and truncated is False


def test_reset_restarts_the_cells_but_keeps_the_states(monkeypatch):
    env = HippoCells(TwoRoomsEnv(), _Model(), _Protos())  # type: ignore[arg-type]
    calls: list[Any] = []
    layer_reset = env.layer.reset
    monkeypatch.setattr(env.layer, "reset",
                        lambda **kw: (calls.append(("layer", kw)), layer_reset(**kw))[1])
    monkeypatch.setattr(env.timing, "reset", lambda: calls.append("timing"))
    monkeypatch.setattr(env.brain.nonocc, "reset", lambda: calls.append("nonocc"))
    _, info = env.reset(seed=1, options={"pose": (20.0, 44.0, 0.0)})
    assert calls == [("layer", {"keep_states": True}), "timing", "nonocc"]
    assert env.place_cells.resets == 1
    first = info["hippo_state"]
    for _ in range(5):
        env.step([0.9, 0.9])
    n_states = env.layer.n_states
    calls.clear()
    _, info = env.reset(seed=1, options={"pose": (20.0, 44.0, 0.0)})
    assert calls == [("layer", {"keep_states": True}), "timing", "nonocc"]
    assert env.place_cells.resets == 2
    assert env.layer.n_states >= n_states        # the states recruited are kept
    assert info["hippo_state"] == first and info["hippo_event"] is True


def test_the_constructor_arguments_are_recorded():
    model, protos = _Model(), _Protos()
    mine, timing = StateLayerParams(place_scale=0.3), SpectralParams(n_cells=16)
    env = HippoCells(TwoRoomsEnv(), model, protos, states=mine,  # type: ignore[arg-type]
                     timing=timing)
    saved = env._saved_kwargs      # (gymnasium keeps copies of them)
    assert set(saved) == {"place_cells", "prototypes", "states", "timing"}
    assert isinstance(saved["place_cells"], _Model) and isinstance(saved["prototypes"], _Protos)
    assert saved["states"] == mine and saved["timing"] == timing


def test_reset_passes_its_options_and_the_floor_and_sound_reach_the_cells():
    """In the goal zone (goal-arena: (0, 70)-(24, 82), colour 1) and still, the robot hears
    the reward sound once the delay is over: colour and sound must reach the state layer as
    a Brain stepped by hand sees them."""
    env = HippoCells(PlacePreferenceEnv(delay=0.4), _Model(), _Protos())  # type: ignore[arg-type]
    twin = Brain(params=BrainParams(states=PLACE_STATES, spectral=SpectralParams()))
    obs, info = env.reset(seed=0, options={"pose": (12.0, 76.0, 0.0)})
    np.testing.assert_array_equal(info["pose"], [12.0, 76.0, 0.0])
    floors, sounds = [], []
    for k in range(6):
        if k:
            obs, _, _, _, info = env.step([0.0, 0.0])
        floors.append(int(obs["floor"]))
        sounds.append(int(obs["sound"]))
        seen = twin.perceive(np.asarray(obs["place"], float), colour=int(obs["floor"]),
                             sound=bool(obs["sound"]), moving=bool(obs["moving"]), dt=0.2)
        assert info["hippo_state"] == seen.event.winner
        assert env.describe(info["hippo_state"]) == twin.layer.describe(seen.event.winner)
        np.testing.assert_array_equal(obs["time"],
                                      seen.timing.battery.activity.astype(np.float32))
    assert floors == [1] * 6 and 1 in sounds
    assert any(env.describe(s).startswith(("colour", "sound"))
               for s in range(env.layer.n_states))
