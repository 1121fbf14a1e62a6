"""A saved map whose fields were edited out of range is refused, and the message names the
field and its value (found by mutation testing: the range checks' messages and several
integer checks of the GraphML loader were never exercised)."""

from __future__ import annotations

import json

import networkx as nx
import pytest

from hippo.cognitive_map import TransitionGraph
from hippo.io import CorruptFileError


def _saved(tmp_path):
    g = TransitionGraph()
    g.add_transition(0, 1, (0.0, 1.0))
    g.add_transition(1, 2, "wait", delay=2.0)
    g.set_position(0, (1.0, 2.0))
    return nx.read_graphml(g.to_graphml(tmp_path / "map.graphml"))


def _load_edited(tmp_path, h):
    path = tmp_path / "edited.graphml"
    nx.write_graphml(h, path)
    return TransitionGraph.from_graphml(path)


@pytest.mark.parametrize(("node", "field", "value", "message"), [
    ("0->1", "heading", 4.0, r"heading of '0->1' must lie in \(-pi, pi\], got 4.0"),
    ("0->1", "heading_r", 1.5, r"heading_r of '0->1' must lie in \[0, 1\], got 1.5"),
    ("0->1", "action", "wait", r"action 'wait' is not the majority of 0 wait\(s\) in 1"),
    ("0->1", "count", 1.5, r"count .*must be an integer, got 1.5"),
    ("0->1", "a", -1, r"must be >= 0, got -1"),
    ("0->1", "a", 2**63, r"a of '0->1' must be <= 2\*\*63 - 1"),
    ("1->2", "heading", 0.5, r"node '1->2' has no move but a heading"),
    ("1->2", "distance", 3.0, r"node '1->2' has no move but a distance"),
])
def test_an_edited_transition_is_refused_by_name(tmp_path, node, field, value, message):
    h = _saved(tmp_path)
    h.nodes[node][field] = value
    with pytest.raises(CorruptFileError, match=message):
        _load_edited(tmp_path, h)


@pytest.mark.parametrize(("row", "message"), [
    ([0, 1.0, 2.0, -1], r"observation count of state 0 must be >= 0, got -1"),
    ([-1, None, None, 0], r"state must be >= 0, got -1"),
    ([0, 1.0, 2.0, True], r"observation count of state 0 must be an integer, got True"),
    ([2**63, None, None, 0], r"state must be <= 2\*\*63 - 1"),
    ("[" * 100_000 + "]" * 100_000, r"'states' is JSON nested too deeply"),
])
def test_an_edited_state_row_is_refused_by_name(tmp_path, row, message):
    h = _saved(tmp_path)
    rows = json.loads(h.graph["states"])
    rows[0] = row
    h.graph["states"] = row if isinstance(row, str) else json.dumps(rows)
    with pytest.raises(CorruptFileError, match=message):
        _load_edited(tmp_path, h)


def test_a_foreign_format_is_named(tmp_path):
    h = _saved(tmp_path)
    h.graph["format"] = "someone.else/7"
    with pytest.raises(CorruptFileError, match=r"not a hippo transition graph "
                                               r"\(format 'someone.else/7'\)"):
        _load_edited(tmp_path, h)
    h.graph["format"] = "hippo.cognitive_map.TransitionGraph/1"
    assert _load_edited(tmp_path, h).position(0) == (1.0, 2.0)
