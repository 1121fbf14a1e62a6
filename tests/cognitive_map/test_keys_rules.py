"""The map's keys (hippo/cognitive_map/keys.py): a state id is an integer >= 0 (Python or
numpy, no bool, no float) and a transition a pair of them; each refusal names what was wrong,
word for word."""

from __future__ import annotations

import re

import numpy as np
import pytest

from hippo.cognitive_map.keys import as_transition, state_id


def refused(message: str):
    return pytest.raises(ValueError, match="^" + re.escape(message) + "$")


def test_a_state_id_is_an_integer_at_least_0_and_comes_back_as_an_int():
    for v in (0, 7, np.int64(7), np.uint8(7), 2**63 - 1):
        got = state_id(v)
        assert got == v and type(got) is int
    # the default name is "state"; a caller's name replaces it
    with refused("state must be a state id >= 0, got -1"):
        state_id(-1)
    with refused("goal must be a state id >= 0, got -1"):
        state_id(-1, "goal")
    for bad in (True, np.bool_(False), 1.0, "1", None):
        with refused(f"state must be an integer state id, got {bad!r}"):
            state_id(bad)
    with refused("state must be a state id <= 2**63 - 1 (ids are stored as int64), "
                 "got 9223372036854775808"):
        state_id(2**63)


def test_a_transition_is_a_pair_of_state_ids_named_by_its_end():
    for t in ((0, 1), [3, 3], np.array([2, 5]), (np.int32(4), 9)):
        got = as_transition(t)
        assert got == (int(t[0]), int(t[1])) and type(got) is tuple
        assert all(type(s) is int for s in got)
    for bad in (5, None, (1,), (1, 2, 3), [], 1.5, {2, 1}, frozenset({0, 3}), {1: 0, 2: 0},
                "12", b"12"):
        with refused(f"a transition is a pair (a, b) of state ids, got {bad!r}"):
            as_transition(bad)
    with refused("transition start state must be a state id >= 0, got -1"):
        as_transition((-1, 2))
    with refused("transition end state must be a state id >= 0, got -2"):
        as_transition((1, -2))
    with refused("transition start state must be an integer state id, got 1.0"):
        as_transition((1.0, 2))
    with refused("transition end state must be an integer state id, got True"):
        as_transition((1, True))
    # a pair of a str subclass is still refused up front (not through its characters)
    with refused("a transition is a pair (a, b) of state ids, got 'ab'"):
        as_transition(type("Text", (str,), {})("ab"))
