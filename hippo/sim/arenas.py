"""The arenas of the papers, rebuilt for the e-puck, plus a name registry.

Design rule (from the project's feasibility study): places must differ *within sensor range*.
Rooms that map onto each other by a symmetry are identical to any sensor history, so every arena
here gives its rooms shapes the 30 cm infra-red rays can tell apart (a narrow room, chamfered
corners, pillars, alcoves).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from hippo.sim.arena import Arena, ArenaBuilder


def two_rooms() -> Arena:
    """SMC09 Fig. 3: 120 × 90 cm, two rooms joined by a corridor, 25 labelled locations.

    Room A (left, x < 30) is a narrow 30 × 90 cm room: from inside it the robot sees both long
    walls. Room B (right, x > 60) is 60 × 90 cm with 12 cm chamfers in its four corners and
    a pillar. The corridor (30 ≤ x ≤ 60) is 24 cm wide at mid-height; with SMC09's wall
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
    b.box((95, 40, 103, 48))  # a pillar off-centre in room B
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
    """Passages of a perfect maze on an n × n grid (randomised depth-first search)."""
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
    bottom-left cell.
    """
    passages = _perfect_maze(n, seed)
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
    """HIREL's place-preference arena scaled to the e-puck: 150 × 150 cm, goal zone 24 × 12 cm.

    HIREL used a 1 m × 0.5 m zone in a 5 m × 5 m room; here the zone keeps that proportion of a
    short side (24 × 12 cm), so the robot crosses it at its default speed (5 cm/s) in 2.4–4.8 s,
    well under the 7 s reward delay. Interior walls make four distinct quadrants around an open
    centre: a chamfered corner (south-west), a pillar (north-east), a buttress (south-east) and
    the goal along the west wall of the north-west quadrant (colour 1).
    """
    b = ArenaBuilder("goal-arena", 150, 150)
    # outer walls with a 25 cm chamfer in the south-west corner
    b.polyline([(25, 0), (150, 0), (150, 150), (0, 150), (0, 25)], closed=True)
    # interior walls: a cross with an open centre
    b.wall((75, 0), (75, 40)).wall((75, 110), (75, 150))
    b.wall((0, 75), (40, 75)).wall((110, 75), (150, 75))
    b.box((112, 112, 124, 124))  # pillar, north-east
    b.polyline([(150, 30), (135, 30), (135, 45), (150, 45)])  # a buttress, south-east
    b.zone("goal", (2, 100, 26, 112), colour=1)
    b.landmark("goal", 14, 106)
    b.region("south_west", (0, 0, 75, 75)).region("south_east", (75, 0, 150, 75))
    b.region("north_west", (0, 75, 75, 150)).region("north_east", (75, 75, 150, 150))
    b.grid_locations(6, 6)
    b.start(110, 20, np.pi)
    arena = b.build()
    free = [i for i, (x, y) in enumerate(arena.locations) if arena.is_free(x, y, 6.0)]
    return _with_locations(arena, arena.locations[free])


def patrol_course() -> Arena:
    """A 160 × 120 cm loop around a central block, 35 cm-wide corridors, three checkpoints.

    The corners differ (two chamfered, one square, one with a notch) so places along the loop
    are distinct within IR range. Landmarks ``checkpoint-1..3`` and ``loop`` waypoints (the
    centre line of the corridor, counter-clockwise) are provided for the teacher.
    """
    b = ArenaBuilder("patrol-course", 160, 120)
    b.polyline([(0, 0), (140, 0), (160, 20), (160, 120), (20, 120), (0, 100)], closed=True)
    b.box((35, 35, 125, 85))
    b.polyline([(70, 85), (70, 95), (90, 95), (90, 85)])   # a notch into the top corridor
    b.box((140, 55, 160, 62))                               # a fin on the right wall
    b.landmark("checkpoint-1", 80, 17).landmark("checkpoint-2", 142, 80)
    b.landmark("checkpoint-3", 40, 103)
    b.region("south", (0, 0, 160, 35)).region("east", (125, 35, 160, 85))
    b.region("north", (0, 85, 160, 120)).region("west", (0, 35, 35, 85))
    loop = loop_waypoints()
    for x, y in loop:
        b.location(x, y)
    b.start(20, 17, 0.0)
    return b.build()


def loop_waypoints() -> list[tuple[float, float]]:
    """Centre line of the patrol course's corridor, counter-clockwise from the south-west."""
    pts = [(20, 17), (50, 17), (80, 17), (110, 17), (137, 20), (142, 40), (146, 70), (142, 100),
           (110, 103), (80, 107), (50, 103), (20, 98), (17, 70), (17, 40)]
    return [(float(x), float(y)) for x, y in pts]


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
    key = name.replace("_", "-")
    if key == "maze":
        key = "maze-e1"
    if key not in ARENAS:
        raise ValueError(f"unknown arena {name!r}; choose from {', '.join(ARENAS)}")
    return ARENAS[key]()
