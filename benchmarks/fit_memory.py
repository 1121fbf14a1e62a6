"""Peak memory of an RC-SFA-ICA fit against the length of the recording.

Run: ``python benchmarks/fit_memory.py [--n 600] [--ticks 1e4 1e5 1e6] [--modes stream hold]``.

Each fit runs in a fresh process (peak RSS, ``VmHWM``, is per process); the table
gives the peak RSS of the whole process, the RSS once the recording is in memory (baseline:
Python, numpy, the recording ``U`` (T, 8) in float64), the difference (what the fit itself
needs), and the wall / process CPU time of the fit. ``stream``: ``fit(U, stream=True)``, the
states are summarised chunk by chunk and never held; ``hold``: ``fit(U, stream=False)``, the
whole state sequence (T, N + 8) float32 is held. The recording is a smooth synthetic 8-sensor
signal (memory does not depend on what the sensors see). Target (issue 14): flat in T at
N = 600 from 1e4 to 1e6 ticks; N = 2400 x 1e6 ticks in <= 2 GB.

Measured 2026-11-24 (streamed fit, 2 shared cores, ``ica_restarts=2``), MB the fit needs
above the baseline: N = 600: 60 / 64 / 84 at T = 1e4 / 1e5 / 1e6 (before the ICA input was
streamed: 61 / 81 / 430); N = 2400: 478 / 480 at T = 1e4 / 1e5 (peak RSS 586 / 598), and
515 at T = 1e6 (peak RSS 743 MB; measured 2026-11-25, ``--n 2400 --ticks 1e6 --modes
stream``, 3,495 s wall, 2,039 s CPU). What still grows with T is the ICA input itself,
T x n_sfa float32 (16 MB at 1e6), and the chunks' starting states (N floats per 2,048 ticks).
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time


def peak_rss_mb() -> float:
    """This process's peak resident memory (MB): ``VmHWM`` of ``/proc/self/status`` (it starts
    afresh at exec), else ``ru_maxrss`` (which Linux carries over from a large parent)."""
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmHWM:"):
                    return float(line.split()[1]) / 2**10
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**10


def child(n: int, T: int, mode: str) -> None:
    import numpy as np

    from hippo.perception.place_cells import RCSFAICA

    rng = np.random.default_rng(0)
    U = np.empty((T, 8))
    for k in range(8):  # slow sinusoids + noise, built column by column
        U[:, k] = 0.5 + 0.4 * np.sin(2 * np.pi * np.arange(T) / rng.uniform(300, 900)
                                     + rng.uniform(0, 6))
    U += 0.05 * rng.standard_normal(U.shape)
    np.clip(U, 0.0, 1.0, out=U)
    base = peak_rss_mb()
    w, c = time.perf_counter(), time.process_time()
    RCSFAICA(n_reservoir=n, ica_restarts=2).fit(U, stream=(mode == "stream"))
    wall, cpu = time.perf_counter() - w, time.process_time() - c
    peak = peak_rss_mb()
    print(json.dumps({"n": n, "T": T, "mode": mode, "base_mb": base, "peak_mb": peak,
                      "wall_s": wall, "cpu_s": cpu}))


def measure(n: int, T: int, mode: str = "stream") -> dict:
    """One fit in a fresh process: its peak RSS, baseline, wall and CPU seconds (a dict)."""
    out = subprocess.run([sys.executable, __file__, "--child", str(n), str(T), mode],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=600)
    ap.add_argument("--ticks", type=float, nargs="+", default=[1e4, 1e5, 1e6])
    ap.add_argument("--modes", nargs="+", default=["stream", "hold"])
    ap.add_argument("--hold-limit", type=float, default=2e5,
                    help="skip 'hold' beyond this many ticks (its memory grows with T)")
    ap.add_argument("--child", nargs=3, help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.child:
        child(int(a.child[0]), int(a.child[1]), a.child[2])
        return
    print(f"N = {a.n}; MB of peak RSS; fit time wall (CPU)")
    print(f"{'T':>9s} {'mode':>7s} {'peak':>8s} {'baseline':>9s} {'fit':>8s} {'time s':>14s}")
    for T in (int(t) for t in a.ticks):
        for mode in a.modes:
            if mode == "hold" and T > a.hold_limit:
                continue
            r = measure(a.n, T, mode)
            print(f"{T:9,d} {mode:>7s} {r['peak_mb']:8.0f} {r['base_mb']:9.0f} "
                  f"{r['peak_mb'] - r['base_mb']:8.0f} {r['wall_s']:7.1f} ({r['cpu_s']:5.1f})",
                  flush=True)


if __name__ == "__main__":
    main()
