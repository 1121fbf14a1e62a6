"""The transition graph: HIREL's cognitive map of *transitions* between states.

HIREL (Hirel et al., sec. II, "The cognitive map forms a topological representation of the
environment by linking subsequent transitions") plans over transitions ``A→B`` rather than over
places. Each node of :class:`TransitionGraph` is one transition, keyed by the tuple ``(a, b)`` of
integer state ids (the same key as :mod:`hippo.timing`), with the attributes

``action``     ``"move"`` or ``"wait"`` (HIREL's checkpoints: the action of a transition learned
               while the robot stood still is to wait, sec. III-B);
``heading``    circular mean of the headings measured by path integration (radians, in (-π, π]);
``heading_r``  mean resultant length of those headings (1 = always the same heading, 0 = none);
``distance``   mean travelled distance (cm);
``delay``      mean learned delay (s) between entering ``a`` and entering ``b``;
``count``      how often the transition was taken (``n_wait`` of those as a wait, ``n_delay`` with a
               delay measurement);
``strength``   1 when last used, multiplied by the factor of :meth:`TransitionGraph.decay`;
``last_used``  time of the last use, if the caller gives times;
``inferred``   True for a move never made but inferred (``B→A`` from ``A→B``:
               :meth:`TransitionGraph.infer_reverse`); the first real ``B→A`` replaces it.

Edges link ``A→B`` to every ``B→C``: the graph is the *line graph* of the state graph, so an edge
exists exactly when the end state of one transition is the start state of the other. The edge set
is maintained by the graph itself (adding ``B→C`` links every known ``A→B`` to it, and links it to
every known ``C→D``), which is what lets :mod:`hippo.cognitive_map.planner` propagate on the much
smaller state graph.

Merging a repeat updates running means (the heading as an exact circular mean; the kind is the
majority kind): :mod:`hippo.cognitive_map.merge`. Keys are checked by
:mod:`hippo.cognitive_map.keys`.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Hashable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import networkx as nx
import numpy as np

from hippo._checks import check_finite, check_positive, check_range
from hippo.cognitive_map.actions import MOVE, WAIT, Action, ActionLike, as_action, wrap_exact
from hippo.cognitive_map.graphml import GRAPHML_FORMAT, NODE_ATTRS, read_graphml, write_graphml
from hippo.cognitive_map.keys import as_transition, state_id
from hippo.cognitive_map.merge import merge_repeat
from hippo.types import Transition

__all__ = [
    "GRAPHML_FORMAT", "MOVE", "NODE_ATTRS", "WAIT", "Action", "ActionLike", "TransitionGraph",
    "TransitionIndex", "as_transition", "state_id",
]


def _xy(state: int, position: Any) -> tuple[float, float]:
    arr = check_finite(f"position of state {state}", position).ravel()
    if arr.shape != (2,):
        raise ValueError(f"position of state {state} must be (x, y), got {position!r}")
    return float(arr[0]), float(arr[1])


class TransitionGraph:
    """HIREL's cognitive map: a networkx ``DiGraph`` of transitions ``(a, b)`` linked ``A→B → B→C``.

    Mutate it only through its methods (they keep the edges and the version counters right);
    :attr:`nx` is a read-only view for analysis and drawing.

    ``version`` grows on every change; ``structure_version`` only when transitions are added or
    removed (the planner's cached sparse matrices depend on the structure only).
    """

    def __init__(self) -> None:
        self._g = nx.DiGraph()
        self._out: dict[int, dict[Transition, None]] = {}
        self._in: dict[int, dict[Transition, None]] = {}
        self._states: dict[int, tuple[float, float] | None] = {}
        self._pos_n: dict[int, int] = {}  # observations behind each position
        self.version = 0
        self.structure_version = 0
        self._cache: dict[Hashable, Any] = {}
        self._cache_version = -1

    # ------------------------------------------------------------------ queries
    def __len__(self) -> int:
        return self._g.number_of_nodes()

    def __contains__(self, t: object) -> bool:
        try:
            return as_transition(t) in self._g
        except ValueError:
            return False

    def __iter__(self) -> Iterator[Transition]:
        return iter(self._g)

    def __repr__(self) -> str:
        return (f"TransitionGraph({len(self)} transitions, {self._g.number_of_edges()} links, "
                f"{len(self._states)} states)")

    @property
    def nx(self) -> nx.DiGraph:
        """A read-only view of the underlying networkx ``DiGraph`` (nodes = transitions)."""
        return self._g.copy(as_view=True)

    @property
    def transitions(self) -> list[Transition]:
        """All transitions, in insertion order."""
        return list(self._g)

    @property
    def n_links(self) -> int:
        """Number of edges ``A→B → B→C``."""
        return self._g.number_of_edges()

    @property
    def states(self) -> frozenset[int]:
        """Every state known: ends of transitions, plus states added with :meth:`add_state`.

        Forgetting a transition does not forget its states (the place is still known).
        """
        return frozenset(self._states)

    def has_state(self, state: int) -> bool:
        return state in self._states

    def _check_state(self, state: Any) -> int:
        s = state_id(state)
        if s not in self._states:
            raise KeyError(f"unknown state {s}: the map knows {len(self._states)} state(s)")
        return s

    def outgoing(self, state: int) -> list[Transition]:
        """Transitions ``(state, x)``, in insertion order; ``KeyError`` for an unknown state."""
        s = self._check_state(state)
        return list(self._out.get(s, ()))

    def incoming(self, state: int) -> list[Transition]:
        """Transitions ``(x, state)``, in insertion order; ``KeyError`` for an unknown state."""
        s = self._check_state(state)
        return list(self._in.get(s, ()))

    def successors(self, t: Transition) -> list[Transition]:
        """The transitions that can follow ``t`` (those starting where ``t`` ends)."""
        return list(self._g.successors(self._check_transition(t)))

    def predecessors(self, t: Transition) -> list[Transition]:
        return list(self._g.predecessors(self._check_transition(t)))

    def _check_transition(self, t: Any) -> Transition:
        key = as_transition(t)
        if key not in self._g:
            raise KeyError(f"unknown transition {key[0]}->{key[1]}")
        return key

    def attributes(self, t: Transition) -> dict[str, Any]:
        """A copy of the attributes of transition ``t`` (see the module docstring)."""
        return dict(self._g.nodes[self._check_transition(t)])

    def action(self, t: Transition) -> Action:
        """The motor action of ``t``: :meth:`Action.wait`, or a move with mean heading/distance."""
        d = self._g.nodes[self._check_transition(t)]
        if d["action"] == WAIT:
            return Action.wait()
        return Action(MOVE, d["heading"], d["distance"])

    def direction(self, t: Transition, min_r: float = 0.0) -> float | None:
        """The mean heading of move ``t``, or None for a wait or a move whose measured headings
        disagree (``heading_r`` < ``min_r``: made both ways, a move with no direction)."""
        d = self._g.nodes[self._check_transition(t)]
        r = d["heading_r"]
        return None if d["heading"] is None or (r is not None and r < min_r) else d["heading"]

    def delay(self, t: Transition) -> float | None:
        """The mean learned delay (s) of ``t``, or ``None`` if never measured."""
        return self._g.nodes[self._check_transition(t)]["delay"]

    def count(self, t: Transition) -> int:
        return self._g.nodes[self._check_transition(t)]["count"]

    # --------------------------------------------------------------- positions
    def add_state(self, state: int, position: tuple[float, float] | None = None) -> int:
        """Declare a state (e.g. the current one before any transition), maybe with a position."""
        s = state_id(state)
        if s not in self._states:
            self._states[s] = None
            self.version += 1
        if position is not None:
            self.set_position(s, position)
        return s

    def set_position(self, state: int, position: tuple[float, float] | None) -> None:
        """Store an (x, y) estimate of ``state`` (e.g. from path integration), for figures only."""
        s = state_id(state)
        pos = None if position is None else _xy(s, position)
        self._states[s] = pos
        self._pos_n[s] = 0 if pos is None else 1
        self.version += 1

    def observe_position(self, state: int, position: tuple[float, float]) -> tuple[float, float]:
        """Fold one more (x, y) estimate of ``state`` into its running-mean position; returns it."""
        s = state_id(state)
        x, y = _xy(s, position)
        n = self._pos_n.get(s, 0) if self._states.get(s) is not None else 0
        if n == 0:
            pos = (x, y)
        else:
            px, py = self._states[s]  # type: ignore[misc]
            pos = (px + (x - px) / (n + 1), py + (y - py) / (n + 1))
            if not (math.isfinite(pos[0]) and math.isfinite(pos[1])):  # the map could not load
                raise ValueError(f"position of state {s}: {position!r} would overflow the "
                                 f"running mean of {n} at {(px, py)!r}")
        self._states[s] = pos
        self._pos_n[s] = n + 1
        self.version += 1
        return pos

    def position(self, state: int) -> tuple[float, float] | None:
        return self._states[self._check_state(state)]

    @property
    def positions(self) -> dict[int, tuple[float, float]]:
        """The states that have a position, with it."""
        return {s: p for s, p in self._states.items() if p is not None}

    # ---------------------------------------------------------------- mutation
    def add_transition(self, a: int, b: int, action: ActionLike, delay: float | None = None,
                       *, time: float | None = None) -> Transition:
        """Add transition ``a→b`` or merge a repeat of it; returns the key ``(a, b)``.

        ``action`` is an :class:`Action`, ``"wait"`` or ``(heading_rad, distance_cm)``; ``delay``
        (s) the measured time from entering ``a`` to entering ``b``; ``time`` the current time
        (stored as ``last_used``). A repeat updates the running means (circular mean for the
        heading), the counts, and resets ``strength`` to 1. A new transition is linked to every
        ``x→a`` and every ``b→y`` already known (so ``structure_version`` grows).
        """
        t = (state_id(a, "a"), state_id(b, "b"))
        act = as_action(action)
        if delay is not None:
            delay = check_positive("delay", delay, allow_zero=True)
        if time is not None:
            time = float(check_finite("time", time))
        node = self._g.nodes.get(t)
        if node is None:
            attrs = {
                "a": t[0], "b": t[1], "action": act.kind,
                "heading": None, "heading_r": None, "distance": None,
                "delay": delay, "count": 1, "n_wait": int(act.is_wait),
                "n_delay": int(delay is not None), "strength": 1.0, "last_used": time,
                "inferred": False,
            }
            if not act.is_wait:
                attrs.update(heading=act.heading, heading_r=1.0, distance=act.distance)
            self._insert(t, attrs)
        else:
            if node.get("inferred"):  # experience replaces the guess (a first real sample)
                node.update(count=0, n_wait=0, n_delay=0, delay=None, heading=None,
                            heading_r=None, distance=None, inferred=False)
            merge_repeat(node, act, delay, time)
            self.version += 1
        return t

    def infer_reverse(self, t: Transition, *, time: float | None = None) -> Transition | None:
        """Infer the way back of move ``t = A→B``: ``B→A`` with heading ``h + π`` and the same
        distance, marked ``inferred`` (count 1, no delay), unless ``B→A`` is known (or ``t`` is
        a wait or a self-loop). Path integration makes the reverse of a move a plausible move:
        the wall-following robot learns its corridors one way round only, and the reverse
        edges let the planner see the short way back (the robot confirms it by making it,
        see :meth:`add_transition`, or forgets it, :meth:`remove_transition`). Returns the
        inferred transition, or None."""
        a, b = self._check_transition(t)
        d = self._g.nodes[(a, b)]
        if a == b or d["action"] != MOVE or d["heading"] is None or (b, a) in self._g:
            return None
        self._insert((b, a), {
            "a": b, "b": a, "action": MOVE, "heading": wrap_exact(d["heading"] + math.pi),
            "heading_r": d["heading_r"], "distance": d["distance"], "delay": None, "count": 1,
            "n_wait": 0, "n_delay": 0, "strength": 1.0, "last_used": time, "inferred": True})
        return b, a

    def inferred(self, t: Transition) -> bool:
        """Is ``t`` an inferred move the robot has not made yet?"""
        return bool(self._g.nodes[self._check_transition(t)].get("inferred", False))

    def _insert(self, t: Transition, attrs: dict[str, Any]) -> None:
        a, b = t
        self._g.add_node(t, **attrs)
        for s in (a, b):
            self._states.setdefault(s, None)
        # A->B follows every X->A and precedes every B->Y (a self-loop a==b links to itself).
        self._out.setdefault(a, {})[t] = None
        self._in.setdefault(b, {})[t] = None
        self._g.add_edges_from((p, t) for p in self._in.get(a, ()))
        self._g.add_edges_from((t, s) for s in self._out.get(b, ()))
        self.version += 1
        self.structure_version += 1

    def mark_used(self, t: Transition, *, time: float | None = None) -> None:
        """Reset the strength of ``t`` to 1 (and ``last_used``) without counting a new sample."""
        d = self._g.nodes[self._check_transition(t)]
        d["strength"] = 1.0
        if time is not None:
            d["last_used"] = float(check_finite("time", time))
        self.version += 1

    def remove_transition(self, t: Transition) -> None:
        """Forget transition ``t`` and its links (its states stay known)."""
        key = self._check_transition(t)
        self._g.remove_node(key)
        del self._out[key[0]][key]
        del self._in[key[1]][key]
        self.version += 1
        self.structure_version += 1

    def decay(self, factor: float, *, threshold: float = 0.05) -> list[Transition]:
        """Forget unused transitions: ``strength *= factor``, drop those below ``threshold``.

        Use (:meth:`add_transition`, :meth:`mark_used`) resets the strength to 1, so after ``k``
        calls without use a transition has strength ``factor**k``. Returns the removed transitions.
        """
        factor = check_range("decay factor", factor, 0.0, 1.0)
        threshold = check_range("decay threshold", threshold, 0.0, 1.0)
        removed = []
        for t, d in self._g.nodes(data=True):
            d["strength"] *= factor
            if d["strength"] < threshold:
                removed.append(t)
        for t in removed:
            self.remove_transition(t)
        self.version += 1
        return removed

    # ------------------------------------------------------------------- cache
    def cached(self, key: Hashable, build: Callable[[], Any]) -> Any:
        """Memoise ``build()`` under ``key`` until the structure changes (used by the planner)."""
        if self._cache_version != self.structure_version:
            self._cache.clear()
            self._cache_version = self.structure_version
        if key not in self._cache:
            self._cache[key] = build()
        return self._cache[key]

    def index(self) -> TransitionIndex:
        """Arrays describing the structure (cached until the structure changes)."""
        return self.cached("index", lambda: TransitionIndex.build(self))

    # ----------------------------------------------------------------- GraphML
    def to_graphml(self, path: str | os.PathLike) -> Path:
        """Write the map to a GraphML file atomically (see
        :func:`~hippo.cognitive_map.graphml.write_graphml`)."""
        return write_graphml(self, path)

    @classmethod
    def from_graphml(cls, path: str | os.PathLike) -> TransitionGraph:
        """Read a map written by :meth:`to_graphml`, trusting nothing (see
        :func:`~hippo.cognitive_map.graphml.read_graphml`); :class:`~hippo.io.CorruptFileError`
        if bad."""
        return read_graphml(path, cls)

    def same_as(self, other: TransitionGraph) -> bool:
        """True when both maps hold the same transitions, links, attributes and states."""
        return (self._states == other._states
                and self.positions.keys() == other.positions.keys()
                and all(self._pos_n.get(s) == other._pos_n.get(s) for s in self.positions)
                and dict(self._g.nodes(data=True)) == dict(other._g.nodes(data=True))
                and set(self._g.edges) == set(other._g.edges))


@dataclass(frozen=True)
class TransitionIndex:
    """Array form of the structure: transition ``i`` is ``nodes[i] = (a[i], b[i])``.

    ``states`` are the state ids met in transitions (sorted); ``a_s[i]`` / ``b_s[i]`` the positions
    of ``a[i]`` / ``b[i]`` in ``states``.
    """

    nodes: tuple[Transition, ...]
    pos: dict[Transition, int]
    a: np.ndarray
    b: np.ndarray
    states: np.ndarray
    a_s: np.ndarray
    b_s: np.ndarray

    @classmethod
    def build(cls, graph: TransitionGraph) -> TransitionIndex:
        nodes = tuple(graph._g)
        n = len(nodes)
        ab = np.fromiter((x for t in nodes for x in t), dtype=np.int64, count=2 * n).reshape(n, 2)
        states, inv = np.unique(ab.ravel(), return_inverse=True)
        inv = inv.reshape(n, 2)
        return cls(nodes, {t: i for i, t in enumerate(nodes)}, ab[:, 0].copy(), ab[:, 1].copy(),
                   states, inv[:, 0].copy(), inv[:, 1].copy())

    def __len__(self) -> int:
        return len(self.nodes)
