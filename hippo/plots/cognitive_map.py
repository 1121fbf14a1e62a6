"""Figure of the cognitive map over its arena (HIREL Fig. 5a / Fig. 7a).

Place centres are circles, transitions arrows between state positions (coloured by their drive
activity when one is given), wait transitions squares (HIREL's proprioceptive events), goal
transitions red stars, and an optional path (e.g. :meth:`Planner.plan`) a thick line. Arena walls
are an optional list of segments ``((x0, y0), (x1, y1))`` so that this module does not depend on
:mod:`hippo.sim`. Figures are plain ``matplotlib.figure.Figure`` objects (no pyplot, no global
backend switch); ``fig.savefig`` renders them with Agg.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence

import networkx as nx
import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure

from hippo.cognitive_map.drives import Drives
from hippo.cognitive_map.graph import Transition, TransitionGraph
from hippo.cognitive_map.planner import Activity

Segment = tuple[tuple[float, float], tuple[float, float]]


def state_layout(graph: TransitionGraph, seed: int = 0) -> dict[int, np.ndarray]:
    """Positions of every state: the stored ones, the others by a spring layout around them."""
    known = {s: np.asarray(p, dtype=float) for s, p in graph.positions.items()}
    states = sorted(graph.states)
    missing = [s for s in states if s not in known]
    if not missing:
        return known
    sg = nx.DiGraph()
    sg.add_nodes_from(states)
    sg.add_edges_from(t for t in graph if t[0] != t[1])
    if known:
        pts = np.array(list(known.values()))
        span = float(np.ptp(pts, axis=0).max()) or 1.0
        pos = nx.spring_layout(sg.to_undirected(), pos=dict(known), fixed=list(known), seed=seed,
                               scale=span)
    else:
        pos = nx.spring_layout(sg.to_undirected(), seed=seed)
    return {s: np.asarray(pos[s], dtype=float) for s in states}


def plot_cognitive_map(graph: TransitionGraph, activity: Activity | Mapping[Transition, float]
                       | None = None, drives: Drives | None = None, *,
                       walls: Iterable[Segment] | None = None, path: Sequence[Transition] = (),
                       ax: Axes | None = None, positions: Mapping[int, Sequence[float]]
                       | None = None, cmap: str = "viridis", log_activity: bool = True,
                       labels: bool | None = None, title: str | None = None,
                       restrict: bool = False) -> tuple[Figure, Axes]:
    """Draw ``graph`` over its arena; returns ``(fig, ax)``.

    activity:  per-transition activity (an :class:`Activity` or mapping); arrows take its colour
               (log10 scale if ``log_activity``, since it falls as ``w^hops``).
    drives:    marks the goal transitions linked to these drives (red stars, named).
    walls:     arena wall segments ``((x0, y0), (x1, y1))``.
    path:      transitions to highlight (e.g. a plan).
    positions: state → (x, y), overriding the graph's stored positions.
    labels:    write state ids (default: when there are at most 60 states).
    restrict:  draw only the states given in ``positions`` and the transitions between them
               (positions from another frame, such as path integration, are not mixed in).
    """
    if ax is None:
        fig = Figure(figsize=(6.5, 6.5), layout="constrained")
        ax = fig.add_subplot(1, 1, 1)
    else:
        fig = ax.figure
    pos = {} if restrict and positions is not None else state_layout(graph)
    if positions is not None:
        pos.update({int(s): np.asarray(p, dtype=float) for s, p in positions.items()})

    if walls is not None:
        segs = [np.asarray(s, dtype=float) for s in walls]
        if segs:
            ax.add_collection(LineCollection(segs, colors="k", linewidths=2.0, zorder=1))

    if isinstance(activity, Activity):
        act = activity.as_dict()
    else:
        act = dict(activity) if activity is not None else None

    drawn = [t for t in graph if t[0] in pos and t[1] in pos]
    moves = [t for t in drawn if t[0] != t[1] and graph.action(t).kind == "move"]
    waits = [t for t in drawn if t not in set(moves)]
    scale = np.ptp(np.array(list(pos.values())), axis=0).max() if pos else 1.0
    scale = float(scale) or 1.0
    off = 0.012 * scale

    if moves:
        p0 = np.array([pos[t[0]] for t in moves])
        p1 = np.array([pos[t[1]] for t in moves])
        d = p1 - p0
        length = np.hypot(d[:, 0], d[:, 1])
        length[length == 0] = 1.0
        unit = d / length[:, None]
        normal = np.stack([-unit[:, 1], unit[:, 0]], axis=1)
        # from the rim of A's circle to the rim of B's (offset sideways so that A->B and B->A
        # do not overlap); very short transitions keep a tenth of their length
        rim = np.minimum(2.2 * off, 0.45 * length)[:, None]
        start = p0 + off * normal + rim * unit
        vec = d - 2 * rim * unit
        kw = dict(angles="xy", scale_units="xy", scale=1.0, width=0.004, headwidth=4,
                  headlength=5, zorder=2)
        if act is not None:
            vals = np.array([act.get(t, 0.0) for t in moves])
            if log_activity:
                pos_vals = vals[vals > 0]
                floor = pos_vals.min() if pos_vals.size else 1.0
                c = np.log10(np.maximum(vals, floor))
                clabel = "drive activity, log10 (× w per transition from the goal)"
            else:
                c, clabel = vals, "activity"
            q = ax.quiver(start[:, 0], start[:, 1], vec[:, 0], vec[:, 1], c, cmap=cmap, **kw)
            fig.colorbar(q, ax=ax, shrink=0.7, label=clabel)
        else:
            ax.quiver(start[:, 0], start[:, 1], vec[:, 0], vec[:, 1], color="0.45", **kw)

    if waits:
        wp = np.array([pos[t[0]] for t in waits])
        ax.scatter(wp[:, 0] + 2 * off, wp[:, 1] + 2 * off, marker="s", s=40, c="k", zorder=4,
                   label="wait transition")

    if pos:
        states = sorted(pos)
        sp = np.array([pos[s] for s in states])
        ax.scatter(sp[:, 0], sp[:, 1], s=120, facecolors="white", edgecolors="k", zorder=3,
                   label="place")
        if labels is None:
            labels = len(states) <= 60
        if labels:
            for s, (x, y) in zip(states, sp, strict=True):
                ax.text(x, y, str(s), ha="center", va="center", fontsize=6, zorder=5,
                        clip_on=True)

    if drives is not None:
        first = True
        for t, names in drives.goals.items():
            if t not in graph or t[0] not in pos or t[1] not in pos:
                continue
            a, b = pos[t[0]], pos[t[1]]
            m = a + 0.8 * (b - a) if t[0] != t[1] else a
            ax.scatter([m[0]], [m[1]], marker="*", s=220, c="red", edgecolors="k", zorder=6,
                       label="goal transition" if first else None)
            ax.annotate(", ".join(names), m, textcoords="offset points", xytext=(6, 6),
                        fontsize=7, color="darkred", zorder=6, annotation_clip=True)
            first = False

    if path:
        pts = [pos[path[0][0]]] + [pos[t[1]] for t in path]
        pts_arr = np.array(pts)
        ax.plot(pts_arr[:, 0], pts_arr[:, 1], "-", color="orange", lw=3, alpha=0.8, zorder=2.5,
                label="plan")

    ax.set_aspect("equal", adjustable="box")
    ax.autoscale_view()
    ax.set_xlabel("x (cm)")
    ax.set_ylabel("y (cm)")
    if title:
        ax.set_title(title)
    handles, _ = ax.get_legend_handles_labels()
    if handles:
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=4, fontsize=7,
                  frameon=False)
    return fig, ax
