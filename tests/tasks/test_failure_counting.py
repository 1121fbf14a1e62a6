"""The long deployment's failure counting (RatSLAM style) and its stuck watch, on tracks
built by hand whose every failure is known."""

import math

import numpy as np
import pytest

from hippo.sim import arenas
from hippo.tasks import Route
from hippo.tasks.deployment import DeploymentParams, StuckWatch, tally_failures
from hippo.tasks.patrol import ARENA_CHECKPOINTS, check_patrol, patrol_route
from hippo.tasks.patrol_sets import MAX_WAIT_S, MIN_WAIT_S
from hippo.types import Mode

SQUARE = Route([(0, 0), (100, 0), (100, 100), (0, 100)])
CPS = [(50.0, 0.0), (50.0, 100.0)]  # progress 50 and 250 along the square
LEARNED = [10.0, 6.0]  # s: the waits learned at each checkpoint


def _track(events: dict[int, tuple[int, int, int]], laps: float = 3.0, start: float = 150.0):
    """A robot going round the square at 5 cm per 1-s tick from progress ``start``; at the
    tick where it reaches progress ``p`` (a key of ``events``) it stands still for ``n``
    ticks in mode ``mode`` waiting for drive ``drive`` (``events[p] = (n, mode, drive)``)."""
    x, y, speed, mode, drive = [], [], [], [], []
    s = start
    pending = dict(events)
    while s < start + laps * SQUARE.length:
        px, py, _ = SQUARE.at(s)
        hit = [p for p in pending if s >= p]
        if hit:
            n, m, d = pending.pop(hit[0])
            for _ in range(n):
                x.append(px), y.append(py), speed.append(0.0), mode.append(m), drive.append(d)
        x.append(px), y.append(py), speed.append(5.0), mode.append(int(Mode.MOVE))
        drive.append(-1)
        s += 5.0
    n = len(x)
    return {"t": np.arange(n, dtype=float), "x": np.array(x), "y": np.array(y),
            "speed": np.array(speed), "mode": np.array(mode), "wait_drive": np.array(drive),
            "phase": np.full(n, 7), "trial": np.zeros(n, int)}


W = int(Mode.WAIT)


def test_a_perfect_patrol_has_no_failures():
    # laps from progress 150: checkpoint 0 at 450, 850, 1250; checkpoint 1 at 250, 650, 1050
    ev = {p: (10, W, 0) for p in (450, 850, 1250)} | {p: (6, W, 1) for p in (250, 650, 1050)}
    out = tally_failures(_track(ev), SQUARE, CPS, LEARNED, 0.5, phase=7)
    assert out["tasks"] == 6
    assert (out["missed"], out["misplaced"], out["wait_off"]) == (0, 0, 0)
    assert out["waits_s"] == [[10.0] * 3, [6.0] * 3]


def test_each_kind_of_failure_is_counted_once():
    ev = {450: (10, W, 0), 850: (12, W, 0),   # checkpoint 0: a right wait, one 20 % too long
          1250: (10, W, 0),
          250: (6, W, 1),                     # checkpoint 1: right
          650: (6, W, 0),                     # ... a stop there for checkpoint 0's drive
          1050: (6, int(Mode.EXPLORE), 1),    # ... still, but not a chosen stop: missed
          350: (8, W, 1)}                     # a chosen stop at a corner, far from both
    out = tally_failures(_track(ev), SQUARE, CPS, LEARNED, 0.5, phase=7, tolerance=0.05)
    assert out["tasks"] == 6
    assert out["missed"] == 2       # lap 2 (wrong drive) and lap 3 (not chosen) at cp 1
    assert out["misplaced"] == 2    # the wrong drive at cp 1, the stop at the corner
    assert out["wait_off"] == 1     # the 12 s wait against 10 s learned
    assert out["waits_s"][0] == [10.0, 12.0, 10.0]
    # a looser tolerance forgives the long wait; another phase holds nothing
    assert tally_failures(_track(ev), SQUARE, CPS, LEARNED, 0.5, phase=7,
                          tolerance=0.25)["wait_off"] == 0
    assert tally_failures(_track(ev), SQUARE, CPS, LEARNED, 0.5, phase=3)["tasks"] == 0


def test_a_second_stop_in_one_pass_is_extra_not_a_task():
    ev = {450: (10, W, 0), 460: (10, W, 0), 850: (10, W, 0), 1250: (10, W, 0),
          250: (6, W, 1), 650: (6, W, 1), 1050: (6, W, 1)}
    out = tally_failures(_track(ev), SQUARE, CPS, LEARNED, 0.5, phase=7)
    assert (out["tasks"], out["missed"], out["extra_stops"]) == (6, 0, 1)


def test_stuck_watch_fires_after_stuck_s_without_progress():
    w = StuckWatch(stuck_s=60.0, stuck_cm=10.0)
    w.reset(0.0, 0.0)
    # steady progress: never stuck
    assert not any(w.update(t, 0.5 * t) for t in np.arange(0.0, 600.0, 0.2))
    w.reset(600.0, 300.0)
    # wiggling back and forth by 8 cm: no 10 cm of new progress; stuck exactly 60 s on
    fired = [t for t in np.arange(600.2, 700.0, 0.2)
             if w.update(t, 300.0 + 8.0 * math.sin(t))]
    assert fired and fired[0] == pytest.approx(660.0, abs=0.21)
    # going the wrong way round is stuck too
    w.reset(0.0, 300.0)
    assert w.update(61.0, 250.0) and not StuckWatch(60.0, 10.0).update(61.0, 250.0)


def test_deployment_params_refuse_impossible_values():
    for bad in ({"tolerance": 0.0}, {"stuck_s": -1.0}, {"stuck_cm": math.nan}):
        with pytest.raises(ValueError, match=next(iter(bad))):
            DeploymentParams(**bad)


def test_check_patrol_names_the_problem():
    route = check_patrol("patrol-course", ARENA_CHECKPOINTS["patrol-course"], [2.0, 3.0, 4.0])
    assert route.length == pytest.approx(patrol_route(
        "patrol-course", ARENA_CHECKPOINTS["patrol-course"]).length)
    with pytest.raises(ValueError, match="3 waits for 2 checkpoints"):
        check_patrol("two-rooms", ARENA_CHECKPOINTS["two-rooms"][:2], [2.0, 3.0, 4.0])
    with pytest.raises(ValueError, match="not free floor"):
        check_patrol("two-rooms", [(0.5, 0.5), (90.0, 20.0)], [2.0, 3.0])
    with pytest.raises(ValueError, match="apart along the route"):
        check_patrol("two-rooms", [(90.0, 20.0), (100.0, 22.0)], [2.0, 3.0])
    # a 1-s wait was learned as 0.8 s and never reproduced (ground truth); NaN is no wait
    for short in (1.0, float("nan")):
        with pytest.raises(ValueError, match=f"must be at least {MIN_WAIT_S:g} s"):
            check_patrol("patrol-course", ARENA_CHECKPOINTS["patrol-course"], [short, 3.0, 4.0])
    # beyond the timing battery's longest delay a wait was learned as 120 s (500 s), never
    # ended (1e9: 5e9 ticks of block) or failed after the exploration (inf)
    for long in (120.5, 500.0, 1e9, float("inf")):
        with pytest.raises(ValueError, match=f"must be at most {MAX_WAIT_S:g} s"):
            check_patrol("patrol-course", ARENA_CHECKPOINTS["patrol-course"], [3.0, long, 4.0])
    check_patrol("patrol-course", ARENA_CHECKPOINTS["patrol-course"], [3.0, MAX_WAIT_S, 4.0])
    assert arenas.get("two-rooms").is_free(90.0, 20.0, 6.0)
