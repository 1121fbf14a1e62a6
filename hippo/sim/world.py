"""The simulated world: a pymunk space with the arena's walls, floor zones, obstacles and a robot.

``World.step(action)`` advances one control period ``dt`` (default 0.2 s, the e-puck's
sense-act cycle) in ``substeps`` physics steps and returns an :class:`~hippo.types.Observation`
(what the robot senses, nothing more); ``World.truth`` is the matching
:class:`~hippo.types.GroundTruth` (pose, speed) for analysis, recordings and the teacher. Units
are centimetres, seconds and radians. ``reset(seed)`` rebuilds the pymunk space from scratch
(pymunk keeps contact state; moving the robot back is no reset); ``reset()`` keeps the noise.

Something outside the robot that acts on the world every tick (the teacher of
:mod:`hippo.sim.teacher`) is an :class:`Intervention`: it attaches itself with
:meth:`World.attach`; the world knows only that protocol, not the teacher.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
import pymunk

from hippo._checks import check_finite, check_int, check_positive, check_seed
from hippo.sim.arena import Arena
from hippo.sim.robot import RobotParams, SensorModel, get_sensor_model
from hippo.types import GroundTruth, Observation, wrap_angle

__all__ = ["GroundTruth", "Intervention", "Observation", "Obstacle", "World", "wrap_angle"]

_CAT_ROBOT, _CAT_WALL, _CAT_OBSTACLE = 0b001, 0b010, 0b100
_RAY_FILTER = pymunk.ShapeFilter(mask=_CAT_WALL | _CAT_OBSTACLE)
_ANGLE = pymunk.Body.angle.fget
_SET_VELOCITY = pymunk.Body.velocity.fset
_SET_ANGULAR_VELOCITY = pymunk.Body.angular_velocity.fset
#: the most physics steps one control tick may take (``dt`` x ``speed_max`` in cm, or the
#: ``substeps`` asked for): more would make a tick last seconds (dt=1e7 asked for 5e7)
MAX_SUBSTEPS = 10_000


class Intervention(Protocol):
    """Acts on the world from outside the robot each tick (the teacher's leash and block)."""

    @property
    def active(self) -> bool: ...

    def override(self, left: float, right: float) -> tuple[float, float]: ...

    def after_step(self) -> None: ...

    def reset(self) -> None: ...


@dataclass
class Obstacle:
    """A body added to the world at run time (movable box or the teacher's block)."""

    body: pymunk.Body
    shapes: list[pymunk.Shape] = field(default_factory=list)
    kind: str = "box"


class World:
    """A robot in an arena, simulated with pymunk.

    Parameters
    ----------
    arena : the static geometry (see :mod:`hippo.sim.arenas`).
    robot : body and drive parameters (default: the e-puck of SMC09).
    sensors : ``"ir8"`` (SMC09), ``"ray17"`` (ICANN09) or a :class:`SensorModel`.
    dt : control period in s (>= 1 ns); ``substeps`` physics steps (at least) per period, raised
        automatically so that the robot travels at most about 1 cm per physics step.
    seed : seed of the world's random stream (sensor and odometry noise).
    """

    def __init__(self, arena: Arena, robot: RobotParams | None = None,
                 sensors: str | SensorModel = "ir8", dt: float = 0.2, substeps: int = 5,
                 seed: int | None = 0) -> None:
        if not isinstance(arena, Arena):
            raise ValueError(f"arena must be an Arena (e.g. hippo.sim.arenas.get('two_rooms')), "
                             f"got {arena!r:.80}")
        if robot is not None and not isinstance(robot, RobotParams):
            raise ValueError(f"robot must be RobotParams or None, got {type(robot).__name__}")
        self.arena = arena
        self.robot = robot or RobotParams()
        self.sensors = get_sensor_model(sensors)
        self.dt = check_positive("dt", dt)
        if self.dt < 1e-9:
            raise ValueError(f"dt must be >= 1e-9 s (the clock counts nanoseconds), got {dt!r}")
        check_int("substeps", substeps, lo=1, hi=MAX_SUBSTEPS)
        # at most ~1 cm of travel per physics step, so contacts are resolved before the body
        # sinks into a wall (penetration is about one step's travel; 10x speed needs 11 steps)
        travel = self.robot.speed_max * self.dt / 1.0  # (inf for dt=1e308)
        if travel > MAX_SUBSTEPS:
            raise ValueError(f"dt={dt!r} s needs {travel:.3g} physics substeps per tick at "
                             f"speed_max {self.robot.speed_max:g} cm/s (at most {MAX_SUBSTEPS})"
                             f": dt must be <= {MAX_SUBSTEPS / self.robot.speed_max:g} s")
        self.substeps = max(int(substeps), math.ceil(travel))
        ang = self.sensors.angles
        self._ray_cos, self._ray_sin = np.cos(ang).tolist(), np.sin(ang).tolist()
        self._span = self.sensors.range_max - self.sensors.range_min
        self._interventions: list[Intervention] = []
        #: the last attached intervention (``Teacher(world)`` attaches itself), else None
        self.teacher: Any = None
        self.reset(seed)

    def attach(self, intervention: Intervention) -> None:
        """Let ``intervention`` act on every step (override the wheels, then look after the
        step) and be reset with the world. ``Teacher(world)`` calls this itself."""
        if intervention not in self._interventions:
            self._interventions.append(intervention)
        self.teacher = intervention

    def detach(self, intervention: Intervention) -> None:
        """Stop ``intervention`` acting on the world (the inverse of :meth:`attach`)."""
        if intervention in self._interventions:
            self._interventions.remove(intervention)
        if self.teacher is intervention:
            self.teacher = self._interventions[-1] if self._interventions else None

    # -- snapshots (hippo.snapshot) ----------------------------------------------------------
    def __snapshot_state__(self) -> dict[str, Any]:
        """The world's whole state for :func:`hippo.snapshot.save_snapshot`: the robot body's
        pose and velocities, the random stream, the clock, the event log and the last command.
        Restoring it continues the simulation bit for bit. Obstacles and interventions (the
        teacher) are not stored yet: a world holding them is refused."""
        if self.obstacles or self._interventions:
            raise TypeError("a World with obstacles or an attached teacher cannot be saved in a "
                            "snapshot yet (remove them first)")
        b = self.body
        return {"arena": self.arena, "robot": self.robot, "sensors": self.sensors,
                "dt": self.dt, "substeps": self.substeps, "seed": self.seed, "rng": self.rng,
                "t": self.t, "tick": self.tick, "events": self.events,
                "sound_pending": self._sound_pending, "last_command": self._last_command,
                "v": self._v, "omega": self._omega, "truth": getattr(self, "truth", None),
                "position": tuple(b.position), "angle": b.angle, "velocity": tuple(b.velocity),
                "angular_velocity": b.angular_velocity}

    @classmethod
    def __snapshot_restore__(cls, st: dict[str, Any]) -> World:
        world = cls(st["arena"], st["robot"], st["sensors"], st["dt"], st["substeps"],
                    st["seed"])
        x, y = st["position"]
        world.reset(st["seed"], pose=(x, y, st["angle"]))
        if not isinstance(st["rng"], np.random.Generator):
            raise ValueError("rng must be a numpy Generator")
        world.rng = st["rng"]
        world.t, world.tick = float(st["t"]), int(st["tick"])
        world.events = list(st["events"])
        world._sound_pending = bool(st["sound_pending"])
        world._last_command = tuple(st["last_command"])
        world._v, world._omega = float(st["v"]), float(st["omega"])
        if st["truth"] is not None:
            world.truth = st["truth"]
        b = world.body
        b.position, b.angle = (x, y), st["angle"]
        b.velocity, b.angular_velocity = tuple(st["velocity"]), st["angular_velocity"]
        return world

    # -- construction -----------------------------------------------------------------------
    def reset(self, seed: int | None = None, pose: tuple[float, float, float] | None = None
              ) -> Observation:
        """Rebuild the space, put the robot at ``pose`` (default: the arena's start pose);
        ``seed`` (an integer in [0, 2**63)) seeds the noise again; None goes on with the noise
        stream (Gymnasium's convention: a seeded world stays reproducible across resets)."""
        if seed is not None:
            check_seed("seed", seed)
        x, y, h = self._check_pose(pose if pose is not None else self.arena.start_pose)
        if seed is not None or not hasattr(self, "rng"):
            self.rng, self.seed = np.random.default_rng(seed), seed
        self.space = space = pymunk.Space()
        space.iterations = 10
        for a, b in self.arena.walls:
            seg = pymunk.Segment(space.static_body, a, b, self.arena.wall_radius)
            seg.friction, seg.elasticity = 0.0, 0.0
            seg.filter = pymunk.ShapeFilter(categories=_CAT_WALL)
            space.add(seg)
        r = self.robot
        body = pymunk.Body(r.mass, pymunk.moment_for_circle(r.mass, 0, r.radius))
        shape = pymunk.Circle(body, r.radius)
        shape.friction, shape.elasticity = 0.0, 0.0
        shape.filter = pymunk.ShapeFilter(categories=_CAT_ROBOT)
        self._v, self._omega = 0.0, 0.0

        def drive(b: pymunk.Body, gravity: object, damping: float, dt: float) -> None:
            # the properties' own getter and setters (b.velocity = ... without pymunk's
            # __setattr__ hook): the same calls into chipmunk, run every physics substep
            a = _ANGLE(b)
            _SET_VELOCITY(b, (self._v * math.cos(a), self._v * math.sin(a)))
            _SET_ANGULAR_VELOCITY(b, self._omega)

        body.velocity_func = drive
        self.body, self._shape = body, shape
        body.position, body.angle = (x, y), h
        space.add(body, shape)
        self.obstacles: list[Obstacle] = []
        self.t = 0.0
        self.tick = 0
        self.events: list[tuple[float, str, str]] = []
        self._sound_pending = False
        self._last_command = (0.0, 0.0)
        for iv in self._interventions:
            iv.reset()
        return self._observe(np.zeros(3), 0.0, sound=False)

    def _check_pose(self, pose: Any) -> tuple[float, float, float]:
        """``(x, y, heading)`` checked: finite numbers, the robot free of walls there."""
        try:
            x, y, h = (float(v) for v in pose)
        except (TypeError, ValueError):
            raise ValueError(f"pose must be three numbers (x, y, heading), got {pose!r:.80}"
                             ) from None
        if not math.isfinite(h):
            raise ValueError(f"heading must be finite (radians), got {h!r}")
        self._check_free(x, y)
        return x, y, h

    def _check_free(self, x: float, y: float) -> None:
        if not all(math.isfinite(v) for v in (x, y)):
            raise ValueError(f"robot position must be finite, got ({x}, {y})")
        if not self.arena.is_free(x, y, self.robot.radius):
            raise ValueError(f"cannot place the robot at ({x:.1f}, {y:.1f}) in "
                             f"{self.arena.name!r}: it would overlap a wall or leave the arena")

    # -- the robot's state ------------------------------------------------------------------
    @property
    def pose(self) -> tuple[float, float, float]:
        """Ground-truth (x, y, heading) of the robot."""
        p = self.body.position
        return p.x, p.y, wrap_angle(self.body.angle)

    def place_robot(self, x: float, y: float, heading: float, *, event: str = "kidnap"
                    ) -> None:
        """Move the robot to a pose and keep going (kidnapping); the pose must be free."""
        x, y, heading = self._check_pose((x, y, heading))
        for o in self.obstacles:
            if any(s.point_query((x, y)).distance < self.robot.radius for s in o.shapes):
                raise ValueError(f"cannot place the robot at ({x:.1f}, {y:.1f}): obstacle there")
        self.body.position, self.body.angle = (x, y), heading
        self.body.velocity, self.body.angular_velocity = (0, 0), 0
        self.space.reindex_shapes_for_body(self.body)
        self.events.append((self.t, event, f"{x:.2f},{y:.2f},{heading:.4f}"))

    # -- obstacles --------------------------------------------------------------------------
    def add_box(self, rect: tuple[float, float, float, float], *, movable: bool = True,
                mass: float = 2.0) -> Obstacle:
        """Add a box obstacle ``(x0, y0, x1, y1)``, inside the arena and clear of the robot;
        ``movable`` boxes (``mass`` > 0, in kg) can be pushed (with floor friction)."""
        r = check_finite("box rect", rect).ravel().tolist()
        if len(r) != 4:
            raise ValueError(f"box rect must be (x0, y0, x1, y1), got {rect!r:.80}")
        x0, y0, x1, y1 = r
        w, h = x1 - x0, y1 - y0
        if w <= 0 or h <= 0:
            raise ValueError(f"box {rect} has no area (it needs x0 < x1 and y0 < y1)")
        self._check_inside("box", rect, x0, y0, x1, y1)
        px, py, _ = self.pose
        near = math.hypot(px - min(max(px, x0), x1), py - min(max(py, y0), y1))
        if near < self.robot.radius:
            raise ValueError(f"box {rect} overlaps the robot at ({px:.1f}, {py:.1f}): put it "
                             "elsewhere or move the robot first")
        if movable:
            mass = check_positive("box mass", mass)
            body = pymunk.Body(mass, pymunk.moment_for_box(mass, (w, h)))

            def floor_friction(b: pymunk.Body, g: object, damping: float, dt: float) -> None:
                pymunk.Body.update_velocity(b, (0, 0), 0.05 ** dt, dt)

            body.velocity_func = floor_friction
        else:
            body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        body.position = ((x0 + x1) / 2, (y0 + y1) / 2)
        shape = pymunk.Poly.create_box(body, (w, h))
        return self._add_obstacle(body, [shape], "box")

    def add_ring(self, centre: tuple[float, float], radius: float, *, n: int = 16,
                 kind: str = "block") -> Obstacle:
        """A fixed ring of wall (``n`` >= 3 segments) of ``radius`` > 0 around ``centre``, a
        point of the arena (the teacher's block uses it)."""
        c = check_finite("ring centre", centre).ravel().tolist()
        if len(c) != 2:
            raise ValueError(f"ring centre must be (x, y), got {centre!r:.80}")
        self._check_inside("ring centre", centre, c[0], c[1], c[0], c[1])
        radius = check_positive("ring radius", radius)
        n = check_int("ring segments n", n, lo=3)
        body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        body.position = tuple(c)
        pts = [(radius * math.cos(2 * math.pi * k / n), radius * math.sin(2 * math.pi * k / n))
               for k in range(n)]
        shapes = [pymunk.Segment(body, pts[k], pts[(k + 1) % n], 0.5) for k in range(n)]
        return self._add_obstacle(body, shapes, kind)

    def _check_inside(self, what: str, given: Any, x0: float, y0: float, x1: float,
                      y1: float) -> None:
        a = self.arena
        if x0 < 0 or y0 < 0 or x1 > a.width or y1 > a.height:
            raise ValueError(f"{what} {given!r:.80} lies outside the {a.width:g} x "
                             f"{a.height:g} arena {a.name!r}")

    def _add_obstacle(self, body: pymunk.Body, shapes: list[pymunk.Shape], kind: str
                      ) -> Obstacle:
        for s in shapes:
            s.friction, s.elasticity = 0.0, 0.0
            s.filter = pymunk.ShapeFilter(categories=_CAT_OBSTACLE)
        self.space.add(body, *shapes)
        obst = Obstacle(body, shapes, kind)
        self.obstacles.append(obst)
        return obst

    def remove_obstacle(self, obstacle: Obstacle) -> None:
        """Take an obstacle out of the world."""
        if obstacle not in self.obstacles:
            raise ValueError("this obstacle is not in the world")
        self.space.remove(obstacle.body, *obstacle.shapes)
        self.obstacles.remove(obstacle)

    # -- sensing ----------------------------------------------------------------------------
    def ray_distances(self) -> np.ndarray:
        """Noise-free free length (cm) of each sensor ray from the body's rim, capped at range."""
        p = self.body.position
        a = self.body.angle
        ca, sa = math.cos(a), math.sin(a)
        r = self.robot.radius
        rmax = self.sensors.range_max
        query = self.space.segment_query_first
        out = []
        for c, s in zip(self._ray_cos, self._ray_sin):
            dx, dy = c * ca - s * sa, s * ca + c * sa
            sx, sy = p.x + r * dx, p.y + r * dy
            hit = query((sx, sy), (sx + rmax * dx, sy + rmax * dy), 0.0, _RAY_FILTER)
            out.append(hit.alpha * rmax if hit is not None else rmax)
        return np.array(out)

    def sense(self) -> np.ndarray:
        """Sensor readings in [0, 1] with Gaussian noise (0 = touching, 1 = nothing in range)."""
        d = self.ray_distances()
        u = (d - self.sensors.range_min) / self._span
        if self.sensors.noise_sd > 0:
            u = u + self.rng.normal(0.0, self.sensors.noise_sd, u.shape)
        return np.clip(u, 0.0, 1.0)

    def emit_sound(self) -> None:
        """Play the reward sound: the next observation has ``sound=True``."""
        self._sound_pending = True
        self.events.append((self.t, "sound", ""))

    # -- dynamics ---------------------------------------------------------------------------
    def step(self, action: tuple[float, float] | np.ndarray) -> Observation:
        """Apply wheel speeds ``(left, right)`` in cm/s for one control period."""
        try:
            if len(action) != 2 or isinstance(action, str | bytes):
                raise ValueError
            left, right = float(action[0]), float(action[1])
        except (TypeError, IndexError, ValueError, KeyError):
            raise ValueError(f"action must be a pair of wheel speeds (left, right) in cm/s, "
                             f"got {action!r}") from None
        if not (math.isfinite(left) and math.isfinite(right)):
            raise ValueError(f"wheel commands must be finite, got ({left}, {right})")
        for iv in self._interventions:
            if iv.active:
                left, right = iv.override(left, right)
        left, right = self.robot.limit_wheels(left, right)
        self._last_command = (left, right)
        self._v, self._omega = self.robot.body_velocity(left, right)
        x0, y0, h0 = self.pose
        # chipmunk integrates positions before velocities: seed the first substep's velocity
        # (velocity_func then imposes it again at every substep, after contacts are solved)
        a = _ANGLE(self.body)
        _SET_VELOCITY(self.body, (self._v * math.cos(a), self._v * math.sin(a)))
        _SET_ANGULAR_VELOCITY(self.body, self._omega)
        h = self.dt / self.substeps
        for _ in range(self.substeps):
            self.space.step(h)
        self.t = round(self.t + self.dt, 9)
        self.tick += 1
        x1, y1, h1 = self.pose
        ddx, ddy = x1 - x0, y1 - y0
        c, s = math.cos(h0), math.sin(h0)
        odo = np.array([c * ddx + s * ddy, -s * ddx + c * ddy, wrap_angle(h1 - h0)])
        speed = math.hypot(ddx, ddy) / self.dt
        if self.robot.odometry_noise > 0:
            odo *= 1.0 + self.rng.normal(0.0, self.robot.odometry_noise, 3)
        sound, self._sound_pending = self._sound_pending, False
        for iv in self._interventions:
            if iv.active:
                iv.after_step()
        # an intervention may have moved the robot after the step: then read the pose again
        return self._observe(odo, speed, sound, None if self._interventions else (x1, y1, h1))

    def observe(self) -> Observation:
        """Sense without moving: the observation of a robot standing where it is (no odometry,
        not moving, no sound). Draws sensor noise like a step does; updates :attr:`truth`."""
        return self._observe(np.zeros(3), 0.0, False)

    def _observe(self, odo: np.ndarray, speed: float, sound: bool,
                 pose: tuple[float, float, float] | None = None) -> Observation:
        x, y, h = self.pose if pose is None else pose
        self.truth = GroundTruth(self.t, self.tick, (x, y, h), speed)
        return Observation(self.t, self.tick, self.sense(), self.arena.zone_of(x, y), sound, odo,
                           speed > self.robot.moving_threshold)
