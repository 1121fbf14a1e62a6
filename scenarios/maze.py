"""ICANN09 place cells in the big maze: ``python scenarios/maze.py --out out/maze``."""

import sys

from hippo.cli import run_scenario

if __name__ == "__main__":
    run_scenario("maze", sys.argv[1:])
