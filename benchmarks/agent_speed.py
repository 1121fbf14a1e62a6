"""Closed-loop speed: agent ticks per second and simulated time / wall time.

Run: ``python benchmarks/agent_speed.py [--profile]``. One tick = world physics + 8 IR rays +
reservoir step + SFA/ICA readout + place prototypes + state layer + spectral timing + transition
cells + non-occurrence + drives + planner + motor. Measured after the place cells are fitted
and the map is learned (the place-preference setting, 5 Hz control), for learned and
ground-truth place cells, on one thread. HIREL's robot ran in real time at 5 Hz; the goal is
>= 500x real time on one core of the 2-core development machine.
"""

from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import time

import numpy as np

from hippo.agent import Agent, AgentParams
from hippo.cognitive_map import DriveParams, PlannerParams
from hippo.sim import WallFollower, World, arenas
from hippo.tasks import PLACE_STATES, make_places


def setup(kind: str, seed: int = 0) -> tuple[World, Agent, object]:
    arena = arenas.goal_arena()
    world = World(arena, seed=seed)
    ctrl = WallFollower(rng=seed)
    obs = world.reset(seed)
    sensors = []
    for _ in range(4000):
        obs = world.step(ctrl.act(obs))
        sensors.append(obs.ir)
    places = make_places(kind, arena, np.array(sensors), 24, seed, 32)
    params = AgentParams(states=PLACE_STATES, planner=PlannerParams(exploration_threshold=0.3))
    agent = Agent(places, drives={"sound": DriveParams(epsilon=0.02)}, params=params,
                  sensors=world.sensors, robot=world.robot, seed=seed)
    for _ in range(2000):  # learn a map first
        obs = world.step(agent.step(obs, world.truth))
    return world, agent, obs


def bench(kind: str, ticks: int) -> tuple[float, float]:
    world, agent, obs = setup(kind)
    agent.drives.set_level("sound", 0.8)
    t0 = time.perf_counter()
    for _ in range(ticks):
        obs = world.step(agent.step(obs, world.truth))
    wall = time.perf_counter() - t0
    return ticks / wall, ticks * world.dt / wall


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ticks", type=int, default=10000)
    ap.add_argument("--profile", action="store_true")
    a = ap.parse_args()
    os.environ["HIPPO_QUIET"] = "1"
    if a.profile:
        world, agent, obs = setup("learned")
        prof = cProfile.Profile()
        prof.enable()
        for _ in range(a.ticks // 2):
            obs = world.step(agent.step(obs, world.truth))
        prof.disable()
        pstats.Stats(prof).sort_stats("tottime").print_stats(18)
        return
    print(f"{'place cells':14s} {'ticks/s':>9s} {'x real time':>12s}")
    for kind in ("learned", "ground-truth"):
        tps, rt = bench(kind, a.ticks)
        print(f"{kind:14s} {tps:9,.0f} {rt:12,.0f}")


if __name__ == "__main__":
    main()
