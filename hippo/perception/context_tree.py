"""The parts of context states (:mod:`hippo.perception.contexts`): their parameters
(:class:`ContextParams`), the key of a context state (:class:`ContextKey`), the G-test that
decides a split (:func:`g_test`) and the nodes of each place's suffix tree of histories."""

from __future__ import annotations

from collections.abc import Callable, Hashable
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from scipy.stats import chi2

from hippo._checks import check_fields, check_positive, check_range

__all__ = ["ContextKey", "ContextParams", "g_test"]

@dataclass(frozen=True)
class ContextParams:
    """Parameters of :class:`ContextStates`.

    max_depth: longest history a context may use (places before the current one; default 3).
    min_count: instances a predecessor value needs before it can found a group (default 6).
    alpha: significance of a split (G-test of the successors, or the dwell test; default 1e-3).
    alpha_merge: children merge back when no test between them reaches this (default 0.05;
        laxer than ``alpha``, so a state is not split and merged back on alternate events).
    dwell_tolerance: dwell times differ only beyond this relative difference (default 0.5).
    weber: floor on the sd of log-dwell times (default 0.1: the batteries' Weber fraction).
    memory: instances kept per place (default 256).
    merge_places: merge two places that the robot enters from the same place and leaves to the
        same place, alike in their distributions of both and in dwell (default True).
    merge_horizon: places merge only if no step of their past or future up to this many
        events apart tells them apart (default 8; longer than ``max_depth``, so that a place
        a split depends on is not merged away).
    merge_bypasses: merge a place that the robot passes through on the way from ``P`` to ``Y``
        on some passes and skips on others (``P → Y`` directly) into ``Y`` (default True).
    """

    max_depth: int = 3
    min_count: int = 6
    alpha: float = 1e-3
    alpha_merge: float = 0.05
    dwell_tolerance: float = 0.5
    weber: float = 0.1
    memory: int = 256
    merge_places: bool = True
    merge_horizon: int = 8
    merge_bypasses: bool = True

    def __post_init__(self) -> None:
        check_fields(self)
        if int(self.max_depth) != self.max_depth or self.max_depth < 0:
            raise ValueError(f"max_depth must be an integer >= 0, got {self.max_depth!r}")
        if int(self.min_count) != self.min_count or self.min_count < 2:
            raise ValueError(f"min_count must be an integer >= 2, got {self.min_count!r}")
        check_range("alpha", self.alpha, 0.0, 1.0, closed="neither")
        check_range("alpha_merge", self.alpha_merge, 0.0, 1.0, closed="neither")
        if self.alpha_merge < self.alpha:
            raise ValueError(f"alpha_merge ({self.alpha_merge}) must be >= alpha ({self.alpha})")
        check_positive("dwell_tolerance", self.dwell_tolerance, allow_zero=True)
        check_positive("weber", self.weber)
        if int(self.merge_horizon) != self.merge_horizon or self.merge_horizon < 1:
            raise ValueError(f"merge_horizon must be an integer >= 1, got {self.merge_horizon!r}")
        if int(self.memory) != self.memory or self.memory < 2 * self.min_count:
            raise ValueError(f"memory must be an integer >= 2 * min_count "
                             f"({2 * self.min_count}), got {self.memory!r}")


class ContextKey(NamedTuple):
    """What a context state stands for: ``place`` entered after a history matching ``history``
    (pairs ``(j, places)``: the place ``j`` steps back, counting from 1, is one of ``places``;
    empty: any history)."""

    place: Hashable
    history: tuple[tuple[int, frozenset], ...]


def g_test(table: np.ndarray) -> float:
    """p-value of the G-test of independence on a contingency table (rows: groups).

    ``G = 2 Σ O ln(O / E)`` with ``E`` the product of the margins over the total; ``G`` is
    χ²-distributed with ``(rows − 1)(columns − 1)`` degrees of freedom (empty rows and
    columns are dropped). Returns 1.0 when there is nothing to test."""
    o = np.asarray(table, dtype=float)
    if o.ndim != 2 or np.any(o < 0) or not np.all(np.isfinite(o)):
        raise ValueError(f"table must be a 2-D array of counts >= 0, got {table!r}")
    o = o[o.sum(axis=1) > 0][:, o.sum(axis=0) > 0]
    if o.shape[0] < 2 or o.shape[1] < 2:
        return 1.0
    e = o.sum(axis=1, keepdims=True) * o.sum(axis=0, keepdims=True) / o.sum()
    nz = o > 0
    g = 2.0 * float(np.sum(o[nz] * np.log(o[nz] / e[nz])))
    df = (o.shape[0] - 1) * (o.shape[1] - 1)
    return float(chi2.sf(g, df))


class _Inst(NamedTuple):
    history: tuple
    next: Hashable
    dwell: float
    future: list   # next, and the places after it as they come (up to merge_horizon)
    future_dwell: list  # the stays in those places, as they end


@dataclass(eq=False)
class _Node:
    start: int                                      # first history index it may split on
    pos: int = -1                                   # internal: history index it routes on
    cid: int | None = None                          # leaf: its context id
    route: dict = field(default_factory=dict)       # internal: predecessor value -> child
    default: _Node | None = None                    # internal: child for rare/unseen values

    @property
    def leaf(self) -> bool:
        return self.cid is not None

    def child(self, value: Hashable) -> _Node:
        return self.route.get(value, self.default)  # type: ignore[return-value]

    def step(self, history: tuple, same: Callable[[Hashable], Hashable]) -> _Node:
        """The child an instance with ``history`` goes to (places read through ``same``)."""
        return self.child(same(history[self.pos])) if self.pos < len(history) \
            else self.default  # type: ignore[return-value]

    def children(self) -> list[_Node]:
        out: list[_Node] = []
        for c in [*self.route.values(), self.default]:
            if c is not None and all(c is not o for o in out):
                out.append(c)
        return out
