"""The tasks behind hippo's Gymnasium environments: where an episode starts and what earns reward.

A task sees the world (ground truth included) to decide the reward, but the agent receives only
the reward and what the robot senses; everything a task knows about the true state goes to
``info``. Both tasks of HIREL reward by the **sound**: the robot hears it in the observation
(``sound = 1``) on the tick the reward is paid, as HIREL's robot heard the experimenter's
reward sound.

- :class:`ShuttleTask` (two rooms): +1 each time the robot reaches the room it was not in.
- :class:`GoalWaitTask` (HIREL III-A place preference): +1, with the sound, once the robot has
  stood still in the goal zone for ``delay`` seconds; the episode then ends.
- :class:`PatrolTask` (HIREL III-B security patrol): +1, with the sound, each time the robot has
  stood still at the next checkpoint of the round for that checkpoint's wait.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, ClassVar

import numpy as np

from hippo._checks import check_positive
from hippo.sim import arenas
from hippo.sim.arena import Arena
from hippo.sim.world import Observation, World

Pose = tuple[float, float, float]


class Task:
    """Base class: an arena, a start pose, and a reward rule applied after each tick."""

    #: arena the task runs in
    arena: Arena
    #: named points drawn by ``render`` (goal, checkpoints)
    marks: dict[str, tuple[float, float]]

    def start_pose(self, rng: np.random.Generator) -> Pose:
        """Where an episode starts (drawn from ``rng``, the environment's ``np_random``)."""
        raise NotImplementedError

    def reset(self, world: World, obs: Observation) -> dict[str, Any]:
        """Start an episode; returns the task's part of ``info``."""
        raise NotImplementedError

    def step(self, world: World, obs: Observation) -> tuple[float, bool, dict[str, Any]]:
        """Reward, termination and the task's part of ``info`` after one tick."""
        raise NotImplementedError


class ShuttleTask(Task):
    """Two rooms (SMC09 Fig. 3): +1 each time the robot enters the room it was not in last.

    The target room is never observed: an agent has to remember where it has been, which is
    what the reservoir's memory gives hippo's place cells. Episodes start at a random free pose.
    ``info`` has ``target`` (the room that pays next) and ``visits`` (rewards so far).
    """

    ROOMS: ClassVar[tuple[str, str]] = ("room_a", "room_b")

    def __init__(self) -> None:
        self.arena = arenas.two_rooms()
        self.marks = {}

    def start_pose(self, rng: np.random.Generator) -> Pose:
        return self.arena.sample_free_pose(rng)

    def _room(self, world: World) -> str | None:
        x, y, _ = world.truth.pose  # the task reads the ground truth, never the agent
        name = self.arena.region_of(x, y)
        return name if name in self.ROOMS else None

    def reset(self, world: World, obs: Observation) -> dict[str, Any]:
        room = self._room(world)
        # in the corridor: the room it faces pays first
        if room is None:
            room = "room_a" if math.cos(world.truth.pose[2]) > 0 else "room_b"
        self.target = self.ROOMS[1 - self.ROOMS.index(room)]
        self.visits = 0
        return {"target": self.target, "visits": 0}

    def step(self, world: World, obs: Observation) -> tuple[float, bool, dict[str, Any]]:
        reward = 0.0
        if self._room(world) == self.target:
            reward = 1.0
            self.visits += 1
            self.target = self.ROOMS[1 - self.ROOMS.index(self.target)]
        return reward, False, {"target": self.target, "visits": self.visits}


class _StillTimer:
    """Seconds the robot has stood still inside a condition (reset when it moves or leaves)."""

    def __init__(self) -> None:
        self.still = 0.0

    def update(self, inside: bool, obs: Observation, dt: float) -> float:
        self.still = self.still + dt if inside and not obs.moving else 0.0
        return self.still


class GoalWaitTask(Task):
    """HIREL III-A place preference in :func:`~hippo.sim.arenas.goal_arena`.

    The goal zone is coloured floor (the robot senses ``floor = 1`` there). Once the robot has
    stood still in it for ``delay`` seconds (HIREL: 7 s) the reward sound plays: reward +1 and
    the episode ends. Episodes start at one of the four corridor start places (``start-south``,
    ``-east``, ``-north``, ``-west``), drawn at random, facing counter-clockwise along the
    corridor. ``info`` has ``still_in_goal_s`` (the current stop in the zone).
    """

    STARTS: ClassVar[dict[str, float]] = {"south": 0.0, "east": math.pi / 2,
                                          "north": math.pi, "west": -math.pi / 2}

    def __init__(self, delay: float = 7.0) -> None:
        self.delay = check_positive("delay", delay)
        self.arena = arenas.goal_arena()
        self.marks = {"goal": self.arena.landmarks["goal"]}
        self.colour = self.arena.zones[0].colour

    def start_pose(self, rng: np.random.Generator) -> Pose:
        name = list(self.STARTS)[int(rng.integers(len(self.STARTS)))]
        x, y = self.arena.landmarks[f"start-{name}"]
        return x, y, self.STARTS[name]

    def reset(self, world: World, obs: Observation) -> dict[str, Any]:
        self.timer = _StillTimer()
        self.sounded = False
        return {"still_in_goal_s": 0.0}

    def step(self, world: World, obs: Observation) -> tuple[float, bool, dict[str, Any]]:
        if obs.sound:  # the sound asked for at the previous tick is heard now
            return 1.0, True, {"still_in_goal_s": self.timer.still}
        still = self.timer.update(obs.floor == self.colour, obs, world.dt)
        if not self.sounded and still >= self.delay - 1e-9:
            world.emit_sound()
            self.sounded = True
        return 0.0, False, {"still_in_goal_s": still}


class PatrolTask(Task):
    """HIREL III-B security patrol on :func:`~hippo.sim.arenas.patrol_course`.

    The round is checkpoint 1, 2, 3, 1, ... (south, east, north corridor). When the robot has
    stood still within ``radius`` cm of the next checkpoint for that checkpoint's wait
    (``waits``, HIREL: 24.1, 19.1, 11.6 s) the reward sound plays (+1) and the next checkpoint
    of the round becomes due. Stops elsewhere earn nothing. The task never ends by itself
    (``gymnasium.make`` adds a time limit). ``info`` has ``checkpoint`` (1-based, the one due),
    ``still_s`` (the current stop there) and ``served`` (rewards so far).
    """

    def __init__(self, waits: Sequence[float] = (24.1, 19.1, 11.6), radius: float = 12.0) -> None:
        try:   # no string ("123" reads as 1, 2, 3 s), nor a string or bool wait ("24.1", True)
            given = None if isinstance(waits, str | bytes) else tuple(waits)
            if given is None or any(isinstance(w, str | bytes | bool | np.bool_) for w in given):
                raise TypeError
            waits = tuple(float(w) for w in given)
        except (TypeError, ValueError):   # 5, "abc", (None, 2, 3): no three waits
            raise ValueError(f"waits must be three waits in s, one per checkpoint, got "
                             f"{waits!r:.80}") from None
        if len(waits) != 3:
            raise ValueError(f"waits must give one wait per checkpoint (3), got {waits}")
        for w in waits:
            check_positive("waits", w)
        self.waits = waits
        self.radius = check_positive("radius", radius)
        self.arena = arenas.patrol_course()
        self.checkpoints = [self.arena.landmarks[f"checkpoint-{k}"] for k in (1, 2, 3)]
        self.marks = {f"checkpoint-{k + 1}": c for k, c in enumerate(self.checkpoints)}

    def start_pose(self, rng: np.random.Generator) -> Pose:
        return self.arena.start_pose

    def reset(self, world: World, obs: Observation) -> dict[str, Any]:
        self.due = 0
        self.served = 0
        self.timer = _StillTimer()
        self.sounded = False
        return self._info()

    def _info(self) -> dict[str, Any]:
        return {"checkpoint": self.due + 1, "still_s": self.timer.still, "served": self.served}

    def step(self, world: World, obs: Observation) -> tuple[float, bool, dict[str, Any]]:
        if obs.sound and self.sounded:
            self.served += 1
            self.due = (self.due + 1) % 3
            self.sounded = False
            self.timer = _StillTimer()
            return 1.0, False, self._info()
        cx, cy = self.checkpoints[self.due]
        x, y, _ = world.truth.pose
        near = math.hypot(x - cx, y - cy) <= self.radius
        still = self.timer.update(near, obs, world.dt)
        if not self.sounded and still >= self.waits[self.due] - 1e-9:
            world.emit_sound()
            self.sounded = True
        return 0.0, False, self._info()
