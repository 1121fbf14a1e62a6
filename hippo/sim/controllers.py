"""Low-level controllers: wall following with random side switching, avoidance, go-to-heading.

Every controller maps an :class:`~hippo.sim.world.Observation` to wheel speeds ``(left, right)``
in cm/s through ``act(obs)``; it sees only the robot's own senses (sensor readings and, for
go-to-heading, a heading estimate supplied by the caller, e.g. from path integration).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hippo._checks import check_fields, check_positive, check_range, check_wall_side
from hippo.sim.robot import RobotParams, SensorModel, get_sensor_model
from hippo.types import Observation, wrap_angle


class _SensorGeometry:
    """Turns readings in [0, 1] back into distances and groups rays by direction."""

    def __init__(self, sensors: str | SensorModel, robot: RobotParams) -> None:
        self.model = get_sensor_model(sensors)
        self.robot = robot
        a = self.model.angles
        self.angles = a
        self.front = np.abs(a) <= np.deg2rad(30)
        self.front_left = (a > np.deg2rad(5)) & (a <= np.deg2rad(60))
        self.front_right = (a < -np.deg2rad(5)) & (a >= -np.deg2rad(60))
        self.left = (a >= np.deg2rad(30)) & (a <= np.deg2rad(120))
        self.right = (a <= -np.deg2rad(30)) & (a >= -np.deg2rad(120))
        # the ray closest to perpendicular on each side, and the diagonal (about 45°) rays
        self.perp_left = int(np.argmin(np.abs(a - np.pi / 2)))
        self.perp_right = int(np.argmin(np.abs(a + np.pi / 2)))
        self.diag_left = (a > np.deg2rad(25)) & (a < np.deg2rad(65))
        self.diag_right = (a < -np.deg2rad(25)) & (a > -np.deg2rad(65))

    def distances(self, ir: np.ndarray) -> np.ndarray:
        m = self.model
        return m.range_min + np.asarray(ir) * (m.range_max - m.range_min)

    def side_distance(self, d: np.ndarray, side: int) -> float:
        """Gap (cm) between the body and a wall on ``side`` (+1 left, -1 right), read by the
        ray closest to perpendicular (diagonal rays would see corners ahead, not the wall)."""
        return float(d[self.perp_left if side > 0 else self.perp_right])

    def diagonal_distance(self, d: np.ndarray, side: int) -> float:
        """Nearest obstacle seen by the diagonal (about 45°) rays on ``side``."""
        mask = self.diag_left if side > 0 else self.diag_right
        return float(d[mask].min()) if mask.any() else math.inf

    def in_range(self, d: np.ndarray, mask: np.ndarray) -> bool:
        return bool(np.any(d[mask] < self.model.range_max - 0.5))


@dataclass(frozen=True)
class WallFollowerParams:
    """SMC09's wall follower: follow one side, switch side with probability ``rho`` per tick."""

    rho: float = 0.008            #: probability of switching side per tick (SMC09: 0, .004, .008)
    target: float = 5.0           #: cm kept between the body and the followed wall
    gain: float = 0.12            #: rad/s per cm of distance error
    front_slow: float = 12.0      #: cm: start turning away from a wall ahead
    front_stop: float = 4.5       #: cm: turn in place
    search_radius: float = 10.0   #: cm: radius of the arc that looks for a lost wall
    speed_min: float = 2.5        #: cm/s: speed drifts between speed_min and speed_max
    speed_max: float = 5.08
    speed_drift: float = 0.15     #: relative sd of the speed random walk per tick

    def __post_init__(self) -> None:
        check_fields(self)
        check_range("rho", self.rho, 0.0, 1.0)
        if not 0 < self.speed_min <= self.speed_max:
            raise ValueError("WallFollowerParams needs 0 < speed_min <= speed_max")


class WallFollower:
    """Follow the left or right wall; switch side at random (SMC09 §III).

    After a switch the new side usually has no wall in range: the robot arcs toward it on a
    circle of ``search_radius`` until it finds one, which draws the ellipse-like loops of SMC09
    Fig. 4. The cruising speed drifts at random between ``speed_min`` and ``speed_max``.
    """

    def __init__(self, params: WallFollowerParams | None = None, *,
                 sensors: str | SensorModel = "ir8", robot: RobotParams | None = None,
                 rng: np.random.Generator | int | None = 0, side: int = -1) -> None:
        self.params = params or WallFollowerParams()
        self.geom = _SensorGeometry(sensors, robot or RobotParams())
        self.rng = np.random.default_rng(rng)
        self.side = check_wall_side("side", side)
        self.speed = self.params.speed_max
        self.switches = 0

    def act(self, obs: Observation) -> tuple[float, float]:
        p, g = self.params, self.geom
        rng = self.rng
        if p.rho > 0 and rng.random() < p.rho:
            self.side = -self.side
            self.switches += 1
        if p.speed_drift > 0:
            # np.clip's value on one float, without an array round trip every tick
            self.speed = min(max(self.speed * (1 + p.speed_drift * rng.standard_normal()),
                                 p.speed_min), p.speed_max)
        d = g.distances(obs.ir)
        side = self.side
        front = float(d[g.front].min()) if g.front.any() else math.inf
        v = self.speed
        if front < p.front_stop:
            return g.robot.wheels_for(0.0, -side * 1.5)
        if front < p.front_slow:
            k = (p.front_slow - front) / (p.front_slow - p.front_stop)
            return g.robot.wheels_for(v * (1 - 0.7 * k), -side * (0.6 + 1.2 * k))
        gap = g.side_distance(d, side)
        if gap < g.model.range_max - 1:
            omega = side * p.gain * (gap - p.target)
            diag = g.diagonal_distance(d, side)
            if diag < 1.6 * p.target:  # a wall closing in ahead on the followed side
                omega -= side * p.gain * (1.6 * p.target - diag)
            omega = max(-1.2, min(1.2, omega))
        else:
            omega = side * v / p.search_radius
        return g.robot.wheels_for(v, omega)


@dataclass(frozen=True)
class AvoidanceParams:
    """Braitenberg-style obstacle avoidance."""

    slow: float = 10.0   #: cm: obstacles closer than this ahead slow the robot and turn it
    stop: float = 1.5    #: cm beyond the sensors' minimum range: boxed in, or no forward motion
    turn_gain: float = 1.6

    def __post_init__(self) -> None:
        check_fields(self)
        if not (self.slow > 0 and self.stop >= 0 and self.turn_gain >= 0):
            raise ValueError(f"AvoidanceParams needs slow > 0, stop >= 0 and turn_gain >= 0, got "
                             f"slow={self.slow!r}, stop={self.stop!r}, "
                             f"turn_gain={self.turn_gain!r}")


class ObstacleAvoidance:
    """Steer away from near obstacles; stop when boxed in (all front rays closer than ``stop``).

    ``modulate(v, omega, obs)`` adjusts a desired motion so that it avoids what the sensors see;
    ``act(obs)`` drives straight at cruising speed with avoidance (a random-ish wander when
    combined with the ``noise`` of the caller).
    """

    def __init__(self, params: AvoidanceParams | None = None, *,
                 sensors: str | SensorModel = "ir8", robot: RobotParams | None = None,
                 speed: float | None = None) -> None:
        self.params = params or AvoidanceParams()
        self.geom = _SensorGeometry(sensors, robot or RobotParams())
        stop_at = self.geom.model.range_min + self.params.stop
        if not self.params.slow > stop_at:  # k's denominator: 0 divides, below 0 turns it off
            raise ValueError(f"AvoidanceParams.slow ({self.params.slow:g} cm) must exceed the "
                             f"sensors' minimum range + stop ({stop_at:g} cm): closer obstacles "
                             f"all read the same")
        self.speed = (check_positive("speed", speed, allow_zero=True) if speed is not None
                      else self.geom.robot.speed_max)
        self._turn = 0.0
        #: the forward-facing rays (within ±100°) that :meth:`boxed_in` reads
        self._forward = np.flatnonzero(np.abs(self.geom.angles) <= np.deg2rad(100)).tolist()

    #: the last observation asked about, its readings and the answer (see boxed_in)
    _asked: tuple = (None, None, False)

    def boxed_in(self, obs: Observation) -> bool:
        """True when every forward-facing ray (within ±100°) reads an obstacle within
        ``range_min + stop`` cm (readings saturate at ``range_min``: closer reads the same).

        Asked twice a tick (the brain's occlusion test, the motor's stop) on 8 numbers: plain
        float arithmetic over the forward rays, the same numbers as the array form; the answer
        is kept for the observation (and readings array) asked about last."""
        asked, readings, answer = self._asked
        if asked is obs and readings is obs.ir:
            return answer
        m = self.geom.model
        lo, span = m.range_min, m.range_max - m.range_min
        limit = lo + self.params.stop
        ir = obs.ir.tolist() if isinstance(obs.ir, np.ndarray) else list(obs.ir)
        answer = all(lo + ir[i] * span <= limit for i in self._forward)
        self._asked = (obs, obs.ir, answer)
        return answer

    def modulate(self, v: float, omega: float, obs: Observation) -> tuple[float, float]:
        """Blend a desired motion with turning away from what is ahead.

        With ``front`` the nearest obstacle ahead, ``k = (slow − front) / (slow − stop_at)``
        (clipped to [0, 1], ``stop_at = range_min + stop``) weighs the avoidance turn against the
        desired one and slows the robot by ``1 − k``. The turn direction is kept while the
        obstacle stays in view, so the robot does not dither between two equal escapes.
        """
        p, g = self.params, self.geom
        if self.boxed_in(obs):
            return 0.0, 0.0
        d = g.distances(obs.ir)
        fl = float(d[g.front_left].min()) if g.front_left.any() else math.inf
        fr = float(d[g.front_right].min()) if g.front_right.any() else math.inf
        front = min(fl, fr, float(d[g.front].min()) if g.front.any() else math.inf)
        stop_at = g.model.range_min + p.stop
        if front < p.slow:
            if self._turn == 0.0:
                self._turn = 1.0 if fl > fr else -1.0
            k = min(1.0, max(0.0, (p.slow - front) / (p.slow - stop_at)))
            omega = (1 - k) * omega + k * self._turn * p.turn_gain
            v = v * (1 - k)
        else:
            self._turn = 0.0
        return v, omega

    def act(self, obs: Observation) -> tuple[float, float]:
        v, omega = self.modulate(self.speed, 0.0, obs)
        return self.geom.robot.wheels_for(v, omega)


class GoToHeading:
    """Turn toward a target heading and drive, with obstacle avoidance.

    ``omega = gain · wrap(target − heading)``; forward speed falls with the heading error
    (``v = speed · max(0, cos err)²``) so the robot turns on the spot for large errors.
    """

    def __init__(self, *, sensors: str | SensorModel = "ir8", robot: RobotParams | None = None,
                 speed: float | None = None, gain: float = 2.0,
                 avoidance: AvoidanceParams | None = None) -> None:
        self.avoid = ObstacleAvoidance(avoidance, sensors=sensors, robot=robot)
        self.robot = self.avoid.geom.robot
        self.speed = (check_positive("speed", speed, allow_zero=True) if speed is not None
                      else self.robot.speed_max)
        self.gain = check_positive("gain", gain, allow_zero=True)

    def act(self, obs: Observation, heading: float, target: float) -> tuple[float, float]:
        """Wheel speeds steering from ``heading`` (an estimate) toward ``target`` (radians)."""
        err = wrap_angle(target - heading)
        v = self.speed * max(0.0, math.cos(err)) ** 2
        omega = max(-2.5, min(2.5, self.gain * err))
        v, omega = self.avoid.modulate(v, omega, obs)
        return self.robot.wheels_for(v, omega)


class WallGuidedHeading:
    """Go along a heading the way the robot explores: by following a wall when that goes the
    right way, by steering to the heading otherwise.

    While a wall is in range on the follower's side and the wall follower's own direction of
    travel (the robot's heading) lies within ``tolerance`` of the target heading, the command is
    the :class:`WallFollower`'s (without side switching), so the robot moves as it did when it
    learned its place cells; otherwise :class:`GoToHeading` turns it toward the target. Place
    cells learned from wall following stay in the regime they were trained in.
    """

    def __init__(self, *, sensors: str | SensorModel = "ir8", robot: RobotParams | None = None,
                 side: int = -1, speed: float | None = None, tolerance: float = 1.2,
                 params: WallFollowerParams | None = None,
                 rng: np.random.Generator | int | None = 0) -> None:
        base = params or WallFollowerParams()
        # the exploring follower's speed statistics, without side switching
        fparams = WallFollowerParams(**{**base.__dict__, "rho": 0.0})
        self.follower = WallFollower(fparams, sensors=sensors, robot=robot, rng=rng, side=side)
        self.steer = GoToHeading(sensors=sensors, robot=robot, speed=speed)
        self.tolerance = check_positive("tolerance", tolerance)

    def act(self, obs: Observation, heading: float, target: float) -> tuple[float, float]:
        g = self.follower.geom
        d = g.distances(obs.ir)
        wall = g.side_distance(d, self.follower.side) < g.model.range_max - 1
        if wall and abs(wrap_angle(target - heading)) < self.tolerance:
            return self.follower.act(obs)
        return self.steer.act(obs, heading, target)


class Stop:
    """Stand still."""

    def act(self, obs: Observation) -> tuple[float, float]:
        return 0.0, 0.0
