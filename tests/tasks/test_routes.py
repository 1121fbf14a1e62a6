"""Routes and checkpoints: progress along a route, laps, passes and stops."""

import math

import numpy as np
import pytest

from hippo.tasks import AngleLaps, LapCounter, Route, passes, stops
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
