"""Which label-free criterion ranks RC-SFA-ICA settings like the labels do? (issue 11.3)

Run: ``python benchmarks/selection_criteria.py --world two-rooms --seeds 0-9 --json out.json``
(``--world flats`` for generated 3-room flats). Only for TUNING seeds: this is where the
criterion is chosen.

Per seed (one recording, one reservoir), the 16 leak pairs of the two-rooms sweep are
harvested once (:func:`~hippo.perception.leak_sweep.sweep_features`). The labelled accuracy
of a pair is that of the model fitted on the scenario's training part, scored on its test
part (two rooms: the room cell's balanced accuracy; flats: the mean per-room cell balanced
accuracy and the nearest-centroid decoder). The criteria see only the training part: models
fitted on its first 80 % are scored on the held-out 20 % that follows (and two more fitted on
the two halves of the 80 % for stability):

* ``slow_sfa`` / ``slow_ica``: held-out normalised slowness of the SFA / ICA outputs;
* ``pred1`` / ``pred10``: held-out error of a ridge map from the SFA outputs to the input
  1 / 10 ticks later;
* ``instab_ica`` / ``instab_sfa``: 1 - matched |correlation| of the ICA / SFA outputs of the
  two half-fits on the held-out block;
* ``kurt_ica``: minus the mean |excess kurtosis| of the ICA outputs on the held-out block;
* ``slow_stable``: ``slow_sfa`` x ``instab_sfa`` (``--select``'s criterion, "slow-stable").

All are "lower is better"; the Spearman correlation of -criterion with the labelled accuracy
is computed per seed and averaged.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from scipy.stats import kurtosis

from hippo.perception import RCSFAICA, ICAConvergenceWarning
from hippo.perception import metrics as M
from hippo.perception.leak_sweep import sweep_features
from hippo.perception.selection import (
    bimodality,
    instability,
    normalised_slowness,
    prediction_error,
    rank_correlation,
    separability,
)
from hippo.scenarios._common import cached_recording, parse_seeds
from hippo.sim import arenas
from hippo.sim.record import record

SLOW = (0.03, 0.05, 0.08, 0.11)
FAST = (0.14, 0.15, 0.2, 0.3)
LEAKS = [(a, b) for a in SLOW for b in FAST]
CRITERIA = ("slow_sfa", "slow_ica", "pred1", "pred10", "instab_ica", "instab_sfa", "kurt_ica",
            "slow_stable", "bimodal_sfa", "bimodal_ica", "bimodal_slowest")


def _world(world: str, seed: int, cache: str | None, ticks: int | None):
    if world == "two-rooms":
        from hippo.scenarios._two_rooms_report import _room_masks
        T = ticks or 18120
        rec = cached_recording(cache, f"two-rooms_t{T}_rho0.008_s{seed}", lambda: record(
            arenas.two_rooms(), T, seed=seed, rho=0.008, sensors="ir8", progress=False))
        rooms = _room_masks(rec)
        lab = np.where(rooms["room"], rooms["room_b"].astype(int), -1)
        return rec.sensors, lab, T * 7 // 8, 4
    from hippo.scenarios.rooms import room_labels
    from hippo.sim.flats import random_flat, room_names
    arena = random_flat(3, seed)
    T = ticks or 24000
    rec = cached_recording(cache, f"{arena.name}_t{T}_rho0.008", lambda: record(
        arena, T, seed=seed, rho=0.008, sensors="ir8", progress=False))
    return rec.sensors, room_labels(rec, room_names(arena)), T * 3 // 4, 6


def _labelled(Y: np.ndarray, lab: np.ndarray, n_train: int) -> dict[str, float]:
    n = int(lab.max()) + 1
    tr, te = slice(0, n_train), slice(n_train, len(lab))
    m_tr, m_te = lab[tr] >= 0, lab[te] >= 0
    if n == 2:
        cell = M.fit_binary_cell(Y[tr], lab[tr] == 1, m_tr)
        return {"acc": M.balanced_accuracy(cell.predict(Y[te])[m_te], (lab[te] == 1)[m_te])}
    bacc = []
    for r in range(n):
        c = M.fit_binary_cell(Y[tr], lab[tr] == r, m_tr)
        bacc.append(M.balanced_accuracy(c.predict(Y[te])[m_te], (lab[te] == r)[m_te]))
    cent = np.stack([Y[tr][lab[tr] == r].mean(axis=0) for r in range(n)])
    dec = np.argmin(((Y[te][:, None] - cent[None]) ** 2).sum(axis=2), axis=1)
    rec = [np.mean(dec[m_te][lab[te][m_te] == r] == r) for r in range(n)]
    return {"acc": float(np.nanmean(bacc)), "decoder": float(np.nanmean(rec))}


def one_seed(world: str, seed: int, cache: str | None, ticks: int | None, neurons: int,
             restarts: int, n_units: int | None = None, slow_pool: float = 0.0) -> dict:
    U, lab, n_train, units = _world(world, seed, cache, ticks)
    units = n_units or units
    n_fit = round(n_train * 0.8)
    base = RCSFAICA.smc09(n_reservoir=neurons, seed=seed, n_sfa=units, n_ica=units,
                          ica_restarts=restarts, slow_pool=slow_pool).params
    t0 = time.perf_counter()
    F = sweep_features(U, LEAKS, base)
    rows = []
    val = slice(n_fit, n_train)
    for b, lk in enumerate(LEAKS):
        X = F.X[b]
        h = n_fit // 2
        A, B, C = F.moments(b, 0, h), F.moments(b, h, n_fit), F.moments(b, n_fit, n_train)
        AB = A.merged(B)
        full = F.fit(b, 0, n_train, AB.merged(C))
        row = {"leak": list(lk), **_labelled(full.readout(X), lab, n_train)}
        m = F.fit(b, 0, n_fit, AB)
        Yica, Ysfa = m.readout(X, return_sfa=True)
        row["slow_sfa"] = float(np.mean(normalised_slowness(Ysfa[val])))
        row["slow_ica"] = float(np.mean(normalised_slowness(Yica[val])))
        row["pred1"] = prediction_error(Ysfa, U, n_fit, n_train, horizon=1)
        row["pred10"] = prediction_error(Ysfa, U, n_fit, n_train, horizon=10)
        row["kurt_ica"] = -float(np.mean(np.abs(kurtosis(Yica[val], axis=0))))
        ha, hb = F.fit(b, 0, h, A), F.fit(b, h, n_fit, B)
        Ia, Sa = ha.readout(X[val], return_sfa=True)
        Ib, Sb = hb.readout(X[val], return_sfa=True)
        row["instab_ica"] = instability(Ia, Ib)
        row["instab_sfa"] = instability(Sa, Sb)
        row["slow_stable"] = row["slow_sfa"] * row["instab_sfa"]
        row["bimodal_sfa"] = bimodality(Ysfa[val])
        row["bimodal_ica"] = bimodality(Yica[val])
        row["bimodal_slowest"] = 1 - separability(Ysfa[val, 0])
        rows.append(row)
    acc = [r["acc"] for r in rows]
    rho = {c: rank_correlation([r[c] for r in rows], acc) for c in CRITERIA}
    return {"seed": seed, "rows": rows, "spearman": rho, "seconds": time.perf_counter() - t0}


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--world", choices=["two-rooms", "flats"], default="two-rooms")
    ap.add_argument("--seeds", type=parse_seeds, default="0-9")
    ap.add_argument("--cache", default=None)
    ap.add_argument("--ticks", type=int, default=None)
    ap.add_argument("--neurons", type=int, default=600)
    ap.add_argument("--restarts", type=int, default=10)
    ap.add_argument("--units", type=int, default=None,
                    help="SFA and ICA units (default: SMC09's 4 in two rooms, 6 in flats)")
    ap.add_argument("--slow-pool", type=float, default=0.0)
    ap.add_argument("--json", required=True)
    a = ap.parse_args(argv)
    seeds = list(range(a.seeds)) if isinstance(a.seeds, int) else a.seeds
    out = []
    path = Path(a.json)
    if path.exists():
        out = json.loads(path.read_text())
    done = {r["seed"] for r in out}
    for s in seeds:
        if s in done:
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ICAConvergenceWarning)
            r = one_seed(a.world, s, a.cache, a.ticks, a.neurons, a.restarts, a.units,
                         a.slow_pool)
        out.append(r)
        path.write_text(json.dumps(out, indent=1))
        print(f"seed {s} ({r['seconds']:.0f} s): " + ", ".join(
            f"{c} {v:+.2f}" for c, v in r["spearman"].items()), file=sys.stderr, flush=True)
    for r in out:      # runs written before slow_stable was added
        if "slow_stable" not in r["spearman"]:
            for row in r["rows"]:
                row["slow_stable"] = row["slow_sfa"] * row["instab_sfa"]
            r["spearman"]["slow_stable"] = rank_correlation(
                [row["slow_stable"] for row in r["rows"]], [row["acc"] for row in r["rows"]])
    for c in CRITERIA:
        v = [r["spearman"][c] for r in out]
        print(f"{c:11s} mean Spearman {np.nanmean(v):+.3f}  per seed "
              + " ".join(f"{x:+.2f}" for x in v))


if __name__ == "__main__":
    main()
