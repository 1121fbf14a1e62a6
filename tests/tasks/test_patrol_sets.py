"""A patrol's checkpoints, waits and route (:mod:`hippo.tasks.patrol_sets`) on known answers:
small arenas built by hand, where each rule's answer can be worked out."""

import re

import numpy as np
import pytest

from hippo.sim import ArenaBuilder, arenas
from hippo.tasks.explore import arena_tour
from hippo.tasks.patrol_sets import (
    ARENA_CHECKPOINTS,
    MAX_WAIT_S,
    MIN_WAIT_S,
    _arena,
    check_patrol,
    checked_route,
    choose_route,
    random_patrol,
)

SIDE = 150.0
#: a closed square room's walls, each as (a, b); ``walled(gap=side)`` leaves a 30-cm gap in one
WALLS = {"south": ((0, 0), (SIDE, 0)), "east": ((SIDE, 0), (SIDE, SIDE)),
         "north": ((SIDE, SIDE), (0, SIDE)), "west": ((0, SIDE), (0, 0))}


def walled(gap: str | None = None):
    """A 150 x 150 room (start in its middle), closed, or with a gap from 60 to 90 cm along
    the wall ``gap``."""
    b = ArenaBuilder(f"room-{gap or 'closed'}", SIDE, SIDE)
    for side, (a, c) in WALLS.items():
        if side != gap:
            b.wall(a, c)
            continue
        (x0, y0), (x1, y1) = a, c
        p, q = ((x0 + (x1 - x0) * f, y0 + (y1 - y0) * f) for f in (0.4, 0.6))
        b.wall(a, p).wall(q, c)
    return b.start(75, 75).build()


CPS = [(30.0, 30.0), (120.0, 30.0), (120.0, 120.0)]


@pytest.mark.parametrize("gap", ["south", "east", "north", "west"])
def test_an_arena_whose_edge_the_robot_can_reach_is_open_and_says_where(gap):
    with pytest.raises(ValueError, match=rf"^arena 'room-{gap}' is open: the robot can reach its "
                       r"edge near \(\d+, \d+\) where no wall stands \(close it, e.g. with "
                       r"ArenaBuilder.outer_walls\(\)\)$") as err:
        check_patrol(walled(gap), CPS, [10.0, 10.0, 10.0])
    x, y = map(int, re.search(r"near \((\d+), (\d+)\)", str(err.value)).groups())
    # a cell by the gap (60-90 cm along that wall), within the rim band (3.7 + 2 x 2 cm)
    along, off = {"south": (x, y), "north": (x, SIDE - y), "west": (y, x),
                  "east": (y, SIDE - x)}[gap]
    assert 60 <= along <= 90 and 0 <= off < 8
    with pytest.raises(ValueError, match="is open"):
        random_patrol(walled(gap), 2, 0)


def test_a_closed_arena_is_not_open():
    assert check_patrol(walled(), CPS, [10.0, 10.0, 10.0]).length > 0


def test_a_gap_just_wider_than_the_robot_leads_on_and_one_narrower_does_not():
    # a wall across the room at x = 75 with a gap: the checkpoint east of it is reachable
    # through a gap of 10 cm (on the 2-cm floor grid, cells 4 cm from either end; the robot
    # needs 3.7 cm a side), not through 6 cm
    def split(gap: float):
        return (ArenaBuilder(f"split-{gap:g}", SIDE, SIDE).outer_walls()
                .wall((75, 0), (75, 70)).wall((75, 70 + gap), (75, SIDE)).start(30, 75).build())

    east = [(30.0, 30.0), (120.0, 120.0)]
    with pytest.raises(ValueError, match=r"^checkpoint \(120, 120\) cannot be reached from the "
                       r"start of arena 'split-6' \(it lies inside walls, or behind a gap "
                       r"narrower than the robot\)$"):
        checked_route(split(6.0), east, [10.0, 10.0], "shortest")
    kind, route = checked_route(split(10.0), east, [10.0, 10.0], "shortest")
    assert kind == "shortest" and route.length > 0


def test_a_checkpoint_needs_6_cm_clear_of_every_wall():
    arena = walled()
    check_patrol(arena, [(6.5, 75.0), (120.0, 30.0)], [10.0, 10.0], "shortest")
    with pytest.raises(ValueError, match=r"^checkpoint \(5.5, 75\) is not free floor of arena "
                       r"'room-closed' \(150 x 150 cm; a checkpoint needs 6 cm clear of every "
                       r"wall\)$"):
        check_patrol(arena, [(5.5, 75.0), (120.0, 30.0)], [10.0, 10.0], "shortest")


def test_the_waits_bounds_are_inclusive_and_every_wait_out_of_them_is_named():
    arena, cps = walled(), CPS
    check_patrol(arena, cps, [MIN_WAIT_S, MAX_WAIT_S, 10.0])
    with pytest.raises(ValueError, match=r"^wait\(s\) 1, 0.5 s: a checkpoint's wait must be at "
                       r"least 2 s \(a shorter stop is not reproduced\)$"):
        check_patrol(arena, cps, [1.0, 0.5, 10.0])
    with pytest.raises(ValueError, match=r"^wait\(s\) 121, 130 s: a checkpoint's wait must be "
                       r"at most 120 s \(the timing battery's longest delay\)$"):
        check_patrol(arena, cps, [121.0, 10.0, 130.0])


@pytest.mark.parametrize(("cps", "waits", "pattern"), [
    ([*CPS, (30.0, 120.0), (75.0, 120.0)], [10.0] * 5,
     r"^a patrol has 2 to 4 checkpoints, got 5$"),
    (CPS, [10.0, 10.0], r"^got 2 waits for 3 checkpoints; give one wait per checkpoint$"),
    ([(30.0, 30.0), (120.0, 40.0), (30.0, 30.0)], [10.0] * 3,
     r"^checkpoints 1 and 3 are the same point \(30, 30\); each checkpoint must have a spot "
     r"of its own$"),
    ([(30.0, 40.0), (120.0, 40.0), (30.0, 40.0)], [10.0] * 3, r"same point \(30, 40\)"),
    (CPS, [[10.0, 10.0, 10.0]], r"^waits must be a list of waits in s"),
    (CPS, "10,10,10", r"^waits must be a list of waits in s"),
    (CPS, 10.0, r"^waits must be a list of waits in s"),
    (CPS, np.array([[10.0, 10.0, 10.0]]), r"^waits must be a list of waits in s"),
])
def test_a_course_that_is_no_course_is_refused_by_name(cps, waits, pattern):
    with pytest.raises(ValueError, match=pattern):
        check_patrol(walled(), cps, waits)


def test_the_arena_is_a_name_or_an_arena():
    assert _arena("goal-arena").name == "goal-arena"
    with pytest.raises(TypeError, match=r"^arena must be an arena's name or an Arena, got int$"):
        _arena(12)


def test_two_checkpoints_too_close_across_the_routes_start_are_refused():
    # the shortest route starts at the first checkpoint: a third 25 cm before it (on the way
    # back) is 25 cm from it along the route, across the loop's start
    arena = walled()
    cps = [(30.0, 30.0), (120.0, 30.0), (120.0, 120.0)]
    route = choose_route(arena, cps, "shortest")[1]
    x, y, _ = route.at(route.length - 25.0)
    with pytest.raises(ValueError, match=r"^two checkpoints are 2[45] cm apart along the route; "
                       r"they need 40 cm \(a pass is 30 cm either side\)$"):
        check_patrol(arena, [*cps, (round(x, 3), round(y, 3))], [10.0] * 4, "shortest")


def test_checked_route_chooses_as_check_patrol_and_choose_route_with_the_kind_given():
    cps, waits = random_patrol("goal-arena", 3, 5)
    for kind in ("auto", "shortest", "tour"):
        try:
            want = choose_route("goal-arena", cps, kind)
        except ValueError:
            continue
        got = checked_route("goal-arena", cps, waits, kind)
        assert got[0] == want[0] and got[1].waypoints == want[1].waypoints
        assert check_patrol("goal-arena", cps, waits, kind).waypoints == want[1].waypoints
    assert checked_route("goal-arena", cps, waits)[0] == choose_route("goal-arena", cps)[0]
    assert choose_route("goal-arena", cps, "shortest")[0] == "shortest"
    assert choose_route(walled(), CPS)[0] == "shortest"   # no tour goes round anything


def test_the_course_of_patrol_course_is_its_own_loop_by_name_or_as_an_arena():
    own = ARENA_CHECKPOINTS["patrol-course"]
    assert choose_route("patrol-course", own)[0] == "course"
    assert choose_route(arenas.get("patrol-course"), own)[0] == "course"
    assert choose_route("patrol-course", own, "shortest")[0] == "shortest"


def test_a_tour_asked_for_is_taken_even_where_it_runs_out_and_back():
    # goal-arena's right wall tour turns back at the south nook (winding 0): asked for, it is
    # the route when it passes every checkpoint (the left one, round the block, is not it)
    right = arena_tour("goal-arena", -1)
    assert right.winding == 0
    cps = [tuple(round(v, 3) for v in right.at(s)[:2]) for s in (100.0, 300.0, 500.0)]
    kind, route = choose_route("goal-arena", cps, "tour")
    assert kind == "tour" and route.waypoints == right.waypoints


def test_no_tour_near_every_checkpoint_names_the_ones_left_out():
    # started in the middle of a closed square, the right wall follower circles the start (a
    # loop of ~1 m) and the left one makes no tour: the checkpoints by the corners are the
    # ones no tour passes
    with pytest.raises(ValueError, match=r"^no wall tour of arena 'room-closed' passes within "
                       r"20 cm of checkpoint\(s\) \(10, 10\), \(140, 10\)$"):
        choose_route(walled(), [(10.0, 10.0), (75.0, 75.0), (140.0, 10.0)], "tour")


@pytest.mark.parametrize(("kw", "pattern"), [
    ({"n": 5}, r"^n must be 2 to 4 checkpoints, got 5$"),
    ({"n": True}, r"^n must be 2 to 4 checkpoints, got True$"),
    ({"n": 2.0}, r"^n must be 2 to 4 checkpoints, got 2.0$"),
    ({"waits": (1.9, 30.0)}, r"^waits must be \(low, high\) with 2 <= low <= high <= 120 s, "
                             r"got \(1.9, 30.0\)$"),
    ({"waits": (30.0, 20.0)}, r"got \(30.0, 20.0\)$"),
    ({"waits": (8.0, 120.5)}, r"got \(8.0, 120.5\)$"),
    ({"clearance": -0.5}, r"^clearance must be a finite number of cm >= 0, got -0.5$"),
    ({"clearance": 1e6}, r"^clearance must be a finite number of cm >= 0, got 1000000.0$"),
    ({"clearance": 80.0}, r"^arena 'room-closed' has \d+ points of floor 80 cm clear of every "
                          r"wall; 2 checkpoints need more \(a smaller clearance\)$"),
])
def test_random_patrol_refuses_what_cannot_be_drawn_by_name(kw, pattern):
    args = {"n": 2, **kw}
    with pytest.raises(ValueError, match=pattern):
        random_patrol(walled(), args.pop("n"), 0, **args)


def test_random_patrol_draws_distinct_checkpoints_on_roomy_reachable_floor():
    arena = walled()
    for seed in range(6):
        cps, waits = random_patrol(arena, 4, seed, waits=(MIN_WAIT_S, MAX_WAIT_S),
                                   clearance=0.0)
        assert len(set(cps)) == 4 and len(waits) == 4
        assert all(MIN_WAIT_S <= w <= MAX_WAIT_S and w == round(w, 1) for w in waits)
        gaps = [np.hypot(a[0] - b[0], a[1] - b[1]) for i, a in enumerate(cps) for b in cps[i + 1:]]
        assert min(gaps) >= 40.0
        check_patrol(arena, cps, waits)            # what it returns passes the checks
    # the waits to a tenth of a second, in the range given; equal bounds give that wait
    cps, waits = random_patrol(arena, 3, 1, waits=(12.34, 12.34))
    assert waits == [12.3, 12.3, 12.3]
    # clearance: every checkpoint that far from the walls (the room's walls are its sides)
    for seed in range(6):
        cps, _ = random_patrol(arena, 3, seed, clearance=30.0)
        assert all(30.0 <= min(x, y, SIDE - x, SIDE - y) for x, y in cps)
    # 62 cm from every wall the floor is a 26-cm square: 2 points 40 cm apart never fit
    with pytest.raises(ValueError, match=r"^no 2 checkpoints 40 cm apart along a route found "
                       r"in arena 'room-closed' after 2000 tries$"):
        random_patrol(arena, 2, 0, clearance=62.0)
    with pytest.raises(ValueError, match=r"after 3 tries$"):
        random_patrol(arena, 2, 0, clearance=62.0, tries=3)


def test_an_unknown_route_kind_is_refused_with_the_kinds_named():
    with pytest.raises(ValueError, match=r"^route kind must be one of auto, shortest, tour, "
                       r"got 'loop'$"):
        choose_route(walled(), CPS, "loop")
