"""SMC09 room and corridor cells: ``python scenarios/two_rooms.py --out out/two-rooms``."""

import sys

from hippo.cli import run_scenario

if __name__ == "__main__":
    run_scenario("two-rooms", sys.argv[1:])
