"""Two goals, two drives: a task the papers never ran, written in one short script.

A loop of corridors has two coloured floor zones, ``food`` (colour 1, south corridor) and
``water`` (colour 2, north corridor), each with its own drive; the food drive rises 2.5 times
faster. The robot first explores with the wall follower (its place cells and its map come from
that tour). Then, on a leash, the teacher walks it counter-clockwise around the loop (the way
the explorer goes) into each zone, holds it there for that zone's wait (a block) and rewards the
zone's drive as the block ends, which links the drive to that wait. Left alone, the robot heads
for the zone whose drive pulls hardest, stops there, waits as long as it was taught, moves on
when the wait is over and that drive drops, and goes to the other zone as the drives rise again.

    python scenarios/two_goals.py --out out/two-goals [--quick] [--place-cells ground-truth]

Writes ``metrics.json`` (visits, waits and drive level at arrival per zone; visit ratio against
rate ratio), ``two_goals.png`` (trajectories; drives over time) and ``run.npz`` (per tick).
"""

from __future__ import annotations

import itertools
import math
from enum import IntEnum
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from hippo.agent import Agent, AgentParams
from hippo.cli_args import Parser, add_place_cells, integer, number, out_dir
from hippo.cognitive_map import DriveParams, PlannerParams
from hippo.io import save_json
from hippo.plots.sim import draw_arena
from hippo.sim import ArenaBuilder, World
from hippo.sim.arena import Arena
from hippo.tasks import PLACE_STATES, Log, Route, Session, explore, learn_map, make_places
from hippo.types import Mode, StateKind


class Phase(IntEnum):
    EXPLORATION = 0
    LESSON = 1
    ALONE = 2


DRIVES = {"food": DriveParams(epsilon=0.02), "water": DriveParams(epsilon=0.008)}
WAIT_S = {"food": 8.0, "water": 12.0}        # how long the teacher holds the robot in each zone
PLANNER = PlannerParams(w=0.9, noise=0.0, exploration_threshold=0.05)
#: the leash route, counter-clockwise about 9 cm from the outer wall (where the explorer runs)
ROUTE = [(9, 60), (9, 30), (14, 12), (35, 9), (58, 9), (85, 9), (110, 9), (128, 10), (141, 26),
         (141, 50), (141, 75), (141, 100), (125, 101), (102, 101), (80, 101), (50, 101),
         (30, 101), (14, 94), (9, 80)]


def build_arena() -> Arena:
    """150 × 110 cm around a central block: corridors 22 (south), 28 (east), 26 (north, 18 at a
    notch) and 20 cm (west) wide, two chamfered corners: places differ within IR range."""
    b = ArenaBuilder("two-goals", 150, 110)
    b.polyline([(0, 0), (130, 0), (150, 20), (150, 110), (18, 110), (0, 92)], closed=True)
    b.box((20, 22, 122, 84))
    b.polyline([(60, 84), (60, 92), (76, 92), (76, 84)])            # notch, north corridor
    b.zone("food", (52, 0, 64, 22), colour=1).landmark("food", 58, 9)
    b.zone("water", (96, 84, 108, 110), colour=2).landmark("water", 102, 101)
    for (x0, y0), (x1, y1) in itertools.pairwise([*ROUTE, ROUTE[0]]):  # ground-truth centres
        n = max(1, round(math.hypot(x1 - x0, y1 - y0) / 12))
        for k in range(n):
            b.location(x0 + (x1 - x0) * k / n, y0 + (y1 - y0) * k / n)
    return b.start(9, 60, -math.pi / 2).build()


def main(argv: list[str] | None = None) -> dict:
    ap = Parser(prog="two_goals.py", description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=integer(0, 2**32 - 1), default=0, help="random seed")
    ap.add_argument("--out", type=out_dir, default="out/two-goals",
                    help="output folder (created if needed)")
    ap.add_argument("--quick", action="store_true",
                    help="a short run for tests and first looks: its numbers are a smoke test")
    add_place_cells(ap)
    ap.add_argument("--minutes", type=number(1.0, 600.0), default=20.0,
                    help="simulated minutes alone (quick: at most 6)")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    minutes = min(args.minutes, 6.0) if args.quick else args.minutes
    arena = build_arena()
    world = World(arena, sensors="ir8", seed=args.seed)
    dt, names = world.dt, list(DRIVES)
    log = Log(n_drives=len(names))
    route = Route(ROUTE)

    # 1. explore with the wall follower: place cells from the robot's own sensors, then the map
    tour = explore(world, round((10 if args.quick else 30) * 60 / dt), 0.0, args.seed, log)
    places = make_places(args.place_cells, arena, tour.sensors, 16 if args.quick else 24,
                         args.seed)
    agent = Agent(places, drives=DRIVES, params=AgentParams(states=PLACE_STATES, planner=PLANNER),
                  sensors=world.sensors, robot=world.robot, seed=args.seed)
    learn_map(agent, tour)
    s = Session(world, agent, log, obs=tour[-1], phase=Phase.LESSON)

    # 2. the lesson: leash into each zone, block there for its wait, reward its drive as it ends
    for _ in range(1 if args.quick else 2):
        for name in names:
            s.lead(route.leg(s.truth.pose, arena.landmarks[name]), limit=5000)
            s.block(WAIT_S[name])
            agent.reward(name)   # linked to the robot's next transition: the wait just ended
            s.run(round(10 / dt), until=lambda o: agent.kind(agent.state) != StateKind.STILL)
    s.lead(route.leg(s.truth.pose, arena.landmarks[names[0]]), limit=5000)  # close the loop

    # 3. alone: each drive rises at its own rate from where the lesson left it
    i0 = len(log)
    s.phase = Phase.ALONE
    s.run(round(minutes * 60 / dt))
    a = log.arrays()
    stops = chosen_stops(a, i0, world.robot.moving_threshold, dt)
    by_zone = {n: [s for s in stops if s[0] == k + 1] for k, n in enumerate(names)}
    visits = {n: len(s) for n, s in by_zone.items()}
    metrics = {
        "place_cells": args.place_cells, "seed": args.seed, "quick": args.quick,
        "minutes_alone": minutes, "taught_wait_s": WAIT_S,
        "learned_wait_s": {n: [agent.cells.learned_delay(t) for t in agent.drives.links(n)
                               if t in agent.cells.transitions] for n in names},
        "epsilon": {n: DRIVES[n].epsilon for n in names},
        "visits": visits, "wait_s": {n: [s[1] for s in v] for n, v in by_zone.items()},
        "drive_at_arrival": {n: [float(a["drives"][s[2], k]) for s in v]
                             for k, (n, v) in enumerate(by_zone.items())},
        "visit_order": [names[s[0] - 1] for s in stops],
        "visit_ratio": visits["food"] / visits["water"] if visits["water"] else None,
        "epsilon_ratio": DRIVES["food"].epsilon / DRIVES["water"].epsilon,
        "states": agent.layer.n_states, "transitions": len(agent.graph),
    }
    save_json(out / "metrics.json", metrics)
    s.save(out, Phase)
    plot(arena, a, i0, names, out / "two_goals.png")
    return metrics


def chosen_stops(a: dict, i0: int, threshold: float, dt: float) -> list[tuple[int, float, int]]:
    """(zone colour, seconds, first tick) of each completed stop of >= 1 s in a zone, from tick
    ``i0`` on, that the agent chose (it was in its "wait" mode)."""
    still = np.r_[0, (a["speed"][i0:] <= threshold).astype(int), 0]
    edges = np.flatnonzero(np.diff(still)) + i0
    out = []
    for s, e in zip(edges[::2], edges[1::2]):
        if (e - s) * dt >= 1.0 and e < len(a["t"]) and a["zone"][s] > 0 and \
                np.any(a["mode"][s:e] == Mode.WAIT):
            out.append((int(a["zone"][s]), round(float((e - s) * dt), 3), int(s)))
    return out


def plot(arena: Arena, a: dict, i0: int, names: list[str], path: Path) -> None:
    """Left: the arena with the lesson and the run alone. Right: drive levels over time."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 4.8), layout="constrained")
    draw_arena(arena, ax1, locations=False)
    lesson = a["phase"] == 1
    ax1.plot(a["x"][lesson], a["y"][lesson], "--", lw=1, color="tab:orange", label="lesson")
    ax1.plot(a["x"][i0:], a["y"][i0:], lw=0.5, color="tab:blue", alpha=0.7, label="alone")
    ax1.legend(loc="center", fontsize=8)
    ax1.set_title("red: food zone, green: water zone")
    t = a["t"][i0:] - a["t"][i0]
    for k, (name, c) in enumerate(zip(names, ("tab:red", "tab:green"))):
        ax2.plot(t, a["drives"][i0:, k], color=c, label=f"{name} drive")
        ax2.fill_between(t, 0, 1, where=a["zone"][i0:] == k + 1, color=c, alpha=0.2, lw=0)
    ax2.set(xlabel="time alone (s)", ylabel="drive level", ylim=(0, 1),
            title="drive levels (shaded: robot in that zone)")
    ax2.legend(loc="upper right")
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    m = main()
    print(f"visits {m['visits']} (ratio {m['visit_ratio']}, rate ratio {m['epsilon_ratio']}); "
          f"waits {m['wait_s']}; order {' '.join(m['visit_order'])}")
