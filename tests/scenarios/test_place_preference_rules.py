"""The place-preference scenario's helpers (:mod:`hippo.scenarios.place_preference`) on
stand-ins: its options (defaults, each bound and one past), check_args with and without --load
(every refusal word for word, what a loaded robot fixes), the saved robot's checks (scenario,
agent and world, the meta's fields on their edges), saving with the teacher detached, the
extinction's patience, the summary of how extinction stops ended, and the learned reward
delay, all by hand."""

from __future__ import annotations

import argparse
import math
from types import SimpleNamespace
from typing import Any

import pytest
from stand_ins import Refused, RefusingParser, recording_progress

import hippo.scenarios.place_preference as PP
from hippo.agent import Agent
from hippo.io import CorruptFileError
from hippo.sim import World


def _parser() -> RefusingParser:
    p = RefusingParser(prog="place-preference")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--quick", action="store_true")
    PP.add_arguments(p)
    return p


def _refusal(fn: Any, *args: Any) -> str:
    with pytest.raises(Refused) as e:
        fn(*args)
    return str(e.value)


# ------------------------------------------------------------------------------ the options
def test_the_options_defaults():
    a = _parser().parse_args([])
    assert (a.delay, a.explore_min, a.explore_rho, a.teach, a.trials, a.extinction) == (
        7.0, 40.0, 0.0, 3, 12, 4)
    assert (a.units, a.places, a.trial_timeout, a.start_facing) == (24, 32, 240.0, "explored")
    assert (a.place_cells, a.reanchor, a.save, a.load) == ("learned", False, None, None)
    assert {x.dest: x for x in _parser()._actions}["start_facing"].choices == ["explored",
                                                                               "kept"]


@pytest.mark.parametrize("dest, ok, bad", [
    ("delay", ("0.2", "100"), ("0.19", "100.01")),
    ("explore_min", ("5", "600"), ("4.99", "600.01")),
    ("explore_rho", ("0", "1"), ("-0.01", "1.01")),
    ("teach", ("1", "100"), ("0", "101")),
    ("trials", ("1", "1000"), ("0", "1001")),
    ("extinction", ("0", "1000"), ("-1", "1001")),
    ("units", ("1", "200"), ("0", "201")),
    ("places", ("1", "256"), ("0", "257")),
    ("trial_timeout", ("10", "3600"), ("9.99", "3600.01")),
])
def test_each_bound_taken_and_one_past_refused(dest, ok, bad):
    f = {x.dest: x for x in _parser()._actions}[dest].type
    assert [float(f(v)) for v in ok] == [float(v) for v in ok]
    for v in bad:
        with pytest.raises(argparse.ArgumentTypeError):
            f(v)


# ------------------------------------------------------------------------------ check_args
def test_check_args_without_load():
    p = _parser()
    a = p.parse_args([])
    a.loaded = "stale"
    PP.check_args(a, p)
    assert a.loaded is None
    a = p.parse_args(["--place-cells", "ground-truth", "--units", "7"])
    assert _refusal(PP.check_args, a, p) == ("argument --units: only for learned place cells; "
                                             "leave it out with --place-cells ground-truth")


def _loaded(place_cells: str = "learned", **meta: Any) -> dict:
    m = {"seed": 3, "place_cells": place_cells, "explore_min": 40.0, "explore_rho": 0.0,
         "quick": False}
    m.update(meta)
    return {"meta": m, "agent": SimpleNamespace(places=SimpleNamespace(relocaliser=None))}


def test_check_args_with_load(monkeypatch, tmp_path):
    (tmp_path / "manifest.json").write_text("{}")
    p = _parser()
    robot = _loaded()
    monkeypatch.setattr(PP, "_load_robot", lambda folder: robot)
    a = p.parse_args(["--load", str(tmp_path)])
    PP.check_args(a, p)
    assert a.loaded is robot
    a = p.parse_args(["--load", str(tmp_path), "--seed", "3", "--explore-min", "40"])
    PP.check_args(a, p)
    a = p.parse_args(["--load", str(tmp_path), "--save", str(tmp_path / "s")])
    assert _refusal(PP.check_args, a, p) == ("argument --save: not allowed with --load (the "
                                             "loaded robot is already saved)")
    a = p.parse_args(["--load", str(tmp_path), "--seed", "4"])
    assert _refusal(PP.check_args, a, p) == ("argument --seed: the loaded robot was made with "
                                             "seed 3; leave --seed out with --load")
    a = p.parse_args(["--load", str(tmp_path), "--explore-rho", "0.5"])
    assert "argument --explore-rho: the loaded robot was made with explore_rho 0.0" in (
        _refusal(PP.check_args, a, p))
    a = p.parse_args(["--load", str(tmp_path), "--reanchor"])
    assert "argument --reanchor: the loaded robot was made with reanchor False" in (
        _refusal(PP.check_args, a, p))
    a = p.parse_args(["--load", str(tmp_path), "--teach", "4"])
    assert _refusal(PP.check_args, a, p) == ("argument --teach: the loaded robot was taught "
                                             "already; leave --teach out with --load")
    a = p.parse_args(["--load", str(tmp_path), "--teach", "3"])
    PP.check_args(a, p)
    # a ground-truth robot: the learned cells' options are refused as given without --load
    robot = _loaded("ground-truth")
    a = p.parse_args(["--load", str(tmp_path), "--places", "10"])
    assert _refusal(PP.check_args, a, p) == ("argument --places: only for learned place cells; "
                                             "leave it out with --place-cells ground-truth")


@pytest.mark.parametrize("error", [CorruptFileError("bad  file\n here"), ValueError("bad  file"),
                                   TypeError("bad\tfile")])
def test_check_args_names_an_unreadable_snapshot(monkeypatch, tmp_path, error):
    def load(folder):
        raise error

    monkeypatch.setattr(PP, "_load_robot", load)
    (tmp_path / "manifest.json").write_text("{}")
    p = _parser()
    a = p.parse_args(["--load", str(tmp_path)])
    msg = _refusal(PP.check_args, a, p)
    assert msg.startswith(f"argument --load: {tmp_path}: bad file")
    assert "  " not in msg and "\n" not in msg and "\t" not in msg


# ------------------------------------------------------------------------------ the snapshot
GOOD = {"seed": 4, "place_cells": "learned", "explore_min": 40.0, "explore_rho": 0.0,
        "quick": False}


def _state(**kw: Any) -> dict:
    s = {"scenario": "place-preference", "agent": object.__new__(Agent),
         "world": object.__new__(World), "meta": dict(GOOD)}
    s.update(kw)
    return s


def _load(monkeypatch, state: dict) -> dict:
    asked = []

    def load_snapshot(folder, kind):
        asked.append((folder, kind))
        return state

    monkeypatch.setattr(PP, "load_snapshot", load_snapshot)
    out = PP._load_robot("robot")
    assert asked == [("robot", dict)]
    return out


def _load_error(monkeypatch, state: dict) -> str:
    with pytest.raises(ValueError) as e:
        _load(monkeypatch, state)
    return str(e.value)


def test_load_robot_checks_what_the_snapshot_holds(monkeypatch):
    s = _state()
    assert _load(monkeypatch, s) is s
    assert _load_error(monkeypatch, _state(scenario="patrol")) == (
        "a snapshot of 'patrol', not of place-preference")
    st = _state()
    del st["scenario"]
    assert _load_error(monkeypatch, st) == "a snapshot of None, not of place-preference"
    for bad in (_state(agent=None), _state(world="w"), _state(agent=object.__new__(World))):
        assert _load_error(monkeypatch, bad) == "the snapshot holds no agent and world"
    want = ("the snapshot's meta must hold seed, place_cells, explore_min, explore_rho, quick")
    assert _load_error(monkeypatch, _state(meta=None)) == want
    assert _load_error(monkeypatch, _state(meta=[1])) == want
    for k in GOOD:
        meta = dict(GOOD)
        del meta[k]
        assert _load_error(monkeypatch, _state(meta=meta)) == want
    assert "explore_min" in _load_error(monkeypatch, _state(meta={**GOOD, "explore_min": 4.9}))


@pytest.mark.parametrize("key, good, bad", [
    ("seed", (0, 2**32 - 1), (-1, 2**32, 1.5, "1")),
    ("place_cells", ("learned", "ground-truth"), ("bogus", None)),
    ("explore_min", (5.0, 600.0, 30), (math.nextafter(5.0, 0.0), math.nextafter(600.0, 1e9),
                                       math.nan, "30")),
    ("explore_rho", (0.0, 1.0, 0.5), (-5e-324, math.nextafter(1.0, 2.0), math.inf)),
    ("quick", (True, False), (1, 0, "True", None)),
])
def test_check_meta_edges(key, good, bad):
    for v in good:
        PP._check_meta({**GOOD, key: v})
    for v in bad:
        with pytest.raises(ValueError, match=key):
            PP._check_meta({**GOOD, key: v})


def test_save_robot_detaches_the_teacher_while_writing(monkeypatch, tmp_path):
    events: list[Any] = []
    teacher = object()
    world = SimpleNamespace(detach=lambda t: events.append(("detach", t)),
                            attach=lambda t: events.append(("attach", t)))
    s = SimpleNamespace(teacher=teacher, world=world, agent="agent", obs="obs")

    def save(state, folder):
        events.append(("save", state, folder))

    monkeypatch.setattr(PP, "save_snapshot", save)
    PP._save_robot(tmp_path, s, {"seed": 1})
    assert events == [("detach", teacher),
                      ("save", {"scenario": "place-preference", "meta": {"seed": 1},
                                "agent": "agent", "world": world, "obs": "obs"}, tmp_path),
                      ("attach", teacher)]
    events.clear()

    def fail(state, folder):
        raise OSError("disk full")

    monkeypatch.setattr(PP, "save_snapshot", fail)
    with pytest.raises(OSError, match="disk full"):
        PP._save_robot(tmp_path, s, {})
    assert events == [("detach", teacher), ("attach", teacher)]


# ------------------------------------------------------------------------------ the numbers
def test_extinction_patience_three_delays_at_least_a_minute():
    assert PP.extinction_patience(7.0) == 60.0
    assert PP.extinction_patience(20.0) == 60.0
    assert PP.extinction_patience(21.0) == 63.0
    assert PP.extinction_patience(100) == 300.0 and type(PP.extinction_patience(100)) is float


def test_gave_up_summary_every_branch():
    assert PP._gave_up_summary([], 0, 60.0) == " (no stop)"
    assert PP._gave_up_summary([1.0, 2.5], 0, 60.0) == " and moved on 1.8 s after the learned delay"
    assert PP._gave_up_summary([], 2, 63.5) == " and never moved on in 2 (still after 63.5 s)"
    assert PP._gave_up_summary([-1.0], 1, 60.0) == (
        " and moved on -1.0 s after the learned delay; never moved on in 1 (still after 60 s)")


class _Layer:
    def __init__(self, kinds: dict[int, str], sound: int | None) -> None:
        self.kinds, self.sound = kinds, sound

    def find(self, name: str) -> int:
        assert name == "sound"
        if self.sound is None:
            raise ValueError("no state sound")
        return self.sound

    def key(self, i: int) -> Any:
        return SimpleNamespace(kind=self.kinds[i])


def _agent(delays: dict[tuple[int, int], float], sound: int | None = 9) -> Any:
    kinds = {1: "still", 2: "still", 3: "place", 4: "still", 9: "sound"}
    cells = SimpleNamespace(transitions=list(delays), learned_delay=lambda k: delays[k])
    return SimpleNamespace(layer=_Layer(kinds, sound), cells=cells)


def test_learned_reward_delay():
    assert PP._learned_reward_delay(_agent({(1, 9): 7.0}, sound=None)) is None
    assert PP._learned_reward_delay(_agent({})) is None
    assert PP._learned_reward_delay(_agent({(3, 9): 5.0})) is None        # not from a stop
    assert PP._learned_reward_delay(_agent({(1, 4): 5.0})) is None        # not to the sound
    assert PP._learned_reward_delay(_agent({(1, 9): math.nan})) is None   # not learned
    assert PP._learned_reward_delay(_agent({(1, 9): 7.0, (2, 9): 8.0, (4, 9): 12.0,
                                            (3, 9): 100.0, (1, 4): 100.0,
                                            (2, 4): math.nan})) == 8.0
    got = PP._learned_reward_delay(_agent({(1, 9): 7.0, (2, 9): 8.0, (4, 9): math.nan}))
    assert got == 7.5 and type(got) is float


def test_run_refuses_a_delay_that_is_not_positive_and_finite(tmp_path):
    for bad in (0.0, -1.0, math.nan, math.inf):
        args = argparse.Namespace(out=str(tmp_path / "out"), seed=0, delay=bad)
        with pytest.raises(SystemExit) as e:
            PP.run(args)
        assert str(e.value) == f"--delay must be a positive number of seconds, got {bad}"
    # refused before the output folder is prepared: the last run's metrics.json is kept
    assert not (tmp_path / "out").exists()
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "metrics.json").write_text("{}")
    with pytest.raises(SystemExit):
        PP.run(argparse.Namespace(out=str(tmp_path / "out"), seed=0, delay=-1.0))
    assert (tmp_path / "out" / "metrics.json").read_text() == "{}"


# ------------------------------------------------------------------------------ run
def _o(t: float, floor: int = 0, *, still: float | None = None, sound: bool = False,
       moving: bool = True) -> Any:
    return SimpleNamespace(t=t, floor=floor, still=still, sound=sound, moving=moving)


#: per trial the observations the stand-in session gives, in order
SCRIPTS = [
    # rewarded, south: in the zone at 11, still from 12, the sound at 19
    [_o(10.0), _o(11.0, 1), _o(12.0, 1, still=12.0, moving=False),
     _o(19.0, 1, still=12.0, sound=True, moving=False), _o(20.0)],
    # rewarded, east: never in the zone (the timeout ends it)
    [_o(20.0), _o(21.0)],
    # extinction, north: still 32-40 (a stop of 1 s before it), moves out at 41
    [_o(31.0, 1), _o(31.5, 1, still=31.5, moving=False), _o(32.0, 1),
     _o(32.5, 1, still=32.5, moving=False), _o(40.5, 1, still=32.5, moving=False),
     _o(40.7, 1, moving=True), _o(41.0, 0, moving=True), _o(45.0)],
    # extinction, west: still from 52, past the 60 s patience at 112.5
    [_o(51.0, 1), _o(52.0, 1, still=52.0, moving=False),
     _o(112.0, 1, still=52.0, moving=False), _o(112.5, 1, still=52.0, moving=False),
     _o(113.0, 1, still=52.0, moving=False)],
    # extinction, south: a stop of 1.5 s only, then out (no stop counted)
    [_o(60.0, 1, still=60.0, moving=False), _o(61.5, 0), _o(62.0, 0)],
    # extinction, east: a stop of 2 s exactly (counted), then out
    [_o(70.0, 1, still=70.0, moving=False), _o(72.0, 1, still=70.0, moving=False),
     _o(72.25, 0), _o(73.0, 0)],
]


class _Exp:
    def __init__(self) -> None:
        self.still_since: float | None = None
        self.sounded = False
        self.resets: list[bool] = []

    def reset(self, rewarding: bool = True) -> None:
        self.resets.append(rewarding)
        self.still_since, self.sounded = None, False

    def __call__(self, o: Any) -> bool:
        self.still_since = o.still
        self.sounded = self.sounded or o.sound
        return o.sound


class _PPSession:
    def __init__(self, seen: dict) -> None:
        self.seen = seen
        self.world = SimpleNamespace(dt=0.25, step=lambda action: seen["steps"].append(action)
                                     or _o(-1.0))
        levels = {"sound": 0.8}
        self.agent = SimpleNamespace(
            places=SimpleNamespace(n_units=9, relocaliser=None),
            drives=SimpleNamespace(level=lambda n: levels[n],
                                   set_level=lambda n, v: seen["levels"].append((n, v))),
            layer=SimpleNamespace(n_states=11), graph=[1, 2])
        self.truth = SimpleNamespace(pose=(1.0, 2.0, 0.75))
        self.rows = 0
        self.log = self
        self.teacher = "teacher"

    def __len__(self) -> int:
        return self.rows

    def path_length(self, i0: int, origin: tuple, until_t: float) -> float:
        self.seen["paths"].append((i0, origin, until_t))
        return 150.0

    def put(self, x: float, y: float, heading: float, event: str) -> None:
        self.seen["puts"].append((x, y, heading, event))

    def run(self, n: int, until: Any = None) -> Any:
        self.seen["runs"].append(n)
        self.rows += 10
        if until is None:
            return _o(999.0)
        o = None
        for o in SCRIPTS[self.trial % len(SCRIPTS)]:
            if until(o):
                break
        return o

    def save(self, out: Any, phase: Any) -> dict:
        self.seen["saved"] = phase
        return {"arrays": 1}


def _pp_run(monkeypatch, tmp_path, argv: list[str], loaded: dict | None = None
            ) -> tuple[dict, dict]:
    seen: dict[str, Any] = {"steps": [], "levels": [], "paths": [], "puts": [], "runs": []}
    s, exp = _PPSession(seen), _Exp()
    seen["exp"] = exp
    arena = SimpleNamespace(
        zones=[SimpleNamespace(rect=(0, 0, 10, 10))],
        landmarks={"start-south": (1.0, 1.0), "start-east": (2.0, 2.0),
                   "start-north": (3.0, 3.0), "start-west": (4.0, 4.0)},
        geodesic_distance=lambda p, zone: {(1.0, 1.0): 100.0, (2.0, 2.0): 50.0,
                                           (3.0, 3.0): 0.0, (4.0, 4.0): 80.0}[tuple(p)])
    monkeypatch.setattr(PP.arenas, "goal_arena", lambda: arena)

    def learn(args, arena_, seed, explore_min, n_teach, units):
        assert arena_ is arena
        seen["learn"] = (seed, explore_min, n_teach, units)
        return s, exp, 12.5

    monkeypatch.setattr(PP, "_learn", learn)
    monkeypatch.setattr(PP, "_learned_reward_delay", lambda agent: (agent is s.agent) * 7.5)
    clock = iter(range(10, 10_000))
    monkeypatch.setattr(PP, "time", SimpleNamespace(perf_counter=lambda: float(next(clock))))

    monkeypatch.setattr(PP, "Progress", recording_progress(seen))
    if loaded is not None:
        def session(world, agent, log, obs):
            seen["session"] = (world, agent, obs)
            return s

        monkeypatch.setattr(PP, "Session", session)
        monkeypatch.setattr(PP, "Experimenter", lambda teacher, delay: seen.update(
            exp=(teacher, delay)) or exp)
    import hippo.plots.agent as plots_agent

    monkeypatch.setattr(plots_agent, "plot_place_preference",
                        lambda out, a, agent, arrays, results, delay: seen.update(
                            plot=(len(results), delay)))
    args = _parser().parse_args(argv)
    args.out = str(tmp_path / "out")
    args.loaded = loaded
    if loaded is not None:
        args.load = tmp_path / "robot"
    return PP.run(args), seen


def test_run_on_a_stand_in_session(monkeypatch, tmp_path, capsys):
    m, seen = _pp_run(monkeypatch, tmp_path, ["--trials", "2", "--extinction", "3",
                                              "--seed", "5"])
    assert seen["learn"] == (5, 40.0, 3, 24)
    hd = PP.START_HEADINGS
    assert seen["puts"] == [(1.0, 1.0, hd["south"], "trial_start"),
                            (2.0, 2.0, hd["east"], "trial_start"),
                            (3.0, 3.0, hd["north"], "trial_start"),
                            (4.0, 4.0, hd["west"], "trial_start"),
                            (1.0, 1.0, hd["south"], "trial_start")]
    assert seen["levels"] == [("sound", 0.8)] * 5
    assert seen["exp"].resets == [True, True, False, False, False]
    assert seen["steps"] == [(0.0, 0.0)] * 5
    # each trial's timeout 240 s / 0.25, then 20 s / 0.25 of exploring
    assert seen["runs"] == [960, 80] * 5
    trials = m["trials"]
    assert trials[0] == {"rewarded": True, "start": [1.0, 1.0], "shortest_cm": 100.0,
                         "entered_t": 11.0, "still_t": 12.0, "path_cm": 150.0,
                         "success": True, "wait_s": 7.0}
    # the log's rows before each trial: 20 a trial (the stand-in's 10 a run)
    assert seen["paths"] == [(0, (1.0, 1.0), 11.0), (40, (3.0, 3.0), 31.0),
                             (60, (4.0, 4.0), 51.0), (80, (1.0, 1.0), 60.0)]
    assert trials[1] == {"rewarded": True, "start": [2.0, 2.0], "shortest_cm": 50.0,
                         "success": False}
    # the longest stop, 32.5 to 40.5, plus the tick that ended it
    assert trials[2] == {"rewarded": False, "start": [3.0, 3.0], "shortest_cm": 0.0,
                         "entered_t": 31.0, "still_t": 32.5, "still_s": 8.25,
                         "path_cm": 150.0, "gave_up": True, "resume_t": 40.75}
    assert trials[3] == {"rewarded": False, "start": [4.0, 4.0], "shortest_cm": 80.0,
                         "entered_t": 51.0, "still_t": 52.0, "still_s": 60.75,
                         "path_cm": 150.0, "gave_up": False}
    assert trials[4] == {"rewarded": False, "start": [1.0, 1.0], "shortest_cm": 100.0,
                         "entered_t": 60.0, "still_t": 60.0, "path_cm": 150.0}
    assert m["place_cells"] == "learned" and m["seed"] == 5 and m["delay_s"] == 7.0
    assert m["loaded_from"] is None and m["start_facing"] == "explored"
    assert m["quick"] is False and m["explore_min"] == 40.0 and m["place_units"] == 9
    assert m["reanchor"] is False
    assert (m["rewarded_trials"], m["rewarded_successes"], m["waits_s"]) == (2, 1, [7.0])
    assert m["learned_delay_s"] == 7.5
    assert (m["extinction_trials"], m["extinction_stops"]) == (3, 2)
    assert m["extinction_still_s"] == [8.25, 60.75]
    assert m["extinction_resume_delays_s"] == [8.25 - 7.5]
    assert m["extinction_never_gave_up"] == 1 and m["extinction_patience_s"] == 60.0
    assert m["path_length_ratio"] == 1.5 and m["path_length_ratios"] == [1.5]
    assert (m["states"], m["transitions"], m["simulated_s"]) == (11, 2, 999.0)
    # the clock: t0 at 10, the wall time read at 11
    assert m["fit_s"] == 12.5 and m["wall_s"] == 1.0 and m["realtime_factor"] == 999.0
    assert seen["progress"] == [5, "trials", 1, 1, 1, 1, 1]
    assert seen["plot"] == (5, 7.0) and seen["saved"] is PP.Phase
    err = capsys.readouterr().err
    assert ("place preference (learned place cells): 1 of 2 rewarded trials reached the goal, "
            "stopped and waited for the sound; extinction: stopped in 2 of 3 trials and moved "
            "on 0.8 s after the learned delay; never moved on in 1 (still after 60 s); path "
            "1.50 x the shortest") in err


def test_run_quick_and_kept_heading(monkeypatch, tmp_path):
    m, seen = _pp_run(monkeypatch, tmp_path, ["--quick", "--trials", "5", "--extinction", "3",
                                              "--teach", "3", "--units", "20",
                                              "--start-facing", "kept", "--explore-min", "30"])
    assert seen["learn"] == (0, 20.0, 2, 16)
    assert [p[2] for p in seen["puts"]] == [0.75] * 6
    assert (m["rewarded_trials"], m["extinction_trials"]) == (4, 2)
    assert m["quick"] is True and m["explore_min"] == 20.0
    m, seen = _pp_run(monkeypatch, tmp_path, ["--quick", "--trials", "3", "--extinction", "1",
                                              "--teach", "1", "--units", "15",
                                              "--explore-min", "10"])
    assert seen["learn"] == (0, 10.0, 1, 15)
    assert (m["rewarded_trials"], m["extinction_trials"]) == (3, 1)


# ------------------------------------------------------------------------------ _learn
def test_learn_on_stand_ins(monkeypatch, tmp_path):
    seen: dict[str, Any] = {"runs": [], "teacher": []}
    world = SimpleNamespace(dt=0.25, sensors="sensors", robot="robot")
    tour = SimpleNamespace(sensors="tour-sensors", moving="tour-moving")
    tour_last = "last-obs"

    class _Tour(list):
        sensors, moving = tour.sensors, tour.moving

    the_tour = _Tour([None, tour_last])

    def make_world(arena, sensors, seed):
        seen["world"] = (arena, sensors, seed)
        return world

    def explore(w, n, rho, seed, log):
        seen["explore"] = (w is world, n, rho, seed)
        return the_tour

    def make_places(kind, arena, sensors, units, seed, places, moving):
        seen["places"] = (kind, arena, sensors, units, seed, places, moving)
        return "places"

    class _Agent:
        def __init__(self, places, drives, params, sensors, robot, seed):
            seen["agent"] = (places, drives, params, sensors, robot, seed)

    class _Teacher:
        leading = False

        def lead(self, path):
            seen["teacher"].append(("lead", path))

        def block(self, s):
            seen["teacher"].append(("block", s))

    class _S:
        def __init__(self, w, agent, log, obs):
            seen["session"] = (w is world, obs)
            self.teacher, self.truth = _Teacher(), SimpleNamespace(pose=(5.0, 6.0, 1.0))
            self.phase = self.trial = None

        def run(self, n, until=None):
            seen["runs"].append((n, self.phase, self.trial))
            if n == 480:                                  # until the robot is out of the zone
                assert until(SimpleNamespace(floor=0)) and not until(SimpleNamespace(floor=1))
            if n == 3000:                                 # until the teacher stops leading
                assert until(None)

    arena = SimpleNamespace(landmarks={"goal": (9.0, 9.0)},
                            shortest_path=lambda a, b: (1.0, [tuple(a), b]))
    monkeypatch.setattr(PP, "World", make_world)
    monkeypatch.setattr(PP, "explore", explore)
    monkeypatch.setattr(PP, "make_places", make_places)
    monkeypatch.setattr(PP, "Agent", _Agent)
    monkeypatch.setattr(PP, "learn_map", lambda agent, t: seen.update(mapped=t is the_tour))
    monkeypatch.setattr(PP, "Session", _S)
    monkeypatch.setattr(PP, "Experimenter", lambda teacher, delay: SimpleNamespace(
        delay=delay, reset=lambda: seen["teacher"].append(("reset",))))
    monkeypatch.setattr(PP, "_save_robot", lambda folder, s, meta: seen.update(
        saved=(folder, meta)))
    args = _parser().parse_args(["--delay", "3", "--explore-rho", "0.25", "--places", "12",
                                 "--reanchor", "--save", str(tmp_path / "robot"), "--quick"])
    _, exp, fit_s = PP._learn(args, arena, 4, 10.0, 2, 8)
    assert seen["world"] == (arena, "ir8", 4)
    assert seen["explore"] == (True, 2400, 0.25, 4)       # 10 min of 0.25 s ticks
    assert seen["places"] == ("learned", arena, "tour-sensors", 8, 4, 12, "tour-moving")
    places, drives, params, sensors, robot, seed = seen["agent"]
    assert (places, sensors, robot, seed) == ("places", "sensors", "robot", 4)
    assert list(drives) == ["sound"]
    assert (drives["sound"].epsilon, drives["sound"].learning_rate) == (0.02, 0.5)
    assert params.states == PP.PLACE_STATES and params.explore_rho == 0.25
    assert params.relocalise == PP.LocaliserParams()
    assert (params.planner.w, params.planner.noise, params.planner.exploration_threshold) == (
        0.9, 0.01, 0.3)
    assert seen["mapped"] is True and seen["session"] == (True, "last-obs")
    assert exp.delay == 3.0 and fit_s >= 0.0
    T = PP.Phase.TEACHING
    # per guided trial: out of the zone (120 s), the leash, the block's 5 s + 5 ticks, 30 s
    assert seen["runs"] == [(480, T, 0), (3000, T, 0), (25, T, 0), (120, T, 0),
                            (480, T, 1), (3000, T, 1), (25, T, 1), (120, T, 1)]
    assert seen["teacher"] == [("lead", [(5.0, 6.0), (9.0, 9.0)]), ("reset",), ("block", 5.0),
                               ("lead", [(5.0, 6.0), (9.0, 9.0)]), ("reset",), ("block", 5.0)]
    assert seen["saved"] == (tmp_path / "robot", {"seed": 4, "place_cells": "learned",
                                                  "explore_min": 10.0, "explore_rho": 0.25,
                                                  "quick": True})
    seen.pop("saved")
    args = _parser().parse_args(["--place-cells", "ground-truth"])
    PP._learn(args, arena, 1, 5.0, 1, 24)
    assert seen["places"] == ("ground-truth", arena, "tour-sensors", 24, 1, 32, None)
    assert "saved" not in seen


def test_run_on_a_loaded_robot(monkeypatch, tmp_path):
    loaded = {"world": "w", "agent": "a", "obs": "o",
              "meta": {"seed": 9, "place_cells": "ground-truth", "explore_min": 33.0,
                       "explore_rho": 0.0, "quick": True}}
    m, seen = _pp_run(monkeypatch, tmp_path, ["--trials", "1", "--extinction", "0",
                                              "--delay", "0.5"], loaded=loaded)
    assert "learn" not in seen
    assert seen["session"] == ("w", "a", "o") and seen["exp"] == ("teacher", 0.5)
    assert m["seed"] == 9 and m["place_cells"] == "ground-truth" and m["explore_min"] == 33.0
    assert m["fit_s"] == 0.0 and m["loaded_from"] == str(tmp_path / "robot")
    assert m["quick"] is True and m["delay_s"] == 0.5
    assert m["extinction_patience_s"] == 60.0


def test_the_options_help():
    acts = {x.dest: x for x in _parser()._actions}
    assert acts["units"].help == "ICA units of the place cells"
    assert acts["places"].help == "place prototypes read out from the ICA units (learned cells)"
    assert acts["explore_rho"].help == "side-switch probability of the exploring wall follower"
    assert acts["start_facing"].help == (
        "trials start facing along the corridor in the direction the robot explored (its "
        "place cells are direction-specific), or with the heading it had when picked up")
    assert acts["load"].help == (
        "skip exploration, map learning and teaching: run the trials on a robot written with "
        "--save (its seed, place cells and exploration come from the snapshot)")


def test_check_args_with_load_reads_the_units_of_learned_cells(monkeypatch, tmp_path):
    (tmp_path / "manifest.json").write_text("{}")
    robot = _loaded()
    robot["agent"].places.model = SimpleNamespace(params=SimpleNamespace(n_ica=20))
    robot["agent"].places.n_units = 30
    monkeypatch.setattr(PP, "_load_robot", lambda folder: robot)
    p = _parser()
    PP.check_args(p.parse_args(["--load", str(tmp_path), "--units", "20", "--places", "30"]), p)
    a = p.parse_args(["--load", str(tmp_path), "--units", "16"])
    assert _refusal(PP.check_args, a, p) == ("argument --units: the loaded robot was made with "
                                             "units 20; leave --units out with --load")
    a = p.parse_args(["--load", str(tmp_path), "--places", "31"])
    assert _refusal(PP.check_args, a, p) == ("argument --places: the loaded robot was made with "
                                             "places 30; leave --places out with --load")


def test_an_extinction_stop_of_two_seconds_exactly_counts(monkeypatch, tmp_path):
    m, _ = _pp_run(monkeypatch, tmp_path, ["--trials", "1", "--extinction", "5"])
    assert m["trials"][5] == {"rewarded": False, "start": [2.0, 2.0], "shortest_cm": 50.0,
                              "entered_t": 70.0, "still_t": 70.0, "still_s": 2.25,
                              "path_cm": 150.0, "gave_up": True, "resume_t": 72.25}
    assert m["extinction_stops"] == 3
