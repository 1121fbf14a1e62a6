"""Planner: propagation against an independent computation, gradient following, exploration."""

from __future__ import annotations

import itertools
import math

import networkx as nx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hippo.cognitive_map import (
    DriveParams,
    Drives,
    Planner,
    PlannerParams,
    TransitionGraph,
    drive_input,
    propagate,
    propagate_reference,
)
from hippo.cognitive_map.synthetic import random_transition_graph, transitions_from_state_edges

METHODS = ("states", "transitions")


def independent_activity(g: TransitionGraph, inputs: dict, w: float) -> dict:
    """max over goals g of I(g) * w**hops(n -> g), hops by networkx BFS on the transition graph."""
    rev = g.nx.reverse(copy=True)
    out = dict.fromkeys(g, 0.0)
    for goal, v in inputs.items():
        if v <= 0:
            continue
        for n, h in nx.single_source_shortest_path_length(rev, goal).items():
            out[n] = max(out[n], v * w**h)
    return out


def check_against_independent(g, inputs, w):
    want = independent_activity(g, inputs, w)
    ref = propagate_reference(g, inputs, w)
    for t in g:
        assert ref[t] == pytest.approx(want[t], rel=1e-12, abs=0), t
    for method in METHODS:
        act = propagate(g, inputs, w, method=method)
        got = act.as_dict()
        for t in g:
            assert got[t] == pytest.approx(want[t], rel=1e-9, abs=0), (method, t)
            if want[t] == 0:
                assert got[t] == 0.0  # unreachable transitions get exactly 0
        assert act.values.max(initial=0) <= max(inputs.values(), default=0) + 1e-15


def test_propagation_equals_independent_computation_on_seeded_random_graphs():
    rng = np.random.default_rng(2024)
    for trial in range(25):
        n_states = int(rng.integers(2, 25))
        max_t = n_states * n_states
        g = random_transition_graph(n_states, int(rng.integers(1, min(max_t, 80) + 1)), rng,
                                    allow_self=True)
        nodes = list(g)
        k = int(rng.integers(1, min(4, len(nodes)) + 1))
        goals = [nodes[i] for i in rng.choice(len(nodes), size=k, replace=False)]
        inputs = {t: float(rng.uniform(0.01, 1.0)) for t in goals}
        if trial % 5 == 0:
            inputs[goals[0]] = 1.0  # zero start cost
        check_against_independent(g, inputs, float(rng.uniform(0.05, 0.99)))


@settings(max_examples=40, deadline=None)
@given(
    edges=st.lists(st.tuples(st.integers(0, 9), st.integers(0, 9)), min_size=1, max_size=40,
                   unique=True),
    data=st.data(),
    w=st.floats(0.01, 0.99),
)
def test_propagation_equals_independent_computation_hypothesis(edges, data, w):
    g = TransitionGraph()
    for a, b in edges:
        g.add_transition(a, b, (0.0, 1.0))
    goals = data.draw(st.lists(st.sampled_from(edges), min_size=1, max_size=4, unique=True))
    levels = data.draw(st.lists(st.floats(1e-6, 1.0), min_size=len(goals), max_size=len(goals)))
    check_against_independent(g, dict(zip(goals, levels, strict=True)), w)


def test_propagation_from_drives_never_exceeds_the_drive_level():
    rng = np.random.default_rng(5)
    g = random_transition_graph(30, 120, rng)
    d = Drives({"a": DriveParams(learning_rate=1.0), "b": DriveParams(learning_rate=1.0)})
    nodes = list(g)
    d.link("a", nodes[3])
    d.link("b", nodes[40])
    d.link("b", nodes[41])
    d.set_level("a", 0.7)
    d.set_level("b", 0.4)
    inp = drive_input(g, d)
    assert inp.max() == pytest.approx(0.7) and np.count_nonzero(inp) == 3
    for method in METHODS:
        act = propagate(g, d, 0.95, method=method)
        assert act.values.max() <= 0.7 + 1e-15
        assert act[nodes[3]] == pytest.approx(0.7)
    ref = propagate_reference(g, d, 0.95)
    assert max(ref.values()) == pytest.approx(0.7)


def corridor(n: int) -> TransitionGraph:
    return transitions_from_state_edges((i, i + 1) for i in range(n - 1))


def one_goal(goal, level=1.0, name="goal") -> Drives:
    d = Drives({name: DriveParams(learning_rate=1.0)})
    d.link(name, goal)
    d.set_level(name, level)
    return d


@pytest.mark.parametrize("method", METHODS)
def test_corridor_choices_reach_the_goal_by_the_shortest_path(method):
    n = 12
    g = corridor(n)
    d = one_goal((n - 2, n - 1))
    planner = Planner(PlannerParams(w=0.9, noise=0.02, method=method))
    rng = np.random.default_rng(0)
    s, steps = 0, []
    while not steps or steps[-1] != (n - 2, n - 1):
        t = planner.choose(g, d, s, rng)
        steps.append(t)
        s = t[1]
        assert len(steps) <= n
    assert steps == [(i, i + 1) for i in range(n - 1)]
    assert planner.plan(g, d, 0) == steps


def grid(n: int) -> tuple[TransitionGraph, nx.Graph]:
    sg = nx.grid_2d_graph(n, n)
    ids = {p: i for i, p in enumerate(sorted(sg))}
    g = TransitionGraph()
    for (i, j), k in ids.items():
        g.add_state(k, (20.0 * j, 20.0 * i))
    for u, v in sg.edges:
        g.add_transition(ids[u], ids[v], (0.0, 20.0))
        g.add_transition(ids[v], ids[u], (math.pi, 20.0))
    return g, nx.relabel_nodes(sg, ids)


def test_grid_plans_are_shortest_paths_in_hops():
    g, sg = grid(7)
    goal = (24, 31)
    d = one_goal(goal, 0.8)
    planner = Planner(PlannerParams(w=0.85, noise=0.01))
    rng = np.random.default_rng(1)
    for start in range(49):
        path = planner.plan(g, d, start)
        if start == goal[0]:
            assert path == [goal]
            continue
        want = nx.shortest_path_length(sg, start, goal[0]) + 1
        assert len(path) == want, start
        assert path[-1] == goal and path[0][0] == start
        assert all(p[1] == q[0] for p, q in itertools.pairwise(path))
        # noisy choices follow the same number of hops (noise << 1 - w)
        s, n_hops = start, 0
        while True:
            t = planner.choose(g, d, s, rng)
            n_hops += 1
            if t == goal:
                break
            s = t[1]
        assert n_hops == want


def test_two_goals_choice_follows_drive_times_w_power_hops():
    n, w = 15, 0.8
    g = corridor(n)
    d = Drives({"left": DriveParams(learning_rate=1.0), "right": DriveParams(learning_rate=1.0)})
    left, right = (1, 0), (n - 2, n - 1)
    d.link("left", left)
    d.link("right", right)
    planner = Planner(PlannerParams(w=w, noise=0.0))
    for lv, rv in [(0.9, 0.3), (0.3, 0.9), (0.6, 0.6), (1.0, 0.1)]:
        d.set_level("left", lv)
        d.set_level("right", rv)
        n_left_wins = 0
        for s in range(1, n - 1):
            score_left = lv * w ** (s - 1)  # hops after the first step (s -> s-1 ... -> 0)
            score_right = rv * w ** (n - 2 - s)
            t = planner.choose(g, d, s, np.random.default_rng(0))
            if not math.isclose(score_left, score_right, rel_tol=1e-9):
                assert t == ((s, s - 1) if score_left > score_right else (s, s + 1)), (lv, rv, s)
            act = planner.activity(g, d)
            assert act[(s, s - 1)] == pytest.approx(max(score_left, rv * w ** (n - 2 - s + 2)))
            n_left_wins += t == (s, s - 1)
        assert 0 < n_left_wins < n - 2  # the weaker drive wins where it is close enough


def test_no_active_drive_explores_uniformly():
    g = TransitionGraph()
    for b in range(1, 5):
        g.add_transition(0, b, (b * 1.0, 10.0))
    d = one_goal((0, 2), level=0.04)  # below the default exploration threshold 0.05
    planner = Planner(PlannerParams(noise=0.0))
    rng = np.random.default_rng(123)
    picks = [planner.decide(g, d, 0, rng) for _ in range(4000)]
    assert all(c.explored for c in picks)
    counts = np.array([sum(c.transition == (0, b) for c in picks) for b in range(1, 5)])
    expected = 1000.0
    chi2 = float(((counts - expected) ** 2 / expected).sum())
    assert chi2 < 16.27, counts  # chi-square, 3 dof, p = 0.001
    assert planner.n_propagations == 0  # no drive active: no propagation needed
    d.set_level("goal", 0.5)  # now active: always the goal transition
    assert {planner.choose(g, d, 0, rng) for _ in range(200)} == {(0, 2)}


def test_drive_not_reaching_the_state_explores():
    g = transitions_from_state_edges([(0, 1), (2, 3)], both_ways=False)
    g.add_transition(0, 5, (0.0, 1.0))
    d = one_goal((2, 3))
    c = Planner().decide(g, d, 0, np.random.default_rng(0))
    assert c.explored and c.transition in {(0, 1), (0, 5)}
    assert Planner().plan(g, d, 0) == []


def test_ties_are_broken_at_random_and_noise_is_seeded():
    g = TransitionGraph()
    for b in (1, 2):
        g.add_transition(0, b, (0.0, 1.0))
        g.add_transition(b, 3, (0.0, 1.0))
    d = one_goal((3, 3), 1.0)
    g.add_transition(3, 3, "wait")
    planner = Planner(PlannerParams(noise=0.0))
    picks = {planner.choose(g, d, 0, np.random.default_rng(i)) for i in range(40)}
    assert picks == {(0, 1), (0, 2)}
    noisy = Planner(PlannerParams(noise=0.5))
    a = [noisy.choose(g, d, 0, np.random.default_rng(9)) for _ in range(5)]
    b = [noisy.choose(g, d, 0, np.random.default_rng(9)) for _ in range(5)]
    assert a == b


def test_propagation_is_cached_until_something_relevant_changes():
    g = corridor(6)
    d = one_goal((4, 5), 0.5)
    planner = Planner(PlannerParams(replan_tolerance=0.01))
    rng = np.random.default_rng(0)
    for _ in range(10):
        planner.choose(g, d, 0, rng)
    assert planner.n_propagations == 1
    d.set_level("goal", 0.505)  # within tolerance
    planner.choose(g, d, 0, rng)
    assert planner.n_propagations == 1
    d.set_level("goal", 0.6)
    planner.choose(g, d, 0, rng)
    assert planner.n_propagations == 2
    g.add_transition(0, 5, (0.0, 1.0))  # a shortcut: structure changed
    assert planner.choose(g, d, 0, rng) == (0, 5)  # 0->5->4->5: 0.6 w^2 > 0.6 w^4
    assert planner.n_propagations == 3
    d.link("goal", (1, 2))
    assert planner.activity(g, d)[(1, 2)] == pytest.approx(0.6)  # learning rate 1
    assert planner.n_propagations == 4
    g.remove_transition((1, 2))
    assert (1, 2) not in planner.activity(g, d).as_dict()


def test_wait_transition_wins_when_its_drive_is_strong():
    # HIREL's patrol: at a checkpoint the wait transition competes with the move onwards.
    g = corridor(5)
    g.add_transition(2, 2, "wait")
    d = Drives({"checkpoint": DriveParams(learning_rate=1.0), "end": DriveParams(learning_rate=1)})
    d.link("checkpoint", (2, 2))
    d.link("end", (3, 4))
    d.set_level("checkpoint", 0.8)
    d.set_level("end", 0.5)
    p = Planner(PlannerParams(noise=0.0))
    assert p.choose(g, d, 2, np.random.default_rng(0)) == (2, 2)
    assert g.action(p.choose(g, d, 2, np.random.default_rng(0))).is_wait
    d.step(0.2, inhibited={"checkpoint"})  # non-occurrence: the wait loses
    assert p.choose(g, d, 2, np.random.default_rng(0)) == (2, 3)


def test_bad_input():
    for w in (0.0, 1.0, 1.5, -0.1, float("nan")):
        with pytest.raises(ValueError, match=r"propagation weight w|PlannerParams\.w must"):
            PlannerParams(w=w)
    with pytest.raises(ValueError, match="noise"):
        PlannerParams(noise=-0.1)
    with pytest.raises(ValueError, match="method"):
        PlannerParams(method="bfs")
    g = corridor(4)
    d = one_goal((2, 3))
    with pytest.raises(ValueError, match="propagation weight w"):
        propagate(g, d, 1.0)
    with pytest.raises(ValueError, match="propagation weight w"):
        propagate_reference(g, d, 0.0)
    with pytest.raises(ValueError, match=r"drive inputs must lie in \[0, 1\]"):
        propagate(g, {(0, 1): 1.5}, 0.9)
    with pytest.raises(KeyError, match="unknown transition 7->8"):
        propagate(g, {(7, 8): 0.5}, 0.9)
    planner = Planner()
    with pytest.raises(KeyError, match="unknown state 42"):
        planner.choose(g, d, 42, np.random.default_rng(0))
    with pytest.raises(ValueError, match="integer state id"):
        planner.choose(g, d, 1.5, np.random.default_rng(0))
    with pytest.raises(TypeError, match="Generator"):
        planner.choose(g, d, 0, 123)
    with pytest.raises(KeyError, match="unknown transition"):
        planner.activity(g, d)[(9, 9)]
    g.add_state(10)
    assert planner.choose(g, d, 10, np.random.default_rng(0)) is None  # known, no way out


def test_empty_graph_and_no_goals():
    g = TransitionGraph()
    act = propagate(g, {}, 0.9)
    assert len(act) == 0
    g = corridor(3)
    for method in METHODS:
        assert not propagate(g, Drives(["x"]), 0.9, method=method).values.any()


def test_agent_flow_learn_by_exploring_then_go_to_the_rewarded_place():
    """The agent's loop: explore (random walk) -> add transitions -> reward links the drive ->
    the drive builds up -> choices follow the map to the goal by a shortest path."""
    world = grid(5)[1]  # the true corridors between places (ids 0..24, 12 = centre)
    rng = np.random.default_rng(4)
    g = TransitionGraph()
    drives = Drives({"food": DriveParams(epsilon=0.5, learning_rate=1.0)})
    planner = Planner(PlannerParams(w=0.9, noise=0.01))
    food_place, s, last = 12, 0, None
    g.add_state(s)
    for _ in range(3000):  # exploration: the drive is satisfied at each visit, so stays low
        nxt = int(rng.choice(list(world[s])))
        last = g.add_transition(s, nxt, (0.0, 20.0), 1.0)
        s = nxt
        if s == food_place:
            drives.reward("food", last)
        drives.step(0.01)
    assert len(g) == 2 * world.number_of_edges()  # every corridor learned both ways
    goals = set(drives.links("food"))
    assert goals == {(x, food_place) for x in world[food_place]}
    for _ in range(100):
        drives.step(0.2)
    assert drives.level("food") > 0.99
    for start in (0, 4, 20, 24, 7):
        s, hops = start, 0
        while True:
            t = planner.choose(g, drives, s, rng)
            hops += 1
            s = t[1]
            if s == food_place:
                break
        assert hops == nx.shortest_path_length(world, start, food_place)
    drives.step(0.2, inhibited={"food"})  # non-occurrence: back to exploration
    assert planner.decide(g, drives, 0, rng).explored
