"""The ``hippo`` command: ``hippo run SCENARIO``, ``hippo sweep SCENARIO``,
``hippo record ARENA``, ``hippo demo``, ``hippo list``.

Each scenario is a module under :mod:`hippo.scenarios` that defines
``add_arguments(parser)`` and ``run(args) -> dict`` (the metrics it wrote), and may define
``check_args(args, parser)`` for checks that involve several arguments. The scripts in
``scenarios/`` call the same functions, so the command line and the scripts run the same code.

Every argument is checked before any work starts (:mod:`hippo.cli_args`); a mistake is one
line on stderr and exit status 2. A failure while running is one line and exit status 1
(``HIPPO_DEBUG=1`` shows the traceback).
"""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence

from hippo.cli_args import FAILURE, USAGE_ERROR, Parser, integer, out_file, probability
from hippo.runner import (
    DESCRIPTIONS,
    SCENARIOS,
    _scenario_name,
    parse_scenario_args,
    run_scenario,
    scenario_parser,
)

__all__ = ["DESCRIPTIONS", "SCENARIOS", "main", "parse_scenario_args", "record_main",
           "run_scenario", "scenario_parser"]


def record_main(argv: Sequence[str]) -> int:
    """``hippo record ARENA --ticks N --rho R --sensors ir8 --seed S --out run.npz``."""
    from hippo.sim import arenas as arena_registry

    p = Parser(prog="hippo record",
               description="Record a wall-following run (SMC09's explorer) to .npz: what the "
                           "robot sensed, and apart, where it truly was.")
    p.add_argument("arena", choices=list(arena_registry.ARENAS), metavar="ARENA",
                   help=f"one of: {', '.join(arena_registry.ARENAS)}")
    p.add_argument("--ticks", type=integer(1, 10_000_000), default=18120,
                   help="control ticks of 0.2 s")
    p.add_argument("--rho", type=probability, default=0.008,
                   help="probability per tick of switching the followed wall")
    p.add_argument("--sensors", default="ir8", choices=["ir8", "ray17"],
                   help="ir8: the e-puck of SMC09; ray17: ICANN09's 17 rays")
    p.add_argument("--seed", type=integer(0, 2**32 - 1), default=0, help="random seed")
    p.add_argument("--out", type=out_file, default="run.npz", help="the .npz file to write")
    p.add_argument("--figure", action="store_true", help="also write a trajectory PNG")
    a = p.parse_args(list(argv))
    from hippo.sim.record import record

    arena = arena_registry.get(a.arena)
    rec = record(arena, a.ticks, seed=a.seed, rho=a.rho, sensors=a.sensors)
    a.out.parent.mkdir(parents=True, exist_ok=True)
    path = rec.save(a.out)
    print(f"wrote {len(rec)} ticks to {path}", file=sys.stderr)
    if a.figure:
        from hippo.io import save_figure
        from hippo.plots.sim import plot_trajectory

        fig, _ = plot_trajectory(arena, rec)
        png = a.out.with_suffix(".png")
        save_figure(fig, png, dpi=120)
        print(f"wrote {png}", file=sys.stderr)
    return 0


def _list() -> None:
    width = max(map(len, SCENARIOS)) + 2
    print("scenarios (hippo run NAME --help for the options of one):")
    for name in SCENARIOS:
        print(f"  {name:{width}s}{DESCRIPTIONS.get(name, '')}")


def _top_parser() -> Parser:
    top = Parser(prog="hippo", description="hippocampus-inspired navigation of a simulated "
                 "robot: run its experiments, record runs")
    # the commands, for the help only: _main reads them itself (each parses its own options)
    sub = top.add_subparsers(metavar="COMMAND")
    sub.add_parser("run", help="run a scenario: hippo run NAME [options] (see hippo list)")
    sub.add_parser("demo", help="drive the robot in the two-rooms arena (same as run demo)")
    sub.add_parser("record", help="record a wall-following run to .npz")
    sub.add_parser("sweep", help="run a scenario over seeds x parameters on Dask distributed")
    sub.add_parser("list", help="list the scenarios with what each does")
    return top


def _main(argv: list[str]) -> int:
    top = _top_parser()
    if not argv or argv[0] in ("-h", "--help"):
        top.print_help()
        print()
        _list()
        return 0
    cmd, rest = argv[0], argv[1:]
    if cmd == "list":
        if rest in (["-h"], ["--help"]):   # every command takes -h; list's help is the list
            print("usage: hippo list   (the scenarios; hippo run NAME --help for the options)\n")
        elif rest:
            top.error(f"'hippo list' takes no arguments, got {' '.join(rest)!r}")
        _list()
        return 0
    if cmd == "demo":
        run_scenario("demo", rest)
        return 0
    if cmd == "sweep":
        from hippo.sweep_cli import sweep_main

        return sweep_main(rest)
    if cmd == "record":
        return record_main(rest)
    if cmd == "run":
        run_parser = Parser(prog="hippo run")
        if not rest:
            run_parser.error(f"name a scenario: {', '.join(SCENARIOS)}")
        if rest[0] in ("-h", "--help"):
            print("usage: hippo run NAME [options]   (hippo run NAME --help for the options)\n")
            _list()
            return 0
        name = _scenario_name(rest[0], run_parser)
        run_scenario(name, rest[1:])
        return 0
    top.error(f"unknown command {cmd!r}; choose from: run, demo, record, sweep, list")
    return USAGE_ERROR  # (not reached: error exits)


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``hippo`` command; returns the exit status."""
    args = list(sys.argv[1:] if argv is None else argv)
    try:
        return _main(args)
    except KeyboardInterrupt:
        print("hippo: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:
        if os.environ.get("HIPPO_DEBUG"):
            raise
        if isinstance(exc, OSError) and exc.strerror:
            where = f": {exc.filename}" if exc.filename else ""
            msg = f"{exc.strerror}{where}"
        else:
            msg = f"{type(exc).__name__}: {exc}" if str(exc).strip() else type(exc).__name__
        print(f"hippo: error: {_one_line(msg)} (HIPPO_DEBUG=1 shows where)", file=sys.stderr)
        return FAILURE


if __name__ == "__main__":
    raise SystemExit(main())
