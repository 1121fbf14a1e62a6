"""Every issue-14 speed and memory measure in one run: one table, one JSON file.

Run: ``python benchmarks/run_all.py [--json benchmarks/results.json] [--size small|full]``.

Each row is one measure: hippo's figure, its peer's in the same run (interleaved where both
run in this process, best of a few rounds), the ratio the target is stated in, the target, and
process CPU time beside wall time. The default ``small`` size finishes in about 6-8 minutes on 2
quiet cores; ``full`` uses the sizes of the single benchmarks (and adds N = 2400 x 10⁶ ticks to
the memory curve: about half an hour on its own). The machine's load average is recorded before
and after: on busy cores (load > cores) wall-time ratios mean little, CPU-time ratios more.

Measures (the single scripts give details and more contenders):

* ``agent_speed.py``: agent tick / (world + wall-follower tick), learned and ground-truth place
  cells; the closed loop (agent + world) as a multiple of real time (dt = 0.2 s);
* ``harvest_floor.py``: the reservoir harvest / a C loop of OpenBLAS ``sgemv``;
* ``fit_memory.py``: peak RSS of a streamed fit at N = 600 against T (fresh process each);
* leak sweep (16 pairs): default workers / ``workers=1``, and 16 separate fits / default;
* ``sweep_speed.py``: ``hippo sweep`` on a LocalCluster, 1 worker / 2 workers;
* whole fit: ReservoirPy + SFA + scikit-learn FastICA / ``RCSFAICA.fit`` (peers from
  ``benchmarks/.venv-peers``, see ``perception_fit.py``; skipped with a note when missing).
"""

from __future__ import annotations

import argparse
import glob
import os
import subprocess
import sys
import time
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.extend(sorted(glob.glob(str(HERE / ".venv-peers/lib/python*/site-packages"))))
os.environ.setdefault("HIPPO_QUIET", "1")

import numpy as np  # noqa: E402
from threadpoolctl import threadpool_limits  # noqa: E402

SIZES = {
    "small": {"agent_ticks": 1000, "agent_rounds": 3, "harvest_ticks": 8000, "harvest_rounds": 3,
              "memory": [(600, 10_000), (600, 100_000), (600, 1_000_000)], "leak_ticks": 4000,
              "leak_rounds": 1, "sweep_seeds": 8, "sweep_rounds": 1, "fit_ticks": 18120,
              "fit_rounds": 2},
    "full": {"agent_ticks": 2000, "agent_rounds": 5, "harvest_ticks": 15855, "harvest_rounds": 5,
             "memory": [(600, 10_000), (600, 100_000), (600, 1_000_000), (2400, 10_000),
                        (2400, 1_000_000)], "leak_ticks": 8000, "leak_rounds": 2,
             "sweep_seeds": 8, "sweep_rounds": 2, "fit_ticks": 18120, "fit_rounds": 3},
}


def timed(fn) -> tuple[float, float, object]:
    w, c = time.perf_counter(), time.process_time()
    out = fn()
    return time.perf_counter() - w, time.process_time() - c, out


def best_of(runs: dict, rounds: int) -> dict[str, tuple[float, float]]:
    """Interleaved: every contender once per round; best wall and best CPU of each."""
    best = {k: (np.inf, np.inf) for k in runs}
    for _ in range(rounds):
        for k, fn in runs.items():
            w, c, _ = timed(fn)
            best[k] = (min(best[k][0], w), min(best[k][1], c))
    return best


def row(measure: str, hippo: tuple[float, float] | None, peer: tuple[float, float] | None,
        peer_name: str, unit: str, ratio_of: str, target: str, ok: bool | None,
        note: str = "") -> dict:
    """One table row; ``ratio`` = the ratio named by ``ratio_of`` (wall, and CPU)."""
    r = rc = None
    if hippo and peer:
        if ratio_of == "hippo/peer":
            r, rc = hippo[0] / peer[0], hippo[1] / peer[1]
        else:
            r, rc = peer[0] / hippo[0], peer[1] / hippo[1]
    return {"measure": measure, "hippo_wall": hippo and hippo[0], "hippo_cpu": hippo and hippo[1],
            "peer": peer_name, "peer_wall": peer and peer[0], "peer_cpu": peer and peer[1],
            "unit": unit, "ratio": ratio_of, "ratio_wall": r, "ratio_cpu": rc,
            "target": target, "met": ok, "note": note}


# ---------------------------------------------------------------------------- the measures
def agent(size: dict) -> list[dict]:
    import agent_speed

    rows = []
    with threadpool_limits(1):
        for kind in ("learned", "ground-truth"):
            b = agent_speed.bench(kind, size["agent_ticks"], size["agent_rounds"])
            ag, wo = b["agent"], b["world"]
            peer = tuple(x + y for x, y in zip(b["peer world"], b["wall follower"]))
            us = tuple(v * 1e6 for v in ag)
            r = row(f"agent tick ({kind} place cells)", us, tuple(v * 1e6 for v in peer),
                    "world + wall-follower tick", "µs/tick", "hippo/peer", "<= 2",
                    ag[0] / peer[0] <= 2.0)
            rows.append(r)
            loop = (ag[0] + wo[0], ag[1] + wo[1])
            x = (0.2 / loop[0], 0.2 / loop[1])
            rows.append({**row(f"closed loop, x real time ({kind})", None, None, "real time",
                               "x", "real/loop", ">= 1500", x[0] >= 1500,
                               f"agent + world {loop[0] * 1e6:.0f} µs/tick at dt = 0.2 s; 1,500 x "
                               "needs <= 133 µs"), "ratio_wall": x[0], "ratio_cpu": x[1]})
    return rows


def harvest(size: dict) -> list[dict]:
    import harvest_floor

    best, floor = harvest_floor.measure(600, size["harvest_ticks"], size["harvest_rounds"])
    h = tuple(v * 1e6 for v in best["hippo Reservoir.run"])
    f = tuple(v * 1e6 for v in floor) if floor else None
    return [row("reservoir harvest, N = 600", h, f, "C loop of OpenBLAS sgemv", "µs/tick",
                "hippo/peer", "<= 1.25", (h[0] / f[0] <= 1.25) if f else None,
                "" if f else "C floor not built (needs gcc)")]


def memory(size: dict) -> list[dict]:
    import fit_memory

    rows, fit_mb = [], {}
    for n, T in size["memory"]:
        r = fit_memory.measure(n, T, "stream")
        fit_mb[(n, T)] = r["peak_mb"] - r["base_mb"]
        ok = r["peak_mb"] <= 2048 if n == 2400 else None
        rows.append({**row(f"fit memory, N = {n}, T = {T:.0e}", (r["wall_s"], r["cpu_s"]), None,
                           "", "s", "hippo/peer", "<= 2 GB" if n == 2400 else "flat in T", ok,
                           f"peak RSS {r['peak_mb']:.0f} MB, of which the fit "
                           f"{fit_mb[(n, T)]:.0f} MB (baseline: Python + U)"),
                     "peak_mb": r["peak_mb"], "fit_mb": fit_mb[(n, T)]})
    ts = sorted(T for n, T in fit_mb if n == 600)
    if len(ts) >= 2 and fit_mb[(600, ts[0])] > 0:
        lo, hi = fit_mb[(600, ts[0])], fit_mb[(600, ts[-1])]
        rows.append({**row(f"fit memory growth, N = 600, T {ts[0]:.0e} -> {ts[-1]:.0e}", None,
                           None, "", "x", "hippo/peer", "flat (<= 1.5 x)", hi / lo <= 1.5,
                           f"{lo:.0f} -> {hi:.0f} MB"), "ratio_wall": hi / lo})
    return rows


def leak_sweep(size: dict) -> list[dict]:
    from leak_sweep_threads import LEAKS, recording

    from hippo._threads import free_cores
    from hippo.perception import RCSFAICA, RCSFAICAParams, fit_leak_sweep

    U = recording(size["leak_ticks"])
    params = RCSFAICAParams(ica_restarts=3)
    runs = {"default": lambda: fit_leak_sweep(U, LEAKS, params),
            "workers=1": lambda: fit_leak_sweep(U, LEAKS, params, workers=1),
            "separate": lambda: [RCSFAICA(params, leak=lk).fit(U) for lk in LEAKS]}
    cores = free_cores()
    b = best_of(runs, size["leak_rounds"])
    return [row("leak sweep 16 pairs: default workers", b["default"], b["workers=1"],
                "workers=1", "s", "hippo/peer", "<= 1",
                b["default"][0] <= b["workers=1"][0] * 1.05,
                f"free_cores() = {cores} at the start; within 5 % counts as equal"),
            row("leak sweep 16 pairs vs 16 separate fits", b["default"], b["separate"],
                "16 separate RCSFAICA.fit", "s", "peer/hippo", ">= 3",
                b["separate"][0] / b["default"][0] >= 3)]


def sweep(size: dict) -> list[dict]:
    import sweep_speed

    b = sweep_speed.measure(size["sweep_seeds"], size["sweep_rounds"], verbose=False)
    return [row(f"hippo sweep, {2 * size['sweep_seeds']} cells: 2 workers",
                (b[2][0], b[2][1]), (b[1][0], b[1][1]), "1 worker", "s", "peer/hippo",
                ">= 1.7", b[1][0] / b[2][0] >= 1.7,
                "CPU column: the cells' own seconds summed (they run in worker processes)")]


def whole_fit(size: dict) -> list[dict]:
    from leak_sweep_threads import recording
    from perception_fit import eigh_sfa

    from hippo.perception import RCSFAICA, ICAConvergenceWarning, Reservoir

    warnings.simplefilter("ignore", ICAConvergenceWarning)
    U = recording(size["fit_ticks"])
    Utr = U[: len(U) * 7 // 8]
    model = RCSFAICA.smc09(ica_restarts=1, seed=0)
    try:
        from reservoirpy.mat_gen import normal
        from reservoirpy.nodes import Reservoir as RpyReservoir
        from sklearn.decomposition import FastICA as SkICA
    except Exception as exc:
        return [row("whole fit", None, None, "ReservoirPy + SFA + sklearn FastICA", "s",
                    "peer/hippo", ">= 3", None, f"peers missing ({exc}); see perception_fit.py")]
    res = Reservoir(model.params.reservoir_params())

    def peer() -> None:
        normal(600, 600, sr=0.99, connectivity=1.0, seed=0)
        node = RpyReservoir(units=600, lr=0.1, W=res.W_res, Win=res.W_in, bias=0.0, input_dim=8)
        X = np.concatenate([Utr, node.run(Utr)], axis=1)
        W = eigh_sfa(X, 4)  # the textbook SFA, 10 x faster than sklearn-sfa: conservative
        Y = ((X - X.mean(0)) / X.std(0)) @ W
        SkICA(n_components=4, fun="cube", algorithm="parallel", whiten="unit-variance",
              random_state=0).fit(Y)

    b = best_of({"hippo": lambda: model.fit(Utr), "peer": peer}, size["fit_rounds"])
    return [row(f"whole fit, {len(Utr):,} ticks, N = 600", b["hippo"], b["peer"],
                "ReservoirPy + eigh SFA + sklearn FastICA", "s", "peer/hippo", ">= 3",
                b["peer"][0] / b["hippo"][0] >= 3,
                "hippo: RCSFAICA.fit, 1 ICA start (draw + harvest + SFA + ICA)")]


MEASURES = {"agent": agent, "harvest": harvest, "memory": memory, "leak": leak_sweep,
            "sweep": sweep, "fit": whole_fit}


def fmt(v: float | None, w: int = 9, p: int = 1) -> str:
    return f"{'-':>{w}s}" if v is None else f"{v:{w},.{p}f}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", choices=sorted(SIZES), default="small")
    ap.add_argument("--only", nargs="+", choices=sorted(MEASURES), default=list(MEASURES))
    ap.add_argument("--json", default=str(HERE / "results.json"))
    a = ap.parse_args()
    size = SIZES[a.size]
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True, cwd=HERE).stdout.strip()
    except OSError:
        commit = ""
    meta = {"date": time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime()), "commit": commit,
            "cores": len(os.sched_getaffinity(0)), "load_before": os.getloadavg(),
            "size": a.size}
    rows: list[dict] = []
    t0 = time.perf_counter()
    for name in a.only:
        t = time.perf_counter()
        rows.extend(MEASURES[name](size))
        print(f"[{name}: {time.perf_counter() - t:.0f} s]", file=sys.stderr, flush=True)
    meta["load_after"] = os.getloadavg()
    meta["seconds"] = time.perf_counter() - t0
    print(f"\nissue 14 benchmarks ({a.size}), {meta['date']}, commit {commit}, "
          f"{meta['cores']} cores, load {meta['load_before'][0]:.2f} -> "
          f"{meta['load_after'][0]:.2f}, {meta['seconds']:.0f} s")
    print(f"{'measure':46s} {'hippo wall (CPU)':>20s} {'peer wall (CPU)':>20s} {'unit':>7s} "
          f"{'ratio wall (CPU)':>22s} {'target':>9s} met")
    for r in rows:
        h = f"{fmt(r['hippo_wall'])} ({fmt(r['hippo_cpu'], 7)})"
        p = f"{fmt(r['peer_wall'])} ({fmt(r['peer_cpu'], 7)})"
        ratio = (f"{r['ratio']:>10s} {fmt(r['ratio_wall'], 5, 2)} "
                 f"({fmt(r['ratio_cpu'], 4, 2)})" if r["ratio_wall"] is not None else "")
        met = {True: "yes", False: "NO", None: "-"}[r["met"]]
        print(f"{r['measure']:46s} {h:>20s} {p:>20s} {r['unit']:>7s} {ratio:>22s} "
              f"{r['target']:>9s} {met}")
        if r["note"]:
            print(f"{'':6s}{r['peer'] + ': ' if r['peer'] else ''}{r['note']}")
    from hippo.io import save_json

    save_json(a.json, {"meta": meta, "rows": rows})
    print(f"written {a.json}")


if __name__ == "__main__":
    main()
