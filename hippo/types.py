"""The shared vocabulary of hippo: what every package means by a state, a transition, a mode.

- :data:`StateId` and :func:`check_state_id` — a state is an integer id >= 0 (one rule
  everywhere: the state layer, the timing batteries, the transition cells, the map).
- :data:`Transition` — ``(a, b)``: the state left and the state entered.
- :class:`StateKind` — what a state stands for: a place, a floor colour, the sound, a stop
  (``still``) or a resumption (``moving``).
- :class:`Mode` — what the motor layer is doing: explore, move, approach a stop, wait.
- :func:`wrap_angle` — every angle difference, one convention: (-π, π].
- :class:`Observation` — what the robot senses in one tick (the only input of the brain);
  :class:`GroundTruth` — where the robot really is, for analysis, recording and the teacher.

Nothing here imports another hippo module, so every package can import it.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Mapping, Set
from dataclasses import dataclass
from enum import Enum, IntEnum
from typing import Any

import numpy as np

__all__ = [
    "MAX_STATE_ID", "GroundTruth", "Mode", "Observation", "StateId", "StateKind", "Transition",
    "check_state_id", "check_transition", "wrap_angle",
]

StateId = int
"""A state of the state layer: an integer >= 0, in the order the states were recruited."""

Transition = tuple[int, int]
"""A transition key ``(a, b)``: the id of the state left and of the state entered."""


MAX_STATE_ID = 2**63 - 1
"""The largest state id: ids are stored as int64 (index arrays, GraphML files)."""


def check_state_id(name: str, state: object) -> int:
    """Return ``state`` as an ``int`` state id, or raise ``ValueError`` naming ``name``.

    A state id is an integer in [0, :data:`MAX_STATE_ID`] (Python or numpy integer; ``bool``
    and floats are refused, even when integral, so that a mask or a mean never passes for an
    id; a larger one would overflow the int64 arrays the ids are kept in).
    """
    if type(state) is int and 0 <= state <= MAX_STATE_ID:  # the usual case (every tick)
        return state
    if isinstance(state, bool | np.bool_):
        raise ValueError(f"{name} must be an integer state id, got {state!r}")
    try:
        s = operator.index(state)  # type: ignore[arg-type]
    except TypeError:
        raise ValueError(f"{name} must be an integer state id, got {state!r}") from None
    if s < 0:
        raise ValueError(f"{name} must be a state id >= 0, got {state!r}")
    if s > MAX_STATE_ID:
        raise ValueError(f"{name} must be a state id <= 2**63 - 1 (ids are stored as int64), "
                         f"got {state!r}")
    return int(s)


def check_transition(name: str, value: Any) -> Transition:
    """Return ``value`` as an ``(a, b)`` tuple of state ids, or raise ``ValueError``.

    A set or a mapping is no pair even with two ids (a set has no order: ``{2, 1}`` unpacks
    as ``1, 2``; a dict unpacks its keys), nor is a string.
    """
    if isinstance(value, str | bytes | Set | Mapping):
        raise ValueError(f"{name} must be a pair (a, b) of state ids, got {value!r}")
    try:
        a, b = value
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a pair (a, b) of state ids, got {value!r}") from None
    return check_state_id(f"{name}[0]", a), check_state_id(f"{name}[1]", b)


class StateKind(str, Enum):
    """What a state of the state layer stands for (its value is the name used in files)."""

    PLACE = "place"      #: a place cell won
    COLOUR = "colour"    #: the floor colour under the robot
    SOUND = "sound"      #: the reward sound
    STILL = "still"      #: the robot stopped (bound to the place it stopped in)
    MOVING = "moving"    #: the robot moved on after a stop (bound to that place)

    def __str__(self) -> str:
        return self.value

    def __format__(self, spec: str) -> str:
        return format(self.value, spec)

    @property
    def is_context(self) -> bool:
        """Can a state of this kind be the context of a stop (a place or a floor colour)?"""
        return self in (StateKind.PLACE, StateKind.COLOUR)


class Mode(IntEnum):
    """What the motor layer does this tick; the integer is what ``run.npz`` stores."""

    EXPLORE = 0    #: wall following (SMC09), no transition chosen
    MOVE = 1       #: along the heading of the chosen transition
    APPROACH = 2   #: keep going until the learned time-to-stop is over, then stop
    WAIT = 3       #: stand still until the wait is over (learned delay or non-occurrence)

    def __str__(self) -> str:
        return self.name.lower()


def wrap_angle(a: float) -> float:
    """Wrap an angle (rad) to (-π, π]: ``wrap_angle(π) == π``, ``wrap_angle(-π) == π``.

    Computed as ``(a + π) mod 2π − π`` (the floating-point result every module has always
    used), with the one value that formula gives at the open end, -π, mapped to π.
    """
    r = (a + math.pi) % (2 * math.pi) - math.pi
    return math.pi if r == -math.pi else r


@dataclass(frozen=True, slots=True, eq=False)
class Observation:
    """What the robot senses after one tick — and nothing else.

    t: time (s); tick: tick counter; ir: distance-sensor readings in [0, 1]; floor: colour id
    under the robot (0 = plain); sound: the reward sound was played this tick; odometry: (dx,
    dy) in the robot frame at the start of the tick and dθ (cm, rad); moving: proprioception
    (the robot translated this tick).

    Where the robot really is (pose, speed) is not a sense: it is in :class:`GroundTruth`
    (``World.truth``), which only analysis, recordings and the teacher read.
    """

    t: float
    tick: int
    ir: np.ndarray
    floor: int
    sound: bool
    odometry: np.ndarray
    moving: bool

    def with_ir(self, ir: np.ndarray) -> Observation:
        """The same observation with other sensor readings (e.g. the last clear view)."""
        return Observation(self.t, self.tick, ir, self.floor, self.sound, self.odometry,
                           self.moving)

    def __getattr__(self, name: str) -> Any:
        if name in ("pose", "speed"):
            raise AttributeError(
                f"Observation has no {name!r}: it holds only what the robot senses; the "
                f"ground truth is World.truth.{name} (a GroundTruth), for analysis only")
        raise AttributeError(f"'Observation' object has no attribute {name!r}")

    def __repr__(self) -> str:
        return (f"Observation(t={self.t:.1f}, floor={self.floor}, sound={self.sound}, "
                f"moving={self.moving})")


@dataclass(frozen=True, slots=True)
class GroundTruth:
    """Where the robot really is after a tick: for analysis, recording and the teacher only.

    pose: (x, y, heading) in cm and rad (heading in (-π, π]); speed: translation speed over the
    tick (cm/s).
    """

    t: float
    tick: int
    pose: tuple[float, float, float]
    speed: float
