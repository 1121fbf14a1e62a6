"""The transition graph's file format: GraphML, written atomically, read trusting nothing.

Node ids are ``"a->b"`` strings; every node attribute (:data:`NODE_ATTRS`) is written with its
type, ``None`` values are left out (GraphML has no null) and restored as ``None`` on reading.
State positions go into the graph attribute ``states`` as JSON. :func:`read_graphml` checks
every attribute's type and range and the ``A->B -> B->C`` links before it builds the map.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any

import networkx as nx

from hippo.cognitive_map.actions import MOVE, WAIT
from hippo.io import CorruptFileError, atomic_write_text
from hippo.types import MAX_STATE_ID, Transition

__all__ = ["GRAPHML_FORMAT", "NODE_ATTRS", "node_id", "read_graphml", "write_graphml"]

GRAPHML_FORMAT = "hippo.cognitive_map.TransitionGraph/1"

_FLOAT_ATTRS = ("heading", "heading_r", "distance", "delay", "strength", "last_used")
_INT_ATTRS = ("a", "b", "count", "n_wait", "n_delay")
_STR_ATTRS = ("action",)
_BOOL_ATTRS = ("inferred",)  # optional on reading (False when absent)
NODE_ATTRS = _INT_ATTRS + _STR_ATTRS + _FLOAT_ATTRS + _BOOL_ATTRS
"""Every attribute a transition node carries (``None`` allowed for the float ones but strength)."""




def node_id(t: Transition) -> str:
    """The GraphML node id of transition ``t``: ``"a->b"``."""
    return f"{t[0]}->{t[1]}"


def write_graphml(graph: Any, path: str | os.PathLike) -> Path:
    """Write the map to a GraphML file atomically (temp file + rename; never half-written).

    Node ids are ``"a->b"`` strings; every node attribute is written with its type, ``None``
    values are left out (GraphML has no null) and restored as ``None`` on reading. State
    positions go into the graph attribute ``states`` as JSON.
    """
    h = nx.DiGraph()
    h.graph["format"] = GRAPHML_FORMAT
    h.graph["states"] = json.dumps(
        [[s, None, None, 0] if p is None else [s, p[0], p[1], graph._pos_n.get(s, 1)]
         for s, p in graph._states.items()])
    for t, d in graph._g.nodes(data=True):
        attrs: dict[str, Any] = {}
        for k in _INT_ATTRS:
            attrs[k] = int(d[k])
        attrs["action"] = str(d["action"])
        for k in _FLOAT_ATTRS:
            if d[k] is not None:
                attrs[k] = float(d[k])
        attrs["inferred"] = bool(d.get("inferred", False))
        h.add_node(node_id(t), **attrs)
    h.add_edges_from((node_id(u), node_id(v)) for u, v in graph._g.edges)
    text = "\n".join(nx.generate_graphml(h)) + "\n"
    return atomic_write_text(path, text)

def read_graphml(path: str | os.PathLike, cls: type) -> Any:
    """Read a map written by :func:`write_graphml` into a new ``cls()`` (a
    :class:`~hippo.cognitive_map.graph.TransitionGraph`); :class:`~hippo.io.CorruptFileError`
    if bad.

    Nothing is trusted: every node attribute must have its type (integers as integers,
    finite floats) and lie in its range (ids >= 0; ``count >= 1``; ``0 <= n_wait, n_delay
    <= count``; the action the majority of ``n_wait``; a move has a heading in (-π, π], a
    ``heading_r`` in [0, 1] and a distance >= 0; delay >= 0 and present exactly when
    ``n_delay > 0``; strength in [0, 1]); unknown attributes, node ids that do not match
    their ``a``/``b``, state positions that are not finite, and links that break the
    ``A->B -> B->C`` rule are refused. The map is built only once every check passed.
    """
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"no such file: {path}")
    try:
        h = nx.read_graphml(path, node_type=str)
    except Exception as exc:  # any parse failure of the file is a corrupt file
        raise CorruptFileError(f"{path} is not a readable GraphML file ({exc!r})") from exc
    if h.graph.get("format") != GRAPHML_FORMAT:
        raise CorruptFileError(
            f"{path} is not a hippo transition graph (format {h.graph.get('format')!r})")
    if not isinstance(h, nx.DiGraph) or isinstance(h, nx.MultiDiGraph):
        raise CorruptFileError(f"{path} is not a directed simple graph")
    g = cls()
    try:
        _read_states(g, h.graph.get("states", "[]"))
        for nid, d in h.nodes(data=True):
            attrs = _checked_node(nid, d)
            t = (attrs["a"], attrs["b"])
            if t in g._g:
                raise ValueError(f"transition {nid} appears twice")
            g._insert(t, attrs)
    except (KeyError, ValueError, TypeError, OverflowError, json.JSONDecodeError) as exc:
        raise CorruptFileError(f"{path}: bad transition graph content ({exc})") from exc
    file_edges = set(h.edges)
    own_edges = {(node_id(u), node_id(v)) for u, v in g._g.edges}
    if file_edges != own_edges:
        raise CorruptFileError(
            f"{path}: links differ from the A->B -> B->C rule "
            f"({len(file_edges - own_edges)} extra, {len(own_edges - file_edges)} missing)")
    return g

def _read_states(graph: Any, text: Any) -> None:
    if not isinstance(text, str):
        raise ValueError(f"the graph attribute 'states' must be a JSON string, got {text!r}")
    try:
        rows = json.loads(text)
    except RecursionError:  # "[[[[..." nested beyond Python's limit
        raise ValueError("the graph attribute 'states' is JSON nested too deeply") from None
    if not isinstance(rows, list):
        raise ValueError("'states' must be a list of [state, x, y, n]")
    for row in rows:
        if not isinstance(row, list) or len(row) != 4:
            raise ValueError(f"a state row must be [state, x, y, n], got {row!r}")
        s, x, y, n = row
        s = _file_int("state", s, lo=0)
        if s in graph._states:
            raise ValueError(f"state {s} is listed twice")
        n = _file_int(f"observation count of state {s}", n, lo=0)
        if x is None and y is None:
            if n != 0:
                raise ValueError(f"state {s} has no position but {n} observations")
            graph._states[s] = None
        else:
            graph._states[s] = (_file_float(f"x of state {s}", x),
                               _file_float(f"y of state {s}", y))
            if n < 1:
                raise ValueError(f"state {s} has a position but {n} observations")
        graph._pos_n[s] = n


def _file_int(name: str, v: Any, lo: int | None = None) -> int:
    """An integer of the file; at most ``MAX_STATE_ID`` (ids and counts are int64 in a map)."""
    if isinstance(v, bool) or not isinstance(v, int):
        raise ValueError(f"{name} must be an integer, got {v!r}")
    if lo is not None and v < lo:
        raise ValueError(f"{name} must be >= {lo}, got {v}")
    if v > MAX_STATE_ID:
        raise ValueError(f"{name} must be <= 2**63 - 1, got {v}")
    return v


def _file_float(name: str, v: Any, lo: float = -math.inf, hi: float = math.inf) -> float:
    if isinstance(v, bool) or not isinstance(v, int | float):
        raise ValueError(f"{name} must be a number, got {v!r}")
    f = float(v)
    if not (math.isfinite(f) and lo <= f <= hi):
        raise ValueError(f"{name} must be finite and in [{lo}, {hi}], got {v!r}")
    return f


def _checked_node(nid: str, d: dict[str, Any]) -> dict[str, Any]:
    """The attributes of node ``nid`` read from a file, each checked for type and range."""
    extra = set(d) - set(NODE_ATTRS)
    if extra:
        raise ValueError(f"node {nid!r} has unknown attribute(s) {sorted(extra)}")
    missing = [k for k in (*_INT_ATTRS, "action", "strength") if k not in d]
    if missing:
        raise ValueError(f"node {nid!r} lacks attribute(s) {missing}")
    at: dict[str, Any] = {k: _file_int(f"{k} of {nid!r}", d[k], lo=0) for k in _INT_ATTRS}
    if node_id((at["a"], at["b"])) != nid:
        raise ValueError(f"node id {nid!r} does not match a={at['a']}, b={at['b']}")
    count = at["count"]
    if count < 1 or at["n_wait"] > count or at["n_delay"] > count:
        raise ValueError(f"node {nid!r}: need count >= 1 and n_wait, n_delay <= count, got "
                         f"count={count}, n_wait={at['n_wait']}, n_delay={at['n_delay']}")
    action = d["action"]
    if action not in (MOVE, WAIT):
        raise ValueError(f"node {nid!r}: action must be 'move' or 'wait', got {action!r}")
    if (action == WAIT) != (2 * at["n_wait"] > count):
        raise ValueError(f"node {nid!r}: action {action!r} is not the majority of "
                         f"{at['n_wait']} wait(s) in {count}")
    at["action"] = action
    for k in _FLOAT_ATTRS:
        at[k] = _file_float(f"{k} of {nid!r}", d[k]) if k in d else None
    moves = count - at["n_wait"]
    for k in ("heading", "heading_r", "distance"):
        if moves > 0 and at[k] is None:
            raise ValueError(f"node {nid!r} has {moves} move(s) but no {k}")
        if moves == 0 and at[k] is not None:
            raise ValueError(f"node {nid!r} has no move but a {k}")
    if at["heading"] is not None and not -math.pi < at["heading"] <= math.pi:
        raise ValueError(f"heading of {nid!r} must lie in (-pi, pi], got {at['heading']}")
    if at["heading_r"] is not None and not 0.0 <= at["heading_r"] <= 1.0:
        raise ValueError(f"heading_r of {nid!r} must lie in [0, 1], got {at['heading_r']}")
    if at["distance"] is not None and at["distance"] < 0:
        raise ValueError(f"distance of {nid!r} must be >= 0, got {at['distance']}")
    if (at["delay"] is None) != (at["n_delay"] == 0):
        raise ValueError(f"node {nid!r}: a delay must be present exactly when n_delay > 0")
    if at["delay"] is not None and at["delay"] < 0:
        raise ValueError(f"delay of {nid!r} must be >= 0, got {at['delay']}")
    if not 0.0 <= at["strength"] <= 1.0:
        raise ValueError(f"strength of {nid!r} must lie in [0, 1], got {at['strength']}")
    inferred = d.get("inferred", False)
    if not isinstance(inferred, bool):
        raise ValueError(f"inferred of {nid!r} must be a boolean, got {inferred!r}")
    if inferred and (action != MOVE or count != 1 or at["n_delay"] != 0):
        raise ValueError(f"node {nid!r}: an inferred transition is one move without a delay")
    at["inferred"] = inferred
    return at
