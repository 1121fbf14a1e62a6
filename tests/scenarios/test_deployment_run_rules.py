"""The deployment scenario (:mod:`hippo.scenarios.deployment`) on stand-ins: its options on
their bounds and one past, --save with --resume refused word for word, the checkpoint's meta
field by field, one segment on a stand-in session (the stuck robot rescued 20 cm ahead, the
run to the quiet point, the tally asked for), the metrics and the growth after the first
hour, by hand."""

from __future__ import annotations

import argparse
import math
from types import SimpleNamespace
from typing import Any, ClassVar

import numpy as np
import pytest
from stand_ins import Refused, RefusingParser, recording_progress

import hippo.scenarios.deployment as D
from hippo.tasks.deployment import DeploymentParams
from hippo.tasks.patrol import PatrolPhase


def _parser() -> RefusingParser:
    p = RefusingParser(prog="deployment")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--quick", action="store_true")
    D.add_arguments(p)
    return p


# ------------------------------------------------------------------------------ the options
def test_the_options_defaults_and_bounds():
    a = _parser().parse_args([])
    assert (a.hours, a.segment_min, a.resume) == (8.0, 30.0, False)
    assert _parser().parse_args(["--resume"]).resume is True
    acts = {x.dest: x for x in _parser()._actions}
    hours, seg = acts["hours"].type, acts["segment_min"].type
    assert hours("0.1") == 0.1 and hours("1000") == 1000.0
    assert seg("5") == 5.0 and seg("600") == 600.0
    for f, bad in ((hours, "0.09"), (hours, "1000.01"), (seg, "4.99"), (seg, "600.01")):
        with pytest.raises(argparse.ArgumentTypeError):
            f(bad)
    assert D.Phase is PatrolPhase


def test_the_resume_help():
    acts = {x.dest: x for x in _parser()._actions}
    assert acts["resume"].help == ("continue from the last checkpoint in OUT/resume (a run that "
                                   "was killed); without it a run starts afresh")


def test_save_with_resume_is_refused_before_the_course_checks(monkeypatch):
    checked = []
    monkeypatch.setattr(D, "check_course_args", lambda a, p: checked.append(a))
    p = _parser()
    args = argparse.Namespace(resume=True, save="robot")
    with pytest.raises(Refused) as e:
        D.check_args(args, p)
    assert str(e.value) == ("argument --save: not allowed with --resume (a resumed run teaches "
                            "no robot to save); save with the run that teaches it")
    assert checked == []
    for ok in (argparse.Namespace(resume=True, save=None), argparse.Namespace(save="robot"),
               argparse.Namespace(resume=False, save="robot"), argparse.Namespace()):
        D.check_args(ok, p)
    assert len(checked) == 4


# ------------------------------------------------------------------------------ the meta
def _args(**kw: Any) -> argparse.Namespace:
    a = argparse.Namespace(seed=np.int64(4), arena="patrol-course",
                           checkpoints=[(80, 11), (140, 56)], waits=[10, 20.5],
                           place_cells="learned", explore_min=30, places=np.int64(40),
                           route="tour", heading_sectors=None, reanchor=0, segment_min=15,
                           quick=False, load=None, loaded=None)
    for k, v in kw.items():
        setattr(a, k, v)
    return a


def test_meta_field_by_field(monkeypatch):
    monkeypatch.setattr(D, "heading_sectors", lambda a: 6)
    m = D._meta(_args(), 2, np.int64(16))
    assert m == {"scenario": "deployment", "seed": 4, "arena": "patrol-course",
                 "checkpoints": [[80.0, 11.0], [140.0, 56.0]], "waits": [10.0, 20.5],
                 "place_cells": "learned", "explore_min": 30.0, "units": 16, "places": 40,
                 "route": "tour", "heading_sectors": 6, "reanchor": False, "hours": 2.0,
                 "segment_min": 15.0, "quick": False}
    for k in ("seed", "units", "places"):
        assert type(m[k]) is int
    for k in ("explore_min", "hours", "segment_min"):
        assert type(m[k]) is float
    assert type(m["checkpoints"][0][0]) is float and type(m["waits"][0]) is float
    a = _args(quick=True)
    del a.route
    m = D._meta(a, 0.5, 8)
    assert m["route"] == "auto" and m["quick"] is True
    assert D._meta(_args(reanchor=1), 1.0, 8)["reanchor"] is True


def test_checkpoint_holds_the_whole_run():
    s = SimpleNamespace(agent="agent", world="world", obs="obs")
    course = SimpleNamespace(loop="loop")
    assert D._checkpoint({"m": 1}, s, course, {"r": 2}) == {
        "meta": {"m": 1}, "agent": "agent", "world": "world", "obs": "obs", "loop": "loop",
        "run": {"r": 2}}


# ------------------------------------------------------------------------------ the metrics
def _seg(t1: float, states: int, *, tasks: int = 0, waits: Any = None, **kw: Any) -> dict:
    g = {"t0_h": 0.0, "t1_h": t1, "laps": 1.5, "stuck": 0, "tasks": tasks, "missed": 0,
         "misplaced": 0, "wait_off": 0, "extra_stops": 0,
         "waits_s": waits if waits is not None else [[], []],
         "health": {"states": states, "transitions": 2 * states}}
    g.update(kw)
    return g


def test_growth_after_the_first_hour():
    assert D._growth([], "states") is None
    assert D._growth([_seg(0.5, 3), _seg(0.99, 4)], "states") is None
    assert D._growth([_seg(0.5, 3), _seg(1.0, 4)], "states") is None     # one sample only
    assert D._growth([_seg(0.5, 3), _seg(1.0, 4), _seg(1.5, 9)], "states") == 5
    assert D._growth([_seg(1.0, 4), _seg(1.5, 9), _seg(2.0, 7)], "transitions") == 6
    assert type(D._growth([_seg(1.0, 4.0), _seg(1.5, 9.0)], "states")) is int


def test_metrics_by_hand():
    meta = {"waits": [10.0, 20.0], "seed": 1}
    h0 = {"states": 1, "transitions": 2}
    segs = [_seg(0.5, 3, tasks=4, missed=1, misplaced=2, waits=[[9.0, 11.0], [20.0]],
                 extra_stops=1),
            _seg(1.0, 5, tasks=6, wait_off=1, stuck=3, waits=[[10.0], []], laps=-0.25,
                 extra_stops=2)]
    state = {"segments": segs, "health0": h0, "reproduced": 0.1234567891234, "learned": [9, 21]}
    s = SimpleNamespace(t=3600.5)
    m = D._metrics(meta, state, s, 12.5)
    assert m["failures"] == {"missed": 1, "misplaced": 2, "wait_off": 1, "stuck": 3}
    assert m["seed"] == 1 and m["hours"] == 1.0 and m["tasks"] == 10
    assert m["failures_total"] == 7 and m["failures_per_hour"] == 7.0
    assert m["tasks_per_failure"] == 10 / 7
    assert m["success_rate"] == 1.0 - 2 / 10
    assert m["extra_stops"] == 3 and m["laps"] == 1.25
    assert m["reproduced_loop_fraction"] == 0.123456789
    assert m["learned_waits_s"] == [9, 21]
    assert m["waits_s"] == [{"mean": 10.0, "sd": math.sqrt(2 / 3), "n": 3},
                            {"mean": 20.0, "sd": 0.0, "n": 1}]
    assert m["health_start"] is h0 and m["health_end"] == segs[-1]["health"]
    assert m["states_growth_after_first_hour"] is None
    assert m["segments"] is segs and m["simulated_s"] == 3600.5 and m["wall_s"] == 12.5
    for k in ("tasks", "failures_total", "extra_stops"):
        assert type(m[k]) is int


def test_metrics_of_no_segment_and_of_no_failure():
    meta = {"waits": [10.0]}
    h0 = {"states": 1}
    m = D._metrics(meta, {"segments": [], "health0": h0, "reproduced": 1.0, "learned": [10]},
                   SimpleNamespace(t=0.0), 0.0)
    assert m["hours"] == 0.0 and m["tasks"] == 0 and m["failures_total"] == 0
    assert m["failures_per_hour"] is None and m["tasks_per_failure"] is None
    assert m["success_rate"] is None and m["health_end"] is h0
    assert m["waits_s"] == [{"mean": None, "sd": None, "n": 0}]
    assert m["laps"] == 0.0
    segs = [_seg(2.0, 3, tasks=5, waits=[[10.0]])]
    m = D._metrics(meta, {"segments": segs, "health0": h0, "reproduced": 1.0, "learned": [10]},
                   SimpleNamespace(t=0.0), 0.0)
    assert m["failures_per_hour"] == 0.0 and m["tasks_per_failure"] is None
    assert m["success_rate"] == 1.0


# ------------------------------------------------------------------------------ one segment
class _Loop:
    def __init__(self) -> None:
        self.travelled, self.turns, self.progress, self.resets = 0.0, 0.0, 40.0, 0

    def reset(self) -> None:
        self.resets += 1


class _Session:
    """A clock of 0.5 s ticks; the robot makes no progress until it is rescued, then 1 cm a
    tick; 1/64 of a lap a tick."""

    def __init__(self, course: Any, seen: dict) -> None:
        self.t, self.course, self.seen = 100.0, course, seen
        self.world = SimpleNamespace(dt=0.5, robot=SimpleNamespace(moving_threshold=0.5))
        self.agent = "agent"
        self.runs: list[int] = []

    def run(self, n: int, until: Any) -> None:
        self.runs.append(n)
        for _ in range(n):
            self.t += self.world.dt
            if self.course.loop.resets:
                self.course.loop.travelled += 1.0
            self.course.loop.turns += 1 / 64
            if until(SimpleNamespace(t=self.t)):
                return

    def put(self, x: float, y: float, heading: float, event: str, keep_drives: bool) -> None:
        self.seen.setdefault("put", []).append((x, y, heading, event, keep_drives, self.t))


def test_one_segment_on_stand_ins(monkeypatch):
    seen: dict[str, Any] = {}
    loop = _Loop()
    route = SimpleNamespace(at=lambda p: (p, 2 * p, 0.5))
    course = SimpleNamespace(loop=loop, route=route, names=["a", "b", "c"],
                             checkpoints=[(1.0, 2.0)], lap_s=50.0)
    laps_calls = []

    def laps() -> float:
        laps_calls.append(loop.turns)
        return loop.turns

    course.laps = laps
    course.laps_to_quiet = lambda k: loop.turns + 0.25

    def tally(arrays, r, cps, learned, threshold, phase, tolerance):
        seen["tally"] = (r is route, cps, learned, threshold, phase, tolerance)
        return {"tasks": 3, "missed": 1, "rel_errors": [0.5], "waits_s": [[1.0]]}

    monkeypatch.setattr(D, "tally_failures", tally)
    monkeypatch.setattr(D, "health", lambda agent, t: {"agent": agent, "t": t})
    monkeypatch.setattr(D, "Log", lambda n_drives: SimpleNamespace(
        n=n_drives, arrays=lambda: "arrays"))
    s = _Session(course, seen)
    state = {"segments": [{}, {}], "t_start": 100.0 - 1800.0, "learned": [7.0]}
    p = DeploymentParams(stuck_s=180.0, stuck_cm=10.0)
    seg = D._segment(s, course, state, p, t_stop=100.0 + 300.0)
    assert s.log.n == 3
    assert (s.phase, s.trial) == (PatrolPhase.DEPLOYMENT, 2)
    # no progress: stuck 180 s after the start (t = 280), put 20 cm ahead of progress 40
    assert seen["put"] == [(60.0, 120.0, 0.5, "rescue", True, 280.0)]
    assert loop.resets == 1
    # the first run: (400 - 100) / 0.5 + 1 ticks, ended at t = 400 (600 ticks, 9.375 laps);
    # the second a lap's 50 / 0.5 ticks at most, ended at the quiet point a quarter lap (16
    # ticks of 1/64, 8 s) on
    assert s.runs == [601, 100]
    assert s.t == 408.0
    assert seg["t0_h"] == 0.5 and seg["t1_h"] == (408.0 - state["t_start"]) / 3600.0
    assert seg["laps"] == 616 / 64
    assert seg["stuck"] == 1
    assert seg["tasks"] == 3 and seg["missed"] == 1 and seg["waits_s"] == [[1.0]]
    assert "rel_errors" not in seg
    assert seg["health"] == {"agent": "agent", "t": 408.0 - state["t_start"]}
    assert seen["tally"] == (True, [(1.0, 2.0)], [7.0], 0.5, PatrolPhase.DEPLOYMENT, 0.05)


def test_rescue_puts_the_robot_20_cm_ahead():
    seen: dict[str, Any] = {}
    loop = _Loop()
    loop.progress = None
    counted = []
    course = SimpleNamespace(loop=loop, route=SimpleNamespace(at=lambda p: (p, -p, 1.25)),
                             laps=lambda: counted.append(1))
    s = _Session(course, seen)
    D._rescue(s, course)
    assert seen["put"] == [(20.0, -20.0, 1.25, "rescue", True, 100.0)]
    assert loop.resets == 1 and counted == [1]


# ------------------------------------------------------------------------------ run
class _Ckpt:
    """Checkpoints in memory: ``stored`` is what load() gives."""

    stored: Any = None
    log: ClassVar[list[Any]] = []
    walls: ClassVar[list[float]] = []

    def __init__(self, folder: Any) -> None:
        self.folder = folder
        _Ckpt.log.append(("open", folder))

    def load(self, kind: Any) -> Any:
        _Ckpt.log.append(("load", kind))
        return _Ckpt.stored

    def clear(self) -> None:
        _Ckpt.log.append(("clear",))

    def save(self, state: dict) -> None:
        _Ckpt.log.append(("save", len(state["run"]["segments"]), state["meta"]["hours"]))
        _Ckpt.walls.append(state["run"]["wall_s"])

    def latest(self) -> str:
        return "ckpt-7"


def _deploy(monkeypatch, tmp_path, argv: list[str], *, overrun: float = 10.0,
            stored: Any = None, drop: tuple[str, ...] = ()) -> tuple[dict, dict]:
    seen: dict[str, Any] = {"stops": [], "order": []}
    _Ckpt.stored, _Ckpt.log, _Ckpt.walls = stored, [], []
    world = SimpleNamespace(detach=lambda t: seen["order"].append(("detach", t)))
    s = SimpleNamespace(world=world, teacher="teacher", t=1000.0, agent="agent", obs="o",
                        save=lambda out, phase: seen.update(saved=(out, phase)))
    course = SimpleNamespace(drives_up=lambda: seen["order"].append("drives_up"),
                             laps=lambda: seen["order"].append("laps"),
                             learned_waits=lambda: [10.0, 20.0], loop="loop0")
    lesson = SimpleNamespace(session=s, course=course, reproduced=0.75)

    def teach(args, seed, units):
        seen["order"].append(("teach", seed, units))
        return lesson

    def segment(s_, course_, state, p, t_stop):
        seen["stops"].append(t_stop - 1000.0)
        assert p == DeploymentParams()
        t0 = s_.t
        s_.t = t_stop + overrun
        k = len(state["segments"])
        return {"t0_h": (t0 - state["t_start"]) / 3600, "t1_h": (s_.t - state["t_start"]) / 3600,
                "laps": 1.0, "stuck": 0, "tasks": 2, "missed": k, "misplaced": 0,
                "wait_off": 0, "extra_stops": 0, "waits_s": [[10.0], [20.0]],
                "health": {"states": 5 + k, "transitions": 9, "rss_mb": 100.0 + k}}

    monkeypatch.setattr(D, "Checkpoints", _Ckpt)
    monkeypatch.setattr(D, "teach_patrol", teach)
    monkeypatch.setattr(D, "_segment", segment)
    monkeypatch.setattr(D, "health", lambda agent, t: {"states": 4, "transitions": 8,
                                                       "rss_mb": 90.0, "t": t})
    monkeypatch.setattr(D, "heading_sectors", lambda a: 4)
    monkeypatch.setattr(D, "save_figure", lambda fig, path: seen.update(
        figure=(fig, path.name)))
    import hippo.plots.deployment as plots_deployment

    monkeypatch.setattr(plots_deployment, "plot_deployment",
                        lambda segs: (("fig", len(segs)), None))
    clock = iter(range(10_000))
    monkeypatch.setattr(D, "time", SimpleNamespace(perf_counter=lambda: float(next(clock))))

    monkeypatch.setattr(D, "Progress", recording_progress(seen))
    seen["session"], seen["course"] = s, course
    p = _parser()
    args = p.parse_args(["--arena", "patrol-course", *argv])
    args.out = str(tmp_path / "out")
    if args.checkpoints is None:
        args.checkpoints = [(80.0, 11.0), (140.0, 56.0)]
        args.waits = [10.0, 20.0]
    args.loaded = None
    for name in drop:
        delattr(args, name)
    return D.run(args), seen


def test_run_teaches_then_patrols_in_segments(monkeypatch, tmp_path, capsys):
    m, seen = _deploy(monkeypatch, tmp_path, ["--hours", "1", "--segment-min", "25",
                                              "--seed", "3"])
    assert seen["order"][:4] == [("teach", 3, 24), ("detach", "teacher"), "drives_up", "laps"]
    # segments of 1500 s: to 1500, then from 1510 to 3010, then to the end at 3600
    assert seen["stops"] == [1500.0, 3010.0, 3600.0]
    assert _Ckpt.log[0] == ("open", tmp_path / "out" / "resume")
    assert [e for e in _Ckpt.log if e[0] in ("load", "clear", "save")] == [
        ("clear",), ("save", 0, 1.0), ("save", 1, 1.0), ("save", 2, 1.0), ("save", 3, 1.0),
        ("clear",)]
    assert seen["saved"] == (tmp_path / "out", PatrolPhase)
    assert seen["figure"] == (("fig", 3), "deployment.png")
    assert seen["progress"] == [3, "deployment", 0, 1, 1, 1]
    # one clock tick a call: the lesson's 1 s, then 1 s a segment; the metrics' at 6 s
    assert _Ckpt.walls == [1.0, 3.0, 4.0, 5.0] and m["wall_s"] == 6.0
    assert (tmp_path / "out" / "segments.json").exists()
    assert m["tasks"] == 6 and m["failures"]["missed"] == 3 and m["hours"] == 3610 / 3600
    assert m["learned_waits_s"] == [10.0, 20.0] and m["reproduced_loop_fraction"] == 0.75
    assert m["health_start"] == {"states": 4, "transitions": 8, "rss_mb": 90.0, "t": 0.0}
    assert m["scenario"] == "deployment" and m["seed"] == 3 and m["hours"] > 1.0
    assert m["simulated_s"] == 4610.0
    err = capsys.readouterr().err
    assert ("deployment (patrol-course, learned place cells): 1.0 h, 6 checkpoint passes, "
            "3 failures (missed 3, misplaced 0, wait_off 0, stuck 0); states 4 -> 7, memory "
            "90 -> 102 MB") in err


def test_run_stops_after_its_segment_count(monkeypatch, tmp_path):
    # segments ending 100 s short: hours 1 in 30-minute segments is 2 segments, not more
    _, seen = _deploy(monkeypatch, tmp_path, ["--hours", "1", "--segment-min", "30"],
                      overrun=-100.0)
    assert seen["stops"] == [1800.0, 3500.0]
    _, seen = _deploy(monkeypatch, tmp_path, ["--hours", "0.5", "--segment-min", "10"],
                      overrun=0.0)
    assert seen["stops"] == [600.0, 1200.0, 1800.0]


def test_run_quick_caps_the_hours_and_units(monkeypatch, tmp_path):
    m, seen = _deploy(monkeypatch, tmp_path, ["--quick", "--hours", "2", "--segment-min", "15",
                                              "--units", "20"])
    assert seen["order"][0] == ("teach", 0, 16)
    assert seen["stops"] == [900.0, 1800.0]
    assert m["hours"] == 1810 / 3600 and m["units"] == 16 and m["quick"] is True
    m, seen = _deploy(monkeypatch, tmp_path, ["--quick", "--hours", "0.25", "--units", "8"])
    assert seen["order"][0] == ("teach", 0, 8) and seen["stops"] == [900.0]


def test_run_resume_without_a_checkpoint_starts_afresh(monkeypatch, tmp_path, capsys):
    _, seen = _deploy(monkeypatch, tmp_path, ["--hours", "0.5", "--resume"])
    assert _Ckpt.log[1] == ("load", dict)
    assert seen["order"][0] == ("teach", 0, 24)
    assert (f"--resume: no checkpoint in {tmp_path / 'out' / 'resume'}; starting afresh"
            in capsys.readouterr().err)


def test_run_resume_refuses_other_options(monkeypatch, tmp_path):
    meta = D._meta(argparse.Namespace(
        seed=0, arena="patrol-course", checkpoints=[(80.0, 11.0), (140.0, 56.0)],
        waits=[10.0, 20.0], place_cells="learned", explore_min=30.0, places=40, route="auto",
        heading_sectors=None, reanchor=False, segment_min=30.0, quick=False, loaded=None),
        2.0, 24)
    with pytest.raises(SystemExit) as e:
        _deploy(monkeypatch, tmp_path, ["--hours", "1", "--resume"],
                stored={"meta": dict(meta, heading_sectors=4, units=12)})
    assert str(e.value) == (
        f"--resume: the checkpoint in {tmp_path / 'out' / 'resume'} was made with other "
        "options (hours: 2.0 there, 1.0 now; units: 12 there, 24 now); give the same options, "
        "or leave out --resume to start afresh")
    with pytest.raises(SystemExit, match=r"options \(arena: None there, 'patrol-course' now; "):
        _deploy(monkeypatch, tmp_path, ["--hours", "1", "--resume"], stored={"meta": {}})


def test_run_resumes_from_its_checkpoint(monkeypatch, tmp_path, capsys):
    made: dict[str, Any] = {}
    world = SimpleNamespace(detach=lambda t: made.setdefault("detached", t))

    class _Session:
        def __init__(self, w, agent, log, obs):
            self.world, self.agent, self.log, self.obs = w, agent, log, obs
            self.teacher, self.t = "teacher2", 1000.0 + 1800.0
            made["session"] = self

        def save(self, out, phase):
            made["saved"] = phase

    class _Course:
        def __init__(self, s, loop, cps, names):
            made["course"] = (loop, cps, names)

    monkeypatch.setattr(D, "Session", _Session)
    monkeypatch.setattr(D, "Log", lambda n_drives: ("log", n_drives))
    monkeypatch.setattr(D, "PatrolCourse", _Course)
    monkeypatch.setattr(D, "led_route", lambda arena, cps, route, side: (
        made.setdefault("route", (arena, route, side)), "the-loop"))
    meta = None
    stored: dict[str, Any] = {}

    def capture_meta(*a):
        nonlocal meta
        meta = orig_meta(*a)
        return meta

    orig_meta = D._meta
    monkeypatch.setattr(D, "_meta", capture_meta)
    first_seg = {"t0_h": 0.0, "t1_h": 0.5, "laps": 2.0, "stuck": 0, "tasks": 1, "missed": 1,
                 "misplaced": 0, "wait_off": 0, "extra_stops": 0, "waits_s": [[], []],
                 "health": {"states": 5, "transitions": 9, "rss_mb": 100.0}}

    class _Lazy(dict):
        def get(self, k, d=None):     # the meta is known only once run() has made it
            return meta if k == "meta" else super().get(k, d)

    stored = _Lazy(world=world, obs="obs",
                   agent=SimpleNamespace(params=SimpleNamespace(
                       motor=SimpleNamespace(wall_side=-1))),
                   loop="saved-loop",
                   run={"learned": [10.0, 20.0], "reproduced": 0.5, "t_start": 1000.0,
                        "segments": [first_seg], "health0": {"states": 4, "rss_mb": 90.0},
                        "wall_s": 40.0})
    stored["meta"] = None
    m, seen = _deploy(monkeypatch, tmp_path, ["--hours", "1", "--resume"], stored=stored)
    assert made["detached"] == "teacher2"
    assert made["route"] == ("patrol-course", "auto", -1)
    assert made["course"] == ("the-loop", [(80.0, 11.0), (140.0, 56.0)],
                              ["checkpoint-1", "checkpoint-2"])
    assert made["session"].log == ("log", 2) and made["session"].obs == "obs"
    assert seen["order"] == []          # nothing taught
    # one segment left: from 0.5 h to the end at 1 h
    assert seen["stops"] == [3600.0]
    assert m["tasks"] == 3 and m["wall_s"] >= 40.0
    assert ("resuming from ckpt-7 (1 segments done, 0.50 of 1 h)"
            in capsys.readouterr().out)


def test_run_of_a_program_without_the_options(monkeypatch, tmp_path, capsys):
    _, seen = _deploy(monkeypatch, tmp_path, ["--hours", "0.5"], drop=("resume",))
    assert seen["order"][0] == ("teach", 0, 24)
    assert [e[0] for e in _Ckpt.log[:2]] == ["open", "clear"]
    assert "--resume" not in capsys.readouterr().err
    asked = []

    def check(a, parser):
        asked.append(parser.prog)
        raise SystemExit("checked")

    monkeypatch.setattr(D, "check_args", check)
    for missing in ("checkpoints", "waits"):
        with pytest.raises(SystemExit, match="checked"):
            a = _parser().parse_args(["--arena", "patrol-course"])
            a.checkpoints, a.waits = [(80.0, 11.0), (140.0, 56.0)], [10.0, 20.0]
            setattr(a, missing, None)
            a.out = str(tmp_path / "out")
            D.run(a)
    assert asked == ["hippo run deployment"] * 2
    # with both given (the command line's checks ran) they are not checked again
    _deploy(monkeypatch, tmp_path, ["--hours", "0.5"])
    assert asked == ["hippo run deployment"] * 2
