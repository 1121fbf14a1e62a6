"""The session's rules with stand-ins that record what they are given: a world that counts its
ticks (dt 0.2 s), an agent, a teacher and a log. The observations the agent acts on, the
ground truth handed to it only for ground-truth place cells, the tick counts by hand
(rounded down), the lead's limit and its warning word for word, the block's length, the
turn a lift reports (worked out by hand) and every refusal word for word."""

from __future__ import annotations

import math
import warnings
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from hippo.sim import ArenaBuilder, World
from hippo.sim.teacher import Teacher
from hippo.tasks.log import Log
from hippo.tasks.session import LeashWarning, Session
from hippo.types import GroundTruth, Observation


class _World:
    """Moves 1 cm along x a tick; every observation and truth is a new object."""

    dt = 0.2

    def __init__(self, heading: float = 0.0) -> None:
        self.tick = 0
        self.teacher: Any = None
        self.events: list[tuple[float, str, str]] = []
        self.actions: list[Any] = []
        self.placed: list[tuple] = []
        self.heading = heading
        self.truth = self._truth()

    def _truth(self) -> GroundTruth:
        return GroundTruth(t=self.tick * self.dt, tick=self.tick,
                           pose=(float(self.tick), 7.0, self.heading), speed=5.0)

    def observe(self) -> Observation:
        return Observation(t=self.tick * self.dt, tick=self.tick, ir=np.zeros(8), floor=0,
                           sound=False, odometry=np.array([0.0, 0.0, 0.1]), moving=True)

    def step(self, action: Any) -> Observation:
        self.actions.append(action)
        self.tick += 1
        self.truth = self._truth()
        return self.observe()

    def place_robot(self, x: float, y: float, heading: float, *, event: str) -> None:
        self.placed.append((x, y, heading, event))


class _Agent:
    """Records each step's observation and truth (and whether the truth was the world's)."""

    def __init__(self, world: _World, kind: str = "learned", drives: int = 2) -> None:
        self.world = world
        self.places = SimpleNamespace(kind=kind)
        self.drives = SimpleNamespace(names=[f"d{i}" for i in range(drives)])
        self.seen: list[Observation] = []
        self.truths: list[Any] = []
        self.lifts: list[dict] = []

    def step(self, obs: Observation, truth: Any) -> tuple[float, float]:
        self.seen.append(obs)
        self.truths.append(truth)
        if truth is not None:
            assert truth is self.world.truth           # the truth of the tick before
        return (float(obs.tick), -1.0)

    def snapshot(self) -> dict[str, Any]:
        return {"winner": len(self.seen), "mode": 1, "prediction": 0.0,
                "non_occurrence": False, "sound_prediction": 0.0,
                "sound_non_occurrence": False, "drives": [0.0] * len(self.drives.names),
                "wait_drive": -1}

    def lifted(self, *, heading_change: float, keep_drives: bool) -> None:
        self.lifts.append({"heading_change": heading_change, "keep_drives": keep_drives})


class _Teacher:
    """Leads until tick ``lead_until`` and blocks until tick ``block_until`` of its world."""

    def __init__(self, world: _World, lead_until: float = math.inf,
                 block_until: float = math.inf) -> None:
        self.world, self.lead_until, self.block_until = world, lead_until, block_until
        self.calls: list[tuple[str, Any]] = []

    @property
    def leading(self) -> bool:
        return self.world.tick < self.lead_until

    @property
    def blocking(self) -> bool:
        return self.world.tick < self.block_until

    def lead(self, route: Any) -> None:
        self.calls.append(("lead", route))

    def stop_leading(self) -> None:
        self.calls.append(("stop_leading", self.world.tick))
        self.lead_until = -1

    def block(self, seconds: float) -> None:
        self.calls.append(("block", seconds))


def _session(kind: str = "learned", **teacher: float) -> tuple[_World, _Agent, Session]:
    world = _World()
    agent = _Agent(world, kind)
    return world, agent, Session(world, agent, teacher=_Teacher(world, **teacher))


def test_the_defaults_log_teacher_first_observation_phase_and_trial():
    world = _World()
    agent = _Agent(world, drives=3)
    s = Session(world, agent, teacher=_Teacher(world))
    assert isinstance(s.log, Log) and s.log.n_drives == 3 and len(s.log) == 0
    assert (s.phase, s.trial) == (0, 0)
    assert s.obs.tick == 0 and s.t == 0.0 and isinstance(s.t, float)
    assert s.truth is world.truth
    log = Log(n_drives=5)
    first = world.observe()
    s = Session(world, agent, log, obs=first, teacher=_Teacher(world), phase=2, trial=6)
    assert s.log is log and s.obs is first and (s.phase, s.trial) == (2, 6)
    s.run(2)
    assert agent.seen[0] is first                           # the agent acts on it first
    np.testing.assert_array_equal(log.column("phase"), [2, 2])
    np.testing.assert_array_equal(log.column("trial"), [6, 6])


def test_the_default_teacher_is_the_worlds_own_or_a_new_one_attached_to_it():
    arena = ArenaBuilder("box", 60, 60).outer_walls().start(30, 30, 0.0).build()
    world = World(arena, seed=0)
    agent = _Agent(world)                                    # type: ignore[arg-type]
    s = Session(world, agent)
    assert isinstance(s.teacher, Teacher) and world.teacher is s.teacher
    assert Session(world, agent).teacher is s.teacher        # the world's own, not a new one
    assert s.obs.tick == world.tick == 0                     # the world senses where it is
    world2 = World(arena, seed=0)
    world2.teacher = object()                                # some other intervention
    s2 = Session(world2, agent)
    assert isinstance(s2.teacher, Teacher) and world2.teacher is s2.teacher


def test_run_feeds_each_observation_back_and_logs_every_tick():
    world, agent, s = _session()
    first = s.obs
    last = s.run(3)
    # the agent acts on the first observation, then on each the world returned
    assert agent.seen[0] is first and [o.tick for o in agent.seen] == [0, 1, 2]
    assert world.actions == [(0.0, -1.0), (1.0, -1.0), (2.0, -1.0)]
    assert last is s.obs and last.tick == 3 and s.t == pytest.approx(0.6)
    assert agent.truths == [None, None, None]                # learned cells get no truth
    np.testing.assert_array_equal(s.log.column("x"), [1.0, 2.0, 3.0])  # after each step
    np.testing.assert_array_equal(s.log.column("winner"), [1, 2, 3])   # the agent's snapshot


def test_ground_truth_place_cells_get_the_worlds_truth():
    world, agent, s = _session("ground-truth")
    s.run(2)
    assert [t.tick for t in agent.truths] == [0, 1]
    # place cells that name no kind get none
    agent = _Agent(world)
    agent.places = object()                 # type: ignore[assignment]
    Session(world, agent, teacher=_Teacher(world)).run(2)
    assert agent.truths == [None, None]


def test_until_stops_after_the_tick_it_is_true_on_and_the_bar_counts_ticks():
    _world, _agent, s = _session()
    seen: list[int] = []
    bar = SimpleNamespace(n=0)
    bar.update = lambda: setattr(bar, "n", bar.n + 1)

    def until(o: Observation) -> bool:
        seen.append(o.tick)
        return o.tick == 4

    obs = s.run(10, until=until, bar=bar)   # type: ignore[arg-type]
    assert seen == [1, 2, 3, 4] and obs.tick == 4 and len(s.log) == 4 and bar.n == 4


def test_seconds_are_whole_ticks_rounded_down():
    world, _agent, s = _session()
    assert [s.ticks(x) for x in (0.0, 0.19, 0.2, 0.5, 1.0)] == [0, 0, 1, 2, 5]
    s.run(seconds=0.5)                       # 2.5 ticks: 2
    assert world.tick == 2
    s.run(seconds=0.0)
    assert world.tick == 2
    s.run(0)
    assert world.tick == 2


def test_seconds_that_are_whole_ticks_are_not_lost_to_floating_point():
    # 0.6 / 0.2 == 2.9999999999999996 and 9.2 / 0.2 == 45.99999999999999: those are 3 and 46
    # ticks, not 2 and 45; a quotient short of a whole number by more than rounding stays down
    world, _agent, s = _session()
    assert 0.6 / world.dt < 3 and 9.2 / world.dt < 46
    assert [s.ticks(x) for x in (0.6, 1.4, 9.2, 0.59, 0.7999)] == [3, 7, 46, 2, 3]
    s.run(seconds=0.6)
    assert world.tick == 3


def test_run_refusals_word_for_word():
    world, _agent, s = _session()
    for kwargs in ({}, {"ticks": 3, "seconds": 1.0}):
        with pytest.raises(ValueError) as e:
            s.run(**kwargs)
        assert str(e.value) == "give either ticks or seconds"
    with pytest.raises(ValueError) as e:
        s.run(seconds=-0.5)
    assert str(e.value) == "seconds must be >= 0, got -0.5"
    with pytest.raises(ValueError) as e:
        s.run(-1)
    assert str(e.value) == "ticks must be an integer >= 0, got -1"
    assert world.tick == 0 and len(s.log) == 0


def test_a_lead_that_arrives_in_time_says_nothing():
    world, _agent, s = _session(lead_until=3)
    route = [(10.0, 7.0), (40.0, 7.0)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        obs = s.lead(route, limit=5)
    assert s.teacher.calls == [("lead", route)] and world.tick == 3 and obs.tick == 3


def test_a_lead_that_runs_out_of_ticks_drops_the_leash_with_its_message():
    world, _agent, s = _session()
    with pytest.warns(LeashWarning) as rec:
        s.lead([(10.0, 7.0), (185.0, 15.0)], limit=7)
    assert world.tick == 7 and s.teacher.calls[-1] == ("stop_leading", 7)
    # the robot stands at (7, 7) after 7 ticks of 1 cm
    assert str(rec[0].message) == ("the leash was dropped after 7 ticks with the robot at "
                                   "(7, 7), short of the route's end (185.0, 15.0)")
    assert len(rec) == 1


def test_a_lead_runs_6000_ticks_at_most_by_default():
    world, _agent, s = _session()
    with pytest.warns(LeashWarning, match="dropped after 6000 ticks"):
        s.lead([(1.0, 1.0)])
    assert world.tick == 6000


def test_block_holds_for_the_seconds_and_one_more_or_until_the_teacher_lets_go():
    world, _, s = _session()
    s.block(1.0)                              # never released: (1 + 1) s = 10 ticks
    assert s.teacher.calls == [("block", 1.0)] and world.tick == 10
    s.block(1.0, extra=0.5)                   # 1.5 s = 7.5 ticks: 7
    assert world.tick == 17
    world, _agent, s = _session(block_until=3)
    obs = s.block(4.0)
    assert world.tick == 3 and obs.tick == 3


def test_put_reports_the_turn_from_the_heading_the_agent_last_integrated():
    world, agent, s = _session()
    world.heading = 0.5
    world.truth = world._truth()
    # turned = 2.0 - 0.5 + 0.1 (the odometry the agent has not integrated yet) = 1.6
    s.put(30.0, 8.0, 2.0)
    assert world.placed == [(30.0, 8.0, 2.0, "kidnap")]
    assert agent.lifts[0]["heading_change"] == pytest.approx(1.6)
    assert agent.lifts[0]["keep_drives"] is False
    # 3.0 - (-3.0) + 0.1 = 6.1, wrapped to 6.1 - 2 pi
    world.heading = -3.0
    world.truth = world._truth()
    s.put(1.0, 2.0, 3, event="rescue", keep_drives=True)
    assert world.placed[-1] == (1.0, 2.0, 3.0, "rescue")
    assert agent.lifts[-1]["heading_change"] == pytest.approx(6.1 - 2 * math.pi)
    assert agent.lifts[-1]["keep_drives"] is True
    with pytest.raises(ValueError) as e:
        s.put(1.0, 2.0, math.inf)
    assert str(e.value) == "heading must be finite, got inf"
    assert len(world.placed) == 2 and len(agent.lifts) == 2


def test_save_hands_the_log_its_agent_world_and_phases(tmp_path):
    world, agent, s = _session()
    calls: list[tuple] = []

    def save(out: Any, a: Any, w: Any, *, phases: Any = None) -> dict:
        calls.append((out, a, w, phases))
        return {"t": "given back"}

    s.log = SimpleNamespace(save=save)       # type: ignore[assignment]
    assert s.save(tmp_path, "PHASES") == {"t": "given back"}
    assert s.save(tmp_path) == {"t": "given back"}
    assert calls == [(tmp_path, agent, world, "PHASES"), (tmp_path, agent, world, None)]
