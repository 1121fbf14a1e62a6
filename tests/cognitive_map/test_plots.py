"""The cognitive-map figure renders with and without positions, walls, activity and a plan."""

from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure

from hippo.cognitive_map import DriveParams, Drives, Planner, PlannerParams, TransitionGraph
from hippo.plots.cognitive_map import plot_cognitive_map, state_layout


def small_map(with_positions: bool) -> TransitionGraph:
    g = TransitionGraph()
    for i in range(5):
        g.add_transition(i, i + 1, (0.0, 20.0), 2.0)
        g.add_transition(i + 1, i, (math.pi, 20.0), 2.0)
        if with_positions:
            g.set_position(i, (20.0 * i, 5.0 * (i % 2)))
    g.add_transition(2, 2, "wait", 6.0)
    return g


def test_figure_with_everything(tmp_path):
    g = small_map(True)
    d = Drives({"sound": DriveParams(learning_rate=1.0)})
    d.link("sound", (4, 5))
    d.set_level("sound", 0.7)
    planner = Planner(PlannerParams(noise=0.0))
    walls = [((-10, -10), (110, -10)), ((110, -10), (110, 20)), ((-10, 20), (-10, -10))]
    fig, ax = plot_cognitive_map(g, planner.activity(g, d), d, walls=walls,
                                 path=planner.plan(g, d, 0), title="map")
    assert isinstance(fig, Figure) and ax is fig.axes[0]
    out = tmp_path / "map.png"
    fig.savefig(out, dpi=60)
    assert out.stat().st_size > 1000
    ax = fig.axes[0]
    assert ax.get_title() == "map" and len(fig.axes) == 2  # map + colour bar
    assert "goal transition" in ax.get_legend_handles_labels()[1]


def test_figure_without_positions_uses_a_layout_and_given_axes():
    g = small_map(False)
    pos = state_layout(g)
    assert set(pos) == g.states and all(np.all(np.isfinite(p)) for p in pos.values())
    fig = Figure()
    ax = fig.add_subplot(1, 2, 2)
    assert plot_cognitive_map(g, ax=ax) == (fig, ax)
    partial = small_map(True)  # state 5 has no position: placed around the others
    assert set(state_layout(partial)) == partial.states
