"""Inferred reverse moves: the graph infers ``B->A`` from ``A->B``, experience confirms it, the
planner takes it only when it saves enough known steps, and GraphML keeps the flag."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from hippo.cognitive_map import (
    Action,
    Planner,
    PlannerParams,
    TransitionGraph,
    propagate,
    propagate_reference,
)
from hippo.cognitive_map.inputs import inferred_mask
from hippo.io import CorruptFileError


def test_infer_reverse_turns_the_heading_round_and_keeps_the_distance():
    g = TransitionGraph()
    g.add_transition(0, 1, (0.25, 30.0), 4.0)
    assert g.infer_reverse((0, 1), time=7.0) == (1, 0)
    assert g.inferred((1, 0)) and not g.inferred((0, 1))
    a = g.attributes((1, 0))
    assert a["heading"] == pytest.approx(0.25 - math.pi) and a["distance"] == 30.0
    assert a["delay"] is None and a["count"] == 1 and a["last_used"] == 7.0
    assert (0, 1) in g.successors((1, 0)) and (1, 0) in g.successors((0, 1))
    # nothing to infer: the way back is known, a wait, a self-loop
    assert g.infer_reverse((0, 1)) is None and g.infer_reverse((1, 0)) is None
    g.add_transition(1, 2, "wait")
    g.add_transition(2, 2, (1.0, 3.0))
    assert g.infer_reverse((1, 2)) is None and g.infer_reverse((2, 2)) is None
    assert len(g) == 4
    with pytest.raises(KeyError, match="unknown transition"):
        g.infer_reverse((5, 6))


def test_the_first_real_move_replaces_the_guess():
    g = TransitionGraph()
    g.add_transition(0, 1, (0.0, 30.0))
    g.infer_reverse((0, 1))
    g.add_transition(1, 0, (3.0, 20.0), 6.0)        # the robot made it: its own measurement
    a = g.attributes((1, 0))
    assert not g.inferred((1, 0))
    assert a["count"] == 1 and a["heading"] == 3.0 and a["distance"] == 20.0
    assert a["delay"] == 6.0 and a["heading_r"] == 1.0
    g.add_transition(1, 0, (3.0, 22.0))
    assert g.count((1, 0)) == 2 and g.attributes((1, 0))["distance"] == pytest.approx(21.0)


def test_a_real_wait_replaces_the_guess_and_keeps_no_heading(tmp_path):
    g = TransitionGraph()
    g.add_transition(0, 1, (1.0, 30.0))
    g.infer_reverse((0, 1))
    g.add_transition(1, 0, "wait", 3.0)  # the robot waited there: no way back was made
    a = g.attributes((1, 0))
    assert a["action"] == "wait" and a["count"] == 1 and a["delay"] == 3.0
    assert a["heading"] is None and a["heading_r"] is None and a["distance"] is None
    assert TransitionGraph.from_graphml(g.to_graphml(tmp_path / "g.graphml")).same_as(g)


def test_graphml_keeps_inferred_moves_and_refuses_bad_ones(tmp_path):
    g = TransitionGraph()
    g.add_transition(0, 1, (0.5, 10.0), 2.0)
    g.infer_reverse((0, 1))
    h = TransitionGraph.from_graphml(g.to_graphml(tmp_path / "g.graphml"))
    assert h.same_as(g) and h.inferred((1, 0)) and not h.inferred((0, 1))
    text = (tmp_path / "g.graphml").read_text()
    key = re.search(r'<key id="(d\d+)" for="node" attr.name="inferred"', text).group(1)
    # 0 -> 1 has a delay: marked inferred, it is refused
    bad = text.replace(f'<data key="{key}">False</data>', f'<data key="{key}">True</data>', 1)
    assert bad != text
    (tmp_path / "b.graphml").write_text(bad)
    with pytest.raises(CorruptFileError, match="inferred transition is one move"):
        TransitionGraph.from_graphml(tmp_path / "b.graphml")


def _ring_with_a_stop(n: int = 6) -> TransitionGraph:
    """States 0..n-1 in a one-way ring (heading 0 for every move), a stop at state 1 (the
    wait 1 -> 99), and the inferred way back of 1 -> 2."""
    g = TransitionGraph()
    for s in range(n):
        g.add_transition(s, (s + 1) % n, (0.0, 20.0))
    g.add_transition(1, 99, "wait")
    g.infer_reverse((1, 2))
    return g


@pytest.mark.parametrize("method", ["states", "transitions"])
def test_only_the_inferred_way_back_gives_the_short_route(method):
    # from state 2 the known route to the stop is 2-3-4-5-0-1 (5 moves + the wait); the
    # inferred 2 -> 1 is one move: act = w * f against w**5
    g, w = _ring_with_a_stop(), 0.9
    goal = {(1, 99): 1.0}
    for f, best in ((0.8, (2, 1)), (0.5, (2, 3))):          # 0.72 > 0.59 > 0.45
        act = propagate(g, goal, w, method=method, inferred_weight=f)
        assert act[(2, 1)] == pytest.approx(w * f)
        assert act[(2, 3)] == pytest.approx(w**5)
        ref = propagate_reference(g, goal, w, inferred_weight=f)
        np.testing.assert_allclose([act[t] for t in g], [ref[t] for t in g], rtol=1e-12)
        assert max(g.outgoing(2), key=lambda t: act[t]) == best
    # without the inference discount the way back counts as a known move
    assert propagate(g, goal, w, method=method)[(2, 1)] == pytest.approx(w)


def test_the_planner_chooses_the_inferred_way_back_and_replans_when_it_is_confirmed():
    from hippo.cognitive_map import Drives

    g = _ring_with_a_stop()
    drives = Drives(["food"])
    drives.link("food", (1, 99), 1.0)
    drives.set_level("food", 1.0)
    planner = Planner(PlannerParams(w=0.9, noise=0.0, inferred_weight=0.8))
    assert planner.plan(g, drives, 2) == [(2, 1), (1, 99)]
    goal = drives.links("food")[(1, 99)]
    assert planner.decide(g, drives, 2).activity == pytest.approx(0.72 * goal)
    g.add_transition(2, 1, Action.move(math.pi, 20.0))    # made for real: a known move now
    assert inferred_mask(g).sum() == 0
    # replanned (not the cached 0.72): the way back is a known move
    assert planner.decide(g, drives, 2).activity == pytest.approx(0.9 * goal)
    with pytest.raises(ValueError, match="inferred_weight"):
        PlannerParams(inferred_weight=0.0)


@pytest.mark.parametrize("f", [5.0, -1.0, 0.0, np.nan])
def test_the_reference_sweep_checks_inferred_weight_as_the_planner_does(f):
    # fifth fuzzing pass: propagate_reference took 5 and -1 (propagate refused them)
    g = _ring_with_a_stop()
    for sweep in (propagate, propagate_reference):
        with pytest.raises(ValueError, match=r"^inferred_weight must lie in \(0.0, 1.0\]"):
            sweep(g, {(1, 99): 1.0}, 0.9, inferred_weight=f)
    assert propagate_reference(g, {(1, 99): 1.0}, 0.9, inferred_weight=1.0)[(2, 1)] == 0.9
