"""Folding a repeat of a transition into its attributes: running means, kept exactly.

Merging a repeat updates running means: the distance, the delay, and the heading as an exact
circular mean. With ``S_n = Σ (cos θ_k, sin θ_k) = n R_n (cos h_n, sin h_n)`` (``h`` = heading,
``R`` = ``heading_r``), a new heading ``θ`` gives ``S_{n+1} = S_n + (cos θ, sin θ)``,
``h_{n+1} = atan2(S_{n+1})``, ``R_{n+1} = |S_{n+1}| / (n+1)`` — the same as the circular mean of all
samples, without storing them. The kind (move/wait) is the majority kind (a tie keeps ``move``).
Used by :meth:`hippo.cognitive_map.graph.TransitionGraph.add_transition`.
"""

from __future__ import annotations

import math
from typing import Any

from hippo.cognitive_map.actions import MOVE, WAIT, Action, wrap_exact

__all__ = ["merge_repeat"]


def merge_repeat(d: dict[str, Any], act: Action, delay: float | None,
                 time: float | None) -> None:
    """Fold one more sample (``act``, ``delay`` s, at ``time``) into the attributes ``d`` of a
    known transition, in place; its strength goes back to 1."""
    n_move = d["count"] - d["n_wait"]
    if act.is_wait:
        d["n_wait"] += 1
    else:
        if n_move == 0 or d["heading"] is None:
            d["heading"], d["heading_r"], d["distance"] = act.heading, 1.0, act.distance
        else:
            r = d["heading_r"] * n_move
            sx = r * math.cos(d["heading"]) + math.cos(act.heading)
            sy = r * math.sin(d["heading"]) + math.sin(act.heading)
            d["heading"] = wrap_exact(math.atan2(sy, sx))
            d["heading_r"] = min(1.0, math.hypot(sx, sy) / (n_move + 1))
            d["distance"] += (act.distance - d["distance"]) / (n_move + 1)
    d["count"] += 1
    d["action"] = WAIT if 2 * d["n_wait"] > d["count"] else MOVE
    if delay is not None:
        d["n_delay"] += 1
        d["delay"] = delay if d["delay"] is None else (
            d["delay"] + (delay - d["delay"]) / d["n_delay"])
    d["strength"] = 1.0
    if time is not None:
        d["last_used"] = time
