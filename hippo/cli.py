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

import argparse
import importlib
import os
import re
import sys
from collections.abc import Sequence
from types import ModuleType
from typing import Any

from hippo.cli_args import FAILURE, USAGE_ERROR, Parser, integer, out_dir

#: scenario name -> module implementing it
SCENARIOS: dict[str, str] = {
    "demo": "hippo.scenarios.demo",
    "two-rooms": "hippo.scenarios.two_rooms",
    "maze": "hippo.scenarios.maze",
    "timing-demo": "hippo.scenarios.timing_demo",
    "place-preference": "hippo.scenarios.place_preference",
    "patrol": "hippo.scenarios.patrol",
    "rooms": "hippo.scenarios.rooms",
}
#: scenario name -> what it does, in one line (``hippo list``)
DESCRIPTIONS: dict[str, str] = {
    "demo": "drive the robot with SMC09's wall follower in an arena; plot its path and sensors",
    "two-rooms": "SMC09: place cells learned from 8 IR sensors in two rooms; room cell and "
                 "recovery from kidnapping",
    "maze": "ICANN09: 70 place cells learned in a big maze; localized units and decoding",
    "timing-demo": "time cells and NLMS transition cells learn delays and reproduce them "
                   "(HIREL Table I)",
    "place-preference": "HIREL III-A: go to a goal zone, wait for the reward sound, give up "
                        "in extinction",
    "patrol": "HIREL III-B: learn a loop on a leash and three checkpoint waits, then patrol "
              "alone",
}


def _plain(text: str) -> str:
    """reST markup out of a docstring for the terminal (``x`` -> x, :class:`X` -> X)."""
    text = re.sub(r":\w+:`~?([^`]+)`", r"\1", text)
    text = re.sub(r"``([^`]+)``", r"\1", text)
    return re.sub(r"\*\*([^*]+)\*\*", r"\1", text)


def _scenario_name(name: str, parser: Parser) -> str:
    if name not in SCENARIOS:
        parser.error(f"unknown scenario {name!r}; choose from: {', '.join(SCENARIOS)}")
    return name


def scenario_parser(name: str, prog: str | None = None) -> tuple[argparse.ArgumentParser,
                                                                    ModuleType]:
    """The argument parser of scenario ``name`` (common options plus its own) and its module."""
    name = _scenario_name(name, Parser(prog=prog or "hippo run"))
    module = importlib.import_module(SCENARIOS[name])
    doc = _plain((module.__doc__ or "").strip())
    parser = Parser(prog=prog or f"hippo run {name}", description=doc)
    parser.add_argument("--out", type=out_dir, default=f"out/{name}",
                        help="output folder (created if needed)")
    parser.add_argument("--seed", type=integer(0, 2**32 - 1), default=0, help="random seed")
    parser.add_argument("--quick", action="store_true",
                        help="a short run for tests and first looks: its numbers are a smoke "
                             "test, not results")
    module.add_arguments(parser)
    return parser, module


def parse_scenario_args(name: str, argv: Sequence[str] = (), prog: str | None = None
                        ) -> tuple[argparse.Namespace, ModuleType]:
    """Parse and check ``argv`` for scenario ``name`` (exit status 2 on a mistake)."""
    parser, module = scenario_parser(name, prog)
    args = parser.parse_args(list(argv))
    check = getattr(module, "check_args", None)
    if check is not None:
        check(args, parser)
    return args, module


def run_scenario(name: str, argv: Sequence[str] = ()) -> dict[str, Any]:
    """Parse ``argv`` for scenario ``name``, run it, and return its metrics."""
    args, module = parse_scenario_args(name, argv)
    return module.run(args)


def record_main(argv: Sequence[str]) -> int:
    """``hippo record ARENA --ticks N --rho R --sensors ir8 --seed S --out run.npz``."""
    from hippo.sim import arenas as arena_registry
    from hippo.sim.record import record

    p = argparse.ArgumentParser(prog="hippo record",
                                description="Record a wall-following run to .npz")
    p.add_argument("arena", help=f"one of: {', '.join(arena_registry.ARENAS)}")
    p.add_argument("--ticks", type=int, default=18120)
    p.add_argument("--rho", type=float, default=0.008)
    p.add_argument("--sensors", default="ir8", choices=["ir8", "ray17"])
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--out", default="run.npz")
    p.add_argument("--figure", action="store_true", help="also write a trajectory PNG")
    a = p.parse_args(list(argv))
    try:
        arena = arena_registry.get(a.arena)
    except ValueError as exc:
        p.error(str(exc))
    rec = record(arena, a.ticks, seed=a.seed, rho=a.rho, sensors=a.sensors)
    path = rec.save(a.out)
    print(f"wrote {len(rec)} ticks to {path}", file=sys.stderr)
    if a.figure:
        from pathlib import Path

        from hippo.io import save_figure
        from hippo.plots.sim import plot_trajectory

        fig, _ = plot_trajectory(arena, rec)
        png = Path(a.out).with_suffix(".png")
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
    sub = top.add_subparsers(dest="command", metavar="COMMAND")
    sub.add_parser("run", help="run a scenario: hippo run NAME [options] (see hippo list)",
                   add_help=False)
    sub.add_parser("demo", help="drive the robot in the two-rooms arena (same as run demo)",
                   add_help=False)
    sub.add_parser("record", help="record a wall-following run to .npz", add_help=False)
    sub.add_parser("sweep", help="run a scenario over seeds x parameters on Dask distributed",
                   add_help=False)
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
        if rest:
            top.error(f"'hippo list' takes no arguments, got {' '.join(rest)!r}")
        _list()
        return 0
    if cmd == "demo":
        run_scenario("demo", rest)
        return 0
    if cmd == "sweep":
        from hippo.sweep import sweep_main

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
            msg = f"{type(exc).__name__}: {exc}"
        print(f"hippo: error: {_one_line(msg)} (HIPPO_DEBUG=1 shows where)", file=sys.stderr)
        return FAILURE


if __name__ == "__main__":
    raise SystemExit(main())
