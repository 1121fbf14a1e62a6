"""The motor action of a transition: move along a heading for a distance, or wait.

HIREL (Hirel et al., sec. II-C, III-B): a transition learned while the robot moved carries the
heading measured by path integration and the distance travelled; one learned while it stood
still (a checkpoint) carries "wait".
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from hippo._checks import check_finite, check_positive

__all__ = ["MOVE", "WAIT", "Action", "ActionLike", "as_action", "wrap_exact"]

WAIT = "wait"
MOVE = "move"


def wrap_exact(angle: float) -> float:
    """Wrap an angle to (-π, π] by ``math.remainder``: an angle already in range comes back
    unchanged to the bit (the map's stored headings are exact; :func:`hippo.types.wrap_angle`
    rounds in the last bit)."""
    a = math.remainder(angle, 2.0 * math.pi)
    return math.pi if a == -math.pi else a


@dataclass(frozen=True)
class Action:
    """The motor action of a transition: move along ``heading`` (rad) for ``distance`` (cm) or wait.

    Build with :meth:`move` or :meth:`wait`.
    """

    kind: Literal["move", "wait"]
    heading: float | None = None
    distance: float | None = None

    def __post_init__(self) -> None:
        if self.kind not in (MOVE, WAIT):
            raise ValueError(f"action kind must be 'move' or 'wait', got {self.kind!r}")
        if self.kind == MOVE:
            if self.heading is None or self.distance is None:
                raise ValueError("a move action needs both a heading (rad) and a distance (cm)")
            check_finite("heading", self.heading)
            check_positive("distance", self.distance, allow_zero=True)

    @classmethod
    def move(cls, heading: float, distance: float) -> Action:
        """A move along ``heading`` (rad; stored wrapped to (-π, π]) for ``distance`` cm."""
        return cls(MOVE, wrap_exact(float(heading)), float(distance))

    @classmethod
    def wait(cls) -> Action:
        """Stand still (HIREL's checkpoint transitions)."""
        return cls(WAIT)

    @property
    def is_wait(self) -> bool:
        return self.kind == WAIT


ActionLike = Action | Literal["wait"] | tuple[float, float]


def as_action(action: ActionLike) -> Action:
    """``action`` as an :class:`Action`: an Action, ``"wait"`` or ``(heading, distance)``."""
    if isinstance(action, Action):
        return action
    if isinstance(action, str):
        if action == WAIT:
            return Action.wait()
        raise ValueError(f"action must be an Action, 'wait' or (heading, distance), got {action!r}")
    try:
        heading, distance = action
    except (TypeError, ValueError):
        raise ValueError(
            f"action must be an Action, 'wait' or (heading, distance), got {action!r}"
        ) from None
    return Action.move(heading, distance)
