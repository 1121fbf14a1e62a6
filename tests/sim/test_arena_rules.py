"""The arena's geometry on small hand-made arenas: zones, regions, distances, the free grid,
shortest and geodesic paths, free poses.

Arenas are built directly (plain geometry, walls of 0.5 cm radius). Grid cells are ``cell`` cm
wide with centres at ``cell / 2, 3 cell / 2, ...``; a disc of radius ``r`` fits a centre when it
lies inside the arena by ``r`` and is ``r + 0.5`` from every wall's centre line. Each expected
value is worked out by hand in the comments.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hippo.sim.arena import Arena, Region, Zone, _segment_clear


def walled(w: float, h: float, *inner, name: str = "a", **kw) -> Arena:
    walls = (((0.0, 0.0), (w, 0.0)), ((w, 0.0), (w, h)), ((w, h), (0.0, h)),
             ((0.0, h), (0.0, 0.0)), *inner)
    return Arena(name, w, h, walls, **kw)


# -- zones and regions ----------------------------------------------------------------------

def test_a_zone_holds_its_edges_and_nothing_beyond():
    z = Zone("g", (10.0, 20.0, 30.0, 40.0), 2)
    for x, y in ((10, 20), (30, 40), (10, 40), (30, 20), (20, 30)):
        assert z.contains(x, y)
    for x, y in ((9.99, 30), (30.01, 30), (20, 19.99), (20, 40.01)):
        assert not z.contains(x, y)


def test_a_region_holds_any_of_its_rectangles_edges_included():
    r = Region("L", ((0.0, 0.0, 10.0, 5.0), (0.0, 5.0, 4.0, 20.0)))
    for x, y in ((0, 0), (10, 5), (4, 20), (2, 12)):
        assert r.contains(x, y)
    for x, y in ((10.01, 2), (-0.01, 2), (6, 12), (2, 20.01), (5, -0.01)):
        assert not r.contains(x, y)


def test_zone_names_by_colour_with_gaps_named_empty():
    a = walled(10, 10, zones=(Zone("blue", (0, 0, 1, 1), 3), Zone("red", (2, 2, 3, 3), 1)))
    assert a.zone_names == ["floor", "red", "", "blue"]
    assert walled(10, 10).zone_names == ["floor"]


def test_the_first_zone_holding_a_point_gives_its_colour():
    a = walled(10, 10, zones=(Zone("a", (0, 0, 5, 5), 2), Zone("b", (4, 4, 8, 8), 5)))
    assert a.zone_of(4.5, 4.5) == 2  # in both: the first
    assert a.zone_of(6, 6) == 5
    assert a.zone_of(9, 1) == 0


def test_regions_by_name_and_index():
    a = walled(20, 10, regions=(Region("left", ((0, 0, 10, 10),)),
                                Region("right", ((10, 0, 20, 10),))))
    assert a.region_names == ["left", "right"]
    assert (a.region_of(10, 5), a.region_index(10, 5)) == ("left", 0)  # on both: the first
    assert (a.region_of(15, 5), a.region_index(15, 5)) == ("right", 1)
    assert (a.region_of(25, 5), a.region_index(25, 5)) == ("none", -1)
    assert walled(5, 5).region_of(1, 1) == "none" and walled(5, 5).region_names == []


# -- locations and walls --------------------------------------------------------------------

def test_the_nearest_location_of_each_point():
    a = walled(10, 10, locations=np.array([[1.0, 1.0], [9.0, 1.0], [5.0, 9.0]]))
    assert a.nearest_location(2.0, 2.0) == 0
    assert list(a.nearest_location(np.array([8.0, 5.0, 5.0]), np.array([2.0, 8.0, 5.1]))) == \
        [1, 2, 2]  # (5, 5.1): 5.66 from (1, 1) and (9, 1), 3.9 from (5, 9)
    assert a.nearest_location(5.0, 1.0) == 0  # a tie: the first
    grid = a.nearest_location(np.array([[1.0, 9.0]]), np.array([[1.0, 1.0]]))
    assert grid.shape == (1, 2) and list(grid[0]) == [0, 1]


def test_no_locations_gives_minus_one_shaped_like_the_points():
    a = walled(10, 10)
    got = a.nearest_location(np.zeros((2, 3)), np.zeros((2, 3)))
    assert got.shape == (2, 3) and np.all(got == -1) and got.dtype.kind == "i"
    assert a.nearest_location(1.0, 1.0) == -1


def test_wall_array_lists_the_walls_in_order():
    a = walled(10, 6)
    assert a.wall_array().tolist() == [[0, 0, 10, 0], [10, 0, 10, 6], [10, 6, 0, 6],
                                       [0, 6, 0, 0]]
    assert a.wall_array().dtype == float


def test_distance_to_walls_along_a_wall_and_past_its_ends():
    a = Arena("one", 40, 40, (((10.0, 10.0), (30.0, 10.0)),))
    assert a.distance_to_walls(20, 13) == pytest.approx(3.0, abs=1e-12)   # above its middle
    assert a.distance_to_walls(10, 7) == pytest.approx(3.0, abs=1e-12)    # below its end
    assert a.distance_to_walls(33, 14) == pytest.approx(5.0, abs=1e-12)   # past (30, 10)
    assert a.distance_to_walls(7, 6) == pytest.approx(5.0, abs=1e-12)     # before (10, 10)
    two = Arena("two", 40, 40, (((10.0, 10.0), (30.0, 10.0)), ((20.0, 12.0), (20.0, 30.0))))
    assert two.distance_to_walls(21, 13) == pytest.approx(1.0, abs=1e-12)  # the nearer one
    dot = Arena("dot", 40, 40, (((5.0, 5.0), (5.0, 5.0)),))  # a wall of no length: a point
    assert dot.distance_to_walls(8, 9) == pytest.approx(5.0, abs=1e-12)


def test_a_disc_is_free_exactly_on_its_bounds():
    a = walled(20, 10)
    # radius 2: 2.5 from every wall's centre line, inside by 2
    assert a.is_free(2.5, 5.0, 2.0) and a.is_free(17.5, 5.0, 2.0)
    assert a.is_free(10.0, 2.5, 2.0) and a.is_free(10.0, 7.5, 2.0)
    assert not a.is_free(2.49, 5.0, 2.0) and not a.is_free(17.51, 5.0, 2.0)
    assert not a.is_free(10.0, 2.49, 2.0) and not a.is_free(10.0, 7.51, 2.0)
    # without walls only the edges bound it: inside by the radius exactly
    open_ = Arena("open", 20, 10, (((100.0, 100.0), (101.0, 100.0)),))
    assert open_.is_free(2.0, 2.0, 2.0) and open_.is_free(18.0, 8.0, 2.0)
    for x, y in ((1.99, 5.0), (18.01, 5.0), (10.0, 1.99), (10.0, 8.01)):
        assert not open_.is_free(x, y, 2.0)


# -- the free grid --------------------------------------------------------------------------

def test_the_free_grid_by_hand():
    a = walled(10, 6)
    xs, ys, free = a.free_grid(1.0)
    assert xs.tolist() == [1, 3, 5, 7, 9] and ys.tolist() == [1, 3, 5]
    # radius 1: 1.5 from each wall; x = 1 and 9 are 1 from the side walls, y = 1 and 5 from
    # the top and bottom: only (3..7, 3)
    want = np.zeros((5, 3), bool)
    want[1:4, 1] = True
    assert free.shape == (5, 3) and np.array_equal(free, want)
    # radius 2.5 needs 3 from each wall: (3, 3) is exactly 3 from the left and the bottom
    assert np.array_equal(a.free_grid(2.5)[2], want)
    assert not a.free_grid(2.51)[2].any()
    # cells of 4: centres 2, 6 and 2 (the last cell may stick out)
    xs, ys, free = a.free_grid(1.0, cell=4.0)
    assert xs.tolist() == [2, 6] and ys.tolist() == [2]
    assert free.tolist() == [[True], [True]]  # 2 from the nearest wall


def test_the_free_grid_keeps_inside_the_edges_without_walls():
    a = Arena("open", 10, 6, (((100.0, 100.0), (101.0, 100.0)),))
    _, _, free = a.free_grid(1.0)
    assert free.all()  # x from 1 to 9 and y from 1 to 5: inside by 1 exactly
    _, _, free = a.free_grid(1.01)
    want = np.zeros((5, 3), bool)
    want[1:4, 1] = True
    assert np.array_equal(free, want)


# -- shortest paths -------------------------------------------------------------------------

STRIP = walled(20, 10)  # cells x = 1, 3, ..., 19, y = 1, 3, ..., 9


def test_a_straight_path_along_the_grid():
    # radius 1 (free: x 3..17, y 3..7), no clearance penalty: 7 steps of 2 cm
    length, pts = STRIP.shortest_path((3, 5), (17, 5), radius=1.0, clearance=0.0, thin=False)
    assert length == 14.0
    assert pts == [(float(x), 5.0) for x in range(3, 18, 2)]
    # thinned: every third point and the last
    assert STRIP.shortest_path((3, 5), (17, 5), radius=1.0, clearance=0.0) == \
        (14.0, [(3.0, 5.0), (9.0, 5.0), (15.0, 5.0), (17.0, 5.0)])
    # 7 points: every third (0, 3, 6), the last already among them
    assert STRIP.shortest_path((3, 5), (15, 5), radius=1.0, clearance=0.0)[1] == \
        [(3.0, 5.0), (9.0, 5.0), (15.0, 5.0)]


def test_the_start_and_goal_snap_to_the_nearest_cells():
    # (3.9, 4.2) is nearest the cell (3, 5), (16.2, 5.8) the cell (17, 5)
    length, pts = STRIP.shortest_path((3.9, 4.2), (16.2, 5.8), radius=1.0, clearance=0.0,
                                      thin=False)
    assert length == 14.0 and pts[0] == (3.0, 5.0) and pts[-1] == (17.0, 5.0)


def test_a_diagonal_step_costs_its_length():
    # (3, 3) to (7, 7) in a 10 x 10 box: two diagonal steps, 2 x 2 sqrt 2
    box = walled(10, 10)
    length, pts = box.shortest_path((3, 3), (7, 7), radius=1.0, clearance=0.0, thin=False)
    assert length == pytest.approx(4 * math.sqrt(2), abs=1e-12)
    assert pts == [(3.0, 3.0), (5.0, 5.0), (7.0, 7.0)]


def test_the_path_to_a_rectangle_ends_at_its_first_free_cell():
    # the rectangle x 12..20, y 0..10: its nearest free cell on the line y = 5 is (13, 5)
    length, pts = STRIP.shortest_path((3, 5), (12, 0, 20, 10), radius=1.0, clearance=0.0,
                                      thin=False)
    assert length == 10.0 and pts[-1] == (13.0, 5.0)


def test_an_unreachable_goal_gives_infinity_and_no_points():
    # a wall across the strip at x = 10
    cut = walled(20, 10, ((10.0, 0.0), (10.0, 10.0)))
    assert cut.shortest_path((3, 5), (17, 5), radius=1.0, clearance=0.0) == (math.inf, [])
    # a rectangle with no free cell
    assert STRIP.shortest_path((3, 5), (18.5, 0, 20, 10), radius=1.0) == (math.inf, [])
    assert cut.geodesic_distance((3, 5), (17, 5), radius=1.0) == math.inf


def test_a_blocked_point_keeps_the_path_its_radius_away():
    # a 20 x 14 box (free for radius 1: x 3..17, y 3..11); the straight line y = 7 passes
    # (9, 7): blocked with radius 3.5, the cells nearer than 3.5 to it are taken out (those at
    # 2 or 2.83 cm), so the path bends round; with radius 2 only the cell itself goes
    box = walled(20, 14)
    length, pts = box.shortest_path((3, 7), (17, 7), radius=1.0, clearance=0.0, thin=False,
                                    block=[(9.0, 7.0)], block_radius=2.0)
    assert (9.0, 7.0) not in pts and all(math.dist(p, (9, 7)) >= 2.0 for p in pts)
    assert length == pytest.approx(12 + 2 * 2 * math.sqrt(2) - 2, abs=1e-12)
    length, pts = box.shortest_path((3, 7), (17, 7), radius=1.0, clearance=0.0, thin=False,
                                    block=[(9.0, 7.0)], block_radius=3.5)
    assert all(math.dist(p, (9, 7)) >= 3.5 for p in pts)
    # without the block: straight, 14 cm
    assert box.shortest_path((3, 7), (17, 7), radius=1.0, clearance=0.0)[0] == 14.0


BOX = walled(20, 14)  # free for radius 1: x 3..17, y 3..11 (cells i 1..8, j 1..5)
# the bend from (3, 3) to (17, 3) through the row y = 5: 2 sqrt 2 + 10 + 2 sqrt 2 cm
BEND = [(3.0, 3.0)] + [(float(x), 5.0) for x in range(5, 16, 2)] + [(17.0, 3.0)]


def test_the_clearance_penalty_prefers_the_roomy_way():
    # from (3, 3) to (17, 3) along the bottom row (3 cm from the wall) or through the middle.
    # With clearance 3 (the default) a roomy cell is 4.5 cm from every wall: x 5..15, y 5..9.
    # The bottom row costs 3 a step (7 steps: 42); up to (5, 5) (2 sqrt 2, roomy), along y = 5
    # (10) and down to (17, 3) (3 x 2 sqrt 2) costs 21.3: the path leaves the wall
    length, pts = BOX.shortest_path((3, 3), (17, 3), radius=1.0, clearance=0.0, thin=False)
    assert length == 14.0 and all(y == 3.0 for _, y in pts)  # no penalty: the straight line
    length, pts = BOX.shortest_path((3, 3), (17, 3), radius=1.0, thin=False)
    assert length == pytest.approx(10 + 4 * math.sqrt(2), abs=1e-12) and pts == BEND


def test_the_graded_penalty_grows_with_the_clearance_missing():
    # clearance 10: no cell is roomy (11.5 cm from every wall), so the flat penalty is 3
    # everywhere and the path is the straight line
    length, pts = BOX.shortest_path((3, 3), (17, 3), radius=1.0, clearance=10.0, thin=False)
    assert length == 14.0 and all(y == 3.0 for _, y in pts)
    # graded: a free cell k cells from the nearest blocked one is e = 2k - 1 cm roomier than the
    # radius: 1 + 2 (1 - e / 10) = 2.8 on the rows y = 3 (k = 1), 2.4 on y = 5 (k = 2), 2 on
    # y = 7 (k = 3). Straight: 7 x 2 x 2.8 = 39.2; BEND: 2 sqrt 2 x 2.4 + 5 x 2 x 2.4 +
    # 2 sqrt 2 x 2.8 = 38.70; through y = 7: 39.16; so the bend
    length, pts = BOX.shortest_path((3, 3), (17, 3), radius=1.0, clearance=10.0, thin=False,
                                    graded=True)
    assert length == pytest.approx(10 + 4 * math.sqrt(2), abs=1e-12) and pts == BEND


def test_graded_without_clearance_is_the_plain_path():
    # clearance 0: every free cell is roomy, no penalty (and no division by 0)
    with np.errstate(all="raise"):
        got = BOX.shortest_path((3, 3), (17, 3), radius=1.0, clearance=0.0, thin=False,
                                graded=True)
    assert got == (14.0, [(float(x), 3.0) for x in range(3, 18, 2)])


def test_a_coarser_grid_takes_longer_steps():
    # cells of 4 in a 20 x 12 box: centres x 2..18, y 2, 6, 10, all 2 from the walls (free for
    # radius 1 and roomy with clearance 0.5)
    box = walled(20, 12)
    assert box.shortest_path((2, 6), (18, 6), radius=1.0, cell=4.0, clearance=0.5,
                             thin=False) == (16.0, [(float(x), 6.0) for x in range(2, 19, 4)])


def test_the_roomy_cells_are_on_the_same_coarse_grid():
    # cells of 4 in a 20 x 12 box, radius 1, clearance 1.5: a roomy centre is 3 from every
    # wall, only (6..14, 6). From (2, 2) to (18, 2): the bottom row costs 3 x 4 a step (48);
    # up to (6, 6) (4 sqrt 2), along y = 6 (8), and down to (18, 2) (3 x 4 sqrt 2): 30.6. The
    # cell (18, 6) is 2 from the wall, not roomy, so the last step is the diagonal
    box = walled(20, 12)
    assert box.shortest_path((2, 2), (18, 2), radius=1.0, cell=4.0, clearance=1.5,
                             thin=False) == \
        (pytest.approx(8 + 8 * math.sqrt(2), abs=1e-12),
         [(2.0, 2.0), (6.0, 6.0), (10.0, 6.0), (14.0, 6.0), (18.0, 2.0)])


def test_a_goal_rectangle_holds_its_edges():
    # the rectangle's left edge x = 13 is a cell centre: reached there (10 cm from (3, 5))
    assert STRIP.shortest_path((3, 5), (13, 0, 20, 10), radius=1.0, clearance=0.0,
                               thin=False)[1][-1] == (13.0, 5.0)
    # its bottom edge y = 7: the cell (9, 7) above (9, 3) is 4 cm away
    length, pts = STRIP.shortest_path((9, 3), (0, 7, 20, 10), radius=1.0, clearance=0.0)
    assert length == 4.0 and pts[-1] == (9.0, 7.0)


OPEN = Arena("open", 20, 14, (((100.0, 100.0), (101.0, 100.0)),))  # every cell free, radius 1


def test_an_avoided_point_costs_three_times_near_it():
    # avoid (7, 7) within 1 cm: only its own cell. From (5, 7) to (9, 7) straight costs
    # 2 x 3 + 2 = 8; round it (5, 7) -> (7, 5) -> (9, 7) costs 4 sqrt 2 = 5.66
    length, pts = OPEN.shortest_path((5, 7), (9, 7), radius=1.0, clearance=0.0, thin=False,
                                     avoid=[(7.0, 7.0)], avoid_radius=1.0)
    assert length == pytest.approx(4 * math.sqrt(2), abs=1e-12) and (7.0, 7.0) not in pts
    # the same along the top row (y = 13, the last): only downwards round it
    length, pts = OPEN.shortest_path((5, 13), (9, 13), radius=1.0, clearance=0.0, thin=False,
                                     avoid=[(7.0, 13.0)], avoid_radius=1.0)
    assert pts == [(5.0, 13.0), (7.0, 11.0), (9.0, 13.0)]
    # a point beyond the arena is taken at its nearest cell, (19, 13): the goal, entered anyway
    assert OPEN.shortest_path((15, 13), (19, 13), radius=1.0, clearance=0.0, thin=False,
                              avoid=[(21.0, 15.0)], avoid_radius=1.0) == \
        (4.0, [(15.0, 13.0), (17.0, 13.0), (19.0, 13.0)])


def test_an_avoided_path_is_sampled_at_eight_points_a_segment():
    # a 60 x 10 open arena, the path (1, 5)-(59, 5) to avoid within 1 cm: its 8 points
    # x = 1 + 58 k / 7 fall in the cells x = 1, 9, 17, 25, 35, 43, 51, 59 of the row y = 5.
    # From (9, 1) to (9, 9): (9, 5) costs 3, its neighbours (7, 5) and (11, 5) do not: round
    # one, 2 + 4 sqrt 2 + 2 = 9.66 (cost 9.66 < 12 straight)
    arena = Arena("long", 60, 10, (((100.0, 100.0), (101.0, 100.0)),))
    length, pts = arena.shortest_path((9, 1), (9, 9), radius=1.0, clearance=0.0, thin=False,
                                      avoid=[(1.0, 5.0), (59.0, 5.0)], avoid_radius=1.0)
    assert length == pytest.approx(4 + 4 * math.sqrt(2), abs=1e-12) and (9.0, 5.0) not in pts
    # and (13, 1) to (13, 9) crosses at (13, 5), between two points: straight
    assert arena.shortest_path((13, 1), (13, 9), radius=1.0, clearance=0.0,
                               avoid=[(1.0, 5.0), (59.0, 5.0)], avoid_radius=1.0)[0] == 8.0


WIDE = Arena("wide", 60, 40, (((100.0, 100.0), (101.0, 100.0)),))  # cells x 1..59, y 1..39


def test_the_default_avoid_radius_is_10_cm():
    # avoid (31, 1): the row y = 11 is 10 cm from it at x = 31, not nearer than 10: straight,
    # 58 cm. With 11 cm, the cells x = 27..35 of that row are near: the path bends up a row
    # round them (the ends 2 sqrt 2 each instead of 2)
    length = WIDE.shortest_path((1, 11), (59, 11), radius=1.0, clearance=0.0,
                                avoid=[(31.0, 1.0)])[0]
    assert length == 58.0
    assert WIDE.shortest_path((1, 11), (59, 11), radius=1.0, clearance=0.0, avoid=[(31.0, 1.0)],
                              avoid_radius=11.0)[0] == pytest.approx(54 + 4 * math.sqrt(2))


def test_the_default_block_radius_is_25_cm():
    # block (31, 2): the row y = 27 is 25 cm from it at x = 31, not nearer: straight, 58 cm;
    # with 26 cm the cell (31, 27) and its neighbours are taken out: longer
    assert WIDE.shortest_path((1, 27), (59, 27), radius=1.0, clearance=0.0,
                              block=[(31.0, 2.0)])[0] == 58.0
    assert WIDE.shortest_path((1, 27), (59, 27), radius=1.0, clearance=0.0, block=[(31.0, 2.0)],
                              block_radius=26.0)[0] > 58.0


def test_each_blocked_point_stands_alone():
    # two points: (9, 7) and (15, 3) within 2 cm; x and y of each are taken as given
    box = walled(20, 14)
    length, pts = box.shortest_path((3, 7), (17, 7), radius=1.0, clearance=0.0, thin=False,
                                    block=[(9.0, 7.0), (15.0, 3.0)], block_radius=2.0)
    assert length == pytest.approx(10 + 4 * math.sqrt(2), abs=1e-12) and (9.0, 7.0) not in pts
    # blocking (7, 9) instead (x and y swapped) leaves the row y = 7 open
    assert box.shortest_path((3, 7), (17, 7), radius=1.0, clearance=0.0,
                             block=[(7.0, 9.0)], block_radius=2.0)[0] == 14.0


def test_a_path_may_use_the_last_column_and_row():
    # the open arena: (19, 13) is a free cell; a path along the edge expands to it and past
    length, pts = OPEN.shortest_path((11, 13), (19, 5), radius=1.0, clearance=0.0, thin=False)
    assert length == pytest.approx(4 * 2 * math.sqrt(2), abs=1e-12)
    assert pts[-1] == (19.0, 5.0)
    assert OPEN.shortest_path((19, 1), (19, 13), radius=1.0, clearance=0.0)[0] == 12.0


# -- geodesic distances ---------------------------------------------------------------------

def test_a_tight_turn_round_a_wall_end_is_no_shorter_than_the_taut_string():
    # a wall (50, 0)-(50, 40), the disc keeping r = 3.7 + 0.5 from its centre line: from
    # P = (44, 38) to Q = (56, 38) round the end C = (50, 40). Tangents of sqrt(d^2 - r^2) with
    # d = |PC| = sqrt 40, and the arc between them: 2 pi - angle PCQ - 2 acos(r / d), with
    # angle PCQ = pi - 2 atan(2 / 6)
    arena = walled(100, 60, ((50.0, 0.0), (50.0, 40.0)))
    r, d = 4.2, math.sqrt(40.0)
    pcq = math.pi - 2 * math.atan(2 / 6)
    optimum = 2 * math.sqrt(d * d - r * r) + r * (2 * math.pi - pcq - 2 * math.acos(r / d))
    g = arena.geodesic_distance((44, 38), (56, 38))
    assert optimum <= g <= 1.08 * optimum


def test_the_geodesic_to_a_rectangle_ends_at_its_nearest_point():
    # from (3, 5) in the strip straight to the rectangle x >= 12.5: 9.5 cm
    assert STRIP.geodesic_distance((3, 5), (12.5, 0, 20, 10), radius=1.0) == \
        pytest.approx(9.5, abs=1e-12)
    # to a point: the straight line, whatever the grid
    assert STRIP.geodesic_distance((3.3, 4.1), (16.7, 6.2), radius=1.0) == \
        pytest.approx(math.hypot(13.4, 2.1), abs=1e-12)


# -- free poses -----------------------------------------------------------------------------

def test_a_free_pose_is_the_first_free_draw_and_a_heading():
    box = walled(100, 100, name="box")
    rng = np.random.default_rng(3)
    want = (rng.uniform(20, 80), rng.uniform(30, 70), rng.uniform(-math.pi, math.pi))
    got = box.sample_free_pose(np.random.default_rng(3), rect=(20, 30, 80, 70))
    assert got == want and all(type(v) is float for v in got)
    # the whole arena by default: x and y over 0..100 (this seed's first draw is free)
    rng = np.random.default_rng(0)
    want = (rng.uniform(0, 100), rng.uniform(0, 100), rng.uniform(-math.pi, math.pi))
    assert all(6.2 <= v <= 93.8 for v in want[:2])
    assert box.sample_free_pose(np.random.default_rng(0)) == want


def test_a_free_pose_keeps_radius_and_margin_from_the_walls():
    # 3.7 + 2 + 0.5 = 6.2 from a wall: the square 6.2..7 is free; with a margin of 3 it is not
    box = walled(100, 100, name="box")
    x, y, _ = box.sample_free_pose(np.random.default_rng(1), rect=(6.2, 6.2, 7.0, 7.0))
    assert 6.2 <= x <= 7.0 and 6.2 <= y <= 7.0
    with pytest.raises(RuntimeError, match=r"^no free pose found in box inside "
                                           r"\(6\.2, 6\.2, 7\.0, 7\.0\)$"):
        box.sample_free_pose(np.random.default_rng(1), margin=3.0, rect=(6.2, 6.2, 7.0, 7.0))
    with pytest.raises(RuntimeError, match=r"^no free pose found in box inside "
                                           r"\(6\.2, 6\.2, 7\.0, 7\.0\)$"):
        box.sample_free_pose(np.random.default_rng(1), radius=4.8, rect=(6.2, 6.2, 7.0, 7.0))


# -- the segment test -----------------------------------------------------------------------

WALL = np.array([[0.0, 0.0, 10.0, 0.0]])


def test_a_segment_is_clear_at_the_reach_exactly():
    assert _segment_clear((0, 5), (10, 5), WALL, 5.0)  # parallel, 5 away
    assert not _segment_clear((0, 5), (10, 5), WALL, 5.01)
    # beside the wall's end (10, 0): 2 away
    assert _segment_clear((12, -5), (12, 5), WALL, 2.0)
    assert not _segment_clear((12, -5), (12, 5), WALL, 2.01)
    # its end point nearest: (3, 4) is 4 from the wall
    assert _segment_clear((3, 4), (3, 9), WALL, 4.0)
    assert not _segment_clear((3, 9), (3, 4), WALL, 4.01)


def test_a_crossing_segment_is_never_clear_and_a_touching_one_only_at_reach_0():
    assert not _segment_clear((5, -1), (5, 1), WALL, 0.0)
    # from a point on the wall: touching, not crossing
    assert _segment_clear((5, 0), (5, 5), WALL, 0.0)
    assert not _segment_clear((5, 0), (5, 5), WALL, 0.01)
    # 0.01 above it, the cross products' product is 0.5 (< 1, > 0): not crossing
    assert _segment_clear((5, 0.01), (5, 0.5), WALL, 0.005)


def test_short_walls_are_measured_to_their_own_length():
    # a wall 0.5 cm long (its squared length 0.25 < 1): from (0.5, 1) the nearest point is
    # its end (0.5, 0), 1 away
    short = Arena("short", 10, 10, (((0.0, 0.0), (0.5, 0.0)),))
    assert short.distance_to_walls(0.5, 1.0) == pytest.approx(1.0, abs=1e-12)
    assert short.distance_to_walls(0.25, 1.0) == pytest.approx(1.0, abs=1e-12)
    walls = np.array([[0.0, 0.0, 0.5, 0.0]])
    assert _segment_clear((0.5, 1.0), (0.5, 2.0), walls, 1.0)
    assert not _segment_clear((0.5, 1.0), (0.5, 2.0), walls, 1.01)
    # the free grid likewise: the centre (1, 1) of 2 cm cells is hypot(0.5, 1) from the wall
    _, _, free = Arena("short", 4, 4, (((0.0, 0.0), (0.5, 0.0)),)).free_grid(0.5)
    assert free[0, 0] == (math.hypot(0.5, 1.0) >= 1.0)
    _, _, free = Arena("short", 4, 4, (((0.0, 0.0), (0.5, 0.0)),)).free_grid(0.62)
    assert not free[0, 0]  # hypot(0.5, 1) = 1.118 < 1.12


def test_a_segment_is_measured_from_walls_anywhere_in_the_plane():
    # the wall (2, 3)-(12, 3), away from the origin
    wall = np.array([[2.0, 3.0, 12.0, 3.0]])
    assert _segment_clear((4, 7), (10, 7), wall, 4.0)  # parallel, 4 above
    assert not _segment_clear((4, 7), (10, 7), wall, 4.01)
    assert not _segment_clear((6, 0), (8, 10), wall, 0.0)  # crosses it
    assert _segment_clear((14, 0), (16, 10), wall, 1.9)  # beside its end (12, 3): 2.0 ... 3.3
    assert not _segment_clear((6, 1), (9, 2), wall, 1.01)  # below it, 1 away at (9, 2)
    assert _segment_clear((6, 1), (9, 2), wall, 1.0)


def test_past_the_ends_the_nearest_point_is_the_end():
    # a segment beyond the wall's end: the nearest points are (10, 0) and (12, 1), sqrt 5 apart
    # (not 1, the distance to the wall's line)
    assert _segment_clear((12, 1), (20, 1), WALL, 2.2)
    assert not _segment_clear((12, 1), (20, 1), WALL, 2.3)
    # a wall beyond the segment's end: from (4, 0) to the wall's end (6, 1), sqrt 5 (not 1)
    wall = np.array([[6.0, 1.0, 6.0, 10.0]])
    assert _segment_clear((0, 0), (4, 0), wall, 2.2)
    assert not _segment_clear((0, 0), (4, 0), wall, 2.3)


def test_short_segments_are_measured_to_their_own_length():
    # a wall 0.5 long under the middle of the segment: 1 away; a segment 0.5 long over the end
    # of a wall: 1 away (squared lengths 0.25 < 1)
    walls = np.array([[0.0, 0.0, 0.5, 0.0]])
    assert not _segment_clear((0.25, 1.0), (0.25, 2.0), walls, 1.01)
    walls = np.array([[0.25, 0.0, 0.25, -5.0]])
    assert not _segment_clear((0.0, 1.0), (0.5, 1.0), walls, 1.01)
    assert _segment_clear((0.0, 1.0), (0.5, 1.0), walls, 1.0)


def test_a_segment_through_a_wall_end_or_ending_on_the_wall_only_touches():
    # through the wall's end (10, 0), either way round, and ending on the wall: touching (the
    # cross products are 0), clear at reach 0, not beyond
    for p, q in (((10, -1), (10, 1)), ((10, 1), (10, -1)), ((5, -5), (5, 0)), ((5, 0), (5, -5))):
        assert _segment_clear(p, q, WALL, 0.0)
        assert not _segment_clear(p, q, WALL, 0.01)
    # 0.01 past the end: s1 is 0.4 (> 0, < 1), not crossing; 0.01 away
    assert _segment_clear((10.01, -1), (10.01, 1), WALL, 0.005)


def test_the_geodesic_grid_has_the_cell_given():
    # a wall along y = 4 cuts a 20 x 10 box; above it, the row y = 7 of 2 cm cells is free for
    # radius 1. Cells of 8 have their only row at y = 4, on the wall: no path
    arena = walled(20, 10, ((0.0, 4.0), (20.0, 4.0)))
    assert arena.geodesic_distance((2, 7), (18, 7), radius=1.0) == pytest.approx(16.0)
    assert arena.geodesic_distance((2, 7), (18, 7), radius=1.0, cell=8.0) == math.inf


def test_a_geodesic_into_a_one_point_rectangle_is_the_geodesic_to_the_point():
    # round the wall end (50, 40): into the rectangle (61, 11)-(61, 11) (a cell centre) as to
    # the point itself: the same grid path, pulled taut the same way
    arena = walled(100, 60, ((50.0, 0.0), (50.0, 40.0)))
    to_point = arena.geodesic_distance((20, 10), (61, 11))
    assert arena.geodesic_distance((20, 10), (61, 11, 61, 11)) == pytest.approx(to_point,
                                                                                abs=1e-9)
    assert to_point > math.dist((20, 10), (50, 40)) + math.dist((50, 40), (61, 11))


def test_the_default_radius_is_the_e_puck_s():
    # radius 3.7: a centre 4.2 from every wall; in the 20 x 14 box (5, 5) and (15, 5) are free
    # (5 away), 10 cm apart; with 4.7 (5.2 needed) they are not
    assert BOX.shortest_path((5, 5), (15, 5), clearance=0.0)[0] == 10.0
    assert BOX.shortest_path((5, 5), (15, 5), radius=4.7, clearance=0.0) == (math.inf, [])


def test_a_goal_rectangle_holds_its_far_edges():
    # reached from the right: its right edge x = 13 is a cell centre (4 cm from (17, 5))
    length, pts = STRIP.shortest_path((17, 5), (0, 0, 13, 10), radius=1.0, clearance=0.0)
    assert length == 4.0 and pts[-1] == (13.0, 5.0)
    # from above: its top edge y = 7 (4 cm from (9, 11))
    length, pts = BOX.shortest_path((9, 11), (0, 0, 20, 7), radius=1.0, clearance=0.0)
    assert length == 4.0 and pts[-1] == (9.0, 7.0)


def test_a_path_may_use_the_first_column_and_row():
    assert OPEN.shortest_path((1, 1), (1, 13), radius=1.0, clearance=0.0)[0] == 12.0
    assert OPEN.shortest_path((1, 1), (19, 1), radius=1.0, clearance=0.0)[0] == 18.0


def test_avoided_points_off_the_grid_are_taken_at_the_nearest_cell():
    # (1, 7) on the first column and (-3, 7) beyond it both mark the cell (1, 7): from (1, 5)
    # to (1, 9) round it, 4 sqrt 2 (cost 5.66 < 8)
    for point in ((1.0, 7.0), (-3.0, 7.0)):
        _, pts = OPEN.shortest_path((1, 5), (1, 9), radius=1.0, clearance=0.0, thin=False,
                                    avoid=[point], avoid_radius=1.0)
        assert pts == [(1.0, 5.0), (3.0, 7.0), (1.0, 9.0)]
    # (9, -3) below the first row marks (9, 1)
    _, pts = OPEN.shortest_path((7, 1), (11, 1), radius=1.0, clearance=0.0, thin=False,
                                avoid=[(9.0, -3.0)], avoid_radius=1.0)
    assert pts == [(7.0, 1.0), (9.0, 3.0), (11.0, 1.0)]


def test_an_avoided_path_of_three_points_is_two_segments():
    # (1, 5) - (19, 5) - (19, 13): the second segment's 8 points, y = 5 + 8 k / 7, mark the
    # cells (19, 5), (19, 7), ..., (19, 13). From (19, 7) to (19, 11) (the goal marked too,
    # cost 6 to enter): straight 6 + 6 = 12; (17, 9), (17, 11), (19, 11): 2 sqrt 2 + 2 + 6
    # = 10.83, the cheapest
    length, pts = OPEN.shortest_path((19, 7), (19, 11), radius=1.0, clearance=0.0, thin=False,
                                     avoid=[(1.0, 5.0), (19.0, 5.0), (19.0, 13.0)],
                                     avoid_radius=1.0)
    assert pts == [(19.0, 7.0), (17.0, 9.0), (17.0, 11.0), (19.0, 11.0)]
    assert length == pytest.approx(4 + 2 * math.sqrt(2), abs=1e-12)


def test_the_eighth_points_fall_where_eight_put_them():
    # the long arena's row y = 5 is marked at x = 1, 9, 17, 25, 35, 43, 51, 59 (not at 15 or 29
    # as nine points would): crossing at x = 17 goes round, at x = 15 straight
    arena = Arena("long", 60, 10, (((100.0, 100.0), (101.0, 100.0)),))
    line = [(1.0, 5.0), (59.0, 5.0)]
    assert arena.shortest_path((17, 1), (17, 9), radius=1.0, clearance=0.0, avoid=line,
                               avoid_radius=1.0)[0] == pytest.approx(4 + 4 * math.sqrt(2))
    for x in (15, 29):
        assert arena.shortest_path((x, 1), (x, 9), radius=1.0, clearance=0.0, avoid=line,
                                   avoid_radius=1.0)[0] == 8.0


class Scripted:
    """A stand-in generator: uniform() hands out the scripted values in turn."""

    def __init__(self, values) -> None:
        self.values = iter(values)

    def uniform(self, lo: float, hi: float) -> float:
        return next(self.values)


def test_a_free_pose_is_given_up_after_ten_thousand_draws():
    # 9 999 draws on the wall, then (50, 50): found; 10 000 on the wall: not
    box = walled(100, 100, name="box")
    assert box.sample_free_pose(Scripted([0.0, 0.0] * 9999 + [50.0, 50.0, 1.0])) == \
        (50.0, 50.0, 1.0)
    with pytest.raises(RuntimeError, match=r"^no free pose found in box inside None$"):
        box.sample_free_pose(Scripted([0.0, 0.0] * 10_000 + [50.0, 50.0, 1.0]))


def test_a_roomy_cell_costs_a_third_of_a_cramped_one():
    # the 20 x 14 box, radius 1, clearance 3: roomy x 5..15, y 5..9. From (3, 3) to (3, 7) up
    # the cramped column x = 3: 2 x 2 x 3 = 12; by (5, 5) and (5, 7) (roomy) and back:
    # 2 sqrt 2 + 2 + 2 x 3 = 10.83, cheaper (at 2 a roomy cell it would cost 15.66)
    length, pts = BOX.shortest_path((3, 3), (3, 7), radius=1.0, thin=False)
    assert pts == [(3.0, 3.0), (5.0, 5.0), (5.0, 7.0), (3.0, 7.0)]
    assert length == pytest.approx(4 + 2 * math.sqrt(2), abs=1e-12)


def test_graded_with_a_small_clearance_is_graded():
    # radius 1.6 (2.1 from the walls), clearance 1: every free cell is at least 1 cm roomier
    # than the radius (e = 2 k - 1 >= 1), so its graded penalty is 1: the straight line along
    # y = 3. The flat penalty would make that row (3 from the wall, < 3.1) cost 3 and bend
    length, pts = BOX.shortest_path((3, 3), (17, 3), radius=1.6, clearance=1.0, thin=False,
                                    graded=True)
    assert length == 14.0 and all(y == 3.0 for _, y in pts)
    assert BOX.shortest_path((3, 3), (17, 3), radius=1.6, clearance=1.0, thin=False)[1] == BEND


def test_a_graded_roomy_cell_costs_one():
    # clearance 3, graded: the bottom row (k = 1, e = 1) costs 1 + 2 (1 - 1/3) = 7/3 a cm, a
    # roomy cell 1. From (3, 3) to (13, 3): straight 10 x 7/3 = 23.3; up to (5, 5), along y = 5
    # to (11, 5) and down to (13, 3): 2 sqrt 2 + 6 + 2 sqrt 2 x 7/3 = 15.43 (leaving at (13, 5)
    # instead: 15.50); were a roomy cell to cost 2, the bend would cost 24.3
    length, pts = BOX.shortest_path((3, 3), (13, 3), radius=1.0, thin=False, graded=True)
    assert pts == [(3.0, 3.0), (5.0, 5.0), (7.0, 5.0), (9.0, 5.0), (11.0, 5.0), (13.0, 3.0)]
    assert length == pytest.approx(6 + 4 * math.sqrt(2), abs=1e-12)


def test_a_geodesic_between_neighbouring_cells_is_the_straight_line():
    # start and goal in neighbouring cells: a grid path of two points, pulled taut to the line
    assert STRIP.geodesic_distance((3, 5), (5, 5), radius=1.0) == 2.0
    assert STRIP.geodesic_distance((3.3, 4.7), (5.1, 5.2), radius=1.0) == \
        pytest.approx(math.hypot(1.8, 0.5), abs=1e-12)


def test_a_grid_step_grazing_a_wall_end_is_kept():
    # the wall (48, 0)-(48, 38.9): the cells (47, 43) and (49, 43) are hypot(1, 4.1) = 4.22 from
    # its end, free for the reach 4.2, but the step between them passes 4.1 from it. Pulling
    # taut keeps such a step rather than search on (which never ended). From P = (40, 30) to
    # Q = (56, 30) round the end C: tangents sqrt(d^2 - r^2), d = hypot(8, 8.9), and the arc
    # 2 pi - angle PCQ - 2 acos(r / d), angle PCQ = 2 atan(8 / 8.9)
    arena = walled(100, 60, ((48.0, 0.0), (48.0, 38.9)))
    r, d = 4.2, math.hypot(8.0, 8.9)
    optimum = 2 * math.sqrt(d * d - r * r) + r * (2 * math.pi - 2 * math.atan(8 / 8.9)
                                                  - 2 * math.acos(r / d))
    assert optimum <= arena.geodesic_distance((40, 30), (56, 30)) <= 1.08 * optimum


def test_an_arena_without_walls_is_open_floor():
    # built directly (the builder refuses one): every disc inside the bounds is free, no wall
    # is near, and the free grid is the bounds shrunk by the radius
    open_floor = Arena(name="open", width=50.0, height=40.0, walls=(), zones=(), regions=(),
                       locations=np.zeros((0, 2)), start_pose=(25.0, 20.0, 0.0), landmarks={})
    assert open_floor.wall_array().shape == (0, 4)
    assert open_floor.distance_to_walls(1.0, 1.0) == math.inf
    assert open_floor.is_free(25.0, 20.0, 3.7) and open_floor.is_free(4.0, 4.0, 4.0)
    assert not open_floor.is_free(3.9, 20.0, 4.0)          # the bounds still hold
    xs, ys, free = open_floor.free_grid(4.0, cell=10.0)     # centres 5, 15, ..., 45 and 5..35
    assert list(xs) == [5.0, 15.0, 25.0, 35.0, 45.0] and list(ys) == [5.0, 15.0, 25.0, 35.0]
    assert free.all()
