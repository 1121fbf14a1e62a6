"""Path integration of odometry: the robot's own estimate of its pose (never a place-cell input).

Each tick's odometry is ``(dx, dy, dθ)`` with ``(dx, dy)`` in the robot frame at the start of
the tick. Integration: ``x += cos θ dx − sin θ dy``, ``y += sin θ dx + cos θ dy``, ``θ += dθ``.
"""

from __future__ import annotations

import math

import numpy as np

from hippo._checks import check_finite
from hippo.types import wrap_angle


def _three(name: str, value: object, what: str) -> np.ndarray:
    """``value`` as 3 finite floats, or a ``ValueError`` naming ``name`` and ``what`` they are."""
    arr = check_finite(name, value)
    if arr.shape != (3,):
        raise ValueError(f"{name} must be 3 numbers {what}, got shape {arr.shape}")
    return arr


class PathIntegrator:
    """Dead reckoning from odometry, starting at ``pose`` (default: origin, heading 0)."""

    def __init__(self, pose: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> None:
        self.reset(pose)

    def reset(self, pose: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> None:
        """Start again at ``pose`` = ``(x, y, heading)``: three finite numbers."""
        self.x, self.y, self.heading = (float(v) for v in _three("pose", pose, "(x, y, heading)"))

    @property
    def pose(self) -> tuple[float, float, float]:
        return self.x, self.y, self.heading

    def step(self, odometry: np.ndarray) -> tuple[float, float, float]:
        """Integrate one tick of odometry and return the new pose estimate."""
        return self.advance(*_three("odometry", odometry, "(dx, dy, dtheta)"))

    def advance(self, dx: float, dy: float, dth: float) -> tuple[float, float, float]:
        """:meth:`step` on odometry already checked finite (the brain's tick: the agent checks
        each observation whole)."""
        c, s = math.cos(self.heading), math.sin(self.heading)
        self.x += c * dx - s * dy
        self.y += s * dx + c * dy
        self.heading = wrap_angle(self.heading + dth)
        return self.pose
