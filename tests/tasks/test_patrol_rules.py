"""PatrolCourse's rules (hippo/tasks/patrol.py) on a stand-in session that records what it is
asked and moves the robot where each case's script says, along a hand-made route.

The route is the square (100, 100), (200, 100), (200, 200), (100, 200), counter-clockwise,
400 cm long; progress s along it is x - 100 on the bottom edge, 100 + (y - 100) on the right,
200 + (200 - x) on top and 300 + (200 - y) on the left. The checkpoints are c0 = (150, 100)
at s = 50, c1 = (200, 150) at s = 150 and c2 = (100, 150) at s = 350, with drives a, b, c.
Their circular distances leave s = 250 farthest from every checkpoint (100 cm from c1 and
c2): the quiet point; the checkpoint before it is c1, so "just past the last" is s = 160.
The robot walks in steps of 25 cm (1/16 of a lap: lap counts stay exact in binary). Ticks are
0.25 s, so every tick count is worked out exactly: int(seconds / 0.25)."""

from __future__ import annotations

import math
import re
from types import SimpleNamespace
from typing import Any

import pytest

import hippo.tasks.patrol as P
from hippo.sim import ArenaBuilder
from hippo.tasks.patrol import DETOUR_RATIO, DETOUR_SLACK, PatrolCourse, PatrolPhase
from hippo.tasks.routes import Route
from hippo.types import Mode, StateKind

DT = 0.25
ARENA = ArenaBuilder("open", 600, 600).outer_walls().start(50, 50).build()
CPS = [(150.0, 100.0), (200.0, 150.0), (100.0, 150.0)]
NAMES = ["a", "b", "c"]


def _square(side: float = 100.0) -> Route:
    o = 100.0
    return Route([(o, o), (o + side, o), (o + side, o + side), (o, o + side)])


ROUTE = _square()


class _Drives:
    def __init__(self, events: list, levels: dict | None = None,
                 links: dict | None = None) -> None:
        self.events, self.levels, self._links = events, dict(levels or {}), links or {}

    def step(self, dt: float) -> None:
        self.events.append(("step", dt))

    def inhibit(self, name: str) -> None:
        self.events.append(("inhibit", name))

    def release(self, name: str) -> None:
        self.events.append(("release", name))

    def set_level(self, name: str, level: float) -> None:
        self.events.append(("set_level", name, level))

    def level(self, name: str) -> float:
        return self.levels[name]

    def links(self, name: str) -> list:
        return self._links.get(name, [])


class _Agent:
    def __init__(self, events: list, **drives: Any) -> None:
        self.events = events
        self.p = SimpleNamespace(settle_time=3.0)
        self.drives = _Drives(events, **drives)
        self.mode, self.state, self.kinds = Mode.EXPLORE, None, {}
        self.brain = SimpleNamespace(localiser=None)
        self.wait_drive = -1
        self.cells = SimpleNamespace(transitions=set(), learned_delay=None)

    def kind(self, state: int) -> StateKind:
        return self.kinds[state]

    def lifted(self, **kw: Any) -> None:
        self.events.append(("lifted", kw))

    def reward(self, name: str, runup: bool) -> None:
        self.events.append(("reward", name, runup))

    def snapshot(self) -> dict:
        return {"wait_drive": self.wait_drive}


class _Session:
    """What PatrolCourse uses of a Session. ``script`` holds, per call of run (in order), the
    steps of that run: a number moves the robot to that progress along ROUTE (facing along
    it), a callable changes something else; ``until`` is asked after each step, as Session.run
    asks it after each tick. Every call is recorded in ``events``."""

    def __init__(self, s0: float, route: Route = ROUTE) -> None:
        self.events: list = []
        self.route = route
        self.agent = _Agent(self.events)
        self.world = SimpleNamespace(dt=DT, arena=ARENA)
        self.truth = SimpleNamespace(pose=list(route.at(s0)))
        self.teacher = SimpleNamespace(leading=False, lead=self._teacher_lead)
        self.script: list[list] = []
        self.phase: Any = None
        self.trial: Any = None
        self.rows = 0
        self.t = 0.0
        self.ran: list[float] = []
        self.log = _Log(self)
        self.untils: list = []

    def _teacher_lead(self, waypoints: list) -> None:
        self.events.append(("teacher.lead", waypoints))
        self.teacher.leading = True

    def _path_length(self, row: int, xy: tuple) -> float:
        self.events.append(("path_length", row, xy))
        return self.ran.pop(0)

    def go(self, s: float) -> None:
        self.truth.pose = list(self.route.at(s))

    def run(self, ticks: int | None = None, *, until: Any = None) -> Any:
        self.events.append(("run", ticks, self.phase, self.trial))
        self.untils.append(until)
        for step in (self.script.pop(0) if self.script else []):
            if callable(step):
                step(self)
            else:
                self.go(step)
            self.t += DT
            self.rows += 1
            if until is not None and until(None):
                break
        return SimpleNamespace(t=self.t)

    def lead(self, path: list, limit: int = 6000) -> None:
        self.events.append(("lead", path, limit))
        x, y = path[-1]
        self.truth.pose = [x, y, 0.0]

    def block(self, seconds: float, extra: float = 1.0) -> None:
        self.events.append(("block", seconds, extra))

    def put(self, x: float, y: float, heading: float, *, keep_drives: bool = False) -> None:
        self.events.append(("put", (x, y, heading), keep_drives))
        self.truth.pose = [x, y, heading]


class _Log:
    def __init__(self, s: _Session) -> None:
        self.s = s

    def __len__(self) -> int:
        return self.s.rows

    def path_length(self, row: int, xy: tuple) -> float:
        return self.s._path_length(row, xy)


def _walk(a: float, b: float, step: float = 25.0) -> list[float]:
    """Progress a + step, a + 2 step, ... up to b (b itself last)."""
    n = round((b - a) / step)
    assert math.isclose(a + n * step, b)
    return [a + k * step for k in range(1, n + 1)]


def _state(kind: StateKind) -> Any:
    def set_state(s: _Session) -> None:
        sid = len(s.agent.kinds)
        s.agent.kinds[sid] = kind
        s.agent.state = sid
    return set_state


def _mode(mode: Mode) -> Any:
    def set_mode(s: _Session) -> None:
        s.agent.mode = mode
    return set_mode


def _leash_off(s: _Session) -> None:
    s.teacher.leading = False


def _noop(s: _Session) -> None:
    pass


LEFT = [_state(StateKind.STILL), _state(StateKind.MOVING)]   # a stop, then moving on


def _course(s0: float = 30.0, route: Route = ROUTE, cps: list = CPS, names: list = NAMES,
            **kw: Any) -> tuple[PatrolCourse, _Session]:
    s = _Session(s0, route)
    return PatrolCourse(s, route, cps, names, **kw), s   # type: ignore[arg-type]


def _kinds(s: _Session, *names: str) -> list:
    return [e for e in s.events if e[0] in names]


@pytest.fixture
def bars(monkeypatch: pytest.MonkeyPatch) -> list:
    """The progress bars made: [total, label, updates]."""
    made: list = []

    class Bar:
        def __init__(self, total: int, desc: str) -> None:
            self.rec = [total, desc, 0]
            made.append(self.rec)

        def __enter__(self) -> Bar:
            return self

        def __exit__(self, *exc: object) -> None:
            pass

        def update(self) -> None:
            self.rec[2] += 1
    monkeypatch.setattr(P, "Progress", Bar)
    return made


# --- the course's geometry


def test_the_phases_are_numbered_as_run_npz_stores_them():
    assert [(p.name, int(p)) for p in PatrolPhase] == [
        ("EXPLORATION", 0), ("LEASH", 1), ("REPRODUCTION", 2), ("CHECKPOINTS", 3),
        ("PATROL", 4), ("ADAPTATION", 5), ("KIDNAP", 6), ("DEPLOYMENT", 7)]
    assert (DETOUR_RATIO, DETOUR_SLACK) == (1.25, 10.0)


def test_the_course_keeps_its_parts_and_finds_the_quiet_point():
    course, s = _course()
    assert course.s is s and course.agent is s.agent and course.dt == DT
    assert course.route is ROUTE and course.tour is False and course.relocalised_s is None
    assert course.checkpoints == CPS and all(type(v) is float for c in course.checkpoints
                                             for v in c)
    assert course.names == NAMES and course.loop.route is ROUTE
    assert list(course._s_cp) == [50.0, 150.0, 350.0]
    assert course.quiet == 250.0 and course.order == [0, 1, 2]
    # one checkpoint at s = 50: the quiet point is half the loop on, at s = 250
    assert _course(cps=[(150.0, 100.0)], names=["a"])[0].quiet == 250.0
    # two half a loop apart (s = 0 and 200) leave s = 100 and 300 equally quiet: the first
    assert _course(cps=[(100.0, 100.0), (200.0, 200.0)], names=["a", "b"])[0].quiet == 100.0
    # s = 20 and 60: 40 cm apart; farthest from both is s = 240, 180 from 60 and 220 from 20
    assert _course(cps=[(120.0, 100.0), (160.0, 100.0)], names=["a", "b"])[0].quiet == 240.0
    # ... and 390 (s = 390 and 30): the gap runs over the route's start, 40 cm again
    c = _course(cps=[(100.0, 110.0), (130.0, 100.0)], names=["a", "b"])[0]
    assert c.quiet == 210.0 and c.order == [0, 1]


def test_the_order_is_the_routes_from_the_first_checkpoint():
    # given c1, c2, c0 (s = 150, 350, 50): from c1 the route passes c2 after 200, c0 after 300
    assert _course(cps=[CPS[1], CPS[2], CPS[0]])[0].order == [0, 1, 2]
    # given c2, c1, c0 (s = 350, 150, 50): from c2, c0 comes after 100 and c1 after 200
    assert _course(cps=[CPS[2], CPS[1], CPS[0]])[0].order == [0, 2, 1]


def test_names_are_one_distinct_drive_per_checkpoint():
    for bad in ("abc", ["a", "b"], ["a", "b", "a"], ["a", "b", "c", "d"]):
        with pytest.raises(ValueError, match="^" + re.escape(
                f"names must be one distinct drive name per checkpoint (3), got {bad!r}") + "$"):
            _course(names=bad)
    assert _course(names=("x", "y", "z"))[0].names == ["x", "y", "z"]


def test_a_lap_is_given_three_times_the_route_at_5_cm_s_and_at_least_600_s():
    assert _course()[0].lap_s == 600.0                   # 3 * 400 / 5 = 240 s
    assert _course(route=_square(250.0), cps=[(150.0, 100.0)], names=["a"])[0].lap_s == 600.0
    # 1000 cm: exactly 600 s either way; 1200 cm: 720 s
    big = _course(route=_square(300.0), cps=[(150.0, 100.0)], names=["a"])[0]
    assert big.lap_s == 720.0


def test_laps_follow_the_robot_and_lap_until_compares_with_the_target():
    course, s = _course(s0=30.0)
    assert course.laps() == 0.0 and course.loop.progress == 30.0
    until = course.lap_until(0.125)
    s.go(55.0)
    assert until(None) is False                        # 0.0625 < 0.125
    s.go(80.0)
    assert until(None) is True                         # 0.125 >= 0.125, on the edge
    assert course.laps() == 0.125


def test_laps_to_quiet_adds_the_way_to_the_quiet_point_and_the_loops():
    course, s = _course(s0=150.0)
    # from s = 150 the quiet point (250) is 100 cm = 0.25 lap ahead
    assert course.laps_to_quiet(1) == 1.25
    assert course.laps_to_quiet(3) == 3.25
    for step in _walk(150.0, 300.0):
        s.go(step)
        course.laps()
    # at s = 325, past the quiet point, after 175 cm (0.4375 laps): the next quiet point is
    # 325 cm (0.8125) ahead
    s.go(325.0)
    assert course.laps_to_quiet(1) == 0.4375 + 0.8125 + 1
    # to a point given instead: s = 165 from s = 325 is 240 cm (0.6) ahead
    assert course.laps_to_quiet(2, 165.0) == 0.4375 + 0.6 + 2


def test_just_past_last_is_10_cm_past_the_checkpoint_before_the_quiet_point():
    assert _course()[0].just_past_last() == 160.0
    # checkpoints at s = 20 and 60: quiet at 240, the one before it is at 60
    assert _course(cps=[(120.0, 100.0), (160.0, 100.0)],
                   names=["a", "b"])[0].just_past_last() == 70.0
    # s = 390 and 310: the long gap runs from 390 over the route's start to 310, its middle
    # is s = 150; the checkpoint before it is the one at 390, and 10 cm past it is 400
    c = _course(cps=[(100.0, 110.0), (100.0, 190.0)], names=["a", "b"])[0]
    assert (c.quiet, c.just_past_last()) == (150.0, 400.0)


def test_state_kind_near_and_from_here():
    course, s = _course(s0=30.0)
    assert course.state_kind() is None
    s.agent.kinds[4] = StateKind.STILL
    s.agent.state = 4
    assert course.state_kind() is StateKind.STILL
    s.agent.kinds[0] = StateKind.PLACE
    s.agent.state = 0                                 # state 0 is a state
    assert course.state_kind() is StateKind.PLACE
    # near: strictly within the radius, (130, 100) to (150, 100) is 20 cm
    assert course.near((150.0, 100.0), 20.0 + 2**-40) and not course.near((150.0, 100.0), 20.0)
    assert course.near((130.0, 130.0), 30.5) and not course.near((130.0, 130.0), 30.0)
    # from here: a leash that can go straight keeps the waypoints
    assert course.from_here([(160.0, 120.0), (200.0, 200.0)]) == [(160.0, 120.0),
                                                                  (200.0, 200.0)]


def test_from_here_goes_round_a_wall_between_the_robot_and_the_first_waypoint():
    walled = (ArenaBuilder("walled", 300, 300).outer_walls().wall((150, 40), (150, 260))
              .start(50, 50).build())
    course, s = _course(s0=30.0)
    s.world.arena = walled
    s.truth.pose = [100.0, 150.0, 0.0]
    got = course.from_here([(200.0, 150.0)])
    assert got[-1] == (200.0, 150.0) and len(got) > 1
    # the path goes round an end of the wall (y < 40 or y > 260)
    assert any(y < 40.0 or y > 260.0 for _, y in got[:-1])


def test_reached_is_level_with_the_checkpoint_coming_from_behind():
    course, s = _course(s0=30.0)
    s.go(50.0)
    assert course.reached(CPS[0]) is False   # never seen behind it since the course began
    s.go(25.0)
    course.laps()
    s.go(40.0)
    assert course.reached(CPS[0]) is False   # 10 cm behind it
    s.go(50.0)
    assert course.reached(CPS[0]) is True
    s.go(75.0)                               # 25 cm past it, within 30 cm: still
    assert course.reached(CPS[0]) is True
    course.set_off_for(CPS[0])               # forgotten: it has to come up behind it anew
    assert course.reached(CPS[0]) is False


def test_learned_waits_are_the_median_delay_of_the_links_that_are_transitions():
    course, s = _course()
    delays = {(1, 2): 2.0, (3, 4): 4.0, (5, 6): 9.0, (7, 8): 1.0, (9, 9): 5.0, (2, 2): 2.5}
    s.agent.cells = SimpleNamespace(transitions={(1, 2), (3, 4), (7, 8), (9, 9), (2, 2)},
                                    learned_delay=delays.__getitem__)
    s.agent.drives = _Drives(s.events, links={"a": [(1, 2), (3, 4), (5, 6)],
                                              "c": [(7, 8), (9, 9), (2, 2)]})
    course.agent = s.agent
    # a: (5, 6) is no transition: median(2, 4) = 3; b: no links; c: median(1, 5, 2.5) = 2.5
    got = course.learned_waits()
    assert got == [3.0, None, 2.5] and type(got[0]) is float


def test_a_detour_is_more_than_1_25_times_the_leg_and_10_cm():
    course, _ = _course()
    # legs: c0 -> c1 100 cm, c1 -> c2 200, c2 -> c0 100 (over the route's start), c1 -> c0 300
    for a, b, leg in ((0, 1, 100.0), (1, 2, 200.0), (2, 0, 100.0), (1, 0, 300.0)):
        limit = 1.25 * leg + 10.0
        assert course.detour(a, b, limit) is False
        assert course.detour(a, b, limit + 2**-20) is True
        assert course.detour(a, b, leg) is False


def test_drives_up_sets_every_drive_but_the_first_to_1():
    course, s = _course()
    course.drives_up()
    assert s.events == [("set_level", "b", 1.0), ("set_level", "c", 1.0)]


# --- the lesson


def test_teach_settles_leads_a_loop_lets_it_reproduce_and_teaches_each_checkpoint(bars):
    course, s = _course(s0=30.0)
    waits = [2.0, 3.0, 1.5]
    s.script = [
        [],                                           # settle: 3 s / 0.25 + 1 = 13 ticks
        [_leash_off, 55.0],                           # the leash ends (55: not reached)
        _walk(30.0, 530.0),                           # one lap (16 steps), 4 steps more
        # c0 (s = 50) from s = 30: reached at 50
        [40.0, 50.0, 75.0], [*LEFT, 60.0],
        # c1 (s = 150): not reached, the robot stops in a wait of its own
        [60.0, 70.0, _mode(Mode.WAIT)], [_noop, _mode(Mode.MOVE), 80.0], [*LEFT, 160.0],
        # c2 (s = 350) from where the leash left it (s = 150)
        [*_walk(150.0, 350.0), 375.0], LEFT,
        # c0 again, then c1 again (its lesson given once more)
        [*_walk(350.0, 450.0), 475.0], LEFT,
        _walk(50.0, 150.0), LEFT,
    ]
    assert course.teach(waits) == 1.0
    assert s.script == []
    ev = s.events
    runs = [e[1:] for e in ev if e[0] == "run"]
    C = PatrolPhase.CHECKPOINTS
    assert runs == [
        (13, None, None), (6000, None, None), (1600, PatrolPhase.REPRODUCTION, None),
        # c0: 20 cm ahead: (60 + 2 * 20 / 5) / 0.25 = 272; then 10 s = 40 ticks
        (272, C, 0), (40, C, 0),
        # c1: 100 cm ahead (from s = 50): (60 + 40) / 0.25 = 400; its own wait out:
        # 2 * 3 / 0.25 + 1 = 25
        (400, C, 1), (25, C, 1), (40, C, 1),
        # c2: 200 ahead (from 150): 140 / 0.25 = 560; c0: 100 ahead; c1: 100 ahead
        (560, C, 2), (40, C, 2), (400, C, 0), (40, C, 0), (400, C, 1), (40, C, 1)]
    assert ev[0] == ("lifted", {"moved": False})
    assert ev[2] == ("teacher.lead", [(200.0, 100.0), (200.0, 200.0), (100.0, 200.0),
                                      (100.0, 100.0), (200.0, 100.0)])
    assert ev[4] == ("step", 0.0)
    # the lead of c1 from s = 70: along the route to the waypoint nearest c1, then c1
    assert _kinds(s, "lead") == [("lead", [(200.0, 150.0)], 6000)]
    assert _kinds(s, "block") == [("block", w, 1.0) for w in (2.0, 3.0, 1.5, 2.0, 3.0)]
    assert _kinds(s, "reward") == [("reward", "a", True), ("reward", "b", False),
                                   ("reward", "c", True), ("reward", "a", True),
                                   ("reward", "b", True)]
    held = [e for e in ev if e[0] in ("inhibit", "release", "reward")]
    assert held == [x for n, r in (("a", True), ("b", False), ("c", True), ("a", True),
                                   ("b", True)) for x in (("inhibit", n), ("reward", n, r),
                                                          ("release", n))]
    assert bars == [[1, "leash", 1], [1, "reproduction", 1], [4, "checkpoints", 5]]
    assert s.phase == C and s.trial == 1


def test_teach_each_until_stops_its_run_where_it_should():
    course, s = _course(s0=30.0)
    s.script = [[], [_leash_off], _walk(30.0, 430.0), [40.0, 50.0], LEFT,
                [75.0], [_mode(Mode.MOVE)], LEFT,
                _walk(150.0, 350.0), LEFT, _walk(350.0, 450.0), LEFT]
    course.teach([2.0, 3.0, 1.5])
    u = s.untils
    assert u[0] is None
    s.teacher.leading = True
    assert u[1](None) is False
    s.teacher.leading = False
    assert u[1](None) is True
    # the run after a reward ends when the robot is in a state that is neither none nor a stop
    after = u[4]
    s.agent.state = None
    assert after(None) is False
    for kind, ends in ((StateKind.STILL, False), (StateKind.MOVING, True),
                       (StateKind.PLACE, True)):
        s.agent.kinds[99] = kind
        s.agent.state = 99
        assert after(None) is ends
    # a robot not in a wait of its own is led at once: no wait-out run
    assert [e[1] for e in s.events if e[0] == "run"][5:7] == [400, 40]
    # the wait-out run of a robot in a wait of its own when not there (the first test's c1)
    course, s = _course(s0=30.0)
    s.script = [[], [_leash_off], _walk(30.0, 430.0), [40.0, 50.0], LEFT,
                [_mode(Mode.WAIT)], [_mode(Mode.MOVE)], LEFT,
                _walk(150.0, 350.0), LEFT, _walk(350.0, 450.0), LEFT, _walk(50.0, 150.0), LEFT]
    course.teach([2.0, 3.0, 1.5])
    assert [e[1] for e in s.events if e[0] == "run"][5:8] == [400, 25, 40]
    wait_out = s.untils[6]
    s.agent.mode = Mode.WAIT
    assert wait_out(None) is False
    for mode in (Mode.EXPLORE, Mode.MOVE, Mode.APPROACH):
        s.agent.mode = mode
        assert wait_out(None) is True


def test_teach_on_a_tour_takes_a_detour_for_no_run_up_and_teaches_it_again(bars):
    course, s = _course(s0=30.0, tour=True)
    s.script = [[], [_leash_off], _walk(30.0, 430.0),
                [40.0, 50.0], LEFT, _walk(50.0, 150.0), LEFT, _walk(150.0, 350.0), LEFT,
                _walk(350.0, 450.0), LEFT, _walk(50.0, 150.0), LEFT]
    # runs measured since each reward: c0 -> c1 136 (leg 100: > 135, a detour), c1 -> c2
    # 260 (leg 200: exactly 260, not one), c2 -> c0 140 (leg 100: a detour, but c0's lesson
    # is not given again), c0 -> c1 500 (c1 is taught again: no detour test)
    s.ran = [136.0, 260.0, 140.0]
    course.teach([2.0, 3.0, 1.5])
    assert s.ran == []
    lengths = _kinds(s, "path_length")
    assert [e[2] for e in lengths] == [(150.0, 100.0), (200.0, 150.0), (100.0, 150.0)]
    # each from the log row of the reward before it (the rows the runs made up to then)
    assert lengths[0][1] == 1 + 16 + 2     # leash, reproduction, c0
    assert _kinds(s, "reward") == [("reward", "a", True), ("reward", "b", False),
                                   ("reward", "c", True), ("reward", "a", False),
                                   ("reward", "b", True)]
    assert _kinds(s, "lead") == []
    assert bars[-1] == [4, "checkpoints", 5]


def test_teach_the_first_lesson_is_never_a_detour_and_a_leash_lesson_comes_back_once():
    course, s = _course(s0=30.0, tour=True)
    # c0 needs the leash (not in a wait), c1 and c2 come by themselves; c0's lesson is not
    # given again (it is taught twice anyway); the last c0 is then a detour (ran 500)
    s.script = [[], [_leash_off], _walk(30.0, 430.0),
                [35.0], LEFT, _walk(50.0, 150.0), LEFT, _walk(150.0, 350.0), LEFT,
                _walk(350.0, 450.0), LEFT]
    s.ran = [100.0, 200.0, 500.0]
    course.teach([2.0, 3.0, 1.5])
    # from s = 35 the waypoint nearest c0 is (100, 100), the one nearest the robot: c0 alone
    assert _kinds(s, "lead") == [("lead", [(150.0, 100.0)], 6000)]
    assert _kinds(s, "reward") == [("reward", "a", False), ("reward", "b", True),
                                   ("reward", "c", True), ("reward", "a", False)]


def test_teach_on_a_long_route_gives_the_reproduction_three_times_its_length_at_5_cm_s():
    route = _square(300.0)   # 1200 cm: 3 * 1200 / 5 = 720 s > 400 s
    course, s = _course(s0=30.0, route=route, cps=[(150.0, 100.0)], names=["a"])
    s.script = [[], [_leash_off], [], [40.0, 50.0], LEFT]
    course.teach([4.0])
    # one checkpoint: taught twice, the second time from where it is (0 cm ahead: 60 s)
    assert [e[1] for e in s.events if e[0] == "run"] == [13, 6000, 2880, 272, 40, 240, 40]


# --- patrol, adaptation, kidnap


def test_patrol_runs_the_laps_from_the_quiet_point_and_counts_them(bars):
    course, s = _course(s0=150.0)
    s.script = [[*_walk(150.0, 650.0), 675.0], [*_walk(650.0, 1050.0), 1075.0]]
    assert course.patrol(2) == 2.0      # 2.25 laps run, at most the 2 asked for
    assert _kinds(s, "set_level") == [("set_level", "b", 1.0), ("set_level", "c", 1.0)]
    # the first lap ends at the quiet point after a whole loop: 0.25 + 1 laps from s = 150
    assert [e[1:] for e in s.events if e[0] == "run"] == [(2400, PatrolPhase.PATROL, 0),
                                                          (2400, PatrolPhase.PATROL, 1)]
    assert course.loop.turns == 2.25
    assert bars == [[2, "patrol", 2]]


def test_patrol_refuses_no_loops_and_warns_below_half_word_for_word():
    with pytest.raises(ValueError, match=r"^loops must be an integer >= 1, got 0$"):
        _course()[0].patrol(0)
    with pytest.raises(ValueError, match=r"^loops must be an integer, got 1.0 \(float\)$"):
        _course()[0].patrol(1.0)   # type: ignore[arg-type]
    tail = (": where a corridor lets the wall follower take either wall, the other side may "
            "hold (teach_patrol(..., side=...); the patrol tutorial's known limitation)")
    course, s = _course(s0=150.0)
    for step in _walk(150.0, 200.0):                   # 0.125 laps before the patrol
        s.go(step)
        course.laps()
    s.script = [_walk(200.0, 450.0)]                   # 0.625 of 2 loops (to 0.75 laps)
    with pytest.warns(P.PatrolWarning) as w:
        assert course.patrol(2) == 0.625
    assert [str(x.message) for x in w] == ["the robot completed 0.62 of 2 loops" + tail]
    course, s = _course(s0=150.0)                      # not moved at all: 0 laps, not backwards
    with pytest.warns(P.PatrolWarning) as w:
        assert course.patrol(2) == 0.0
    assert [str(x.message) for x in w] == ["the robot completed 0.00 of 2 loops" + tail]
    course, s = _course(s0=150.0)
    s.script = [_walk(150.0, 50.0, -25.0)]             # backwards
    with pytest.warns(P.PatrolWarning) as w:
        assert course.patrol(2) == -0.25
    assert [str(x.message) for x in w] == [
        "the robot completed -0.25 of 2 loops, round the route backwards" + tail]


def test_patrol_half_the_loops_is_enough_not_to_warn(recwarn):
    course, s = _course(s0=150.0)
    s.script = [_walk(150.0, 550.0)]                   # exactly 1 of 2 loops
    assert course.patrol(2) == 1.0
    course, s = _course(s0=150.0)
    s.script = [_walk(150.0, 350.0)]                   # exactly 0.5 of 1 loop
    assert course.patrol(1) == 0.5
    assert [w for w in recwarn if issubclass(w.category, P.PatrolWarning)] == []


class _Arena:
    def __init__(self, s: _Session) -> None:
        self.s = s

    def shortest_path(self, start: Any, goal: Any) -> tuple[float, list]:
        self.s.events.append(("shortest_path", tuple(start), tuple(goal)))
        return 50.0, [(200.0, 160.0), tuple(goal)]


def test_adapt_holds_the_robot_longer_at_c0_restarts_it_early_at_c1_and_runs_a_loop():
    course, s = _course(s0=5.0)
    s.script = [
        # to c0 (s = 50): 35 cm away at s = 15, 25 cm at s = 25 but not stopping, then about to
        [15.0, 25.0, _mode(Mode.APPROACH), 60.0],
        [_noop, _mode(Mode.WAIT), 65.0],              # let it stop
        # to c1 (s = 150): a stop 30 cm before it is not near; one 25 cm before it is
        [_state(StateKind.STILL), 90.0, 100.0, _state(StateKind.MOVING), 125.0,
         _state(StateKind.STILL), 130.0],
        [_noop] * 6,                                  # half its wait, 1.5 s
        _walk(180.0, 1005.0),                         # one loop and a bit
    ]
    longer, shorter, i_adapt, end = course.adapt([2.0, 3.0, 1.5], _Arena(s))
    assert (longer, shorter) == (10.0, 1.5)
    A = PatrolPhase.ADAPTATION
    runs = [e[1:] for e in s.events if e[0] == "run"]
    # 400 s, 20 s, 400 s, 1.5 s, and max(800, 4 * 400 / 5) = 800 s
    assert runs == [(1600, A, 0), (80, A, 0), (1600, A, 1), (6, A, 1), (3200, A, 2)]
    assert _kinds(s, "block") == [("block", 10.0, 10.0)]
    # led 30 cm on from c1 along the route: s = 180, (200, 180), by the arena's shortest path
    assert _kinds(s, "shortest_path") == [("shortest_path", (200.0, 125.0), (200.0, 180.0))]
    assert _kinds(s, "lead") == [("lead", [(200.0, 160.0), (200.0, 180.0)], 2000)]
    # to 10 cm past c1 (s = 160) from s = 180: 380 cm, then a whole loop: 780 cm, reached
    # at s = 980 (800 cm walked, 32 steps); the rows: 3 + 2 + 6 + 6 = 17, then 32
    assert (i_adapt, end) == (17, 17 + 32)
    assert s.script == [] and s.truth.pose[:2] == [200.0, 180.0]   # s = 980, not 1005


def test_adapt_at_c0_is_within_30_cm_and_there_stopped_or_stopping():
    course, s = _course(s0=5.0)
    s.script = [[], [], [], []]
    course.adapt([2.0, 3.0, 1.5], _Arena(s))
    at_c0, near_c1 = s.untils[0], s.untils[1]    # (not about to stop: no run between)
    course.loop.reset()
    agent = s.agent
    s.go(25.0)                                        # 25 cm before c0, moving
    assert at_c0(None) is False
    for mode in (Mode.APPROACH, Mode.WAIT):
        agent.mode = mode
        assert at_c0(None) is True
    agent.mode = Mode.MOVE
    agent.kinds[1] = StateKind.STILL
    agent.state = 1
    assert at_c0(None) is True                        # stopped there by itself
    agent.state = None
    s.go(20.0)                                        # 30 cm before it: not near
    agent.mode = Mode.WAIT
    assert at_c0(None) is False
    agent.mode = Mode.MOVE
    course.set_off_for(CPS[0])
    s.go(45.0)
    at_c0(None)
    s.go(50.0)                                        # level with it, come from behind
    assert at_c0(None) is True
    # c1: stopped within 30 cm of it, whatever the mode
    s.go(120.0)
    agent.state = 1
    assert near_c1(None) is False                     # 30 cm
    s.go(121.0)
    assert near_c1(None) is True
    agent.kinds[2] = StateKind.MOVING
    agent.state = 2
    assert near_c1(None) is False


def test_adapt_on_a_long_route_gives_the_loop_four_fifths_of_its_length_in_seconds():
    route = _square(300.0)   # 1200 cm: 4 * 1200 / 5 = 960 s > 800 s
    course, s = _course(s0=5.0, route=route, cps=[(150.0, 100.0), (400.0, 150.0)],
                        names=["a", "b"])
    course.adapt([4.0, 5.0], _Arena(s))
    assert [e[1] for e in s.events if e[0] == "run"] == [1600, 1600, 10, 3840]


def test_kidnap_puts_the_robot_75_cm_before_the_checkpoint_with_the_lowest_drive():
    course, s = _course(s0=300.0)
    agent = s.agent
    agent.drives.levels = {"a": 0.9, "b": 0.2, "c": 0.5}
    agent.brain.localiser = SimpleNamespace(time_to_localise=4.5)
    agent.wait_drive = 1
    course.laps()
    s.t = 100.0
    s.script = [[_noop, 140.0, _mode(Mode.WAIT), 145.0], []]
    levels, low, stop = course.kidnap()
    assert levels == {"a": 0.9, "b": 0.2, "c": 0.5} and low == "b"
    # c1 is at s = 150: 75 cm before it is s = 75, (175, 100), facing along the route (0)
    assert _kinds(s, "put") == [("put", (175.0, 100.0, 0.0), True)]
    assert (s.phase, s.trial) == (PatrolPhase.KIDNAP, 0)
    assert course.loop.progress is None               # searched afresh after the put
    # stopped after 3 ticks (0.75 s), 10 cm from c1 at (200, 140)
    assert stop == {"nearest_checkpoint": "b", "distance_cm": 10.0, "t_after_kidnap_s": 0.75,
                    "drive": "b"}
    assert course.relocalised_s == 4.5
    assert [e[1:] for e in s.events if e[0] == "run"] == [
        (1200, PatrolPhase.KIDNAP, 0), (20, PatrolPhase.KIDNAP, 0)]


def test_kidnap_a_robot_that_does_not_stop_and_the_drive_it_served():
    course, s = _course(s0=300.0)
    agent = s.agent
    agent.drives.levels = {"a": 0.3, "b": 0.3, "c": 0.5}   # a tie: the first name
    s.script = [[_noop, 45.0]]
    _levels, low, stop = course.kidnap()
    assert low == "a" and stop is None and course.relocalised_s is None
    assert _kinds(s, "put") == [("put", (100.0, 125.0, -math.pi / 2), True)]
    assert [e[1] for e in s.events if e[0] == "run"] == [1200]
    # stopped at c0 serving drive 0 (a), or serving none (-1)
    for served, drive in ((0, "a"), (-1, None), (2, "c")):
        course, s = _course(s0=300.0)
        s.agent.drives.levels = {"a": 0.3, "b": 0.1, "c": 0.5}
        s.agent.wait_drive = served
        s.script = [[_mode(Mode.WAIT)]]
        stop = course.kidnap()[2]
        assert stop is not None and stop["drive"] == drive
        # put at s = 75 (175, 100): c0 (150, 100) is the nearest, 25 cm
        assert (stop["nearest_checkpoint"], stop["distance_cm"]) == ("a", 25.0)


def test_teach_and_adapt_refuse_too_few_waits_before_any_run():
    # (they had failed with an IndexError: teach after the settle, the leash and the loop
    # reproduced, adapt after the run to c0)
    for waits in ([2.0, 3.0], [2.0, 3.0, 1.5, 4.0]):
        course, s = _course()
        with pytest.raises(ValueError, match=re.escape(
                f"waits must give one wait per checkpoint (3), got {len(waits)}") + "$"):
            course.teach(waits)
        assert s.events == []
    course, s = _course()
    with pytest.raises(ValueError, match=r"^adapt needs two checkpoints and their waits, got 3 "
                                         r"and 1$"):
        course.adapt([2.0], _Arena(s))
    course, s = _course(cps=[(150.0, 100.0)], names=["a"])
    with pytest.raises(ValueError, match=r"^adapt needs two checkpoints and their waits, got 1 "
                                         r"and 2$"):
        course.adapt([2.0, 3.0], _Arena(s))
    assert s.events == []
    # two of each is enough (a third wait is not read)
    course, s = _course(cps=CPS[:2], names=["a", "b"])
    assert course.adapt([2.0, 3.0, 9.0], _Arena(s))[:2] == (10.0, 1.5)
