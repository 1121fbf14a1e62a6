"""The papers' arenas by hand (hippo.sim.arenas), each against the design its docstring gives.

Each arena's walls are rebuilt here from its documented dimensions (room sizes, corridor
widths, chamfers, the central block) and compared as a set of segments, its corridors
measured with ``distance_to_walls`` on their centre lines (half the documented width), its
regions derived from the same walls, its locations from their rule (a grid of cell centres,
points every 15 cm along corridor centre lines) and its landmarks and start from the places
the design names. The maze is checked as a perfect maze (a spanning tree of the grid, its
first passage drawn by hand from the seed's generator) whose walls cover exactly the grid
edges that are no passage, merged into maximal runs; its cell size, grid and seed are refused
by name when bad (a cell of -1 was reported as an arena of -8 x -8, n = 1.5 failed in range(),
seed -1 with numpy's words). ``_corridor_points`` is worked by hand
on small polylines (round half to even at 22.5 and 37.5 cm), and ``get`` refuses word for
word: a non-string (its repr shown up to 60 characters exactly), an unknown name.
"""

from __future__ import annotations

import itertools
import math
import re

import numpy as np
import pytest

from hippo.sim import arenas
from hippo.sim.arena import Arena
from hippo.sim.arenas import _corridor_points, _perfect_maze

NAMES = "two-rooms, maze-e1, goal-arena, patrol-course"


def refused(message: str):
    return pytest.raises(ValueError, match="^" + re.escape(message) + "$")


def segments(walls) -> set[frozenset[tuple[float, float]]]:
    """The walls as a set of undirected segments."""
    out = {frozenset((tuple(map(float, a)), tuple(map(float, b)))) for a, b in walls}
    assert len(out) == len(walls), "a wall is repeated"
    return out


def chain(*points: tuple[float, float], closed: bool = False) -> list:
    pts = list(points) + ([points[0]] if closed else [])
    return list(itertools.pairwise(pts))


def rect_walls(x0: float, y0: float, x1: float, y1: float) -> list:
    return chain((x0, y0), (x1, y0), (x1, y1), (x0, y1), closed=True)


def points(arena: Arena) -> list[tuple[float, float]]:
    return [(float(x), float(y)) for x, y in arena.locations]


# ---------------------------------------------------------------------------- two rooms
def test_two_rooms_walls_are_the_documented_rooms_corridor_and_chamfers():
    a = arenas.two_rooms()
    assert (a.name, a.width, a.height) == ("two-rooms", 120.0, 90.0)
    # the corridor: 24 cm wide at mid-height (45 of 90): walls at y = 33 and 57
    lo, hi = 45 - 12, 45 + 12
    room_a = chain((30, lo), (30, 0), (0, 0), (0, 90), (30, 90), (30, hi))
    corridor = [((30, lo), (60, lo)), ((30, hi), (60, hi))]
    c = 12  # room B (x 60-120) with 12 cm chamfers in its four corners
    room_b = chain((60, hi), (60, 90 - c), (60 + c, 90), (120 - c, 90), (120, 90 - c),
                   (120, c), (120 - c, 0), (60 + c, 0), (60, c), (60, lo))
    # the buttress on the east wall: 8 cm deep, 8 cm high, from y = 40
    buttress = chain((120, 40), (112, 40), (112, 48), (120, 48))
    assert segments(a.walls) == segments(room_a + corridor + room_b + buttress)
    assert a.zones == () and a.landmarks == {}


def test_two_rooms_widths_measured_on_centre_lines():
    a = arenas.two_rooms()
    assert a.distance_to_walls(15, 20) == 15.0       # room A: 30 cm wide
    assert a.distance_to_walls(45, 45) == 12.0       # the corridor: 24 cm
    # room B: 30 cm to each side wall at mid-height, but the buttress 8 cm nearer
    assert a.distance_to_walls(90, 45) == 22.0
    # the south-west chamfer, the line x + y = 72 from (72, 0) to (60, 12), seen from
    # (70, 10): |70 + 10 - 72| / sqrt 2 = 4 sqrt 2 (its foot (66, 6) lies on the segment)
    assert a.distance_to_walls(70, 10) == pytest.approx(4 * math.sqrt(2), abs=1e-12)


def test_two_rooms_regions_rooms_and_the_corridor_centred_between_its_walls():
    a = arenas.two_rooms()
    assert a.region_names == ["room_a", "corridor", "room_b"]
    assert a.regions[0].rects == ((0.0, 0.0, 30.0, 90.0),)       # room A: x < 30
    assert a.regions[2].rects == ((60.0, 0.0, 120.0, 90.0),)     # room B: x > 60
    ((x0, y0, x1, y1),) = a.regions[1].rects
    assert (x0, x1) == (30.0, 60.0)            # 30 <= x <= 60
    assert (y0 + y1) / 2 == 45.0               # centred at mid-height
    assert 33 < y0 < y1 < 57 and y1 - y0 == 16.0  # 4 cm clear of each corridor wall
    assert (a.region_of(29.5, 45), a.region_of(45, 45), a.region_of(61, 45)) == (
        "room_a", "corridor", "room_b")


def test_two_rooms_25_locations_room_a_grid_corridor_and_room_b():
    a = arenas.two_rooms()
    # room A: two columns 6 cm either side of its axis x = 15, five rows every 18 cm from 9
    room_a = [(x, 9.0 + 18 * k) for k in range(5) for x in (15.0 - 6, 15.0 + 6)]
    corridor = [(38.0, 45.0), (52.0, 45.0)]     # 8 cm inside each end, at mid-height
    room_b = [(x, y) for y in (12.0, 33.0, 57.0, 78.0) for x in (72.0, 90.0, 110.0)]
    room_b.append((84.0, 45.0))
    assert points(a) == room_a + corridor + room_b
    assert len(a.locations) == 25 and a.locations.dtype == float
    regions = [a.region_of(x, y) for x, y in points(a)]
    assert regions == ["room_a"] * 10 + ["corridor"] * 2 + ["room_b"] * 13


def test_two_rooms_start_in_room_a_facing_north():
    a = arenas.two_rooms()
    assert a.start_pose == (15.0, 20.0, math.pi / 2)
    assert a.region_of(*a.start_pose[:2]) == "room_a"


# ---------------------------------------------------------------------------- the maze
def test_a_one_cell_maze_has_no_passage():
    assert _perfect_maze(1, 0) == set()


@pytest.mark.parametrize("n, seed", [(2, 0), (3, 1), (5, 7), (8, 1)])
def test_the_maze_is_a_spanning_tree_of_the_grid(n, seed):
    passages = _perfect_maze(n, seed)
    assert len(passages) == n * n - 1
    parent = {(i, j): (i, j) for i in range(n) for j in range(n)}

    def root(c):
        while parent[c] != c:
            c = parent[c]
        return c

    for a, b in passages:
        assert a < b                                       # (min, max)
        assert abs(a[0] - b[0]) + abs(a[1] - b[1]) == 1    # neighbours
        assert all(0 <= v < n for v in (*a, *b))
        ra, rb = root(a), root(b)
        assert ra != rb                                    # no cycle
        parent[ra] = rb
    assert len({root(c) for c in parent}) == 1             # connected


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_the_first_two_passages_are_drawn_by_hand(seed):
    rng = np.random.default_rng(seed)
    # from (0, 0) in the order +x, -x, +y, -y, inside the grid: (1, 0) and (0, 1)
    first = [(1, 0), (0, 1)][int(rng.integers(2))]
    # from there, unseen neighbours in the same order (a 4 x 4 grid)
    second_choices = [(2, 0), (1, 1)] if first == (1, 0) else [(1, 1), (0, 2)]
    second = second_choices[int(rng.integers(2))]
    passages = _perfect_maze(4, seed)
    assert ((0, 0), first) in passages
    assert (min(first, second), max(first, second)) in passages


def _dfs_by_the_docstring(n: int, seed: int) -> set:
    """The documented search, written out: from (0, 0), the unvisited neighbours of the cell on
    top of the stack in the order +x, -x, +y, -y, one drawn with integers(k); none: pop."""
    rng = np.random.default_rng(seed)
    stack, seen, out = [(0, 0)], {(0, 0)}, set()
    while stack:
        x, y = stack[-1]
        free = [q for q in ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1))
                if q[0] in range(n) and q[1] in range(n) and q not in seen]
        if free:
            q = free[int(rng.integers(len(free)))]
            out.add(tuple(sorted([(x, y), q])))
            seen.add(q)
            stack.append(q)
        else:
            stack.pop()
    return out


@pytest.mark.parametrize("n, seed", [(3, 0), (3, 4), (4, 2), (5, 9), (8, 1)])
def test_the_maze_follows_the_documented_search_step_by_step(n, seed):
    # the neighbours' order decides which one each draw picks: the default maze (8, seed 1)
    # is the maze scenario's arena
    assert _perfect_maze(n, seed) == _dfs_by_the_docstring(n, seed)


def test_the_maze_is_the_same_for_a_seed_and_differs_across_seeds():
    assert _perfect_maze(8, 1) == _perfect_maze(8, 1)
    assert _perfect_maze(8, 1) != _perfect_maze(8, 2)


def _covered(walls, cell: float, n: int) -> list[tuple[tuple[int, int], tuple[int, int]]]:
    """The grid edges (between two cells) that the interior walls cover, one entry per cell
    edge covered (so a double cover shows twice); the outer walls are set apart."""
    out = []
    size = n * cell
    for (x0, y0), (x1, y1) in walls:
        if x0 == x1 and x0 not in (0, size):          # vertical, on x = i * cell
            i = round(x0 / cell)
            for j in range(round(min(y0, y1) / cell), round(max(y0, y1) / cell)):
                out.append(((i - 1, j), (i, j)))
        elif y0 == y1 and y0 not in (0, size):        # horizontal, on y = j * cell
            j = round(y0 / cell)
            for i in range(round(min(x0, x1) / cell), round(max(x0, x1) / cell)):
                out.append(((i, j - 1), (i, j)))
    return out


@pytest.mark.parametrize("cell, n, seed", [(40.0, 8, 1), (10.0, 3, 5), (20.0, 4, 2)])
def test_maze_walls_cover_every_edge_that_is_no_passage_in_maximal_runs(cell, n, seed):
    a = arenas.maze_e1(cell=cell, n=n, seed=seed)
    size = n * cell
    assert (a.name, a.width, a.height) == ("maze-e1", size, size)
    outer = segments(rect_walls(0, 0, size, size))
    assert outer <= segments(a.walls)
    inner = [w for w in a.walls if frozenset(map(tuple, w)) not in outer]
    for (x0, y0), (x1, y1) in inner:
        assert x0 == x1 or y0 == y1
        assert all(v / cell == round(v / cell) for v in (x0, y0, x1, y1))  # on the grid
    covered = _covered(inner, cell, n)
    passages = _perfect_maze(n, seed)
    edges = {((i, j), (i + 1, j)) for i in range(n - 1) for j in range(n)}
    edges |= {((i, j), (i, j + 1)) for i in range(n) for j in range(n - 1)}
    assert len(covered) == len(set(covered))                # no edge walled twice
    assert set(covered) == edges - passages
    # maximal runs: no two walls on one grid line meet end to end
    ends = [(w[0], w[1]) for w in inner]
    for k, (p, q) in enumerate(ends):
        for p2, q2 in ends[k + 1:]:
            same_line = (p[0] == q[0] == p2[0] == q2[0]) or (p[1] == q[1] == p2[1] == q2[1])
            assert not (same_line and {p, q} & {p2, q2})


def test_the_maze_default_has_64_cell_centres_row_by_row_and_a_region_per_row():
    a = arenas.maze_e1()
    assert a.width == 320.0                                   # 8 cells of 40 cm
    want = [(40 * (k % 8) + 20.0, 40 * (k // 8) + 20.0) for k in range(64)]
    assert points(a) == want
    assert a.region_names == [f"row{j}" for j in range(8)]
    assert [r.rects for r in a.regions] == [((0.0, 40.0 * j, 320.0, 40.0 * (j + 1)),)
                                            for j in range(8)]
    assert a.start_pose == (20.0, 20.0, 0.0)
    assert segments(a.walls) == segments(arenas.maze_e1(40.0, 8, 1).walls)
    assert segments(a.walls) != segments(arenas.maze_e1(seed=2).walls)


@pytest.mark.parametrize("kw, message", [
    (dict(cell=0.0), "cell must be finite and > 0, got 0.0"),
    (dict(cell=-1.0), "cell must be finite and > 0, got -1.0"),
    (dict(cell=math.inf), "cell must be finite and > 0, got inf"),
    (dict(n=0), "n must be an integer >= 1, got 0"),
    (dict(n=1.5), "n must be an integer, got 1.5 (float)"),
    (dict(n=True), "n must be an integer, got True (a bool)"),
    (dict(seed=-1), "seed must be an integer in [0, 9223372036854775807], got -1"),
    (dict(seed=1.5), "seed must be an integer, got 1.5 (float)"),
])
def test_the_maze_refuses_bad_sizes_and_seeds_by_name(kw, message):
    # before: "arena size must be positive and finite, got -8.0 x -8.0" for a cell of -1, a
    # TypeError from range() for n = 1.5, numpy's "expected non-negative integer" for seed -1
    with refused(message):
        arenas.maze_e1(**kw)


def test_the_least_maze_is_one_cell_and_an_integer_cell_size_is_taken():
    a = arenas.maze_e1(cell=10.0, n=1, seed=0)
    assert segments(a.walls) == segments(rect_walls(0, 0, 10, 10))
    assert points(a) == [(5.0, 5.0)] and a.start_pose == (5.0, 5.0, 0.0)
    b = arenas.maze_e1(cell=40, n=np.int64(8), seed=np.int64(1))
    assert segments(b.walls) == segments(arenas.maze_e1().walls) and b.width == 320.0


def test_a_small_maze_scales_its_locations_regions_and_start():
    a = arenas.maze_e1(cell=10.0, n=3, seed=5)
    assert points(a) == [(10 * i + 5.0, 10 * j + 5.0) for j in range(3) for i in range(3)]
    assert [r.rects for r in a.regions] == [((0.0, 0.0, 30.0, 10.0),),
                                            ((0.0, 10.0, 30.0, 20.0),),
                                            ((0.0, 20.0, 30.0, 30.0),)]
    assert a.start_pose == (5.0, 5.0, 0.0)


# ---------------------------------------------------------------------------- goal arena
# the central block from the four documented corridor widths: west 24, south 30, east 36,
# north 28 cm in a 150 x 150 cm arena
BLOCK = (24.0, 30.0, 150.0 - 36, 150.0 - 28)


def test_goal_arena_walls_ring_block_notches_and_fin():
    a = arenas.goal_arena()
    assert (a.name, a.width, a.height) == ("goal-arena", 150.0, 150.0)
    c = 20  # the chamfered south-west and north-east corners
    outer = chain((c, 0), (150, 0), (150, 150 - c), (150 - c, 150), (0, 150), (0, c),
                  closed=True)
    x0, y0, x1, y1 = BLOCK
    # 6 cm deep notches in the south face (x 60-76) and in the east face (y 70-82; the
    # docstring called this one a bump, but the face steps into the block)
    block = chain((x0, y0), (60, y0), (60, y0 + 6), (76, y0 + 6), (76, y0), (x1, y0),
                  (x1, 70), (x1 - 6, 70), (x1 - 6, 82), (x1, 82), (x1, y1), (x0, y1),
                  closed=True)
    fin = chain((95, 0), (95, 10), (103, 10), (103, 0))  # 8 cm wide, 10 cm into the south
    assert segments(a.walls) == segments(outer + block + fin)


def test_goal_arena_corridor_widths_measured_on_centre_lines():
    a = arenas.goal_arena()
    assert a.distance_to_walls(12, 100) == 12.0    # west 24
    assert a.distance_to_walls(45, 15) == 15.0     # south 30
    assert a.distance_to_walls(132, 100) == 18.0   # east 36
    assert a.distance_to_walls(60, 136) == 14.0    # north 28


def test_goal_arena_zone_spans_the_west_corridor_12_cm_long_and_its_landmark_is_its_centre():
    a = arenas.goal_arena()
    ((zone),) = a.zones
    assert (zone.name, zone.colour) == ("goal", 1)
    x0, y0, x1, y1 = zone.rect
    assert (x0, x1) == (0.0, BLOCK[0])             # wall to block: the whole corridor
    assert y1 - y0 == 12.0
    assert a.landmarks["goal"] == ((x0 + x1) / 2, (y0 + y1) / 2) == (12.0, 76.0)
    assert a.zone_names == ["floor", "goal"]
    # crossed at 5 cm/s in 12 / 5 = 2.4 s
    assert (y1 - y0) / 5.0 == pytest.approx(2.4)


def test_goal_arena_regions_are_the_four_corridors_of_the_block():
    a = arenas.goal_arena()
    x0, y0, x1, y1 = BLOCK
    assert a.region_names == ["west", "south", "east", "north"]
    assert [r.rects for r in a.regions] == [((0.0, y0, x0, y1),), ((0.0, 0.0, 150.0, y0),),
                                            ((x1, y0, 150.0, y1),), ((0.0, y1, 150.0, 150.0),)]


def test_goal_arena_landmarks_and_start_lie_on_the_corridor_centre_lines():
    a = arenas.goal_arena()
    west, south, east, north = 12.0, 15.0, 132.0, 136.0   # half of each width off its wall
    assert a.landmarks["start-south"] == (85.0, south)
    assert a.landmarks["start-east"] == (east, 100.0)
    assert a.landmarks["start-north"] == (60.0, north)
    assert a.landmarks["start-west"] == (west, 105.0)
    assert list(a.landmarks) == ["goal", "start-south", "start-east", "start-north",
                                 "start-west"]
    assert a.start_pose == (120.0, south, 0.0)          # heading east along the south
    for name in ("start-south", "start-east", "start-north", "start-west"):
        assert a.region_of(*a.landmarks[name]) == name.split("-")[1]


def test_goal_arena_locations_every_15_cm_along_the_centre_lines():
    a = arenas.goal_arena()
    way = [(12, 100), (12, 76), (12, 45), (18, 18), (45, 15), (85, 15), (120, 15), (132, 40),
           (132, 76), (132, 110), (125, 136), (85, 136), (45, 136), (17, 134)]
    assert points(a) == _corridor_points(way)
    # by hand: 24 cm from (12, 100) to (12, 76) is round(1.6) = 2 steps of 12 cm
    assert points(a)[:3] == [(12.0, 100.0), (12.0, 88.0), (12.0, 76.0)]
    # the centre-line stretches: x = 12 in the west, y = 15 south, 132 east, 136 north
    assert (12.0, 60.5) in points(a) and (58.333333333333336, 15.0) in points(a)
    assert (132.0, 93.0) in points(a) and (98.33333333333333, 136.0) in points(a)
    assert len(a.locations) == 29


# ---------------------------------------------------------------------------- patrol course
# the block from the documented widths: south 22, east 40, north 30, west 28 in 160 x 120
PBOX = (28.0, 22.0, 160.0 - 40, 120.0 - 30)


def test_patrol_course_walls_loop_block_and_notch():
    a = arenas.patrol_course()
    assert (a.name, a.width, a.height) == ("patrol-course", 160.0, 120.0)
    c = 20  # the chamfered south-east and north-west corners
    outer = chain((0, 0), (160 - c, 0), (160, c), (160, 120), (c, 120), (0, 120 - c),
                  closed=True)
    # the notch: 20 cm wide, 8 cm into the north corridor (30 - 8 = 22 cm left at it)
    notch = chain((70, PBOX[3]), (70, PBOX[3] + 8), (90, PBOX[3] + 8), (90, PBOX[3]))
    assert segments(a.walls) == segments(outer + rect_walls(*PBOX) + notch)


def test_patrol_course_corridor_widths_measured_on_centre_lines():
    a = arenas.patrol_course()
    assert a.distance_to_walls(50, 11) == 11.0     # south 22
    assert a.distance_to_walls(140, 56) == 20.0    # east 40
    assert a.distance_to_walls(50, 105) == 15.0    # north 30
    assert a.distance_to_walls(80, 109) == 11.0    # north at the notch: 22
    assert a.distance_to_walls(14, 60) == 14.0     # west 28


def test_patrol_course_regions_checkpoints_and_start():
    a = arenas.patrol_course()
    x0, y0, x1, y1 = PBOX
    assert a.region_names == ["south", "east", "north", "west"]
    assert [r.rects for r in a.regions] == [((0.0, 0.0, 160.0, y0),), ((x1, y0, 160.0, y1),),
                                            ((0.0, y1, 160.0, 120.0),), ((0.0, y0, x0, y1),)]
    # checkpoints on the corridor centre lines: the south one under the notch's centre, the
    # east one at the block's mid-height
    assert a.landmarks == {"checkpoint-1": ((70 + 90) / 2, y0 / 2),
                           "checkpoint-2": ((x1 + 160) / 2, (y0 + y1) / 2),
                           "checkpoint-3": (50.0, (y1 + 120) / 2)}
    assert a.landmarks["checkpoint-1"] == (80.0, 11.0)
    regions = [a.region_of(*a.landmarks[f"checkpoint-{i}"]) for i in (1, 2, 3)]
    assert regions == ["south", "east", "north"]
    # in the west corridor's centre, heading south: counter-clockwise round the loop
    assert a.start_pose == (x0 / 2, 60.0, -math.pi / 2)
    assert points(a) == _corridor_points(arenas.loop_waypoints())
    assert len(a.locations) == 30


def test_the_loop_is_closed_counter_clockwise_and_10_cm_off_the_outer_wall():
    way = arenas.loop_waypoints()
    assert len(way) == 18 and way[0] == way[-1] == (10.0, 60.0)
    assert all(type(v) is float for p in way for v in p)
    # the shoelace area is positive: counter-clockwise
    area = sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in itertools.pairwise(way)) / 2
    assert area > 0
    a = arenas.patrol_course()
    x0, y0, x1, y1 = PBOX
    for x, y in way:
        assert not (x0 <= x <= x1 and y0 <= y <= y1)        # round the block
        assert 10.0 <= a.distance_to_walls(x, y) <= 14.0
    # the straight stretches run exactly 10 cm from the outer wall
    assert [p for p in way if p[0] == 10.0] == [(10.0, 60.0), (10.0, 30.0), (10.0, 80.0),
                                                (10.0, 60.0)]
    assert [p for p in way if p[1] == 10.0] == [(50.0, 10.0), (80.0, 10.0), (110.0, 10.0)]
    assert [p for p in way if p[0] == 150.0] == [(150.0, 56.0), (150.0, 80.0)]
    assert [p for p in way if p[1] == 110.0] == [(124.0, 110.0), (80.0, 110.0), (50.0, 110.0)]
    corners = [(14.0, 14.0), (136.0, 12.0), (148.0, 26.0), (148.0, 104.0), (26.0, 108.0),
               (12.0, 96.0)]
    assert [p for p in way if p[0] not in (10.0, 150.0) and p[1] not in (10.0, 110.0)] == \
        corners


# ---------------------------------------------------------------------------- corridor points
def test_corridor_points_every_15_cm_without_the_end():
    assert _corridor_points([(0, 0), (30, 0)]) == [(0.0, 0.0), (15.0, 0.0)]
    assert _corridor_points([(0, 0), (0, 45), (30, 45)]) == [
        (0.0, 0.0), (0.0, 15.0), (0.0, 30.0), (0.0, 45.0), (15.0, 45.0)]
    assert _corridor_points([(0, 0), (30, 40)]) == [  # 50 cm: round(3.33) = 3 steps
        (0.0, 0.0), (10.0, 40 / 3), (20.0, 80 / 3)]
    assert _corridor_points([(0, 0)]) == []


def test_corridor_points_round_half_to_even_and_at_least_one_step():
    # 22.5 cm is 1.5 spacings: round to 2; 37.5 cm is 2.5: round to 2
    assert _corridor_points([(0, 0), (22.5, 0)]) == [(0.0, 0.0), (11.25, 0.0)]
    assert _corridor_points([(0, 0), (37.5, 0)]) == [(0.0, 0.0), (18.75, 0.0)]
    # 7 cm rounds to 0 spacings: one step, the start alone; a repeated point too
    assert _corridor_points([(0, 0), (7, 0)]) == [(0.0, 0.0)]
    assert _corridor_points([(5, 5), (5, 5)]) == [(5.0, 5.0)]
    # another spacing
    assert _corridor_points([(0, 0), (30, 0)], spacing=10.0) == [(0.0, 0.0), (10.0, 0.0),
                                                                 (20.0, 0.0)]


def test_with_locations_replaces_only_the_locations():
    a = arenas.two_rooms()
    b = arenas._with_locations(a, [[1, 2], [3, 4]])
    assert b.locations.dtype == float and b.locations.tolist() == [[1.0, 2.0], [3.0, 4.0]]
    assert (b.walls, b.regions, b.start_pose, b.name) == (a.walls, a.regions, a.start_pose,
                                                          a.name)


# ---------------------------------------------------------------------------- get
def test_the_registry_names_the_four_arenas_in_order():
    assert list(arenas.ARENAS) == ["two-rooms", "maze-e1", "goal-arena", "patrol-course"]
    for name, build in arenas.ARENAS.items():
        assert build().name == name


@pytest.mark.parametrize("name, want", [("two-rooms", "two-rooms"), ("two_rooms", "two-rooms"),
                                        ("maze", "maze-e1"), ("maze_e1", "maze-e1"),
                                        ("goal_arena", "goal-arena"),
                                        ("patrol_course", "patrol-course")])
def test_get_builds_by_name_with_underscores_and_the_maze_alias(name, want):
    assert arenas.get(name).name == want


@pytest.mark.parametrize("name", ["three-rooms", "Two-Rooms", "maze-e2", "", "maze "])
def test_get_refuses_an_unknown_name_as_given(name):
    with refused(f"unknown arena {name!r}; choose from {NAMES}"):
        arenas.get(name)


def test_get_refuses_a_non_string_showing_its_repr_up_to_60_characters():
    with refused(f"arena name must be a string ({NAMES}), got 5"):
        arenas.get(5)  # type: ignore[arg-type]
    with refused(f"arena name must be a string ({NAMES}), got None"):
        arenas.get(None)  # type: ignore[arg-type]
    sixty = [1] * 20                 # "[1, 1, ..., 1]": 2 + 20 + 19 * 2 = 60 characters
    assert len(repr(sixty)) == 60
    with refused(f"arena name must be a string ({NAMES}), got {sixty!r}"):
        arenas.get(sixty)  # type: ignore[arg-type]
    sixty_one = [1] * 19 + [10]      # one character more
    assert len(repr(sixty_one)) == 61
    with refused(f"arena name must be a string ({NAMES}), got a long list"):
        arenas.get(sixty_one)  # type: ignore[arg-type]
    with refused(f"arena name must be a string ({NAMES}), got a long bytes"):
        arenas.get(b"x" * 58)  # type: ignore[arg-type]
