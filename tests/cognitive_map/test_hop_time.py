"""The planner's time discount (``PlannerParams.hop_time``): a transition of learned delay
``δ`` passes on ``w^(δ / hop_time)``, so the activity falls with the time a way takes."""

from __future__ import annotations

import math

import networkx as nx
import numpy as np
import pytest

from hippo.cognitive_map import (
    DriveParams,
    Drives,
    Planner,
    PlannerParams,
    TransitionGraph,
    propagate,
    propagate_reference,
)
from hippo.cognitive_map.inputs import MIN_HOPS, hop_counts
from hippo.cognitive_map.synthetic import random_transition_graph

METHODS = ("states", "transitions")


def chain(delays: list[float | None]) -> TransitionGraph:
    """0 -> 1 -> ... -> n, transition i with delay ``delays[i]`` (None: never measured)."""
    g = TransitionGraph()
    for i, d in enumerate(delays):
        g.add_transition(i, i + 1, (0.0, 10.0), d)
    return g


def timed_activity(g: TransitionGraph, inputs: dict, w: float, hop_time: float) -> dict:
    """Independent answer: max over goals of I(g) · w^(sum of the hop counts of the transitions
    from n up to, not including, g), by Dijkstra on networkx with those costs."""
    counts = dict(zip(g.index().nodes, hop_counts(g, hop_time).tolist(), strict=True))
    rev = nx.DiGraph()
    rev.add_nodes_from(g)
    # the edge n -> s of the transition graph costs n's hops (n passes on w^hops(n) · act(s))
    rev.add_weighted_edges_from((s, n, counts[n]) for n, s in g.nx.edges)
    out = dict.fromkeys(g, 0.0)
    for goal, v in inputs.items():
        for n, h in nx.single_source_dijkstra_path_length(rev, goal).items():
            out[n] = max(out[n], v * w**h)
    return out


def test_a_chain_discounts_by_the_sum_of_its_delays():
    g = chain([4.0, 10.0, 2.0])
    inputs = {(2, 3): 0.8}
    for method in METHODS:
        act = propagate(g, inputs, 0.9, method=method, hop_time=5.0)
        assert act[(2, 3)] == pytest.approx(0.8)
        assert act[(1, 2)] == pytest.approx(0.8 * 0.9 ** (10.0 / 5.0))
        assert act[(0, 1)] == pytest.approx(0.8 * 0.9 ** ((4.0 + 10.0) / 5.0))
        # per hop (HIREL) the delays do not count
        hops = propagate(g, inputs, 0.9, method=method)
        assert hops[(0, 1)] == pytest.approx(0.8 * 0.9**2)
    ref = propagate_reference(g, inputs, 0.9, hop_time=5.0)
    assert ref[(0, 1)] == pytest.approx(0.8 * 0.9 ** (14.0 / 5.0))


def test_unmeasured_delays_count_one_hop_and_short_ones_at_least_min_hops():
    g = chain([None, 0.0, 1e-9, 7.5])
    assert hop_counts(g, 5.0).tolist() == [1.0, MIN_HOPS, MIN_HOPS, 1.5]
    act = propagate(g, {(3, 4): 1.0}, 0.5, hop_time=5.0)
    # a zero delay is still an edge: the activity flows through it (w^MIN_HOPS, not 0)
    assert act[(1, 2)] == pytest.approx(0.5 ** (2 * MIN_HOPS))
    assert act[(0, 1)] == pytest.approx(0.5 ** (1 + 2 * MIN_HOPS))


def test_a_quick_long_way_beats_a_slow_short_one_only_by_time():
    # from state 0 to the goal (9, 10): 0 -> 9 (one hop, 60 s: a wait on the way) or
    # 0 -> 1 -> 2 -> 9 (three hops of 3 s)
    g = TransitionGraph()
    g.add_transition(0, 9, (0.0, 10.0), 60.0)
    for a, b in ((0, 1), (1, 2), (2, 9)):
        g.add_transition(a, b, (1.0, 10.0), 3.0)
    g.add_transition(9, 10, "wait", 20.0)
    d = Drives({"goal": DriveParams(learning_rate=1.0)})
    d.set_level("goal", 0.9)
    d.link("goal", (9, 10))
    rng = np.random.default_rng(0)
    hops = Planner(PlannerParams(noise=0.0))
    timed = Planner(PlannerParams(noise=0.0, hop_time=5.0))
    assert hops.choose(g, d, 0, rng) == (0, 9)      # 0.9 · w^1 > 0.9 · w^3
    assert timed.choose(g, d, 0, rng) == (0, 1)     # w^(9/5) > w^(60/5)
    assert timed.plan(g, d, 0) == [(0, 1), (1, 2), (2, 9), (9, 10)]


@pytest.mark.parametrize("seed", range(12))
def test_fast_forms_equal_the_reference_and_the_independent_answer(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(3, 20))
    g = random_transition_graph(n, int(rng.integers(2, min(n * n, 60) + 1)), rng,
                                allow_self=True)
    for t in list(g):   # measured delays on most transitions, none on some, 0 on a few
        u = rng.uniform()
        if u < 0.8:
            a, b = t
            g.add_transition(a, b, g.action(t), 0.0 if u < 0.05 else float(rng.uniform(0, 30)))
    nodes = list(g)
    goals = [nodes[i] for i in rng.choice(len(nodes), size=min(3, len(nodes)), replace=False)]
    inputs = {t: float(rng.uniform(0.05, 1.0)) for t in goals}
    w, hop_time = float(rng.uniform(0.3, 0.99)), float(rng.uniform(0.5, 10.0))
    want = timed_activity(g, inputs, w, hop_time)
    ref = propagate_reference(g, inputs, w, hop_time=hop_time)
    for method in METHODS:
        got = propagate(g, inputs, w, method=method, hop_time=hop_time).as_dict()
        for t in g:
            assert got[t] == pytest.approx(want[t], rel=1e-9, abs=1e-300), (method, t)
            assert ref[t] == pytest.approx(want[t], rel=1e-12, abs=1e-300), t


def test_a_new_delay_replans_with_a_hop_time_and_not_without():
    g = chain([5.0, 5.0])
    d = Drives({"goal": DriveParams(learning_rate=1.0)})
    d.set_level("goal", 0.5)
    d.link("goal", (1, 2))
    timed, hops = Planner(PlannerParams(hop_time=5.0)), Planner(PlannerParams())
    assert timed.activity(g, d)[(0, 1)] == pytest.approx(0.5 * 0.9)
    hops.activity(g, d)
    g.add_transition(0, 1, (0.0, 10.0), 15.0)   # a repeat: the mean delay becomes 10 s
    assert g.delay((0, 1)) == pytest.approx(10.0)
    assert timed.activity(g, d)[(0, 1)] == pytest.approx(0.5 * 0.9**2)
    assert timed.n_propagations == 2
    hops.activity(g, d)
    assert hops.n_propagations == 1   # the structure did not change: per hop, nothing to redo


def test_the_refusal_names_the_hop_time_word_for_word():
    for bad in (0.0, -1.0):
        for call in (lambda b: propagate(chain([1.0]), {(0, 1): 1.0}, hop_time=b),
                     lambda b: propagate_reference(chain([1.0]), {(0, 1): 1.0}, hop_time=b)):
            with pytest.raises(ValueError) as e:
                call(bad)
            assert str(e.value) == f"hop_time must be finite and > 0, got {bad}"


@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf, "5", True])
def test_impossible_hop_times_are_refused(bad):
    with pytest.raises((ValueError, TypeError), match="hop_time"):
        PlannerParams(hop_time=bad)
    with pytest.raises((ValueError, TypeError), match="hop_time"):
        propagate(chain([1.0]), {(0, 1): 1.0}, hop_time=bad)
    with pytest.raises((ValueError, TypeError), match="hop_time"):
        propagate_reference(chain([1.0]), {(0, 1): 1.0}, hop_time=bad)


def test_hop_counts_are_kept_until_the_map_changes():
    g = chain([5.0, 10.0])
    first = hop_counts(g, 5.0)
    assert first.tolist() == [1.0, 2.0] and not first.flags.writeable
    assert hop_counts(g, 5.0) is first                   # nothing changed: the same counts
    assert hop_counts(g, 2.5).tolist() == [2.0, 4.0]     # another hop time: counted again
    g.add_transition(1, 2, (0.0, 10.0), 20.0)            # a repeat: the mean delay is 15 s
    assert hop_counts(g, 5.0).tolist() == [1.0, 3.0]
    g.add_transition(2, 3, "wait", None)                 # a new transition, never timed
    assert hop_counts(g, 5.0).tolist() == [1.0, 3.0, 1.0]
