"""hippo's robot as a Gymnasium environment: the robot's senses in, wheel speeds out.

The observation is what the e-puck senses and nothing else (a :class:`gymnasium.spaces.Dict`):

- ``ir`` ``Box(0, 1, (n,), float32)``: distance sensors (0 touching, 1 nothing in range);
- ``floor`` ``Discrete(colours + 1)``: floor colour under the robot (0 = plain);
- ``sound`` ``Discrete(2)``: the reward sound is heard this tick;
- ``moving`` ``Discrete(2)``: proprioception, the robot is translating;
- ``odometry`` ``Box(-b, b, (3,), float32)``: wheel odometry of the tick, dx and dy (cm, in
  the robot's frame at the tick's start, within twice the top speed × dt) and dθ (rad,
  within ±π).

The action is a pair of wheel speeds normalised to ``[-1, 1]`` (left, right), scaled by the
robot's top speed (5.08 cm/s for the e-puck); actions outside the box are clipped. One step is
one control tick, ``dt`` = 0.2 s. Ground truth (pose, speed, region, nearest labelled location
and the task's own bookkeeping) is in ``info`` only.

Seeding follows Gymnasium: ``reset(seed=s)`` seeds :attr:`np_random`, from which each episode
draws its start pose and the world's noise seed; ``reset()`` without a seed continues the
stream. ``reset(options={"pose": (x, y, heading)})`` starts at a chosen pose instead.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any, ClassVar

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from hippo.envs.rewards import GoalWaitTask, PatrolTask, ShuttleTask, Task
from hippo.sim.robot import RobotParams, SensorModel
from hippo.sim.world import Observation, World


class RobotEnv(gym.Env):
    """A hippo :class:`~hippo.sim.world.World` driven through Gymnasium's API.

    Parameters
    ----------
    task : the arena, start places and reward rule (:mod:`hippo.envs.rewards`).
    sensors : ``"ir8"`` (SMC09's e-puck, default) or ``"ray17"`` (ICANN09), or a
        :class:`~hippo.sim.robot.SensorModel`.
    robot : body and drive (default: the e-puck).
    dt : control period, s.
    render_mode : ``None`` or ``"rgb_array"`` (the arena and the robot, drawn with matplotlib).
    """

    metadata: ClassVar[dict[str, Any]] = {"render_modes": ["rgb_array"], "render_fps": 5}

    def __init__(self, task: Task, *, sensors: str | SensorModel = "ir8",
                 robot: RobotParams | None = None, dt: float = 0.2,
                 render_mode: str | None = None) -> None:
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be None or one of "
                             f"{self.metadata['render_modes']}, got {render_mode!r}")
        self.task = task
        self.render_mode = render_mode
        self.world = World(task.arena, robot=robot, sensors=sensors, dt=dt, seed=None)
        self.metadata = {**self.metadata, "render_fps": round(1.0 / self.world.dt)}
        step = 2.0 * self.world.robot.speed_max * self.world.dt
        self._odometry_bound = np.array([step, step, np.pi], dtype=np.float32)
        n_colours = max((z.colour for z in task.arena.zones), default=0)
        self.observation_space = spaces.Dict({
            "ir": spaces.Box(0.0, 1.0, (self.world.sensors.n,), np.float32),
            "floor": spaces.Discrete(n_colours + 1),
            "sound": spaces.Discrete(2),
            "moving": spaces.Discrete(2),
            "odometry": spaces.Box(-self._odometry_bound, self._odometry_bound, (3,),
                                   np.float32),
        })
        self.action_space = spaces.Box(-1.0, 1.0, (2,), np.float32)
        self._renderer: Any = None
        self._last: Observation | None = None

    # -- Gymnasium API ------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[dict[str, Any], dict[str, Any]]:
        """Start an episode: ``(observation, info)``.

        ``seed`` seeds :attr:`np_random` (only when given); ``options={"pose": (x, y,
        heading)}`` starts the robot there instead of the task's start place.
        """
        super().reset(seed=seed)
        options = options or {}
        if not isinstance(options, Mapping):
            raise ValueError(f"options must be a dict, got {options!r:.80}")
        unknown = set(options) - {"pose"}
        if unknown:
            raise ValueError(f"unknown reset option(s) {sorted(unknown)}; allowed: 'pose'")
        given = options.get("pose")
        try:
            pose = tuple(float(v) for v in given) if given is not None else \
                self.task.start_pose(self.np_random)
        except (TypeError, ValueError):
            pose = ()
        if len(pose) != 3 or not all(map(math.isfinite, pose)):
            raise ValueError(f"options['pose'] must be three finite numbers (x, y, heading), "
                             f"got {given!r:.80}")
        world_seed = int(self.np_random.integers(0, 2**63 - 1))
        obs = self.world.reset(world_seed, pose=pose)  # type: ignore[arg-type]
        self._last = obs
        info = {**self._truth(obs), **self.task.reset(self.world, obs)}
        return self._observation(obs), info

    def step(self, action: Any) -> tuple[dict[str, Any], float, bool, bool, dict[str, Any]]:
        """One control tick with wheel speeds ``action`` in [-1, 1]² (clipped):
        ``(observation, reward, terminated, truncated, info)``."""
        if self._last is None:
            raise RuntimeError("call reset() before step()")
        try:
            a = np.asarray(action, dtype=float).reshape(-1)
        except (TypeError, ValueError):   # a string, a dict, complex numbers: no wheel speeds
            a = np.full(0, np.nan)
        if a.shape != (2,) or not np.all(np.isfinite(a)):
            raise ValueError(f"action must be two finite wheel speeds (in [-1, 1]; beyond it "
                             f"they are clipped), got {action!r:.80}")
        wheels = np.clip(a, -1.0, 1.0) * self.world.robot.speed_max
        obs = self.world.step(wheels)
        self._last = obs
        reward, terminated, task_info = self.task.step(self.world, obs)
        info = {**self._truth(obs), **task_info}
        return self._observation(obs), float(reward), bool(terminated), False, info

    def render(self) -> np.ndarray | None:
        """The arena with the robot, ``(H, W, 3)`` uint8 (``render_mode="rgb_array"``)."""
        if self.render_mode is None:
            gym.logger.warn("render() called without a render_mode; "
                            "make the environment with render_mode='rgb_array'")
            return None
        if self._renderer is None:
            from hippo.envs.render import ArenaRenderer

            self._renderer = ArenaRenderer(self.task.arena, self.world.robot.radius,
                                           marks=self.task.marks)
        return self._renderer.frame(self.world.pose)

    def close(self) -> None:
        """Release the figure used for rendering (safe to call twice)."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

    # -- conversions --------------------------------------------------------------------------
    def _observation(self, obs: Observation) -> dict[str, Any]:
        odo = np.clip(np.asarray(obs.odometry, dtype=np.float32), -self._odometry_bound,
                      self._odometry_bound)
        return {
            "ir": np.asarray(obs.ir, dtype=np.float32),
            "floor": np.int64(obs.floor),
            "sound": np.int64(obs.sound),
            "moving": np.int64(obs.moving),
            "odometry": odo,
        }

    def _truth(self, obs: Observation) -> dict[str, Any]:
        truth = self.world.truth  # the ground truth of obs (info only, never the observation)
        x, y, h = truth.pose
        arena = self.task.arena
        return {"t": obs.t, "pose": np.array([x, y, h]), "speed": truth.speed,
                "region": arena.region_of(x, y),
                "location": int(arena.nearest_location(x, y))}


class TwoRoomsEnv(RobotEnv):
    """``hippo/TwoRooms-v0``: SMC09's two rooms; +1 for reaching the other room
    (:class:`~hippo.envs.rewards.ShuttleTask`). Keyword arguments go to :class:`RobotEnv`."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(ShuttleTask(), **kwargs)


class PlacePreferenceEnv(RobotEnv):
    """``hippo/PlacePreference-v0``: HIREL's place preference; +1 and the end of the episode
    after ``delay`` s still in the goal zone (:class:`~hippo.envs.rewards.GoalWaitTask`)."""

    def __init__(self, delay: float = 7.0, **kwargs: Any) -> None:
        super().__init__(GoalWaitTask(delay), **kwargs)


class PatrolEnv(RobotEnv):
    """``hippo/Patrol-v0``: HIREL's security patrol; +1 for each checkpoint served in order
    with its wait (:class:`~hippo.envs.rewards.PatrolTask`)."""

    def __init__(self, waits: tuple[float, float, float] = (24.1, 19.1, 11.6),
                 radius: float = 12.0, **kwargs: Any) -> None:
        super().__init__(PatrolTask(waits, radius), **kwargs)
