"""Context-split states: one learned place, several map states, by the way the robot came in.

A learned place can stand for a stretch of track that two routes share (aliasing): from the
place alone, the next place is uncertain; from the place *and* the way the robot came in, it
is not. Clone-structured cognitive graphs (George et al., Nat. Commun. 2021) learn such
"clones" of an observation offline with EM; here they are recruited online, from the event
sequence the state layer already produces, by the suffix-tree rule of McCallum's Utile Suffix
Memory (1995): a state is split by one more step of history only when that history makes a
statistically significant difference to what comes next.

**Instances.** Every stay in a place ``p`` that ends (the robot enters the next place) is an
instance ``(h, n, d)``: ``h = (q1, q2, …, qK)`` the places entered before ``p``, most recent
first (``K = max_depth``); ``n`` the place entered next; ``d`` how long the robot stayed in
``p`` (the elapsed time the timing battery reads at the event, seconds).

**Context tree.** Each place has a tree whose leaves are its context states; the root (no
history) is the unsplit place. An internal node routes an instance by one step of its history,
``q_j``; several values of ``q_j`` may share a child (they were found alike: merged). A leaf
is split on the most recent step ``q_j`` not yet used on its path (``j ≤ max_depth``) whose
values tell its instances apart — USM's fringe, so that a stretch shared by two routes (where
``q1`` is the same place on both) splits on the place before it. Grouped by ``q_j`` (each
value with at least ``min_count`` instances), the instances must differ

- in their successors — G-test of independence on the groups × successors table::

      G = 2 Σ O_gn ln(O_gn / E_gn),   E_gn = O_g· O_·n / O_··,   split if P(χ²_df ≥ G) < alpha,
      df = (groups − 1)(successors − 1);

- or in their dwell time — Weber's law: the mean log-dwells differ by more than
  ``ln(1 + dwell_tolerance)`` and by more than ``z`` standard errors (log-dwell sd floored
  at ``weber``, the timing batteries' own precision).

Values are grouped greedily (most frequent first, each joining the first group it is not
different from); every group becomes a leaf with a new context id. Values seen less than
``min_count`` times, and values never seen, follow the first group (the one the most
frequent value founded; another group may grow larger as values join it).

**Merging.** When the children of a node (all leaves) stop being different — the same tests
with the laxer ``alpha_merge`` — they are merged back into one leaf, which keeps the id of
the oldest child; :meth:`ContextStates.resolve` maps a retired id to its survivor.

**Merging places.** Learned place cells also do the opposite of aliasing: two prototypes
can share one stretch of track and win on alternate laps, so the robot sees ``A → B → D`` on
one lap and ``A → C → D`` on the next. Two places are merged into one state (the CSCG measure
of a map rewards it: what follows ``A`` becomes certain) when each has a usual way in and out
(the most frequent predecessor and successor hold at least half of its stays), these are the
same for both, and no step of their past or future up to ``merge_horizon`` events away — nor
the stays in the places after them — differs (the same tests at ``alpha_merge``; until every
step has ``min_count`` stays on both sides, they count as different). The horizon is longer
than ``max_depth``, so a place that a split depends on is not merged away. A merged place
starts again unsplit; :meth:`ContextStates.same` names the place it was merged into.

A learned field can also win only on some passes, for a moment, at the start of the next
one's stretch: the robot goes ``P → X → Y`` on some passes and ``P → Y`` on others. Such a
bypassed place ``X`` (its usual way in is ``P`` and out is ``Y``, and ``P`` is also ``Y``'s
usual way in, ``min_count`` times without ``X``) is merged into ``Y``: one state that
follows ``P`` on every pass. Both merges: :mod:`~hippo.perception.place_merges`.

**Memory.** Each place keeps only its last ``memory`` instances (a ring buffer), so a long
deployment holds a bounded amount of data; trees are bounded by ``max_depth`` and the number
of places.

Typical use (at each change of the place winner)::

    contexts = ContextStates(ContextParams())
    cid = contexts.observe(place, t)      # the context state the robot is in now
    contexts.predict(cid)                 # its next-place distribution
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable, Hashable, Iterable

import numpy as np
from scipy.stats import norm

from hippo.perception.context_tree import ContextKey, ContextParams, _Inst, _Node, g_test
from hippo.perception.place_merges import PlaceMerges

__all__ = ["ContextKey", "ContextParams", "ContextStates", "g_test"]


class ContextStates(PlaceMerges):
    """Online context splitting of learned places (see the module docstring).

    :meth:`observe` takes the place the robot just entered and the time; it returns the id of
    the context state for that entry (ids are integers from 0, never reused). ``n_splits`` and
    ``n_merges`` count the tree's changes.
    """

    def __init__(self, params: ContextParams | None = None) -> None:
        self.params = params or ContextParams()
        if not isinstance(self.params, ContextParams):
            raise TypeError(f"params must be ContextParams, got {self.params!r}")
        self._z = float(norm.isf(self.params.alpha / 2))
        self._z_merge = float(norm.isf(self.params.alpha_merge / 2))
        self._trees: dict[Hashable, _Node] = {}
        self._data: dict[Hashable, deque[_Inst]] = {}
        self._keys: list[ContextKey] = []
        self._alias: dict[int, int] = {}
        self._same: dict[Hashable, Hashable] = {}
        self.n_splits = 0
        self.n_merges = 0
        self.n_place_merges = 0
        self.reset()

    # ------------------------------------------------------------------ sequence
    def reset(self) -> None:
        """Forget the recent history (after a kidnap): the tree and its data are kept."""
        p = self.params
        self._history: deque[Hashable] = deque(maxlen=max(p.max_depth, p.merge_horizon) + 1)
        self._pending: deque[_Inst] = deque(maxlen=p.merge_horizon)
        self._entered: float | None = None
        self.current: int | None = None

    def observe(self, place: Hashable, t: float) -> int:
        """The robot entered ``place`` at time ``t`` (s): learn from the stay that ended, and
        return the context id of this entry."""
        if not isinstance(place, Hashable) or place is None:
            raise ValueError(f"place must be a hashable, non-None label, got {place!r}")
        t = float(t)
        if not math.isfinite(t):
            raise ValueError(f"t must be a finite time in seconds, got {t!r}")
        place = self.same(place)
        if self._history and self._entered is not None:
            if t < self._entered:
                raise ValueError(f"time went backwards: entered at {self._entered}, now {t}")
            prev = self.same(self._history[-1])
            if place == prev:
                return self.current  # type: ignore[return-value]
            hist = tuple(reversed(list(self._history)[:-1]))  # before prev, most recent first
            for older in self._pending:
                if len(older.future) < self.params.merge_horizon:
                    older.future.append(place)
                if len(older.future_dwell) < len(older.future) - 1:
                    older.future_dwell.append(t - self._entered)  # the stay in prev ended
            inst = _Inst(hist, place, t - self._entered, [place], [])
            self._pending.append(inst)
            self._learn(prev, inst)
            self._merge_places(prev)
            place = self.same(place)
        self._tree(place)
        self._history.append(place)
        self._entered = t
        self.current = self.context_of(place, tuple(reversed(list(self._history)[:-1])))
        return self.current

    def same(self, place: Hashable) -> Hashable:
        """The place ``place`` was merged into (itself when it never was)."""
        while place in self._same:
            place = self._same[place]
        return place

    def members(self, place: Hashable) -> list[Hashable]:
        """Every place merged into the same state as ``place`` (itself included)."""
        rep = self.same(place)
        return [q for q in [*self._trees, *self._same] if self.same(q) == rep]

    def context_of(self, place: Hashable, history: Iterable[Hashable] = ()) -> int:
        """The context id of ``place`` entered after ``history`` (most recent first)."""
        h = tuple(history)
        node = self._tree(self.same(place))
        while not node.leaf:
            node = node.step(h, self.same)
        return node.cid  # type: ignore[return-value]

    # ------------------------------------------------------------------ introspection
    @property
    def n_states(self) -> int:
        """Context states alive now (leaves of every tree)."""
        return sum(len(self._leaves(r)) for r in self._trees.values())

    def states_of(self, place: Hashable) -> list[int]:
        """The live context ids of ``place`` (one when it is not split)."""
        return [n.cid for n in self._leaves(self._tree(place))]  # type: ignore[misc]

    def key(self, cid: int) -> ContextKey:
        """What context ``cid`` stands for (a retired id: its survivor's key)."""
        return self._keys[self.resolve(cid)]

    def resolve(self, cid: int) -> int:
        """A retired (merged) id's surviving id; a live id is returned as is."""
        if isinstance(cid, bool) or not isinstance(cid, (int, np.integer)) or not \
                0 <= cid < len(self._keys):
            raise ValueError(f"unknown context id {cid!r} ({len(self._keys)} ids issued)")
        cid = int(cid)
        while cid in self._alias:
            cid = self._alias[cid]
        return cid

    def predict(self, cid: int) -> dict[Hashable, float]:
        """Next-place distribution of context ``cid`` (frequencies of its kept instances; merged
        places under the name of their state, :meth:`same`)."""
        cid = self.resolve(cid)
        place = self._keys[cid].place
        nxt = [self.same(i.next) for i in self._data.get(place, ())
               if self._leaf_of(place, i) == cid]
        counts: dict[Hashable, int] = {}
        for v in nxt:
            counts[v] = counts.get(v, 0) + 1
        try:
            order = sorted(counts)  # ascending, as np.unique gave them
        except TypeError:           # labels of mixed types: as first seen
            order = list(counts)
        return {v: counts[v] / len(nxt) for v in order}

    def describe(self, cid: int) -> str:
        """``C`` for an unsplit place, ``C|1:B`` (B one place back) or ``C|1:B,2:{A1 A2}`` for a
        context."""
        k = self.key(cid)
        if not k.history:
            return str(k.place)
        parts = [f"{j + 1}:" + (str(next(iter(s))) if len(s) == 1 else "{" + " ".join(
            map(str, sorted(s, key=str))) + "}") for j, s in k.history]
        return f"{k.place}|" + ",".join(parts)

    # ------------------------------------------------------------------ learning
    def _tree(self, place: Hashable) -> _Node:
        root = self._trees.get(place)
        if root is None:
            root = self._trees[place] = _Node(0, cid=self._new_id(place, ()))
            self._data[place] = deque(maxlen=self.params.memory)
        return root

    def _new_id(self, place: Hashable, history: tuple[frozenset, ...]) -> int:
        self._keys.append(ContextKey(place, history))
        return len(self._keys) - 1

    def _leaves(self, node: _Node) -> list[_Node]:
        return [node] if node.leaf else [x for c in node.children() for x in self._leaves(c)]

    def _leaf_of(self, place: Hashable, inst: _Inst) -> int:
        return self.context_of(place, inst.history)

    def _learn(self, place: Hashable, inst: _Inst) -> None:
        data = self._data[place]
        data.append(inst)
        # walk the instance's path; merge where children became alike, split the leaf
        path, node = [], self._trees[place]
        while not node.leaf:
            path.append(node)
            node = node.step(inst.history, self.same)
        for parent in reversed(path):
            if all(c.leaf for c in parent.children()) and self._merge(place, parent):
                return
        self._split(place, node)

    def _members(self, place: Hashable, node: _Node) -> list[_Inst]:
        """Kept instances of ``place`` routed through ``node``."""
        out = []
        for i in self._data[place]:
            n = self._trees[place]
            while n is not node and not n.leaf:
                n = n.step(i.history, self.same)
            if n is node:
                out.append(i)
        return out

    def _different(self, a: list[_Inst], b: list[_Inst], *, merge: bool = False) -> bool:
        """Do two sets of instances differ in successors or in dwell (see the docstring)?"""
        p = self.params
        alpha, z = (p.alpha_merge, self._z_merge) if merge else (p.alpha, self._z)
        if self._differ_in(a, b, lambda i: self.same(i.next), alpha):
            return True
        return self._differ_dwell([i.dwell for i in a], [i.dwell for i in b], z)

    def _differ_dwell(self, a: list[float], b: list[float], z: float) -> bool:
        """Weber-tolerant test of the mean log-dwell (see the module docstring)."""
        p = self.params
        la = np.log(np.maximum(a, 1e-9))
        lb = np.log(np.maximum(b, 1e-9))
        diff = abs(float(la.mean() - lb.mean()))
        se = math.sqrt(max(float(la.var()), p.weber**2) / len(la)
                       + max(float(lb.var()), p.weber**2) / len(lb))
        return diff > math.log1p(p.dwell_tolerance) and diff > z * se

    def _differ_in(self, a: list[_Inst], b: list[_Inst], what: Callable[[_Inst], Hashable],
                   alpha: float) -> bool:
        """G-test: do ``a`` and ``b`` differ in the distribution of ``what(instance)``?"""
        va, vb = [what(i) for i in a], [what(i) for i in b]
        vals = sorted(set(va) | set(vb), key=repr)
        table = np.array([[v.count(x) for x in vals] for v in (va, vb)])
        return g_test(table) < alpha

    def _groups(self, insts: list[_Inst], pos: int) -> list[tuple[set, list[_Inst]]]:
        """Values of ``q_{pos+1}`` grouped by alike futures (most frequent first)."""
        by: dict[Hashable, list[_Inst]] = {}
        for i in insts:
            if pos < len(i.history):
                by.setdefault(self.same(i.history[pos]), []).append(i)
        vals = sorted((v for v in by if len(by[v]) >= self.params.min_count),
                      key=lambda v: (-len(by[v]), repr(v)))
        groups: list[tuple[set, list[_Inst]]] = []
        for v in vals:
            for members, pooled in groups:
                if not self._different(by[v], pooled):
                    members.add(v)
                    pooled.extend(by[v])
                    break
            else:
                groups.append(({v}, list(by[v])))
        return groups

    def _split(self, place: Hashable, leaf: _Node) -> None:
        members = self._members(place, leaf)
        for pos in range(leaf.start, self.params.max_depth):
            groups = self._groups(members, pos)
            if len(groups) >= 2:
                break
        else:
            return
        hist = self._keys[leaf.cid].history  # type: ignore[index]
        children = [_Node(pos + 1, cid=self._new_id(place, (*hist, (pos, frozenset(vals)))))
                    for vals, _ in groups]
        self._alias[leaf.cid] = children[0].cid  # type: ignore[index]
        leaf.cid, leaf.default, leaf.pos = None, children[0], pos
        leaf.route = {v: c for (vals, _), c in zip(groups, children, strict=True) for v in vals}
        self.n_splits += 1

    def _merge(self, place: Hashable, node: _Node) -> bool:
        """Merge ``node``'s leaf children back into one leaf if none differs any more."""
        kids = node.children()
        sets = [self._members(place, c) for c in kids]
        if any(len(s) < self.params.min_count for s in sets):
            return False
        for i in range(len(kids)):
            for j in range(i + 1, len(kids)):
                if self._different(sets[i], sets[j], merge=True):
                    return False
        keep = min(c.cid for c in kids)  # type: ignore[type-var]
        for c in kids:
            if c.cid != keep:
                self._alias[c.cid] = keep  # type: ignore[index]
        self._keys[keep] = ContextKey(place, tuple(
            (j, s) for j, s in self._keys[keep].history if j < node.pos))
        node.cid, node.route, node.default, node.pos = keep, {}, None, -1
        self.n_merges += 1
        return True
