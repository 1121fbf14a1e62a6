"""Closed-loop speed: the brain's tick against the physics' tick, and simulated / wall time.

Run: ``python benchmarks/agent_speed.py [--ticks N] [--rounds R] [--profile]``.

One agent tick = reservoir step + SFA/ICA readout + place prototypes + state layer + spectral
timing + transition cells + non-occurrence + drives + planner + motor (``Agent.step``). Its peer,
measured in the same process and interleaved with it round by round, is the cheapest robot that
moves at all: one world tick (pymunk physics + 8 IR rays) plus SMC09's wall follower. Measured
after the place cells are fitted and the map is learned (the place-preference setting, 5 Hz
control), for learned and ground-truth place cells, on one BLAS thread; best of ``--rounds``
rounds, wall time and process CPU time. Targets (issue 14): agent tick <= 2 x (world +
wall-follower tick); the full closed loop (agent + world) >= 1,500 x real time.
``--sectors 4 --hop-time 5`` measures the patrol's setting (each place state split by the
direction of travel: 4 x the place inputs; drives discounted by the learned time to a goal).
"""

from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import time

import numpy as np
from threadpoolctl import threadpool_limits

from hippo.agent import Agent, AgentParams
from hippo.cognitive_map import DriveParams, PlannerParams
from hippo.sim import WallFollower, World, arenas
from hippo.tasks import PLACE_STATES, make_places


def setup(kind: str, seed: int = 0, sectors: int = 1, hop_time: float | None = None
          ) -> tuple[World, Agent, object]:
    arena = arenas.goal_arena()
    world = World(arena, seed=seed)
    ctrl = WallFollower(rng=seed)
    obs = world.reset(seed)
    sensors = []
    for _ in range(4000):
        obs = world.step(ctrl.act(obs))
        sensors.append(obs.ir)
    places = make_places(kind, arena, np.array(sensors), 24, seed, 32)
    params = AgentParams(states=PLACE_STATES, heading_sectors=sectors,
                         planner=PlannerParams(exploration_threshold=0.3, hop_time=hop_time))
    agent = Agent(places, drives={"sound": DriveParams(epsilon=0.02)}, params=params,
                  sensors=world.sensors, robot=world.robot, seed=seed)
    for _ in range(2000):  # learn a map first
        obs = world.step(agent.step(obs, world.truth))
    agent.drives.set_level("sound", 0.8)
    return world, agent, obs


class Clock:
    """Wall and process CPU seconds summed over the calls it times."""

    def __init__(self) -> None:
        self.wall = self.cpu = 0.0

    def __call__(self, f, *args):
        w, c = time.perf_counter(), time.process_time()
        out = f(*args)
        self.wall += time.perf_counter() - w
        self.cpu += time.process_time() - c
        return out


def one_round(agent_world, peer_world, ticks: int) -> dict[str, tuple[float, float]]:
    """Run ``ticks`` closed-loop ticks, then ``ticks`` wall-follower ticks; seconds per tick."""
    world, agent, obs = agent_world
    t_agent, t_world = Clock(), Clock()
    for _ in range(ticks):
        obs = t_world(world.step, t_agent(agent.step, obs, world.truth))
    agent_world[2] = obs
    pworld, ctrl, pobs = peer_world
    t_pworld, t_ctrl = Clock(), Clock()
    for _ in range(ticks):
        pobs = t_pworld(pworld.step, t_ctrl(ctrl.act, pobs))
    peer_world[2] = pobs
    return {name: (c.wall / ticks, c.cpu / ticks) for name, c in
            (("agent", t_agent), ("world", t_world), ("peer world", t_pworld),
             ("wall follower", t_ctrl))}


def bench(kind: str, ticks: int, rounds: int, sectors: int = 1, hop_time: float | None = None
          ) -> dict[str, tuple[float, float]]:
    world, agent, obs = setup(kind, sectors=sectors, hop_time=hop_time)
    pworld = World(arenas.goal_arena(), seed=1)
    peer = [pworld, WallFollower(rng=1), pworld.reset(1)]
    loop = [world, agent, obs]
    best: dict[str, tuple[float, float]] = {}
    for _ in range(rounds):
        for k, (w, c) in one_round(loop, peer, ticks).items():
            bw, bc = best.get(k, (np.inf, np.inf))
            best[k] = (min(bw, w), min(bc, c))
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ticks", type=int, default=2000, help="ticks per round")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--profile", action="store_true")
    ap.add_argument("--sectors", type=int, default=1,
                    help="BrainParams.heading_sectors (the patrol's learned cells use 4)")
    ap.add_argument("--hop-time", type=float, default=None,
                    help="PlannerParams.hop_time (the patrol's: 5 s; default: per hop)")
    a = ap.parse_args()
    os.environ["HIPPO_QUIET"] = "1"
    with threadpool_limits(1):
        if a.profile:
            world, agent, obs = setup("learned", sectors=a.sectors, hop_time=a.hop_time)
            prof = cProfile.Profile()
            prof.enable()
            for _ in range(a.ticks):
                obs = world.step(agent.step(obs, world.truth))
            prof.disable()
            pstats.Stats(prof).sort_stats("tottime").print_stats(25)
            return
        print(f"best of {a.rounds} rounds x {a.ticks} ticks; µs per tick, wall (process CPU)")
        print(f"{'place cells':13s} {'agent':>13s} {'world':>13s} {'world+WF':>13s} "
              f"{'agent/(world+WF)':>17s} {'loop x real time':>17s}")
        for kind in ("learned", "ground-truth"):
            b = bench(kind, a.ticks, a.rounds, a.sectors, a.hop_time)
            ag, wo = b["agent"], b["world"]
            peer = tuple(x + y for x, y in zip(b["peer world"], b["wall follower"]))
            dt = 0.2
            print(f"{kind:13s} {ag[0]*1e6:6.0f} ({ag[1]*1e6:4.0f}) {wo[0]*1e6:6.0f} "
                  f"({wo[1]*1e6:4.0f}) {peer[0]*1e6:6.0f} ({peer[1]*1e6:4.0f}) "
                  f"{ag[0]/peer[0]:9.2f} ({ag[1]/peer[1]:4.2f}) "
                  f"{dt/(ag[0]+wo[0]):9,.0f} ({dt/(ag[1]+wo[1]):5,.0f})")


if __name__ == "__main__":
    main()
