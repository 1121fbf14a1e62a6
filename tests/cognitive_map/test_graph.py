"""Transition graph: structure, merging (circular mean), forgetting, positions, GraphML."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import circmean

from hippo.cognitive_map import WAIT, Action, TransitionGraph
from hippo.cognitive_map.graph import NODE_ATTRS
from hippo.cognitive_map.synthetic import random_transition_graph
from hippo.io import CorruptFileError


def structural_edges(g: TransitionGraph) -> set:
    ts = list(g)
    return {(u, v) for u in ts for v in ts if u[1] == v[0]}


def test_new_transition_attributes_and_links():
    g = TransitionGraph()
    g.add_transition(1, 2, (0.5, 20.0), 3.0, time=10.0)
    g.add_transition(2, 3, WAIT, 4.0)
    g.add_transition(0, 1, Action.move(-1.0, 5.0))
    d = g.attributes((1, 2))
    assert d["action"] == "move" and d["heading"] == 0.5 and d["distance"] == 20.0
    assert d["delay"] == 3.0 and d["count"] == 1 and d["last_used"] == 10.0
    assert g.action((2, 3)) == Action.wait() and g.attributes((2, 3))["heading"] is None
    # A->B links to B->C whichever was learned first
    assert set(g.nx.edges) == {((0, 1), (1, 2)), ((1, 2), (2, 3))}
    assert g.states == {0, 1, 2, 3}
    assert g.outgoing(1) == [(1, 2)] and g.incoming(2) == [(1, 2)] and g.outgoing(3) == []
    assert g.successors((1, 2)) == [(2, 3)] and g.predecessors((1, 2)) == [(0, 1)]


def test_edges_follow_the_line_graph_rule_through_adds_and_removals():
    rng = np.random.default_rng(3)
    g = random_transition_graph(12, 50, rng, allow_self=True)
    assert set(g.nx.edges) == structural_edges(g)
    for t in list(g)[:15]:
        g.remove_transition(t)
    assert set(g.nx.edges) == structural_edges(g)
    assert len(g) == 35 and g.states >= {t[0] for t in g}


def test_merge_uses_the_circular_mean_of_headings():
    g = TransitionGraph()
    g.add_transition(0, 1, (math.radians(350), 10.0), 2.0)
    g.add_transition(0, 1, (math.radians(10), 30.0), None)
    g.add_transition(0, 1, (math.radians(0), 20.0), 4.0)
    d = g.attributes((0, 1))
    assert d["heading"] == pytest.approx(0.0, abs=1e-12)  # not 120 degrees (arithmetic mean)
    assert d["heading_r"] == pytest.approx((1 + 2 * math.cos(math.radians(10))) / 3)
    assert d["distance"] == pytest.approx(20.0)
    assert d["delay"] == pytest.approx(3.0) and d["n_delay"] == 2 and d["count"] == 3
    assert g.structure_version == 1 and g.version == 3  # merges change attributes only


def test_a_move_made_both_ways_has_no_direction():
    g = TransitionGraph()
    g.add_transition(0, 1, (math.radians(80), 10.0))
    g.add_transition(0, 1, (math.radians(100), 10.0))
    assert g.direction((0, 1), 0.5) == pytest.approx(math.radians(90))   # r = cos 10 deg
    g.add_transition(0, 1, (math.radians(-90), 10.0))                    # and back: r = 0.32
    assert g.direction((0, 1), 0.5) is None
    assert g.direction((0, 1)) == pytest.approx(math.radians(90))        # no minimum
    g.add_transition(1, 1, "wait")
    assert g.direction((1, 1)) is None


def test_merge_matches_batch_circular_mean_on_random_samples():
    rng = np.random.default_rng(7)
    for _ in range(20):
        mu = rng.uniform(-math.pi, math.pi)
        th = mu + rng.vonmises(0.0, 2.0, size=int(rng.integers(2, 40)))
        dist = rng.uniform(1, 50, size=th.size)
        g = TransitionGraph()
        for h, r in zip(th, dist, strict=True):
            g.add_transition(4, 5, (float(h), float(r)))
        d = g.attributes((4, 5))
        want = math.remainder(circmean(th, high=math.pi, low=-math.pi), 2 * math.pi)
        assert math.remainder(d["heading"] - want, 2 * math.pi) == pytest.approx(0, abs=1e-9)
        assert d["heading_r"] == pytest.approx(np.hypot(np.cos(th).mean(), np.sin(th).mean()))
        assert d["distance"] == pytest.approx(dist.mean())


def test_action_kind_is_the_majority_and_moves_keep_their_mean():
    g = TransitionGraph()
    g.add_transition(1, 2, WAIT)
    g.add_transition(1, 2, (1.0, 4.0))
    assert g.action((1, 2)).kind == "move"  # tie keeps move
    g.add_transition(1, 2, WAIT)
    assert g.action((1, 2)).is_wait
    assert g.attributes((1, 2))["heading"] == 1.0 and g.attributes((1, 2))["n_wait"] == 2


def test_forgetting_remove_and_decay():
    g = TransitionGraph()
    for a, b in [(0, 1), (1, 2), (2, 3)]:
        g.add_transition(a, b, (0.0, 1.0))
    g.remove_transition((1, 2))
    assert (1, 2) not in g and g.n_links == 0 and 1 in g.states and 2 in g.states
    with pytest.raises(KeyError, match="unknown transition 1->2"):
        g.remove_transition((1, 2))
    for _ in range(3):
        assert g.decay(0.5, threshold=0.1) == []
        g.mark_used((0, 1), time=1.0)
    assert g.decay(0.5, threshold=0.1) == [(2, 3)]  # 0.5**4 < 0.1; (0, 1) was used
    assert list(g) == [(0, 1)] and g.attributes((0, 1))["strength"] == 0.5


def test_positions_and_states():
    g = TransitionGraph()
    g.add_state(7, (1.5, -2.0))
    g.add_transition(7, 8, (0.0, 1.0))
    assert g.position(7) == (1.5, -2.0) and g.position(8) is None
    assert g.positions == {7: (1.5, -2.0)} and g.states == {7, 8}
    with pytest.raises(ValueError, match="position of state 8"):
        g.set_position(8, (1.0, float("nan")))
    with pytest.raises(ValueError, match="must be \\(x, y\\)"):
        g.set_position(8, (1.0, 2.0, 3.0))
    with pytest.raises(KeyError, match="unknown state 9"):
        g.position(9)
    assert g.observe_position(8, (2.0, 4.0)) == (2.0, 4.0)
    g.observe_position(8, (4.0, 0.0))
    assert g.observe_position(8, (6.0, 2.0)) == pytest.approx((4.0, 2.0))  # running mean
    assert g.observe_position(7, (3.5, 0.0)) == pytest.approx((2.5, -1.0))  # set counts once


def test_a_position_that_overflows_the_running_mean_is_refused(tmp_path):
    """(1e308 then -1e308: x - mean overflows to -inf, a map to_graphml would write and
    from_graphml refuse.) The position is refused and the state keeps its mean."""
    g = TransitionGraph()
    g.observe_position(0, (1e308, 0.0))
    with pytest.raises(ValueError, match=r"position of state 0: .* would overflow the running"):
        g.observe_position(0, (-1e308, 0.0))
    assert g.position(0) == (1e308, 0.0) and g._pos_n[0] == 1
    assert TransitionGraph.from_graphml(g.to_graphml(tmp_path / "g.graphml")).same_as(g)


def test_structure_version_grows_on_structural_changes_only():
    g = TransitionGraph()
    g.add_transition(0, 1, (0.0, 1.0))
    v = g.structure_version
    g.add_transition(0, 1, (0.1, 1.0))
    g.mark_used((0, 1))
    assert g.structure_version == v
    g.add_transition(1, 0, (0.0, 1.0))
    assert g.structure_version == v + 1
    g.remove_transition((1, 0))
    assert g.structure_version == v + 2


@pytest.mark.parametrize("bad", [1.5, True, "3", None])
def test_bad_state_ids(bad):
    with pytest.raises(ValueError, match="integer state id"):
        TransitionGraph().add_transition(bad, 1, WAIT)


def test_bad_actions_and_delays():
    g = TransitionGraph()
    with pytest.raises(ValueError, match="action"):
        g.add_transition(0, 1, "run")
    with pytest.raises(ValueError, match="heading"):
        g.add_transition(0, 1, (float("nan"), 3.0))
    with pytest.raises(ValueError, match="distance"):
        g.add_transition(0, 1, (0.0, -3.0))
    with pytest.raises(ValueError, match="delay"):
        g.add_transition(0, 1, (0.0, 3.0), -1.0)
    with pytest.raises(ValueError, match="move action needs"):
        Action("move")
    assert len(g) == 0


def test_graphml_round_trip_keeps_every_attribute(tmp_path):
    rng = np.random.default_rng(11)
    g = random_transition_graph(15, 60, rng, allow_self=True)
    g.add_transition(20, 21, WAIT)  # wait, no delay (None), no heading
    g.add_transition(21, 20, (math.pi, 12.5), None, time=3.25)
    g.add_transition(21, 20, (-3.0, 2.5), 1.0 / 3.0)
    g.add_state(99)  # a state without transitions or position
    for s in range(10):
        g.set_position(s, (float(rng.normal()), float(rng.normal()) * 1e-7))
    g.observe_position(12, (1.0, 2.0))
    g.observe_position(12, (2.0, 3.0))
    g.decay(0.9)
    path = g.to_graphml(tmp_path / "map.graphml")
    assert [p.name for p in tmp_path.iterdir()] == ["map.graphml"]  # no temp file left
    h = TransitionGraph.from_graphml(path)
    assert h.same_as(g)
    assert list(h) == list(g) and h.states == g.states
    for t in g:
        a, b = g.attributes(t), h.attributes(t)
        assert set(a) == set(NODE_ATTRS) == set(b)
        for k in NODE_ATTRS:
            assert a[k] == b[k] and type(a[k]) is type(b[k]), (t, k)
    assert h.attributes((20, 21))["delay"] is None and h.action((20, 21)).is_wait
    assert h.position(99) is None and h.positions == g.positions
    assert h.observe_position(12, (4.5, 5.5)) == g.observe_position(12, (4.5, 5.5)) == (2.5, 3.5)


def test_graphml_bad_files(tmp_path):
    with pytest.raises(FileNotFoundError):
        TransitionGraph.from_graphml(tmp_path / "none.graphml")
    bad = tmp_path / "bad.graphml"
    bad.write_text("<graphml><graph>")
    with pytest.raises(CorruptFileError):
        TransitionGraph.from_graphml(bad)
    import networkx as nx
    other = tmp_path / "other.graphml"
    nx.write_graphml(nx.path_graph(3), other)
    with pytest.raises(CorruptFileError, match="not a hippo transition graph"):
        TransitionGraph.from_graphml(other)
    g = TransitionGraph()
    g.add_transition(0, 1, (0.0, 1.0))
    g.add_transition(1, 2, (0.0, 1.0))
    good = g.to_graphml(tmp_path / "g.graphml")
    text = good.read_text()
    assert ">move</data>" in text
    (tmp_path / "g2.graphml").write_text(text.replace(">move</data>", ">fly</data>", 1))
    with pytest.raises(CorruptFileError, match="action must be 'move' or 'wait'"):
        TransitionGraph.from_graphml(tmp_path / "g2.graphml")
    lines = text.splitlines()
    edge = next(i for i, line in enumerate(lines) if "<edge " in line)
    (tmp_path / "g3.graphml").write_text("\n".join(lines[:edge] + lines[edge + 1:]))
    with pytest.raises(CorruptFileError, match="links differ"):
        TransitionGraph.from_graphml(tmp_path / "g3.graphml")

