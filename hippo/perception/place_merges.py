"""Merging places, the opposite of a context split (:mod:`hippo.perception.contexts`).

Two learned places can stand for one stretch of track: two prototypes that win on alternate
laps (the robot sees ``A → B → D`` on one lap and ``A → C → D`` on the next), or a field that
wins only on some passes, for a moment, at the start of the next one's stretch (``P → X → Y``
on some passes, ``P → Y`` on others). :class:`PlaceMerges` holds what
:class:`~hippo.perception.contexts.ContextStates` does about it after each stay: it merges a
place into another when each has a usual way in and out, these are the same for both, and no
step of their past or future up to ``merge_horizon`` events away (nor the stays after them)
differs; and it merges a bypassed place into the place it leads to. A merged place starts
again unsplit, under the oldest of the two places' context ids.

It is a part of :class:`~hippo.perception.contexts.ContextStates` (which inherits it), and
works on that class's state: its parameters, its kept instances and trees by place, its
tests of difference and its id aliases.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable

from hippo.perception.context_tree import ContextKey, _Inst, _Node

__all__ = ["PlaceMerges"]


class PlaceMerges:
    """How :class:`~hippo.perception.contexts.ContextStates` merges places (see the module
    docstring); it reads and changes that class's state."""

    def _merge_places(self, place: Hashable) -> None:
        """Merge ``place`` into another place entered from and left to the same places."""
        p = self.params
        if not p.merge_places:
            return

        def pred(i: _Inst) -> Hashable:
            return self.same(i.history[0])

        def succ(i: _Inst) -> Hashable:
            return self.same(i.next)

        def top(insts: list[_Inst], f: Callable[[_Inst], Hashable]) -> Hashable:
            counts: dict[Hashable, int] = {}
            for i in insts:
                counts[f(i)] = counts.get(f(i), 0) + 1
            return max(counts, key=lambda v: (counts[v], repr(v)))

        mine = [i for i in self._data[place] if i.history]
        if len(mine) < p.min_count:
            return
        tp, ts = top(mine, pred), top(mine, succ)
        if min(sum(pred(i) == tp for i in mine), sum(succ(i) == ts for i in mine)) < \
                0.5 * len(mine):
            return  # no usual way in and out: nothing says another place is the same
        if p.merge_bypasses and ts in self._data and ts != tp:
            # a bypass: the robot goes tp -> place -> ts on some passes and tp -> ts on others
            direct = [i for i in self._data[ts] if i.history and pred(i) != place]
            if (sum(pred(i) == tp for i in direct) >= p.min_count
                    and top(direct, pred) == tp):
                self._join(ts, place)
                return
        for other in list(self._trees):
            if other == place or other in (tp, ts):
                continue
            theirs = [i for i in self._data[other] if i.history]
            if (len(theirs) < p.min_count or top(theirs, pred) != tp
                    or top(theirs, succ) != ts
                    or self._differ_dwell([i.dwell for i in mine], [i.dwell for i in theirs],
                                          self._z_merge)
                    or self._differ_around(mine, theirs)):
                continue
            keep, gone = (other, place) if len(self._data[other]) >= len(self._data[place]) \
                else (place, other)
            self._join(keep, gone)
            return

    def _differ_around(self, a: list[_Inst], b: list[_Inst]) -> bool:
        """Do ``a`` and ``b`` differ in any step of their past or future (``merge_horizon``)?
        Until each step has ``min_count`` instances on both sides, they count as different."""
        p = self.params
        for k in range(p.merge_horizon):
            for seq in ("history", "future"):
                aa = [i for i in a if len(getattr(i, seq)) > k]
                bb = [i for i in b if len(getattr(i, seq)) > k]
                if min(len(aa), len(bb)) < p.min_count:
                    return True  # not seen enough yet to call them the same
                if self._differ_in(aa, bb, lambda i, s=seq, k=k: self.same(getattr(i, s)[k]),
                                   p.alpha_merge):
                    return True
            da = [i.future_dwell[k] for i in a if len(i.future_dwell) > k]
            db = [i.future_dwell[k] for i in b if len(i.future_dwell) > k]
            if min(len(da), len(db)) >= p.min_count and self._differ_dwell(da, db, self._z_merge):
                return True
        return False

    def _join(self, keep: Hashable, gone: Hashable) -> None:
        """``gone`` becomes the same state as ``keep``: one unsplit place again, whose id is the
        oldest of their contexts (the others are retired into it)."""
        self._same[gone] = keep
        data = self._data[keep]
        for i in self._data.pop(gone):
            data.append(i)
        leaves = self._leaves(self._trees[keep]) + self._leaves(self._trees.pop(gone))
        root = min(n.cid for n in leaves)  # type: ignore[type-var]
        for n in leaves:
            if n.cid != root:
                self._alias[n.cid] = root  # type: ignore[index]
        self._trees[keep] = _Node(0, cid=root)
        self._keys[root] = ContextKey(keep, ())
        self.n_place_merges += 1
