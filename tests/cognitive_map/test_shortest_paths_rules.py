"""The planner's fast form (hippo/cognitive_map/shortest_paths.py) on a four-transition map
worked out by hand: the CSR patterns of the reversed state graph and of the reversed
transition graph (indptr with the super-source's spare row, indices sorted within each row),
the transition behind each state-graph entry, and the multi-source Dijkstra on a small chain
(one start cost per goal node, the smallest; per-edge costs; unreachable nodes at inf).

The map: states 10, 20, 30 (positions 0, 1, 2) and transitions, in the order added,
t0 = 10->20, t1 = 20->30, t2 = 30->10, t3 = 10->30."""

from __future__ import annotations

import math

import numpy as np

from hippo.cognitive_map.graph import TransitionGraph
from hippo.cognitive_map.shortest_paths import (
    _csr_pattern,
    _dijkstra_from_goals,
    _state_order,
    state_pattern,
    transition_pattern,
)


def _map() -> TransitionGraph:
    g = TransitionGraph()
    for a, b in ((10, 20), (20, 30), (30, 10), (10, 30)):
        g.add_transition(a, b, (0.0, 10.0))
    return g


def _same(got: np.ndarray, want: list[int]) -> None:
    assert got.dtype == np.int32
    np.testing.assert_array_equal(got, np.array(want))


def test_a_csr_pattern_sorts_each_row_and_keeps_a_spare_row():
    # entries (2, 0), (0, 1), (2, 1), (1, 2) of a 3 x 3 pattern: rows 0: [1], 1: [2], 2: [0, 1]
    indptr, indices = _csr_pattern(np.array([2, 0, 2, 1]), np.array([1, 1, 0, 2]), 3)
    _same(indices, [1, 2, 0, 1])
    _same(indptr, [0, 1, 2, 4, 4])      # the spare row (the super-source's) is empty
    # rows with no entries, and the last row empty
    indptr, indices = _csr_pattern(np.array([1, 1]), np.array([3, 0]), 4)
    _same(indices, [0, 3])
    _same(indptr, [0, 0, 2, 2, 2, 2])


def test_the_reversed_state_graph_has_an_edge_b_to_a_per_transition():
    g = _map()
    indptr, indices = state_pattern(g)
    # edges b -> a: t0 1->0, t1 2->1, t2 0->2, t3 2->0; rows 0: [2], 1: [0], 2: [0, 1]
    _same(indices, [2, 0, 0, 1])
    _same(indptr, [0, 1, 2, 4, 4])
    # the transition behind each entry, in that order: t2, t0, t3, t1
    np.testing.assert_array_equal(_state_order(g), [2, 0, 3, 1])
    # cached until the structure changes
    assert state_pattern(g)[0] is indptr and _state_order(g) is _state_order(g)
    g.add_transition(20, 10, (0.0, 10.0))           # t4 = 20->10: edge 0 -> 1
    indptr2, indices2 = state_pattern(g)
    _same(indices2, [1, 2, 0, 0, 1])
    _same(indptr2, [0, 2, 3, 5, 5])
    # row 0 holds t4 (from 1) before t2 (from 2): the order is t4, t2, t0, t3, t1
    np.testing.assert_array_equal(_state_order(g), [4, 2, 0, 3, 1])
    # each entry's column is the start of the transition behind it
    np.testing.assert_array_equal(g.index().a_s[_state_order(g)], indices2)


def test_the_reversed_transition_graph_links_each_transition_to_those_before_it():
    g = _map()
    indptr, indices = transition_pattern(g)
    # edge j -> i when i ends where j starts: t1 -> t0 (at 20), t2 -> t1 and t2 -> t3 (at 30),
    # t0 -> t2 and t3 -> t2 (at 10); rows 0: [2], 1: [0], 2: [1, 3], 3: [2]
    _same(indices, [2, 0, 1, 3, 2])
    _same(indptr, [0, 1, 2, 4, 5, 5])
    assert transition_pattern(g)[1] is indices
    g.add_transition(30, 30, "wait")                 # t4 = 30->30: a loop at 30
    indptr2, indices2 = transition_pattern(g)
    # t4 starts at 30: after t1, t3 and itself; ends at 30: before t2 and itself
    _same(indices2, [2, 0, 1, 3, 4, 2, 1, 3, 4])
    _same(indptr2, [0, 1, 2, 5, 6, 9, 9])


def _chain() -> tuple[np.ndarray, np.ndarray]:
    """A chain 0 -> 1 -> 2 of 3 nodes (and the spare row)."""
    return _csr_pattern(np.array([0, 1]), np.array([1, 2]), 3)


def test_dijkstra_from_the_goals_adds_the_edge_costs_to_the_start_cost():
    indptr, indices = _chain()
    kept = indptr.copy()
    got = _dijkstra_from_goals(indptr, indices, 3, 2.0, np.array([0]), np.array([0.5]))
    np.testing.assert_array_equal(got, [0.5, 2.5, 4.5])
    np.testing.assert_array_equal(indptr, kept)           # the cached pattern is not touched
    got = _dijkstra_from_goals(indptr, indices, 3, np.array([1.0, 3.0]), np.array([0]),
                               np.array([0.0]))
    np.testing.assert_array_equal(got, [0.0, 1.0, 4.0])   # per-edge costs


def test_dijkstra_takes_the_cheapest_start_per_goal_and_leaves_the_unreachable_at_inf():
    indptr, indices = _chain()
    # node 1 is a goal twice (3.0 and 0.25) and node 0 once (0.5): node 1 starts at 0.25,
    # cheaper than 0.5 + 2; node 2 is 0.25 + 2
    got = _dijkstra_from_goals(indptr, indices, 3, 2.0, np.array([1, 0, 1]),
                               np.array([3.0, 0.5, 0.25]))
    np.testing.assert_array_equal(got, [0.5, 0.25, 2.25])
    got = _dijkstra_from_goals(indptr, indices, 3, 2.0, np.array([1, 1]), np.array([0.25, 3.0]))
    np.testing.assert_array_equal(got, [math.inf, 0.25, 2.25])
    # a goal reached more cheaply through another goal keeps the cheaper cost
    got = _dijkstra_from_goals(indptr, indices, 3, 0.5, np.array([0, 2]), np.array([0.0, 4.0]))
    np.testing.assert_array_equal(got, [0.0, 0.5, 1.0])
    # a start cost of 0 and a negative one above -1 (the offset keeps every edge > 0)
    got = _dijkstra_from_goals(indptr, indices, 3, 1.0, np.array([2]), np.array([-0.5]))
    np.testing.assert_array_equal(got, [math.inf, math.inf, -0.5])
