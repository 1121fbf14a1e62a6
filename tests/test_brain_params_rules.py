"""The brain's parameters by hand (hippo.brain_params): every checked field on its documented
edge (taken) and one step past it (refused word for word, the field named), the unit-interval
fields at 0 and 1 exactly and at -5e-324 and 1 + 2**-52, the integer fields at their least
value and one below, the habituation's three fields (accepted unchecked before: a
``cycle_visits`` of 0 counted every place entry as a cycle), the type checks before the
ranges, the documented defaults field by field, and the transition cells' latency as one
tick from decision to motion plus ``proprio_ticks - 1`` ticks of debounce."""

from __future__ import annotations

import math
import re
from dataclasses import FrozenInstanceError

import pytest

from hippo.brain_params import BrainParams
from hippo.cognitive_map import PlannerParams
from hippo.perception.states import StateLayerParams
from hippo.timing import NonOccurrenceParams, SpectralParams, TransitionParams

TINY = 5e-324          # the least positive float
ABOVE_ONE = 1 + 2**-52  # the least float above 1


def refused(message: str):
    return pytest.raises(ValueError, match="^" + re.escape(message) + "$")


# float fields that must be > 0: the least positive float is taken, 0 refused
POSITIVE = ["dt", "move_timeout", "default_delay", "stop_timeout", "turn_limit",
            "alias_tolerance"]
# float fields that may be 0: 0 and -0.0 are taken, the least negative float refused
NON_NEGATIVE = ["still_turn", "move_margin", "settle_time", "release_distance",
                "runup_tolerance", "runup_window", "cycle_window", "cycle_explore"]
UNIT = ["coactive", "leave_fraction", "stop_lead", "turn_discount", "forget", "min_heading_r"]


@pytest.mark.parametrize("name", POSITIVE)
def test_positive_fields_take_the_least_float_and_refuse_zero(name):
    assert getattr(BrainParams(**{name: TINY}), name) == TINY
    with refused(f"{name} must be finite and > 0, got 0.0"):
        BrainParams(**{name: 0.0})
    with refused(f"{name} must be finite and > 0, got -1.5"):
        BrainParams(**{name: -1.5})


@pytest.mark.parametrize("name", NON_NEGATIVE)
def test_non_negative_fields_take_zero_and_refuse_the_least_negative_float(name):
    assert getattr(BrainParams(**{name: 0.0}), name) == 0.0
    assert getattr(BrainParams(**{name: -0.0}), name) == 0.0
    with refused(f"{name} must be finite and >= 0, got -5e-324"):
        BrainParams(**{name: -TINY})


@pytest.mark.parametrize("name", UNIT)
def test_unit_interval_fields_take_both_ends_and_refuse_one_step_past(name):
    assert getattr(BrainParams(**{name: 0.0}), name) == 0.0
    assert getattr(BrainParams(**{name: 1.0}), name) == 1.0
    with refused(f"{name} must lie in [0, 1], got -5e-324"):
        BrainParams(**{name: -TINY})
    with refused(f"{name} must lie in [0, 1], got 1.0000000000000002"):
        BrainParams(**{name: ABOVE_ONE})


def test_integer_fields_at_their_least_value_and_one_below():
    assert BrainParams(companions=0).companions == 0
    with refused("companions must be >= 0, got -1"):
        BrainParams(companions=-1)
    assert BrainParams(runup_hops=0).runup_hops == 0
    with refused("runup_hops must be >= 0, got -1"):
        BrainParams(runup_hops=-1)
    assert BrainParams(proprio_ticks=1).proprio_ticks == 1
    with refused("proprio_ticks must be >= 1, got 0"):
        BrainParams(proprio_ticks=0)
    assert BrainParams(heading_sectors=1).heading_sectors == 1
    with refused("heading_sectors must be an integer >= 1, got 0"):
        BrainParams(heading_sectors=0)
    assert BrainParams(cycle_visits=1).cycle_visits == 1
    with refused("cycle_visits must be an integer >= 1, got 0"):
        BrainParams(cycle_visits=0)
    with refused("cycle_visits must be an integer >= 1, got -3"):
        BrainParams(cycle_visits=-3)


def test_the_negative_run_up_stop_disables_and_is_taken():
    # documented: "Negative disables"; no range to check
    assert BrainParams(runup_stop=-1.0).runup_stop == -1.0


@pytest.mark.parametrize("name, value, shown", [
    ("dt", math.nan, "a finite real number, got nan (float)"),
    ("coactive", math.inf, "a finite real number, got inf (float)"),
    ("companions", 2.0, "an integer, got 2.0 (float)"),
    ("cycle_visits", True, "an integer, got True (bool)"),
    ("approach", 1, "a bool, got 1 (int)"),
])
def test_types_are_checked_before_the_ranges(name, value, shown):
    with refused(f"BrainParams.{name} must be {shown}"):
        BrainParams(**{name: value})


def test_the_first_bad_field_in_check_order_is_named():
    with refused("dt must be finite and > 0, got 0.0"):
        BrainParams(dt=0.0, coactive=2.0, companions=-1)
    with refused("companions must be >= 0, got -1"):
        BrainParams(companions=-1, runup_hops=-1)


def test_the_documented_defaults():
    p = BrainParams()
    assert (p.dt, p.still_turn, p.proprio_ticks, p.settle_time, p.relocalise) == (
        0.2, 0.15, 2, 6.0, None)
    assert (p.move_timeout, p.move_margin, p.default_delay, p.approach) == (3.0, 5.0, 5.0, True)
    assert (p.leave_fraction, p.stop_lead, p.turn_limit, p.turn_discount) == (0.8, 0.5, 1.75,
                                                                              0.5)
    assert (p.hold_heading, p.min_heading_r) == (False, 0.5)
    assert (p.cycle_visits, p.cycle_window, p.cycle_explore) == (3, 60.0, 20.0)
    assert (p.coactive, p.aliases, p.alias_tolerance, p.companions) == (0.6, True, 0.5, 3)
    assert (p.runup_tolerance, p.runup_window, p.runup_stop, p.runup_hops) == (5.0, 100.0,
                                                                               10.0, 1)
    assert (p.stop_timeout, p.due_first, p.release_distance, p.forget) == (2.0, False, 60.0,
                                                                           1.0)
    assert (p.infer_reverse, p.own_stops_only, p.heading_sectors) == (False, True, 1)
    assert p.states == StateLayerParams() and p.spectral == SpectralParams()
    assert p.non_occurrence == NonOccurrenceParams()
    assert p.planner == PlannerParams(w=0.9, noise=0.01)
    assert p.transitions == TransitionParams(latency=0.4)
    # turn_limit "about 100°"
    assert math.degrees(p.turn_limit) == pytest.approx(100.0, abs=0.3)
    with pytest.raises(FrozenInstanceError):
        p.dt = 0.1  # type: ignore[misc]


def test_the_latency_is_one_tick_to_motion_and_the_debounce():
    p = BrainParams()
    # one tick from decision to motion + (proprio_ticks - 1) ticks of debounce
    assert p.transitions.latency == pytest.approx(p.dt * (1 + p.proprio_ticks - 1))
    # the nested defaults are built afresh for each instance
    assert BrainParams().transitions is not p.transitions
    assert BrainParams().states is not p.states
