"""The arenas of the papers, rebuilt for the e-puck, plus a name registry.

Design rule (from the project's feasibility study): places must differ *within sensor range*.
Rooms that map onto each other by a symmetry are identical to any sensor history, so every arena
here gives its rooms shapes the 30 cm infra-red rays can tell apart (a narrow room, chamfered
corners, pillars, alcoves).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable

import numpy as np

from hippo._checks import check_int, check_positive, check_seed
from hippo.sim.arena import Arena
from hippo.sim.builder import ArenaBuilder


def two_rooms() -> Arena:
    """SMC09 Fig. 3: 120 × 90 cm, two rooms joined by a corridor, 25 labelled locations.

    Room A (left, x < 30) is a narrow 30 × 90 cm room: from inside it the robot sees both long
    walls. Room B (right, x > 60) is 60 × 90 cm with 12 cm chamfers in its four corners and a
    buttress on its east wall (a free-standing pillar would leave a narrow gap that looks like
    room A: with one, the room cell fell from 0.95 to 0.85 balanced accuracy). The corridor
    (30 ≤ x ≤ 60) is 24 cm wide at mid-height; with SMC09's wall
    follower (ρ = 0.008) the robot changes room about 40 times in 18,120 ticks.
    """
    b = ArenaBuilder("two-rooms", 120, 90)
    # room A: left, top, bottom outer walls; its right wall has the corridor opening
    b.polyline([(30, 33), (30, 0), (0, 0), (0, 90), (30, 90), (30, 57)])
    # corridor
    b.wall((30, 33), (60, 33)).wall((30, 57), (60, 57))
    # room B with chamfered corners
    b.polyline([(60, 57), (60, 78), (72, 90), (108, 90), (120, 78), (120, 12), (108, 0),
                (72, 0), (60, 12), (60, 33)])
    b.polyline([(120, 40), (112, 40), (112, 48), (120, 48)])  # an alcove-like buttress
    b.region("room_a", (0, 0, 30, 90)).region("corridor", (30, 37, 60, 53))
    b.region("room_b", (60, 0, 120, 90))
    for y in (9, 27, 45, 63, 81):
        for x in (9, 21):
            b.location(x, y)
    b.location(38, 45).location(52, 45)
    for y in (12, 33, 57, 78):
        for x in (72, 90, 110):
            b.location(x, y)
    b.location(84, 45)
    b.start(15, 20, np.pi / 2)
    return b.build()


def _perfect_maze(n: int, seed: int) -> set[tuple[tuple[int, int], tuple[int, int]]]:
    """Passages of a perfect maze on an n × n grid (randomised depth-first search from cell
    (0, 0): the unvisited neighbours of the cell on top of the stack, in the order +x, -x, +y,
    -y, one drawn with ``integers(k)`` from ``default_rng(seed)``)."""
    rng = np.random.default_rng(seed)
    seen = {(0, 0)}
    stack = [(0, 0)]
    passages = set()
    while stack:
        c = stack[-1]
        nbrs = [(c[0] + dx, c[1] + dy) for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1))]
        nbrs = [q for q in nbrs if 0 <= q[0] < n and 0 <= q[1] < n and q not in seen]
        if not nbrs:
            stack.pop()
            continue
        q = nbrs[int(rng.integers(len(nbrs)))]
        passages.add((min(c, q), max(c, q)))
        seen.add(q)
        stack.append(q)
    return passages


def maze_e1(cell: float = 40.0, n: int = 8, seed: int = 1) -> Arena:
    """A big maze in the spirit of ICANN09's E1: an n × n perfect maze, 64 labelled locations.

    Corridors are ``cell`` = 40 cm wide, comparable to the 17-ray robot's 50 cm range, so the
    robot sees the walls of the corridor it is in and not much further. Being a perfect maze
    (a tree), following one wall visits every cell. Locations are numbered row by row from the
    bottom-left cell. ``cell`` > 0 cm, ``n`` >= 1 and ``seed`` (the maze's) are checked.
    """
    cell = check_positive("cell", cell)
    n = check_int("n", n, lo=1)
    passages = _perfect_maze(n, check_seed("seed", seed))
    size = n * cell
    b = ArenaBuilder("maze-e1", size, size).outer_walls()
    # vertical walls between (i, j) and (i+1, j); merge runs along each grid line
    for i in range(1, n):
        run = None
        for j in range(n + 1):
            wall = j < n and ((i - 1, j), (i, j)) not in passages
            if wall and run is None:
                run = j
            elif not wall and run is not None:
                b.wall((i * cell, run * cell), (i * cell, j * cell))
                run = None
    for j in range(1, n):
        run = None
        for i in range(n + 1):
            wall = i < n and ((i, j - 1), (i, j)) not in passages
            if wall and run is None:
                run = i
            elif not wall and run is not None:
                b.wall((run * cell, j * cell), (i * cell, j * cell))
                run = None
    b.grid_locations(n, n)
    for j in range(n):
        b.region(f"row{j}", (0, j * cell, size, (j + 1) * cell))
    b.start(cell / 2, cell / 2, 0.0)
    return b.build()


def goal_arena() -> Arena:
    """HIREL's place-preference arena scaled to the e-puck: 150 × 150 cm around a central block.

    HIREL used an open 5 m × 5 m room with a 1 m × 0.5 m goal zone. The e-puck's 30 cm infra-red
    rays see nothing in an open room, so a central block turns the arena into four corridors of
    different widths (west 24 cm, south 30 cm, east 36 cm, north 28 cm), narrow enough for the
    rays to reach both walls, with chamfered south-west and north-east corners, a fin in the
    south corridor and a notch (6 cm deep) in each of the block's south and east faces: every
    stretch looks different within sensor range. The goal zone (colour 1) spans the west
    corridor and is 12 cm long, so the robot crosses it at its default speed (5 cm/s) in about
    2.4 s, well under the 7 s reward delay.
    """
    b = ArenaBuilder("goal-arena", 150, 150)
    b.polyline([(20, 0), (150, 0), (150, 130), (130, 150), (0, 150), (0, 20)], closed=True)
    b.polyline([(24, 30), (60, 30), (60, 36), (76, 36), (76, 30), (114, 30), (114, 70),
                (108, 70), (108, 82), (114, 82), (114, 122), (24, 122)], closed=True)
    b.polyline([(95, 0), (95, 10), (103, 10), (103, 0)])        # fin, south corridor
    b.zone("goal", (0, 70, 24, 82), colour=1)
    b.landmark("goal", 12, 76)
    b.region("west", (0, 30, 24, 122)).region("south", (0, 0, 150, 30))
    b.region("east", (114, 30, 150, 122)).region("north", (0, 122, 150, 150))
    for x, y in _corridor_points([(12, 100), (12, 76), (12, 45), (18, 18), (45, 15), (85, 15),
                                  (120, 15), (132, 40), (132, 76), (132, 110), (125, 136),
                                  (85, 136), (45, 136), (17, 134)]):
        b.location(x, y)
    b.landmark("start-south", 85, 15).landmark("start-east", 132, 100)
    b.landmark("start-north", 60, 136).landmark("start-west", 12, 105)
    b.start(120, 15, 0.0)
    return b.build()


def patrol_course() -> Arena:
    """A 160 × 120 cm loop around a central block with corridors of different widths.

    South 22 cm, east 40 cm, north 30 cm (22 cm at a notch), west 28 cm; two chamfered corners:
    places along the loop are distinct within IR range. Landmarks ``checkpoint-1..3`` lie in the
    south, east and north corridors; :func:`loop_waypoints` is the corridor centre line,
    counter-clockwise, for the teacher's leash.
    """
    b = ArenaBuilder("patrol-course", 160, 120)
    b.polyline([(0, 0), (140, 0), (160, 20), (160, 120), (20, 120), (0, 100)], closed=True)
    b.box((28, 22, 120, 90))
    b.polyline([(70, 90), (70, 98), (90, 98), (90, 90)])   # a notch into the north corridor
    b.landmark("checkpoint-1", 80, 11).landmark("checkpoint-2", 140, 56)
    b.landmark("checkpoint-3", 50, 105)
    b.region("south", (0, 0, 160, 22)).region("east", (120, 22, 160, 90))
    b.region("north", (0, 90, 160, 120)).region("west", (0, 22, 28, 90))
    for x, y in _corridor_points(loop_waypoints()):
        b.location(x, y)
    b.start(14, 60, -np.pi / 2)
    return b.build()


def loop_waypoints() -> list[tuple[float, float]]:
    """The patrol route for the teacher's leash: counter-clockwise, about 10 cm from the outer
    wall (where the wall-following robot runs), from the west corridor."""
    pts = [(10, 60), (10, 30), (14, 14), (50, 10), (80, 10), (110, 10), (136, 12), (148, 26),
           (150, 56), (150, 80), (148, 104), (124, 110), (80, 110), (50, 110), (26, 108),
           (12, 96), (10, 80), (10, 60)]
    return [(float(x), float(y)) for x, y in pts]


def _corridor_points(pts: list[tuple[float, float]], spacing: float = 15.0
                     ) -> list[tuple[float, float]]:
    """Points every ``spacing`` cm along a polyline (labelled locations along corridors)."""
    out: list[tuple[float, float]] = []
    for (x0, y0), (x1, y1) in itertools.pairwise(pts):
        n = max(1, round(np.hypot(x1 - x0, y1 - y0) / spacing))
        out.extend((x0 + (x1 - x0) * k / n, y0 + (y1 - y0) * k / n) for k in range(n))
    return out


def _with_locations(arena: Arena, locations: np.ndarray) -> Arena:
    from dataclasses import replace

    return replace(arena, locations=np.asarray(locations, float))


ARENAS: dict[str, Callable[[], Arena]] = {
    "two-rooms": two_rooms,
    "maze-e1": maze_e1,
    "goal-arena": goal_arena,
    "patrol-course": patrol_course,
}


def get(name: str) -> Arena:
    """Build an arena by name (``two-rooms``, ``maze-e1``, ``goal-arena``, ``patrol-course``)."""
    if not isinstance(name, str):
        shown = repr(name) if len(repr(name)) <= 60 else f"a long {type(name).__name__}"
        raise ValueError(f"arena name must be a string ({', '.join(ARENAS)}), got {shown}")
    key = name.replace("_", "-")
    if key == "maze":
        key = "maze-e1"
    if key not in ARENAS:
        raise ValueError(f"unknown arena {name!r}; choose from {', '.join(ARENAS)}")
    return ARENAS[key]()
