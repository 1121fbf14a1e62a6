"""``hippo sweep`` on a LocalCluster: 2 workers against 1 worker on the same 16-cell grid.

Run: ``python benchmarks/sweep_speed.py [--rounds 2] [--seeds 8]``.

The grid is the timing demo (``--quick --reproductions 1``) over ``--seeds`` seeds x 2 reward
delays (16 cells by default), each cell a real scenario run in a worker process. Each round runs
the grid on a fresh 1-worker and a fresh 2-worker LocalCluster (interleaved, into fresh output
folders, so nothing is skipped); the cluster start-up is included, as a user sees it. Reported:
best wall time per configuration, the CPU time the cells took (summed from the cells'
``seconds``, wall on their worker), and the speed-up. Target (issue 14): >= 1.7x.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

from hippo.sweep import grid, run_sweep


def measure(seeds: int = 8, rounds: int = 2, *, verbose: bool = True
            ) -> dict[int, tuple[float, float]]:
    """Best wall seconds of the grid per worker count (1, 2), with the cells' summed seconds."""
    os.environ["HIPPO_QUIET"] = "1"
    cells = grid("timing-demo", list(range(seeds)), {"delay": ["2", "7"]},
                 ["--quick", "--reproductions", "1"])
    best: dict[int, tuple[float, float]] = {}
    for r in range(rounds):
        for workers in (1, 2):
            with tempfile.TemporaryDirectory() as tmp:
                t0 = time.perf_counter()
                res = run_sweep(cells, tmp, workers=workers, figure=False)
                wall = time.perf_counter() - t0
            assert res.ok and len(res.rows) == len(cells), res.failed
            busy = sum(float(row["seconds"]) for row in res.rows)
            if verbose:
                print(f"round {r}: {workers} worker(s) {wall:6.1f} s wall, cells {busy:6.1f} s",
                      flush=True)
            if wall < best.get(workers, (float("inf"), 0.0))[0]:
                best[workers] = (wall, busy)
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--seeds", type=int, default=8)
    a = ap.parse_args()
    best = measure(a.seeds, a.rounds)
    print(f"{2 * a.seeds} cells; best of {a.rounds}: 1 worker {best[1][0]:.1f} s, 2 workers "
          f"{best[2][0]:.1f} s: speed-up {best[1][0] / best[2][0]:.2f}x")


if __name__ == "__main__":
    main()
