"""Robot ticks per second (sense all rays + wall-follower controller + physics).

Run: ``python benchmarks/sim_speed.py``. Target (issue 2): >= 10,000 ticks/s in two-rooms
with the 8 IR sensors; a plain prototype reached about 14,000 with pymunk's
``segment_query_first``. The robot-only loop is compared with the same loop without sensing and
without the controller, so the table shows where the time goes.
"""

from __future__ import annotations

import time

from hippo.sim import WallFollower, WallFollowerParams, World, arenas


def bench(arena_name: str, sensors: str, ticks: int, *, sense: bool = True,
          control: bool = True, repeats: int = 3) -> float:
    arena = arenas.get(arena_name)
    best = 0.0
    for r in range(repeats):
        world = World(arena, sensors=sensors, seed=r)
        ctrl = WallFollower(WallFollowerParams(rho=0.008), sensors=sensors, rng=r)
        obs = world.reset(r)
        if not sense:
            frozen = obs.ir.copy()
            world.sense = lambda frozen=frozen: frozen  # type: ignore[method-assign]
        cmd = (3.0, 3.2)
        t0 = time.perf_counter()
        for _ in range(ticks):
            obs = world.step(ctrl.act(obs) if control else cmd)
        best = max(best, ticks / (time.perf_counter() - t0))
    return best


def main() -> None:
    rows = [
        ("two-rooms", "ir8"), ("maze-e1", "ir8"), ("maze-e1", "ray17"),
        ("goal-arena", "ir8"), ("patrol-course", "ir8"),
    ]
    print(f"{'arena':15s} {'sensors':8s} {'full ticks/s':>13s} {'no ctrl':>10s} "
          f"{'physics only':>13s}")
    for arena, sensors in rows:
        full = bench(arena, sensors, 20000)
        noctl = bench(arena, sensors, 20000, control=False)
        phys = bench(arena, sensors, 20000, control=False, sense=False)
        print(f"{arena:15s} {sensors:8s} {full:13,.0f} {noctl:10,.0f} {phys:13,.0f}")


if __name__ == "__main__":
    main()
