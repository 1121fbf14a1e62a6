"""The motor layer: turns the brain's decision (a :class:`~hippo.brain.Tick`) and the senses into
wheel speeds.

By the tick's :class:`~hippo.types.Mode`:

- ``WAIT`` (or boxed in: every forward ray reads an obstacle) — stand still;
- ``MOVE`` / ``APPROACH`` with a heading — go along the heading the way the robot explored
  (:class:`~hippo.sim.controllers.WallGuidedHeading`: follow the wall while that goes the right
  way, steer to the heading otherwise, with obstacle avoidance). A heading that runs into a wall
  leaves the robot stalled (own speed under ``stall_speed`` for ``stall_time`` s): it then
  follows the wall for ``unstick_time`` s. A move that takes longer than the brain's
  ``move_limit`` is given up (:attr:`MotorCommand.gave_up`) and the robot explores;
- ``EXPLORE``, or a settling robot — SMC09's wall follower.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from hippo._checks import check_fields, check_positive, check_wall_side
from hippo.sim.controllers import (
    ObstacleAvoidance,
    WallFollower,
    WallFollowerParams,
    WallGuidedHeading,
)
from hippo.sim.robot import RobotParams, SensorModel, get_sensor_model
from hippo.types import Mode, Observation

if TYPE_CHECKING:
    from hippo.ticks import Tick

__all__ = ["Motor", "MotorCommand", "MotorParams"]


@dataclass(frozen=True)
class MotorParams:
    """Parameters of the motor layer (speed: the e-puck of SMC09).

    speed: cm/s of a move along a heading.
    explore_rho: side-switch probability of the exploring wall follower (0: a steady tour).
    stall_speed: cm/s (from odometry) under which a moving robot counts as stalled.
    stall_time, unstick_time: a move that leaves the robot stalled for ``stall_time`` s (its
        heading runs into a wall) hands over to the wall follower for ``unstick_time`` s.
    wall_tolerance: a move goes along the followed wall (the exploration's own motion, so the
        place cells see what they were trained on) while the move's heading is within this
        many radians of the robot's; beyond it the robot steers to the heading.
    wall_side: the wall both followers keep to: -1 right (around a ring: counter-clockwise),
        +1 left (clockwise). It must be the side the robot explored along: place cells learned
        on one direction of travel along one wall code that motion, not its mirror.
    """

    speed: float = 5.08
    explore_rho: float = 0.0
    stall_speed: float = 0.5
    stall_time: float = 1.0
    unstick_time: float = 4.0
    wall_tolerance: float = 2.0
    wall_side: int = -1

    def __post_init__(self) -> None:
        check_fields(self)
        check_positive("speed", self.speed)
        check_positive("stall_speed", self.stall_speed, allow_zero=True)
        check_positive("stall_time", self.stall_time, allow_zero=True)
        check_positive("unstick_time", self.unstick_time, allow_zero=True)
        check_positive("wall_tolerance", self.wall_tolerance)
        check_wall_side("wall_side", self.wall_side)
        if not 0.0 <= self.explore_rho <= 1.0:
            raise ValueError(f"explore_rho must lie in [0, 1], got {self.explore_rho}")


@dataclass(frozen=True, slots=True)
class MotorCommand:
    """Wheel speeds (cm/s) and whether the current move was given up (it took too long)."""

    left: float
    right: float
    gave_up: bool = False

    @property
    def wheels(self) -> tuple[float, float]:
        return self.left, self.right


class Motor:
    """Exploration, steering to a heading, avoidance, stall handling and waiting.

    ``rng_explore`` and ``rng_steer`` drive the two wall followers' speed drift and side
    switches (Generators, or seeds).
    """

    def __init__(self, params: MotorParams | None = None, *, dt: float = 0.2,
                 sensors: str | SensorModel = "ir8", robot: RobotParams | None = None,
                 rng_explore: np.random.Generator | int | None = 0,
                 rng_steer: np.random.Generator | int | None = 0) -> None:
        self.p = p = params or MotorParams()
        self.dt = check_positive("dt", dt)
        self.robot = robot or RobotParams()
        self.sensors = get_sensor_model(sensors)
        self.explorer = WallFollower(WallFollowerParams(rho=p.explore_rho), sensors=self.sensors,
                                     robot=self.robot, rng=rng_explore, side=p.wall_side)
        self.steer = WallGuidedHeading(sensors=self.sensors, robot=self.robot, side=p.wall_side,
                                       tolerance=p.wall_tolerance, speed=p.speed, rng=rng_steer)
        self.avoid = ObstacleAvoidance(sensors=self.sensors, robot=self.robot)
        self._stalled = 0
        self._unstick_until = -math.inf

    def boxed_in(self, obs: Observation) -> bool:
        """Every forward ray reads an obstacle at touching distance (e.g. the teacher's block)."""
        return self.avoid.boxed_in(obs)

    def act(self, obs: Observation, tick: Tick) -> MotorCommand:
        """Wheel speeds for this tick's decision."""
        if tick.settling:
            return MotorCommand(*self.explorer.act(obs))
        if self.avoid.boxed_in(obs) or tick.mode == Mode.WAIT:
            return MotorCommand(0.0, 0.0)
        if tick.mode in (Mode.MOVE, Mode.APPROACH) and tick.target_heading is not None:
            own_speed = math.hypot(obs.odometry[0], obs.odometry[1]) / self.dt  # odometry
            self._stalled = self._stalled + 1 if own_speed < self.p.stall_speed else 0
            if self._stalled * self.dt >= self.p.stall_time:
                self._unstick_until, self._stalled = tick.t + self.p.unstick_time, 0
            if tick.t < self._unstick_until:
                return MotorCommand(*self.explorer.act(obs))
            if tick.t - tick.move_since <= tick.move_limit:  # type: ignore[operator]
                return MotorCommand(*self.steer.act(obs, tick.heading, tick.target_heading))
            return MotorCommand(*self.explorer.act(obs), gave_up=True)
        return MotorCommand(*self.explorer.act(obs))
