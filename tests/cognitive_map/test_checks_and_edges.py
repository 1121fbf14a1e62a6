"""Edges of the cognitive map's loaders and planner (written from surviving mutants)."""

import numpy as np
import pytest

from hippo.cognitive_map import DriveParams, Drives, TransitionGraph
from hippo.cognitive_map.planner import Planner, PlannerParams, propagate
from hippo.cognitive_map.synthetic import random_transition_graph
from hippo.io import CorruptFileError


def _drives_dict():
    d = Drives({"a": DriveParams()})
    d.reward("a", (0, 1))
    return d.to_dict()


def test_drives_from_dict_names_what_is_wrong():
    data = _drives_dict()
    data["drives"][0]["colour"] = "red"
    with pytest.raises(ValueError, match="exactly the keys"):
        Drives.from_dict(data)
    data = _drives_dict()
    data["drives"][0]["links"][0][2] = "0.5"  # a weight written as text is refused
    with pytest.raises(ValueError, match="link weight must be a number"):
        Drives.from_dict(data)
    data = _drives_dict()
    data["drives"][0]["links"].append(list(data["drives"][0]["links"][0]))
    with pytest.raises(ValueError, match="twice"):
        Drives.from_dict(data)
    data = _drives_dict()
    data["drives"][0]["inhibited"] = 1
    with pytest.raises(ValueError, match="inhibited"):
        Drives.from_dict(data)
    assert Drives.from_dict(_drives_dict()).links("a") == {(0, 1): 0.5}


def test_decay_threshold_above_one_is_refused():
    g = TransitionGraph()
    g.add_transition(0, 1, "wait")
    with pytest.raises(ValueError, match="decay threshold"):
        g.decay(0.5, threshold=1.5)
    assert g.decay(0.5, threshold=1.0) == [(0, 1)]  # 1 itself is allowed: forget everything


def _graphml(tmp_path, edit):
    g = TransitionGraph()
    g.add_transition(0, 1, (0.5, 10.0), 2.0)
    g.add_transition(1, 2, "wait", 5.0)
    g.observe_position(0, (1.0, 2.0))
    text = g.to_graphml(tmp_path / "g.graphml").read_text()
    (tmp_path / "e.graphml").write_text(edit(text))
    return tmp_path / "e.graphml"


def test_graphml_without_states_loads_and_bad_values_are_quoted(tmp_path):
    import re

    no_states = _graphml(tmp_path, lambda t: re.sub(r'\s*<data key="d1">\[\[.*?</data>', "", t))
    g = TransitionGraph.from_graphml(no_states)
    assert len(g) == 2 and g.positions == {}
    bad_y = _graphml(tmp_path, lambda t: t.replace("[0, 1.0, 2.0, 1]", '[0, 1.0, "up", 1]'))
    with pytest.raises(CorruptFileError, match="y of state 0"):
        TransitionGraph.from_graphml(bad_y)
    for key, value, message in (("d10", "-3.0", r"distance .* got -3\.0"),
                                ("d11", "-2.0", r"delay .* got -2\.0"),
                                ("d5", "4", r"n_wait=4")):
        path = _graphml(tmp_path, lambda t, k=key, v=value: re.sub(
            rf'<data key="{k}">[^<]*</data>', f'<data key="{k}">{v}</data>', t, count=1))
        with pytest.raises(CorruptFileError, match=message):
            TransitionGraph.from_graphml(path)


def test_random_transition_graph_spreads_headings_and_delays():
    g = random_transition_graph(10, 60, np.random.default_rng(0))
    moves = [g.action(t) for t in g if not g.action(t).is_wait]
    headings = np.array([a.heading for a in moves])
    delays = np.array([g.delay(t) for t in g])
    assert headings.min() < -1.0 and headings.max() > 1.0  # over (-pi, pi]
    assert delays.min() >= 0.5 and delays.max() > 5.0 and delays.max() <= 10.0


def test_propagate_without_goals_and_input_messages():
    g = random_transition_graph(5, 8, np.random.default_rng(1))
    act = propagate(g, {}, 0.9)
    assert not act.values.any() and not act.inputs.any()
    assert act.state_values is not None and not act.state_values.any()
    act_t = propagate(g, {}, 0.9, method="transitions")
    assert act_t.state_values is None
    with pytest.raises(ValueError, match="drive inputs"):
        propagate(g, np.full(len(g), np.nan), 0.9)


def test_planner_activity_uses_the_planners_method():
    g = random_transition_graph(5, 8, np.random.default_rng(2))
    d = Drives({"a": DriveParams(initial=1.0)})
    d.reward("a", g.transitions[0])  # a goal link
    d.set_level("a", 1.0)
    act = Planner(PlannerParams(method="transitions")).activity(g, d)
    assert act.state_values is None
    act = Planner(PlannerParams(method="states")).activity(g, d)
    assert act.state_values is not None and act.values.max() > 0
