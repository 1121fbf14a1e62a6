"""The records of a brain tick by hand (hippo.ticks): every field of a Tick and a Perception
holds what it was given (each a different value, so that no two fields can be swapped
unseen), novel defaults to False, both are frozen, a Tick compares by value and a Perception
by identity, and a Tick built by position equals the same one built by keyword."""

from __future__ import annotations

from dataclasses import FrozenInstanceError, fields

import pytest

from hippo.perception.state_params import StateEvent
from hippo.ticks import Perception, Tick
from hippo.timing.chain import TimingStep
from hippo.types import Mode

VALUES = dict(t=1.5, winner=3, event=True, mode=Mode.APPROACH, transition=(3, 4),
              target_heading=0.25, heading=-0.5, move_since=1.25, move_limit=7.0,
              settling=False, omitted=((1, 2), (2, 5)), novel=True)


def test_every_field_of_a_tick_holds_what_it_was_given():
    tick = Tick(*VALUES.values())
    assert [f.name for f in fields(Tick)] == list(VALUES)
    assert {name: getattr(tick, name) for name in VALUES} == VALUES
    assert tick == Tick(**VALUES)


def test_novel_defaults_to_false():
    rest = {k: v for k, v in VALUES.items() if k != "novel"}
    tick = Tick(**rest)
    assert tick.novel is False
    assert tick != Tick(**VALUES)
    assert tick == Tick(**rest, novel=False)


def test_a_tick_is_frozen_and_compared_by_value():
    tick = Tick(**VALUES)
    with pytest.raises(FrozenInstanceError):
        tick.mode = Mode.WAIT  # type: ignore[misc]
    for name, other in (("winner", 4), ("heading", 0.5), ("omitted", ())):
        assert tick != Tick(**{**VALUES, name: other})


def _event() -> StateEvent:
    return StateEvent(2.0, 5, True, 4, 2.0, False)


def test_a_perception_holds_its_event_and_timing_step():
    event, step = _event(), TimingStep(None, {}, [(1, 2)])  # type: ignore[arg-type]
    p = Perception(event, step)
    assert p.event is event and p.timing is step
    assert [f.name for f in fields(Perception)] == ["event", "timing"]
    with pytest.raises(FrozenInstanceError):
        p.event = _event()  # type: ignore[misc]
    # eq=False: two perceptions of the same objects are still two records
    assert p != Perception(event, step) and p == p
