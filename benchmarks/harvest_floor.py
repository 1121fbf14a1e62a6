"""The reservoir harvest against its hardware floor: hippo / (a C loop of OpenBLAS sgemv).

Run: ``python benchmarks/harvest_floor.py [--n 600] [--ticks 15855] [--rounds 5]``.

Per tick, every contender computes ``x(t+1) = tanh(M x(t) + d(t))`` with an N x N float32
matrix on one BLAS thread:

* ``hippo``: ``Reservoir.run`` (SMC09 reservoir, 8 inputs), the input drive included;
* ``C sgemv floor``: ``benchmarks/harvest_floor.c``, built here with gcc against the OpenBLAS
  that numpy ships (``cblas_sgemv`` looked up by name), ``sgemv`` + ``tanhf`` per tick with no
  interpreter in the loop. Skipped with a note if gcc or the library is missing;
* ``numpy sgemv loop``: ``np.dot(M, x, out=)``, ``+=``, ``np.tanh(out=)`` in a Python loop;
* ``scipy sgemv loop``: ``scipy.linalg.blas.sgemv(1, M, x, 1, y, overwrite_y=1)`` then tanh;
* ``hippo torch backend (CPU)``, where torch is installed: the loop meant for CUDA, run on the CPU
  (it is not the default there: this line shows why).

Python contenders run in this process, interleaved, best of ``--rounds``, wall and process CPU
time per tick; the C loop runs in a child process (best of the same number of repeats). Target
(issue 14): hippo <= 1.25 x the C floor.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np
import scipy.linalg.blas as sblas
from threadpoolctl import threadpool_info, threadpool_limits

from hippo.perception.reservoir import Reservoir
from hippo.perception.reservoir_params import ReservoirParams

HERE = Path(__file__).resolve().parent


def c_floor(n: int, ticks: int, rounds: int) -> tuple[float, float] | None:
    """Wall and CPU seconds per tick of the C loop, or None (with a note) if it cannot be built."""
    libs = [i for i in threadpool_info() if i["internal_api"] == "openblas"]
    gcc = shutil.which("gcc") or shutil.which("cc")
    if not libs or gcc is None:
        print("(C floor skipped: needs gcc and numpy's OpenBLAS)")
        return None
    lib = libs[0]["filepath"]
    out = subprocess.run(["nm", "-D", lib], capture_output=True, text=True).stdout
    names = [ln.split()[-1] for ln in out.splitlines() if ln.split()[-1:] and
             ln.split()[-1].endswith(("cblas_sgemv64_", "cblas_sgemv"))]
    if not names:
        print("(C floor skipped: no cblas_sgemv in " + lib + ")")
        return None
    sym = names[0]
    with tempfile.TemporaryDirectory() as tmp:
        exe = Path(tmp) / "harvest_floor"
        flags = [] if "64" in sym else ["-DBLASINT=int"]
        subprocess.run([gcc, "-O2", *flags, str(HERE / "harvest_floor.c"), "-o", str(exe),
                        "-ldl", "-lm"], check=True)
        env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
        res = subprocess.run([str(exe), lib, sym, str(n), str(ticks), str(rounds)],
                             capture_output=True, text=True, env=env, check=True)
    wall, cpu = (float(v) for v in res.stdout.split())
    return wall, cpu


def loop_numpy(M: np.ndarray, D: np.ndarray) -> None:
    x = np.zeros(M.shape[0], np.float32)
    pre = np.empty_like(x)
    out = np.empty_like(D)
    for t in range(D.shape[0]):
        np.dot(M, x, out=pre)
        pre += D[t]
        np.tanh(pre, out=out[t])
        x = out[t]


def loop_scipy(M: np.ndarray, D: np.ndarray) -> None:
    x = np.zeros(M.shape[0], np.float32)
    Mf = np.asfortranarray(M)
    out = np.empty_like(D)
    for t in range(D.shape[0]):
        y = D[t].copy()
        y = sblas.sgemv(1.0, Mf, x, 1.0, y, overwrite_y=1)
        np.tanh(y, out=out[t])
        x = out[t]


def measure(n: int = 600, ticks: int = 15855, rounds: int = 5
            ) -> tuple[dict[str, tuple[float, float]], tuple[float, float] | None]:
    """Best (wall, CPU) seconds per tick of each Python contender, and of the C floor (or
    None if it cannot be built)."""
    rng = np.random.default_rng(0)
    U = rng.random((ticks, 8))
    res = Reservoir(ReservoirParams(n_inputs=8, n_neurons=n))
    M = (rng.standard_normal((n, n)) * 0.04).astype(np.float32)
    D = (rng.standard_normal((ticks, n)) * 0.1).astype(np.float32)
    runs = {"hippo Reservoir.run": lambda: res.run(U),
            "numpy sgemv loop": lambda: loop_numpy(M, D),
            "scipy sgemv loop": lambda: loop_scipy(M, D)}
    try:  # the CUDA backend, here on the CPU: kept honest, not the default there
        import torch  # noqa: F401

        runs["hippo torch backend (CPU)"] = lambda: res.run(U, backend="torch")
    except ImportError:
        pass
    best = {k: (np.inf, np.inf) for k in runs}
    with threadpool_limits(1):
        for _ in range(rounds):
            for k, fn in runs.items():
                w, c = time.perf_counter(), time.process_time()
                fn()
                w, c = (time.perf_counter() - w) / ticks, (time.process_time() - c) / ticks
                best[k] = (min(best[k][0], w), min(best[k][1], c))
    return best, c_floor(n, ticks, rounds)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=600)
    ap.add_argument("--ticks", type=int, default=15855)
    ap.add_argument("--rounds", type=int, default=5)
    a = ap.parse_args()
    best, floor = measure(a.n, a.ticks, a.rounds)
    print(f"N = {a.n}, {a.ticks} ticks, 1 BLAS thread, best of {a.rounds}: µs per tick")
    print(f"  {'':26s} {'wall':>7s} {'CPU':>7s}   x floor, wall (CPU)")
    if floor is not None:
        print(f"  {'C sgemv floor':26s} {floor[0] * 1e6:7.1f} {floor[1] * 1e6:7.1f}")
    for k, (w, c) in best.items():
        ratio = f"   {w / floor[0]:5.2f} ({c / floor[1]:4.2f})" if floor else ""
        print(f"  {k:26s} {w * 1e6:7.1f} {c * 1e6:7.1f}{ratio}")


if __name__ == "__main__":
    main()
