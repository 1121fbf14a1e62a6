"""run_sweep's rules on a synchronous stand-in client (hippo.sweep): what is submitted, the
attempts the scheduler plugin counts, the table written and read back, finished cells skipped
on a rerun, failed ones retried and reported, the BLAS budgets, the summary figure, the own
cluster closed, and every refusal and warning word for word. No cluster is started."""

from __future__ import annotations

import csv
import math
import os
import socket
import struct
import sys
import types
import warnings
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import matplotlib.pyplot as plt
import pytest

distributed = pytest.importorskip("distributed")

import hippo.plots.sweep as plots  # noqa: E402
import hippo.sweep as sweep  # noqa: E402
from hippo.io import load_json, save_json  # noqa: E402
from hippo.sweep import (  # noqa: E402
    PLUGIN_NAME,
    Cell,
    SweepResult,
    _StartCounter,
    grid,
    run_sweep,
    scenario_task,
)


# ---------------------------------------------------------------------------- the stand-ins
class Future:
    def __init__(self, key: str, value: Any = None, error: BaseException | None = None) -> None:
        self.key, self._value, self._error = key, value, error
        self.status = "finished" if error is None else "error"

    def result(self) -> Any:
        return self._value

    def exception(self) -> BaseException | None:
        return self._error


class SyncClient:
    """A distributed.Client that runs each submitted cell at once, here, with the scheduler's
    retries, telling the registered plugins of every start as the scheduler would."""

    def __init__(self, workers: dict | None = None, cores: dict | None = None) -> None:
        self.scheduler = types.SimpleNamespace(plugins={})
        self.workers, self.cores = workers or {}, cores or {}
        self.submitted: list[dict[str, Any]] = []
        self.answers: list[Any] = []           # what the function run on the workers gave
        self.registered: list[str] = []
        self.closed = False

    def scheduler_info(self) -> dict:
        return {"workers": self.workers}

    def run(self, fn: Any) -> dict:
        self.answers.append(fn())              # what each worker would run (here, once)
        return dict(self.cores)

    def run_on_scheduler(self, fn: Any) -> Any:
        return fn(dask_scheduler=self.scheduler)

    def register_plugin(self, plugin: Any, name: str) -> None:
        self.registered.append(name)
        self.scheduler.plugins[name] = plugin

    def submit(self, fn: Any, *args: Any, key: str, retries: int, pure: bool) -> Future:
        self.submitted.append({"fn": fn, "args": args, "key": key, "retries": retries,
                               "pure": pure})
        error = None
        for _ in range(retries + 1):
            for p in list(self.scheduler.plugins.values()):
                p.transition(key, "waiting", "processing")
                p.transition(key, "processing", "memory")
            try:
                return Future(key, fn(*args))
            except Exception as exc:  # the scheduler retries it
                error = exc
        return Future(key, error=error)

    def close(self) -> None:
        self.closed = True


class Clock:
    """perf_counter and time_ns for hippo.sweep: each reading 1.25 s on, keys end in -7."""

    def __init__(self) -> None:
        self.t = 100.0

    def perf_counter(self) -> float:
        self.t += 1.25
        return self.t

    @staticmethod
    def time_ns() -> int:
        return 7


@pytest.fixture
def sync(monkeypatch):
    """In-order completion and a fixed clock (as_completed yields the futures as given)."""
    monkeypatch.setattr(distributed, "as_completed", lambda fs: iter(fs))
    monkeypatch.setattr(sweep, "time", Clock())
    return SyncClient()


def task(cell: Cell, out: str) -> dict:
    """value = seed * gain; mode broken always fails, flaky on its first attempt only."""
    p = dict(cell.params)
    Path(out).mkdir(parents=True, exist_ok=True)
    ran = Path(out) / "ran"
    ran.write_text(ran.read_text() + "x" if ran.exists() else "x")
    if p.get("mode") == "broken":
        raise RuntimeError(f"broken cell {cell.seed}")
    if p.get("mode") == "flaky" and ran.read_text() == "x":
        raise ValueError("first attempt")
    return {"value": cell.seed * float(p.get("gain", 1.0)), "nested": {"half": cell.seed / 2},
            "trace": [1, 2], "nan": math.nan}


def runs(out: Path, cell: Cell) -> int:
    f = out / "cells" / cell.id / "ran"
    return len(f.read_text()) if f.exists() else 0


# ------------------------------------------------------------------------- helper functions
def test_flatten_keeps_scalars_under_dotted_names():
    d = {"a": 1, "b": {"c": 2.5, "d": {"e": "x"}, "l": [1]}, "n": None, "t": True,
         "arr": (1, 2), "obj": object()}
    assert sweep._flatten(d) == {"a": 1, "b.c": 2.5, "b.d.e": "x", "n": None, "t": True}
    assert sweep._flatten({"x": {"y": 1}}, "p.") == {"p.x.y": 1}


def test_a_record_and_its_row_field_by_field():
    cell = Cell("demo", 3, (("gain", "2"),), ("--quick",))
    res = {"metrics": {"v": 1.0, "m": {"k": 2}}, "seconds": 4.5, "worker": "tcp://w:1"}
    rec = sweep._record(cell, "ok", 2, res)
    assert rec == {"cell": cell.id, "scenario": "demo", "seed": 3, "params": {"gain": "2"},
                   "extra": ["--quick"], "status": "ok", "attempts": 2, "error": "",
                   "seconds": 4.5, "worker": "tcp://w:1", "metrics": {"v": 1.0, "m": {"k": 2}}}
    bad = sweep._record(cell, "failed", 1, None, "E: x")
    assert (bad["seconds"], bad["worker"], bad["metrics"], bad["error"]) == (None, "", {}, "E: x")
    row = sweep._row(rec, ["gain", "other"])
    # the columns in order: the cell, its parameters (missing ones empty), the run, the metrics
    assert list(row.items()) == [
        ("cell", cell.id), ("scenario", "demo"), ("seed", 3), ("gain", "2"), ("other", ""),
        ("status", "ok"), ("attempts", 2), ("seconds", 4.5), ("worker", "tcp://w:1"),
        ("error", ""), ("v", 1.0), ("m.k", 2)]


def test_a_metric_named_like_a_column_never_overwrites_it():
    # a scenario's metrics.json repeats its seed and arena; one that says something else (a
    # metric "seconds", a parameter the scenario changed) is kept beside the column
    cell = Cell("demo", 3, (("arena", "maze"), ("gain", "0.5"), ("flag", "1")), ())
    res = {"metrics": {"seed": 3, "arena": "maze", "gain": 0.5, "flag": True,
                       "seconds": 99.0, "status": "bad", "x": {"seed": 4}},
           "seconds": 4.5, "worker": "w"}
    row = sweep._row(sweep._record(cell, "ok", 1, res), ["arena", "gain", "flag"])
    assert row["seed"] == 3 and row["arena"] == "maze" and row["gain"] == "0.5"
    assert row["seconds"] == 4.5 and row["status"] == "ok"       # the run's own, kept
    assert row["metrics.seconds"] == 99.0 and row["metrics.status"] == "bad"
    assert row["metrics.flag"] is True          # True is not the string "1"
    assert row["x.seed"] == 4                   # a nested name is no column
    for same in ("metrics.seed", "metrics.arena", "metrics.gain"):
        assert same not in row                  # said what the column says: left out
    assert sweep._same(3, 3) and sweep._same("0.5", 0.5) and sweep._same(True, True)
    assert not sweep._same("1", True) and not sweep._same(1, True)
    assert not sweep._same("0.1", 0.10000001)


def test_cell_text_leaves_missing_numbers_empty():
    assert sweep._cell_text(None) == "" and sweep._cell_text(math.nan) == ""
    assert sweep._cell_text(0.0) == 0.0 and sweep._cell_text("x") == "x"
    assert sweep._cell_text(0) == 0 and sweep._cell_text(math.inf) == math.inf


def test_oversubscription_is_warned_one_past_the_cores():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert sweep._warn_oversubscribed(2, 2) is False     # on the edge: no warning
    with pytest.warns(RuntimeWarning) as caught:
        assert sweep._warn_oversubscribed(3, 2) is True
    assert [str(w.message) for w in caught] == [
        "--workers 3 starts 3 worker processes on 2 cores: they share the cores, so no cell "
        "runs faster; leave --workers out for the free cores, or give --scheduler for a "
        "larger cluster"]


def test_connect_makes_a_local_cluster_or_joins_a_scheduler(monkeypatch):
    made: list[tuple[str, tuple, dict]] = []

    def recorder(kind: str):
        def make(*a: Any, **kw: Any) -> Any:
            made.append((kind, a, kw))
            return f"{kind}{len(made)}"
        return make

    monkeypatch.setattr(distributed, "Client", recorder("client"))
    monkeypatch.setattr(distributed, "LocalCluster", recorder("cluster"))
    assert sweep._connect("tcp://x:8786", 5) == ("client1", None)
    assert made == [("client", ("tcp://x:8786",), {})]
    made.clear()
    assert sweep._connect(None, 3) == ("client2", "cluster1")
    assert made == [("cluster", (), {"n_workers": 3, "threads_per_worker": 1, "processes": True,
                                     "dashboard_address": ":0"}),
                    ("client", ("cluster1",), {})]


def test_the_start_counter_counts_only_a_cells_starts():
    c = _StartCounter()
    assert c.name == PLUGIN_NAME == "hippo-sweep-starts"
    for key, start, finish in (("hippo-cell-a-1", "waiting", "processing"),
                               ("hippo-cell-a-1", "processing", "memory"),
                               ("hippo-cell-a-1", "processing", "processing"),
                               ("hippo-cell-b-1", "waiting", "processing"),
                               ("other-a", "waiting", "processing"),
                               ("xhippo-cell-a", "waiting", "processing"),
                               ("hippo-cell-c-1", "waiting", "released")):
        c.transition(key, start, finish)
    assert c.starts == {"hippo-cell-a-1": 2, "hippo-cell-b-1": 1}
    sched = types.SimpleNamespace(plugins={})
    assert sweep._has_counter(sched) is False and sweep._starts_on(sched) == {}
    sched.plugins[PLUGIN_NAME] = c
    assert sweep._has_counter(sched) is True
    got = sweep._starts_on(sched)
    assert got == {"hippo-cell-a-1": 2, "hippo-cell-b-1": 1} and got is not c.starts


def test_blas_budgets_share_each_hosts_cores():
    # host a: two one-thread workers on 8 cores -> 8 // 2 = 4 each; host b: one worker of two
    # threads on 3 cores -> 3 // 2 = 1; host c's worker did not answer: no budget; a worker
    # without "host" is its own host, without "nthreads" one thread: 5 // 1 = 5
    workers = {"tcp://a:1": {"host": "a", "nthreads": 1}, "tcp://a:2": {"host": "a"},
               "tcp://b:1": {"host": "b", "nthreads": 2}, "tcp://c:1": {"host": "c"},
               "tcp://d:1": {}}
    cores = {"tcp://a:1": 8, "tcp://a:2": 8, "tcp://b:1": 3, "tcp://d:1": 5}
    client = SyncClient(workers, cores)
    got = sweep._blas_budgets(client)
    assert client.answers == [len(os.sched_getaffinity(0))]   # each worker counts its cores
    assert got == {"tcp://a:1": 4, "tcp://a:2": 4, "tcp://b:1": 1, "tcp://d:1": 5,
                   "client": f"{socket.gethostname()}:{os.getpid()}"}
    assert sweep._blas_budgets(SyncClient()) == {"client": sweep._process_id()}
    # workers that cannot say their cores (no sched_getaffinity): no budget but the client's
    blind = SyncClient(workers)

    def no_affinity(fn: Any) -> dict:
        raise AttributeError("module 'os' has no attribute 'sched_getaffinity'")

    blind.run = no_affinity  # type: ignore[method-assign]
    assert sweep._blas_budgets(blind) == {"client": sweep._process_id()}
    # a scheduler that lists no workers (yet): no budget but the client's
    empty = SyncClient(workers, cores)
    empty.scheduler_info = lambda: {}  # type: ignore[method-assign]
    assert sweep._blas_budgets(empty) == {"client": sweep._process_id()}


def test_a_cell_runs_on_its_workers_budget_in_a_process_of_its_own(monkeypatch):
    asked: list[Any] = []

    @contextmanager
    def budget(n: Any):
        asked.append(n)
        yield

    monkeypatch.setattr(sweep, "blas_threads", budget)
    monkeypatch.setattr(sweep, "time", Clock())
    cell = Cell("demo", 4, (("gain", "3"),))
    # not on a worker: no address; the caller's own process: BLAS threads left alone
    out = sweep._run_cell(lambda c, o: {"value": 1}, cell, "o", {"client": sweep._process_id()})
    assert out == {"metrics": {"value": 1}, "seconds": 1.25, "worker": ""} and asked == [None]
    monkeypatch.setattr(distributed, "get_worker",
                        lambda: types.SimpleNamespace(address="tcp://w:9"))
    got = sweep._run_cell(lambda c, o: {"c": c.seed, "o": o}, cell, "here",
                          {"tcp://w:9": 3, "client": "elsewhere:1"})
    assert got == {"metrics": {"c": 4, "o": "here"}, "seconds": 1.25, "worker": "tcp://w:9"}
    sweep._run_cell(lambda c, o: None, cell, "o", {"client": "elsewhere:1"})   # no budget: 1
    assert asked == [None, 3, 1]


# ----------------------------------------------------------------------------- run_sweep
def test_a_sweep_submits_each_cell_once_and_tables_it(tmp_path, sync):
    cells = grid("demo", [0, 1], {"gain": ["2", "3"]})
    res = run_sweep(cells, tmp_path, client=sync, task=task, retries=1, figure=False)
    assert isinstance(res, SweepResult) and res.out == tmp_path
    assert res.ok and res.ran == 4 and res.skipped == 0 and res.failed == []
    assert sync.registered == [PLUGIN_NAME]
    budgets = {"client": sweep._process_id()}
    assert sync.submitted == [
        {"fn": sweep._run_cell, "args": (task, c, str(tmp_path / "cells" / c.id), budgets),
         "key": f"hippo-cell-{c.id}-7", "retries": 1, "pure": False} for c in cells]
    # the table by hand: grid order (gain 2 for seeds 0 and 1, then gain 3); value = seed *
    # gain, half = seed / 2, each cell 1.25 s (one step of the clock between its two
    # readings), NaN as an empty field
    text = (tmp_path / "results.csv").read_bytes().decode()   # "\n" ends a line, not "\r\n"
    head = "cell,scenario,seed,gain,status,attempts,seconds,worker,error,value,nested.half,nan\n"
    body = "".join(f"{c.id},demo,{c.seed},{g},ok,1,1.25,,,{c.seed * int(g)}.0,{c.seed / 2},\n"
                   for c, g in zip(cells, ["2", "2", "3", "3"], strict=True))
    assert text == head + body
    # the rows are the records as a later run reads them: NaN written as null, read as None
    assert [r["nan"] for r in res.rows] == [None] * 4
    assert [r["value"] for r in res.rows] == [0.0, 2.0, 0.0, 3.0]
    for c in cells:
        rec = load_json(tmp_path / "cells" / f"{c.id}.json")
        assert rec["status"] == "ok" and rec["attempts"] == 1 and rec["seconds"] == 1.25
    # a rerun skips every finished cell and makes no client at all
    again = run_sweep(cells, tmp_path, client=None, task=task, figure=False)
    assert again.ran == 0 and again.skipped == 4 and len(again.rows) == 4
    assert all(runs(tmp_path, c) == 1 for c in cells)
    assert (tmp_path / "results.csv").read_bytes().decode() == text


def test_failed_cells_are_retried_counted_and_reported(tmp_path, sync):
    cells = grid("demo", [0, 1], {"mode": ["ok", "flaky", "broken"]})
    res = run_sweep(cells, tmp_path, client=sync, task=task, retries=2, figure=False)
    # flaky: its second start succeeds; broken: 1 + 2 retries = 3 starts, then failed
    want = {"ok": ("ok", 1, ""), "flaky": ("ok", 2, ""),
            "broken": ("failed", 3, "RuntimeError: broken cell {seed}")}
    for r in res.rows:
        status, attempts, error = want[r["mode"]]
        assert (r["status"], r["attempts"], r["error"]) == (status, attempts,
                                                            error.format(seed=r["seed"]))
    broken = [c.id for c in cells if dict(c.params)["mode"] == "broken"]
    assert res.failed == broken and not res.ok and len(res.rows) == 6 and res.ran == 6
    assert [r["cell"] for r in res.rows] == [c.id for c in cells]   # the grid's order
    failed = [r for r in res.rows if r["status"] == "failed"]
    assert all(r["seconds"] is None and r["worker"] == "" and "value" not in r for r in failed)
    # a rerun runs the failed cells again, and only them
    sync2 = SyncClient()
    again = run_sweep(cells, tmp_path, client=sync2, task=task, retries=0, figure=False)
    assert again.ran == 2 and again.skipped == 4
    assert [s["args"][1].id for s in sync2.submitted] == broken
    assert [s["retries"] for s in sync2.submitted] == [0, 0]
    assert {c.id: runs(tmp_path, c) for c in cells} == {
        c.id: {"ok": 1, "flaky": 2, "broken": 4}[dict(c.params)["mode"]] for c in cells}


def test_attempts_without_a_count_are_one_and_the_plugin_is_registered_once(tmp_path, sync):
    run_sweep(grid("demo", [0]), tmp_path / "a", client=sync, task=task, figure=False)
    run_sweep(grid("demo", [1]), tmp_path / "b", client=sync, task=task, figure=False)
    assert sync.registered == [PLUGIN_NAME]         # already on the scheduler the second time
    # a scheduler whose counter lost the cell's key (or has none): one attempt
    sync.scheduler.plugins[PLUGIN_NAME] = types.SimpleNamespace(starts={},
                                                                transition=lambda *a: None)
    res = run_sweep(grid("demo", [2], {"mode": ["broken"]}), tmp_path / "c", client=sync,
                    task=task, retries=2, figure=False)
    assert res.rows[0]["attempts"] == 1 and res.rows[0]["status"] == "failed"


def test_parameters_become_columns_in_first_seen_order(tmp_path, sync):
    cells = [Cell("demo", 0, (("b", "1"),)), Cell("demo", 1, (("a", "2"), ("b", "3")))]
    res = run_sweep(cells, tmp_path, client=sync, task=task, figure=False)
    rows = list(csv.DictReader(open(tmp_path / "results.csv")))
    assert list(rows[0])[:5] == ["cell", "scenario", "seed", "b", "a"]
    assert (rows[0]["b"], rows[0]["a"], rows[1]["b"], rows[1]["a"]) == ("1", "", "3", "2")
    assert [r["a"] for r in res.rows] == ["", "2"]


def test_refusals_word_for_word(tmp_path, sync):
    with pytest.raises(ValueError) as exc:
        run_sweep(grid("demo", [0]), tmp_path, client=sync, task=task, retries=-1)
    assert str(exc.value) == "retries must be >= 0, got -1"
    with pytest.raises(ValueError) as exc:
        run_sweep(grid("demo", [0, 0]), tmp_path, client=sync, task=task)
    assert str(exc.value) == "the grid lists the same cell twice"
    assert sync.submitted == []
    assert not (tmp_path / "cells").exists()   # a refused sweep leaves nothing on disk
    res = run_sweep(grid("demo", [0]), tmp_path, client=sync, task=task, retries=0,
                    figure=False)
    assert res.ok and sync.submitted[0]["retries"] == 0
    for out, kind, says in (("", ValueError,
                             "out must not be an empty path (use '.' for the current folder)"),
                            (5, TypeError, "out must be a path (str or os.PathLike), got int")):
        with pytest.raises(kind) as exc:
            run_sweep(grid("demo", [0]), out, client=sync, task=task)
        assert str(exc.value) == says


def test_two_retries_by_default(tmp_path, sync):
    # a cell that always fails starts 1 + 2 times when retries is not given
    res = run_sweep(grid("demo", [0], {"mode": ["broken"]}), tmp_path, client=sync, task=task,
                    figure=False)
    assert sync.submitted[0]["retries"] == 2 and res.rows[0]["attempts"] == 3
    assert runs(tmp_path, grid("demo", [0], {"mode": ["broken"]})[0]) == 3


def test_only_the_default_task_has_its_options_checked(tmp_path, sync, monkeypatch):
    checked: list[list[Cell]] = []

    class Stop(Exception):
        pass

    def check(cells: Any) -> None:
        checked.append(list(cells))
        raise Stop

    monkeypatch.setattr(sweep, "check_cells", check)
    cells = grid("demo", [0, 1])
    with pytest.raises(Stop):
        run_sweep(cells, tmp_path / "a", client=sync, task=scenario_task)
    assert checked == [cells] and not (tmp_path / "a").exists()
    run_sweep(cells, tmp_path / "b", client=sync, task=task, figure=False)
    assert len(checked) == 1


def test_a_damaged_cell_file_is_named_in_a_warning_and_run_again(tmp_path, sync):
    cells = grid("demo", [0, 1], {"gain": ["2"]})
    (tmp_path / "cells").mkdir()
    path = tmp_path / "cells" / f"{cells[0].id}.json"
    path.write_text("[1]")
    with pytest.warns(UserWarning) as caught:
        res = run_sweep(cells, tmp_path, client=sync, task=task, figure=False)
    said = [str(w.message) for w in caught if "sweep cell" in str(w.message)]
    assert said == [f"the sweep cell file is unusable ({path}: holds a list, not a cell "
                    f"record): running the cell again"]
    assert res.ran == 2 and res.skipped == 0 and load_json(path)["status"] == "ok"
    # a failed record (good as a file) is run again without a warning
    rec = load_json(path)
    save_json(path, {**rec, "status": "failed"})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = run_sweep(cells, tmp_path, client=SyncClient(), task=task, figure=False)
    assert res.ran == 1 and res.skipped == 1


def test_an_own_cluster_is_made_from_the_workers_and_closed(tmp_path, sync, monkeypatch):
    made: list[tuple[Any, int]] = []
    cluster = SyncClient()                       # anything with close()

    def connect(scheduler: Any, workers: int):
        made.append((scheduler, workers))
        return sync, (None if scheduler else cluster)

    monkeypatch.setattr(sweep, "_connect", connect)
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    with pytest.warns(RuntimeWarning, match="--workers 3 starts 3 worker processes on 2 cores"):
        run_sweep(grid("demo", [0]), tmp_path / "a", workers=3, task=task, figure=False)
    assert made == [(None, 3)] and sync.closed and cluster.closed
    sync.closed = cluster.closed = False
    with warnings.catch_warnings():
        warnings.simplefilter("error")       # a scheduler's cluster is not this machine's
        run_sweep(grid("demo", [0]), tmp_path / "b", workers=3, scheduler="tcp://s:1",
                  task=task, figure=False)
    assert made[-1] == ("tcp://s:1", 3) and sync.closed and not cluster.closed
    # a client given is the caller's: never closed
    mine = SyncClient()
    run_sweep(grid("demo", [0]), tmp_path / "c", client=mine, task=task, figure=False)
    assert not mine.closed and len(made) == 2


def test_the_own_client_is_closed_when_a_cell_breaks_the_sweep(tmp_path, sync, monkeypatch):
    cluster = SyncClient()
    monkeypatch.setattr(sweep, "_connect", lambda s, w: (sync, cluster))

    def explode(*a: Any, **k: Any) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(sync, "submit", explode)
    with pytest.raises(KeyboardInterrupt):
        run_sweep(grid("demo", [0]), tmp_path, workers=1, task=task, figure=False)
    assert sync.closed and cluster.closed


def _png_size(path: Path) -> tuple[int, int]:
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", data[16:24])


def test_the_summary_figure_is_made_at_120_dpi_or_removed(tmp_path, sync, monkeypatch):
    asked: list[tuple[Any, ...]] = []

    def summary(rows: Any, names: Any, *, metric: Any = None):
        asked.append((len(rows), list(names), metric))
        if metric == "nope":
            raise ValueError("metric 'nope' is missing")
        fig = plt.figure(figsize=(2.0, 1.0))
        asked.append(fig)
        asked.append(plt.figure())   # another figure made after it, the current one now
        return fig, None

    monkeypatch.setattr(plots, "plot_sweep_summary", summary)
    cells = grid("demo", [0, 1], {"gain": ["2"]})
    run_sweep(cells, tmp_path, client=sync, task=task, metric="value")
    assert asked[0] == (2, ["gain"], "value")
    # 2 x 1 inches at 120 dpi: 240 x 120 pixels; the figure is closed after
    assert _png_size(tmp_path / "summary.png") == (240, 120)
    assert not plt.fignum_exists(asked[1].number)     # the summary's figure, not another
    assert plt.fignum_exists(asked[2].number)
    plt.close("all")
    with pytest.warns(UserWarning) as caught:
        run_sweep(cells, tmp_path, client=sync, task=task, metric="nope")
    assert [str(w.message) for w in caught] == ["no summary figure: metric 'nope' is missing"]
    assert not (tmp_path / "summary.png").exists()     # the earlier figure is not left
    run_sweep(cells, tmp_path, client=sync, task=task)
    assert (tmp_path / "summary.png").exists()
    n = len(asked)
    run_sweep(cells, tmp_path, client=sync, task=task, figure=False)
    assert not (tmp_path / "summary.png").exists() and len(asked) == n
    # no rows (an empty grid): a table of no rows, no figure asked for
    res = run_sweep([], tmp_path / "empty", client=sync, task=task)
    assert res.rows == [] and len(asked) == n and res.ok
    assert (tmp_path / "empty" / "results.csv").read_bytes() == b"\n"
    assert sorted(p.name for p in (tmp_path / "empty").iterdir()) == ["cells", "results.csv"]


def test_parquet_is_written_beside_the_table(tmp_path, sync, monkeypatch):
    written: list[tuple[list, list, Path]] = []

    class DataFrame:
        def __init__(self, rows: list, columns: list) -> None:
            self.rows, self.columns = rows, columns

        def to_parquet(self, path: Path) -> None:
            written.append((self.rows, self.columns, Path(path)))
            Path(path).write_text(f"{len(self.rows)} rows")

    monkeypatch.setitem(sys.modules, "pandas", types.SimpleNamespace(DataFrame=DataFrame))
    cells = grid("demo", [0, 1])
    res = run_sweep(cells, tmp_path, client=sync, task=task, parquet=True, figure=False)
    assert (tmp_path / "results.parquet").read_text() == "2 rows"
    assert not (tmp_path / ".results.parquet.tmp").exists()
    assert written[0][0] == res.rows
    assert written[0][1] == ["cell", "scenario", "seed", "status", "attempts", "seconds",
                             "worker", "error", "value", "nested.half", "nan"]
    # written under a hidden temporary name first, then renamed into place
    assert written[0][2] == tmp_path / ".results.parquet.tmp"
    assert not list(tmp_path.glob("*.tmp"))


def test_parquet_without_pandas_is_refused_after_the_table(tmp_path, sync, monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)     # import pandas raises ImportError
    with pytest.raises(ImportError) as exc:
        run_sweep(grid("demo", [0]), tmp_path, client=sync, task=task, parquet=True,
                  figure=False)
    assert str(exc.value) == ("--parquet needs pandas and pyarrow: pip install pandas pyarrow "
                              "(results.csv is written)")
    assert exc.value.__suppress_context__
    assert (tmp_path / "results.csv").exists() and not (tmp_path / "results.parquet").exists()


def test_the_progress_counts_the_cells_run(tmp_path, sync, monkeypatch, capsys):
    monkeypatch.delenv("HIPPO_QUIET", raising=False)     # the progress shows when not quiet
    cells = grid("demo", [0, 1, 2])
    save_json(tmp_path / "cells" / f"{cells[0].id}.json",
              {**sweep._record(cells[0], "ok", 1, None)})
    res = run_sweep(cells, tmp_path, client=sync, task=task, figure=False)
    assert res.ran == 2 and res.skipped == 1
    err = capsys.readouterr().err
    assert "sweep: 100%" in err and "2/2" in err         # the two cells left to run


def test_the_warnings_point_at_the_caller_of_run_sweep(tmp_path, sync, monkeypatch):
    # (mutmut's trampolines add frames: checked only outside a mutation run, as in test_ica)
    if "MUTANT_UNDER_TEST" in os.environ:
        pytest.skip("stack levels are not measurable under mutmut")
    monkeypatch.setattr(sweep, "_connect", lambda s, w: (sync, None))
    monkeypatch.setattr(os, "cpu_count", lambda: 1)
    cells = grid("demo", [0])
    (tmp_path / "cells").mkdir()
    (tmp_path / "cells" / f"{cells[0].id}.json").write_text("{")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run_sweep(cells, tmp_path, workers=2, task=task, metric="nope")
    said = {str(w.message).split(" ")[0]: w.filename for w in caught}
    assert said == {"--workers": __file__, "the": __file__, "no": __file__}


def test_a_sweep_without_distributed_is_refused_word_for_word(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)   # import distributed fails
    with pytest.raises(ImportError) as exc:
        run_sweep(grid("demo", [0]), tmp_path / "never", task=task)
    assert str(exc.value) == "hippo sweep needs Dask distributed: pip install 'hippo[sweep]'"
    assert exc.value.__suppress_context__ and not (tmp_path / "never").exists()


def test_an_unknown_core_count_is_taken_as_one(tmp_path, sync, monkeypatch):
    # os.cpu_count() may be None: one core, so two local workers are warned about
    monkeypatch.setattr(sweep, "_connect", lambda s, w: (sync, None))
    monkeypatch.setattr(os, "cpu_count", lambda: None)
    with pytest.warns(RuntimeWarning, match="2 worker processes on 1 cores"):
        run_sweep(grid("demo", [0]), tmp_path, workers=2, task=task, figure=False)
