"""SMC09 reproduction: a room cell and a corridor cell learned from 8 IR sensors (RC-SFA-ICA).

The e-puck wall-follows (ρ = 0.008) in the two-rooms arena for 18,120 ticks; an RC-SFA-ICA
model (600 neurons, leaks 0.05/0.15, 4 SFA / 4 ICA units) is fitted on the first 7/8 without
labels and tested on the last 1/8. Which unit is the room cell (and its threshold) is chosen on
the training part only, then scored on the test part by balanced accuracy (room A vs room B,
corridor ticks left out). The test part is then replayed with the robot kidnapped to the other
room at test ticks 150 and 640 and put back at 400 and 980 (SMC09 Fig. 7); we count the ticks
until the room cell is right again and stays right for ``--hold`` ticks (mean over the events
that really changed the robot's room: a wall follower that walked home by itself before being
put back was not kidnapped). With leaks 0.11/0.14 a corridor cell appears (SMC09 Fig. 8).
Everything is repeated over ``--seeds`` reservoirs (mean ± sd).

``--leak`` replaces SMC09's leak pair for the room cell. ``--leak-sweep 1`` also fits a grid of
16 leak pairs over each reservoir (:func:`~hippo.perception.fit_leak_sweep`: one batched harvest
and parallel fits) and reports the room cell's accuracy and kidnapping recovery for each pair
(``leak_sweep`` in the metrics, ``leak_sweep.png``): the slow leak sets both, one against the
other.
"""

from __future__ import annotations

import argparse
import time
import warnings
from typing import Any

import numpy as np

from hippo.io import save_figure, save_npz
from hippo.perception import RCSFAICA, ICAConvergenceWarning, fit_leak_sweep
from hippo.perception import metrics as M
from hippo.progress import Progress
from hippo.scenarios._common import mean_sd, prepare_out, sfa_cutoff, write_metrics
from hippo.sim import arenas
from hippo.sim.record import Recording, record

PAPER_LEAK = (0.05, 0.15)
CORRIDOR_LEAK = (0.11, 0.14)
KIDNAP_AWAY = (150, 640)    # test ticks: moved to the other room (SMC09 Fig. 7)
KIDNAP_BACK = (400, 980)    # test ticks: put back where it was taken from
TARGETS = {"room_cell_test_balanced_accuracy": 0.97, "kidnap_recovery_ticks": 15}
SWEEP_SLOW = (0.03, 0.05, 0.08, 0.11)     # leak of the first half of the neurons
SWEEP_FAST = (0.14, 0.15, 0.2, 0.3)       # leak of the second half


def parse_leak(text: str) -> tuple[float, ...]:
    """``"0.05,0.15"`` -> ``(0.05, 0.15)``: one leak rate or one per group of neurons."""
    try:
        vals = tuple(float(v) for v in str(text).split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"--leak takes comma-separated numbers, got {text!r}"
                                         ) from None
    if not vals or not all(0.0 < v <= 1.0 for v in vals):
        raise argparse.ArgumentTypeError(f"leak rates must lie in (0, 1], got {text!r}")
    return vals


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--ticks", type=int, default=18120, help="recorded control ticks")
    parser.add_argument("--rho", type=float, default=0.008, help="wall-side switch probability")
    parser.add_argument("--neurons", type=int, default=600, help="reservoir size")
    parser.add_argument("--n-sfa", type=int, default=4, help="SFA units")
    parser.add_argument("--n-ica", type=int, default=4, help="ICA units")
    parser.add_argument("--seeds", type=int, default=1,
                        help="reservoirs to repeat over (seeds seed, seed+1, ...)")
    parser.add_argument("--ica-restarts", type=int, default=10,
                        help="FastICA restarts, best kept by --ica-score (no labels)")
    parser.add_argument("--ica-score", default="kurtosis",
                        choices=["kurtosis", "sparseness", "slowness"])
    parser.add_argument("--sfa-cutoff", default="1e-8",
                        help="relative whitening cutoff, or 'auto' (default: %(default)s)")
    parser.add_argument("--leak", type=parse_leak, default=PAPER_LEAK,
                        help="leak rates of the room-cell reservoir, one per half "
                             "(default: SMC09's 0.05,0.15)")
    parser.add_argument("--leak-sweep", type=int, default=0, choices=[0, 1],
                        help="also fit a 4x4 grid of leak pairs and report each")
    parser.add_argument("--hold", type=int, default=5,
                        help="recovered = right for this many consecutive ticks")
    parser.add_argument("--figures", type=int, default=1, choices=[0, 1], help="write PNGs")


def _other_room_pose(arena, room: str, rng: np.random.Generator) -> tuple[float, float, float]:
    target = "room_a" if room == "room_b" else "room_b"
    region = next(r for r in arena.regions if r.name == target)
    x0, y0, x1, y1 = region.rects[0]
    return arena.sample_free_pose(rng, margin=4.0, rect=(x0 + 6, y0 + 6, x1 - 6, y1 - 6))


def _room_at(arena, x: float, y: float) -> str:
    name = arena.region_of(x, y)
    if name in ("room_a", "room_b"):
        return name
    return "room_a" if x < arena.width * 0.375 else "room_b"


def kidnapped_recording(arena, ticks: int, n_train: int, *, seed: int, rho: float
                        ) -> tuple[Recording, list[int], list[str], list[bool]]:
    """The same run as the clean recording, but kidnapped during the test part.

    At test ticks 150 and 640 the robot is moved to a random free pose in the other room; at
    400 and 980 it is put back at the pose it was taken from. Returns the recording, the
    absolute event ticks, the kind of each event, and whether the event really changed the
    robot's room (the wall follower sometimes walks back to its room on its own before it is
    put back; such a "kidnap" changes nothing and is left out of the recovery statistics).
    """
    rng = np.random.default_rng([seed, 7])
    kid: list[tuple[int, tuple[float, float, float]]] = []
    events, kinds, moved = [], [], []
    test_len = ticks - n_train

    def pose_before(tick: int) -> tuple[float, float, float]:
        # the trajectory is deterministic up to the next kidnap: read the pose there
        probe = record(arena, tick, seed=seed, rho=rho, sensors="ir8", kidnaps=kid,
                       progress=False)
        return float(probe.x[-1]), float(probe.y[-1]), float(probe.heading[-1])

    for away, back in zip(KIDNAP_AWAY, KIDNAP_BACK):
        if back >= test_len:
            break
        pose = pose_before(n_train + away)
        room = _room_at(arena, pose[0], pose[1])
        dest = _other_room_pose(arena, room, rng)
        kid.append((n_train + away, dest))
        here = pose_before(n_train + back)
        kid.append((n_train + back, pose))
        events += [n_train + away, n_train + back]
        kinds += [f"away from {room}", f"back to {room}"]
        moved += [True, _room_at(arena, here[0], here[1]) != room]
    rec = record(arena, ticks, seed=seed, rho=rho, sensors="ir8", kidnaps=kid, progress=False)
    return rec, events, kinds, moved


def _evaluate(model: RCSFAICA, U: np.ndarray, rooms: dict[str, np.ndarray], n_train: int,
              U_kid: np.ndarray | None, kid_rooms: dict[str, np.ndarray] | None,
              events: list[int], moved: list[bool], hold: int) -> dict[str, Any]:
    Y, Ysfa = model.transform(U, return_sfa=True)
    tr, te = slice(0, n_train), slice(n_train, len(U))
    in_b, in_room, in_cor = rooms["room_b"], rooms["room"], rooms["corridor"]
    cell = M.fit_binary_cell(Y[tr], in_b[tr], in_room[tr])
    m = in_room[te]
    room_bacc = M.balanced_accuracy(cell.predict(Y[te])[m], in_b[te][m])
    cor = M.fit_binary_cell(Y[tr], in_cor[tr])
    cor_bacc = M.balanced_accuracy(cor.predict(Y[te]), in_cor[te])
    # analysis only: the best a supervised linear read-out of the same SFA units could do
    X = np.column_stack([Ysfa, np.ones(len(U))])
    w = np.linalg.lstsq(X[tr][in_room[tr]], np.where(in_b[tr][in_room[tr]], 1.0, -1.0),
                        rcond=None)[0]
    lin = M.fit_binary_cell((X @ w)[tr, None], in_b[tr], in_room[tr])
    sup = M.balanced_accuracy(lin.predict((X @ w)[te, None])[m], in_b[te][m])
    out = {"room_cell_unit": cell.unit, "room_cell_train_balanced_accuracy":
           cell.train_balanced_accuracy, "room_cell_test_balanced_accuracy": room_bacc,
           "corridor_cell_unit": cor.unit, "corridor_cell_test_balanced_accuracy": cor_bacc,
           "sfa_supervised_readout_test_balanced_accuracy": sup,
           "sfa_slowness": model.sfa_slowness_.tolist(),
           "sfa_whitened_dims": int(model.sfa_.n_whitened_),
           "ica_converged": bool(model.ica_.converged_), "Y": Y, "Ysfa": Ysfa,
           "room_cell": cell, "corridor_cell": cor}
    if U_kid is not None:
        Yk = model.transform(U_kid)
        pred = cell.predict(Yk)
        correct = (pred == kid_rooms["room_b"]) | ~kid_rooms["room"]
        rec_t = M.recovery_times(correct, events, hold=hold)
        real = rec_t[np.asarray(moved, bool)]
        fin = real[np.isfinite(real)]
        out.update(kidnap_recovery_ticks_each=rec_t.tolist(),
                   kidnap_recovery_ticks=float(fin.mean()) if fin.size else float("nan"),
                   kidnap_recovery_ticks_max=float(fin.max()) if fin.size else float("nan"),
                   kidnap_unrecovered=int(np.isnan(real).sum()), Y_kid=Yk)
    return out


def _room_masks(rec: Recording) -> dict[str, np.ndarray]:
    names = np.array([*rec.region_names, "none"])
    reg = names[rec.region]
    return {"room_b": reg == "room_b", "room": (reg == "room_a") | (reg == "room_b"),
            "corridor": reg == "corridor"}




def run(args: argparse.Namespace) -> dict:
    out = prepare_out(args.out)
    quick = bool(args.quick)
    ticks = min(args.ticks, 8000) if quick else args.ticks
    neurons = min(args.neurons, 120) if quick else args.neurons
    restarts = min(args.ica_restarts, 3) if quick else args.ica_restarts
    arena = arenas.two_rooms()
    t0 = time.perf_counter()
    rec = record(arena, ticks, seed=args.seed, rho=args.rho, sensors="ir8", desc="two-rooms")
    n_train = ticks * 7 // 8
    rec_kid, events, kinds, moved = kidnapped_recording(arena, ticks, n_train, seed=args.seed,
                                                        rho=args.rho)
    t_rec = time.perf_counter() - t0
    rooms, kid_rooms = _room_masks(rec), _room_masks(rec_kid)
    U, U_kid = rec.sensors, rec_kid.sensors

    configs = {"paper": tuple(args.leak), "corridor": CORRIDOR_LEAK}
    per: dict[str, list[dict[str, Any]]] = {k: [] for k in configs}
    keep: dict[str, dict[str, Any]] = {}
    t_fit = 0.0
    with Progress(args.seeds * len(configs), "two-rooms fits") as bar:
        for i in range(args.seeds):
            for name, leak in configs.items():
                model = RCSFAICA.smc09(n_reservoir=neurons, leak=leak, seed=args.seed + i,
                                       n_sfa=args.n_sfa, n_ica=args.n_ica,
                                       ica_restarts=restarts, ica_score=args.ica_score,
                                       sfa_cutoff=sfa_cutoff(args.sfa_cutoff))
                t1 = time.perf_counter()
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", ICAConvergenceWarning)
                    model.fit(U[:n_train])
                t_fit += time.perf_counter() - t1
                res = _evaluate(model, U, rooms, n_train, U_kid, kid_rooms, events, moved,
                                args.hold)
                if i == 0:
                    keep[name] = res
                    if name == "paper":
                        model.save(out / "place_cells.npz")
                per[name].append({k: v for k, v in res.items()
                                  if not isinstance(v, np.ndarray | M.BinaryCell)})
                bar.update()
    sweep = (_leak_sweep(args, neurons, restarts, U, rooms, n_train, U_kid, kid_rooms, events,
                         moved) if args.leak_sweep else None)

    def summary(name: str, key: str) -> dict[str, Any]:
        vals = [r[key] for r in per[name]]
        mean, sd = mean_sd(vals)
        return {"mean": mean, "sd": sd, "per_seed": vals}

    paper_room = summary("paper", "room_cell_test_balanced_accuracy")
    paper_kid = summary("paper", "kidnap_recovery_ticks")
    cor_cell = summary("corridor", "corridor_cell_test_balanced_accuracy")
    metrics: dict[str, Any] = {
        "scenario": "two-rooms", "paper": "SMC09", "quick": quick, "seed": args.seed,
        "ticks": ticks, "train_ticks": n_train, "test_ticks": ticks - n_train,
        "reservoir_seeds": [args.seed + i for i in range(args.seeds)],
        "neurons": neurons, "n_sfa": args.n_sfa, "n_ica": args.n_ica, "rho": args.rho,
        "ica_restarts": restarts, "ica_score": args.ica_score, "sfa_cutoff": args.sfa_cutoff,
        "room_changes": int(np.sum(np.diff(rec.region.astype(int)) != 0)),
        "region_occupancy": {n: float(np.mean(rec.region == i))
                             for i, n in enumerate(rec.region_names)},
        "leak": list(configs["paper"]),
        # headline numbers (leaks --leak, SMC09's 0.05/0.15 by default, unless stated)
        "room_cell_test_balanced_accuracy": paper_room["mean"],
        "room_cell_test_balanced_accuracy_sd": paper_room["sd"],
        "kidnap_recovery_ticks": paper_kid["mean"],
        "kidnap_recovery_ticks_sd": paper_kid["sd"],
        "corridor_cell_test_balanced_accuracy": cor_cell["mean"],
        "corridor_cell_test_balanced_accuracy_sd": cor_cell["sd"],
        "kidnap_events": [{"tick": e - n_train, "kind": k, "changed_room": c}
                          for e, k, c in zip(events, kinds, moved)],
        _leak_key(configs["paper"]): {k: summary("paper", k) for k in
                           ("room_cell_test_balanced_accuracy", "kidnap_recovery_ticks",
                            "kidnap_recovery_ticks_max", "corridor_cell_test_balanced_accuracy",
                            "sfa_supervised_readout_test_balanced_accuracy")},
        "leak_0.11_0.14": {k: summary("corridor", k) for k in
                           ("room_cell_test_balanced_accuracy", "kidnap_recovery_ticks",
                            "kidnap_recovery_ticks_max", "corridor_cell_test_balanced_accuracy",
                            "sfa_supervised_readout_test_balanced_accuracy")},
        "runs": per,
        "targets": TARGETS,
        "timing_s": {"record": t_rec, "fit_total": t_fit},
    }
    if sweep is not None:
        metrics["leak_sweep"] = sweep["rows"]
        metrics["leak_sweep_meeting_targets"] = [r["leak"] for r in sweep["rows"]
                                                 if r["meets_targets"]]
        metrics["timing_s"]["leak_sweep"] = sweep["seconds"]
    save_npz(out / "run.npz", dict(
        t=rec.t, x=rec.x, y=rec.y, label=rec.label, region=rec.region,
        sensors=U, n_train=n_train, Y=keep["paper"]["Y"], Ysfa=keep["paper"]["Ysfa"],
        Y_kid=keep["paper"].get("Y_kid", np.zeros(0)), x_kid=rec_kid.x, y_kid=rec_kid.y,
        label_kid=rec_kid.label, kidnap_ticks=np.array(events),
        Y_corridor_leaks=keep["corridor"]["Y"]))
    if args.figures:
        _figures(out, arena, rec, rec_kid, n_train, events, keep, configs["paper"])
        if sweep is not None:
            _sweep_figure(out, sweep["rows"])
    write_metrics(out, metrics)
    return metrics


def _leak_key(leak: tuple[float, ...]) -> str:
    return "leak_" + "_".join(f"{v:g}" for v in leak)


def _leak_sweep(args: argparse.Namespace, neurons: int, restarts: int, U: np.ndarray,
                rooms: dict[str, np.ndarray], n_train: int, U_kid: np.ndarray,
                kid_rooms: dict[str, np.ndarray], events: list[int], moved: list[bool]
                ) -> dict[str, Any]:
    """Room cell and kidnapping recovery for each leak pair of the grid, over the seeds."""
    leaks = [(a, b) for a in SWEEP_SLOW for b in SWEEP_FAST]
    scores: dict[tuple[float, float], list[tuple[float, float]]] = {lk: [] for lk in leaks}
    t0 = time.perf_counter()
    with Progress(args.seeds, "two-rooms leak sweep") as bar:
        for i in range(args.seeds):
            base = RCSFAICA.smc09(n_reservoir=neurons, seed=args.seed + i, n_sfa=args.n_sfa,
                                  n_ica=args.n_ica, ica_restarts=restarts,
                                  ica_score=args.ica_score,
                                  sfa_cutoff=sfa_cutoff(args.sfa_cutoff)).params
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ICAConvergenceWarning)
                models = fit_leak_sweep(U[:n_train], leaks, base)
            for lk, model in zip(leaks, models):
                r = _evaluate(model, U, rooms, n_train, U_kid, kid_rooms, events, moved,
                              args.hold)
                scores[lk].append((r["room_cell_test_balanced_accuracy"],
                                   r["kidnap_recovery_ticks"]))
            bar.update()
    rows = []
    for lk in leaks:
        room, rec = (mean_sd([v[j] for v in scores[lk]]) for j in (0, 1))
        rows.append({"leak": list(lk), "room_cell_test_balanced_accuracy": room[0],
                     "room_cell_test_balanced_accuracy_sd": room[1],
                     "kidnap_recovery_ticks": rec[0], "kidnap_recovery_ticks_sd": rec[1],
                     "meets_targets": bool(
                         room[0] >= TARGETS["room_cell_test_balanced_accuracy"]
                         and rec[0] <= TARGETS["kidnap_recovery_ticks"])})
    return {"rows": rows, "seconds": time.perf_counter() - t0}


def _sweep_figure(out, rows: list[dict[str, Any]]) -> None:
    import matplotlib.pyplot as plt

    grid = {(r["leak"][0], r["leak"][1]): r for r in rows}
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    for ax, key, label, cmap in (
            (axes[0], "room_cell_test_balanced_accuracy", "room cell: balanced accuracy (test)",
             "viridis"),
            (axes[1], "kidnap_recovery_ticks", "kidnapping: ticks to recover", "viridis_r")):
        Z = np.array([[grid[(a, b)][key] for b in SWEEP_FAST] for a in SWEEP_SLOW])
        im = ax.imshow(Z, cmap=cmap, origin="lower", aspect="auto")
        for i, a in enumerate(SWEEP_SLOW):
            for j, b in enumerate(SWEEP_FAST):
                r = grid[(a, b)]
                rgb = im.cmap(im.norm(Z[i, j]))[:3]
                dark = 0.299 * rgb[0] + 0.587 * rgb[1] + 0.114 * rgb[2] < 0.55
                ax.text(j, i, f"{Z[i, j]:.3g}", ha="center", va="center", fontsize=8,
                        color="w" if dark else "k",
                        fontweight="bold" if r["meets_targets"] else "normal")
        ax.set_xticks(range(len(SWEEP_FAST)), [f"{b:g}" for b in SWEEP_FAST])
        ax.set_yticks(range(len(SWEEP_SLOW)), [f"{a:g}" for a in SWEEP_SLOW])
        ax.set_xlabel("leak of the fast half")
        ax.set_ylabel("leak of the slow half")
        ax.set_title(label, fontsize=10)
        fig.colorbar(im, ax=ax, shrink=0.85)
    fig.suptitle(f"leak sweep (bold: room cell >= {TARGETS['room_cell_test_balanced_accuracy']}"
                 f" and recovery <= {TARGETS['kidnap_recovery_ticks']} ticks); SMC09: 0.05/0.15",
                 fontsize=10)
    fig.tight_layout()
    save_figure(fig, out / "leak_sweep.png", dpi=110)
    plt.close(fig)


def _figures(out, arena, rec, rec_kid, n_train, events, keep, leak) -> None:
    import matplotlib.pyplot as plt

    from hippo.plots.perception import plot_place_cell

    xy, lab = rec.positions, rec.label
    p, c = keep["paper"], keep["corridor"]
    j = p["room_cell"].unit
    sign = p["room_cell"].polarity
    tr, te = slice(0, n_train), slice(n_train, len(rec))
    figs = {
        "fig5_room_cell_train.png": plot_place_cell(
            arena, xy[tr], lab[tr], sign * p["Y"][tr, j],
            title=f"room cell (ICA unit {j + 1}) on training data, leaks "
                  f"{'/'.join(f'{v:g}' for v in leak)}"),
        "fig6_room_cell_test.png": plot_place_cell(
            arena, xy[te], lab[te], sign * p["Y"][te, j], t=np.arange(n_train, len(rec)),
            title=f"room cell (ICA unit {j + 1}) on test data: balanced accuracy "
                  f"{p['room_cell_test_balanced_accuracy']:.3f}",
            truth=_room_masks(rec)["room_b"][te], truth_label="in room B"),
    }
    if "Y_kid" in p:
        Yk = p["Y_kid"]
        figs["fig7_kidnapping.png"] = plot_place_cell(
            arena, rec_kid.positions[te], rec_kid.label[te], sign * Yk[te, j],
            t=np.arange(len(rec) - n_train), events=[e - n_train for e in events],
            title=f"kidnapping: recovery {p['kidnap_recovery_ticks_each']} ticks",
            truth=_room_masks(rec_kid)["room_b"][te], truth_label="in room B")
    k = c["corridor_cell"].unit
    figs["fig8_corridor_cell_test.png"] = plot_place_cell(
        arena, xy[te], lab[te], c["corridor_cell"].polarity * c["Y"][te, k],
        t=np.arange(n_train, len(rec)),
        title=f"corridor cell (ICA unit {k + 1}), leaks 0.11/0.14: balanced accuracy "
              f"{c['corridor_cell_test_balanced_accuracy']:.3f}",
        truth=_room_masks(rec)["corridor"][te], truth_label="in corridor")
    for name, (fig, _) in figs.items():
        save_figure(fig, out / name, dpi=110)
        plt.close(fig)
