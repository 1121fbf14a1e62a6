"""A wrapper that adds hippo's own cells to a robot environment's observation.

:class:`HippoCells` runs, at every tick, the same perception as hippo's agent (the brain's
neural chain, :meth:`hippo.brain.Brain.perceive`)::

    place = PlacePrototypes(RCSFAICA.step(ir))      learned place cells (or the ICA units)
    event = StateLayer.step(place, floor, sound, moving)    winner-take-all state, sensory events
    time  = SpectralTiming.step(event.winner)        the winner's battery of time cells
            (then the transition cells and non-occurrence neurons, as in the brain)

and returns the observation with two more keys: ``place`` (place-cell activities) and ``time``
(the time cells of the current state: bumps centred on log-spaced delays since the last
sensory event, HIREL's spectral timing). The winning state's id and whether it just changed go
to ``info`` (``hippo_state``, ``hippo_event``): state ids are recruited as the robot meets new
places, so they do not fit a fixed-size space. An RL agent can then learn on top of cells that
have state and dynamics of their own.
"""

from __future__ import annotations

import copy
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from hippo.brain import Brain, BrainParams
from hippo.perception.place_cells import RCSFAICA
from hippo.perception.prototypes import PlacePrototypes
from hippo.perception.states import StateLayerParams
from hippo.tasks.explore import PLACE_STATES
from hippo.timing.spectral import SpectralParams

#: state-layer settings for place activities in [0, 1] (prototypes), as in hippo's scenarios
PROTOTYPE_STATES = PLACE_STATES


class HippoCells(gym.Wrapper, gym.utils.RecordConstructorArgs):
    """Add place-cell and time-cell activities to a :class:`~hippo.envs.robot.RobotEnv`'s
    observation.

    Parameters
    ----------
    env : an environment whose observation is hippo's ``Dict`` (``ir``, ``floor``, ``sound``,
        ``moving``, ...), e.g. ``gymnasium.make("hippo/TwoRooms-v0")``.
    place_cells : a *fitted* :class:`~hippo.perception.place_cells.RCSFAICA` (fit it on a
        recording of the robot exploring the same arena; see :func:`hippo.sim.record`).
    prototypes : optional fitted :class:`~hippo.perception.prototypes.PlacePrototypes` over the
        model's ICA outputs; the ``place`` key then holds the prototypes' activities in
        [0, 1] instead of the unit-variance ICA units.
    states : state-layer parameters (default: ``PROTOTYPE_STATES`` with prototypes, else the
        layer's defaults).
    timing : time-cell parameters (default :class:`~hippo.timing.spectral.SpectralParams`:
        128 cells, centres 0.2-120 s).

    The wrapper steps its own copy of ``place_cells`` and ``prototypes`` (the objects passed in
    are left as they are), so several wrapped environments can share one fitted model. On
    ``reset`` the reservoir restarts from ``x = 0`` and the state layer forgets its winner
    (it keeps the states it has recruited); a recurrent network needs a few seconds of input
    before its place code is reliable (SMC09 Fig. 7).
    """

    def __init__(self, env: gym.Env, place_cells: RCSFAICA,
                 prototypes: PlacePrototypes | None = None, *,
                 states: StateLayerParams | None = None,
                 timing: SpectralParams | None = None) -> None:
        gym.utils.RecordConstructorArgs.__init__(self, place_cells=place_cells,
                                                 prototypes=prototypes, states=states,
                                                 timing=timing)
        gym.Wrapper.__init__(self, env)
        space = env.observation_space
        if not isinstance(space, spaces.Dict) or "ir" not in space.spaces:
            raise ValueError("HippoCells needs an environment with hippo's Dict observation "
                             f"(keys ir, floor, sound, moving), got {space}")
        for key in ("place", "time"):
            if key in space.spaces:
                raise ValueError(f"the observation already has a key {key!r}")
        if getattr(place_cells, "ica_", None) is None:
            raise ValueError("place_cells must be a fitted RCSFAICA (call fit first)")
        n_ir = space.spaces["ir"].shape[0]
        if place_cells.n_features_in_ != n_ir:
            raise ValueError(f"place_cells were fitted on {place_cells.n_features_in_} sensors, "
                             f"the environment has {n_ir}")
        if prototypes is not None and getattr(prototypes, "centres_", None) is None:
            raise ValueError("prototypes must be fitted PlacePrototypes (call fit first)")
        if prototypes is not None and prototypes.params.recruit_threshold > 0:
            raise ValueError("prototypes that recruit new cells online (recruit_threshold > 0) "
                             "would change the size of the observation; use recruit_threshold=0")
        self.place_cells = copy.deepcopy(place_cells)
        self.prototypes = copy.deepcopy(prototypes)
        layer_params = states or (PROTOTYPE_STATES if prototypes is not None else None)
        self.brain = Brain(params=BrainParams(
            states=layer_params if layer_params is not None else StateLayerParams(),
            spectral=timing if timing is not None else SpectralParams()))
        self.layer, self.timing = self.brain.layer, self.brain.spectral
        self.dt = float(env.unwrapped.world.dt)
        if prototypes is not None:
            n_place, place_space = prototypes.n_units, (0.0, 1.0)
        else:
            n_place, place_space = int(place_cells.params.n_ica), (-np.inf, np.inf)
        self.observation_space = spaces.Dict({
            **space.spaces,
            "place": spaces.Box(*place_space, (n_place,), np.float32),
            "time": spaces.Box(0.0, 1.0, (self.timing.n_cells,), np.float32),
        })

    def _cells(self, obs: dict[str, Any], info: dict[str, Any]) -> dict[str, Any]:
        y = self.place_cells.step(obs["ir"])
        place = y if self.prototypes is None else self.prototypes.step(y)
        seen = self.brain.perceive(place, colour=int(obs["floor"]), sound=bool(obs["sound"]),
                                   moving=bool(obs["moving"]), dt=self.dt)
        event, battery = seen.event, seen.timing.battery
        info["hippo_state"] = event.winner
        info["hippo_event"] = bool(event.changed)
        return {**obs, "place": np.asarray(place, dtype=np.float32),
                "time": np.asarray(battery.activity, dtype=np.float32)}

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[dict[str, Any], dict[str, Any]]:
        """Reset the environment and the cells (reservoir at 0, no winner, batteries silent)."""
        obs, info = self.env.reset(seed=seed, options=options)
        self.place_cells.reset_state()
        self.layer.reset(keep_states=True)
        self.timing.reset()
        self.brain.nonocc.reset()
        return self._cells(obs, info), info

    def step(self, action: Any) -> tuple[dict[str, Any], float, bool, bool, dict[str, Any]]:
        """Step the environment, then the cells on what the robot sensed."""
        obs, reward, terminated, truncated, info = self.env.step(action)
        return self._cells(obs, info), reward, terminated, truncated, info

    def describe(self, state: int) -> str:
        """Name of a state id from ``info["hippo_state"]`` (``place 3``, ``colour 1``, ...)."""
        return self.layer.describe(state)
