"""Drive propagation through the transition map and transition selection (HIREL sec. II).

HIREL: "The drive activity can then be propagated through the map (with synaptic weights < 1)
using a max operator (in a fashion similar to the Bellman-Ford algorithm). The gradient of
activity in the map gives information about the distance to rewarding transitions." At the
current place the transition with the highest activity wins the competition, with a little noise;
"If no drive is active then there is no activity in the cognitive map [...] A small amount of
noise in the action selection system will lead to the selection of a random direction", which is
exploration.

**Propagation.** With drive input ``I(n) = max_d level(d) · W_{d,n}`` (0 for a drive below the
exploration threshold), the activity is the fixed point of the max-product sweep::

    act(n) = max( I(n), w · max_{s ∈ successors(n)} act(s) ),     0 < w < 1

i.e. ``act(n) = max_g I(g) · w^{h(n, g)}`` over goal transitions ``g`` reachable from ``n`` in
``h`` hops (``h = 0`` for ``g = n``): the strongest drive, discounted by distance, wins; it never
exceeds the largest drive level, and a transition from which no goal is reachable gets 0.

**Time, not hops** (``PlannerParams.hop_time``). Per hop, the discount counts the states a
way crosses, and how many there are depends on the place code (a learned code with direction
sectors has more per metre than another), while a stop on the way costs one hop whatever its
wait. With a hop time ``τ`` a transition of learned delay ``δ`` passes on ``w^(δ/τ)`` instead
of ``w``: ``act(n) = max_g I(g) · w^(T(n, g)/τ)``, ``T`` the learned time from ``n`` to the goal.

**Fast form.** Taking ``−log`` turns it into shortest paths: ``cost(n) = −log act(n)``, edges cost
``L = −log w > 0`` on the reversed graph, and each goal ``g`` starts at ``c_g = −log I(g)``.
Different start costs are handled by a virtual super-source joined to each goal by an edge of
cost ``K + c_g`` (``K = 1`` keeps every such edge > 0, since scipy may drop explicit zeros; it is
subtracted afterwards); one ``scipy.sparse.csgraph.dijkstra`` from the super-source solves it.

Two graphs can carry that Dijkstra:

- ``method="transitions"``: the transition graph itself (nodes = transitions, edges
  ``A→B → B→C``) — literally the sweep above;
- ``method="states"`` (default, ~10× faster): because the transition graph is the line graph of
  the state graph, ``act(a→b) = max(I(a→b), w · V(b))`` with the state value
  ``V(s) = max_{(s, x)} act(s→x)``, and ``V`` solves the same kind of shortest-path problem on the
  *state* graph (one edge per transition, instead of one per pair of consecutive transitions).

The sparse matrices (:mod:`hippo.cognitive_map.shortest_paths`) are built once per structure
change (cached on the graph, keyed by its ``structure_version``). :func:`propagate_reference`
is the pure-Python sweep on the networkx graph (Bellman-Ford with a FIFO work list), for tests
and the benchmark.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from typing import Any, Literal

import networkx as nx
import numpy as np

from hippo._checks import check_fields, check_int, check_positive, check_range, check_seed
from hippo.cognitive_map.drives import Drives
from hippo.cognitive_map.graph import Transition, TransitionGraph, TransitionIndex
from hippo.cognitive_map.inputs import (
    MIN_HOPS,
    drive_input,
    effective_levels,
    hop_counts,
    inferred_mask,
)
from hippo.cognitive_map.inputs import input_array as _input_array
from hippo.cognitive_map.keys import as_transition
from hippo.cognitive_map.shortest_paths import (
    _dijkstra_from_goals,
    _state_order,
    state_pattern,
    transition_pattern,
)

Method = Literal["states", "transitions"]


@dataclass(frozen=True)
class PlannerParams:
    """Parameters of :class:`Planner`.

    w:                     propagation weight, ``0 < w < 1`` (activity × w per hop).
    noise:                 std of the Gaussian noise added to the outgoing activities at a choice,
                           relative to the best of them (0 = pure winner-take-all; exact ties are
                           then broken uniformly at random).
    exploration_threshold: a drive whose level is below this is inactive (no input to the map);
                           with no active drive reaching the current state, the choice is uniform
                           over its outgoing transitions (exploration).
    replan_tolerance:      reuse the last propagation while no drive level moved by more than this
                           (and neither the map structure nor the goal links changed).
    method:                ``"states"`` or ``"transitions"`` (see the module docstring).
    inferred_weight:       an inferred move (:meth:`TransitionGraph.infer_reverse`, never made)
                           passes on ``w · inferred_weight`` instead of ``w``: the planner takes
                           a way back it only inferred when it saves enough known steps.
    hop_time:              seconds a hop stands for, or ``None`` (default: HIREL's ``w`` per
                           hop). A transition with a learned delay ``δ`` then passes on
                           ``w^(δ / hop_time)`` (at least ``w^0.01``; ``w`` while its delay is
                           unmeasured): the activity falls with the time a way takes, stops on
                           it included, not with the number of states it crosses.
    """

    w: float = 0.9
    noise: float = 0.01
    exploration_threshold: float = 0.05
    replan_tolerance: float = 1e-3
    method: Method = "states"
    inferred_weight: float = 0.8
    hop_time: float | None = None

    def __post_init__(self) -> None:
        check_fields(self)
        _check_w(self.w)
        check_positive("PlannerParams.noise", self.noise, allow_zero=True)
        check_range("PlannerParams.exploration_threshold", self.exploration_threshold, 0.0, 1.0)
        check_positive("PlannerParams.replan_tolerance", self.replan_tolerance, allow_zero=True)
        _check_method(self.method)
        check_range("PlannerParams.inferred_weight", self.inferred_weight, 0.0, 1.0,
                    closed="right")
        _check_hop_time(self.hop_time)


def _check_w(w: float) -> float:
    return check_range("propagation weight w", w, 0.0, 1.0, closed="neither")


def _check_hop_time(hop_time: float | None) -> float | None:
    return None if hop_time is None else check_positive("hop_time", hop_time)


def _check_method(method: str) -> str:
    if method not in ("states", "transitions"):
        raise ValueError(f"method must be 'states' or 'transitions', got {method!r}")
    return method


@dataclass(frozen=True)
class Activity:
    """Result of a propagation: ``values[i]`` is the activity of ``index.nodes[i]``.

    ``inputs`` holds the drive inputs, ``state_values`` (``"states"`` method only, else ``None``)
    the best outgoing activity of each state in ``index.states``.
    """

    index: TransitionIndex
    values: np.ndarray
    inputs: np.ndarray
    state_values: np.ndarray | None = None

    def __getitem__(self, t: Transition) -> float:
        key = as_transition(t)
        try:
            return float(self.values[self.index.pos[key]])
        except KeyError:
            raise KeyError(f"unknown transition {key[0]}->{key[1]}") from None

    def __len__(self) -> int:
        return len(self.values)

    def as_dict(self) -> dict[Transition, float]:
        return dict(zip(self.index.nodes, self.values.tolist(), strict=True))

    def is_goal(self, t: Transition, rtol: float = 1e-9) -> bool:
        """True when ``t`` gets its activity from its own drive input (a reached goal)."""
        i = self.index.pos[as_transition(t)]
        return bool(self.inputs[i] > 0 and self.inputs[i] >= self.values[i] * (1 - rtol))


# --------------------------------------------------------------------------- propagation
def prepare(graph: TransitionGraph, method: Method = "states") -> None:
    """Build (and cache) the index and sparse structure ahead of the first propagation."""
    graph.index()
    if _check_method(method) == "states":
        state_pattern(graph)
    else:
        transition_pattern(graph)


def propagate(graph: TransitionGraph, inputs: Any, w: float = 0.9, *,
              method: Method = "states", inferred_weight: float = 1.0,
              hop_time: float | None = None) -> Activity:
    """Fixed point of ``act(n) = max(I(n), w_n · max_{s ∈ succ(n)} act(s))`` over ``graph``.

    ``w_n = w`` (``w^(δ_n / hop_time)`` with a ``hop_time``, ``δ_n`` the learned delay of
    ``n``: :func:`~hippo.cognitive_map.inputs.hop_counts`), times ``inferred_weight`` for an
    inferred move ``n``. ``inputs`` is a
    :class:`Drives` (all levels count), a mapping transition → input, or an array aligned with
    ``graph.index().nodes``; inputs lie in [0, 1]. Runs one multi-source Dijkstra on ``−log``
    activities (see the module docstring); ``O(E log V)``.
    """
    w = _check_w(w)
    _check_method(method)
    f = check_range("inferred_weight", inferred_weight, 0.0, 1.0, closed="right")
    hop_time = _check_hop_time(hop_time)
    idx = graph.index()
    inp = _input_array(graph, inputs)
    goals = np.flatnonzero(inp > 0)
    if len(goals) == 0:
        zeros = np.zeros(len(idx))
        return Activity(idx, zeros, inp, np.zeros(len(idx.states)) if method == "states" else None)
    wn = np.full(len(idx), w) if hop_time is None else w ** hop_counts(graph, hop_time)
    if f < 1.0:
        wn[inferred_mask(graph)] *= f
    edge_cost = -np.log(wn)  # per transition
    goal_costs = -np.log(inp[goals])
    if method == "states":
        indptr, indices = state_pattern(graph)
        ns = len(idx.states)
        cost = _dijkstra_from_goals(indptr, indices, ns, edge_cost[_state_order(graph)],
                                    idx.a_s[goals], goal_costs)
        v = np.exp(-cost)  # inf -> 0
        values = np.maximum(inp, wn * v[idx.b_s])
        return Activity(idx, values, inp, v)
    indptr, indices = transition_pattern(graph)
    # the edge j -> i of the reversed transition graph offers act(j) to i at i's weight
    cost = _dijkstra_from_goals(indptr, indices, len(idx), edge_cost[indices], goals,
                                goal_costs)
    values = np.minimum(np.exp(-cost), 1.0)
    values[goals] = np.maximum(values[goals], inp[goals])
    return Activity(idx, values, inp)


def propagate_reference(graph: TransitionGraph | nx.DiGraph, inputs: Any, w: float = 0.9,
                        inferred_weight: float = 1.0, hop_time: float | None = None
                        ) -> dict[Transition, float]:
    """Pure-Python reference of the same sweep on the networkx graph (Bellman-Ford, FIFO list).

    Starts from ``act = I`` and, whenever ``act(s)`` grows, offers ``w · act(s)`` to every
    predecessor of ``s`` (``w · inferred_weight`` to an inferred one; with ``hop_time``,
    ``w^(δ / hop_time)`` for a predecessor of learned delay ``δ``, at least ``w^MIN_HOPS``)
    until nothing changes.
    ``inputs``: a :class:`Drives` (with a :class:`TransitionGraph`) or a mapping transition →
    input. Returns transition → activity.
    """
    w = _check_w(w)
    inferred_weight = check_range("inferred_weight", inferred_weight, 0.0, 1.0, closed="right")
    hop_time = _check_hop_time(hop_time)
    if isinstance(graph, TransitionGraph):
        if isinstance(inputs, Drives):
            arr = drive_input(graph, inputs)
            inputs = dict(zip(graph.index().nodes, arr.tolist(), strict=True))
        g = graph.nx
    else:
        g = graph
        if isinstance(inputs, Drives):
            raise TypeError("give a TransitionGraph to propagate Drives, or a mapping of inputs")
    act = dict.fromkeys(g, 0.0)
    for t, v in inputs.items():
        if t not in act:
            raise KeyError(f"drive input given for unknown transition {t!r}")
        v = float(v)
        if not 0.0 <= v <= 1.0:
            raise ValueError(f"drive input of {t!r} must lie in [0, 1], got {v!r}")
        act[t] = max(act[t], v)
    pred = g.pred
    queue = deque(n for n, v in act.items() if v > 0)
    queued = set(queue)
    while queue:
        s = queue.popleft()
        queued.discard(s)
        for p in pred[s]:
            delay = g.nodes[p].get("delay") if hop_time is not None else None
            wp = w if delay is None else w ** max(delay / hop_time, MIN_HOPS)
            offer = wp * act[s] * (inferred_weight if g.nodes[p].get("inferred") else 1.0)
            if offer > act[p]:
                act[p] = offer
                if p not in queued:
                    queued.add(p)
                    queue.append(p)
    return act


# --------------------------------------------------------------------------- the planner
@dataclass(frozen=True)
class Choice:
    """A decision: the transition to execute (``None``: the state has no outgoing transition),
    its activity, and whether it was an exploratory (random) pick."""

    transition: Transition | None
    activity: float
    explored: bool


class Planner:
    """Propagates drives through a :class:`TransitionGraph` and picks transitions.

    The last propagation is reused while the graph structure, the goal links and the effective
    drive levels (within ``replan_tolerance``) are unchanged; ``n_propagations`` counts real ones.
    """

    def __init__(self, params: PlannerParams | None = None, *, seed: int | None = None) -> None:
        self.params = PlannerParams() if params is None else params
        if not isinstance(self.params, PlannerParams):
            raise TypeError(f"params must be PlannerParams, got {self.params!r}")
        self.rng = np.random.default_rng(None if seed is None else check_seed("seed", seed))
        self.n_propagations = 0
        self._key: tuple[Any, ...] | None = None
        self._levels: dict[str, float] | None = None
        self._activity: Activity | None = None
        self._refs: tuple[TransitionGraph, Drives] | None = None  # the map and drives cached

    def activity(self, graph: TransitionGraph, drives: Drives, *, force: bool = False) -> Activity:
        """The propagated activity for the current drives (cached, see the class docstring)."""
        p = self.params
        levels = effective_levels(drives, p.exploration_threshold)
        # the same map and drives objects (by identity, not by id(): a restored snapshot
        # keeps its cache), unchanged in structure and goal links
        n_inferred = int(inferred_mask(graph).sum()) if p.inferred_weight < 1.0 else 0
        # the learned delays change at every repeat of a transition: with a hop time, every
        # change of the map is one
        version = graph.structure_version if p.hop_time is None else graph.version
        key = (version, drives.links_version, n_inferred)
        same = self._refs is not None and self._refs[0] is graph and self._refs[1] is drives
        if (not force and self._activity is not None and same and key == self._key
                and self._levels is not None and self._levels.keys() == levels.keys()
                and all(abs(levels[n] - v) <= p.replan_tolerance for n, v in self._levels.items())):
            return self._activity
        inp = drive_input(graph, drives, p.exploration_threshold)
        self._activity = propagate(graph, inp, p.w, method=p.method,
                                   inferred_weight=p.inferred_weight, hop_time=p.hop_time)
        self._key, self._levels = key, levels
        self._refs = (graph, drives)
        self.n_propagations += 1
        return self._activity

    def decide(self, graph: TransitionGraph, drives: Drives, state: int,
               rng: np.random.Generator | None = None) -> Choice:
        """Choose the transition to execute from ``state`` (see :meth:`choose`), with details."""
        out = graph.outgoing(state)  # KeyError for an unknown state
        rng = self.rng if rng is None else rng
        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
        if not out:
            return Choice(None, 0.0, False)
        levels = effective_levels(drives, self.params.exploration_threshold)
        if any(v > 0 for v in levels.values()):
            act = self.activity(graph, drives)
            vals = act.values[[act.index.pos[t] for t in out]]
            best = float(vals.max())
            if best > 0:
                score = vals
                if self.params.noise > 0:
                    score = vals + self.params.noise * best * rng.standard_normal(len(vals))
                top = float(score.max())
                cands = np.flatnonzero(score >= top - 1e-12 * abs(top))
                k = int(cands[0] if len(cands) == 1 else rng.choice(cands))
                return Choice(out[k], float(vals[k]), False)
        k = int(rng.integers(len(out)))
        return Choice(out[k], 0.0, True)

    def choose(self, graph: TransitionGraph, drives: Drives, state: int,
               rng: np.random.Generator | None = None) -> Transition | None:
        """The transition ``(state, x)`` to execute: the most active one (+ noise), or a uniform
        random one when no active drive reaches ``state`` (exploration); ``None`` when ``state``
        has no outgoing transition. ``KeyError`` for a state the map does not know.
        """
        return self.decide(graph, drives, state, rng).transition

    def best_transition(self, graph: TransitionGraph, drives: Drives,
                        state: int) -> Transition | None:
        """The most active outgoing transition of ``state`` (no noise; first on ties), or ``None``
        when none has activity."""
        out = graph.outgoing(state)
        if not out:
            return None
        act = self.activity(graph, drives)
        vals = act.values[[act.index.pos[t] for t in out]]
        k = int(np.argmax(vals))
        return out[k] if vals[k] > 0 else None

    def plan(self, graph: TransitionGraph, drives: Drives, state: int,
             max_steps: int | None = None) -> list[Transition]:
        """Follow the activity gradient from ``state``: the best transitions, one after the other,
        up to and including the first goal transition whose activity is its own drive input.

        Empty when no drive activity reaches ``state``. Along the path the activity grows by
        ``1/w`` per step, so it ends after at most ``len(graph)`` steps (or ``max_steps``, an
        integer >= 1).
        """
        limit = len(graph) if max_steps is None else check_int("max_steps", max_steps, lo=1)
        act = self.activity(graph, drives)
        path: list[Transition] = []
        s = state
        while len(path) < limit:
            t = self.best_transition(graph, drives, s)
            if t is None:
                break
            path.append(t)
            if act.is_goal(t):
                break
            s = t[1]
        return path
