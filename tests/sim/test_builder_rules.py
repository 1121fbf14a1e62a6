"""The arena builder's rules on hand-made arenas: its geometry (walls in order, boxes, grids of
locations worked out by hand), every refusal word for word, each bound on its edge and one step
past (points on the arena's edges, a start disc of 3.7 cm exactly 3.7 + 0.5 cm from a wall, a
start inside a pillar), and what build() freezes.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from hippo.sim.arena import Region, Zone
from hippo.sim.builder import MAX_COLOUR, ArenaBuilder


def refused(message: str):
    return pytest.raises(ValueError, match="^" + re.escape(message) + "$")


def walled(w: float = 100.0, h: float = 80.0) -> ArenaBuilder:
    return ArenaBuilder("b", w, h).outer_walls()


# -- the arena itself -----------------------------------------------------------------------

def test_new_builder():
    b = ArenaBuilder("room", 100, 80)
    assert (b.name, b.width, b.height) == ("room", 100.0, 80.0)
    assert type(b.width) is float and type(b.height) is float
    assert (b._walls, b._zones, b._regions, b._locations, b._landmarks, b._start,
            b._boxes) == ([], [], [], [], {}, None, [])
    assert ArenaBuilder("tiny", 1e-9, 1e-9).width == 1e-9


@pytest.mark.parametrize("w, h", [(0.0, 80.0), (100.0, 0.0), (-1.0, 80.0), (100.0, -1.0),
                                  (math.inf, 80.0), (100.0, math.inf), (math.nan, 80.0),
                                  (100.0, math.nan)])
def test_arena_size_must_be_positive_and_finite(w, h):
    with refused(f"arena size must be positive and finite, got {w} x {h}"):
        ArenaBuilder("a", w, h)


@pytest.mark.parametrize("name", [3, None, "", b"a"])
def test_arena_name_must_be_a_non_empty_string(name):
    with refused(f"arena name must be a non-empty string, got {name!r}"):
        ArenaBuilder(name, 10, 10)  # type: ignore[arg-type]


# -- walls ----------------------------------------------------------------------------------

def test_walls_inside_the_arena_edges_included():
    b = ArenaBuilder("a", 100, 80)
    assert b.wall((0, 0), (100, 80)) is b
    b.wall([0, 80], np.array([100.0, 0.0]))
    assert b._walls == [((0.0, 0.0), (100.0, 80.0)), ((0.0, 80.0), (100.0, 0.0))]
    assert all(type(v) is float for w in b._walls for p in w for v in p)


def test_wall_refusals():
    b = ArenaBuilder("a", 100, 80)
    with refused("wall from (1.0, 1.0) to (1.0, 1.0) has zero length"):
        b.wall((1, 1), (1, 1))
    with refused("wall start (-0.001, 10.0) lies outside the 100 x 80 arena"):
        b.wall((-0.001, 10), (10, 10))
    with refused("wall start (100.001, 10.0) lies outside the 100 x 80 arena"):
        b.wall((100.001, 10), (10, 10))
    with refused("wall end (10.0, -0.001) lies outside the 100 x 80 arena"):
        b.wall((10, 10), (10, -0.001))
    with refused("wall end (10.0, 80.001) lies outside the 100 x 80 arena"):
        b.wall((10, 10), (10, 80.001))
    with refused("wall start contains 1 non-finite value(s) (NaN or inf)"):
        b.wall((math.nan, 1), (2, 2))
    with refused("wall end contains 2 non-finite value(s) (NaN or inf)"):
        b.wall((1, 1), (math.inf, math.inf))
    for a, e in (((1, 2, 3), (4, 5)), ((1, 2), (4, 5, 6)), ((1,), (4, 5)), ((1, 2), (4,))):
        with refused("wall end points must be (x, y) pairs"):
            b.wall(a, e)
    assert b._walls == []  # nothing refused was kept


def test_polyline_open_and_closed():
    b = ArenaBuilder("a", 100, 80)
    assert b.polyline([(0, 0), (10, 0), (10, 10)]) is b
    assert b._walls == [((0.0, 0.0), (10.0, 0.0)), ((10.0, 0.0), (10.0, 10.0))]
    c = ArenaBuilder("a", 100, 80).polyline([(0, 0), (10, 0), (10, 10)], closed=True)
    assert c._walls == [((0.0, 0.0), (10.0, 0.0)), ((10.0, 0.0), (10.0, 10.0)),
                        ((10.0, 10.0), (0.0, 0.0))]
    assert ArenaBuilder("a", 100, 80).polyline([(1, 1)])._walls == []
    assert c._boxes == []  # a closed polyline is not a box


def test_box_and_outer_walls():
    b = ArenaBuilder("a", 100, 80)
    assert b.box((10, 20, 30, 50)) is b
    # counter-clockwise from (x0, y0)
    assert b._walls == [((10.0, 20.0), (30.0, 20.0)), ((30.0, 20.0), (30.0, 50.0)),
                        ((30.0, 50.0), (10.0, 50.0)), ((10.0, 50.0), (10.0, 20.0))]
    assert b._boxes == [(10.0, 20.0, 30.0, 50.0)]
    assert all(type(v) is float for v in b._boxes[0])
    o = ArenaBuilder("a", 100, 80)
    assert o.outer_walls() is o
    assert o._walls == [((0.0, 0.0), (100.0, 0.0)), ((100.0, 0.0), (100.0, 80.0)),
                        ((100.0, 80.0), (0.0, 80.0)), ((0.0, 80.0), (0.0, 0.0))]
    assert o._boxes == [(0.0, 0.0, 100.0, 80.0)]


# -- rectangles: zones and regions -----------------------------------------------------------

def test_zone_rules():
    b = walled()
    assert b.zone("goal", (0, 0, 100, 80)) is b  # the whole arena: edges included
    b.zone("pad", (1, 2, 3, 4), colour=MAX_COLOUR)
    assert b._zones == [Zone("goal", (0.0, 0.0, 100.0, 80.0), 1),
                        Zone("pad", (1.0, 2.0, 3.0, 4.0), 255)]
    assert MAX_COLOUR == 255
    assert walled().zone("z", (1, 1, 2, 2), colour=np.int16(7))._zones[0].colour == 7
    for colour in (0, 256):
        with refused(f"zone 'g' colour must be an integer in [1, 255], got {colour}"):
            walled().zone("g", (1, 1, 5, 5), colour=colour)
    with refused("zone 'g' colour must be an integer, got 1.0 (float)"):
        walled().zone("g", (1, 1, 5, 5), colour=1.0)  # type: ignore[arg-type]
    with refused("zone 'g' is already defined; zone names must be distinct"):
        walled().zone("g", (1, 1, 5, 5)).zone("g", (6, 6, 9, 9), colour=2)
    with refused("zone name must be a non-empty string, got 5"):
        walled().zone(5, (1, 1, 5, 5))  # type: ignore[arg-type]
    # the name is checked before the colour and the rectangle
    with refused("zone name must be a non-empty string, got ''"):
        walled().zone("", (5, 5, 1, 1), colour=0)
    with refused("zone 'g' (5.0, 5.0, 1.0, 1.0) must have x0 < x1 and y0 < y1"):
        walled().zone("g", (5, 5, 1, 1))
    # and the colour before the rectangle
    with refused("zone 'g' colour must be an integer in [1, 255], got 0"):
        walled().zone("g", (5, 5, 1, 1), colour=0)


@pytest.mark.parametrize("rect, message", [
    ((5, 1, 5, 9), "region 'r' (5.0, 1.0, 5.0, 9.0) must have x0 < x1 and y0 < y1"),
    ((1, 5, 9, 5), "region 'r' (1.0, 5.0, 9.0, 5.0) must have x0 < x1 and y0 < y1"),
    ((9, 1, 1, 9), "region 'r' (9.0, 1.0, 1.0, 9.0) must have x0 < x1 and y0 < y1"),
    ((-0.5, 0, 10, 10), "region 'r' (-0.5, 0.0, 10.0, 10.0) lies outside the 100 x 80 arena"),
    ((0, -0.5, 10, 10), "region 'r' (0.0, -0.5, 10.0, 10.0) lies outside the 100 x 80 arena"),
    ((0, 0, 100.5, 10), "region 'r' (0.0, 0.0, 100.5, 10.0) lies outside the 100 x 80 arena"),
    ((0, 0, 10, 80.5), "region 'r' (0.0, 0.0, 10.0, 80.5) lies outside the 100 x 80 arena"),
    ((0, 0, 10), "region 'r' must be (x0, y0, x1, y1), got (0, 0, 10)"),
    ((0, 0, 10, 10, 10), "region 'r' must be (x0, y0, x1, y1), got (0, 0, 10, 10, 10)"),
    ((0, 0, math.nan, 10), "region 'r' contains 1 non-finite value(s) (NaN or inf)"),
])
def test_rectangle_refusals(rect, message):
    with refused(message):
        walled().region("r", rect)


def test_region_rules():
    b = walled()
    assert b.region("left", (0, 0, 50, 80), (50, 0, 60, 10)) is b
    b.region("all", (0.0, 0.0, 100.0, 80.0))
    assert b._regions == [Region("left", ((0.0, 0.0, 50.0, 80.0), (50.0, 0.0, 60.0, 10.0))),
                          Region("all", ((0.0, 0.0, 100.0, 80.0),))]
    with refused("region 'r' needs at least one rectangle"):
        walled().region("r")
    with refused("region 'r' is already defined; region names must be distinct"):
        walled().region("r", (1, 1, 5, 5)).region("r", (6, 6, 9, 9))
    with refused("region name must be a non-empty string, got None"):
        walled().region(None, (1, 1, 5, 5))  # type: ignore[arg-type]
    # the second rectangle is checked too, and named by the region
    with refused("region 'r' (1.0, 1.0, 200.0, 5.0) lies outside the 100 x 80 arena"):
        walled().region("r", (1, 1, 5, 5), (1, 1, 200, 5))
    # a zone and a region may share a name (they are different things)
    assert walled().zone("x", (1, 1, 2, 2)).region("x", (1, 1, 2, 2))._regions[0].name == "x"


# -- points: locations, grids, landmarks, start ------------------------------------------------

def test_locations():
    b = walled()
    assert b.location(0, 0) is b
    b.location(100, 80).location(12.5, 7)
    assert b._locations == [(0.0, 0.0), (100.0, 80.0), (12.5, 7.0)]
    with refused("location (100.5, 3.0) lies outside the 100 x 80 arena"):
        b.location(100.5, 3)
    with refused("location (3.0, -0.5) lies outside the 100 x 80 arena"):
        b.location(3, -0.5)
    with refused("location contains 1 non-finite value(s) (NaN or inf)"):
        b.location(math.nan, 3)


def test_grid_locations_are_cell_centres_row_by_row():
    # 100 x 80 in 2 x 2 cells of 50 x 40: centres x 25, 75 and y 20, 60; x varies fastest
    b = walled()
    assert b.grid_locations(2, 2) is b
    assert b._locations == [(25.0, 20.0), (75.0, 20.0), (25.0, 60.0), (75.0, 60.0)]
    # over (10, 20, 40, 80) in 3 x 2 cells of 10 x 30: x 15, 25, 35 and y 35, 65
    c = walled().grid_locations(3, 2, (10, 20, 40, 80))
    assert c._locations == [(15.0, 35.0), (25.0, 35.0), (35.0, 35.0),
                            (15.0, 65.0), (25.0, 65.0), (35.0, 65.0)]
    assert walled().grid_locations(1, 1)._locations == [(50.0, 40.0)]
    assert walled().grid_locations(2.0, 1)._locations == [(25.0, 40.0), (75.0, 40.0)]
    assert walled().grid_locations(1, 3)._locations == [(50.0, 80 / 6), (50.0, 40.0),
                                                        (50.0, 400 / 6)]


@pytest.mark.parametrize("nx, ny", [(0, 1), (1, 0), (-1, 2), (2, -1), (1.5, 1), (1, 2.5)])
def test_grid_locations_refusals(nx, ny):
    with refused(f"a grid of locations needs nx, ny >= 1, got {nx} x {ny}"):
        walled().grid_locations(nx, ny)


def test_grid_rectangle_is_checked():
    with refused("grid rectangle (0.0, 0.0, 101.0, 80.0) lies outside the 100 x 80 arena"):
        walled().grid_locations(1, 1, (0, 0, 101, 80))


def test_landmarks():
    b = walled()
    assert b.landmark("goal", 100, 80) is b
    b.landmark("home", 0, 0)
    assert b._landmarks == {"goal": (100.0, 80.0), "home": (0.0, 0.0)}
    with refused("landmark 'L' (1000000.0, -5.0) lies outside the 100 x 80 arena"):
        walled().landmark("L", 1e6, -5)
    with refused("landmark 'L' contains 1 non-finite value(s) (NaN or inf)"):
        walled().landmark("L", 1, math.inf)
    with refused("landmark 'goal' is already defined; landmark names must be distinct"):
        b.landmark("goal", 1, 1)
    assert b._landmarks["goal"] == (100.0, 80.0)  # not overwritten
    with refused("landmark name must be a non-empty string, got 7"):
        walled().landmark(7, 1, 1)  # type: ignore[arg-type]


def test_start_pose():
    b = walled()
    assert b.start(10, 20) is b
    assert b._start == (10.0, 20.0, 0.0)
    assert walled().start(10, 20, 1.5)._start == (10.0, 20.0, 1.5)
    for pose in ((math.nan, 1, 0), (1, math.inf, 0), (1, 1, math.nan)):
        with refused("start pose contains 1 non-finite value(s) (NaN or inf)"):
            walled().start(*pose)


# -- build ----------------------------------------------------------------------------------

def test_build_freezes_everything():
    b = (walled().wall((50, 0), (50, 40)).zone("goal", (80, 40, 95, 55), colour=3)
         .region("left", (0, 0, 50, 80)).location(20, 20).location(70, 60)
         .landmark("g", 87.5, 47.5).start(25, 60, 0.5))
    a = b.build()
    assert (a.name, a.width, a.height) == ("b", 100.0, 80.0)
    assert a.walls == tuple(b._walls) and len(a.walls) == 5 and isinstance(a.walls, tuple)
    assert a.zones == (Zone("goal", (80.0, 40.0, 95.0, 55.0), 3),)
    assert a.regions == (Region("left", ((0.0, 0.0, 50.0, 80.0),)),)
    np.testing.assert_array_equal(a.locations, [[20.0, 20.0], [70.0, 60.0]])
    assert a.locations.dtype == np.float64
    assert a.start_pose == (25.0, 60.0, 0.5)
    assert a.landmarks == {"g": (87.5, 47.5)}
    b.landmark("later", 1, 1)  # the arena keeps its own copy
    assert a.landmarks == {"g": (87.5, 47.5)}


def test_build_defaults():
    a = walled().build()
    assert a.start_pose == (50.0, 40.0, 0.0)  # the centre, heading 0
    assert a.locations.shape == (0, 2) and a.zones == () and a.regions == ()
    assert a.landmarks == {}


def test_build_needs_walls():
    with refused("arena 'empty' has no walls"):
        ArenaBuilder("empty", 10, 10).build()


def test_start_must_be_free_on_its_edge():
    # the start disc has radius 3.7 and must stay 3.7 + 0.5 (the walls' half thickness) from
    # every wall: 4.2 cm from the wall x = 0 is free, 4.19 is not
    assert walled().start(4.2, 40).build().start_pose == (4.2, 40.0, 0.0)
    with refused("start pose (4.19, 40.0, 0.0) of 'b' is not free"):
        walled().start(4.19, 40).build()
    with refused("start pose (50.0, 75.9, 0.0) of 'b' is not free"):
        walled().start(50, 75.9).build()
    # without outer walls the disc must still lie inside the arena: x >= 3.7
    b = ArenaBuilder("open", 100, 80).wall((50, 60), (60, 60))
    assert b.start(3.7, 20).build().start_pose == (3.7, 20.0, 0.0)
    with refused("start pose (3.69, 20.0, 0.0) of 'open' is not free"):
        ArenaBuilder("open", 100, 80).wall((50, 60), (60, 60)).start(3.69, 20).build()
    # the default start (the centre) on a wall
    with refused("start pose (50.0, 40.0, 0.0) of 'x' is not free"):
        ArenaBuilder("x", 100, 80).outer_walls().wall((50, 0), (50, 80)).build()


def test_start_inside_a_pillar_is_refused():
    # a 9 x 9 pillar at (10, 10): its centre (14.5, 14.5) is 4.5 cm from each side (free),
    # and the outer walls lie outside the pillar
    with refused("start (14.5, 14.5) of 'b' lies inside box (10.0, 10.0, 19.0, 19.0), a pillar "
                 "the robot cannot leave; put it on the floor with ArenaBuilder.start(x, y)"):
        walled().box((10, 10, 19, 19)).start(14.5, 14.5).build()
    # every box is looked at, not only those before the first that misses the start
    with pytest.raises(ValueError, match=r"lies inside box \(10.0, 10.0, 19.0, 19.0\)"):
        walled().box((60, 10, 90, 70)).box((10, 10, 19, 19)).start(14.5, 14.5).build()
    # the default start, the centre (50, 40), inside a central pillar
    with refused("start (50, 40) (the default start, the centre) of 'b' lies inside box "
                 "(30.0, 20.0, 70.0, 60.0), a pillar the robot cannot leave; put it on the "
                 "floor with ArenaBuilder.start(x, y)"):
        walled().box((30, 20, 70, 60)).build()
    # outside the pillar, next to it: fine (each side)
    for x, y in ((50, 10), (50, 70), (20, 40), (80, 40)):
        assert walled().box((30, 20, 70, 60)).start(x, y).build().start_pose[:2] == (x, y)
    # a box holding every wall (the outer walls, or a box used as them) may hold the start
    assert ArenaBuilder("b", 100, 80).box((10, 10, 90, 70)).build().start_pose[:2] == (50, 40)
    assert (ArenaBuilder("b", 100, 80).box((10, 10, 90, 70)).wall((10, 40), (40, 40))
            .start(60, 30).build().start_pose[:2] == (60.0, 30.0))
    # one wall end beyond the box: a pillar again
    with refused("start (60, 30) of 'b' lies inside box (10.0, 10.0, 90.0, 70.0), a pillar the "
                 "robot cannot leave; put it on the floor with ArenaBuilder.start(x, y)"):
        (ArenaBuilder("b", 100, 80).box((10, 10, 90, 70)).wall((10, 40), (5, 40))
         .start(60, 30).build())
    for end in ((40, 75), (95, 40), (40, 5)):
        with pytest.raises(ValueError, match="lies inside box"):
            (ArenaBuilder("b", 100, 80).box((10, 10, 90, 70)).wall((40, 40), end)
             .start(60, 30).build())



def test_a_grid_needs_whole_finite_counts():
    for nx, ny in ((float("inf"), 1), (float("nan"), 2), (True, 2), (2, 1.5), (0, 3)):
        with pytest.raises(ValueError) as e:
            ArenaBuilder("g", 100, 100).grid_locations(nx, ny)
        assert str(e.value) == f"a grid of locations needs nx, ny >= 1, got {nx} x {ny}"
    # 2.0 x 1: two cell centres at x = 25 and 75, y = 50 (a 100 x 100 arena halved)
    a = ArenaBuilder("g", 100, 100).outer_walls().grid_locations(2.0, 1).start(50, 20).build()
    np.testing.assert_array_equal(a.locations, [[25.0, 50.0], [75.0, 50.0]])
