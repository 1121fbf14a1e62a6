"""The e-puck: a circular differential-drive body with ray-cast distance sensors.

Kinematics (differential drive, axle ``L``)::

    v = (v_left + v_right) / 2        ω = (v_right - v_left) / L

The wheel velocities are imposed inside the body's pymunk ``velocity_func`` at every physics
substep, so the contact solver still corrects them: the robot slides along walls and never
passes through them (setting ``body.velocity`` once before ``space.step`` lets a fast body tunnel).

Distance sensors (SMC09 §III; ICANN09 §3) are rays cast from the body's rim. The reading of a
ray whose free length from the rim is ``d`` is ``clip((d - d_min) / (d_max - d_min) + n, 0, 1)``
with ``n ~ N(0, noise_sd²)``: 0 means touching (≤ ``d_min``), 1 means nothing within ``d_max``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hippo._checks import check_fields


@dataclass(frozen=True)
class SensorModel:
    """Ray-cast distance sensors: angles (degrees, CCW from the heading), range and noise."""

    name: str
    angles_deg: tuple[float, ...]
    range_min: float = 4.0
    range_max: float = 30.0
    noise_sd: float = 0.02

    def __post_init__(self) -> None:
        check_fields(self)
        if not 0 <= self.range_min < self.range_max:
            raise ValueError(f"sensor range must satisfy 0 <= min < max, got "
                             f"[{self.range_min}, {self.range_max}]")
        if self.noise_sd < 0:
            raise ValueError("sensor noise_sd must be >= 0")
        if not self.angles_deg:
            raise ValueError("a sensor model needs at least one ray")

    @property
    def n(self) -> int:
        return len(self.angles_deg)

    @property
    def angles(self) -> np.ndarray:
        return np.deg2rad(np.asarray(self.angles_deg, float))


#: The e-puck of SMC09: 8 IR sensors ps0..ps7 (clockwise from front-right), 4–30 cm.
IR8 = SensorModel("ir8", (-17.0, -46.0, -90.0, -152.0, 152.0, 90.0, 46.0, 17.0), 4.0, 30.0, 0.02)
#: ICANN09's robot: 17 rays uniformly over -90..+90 degrees, longer range, noise N(0, 0.01).
RAY17 = SensorModel("ray17", tuple(np.linspace(-90.0, 90.0, 17).round(6).tolist()), 4.0, 50.0,
                    0.01)

SENSOR_MODELS = {"ir8": IR8, "ray17": RAY17}


def get_sensor_model(name: str | SensorModel) -> SensorModel:
    """Look up ``"ir8"`` / ``"ray17"`` (or pass a :class:`SensorModel` through)."""
    if isinstance(name, SensorModel):
        return name
    if not isinstance(name, str):
        raise ValueError(f"sensors must be a sensor model name ({', '.join(SENSOR_MODELS)}) or "
                         f"a SensorModel, got {name!r}")
    try:
        return SENSOR_MODELS[name]
    except KeyError:
        raise ValueError(f"unknown sensor model {name!r}; choose from "
                         f"{', '.join(SENSOR_MODELS)}") from None


#: the fastest wheel speed a robot may have, cm/s (200 times the e-puck's): the world takes
#: one physics step per cm of travel, so a speed_max of 1e9 would take hours per tick
MAX_SPEED = 1000.0


@dataclass(frozen=True)
class RobotParams:
    """Body, drive and proprioception of the robot (defaults: the e-puck of SMC09)."""

    radius: float = 3.7            #: cm
    axle: float = 5.3              #: cm between the wheels
    mass: float = 0.15             #: kg (only ratios matter to the solver)
    speed_min: float = 0.198       #: cm/s; a smaller non-zero wheel command stalls to 0
    speed_max: float = 5.08        #: cm/s; wheel commands are clipped to ±speed_max
    odometry_noise: float = 0.0    #: relative sd of the odometry per tick (0 = exact)
    moving_threshold: float = 0.3  #: cm/s of translation above which the robot "is moving"

    def __post_init__(self) -> None:
        check_fields(self)
        for name in ("radius", "axle", "mass", "speed_max"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0):
                raise ValueError(f"RobotParams.{name} must be > 0, got {v}")
        if self.speed_max > MAX_SPEED:
            raise ValueError(f"RobotParams.speed_max must be <= {MAX_SPEED:g} cm/s, got "
                             f"{self.speed_max!r} (the e-puck's is 5.08)")
        if not 0 <= self.speed_min < self.speed_max:
            raise ValueError("RobotParams needs 0 <= speed_min < speed_max")
        if self.odometry_noise < 0 or self.moving_threshold < 0:
            raise ValueError("RobotParams.odometry_noise and moving_threshold must be >= 0")

    def limit_wheels(self, left: float, right: float) -> tuple[float, float]:
        """Clip wheel speeds to ±speed_max and stall magnitudes below speed_min to 0."""
        out = []
        for w in (left, right):
            if not math.isfinite(w):
                raise ValueError(f"wheel command must be finite, got {w}")
            a = min(abs(w), self.speed_max)
            out.append(0.0 if a < self.speed_min else math.copysign(a, w))
        return out[0], out[1]

    def body_velocity(self, left: float, right: float) -> tuple[float, float]:
        """Forward speed ``v`` (cm/s) and turn rate ``ω`` (rad/s) of a wheel command."""
        return 0.5 * (left + right), (right - left) / self.axle

    def wheels_for(self, v: float, omega: float) -> tuple[float, float]:
        """Wheel speeds for forward speed ``v`` and turn rate ``omega``, within ±speed_max.

        Turning has priority: the turn is capped first, then ``v`` is reduced so that neither
        wheel exceeds ``speed_max``.
        """
        half = max(-self.speed_max, min(self.speed_max, 0.5 * omega * self.axle))
        room = self.speed_max - abs(half)
        v = max(-room, min(room, v))
        return v - half, v + half
