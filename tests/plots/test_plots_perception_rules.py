"""The place cells' figures, read back from their Axes on a 40 x 20 arena and a few ticks.

The colour limits are the 1st and 99th percentiles of the unit's output (numpy's linear
interpolation: for 0, 5, 10 they are 0.1 and 9.9); the places are drawn in the order of
the output (the peak last), the locations counted from 1. The activation map keeps the ticks
where a unit's output is >= threshold, the units in the given order, shaded from 0.6 threshold
to the 95th percentile of the kept outputs (at least threshold + 1e-6).
"""

from __future__ import annotations

import re

import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.colors import to_rgba

from hippo.plots.perception import (
    CMAP,
    plot_activation_map,
    plot_place_cell,
    plot_sfa_units,
    plot_units_over_arena,
)
from hippo.sim.arena import Arena

WALLS = (((0.0, 0.0), (40.0, 0.0)), ((40.0, 0.0), (40.0, 20.0)))
ARENA = Arena("box", 40.0, 20.0, WALLS, locations=np.array([[5.0, 5.0], [30.0, 15.0]]))
XY = np.array([[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]])
Y = np.array([10.0, 0.0, 5.0])          # percentiles 1 and 99: 0.1 and 9.9
LABELS = np.array([0, 1, 1])


def offsets(coll) -> list[list[float]]:
    return np.asarray(coll.get_offsets()).tolist()


def test_the_papers_colours():
    assert CMAP == "jet"


def test_a_place_cell_over_the_arena_and_over_time():
    fig, axes = plot_place_cell(ARENA, XY, LABELS, Y, title="unit 3")
    ax, ax2 = axes
    assert axes.shape == (2,) and tuple(fig.get_size_inches()) == (9.0, 8.5)
    assert fig.get_layout_engine().__class__.__name__ == "ConstrainedLayoutEngine"
    assert ax.get_subplotspec().rowspan == range(0, 1)
    assert ax2.get_subplotspec().rowspan == range(1, 2)
    gs = ax.get_subplotspec().get_gridspec()
    assert list(gs.get_height_ratios()) == [20 / 40 * 1.6, 1]
    assert (gs.nrows, gs.ncols) == (2, 1)
    assert ax.get_title() == "unit 3"
    assert [t.get_text() for t in ax.texts] == ["1", "2"]           # the arena's labels
    (sc,) = ax.collections[1:]
    # the order of the output: 0 (tick 1), 5 (tick 2), 10 (tick 0)
    assert offsets(sc) == [[3.0, 4.0], [5.0, 6.0], [1.0, 2.0]]
    assert sc.get_array().tolist() == [0.0, 5.0, 10.0]
    assert sc.get_clim() == pytest.approx((0.1, 9.9))
    assert sc.get_cmap().name == "jet" and list(sc.get_sizes()) == [6] and sc.get_zorder() == 2
    cb = sc.colorbar
    assert cb.ax.get_ylabel() == "unit output" and cb.ax._colorbar_info["shrink"] == 0.8
    (sc2,) = ax2.collections
    assert offsets(sc2) == [[0, 1], [1, 2], [2, 2]]                  # tick, location + 1
    assert sc2.get_array().tolist() == [10.0, 0.0, 5.0]
    assert sc2.get_clim() == pytest.approx((0.1, 9.9))
    assert sc2.get_cmap().name == "jet" and list(sc2.get_sizes()) == [5]
    assert (ax2.get_xlabel(), ax2.get_ylabel()) == ("tick", "location (labelled)")
    assert ax2.get_xlim() == (0, 2)
    (tw,) = [a for a in fig.axes if a not in (ax, ax2, cb.ax)]
    (out,) = tw.lines
    assert out.get_xdata().tolist() == [0, 1, 2] and out.get_ydata().tolist() == [10, 0, 5]
    assert (out.get_color(), out.get_linestyle(), out.get_linewidth()) == ("k", "--", 0.7)
    assert tw.get_ylabel() == "unit output"
    assert ax2.get_legend() is None and len(ax2.lines) == 0
    assert plot_place_cell(ARENA, XY, LABELS, Y)[1][0].get_title() == ""


def test_a_place_cell_with_times_events_and_the_truth():
    t = np.array([10.0, 10.5, 11.0, 11.5, 12.0])
    y = np.array([1.0, 2.0, 3.0, 4.0, 5.0])
    xy = np.zeros((5, 2))
    labels = np.array([0, 3, 1, 1, 0])
    truth = [0, 1, 1, 0, 0]
    fig, (_, ax2) = plot_place_cell(ARENA, xy, labels, y, t=t, events=[1, 3],
                                     event_label="lift", truth=truth, truth_label="inside")
    assert ax2.get_xlim() == (10.0, 12.0)
    (tw,) = [a for a in fig.axes if a.get_ylabel() == "unit output" and a.get_shared_x_axes()
             .joined(a, ax2)]
    assert tw.lines[0].get_xdata().tolist() == t.tolist()
    (fill,) = [c for c in ax2.collections if c.get_label() == "inside"]
    # max(labels) + 2 = 5 high, over ticks 1-2 with half steps at their midpoint
    (path,) = fill.get_paths()
    xs = sorted({v[0] for v in path.vertices.tolist()})
    assert xs == [10.5, 10.75, 11.0]
    assert {v[1] for v in path.vertices.tolist()} == {0.0, 5.0}
    assert fill.get_facecolor().tolist() == [list(to_rgba("0.88"))]
    assert fill.get_zorder() == 0 and list(fill.get_linewidth()) == [0]
    assert ax2.get_ylim() == (0, 5.0)
    e1, e2 = ax2.lines
    assert list(e1.get_xdata()) == [10.5, 10.5] and list(e2.get_xdata()) == [11.5, 11.5]
    assert e1.get_color() == "m" and e1.get_linewidth() == 1.2
    assert (e1.get_label(), e2.get_label()[:1]) == ("lift", "_")
    leg = ax2.get_legend()
    assert [x.get_text() for x in leg.get_texts()] == ["inside", "lift"]
    assert leg._loc == 2 and leg.get_texts()[0].get_fontsize() == 8
    # only events: a legend of the events; the default label is "kidnap"
    _, (_, b2) = plot_place_cell(ARENA, xy, labels, y, events=[2])
    assert [x.get_text() for x in b2.get_legend().get_texts()] == ["kidnap"]
    assert list(b2.lines[0].get_xdata()) == [2, 2]
    # only the truth: its legend
    _, (_, c2) = plot_place_cell(ARENA, xy, labels, y, truth=truth, truth_label="in")
    assert [x.get_text() for x in c2.get_legend().get_texts()] == ["in"]
    # the truth without a label (""): shaded, not in the legend
    _, (_, d2) = plot_place_cell(ARENA, xy, labels, y, truth=truth, events=[0])
    assert [x.get_text() for x in d2.get_legend().get_texts()] == ["kidnap"]


def test_the_activation_map():
    t = np.array([10.0, 11.0, 12.0, 13.0])
    labels = np.array([0, 2, 1, 1])
    Y = np.array([[5.0, 0.0, 4.5],
                  [1.0, 6.0, 4.4],
                  [4.5, 9.0, 0.0],
                  [0.0, 0.0, 7.0]])
    fig, axes = plot_activation_map(t, labels, Y, np.array([2, 0, 1]), threshold=4.5,
                                    title="ica")
    a1, a2 = axes
    assert axes.shape == (2,) and tuple(fig.get_size_inches()) == (12.0, 5.0)
    assert fig.get_layout_engine().__class__.__name__ == "ConstrainedLayoutEngine"
    assert a1.get_shared_x_axes().joined(a1, a2)
    assert a1.get_subplotspec().get_geometry() == (1, 2, 0, 0)
    assert a2.get_subplotspec().get_geometry() == (1, 2, 1, 1)
    (occ,) = a1.lines
    assert occ.get_xdata().tolist() == [10, 11, 12, 13]
    assert occ.get_ydata().tolist() == [1, 3, 2, 2]
    assert (occ.get_marker(), occ.get_markersize(), occ.get_color()) == (".", 1.5, "k")
    assert a1.get_ylim() == (0.5, 3.5)                    # max(labels) + 1 = 3 locations
    assert (a1.get_xlabel(), a1.get_ylabel(), a1.get_title()) == (
        "tick", "robot location", "occupancy grid")
    (sc,) = a2.collections
    # the units reordered 2, 0, 1; kept where >= 4.5, row by row
    assert offsets(sc) == [[10, 1], [10, 2], [11, 3], [12, 2], [12, 3], [13, 1]]
    kept = [4.5, 5.0, 6.0, 4.5, 9.0, 7.0]
    assert sc.get_array().tolist() == kept
    # 0.6 threshold; the kept sorted, 95th percentile: 7 + 0.75 (9 - 7)
    assert sc.get_clim() == pytest.approx((2.7, 8.5))
    assert sc.get_cmap().name == "Greys" and list(sc.get_sizes()) == [2]
    assert a2.get_ylim() == (0.5, 3.5)
    assert (a2.get_xlabel(), a2.get_ylabel()) == (
        "tick", "ICA unit (ordered by preferred location)")
    assert a2.get_title() == "ICA activation map (output ≥ 4.5)"
    assert fig.get_suptitle() == "ica"


def test_the_activation_map_with_given_locations_and_nothing_kept():
    Y = np.ones((3, 2))
    fig, (a1, a2) = plot_activation_map(np.arange(3), np.array([0, 0, 1]), Y,
                                        np.array([0, 1]), n_locations=5)
    assert a1.get_ylim() == (0.5, 5.5) and a2.get_ylim() == (0.5, 2.5)
    (sc,) = a2.collections
    assert len(sc.get_offsets()) == 0
    assert sc.get_clim() == (4.5 * 0.6, 4.5 + 1e-6)          # exactly 1e-6 above
    assert a2.get_title() == "ICA activation map (output ≥ 4.5)" and fig.get_suptitle() == ""
    # a 95th percentile under threshold + 1e-6 is raised to it
    _, (_, b2) = plot_activation_map(np.arange(2), np.array([0, 1]), np.array([[2.0], [2.0]]),
                                     np.array([0]), threshold=2.0)
    assert b2.collections[0].get_clim() == pytest.approx((1.2, 2.0 + 1e-6))


def test_units_over_the_arena_as_small_multiples():
    fields = np.arange(3 * 2 * 2, dtype=float).reshape(3, 2, 2)
    fields[1, 0, 0] = np.nan
    extent = (0.0, 40.0, 0.0, 20.0)
    fig, axes = plot_units_over_arena(ARENA, fields, extent, ncols=2, title="fields")
    assert axes.shape == (2, 2) and tuple(fig.get_size_inches()) == (3.2, 3.2)
    assert fig.get_layout_engine().__class__.__name__ == "ConstrainedLayoutEngine"
    assert all(not a.axison for a in axes.ravel())
    drawn = axes.ravel()[:3]
    assert [a.get_title() for a in drawn] == ["1", "2", "3"]
    assert len(axes[1, 1].images) == 0 and axes[1, 1].get_title() == ""
    for j, a in enumerate(drawn):
        (im,) = a.images
        np.testing.assert_array_equal(im.get_array(), fields[j])
        assert im.origin == "lower" and im.get_extent() == list(extent)
        assert im.get_cmap().name == "jet" and im.get_interpolation() == "nearest"
        assert a.title.get_fontsize() == 7
        assert a.titleOffsetTrans._t == pytest.approx((0.0, 1 / 72))    # pad 1 point
        lines = [(ln.get_xdata(), ln.get_ydata()) for ln in a.lines]
        assert [(list(x), list(y)) for x, y in lines] == [([0, 40], [0, 0]), ([40, 40], [0, 20])]
        assert all(ln.get_color() == "w" and ln.get_linewidth() == 0.4 for ln in a.lines)
    assert drawn[0].images[0].get_clim() == (0.0, 3.0)
    assert drawn[1].images[0].get_clim() == (5.0, 7.0)       # the nan left out
    assert fig.get_suptitle() == "fields"


def test_chosen_units_and_the_rows_they_take():
    fields = np.zeros((12, 2, 2))
    fields[7] = [[1.0, 2.0], [3.0, 4.0]]
    fig, axes = plot_units_over_arena(ARENA, fields, (0, 1, 0, 1), units=[7, 0])
    assert axes.shape == (1, 10) and tuple(fig.get_size_inches()) == (16.0, 1.6)
    assert [a.get_title() for a in axes[0, :3]] == ["8", "1", ""]
    np.testing.assert_array_equal(axes[0, 0].images[0].get_array(), fields[7])
    assert fig.get_suptitle() == ""
    _, axes = plot_units_over_arena(ARENA, fields, (0, 1, 0, 1))    # 12 units: 2 rows
    assert axes.shape == (2, 10) and axes[1, 1].get_title() == "12"
    _, axes = plot_units_over_arena(ARENA, fields, (0, 1, 0, 1), units=[], ncols=3)
    assert axes.shape == (1, 3)                                      # at least one row
    _, axes = plot_units_over_arena(ARENA, fields, (0, 1, 0, 1), units=range(4), ncols=4)
    assert axes.shape == (1, 4)                                      # exactly one row


def test_sfa_units_over_time_and_over_the_arena():
    Ysfa = np.column_stack([np.array([1.0, 2.0, 3.0]), Y])
    fig, axes = plot_sfa_units(ARENA, XY, LABELS, Ysfa, [1, 0])
    assert axes.shape == (2, 2) and tuple(fig.get_size_inches()) == (11.0, 5.6)
    assert fig.get_layout_engine().__class__.__name__ == "ConstrainedLayoutEngine"
    assert plt.get_fignums() == [fig.number]            # the arenas drawn into the panels
    assert list(axes[0, 0].get_subplotspec().get_gridspec().get_width_ratios()) == [2, 1]
    left, right = axes[0]
    (sc,) = left.collections
    assert offsets(sc) == [[0, 1], [1, 2], [2, 2]]
    assert sc.get_array().tolist() == [10.0, 0.0, 5.0]
    assert sc.get_clim() == pytest.approx((0.1, 9.9)) and list(sc.get_sizes()) == [3]
    assert sc.get_cmap().name == "jet" and left.get_ylabel() == "location"
    twins = [a for a in fig.axes if a not in set(axes.ravel())]
    assert [tw.get_shared_x_axes().joined(tw, row[0]) for tw, row in zip(twins, axes,
                                                                            strict=True)] == [
        True, True]
    assert [tw.get_ylabel() for tw in twins] == ["SFA unit 2", "SFA unit 1"]
    (ln,) = twins[0].lines
    assert ln.get_ydata().tolist() == [10, 0, 5] and ln.get_xdata().tolist() == [0, 1, 2]
    assert (ln.get_color(), ln.get_linestyle(), ln.get_linewidth()) == ("k", "-", 0.5)
    sc_r = right.collections[-1]
    assert offsets(sc_r) == XY.tolist() and sc_r.get_array().tolist() == [10.0, 0.0, 5.0]
    assert sc_r.get_clim() == pytest.approx((0.1, 9.9)) and list(sc_r.get_sizes()) == [2]
    assert sc_r.get_zorder() == 2 and sc_r.get_cmap().name == "jet"
    assert len(right.lines) == 0                                     # no locations drawn
    assert [s.tolist() for s in right.collections[0].get_segments()] == [
        [list(a), list(b)] for a, b in WALLS]
    assert (right.get_xlabel(), right.get_ylabel()) == ("", "")
    assert axes[1, 1].collections[-1].get_clim() == pytest.approx((1.02, 2.98))
    assert axes[1, 0].get_xlabel() == "tick" and axes[0, 0].get_xlabel() == ""
    _, axes = plot_sfa_units(ARENA, XY, LABELS, Ysfa, [0], t=np.array([5.0, 6.0, 7.0]))
    assert axes.shape == (1, 2)
    assert offsets(axes[0, 0].collections[0]) == [[5, 1], [6, 2], [7, 2]]
    (tw,) = [a for a in axes[0, 0].figure.axes if a not in set(axes.ravel())]
    assert tw.lines[0].get_xdata().tolist() == [5.0, 6.0, 7.0]


@pytest.mark.parametrize("ncols, message", [
    (0, "ncols must be an integer >= 1, got 0"),
    (-2, "ncols must be an integer >= 1, got -2"),
    (2.0, "ncols must be an integer, got 2.0 (float)"),
    (True, "ncols must be an integer, got True (a bool)"),
])
def test_small_multiples_need_a_column_or_more_word_for_word(ncols, message):
    # a ZeroDivisionError (or a float count of columns) before; no figure is left open
    fields = np.zeros((3, 2, 2))
    with pytest.raises(ValueError, match="^" + re.escape(message) + "$"):
        plot_units_over_arena(ARENA, fields, (0, 1, 0, 1), ncols=ncols)
    assert plt.get_fignums() == []
    _, axes = plot_units_over_arena(ARENA, fields, (0, 1, 0, 1), ncols=1)
    assert axes.shape == (3, 1)
