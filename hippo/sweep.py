"""Grids of runs on Dask distributed: ``hippo sweep SCENARIO``.

A sweep runs one scenario over a grid, seeds × parameter values, one *cell* per combination,
on a Dask ``distributed`` cluster: a :class:`~distributed.LocalCluster` on this machine by
default, or an existing cluster (``scheduler=ADDRESS``). Parameters are the scenario's own
command-line options (``leak``, ``arena``, ``waits``, ``delay`` ...), given as the strings the
command line would take, so whatever a scenario can run, a sweep can grid.

Results
-------
``OUT/cells/<cell id>.json``
    one file per finished cell, written atomically by the client as soon as the cell comes
    back: scenario, seed, parameters, status (``ok`` / ``failed``), attempts, seconds, worker,
    the error of a failed cell, and the scenario's metrics. A rerun skips cells whose file says
    ``ok`` (resumable) and runs failed ones again; a damaged file (not JSON, wrong types, or a
    seed or parameters that are not its cell's) is run again too, with a warning naming it.
``OUT/cells/<cell id>/``
    the scenario's own output folder (figures, metrics.json; on a remote cluster it is written
    on the worker, so put ``OUT`` on a shared file system to keep them).
``OUT/results.csv`` (and ``results.parquet`` with ``parquet=True``)
    one row per cell, parameters and flattened metrics (``a.b`` for nested ones) as columns;
    a metric named like a column (a scenario's own ``seed``) is left out where it says what
    the column says, and written as ``metrics.<name>`` beside it where it does not.
``OUT/summary.png``
    a chosen metric, mean ± sd over seeds, per parameter combination (removed, not left from an
    earlier sweep, when no figure is made: ``figure=False`` or a metric that is no number).

Faults
------
A cell that raises is retried ``retries`` times by the scheduler; a cell whose worker dies is
rescheduled on another worker (Dask's ``allowed-failures``). A scheduler plugin counts every start
of a cell, so the attempts a cell took are reported even when a worker was lost. A cell
that still fails is written with status ``failed`` and its error, listed at the end, and makes
:func:`run_sweep` report it (the CLI exits with status 1): never silently dropped.

Threads: each worker runs one cell at a time, with ``cores // workers`` BLAS threads
(:func:`hippo._threads.blas_budget`), so a LocalCluster never oversubscribes the machine.

Example::

    hippo sweep two-rooms --seeds 0-3 --param leak 0.05,0.15 0.11,0.14 --workers 2 -- --quick
"""

from __future__ import annotations

import csv
import io
import math
import os
import socket
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from hippo._checks import check_path
from hippo._threads import blas_budget, blas_threads

try:  # the optional extra hippo[sweep]
    from distributed.diagnostics.plugin import SchedulerPlugin
except ImportError:  # pragma: no cover - checked by run_sweep with a clear message
    SchedulerPlugin = object  # type: ignore[assignment,misc]
from hippo.io import CorruptFileError, atomic_write_text, load_json, save_figure, save_json
from hippo.progress import Progress
from hippo.sweep_cells import (
    Cell,
    CellArgumentError,
    check_cells,
    grid,
    load_cell_record,
    scenario_task,
)

__all__ = ["Cell", "CellArgumentError", "SweepResult", "check_cells", "grid", "run_sweep",
           "scenario_task"]

#: name of the scheduler plugin that counts the starts of every cell
PLUGIN_NAME = "hippo-sweep-starts"


def _run_cell(task: Callable[[Cell, str], Mapping[str, Any]], cell: Cell, out: str,
              budgets: Mapping[str, Any]) -> dict[str, Any]:
    """What a worker runs: log the start, run the task on its BLAS thread budget, time it."""
    worker = ""
    try:
        from distributed import get_worker

        worker = get_worker().address
    except ValueError:  # not on a worker (a direct call)
        pass
    t0 = time.perf_counter()
    # BLAS limits are process-wide: set them in a worker process of its own, never in
    # worker threads that share the caller's process (processes=False), where they would race
    own_process = _process_id() != budgets.get("client")
    with blas_threads(budgets.get(worker, 1) if own_process else None):
        metrics = task(cell, out)
    return {"metrics": dict(metrics or {}), "seconds": time.perf_counter() - t0,
            "worker": worker}


@dataclass
class SweepResult:
    """What a sweep produced: rows of the table (one per cell) and the failed cells."""

    out: Path
    rows: list[dict[str, Any]] = field(default_factory=list)
    failed: list[str] = field(default_factory=list)
    skipped: int = 0
    ran: int = 0

    @property
    def ok(self) -> bool:
        return not self.failed


def _flatten(d: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """Scalars of a nested metrics dict as ``a.b`` keys (lists and arrays are left out)."""
    out: dict[str, Any] = {}
    for k, v in d.items():
        key = f"{prefix}{k}"
        if isinstance(v, Mapping):
            out.update(_flatten(v, key + "."))
        elif isinstance(v, (bool, int, float, str)) or v is None:
            out[key] = v
    return out


def _record(cell: Cell, status: str, attempts: int, result: Mapping[str, Any] | None,
            error: str = "") -> dict[str, Any]:
    return {"cell": cell.id, "scenario": cell.scenario, "seed": cell.seed,
            "params": dict(cell.params), "extra": list(cell.extra), "status": status,
            "attempts": attempts, "error": error,
            "seconds": None if result is None else result["seconds"],
            "worker": "" if result is None else result["worker"],
            "metrics": {} if result is None else result["metrics"]}


def _row(rec: Mapping[str, Any], names: Sequence[str]) -> dict[str, Any]:
    row = {"cell": rec["cell"], "scenario": rec["scenario"], "seed": rec["seed"]}
    row.update({n: rec["params"].get(n, "") for n in names})
    row.update({k: rec[k] for k in ("status", "attempts", "seconds", "worker", "error")})
    for k, v in _flatten(rec["metrics"]).items():
        if k in row:   # a metric named like a column (a scenario's own "seed", "arena", ...)
            if _same(row[k], v):
                continue   # says what the column says
            k = f"metrics.{k}"   # says something else: kept beside the column, not over it
        row[k] = v
    return row


def _same(column: Any, metric: Any) -> bool:
    """Does a metric say what the column of the same name says (a parameter is the string
    the command line took: ``"0.5"`` and 0.5 agree; True and 1 do not)?"""
    if isinstance(column, bool) or isinstance(metric, bool):
        return type(column) is type(metric) and column == metric
    return column == metric or str(column) == str(metric)


def _warn_oversubscribed(workers: int, cores: int) -> bool:
    """Warn (and return True) when a LocalCluster of ``workers`` processes would run more cells
    at once than the machine has ``cores``: each cell then runs slower, and the sweep no
    faster (the default, the free cores, never does)."""
    if workers <= cores:
        return False
    warnings.warn(f"--workers {workers} starts {workers} worker processes on {cores} cores: "
                  f"they share the cores, so no cell runs faster; leave --workers out for "
                  f"the free cores, or give --scheduler for a larger cluster",
                  RuntimeWarning, stacklevel=3)
    return True


def _connect(scheduler: str | None, workers: int):
    """A client of the cluster at ``scheduler``, or of a new LocalCluster (closed by the caller)."""
    from distributed import Client, LocalCluster

    if scheduler:
        return Client(scheduler), None
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                           dashboard_address=":0")
    return Client(cluster), cluster


def run_sweep(cells: Sequence[Cell], out: str | os.PathLike, *, workers: int | None = None,
              scheduler: str | None = None, client: Any = None, retries: int = 2,
              task: Callable[[Cell, str], Mapping[str, Any]] = scenario_task,
              metric: str | None = None, parquet: bool = False,
              figure: bool = True) -> SweepResult:
    """Run ``cells`` on a Dask cluster and gather their results under ``out``.

    ``client``: an existing ``distributed.Client`` (else one is made: a LocalCluster of
    ``workers`` single-threaded worker processes, default the free cores
    (:func:`hippo._threads.free_cores`), or the cluster at ``scheduler``). ``retries``: extra
    attempts for a cell that raises. ``task(cell, out_dir)`` runs one cell and returns its
    metrics (default: the scenario, :func:`scenario_task`). Cells already finished under
    ``out`` are skipped. Returns a :class:`SweepResult`; its ``failed`` lists the cells that
    failed every attempt (also in the table). With the default task every cell's options are
    first parsed as its scenario would (:func:`check_cells`): a refused one raises
    :class:`CellArgumentError` before anything runs.
    """
    if task is scenario_task:
        check_cells(cells)
    try:
        from distributed import as_completed
    except ImportError:  # pragma: no cover - the core install
        raise ImportError("hippo sweep needs Dask distributed: pip install 'hippo[sweep]'") \
            from None
    out = check_path("out", out)
    if int(retries) < 0:
        raise ValueError(f"retries must be >= 0, got {retries}")
    ids = [c.id for c in cells]
    if len(set(ids)) != len(ids):
        raise ValueError("the grid lists the same cell twice")
    (out / "cells").mkdir(parents=True, exist_ok=True)   # only once the sweep is accepted
    result = SweepResult(out)
    records: dict[str, dict[str, Any]] = {}
    todo = []
    for c in cells:
        rec = _finished(out / "cells" / f"{c.id}.json", c)
        if rec is not None and rec["status"] == "ok":
            records[c.id] = rec
            result.skipped += 1
        else:
            todo.append(c)
    if todo:
        own_client = own_cluster = None
        if client is None:
            from hippo._threads import n_workers

            # the one rule (hippo._threads): default workers = the free cores, as the leak
            # sweep and the ICA restarts choose them, each worker with cores // workers BLAS
            # threads; on busy cores that is one worker, never more threads than cores
            if scheduler is None:
                _warn_oversubscribed(n_workers(workers), os.cpu_count() or 1)
            client, own_cluster = _connect(scheduler, n_workers(workers))
            own_client = client
        try:
            _execute(client, todo, out, task, int(retries), result, as_completed, records)
        finally:
            if own_client is not None:
                own_client.close()
            if own_cluster is not None:
                own_cluster.close()
    names = list(dict.fromkeys(n for c in cells for n, _ in c.params))
    result.rows = [_row(records[i], names) for i in ids if i in records]
    result.failed = [r["cell"] for r in result.rows if r["status"] != "ok"]
    # a summary.png of an earlier sweep never stays beside this table: replaced or removed
    (out / "summary.png").unlink(missing_ok=True)
    _write_table(result, parquet)
    if figure and result.rows:
        from hippo.plots.sweep import plot_sweep_summary

        try:
            fig, _ = plot_sweep_summary(result.rows, names, metric=metric)
        except ValueError as exc:  # a metric no cell has, or not a number: no figure
            warnings.warn(f"no summary figure: {exc}", stacklevel=2)
        else:
            save_figure(fig, out / "summary.png", dpi=120)
            import matplotlib.pyplot as plt

            plt.close(fig)
    return result


def _finished(path: Path, cell: Cell) -> dict[str, Any] | None:
    """The checked record of ``cell`` at ``path`` (:func:`~hippo.sweep_cells.load_cell_record`),
    or None when there is none; a damaged one is run again, with a warning naming the file."""
    if not path.exists():
        return None
    try:
        return load_cell_record(path, cell)
    except CorruptFileError as exc:
        warnings.warn(f"the sweep cell file is unusable ({exc}): running the cell again",
                      stacklevel=3)
        return None


def _execute(client: Any, todo: Sequence[Cell], out: Path, task: Callable, retries: int,
             result: SweepResult, as_completed: Callable,
             records: dict[str, dict[str, Any]]) -> None:
    budgets = _blas_budgets(client)
    if not client.run_on_scheduler(_has_counter):
        client.register_plugin(_StartCounter(), name=PLUGIN_NAME)
    futures = {}
    for c in todo:
        f = client.submit(_run_cell, task, c, str(out / "cells" / c.id), budgets,
                          key=f"hippo-cell-{c.id}-{time.time_ns()}", retries=retries, pure=False)
        futures[f] = c
    progress = Progress(len(todo), "sweep")
    try:
        for f in as_completed(list(futures)):
            c = futures[f]
            if f.status == "finished":
                rec = _record(c, "ok", 0, f.result())
            else:
                err = f.exception()
                rec = _record(c, "failed", 0, None, f"{type(err).__name__}: {err}")
            rec["attempts"] = max(1, client.run_on_scheduler(_starts_on).get(f.key, 1))
            path = save_json(out / "cells" / f"{c.id}.json", rec)
            records[c.id] = load_json(path)   # as a later run reads it (NaN as null ...)
            result.ran += 1
            progress.update()
    finally:
        progress.close()


def _process_id() -> str:
    return f"{socket.gethostname()}:{os.getpid()}"


def _blas_budgets(client: Any) -> dict[str, Any]:
    """BLAS threads per worker: its machine's cores shared by the worker threads on it."""
    info = client.scheduler_info().get("workers", {})
    try:
        cores = client.run(lambda: len(os.sched_getaffinity(0)))
    except Exception:  # pragma: no cover - platforms without sched_getaffinity
        return {"client": _process_id()}
    per_host: dict[str, int] = {}
    for addr, w in info.items():
        host = w.get("host", addr)
        per_host[host] = per_host.get(host, 0) + int(w.get("nthreads", 1))
    budgets: dict[str, Any] = {addr: blas_budget(per_host[w.get("host", addr)],
                                                 cores=cores.get(addr))
                               for addr, w in info.items() if addr in cores}
    budgets["client"] = _process_id()
    return budgets


class _StartCounter(SchedulerPlugin):
    """Scheduler plugin: how often each cell's task was sent to a worker (a retry after an
    error, or a reschedule after a lost worker, is another start). Counted on the scheduler,
    so a worker killed mid-cell cannot lose the count."""

    name = PLUGIN_NAME

    def __init__(self) -> None:
        self.starts: dict[str, int] = {}

    def transition(self, key: Any, start: str, finish: str, *args: Any, **kwargs: Any) -> None:
        if finish == "processing" and str(key).startswith("hippo-cell-"):
            self.starts[str(key)] = self.starts.get(str(key), 0) + 1


def _has_counter(dask_scheduler: Any = None) -> bool:
    return PLUGIN_NAME in dask_scheduler.plugins


def _starts_on(dask_scheduler: Any = None) -> dict[str, int]:
    plugin = dask_scheduler.plugins.get(PLUGIN_NAME)
    return dict(plugin.starts) if plugin is not None else {}


def _write_table(result: SweepResult, parquet: bool) -> None:
    cols: list[str] = list(dict.fromkeys(k for r in result.rows for k in r))
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=cols, lineterminator="\n")
    writer.writeheader()
    for r in result.rows:
        writer.writerow({k: _cell_text(r.get(k)) for k in cols})
    atomic_write_text(result.out / "results.csv", buf.getvalue())
    if parquet:
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("--parquet needs pandas and pyarrow: pip install pandas pyarrow "
                              "(results.csv is written)") from None

        tmp = result.out / ".results.parquet.tmp"
        pd.DataFrame(result.rows, columns=cols).to_parquet(tmp)
        os.replace(tmp, result.out / "results.parquet")


def _cell_text(v: Any) -> Any:
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return ""
    return v
