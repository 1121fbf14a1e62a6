"""Synthetic maps for tests and benchmarks: random transition graphs and maps from state edges."""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np

from hippo.cognitive_map.actions import WAIT, ActionLike
from hippo.cognitive_map.graph import TransitionGraph
from hippo.types import Transition

__all__ = ["random_transition_graph", "transitions_from_state_edges"]


def random_transition_graph(n_states: int, n_transitions: int, rng: np.random.Generator,
                            *, allow_self: bool = False) -> TransitionGraph:
    """A random map of ``n_transitions`` distinct transitions over ``n_states`` states (for tests).

    Actions are random moves; a few are waits.
    """
    if n_states < 1:
        raise ValueError(f"n_states must be >= 1, got {n_states}")
    max_t = n_states * n_states if allow_self else n_states * (n_states - 1)
    if not 0 <= n_transitions <= max_t:
        raise ValueError(f"n_transitions must lie in [0, {max_t}] for {n_states} states")
    g = TransitionGraph()
    seen: set[Transition] = set()
    while len(seen) < n_transitions:
        a, b = (int(x) for x in rng.integers(0, n_states, size=2))
        if (a == b and not allow_self) or (a, b) in seen:
            continue
        seen.add((a, b))
        act: ActionLike = WAIT if rng.random() < 0.1 else (
            float(rng.uniform(-math.pi, math.pi)), float(rng.uniform(1, 50)))
        g.add_transition(a, b, act, float(rng.uniform(0.5, 10)))
    return g


def transitions_from_state_edges(edges: Iterable[tuple[int, int]], *,
                                 both_ways: bool = True) -> TransitionGraph:
    """A map with one move transition per state edge (and its reverse if ``both_ways``)."""
    g = TransitionGraph()
    for a, b in edges:
        g.add_transition(a, b, (0.0, 1.0))
        if both_ways:
            g.add_transition(b, a, (math.pi, 1.0))
    return g
