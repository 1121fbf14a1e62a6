"""The planner's fast form: the map as sparse graphs and one multi-source Dijkstra over them.

:func:`state_pattern` (the reversed state graph, one edge ``b → a`` per transition ``a→b``) and
:func:`transition_pattern` (the reversed transition graph, ``A→B → B→C`` read backwards) are
CSR patterns with one spare row for a virtual super-source, built once per structure change
(cached on the graph). :func:`_dijkstra_from_goals` solves the ``−log`` form of the drive
propagation on either: see "Fast form" in :mod:`hippo.cognitive_map.planner`.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import dijkstra

from hippo.cognitive_map.graph import TransitionGraph

__all__ = ["state_pattern", "transition_pattern"]

_K = 1.0  # offset of the super-source edges (keeps them strictly positive)


def _csr_pattern(rows: np.ndarray, cols: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(indptr, indices) of an n×n pattern with entries (rows[k], cols[k]) (no duplicates)."""
    order = np.lexsort((cols, rows))
    indices = cols[order].astype(np.int32)
    indptr = np.zeros(n + 2, dtype=np.int32)  # one spare row for the super-source
    np.cumsum(np.bincount(rows, minlength=n), out=indptr[1:n + 1])
    indptr[n + 1] = indptr[n]
    return indptr, indices


def state_pattern(graph: TransitionGraph) -> tuple[np.ndarray, np.ndarray]:
    """Reversed state graph (edge ``b → a`` per transition ``a→b``), cached per structure."""
    def build() -> tuple[np.ndarray, np.ndarray]:
        idx = graph.index()
        return _csr_pattern(idx.b_s, idx.a_s, len(idx.states))
    return graph.cached("planner.state_pattern", build)


def _state_order(graph: TransitionGraph) -> np.ndarray:
    """The transition behind each entry of :func:`state_pattern` (its storage order)."""
    def build() -> np.ndarray:
        idx = graph.index()
        return np.lexsort((idx.a_s, idx.b_s))
    return graph.cached("planner.state_order", build)


def transition_pattern(graph: TransitionGraph) -> tuple[np.ndarray, np.ndarray]:
    """Reversed transition graph (edge ``j → i`` when ``i = x→s`` and ``j = s→y``), cached."""
    def build() -> tuple[np.ndarray, np.ndarray]:
        idx = graph.index()
        n, ns = len(idx), len(idx.states)
        ones = np.ones(n, dtype=np.int8)
        ar = np.arange(n)
        starts = sp.csr_array((ones, (ar, idx.a_s)), shape=(n, ns))  # j starts at s
        ends = sp.csr_array((ones, (idx.b_s, ar)), shape=(ns, n))    # i ends at s
        rev = (starts @ ends).tocoo()                                # rev[j, i] = 1
        return _csr_pattern(rev.row.astype(np.int64), rev.col.astype(np.int64), n)
    return graph.cached("planner.transition_pattern", build)


def _dijkstra_from_goals(indptr: np.ndarray, indices: np.ndarray, n: int,
                         edge_cost: float | np.ndarray, goal_nodes: np.ndarray,
                         goal_costs: np.ndarray) -> np.ndarray:
    """Shortest cost to every node from a super-source with edges ``goal → K + cost``."""
    # One start cost per goal node: the smallest.
    order = np.lexsort((goal_costs, goal_nodes))
    g, c = goal_nodes[order], goal_costs[order]
    first = np.ones(len(g), dtype=bool)
    first[1:] = g[1:] != g[:-1]
    g, c = g[first], c[first]
    nnz = len(indices)
    data = np.empty(nnz + len(g))
    data[:nnz] = edge_cost
    data[nnz:] = _K + c
    ptr = indptr.copy()
    ptr[n + 1] = nnz + len(g)
    mat = sp.csr_array((data, np.concatenate([indices, g.astype(np.int32)]), ptr),
                       shape=(n + 1, n + 1))
    dist = dijkstra(mat, directed=True, indices=n)
    return dist[:n] - _K
