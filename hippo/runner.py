"""The scenario runner: the registry of scenarios, their argument parsers, and running one.

Each scenario is a module under :mod:`hippo.scenarios` that defines
``add_arguments(parser)`` and ``run(args) -> dict`` (the metrics it wrote), and may define
``check_args(args, parser)`` for checks that involve several arguments. The command line
(:mod:`hippo.cli`) and the sweeps (:mod:`hippo.sweep`) both run scenarios through here; the
modules are imported by name, when a scenario is run.
"""

from __future__ import annotations

import argparse
import importlib
import re
from collections.abc import Sequence
from types import ModuleType
from typing import Any

from hippo.cli_args import MAX_SEED, Parser, integer, out_dir

#: scenario name -> module implementing it
SCENARIOS: dict[str, str] = {
    "demo": "hippo.scenarios.demo",
    "two-rooms": "hippo.scenarios.two_rooms",
    "maze": "hippo.scenarios.maze",
    "timing-demo": "hippo.scenarios.timing_demo",
    "place-preference": "hippo.scenarios.place_preference",
    "patrol": "hippo.scenarios.patrol",
    "rooms": "hippo.scenarios.rooms",
    "deployment": "hippo.scenarios.deployment",
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
    "rooms": "place cells in generated multi-room flats: one cell per room, decoding over "
             "rooms, kidnapping, the supervised ceiling",
    "deployment": "the learned patrol alone for hours; failures counted the RatSLAM way, "
                  "health sampled, resumable after a crash",
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
    parser.add_argument("--seed", type=integer(0, MAX_SEED), default=0, help="random seed")
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
