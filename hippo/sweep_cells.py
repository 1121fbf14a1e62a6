"""What a sweep runs: its cells (:class:`Cell`, one scenario run: a seed and parameter values),
the grid of them (:func:`grid`), their command lines checked before anything runs
(:func:`check_cells`) and the default task that runs one (:func:`scenario_task`). The cluster
side is :mod:`hippo.sweep`."""

from __future__ import annotations

import contextlib
import hashlib
import io
import itertools
import json
import os
import tempfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from hippo.io import CorruptFileError, load_json

__all__ = ["Cell", "CellArgumentError", "check_cells", "grid", "load_cell_record",
           "scenario_task"]


@dataclass(frozen=True)
class Cell:
    """One run of a sweep: a scenario, a seed and parameter values (scenario option -> text)."""

    scenario: str
    seed: int
    params: tuple[tuple[str, str], ...] = ()
    extra: tuple[str, ...] = ()

    @property
    def id(self) -> str:
        """Stable name: readable parameters plus a hash of everything that defines the cell."""
        text = json.dumps([self.scenario, self.seed, self.params, self.extra])
        digest = hashlib.sha1(text.encode()).hexdigest()[:10]
        return f"{self.scenario}-s{self.seed}-{digest}"

    def argv(self, out: Path) -> list[str]:
        """The scenario's command line for this cell, writing into ``out``."""
        args = ["--out", str(out), "--seed", str(self.seed)]
        for name, value in self.params:
            args += [f"--{name}", value]
        return args + list(self.extra)


def grid(scenario: str, seeds: Sequence[int], params: Mapping[str, Sequence[str]] | None = None,
         extra: Sequence[str] = ()) -> list[Cell]:
    """Every combination of ``params`` values (option -> list of values) for every seed."""
    params = dict(params or {})
    for name, values in params.items():
        if not values:
            raise ValueError(f"parameter {name!r} has no values")
    if not seeds:
        raise ValueError("seeds must list at least one seed")
    names = list(params)
    combos = list(itertools.product(*(params[n] for n in names))) if names else [()]
    return [Cell(scenario, int(s), tuple(zip(names, (str(v) for v in combo))), tuple(extra))
            for combo in combos for s in seeds]


class CellArgumentError(ValueError):
    """A cell's scenario refused its command line (the message is the scenario's own)."""


def _parse_cell(cell: Cell, out: Path) -> tuple[Any, Any]:
    """Parse ``cell``'s command line as its scenario would; a refusal (argparse's
    ``SystemExit``) becomes :class:`CellArgumentError` with the scenario's one-line message."""
    from hippo.runner import parse_scenario_args

    err = io.StringIO()
    try:
        with contextlib.redirect_stderr(err):
            return parse_scenario_args(cell.scenario, cell.argv(out))
    except SystemExit as exc:
        lines = [ln for ln in err.getvalue().splitlines() if ln.strip()]
        # "hippo run X: error: what (see hippo run X --help)": keep what, and where to look
        why = lines[-1].split(": error: ", 1)[-1] if lines else f"exit status {exc.code}"
        raise CellArgumentError(why) from None


def check_cells(cells: Sequence[Cell]) -> None:
    """Raise :class:`CellArgumentError` naming the first cell whose options its scenario
    refuses, before anything runs (each distinct set of options is parsed once, with a
    placeholder output folder that is never created)."""
    seen: set[tuple] = set()
    for c in cells:
        key = (c.scenario, c.params, c.extra)
        if key in seen:
            continue
        seen.add(key)
        try:
            _parse_cell(c, Path(tempfile.gettempdir()) / "hippo-sweep-check" / c.id)
        except CellArgumentError as exc:
            given = " ".join(f"--{n} {v}" for n, v in c.params)
            raise CellArgumentError(f"the cell {given} {' '.join(c.extra)}".rstrip()
                                    + f": {exc}") from None


def scenario_task(cell: Cell, out: str) -> dict[str, Any]:
    """Run ``cell``'s scenario with its output in ``out``; returns the scenario's metrics (what
    it prints goes to ``out/log.txt``, not to the sweep's terminal). A command line the
    scenario refuses raises :class:`CellArgumentError` (never ``SystemExit``, which would take
    the worker process down with it)."""
    os.environ.setdefault("HIPPO_QUIET", "1")
    args, module = _parse_cell(cell, Path(out))
    Path(out).mkdir(parents=True, exist_ok=True)
    with open(Path(out) / "log.txt", "w") as log, contextlib.redirect_stdout(log):
        try:
            return module.run(args)
        except SystemExit as exc:  # a scenario that exits (e.g. --resume refused)
            raise RuntimeError(f"the scenario exited ({exc.code})") from None


def load_cell_record(path: Path, cell: Cell) -> dict[str, Any]:
    """The record a sweep wrote for ``cell`` at ``path``, checked like hippo's other loaders
    (they trust nothing): a JSON object of the right types whose scenario, seed, parameters and
    options are the cell's own (a file under another cell's id is not this cell's result).
    Anything else raises :class:`~hippo.io.CorruptFileError` saying what is wrong."""
    rec = load_json(path)
    why = _record_problem(rec, cell)
    if why:
        raise CorruptFileError(f"{path}: {why}")
    return rec


def _record_problem(rec: Any, cell: Cell) -> str:
    """What is wrong with ``rec`` as ``cell``'s record ("" if nothing)."""
    if not isinstance(rec, dict):
        return f"holds a {type(rec).__name__}, not a cell record"
    kinds = {"cell": str, "scenario": str, "seed": int, "params": dict, "extra": list,
             "status": str, "attempts": int, "error": str, "worker": str, "metrics": dict}
    for key, kind in kinds.items():
        v = rec.get(key)
        if not isinstance(v, kind) or isinstance(v, bool):
            return f"{key} must be a {kind.__name__}, got {v!r:.60}"
    seconds = rec.get("seconds")
    if seconds is not None and (isinstance(seconds, bool) or not isinstance(seconds, int | float)):
        return f"seconds must be a number or null, got {seconds!r:.60}"
    if rec["status"] not in ("ok", "failed"):
        return f"status must be ok or failed, got {rec['status']!r:.60}"
    if rec["attempts"] < 1:
        return f"attempts must be >= 1, got {rec['attempts']}"
    if not all(isinstance(k, str) for k in rec["metrics"]):
        return "metrics must be keyed by names"
    mine = {"cell": cell.id, "scenario": cell.scenario, "seed": cell.seed,
            "params": dict(cell.params), "extra": list(cell.extra)}
    for key, want in mine.items():
        if rec[key] != want:
            return (f"its {key} is {rec[key]!r:.80}, the cell's {want!r:.80} (the file "
                    "belongs to another cell, or was edited)")
    return ""
