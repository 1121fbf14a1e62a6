"""The sixth fuzzing pass: what a newcomer building a task hands the task API.

Each case failed before with an error that named nothing the caller wrote (an ``IndexError``,
"too many values to unpack", "waypoints must not all be one point" for two equal checkpoints),
returned a silent wrong answer (NaN relative errors, 0 rounds for ``n=0``, no passes for a NaN
radius), or hung (``Route.sample(1e-6)``). Now each raises at the call, naming the argument.
"""

from __future__ import annotations

import math
import re
import typing
from types import SimpleNamespace

import numpy as np
import pytest

from hippo.envs import PatrolEnv
from hippo.sim import ArenaBuilder
from hippo.tasks import (
    PatrolCourse,
    Route,
    check_patrol,
    lead_from,
    pass_report,
    passes,
    progress_along,
    random_patrol,
    route_passes,
    stops,
)
from hippo.tasks.deployment import StuckWatch, tally_failures
from hippo.tasks.patrol_report import patrol_rounds
from hippo.tasks.routes import MAX_SAMPLES
from hippo.types import Mode

SQUARE = [(0.0, 0.0), (100.0, 0.0), (100.0, 100.0), (0.0, 100.0)]
CPS = [(50.0, 0.0), (100.0, 50.0), (50.0, 100.0)]
PHASE = 4


def _log() -> dict:
    """Two laps round ``SQUARE`` at 5 cm a tick (0.2 s), with a 20-tick stop at checkpoint 2
    (for drive 1) on each lap."""
    r = Route(SQUARE)
    pts = []
    for _ in range(2):
        for s in np.arange(0.0, 400.0, 5.0):
            x, y, _ = r.at(s)
            pts.append((x, y))
            if s == 150.0:
                pts += [(x, y)] * 20
    xy = np.array(pts)
    n = len(xy)
    speed = np.r_[5.0, np.hypot(*np.diff(xy, axis=0).T)]
    still = speed == 0
    return {"t": np.arange(n) * 0.2, "x": xy[:, 0], "y": xy[:, 1],
            "phase": np.full(n, PHASE), "speed": speed,
            "mode": np.where(still, int(Mode.WAIT), 0), "wait_drive": np.where(still, 1, -1),
            "trial": np.zeros(n, dtype=int)}


LOG = _log()
STOPS = stops(LOG, CPS, 0.1)
V, T = ValueError, TypeError
#: what PatrolCourse reads of its session when it is built
_SESSION = SimpleNamespace(agent=None, world=SimpleNamespace(dt=0.2))


def _arena():
    return ArenaBuilder("square", 150, 150).outer_walls().start(20, 20).build()


# (id, call, exception, pattern)
CASES: list[tuple[str, typing.Callable, type, str]] = [
    # --- Route
    ("route closed a string", lambda: Route(SQUARE, closed="no"), T,
     r"^closed must be True or False, got 'no'"),
    ("route sample 1e-6 cm (a hang)", lambda: Route(SQUARE).sample(1e-6), V,
     r"^spacing 1e-06 cm gives 4e\+08 points along this 400-cm route; at most 1,000,000"),
    ("route progress_near window -1", lambda: Route(SQUARE).progress_near(5, 0, 5, -1.0), V,
     r"^window must be finite and > 0, got -1"),
    ("route progress_near window nan", lambda: Route(SQUARE).progress_near(5, 0, 5, np.nan), V,
     r"^window must be finite and > 0, got nan"),
    ("route nearest nan", lambda: Route(SQUARE).nearest(np.nan, 0), V, r"^x must be finite"),
    ("route leg goal nan", lambda: Route(SQUARE).leg((0, 0), (np.nan, 5)), V,
     r"^goal x must be finite"),
    ("route leg start of one number", lambda: Route(SQUARE).leg((1,), (5, 5)), V,
     r"^start must be a point \(x, y\)"),
    ("route loop_from (x, y)", lambda: Route(SQUARE).loop_from((0, 0)), V,
     r"^pose must be \(x, y, heading\)"),
    ("route loop_from heading nan", lambda: Route(SQUARE).loop_from((1, 0, np.nan)), V,
     r"^heading must be finite"),
    ("lead_from start of one number", lambda: lead_from(_arena(), (20,), [(50, 50)]), V,
     r"^start must be a point \(x, y\), got \(20,\)"),
    ("route through one point twice", lambda: Route.through(_arena(), [(50, 50), (50, 50)]), V,
     r"^points must not all be one point: got 2 copies of \(50, 50\)"),
    ("route through (x, y, heading)",
     lambda: Route.through(_arena(), [(50, 50, 0), (100, 100, 0)]), V,
     r"^a route needs at least two points \(x, y\), got \(2, 3\)"),
    ("route through nan", lambda: Route.through(_arena(), [(50, 50), (np.nan, 50)]), V,
     r"^points contains 1 non-finite"),
    ("route through radius nan",
     lambda: Route.through(_arena(), [(50, 50), (100, 100)], radius=np.nan), V,
     r"^radius must be finite and > 0"),
    ("route through radius -1",
     lambda: Route.through(_arena(), [(50, 50), (100, 100)], radius=-1), V,
     r"^radius must be finite and > 0"),
    # --- passes and stops
    ("passes radius nan", lambda: passes(LOG, CPS[1], phase=PHASE, radius=np.nan), V,
     r"^radius must be finite and > 0"),
    ("passes centre nan", lambda: passes(LOG, (np.nan, 0), phase=PHASE), V,
     r"^centre x must be finite, got nan"),
    ("passes centre a number", lambda: passes(LOG, 5.0, phase=PHASE), V,
     r"^centre must be a point \(x, y\), got 5\.0"),
    ("route_passes radius nan",
     lambda: route_passes(LOG, Route(SQUARE), CPS[1], phase=PHASE, radius=np.nan), V,
     r"^radius must be finite and > 0"),
    ("route_passes radius 0",
     lambda: route_passes(LOG, Route(SQUARE), CPS[1], phase=PHASE, radius=0), V,
     r"^radius must be finite and > 0"),
    ("route_passes open route",
     lambda: route_passes(LOG, Route(SQUARE, closed=False), CPS[1], phase=PHASE), V,
     r"^route passes need a closed route"),
    ("progress_along x and y differ",
     lambda: progress_along(Route(SQUARE), np.zeros(3), np.zeros(4)), V,
     r"^x and y must be as long, got 3 and 4"),
    ("stops no checkpoints", lambda: stops(LOG, [], 0.1), V,
     r"^checkpoints must be one or more points"),
    ("stops threshold nan", lambda: stops(LOG, CPS, np.nan), V,
     r"^threshold must be finite and >= 0"),
    ("stops radius nan", lambda: stops(LOG, CPS, 0.1, radius=np.nan), V,
     r"^radius must be > 0 cm \(inf: anywhere\)"),
    ("stops min_s nan", lambda: stops(LOG, CPS, 0.1, min_s=np.nan), V,
     r"^min_s must be finite and >= 0"),
    ("stops taught trial names no checkpoint",
     lambda: stops({**LOG, "trial": np.full(len(LOG["t"]), 7)}, CPS, 0.1, taught_phase=PHASE),
     V, r"^the stop at tick 31 \(taught_phase 4\) is in trial 7, which names no checkpoint "
        r"\(there are 3\)"),
    # --- pass_report, patrol_rounds, the failure counter
    ("pass_report one learned wait for three checkpoints",
     lambda: pass_report(LOG, Route(SQUARE), CPS, STOPS, [4.0], phase=PHASE), V,
     r"^learned must give one wait per checkpoint \(3\), got 1"),
    ("pass_report learned nan",
     lambda: pass_report(LOG, Route(SQUARE), CPS, STOPS, [4.0, np.nan, 4.0], phase=PHASE), V,
     r"^learned\[1\] must be a finite wait >= 0 s or None \(not learned\), got nan"),
    ("pass_report learned -4",
     lambda: pass_report(LOG, Route(SQUARE), CPS, STOPS, [4.0, -4.0, 4.0], phase=PHASE), V,
     r"^learned\[1\] must be a finite wait"),
    ("pass_report span backwards",
     lambda: pass_report(LOG, Route(SQUARE), CPS, STOPS, [4.0] * 3, phase=PHASE, span=(100, 10)),
     V, r"^span must be \[i0, i1\) with i0 <= i1, got \(100, 10\)"),
    ("pass_report span nan",
     lambda: pass_report(LOG, Route(SQUARE), CPS, STOPS, [4.0] * 3, phase=PHASE,
                         span=(0, np.nan)), V, r"^span end must be an integer, got nan"),
    ("tally_failures learned nan",
     lambda: tally_failures(LOG, Route(SQUARE), CPS, [4.0, np.nan, 4.0], 0.1, phase=PHASE), V,
     r"^learned\[1\] must be a finite wait"),
    ("tally_failures tolerance nan",
     lambda: tally_failures(LOG, Route(SQUARE), CPS, [4.0] * 3, 0.1, phase=PHASE,
                            tolerance=np.nan), V, r"^tolerance must be finite and > 0"),
    # StuckWatch: a NaN stuck_s never fired, a NaN time restarted the watch every tick
    ("stuck watch stuck_s nan", lambda: StuckWatch(np.nan, 10.0), V,
     r"^stuck_s must be finite and > 0"),
    ("stuck watch stuck_cm -5", lambda: StuckWatch(180.0, -5.0), V,
     r"^stuck_cm must be finite and > 0"),
    ("stuck watch time nan", lambda: StuckWatch(180.0, 10.0).update(np.nan, 0.0), V,
     r"^t must be finite"),
    ("stuck watch progress nan", lambda: StuckWatch(180.0, 10.0).update(0.0, np.nan), V,
     r"^travelled must be finite"),
    ("patrol_rounds n 0", lambda: patrol_rounds(STOPS, 0, phase=PHASE), V,
     r"^n must be an integer >= 1, got 0"),
    ("patrol_rounds n 2.5", lambda: patrol_rounds(STOPS, 2.5, phase=PHASE), V,
     r"^n must be an integer, got 2\.5"),
    # --- check_patrol, random_patrol
    ("check_patrol two checkpoints on one spot",
     lambda: check_patrol(_arena(), [(30, 30), (30, 30)], [9, 9]), V,
     r"^checkpoints 1 and 2 are the same point \(30, 30\)"),
    ("check_patrol a checkpoint twice of three",
     lambda: check_patrol(_arena(), [(30, 30), (120, 120), (30, 30)], [9, 9, 9]), V,
     r"^checkpoints 1 and 3 are the same point \(30, 30\)"),
    ("check_patrol (x, y, heading)",
     lambda: check_patrol(_arena(), [(30, 30, 0), (120, 120, 0)], [9, 9]), V,
     r"^checkpoints must be one or more points \(x, y\), got shape \(2, 3\)"),
    ("check_patrol checkpoint nan",
     lambda: check_patrol(_arena(), [(30, 30), (np.nan, 30)], [9, 9]), V,
     r"^checkpoints contains 1 non-finite"),
    ("check_patrol wait None", lambda: check_patrol(_arena(), [(30, 30), (120, 120)], [None, 9]),
     V, r"^waits must be numbers of seconds, got None"),
    ("check_patrol one wait, no list",
     lambda: check_patrol(_arena(), [(30, 30), (120, 120)], 9), V,
     r"^waits must be a list of waits in s \(one per checkpoint\), got 9"),
    ("random_patrol tries 0", lambda: random_patrol(_arena(), 2, 0, tries=0), V,
     r"^tries must be an integer >= 1, got 0"),
    ("random_patrol waits of one number", lambda: random_patrol(_arena(), 2, 0, waits=(9,)), V,
     r"^waits must be \(low, high\) in s, got \(9,\)"),
    # --- an arena round a pillar built without start(): the robot started in the pillar,
    # and random_patrol drew the checkpoints there
    ("builder default start inside the central box",
     lambda: ArenaBuilder("ring", 150, 150).outer_walls().box((40, 40, 110, 110)).build(), V,
     r"^start \(75, 75\) \(the default start, the centre\) of 'ring' lies inside box "
     r"\(40\.0, 40\.0, 110\.0, 110\.0\), a pillar the robot cannot leave"),
    ("builder start given inside a box",
     lambda: ArenaBuilder("ring", 150, 150).outer_walls().box((40, 40, 110, 110))
     .start(75, 60).build(), V, r"^start \(75, 60\) of 'ring' lies inside box"),
    # --- PatrolCourse (names: one drive each; a shared one served two checkpoints)
    ("course names fewer than checkpoints",
     lambda: PatrolCourse(_SESSION, Route(SQUARE), CPS[:2], ["a"]), V,
     r"^names must be one distinct drive name per checkpoint \(2\), got \['a'\]"),
    ("course one name twice", lambda: PatrolCourse(_SESSION, Route(SQUARE), CPS[:2], ["a", "a"]),
     V, r"^names must be one distinct drive name per checkpoint"),
    ("course no checkpoints", lambda: PatrolCourse(_SESSION, Route(SQUARE), [], []), V,
     r"^checkpoints must be one or more points \(x, y\), got shape \(0,\)"),
    ("course (x, y, heading)", lambda: PatrolCourse(_SESSION, Route(SQUARE), [(50, 0, 0)], ["a"]),
     V, r"^checkpoints must be one or more points \(x, y\), got shape \(1, 3\)"),
    # --- the gymnasium environments
    ("env patrol waits a number", lambda: PatrolEnv(waits=5), V,
     r"^waits must be three waits in s, one per checkpoint, got 5"),
    ("env patrol waits text", lambda: PatrolEnv(waits="abc"), V,
     r"^waits must be three waits in s, one per checkpoint, got 'abc'"),
    ("env step text", lambda: _env().step("ab"), V, r"^action must be two finite wheel speeds"),
    ("env step complex", lambda: _env().step([1j, 0]), V,
     r"^action must be two finite wheel speeds"),
    ("env step dict", lambda: _env().step({"left": 1}), V,
     r"^action must be two finite wheel speeds"),
]


def _env() -> PatrolEnv:
    env = PatrolEnv()
    env.reset(seed=0)
    return env


@pytest.mark.parametrize(("call", "exc", "pattern"), [c[1:] for c in CASES],
                         ids=[c[0] for c in CASES])
def test_a_bad_task_input_is_refused_by_name(call, exc, pattern):
    with pytest.raises(exc) as err:
        call()
    assert type(err.value) is exc
    assert re.search(pattern, str(err.value)), str(err.value)


def test_valid_calls_are_unchanged():
    """The same answers as before the checks, for the inputs they let through."""
    r = Route(SQUARE)
    assert [route_passes(LOG, r, c, phase=PHASE) for c in CPS] == [
        [(5, 16), (105, 117)], [(24, 56), (125, 157)], [(64, 77), (165, 177)]]
    assert [(st["i0"], st["duration"], st["checkpoint"]) for st in STOPS] == [
        (31, 4.0, 1), (131, 4.0, 1)]
    # anywhere (the failure counter's radius=inf): each stop at its nearest checkpoint
    assert stops(LOG, CPS, 0.1, radius=math.inf) == STOPS
    # None and 0: not learned, no relative errors; numpy numbers are numbers
    rows = pass_report(LOG, r, CPS, STOPS, [None, np.float32(5.0), 0.0], phase=PHASE)
    assert [row["rel_errors"] for row in rows] == [[], [0.2, 0.2], []]
    assert patrol_rounds(STOPS, np.int64(1), phase=PHASE) == (1, 1, 2)
    assert len(r.sample(400.0 / MAX_SAMPLES * 100)) == MAX_SAMPLES // 100
    assert r.leg((1.0, 0.0), (np.float32(100.0), np.int64(90))) == [
        (100.0, 0.0), (100.0, 100.0), (100.0, 90.0)]
    course = PatrolCourse(_SESSION, r, [np.array([50, 0]), (100.0, 50.0)], ("a", "b"))
    assert course.checkpoints == [(50.0, 0.0), (100.0, 50.0)] and course.names == ["a", "b"]
    # a numpy bool is taken, and kept as a plain bool
    assert Route(SQUARE, closed=np.bool_(False)).closed is False


def test_a_box_may_hold_the_start_when_it_is_the_outer_wall():
    """A box round every wall is the arena's outer wall, not a pillar: the start may be in it;
    so may a start beside a pillar."""
    assert ArenaBuilder("room", 150, 150).box((0, 0, 150, 150)).build().start_pose[:2] == (
        75.0, 75.0)
    room = ArenaBuilder("room", 150, 150).box((10, 10, 140, 140)).wall((20, 20), (60, 60))
    assert room.build().start_pose[:2] == (75.0, 75.0)
    ring = ArenaBuilder("ring", 150, 150).outer_walls().box((40, 40, 110, 110)).start(20, 60)
    assert ring.build().start_pose[:2] == (20.0, 60.0)


def test_check_patrol_takes_numpy_checkpoints_and_waits():
    cps, waits = np.array([(30, 30), (120, 120)]), np.array([9, 12])
    assert check_patrol(_arena(), cps, waits).length == pytest.approx(
        check_patrol(_arena(), [(30.0, 30.0), (120.0, 120.0)], [9.0, 12.0]).length)
