"""The shared vocabulary: one angle convention, one state-id rule, enums, senses vs truth."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from hippo.sim import World, arenas
from hippo.types import (
    GroundTruth,
    Mode,
    Observation,
    StateKind,
    check_state_id,
    check_transition,
    wrap_angle,
)


def test_wrap_angle_convention_is_half_open_at_minus_pi():
    assert wrap_angle(math.pi) == math.pi
    assert wrap_angle(-math.pi) == math.pi
    assert wrap_angle(3 * math.pi) == math.pi
    assert wrap_angle(0.0) == 0.0
    assert wrap_angle(2 * math.pi) == 0.0
    assert wrap_angle(-math.pi / 2) == pytest.approx(-math.pi / 2)


@given(st.floats(min_value=-1e4, max_value=1e4, allow_nan=False))
def test_wrap_angle_lands_in_range_and_keeps_the_direction(a):
    w = wrap_angle(a)
    assert -math.pi < w <= math.pi
    assert math.cos(w) == pytest.approx(math.cos(a), abs=1e-9)
    assert math.sin(w) == pytest.approx(math.sin(a), abs=1e-9)


def test_one_state_id_rule_everywhere():
    assert check_state_id("s", 3) == 3 and check_state_id("s", np.int64(4)) == 4
    for bad in (True, np.bool_(False), 1.0, "2", None):
        with pytest.raises(ValueError, match="s must be an integer state id"):
            check_state_id("s", bad)
    with pytest.raises(ValueError, match=">= 0"):
        check_state_id("s", -1)
    assert check_state_id("s", 2**63 - 1) == 2**63 - 1  # ids are stored as int64
    for big in (2**63, np.uint64(2**63), 2**70):
        with pytest.raises(ValueError, match=r"s must be a state id <= 2\*\*63 - 1"):
            check_state_id("s", big)
    assert check_transition("t", (1, 2)) == (1, 2)
    with pytest.raises(ValueError, match="pair"):
        check_transition("t", 5)
    # the map and the timing modules apply the same rule
    from hippo.cognitive_map.keys import state_id
    from hippo.timing.spectral import check_state_id as spectral_check

    with pytest.raises(ValueError, match=">= 0"):
        state_id(-2)
    assert spectral_check is check_state_id


def test_enums_keep_the_stored_values():
    assert [int(m) for m in Mode] == [0, 1, 2, 3]
    assert str(Mode.WAIT) == "wait"
    assert StateKind.STILL == "still" and f"{StateKind.PLACE}" == "place"
    assert StateKind("colour").is_context and not StateKind.SOUND.is_context


def test_the_observation_holds_only_senses_and_the_truth_is_apart():
    world = World(arenas.goal_arena(), seed=0)
    obs = world.step((3.0, 3.0))
    assert isinstance(obs, Observation)
    with pytest.raises(AttributeError, match=r"World\.truth"):
        obs.pose  # noqa: B018
    with pytest.raises(AttributeError, match=r"World\.truth"):
        obs.speed  # noqa: B018
    truth = world.truth
    assert isinstance(truth, GroundTruth)
    assert truth.t == obs.t and truth.tick == obs.tick
    assert truth.pose == world.pose and truth.speed > 0
    with pytest.raises(AttributeError):
        obs.t = 1.0  # frozen


def test_named_seed_streams_are_independent_and_reproducible():
    from hippo.seeds import STREAMS, Seeds

    s = Seeds(5)
    a = s.generator("exploration").random(4)
    np.testing.assert_array_equal(a, Seeds(5).generator("exploration").random(4))
    assert not np.allclose(a, s.generator("pauses").random(4))
    assert not np.allclose(a, Seeds(6).generator("exploration").random(4))
    # the keys hippo always used: the named streams are the old numbered ones
    np.testing.assert_array_equal(a, np.random.default_rng([5, STREAMS["exploration"]]).random(4))
    assert len(set(STREAMS.values())) == len(STREAMS)
    with pytest.raises(KeyError, match="unknown random stream"):
        s.generator("teacher")
    with pytest.raises(ValueError, match="seed"):
        Seeds(-1)


def test_seed_sub_streams_are_independent_and_no_scenario_numbers_a_stream_by_hand():
    import re
    from pathlib import Path

    from hippo.seeds import STREAMS, Seeds

    s = Seeds(3)
    a, b = s.generator("sensor-faults", 0).random(4), s.generator("sensor-faults", 1).random(4)
    assert not np.allclose(a, b)
    np.testing.assert_array_equal(a, Seeds(3).generator("sensor-faults", 0).random(4))
    # a sub-stream is the child that spawning the stream makes, never the stream itself
    child = np.random.SeedSequence([3, STREAMS["sensor-faults"]]).spawn(2)[1]
    np.testing.assert_array_equal(b, np.random.default_rng(child).random(4))
    assert not np.allclose(a, s.generator("sensor-faults").random(4))
    for bad in (-1, 1.5, True):
        with pytest.raises(ValueError, match="sub-stream"):
            s.sequence("kidnaps", bad)
    # every stream of a run comes from hippo.seeds: no scenario or task numbers one by hand
    root = Path(__file__).resolve().parents[1] / "hippo"
    hand = [f"{p.relative_to(root)}:{i + 1}" for p in root.rglob("*.py")
            if p.parent.name in ("scenarios", "tasks")
            for i, line in enumerate(p.read_text().splitlines())
            if re.search(r"default_rng\(\[|seed=\[", line)]
    assert hand == []
