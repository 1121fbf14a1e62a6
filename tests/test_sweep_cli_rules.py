"""``hippo sweep`` by hand (hippo.sweep_cli) on a stand-in scenario and a stand-in run_sweep: the
cells it is handed (written out cell by cell), the options passed on, its defaults and bounds
at and one past each end, every refusal before any cell runs word for word (a --param that is
no option, the output, seed, help and snapshot options, a value listed twice, the options after
--, a bookkeeping --metric, --parquet without its libraries), the unique prefix argparse
reads, the summary line, the failed cells and the exit status."""

from __future__ import annotations

import importlib.util
import sys
import types
import warnings
from pathlib import Path
from typing import Any

import pytest

import hippo.sweep_cli as sweep_cli
from hippo.runner import SCENARIOS
from hippo.sweep import CellArgumentError, SweepResult
from hippo.sweep_cells import Cell
from hippo.sweep_cli import _full_name, sweep_main

#: the stand-in's options the sweep may vary (sorted), as the refusal lists them
CHOICES = "Xray, gain, level, loud, quick, select, selector"


@pytest.fixture
def stand_in(monkeypatch) -> None:
    """A scenario ``stand-in`` with --level, --gain, --loud, --select, --selector, --save,
    --load and --Xray besides the common --out, --seed and --quick."""
    module = types.ModuleType("hippo_sweep_stand_in")
    module.__doc__ = "A stand-in."

    def add_arguments(parser: Any) -> None:
        parser.add_argument("--level", type=int, default=3)
        parser.add_argument("--gain", type=float, default=1.0)
        parser.add_argument("--loud", action="store_true")
        parser.add_argument("--select", action="store_true")
        parser.add_argument("--selector", default="a")
        parser.add_argument("--save", default=None)
        parser.add_argument("--load", default=None)
        parser.add_argument("--Xray", default="0")    # a name that begins with X, as no other

    module.add_arguments = add_arguments    # type: ignore[attr-defined]
    module.run = lambda args: {}            # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "hippo_sweep_stand_in", module)
    monkeypatch.setitem(SCENARIOS, "stand-in", "hippo_sweep_stand_in")


@pytest.fixture
def sweeps(monkeypatch, stand_in) -> dict[str, Any]:
    """run_sweep replaced: what it was handed; ``result`` (set by a test) is what it returns."""
    seen: dict[str, Any] = {"result": None, "calls": 0, "other": False}

    def run_sweep(cells: list[Cell], out: Path, **kw: Any) -> SweepResult:
        seen.update(cells=cells, out=out, kw=kw)
        seen["calls"] += 1
        warnings.warn("no summary figure: metric 'x' is not numeric", UserWarning, stacklevel=2)
        if seen["other"]:
            warnings.warn("another warning", UserWarning, stacklevel=2)
        return seen["result"] or SweepResult(out=Path(out), ran=len(cells))

    monkeypatch.setattr(sweep_cli, "run_sweep", run_sweep)
    return seen


def _refused(capsys: pytest.CaptureFixture[str], argv: list[str]) -> str:
    with pytest.raises(SystemExit) as e:
        sweep_main(argv)
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("hippo sweep: error: ") and err.endswith(" (see hippo sweep --help)\n")
    return err[len("hippo sweep: error: "):-len(" (see hippo sweep --help)\n")]


# ----------------------------------------------------------------------- what run_sweep gets
def test_the_grid_cell_by_cell_and_the_options_passed_on(sweeps, tmp_path, capsys):
    out = tmp_path / "s"
    argv = ["stand-in", "--seeds", "4,1", "--param", "level", "1", "2", "--param", "gain", "0.5",
            "--out", str(out), "--workers", "1024", "--scheduler", "tcp://h:1", "--retries",
            "100", "--", "--quick", "-v", "7"]
    assert sweep_main(argv) == 0
    extra = ("--quick", "-v", "7")
    assert sweeps["cells"] == [
        Cell("stand-in", 4, (("level", "1"), ("gain", "0.5")), extra),
        Cell("stand-in", 1, (("level", "1"), ("gain", "0.5")), extra),
        Cell("stand-in", 4, (("level", "2"), ("gain", "0.5")), extra),
        Cell("stand-in", 1, (("level", "2"), ("gain", "0.5")), extra)]
    assert sweeps["out"] == out
    assert sweeps["kw"] == {"workers": 1024, "scheduler": "tcp://h:1", "retries": 100,
                            "metric": None, "parquet": False}
    assert capsys.readouterr().out == f"4 cells: 4 run, 0 already done, 0 failed; table " \
                                      f"{out / 'results.csv'}\n"
    assert sweep_main(["stand-in", "--out", str(out), "--param", "Xray", "1"]) == 0
    assert sweeps["cells"] == [Cell("stand-in", 0, (("Xray", "1"),))]


def test_the_defaults(sweeps, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert sweep_main(["stand-in", "--retries", "0", "--workers", "1"]) == 0
    assert sweeps["cells"] == [Cell("stand-in", 0)]
    assert sweeps["out"] == Path("out/sweep-stand-in")
    assert sweeps["kw"] == {"workers": 1, "scheduler": None, "retries": 0, "metric": None,
                            "parquet": False}
    assert sweep_main(["stand-in"]) == 0
    assert sweeps["kw"]["workers"] is None and sweeps["kw"]["retries"] == 2
    assert capsys.readouterr().out.endswith(
        "1 cells: 1 run, 0 already done, 0 failed; table out/sweep-stand-in/results.csv\n")
    assert not (tmp_path / "out").exists()   # the stand-in wrote nothing; nor did the command


def test_only_the_no_summary_figure_warning_is_silenced(sweeps, tmp_path):
    sweeps["other"] = True
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sweep_main(["stand-in", "--out", str(tmp_path)])
    assert [str(w.message) for w in caught] == ["another warning"]


def test_the_parquet_flag_with_and_without_its_libraries(sweeps, tmp_path, monkeypatch,
                                                          capsys):
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: object() if name in ("pandas", "pyarrow") else real(name))
    assert sweep_main(["stand-in", "--out", str(tmp_path), "--parquet"]) == 0
    assert sweeps["kw"]["parquet"] is True
    for missing in ("pandas", "pyarrow"):
        monkeypatch.setattr(importlib.util, "find_spec",
                            lambda name, *a, gone=missing: None if name == gone else object())
        assert _refused(capsys, ["stand-in", "--out", str(tmp_path), "--parquet"]) == (
            "--parquet needs pandas and pyarrow (pip install pandas pyarrow); they are not "
            "installed")
    assert sweeps["calls"] == 1


# ----------------------------------------------------------------------- the summary, the end
def _result(tmp_path: Path, rows: list[dict[str, Any]], failed: list[str] = ()) -> SweepResult:
    return SweepResult(out=tmp_path, rows=rows, failed=list(failed), skipped=1, ran=2)


def test_failed_cells_are_listed_and_the_status_is_1(sweeps, tmp_path, capsys):
    rows = [{"cell": "c0", "seed": 0, "level": "1", "status": "ok", "score": 1.0},
            {"cell": "c1", "seed": 5, "level": "2", "status": "failed", "attempts": 3,
             "error": "RuntimeError: boom"}]
    sweeps["result"] = _result(tmp_path, rows, ["c1"])
    assert sweep_main(["stand-in", "--out", str(tmp_path), "--param", "level", "1", "2"]) == 1
    assert capsys.readouterr().out == (
        f"2 cells: 2 run, 1 already done, 1 failed; table {tmp_path / 'results.csv'}\n"
        "  FAILED c1 (seed 5, {'level': '2'}) after 3 attempt(s): RuntimeError: boom\n")


def test_a_metric_no_cell_has_is_said_and_the_status_is_1(sweeps, tmp_path, capsys):
    rows = [{"cell": "c0", "seed": 0, "status": "ok", "score": 1.0, "rate": 2, "label": "x"}]
    sweeps["result"] = _result(tmp_path, rows)
    assert sweep_main(["stand-in", "--out", str(tmp_path), "--metric", "score"]) == 0
    assert sweeps["kw"]["metric"] == "score" and capsys.readouterr().err == ""
    assert sweep_main(["stand-in", "--out", str(tmp_path), "--metric", "speed"]) == 1
    assert capsys.readouterr().err == ("hippo sweep: no summary figure: no cell has the metric "
                                       "'speed' (numeric metrics: score, rate)\n")
    assert sweep_main(["stand-in", "--out", str(tmp_path), "--metric", "label"]) == 1
    assert capsys.readouterr().err == (
        "hippo sweep: no summary figure: the metric 'label' is not a number in any finished "
        "cell (numeric metrics: score, rate)\n")
    sweeps["result"] = _result(tmp_path, [{"cell": "c0", "seed": 0, "status": "ok", "l": "x"}])
    assert sweep_main(["stand-in", "--out", str(tmp_path), "--metric", "l"]) == 1
    assert capsys.readouterr().err.endswith("(numeric metrics: none)\n")
    sweeps["result"] = _result(tmp_path, [])       # no rows: nothing to say
    assert sweep_main(["stand-in", "--out", str(tmp_path), "--metric", "speed"]) == 0
    assert capsys.readouterr().err == ""


def test_a_cell_its_scenario_refuses_is_a_usage_error(monkeypatch, stand_in, tmp_path, capsys):
    def refuses(cells: list[Cell], out: Path, **kw: Any) -> SweepResult:
        raise CellArgumentError("the cell --level x: argument --level: invalid int value: 'x'")

    monkeypatch.setattr(sweep_cli, "run_sweep", refuses)
    assert _refused(capsys, ["stand-in", "--out", str(tmp_path), "--param", "level", "x"]) == (
        "the cell --level x: argument --level: invalid int value: 'x'")


# ------------------------------------------------------------------------------- refusals
@pytest.mark.parametrize("argv, says", [
    (["--param", "bogus", "1"],
     f"--param bogus: not an option of scenario 'stand-in' (choose from: {CHOICES})"),
    (["--param", "level-", "1"],
     f"--param level-: not an option of scenario 'stand-in' (choose from: {CHOICES})"),
    (["--param", " level", "1"],    # (the one-line error joins the spaces)
     f"--param level: not an option of scenario 'stand-in' (choose from: {CHOICES})"),
    *[(["--param", name, "1"],
       f"--param {name}: not an option of scenario 'stand-in' (choose from: {CHOICES})")
      for name in ("out", "seed", "help", "h")],
    *[(["--param", name, "x"], f"--param {name}: a sweep runs every cell from scratch, into its "
       "own folder (no snapshot is saved or loaded)") for name in ("save", "load")],
    (["--param", "level"], "--param level needs at least one value"),
    (["--param", "level", "1", "--param", "gain", "2", "--param", "level", "3"],
     "--param level is given twice: list all its values after one --param"),
    (["--param", "level", "2", "1", "2", "1", "3"], "--param level lists 1, 2 more than once"),
    (["--", "--seed", "3"], "--seed after --: the sweep sets each cell's seed and output folder "
                            "(use hippo sweep's --seeds and --out)"),
    (["--", "--see", "3"], "--see after --: the sweep sets each cell's seed and output folder "
                           "(use hippo sweep's --seeds and --out)"),
    (["--", "--seeds=3"], "--seeds after --: the sweep sets each cell's seed and output folder "
                          "(use hippo sweep's --seeds and --out)"),
    (["--", "--quick", "--out=x"], "--out after --: the sweep sets each cell's seed and output "
                                   "folder (use hippo sweep's --seeds and --out)"),
    (["--", "--out=a=b"], "--out after --: the sweep sets each cell's seed and output folder "
                          "(use hippo sweep's --seeds and --out)"),
    (["--", "x", "--seed", "3"], "--seed after --: the sweep sets each cell's seed and output "
                                 "folder (use hippo sweep's --seeds and --out)"),
    (["--", "--sav", "x"], "--sav after --: every cell would write the same snapshot folder"),
    (["--", "--load=x"], "--load after --: every cell would run the snapshot's robot, made with "
                         "the snapshot's seed, whatever the cell's seed (a sweep runs each cell "
                         "from scratch)"),
    *[(["--", "--quick", opt], f"{opt} after --: a cell runs its scenario, not its help "
       "(hippo run stand-in --help lists the options)") for opt in ("--help", "-h", "--he")],
    (["--", "--help=1"], "--help after --: a cell runs its scenario, not its help (hippo run "
                         "stand-in --help lists the options)"),
    (["--param", "level", "1", "--", "--lev", "2"],
     "--lev after -- is also a --param of the sweep: give its values there"),
    (["--metric", "seconds"], "--metric seconds: a column the sweep writes itself (its cells' "
                              "bookkeeping or a --param), not a metric of the scenario"),
    (["--param", "gain", "1", "--metric", "gain"], "--metric gain: a column the sweep writes "
     "itself (its cells' bookkeeping or a --param), not a metric of the scenario"),
    (["--workers", "0"], "argument --workers: got 0; needs an integer in [1, 1024]"),
    (["--workers", "1025"], "argument --workers: got 1025; needs an integer in [1, 1024]"),
    (["--retries", "-1"], "argument --retries: got -1; needs an integer in [0, 100]"),
    (["--retries", "101"], "argument --retries: got 101; needs an integer in [0, 100]"),
])
def test_refused_before_any_cell_runs(sweeps, tmp_path, capsys, argv, says):
    assert _refused(capsys, ["stand-in", "--out", str(tmp_path / "o"), *argv]) == says
    assert sweeps["calls"] == 0 and not (tmp_path / "o").exists()


def test_an_unknown_scenario_is_refused(sweeps, capsys):
    names = ", ".join(repr(n) for n in sorted(SCENARIOS))
    assert _refused(capsys, ["moon"]) == (
        f"argument scenario: invalid choice: 'moon' (choose from {names})")


def test_options_after_dashes_that_the_sweep_leaves_alone(sweeps, tmp_path):
    # an ambiguous prefix (--sel: select or selector), a single dash, values: the cell's own
    # parser judges them
    for extra in (["--sel", "x"], ["-s", "3"], ["seed"], ["--quick", "--loud"],
                  ["--gain", "2"], ["--Xseed", "1"]):
        assert sweep_main(["stand-in", "--out", str(tmp_path), "--param", "level", "1", "--",
                           *extra]) == 0
        assert sweeps["cells"][0].extra == tuple(extra)


def test_the_full_name_of_an_option():
    known = {"seed", "select", "selector", "save", "out", "h", "help"}
    assert _full_name("seed", known) == "seed"          # exact, although a prefix of none
    assert _full_name("select", known) == "select"      # exact, although a prefix of selector
    assert _full_name("see", known) == "seed" and _full_name("o", known) == "out"
    assert _full_name("sa", known) == "save" and _full_name("selecto", known) == "selector"
    assert _full_name("s", known) == "s" and _full_name("sel", known) == "sel"   # ambiguous
    assert _full_name("x", known) == "x" and _full_name("seeds", known) == "seeds"


def test_the_help(stand_in, capsys):
    with pytest.raises(SystemExit) as e:
        sweep_main(["--help"])
    assert e.value.code == 0
    text = " ".join(capsys.readouterr().out.split())
    for line in ("Run a scenario over seeds x parameters on Dask distributed (a LocalCluster "
                 "unless --scheduler is given); resumable.",
                 "--seeds SEEDS e.g. 0-3 or 0,2,5 (default: 0) --param",
                 "--param NAME [VALUE ...] a scenario option and its values, e.g. --param leak "
                 "0.05,0.15 0.11,0.14 (repeat for more; the grid is every combination) --out",
                 "--out OUT output folder (default out/sweep-SCENARIO) --workers",
                 "--workers WORKERS LocalCluster worker processes (default: the free cores, i.e. "
                 "the usable cores less the load of other processes) --scheduler",
                 "--scheduler SCHEDULER address of an existing Dask scheduler --retries",
                 "--metric METRIC metric of the summary figure --parquet",
                 "--retries RETRIES extra attempts of a failing cell (default: 2)",
                 "--parquet also write results.parquet"):
        assert line in text, line
    assert text.endswith(" results.parquet Options after -- go to every cell's scenario (e.g. "
                         "-- --quick).")
    assert text.startswith("usage: hippo sweep [-h]")
