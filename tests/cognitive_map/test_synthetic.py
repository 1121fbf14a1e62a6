"""Synthetic maps for tests and benchmarks: their size limits and their edges."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hippo.cognitive_map.synthetic import random_transition_graph, transitions_from_state_edges


def test_random_transition_graph_sizes_and_their_limits():
    rng = np.random.default_rng(0)
    assert len(random_transition_graph(3, 0, rng).transitions) == 0
    full = random_transition_graph(3, 6, rng)  # every ordered pair of distinct states
    assert set(full.transitions) == {(a, b) for a in range(3) for b in range(3) if a != b}
    assert len(random_transition_graph(1, 1, rng, allow_self=True).transitions) == 1
    with pytest.raises(ValueError, match=r"n_transitions must lie in \[0, 6\] for 3 states"):
        random_transition_graph(3, 7, rng)
    with pytest.raises(ValueError, match=r"n_transitions must lie in \[0, 9\]"):
        random_transition_graph(3, -1, rng, allow_self=True)
    with pytest.raises(ValueError, match="n_states must be >= 1"):
        random_transition_graph(0, 0, rng)


def test_state_edges_become_a_move_there_and_a_turned_move_back():
    g = transitions_from_state_edges([(1, 2)])
    assert set(g.transitions) == {(1, 2), (2, 1)}
    there, back = g.action((1, 2)), g.action((2, 1))
    assert back.distance == there.distance and back.heading == there.heading + math.pi
    assert transitions_from_state_edges([(1, 2)], both_ways=False).transitions == [(1, 2)]
