"""The patrol scenarios' lesson helpers (:mod:`hippo.scenarios._patrol_lesson`) on stand-ins:
the course's options (defaults, each bound exactly and one past), the heading sectors'
default, check_course_args with and without --load (its defaults, which option a course's
refusal names, every --load refusal word for word, what a loaded robot fixes), the JSON form
of an option, the saved lesson's checks field by field on its edges, saving (the teacher
detached while writing, the meta field by field) and teaching or loading on stand-ins of the
expensive parts."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
from stand_ins import Refused, RefusingParser

import hippo.scenarios._patrol_lesson as P
from hippo.agent import Agent
from hippo.sim import World
from hippo.tasks.lesson import Lesson
from hippo.tasks.patrol import PatrolPhase

CPS = [(80.0, 11.0), (140.0, 56.0), (50.0, 105.0)]   # patrol-course's own


def _parser() -> RefusingParser:
    p = RefusingParser(prog="patrol")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--quick", action="store_true")
    P.add_course_arguments(p)
    return p


def _refusal(fn: Any, *args: Any) -> str:
    with pytest.raises(Refused) as e:
        fn(*args)
    return str(e.value)


# ------------------------------------------------------------------------------ the options
def test_the_course_options_defaults():
    a = _parser().parse_args([])
    assert vars(a) == {"seed": 0, "quick": False, "arena": None, "checkpoints": None,
                       "waits": None, "route": "auto", "place_cells": "learned",
                       "reanchor": False, "explore_min": 30.0, "units": 24, "places": 40,
                       "heading_sectors": None, "save": None, "load": None}


def test_the_course_options_on_their_bounds_and_one_past():
    p = _parser()
    a = p.parse_args(["--arena", "maze", "--checkpoints", "1,2;3,4", "--waits", "2,120",
                      "--route", "tour", "--explore-min", "5", "--units", "200",
                      "--places", "256", "--heading-sectors", "16"])
    assert (a.arena, a.checkpoints, a.waits, a.route) == ("maze", [(1.0, 2.0), (3.0, 4.0)],
                                                          [2.0, 120.0], "tour")
    assert (a.explore_min, a.units, a.places, a.heading_sectors) == (5.0, 200, 256, 16)
    a = p.parse_args(["--checkpoints", "1,2;3,4;5,6;7,8", "--waits", "2,3,4,5",
                      "--explore-min", "600", "--units", "1", "--places", "1",
                      "--heading-sectors", "1"])
    assert len(a.checkpoints) == 4 and a.waits == [2.0, 3.0, 4.0, 5.0]
    assert (a.explore_min, a.units, a.places, a.heading_sectors) == (600.0, 1, 1, 1)
    refused = {
        ("--checkpoints", "1,2"): "got '1,2'; needs 2 to 4 points 'x,y' separated by ';' (cm)",
        ("--checkpoints", "1,2;3,4;5,6;7,8;9,9"):
            "got '1,2;3,4;5,6;7,8;9,9'; needs 2 to 4 points 'x,y' separated by ';' (cm)",
        ("--waits", "1.99,3"): "got '1.99,3'; needs 2 to 4 comma-separated numbers in "
                               "[2, 120] (s)",
        ("--waits", "3,120.01"): "got '3,120.01'; needs 2 to 4 comma-separated numbers in "
                                 "[2, 120] (s)",
        ("--waits", "3"): "got '3'; needs 2 to 4 comma-separated numbers in [2, 120] (s)",
        ("--explore-min", "4.99"): "got '4.99'; needs a number in [5, 600]",
        ("--explore-min", "600.01"): "got '600.01'; needs a number in [5, 600]",
        ("--units", "0"): "got 0; needs an integer in [1, 200]",
        ("--units", "201"): "got 201; needs an integer in [1, 200]",
        ("--places", "0"): "got 0; needs an integer in [1, 256]",
        ("--places", "257"): "got 257; needs an integer in [1, 256]",
        ("--heading-sectors", "0"): "got 0; needs an integer in [1, 16]",
        ("--heading-sectors", "17"): "got 17; needs an integer in [1, 16]",
    }
    for (opt, value), why in refused.items():
        assert _refusal(p.parse_args, [opt, value]) == f"argument {opt}: {why}"
    file = Path(__file__)
    assert _refusal(p.parse_args, ["--save", str(file)]) == (
        f"argument --save: {str(file)!r} is a file, not a folder")
    assert _refusal(p.parse_args, ["--save", ""]) == (
        "argument --save: got an empty path; name a folder ('.': the current one)")
    assert _refusal(p.parse_args, ["--load", str(file.parent)]) == (
        f"argument --load: {str(file.parent)!r} holds no saved robot (no manifest.json; write "
        "one with --save)")
    assert _refusal(p.parse_args, ["--arena", "moon"]).startswith(
        "argument --arena: invalid choice: 'moon' (choose from ")
    assert _refusal(p.parse_args, ["--route", "back"]).startswith(
        "argument --route: invalid choice: 'back'")


def test_the_course_options_help_in_their_words():
    helps = {a.dest: a.help for a in _parser()._actions}
    assert helps["arena"] == "the world to patrol (default: patrol-course)"
    assert helps["checkpoints"] == (
        "2 to 4 checkpoints 'x,y;x,y;...' in cm, patrolled in this order (on a wall tour: in "
        "the order the tour meets them, from the first) (default: the arena's own, see "
        "ARENA_CHECKPOINTS)")
    assert helps["waits"] == ("one wait per checkpoint in s, comma-separated (default: "
                              "HIREL's 24.1,19.1,11.6 (and 16 for a fourth))")
    assert helps["route"] == (
        "the leash route: the arena's shortest paths through the checkpoints, the loop the "
        "exploring wall follower runs round the arena (tour), or auto: the shortest paths "
        "where they make a loop a wall tour runs the same way round without running back over "
        "themselves, else the tour where it passes every checkpoint")
    assert helps["explore_min"] == "exploration, simulated minutes"
    assert helps["units"] == "ICA units of the place cells"
    assert helps["places"] == "place prototypes read out from the ICA units (learned cells)"
    assert helps["heading_sectors"] == (
        "split each place state by the direction of travel into this many sectors (the "
        "heading from path integration; 1: no split; default 4 with learned place cells, 1 "
        "with ground truth, whose fields do not alias)")
    assert helps["save"] == ("write the taught robot (after exploration and the lesson) into "
                             "this folder as a hippo snapshot")
    assert helps["load"] == (
        "skip exploration and the lesson: start from a robot written with --save (its seed, "
        "arena, checkpoints, waits and place cells come from the snapshot)")


def test_the_heading_sectors_default_by_place_cells():
    ns = SimpleNamespace
    assert P.heading_sectors(ns(heading_sectors=3, place_cells="ground-truth")) == 3
    assert P.heading_sectors(ns(heading_sectors=1)) == 1
    assert type(P.heading_sectors(ns(heading_sectors=np.int64(2)))) is int
    assert P.heading_sectors(ns(heading_sectors=None, place_cells="learned")) == 4
    assert P.heading_sectors(ns()) == 4                        # learned by default
    assert P.heading_sectors(ns(heading_sectors=None, place_cells="ground-truth")) == 1


# ------------------------------------------------------------------ check_course_args, no load
def _checked(monkeypatch: pytest.MonkeyPatch, argv: list[str], fail: str | None = None
             ) -> tuple[argparse.Namespace, list[tuple[Any, ...]]]:
    calls: list[tuple[Any, ...]] = []

    def check_patrol(*a: Any) -> None:
        calls.append(a)
        if fail:
            raise ValueError(fail)

    monkeypatch.setattr(P, "check_patrol", check_patrol)
    p = _parser()
    args = p.parse_args(argv)
    P.check_course_args(args, p)
    return args, calls


def test_the_course_defaults_to_the_arenas_checkpoints_and_hirels_waits(monkeypatch):
    args, calls = _checked(monkeypatch, [])
    assert calls == [("patrol-course", CPS, [24.1, 19.1, 11.6], "auto")]
    assert args.arena == "patrol-course" and args.checkpoints == CPS and args.loaded is None
    assert args.waits == [24.1, 19.1, 11.6]
    args, calls = _checked(monkeypatch, ["--arena", "maze", "--route", "tour"])
    assert calls == [("maze", [(20.0, 20.0), (140.0, 140.0), (220.0, 60.0)],
                      [24.1, 19.1, 11.6], "tour")]
    args, calls = _checked(monkeypatch, ["--checkpoints", "1,2;3,4;5,6;7,8"])
    assert args.waits == [24.1, 19.1, 11.6, 16.0]
    args, calls = _checked(monkeypatch, ["--checkpoints", "1,2;3,4", "--waits", "9,8"])
    assert calls == [("patrol-course", [(1.0, 2.0), (3.0, 4.0)], [9.0, 8.0], "auto")]
    assert args.checkpoints == [(1.0, 2.0), (3.0, 4.0)] and args.waits == [9.0, 8.0]
    args, calls = _checked(monkeypatch, ["--checkpoints", "1,2;3,4"])
    assert args.waits == [24.1, 19.1]


def test_a_course_refusal_names_the_option_it_is_about(monkeypatch):
    for why, opt in (("got 2 waits for 3 checkpoints; give one wait per checkpoint", "--waits"),
                     ("waits must be numbers of seconds, got None", "--waits"),
                     ("wait(s) 1 s: a checkpoint's wait must be at least 2 s", "--waits"),
                     ("checkpoint (1, 2) is not free floor of arena 'maze'", "--checkpoints"),
                     ("two checkpoints are 12 cm apart along the route; they need 40 cm "
                      "(a pass is 15 cm either side)", "--checkpoints"),
                     # only the words before " for " decide
                     ("no room for a wait at checkpoint 2", "--checkpoints")):
        with pytest.raises(Refused) as e:
            _checked(monkeypatch, [], fail=why)
        assert str(e.value) == f"argument {opt}: {why}"


def test_a_wait_too_short_given_by_a_program_is_refused_as_waits():
    # the command line keeps waits in [2, 120]; a program's args reach check_patrol itself
    p = _parser()
    args = p.parse_args([])
    args.waits = [24.1, 1.5, 11.6]
    assert _refusal(P.check_course_args, args, p) == (
        "argument --waits: wait(s) 1.5 s: a checkpoint's wait must be at least 2 s (a shorter "
        "stop is not reproduced)")


def test_ground_truth_cells_refuse_the_learned_cells_options(monkeypatch):
    with pytest.raises(Refused) as e:
        _checked(monkeypatch, ["--place-cells", "ground-truth", "--units", "7"])
    assert str(e.value) == ("argument --units: only for learned place cells; leave it out with "
                            "--place-cells ground-truth")


# --------------------------------------------------------------------- check_course_args, load
def _meta(**changes: Any) -> dict[str, Any]:
    meta = {"seed": 3, "arena": "patrol-course", "checkpoints": [list(c) for c in CPS],
            "waits": [24.1, 19.1, 11.6], "place_cells": "learned", "explore_min": 30.0,
            "units": 24, "places": 40, "route": "tour", "reproduced": 1.0,
            "taught_stops": [24.8, None, 12.0]}
    meta.update(changes)
    return meta


def _loaded(meta: dict[str, Any], sectors: int = 4) -> dict[str, Any]:
    agent = SimpleNamespace(places=SimpleNamespace(), p=SimpleNamespace(heading_sectors=sectors))
    return {"meta": meta, "agent": agent, "world": "the world", "obs": "obs", "loop": "loop"}


def _load(monkeypatch: pytest.MonkeyPatch, tmp_path: Any, argv: list[str],
          loaded: Any) -> tuple[argparse.Namespace, list[Any]]:
    folder = tmp_path / "robot"
    folder.mkdir(exist_ok=True)
    (folder / "manifest.json").write_text("{}")
    seen: list[Any] = []

    def load_lesson(path: Any) -> Any:
        seen.append(path)
        if isinstance(loaded, Exception):
            raise loaded
        return loaded

    monkeypatch.setattr(P, "load_lesson", load_lesson)
    monkeypatch.setattr(P, "check_patrol", lambda *a: pytest.fail("checked again"))
    p = _parser()
    args = p.parse_args(["--load", str(folder), *argv])
    P.check_course_args(args, p)
    return args, seen


def test_a_loaded_robot_fixes_the_course_and_its_options(monkeypatch, tmp_path):
    loaded = _loaded(_meta())
    args, seen = _load(monkeypatch, tmp_path, [], loaded)
    assert seen == [tmp_path / "robot"] and args.loaded is loaded
    assert (args.seed, args.arena, args.waits, args.place_cells, args.explore_min, args.units,
            args.places) == (3, "patrol-course", [24.1, 19.1, 11.6], "learned", 30.0, 24, 40)
    assert args.checkpoints == CPS and all(type(c) is tuple for c in args.checkpoints)
    assert args.route == "tour" and args.reanchor is False and args.heading_sectors == 4
    old = _meta()
    del old["route"]
    args, _ = _load(monkeypatch, tmp_path, ["--heading-sectors", "2"], _loaded(old, 2))
    assert args.route == "shortest" and args.heading_sectors == 2
    # the same values typed again are no conflict (tuples and ints against JSON lists)
    args, _ = _load(monkeypatch, tmp_path, ["--arena", "patrol-course", "--checkpoints",
                                            "80,11;140,56;50,105", "--waits", "24.1,19.1,11.6",
                                            "--seed", "3"], loaded)
    assert args.seed == 3


def test_a_programs_args_without_the_optional_options(monkeypatch, tmp_path):
    # a Namespace built by a program may lack --load, --save, --arena, --checkpoints,
    # --route and --heading-sectors: read as not given
    calls: list[Any] = []
    monkeypatch.setattr(P, "check_patrol", lambda *a: calls.append(a))
    p = _parser()
    args = argparse.Namespace(place_cells="learned")
    P.check_course_args(args, p)
    assert calls == [("patrol-course", CPS, [24.1, 19.1, 11.6], "auto")]
    assert args.waits == [24.1, 19.1, 11.6]
    loaded = _loaded(_meta())
    monkeypatch.setattr(P, "load_lesson", lambda path: loaded)
    args = p.parse_args(["--route", "tour"])
    args.load = tmp_path
    for key in ("save", "arena", "checkpoints", "waits", "heading_sectors"):
        delattr(args, key)
    P.check_course_args(args, p)
    assert args.loaded is loaded and args.seed == 3 and args.heading_sectors == 4
    assert args.checkpoints == CPS and args.route == "tour"


def test_a_loaded_robots_place_cells_say_their_units_and_reanchoring(monkeypatch, tmp_path):
    # learned cells: the ICA units and prototypes fitted, not the meta's; a relocaliser:
    # re-anchoring on
    loaded = _loaded(_meta(units=40))          # a snapshot before 2026-11-27: prototypes
    loaded["agent"].places = SimpleNamespace(
        model=SimpleNamespace(params=SimpleNamespace(n_ica=np.int64(16))), n_units=40,
        relocaliser=object())
    args, _ = _load(monkeypatch, tmp_path, [], loaded)
    assert (args.units, args.places, args.reanchor) == (16, 40, True)
    assert type(args.units) is int
    with pytest.raises(Refused) as e:
        _load(monkeypatch, tmp_path, ["--units", "40"], loaded)
    assert str(e.value) == ("argument --units: the loaded robot was made with units 16; leave "
                            "--units out with --load")


def test_the_load_refusals_word_for_word(monkeypatch, tmp_path):
    loaded = _loaded(_meta())
    d = tmp_path / "robot"
    cases = [
        (["--save", str(tmp_path / "s")], loaded,
         "argument --save: not allowed with --load (the loaded robot is already saved)"),
        ([], ValueError("the snapshot's meta must hold\n   seed,  arena"),
         f"argument --load: {d}: the snapshot's meta must hold seed, arena"),
        ([], OSError("no such file"), f"argument --load: {d}: no such file"),
        (["--seed", "9"], loaded, "argument --seed: the loaded robot was made with seed 3; "
                                  "leave --seed out with --load"),
        (["--units", "7"], loaded, "argument --units: the loaded robot was made with units 24; "
                                   "leave --units out with --load"),
        (["--places", "41"], loaded, "argument --places: the loaded robot was made with places "
                                     "40; leave --places out with --load"),
        (["--explore-min", "31"], loaded, "argument --explore-min: the loaded robot was made "
                                          "with explore_min 30.0; leave --explore-min out with "
                                          "--load"),
        (["--place-cells", "ground-truth"], loaded,
         "argument --place-cells: the loaded robot was made with place_cells 'learned'; leave "
         "--place-cells out with --load"),
        (["--reanchor"], loaded, "argument --reanchor: the loaded robot was made with reanchor "
                                 "False; leave --reanchor out with --load"),
        (["--route", "shortest"], loaded, "argument --route: the loaded robot was made with "
                                          "route 'tour'; leave --route out with --load"),
        (["--arena", "maze"], loaded, "argument --arena: the loaded robot was taught with "
                                      "arena patrol-course; leave --arena out with --load"),
        (["--checkpoints", "80,11;140,56"], loaded,
         "argument --checkpoints: the loaded robot was taught with checkpoints [[80.0, 11.0], "
         "[140.0, 56.0], [50.0, 105.0]]; leave --checkpoints out with --load"),
        (["--waits", "24.1,19.1,11.7"], loaded,
         "argument --waits: the loaded robot was taught with waits [24.1, 19.1, 11.6]; leave "
         "--waits out with --load"),
        (["--heading-sectors", "1"], loaded,
         "argument --heading-sectors: the loaded robot's place states are split in 4; leave "
         "--heading-sectors out with --load"),
    ]
    for argv, what, want in cases:
        with pytest.raises(Refused) as e:
            _load(monkeypatch, tmp_path, argv, what)
        assert str(e.value) == want, argv


# --------------------------------------------------------------------------- the saved meta
def test_plain_is_the_json_form_of_an_option():
    assert P._plain([(1, 2.5), (3, 4)]) == [[1.0, 2.5], [3.0, 4.0]]
    assert type(P._plain(3)) is float and P._plain(3) == 3.0
    assert P._plain(True) is True and P._plain("maze") == "maze" and P._plain(None) is None
    assert P._plain((True, [np.float64(2.0)])) == [True, [2.0]]
    assert type(P._plain((True, [np.float64(2.0)]))[1][0]) is float


def test_the_route_a_lesson_was_taught_on():
    assert P.meta_route({"route": "tour"}) == "tour"
    assert P.meta_route({}) == "shortest"
    assert P.meta_route({"route": 3}) == "3"


def _snapshot(meta: Any, **changes: Any) -> dict[str, Any]:
    state = {"scenario": "patrol-lesson", "meta": meta, "agent": Agent.__new__(Agent),
             "world": World.__new__(World)}
    state.update(changes)
    return state


def test_load_lesson_checks_the_snapshot(monkeypatch):
    checked: list[Any] = []
    monkeypatch.setattr(P, "_check_meta", checked.append)
    got: list[Any] = []
    good = _snapshot(_meta())

    def refused(state: dict[str, Any]) -> str:
        monkeypatch.setattr(P, "load_snapshot", lambda f, t: state)
        with pytest.raises(ValueError) as e:
            P.load_lesson("dir")
        return str(e.value)

    monkeypatch.setattr(P, "load_snapshot", lambda f, t: got.append((f, t)) or good)
    assert P.load_lesson("dir") is good and got == [("dir", dict)]
    assert checked == [good["meta"]]
    assert refused(_snapshot(_meta(), scenario="place-preference")) == (
        "a snapshot of 'place-preference', not of a patrol lesson")
    state = _snapshot(_meta())
    del state["scenario"]
    assert refused(state) == "a snapshot of None, not of a patrol lesson"
    want = "the snapshot holds no agent and world"
    assert refused(_snapshot(_meta(), agent=SimpleNamespace())) == want
    assert refused(_snapshot(_meta(), world=None)) == want
    keys = ("the snapshot's meta must hold seed, arena, checkpoints, waits, place_cells, "
            "explore_min, units, places, reproduced and taught_stops")
    assert refused(_snapshot([1])) == keys
    for key in ("seed", "places", "reproduced", "taught_stops"):
        meta = _meta()
        del meta[key]
        assert refused(_snapshot(meta)) == keys, key
    assert len(checked) == 1


def _bad(meta: dict[str, Any], monkeypatch: pytest.MonkeyPatch) -> str:
    monkeypatch.setattr(P, "check_patrol", lambda *a: None)
    with pytest.raises(ValueError) as e:
        P._check_meta(meta)
    return str(e.value)


def test_the_saved_meta_on_its_edges(monkeypatch):
    calls: list[Any] = []
    monkeypatch.setattr(P, "check_patrol", lambda *a: calls.append(a))
    for ok in (_meta(), _meta(seed=0), _meta(seed=2**32 - 1), _meta(units=1, places=256),
               _meta(units=200, places=1), _meta(explore_min=5.0), _meta(explore_min=600),
               _meta(waits=[2.0, 120.0, 2]), _meta(taught_stops=[0, 0.0, None]),
               _meta(checkpoints=[[1, 2], [3.5, 4]], taught_stops=[None, None]),
               _meta(checkpoints=[[1, 2]] * 4, taught_stops=[1.0] * 4),
               _meta(reproduced=-1e300), _meta(reproduced=0), _meta(route="auto")):
        assert P._check_meta(ok) is None
    assert calls[0] == ("patrol-course", _meta()["checkpoints"], [24.1, 19.1, 11.6], "tour")
    old = _meta()
    del old["route"]
    P._check_meta(old)
    assert calls[-1][3] == "shortest"


def test_each_bad_field_refused_word_for_word(monkeypatch):
    m = "the snapshot's meta"
    whole = "is not a whole number in"
    cases = [
        (_meta(arena="moon"), "unknown arena 'moon' in the snapshot"),
        # no TypeError (unhashable) or OverflowError (a 400-digit integer) but the field named
        (_meta(arena=["maze"]), "unknown arena ['maze'] in the snapshot"),
        (_meta(arena=None), "unknown arena None in the snapshot"),
        (_meta(seed=10**400), f"{m} seed={10**400} {whole} [0, 4294967295]"),
        (_meta(explore_min=2**1024), f"{m} explore_min must lie in [5.0, 600.0], got {2**1024}"),
        (_meta(reproduced=2**1024), f"{m} reproduced={2**1024} is not a finite number"),
        (_meta(waits=[24.1, 2**1024, 11.6]),
         f"{m} waits=[24.1, {2**1024}, 11.6] is not a list of waits in [2, 120] s"),
        (_meta(checkpoints=[[1, 2], [3, -(2**1024)]], taught_stops=[1.0, 2.0]),
         f"{m} checkpoints=[[1, 2], [3, {-(2**1024)}]] is not 2 to 4 points [x, y] in cm"),
        (_meta(taught_stops=[1.0, 2**1024, None]),
         f"{m} taught_stops=[1.0, {2**1024}, None] is not one stillness (s, or null) per "
         "checkpoint (3)"),
        (_meta(seed=-1), f"{m} seed=-1 {whole} [0, 4294967295]"),
        (_meta(seed=2**32), f"{m} seed=4294967296 {whole} [0, 4294967295]"),
        (_meta(units=0), f"{m} units=0 {whole} [1, 200]"),
        (_meta(units=201), f"{m} units=201 {whole} [1, 200]"),
        (_meta(places=0), f"{m} places=0 {whole} [1, 256]"),
        (_meta(places=257), f"{m} places=257 {whole} [1, 256]"),
        (_meta(explore_min=4.999), f"{m} explore_min must lie in [5.0, 600.0], got 4.999"),
        (_meta(explore_min=600.001), f"{m} explore_min must lie in [5.0, 600.0], got 600.001"),
        (_meta(place_cells="gt"), f"{m} place_cells must be one of 'learned', 'ground-truth'; "
                                  "got 'gt'"),
        (_meta(route="back"), f"{m} route must be one of 'auto', 'shortest', 'tour'; got "
                              "'back'"),
    ]
    pts = "is not 2 to 4 points [x, y] in cm"
    for cps in ([[1, 2]], [[1, 2]] * 5, ((1, 2), (3, 4)), [(1, 2), (3, 4)], [[1, 2], [3]],
                [[1, 2], [3, 4, 5]], [[1, 2], [3, math.nan]], [[1, 2], [math.inf, 4]],
                [[1, 2], [True, 4]], [[1, 2], ["3", 4]], "1,2;3,4"):
        cases.append((_meta(checkpoints=cps), f"{m} checkpoints={cps!r} {pts}"))
    waits = "is not a list of waits in [2, 120] s"
    for w in ([24.1, 1.9999999999999998, 11.6], [24.1, 120.00000000000001, 11.6],
              [24.1, math.nan, 11.6], [True, 3.0, 4.0], (24.1, 19.1, 11.6), "24.1"):
        cases.append((_meta(waits=w), f"{m} waits={w!r} {waits}"))
    for stops, n in (([1.0, 2.0], 3), ([1.0, 2.0, 3.0, 4.0], 3), ([1.0, -5e-324, None], 3),
                     ([1.0, math.inf, None], 3), ([1.0, "2", None], 3), ((1.0, 2.0, 3.0), 3),
                     ([False, 2.0, 3.0], 3)):
        cases.append((_meta(taught_stops=stops),
                      f"{m} taught_stops={stops!r} is not one stillness (s, or null) per "
                      f"checkpoint ({n})"))
    cases.append((_meta(checkpoints=[[1, 2], [3, 4]], taught_stops=[1.0, 2.0, 3.0]),
                  f"{m} taught_stops=[1.0, 2.0, 3.0] is not one stillness (s, or null) per "
                  "checkpoint (2)"))
    for r in (math.nan, -math.inf, None, "1", True):
        cases.append((_meta(reproduced=r), f"{m} reproduced={r!r} is not a finite number"))
    # the first bad field in the order checked
    cases.append((_meta(arena="moon", seed=-1), "unknown arena 'moon' in the snapshot"))
    cases.append((_meta(seed=-1, units=0), f"{m} seed=-1 {whole} [0, 4294967295]"))
    cases.append((_meta(waits=[1.0], taught_stops=[], reproduced=None),
                  f"{m} waits=[1.0] {waits}"))
    for meta, want in cases:
        assert _bad(meta, monkeypatch) == want, want


def test_a_course_check_patrol_refuses_is_the_snapshots_course(monkeypatch):
    def check_patrol(*a: Any) -> None:
        raise ValueError("two checkpoints are 12 cm apart along the route")

    monkeypatch.setattr(P, "check_patrol", check_patrol)
    with pytest.raises(ValueError) as e:
        P._check_meta(_meta())
    assert str(e.value) == "the snapshot's course: two checkpoints are 12 cm apart along the route"
    assert e.value.__cause__ is None and e.value.__suppress_context__


# ------------------------------------------------------------------------------ save and teach
class _World:
    def __init__(self, log: list[Any]) -> None:
        self.log = log

    def detach(self, who: Any) -> None:
        self.log.append(("detach", who))

    def attach(self, who: Any) -> None:
        self.log.append(("attach", who))


def _lesson(log: list[Any], n_ica: int | None) -> SimpleNamespace:
    places = SimpleNamespace(model=None if n_ica is None else SimpleNamespace(
        params=SimpleNamespace(n_ica=np.int64(n_ica))))
    session = SimpleNamespace(world=_World(log), teacher="teacher", agent="agent", obs="obs")
    return SimpleNamespace(session=session, agent=SimpleNamespace(places=places),
                           course=SimpleNamespace(loop="loop"), reproduced=np.float64(0.75),
                           taught_stops=[20.0, None])


def _args(**changes: Any) -> argparse.Namespace:
    a = argparse.Namespace(seed=np.int64(5), arena="two-rooms",
                           checkpoints=[(15, 65), (90.5, 20)], waits=[24.1, 19],
                           place_cells="learned", explore_min=30, units=24, places=40,
                           route="shortest", quick=True)
    vars(a).update(changes)
    return a


def test_save_lesson_writes_the_meta_with_the_teacher_detached(monkeypatch):
    log: list[Any] = []

    def save_snapshot(obj: Any, folder: Any) -> None:
        log.append(("save", obj, folder))

    monkeypatch.setattr(P, "save_snapshot", save_snapshot)
    P.save_lesson("dir", _lesson(log, 12), _args())
    assert [e[0] for e in log] == ["detach", "save", "attach"]
    assert log[0] == ("detach", "teacher") and log[2] == ("attach", "teacher")
    obj, folder = log[1][1], log[1][2]
    assert folder == "dir"
    assert obj == {"scenario": "patrol-lesson", "meta": {
        "seed": 5, "arena": "two-rooms", "checkpoints": [[15.0, 65.0], [90.5, 20.0]],
        "waits": [24.1, 19.0], "place_cells": "learned", "explore_min": 30.0, "units": 12,
        "places": 40.0, "route": "shortest", "quick": True, "reproduced": 0.75,
        "taught_stops": [20.0, None]}, "agent": "agent", "world": log[0] and obj["world"],
        "obs": "obs", "loop": "loop"}
    meta = obj["meta"]
    assert type(meta["seed"]) is int and type(meta["units"]) is int
    assert type(meta["reproduced"]) is float
    # ground-truth cells: the units given; no --quick, no route: False and auto
    log.clear()
    args = _args(place_cells="ground-truth", units=7)
    del args.quick, args.route
    P.save_lesson("dir", _lesson(log, None), args)
    meta = log[1][1]["meta"]
    assert meta["units"] == 7 and meta["quick"] is False and meta["route"] == "auto"
    # place cells without a model attribute at all (ground truth): the units given too
    log.clear()
    lesson = _lesson(log, None)
    lesson.agent.places = SimpleNamespace()
    P.save_lesson("dir", lesson, _args(units=9))
    assert log[1][1]["meta"]["units"] == 9


def test_the_teacher_is_attached_again_when_saving_fails(monkeypatch):
    log: list[Any] = []

    def save_snapshot(obj: Any, folder: Any) -> None:
        raise OSError("disk full")

    monkeypatch.setattr(P, "save_snapshot", save_snapshot)
    with pytest.raises(OSError, match="disk full"):
        P.save_lesson("dir", _lesson(log, 12), _args())
    assert log == [("detach", "teacher"), ("attach", "teacher")]


def test_teach_patrol_from_a_loaded_lesson(monkeypatch):
    calls: dict[str, Any] = {}

    class _Session:
        def __init__(self, world: Any, agent: Any, log: Any, *, obs: Any, phase: Any) -> None:
            calls["session"] = (world, agent, log, obs, phase)
            self.world, self.agent = world, agent

    class _Course:
        def __init__(self, s: Any, route: Any, checkpoints: Any, names: Any) -> None:
            calls["course"] = (s, route, checkpoints, names)
            self.loop = None

    def led_route(*a: Any) -> tuple[str, str]:
        calls["led_route"] = a
        return "tour", "the route"

    monkeypatch.setattr(P, "Session", _Session)
    monkeypatch.setattr(P, "Log", lambda n_drives: ("log", n_drives))
    monkeypatch.setattr(P, "led_route", led_route)
    monkeypatch.setattr(P, "PatrolCourse", _Course)
    monkeypatch.setattr(P, "teach", lambda *a, **k: pytest.fail("taught again"))
    agent = SimpleNamespace(params=SimpleNamespace(motor=SimpleNamespace(wall_side=-1)))
    meta = {"reproduced": 1, "taught_stops": (3.0, None, 5.0), "route": "auto"}
    loaded = {"world": "w", "agent": agent, "obs": "o", "loop": "the loop", "meta": meta}
    args = argparse.Namespace(checkpoints=[(1, 2), [3, 4], (5, 6)], arena="maze", loaded=None,
                              load="dir")
    monkeypatch.setattr(P, "load_lesson", lambda folder: calls.setdefault("load", folder)
                        and loaded)
    lesson = P.teach_patrol(args, 9, units=3)
    assert calls["load"] == "dir"
    assert calls["session"] == ("w", agent, ("log", 3), "o", PatrolPhase.CHECKPOINTS)
    assert calls["led_route"] == ("maze", [(1.0, 2.0), (3.0, 4.0), (5.0, 6.0)], "auto", -1)
    s = calls["course"][0]
    assert calls["course"][1:] == ("the route", [(1.0, 2.0), (3.0, 4.0), (5.0, 6.0)],
                                   ["checkpoint-1", "checkpoint-2", "checkpoint-3"])
    assert isinstance(lesson, Lesson)
    assert (lesson.world, lesson.agent, lesson.session) == ("w", agent, s)
    assert lesson.course.loop == "the loop" and lesson.reproduced == 1.0
    assert type(lesson.reproduced) is float
    assert lesson.taught_stops == [3.0, None, 5.0] and lesson.route_kind == "tour"
    # args.loaded (check_course_args's) is used as it is, without loading again
    del calls["load"]
    del meta["route"]
    args = argparse.Namespace(checkpoints=[(1, 2), (3, 4)], arena="maze", loaded=loaded,
                              load="dir")
    P.teach_patrol(args, 9, units=3)
    assert "load" not in calls and calls["led_route"][2] == "shortest"
    assert calls["session"][2] == ("log", 2)


def test_teach_patrol_teaches_and_saves_when_asked(monkeypatch):
    calls: dict[str, Any] = {}

    def teach(*a: Any, **k: Any) -> str:
        calls["teach"] = (a, k)
        return "lesson"

    monkeypatch.setattr(P, "teach", teach)
    monkeypatch.setattr(P, "save_lesson", lambda *a: calls.setdefault("save", a))
    args = argparse.Namespace(checkpoints=[(1, 2), (3, 4)], arena="maze", waits=[9.0, 8.0],
                              place_cells="ground-truth", explore_min=12.0, units=99,
                              places=7, heading_sectors=None, reanchor=True, route="tour")
    assert P.teach_patrol(args, 11, units=5) == "lesson"
    assert calls["teach"] == (("maze", [(1.0, 2.0), (3.0, 4.0)], [9.0, 8.0]), {
        "seed": 11, "route": "tour", "place_cells": "ground-truth", "explore_min": 12.0,
        "units": 5, "places": 7, "heading_sectors": 1, "reanchor": True})
    assert "save" not in calls
    args.save, args.place_cells, args.heading_sectors = "out", "learned", 3
    del args.route
    P.teach_patrol(args, 11, units=5)
    assert calls["teach"][1]["route"] == "auto" and calls["teach"][1]["heading_sectors"] == 3
    assert calls["save"] == ("out", "lesson", args)
