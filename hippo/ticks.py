"""The records of one brain tick: :class:`Tick` (what the brain did: what the motor layer acts
on and a log records) and :class:`Perception` (the neural chain's part of it).

Both are frozen dataclasses built once a tick, so their ``__init__`` writes the fields
straight into the instance's dict (a frozen dataclass's own ``__init__`` calls
``object.__setattr__`` once per field).
"""

from __future__ import annotations

from dataclasses import dataclass

from hippo.perception.states import StateEvent
from hippo.timing.chain import TimingStep
from hippo.types import Mode, Transition

__all__ = ["Perception", "Tick"]


@dataclass(frozen=True, eq=False, init=False)
class Perception:
    """The neural chain's part of a tick: the state layer's event and the timing chain's step."""

    event: StateEvent
    timing: TimingStep

    def __init__(self, event: StateEvent, timing: TimingStep) -> None:
        # one a tick: the fields written straight into the instance's dict
        self.__dict__["event"], self.__dict__["timing"] = event, timing


@dataclass(frozen=True, init=False)
class Tick:
    """What the brain did in one tick (what the motor layer acts on and a log records).

    t: time (s); winner: the state the brain is in (None before the first decision);
    event: a sensory event happened (the state layer's winner changed); mode: what the motor
    layer is to do; transition: the transition being executed (None: none); target_heading:
    the heading of the last move (rad; kept while the robot is lost); heading: the path
    integrator's heading estimate; move_since, move_limit: when the current move was chosen
    and how long it may take (s; None unless moving or approaching with a heading); settling:
    the robot was just lifted and explores while its place cells recover; omitted: the
    transitions whose predicted event did not come this tick (non-occurrence); novel: no place
    cell reaches the state layer's ``recruit_threshold`` (HIREL's cue to recruit a new place:
    the robot is somewhere its place cells do not know; prototypes recruit a cell for it when
    their own ``recruit_threshold`` is > 0).
    """

    t: float
    winner: int | None
    event: bool
    mode: Mode
    transition: Transition | None
    target_heading: float | None
    heading: float
    move_since: float
    move_limit: float | None
    settling: bool
    omitted: tuple[Transition, ...]
    novel: bool = False

    def __init__(self, t: float, winner: int | None, event: bool, mode: Mode,
                 transition: Transition | None, target_heading: float | None, heading: float,
                 move_since: float, move_limit: float | None, settling: bool,
                 omitted: tuple[Transition, ...], novel: bool = False) -> None:
        # one a tick: the fields written straight into the instance's dict (a frozen
        # dataclass's own __init__ calls object.__setattr__ once per field)
        d = self.__dict__
        d["t"], d["winner"], d["event"], d["mode"] = t, winner, event, mode
        d["transition"], d["target_heading"], d["heading"] = transition, target_heading, heading
        d["move_since"], d["move_limit"], d["settling"] = move_since, move_limit, settling
        d["omitted"], d["novel"] = omitted, novel
