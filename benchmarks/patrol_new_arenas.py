"""The patrol in arenas nobody had used, built with ``ArenaBuilder`` as a user would (issue 12).

Eleven arenas drawn up for the test of ``hippo.tasks.wall_side`` (2026-11-27): five it was
first tried on (``TUNING``) and six drawn up before any result on them was seen
(``HELD_OUT``). For each arena and seed: ``2 + seed % 3`` checkpoints and waits drawn by
:func:`hippo.tasks.random_patrol` (generator = the seed), then
:func:`hippo.tasks.teach_patrol` (30 simulated minutes of exploration, the lesson) and five
loops alone, measured per pass by a checkpoint. One JSON line per run: the route, its winding,
the wall side (``wall_side``'s choice, or the one given), passes and passes with a stop.

    python benchmarks/patrol_new_arenas.py OUT.jsonl --arenas held-out --seeds 4-9
    python benchmarks/patrol_new_arenas.py OUT.jsonl --arenas l_ring --seeds 0-1 --side 1

Measured (learned cells, fresh seeds 4-9 of the six held-out arenas): 304 of 579 passes with a
stop; with the wall side chosen before 2026-11-27, 187 of 797 (docs/results.md).
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from collections.abc import Callable
from pathlib import Path

from hippo.sim import ArenaBuilder
from hippo.sim.arena import Arena
from hippo.tasks import PatrolPhase, pass_report, random_patrol, stops, teach_patrol, wall_side
from hippo.tasks.patrol_sets import checked_route


def _arena(name: str, w: float, h: float, start: tuple[float, float, float],
           blocks: tuple = (), polys: tuple = ()) -> Arena:
    """A box of ``w`` x ``h`` cm with rectangular ``blocks`` and closed polygon ``polys``."""
    b = ArenaBuilder(name, w, h).outer_walls()
    for r in blocks:
        b = b.box(r)
    for p in polys:
        b = b.polyline(p, closed=True)
    return b.grid_locations(max(2, int(w // 20)), max(2, int(h // 20))).start(*start).build()


NORTH = 1.5708
TUNING: dict[str, Callable[[], Arena]] = {
    "l_ring": lambda: _arena("l-ring", 150, 150, (15, 60, NORTH), [(75, 75, 150, 150)], [
        [(30, 30), (120, 30), (120, 45), (45, 45), (45, 120), (30, 120)]]),
    "two_blocks": lambda: _arena("two-blocks", 230, 130, (15, 65, NORTH),
                                 [(30, 30, 100, 100), (130, 30, 200, 100)]),
    "wide_ring": lambda: _arena("wide-ring", 200, 150, (22, 75, NORTH), [(45, 45, 155, 105)]),
    "three_blocks": lambda: _arena("three-blocks", 300, 120, (15, 60, NORTH), [
        (30, 30, 90, 90), (120, 30, 180, 90), (210, 30, 270, 90)]),
    "chamfer_ring": lambda: _arena("chamfer-ring", 180, 140, (15, 70, NORTH), polys=[
        [(40, 30), (140, 30), (150, 40), (150, 110), (60, 110), (60, 100), (40, 100)]]),
}
HELD_OUT: dict[str, Callable[[], Arena]] = {
    "hex_ring": lambda: _arena("hex-ring", 200, 170, (15, 85, NORTH), polys=[
        [(60, 35), (140, 35), (165, 85), (140, 135), (60, 135), (35, 85)]]),
    "u_block": lambda: _arena("u-block", 220, 160, (15, 80, NORTH), polys=[
        [(40, 40), (180, 40), (180, 120), (140, 120), (140, 75), (80, 75), (80, 120),
         (40, 120)]]),
    "offset_ring": lambda: _arena("offset-ring", 190, 140, (15, 70, NORTH), [(30, 30, 140, 110)]),
    "four_blocks": lambda: _arena("four-blocks", 230, 200, (15, 100, NORTH), [
        (30, 30, 100, 85), (130, 30, 200, 85), (30, 115, 100, 170), (130, 115, 200, 170)]),
    "pillar_l": lambda: _arena("pillar-l", 200, 200, (15, 60, NORTH),
                               [(110, 110, 200, 200), (35, 35, 75, 75)]),
    "trapezoid_ring": lambda: _arena("trapezoid-ring", 210, 150, (15, 75, NORTH), polys=[
        [(35, 35), (175, 35), (145, 115), (65, 115)]]),
}
ARENAS = {**TUNING, **HELD_OUT}


def run(name: str, seed: int, side: int | None = None, place_cells: str = "learned",
        loops: int = 5) -> dict:
    """One patrol: ``name``'s arena, ``random_patrol``'s draw for ``seed``, ``loops`` loops."""
    arena = ARENAS[name]()
    cps, waits = random_patrol(arena, 2 + seed % 3, seed)
    kind, route = checked_route(arena, cps, waits)
    side = wall_side(route, arena, seed) if side is None else side
    lesson = teach_patrol(arena, cps, waits, seed=seed, side=side, place_cells=place_cells)
    learned = lesson.course.learned_waits()
    with warnings.catch_warnings():   # a backward patrol's PatrolWarning: counted below
        warnings.simplefilter("ignore")
        lesson.course.patrol(loops)
    arrays = lesson.session.log.arrays()
    found = stops(arrays, cps, lesson.world.robot.moving_threshold)
    rows = pass_report(arrays, lesson.course.route, cps, found, learned,
                       phase=PatrolPhase.PATROL)
    return {"arena": name, "seed": seed, "route": kind, "winding": route.winding, "side": side,
            "place_cells": place_cells, "checkpoints": cps, "waits_s": waits,
            "passes": sum(r["passes"] for r in rows),
            "stops_made": sum(r["stops_made"] for r in rows)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", type=Path, help="a JSON-lines file (appended to)")
    ap.add_argument("--arenas", default="held-out",
                    help="tuning, held-out, all, or names separated by commas")
    ap.add_argument("--seeds", default="4-9")
    ap.add_argument("--side", type=int, choices=(-1, 1), help="default: wall_side's choice")
    ap.add_argument("--place-cells", default="learned", choices=("learned", "ground-truth"))
    args = ap.parse_args()
    groups = {"tuning": list(TUNING), "held-out": list(HELD_OUT), "all": list(ARENAS)}
    names = groups.get(args.arenas, args.arenas.split(","))
    unknown = [n for n in names if n not in ARENAS]
    if unknown:
        sys.exit(f"unknown arena(s) {', '.join(unknown)}; known: {', '.join(ARENAS)}")
    a, _, b = args.seeds.partition("-")
    made = passes = 0
    for name in names:
        for seed in range(int(a), int(b or a) + 1):
            r = run(name, seed, args.side, args.place_cells)
            made, passes = made + r["stops_made"], passes + r["passes"]
            with args.out.open("a") as f:
                f.write(json.dumps(r) + "\n")
            print(f"{name} seed {seed} ({r['route']}, side {r['side']:+d}): "
                  f"{r['stops_made']} / {r['passes']}", flush=True)
    print(f"passes with a stop: {made} / {passes}")


if __name__ == "__main__":
    main()
