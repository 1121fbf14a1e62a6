"""The shared vocabulary's rules by hand (hippo.types): the state-id bounds 0 and 2**63 - 1 as
Python and numpy integers, exactly and one step past, each refusal word for word (also a
transition's element named by its index; a set, a dict or a string of two ids refused: a set
{2, 1} was taken as (1, 2) and a dict as its keys), the angle convention's formula and its open end,
the observation's copy with other readings field by field, its refusals and repr, the kinds'
text and format specs, and the modes' stored integers."""

from __future__ import annotations

import math
import re
from dataclasses import FrozenInstanceError

import numpy as np
import pytest

from hippo.types import (
    MAX_STATE_ID,
    GroundTruth,
    Mode,
    Observation,
    StateKind,
    check_state_id,
    check_transition,
    wrap_angle,
)


def refused(message: str):
    return pytest.raises(ValueError, match="^" + re.escape(message) + "$")


# ---------------------------------------------------------------------------- state ids
def test_the_largest_id_is_that_of_an_int64():
    assert MAX_STATE_ID == 9_223_372_036_854_775_807 == np.iinfo(np.int64).max


@pytest.mark.parametrize("make", [int, np.int64, np.uint64, np.int8])
def test_zero_is_an_id_as_a_python_or_numpy_integer(make):
    got = check_state_id("s", make(0))
    assert got == 0 and type(got) is int


@pytest.mark.parametrize("make", [int, np.int64, np.uint64])
def test_the_largest_id_is_taken_as_a_python_or_numpy_integer(make):
    got = check_state_id("s", make(MAX_STATE_ID))
    assert got == MAX_STATE_ID and type(got) is int


@pytest.mark.parametrize("value", [-1, np.int64(-1), np.int8(-1)])
def test_one_below_zero_is_refused_word_for_word(value):
    with refused(f"s must be a state id >= 0, got {value!r}"):
        check_state_id("s", value)


@pytest.mark.parametrize("value", [2**63, np.uint64(2**63)])
def test_one_past_the_largest_id_is_refused_word_for_word(value):
    with refused(f"s must be a state id <= 2**63 - 1 (ids are stored as int64), got {value!r}"):
        check_state_id("s", value)


@pytest.mark.parametrize("value", [True, False, np.bool_(True), 1.0, np.float64(2.0), "3",
                                   None, (1,)])
def test_bools_floats_and_other_objects_are_no_ids(value):
    with refused(f"state must be an integer state id, got {value!r}"):
        check_state_id("state", value)


def test_a_transition_is_a_pair_of_ids_named_by_their_index():
    got = check_transition("t", [np.int64(4), 0])
    assert got == (4, 0) and type(got) is tuple and all(type(s) is int for s in got)
    with refused("t[0] must be a state id >= 0, got -1"):
        check_transition("t", (-1, 2))
    with refused("t[1] must be a state id >= 0, got -2"):
        check_transition("t", (1, -2))
    with refused("t[1] must be an integer state id, got 2.0"):
        check_transition("t", (1, 2.0))


@pytest.mark.parametrize("value", [5, (1, 2, 3), (1,), None, {2, 1}, frozenset({0, 3}),
                                   {1: "a", 2: "b"}, "12", b"12"])
def test_what_is_no_pair_is_refused_word_for_word(value):
    with refused(f"t must be a pair (a, b) of state ids, got {value!r}"):
        check_transition("t", value)


# ---------------------------------------------------------------------------- angles
@pytest.mark.parametrize("a", [0.1, -0.1, 4.0, 7.0, -15.971951677265368, -15.044193423022731,
                               -13.959073045440489, 100.0])
def test_the_angle_is_the_documented_formula_to_the_last_bit(a):
    # (a + pi) mod 2 pi - pi, the result every module has always used: the same angle written
    # as (a - pi) mod 2 pi - pi is off in the last bits for some of these
    assert wrap_angle(a) == (a + math.pi) % (2 * math.pi) - math.pi


@pytest.mark.parametrize("k", [-5, -3, -1, 1, 3, 5])
def test_every_odd_multiple_of_pi_lands_on_the_closed_end(k):
    assert wrap_angle(k * math.pi) == math.pi


def test_angles_inside_stay_and_whole_turns_come_off():
    assert wrap_angle(3.0) == 3.0 and wrap_angle(-3.0) == -3.0
    assert wrap_angle(0.0) == 0.0
    assert wrap_angle(2 * math.pi + 1.0) == pytest.approx(1.0, abs=1e-15)
    assert wrap_angle(-2 * math.pi - 1.0) == pytest.approx(-1.0, abs=1e-15)


# ---------------------------------------------------------------------------- observations
def _obs() -> Observation:
    return Observation(1.26, 7, np.array([0.5, 1.0]), 2, True, np.array([1.0, 0.0, 0.1]),
                       False)


def test_with_ir_changes_the_readings_and_keeps_every_other_field():
    o = _obs()
    ir = np.array([0.25, 0.75])
    c = o.with_ir(ir)
    assert c.ir is ir and o.ir.tolist() == [0.5, 1.0]
    assert (c.t, c.tick, c.floor, c.sound, c.moving) == (1.26, 7, 2, True, False)
    assert c.odometry is o.odometry


def test_the_pose_and_speed_are_no_senses_word_for_word():
    o = _obs()
    for name in ("pose", "speed"):
        with pytest.raises(AttributeError) as exc:
            getattr(o, name)
        assert str(exc.value) == (
            f"Observation has no {name!r}: it holds only what the robot senses; the ground "
            f"truth is World.truth.{name} (a GroundTruth), for analysis only")
    with pytest.raises(AttributeError) as exc:
        o.heading  # noqa: B018
    assert str(exc.value) == "'Observation' object has no attribute 'heading'"
    assert not hasattr(o, "x")


def test_an_observation_is_frozen_and_prints_its_senses():
    o = _obs()
    with pytest.raises(FrozenInstanceError):
        o.t = 2.0  # type: ignore[misc]
    assert repr(o) == "Observation(t=1.3, floor=2, sound=True, moving=False)"
    assert o != _obs()  # eq=False: compared by identity (arrays have no plain ==)
    truth = GroundTruth(1.0, 5, (1.0, 2.0, 0.5), 3.0)
    assert truth == GroundTruth(1.0, 5, (1.0, 2.0, 0.5), 3.0)


# ---------------------------------------------------------------------------- kinds, modes
def test_kinds_are_their_file_names_in_text_and_format_specs():
    assert [k.value for k in StateKind] == ["place", "colour", "sound", "still", "moving"]
    assert str(StateKind.STILL) == "still" and f"{StateKind.MOVING}" == "moving"
    assert f"{StateKind.PLACE:>7}|" == "  place|"
    assert f"{StateKind.SOUND:^9}|" == "  sound  |"
    assert f"{StateKind.COLOUR:.3}" == "col"
    assert [k for k in StateKind if k.is_context] == [StateKind.PLACE, StateKind.COLOUR]


def test_modes_keep_their_stored_integers_and_lower_case_names():
    assert {m: int(m) for m in Mode} == {Mode.EXPLORE: 0, Mode.MOVE: 1, Mode.APPROACH: 2,
                                         Mode.WAIT: 3}
    assert [str(m) for m in Mode] == ["explore", "move", "approach", "wait"]
    assert Mode(2) is Mode.APPROACH
