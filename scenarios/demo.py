"""Drive the robot in the two-rooms arena: ``python scenarios/demo.py --out out/demo``."""

import sys

from hippo.cli import run_scenario

if __name__ == "__main__":
    run_scenario("demo", sys.argv[1:])
