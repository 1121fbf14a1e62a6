"""The per-tick records written by a hand-made ``__init__`` (one dict write per field instead of
a frozen dataclass's ``object.__setattr__`` calls) are the dataclasses they declare: every
field set from its own argument, positionally or by name, defaults kept, frozen, equal and
printed as dataclasses are."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from hippo.brain import Perception, Tick
from hippo.perception.states import StateEvent
from hippo.timing.chain import TimingStep
from hippo.timing.spectral import BatteryState
from hippo.timing.transition_params import TransitionReadout

RECORDS = [TransitionReadout, StateEvent, BatteryState, TimingStep, Perception, Tick]


def _distinct(cls: type) -> list[object]:
    """A distinct value per field (so that a swapped pair shows)."""
    return [object() for _ in dataclasses.fields(cls)]


@pytest.mark.parametrize("cls", RECORDS)
def test_each_field_is_its_own_argument(cls: type):
    names = [f.name for f in dataclasses.fields(cls)]
    vals = _distinct(cls)
    for rec in (cls(*vals), cls(**dict(zip(names, vals)))):
        assert [getattr(rec, n) for n in names] == vals
        assert vars(rec) == dict(zip(names, vals))  # nothing else stored
        with pytest.raises(dataclasses.FrozenInstanceError):
            setattr(rec, names[0], 1)
    new = _distinct(cls)[0]
    assert getattr(dataclasses.replace(cls(*vals), **{names[0]: new}), names[0]) is new


def test_defaults_and_equality_are_the_dataclass_ones():
    assert Tick(1.0, 2, False, None, None, None, 0.0, 0.0, None, False, ()).novel is False
    b = BatteryState(3, 0.4, np.zeros(2), False)
    assert b.previous is None and math.isnan(b.previous_tau) and b.previous_activity is None
    assert "previous_activity" not in repr(b)  # repr=False kept
    r = TransitionReadout((1, 2), 0.1, 0.2, 3.0, 0.5, False)
    assert r == TransitionReadout((1, 2), 0.1, 0.2, 3.0, 0.5, False)
    assert r != TransitionReadout((1, 2), 0.1, 0.2, 3.0, 0.5, True)
    assert repr(r) == ("TransitionReadout(key=(1, 2), prediction=0.1, strength=0.2, "
                       "learned_delay=3.0, elapsed_fraction=0.5, delay_over=False)")
    e = StateEvent(1.0, 2, True, None, 0.8, False)
    assert e == StateEvent(1.0, 2, True, None, 0.8, False) and hash(e) == hash(
        StateEvent(1.0, 2, True, None, 0.8, False))
