"""The human's part in HIREL's experiments: a leash, a body blocking the robot, a reward sound.

- :meth:`Teacher.lead` overrides the motors like a leash pulling the robot through waypoints
  (HIREL §III-A: "a leash strapped to an artificial neck"); the robot's own command is ignored
  while it lasts, but the robot keeps sensing and learning.
- :meth:`Teacher.block` places a real obstacle around the robot (a ring of wall just outside
  its body, as a person standing in the way); the robot stops because its obstacle avoidance sees
  it, and the ring is removed after ``duration`` seconds.
- :meth:`Teacher.sound` plays the reward sound (the next observation has ``sound=True``).

Every action is logged in ``world.events`` as ``(t, kind, detail)``. The teacher acts on the
world from outside: ``Teacher(world)`` attaches itself (:meth:`World.attach`) and reads the
world's ground truth; the world does not know it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

from hippo._checks import check_finite, check_positive
from hippo.types import wrap_angle

if TYPE_CHECKING:
    from hippo.sim.world import Obstacle, World


class Teacher:
    """Leash, block and sound, acting on one :class:`~hippo.sim.world.World`."""

    def __init__(self, world: World, lead_speed: float | None = None, tolerance: float = 3.0
                 ) -> None:
        """``lead_speed`` (cm/s, default: the robot's ``speed_max``) and ``tolerance`` (cm: a
        waypoint this near is reached) must be finite and > 0."""
        self.world = world
        self.lead_speed = None if lead_speed is None else check_positive("lead_speed",
                                                                         lead_speed)
        self.tolerance = check_positive("tolerance", tolerance)
        self.reset()
        world.attach(self)

    def reset(self) -> None:
        self._waypoints: list[tuple[float, float]] = []
        self._speed: float | None = None
        self._block: Obstacle | None = None
        self._block_until = 0.0

    # -- state --------------------------------------------------------------------------------
    @property
    def leading(self) -> bool:
        return bool(self._waypoints)

    @property
    def blocking(self) -> bool:
        return self._block is not None

    @property
    def active(self) -> bool:
        return self.leading or self.blocking

    # -- actions ------------------------------------------------------------------------------
    def lead(self, waypoints: Sequence[Sequence[float]], speed: float | None = None) -> None:
        """Pull the robot through ``waypoints`` [(x, y), ...]; ends at the last one."""
        pts = check_finite("waypoints", waypoints)
        if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) == 0:
            raise ValueError(f"waypoints must be a non-empty list of (x, y), got shape {pts.shape}")
        lead_speed = check_positive("lead speed", speed) if speed is not None else None
        self._waypoints = [(float(x), float(y)) for x, y in pts]
        self._speed = lead_speed
        self.world.events.append((self.world.t, "lead_start", f"{len(pts)} waypoints"))

    def stop_leading(self) -> None:
        """Drop the leash."""
        if self._waypoints:
            self._waypoints = []
            self.world.events.append((self.world.t, "lead_end", ""))

    def block(self, duration: float, gap: float = 2.5) -> None:
        """Surround the robot with a real obstacle for ``duration`` seconds, then remove it."""
        check_positive("block duration", duration)
        if self._block is not None:
            self.unblock()
        x, y, _ = self.world.pose
        self._block = self.world.add_ring((x, y), self.world.robot.radius + gap)
        self._block_until = self.world.t + duration
        self.world.events.append((self.world.t, "block_start", f"{duration:.3f}"))

    def unblock(self) -> None:
        """Remove the block now."""
        if self._block is not None:
            self.world.remove_obstacle(self._block)
            self._block = None
            self.world.events.append((self.world.t, "block_end", ""))

    def sound(self) -> None:
        """Play the reward sound."""
        self.world.emit_sound()

    # -- called by World.step (the Intervention protocol) ---------------------------------
    def override(self, left: float, right: float) -> tuple[float, float]:
        """The wheel command while the leash is on (pure pursuit of the next waypoint)."""
        if not self._waypoints:
            return left, right
        w = self.world
        x, y, h = w.pose
        while self._waypoints:
            tx, ty = self._waypoints[0]
            if math.hypot(tx - x, ty - y) > self.tolerance:
                break
            self._waypoints.pop(0)
        if not self._waypoints:
            w.events.append((w.t, "lead_end", ""))
            return 0.0, 0.0
        tx, ty = self._waypoints[0]
        err = wrap_angle(math.atan2(ty - y, tx - x) - h)
        vmax = self._speed or self.lead_speed or w.robot.speed_max
        v = vmax * max(0.0, math.cos(err)) ** 2
        omega = max(-3.0, min(3.0, 3.0 * err))
        return w.robot.wheels_for(v, omega)

    def after_step(self) -> None:
        if self._block is not None and self.world.t >= self._block_until - 1e-9:
            self.unblock()
