"""The task-level metrics against answers worked out by hand: progress, heading and laps on a
100 cm square, pass windows and stops on synthetic tracks, the pass report over a span, and
the deployment's failure counter and health sample (found by mutation testing)."""

import math
import resource
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from hippo.sim import arenas
from hippo.tasks import (
    AngleLaps,
    LapCounter,
    Route,
    lead_from,
    pass_report,
    passes,
    route_passes,
    stops,
)
from hippo.tasks.deployment import DeploymentParams, health, tally_failures
from hippo.types import Mode

SQUARE = Route([(0, 0), (100, 0), (100, 100), (0, 100)])   # counter-clockwise, 400 cm
CPS = [(50.0, 0.0), (50.0, 100.0)]                          # progress 50 and 250
W, MOVE = int(Mode.WAIT), int(Mode.MOVE)


def test_the_point_and_heading_at_a_progress_round_a_square():
    # one leg per side: east, north, west, south; a closed route wraps, an open one clips
    assert SQUARE.at(50.0) == pytest.approx((50.0, 0.0, 0.0))
    assert SQUARE.at(150.0) == pytest.approx((100.0, 50.0, math.pi / 2))
    assert SQUARE.at(250.0) == pytest.approx((50.0, 100.0, math.pi))
    assert SQUARE.at(350.0) == pytest.approx((0.0, 50.0, -math.pi / 2))
    assert SQUARE.at(450.0) == pytest.approx(SQUARE.at(50.0))
    assert SQUARE.at(-50.0) == pytest.approx(SQUARE.at(350.0))
    open_ = Route([(0, 0), (100, 0), (100, 100), (0, 100)], closed=False)
    assert open_.at(-10.0) == pytest.approx((0.0, 0.0, 0.0))
    assert open_.at(500.0) == pytest.approx((0.0, 100.0, math.pi))
    # the waypoint nearest a point, whichever coordinate tells them apart
    assert [SQUARE.nearest(*p) for p in [(90, 5), (95, 60), (40, 95), (5, 90), (30, 2)]] == \
        [1, 2, 3, 3, 0]


def test_progress_near_keeps_to_its_stretch_and_searches_everywhere_when_far():
    # a shuttle 2 cm wide: at (100, 0.5) the way out (progress 100) and the way back
    # (progress ~302) are both near; the stretch near the last progress wins
    shuttle = Route([(0, 0), (200, 0), (200, 2), (0, 2)])
    assert shuttle.progress_near(100.0, 0.5, near=95.0) == pytest.approx(100.0, abs=0.5)
    assert shuttle.progress_near(100.0, 0.5, near=310.0) == pytest.approx(302.0, abs=0.5)
    # nothing of the route within the window of progress 50 lies near (100, 60): the whole
    # route is searched (the east side, progress 160)
    assert SQUARE.progress_near(100.0, 60.0, near=50.0) == pytest.approx(160.0)


@pytest.mark.parametrize("sign", [1, -1])
def test_a_lap_counter_counts_each_loop_once_either_way_round(sign):
    # two laps round the square from progress 30, 5 cm a tick, counter-clockwise (+) or
    # clockwise (-), 2 cm off the line: +-1 turn per loop (to the 0.5 cm grid progress_near
    # searches on, biased toward the last progress)
    laps = LapCounter(SQUARE)
    s = 30.0 + sign * np.arange(0.0, 800.0 + 1e-9, 5.0)
    turns = [laps.update(x, y + 2.0) for x, y, _ in map(SQUARE.at, s)]
    assert laps.start == pytest.approx(30.0)
    assert turns[-1] == pytest.approx(2.0 * sign, abs=0.005)
    assert laps.travelled == pytest.approx(800.0 * sign, abs=2.0)
    # one turn when the first loop closes (80 ticks), never counted back on the way
    assert turns[80] == pytest.approx(sign, abs=0.005)
    assert np.all(sign * np.diff(turns) > 0)
    # carried elsewhere: after reset the progress is the new point's, the start is kept
    laps.reset()
    laps.update(100.0, 60.0)
    assert laps.progress == pytest.approx(160.0) and laps.start == pytest.approx(30.0)


def test_winding_is_zero_below_a_quarter_of_the_square_of_the_same_perimeter():
    # 100 x 10: 1,000 cm^2 > 756 (a quarter of a 55 cm square); 100 x 5: 500 < 689
    assert Route([(0, 0), (100, 0), (100, 10), (0, 10)]).winding == 1
    assert Route([(0, 10), (100, 10), (100, 0), (0, 0)]).winding == -1
    assert Route([(0, 0), (100, 0), (100, 5), (0, 5)]).winding == 0


def test_a_leash_to_a_single_waypoint_and_a_bad_start():
    two = arenas.get("two-rooms")
    assert lead_from(two, (20.0, 20.0), [(40.0, 30.0)]) == [(40.0, 30.0)]
    with pytest.raises(ValueError, match="start y must be finite"):
        lead_from(two, (20.0, math.nan), [(40.0, 30.0)])
    with pytest.raises(ValueError, match="outside arena"):
        lead_from(two, (-1.0, 20.0), [(40.0, 30.0)])
    assert lead_from(two, (20.0, 0.0), []) == []    # on the arena's edge: inside it
    with pytest.raises(ValueError, match=r"^y must be finite"):
        SQUARE.progress(0.0, math.nan)


def test_a_pass_is_within_30_cm_by_default():
    # along y = 29.5 or 30.5 past (50, 0) at 5 cm a tick: 29.5 cm is a pass (x 45..55,
    # where sqrt(dx^2 + 29.5^2) < 30), 30.5 cm never is
    x = np.arange(0.0, 101.0, 5.0)
    for y, want in ((29.5, [(9, 12)]), (30.5, [])):
        arrays = {"x": x, "y": np.full_like(x, y), "phase": np.ones(len(x), int)}
        assert passes(arrays, (50.0, 0.0), phase=1) == want


def _square_track(events: dict[float, tuple[int, int, int]], end: float = 805.0,
                  start: float = 5.0) -> dict:
    """Round the square from progress ``start`` at 10 cm per 1-s tick (progress start + 10 j
    at the j-th moving tick); before the moving tick at progress ``p`` the robot stands still there
    for ``n`` ticks in ``mode`` waiting for ``drive`` (``events[p] = (n, mode, drive)``)."""
    cols: dict[str, list] = {k: [] for k in ("x", "y", "speed", "mode", "wait_drive")}

    def tick(px, py, speed, mode, drive):
        for k, v in zip(cols, (px, py, speed, mode, drive), strict=True):
            cols[k].append(v)

    for s in np.arange(start, end + 1e-9, 10.0):
        px, py, _ = SQUARE.at(s)
        n, mode, drive = events.get(float(s), (0, MOVE, -1))
        for _ in range(n):
            tick(px, py, 0.0, mode, drive)
        tick(px, py, 10.0, MOVE, -1)
    out = {k: np.array(v) for k, v in cols.items()}
    n = len(out["x"])
    out |= {"t": np.arange(n, dtype=float), "phase": np.full(n, 2), "trial": np.zeros(n, int)}
    return out


# checkpoint 0 (progress 50): a 5-s wait for its drive on lap 1 (ticks 5-9) and a stop for
# checkpoint 1's drive on lap 2 (ticks 54-58); checkpoint 1 (progress 250): a 4-s wait for
# its drive on lap 1 (ticks 30-33). Moving tick j (progress 5 + 10 j) is tick j, j + 5 after
# the first stop, j + 9 after the second, j + 14 after the third.
EVENTS = {55.0: (5, W, 0), 255.0: (4, W, 1), 455.0: (5, W, 1)}


def test_route_passes_are_the_ticks_within_30_cm_of_progress_once_per_lap():
    arrays = _square_track(EVENTS)
    # checkpoint 0: progress 25..75, moving ticks j = 2..7 (lap 1) and 42..47 (lap 2)
    assert route_passes(arrays, SQUARE, CPS[0], phase=2) == [(2, 13), (51, 62)]
    # checkpoint 1: progress 225..275, j = 22..27 and 62..67
    assert route_passes(arrays, SQUARE, CPS[1], phase=2) == [(27, 37), (76, 82)]
    # the robot the other way round: the same passes, one per lap
    # from progress 105 to 805, checkpoint (0, 50) at progress 350: 325..375 and 725..775
    late = _square_track({}, start=105.0)
    assert route_passes(late, SQUARE, (0.0, 50.0), phase=2) == [(22, 28), (62, 68)]
    # a checkpoint given as a pose (x, y, heading): the same passes
    assert route_passes(late, SQUARE, (0.0, 50.0, 1.0), phase=2) == [(22, 28), (62, 68)]
    back = {k: v[::-1] for k, v in arrays.items()}
    n = len(arrays["x"])
    assert sorted(route_passes(back, SQUARE, CPS[1], phase=2)) == [(n - 82, n - 76),
                                                                   (n - 37, n - 27)]


def test_stops_are_placed_at_their_nearest_checkpoint_with_their_trial():
    arrays = _square_track(EVENTS)
    arrays["trial"] = np.arange(len(arrays["x"])) // 40
    found = stops(arrays, CPS, threshold=0.5)
    assert [(s["i0"], s["duration"], s["checkpoint"], s["drive"], s["trial"]) for s in found] \
        == [(5, 5.0, 0, 0, 0), (30, 4.0, 1, 1, 0), (54, 5.0, 0, 1, 1)]
    # along x only: a stop at (100, 0) is checkpoint 1's of [(0, 0), (100, 0)]; at (50, 0)
    # it is 50 cm from both, no checkpoint's
    for x, want in ((100.0, [1]), (50.0, [])):
        one = {"t": np.arange(4.0), "speed": np.zeros(4), "mode": np.full(4, W),
               "x": np.full(4, x), "y": np.zeros(4), "phase": np.zeros(4, int),
               "trial": np.zeros(4, int), "wait_drive": np.zeros(4, int)}
        assert [s["checkpoint"] for s in stops(one, [(0.0, 0.0), (100.0, 0.0)], 0.5)] == want
    # a log of one tick has no duration: no stop, however still it is
    single = {k: v[:1] for k, v in one.items()}
    assert stops(single, [(0.0, 0.0), (50.0, 0.0)], 0.5) == []


def test_pass_report_per_checkpoint_and_over_a_span():
    arrays = _square_track(EVENTS)
    found = stops(arrays, CPS, threshold=0.5)
    # checkpoint 1's wait was never learned (None): its waits are reported, no errors
    rows = pass_report(arrays, SQUARE, CPS, found, [4.0, None], phase=2)
    assert rows[0] == {"passes": 2, "stops_made": 1, "reproduced_waits_s": [5.0],
                       "extra_stops": 0, "misplaced_stops": 1, "rel_errors": [0.25]}
    assert rows[1] == {"passes": 2, "stops_made": 1, "reproduced_waits_s": [4.0],
                       "extra_stops": 0, "misplaced_stops": 0, "rel_errors": []}

    def at0(i0, i1):
        return pass_report(arrays, SQUARE, CPS, found, [4.0, 4.0], phase=2, span=(i0, i1))[0]

    # the span is [i0, i1): the first pass at checkpoint 0 is [2, 13), the misplaced stop
    # starts at tick 54
    assert at0(0, 13)["passes"] == 1 and at0(0, 12)["passes"] == 0
    assert at0(0, 54)["misplaced_stops"] == 0 and at0(0, 55)["misplaced_stops"] == 1
    assert at0(3, 95)["passes"] == 1
    assert at0(51, 95)["passes"] == 1 and at0(52, 95)["passes"] == 0    # the second pass
    assert at0(54, 95)["misplaced_stops"] == 1 and at0(55, 95)["misplaced_stops"] == 0


def test_failure_counter_on_a_track_with_every_stop_known():
    arrays = _square_track(EVENTS)
    out = tally_failures(arrays, SQUARE, CPS, [5.0, 4.4], 0.5, phase=2)
    # 4 passes, one chosen stop for its drive at each checkpoint: 2 missed; the stop at
    # checkpoint 0 for checkpoint 1's drive is misplaced; 4 s against 4.4 s is 9 % off
    assert {k: out[k] for k in ("tasks", "missed", "misplaced", "wait_off", "extra_stops",
                                "stops")} == {"tasks": 4, "missed": 2, "misplaced": 1,
                                              "wait_off": 1, "extra_stops": 0, "stops": 3}
    assert out["rel_errors"][1] == [pytest.approx(0.4 / 4.4)]
    # a chosen stop 30 cm from the nearest checkpoint is not near it (a pass is within
    # 30 cm): misplaced; at 29 cm it serves it
    for y, misplaced in ((30.0, 1), (29.0, 0)):
        n = 6
        still = {"t": np.arange(float(n)), "speed": np.zeros(n), "mode": np.full(n, W),
                 "x": np.full(n, 50.0), "y": np.full(n, y), "phase": np.full(n, 2),
                 "trial": np.zeros(n, int), "wait_drive": np.zeros(n, int)}
        out = tally_failures(still, SQUARE, CPS, [5.0, 4.0], 0.5, phase=2)
        assert (out["misplaced"], out["stops"]) == (misplaced, 1)
        assert len(stops(still, CPS, 0.5)) == 1 - misplaced   # near it: within 30 cm


def test_health_samples_a_known_agent():
    agent = SimpleNamespace(
        cells=SimpleNamespace(_w=np.array([[0.5, -2.0], [1.0, 0.0]]), transitions=[1, 2, 3]),
        layer=SimpleNamespace(n_states=7), graph=[(0, 1), (1, 2)],
        drives=SimpleNamespace(levels={0: 0.2, 1: 0.9}))
    h = health(agent, 5400.0)
    assert {k: v for k, v in h.items() if k != "rss_mb"} == {
        "t_h": 1.5, "states": 7, "transitions": 3, "map_edges": 2, "drive_min": 0.2,
        "drive_max": 0.9, "weight_max": 2.0, "finite": True}
    # no weights yet and no drives: nothing to take a maximum of
    bare = SimpleNamespace(cells=SimpleNamespace(transitions=[]), graph=[],
                           layer=SimpleNamespace(n_states=0), drives=SimpleNamespace(levels={}))
    h = health(bare, 0.0)
    assert (h["weight_max"], h["finite"], h["drive_min"], h["drive_max"]) == \
        (0.0, True, None, None)
    agent.cells._w = np.array([1.0, math.nan])
    assert health(agent, 0.0)["finite"] is False


def test_deployment_params_default_to_the_documented_values_and_name_a_bad_one():
    assert DeploymentParams() == DeploymentParams(tolerance=0.05, stuck_s=180.0, stuck_cm=10.0)
    for name in ("tolerance", "stuck_s", "stuck_cm"):
        with pytest.raises(ValueError, match=rf"^{name} must"):
            DeploymentParams(**{name: -0.1})


def test_progress_near_is_exact_on_its_half_cm_grid_and_falls_back_off_an_open_route():
    # the points every 0.5 cm from the first waypoint: each one's own progress, 0 included
    # (a new route: the points are computed once per route, on first use)
    square = Route(SQUARE.points)
    for s in (0.0, 0.5, 150.0, 399.5):
        assert square.progress_near(*square.at(s)[:2], near=s) == s
    assert square.progress_near(0.2, 0.0, near=0.0) == 0.0
    # an open route has nothing within 30 cm of progress -100: the whole route is searched
    open_ = Route([(0, 0), (100, 0), (100, 100), (0, 100)], closed=False)
    assert open_.progress_near(100.0, 60.0, near=-100.0) == pytest.approx(160.0)
    # an open shuttle, out along y = 0 and back along y = 2: near progress 50 it stays out
    # (the way back at x = 50 is 152 cm along), though the way back is nearer
    shuttle = Route([(0, 0), (100, 0), (100, 2), (0, 2)], closed=False)
    assert shuttle.progress_near(50.0, 1.5, near=50.0) == 50.0
    assert shuttle.progress(50.0, 1.5) == pytest.approx(152.0)


def test_a_leg_shorter_than_a_cm_is_sampled_along_it():
    r = Route([(0, 0), (0.5, 0), (0.5, 10), (0, 10)])
    assert np.ravel(r.sample(0.25)[:3]) == pytest.approx([0.0, 0.0, 0.25, 0.0, 0.5, 0.0])
    assert r.at(0.25) == pytest.approx((0.25, 0.0, 0.0))


def test_a_leash_round_a_wall_is_the_arenas_shortest_path_then_the_waypoints():
    from hippo.sim import ArenaBuilder

    hall = ArenaBuilder("hall", 120, 120).outer_walls().wall((60, 0), (60, 80)).start(
        30, 30, 0.0).build()
    wp = [(90.0, 30.0), (90.0, 60.0)]
    led = lead_from(hall, (30.0, 30.0), wp)
    _, path = hall.shortest_path((30.0, 30.0), wp[0])
    # the path's last point is the goal's grid cell: the waypoint itself takes its place
    assert led == [tuple(map(float, p)) for p in path[:-1]] + wp
    assert max(y for _, y in led) > 80.0    # round the wall's end
    assert math.dist(led[-3], wp[0]) < 9.0  # one step of the path (3 cells of 2 cm) from it


def test_a_route_to_a_point_that_cannot_be_reached_is_refused():
    with pytest.raises(ValueError, match="no path from"):
        Route.through(arenas.get("two-rooms"), [(15.0, 65.0), (0.5, 0.5)])


def test_progress_along_needs_as_many_ys_as_xs():
    from hippo.tasks import progress_along

    with pytest.raises(ValueError):
        progress_along(SQUARE, np.array([0.0, 10.0, 20.0]), np.array([0.0, 0.0]))


def test_a_stop_is_at_most_the_threshold_speed_for_at_least_min_s():
    # 0.5-s ticks; the robot at checkpoint 0 at exactly the threshold speed (still) for
    # 2 ticks (1 s: the default min_s), moving for 2, still for 1 tick (0.5 s: too short)
    n = 8
    arrays = {"t": 0.5 * np.arange(n), "speed": np.array([1, .5, .5, 1, 1, .5, 1, 1]),
              "mode": np.full(n, W), "x": np.zeros(n), "y": np.zeros(n),
              "phase": np.full(n, 3), "trial": np.zeros(n, int), "wait_drive": np.full(n, 2)}
    found = stops(arrays, [(0.0, 0.0)], threshold=0.5)
    assert [(s["i0"], s["duration"], s["drive"]) for s in found] == [(1, 1.0, 2)]
    # the teacher's block waits for no drive: -1
    arrays["wait_drive"] = np.full(n, -1)
    taught = stops(arrays, [(0.0, 0.0)], threshold=0.5, taught_phase=3)
    assert [(s["i0"], s["drive"]) for s in taught] == [(1, -1)]
    # a one-tick log: a stop of no duration (counted only when min_s is 0)
    one = {k: v[1:2] for k, v in arrays.items()}
    assert [s["duration"] for s in stops(one, [(0.0, 0.0)], 0.5, min_s=0.0)] == [0.0]


def test_a_stop_just_after_a_pass_is_not_that_passs_stop():
    # checkpoint at (90, 0), progress 90: the pass is progress 65..115, moving ticks j = 6..11
    # ([6, 12)); a stop at progress 125, round the corner at (100, 25), 27 cm from the
    # checkpoint (near it), starts at tick 12: after the pass, not its stop
    arrays = _square_track({125.0: (3, W, 0)}, end=295.0)
    found = stops(arrays, [(90.0, 0.0)], threshold=0.5)
    assert [(s["i0"], s["checkpoint"]) for s in found] == [(12, 0)]
    row = pass_report(arrays, SQUARE, [(90.0, 0.0)], found, [3.0], phase=2)[0]
    assert (row["passes"], row["stops_made"], row["misplaced_stops"]) == (1, 0, 0)
    # a stop at progress 65, where the pass begins (its first tick, 6): that pass's stop
    arrays = _square_track({65.0: (3, W, 0)}, end=295.0)
    found = stops(arrays, [(90.0, 0.0)], threshold=0.5)
    assert route_passes(arrays, SQUARE, (90.0, 0.0), phase=2)[0][0] == found[0]["i0"] == 6
    row = pass_report(arrays, SQUARE, [(90.0, 0.0)], found, [3.0], phase=2)[0]
    assert (row["passes"], row["stops_made"], row["reproduced_waits_s"]) == (1, 1, [3.0])


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="needs /proc")
def test_health_memory_is_the_resident_size_now_not_the_peak():
    # 100 MB touched and freed: the peak stays up, the resident size comes back down (what a
    # leak over hours would show)
    big = np.ones(100_000_000 // 8)
    del big
    agent = SimpleNamespace(cells=SimpleNamespace(transitions=[]), graph=[],
                            layer=SimpleNamespace(n_states=0), drives=SimpleNamespace(levels={}))
    rss = health(agent, 0.0)["rss_mb"]
    status = Path("/proc/self/status").read_text()
    vm_rss = int(next(ln.split()[1] for ln in status.splitlines() if ln.startswith("VmRSS:")))
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 / 1e6   # KiB on Linux
    assert rss == pytest.approx(vm_rss * 1024 / 1e6, abs=5.0)
    assert rss < peak_mb - 50.0


@pytest.mark.parametrize(("platform", "maxrss", "mb", "shown"),
                         [("darwin", 123_456_789, 123.456789, 123.5),
                          ("linux", 150_000, 153.6, 153.6)])
def test_health_memory_without_proc_is_the_peak_in_mb(monkeypatch, platform, maxrss, mb, shown):
    # no /proc (macOS, the BSDs): the peak resident size, which getrusage gives in bytes on
    # macOS and in KiB elsewhere (it was divided by 1e3 everywhere: 1000 x too much on macOS);
    # the health sample shows it to 0.1 MB
    import sys

    from hippo.tasks import deployment

    def no_proc(*_a, **_k):
        raise OSError("no /proc")

    monkeypatch.setattr(deployment, "open", no_proc, raising=False)
    monkeypatch.setattr(sys, "platform", platform)
    own = resource.RUSAGE_SELF
    monkeypatch.setattr(resource, "getrusage",
                        lambda who: SimpleNamespace(ru_maxrss=maxrss if who == own else -1))
    assert deployment._rss_mb() == mb
    agent = SimpleNamespace(cells=SimpleNamespace(transitions=[]), graph=[],
                            layer=SimpleNamespace(n_states=0), drives=SimpleNamespace(levels={}))
    assert health(agent, 0.0)["rss_mb"] == shown


def test_a_leash_in_the_open_goes_straight():
    from hippo.sim import ArenaBuilder

    hall = ArenaBuilder("hall", 120, 120).outer_walls().start(20, 60, 0.0).build()
    for start, wp in (((20.0, 60.0), [(50.0, 60.0)]), ((100.0, 60.0), [(70.0, 80.0)])):
        assert lead_from(hall, start, wp) == wp


def test_a_route_for_a_robot_wider_than_the_corridor_is_refused():
    # two-rooms' corridor is 24 cm wide: no way through for a disc of radius 14
    two = arenas.get("two-rooms")
    assert Route.through(two, [(15.0, 45.0), (100.0, 40.0)], radius=5.0).length > 150.0
    with pytest.raises(ValueError, match="no path from"):
        Route.through(two, [(15.0, 45.0), (100.0, 40.0)], radius=14.0)


def test_a_lap_counter_refuses_a_window_of_nothing():
    with pytest.raises(ValueError, match="window must be > 0 cm"):
        LapCounter(SQUARE, window=0.0)


def test_stuck_is_exactly_stuck_s_without_stuck_cm_of_progress():
    from hippo.tasks.deployment import StuckWatch

    w = StuckWatch(stuck_s=60.0, stuck_cm=10.0)
    w.reset(0.0, 100.0)
    assert [w.update(t, 109.0) for t in (30.0, 59.5, 60.0)] == [False, False, True]
    w.reset(0.0, 100.0)
    assert not w.update(59.5, 110.0) and not w.update(119.0, 110.0) and w.update(119.5, 110.0)


def test_angle_laps_sum_the_angle_swept_however_unevenly():
    # round (5, 5) at 10 cm, counter-clockwise in uneven steps (0.9, 1.5, 1.78, 1.5, 0.6 rad):
    # one turn; back the same way: none
    angles = [0.1, 1.0, 2.5, -2.0, -0.5, 0.1]
    laps = AngleLaps((5.0, 5.0))
    turns = [laps.update(5 + 10 * math.cos(a), 5 + 10 * math.sin(a)) for a in angles]
    assert turns[:3] == pytest.approx([0.0, 0.9 / (2 * math.pi), 2.4 / (2 * math.pi)])
    assert turns[-1] == pytest.approx(1.0)
    back = [laps.update(5 + 10 * math.cos(a), 5 + 10 * math.sin(a)) for a in angles[::-1]]
    assert back[-1] == pytest.approx(0.0, abs=1e-12)


def test_a_routes_first_leg_takes_a_narrow_corridor_over_a_long_detour():
    # patrol-course: from the east corridor to the south-west corner the shortest way is the
    # 22 cm south corridor (166 cm), not round the north (278 cm): the route takes it first
    # (clockwise) and comes back round the north
    r = Route.through(arenas.get("patrol-course"), [(137.0, 49.0), (11.0, 15.0)], clearance=8.0)
    assert r.progress(11.0, 15.0) < 0.45 * r.length
    assert r.winding == -1
