"""Routes and checkpoints: progress along a route, laps, passes and stops."""

import math
from itertools import pairwise

import numpy as np
import pytest

from hippo.sim import arenas
from hippo.tasks import (
    AngleLaps,
    LapCounter,
    Route,
    lead_from,
    passes,
    progress_along,
    route_passes,
    stops,
)
from hippo.types import Mode

SQUARE = [(0, 0), (100, 0), (100, 100), (0, 100)]


def test_progress_is_the_distance_along_the_route_of_the_nearest_point():
    r = Route(SQUARE)
    assert r.length == pytest.approx(400.0)
    assert r.progress(0, 0) == pytest.approx(0.0)
    assert r.progress(50, -7) == pytest.approx(50.0)       # off the route: projected
    assert r.progress(104, 30) == pytest.approx(130.0)
    assert r.progress(-3, 40) == pytest.approx(360.0)      # closing leg (0,100) -> (0,0)
    # an open route has no closing leg
    assert Route(SQUARE, closed=False).length == pytest.approx(300.0)
    # a closing point equal to the first is implied, not a zero-length leg
    assert Route([*SQUARE, (0, 0)]).waypoints == Route(SQUARE).waypoints


def test_sample_walks_the_route_at_a_spacing():
    r = Route(SQUARE)
    pts = r.sample(25.0)
    assert len(pts) == 16 and pts[0] == (0.0, 0.0) and pts[5] == (100.0, 25.0)
    assert [r.progress(*p) for p in pts] == pytest.approx([25.0 * k for k in range(16)])
    with pytest.raises(ValueError, match="spacing"):
        r.sample(0.0)


def test_bad_routes_are_refused():
    with pytest.raises(ValueError, match="waypoints"):
        Route([(0, 0)])
    with pytest.raises(ValueError, match="non-finite"):
        Route([(0, 0), (math.nan, 1)])
    with pytest.raises(ValueError, match="closed"):
        LapCounter(Route(SQUARE, closed=False))


def _circle(turns: float, n: int = 400, r: float = 45.0) -> list[tuple[float, float]]:
    a = np.linspace(0, 2 * math.pi * turns, n)
    return [(50 + r * math.cos(x), 50 + r * math.sin(x)) for x in a]


def test_laps_by_route_progress_and_by_angle_agree_on_a_loop():
    # counter-clockwise around the square's centre: 1.5 laps along the route (whose order
    # (0,0) -> (100,0) -> (100,100) is counter-clockwise too)
    laps, angle = LapCounter(Route(SQUARE)), AngleLaps((50, 50))
    for x, y in _circle(1.5):
        a, b = laps.update(x, y), angle.update(x, y)
    assert a == pytest.approx(1.5, abs=0.02)
    assert b == pytest.approx(1.5, abs=1e-9)
    # going back the same way unwinds
    for x, y in reversed(_circle(1.5)):
        a = laps.update(x, y)
    assert a == pytest.approx(0.0, abs=0.02)


def test_leg_and_loop_follow_the_route_direction():
    r = Route(SQUARE)
    assert r.leg((1, 1), (0, 98)) == [(100.0, 0.0), (100.0, 100.0), (0.0, 100.0), (0.0, 98.0)]
    # facing away from the nearest waypoint: the loop starts at the next one
    assert r.loop_from((2, 0, 0.0))[0] == (100.0, 0.0)
    assert r.loop_from((2, 0, 0.0))[-1] == (100.0, 0.0)
    assert len(r.loop_from((2, 0, 0.0))) == 5
    assert r.loop_from((2, 0, math.pi))[0] == (0.0, 0.0)


def test_passes_by_a_checkpoint():
    """Each pass within 30 cm counts once; runs at most ``gap`` ticks apart join; a pass under
    way when the phase starts is not counted."""
    x = np.array([0, 0, 0, 50, 50, 0, 50, 0, 0, 50, 50, 50, 50, 50, 50, 0, 0, 50], float)
    phase = np.array([3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4])
    arrays = {"x": x, "y": np.zeros_like(x), "phase": phase}
    assert passes(arrays, (0.0, 0.0), phase=4, gap=1) == [(5, 9), (15, 17)]
    # a run that joins the pass under way at the phase start is skipped with it
    assert passes(arrays, (0.0, 0.0), phase=4, gap=2) == [(15, 17)]
    assert passes(arrays, (0.0, 0.0), phase=4, gap=0) == [(5, 6), (7, 9), (15, 17)]
    assert passes(arrays, (0.0, 0.0), phase=5) == []


def test_stops_count_chosen_waits_near_checkpoints():
    n = 40
    t = np.arange(n) * 0.2
    speed = np.full(n, 5.0)
    speed[5:15] = 0.0     # 2 s still at checkpoint 0, the agent waiting (mode WAIT)
    speed[20:30] = 0.0    # 2 s still at checkpoint 0, a stall (mode MOVE): not counted
    speed[33:36] = 0.0    # 0.6 s: too short
    mode = np.full(n, int(Mode.MOVE))
    mode[5:15] = int(Mode.WAIT)
    mode[33:36] = int(Mode.WAIT)
    arrays = {"t": t, "speed": speed, "mode": mode, "x": np.zeros(n), "y": np.zeros(n),
              "phase": np.full(n, 4), "trial": np.zeros(n, int),
              "wait_drive": np.where(mode == int(Mode.WAIT), 1, -1)}
    found = stops(arrays, [(0.0, 0.0), (100.0, 0.0)], threshold=0.1)
    assert [(s["i0"], s["checkpoint"], s["drive"]) for s in found] == [(5, 0, 1)]
    assert found[0]["duration"] == pytest.approx(2.0)
    # in the taught phase every stop near a checkpoint counts, at the trial's checkpoint
    taught = stops(arrays, [(0.0, 0.0), (100.0, 0.0)], threshold=0.1, taught_phase=4)
    assert [s["i0"] for s in taught] == [5, 20]


def _walk(route: Route, laps: float, step: float = 1.5, jitter: float = 2.0, seed: int = 0):
    """Positions of a robot walking ``laps`` laps along ``route`` at ``step`` cm per tick,
    up to ``jitter`` cm off the centre line."""
    rng = np.random.default_rng(seed)
    s = np.arange(0.0, laps * route.length, step)
    pts = np.array([route.at(v)[:2] for v in s]) + rng.uniform(-jitter, jitter, (len(s), 2))
    return s, pts


def test_a_route_through_two_rooms_runs_the_corridor_both_ways():
    arena = arenas.two_rooms()
    a, b = (15.0, 65.0), (100.0, 40.0)
    r = Route.through(arena, [a, b])
    # out through the corridor and back: about twice the shortest path, and it starts at a
    one_way, _ = arena.shortest_path(a, b)
    assert r.length == pytest.approx(2 * one_way, rel=0.1)
    assert r.at(0.0)[:2] == pytest.approx(a)
    assert r.progress(*b) == pytest.approx(r.length / 2, rel=0.1)
    # the corridor's middle is on the route twice, once each way, at progress s and L - s
    *_, h_out = r.at(r.progress_near(45.0, 45.0, r.length / 4, 40.0))
    s_back = r.progress_near(45.0, 45.0, 3 * r.length / 4, 40.0)
    assert s_back > r.length / 2 and math.cos(r.at(s_back)[2] - h_out) < -0.9
    # every waypoint is free floor for the robot
    assert all(arena.is_free(px, py, 3.7) for px, py in r.waypoints)
    with pytest.raises(ValueError, match="at least two"):
        Route.through(arena, [a])


def test_lap_counter_follows_a_route_that_runs_over_itself():
    r = Route.through(arenas.two_rooms(), [(15.0, 65.0), (100.0, 40.0)])
    s, pts = _walk(r, 2.5)
    tracked = progress_along(r, pts[:, 0], pts[:, 1])
    # tracked progress follows the walk across both corridor crossings: within the jitter
    # (2 cm) along the stretches, within 12 cm at the turn-around in room A, where the way in
    # and the way out meet
    err = np.abs(tracked - s)
    assert np.max(err) < 12.0 and np.median(err) < 2.0
    assert tracked[-1] / r.length == pytest.approx(2.5, abs=0.02)
    # the nearest point of the whole route alone jumps between the two corridor stretches
    glob = np.array([r.progress(px, py) for px, py in pts])
    wrapped = (glob - s + r.length / 2) % r.length - r.length / 2
    assert np.max(np.abs(wrapped)) > 20.0
    # carried elsewhere: the next update searches the whole route
    laps = LapCounter(r)
    laps.update(*pts[0])
    far = r.at(r.length / 2)
    laps.update(far[0], far[1])
    assert laps.progress == pytest.approx(r.length / 2, abs=3.0)


def test_route_passes_count_one_pass_per_lap_by_progress():
    r = Route(SQUARE)
    s, pts = _walk(r, 3.0, step=2.0, jitter=1.0)
    # a stop of 40 ticks at (100, 50) on the second lap, with wiggles around it
    k = int(np.searchsorted(s, 400.0 + 150.0))
    pts = np.vstack([pts[:k], np.repeat(pts[k:k + 1], 40, axis=0), pts[k:]])
    phase = np.ones(len(pts), int)
    phase[:5] = 0
    arrays = {"x": pts[:, 0], "y": pts[:, 1], "phase": phase}
    runs = route_passes(arrays, r, (100.0, 50.0), phase=1)
    assert len(runs) == 3  # laps 1, 2, 3: the stop is inside the second pass, not a new one
    assert runs[1][0] < k < k + 40 < runs[1][1]
    # a pass under way at the start of the phase does not count
    assert len(route_passes(arrays, r, (2.0, 0.0), phase=1)) == 2
    assert route_passes(arrays, r, (100.0, 50.0), phase=7) == []


def _straight_is_free(arena, a, b, radius=3.7):
    u = np.linspace(0.0, 1.0, int(np.hypot(b[0] - a[0], b[1] - a[1]) / 1.0) + 2)
    return all(arena.is_free(a[0] + (b[0] - a[0]) * k, a[1] + (b[1] - a[1]) * k, radius)
               for k in u)


def test_a_leash_to_a_waypoint_behind_a_wall_goes_round_it():
    # the maze's patrol route for tuning seed 0; the robot stands in the corridor x 120-160,
    # and the route's waypoint nearest it lies beyond the wall x = 160
    maze = arenas.get("maze")
    route = Route.through(maze, [(269.0, 89.0), (205.0, 307.0)])
    start = (129.5, 87.1)
    wp = route.loop_from((*start, -1.57))
    assert not _straight_is_free(maze, start, wp[0])
    led = lead_from(maze, start, wp)
    n = len(led) - len(wp)
    assert n > 5 and led[n:] == [tuple(map(float, p)) for p in wp]
    # the way there: every step of it clear of walls, from the robot to the route
    way = [start, *led[:n + 1]]
    assert all(_straight_is_free(maze, a, b) for a, b in pairwise(way))
    assert np.hypot(led[0][0] - start[0], led[0][1] - start[1]) < 5.0
    # in the open (the west room's floor, where the shortest path is the straight line), the
    # leash goes straight: the waypoints come back unchanged
    two = arenas.get("two-rooms")
    assert two.shortest_path((10.0, 20.0), (20.0, 30.0), 3.7)[0] == pytest.approx(200 ** 0.5)
    assert lead_from(two, (10.0, 20.0), [(20.0, 30.0), (20.0, 60.0)]) == [(20.0, 30.0),
                                                                          (20.0, 60.0)]
    assert lead_from(two, (20.0, 20.0), []) == []
    with pytest.raises(ValueError, match=r"waypoints must be an \(N, 2\) array"):
        lead_from(two, (20.0, 20.0), [(40.0, 30.0, 1.0)])


def test_a_lap_counter_says_the_robot_reached_a_point_only_at_or_past_it():
    r = Route([(0, 0), (100, 0), (100, 50), (0, 50)])
    laps = LapCounter(r)
    seen = [laps.reached(x, 2.0, (60.0, 0.0)) for x in (30.0, 45.0, 55.0, 59.0, 60.5, 64.0, 79.0)]
    assert seen == [False, False, False, False, True, True, True]   # 20-cm disc: 45 is in it
    assert not laps.reached(60.5, 25.0, (60.0, 0.0))   # past it along the route, but 25 cm off
    assert not laps.reached(85.0, 0.0, (60.0, 0.0), radius=20.0)   # past it and out of reach
    with pytest.raises(ValueError, match="radius"):
        laps.reached(60.0, 0.0, (60.0, 0.0), radius=0.0)


def test_from_behind_a_point_is_reached_only_by_a_robot_that_comes_up_to_it_the_routes_way():
    r = Route([(0, 0), (100, 0), (100, 50), (0, 50)])     # 300 cm, counter-clockwise
    laps = LapCounter(r)
    p = (60.0, 0.0)

    def drive(points, **kw):
        return [laps.reached(x, y, p, radius=20.0, **kw) for x, y in points]

    # from 30 backwards round the loop to 70, then on to 58: it comes to 60 from beyond
    back = [(x, 0.0) for x in range(28, -1, -4)] + [(0.0, y) for y in range(4, 51, 4)]
    back += [(x, 50.0) for x in range(4, 101, 4)] + [(100.0, y) for y in range(46, -1, -4)]
    laps.update(30.0, 0.0)
    assert not any(drive(back, from_behind=True))
    assert drive([(70.0, 0.0), (64.0, 0.0)], from_behind=True) == [False, False]
    assert laps.reached(64.0, 0.0, p, radius=20.0)          # without from_behind: "past" it
    # on backwards past it, then forward again: behind it now, reached at it
    assert drive([(59.0, 0.0), (56.0, 0.0), (58.0, 0.0), (60.0, 0.0), (63.0, 0.0)],
                 from_behind=True) == [False, False, False, True, True]
    # forget: from here (3 cm past it) it must come round again
    laps.forget(p)
    assert drive([(66.0, 0.0), (75.0, 0.0), (90.0, 0.0)], from_behind=True) == [False] * 3
    fwd = [(100.0, y) for y in range(4, 50, 4)] + [(x, 50.0) for x in range(96, -1, -4)]
    fwd += [(0.0, y) for y in range(46, -1, -4)] + [(x, 0.0) for x in range(4, 60, 4)]
    assert not any(drive(fwd, from_behind=True))             # up to 56, behind it
    assert drive([(61.0, 0.0)], from_behind=True) == [True]
    # more than a radius past it, then back to it: not from behind
    assert drive([(85.0, 0.0), (70.0, 0.0), (62.0, 0.0)], from_behind=True) == [False] * 3


def test_winding_tells_a_loop_round_from_a_shuttle():
    # the shoelace area of a 100 cm square is 10,000 cm^2, positive counter-clockwise
    ccw, cw = Route(SQUARE), Route(SQUARE[::-1])
    assert ccw.signed_area == pytest.approx(10_000.0)
    assert cw.signed_area == pytest.approx(-10_000.0)
    assert (ccw.winding, cw.winding) == (1, -1)
    # out along a corridor and back, a little off the line each way: it encloses ~2 %
    shuttle = Route([(0, 0), (100, 0), (200, 2), (100, 3), (0, 2)])
    assert abs(shuttle.signed_area) < 0.05 * (shuttle.length / 4) ** 2
    assert shuttle.winding == 0
    # the loop of patrol-course runs counter-clockwise round its inner block
    assert Route(arenas.loop_waypoints()).winding == 1


def test_doubled_length_is_the_stretch_a_loop_runs_back_over():
    assert Route(SQUARE).doubled_length == 0.0
    assert Route(arenas.loop_waypoints()).doubled_length == 0.0
    # up the east side to 150, back down to 50, up again: 100 cm run three times, less the
    # hairpins (within 60 cm along the route a point is its own neighbour, not a return)
    spur = Route([(0, 0), (200, 0), (200, 150), (200, 50), (200, 200), (0, 200)])
    assert 200.0 <= spur.doubled_length <= 300.0
    # a closed shuttle of 2 x 200 cm: all but the 30 cm next to each turn, each way
    assert Route([(0, 0), (200, 0)]).doubled_length == pytest.approx(280.0, abs=21.0)


def _doubled_length_brute_force(r):
    """The all-pairs version doubled_length had until the fourth fuzzing pass (memory N^2)."""
    if r.length <= 0:
        return 0.0
    s = np.arange(0.0, r.length, 3.0)
    p = r._points_at(s)
    k = r._segments_at(s)[1]
    u = r._d[k] / np.maximum(r._len[k], 1e-12)[:, None]
    near = np.hypot(*(p[:, None, :] - p[None, :, :]).transpose(2, 0, 1)) < 12.0
    ds = np.abs(s[:, None] - s[None, :])
    if r.closed:
        ds = np.minimum(ds, r.length - ds)
    back = (u @ u.T) < -0.5
    return float(3.0 * np.count_nonzero(np.any(near & back & (ds > 60.0), axis=1)))


def test_doubled_length_is_the_all_pairs_count_in_memory_linear_in_the_route():
    import tracemalloc

    cps = [(12.0, 100.0), (145.0, 20.0), (145.0, 100.0), (60.0, 10.0)]
    rng = np.random.default_rng(4)
    routes = [Route(SQUARE), Route(SQUARE, closed=False), Route(arenas.loop_waypoints()),
              Route([(0, 0), (200, 0), (200, 150), (200, 50), (200, 200), (0, 200)]),
              Route([(0, 0), (200, 0)]), Route([(0, 0), (200, 0)], closed=False),
              Route([(0, 0), (100, 0), (100, 9), (0, 9)]),   # back 9 cm beside itself
              Route.through(arenas.get("patrol-course"), cps, clearance=8.0),  # doubles back
              *(Route(np.round(rng.uniform(0, 150, (6, 2)) / 10) * 10, closed=c)
                for c in (True, False) for _ in range(10))]
    got = [r.doubled_length for r in routes]
    assert got == [_doubled_length_brute_force(r) for r in routes]
    assert sum(g > 0 for g in got) >= 10 and got[7] > 0 and got[2] == 0.0
    # 11.6 s and 4.4 GB before: a 400 m loop out and back along itself
    tracemalloc.start()
    try:
        long = Route([(0, 0), (20000, 0), (20000, 100), (0, 100)]).doubled_length
        far = Route([(0, 0), (20000, 0)]).doubled_length
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert long == 0.0 and far == pytest.approx(2 * 20000 - 100, abs=30)
    assert peak < 50e6


def test_a_shortest_route_that_runs_back_over_itself_gives_way_to_the_wall_tour():
    # found by trying checkpoints out of the loop's order on patrol-course (seed 333): the
    # shortest paths 1 -> 2 -> 3 -> 4 run the east corridor three times; the robot stopped at
    # checkpoint 3 on every lap and the pass count, by progress along the route, saw none
    from hippo.tasks.patrol_sets import DOUBLED_MAX, choose_route

    cps = [(12.0, 100.0), (145.0, 20.0), (145.0, 100.0), (60.0, 10.0)]
    assert Route.through(arenas.get("patrol-course"), cps, clearance=8.0).doubled_length > \
        DOUBLED_MAX
    kind, route = choose_route("patrol-course", cps)
    assert kind == "tour" and route.doubled_length == 0.0
    assert all(route.distance(*c) <= 30.0 for c in cps)


def test_distance_to_a_route_is_to_its_nearest_point():
    r = Route(SQUARE)
    assert r.distance(50.0, -7.0) == pytest.approx(7.0)
    assert r.distance(50.0, 50.0) == pytest.approx(50.0)
    assert r.distance(130.0, 140.0) == pytest.approx(50.0)   # from the corner (100, 100)
