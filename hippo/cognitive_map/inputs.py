"""The drive input of the transition map, the inferred moves' mask and the transitions' hop
counts (the planner's inputs).

HIREL's drive input (sec. II): ``I(n) = max_d level(d) · W_{d,n}``, a drive below the
exploration threshold giving none; see :mod:`hippo.cognitive_map.planner`.
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Mapping
from typing import Any

import numpy as np

from hippo._checks import check_finite
from hippo.cognitive_map.drives import Drives
from hippo.cognitive_map.graph import TransitionGraph
from hippo.cognitive_map.keys import as_transition

__all__ = ["MIN_HOPS", "drive_input", "effective_levels", "hop_counts", "inferred_mask"]


def inferred_mask(graph: TransitionGraph) -> np.ndarray:
    """``mask[i]``: transition ``graph.index().nodes[i]`` is an inferred move."""
    nodes = graph.nx.nodes
    return np.fromiter((bool(nodes[t].get("inferred", False)) for t in graph.index().nodes),
                       dtype=bool, count=len(graph))


#: the fewest hops a transition counts for with ``hop_time`` (a zero edge cost is no edge
#: to the sparse shortest paths)
MIN_HOPS = 0.01


#: the last hop counts of each map: (its version, the hop time, the counts)
_HOPS: weakref.WeakKeyDictionary[TransitionGraph, tuple[int, float, np.ndarray]] = (
    weakref.WeakKeyDictionary())


def hop_counts(graph: TransitionGraph, hop_time: float) -> np.ndarray:
    """How many hops each transition ``graph.index().nodes[i]`` counts for when a hop stands
    for ``hop_time`` seconds: ``max(δ / hop_time, MIN_HOPS)`` for a learned delay ``δ``, 1 for
    a transition whose delay was never measured. Kept until the map changes (the planner
    replans at every change of a drive level; the delays change only with the map)."""
    kept = _HOPS.get(graph)
    if kept is not None and kept[0] == graph.version and kept[1] == hop_time:
        return kept[2]
    nodes = graph.nx.nodes
    d = np.fromiter((math.nan if nodes[t]["delay"] is None else nodes[t]["delay"]
                     for t in graph.index().nodes), dtype=float, count=len(graph))
    counts = np.where(np.isnan(d), 1.0, np.maximum(d / hop_time, MIN_HOPS))
    counts.flags.writeable = False
    _HOPS[graph] = (graph.version, hop_time, counts)
    return counts


def effective_levels(drives: Drives, threshold: float = 0.0) -> dict[str, float]:
    """Drive levels, with those below ``threshold`` set to 0 (inactive)."""
    return {n: (v if v >= threshold and v > 0 else 0.0) for n, v in drives.levels.items()}


def drive_input(graph: TransitionGraph, drives: Drives, threshold: float = 0.0) -> np.ndarray:
    """``I(n) = max_d level(d) · W_{d,n}`` for every transition of ``graph`` (index order).

    Drives below ``threshold`` give no input; links to transitions not in the graph are ignored.
    """
    idx = graph.index()
    inputs = np.zeros(len(idx))
    for name, level in effective_levels(drives, threshold).items():
        if level <= 0:
            continue
        for t, w in drives.links(name).items():
            i = idx.pos.get(t)
            if i is not None and level * w > inputs[i]:
                inputs[i] = level * w
    return inputs


def input_array(graph: TransitionGraph, inputs: Any) -> np.ndarray:
    idx = graph.index()
    if isinstance(inputs, Drives):
        return drive_input(graph, inputs)
    if isinstance(inputs, Mapping):
        arr = np.zeros(len(idx))
        for t, v in inputs.items():
            key = as_transition(t)
            if key not in idx.pos:
                raise KeyError(f"drive input given for unknown transition {key[0]}->{key[1]}")
            arr[idx.pos[key]] = v
    else:
        arr = np.asarray(inputs, dtype=float)
        if arr.shape != (len(idx),):
            raise ValueError(f"drive inputs must have shape ({len(idx)},), got {arr.shape}")
    check_finite("drive inputs", arr)
    if arr.size and (arr.min() < 0 or arr.max() > 1):
        raise ValueError(f"drive inputs must lie in [0, 1], got range [{arr.min()}, {arr.max()}]")
    return arr
