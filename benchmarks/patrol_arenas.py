"""The patrol on other arenas with checkpoints and waits nobody chose (issue 12, part 2).

For each arena and seed: ``2 + seed % 3`` checkpoints and their waits drawn by
:func:`hippo.tasks.patrol.random_patrol` (generator = the seed), then ``hippo run patrol``
with them on ground-truth and on learned place cells. Prints, per arena and place cells:
passes with a stop / passes, stops whose wait is within 3 % of the learned one, loops
reproduced (reproduction phase >= 0.9 laps) and patrol loops completed; and, without the
route (:func:`hippo.tasks.patrol.patrol_rounds`), the patrol's rounds with every checkpoint
served and its stops that served a checkpoint / all its stops at checkpoints.

    python benchmarks/patrol_arenas.py OUT --seeds 100-109 [--quick]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

from hippo.sim.robot import RobotParams
from hippo.tasks import stops
from hippo.tasks.patrol import PatrolPhase, patrol_rounds, random_patrol

ARENAS = ("two-rooms", "goal-arena", "maze")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("out", type=Path)
    ap.add_argument("--seeds", default="100-109")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--place-cells", default="ground-truth,learned")
    args = ap.parse_args()
    a, _, b = args.seeds.partition("-")
    seeds = range(int(a), int(b or a) + 1)
    for seed in seeds:
        for arena in ARENAS:
            cps, waits = random_patrol(arena, 2 + seed % 3, seed)
            for pc in args.place_cells.split(","):
                out = args.out / f"{arena}_{pc}_s{seed}"
                if (out / "metrics.json").exists():
                    continue
                cmd = [sys.executable, "-m", "hippo.cli", "run", "patrol", "--arena", arena,
                       "--seed", str(seed), "--place-cells", pc, "--out", str(out),
                       "--checkpoints", ";".join(f"{x:g},{y:g}" for x, y in cps),
                       "--waits", ",".join(f"{w:g}" for w in waits)]
                if args.quick:
                    cmd.append("--quick")
                done = subprocess.run(cmd, check=False, capture_output=True, text=True)
                if done.returncode != 0:  # say so: a failed run would only be missing
                    print(f"FAILED ({done.returncode}): {' '.join(cmd)}\n"
                          f"{done.stderr[-2000:]}", file=sys.stderr)
    table(args.out)


def table(folder: Path) -> None:
    rows: dict[tuple[str, str], list[dict]] = {}
    for f in sorted(folder.glob("*/metrics.json")):
        m = json.loads(f.read_text())
        with np.load(f.parent / "run.npz") as z:
            made = stops(dict(z), m["checkpoints_cm"], RobotParams().moving_threshold,
                         taught_phase=PatrolPhase.CHECKPOINTS)
        m["rounds"] = patrol_rounds(made, len(m["checkpoints_cm"]), phase=PatrolPhase.PATROL)
        rows.setdefault((m["arena"], m["place_cells"]), []).append(m)
    print("| arena | place cells | seeds | passes with a stop | extra / misplaced stops | "
          "waits within 3 % | loops reproduced | runs with every patrol loop done | rounds "
          "(every checkpoint served) | stops serving / made |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for (arena, pc), ms in sorted(rows.items()):
        made = sum(m["checkpoint_stops_made"] for m in ms)
        exp = sum(m["checkpoint_stops_expected"] for m in ms)
        extra = sum(m["extra_stops"] for m in ms)
        mis = sum(m["misplaced_stops"] for m in ms)
        errs = [abs(w - r["learned_wait_s"]) / r["learned_wait_s"] for m in ms
                for r in m["checkpoints"] if r["learned_wait_s"] for w in r["reproduced_waits_s"]]
        ok = sum(e <= 0.03 for e in errs)
        rep = sum(m["reproduced_loop_fraction"] >= 0.9 for m in ms)
        done = sum(m["loop_completion"] >= 1.0 for m in ms)
        seeds = ",".join(str(m["seed"]) for m in ms)
        rounds = sum(m["rounds"][0] for m in ms)
        serving, stopped = (sum(m["rounds"][k] for m in ms) for k in (1, 2))
        print(f"| {arena} | {pc} | {seeds} | {made}/{exp} | {extra} / {mis} | {ok}/{len(errs)} "
              f"| {rep}/{len(ms)} | {done}/{len(ms)} | {rounds} | {serving}/{stopped} |")


if __name__ == "__main__":
    main()
