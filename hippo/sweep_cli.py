"""``hippo sweep SCENARIO``: the command line of :mod:`hippo.sweep` (a grid of scenario runs on
Dask distributed)."""

from __future__ import annotations

import importlib.util
import sys
import warnings
from collections.abc import Sequence
from pathlib import Path

from hippo.cli_args import Parser, integer, out_dir, seed_ranges
from hippo.sweep import CellArgumentError, grid, run_sweep

__all__ = ["sweep_main"]


def sweep_main(argv: Sequence[str]) -> int:
    """``hippo sweep SCENARIO [options] [-- scenario options for every cell]``."""
    from hippo.runner import SCENARIOS, scenario_parser

    argv = list(argv)
    extra: list[str] = []
    if "--" in argv:
        i = argv.index("--")
        argv, extra = argv[:i], argv[i + 1:]
    ap = Parser(
        prog="hippo sweep", description="Run a scenario over seeds x parameters on Dask "
        "distributed (a LocalCluster unless --scheduler is given); resumable.",
        epilog="Options after -- go to every cell's scenario (e.g. -- --quick).")
    ap.add_argument("scenario", choices=sorted(SCENARIOS))
    ap.add_argument("--seeds", type=seed_ranges, default="0", help="e.g. 0-3 or 0,2,5")
    ap.add_argument("--param", nargs="+", action="append", metavar=("NAME", "VALUE"),
                    help="a scenario option and its values, e.g. --param leak 0.05,0.15 "
                    "0.11,0.14 (repeat for more; the grid is every combination)")
    ap.add_argument("--out", type=out_dir, help="output folder (default out/sweep-SCENARIO)")
    ap.add_argument("--workers", type=integer(1, 1024),
                    help="LocalCluster worker processes (default: the free cores, i.e. the "
                    "usable cores less the load of other processes)")
    ap.add_argument("--scheduler", help="address of an existing Dask scheduler")
    ap.add_argument("--retries", type=integer(0, 100), default=2,
                    help="extra attempts of a failing cell")
    ap.add_argument("--metric", help="metric of the summary figure")
    ap.add_argument("--parquet", action="store_true", help="also write results.parquet")
    a = ap.parse_args(argv)   # --workers and --retries are checked by their types
    params: dict[str, list[str]] = {}
    parser, _ = scenario_parser(a.scenario)
    known = {s.lstrip("-") for act in parser._actions for s in act.option_strings}
    for item in a.param or []:   # (no default: "(default: [])" in the help said nothing)
        name, values = item[0].lstrip("-"), item[1:]
        if name in ("save", "load"):
            ap.error(f"--param {name}: a sweep runs every cell from scratch, into its own "
                     "folder (no snapshot is saved or loaded)")
        if name not in known or name in ("out", "seed", "h", "help"):   # help: no cell runs
            ap.error(f"--param {name}: not an option of scenario {a.scenario!r} (choose from: "
                     f"{', '.join(sorted(known - {'out', 'seed', 'save', 'load', 'h', 'help'}))})")
        if not values:
            ap.error(f"--param {name} needs at least one value")
        if name in params:
            ap.error(f"--param {name} is given twice: list all its values after one --param")
        twice = sorted({v for v in values if values.count(v) > 1})
        if twice:
            ap.error(f"--param {name} lists {', '.join(twice)} more than once")
        params[name] = values
    # options after -- go to every cell alike: none may set what the sweep sets per cell
    for tok in extra:
        opt = tok.split("=", 1)[0]
        if not opt.startswith("--") and opt != "-h":
            continue
        name = _full_name(opt.lstrip("-"), known)
        if name in ("h", "help"):
            ap.error(f"{opt} after --: a cell runs its scenario, not its help (hippo run "
                     f"{a.scenario} --help lists the options)")
        if name in ("seed", "seeds", "out"):
            ap.error(f"{opt} after --: the sweep sets each cell's seed and output folder "
                     "(use hippo sweep's --seeds and --out)")
        if name == "save":
            ap.error(f"{opt} after --: every cell would write the same snapshot folder")
        if name == "load":
            ap.error(f"{opt} after --: every cell would run the snapshot's robot, made with "
                     "the snapshot's seed, whatever the cell's seed (a sweep runs each cell "
                     "from scratch)")
        if name in params:
            ap.error(f"{opt} after -- is also a --param of the sweep: give its values there")
    if a.parquet and not all(importlib.util.find_spec(m) for m in ("pandas", "pyarrow")):
        ap.error("--parquet needs pandas and pyarrow (pip install pandas pyarrow); they are "
                 "not installed")
    from hippo.plots.sweep import BOOKKEEPING, numeric_metrics

    if a.metric in BOOKKEEPING or a.metric in params:
        ap.error(f"--metric {a.metric}: a column the sweep writes itself (its cells' "
                 "bookkeeping or a --param), not a metric of the scenario")
    cells = grid(a.scenario, a.seeds, params, extra)
    out = Path(a.out or f"out/sweep-{a.scenario}")
    try:  # run_sweep parses every cell's options before anything runs (check_cells)
        with warnings.catch_warnings():   # a --metric no cell has: said below, and exit 1
            warnings.filterwarnings("ignore", message="no summary figure")
            res = run_sweep(cells, out, workers=a.workers, scheduler=a.scheduler,
                            retries=a.retries, metric=a.metric, parquet=a.parquet)
    except CellArgumentError as exc:
        ap.error(str(exc))
    print(f"{len(cells)} cells: {res.ran} run, {res.skipped} already done, "
          f"{len(res.failed)} failed; table {out / 'results.csv'}")
    have = numeric_metrics(res.rows, list(params))
    missing = a.metric is not None and bool(res.rows) and a.metric not in have
    if missing:
        what = (f"the metric {a.metric!r} is not a number in any finished cell"
                if any(a.metric in r for r in res.rows) else
                f"no cell has the metric {a.metric!r}")
        print(f"hippo sweep: no summary figure: {what} (numeric metrics: "
              f"{', '.join(have) or 'none'})", file=sys.stderr)
    for r in res.rows:
        if r["cell"] in res.failed:
            given = {n: r[n] for n in params}
            print(f"  FAILED {r['cell']} (seed {r['seed']}, {given}) after {r['attempts']} "
                  f"attempt(s): {r['error']}")
    return 0 if res.ok and not missing else 1


def _full_name(name: str, known: set[str]) -> str:
    """The option ``name`` stands for: argparse also takes a unique prefix (``--lo`` for
    ``--load``), so the checks of the options after ``--`` look through it."""
    if name in known:
        return name
    longer = [k for k in known if k.startswith(name)]
    return longer[0] if len(longer) == 1 else name
