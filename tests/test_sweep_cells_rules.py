"""The sweep's cells by hand (hippo.sweep_cells): a small grid listed cell by cell, a cell's id
and command line, the options checked once per distinct set, the default task on a stand-in
scenario, and the cell record's checks, each refusal word for word."""

from __future__ import annotations

import hashlib
import json
import os
import sys
import tempfile
import types
from pathlib import Path
from typing import Any

import pytest

import hippo.runner as runner
from hippo.io import CorruptFileError
from hippo.sweep_cells import (
    Cell,
    CellArgumentError,
    _record_problem,
    check_cells,
    grid,
    load_cell_record,
    scenario_task,
)


# ----------------------------------------------------------------------------- cells and grids
def test_a_cells_id_is_its_names_and_a_hash_of_its_definition():
    cell = Cell("demo", 3, (("gain", "2"),), ("--quick",))
    # json.dumps([scenario, seed, params, extra]) written by hand (tuples are JSON lists)
    text = '["demo", 3, [["gain", "2"]], ["--quick"]]'
    digest = hashlib.sha1(text.encode()).hexdigest()
    assert cell.id == "demo-s3-" + digest[:10]
    assert len(cell.id) == len("demo-s3-") + 10
    # every part of the definition changes the hash
    others = [Cell("demo2", 3, cell.params, cell.extra), Cell("demo", 4, cell.params, cell.extra),
              Cell("demo", 3, (("gain", "3"),), cell.extra), Cell("demo", 3, cell.params, ())]
    assert len({c.id[-10:] for c in [cell, *others]}) == 5
    assert Cell("x", 0).id == "x-s0-" + hashlib.sha1(b'["x", 0, [], []]').hexdigest()[:10]


def test_a_cells_command_line_in_order():
    cell = Cell("demo", 7, (("leak", "0.1,0.2"), ("delay", "3")), ("--quick", "-v"))
    assert cell.argv(Path("/o/c")) == ["--out", "/o/c", "--seed", "7", "--leak", "0.1,0.2",
                                       "--delay", "3", "--quick", "-v"]
    assert Cell("demo", 0).argv(Path("o")) == ["--out", "o", "--seed", "0"]


def test_a_small_grid_listed_by_hand():
    # combinations outermost (in the order of the parameters, the first varying slowest),
    # every seed for each; values are written as text, seeds as ints
    cells = grid("demo", [5, 2], {"a": [1, 2], "b": ["x", "y"]}, ["--quick"])
    want = [(5, (("a", "1"), ("b", "x"))), (2, (("a", "1"), ("b", "x"))),
            (5, (("a", "1"), ("b", "y"))), (2, (("a", "1"), ("b", "y"))),
            (5, (("a", "2"), ("b", "x"))), (2, (("a", "2"), ("b", "x"))),
            (5, (("a", "2"), ("b", "y"))), (2, (("a", "2"), ("b", "y")))]
    assert cells == [Cell("demo", s, p, ("--quick",)) for s, p in want]
    assert all(type(c.seed) is int and type(c.extra) is tuple for c in cells)
    # no parameters: one cell per seed; seeds given as text or numpy ints become ints
    assert grid("demo", ["4", 1]) == [Cell("demo", 4), Cell("demo", 1)]
    assert grid("demo", [0], {}) == [Cell("demo", 0)]


def test_a_grid_without_values_or_seeds_is_refused_word_for_word():
    with pytest.raises(ValueError) as exc:
        grid("demo", [0], {"gain": ["1"], "leak": []})
    assert str(exc.value) == "parameter 'leak' has no values"
    for seeds in ([], ()):
        with pytest.raises(ValueError) as exc:
            grid("demo", seeds, {"gain": ["1"]})
        assert str(exc.value) == "seeds must list at least one seed"


# ------------------------------------------------------- parsing the options (stand-in runner)
class StandIn:
    """parse_scenario_args as a scenario would: refuse a value, else return (args, module)."""

    def __init__(self, stderr: str = "", code: int = 2, refuse: str | None = None) -> None:
        self.calls: list[tuple[str, list[str]]] = []
        self.stderr, self.code, self.refuse = stderr, code, refuse
        self.module = types.SimpleNamespace(run=self.run)
        self.ran: list[Any] = []

    def __call__(self, name: str, argv: Any = (), prog: str | None = None):
        argv = list(argv)
        self.calls.append((name, argv))
        if self.refuse is not None and self.refuse in argv:
            sys.stderr.write(self.stderr)
            raise SystemExit(self.code)
        return types.SimpleNamespace(argv=argv), self.module

    def run(self, args: Any) -> dict[str, Any]:
        self.ran.append(args)
        print("the scenario speaks")
        if "--exit" in args.argv:
            raise SystemExit(3)
        return {"value": 1.5}


def test_check_cells_parses_each_distinct_set_of_options_once(monkeypatch):
    stand = StandIn()
    monkeypatch.setattr(runner, "parse_scenario_args", stand)
    cells = [*grid("demo", [0, 1, 2], {"gain": ["1", "2"]}), Cell("other", 0, (("gain", "1"),))]
    check_cells(cells)
    # seeds share their options: the first seed's cell of each set is parsed, at a placeholder
    # folder under the temp dir named by its id (never created)
    place = Path(tempfile.gettempdir()) / "hippo-sweep-check"
    assert stand.calls == [
        ("demo", ["--out", str(place / cells[0].id), "--seed", "0", "--gain", "1"]),
        ("demo", ["--out", str(place / cells[3].id), "--seed", "0", "--gain", "2"]),
        ("other", ["--out", str(place / cells[6].id), "--seed", "0", "--gain", "1"])]
    assert not any((place / c.id).exists() for c in cells)


def test_a_refusal_names_the_cell_and_keeps_the_scenarios_words(monkeypatch):
    err = ("usage: hippo run demo [-h]\n"
           "hippo run demo: error: argument --rho: 2: error: too big (see hippo run demo --help)"
           "\n\n   \n")
    monkeypatch.setattr(runner, "parse_scenario_args", StandIn(err, refuse="2"))
    # the last non-blank line, after its first ": error: " only
    why = "argument --rho: 2: error: too big (see hippo run demo --help)"
    cells = grid("demo", [0], {"rho": ["0.5", "2"], "n": ["4"]}, ["--quick", "-v"])
    with pytest.raises(CellArgumentError) as exc:
        check_cells(cells)
    assert str(exc.value) == f"the cell --rho 2 --n 4 --quick -v: {why}"
    assert exc.value.__cause__ is None and exc.value.__suppress_context__
    # without options after the parameters: no trailing space before the colon
    with pytest.raises(CellArgumentError) as exc:
        check_cells(grid("demo", [0], {"rho": ["2"]}))
    assert str(exc.value) == f"the cell --rho 2: {why}"
    # the default task says the scenario's words alone
    with pytest.raises(CellArgumentError) as exc:
        scenario_task(cells[1], "unused")
    assert str(exc.value) == why


def test_a_refusal_that_says_nothing_gives_the_exit_status(monkeypatch):
    monkeypatch.setattr(runner, "parse_scenario_args", StandIn("", code=4, refuse="2"))
    with pytest.raises(CellArgumentError) as exc:
        check_cells(grid("demo", [0], {"rho": ["2"]}))
    assert str(exc.value) == "the cell --rho 2: exit status 4"
    # a line without ": error: " is kept whole
    monkeypatch.setattr(runner, "parse_scenario_args", StandIn("bad value\n", refuse="2"))
    with pytest.raises(CellArgumentError) as exc:
        check_cells(grid("demo", [0], {"rho": ["2"]}))
    assert str(exc.value) == "the cell --rho 2: bad value"


def test_the_default_task_runs_the_scenario_into_its_folder(monkeypatch, tmp_path):
    stand = StandIn()
    monkeypatch.setattr(runner, "parse_scenario_args", stand)
    monkeypatch.delenv("HIPPO_QUIET", raising=False)
    cell = Cell("demo", 2, (("gain", "3"),))
    out = tmp_path / "a" / "b"
    assert scenario_task(cell, str(out)) == {"value": 1.5}
    assert stand.calls == [("demo", ["--out", str(out), "--seed", "2", "--gain", "3"])]
    assert (out / "log.txt").read_text() == "the scenario speaks\n"   # printed into the log
    assert os.environ["HIPPO_QUIET"] == "1"
    monkeypatch.setenv("HIPPO_QUIET", "0")                 # a value set is kept
    scenario_task(cell, str(out))
    assert os.environ["HIPPO_QUIET"] == "0"
    assert (out / "log.txt").read_text() == "the scenario speaks\n"   # a new log per run


def test_a_scenario_that_exits_raises_instead(monkeypatch, tmp_path):
    monkeypatch.setattr(runner, "parse_scenario_args", StandIn())
    with pytest.raises(RuntimeError) as exc:
        scenario_task(Cell("demo", 0, (), ("--exit",)), str(tmp_path / "c"))
    assert str(exc.value) == "the scenario exited (3)"
    assert exc.value.__cause__ is None and exc.value.__suppress_context__


# ------------------------------------------------------------------------- the cell's record
CELL = Cell("demo", 3, (("gain", "2"),), ("--quick",))


def good_record() -> dict[str, Any]:
    """A record as the sweep writes it for CELL (written out by hand)."""
    return {"cell": CELL.id, "scenario": "demo", "seed": 3, "params": {"gain": "2"},
            "extra": ["--quick"], "status": "ok", "attempts": 1, "error": "",
            "seconds": 0.5, "worker": "", "metrics": {"value": 6.0}}


def _problem(**change: Any) -> str:
    rec = good_record()
    for k, v in change.items():
        if v is KeyError:
            del rec[k]
        else:
            rec[k] = v
    return _record_problem(rec, CELL)


def test_a_good_record_loads(tmp_path):
    path = tmp_path / "c.json"
    path.write_text(json.dumps(good_record()))
    assert load_cell_record(path, CELL) == good_record()
    for ok in ({"seconds": None}, {"seconds": 2}, {"seconds": 0.0}, {"status": "failed"},
               {"attempts": 1}, {"attempts": 3}, {"metrics": {}}):
        assert _problem(**ok) == ""


@pytest.mark.parametrize("change, says", [
    ({"cell": KeyError}, "cell must be a str, got None"),
    ({"cell": 5}, "cell must be a str, got 5"),
    ({"scenario": None}, "scenario must be a str, got None"),
    ({"seed": "3"}, "seed must be a int, got '3'"),
    ({"seed": True}, "seed must be a int, got True"),
    ({"seed": 3.0}, "seed must be a int, got 3.0"),
    ({"params": [["gain", "2"]]}, "params must be a dict, got [['gain', '2']]"),
    ({"extra": "--quick"}, "extra must be a list, got '--quick'"),
    ({"status": 1}, "status must be a str, got 1"),
    ({"attempts": True}, "attempts must be a int, got True"),
    ({"attempts": 1.0}, "attempts must be a int, got 1.0"),
    ({"error": None}, "error must be a str, got None"),
    ({"worker": KeyError}, "worker must be a str, got None"),
    ({"metrics": "fine"}, "metrics must be a dict, got 'fine'"),
    ({"metrics": [1]}, "metrics must be a dict, got [1]"),
    # a repr longer than 60 characters is cut at 60: the quote and 59 letters
    ({"seed": "x" * 100}, "seed must be a int, got '" + "x" * 59),
    ({"seconds": True}, "seconds must be a number or null, got True"),
    ({"seconds": "1"}, "seconds must be a number or null, got '1'"),
    ({"seconds": "y" * 80}, "seconds must be a number or null, got '" + "y" * 59),
    ({"status": "done"}, "status must be ok or failed, got 'done'"),
    ({"status": "OK"}, "status must be ok or failed, got 'OK'"),
    ({"status": "z" * 70}, "status must be ok or failed, got '" + "z" * 59),
    ({"attempts": 0}, "attempts must be >= 1, got 0"),
    ({"attempts": -2}, "attempts must be >= 1, got -2"),
    ({"metrics": {1: 2.0}}, "metrics must be keyed by names"),
])
def test_a_damaged_record_is_refused_word_for_word(change, says):
    assert _problem(**change) == says


def test_not_an_object_is_refused(tmp_path):
    assert _record_problem([1, 2], CELL) == "holds a list, not a cell record"
    assert _record_problem(None, CELL) == "holds a NoneType, not a cell record"
    path = tmp_path / "c.json"
    path.write_text("[1, 2]")
    with pytest.raises(CorruptFileError) as exc:
        load_cell_record(path, CELL)
    assert str(exc.value) == f"{path}: holds a list, not a cell record"


OTHER = "(the file belongs to another cell, or was edited)"


@pytest.mark.parametrize("change, says", [
    ({"cell": "demo-s3-0000000000"}, f"its cell is 'demo-s3-0000000000', the cell's "
                                     f"{CELL.id!r} {OTHER}"),
    ({"scenario": "patrol"}, f"its scenario is 'patrol', the cell's 'demo' {OTHER}"),
    ({"seed": 4}, f"its seed is 4, the cell's 3 {OTHER}"),
    ({"params": {"gain": "3"}}, f"its params is {{'gain': '3'}}, the cell's {{'gain': '2'}} "
                                f"{OTHER}"),
    ({"params": {}}, f"its params is {{}}, the cell's {{'gain': '2'}} {OTHER}"),
    ({"extra": []}, f"its extra is [], the cell's ['--quick'] {OTHER}"),
    # reprs cut at 80 characters: the quote and 79 letters
    ({"scenario": "q" * 100}, f"its scenario is '{'q' * 79}, the cell's 'demo' {OTHER}"),
])
def test_a_record_of_another_cell_is_refused_word_for_word(tmp_path, change, says):
    assert _problem(**change) == says
    path = tmp_path / "c.json"
    rec = {**good_record(), **change}
    path.write_text(json.dumps(rec))
    with pytest.raises(CorruptFileError) as exc:
        load_cell_record(path, CELL)
    assert str(exc.value) == f"{path}: {says}"


def test_a_long_cell_id_is_cut_at_80_characters():
    long = Cell("s" * 100, 3, CELL.params, CELL.extra)
    rec = {**good_record(), "cell": "c"}
    # the cell's own id, repr'd and cut to 80 characters
    want = repr(long.id)[:80]
    assert _record_problem({**rec, "scenario": long.scenario}, long) == (
        f"its cell is 'c', the cell's {want} {OTHER}")
