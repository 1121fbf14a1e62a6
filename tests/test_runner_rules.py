"""The scenario runner's rules: the registry, the docstring made plain for the terminal, the
common options (their defaults and the seed's bounds 0 and 2**32 - 1 exactly and one past),
the unknown name refused word for word, a scenario's own check run after parsing, and running
one. A stand-in scenario module (registered for the test only) records what it is given."""

from __future__ import annotations

import importlib
import re
import sys
import types
from pathlib import Path
from typing import Any

import pytest

from hippo import runner
from hippo.runner import (
    DESCRIPTIONS,
    SCENARIOS,
    _plain,
    parse_scenario_args,
    run_scenario,
    scenario_parser,
)

NAMES = ["demo", "two-rooms", "maze", "timing-demo", "place-preference", "patrol", "rooms",
         "deployment"]


def test_the_registry_names_each_scenario_once_with_its_module_and_line():
    assert list(SCENARIOS) == NAMES and list(DESCRIPTIONS) == NAMES
    for name, module in SCENARIOS.items():
        assert module == "hippo.scenarios." + name.replace("-", "_")
        assert DESCRIPTIONS[name] and "\n" not in DESCRIPTIONS[name]


@pytest.mark.parametrize("text, plain", [
    (":class:`~hippo.sim.World` runs", "hippo.sim.World runs"),
    (":func:`record` and :mod:`hippo.envs`", "record and hippo.envs"),
    ("``--quick`` is **not** a result", "--quick is not a result"),
    ("``a`` ``b``", "a b"),
    ("**x** **y**", "x y"),
    ("no markup: 2 * 3 ` here", "no markup: 2 * 3 ` here"),
    (":ref:`a` :meth:`b.c`", "a b.c"),
])
def test_a_docstring_is_made_plain(text, plain):
    assert _plain(text) == plain


def _stand_in(monkeypatch, *, check: bool = True) -> dict[str, Any]:
    """Register a scenario ``stand-in`` whose module records its calls."""
    calls: dict[str, Any] = {}
    module = types.ModuleType("hippo_stand_in_scenario")
    module.__doc__ = "  A stand-in: :class:`~hippo.X` with ``code``.\n\n  Second paragraph.  "

    def add_arguments(parser: Any) -> None:
        parser.add_argument("--level", type=int, default=3)

    def run(args: Any) -> dict[str, Any]:
        calls["run"] = args
        return {"level": args.level, "seed": args.seed}

    def check_args(args: Any, parser: Any) -> None:
        calls["check"] = (args.level, parser.prog)
        if args.level < 0:
            parser.error("--level must be >= 0")

    module.add_arguments = add_arguments   # type: ignore[attr-defined]
    module.run = run                       # type: ignore[attr-defined]
    if check:
        module.check_args = check_args     # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "hippo_stand_in_scenario", module)
    monkeypatch.setitem(SCENARIOS, "stand-in", "hippo_stand_in_scenario")
    return calls


def test_the_common_options_and_their_defaults(monkeypatch):
    _stand_in(monkeypatch)
    parser, module = scenario_parser("stand-in")
    assert module is sys.modules["hippo_stand_in_scenario"]
    assert parser.prog == "hippo run stand-in"
    assert parser.description == "A stand-in: hippo.X with code.\n\n  Second paragraph."
    args = parser.parse_args([])
    assert vars(args) == {"out": Path("out/stand-in"), "seed": 0, "quick": False, "level": 3}
    args = parser.parse_args(["--out", "elsewhere", "--seed", "4294967295", "--quick"])
    assert (args.out, args.seed, args.quick) == (Path("elsewhere"), 2**32 - 1, True)
    assert parser.parse_args(["--seed", "0"]).seed == 0
    assert scenario_parser("stand-in", prog="hippo sweep")[0].prog == "hippo sweep"


@pytest.mark.parametrize("seed", ["-1", "4294967296"])
def test_the_seed_is_refused_one_past_its_bounds(monkeypatch, capsys, seed):
    _stand_in(monkeypatch)
    parser, _ = scenario_parser("stand-in")
    with pytest.raises(SystemExit) as e:
        parser.parse_args(["--seed", seed])
    assert e.value.code == 2
    assert capsys.readouterr().err.startswith("hippo run stand-in: error: argument --seed: ")


def test_an_unknown_scenario_is_refused_word_for_word(capsys):
    for call in (lambda: scenario_parser("bogus"), lambda: parse_scenario_args("bogus"),
                 lambda: run_scenario("bogus", [])):
        with pytest.raises(SystemExit) as e:
            call()
        assert e.value.code == 2
        assert capsys.readouterr().err == (
            "hippo run: error: unknown scenario 'bogus'; choose from: demo, two-rooms, maze, "
            "timing-demo, place-preference, patrol, rooms, deployment (see hippo run --help)\n")
    with pytest.raises(SystemExit):
        scenario_parser("bogus", prog="hippo sweep")
    assert capsys.readouterr().err.startswith("hippo sweep: error: unknown scenario 'bogus'")


def test_a_scenarios_own_check_runs_after_parsing(monkeypatch, capsys):
    calls = _stand_in(monkeypatch)
    args, module = parse_scenario_args("stand-in", ["--level", "5"])
    assert args.level == 5 and calls["check"] == (5, "hippo run stand-in")
    assert module is sys.modules["hippo_stand_in_scenario"]
    parse_scenario_args("stand-in", ("--level", "1"), prog="hippo sweep")
    assert calls["check"] == (1, "hippo sweep")
    with pytest.raises(SystemExit) as e:
        parse_scenario_args("stand-in", ["--level", "-1"])
    assert e.value.code == 2
    assert capsys.readouterr().err == ("hippo run stand-in: error: --level must be >= 0 "
                                       "(see hippo run stand-in --help)\n")
    assert "run" not in calls


def test_a_scenario_without_its_own_check_is_parsed_alone(monkeypatch):
    calls = _stand_in(monkeypatch, check=False)
    args, _ = parse_scenario_args("stand-in", ["--level", "-1"])
    assert args.level == -1 and calls == {}


def test_running_a_scenario_returns_its_metrics(monkeypatch):
    calls = _stand_in(monkeypatch)
    assert run_scenario("stand-in", ["--seed", "9", "--level", "2"]) == {"level": 2, "seed": 9}
    assert calls["run"].seed == 9 and calls["check"][0] == 2
    assert run_scenario("stand-in") == {"level": 3, "seed": 0}


def test_every_registered_scenario_has_a_parser_with_the_common_options():
    for name in NAMES:
        parser, module = scenario_parser(name)
        assert module is importlib.import_module(SCENARIOS[name])
        assert parser.prog == f"hippo run {name}"
        args = parser.parse_args([])
        assert args.out == Path(f"out/{name}") and args.seed == 0 and args.quick is False
        assert not re.search(r":\w+:`|``", parser.description or "")
    assert runner.SCENARIOS is SCENARIOS


def test_the_common_options_help_in_their_words(monkeypatch):
    _stand_in(monkeypatch)
    text = " ".join(scenario_parser("stand-in")[0].format_help().split())
    assert "--out OUT output folder (created if needed) (default: out/stand-in)" in text
    assert "--seed SEED random seed (default: 0)" in text
    assert ("--quick a short run for tests and first looks: its numbers are a smoke test, "
            "not results") in text


def test_a_scenario_without_a_docstring_has_no_description(monkeypatch):
    _stand_in(monkeypatch)
    sys.modules["hippo_stand_in_scenario"].__doc__ = None
    assert scenario_parser("stand-in")[0].description == ""
