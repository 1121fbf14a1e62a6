"""Patrol a square: a new task in a new arena, written on hippo's public API in 40 lines
(imports, arena, lesson, patrol and metrics; the command-line wrapper at the end aside).

A loop of four corridors of different widths around a block (so places differ within the
30 cm IR range). The robot explores (its place cells are learned from that tour), is walked
one lap on the leash, goes round again by itself and is held at two checkpoints (8 s east,
14 s west), then patrols alone: at each checkpoint its drive makes it stop and the learned
delay ends the wait.

    python scenarios/patrol_square.py --out out/patrol-square [--seed 0] [--quick]

These are the building blocks; ``hippo.tasks.teach_patrol`` is the whole recipe of ``hippo run
patrol`` in one call (the route, the wall side, direction-split place states, a leash for a
robot that went astray: ``scenarios/patrol_new_arena.py``).

Writes ``metrics.json`` (the waits reproduced at each checkpoint during the patrol),
``run.npz`` and ``map.graphml``.
"""

import argparse
from enum import IntEnum

from hippo.agent import Agent, AgentParams
from hippo.cognitive_map import DriveParams, PlannerParams
from hippo.io import save_json
from hippo.sim import ArenaBuilder, World
from hippo.tasks import PLACE_STATES, LapCounter, Route, Session, explore, make_places, stops

Phase = IntEnum("Phase", "EXPLORE LEASH PATROL", start=0)
ROUTE = Route([(11, 50), (11, 11), (65, 11), (117, 11), (117, 50), (117, 91), (65, 91), (11, 91)])
WAITS = {"east": ((117, 50), 8.0), "west": ((11, 50), 14.0)}
PLANNER = PlannerParams(noise=0.0, exploration_threshold=0.05)


def main(seed: int = 0, out: str = "out/patrol-square", quick: bool = False,
         place_cells: str = "learned") -> dict:
    b = ArenaBuilder("square", 130, 100).polyline(
        [(0, 0), (130, 0), (130, 84), (114, 100), (0, 100)], closed=True)
    for x, y in ROUTE.sample(12.0):   # labelled locations: analysis and ground-truth cells
        b.location(x, y)
    arena = b.box((22, 22, 104, 82)).box((60, 22, 72, 28)).start(11, 50, -1.5708).build()
    world = World(arena, seed=seed)
    tour = explore(world, (8 if quick else 20) * 300, 0.0, seed)
    places = make_places(place_cells, arena, tour.sensors, 16 if quick else 24, seed)
    places.prime(tour.sensors[-500:])   # the robot's reservoir ran all along: go on from there
    agent = Agent(places, drives=dict.fromkeys(WAITS, DriveParams(epsilon=0.01)), seed=seed,
                  params=AgentParams(states=PLACE_STATES, planner=PLANNER))
    s, lesson = Session(world, agent, obs=tour[-1], phase=Phase.LEASH), LapCounter(ROUTE)
    s.lead(ROUTE.loop_from(s.truth.pose))   # one lap on the leash: the map of the loop
    for name, (point, wait) in WAITS.items():   # the lesson: hold it at each checkpoint
        s.run(seconds=300, until=lambda o, p=point: lesson.reached(*s.truth.pose[:2], p))
        s.block(wait)
        agent.reward(name)                      # linked to the wait that just ended
    s.phase, laps = Phase.PATROL, LapCounter(ROUTE)
    for name in WAITS:
        agent.drives.set_level(name, 1.0)
    s.run(seconds=900, until=lambda o: laps.update(*s.truth.pose[:2]) >= (1 if quick else 3))
    found = stops(s.save(out, Phase), [p for p, _ in WAITS.values()], world.robot.moving_threshold)
    waits = {name: {"taught_s": w, "reproduced_s": [st["duration"] for st in found if st[
        "phase"] == Phase.PATROL and st["checkpoint"] == st["drive"] == k]}
        for k, (name, (_, w)) in enumerate(WAITS.items())}
    save_json(f"{out}/metrics.json", {"seed": seed, "laps": laps.turns, "waits": waits})
    return waits


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default="out/patrol-square")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--place-cells", choices=["learned", "ground-truth"], default="learned")
    a = ap.parse_args()
    print(main(a.seed, a.out, a.quick, a.place_cells))  # {checkpoint: taught, reproduced waits}
