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
Everything is repeated over ``--seeds`` (a count, or ranges and lists such as ``100-119``):
each seed is one exploration run **and** one reservoir, so held-out seeds are new runs, not
only new weights (mean ± sd, worst seed). The project's convention: settings are chosen on the
tuning seeds 0-9 and reported on the held-out seeds 100-119. ``--cache DIR`` keeps the
recordings for reuse.

Ceiling (``--ceiling``, default; ``--no-ceiling`` skips it): a supervised ridge read-out of
the same reservoir state ``[u; x]`` (room A vs B, 5 blocked folds in time,
:func:`~hippo.perception.metrics.ridge_ceiling`) shows what the sensors allow next to what
the unsupervised room cell reaches.

Faults (``--faults``): sensors die (stuck at 0, stuck at 1, or noise only; 0-3 of the 8) or
all get noisier (s.d. 0.01-0.1) at the start of the test part; the room cell chosen on clean
training data is scored raw and behind a :class:`~hippo.perception.sensor_guard.SensorGuard`
(``faults`` in the metrics, ``faults.png``).

``--leak`` replaces SMC09's leak pair for the room cell. ``--leak-sweep`` also fits a grid of
16 leak pairs over each reservoir (:func:`~hippo.perception.fit_leak_sweep`: one batched harvest
and parallel fits) and reports the room cell's accuracy and kidnapping recovery for each pair
(``leak_sweep`` in the metrics, ``leak_sweep.png``): the slow leak sets both, one against the
other.
"""

from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from hippo.cli_args import integer, probability
from hippo.cli_args import sfa_cutoff as cli_sfa_cutoff
from hippo.io import load_json, save_figure, save_json, save_npz
from hippo.perception import RCSFAICA, ICAConvergenceWarning, fit_leak_sweep
from hippo.perception import metrics as M
from hippo.perception.sensor_guard import SensorGuard
from hippo.progress import Progress
from hippo.scenarios._common import (
    add_cache_argument,
    add_seeds_argument,
    cached_recording,
    mean_sd,
    prepare_out,
    seed_list,
    sfa_cutoff,
    write_metrics,
)
from hippo.sim import arenas
from hippo.sim.controllers import WallFollower, WallFollowerParams
from hippo.sim.faults import SensorFaults
from hippo.sim.record import Recording, record
from hippo.sim.world import World

PAPER_LEAK = (0.05, 0.15)
#: the test part (the last eighth) must hold the first kidnapping and the return (tick 400)
MIN_TICKS = 4000
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
    parser.add_argument("--ticks", type=integer(MIN_TICKS, 10_000_000), default=18120,
                        help="recorded control ticks of 0.2 s; the last eighth is the test part "
                             f"with the kidnappings (at least {MIN_TICKS})")
    parser.add_argument("--rho", type=probability, default=0.008,
                        help="wall-side switch probability per tick")
    parser.add_argument("--neurons", type=integer(1, 20_000), default=600, help="reservoir size")
    parser.add_argument("--n-sfa", type=integer(1, 500), default=4, help="SFA units")
    parser.add_argument("--n-ica", type=integer(1, 500), default=4,
                        help="ICA units (at most --n-sfa)")
    add_seeds_argument(parser, "exploration runs and reservoirs to repeat over (one each "
                               "per seed)")
    add_cache_argument(parser)
    parser.add_argument("--ceiling", action=argparse.BooleanOptionalAction, default=True,
                        help="also report the supervised ceiling (ridge on the reservoir state)")
    parser.add_argument("--faults", action="store_true",
                        help="also draw room-cell accuracy against dead sensors (0-3) and "
                             "added sensor noise (0.01-0.1) on the test part")
    parser.add_argument("--ica-restarts", type=integer(1, 1000), default=10,
                        help="FastICA restarts, best kept by --ica-score (no labels)")
    parser.add_argument("--ica-score", default="kurtosis",
                        choices=["kurtosis", "sparseness", "slowness"])
    parser.add_argument("--sfa-cutoff", type=cli_sfa_cutoff, default="1e-8",
                        help="relative whitening cutoff in (0, 1), or 'auto'")
    parser.add_argument("--leak", type=parse_leak, default=PAPER_LEAK,
                        help="leak rates of the room-cell reservoir, one per half "
                             "(default: SMC09's 0.05,0.15)")
    parser.add_argument("--leak-sweep", action=argparse.BooleanOptionalAction, default=False,
                        help="also fit a 4x4 grid of leak pairs and report each")
    parser.add_argument("--hold", type=integer(1, 10_000), default=5,
                        help="recovered = right for this many consecutive ticks")
    parser.add_argument("--figures", action=argparse.BooleanOptionalAction, default=True,
                        help="write PNGs")


def check_args(args: argparse.Namespace, parser: argparse.ArgumentParser) -> None:
    """Checks across arguments, before any work."""
    if args.n_ica > args.n_sfa:
        parser.error(f"argument --n-ica: {args.n_ica} exceeds --n-sfa {args.n_sfa} "
                     "(ICA rotates the SFA outputs)")
    if args.n_sfa > args.neurons + 8:
        parser.error(f"argument --n-sfa: {args.n_sfa} exceeds the {args.neurons + 8} inputs of "
                     "SFA (--neurons + 8 sensors)")


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
    # one pass of the same run (same world and controller seeds as ``record``) decides the
    # kidnaps as it goes; ``record`` then replays the run with them
    world = World(arena, sensors="ir8", seed=seed)
    world.reset(seed)
    ctrl = WallFollower(WallFollowerParams(rho=rho), sensors=world.sensors, robot=world.robot,
                        rng=np.random.default_rng([seed, 1]))
    plan = {}
    for away, back in zip(KIDNAP_AWAY, KIDNAP_BACK):
        if back < test_len:
            plan[n_train + away] = "away"
            plan[n_train + back] = "back"
    obs = world._observe(np.zeros(3), 0.0, False)
    taken: tuple[float, float, float] | None = None
    room = ""
    for k in range(max(plan, default=-1) + 1):
        if k in plan:
            pose = world.pose
            if plan[k] == "away":
                taken, room = pose, _room_at(arena, pose[0], pose[1])
                dest = _other_room_pose(arena, room, rng)
                kinds.append(f"away from {room}")
                moved.append(True)
            else:
                dest = taken
                kinds.append(f"back to {room}")
                moved.append(_room_at(arena, pose[0], pose[1]) != room)
            kid.append((k, dest))
            events.append(k)
            world.place_robot(*dest)
            obs = world._observe(np.zeros(3), 0.0, False)
        obs = world.step(ctrl.act(obs))
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




def _recordings(args: argparse.Namespace, arena, ticks: int, n_train: int, seed: int):
    """The clean and the kidnapped recording of exploration run ``seed`` (cached with
    ``--cache``)."""
    tag = f"two-rooms_t{ticks}_rho{args.rho:g}_s{seed}"
    rec = cached_recording(args.cache, tag, lambda: record(
        arena, ticks, seed=seed, rho=args.rho, sensors="ir8", desc=f"two-rooms seed {seed}"))
    meta_path = Path(args.cache) / f"{tag}_kid.json" if args.cache else None
    if meta_path is not None and meta_path.exists():
        meta = load_json(meta_path)
        rec_kid = Recording.load(meta_path.with_suffix(".npz"))
        return rec, rec_kid, meta["events"], meta["kinds"], meta["moved"]
    rec_kid, events, kinds, moved = kidnapped_recording(arena, ticks, n_train, seed=seed,
                                                        rho=args.rho)
    if meta_path is not None:
        rec_kid.save(meta_path.with_suffix(".npz"))
        save_json(meta_path, {"events": events, "kinds": kinds, "moved": moved})
    return rec, rec_kid, events, kinds, moved


def room_ceiling(model: RCSFAICA, U: np.ndarray, rooms: dict[str, np.ndarray]) -> M.Ceiling:
    """The supervised ceiling of the room cell: a ridge read-out of the model's own reservoir
    state ``[u; x]``, room A vs room B (corridor left out), 5 blocked folds in time."""
    X = model.features(U)
    return M.ridge_ceiling(X, rooms["room_b"].astype(int), 2, mask=rooms["room"], folds=5,
                           gap=50)


def run(args: argparse.Namespace) -> dict:
    out = prepare_out(args.out)
    quick = bool(args.quick)
    ticks = min(args.ticks, 8000) if quick else args.ticks
    neurons = min(args.neurons, 120) if quick else args.neurons
    restarts = min(args.ica_restarts, 3) if quick else args.ica_restarts
    arena = arenas.two_rooms()
    seeds = seed_list(args)
    n_train = ticks * 7 // 8
    configs = {"paper": tuple(args.leak), "corridor": CORRIDOR_LEAK}
    per: dict[str, list[dict[str, Any]]] = {k: [] for k in configs}
    keep: dict[str, dict[str, Any]] = {}
    t_fit = t_rec = 0.0
    first = None
    sweep_rows: list[dict[str, Any]] = []
    fault_rows: list[dict[str, Any]] = []
    with Progress(len(seeds) * len(configs), "two-rooms fits") as bar:
        for i, seed in enumerate(seeds):
            t0 = time.perf_counter()
            rec, rec_kid, events, kinds, moved = _recordings(args, arena, ticks, n_train, seed)
            t_rec += time.perf_counter() - t0
            rooms, kid_rooms = _room_masks(rec), _room_masks(rec_kid)
            U, U_kid = rec.sensors, rec_kid.sensors
            if first is None:
                first = (rec, rec_kid, events, kinds, moved)
            for name, leak in configs.items():
                model = RCSFAICA.smc09(n_reservoir=neurons, leak=leak, seed=seed,
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
                if name == "paper" and args.ceiling:
                    ceil = room_ceiling(model, U, rooms)
                    res["room_ceiling_balanced_accuracy"] = ceil.balanced_accuracy
                if name == "paper" and args.faults:
                    fault_rows.extend(_fault_curve(model, U, rooms, n_train, res["room_cell"],
                                                   seed, quick))
                res["seed"] = seed
                if i == 0:
                    keep[name] = res
                    if name == "paper":
                        model.save(out / "place_cells.npz")
                per[name].append({k: v for k, v in res.items()
                                  if not isinstance(v, np.ndarray | M.BinaryCell)})
                bar.update()
            if args.leak_sweep:
                sweep_rows.append(_leak_sweep_one(args, neurons, restarts, seed, U, rooms,
                                                  n_train, U_kid, kid_rooms, events, moved))
    rec, rec_kid, events, kinds, moved = first
    sweep = _sweep_summary(sweep_rows) if args.leak_sweep else None

    def summary(name: str, key: str) -> dict[str, Any]:
        vals = [r.get(key, float("nan")) for r in per[name]]
        mean, sd = mean_sd(vals)
        finite = [v for v in vals if np.isfinite(v)]
        return {"mean": mean, "sd": sd, "min": min(finite) if finite else float("nan"),
                "max": max(finite) if finite else float("nan"), "per_seed": vals}

    keys = ("room_cell_test_balanced_accuracy", "kidnap_recovery_ticks",
            "kidnap_recovery_ticks_max", "corridor_cell_test_balanced_accuracy",
            "sfa_supervised_readout_test_balanced_accuracy", "room_ceiling_balanced_accuracy")
    paper_room = summary("paper", "room_cell_test_balanced_accuracy")
    paper_kid = summary("paper", "kidnap_recovery_ticks")
    cor_cell = summary("corridor", "corridor_cell_test_balanced_accuracy")
    metrics: dict[str, Any] = {
        "scenario": "two-rooms", "paper": "SMC09", "quick": quick, "seed": args.seed,
        "seeds": seeds,
        "seeds_note": "each seed is one exploration run (recording) and one reservoir",
        "ticks": ticks, "train_ticks": n_train, "test_ticks": ticks - n_train,
        "reservoir_seeds": seeds,
        "neurons": neurons, "n_sfa": args.n_sfa, "n_ica": args.n_ica, "rho": args.rho,
        "ica_restarts": restarts, "ica_score": args.ica_score, "sfa_cutoff": args.sfa_cutoff,
        "room_changes": int(np.sum(np.diff(rec.region.astype(int)) != 0)),
        "region_occupancy": {n: float(np.mean(rec.region == i))
                             for i, n in enumerate(rec.region_names)},
        "leak": list(configs["paper"]),
        # headline numbers (leaks --leak, SMC09's 0.05/0.15 by default, unless stated)
        "room_cell_test_balanced_accuracy": paper_room["mean"],
        "room_cell_test_balanced_accuracy_sd": paper_room["sd"],
        "room_cell_test_balanced_accuracy_min": paper_room["min"],
        "kidnap_recovery_ticks": paper_kid["mean"],
        "kidnap_recovery_ticks_sd": paper_kid["sd"],
        "kidnap_recovery_ticks_worst_seed": paper_kid["max"],
        "kidnap_unrecovered": int(sum(r.get("kidnap_unrecovered", 0) for r in per["paper"])),
        "corridor_cell_test_balanced_accuracy": cor_cell["mean"],
        "corridor_cell_test_balanced_accuracy_sd": cor_cell["sd"],
        "room_ceiling_balanced_accuracy":
            summary("paper", "room_ceiling_balanced_accuracy")["mean"],
        "kidnap_events": [{"tick": e - n_train, "kind": k, "changed_room": c}
                          for e, k, c in zip(events, kinds, moved)],
        _leak_key(configs["paper"]): {k: summary("paper", k) for k in keys},
        "leak_0.11_0.14": {k: summary("corridor", k) for k in keys},
        "runs": per,
        "targets": TARGETS,
        "timing_s": {"record": t_rec, "fit_total": t_fit},
    }
    if sweep is not None:
        metrics["leak_sweep"] = sweep["rows"]
        metrics["leak_sweep_meeting_targets"] = [r["leak"] for r in sweep["rows"]
                                                 if r["meets_targets"]]
        metrics["timing_s"]["leak_sweep"] = sweep["seconds"]
    if fault_rows:
        metrics["faults"] = _fault_summary(fault_rows)
    U = rec.sensors
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
        if fault_rows:
            _fault_figure(out, metrics["faults"], seeds)
    kid = metrics["kidnap_recovery_ticks"]
    write_metrics(out, metrics, summary=(
        f"two rooms ({len(seeds)} seed(s), leaks {', '.join(f'{v:g}' for v in args.leak)}):"
        f" room cell {paper_room['mean']:.2f} balanced accuracy on the test part, corridor "
        f"cell {cor_cell['mean']:.2f} (leaks 0.11, 0.14); after a kidnapping the room cell is "
        f"right again after " + ("no recovery" if kid != kid else f"{kid:.0f} ticks")
        + f" (targets: {TARGETS['room_cell_test_balanced_accuracy']}, "
        f"{TARGETS['kidnap_recovery_ticks']} ticks)"))
    return metrics


def _leak_key(leak: tuple[float, ...]) -> str:
    return "leak_" + "_".join(f"{v:g}" for v in leak)


def _leak_sweep_one(args: argparse.Namespace, neurons: int, restarts: int, seed: int,
                    U: np.ndarray, rooms: dict[str, np.ndarray], n_train: int,
                    U_kid: np.ndarray, kid_rooms: dict[str, np.ndarray], events: list[int],
                    moved: list[bool]) -> dict[str, Any]:
    """Room cell and kidnapping recovery for each leak pair of the grid, on one seed."""
    leaks = [(a, b) for a in SWEEP_SLOW for b in SWEEP_FAST]
    t0 = time.perf_counter()
    base = RCSFAICA.smc09(n_reservoir=neurons, seed=seed, n_sfa=args.n_sfa,
                          n_ica=args.n_ica, ica_restarts=restarts, ica_score=args.ica_score,
                          sfa_cutoff=sfa_cutoff(args.sfa_cutoff)).params
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        models = fit_leak_sweep(U[:n_train], leaks, base)
    scores = {}
    for lk, model in zip(leaks, models):
        r = _evaluate(model, U, rooms, n_train, U_kid, kid_rooms, events, moved, args.hold)
        scores[lk] = (r["room_cell_test_balanced_accuracy"], r["kidnap_recovery_ticks"])
    return {"scores": scores, "seconds": time.perf_counter() - t0}


def _sweep_summary(per_seed: list[dict[str, Any]]) -> dict[str, Any]:
    leaks = [(a, b) for a in SWEEP_SLOW for b in SWEEP_FAST]
    rows = []
    for lk in leaks:
        room, rec = (mean_sd([p["scores"][lk][j] for p in per_seed]) for j in (0, 1))
        rows.append({"leak": list(lk), "room_cell_test_balanced_accuracy": room[0],
                     "room_cell_test_balanced_accuracy_sd": room[1],
                     "kidnap_recovery_ticks": rec[0], "kidnap_recovery_ticks_sd": rec[1],
                     "meets_targets": bool(
                         room[0] >= TARGETS["room_cell_test_balanced_accuracy"]
                         and rec[0] <= TARGETS["kidnap_recovery_ticks"])})
    return {"rows": rows, "seconds": float(sum(p["seconds"] for p in per_seed))}


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


FAULT_MODES = ("stuck0", "stuck1", "noise")
NOISE_LEVELS = (0.01, 0.02, 0.05, 0.1)
FAULT_TARGETS = {1: 0.90, 2: 0.80, "noise_0.1": 0.93}


def _fault_conditions(n_sensors: int, seed: int, quick: bool) -> list[SensorFaults]:
    """Dead-sensor sets: every single sensor, and random pairs and triples, in each mode; and
    every noise level. The sets depend only on ``seed``."""
    rng = np.random.default_rng([seed, 11])
    n_sets = 2 if quick else 3
    sets: list[tuple[int, ...]] = [()]
    sets += [(i,) for i in range(n_sensors)][: n_sets if quick else None]
    for k in (2, 3):
        sets += [tuple(sorted(rng.choice(n_sensors, k, replace=False).tolist()))
                 for _ in range(n_sets)]
    out = [SensorFaults.of([(i, mode) for i in s]) for s in sets[1:] for mode in FAULT_MODES]
    out.insert(0, SensorFaults())
    out += [SensorFaults.of(sensor_noise=sd) for sd in NOISE_LEVELS]
    return out


def _fault_curve(model: RCSFAICA, U: np.ndarray, rooms: dict[str, np.ndarray], n_train: int,
                 cell: M.BinaryCell, seed: int, quick: bool) -> list[dict[str, Any]]:
    """Room-cell balanced accuracy on the test part when sensors die (or get noisier) at its
    start, read raw and through a :class:`SensorGuard` fitted on the (clean) training part.
    The room cell is the one chosen on the clean training part."""
    guard = SensorGuard().fit(U[:n_train])
    res = model.reservoir_
    x_end = np.asarray(res.run(U[:n_train]))[-1]
    te = slice(n_train, len(U))
    m = rooms["room"][te]
    truth = rooms["room_b"][te][m]
    # guard history: the last window of clean readings precedes the faulty test part
    W = guard.params.window
    rows = []
    for j, faults in enumerate(_fault_conditions(U.shape[1], seed, quick)):
        Ut = faults.apply(U[te], seed=[seed, 13, j])
        for variant in ("raw", "guard"):
            if variant == "guard":
                Ut_v = guard.clean(np.concatenate([U[n_train - W:n_train], Ut]))[W:]
            else:
                Ut_v = Ut
            X = np.asarray(res.run(Ut_v, x0=x_end))
            Z = np.concatenate([Ut_v.astype(X.dtype), X], axis=1)
            Y = model.ica_.transform(model.sfa_.transform(Z))
            rows.append({"seed": seed, "variant": variant, "n_dead": len(faults.dead),
                         "mode": faults.dead[0][1] if faults.dead else "none",
                         "sensors": faults.indices, "noise": faults.sensor_noise,
                         "room_cell_test_balanced_accuracy":
                             M.balanced_accuracy(cell.predict(Y)[m], truth)})
    return rows


def _fault_summary(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Mean, per-seed means and the worst seed, per variant: by number of dead sensors (all
    modes), by mode, and by noise level."""
    out: dict[str, Any] = {"targets": {str(k): v for k, v in FAULT_TARGETS.items()},
                           "rows": rows}
    key = "room_cell_test_balanced_accuracy"
    for variant in ("raw", "guard"):
        R = [r for r in rows if r["variant"] == variant]
        seeds = sorted({r["seed"] for r in R})

        def stat(sel: list[dict[str, Any]], seeds: list[int] = seeds) -> dict[str, Any]:
            per_seed = [float(np.nanmean([r[key] for r in sel if r["seed"] == s]))
                        for s in seeds if any(r["seed"] == s for r in sel)]
            return {"mean": float(np.mean(per_seed)), "worst_seed": float(np.min(per_seed)),
                    "per_seed": per_seed}

        v: dict[str, Any] = {"dead": {}, "dead_by_mode": {}, "noise": {}}
        for k in range(4):
            sel = [r for r in R if r["n_dead"] == k and r["noise"] == 0]
            v["dead"][str(k)] = stat(sel)
            if k:
                v["dead_by_mode"][str(k)] = {mode: stat([r for r in sel if r["mode"] == mode])
                                             for mode in FAULT_MODES}
        for sd in NOISE_LEVELS:
            v["noise"][f"{sd:g}"] = stat([r for r in R if r["noise"] == sd])
        out[variant] = v
    return out


def _fault_figure(out, summary: dict[str, Any], seeds: list[int]) -> None:
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for variant, ls in (("raw", "--"), ("guard", "-")):
        v = summary[variant]
        for mode, c in zip(FAULT_MODES, ("C0", "C1", "C2")):
            ys = [v["dead"]["0"]["mean"]] + [v["dead_by_mode"][str(k)][mode]["mean"]
                                             for k in (1, 2, 3)]
            axes[0].plot(range(4), ys, ls, color=c, marker="o",
                         label=f"{mode}, {'guarded' if variant == 'guard' else 'raw'}")
        axes[1].plot(NOISE_LEVELS, [v["noise"][f"{sd:g}"]["mean"] for sd in NOISE_LEVELS], ls,
                     marker="o", color="k", label="guarded" if variant == "guard" else "raw")
    for k, t in ((1, 0.90), (2, 0.80)):
        axes[0].plot([k], [t], "r_", ms=18, mew=2)
    axes[1].axhline(0.93, color="r", lw=0.8)
    axes[0].set_xlabel("dead sensors (of 8), dying at the start of the test part")
    axes[0].set_xticks(range(4))
    axes[0].set_ylabel("room cell: balanced accuracy (test)")
    axes[1].set_xlabel("added sensor noise s.d.")
    axes[0].legend(fontsize=7)
    axes[1].legend(fontsize=8)
    s = f"{seeds[0]}-{seeds[-1]}" if seeds == list(range(seeds[0], seeds[-1] + 1)) else \
        ",".join(map(str, seeds))
    fig.suptitle(f"room cell under sensor faults (seeds {s}; red: targets)", fontsize=10)
    fig.tight_layout()
    save_figure(fig, out / "faults.png", dpi=110)
    plt.close(fig)
