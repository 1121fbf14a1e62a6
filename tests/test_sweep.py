"""hippo sweep: grids on Dask distributed, resumable, retried, never dropping a cell."""

from __future__ import annotations

import csv
import importlib.util
import os
import signal
import sys
import time
from pathlib import Path

import pytest

distributed = pytest.importorskip("distributed")

from hippo._threads import blas_budget  # noqa: E402
from hippo.cli_args import MAX_SEEDS, seed_ranges  # noqa: E402
from hippo.io import load_json  # noqa: E402
from hippo.sweep import (  # noqa: E402
    Cell,
    CellArgumentError,
    check_cells,
    grid,
    run_sweep,
    scenario_task,
)
from hippo.sweep_cli import sweep_main  # noqa: E402


def square_task(cell: Cell, out: str) -> dict:
    """A cell that computes a known answer from its seed and parameters."""
    p = dict(cell.params)
    Path(out).mkdir(parents=True, exist_ok=True)
    with open(Path(out) / "ran", "a") as f:  # how often this cell ran
        f.write("x")
    if p.get("mode") == "broken":
        raise RuntimeError(f"broken cell {cell.seed}")
    if p.get("mode") == "flaky" and (Path(out) / "ran").read_text() == "x":
        raise RuntimeError("fails on its first attempt only")
    return {"value": cell.seed * float(p.get("gain", 1.0)), "nested": {"half": cell.seed / 2},
            "trace": [1, 2, 3]}


def labelled_task(cell: Cell, out: str) -> dict:
    """A cell with a numeric metric and a text one."""
    return {"value": float(cell.seed), "label": f"seed {cell.seed}"}


def slow_task(cell: Cell, out: str) -> dict:
    time.sleep(1.5)
    return {"value": float(cell.seed)}


@pytest.fixture(scope="module")
def client():
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  dashboard_address=":0") as cluster, \
            distributed.Client(cluster) as c:
        yield c


def test_grid_is_every_combination_for_every_seed():
    cells = grid("two-rooms", [0, 1, 2], {"leak": ["0.05,0.15", "0.11,0.14"], "delay": ["7"]},
                 ["--quick"])
    assert len(cells) == 6 and len({c.id for c in cells}) == 6
    assert {(c.seed, dict(c.params)["leak"]) for c in cells} == {
        (s, leak) for s in (0, 1, 2) for leak in ("0.05,0.15", "0.11,0.14")}
    c = cells[0]
    assert c.argv(Path("o")) == ["--out", "o", "--seed", "0", "--leak", "0.05,0.15",
                                 "--delay", "7", "--quick"]
    assert c.id == grid("two-rooms", [0], {"leak": ["0.05,0.15"], "delay": ["7"]},
                        ["--quick"])[0].id  # stable across runs: resumable
    with pytest.raises(ValueError, match="leak"):
        grid("two-rooms", [0], {"leak": []})
    assert seed_ranges("0-3,7") == [0, 1, 2, 3, 7]


def test_sweep_seeds_are_checked_like_a_scenarios():
    import argparse

    for bad in ("-2", "3-1", "1,1", "a", "", f"0-{MAX_SEEDS}", "0-10000000000000",
                "18446744073709551616-18446744073709551617", "4294967296"):
        with pytest.raises(argparse.ArgumentTypeError):
            seed_ranges(bad)
    assert len(seed_ranges(f"1-{MAX_SEEDS}")) == MAX_SEEDS


def test_seeds_are_plain_ascii_digits(capsys):
    """Fourth fuzzing pass: int() also reads "10_0", "+3" and other scripts' digits, so
    --seeds 10_0 ran the one seed 100 (--seeds 100 is a count) and --seeds ٣ three runs."""
    import argparse

    from hippo import cli
    from hippo.scenarios._common import parse_seeds

    for bad in ("10_0", "1_000", "\u0663", "+3", "1-1_0", "0,\uff15", "3-\u0665"):
        for parse in (seed_ranges, parse_seeds):
            with pytest.raises(argparse.ArgumentTypeError, match="plain digits"):
                parse(bad)
    assert parse_seeds(" 100 ") == 100 and seed_ranges(" 1 - 2 ,5") == [1, 2, 5]
    for argv in (["sweep", "timing-demo", "--seeds", "10_0"],
                 ["run", "two-rooms", "--seeds", "\u0663"]):
        with pytest.raises(SystemExit) as exc:
            cli.main(argv)
        assert exc.value.code == 2 and "argument --seeds" in capsys.readouterr().err


def test_blas_budget_never_oversubscribes():
    for cores in (1, 2, 8):
        for workers in (1, 2, 3, 8):
            b = blas_budget(workers, cores=cores)
            assert b >= 1 and (workers * b <= cores or b == 1)
    assert blas_budget(1, cores=2) == 2 and blas_budget(2, cores=2) == 1
    with pytest.raises(ValueError, match="workers"):
        blas_budget(0)


def test_default_workers_follow_the_one_thread_rule(tmp_path, monkeypatch):
    """With no ``workers`` the LocalCluster gets the free cores, as the leak sweep does: on busy
    cores (free_cores() == 1) one worker, never more processes than the cores left free."""
    import hippo._threads as threads
    import hippo.sweep as sweep

    asked = []

    class Stop(Exception):
        pass

    def fake_connect(scheduler, workers):
        asked.append(workers)
        raise Stop

    monkeypatch.setattr(sweep, "_connect", fake_connect)
    for free in (1, 2):
        monkeypatch.setattr(threads, "free_cores", lambda load=None, free=free: free)
        with pytest.raises(Stop):
            run_sweep(grid("x", [0], {}), tmp_path / f"f{free}", task=square_task)
    assert asked == [1, 2]


def test_sweep_gathers_a_table_and_resumes(tmp_path, client):
    cells = grid("demo", [0, 1, 2], {"gain": ["1", "3"]})
    res = run_sweep(cells, tmp_path, client=client, task=square_task)
    assert res.ok and res.ran == 6 and res.skipped == 0
    with open(tmp_path / "results.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 6
    assert {"seed", "gain", "status", "value", "nested.half"} <= set(rows[0])
    assert "trace" not in rows[0]  # lists are not columns
    for r in rows:
        assert float(r["value"]) == int(r["seed"]) * float(r["gain"])
        assert r["status"] == "ok" and r["attempts"] == "1"
    assert (tmp_path / "summary.png").stat().st_size > 0
    # a rerun skips every finished cell: nothing runs again
    again = run_sweep(cells, tmp_path, client=client, task=square_task)
    assert again.ran == 0 and again.skipped == 6 and len(again.rows) == 6
    assert all((tmp_path / "cells" / c.id / "ran").read_text() == "x" for c in cells)
    # a grown grid runs only the new cells
    parquet = all(importlib.util.find_spec(m) for m in ("pandas", "pyarrow"))
    more = run_sweep(grid("demo", [0, 1, 2, 3], {"gain": ["1", "3"]}), tmp_path,
                     client=client, task=square_task, parquet=parquet)
    assert more.ran == 2 and more.skipped == 6 and len(more.rows) == 8
    assert (tmp_path / "results.parquet").exists() == parquet


def test_failed_cells_are_retried_and_reported(tmp_path, client):
    cells = grid("demo", [0, 1], {"mode": ["ok", "flaky", "broken"]})
    res = run_sweep(cells, tmp_path, client=client, task=square_task, retries=2)
    by_mode = {}
    for r in res.rows:
        by_mode.setdefault(r["mode"], []).append(r)
    assert all(r["status"] == "ok" and r["attempts"] == 1 for r in by_mode["ok"])
    assert all(r["status"] == "ok" and r["attempts"] == 2 for r in by_mode["flaky"])
    broken = by_mode["broken"]
    assert all(r["status"] == "failed" and r["attempts"] == 3 for r in broken)
    assert all("broken cell" in r["error"] for r in broken)
    assert sorted(res.failed) == sorted(r["cell"] for r in broken) and not res.ok
    assert len(res.rows) == 6  # nothing dropped
    # a rerun runs the failed cells again, and only them
    again = run_sweep(cells, tmp_path, client=client, task=square_task, retries=0)
    assert again.ran == 2 and again.skipped == 4


def test_an_empty_output_folder_is_refused(tmp_path, monkeypatch):
    """Fifth fuzzing pass: run_sweep(cells, "") wrote cells/ and results.csv into the current
    folder (Path("") is "."); it is refused before any folder is made or cluster started."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError, match="out must not be an empty path"):
        run_sweep(grid("x", [0], {}), "", task=square_task)
    assert list(tmp_path.iterdir()) == []


def test_cli_names_a_bad_parameter(capsys):
    with pytest.raises(SystemExit):
        sweep_main(["timing-demo", "--param", "no-such-option", "1"])
    assert "no-such-option" in capsys.readouterr().err
    for bad in (["--workers", "0"], ["--retries", "-1"]):
        with pytest.raises(SystemExit):
            sweep_main(["timing-demo", *bad])
        assert bad[0] in capsys.readouterr().err


def test_cli_refuses_a_grid_the_options_after_dashes_would_override(tmp_path, capsys):
    # these ran, silently: "-- --delay 9" ran every delay cell at 9 s while the table said 3;
    # "-- --seed 7 --out X" ran seed 7 into X for every cell; a repeated --param kept its last
    base = ["timing-demo", "--out", str(tmp_path / "s")]
    for args, says in ((["--param", "delay", "3", "--", "--quick", "--delay", "9"],
                        "--delay after -- is also a --param"),
                       (["--", "--quick", "--delay=9", "--seed", "7"], "--seed after --"),
                       (["--", "--out", str(tmp_path / "x")], "--out after --"),
                       (["--param", "delay", "3", "--param", "delay", "5"],
                        "--param delay is given twice"),
                       (["--param", "delay", "3", "3", "5"], "lists 3 more than once")):
        with pytest.raises(SystemExit) as exc:
            sweep_main(base + args)
        assert exc.value.code == 2 and says in capsys.readouterr().err
    assert not (tmp_path / "s").exists() and not (tmp_path / "x").exists()
    # every cell wrote the same snapshot folder (third fuzzing pass)
    patrol = ["patrol", "--out", str(tmp_path / "p")]
    for args, says in ((["--", "--quick", "--save", str(tmp_path / "r")], "--save after --"),
                       (["--param", "save", str(tmp_path / "r")], "--param save")):
        with pytest.raises(SystemExit) as exc:
            sweep_main(patrol + args)
        assert exc.value.code == 2 and says in capsys.readouterr().err
    assert not (tmp_path / "p").exists() and not (tmp_path / "r").exists()


def test_cli_refuses_a_snapshot_for_every_cell(tmp_path, capsys):
    # "-- --load SNAP" ran the snapshot's robot (its seed) in every cell, whatever the seed
    # the cell was named and tabled with (fourth fuzzing pass)
    patrol = ["patrol", "--seeds", "0-1", "--out", str(tmp_path / "p")]
    for args, says in ((["--", "--quick", "--load", str(tmp_path / "r")], "--load after --"),
                       (["--", "--quick", f"--load={tmp_path / 'r'}"], "--load after --"),
                       (["--", "--loa", str(tmp_path / "r")], "--loa after --"),
                       (["--", "--sav", str(tmp_path / "r")], "--sav after --"),
                       (["--param", "load", "a", "b"], "--param load"),
                       (["--metric", "status"], "--metric status"),
                       (["--metric", "seconds"], "--metric seconds")):
        with pytest.raises(SystemExit) as exc:
            sweep_main(patrol + args)
        assert exc.value.code == 2 and says in capsys.readouterr().err
    assert not (tmp_path / "p").exists()


def test_a_damaged_cell_file_is_run_again_with_a_warning(tmp_path, client):
    """Fourth fuzzing pass: a truncated cell file stopped the sweep, a wrong-typed one crashed
    it, and a file whose parameters were not its cell's was put in the table as that cell."""
    import json
    import warnings

    cells = grid("demo", [0, 1, 2, 3, 4], {"gain": ["2"]})
    run_sweep(cells, tmp_path, client=client, task=square_task)
    files = [tmp_path / "cells" / f"{c.id}.json" for c in cells]
    good = json.loads(files[0].read_text())
    files[0].write_text('{"status": "ok"')                               # truncated
    files[1].write_text(json.dumps({**good, "metrics": "fine"}))          # wrong type
    other = {**good, "params": {"gain": "3"}, "metrics": {"value": 12345.0}}
    files[2].write_text(json.dumps({**other, "cell": cells[2].id, "seed": 2}))  # edited
    files[3].write_text("[1, 2]")                                        # not a record
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = run_sweep(cells, tmp_path, client=client, task=square_task)
    said = [str(w.message) for w in caught if "sweep cell file" in str(w.message)]
    assert len(said) == 4 and all(cells[i].id in m for i, m in enumerate(said))
    assert "running the cell again" in said[0] and "gain" in said[2]
    assert res.ok and res.ran == 4 and res.skipped == 1
    assert sorted(r["value"] for r in res.rows) == [0.0, 2.0, 4.0, 6.0, 8.0]
    assert all(r["gain"] == "2" for r in res.rows)
    rows = list(csv.DictReader(open(tmp_path / "results.csv")))
    assert "12345.0" not in {r["value"] for r in rows}
    for i, f in enumerate(files):
        assert load_json(f)["metrics"]["value"] == 2.0 * i   # written again, whole


def test_a_metric_that_is_no_number_leaves_no_stale_figure(tmp_path, client, capsys,
                                                           monkeypatch):
    """Fourth fuzzing pass: --metric of a text column exited 0 with no figure and kept the
    summary.png of an earlier sweep beside the new results.csv."""
    import hippo.sweep_cli as sweep_cli

    cells = grid("demo", [0, 1], {"gain": ["2"]})
    run_sweep(cells, tmp_path, client=client, task=labelled_task)
    assert (tmp_path / "summary.png").exists()
    with pytest.warns(UserWarning, match="no summary figure: metric 'label' is not a numeric"):
        res = run_sweep(cells, tmp_path, client=client, task=labelled_task, metric="label")
    assert res.ok and (tmp_path / "results.csv").exists()
    assert not (tmp_path / "summary.png").exists()   # no figure of another sweep left
    run_sweep(cells, tmp_path, client=client, task=labelled_task)
    run_sweep(cells, tmp_path, client=client, task=labelled_task, figure=False)
    assert not (tmp_path / "summary.png").exists()

    def on_the_test_cluster(cells, out, **kw):
        kw.pop("workers"), kw.pop("scheduler")
        return run_sweep(cells, out, client=client, task=labelled_task, **kw)

    monkeypatch.setattr(sweep_cli, "run_sweep", on_the_test_cluster)
    code = sweep_main(["timing-demo", "--seeds", "0-1", "--out", str(tmp_path / "c"),
                       "--metric", "label"])
    err = capsys.readouterr().err
    assert code == 1 and "'label' is not a number" in err and "numeric metrics: value" in err
    assert sweep_main(["timing-demo", "--seeds", "0-1", "--out", str(tmp_path / "c"),
                       "--metric", "value"]) == 0
    assert (tmp_path / "c" / "summary.png").exists()


def test_parquet_without_pandas_is_refused_before_any_cell_runs(tmp_path, capsys):
    import importlib.util

    if all(importlib.util.find_spec(m) for m in ("pandas", "pyarrow")):
        pytest.skip("pandas and pyarrow are installed")
    with pytest.raises(SystemExit) as exc:
        sweep_main(["timing-demo", "--parquet", "--out", str(tmp_path / "s"), "--", "--quick"])
    assert exc.value.code == 2 and "--parquet needs pandas" in capsys.readouterr().err
    assert not (tmp_path / "s").exists()


def test_a_value_its_scenario_refuses_is_named_before_anything_runs(tmp_path, capsys):
    # the scenario's own refusal (argparse exits) used to kill the Dask worker that ran the
    # cell, so that every cell was reported lost (KilledWorker) and --retries was ignored
    cells = grid("demo", [0, 1], {"rho": ["0.5", "2"]}, ["--quick"])
    with pytest.raises(CellArgumentError, match=r"--rho 2 --quick: argument --rho"):
        check_cells(cells)
    check_cells(cells[:2])   # rho 0.5: fine
    with pytest.raises(CellArgumentError, match="rho"):
        run_sweep(cells, tmp_path / "never", task=scenario_task)
    assert not (tmp_path / "never").exists()   # refused before any folder is made
    with pytest.raises(CellArgumentError, match="unrecognized arguments: --bogus"):
        scenario_task(grid("demo", [0], extra=["--bogus"])[0], str(tmp_path / "cell"))
    assert not (tmp_path / "cell").exists()
    with pytest.raises(SystemExit) as exc:
        sweep_main(["demo", "--param", "rho", "0.5", "2", "--out", str(tmp_path / "cli"),
                    "--", "--quick"])
    assert exc.value.code == 2
    assert "--rho 2" in capsys.readouterr().err and not (tmp_path / "cli").exists()


def test_a_metric_no_cell_has_leaves_the_results_and_warns(tmp_path, client):
    cells = grid("demo", [0, 1], {"gain": ["2"]})
    with pytest.warns(UserWarning, match="no summary figure: metric 'nope'"):
        res = run_sweep(cells, tmp_path, client=client, task=square_task, metric="nope")
    assert res.ok and len(res.rows) == 2 and (tmp_path / "results.csv").exists()
    assert not (tmp_path / "summary.png").exists()


@pytest.mark.slow
def test_cli_sweep_of_a_real_scenario(tmp_path, capsys):
    out = tmp_path / "sw"
    code = sweep_main(["timing-demo", "--seeds", "0-1", "--param", "delay", "2", "--workers",
                       "2", "--out", str(out), "--", "--quick", "--reproductions", "1"])
    assert code == 0
    rows = list(csv.DictReader(open(out / "results.csv")))
    assert len(rows) == 2 and all(r["status"] == "ok" for r in rows)
    assert "1 cells" not in capsys.readouterr().out
    assert all(load_json(out / "cells" / f"{r['cell']}.json")["metrics"] for r in rows)
    # a --metric no cell has: the finished cells are kept, the CLI says so and exits 1
    code = sweep_main(["timing-demo", "--seeds", "0-1", "--param", "delay", "2", "--workers",
                       "1", "--out", str(out), "--metric", "nope", "--", "--quick",
                       "--reproductions", "1"])
    err = capsys.readouterr().err
    assert code == 1 and "no cell has the metric 'nope'" in err and "delay" in err


@pytest.mark.slow
def test_killing_a_worker_loses_no_cell(tmp_path):
    import cloudpickle

    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    cells = grid("demo", list(range(8)))
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=":0") as cluster, \
            distributed.Client(cluster) as c:
        import threading

        def kill_one():
            deadline = time.time() + 60
            while time.time() < deadline:  # once cells are running, kill a busy worker
                busy = [w for w, tasks in c.processing().items() if tasks]
                if busy:  # SIGKILL: the worker process is lost mid-cell
                    pid = c.run(os.getpid, workers=[busy[0]])[busy[0]]
                    os.kill(pid, signal.SIGKILL)
                    return
                time.sleep(0.1)

        killer = threading.Thread(target=kill_one)
        killer.start()
        res = run_sweep(cells, tmp_path, client=c, task=slow_task)
        killer.join()
    assert res.ok and len(res.rows) == 8
    assert sorted(r["value"] for r in res.rows) == list(range(8))
    assert max(r["attempts"] for r in res.rows) >= 2  # the lost cell ran again, and it shows


def test_more_local_workers_than_cores_are_warned_about():
    # (fourth fuzzing pass: --workers 64 on 2 cores started 64 processes without a word)
    from hippo.sweep import _warn_oversubscribed

    with pytest.warns(RuntimeWarning, match="64 worker processes on 2 cores"):
        assert _warn_oversubscribed(64, 2)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert not _warn_oversubscribed(2, 2) and not _warn_oversubscribed(1, 8)
