"""The arena renderer's frames, against the geometry worked out by hand.

The figure spans the arena and 2 cm around it at 100 dpi: width_px / 100 inches wide and
(height + 4) / (width + 4) of that high, its one Axes filling it, so that an arena point
(x, y) is the pixel column (x + 2) W / (width + 4) and row H - (y + 2) H / (height + 4). The
robot is a tab:blue disc of its radius with a white nose from the centre to radius along the
heading; marks are purple crosses with their names at (3, 3) points.
"""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import pytest
from matplotlib.colors import to_rgba

from hippo.envs.render import ArenaRenderer
from hippo.sim.arena import Arena

# 36 x 16 cm: with 2 cm around, 40 x 20 cm; at 400 px, 10 px per cm
ARENA = Arena("box", 36.0, 16.0, (((0.0, 0.0), (36.0, 0.0)), ((36.0, 0.0), (36.0, 16.0))),
              locations=np.array([[5.0, 5.0]]))
BLUE = np.array([31, 119, 180])          # tab:blue


def pixel(frame: np.ndarray, x: float, y: float) -> np.ndarray:
    h, w, _ = frame.shape
    col = int((x + 2) * w / 40)
    row = int(h - (y + 2) * h / 20)
    return frame[row, col].astype(int)


def test_the_figure_and_its_axes():
    r = ArenaRenderer(ARENA, width_px=200)
    assert tuple(r.figure.get_size_inches()) == (2.0, 1.0) and r.figure.dpi == 100
    assert r.canvas.get_width_height() == (200, 100)
    assert r.axes.get_position().bounds == (0, 0, 1, 1) and not r.axes.axison
    assert r.axes.get_xlim() == (-2.0, 38.0) and r.axes.get_ylim() == (-2.0, 18.0)
    assert r.figure.axes == [r.axes]
    frame = r.frame((18.0, 8.0, 0.0))
    assert frame.shape == (100, 200, 3) and frame.dtype == np.uint8
    assert frame.flags["OWNDATA"]                  # a copy, not a view of the canvas
    r.close()
    assert r.figure.axes == []


def test_the_robots_disc_and_nose():
    r = ArenaRenderer(ARENA, robot_radius=5.0, width_px=400)
    disc = r._disc
    assert disc.radius == 5.0 and disc.get_zorder() == 5
    assert disc.get_facecolor() == to_rgba("tab:blue") and disc.get_edgecolor() == to_rgba("k")
    assert disc.get_linewidth() == 0.8
    nose = r._nose
    assert list(nose.get_xdata()) == [] and nose.get_color() == "w"
    assert (nose.get_linestyle(), nose.get_linewidth(), nose.get_zorder()) == ("-", 1.5, 6)
    assert len(r.axes.lines) == 1                   # the nose only: no locations drawn
    frame = r.frame((18.2, 8.2, 0.0, 99.0))        # a pose's extra entries are left alone
    assert disc.center == (18.2, 8.2)
    assert list(nose.get_xdata()) == [18.2, 23.2] and list(nose.get_ydata()) == [8.2, 8.2]
    assert np.abs(pixel(frame, 18.2, 5.7) - BLUE).max() <= 2        # inside, off the nose
    assert pixel(frame, 20.7, 8.2).min() >= 200                     # the nose: white
    assert pixel(frame, 18.2, 15.0).min() >= 250                    # the floor: white
    up = r.frame(np.array([10.2, 6.2, math.pi / 2]))
    assert list(nose.get_xdata()) == pytest.approx([10.2, 10.2])
    assert list(nose.get_ydata()) == pytest.approx([6.2, 11.2])
    assert pixel(up, 10.2, 8.7).min() >= 200
    assert np.abs(pixel(up, 12.7, 6.2) - BLUE).max() <= 2
    assert pixel(up, 18.2, 5.7).min() >= 250                        # moved: floor again
    r.close()


def test_the_default_radius_and_the_aspect():
    r = ArenaRenderer(Arena("tall", 16.0, 36.0, ()))
    assert r._disc.radius == 3.7 and r._radius == 3.7
    assert r.canvas.get_width_height() == (480, 960)      # 480 x 40 / 20
    r.frame((1.0, 2.0, 0.5))
    assert list(r._nose.get_xdata()) == pytest.approx([1.0, 1.0 + 3.7 * math.cos(0.5)])
    assert list(r._nose.get_ydata()) == pytest.approx([2.0, 2.0 + 3.7 * math.sin(0.5)])
    r.close()


def test_marks_are_named_purple_crosses():
    r = ArenaRenderer(ARENA, marks={"goal": (30.0, 4.0), "cp": [2.0, 12.0]}, width_px=400)
    crosses = [ln for ln in r.axes.lines if ln is not r._nose]
    assert [(list(c.get_xdata()), list(c.get_ydata())) for c in crosses] == [
        ([30.0], [4.0]), ([2.0], [12.0])]
    for c in crosses:
        assert (c.get_marker(), c.get_linestyle(), c.get_color()) == ("x", "None", "tab:purple")
        assert (c.get_markersize(), c.get_markeredgewidth()) == (6, 1.5)
    names = r.axes.texts
    assert [t.get_text() for t in names] == ["goal", "cp"]
    assert [tuple(t.xy) for t in names] == [(30.0, 4.0), (2.0, 12.0)]
    for t in names:
        assert t.xyann == (3, 3) and t.anncoords == "offset points"
        assert t.get_fontsize() == 7 and t.get_color() == "tab:purple"
    frame = r.frame((18.0, 8.0, 0.0))
    centre = pixel(frame, 30.0, 4.0)
    assert centre[1] < 150 and centre[0] > centre[1]        # purple: more red than green
    r.close()


def test_the_frame_does_not_follow_the_users_style():
    """Every size and colour is the renderer's own: a matplotlib style with other defaults
    (dpi, line width and style, marker size, patch colour) changes nothing."""
    style = {"figure.dpi": 50, "lines.linewidth": 4.0, "lines.linestyle": "--",
             "lines.markersize": 12.0, "patch.facecolor": "red"}
    with matplotlib.rc_context(style):
        r = ArenaRenderer(ARENA, marks={"goal": (30.0, 4.0)}, width_px=200)
    assert r.figure.dpi == 100 and r.canvas.get_width_height() == (200, 100)
    assert (r._nose.get_linewidth(), r._nose.get_linestyle()) == (1.5, "-")
    (cross,) = [ln for ln in r.axes.lines if ln is not r._nose]
    assert cross.get_markersize() == 6
    assert r._disc.get_facecolor() == to_rgba("tab:blue")
    r.close()
