"""The thread rule on a leak sweep: the default never slower than one worker.

Run: ``python benchmarks/leak_sweep_threads.py [--ticks 8000] [--rounds 2] [--busy 0 2]``.

``fit_leak_sweep`` over 16 leak pairs (one SMC09 reservoir, 600 neurons) with the default
workers (``free_cores()``: the usable cores minus the load of other processes), with
``workers=1`` and with ``workers=2`` forced, interleaved, best of ``--rounds``, wall and process
CPU time. ``--busy K`` also measures with K extra processes spinning on the cores (started and
stopped by this script), to see the default on busy cores; the machine's own load is printed.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import os
import time

import numpy as np

from hippo._threads import free_cores
from hippo.perception import RCSFAICAParams, fit_leak_sweep

LEAKS = [(a, b) for a in (0.05, 0.08, 0.11, 0.14) for b in (0.11, 0.14, 0.15, 0.2)]


def spin() -> None:  # pragma: no cover - a load generator
    while True:
        pass


def recording(ticks: int) -> np.ndarray:
    os.environ.setdefault("HIPPO_QUIET", "1")
    from hippo.sim.record import record

    return record("two-rooms", ticks, seed=0, rho=0.008, sensors="ir8", progress=False).sensors


def timed(fn) -> tuple[float, float]:
    w, c = time.perf_counter(), time.process_time()
    fn()
    return time.perf_counter() - w, time.process_time() - c


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ticks", type=int, default=8000)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--busy", type=int, nargs="+", default=[0, 2])
    a = ap.parse_args()
    U = recording(a.ticks)
    params = RCSFAICAParams(ica_restarts=3)
    for busy in a.busy:
        spinners = [mp.Process(target=spin, daemon=True) for _ in range(busy)]
        for p in spinners:
            p.start()
        try:
            time.sleep(2.0 if busy else 0.0)
            best: dict[str, tuple[float, float]] = {}
            for _ in range(a.rounds):
                for name, w in (("default", None), ("workers=1", 1), ("workers=2", 2)):
                    t = timed(lambda w=w: fit_leak_sweep(U, LEAKS, params, workers=w))
                    if t[0] < best.get(name, (np.inf, np.inf))[0]:
                        best[name] = t
            load = os.getloadavg()[0]
            print(f"+{busy} spinning processes (load {load:.1f}, free_cores()={free_cores()}):")
            for name, (wall, cpu) in best.items():
                print(f"  {name:10s} {wall:7.1f} s wall ({cpu:6.1f} s CPU)  "
                      f"{wall / best['workers=1'][0]:.2f} x workers=1", flush=True)
        finally:
            for p in spinners:
                p.terminate()
                p.join()


if __name__ == "__main__":
    main()
