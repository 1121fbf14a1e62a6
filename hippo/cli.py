"""The ``hippo`` command: ``hippo run SCENARIO``, ``hippo record ARENA``, ``hippo demo``.

Each scenario is a module under :mod:`hippo.scenarios` that defines
``add_arguments(parser)`` and ``run(args) -> dict`` (the metrics it wrote). The scripts in
``scenarios/`` call the same functions, so the command line and the scripts run the same code.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

#: scenario name -> module implementing it
SCENARIOS: dict[str, str] = {
    "demo": "hippo.scenarios.demo",
    "two-rooms": "hippo.scenarios.two_rooms",
    "maze": "hippo.scenarios.maze",
    "timing-demo": "hippo.scenarios.timing_demo",
    "place-preference": "hippo.scenarios.place_preference",
    "patrol": "hippo.scenarios.patrol",
}


def scenario_parser(name: str, prog: str | None = None) -> tuple[argparse.ArgumentParser, object]:
    """The argument parser of scenario ``name`` (common options plus its own) and its module."""
    if name not in SCENARIOS:
        raise SystemExit(f"unknown scenario {name!r}; choose from: {', '.join(SCENARIOS)}")
    module = importlib.import_module(SCENARIOS[name])
    parser = argparse.ArgumentParser(prog=prog or f"hippo run {name}",
                                     description=(module.__doc__ or "").strip().splitlines()[0])
    parser.add_argument("--out", default=f"out/{name}", help="output folder (default: %(default)s)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default: %(default)s)")
    parser.add_argument("--quick", action="store_true",
                        help="a short version for tests and first looks")
    module.add_arguments(parser)
    return parser, module


def run_scenario(name: str, argv: Sequence[str] = ()) -> dict:
    """Parse ``argv`` for scenario ``name``, run it, and return its metrics."""
    parser, module = scenario_parser(name)
    args = parser.parse_args(list(argv))
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


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    top = argparse.ArgumentParser(prog="hippo", description=__doc__.strip().splitlines()[0])
    sub = top.add_subparsers(dest="command", required=True)
    p_run = sub.add_parser("run", help="run a scenario", add_help=False)
    p_run.add_argument("scenario", choices=sorted(SCENARIOS))
    sub.add_parser("demo", help="drive the robot in the two-rooms arena (same as run demo)",
                   add_help=False)
    sub.add_parser("record", help="record a wall-following run to .npz", add_help=False)
    sub.add_parser("list", help="list the scenarios")
    if not argv or argv[0] in ("-h", "--help"):
        top.print_help()
        return 0
    cmd, rest = argv[0], argv[1:]
    if cmd == "list":
        for name, mod in SCENARIOS.items():
            print(f"{name:18s} {mod}")
        return 0
    if cmd == "demo":
        run_scenario("demo", rest)
        return 0
    if cmd == "record":
        return record_main(rest)
    if cmd == "run":
        if not rest or rest[0] in ("-h", "--help"):
            p_run.print_help()
            print("\nscenarios: " + ", ".join(SCENARIOS))
            return 0
        run_scenario(rest[0], rest[1:])
        return 0
    top.parse_args(argv)  # prints the error for an unknown command
    return 2


if __name__ == "__main__":
    raise SystemExit(main())
