"""The motor layer: turns the brain's decision (a :class:`~hippo.brain.Tick`) and the senses into
wheel speeds.

By the tick's :class:`~hippo.types.Mode`:

- ``WAIT`` (or boxed in: every forward ray reads an obstacle) — stand still;
- ``MOVE`` / ``APPROACH`` with a heading — go along the heading the way the robot explored
  (:class:`~hippo.sim.controllers.WallGuidedHeading`: follow the wall while that goes the right
  way, steer to the heading otherwise, with obstacle avoidance). A heading that runs into a wall
  leaves the robot stalled (own speed under ``stall_speed`` for ``stall_time`` s): it then
  goes along the blocking wall for ``unstick_time`` s, the way along it nearer the move's
  heading and the robot's own travel (:meth:`Motor.unstick_way`). A move that takes longer
  than the brain's ``move_limit`` is given up (:attr:`MotorCommand.gave_up`) and the robot
  explores;
- ``EXPLORE``, or a settling robot — SMC09's wall follower.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from hippo._checks import check_fields, check_positive, check_real
from hippo.sim.controllers import (
    ObstacleAvoidance,
    WallFollower,
    WallFollowerParams,
    WallGuidedHeading,
)
from hippo.sim.robot import RobotParams, SensorModel, get_sensor_model
from hippo.types import Mode, Observation, wrap_angle

if TYPE_CHECKING:
    from hippo.ticks import Tick

__all__ = ["Motor", "MotorCommand", "MotorParams"]

#: unsticking: turn on the spot at this rate (rad/s) until the heading is within _ALIGNED (rad)
_TURN, _ALIGNED = 1.5, 0.3
#: cm over which the motor's memory of its direction of travel fades
_TRAVEL_CM = 20.0


@dataclass(frozen=True)
class MotorParams:
    """Parameters of the motor layer (speed: the e-puck of SMC09).

    speed: cm/s of a move along a heading.
    explore_rho: side-switch probability of the exploring wall follower (0: a steady tour).
    stall_speed: cm/s (from odometry) under which a moving robot counts as stalled.
    stall_time, unstick_time: a move that leaves the robot stalled for ``stall_time`` s (its
        heading runs into a wall) goes along the blocking wall for ``unstick_time`` s, the
        way along it nearer the move's heading and the robot's own travel.
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
        if self.wall_side not in (-1, 1):
            raise ValueError(f"wall_side must be -1 (right) or +1 (left), got {self.wall_side!r}")
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
        self._unstick_heading, self._unstick_side = 0.0, p.wall_side
        self._aligning = 0   # ticks the turn to the unstick heading may still take
        self._align_budget = int(math.pi / (_TURN * self.dt)) + 3   # half a turn, and some
        self._travel = (0.0, 0.0)

    def boxed_in(self, obs: Observation) -> bool:
        """Every forward ray reads an obstacle at touching distance (e.g. the teacher's block)."""
        return self.avoid.boxed_in(obs)

    def unstick_way(self, obs: Observation, heading: float, target: float,
                    travel: float | None = None) -> tuple[float, int]:
        """The heading a stalled move takes to get free, and the wall side it then follows:
        along the blocking wall, the way nearer the move's heading ``target`` and the robot's
        recent direction of ``travel`` (all in the frame of the heading estimate; ``travel``
        None: not known).

        The nearest ray points at the wall: its angle ``n`` in the robot's frame is the wall's
        normal, within half the gap between rays. Along the wall the robot can go ``n + 90°``
        or ``n − 90°``. With the move's heading ``a = wrap(target − heading)`` and the travel
        ``b = wrap(travel − heading)`` in the same frame, ``n + 90°`` scores
        ``cos(n + 90° − a) + cos(n + 90° − b) = sin(a − n) + sin(b − n)`` and ``n − 90°`` the
        opposite: the robot goes ``n + 90°`` (the wall on its right: side −1) when that sum is
        positive, else ``n − 90°`` (side +1). The move's heading alone runs into the wall
        head-on when the estimate is off, and then the way the robot was going (its tour)
        decides.
        """
        heading, target = check_real("heading", heading), check_real("target", target)
        g = self.explorer.geom
        normal = float(g.angles[int(np.argmin(g.distances(obs.ir)))])
        score = math.sin(target - heading - normal)
        if travel is not None:
            score += math.sin(check_real("travel", travel) - heading - normal)
        turn = 1 if score > 0 else -1
        return wrap_angle(heading + normal + turn * math.pi / 2), -turn

    @property
    def travel(self) -> float | None:
        """The direction of the robot's last ~``_TRAVEL_CM`` cm of travel (rad, in the frame
        of the heading estimate), None before it has gone a few cm."""
        x, y = self._travel
        return math.atan2(y, x) if x * x + y * y > 4.0 else None

    def _remember_travel(self, obs: Observation, heading: float) -> None:
        """Add this tick's odometry to the travel memory, which fades with distance."""
        odometry = obs.odometry
        dx, dy, turned = odometry.tolist() if isinstance(odometry, np.ndarray) else odometry
        if dx or dy:
            h0 = heading - turned   # the heading at the start of the tick
            c, s = math.cos(h0), math.sin(h0)
            fade = max(0.0, 1.0 - math.hypot(dx, dy) / _TRAVEL_CM)
            x, y = self._travel
            self._travel = (x * fade + c * dx - s * dy, y * fade + s * dx + c * dy)

    def _unstick(self, obs: Observation, heading: float) -> tuple[float, float]:
        """Turn on the spot to the unstick heading once (a round body turns free; the time
        spent turning, at most half a turn's, is added to the unsticking), then follow the
        wall on the side that keeps it."""
        err = wrap_angle(self._unstick_heading - heading)
        if self._aligning > 0 and abs(err) > _ALIGNED:
            self._aligning -= 1
            self._unstick_until += self.dt
            return self.robot.wheels_for(0.0, math.copysign(_TURN, err))
        self._aligning = 0
        return self._follow(obs, self._unstick_side)

    def _follow(self, obs: Observation, side: int) -> tuple[float, float]:
        """The exploring wall follower's command with the wall on ``side`` for this tick
        (its own side, and a random switch of it, carried over)."""
        own = self.explorer.side
        self.explorer.side = side
        try:
            return self.explorer.act(obs)
        finally:
            self.explorer.side = own if self.explorer.side == side else -own

    def act(self, obs: Observation, tick: Tick) -> MotorCommand:
        """Wheel speeds for this tick's decision."""
        self._remember_travel(obs, tick.heading)
        if tick.settling:
            return MotorCommand(*self.explorer.act(obs))
        if self.avoid.boxed_in(obs) or tick.mode == Mode.WAIT:
            return MotorCommand(0.0, 0.0)
        if tick.mode in (Mode.MOVE, Mode.APPROACH) and tick.target_heading is not None:
            if tick.t >= self._unstick_until:
                own_speed = math.hypot(obs.odometry[0], obs.odometry[1]) / self.dt  # odometry
                self._stalled = self._stalled + 1 if own_speed < self.p.stall_speed else 0
                if self._stalled * self.dt >= self.p.stall_time:
                    self._unstick_until, self._stalled = tick.t + self.p.unstick_time, 0
                    self._aligning = self._align_budget
                    self._unstick_heading, self._unstick_side = self.unstick_way(
                        obs, tick.heading, tick.target_heading, self.travel)
            if tick.t < self._unstick_until:  # getting free: turning on the spot is no stall
                return MotorCommand(*self._unstick(obs, tick.heading))
            if tick.t - tick.move_since <= tick.move_limit:  # type: ignore[operator]
                return MotorCommand(*self.steer.act(obs, tick.heading, tick.target_heading))
            return MotorCommand(*self.explorer.act(obs), gave_up=True)
        return MotorCommand(*self.explorer.act(obs))
