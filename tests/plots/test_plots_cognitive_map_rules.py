"""The cognitive map's figure, read back from its Axes on a hand-made map.

States 0 (0, 0), 1 (100, 0), 2 (100, 50), 3 (100, 4) and 4 (0, 0): the positions span 100 cm,
so the sideways offset is off = 0.012 x 100 = 1.2 and an arrow leaves 2.2 off = 2.64 at each
rim (0.45 of a shorter transition's length). 0 -> 1 starts at (0, 0) + 1.2 (0, 1) + 2.64 (1, 0)
= (2.64, 1.2) and runs 100 - 5.28 = 94.72; 1 -> 0 starts at (97.36, -1.2); 1 -> 3 (4 cm)
keeps rim 1.8: from (98.8, 1.8) by (0, 0.4); 0 -> 4 (0 cm) stays at (0, 0). Waits (a wait
action, or a move onto itself) are squares at their state + 2 off. Goals are red stars 0.8
of the way (at the state for a self-loop), a plan an orange line through its states.
"""

from __future__ import annotations

import math

import networkx as nx
import numpy as np
import pytest
from matplotlib.collections import LineCollection, PathCollection
from matplotlib.colors import to_rgba
from matplotlib.figure import Figure
from matplotlib.markers import MarkerStyle
from matplotlib.quiver import Quiver

from hippo.cognitive_map import DriveParams, Drives, TransitionGraph
from hippo.cognitive_map.planner import Activity
from hippo.plots.cognitive_map import plot_cognitive_map, state_layout

POS = {0: (0.0, 0.0), 1: (100.0, 0.0), 2: (100.0, 50.0), 3: (100.0, 4.0), 4: (0.0, 0.0)}
MOVES = [(0, 1), (1, 0), (1, 3), (0, 4)]


def graph(positions: bool = True) -> TransitionGraph:
    g = TransitionGraph()
    g.add_transition(0, 1, (0.0, 100.0))
    g.add_transition(1, 0, (math.pi, 100.0))
    g.add_transition(1, 3, (math.pi / 2, 4.0))
    g.add_transition(1, 2, "wait", 3.0)
    g.add_transition(0, 4, (0.0, 1.0))
    g.add_transition(2, 2, "wait", 6.0)
    if positions:
        for s, p in POS.items():
            g.set_position(s, p)
    return g


def colours(q: Quiver) -> np.ndarray:
    """The arrows' colour values, a masked (non-finite) one as nan."""
    return np.ma.filled(np.ma.masked_invalid(q.get_array()).astype(float), np.nan)


def quiver(ax) -> Quiver:
    (q,) = [c for c in ax.collections if isinstance(c, Quiver)]
    return q


def scatter(ax, label: str) -> PathCollection:
    (s,) = [c for c in ax.collections if isinstance(c, PathCollection) and c.get_label() == label]
    return s


def marker_path(name: str) -> list[list[float]]:
    m = MarkerStyle(name)
    return m.get_path().transformed(m.get_transform()).vertices.tolist()


def test_arrows_from_rim_to_rim_offset_sideways():
    fig, ax = plot_cognitive_map(graph())
    assert isinstance(fig, Figure) and fig.axes == [ax]
    assert ax.get_subplotspec().get_geometry() == (1, 1, 0, 0)
    assert tuple(fig.get_size_inches()) == (6.5, 6.5)
    assert fig.get_layout_engine().__class__.__name__ == "ConstrainedLayoutEngine"
    q = quiver(ax)
    np.testing.assert_allclose(q.X, [2.64, 97.36, 98.8, 0.0])
    np.testing.assert_allclose(q.Y, [1.2, -1.2, 1.8, 0.0])
    np.testing.assert_allclose(q.U, [94.72, -94.72, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(q.V, [0.0, 0.0, 0.4, 0.0], atol=1e-12)
    assert (q.angles, q.scale_units, q.scale) == ("xy", "xy", 1.0)
    assert (q.width, q.headwidth, q.headlength, q.get_zorder()) == (0.004, 4, 5, 2)
    assert q.get_facecolor().tolist() == [list(to_rgba("0.45"))]


def test_waits_places_and_their_numbers():
    _, ax = plot_cognitive_map(graph())
    w = scatter(ax, "wait transition")
    assert np.asarray(w.get_offsets()).tolist() == [[102.4, 2.4], [102.4, 52.4]]
    assert list(w.get_sizes()) == [40] and w.get_zorder() == 4
    assert w.get_facecolor().tolist() == [list(to_rgba("k"))]
    assert w.get_paths()[0].vertices.tolist() == marker_path("s")
    p = scatter(ax, "place")
    assert np.asarray(p.get_offsets()).tolist() == [list(POS[s]) for s in range(5)]
    assert list(p.get_sizes()) == [120] and p.get_zorder() == 3
    assert p.get_facecolor().tolist() == [list(to_rgba("white"))]
    assert p.get_edgecolor().tolist() == [list(to_rgba("k"))]
    assert [t.get_text() for t in ax.texts] == ["0", "1", "2", "3", "4"]
    for t, s in zip(ax.texts, range(5), strict=True):
        assert t.get_position() == POS[s]
        assert (t.get_ha(), t.get_va(), t.get_fontsize(), t.get_zorder()) == (
            "center", "center", 6, 5)
        assert t.get_clip_on()
    assert ax.get_aspect() == 1.0 and ax.get_adjustable() == "box"
    assert (ax.get_xlabel(), ax.get_ylabel(), ax.get_title()) == ("x (cm)", "y (cm)", "")
    leg = ax.get_legend()
    assert [t.get_text() for t in leg.get_texts()] == ["wait transition", "place"]
    assert leg._loc == 9 and leg._ncols == 4 and not leg.get_frame_on()
    assert leg.get_texts()[0].get_fontsize() == 7
    assert leg._bbox_to_anchor._bbox.bounds == (0.5, -0.12, 0.0, 0.0)
    x0, x1 = ax.get_xlim()
    assert x0 <= 0.0 and x1 >= 102.4            # autoscaled over what is drawn


def test_a_move_onto_itself_is_a_wait_square():
    g = TransitionGraph()
    g.add_transition(0, 0, (0.0, 5.0))
    g.set_position(0, (10.0, 20.0))
    _, ax = plot_cognitive_map(g)
    assert not [c for c in ax.collections if isinstance(c, Quiver)]
    # one state: no span, so off = 0.012 x 1
    assert np.asarray(scatter(ax, "wait transition").get_offsets()).tolist() == [
        [10.024, 20.024]]


def test_numbers_up_to_60_states_unless_asked():
    g = TransitionGraph()
    for s in range(61):
        g.add_state(s, (float(s), 0.0))
    assert len(plot_cognitive_map(g)[1].texts) == 0
    assert len(plot_cognitive_map(g, labels=True)[1].texts) == 61
    g60 = TransitionGraph()
    for s in range(60):
        g60.add_state(s, (float(s), 0.0))
    assert len(plot_cognitive_map(g60)[1].texts) == 60
    assert len(plot_cognitive_map(g60, labels=False)[1].texts) == 0


def test_activity_colours_on_a_log_scale_with_the_smallest_positive_as_floor():
    act = {(0, 1): 0.01, (1, 0): 1.0, (1, 3): 0.0}            # (0, 4) missing: 0
    fig, ax = plot_cognitive_map(graph(), act, cmap="plasma")
    q = quiver(ax)
    np.testing.assert_array_equal(colours(q), [-2.0, 0.0, -2.0, -2.0])
    np.testing.assert_allclose(q.X, [2.64, 97.36, 98.8, 0.0])
    np.testing.assert_allclose(q.U, [94.72, -94.72, 0.0, 0.0], atol=1e-12)
    assert (q.angles, q.scale_units, q.scale) == ("xy", "xy", 1.0)
    assert (q.width, q.headwidth, q.headlength, q.get_zorder()) == (0.004, 4, 5, 2)
    assert q.get_cmap().name == "plasma"
    assert len(fig.axes) == 2
    cb = q.colorbar
    assert cb.ax.get_ylabel() == "drive activity, log10 (× w per transition from the goal)"
    assert cb.ax._colorbar_info["shrink"] == 0.7
    _, ax = plot_cognitive_map(graph(), act, log_activity=False)
    q = quiver(ax)
    np.testing.assert_array_equal(colours(q), [0.01, 1.0, 0.0, 0.0])
    assert q.get_cmap().name == "viridis" and q.colorbar.ax.get_ylabel() == "activity"
    _, ax = plot_cognitive_map(graph(), {(0, 1): 0.0})           # nothing positive: floor 1
    np.testing.assert_array_equal(colours(quiver(ax)), [0.0, 0.0, 0.0, 0.0])


def test_an_activity_object_is_read_as_its_dict():
    g = graph()
    index = g.index()
    values = np.array([10.0 ** -(k + 1) for k in range(len(index.nodes))])
    act = Activity(index=index, values=values, inputs=np.zeros(len(values)))
    _, ax = plot_cognitive_map(g, act)
    want = [-(list(index.nodes).index(t) + 1.0) for t in MOVES]
    np.testing.assert_allclose(colours(quiver(ax)), want)


def test_goal_stars_named_by_their_drives():
    d = Drives({"sound": DriveParams(learning_rate=1.0), "food": DriveParams(learning_rate=1.0)})
    d.link("sound", (0, 1))
    d.link("food", (0, 1))
    d.link("food", (7, 8))              # not in the map
    d.link("food", (0, 2))              # not in the map, though 0 and 2 are drawn
    d.link("sound", (2, 2))
    d.link("food", (1, 2))
    g = graph()
    _, ax = plot_cognitive_map(g, drives=d, positions={s: POS[s] for s in (0, 1, 2)},
                               restrict=True)
    stars = [c for c in ax.collections if isinstance(c, PathCollection)
             and c.get_paths()[0].vertices.tolist() == marker_path("*")]
    where = [np.asarray(s.get_offsets()).tolist() for s in stars]
    assert sorted(where) == sorted([[[80.0, 0.0]], [[100.0, 50.0]], [[100.0, 40.0]]])
    assert [s.get_label() for s in stars].count("goal transition") == 1
    assert stars[0].get_label() == "goal transition"
    for s in stars:
        assert list(s.get_sizes()) == [220] and s.get_zorder() == 6
        assert s.get_facecolor().tolist() == [list(to_rgba("red"))]
        assert s.get_edgecolor().tolist() == [list(to_rgba("k"))]
    notes = {a.get_text(): tuple(a.xy) for a in ax.texts if a.get_text() not in "0123"}
    assert notes == {"sound, food": (80.0, 0.0), "sound": (100.0, 50.0),
                     "food": (100.0, 40.0)}
    for a in ax.texts:
        if a.get_text() in notes:
            assert a.xyann == (6, 6) and a.anncoords == "offset points"
            assert (a.get_fontsize(), a.get_color(), a.get_zorder()) == (7, "darkred", 6)
            assert a.get_annotation_clip() is True
    # a goal whose state is not drawn is left out, at either end
    _, ax = plot_cognitive_map(g, drives=d, positions={0: POS[0], 1: POS[1]}, restrict=True)
    assert sorted(a.get_text() for a in ax.texts) == ["0", "1", "sound, food"]
    _, ax = plot_cognitive_map(g, drives=d, positions={0: POS[0], 2: POS[2]}, restrict=True)
    assert sorted(a.get_text() for a in ax.texts) == ["0", "2", "sound"]


def test_a_plan_walls_a_title_and_given_axes():
    fig = Figure()
    given = fig.add_subplot(1, 2, 2)
    given.set_adjustable("datalim")                  # the map's own: box
    walls = [((-10.0, -10.0), (110.0, -10.0)), ((110.0, -10.0), (110.0, 60.0))]
    out = plot_cognitive_map(graph(), walls=walls, path=[(0, 1), (1, 3)], ax=given,
                             title="plan")
    assert out == (fig, given)
    (lc,) = [c for c in given.collections if type(c) is LineCollection]
    assert [s.tolist() for s in lc.get_segments()] == [[list(a), list(b)] for a, b in walls]
    assert lc.get_colors().tolist() == [list(to_rgba("k"))]
    assert list(lc.get_linewidths()) == [2.0] and lc.get_zorder() == 1
    (plan,) = given.lines
    assert plan.get_xdata().tolist() == [0.0, 100.0, 100.0]
    assert plan.get_ydata().tolist() == [0.0, 0.0, 4.0]
    assert (plan.get_color(), plan.get_linewidth(), plan.get_alpha()) == ("orange", 3, 0.8)
    assert (plan.get_linestyle(), plan.get_zorder(), plan.get_label()) == ("-", 2.5, "plan")
    assert given.get_title() == "plan" and given.get_adjustable() == "box"
    assert given.get_xlim()[0] <= -10 and given.get_ylim()[1] >= 60
    _, ax = plot_cognitive_map(graph(), walls=[])
    assert not [c for c in ax.collections if type(c) is LineCollection]


def test_positions_given_override_or_restrict():
    g = graph()
    _, ax = plot_cognitive_map(g, positions={1: (50, 60)})
    offs = np.asarray(scatter(ax, "place").get_offsets()).tolist()
    assert offs == [list(POS[0]), [50.0, 60.0], *[list(POS[s]) for s in (2, 3, 4)]]
    _, ax = plot_cognitive_map(g, positions={0: (0, 0), 1: (10, 0)}, restrict=True)
    assert np.asarray(scatter(ax, "place").get_offsets()).tolist() == [[0, 0], [10, 0]]
    q = quiver(ax)           # only 0 -> 1 and 1 -> 0; span 10: off 0.12, rim 0.264
    np.testing.assert_allclose(q.X, [0.264, 9.736])
    np.testing.assert_allclose(q.Y, [0.12, -0.12])
    _, ax = plot_cognitive_map(g, restrict=True)        # restrict without positions: all
    assert len(scatter(ax, "place").get_offsets()) == 5


def test_an_empty_map_draws_nothing_and_no_legend():
    fig, ax = plot_cognitive_map(TransitionGraph(), title="empty")
    assert ax.get_legend() is None and len(ax.collections) == 0
    assert ax.get_title() == "empty" and fig.axes == [ax]


def test_state_layout_keeps_the_stored_positions_and_springs_the_others():
    g = graph()
    lay = state_layout(g)
    assert set(lay) == set(POS) and all(lay[s].tolist() == list(POS[s]) for s in POS)
    partial = graph(positions=False)
    partial.set_position(0, (0.0, 0.0))
    partial.set_position(1, (30.0, 10.0))
    lay = state_layout(partial, seed=3)
    assert lay[0].tolist() == [0.0, 0.0] and lay[1].tolist() == [30.0, 10.0]
    # the recipe: the states' undirected moves (self-loops left out), the stored ones fixed
    sg = nx.Graph()
    sg.add_nodes_from(range(5))
    sg.add_edges_from([(0, 1), (1, 3), (1, 2), (0, 4)])
    want = nx.spring_layout(sg, pos={0: (0.0, 0.0), 1: (30.0, 10.0)}, fixed=[0, 1], seed=3,
                            scale=30.0)
    for s in range(5):
        np.testing.assert_allclose(lay[s], want[s])
    none = state_layout(graph(positions=False), seed=5)
    want = nx.spring_layout(sg, seed=5)
    assert set(none) == set(range(5))
    for s in range(5):
        np.testing.assert_allclose(none[s], want[s])
    dflt = state_layout(graph(positions=False))
    want = nx.spring_layout(sg, seed=0)
    for s in range(5):
        np.testing.assert_allclose(dflt[s], want[s])
    assert state_layout(TransitionGraph()) == {}


def test_a_layout_around_one_stored_position():
    g = TransitionGraph()
    g.add_transition(0, 1, (0.0, 5.0))
    g.set_position(0, (4.0, 4.0))
    lay = state_layout(g)
    assert lay[0].tolist() == [4.0, 4.0] and np.all(np.isfinite(lay[1]))
    assert lay[1].tolist() != [4.0, 4.0]


@pytest.mark.parametrize("restrict", [False, True])
def test_transitions_to_a_state_without_position_are_left_out_when_restricted(restrict: bool):
    g = graph()
    g.add_transition(3, 9, (0.0, 5.0))                 # 9 has no stored position
    g.add_transition(9, 2, (0.0, 5.0))
    _, ax = plot_cognitive_map(g, positions=POS, restrict=restrict)
    n = len(scatter(ax, "place").get_offsets())
    assert n == (5 if restrict else 6)
    assert len(quiver(ax).X) == (4 if restrict else 6)


def test_the_plan_does_not_follow_the_users_style():
    import matplotlib

    with matplotlib.rc_context({"lines.linestyle": "--"}):
        _, ax = plot_cognitive_map(graph(), path=[(0, 1)])
    assert ax.lines[0].get_linestyle() == "-"
