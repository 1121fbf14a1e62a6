"""The world's figures, read back from the Axes on a hand-made 40 x 20 arena.

draw_arena: each zone a rectangle from its rect (x0, y0, width x1 - x0, height y1 - y0) at
alpha 0.35 with no edge, colour 0 unfilled and 1, 2, ... the five colours of ZONE_COLOURS[1:]
in turn (6 is red again); the walls one black LineCollection 2 wide; the locations grey
(0.55) triangles of size 4 under the walls' zorder 1, numbered from 1 at (2, 2) points only
with labels; the limits 2 cm past the arena; equal aspect. A new
figure is 6 inches wide and 6 h / w high. plot_trajectory: one segment per step, coloured by
the tick (or the colour given) of its first point; plot_sensor_strip: the sensors as rows, the
time axis from t[start] to t[stop - 1].
"""

from __future__ import annotations

import re

import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.collections import LineCollection
from matplotlib.colors import to_rgba
from matplotlib.image import AxesImage
from matplotlib.patches import Rectangle

from hippo.plots.sim import ZONE_COLOURS, draw_arena, plot_sensor_strip, plot_trajectory
from hippo.sim.arena import Arena, Zone
from hippo.sim.record import Recording

WALLS = (((0.0, 0.0), (40.0, 0.0)), ((40.0, 0.0), (40.0, 20.0)), ((0.0, 20.0), (0.0, 0.0)))


def arena(zones: tuple[Zone, ...] = (), locations: list[list[float]] | None = None) -> Arena:
    locs = np.zeros((0, 2)) if locations is None else np.array(locations, dtype=float)
    return Arena("box", 40.0, 20.0, WALLS, zones=zones, locations=locs)


def recording(n: int = 5, sensors: int = 3) -> Recording:
    t = 0.5 * np.arange(n) + 1.0          # 1.0, 1.5, 2.0, ...
    # readings from 1 / (n s + 1) to n s / (n s + 1): none at 0 or 1
    s = ((np.arange(n * sensors, dtype=float) + 1) / (n * sensors + 1)).reshape(n, sensors)
    x = np.arange(n, dtype=float) * 2 + 3
    y = np.arange(n, dtype=float) + 4
    z = np.zeros(n)
    return Recording("box", "ir8", 0.5, 0, t, s, x, y, z, z, z.astype(int), z.astype(int),
                     z.astype(int) - 1)


def test_the_zone_colours_are_the_documented_list():
    assert ZONE_COLOURS == ["none", "tab:red", "tab:green", "tab:blue", "tab:orange",
                            "tab:purple"]


def test_zones_are_rectangles_from_their_rect_in_their_colour():
    zones = tuple(Zone(f"z{c}", (1.0 + c, 2.0, 5.0 + 2 * c, 9.0 - c), c) for c in range(8))
    fig, ax = draw_arena(arena(zones))
    assert fig is ax.figure
    patches = [p for p in ax.patches if isinstance(p, Rectangle)]
    assert len(patches) == 8
    for c, p in enumerate(patches):
        assert p.get_xy() == (1.0 + c, 2.0)
        assert p.get_width() == pytest.approx(4.0 + c)      # (5 + 2c) - (1 + c)
        assert p.get_height() == pytest.approx(7.0 - c)     # (9 - c) - 2
        assert p.get_alpha() == 0.35 and p.get_linewidth() == 0
        if c == 0:
            assert p.get_facecolor()[3] == 0.0      # colour 0: the plain floor, no fill
            continue
        name = ["tab:red", "tab:green", "tab:blue", "tab:orange", "tab:purple"][(c - 1) % 5]
        assert p.get_facecolor() == to_rgba(name, 0.35)
    # colours 6 and 7 cycle round the five: red and green again (6 was drawn unfilled)
    assert patches[6].get_facecolor() == to_rgba("tab:red", 0.35)
    assert patches[7].get_facecolor() == to_rgba("tab:green", 0.35)
    _, ax = draw_arena(arena((Zone("z", (0, 0, 1, 1), 255),)))
    assert ax.patches[0].get_facecolor() == to_rgba("tab:purple", 0.35)    # 1 + 254 % 5 = 5


def test_walls_limits_labels_and_a_new_figure():
    fig, ax = draw_arena(arena())
    assert tuple(fig.get_size_inches()) == (6.0, 3.0)        # 6 x 6 * 20 / 40
    (walls,) = [c for c in ax.collections if isinstance(c, LineCollection)]
    assert [s.tolist() for s in walls.get_segments()] == [[list(a), list(b)] for a, b in WALLS]
    assert [tuple(c) for c in walls.get_colors()] == [to_rgba("k")]
    assert list(walls.get_linewidths()) == [2.0]
    assert ax.get_xlim() == (-2.0, 42.0) and ax.get_ylim() == (-2.0, 22.0)
    assert ax.get_aspect() == 1.0
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("x (cm)", "y (cm)")
    assert len(ax.lines) == 0 and len(ax.texts) == 0     # no locations: no triangles, no numbers


def test_drawn_into_a_given_axes():
    fig, given = plt.subplots(figsize=(2.0, 5.0))
    out = draw_arena(arena(), given)
    assert out == (fig, given) and tuple(fig.get_size_inches()) == (2.0, 5.0)
    assert len(plt.get_fignums()) == 1


def test_locations_are_grey_triangles_numbered_only_with_labels():
    locs = [[5.0, 6.0], [7.0, 8.0], [9.0, 1.0]]
    _, ax = draw_arena(arena(locations=locs))
    (tri,) = ax.lines
    assert tri.get_xdata().tolist() == [5.0, 7.0, 9.0]
    assert tri.get_ydata().tolist() == [6.0, 8.0, 1.0]
    assert tri.get_marker() == "^" and tri.get_linestyle() == "None"
    assert tri.get_color() == "0.55" and tri.get_markersize() == 4 and tri.get_zorder() == 1
    assert len(ax.texts) == 0
    _, ax = draw_arena(arena(locations=locs), labels=True)
    assert [a.get_text() for a in ax.texts] == ["1", "2", "3"]
    for a, xy in zip(ax.texts, locs, strict=True):
        assert list(a.xy) == xy and a.get_fontsize() == 6 and a.get_color() == "0.4"
        assert a.xyann == (2, 2) and a.anncoords == "offset points"
    _, ax = draw_arena(arena(locations=locs), locations=False, labels=True)
    assert len(ax.lines) == 0 and len(ax.texts) == 0


def test_a_trajectory_needs_positions_word_for_word():
    with pytest.raises(ValueError, match="^" + re.escape(
            "give a Recording or an (T, 2) array of positions") + "$"):
        plot_trajectory(arena())


def test_a_trajectory_is_one_segment_per_step_coloured_by_tick():
    rec = recording(5)
    fig, ax = plot_trajectory(arena(), rec)
    lc = ax.collections[-1]
    pts = [[3.0 + 2 * k, 4.0 + k] for k in range(5)]
    assert [s.tolist() for s in lc.get_segments()] == [[pts[k], pts[k + 1]] for k in range(4)]
    assert lc.get_array().tolist() == [0, 1, 2, 3]
    assert lc.get_cmap().name == "viridis" and list(lc.get_linewidths()) == [0.8]
    assert ax.get_title() == "box: 5 ticks"
    cbar = lc.colorbar
    assert cbar.ax.get_ylabel() == "tick" and cbar.ax._colorbar_info["shrink"] == 0.8
    assert len(fig.axes) == 2


def test_a_trajectory_from_positions_with_its_own_colour_title_and_axes():
    xy = np.array([[1.0, 1.0], [2.0, 3.0], [4.0, 3.0]])
    fig, given = plt.subplots()
    out = plot_trajectory(arena(), recording(7), xy=xy, colour=[0.5, -1.0, 9.0], ax=given,
                          title="mine", cmap="jet")
    assert out == (fig, given)
    lc = given.collections[-1]
    assert [s.tolist() for s in lc.get_segments()] == [[[1, 1], [2, 3]], [[2, 3], [4, 3]]]
    assert lc.get_array().tolist() == [0.5, -1.0] and lc.get_cmap().name == "jet"
    assert lc.colorbar.ax.get_ylabel() == "activity"
    assert given.get_title() == "mine"


def test_the_sensor_strip_is_the_sensors_as_rows_over_time():
    rec = recording(6, 3)
    fig, ax = plot_sensor_strip(rec)
    assert tuple(fig.get_size_inches()) == (10.0, 3.0)
    assert fig.get_layout_engine().__class__.__name__ == "ConstrainedLayoutEngine"
    (im,) = [a for a in ax.images if isinstance(a, AxesImage)]
    np.testing.assert_array_equal(im.get_array(), rec.sensors.T)
    # t runs 1.0, 1.5, ..., 3.5: from t[0] to t[5]; rows 0..2 centred on their index
    assert im.get_extent() == [1.0, 3.5, 2.5, -0.5]
    assert im.get_cmap().name == "gray" and im.get_clim() == (0, 1)
    assert im.get_interpolation() == "nearest" and ax.get_aspect() == "auto"
    cbar = im.colorbar
    assert cbar.ax.get_ylabel() == "reading" and cbar.ax._colorbar_info["pad"] == 0.01
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("time (s)", "sensor")
    assert ax.get_title() == "sensor readings (0 = touching, 1 = nothing in range)"


def test_a_window_of_the_sensor_strip_into_a_given_axes():
    rec = recording(6, 3)
    fig, given = plt.subplots()
    assert plot_sensor_strip(rec, 2, 5, ax=given) == (fig, given)
    (im,) = given.images
    np.testing.assert_array_equal(im.get_array(), rec.sensors[2:5].T)
    assert im.get_extent() == [2.0, 3.0, 2.5, -0.5]      # t[2] = 2.0 to t[4] = 3.0
    (im1,) = plot_sensor_strip(rec, 1)[1].images         # stop defaults to len(rec)
    assert im1.get_extent() == [1.5, 3.5, 2.5, -0.5]


@pytest.mark.parametrize("start, stop, message", [
    (5, None, "start must be an integer in [0, 4], got 5"),
    (-1, None, "start must be an integer in [0, 4], got -1"),
    (2, 2, "stop must be an integer in [3, 5], got 2"),
    (0, 6, "stop must be an integer in [1, 5], got 6"),
    (1.0, None, "start must be an integer, got 1.0 (float)"),
])
def test_a_sensor_strip_window_outside_the_recording_is_refused_word_for_word(start, stop,
                                                                               message):
    # numpy's IndexError (or an empty image) before; the window's edges 0 and len(rec) are fine
    rec = recording(5)
    with pytest.raises(ValueError, match="^" + re.escape(message) + "$"):
        plot_sensor_strip(rec, start, stop)
    assert plt.get_fignums() == []
    plot_sensor_strip(rec, 3, 5)
    plot_sensor_strip(rec, 0, 5)
