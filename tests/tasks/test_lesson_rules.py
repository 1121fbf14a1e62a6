"""teach_patrol's rules: every refusal word for word, each bound exactly on its edge and one
step past, and the recipe on stand-ins that record what they are given (the route, the wall,
the exploration, the place cells, the agent's settings, the session, the course, the lesson
and the longest taught stop per checkpoint worked out by hand)."""

from __future__ import annotations

import importlib
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from hippo.cognitive_map import LocaliserParams
from hippo.sim import ArenaBuilder
from hippo.tasks.log import Log
from hippo.tasks.patrol import PatrolPhase
from hippo.types import Observation

L = importlib.import_module("hippo.tasks.lesson")
ex = importlib.import_module("hippo.tasks.explore")

CPS = [(80, 11), (140, 56), (50, 105)]
WAITS = [24.1, 19.1, 11.6]


def _refused(**kwargs: Any) -> str:
    args = {"arena": "patrol-course", "checkpoints": CPS, "waits": WAITS, **kwargs}
    with pytest.raises(ValueError) as e:
        L.teach_patrol(args.pop("arena"), args.pop("checkpoints"), args.pop("waits"), **args)
    return str(e.value)


def test_the_refusals_word_for_word():
    assert _refused(place_cells="gt") == ("place_cells must be 'learned' or 'ground-truth', "
                                          "got 'gt'")
    assert _refused(side=0) == "side must be -1 (right wall), +1 (left wall) or None, got 0"
    assert _refused(side=2) == "side must be -1 (right wall), +1 (left wall) or None, got 2"
    assert _refused(side=1.0) == "side must be -1 (right wall), +1 (left wall) or None, got 1.0"
    assert _refused(side=True) == "side must be -1 (right wall), +1 (left wall) or None, got True"
    for v in (0.0, -5.0, float("nan")):   # before any work, as every other refusal here
        assert "hop_time must be" in _refused(hop_time=v)
    for v in (0.0999, 10000.001):
        assert _refused(explore_min=v) == (f"explore_min must be 0.1 to 10,000 simulated "
                                           f"minutes, got {v!r}")
    for name, hi in (("units", 600), ("places", 256), ("heading_sectors", 360)):
        for v in (0, hi + 1):
            assert _refused(place_cells="ground-truth", **{name: v}) == (
                f"{name} must be an integer in [1, {hi}], got {v}")
    bare = ArenaBuilder("bare", 200, 150).outer_walls().start(20, 20, 0.0).build()
    assert _refused(arena=bare, place_cells="ground-truth") == (
        "arena 'bare' has no reference locations for ground-truth place cells "
        "(ArenaBuilder.grid_locations)")
    assert _refused(units=409) == (
        "units=409 exceeds the 408 inputs of the learned place cells' SFA (8 IR readings + "
        "400 reservoir neurons): at most 408")
    # the fit needs (100 + 0 - 1) * 1 + 1 = 100 ticks = 20 s = 1/3 min, rounded up to 0.34
    assert _refused(explore_min=0.33) == (
        "explore_min=0.33 gives 99 ticks of exploration; the place cells' fit needs at least "
        "100 (20 s): explore_min >= 0.34")
    # re-anchoring: skip 250 + window 5 + 2 * spread 25 = 305 moving ticks = 61 s = 1.0167 min
    assert _refused(explore_min=1.0, reanchor=True) == (
        "explore_min=1.0 gives 300 ticks of exploration; reanchor's sequence matching (of the "
        "ticks the robot moves) needs at least 305 (61 s): explore_min >= 1.02")
    assert "304 ticks" in _refused(explore_min=304 * 0.2 / 60, reanchor=True)


class _Recorder:
    """Stand-ins for the lesson's parts; each records its arguments."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch, kind: str = "shortest",
                 taught: list[dict] | None = None) -> None:
        self.calls: dict[str, Any] = {}
        self.loop = SimpleNamespace(name="the loop")
        obs = [Observation(t=0.2 * i, tick=i, ir=np.full(8, float(i)), floor=0, sound=False,
                           odometry=np.zeros(3), moving=bool(i % 3)) for i in range(600)]
        self.tour = ex.Tour(obs, [None] * 600)
        rec = self

        def checked_route(*a: Any) -> tuple[str, Any]:
            rec.calls["checked_route"] = a
            return kind, rec.loop

        def wall_side(*a: Any) -> int:
            rec.calls["wall_side"] = a
            return 1

        def explore(*a: Any, **kw: Any) -> ex.Tour:
            rec.calls["explore"] = (a, kw)
            return rec.tour

        class Cells:
            def prime(self, s: np.ndarray) -> None:
                rec.calls["prime"] = s

        def make_places(*a: Any, **kw: Any) -> Cells:
            rec.calls["make_places"] = (a, kw)
            rec.cells = Cells()
            return rec.cells

        def agent(*a: Any, **kw: Any) -> Any:
            rec.calls["agent"] = (a, kw)
            return SimpleNamespace(name="agent")

        def session(*a: Any, **kw: Any) -> Any:
            rec.calls["session"] = (a, kw)
            return SimpleNamespace(log=SimpleNamespace(arrays=lambda: "arrays"))

        class Course:
            def __init__(self, *a: Any, **kw: Any) -> None:
                rec.calls["course"] = (a, kw)
                rec.course = self

            def teach(self, waits: list[float]) -> float:
                rec.calls["teach"] = waits
                return 0.75

        def stops(*a: Any, **kw: Any) -> list[dict]:
            rec.calls["stops"] = (a, kw)
            return taught or []

        # the route the robot is led along: the followed wall's tour (a route of its own)
        self.led = SimpleNamespace(name="the followed wall's tour")

        def tour_of_side(*a: Any) -> Any:
            rec.calls["tour_of_side"] = a
            return rec.led

        for name, f in (("checked_route", checked_route), ("wall_side", wall_side),
                        ("tour_of_side", tour_of_side),
                        ("explore", explore), ("make_places", make_places), ("Agent", agent),
                        ("Session", session), ("PatrolCourse", Course), ("stops", stops)):
            monkeypatch.setattr(L, name, f)


def test_the_recipe_hands_each_part_what_it_needs(monkeypatch):
    C, S = PatrolPhase.CHECKPOINTS, PatrolPhase.LEASH
    # per checkpoint, the longest stop in the checkpoints' phase: 0 -> 4.0 (not the 9.0 of
    # another phase), 1 -> none, 2 -> 2.5
    taught = [{"checkpoint": 0, "phase": C, "duration": 3.0},
              {"checkpoint": 0, "phase": C, "duration": 4.0},
              {"checkpoint": 0, "phase": S, "duration": 9.0},
              {"checkpoint": 2, "phase": C, "duration": 2.5}]
    rec = _Recorder(monkeypatch, kind="tour", taught=taught)
    lesson = L.teach_patrol("patrol-course", [[80, 11], (140.5, 56), (50, 105)], [24, 19.1, 11],
                            seed=3, route="tour", explore_min=2.0, units=6, places=7)
    cps = [(80.0, 11.0), (140.5, 56.0), (50.0, 105.0)]
    world = lesson.world
    assert world.arena.name == "patrol-course" and world.dt == 0.2 and world.seed == 3
    assert world.sensors.n == 8                              # the 8 IR sensors
    assert rec.calls["checked_route"] == ("patrol-course", cps, [24, 19.1, 11], "tour")
    assert all(type(v) is float for c in rec.calls["checked_route"][1] for v in c)
    arena, seed = rec.calls["wall_side"][1:]
    assert rec.calls["wall_side"][0] is rec.loop and arena is world.arena and seed == 3
    (w, ticks, rho, seed, log), kw = rec.calls["explore"]
    # 2 min at 0.2 s a tick: 600 ticks; the side wall_side gave
    assert (w, ticks, rho, seed, kw) == (world, 600, 0.0, 3, {"side": 1})
    assert isinstance(log, Log) and log.n_drives == 3
    a, kw = rec.calls["make_places"]
    assert a[:2] == ("learned", world.arena) and a[3:] == (6, 3, 7)
    np.testing.assert_array_equal(a[2], rec.tour.sensors)
    assert kw == {"moving": None}
    np.testing.assert_array_equal(rec.calls["prime"], rec.tour.sensors[100:])   # the last 500
    (cells,), kw = rec.calls["agent"]
    assert cells is rec.cells and kw["seed"] == 3
    assert kw["sensors"] is world.sensors and kw["robot"] is world.robot
    names = ["checkpoint-1", "checkpoint-2", "checkpoint-3"]
    assert list(kw["drives"]) == names
    d = kw["drives"]["checkpoint-2"]
    assert (d.epsilon, d.learning_rate) == (0.01, 0.5)
    p = kw["params"]
    assert p.brain.states == ex.PLACE_STATES and p.brain.relocalise == LocaliserParams()
    assert (p.brain.planner.w, p.brain.planner.noise, p.brain.planner.exploration_threshold) \
        == (0.9, 0.0, 0.05)
    # the drives discounted by the learned time to a checkpoint, 5 s a hop
    assert p.brain.planner.hop_time == L.PATROL_HOP_TIME == 5.0
    assert (p.motor.wall_side, p.brain.heading_sectors) == (1, L.LEARNED_SECTORS) == (1, 4)
    (w, agent, slog), kw = rec.calls["session"]
    assert w is world and agent is lesson.agent and slog is log
    assert set(kw) == {"obs", "phase"} and kw["phase"] == PatrolPhase.LEASH
    assert kw["obs"] is rec.tour[-1]                  # the exploration's last observation
    # led along the tour of the wall wall_side gave (after the side is known)
    assert rec.calls["tour_of_side"] == ("patrol-course", cps, "tour", rec.loop, 1)
    (s, loop, cps2, names2), kw = rec.calls["course"]
    assert s is lesson.session and loop is rec.led and cps2 == cps and names2 == names
    assert kw == {"tour": True}
    assert rec.calls["teach"] == [24.0, 19.1, 11.0]
    assert all(type(v) is float for v in rec.calls["teach"])
    (arrays, cps3, threshold), kw = rec.calls["stops"]
    assert arrays == "arrays" and cps3 == cps and threshold == world.robot.moving_threshold
    assert kw == {"taught_phase": PatrolPhase.CHECKPOINTS}
    assert lesson.course is rec.course and lesson.agent is not None
    assert lesson.reproduced == 0.75 and lesson.taught_stops == [4.0, None, 2.5]
    assert lesson.route_kind == "tour"


def test_the_recipe_with_a_side_given_ground_truth_and_reanchoring(monkeypatch):
    rec = _Recorder(monkeypatch)
    lesson = L.teach_patrol("goal-arena", CPS[:2], WAITS[:2], place_cells="ground-truth",
                            side=-1, explore_min=0.1, reanchor=True)
    assert "wall_side" not in rec.calls                       # the side given is taken
    assert rec.calls["checked_route"][3] == "auto" and lesson.world.seed == 0
    (_w, ticks, _rho, seed, log), kw = rec.calls["explore"]
    assert (ticks, seed, kw, log.n_drives) == (30, 0, {"side": -1}, 2)
    a, kw = rec.calls["make_places"]
    assert a[0] == "ground-truth" and a[3:] == (24, 0, 40)       # the default units, places
    np.testing.assert_array_equal(kw["moving"], rec.tour.moving)
    p = rec.calls["agent"][1]["params"]
    assert (p.motor.wall_side, p.brain.heading_sectors) == (-1, 1)   # one sector for fields
    assert p.brain.planner.hop_time == L.PATROL_HOP_TIME
    assert rec.calls["course"][1] == {"tour": False}
    assert lesson.taught_stops == [None, None] and lesson.route_kind == "shortest"


def test_the_drives_discount_per_hop_or_per_time_as_asked(monkeypatch):
    rec = _Recorder(monkeypatch)
    L.teach_patrol("goal-arena", CPS[:2], WAITS[:2], place_cells="ground-truth",
                   side=-1, explore_min=0.1, hop_time=None)     # HIREL's w per state crossed
    assert rec.calls["agent"][1]["params"].brain.planner.hop_time is None
    L.teach_patrol("goal-arena", CPS[:2], WAITS[:2], place_cells="ground-truth",
                   side=-1, explore_min=0.1, hop_time=2.5)
    assert rec.calls["agent"][1]["params"].brain.planner.hop_time == 2.5


def test_the_bounds_on_their_edges_are_taken(monkeypatch):
    rec = _Recorder(monkeypatch)
    for kw in ({"explore_min": 0.1}, {"explore_min": 1e4}, {"units": 600}, {"places": 256},
               {"heading_sectors": 360}, {"units": 1, "places": 1, "heading_sectors": 1}):
        L.teach_patrol("patrol-course", CPS, WAITS, place_cells="ground-truth", **kw)
    assert rec.calls["explore"][0][1] == 9000    # the last: the default 30 min of 0.2-s ticks
    p = rec.calls["agent"][1]["params"]
    assert p.brain.heading_sectors == 1
    # learned: exactly the 100 ticks the fit needs (1/3 min), exactly 408 units; and with
    # re-anchoring exactly 305 ticks
    L.teach_patrol("patrol-course", CPS, WAITS, explore_min=1 / 3, units=408)
    assert rec.calls["explore"][0][1] == 100 and rec.calls["make_places"][0][3] == 408
    L.teach_patrol("patrol-course", CPS, WAITS, explore_min=305 * 0.2 / 60, reanchor=True,
                   heading_sectors=2)
    assert rec.calls["explore"][0][1] == 305
    assert rec.calls["agent"][1]["params"].brain.heading_sectors == 2
