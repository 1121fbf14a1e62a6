"""SMC09 reproduction: a room cell and a corridor cell learned from 8 IR sensors (RC-SFA-ICA).

The e-puck wall-follows (ρ = 0.008) in the two-rooms arena for 18,120 ticks; an RC-SFA-ICA
model (600 neurons) is fitted on the first 7/8 without labels and tested on the last 1/8. The
room cell's default model is **2 SFA / 2 ICA units with leaks 0.08/0.15**: FastICA rotates only
the two slowest SFA outputs, so a sparse unit cannot pull the slow room signal into a mixture
(SMC09's 4/4 units with 0.05/0.15 do on some runs: ``--n-sfa 4 --n-ica 4 --leak 0.05,0.15``
gives the paper's setting). Chosen on the tuning seeds 0-9 (room cell 0.970 vs 0.914, recovery
12.8 vs 15.9 ticks; docs/results.md). Which unit is the room cell (and its threshold) is chosen
on the training part only (``room_cell_is_slowest`` reports whether it is the slowest unit, a choice
that needs no labels), then scored on the test part by balanced accuracy (room A vs room B,
corridor ticks left out). The test part is then replayed with the robot kidnapped to the other
room at test ticks 150 and 640 and put back at 400 and 980 (SMC09 Fig. 7); we count the ticks
until the room cell is right again and stays right for ``--hold`` ticks (mean over the events
that really changed the robot's room: a wall follower that walked home by itself before being
put back was not kidnapped; not reported for a room cell too near chance,
``_two_rooms_report.RECOVERY_MIN_ACCURACY``). A seed whose training part visits one room has
no room cell, one whose test part does has no score: both are reported unscored, with why
(``unscored_seeds``, ``seeds_scored``). With leaks 0.11/0.14 and SMC09's 4/4 units a corridor cell
appears (SMC09 Fig. 8).
Everything is repeated over ``--seeds`` (a count, or ranges and lists such as ``100-119``):
each seed is one exploration run **and** one reservoir, so held-out seeds are new runs, not
only new weights (mean ± sd, worst seed). The project's convention: settings are chosen on the
tuning seeds 0-9 and reported on the held-out seeds 100-119. ``--cache DIR`` keeps the
recordings for reuse.

Ceiling (``--ceiling``, default; ``--no-ceiling`` skips it): a supervised ridge read-out of
the same reservoir state ``[u; x]`` (room A vs B, 5 blocked folds in time,
:func:`~hippo.perception.ceiling.ridge_ceiling`) shows what the sensors allow next to what
the unsupervised room cell reaches.

Faults (``--faults``): sensors die (stuck at 0, stuck at 1, or noise only; 0-3 of the 8) or
all get noisier (s.d. 0.01-0.1) at the start of the test part; the room cell chosen on clean
training data is scored raw and behind a :class:`~hippo.perception.sensor_guard.SensorGuard`
(``faults`` in the metrics, ``faults.png``).

``--leak`` replaces the room cell's leak pair (default 0.08/0.15). ``--leak-sweep`` also fits a
grid of 16 leak pairs over each reservoir (:func:`~hippo.perception.fit_leak_sweep`: one batched
harvest and parallel fits) and reports the room cell's accuracy and kidnapping recovery for each
pair (``leak_sweep`` in the metrics, ``leak_sweep.png``): the slow leak sets both, one against
the other.
"""

from __future__ import annotations

import argparse
import time
import warnings
from typing import Any

import numpy as np

from hippo.cli_args import Given, distinct_integers, integer, probability, slow_pool
from hippo.cli_args import sfa_cutoff as cli_sfa_cutoff
from hippo.io import save_npz
from hippo.perception import RCSFAICA, ICAConvergenceWarning
from hippo.perception import metrics as M
from hippo.progress import Progress
from hippo.scenarios._common import (
    add_cache_argument,
    add_seeds_argument,
    check_leak_groups,
    check_sfa_inputs,
    mean_sd,
    only_with,
    parse_leak,
    prepare_out,
    seed_list,
    sfa_cutoff,
    write_metrics,
)
from hippo.scenarios._selection import (
    CRITERIA,
    DEFAULT_CRITERION,
    GROUP,
    select_setting,
    selection_summary,
)
from hippo.scenarios._two_rooms_recordings import _recordings
from hippo.scenarios._two_rooms_report import (
    TARGETS,
    _evaluate,
    _fault_curve,
    _fault_figure,
    _fault_summary,
    _figures,
    _leak_key,
    _leak_sweep_one,
    _room_cell_accuracy,
    _room_masks,
    _sweep_figure,
    _sweep_summary,
    headline,
    room_visits,
)
from hippo.sim import arenas

#: SMC09's fixed settings: leaks and SFA / ICA units (reported beside --select's pick)
PAPER_LEAK = (0.05, 0.15)
SMC09_UNITS = 4
#: the room cell's defaults, chosen on tuning seeds 0-9: leaks and SFA / ICA units
ROOM_LEAK = (0.08, 0.15)
ROOM_UNITS = 2
#: the corridor cell keeps SMC09's 4 SFA / 4 ICA units (Fig. 8)
CORRIDOR_UNITS = 4
#: the test part (the last eighth) must hold the first kidnapping and the return (tick 400)
MIN_TICKS = 4000
CORRIDOR_LEAK = (0.11, 0.14)
#: --quick's reservoir size (at most)
QUICK_NEURONS = 120


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--ticks", type=integer(MIN_TICKS, 10_000_000), default=18120,
                        help="recorded control ticks of 0.2 s; the last eighth is the test part "
                             f"with the kidnappings (at least {MIN_TICKS})")
    parser.add_argument("--rho", type=probability, default=0.008,
                        help="wall-side switch probability per tick")
    parser.add_argument("--neurons", type=integer(1, 20_000), default=600, help="reservoir size")
    parser.add_argument("--n-sfa", type=integer(1, 500), default=ROOM_UNITS,
                        help="SFA units of the room-cell model (SMC09: 4)")
    parser.add_argument("--n-ica", type=integer(1, 500), default=ROOM_UNITS,
                        help="ICA units of the room-cell model (at most --n-sfa; SMC09: 4)")
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
    parser.add_argument("--ica-algorithm", default="symmetric",
                        choices=["symmetric", "deflation"],
                        help="FastICA: all units at once, or one after another")
    parser.add_argument("--sfa-cutoff", type=cli_sfa_cutoff, default="1e-8",
                        help="relative whitening cutoff in (0, 1), or 'auto'")
    parser.add_argument("--leak", type=parse_leak, default=ROOM_LEAK,
                        help="leak rates of the room-cell reservoir, one per group of neurons "
                             "(split evenly; default 0.08,0.15; SMC09's halves: 0.05,0.15)")
    parser.add_argument("--slow-pool", type=slow_pool, default=0.0, metavar="TICKS",
                        help="time constant of a slow pool, a leaky running mean of the "
                             "reservoir state appended to the SFA input (default 0: off)")
    parser.add_argument("--leak-sweep", action=argparse.BooleanOptionalAction, default=False,
                        help="also fit a 4x4 grid of leak pairs and report each")
    parser.add_argument("--select", action=argparse.BooleanOptionalAction, default=False,
                        help="also choose the leak pair per seed from the recording alone "
                             "(label-free criterion over the 16-pair grid) and report it "
                             "beside SMC09's")
    parser.add_argument("--select-criterion", choices=CRITERIA, default=DEFAULT_CRITERION,
                        action=Given, help="label-free criterion of --select")
    parser.add_argument("--select-units", type=distinct_integers(1, 500), action=Given,
                        default=(ROOM_UNITS, SMC09_UNITS), metavar="K,K",
                        help="SFA/ICA unit counts --select chooses among (default: "
                             f"{ROOM_UNITS}, the room cell's, and {SMC09_UNITS}, SMC09's)")
    parser.add_argument("--hold", type=integer(1, 10_000), default=5,
                        help="recovered = right for this many consecutive ticks")
    parser.add_argument("--figures", action=argparse.BooleanOptionalAction, default=True,
                        help="write PNGs")


def _neurons(args: argparse.Namespace) -> int:
    """The reservoir size :func:`run` builds: ``--quick`` caps it at :data:`QUICK_NEURONS`."""
    return min(args.neurons, QUICK_NEURONS) if getattr(args, "quick", False) else args.neurons


def check_args(args: argparse.Namespace, parser: argparse.ArgumentParser) -> None:
    """Checks across arguments, before any work."""
    check_leak_groups(args, parser)
    if args.n_ica > args.n_sfa:
        parser.error(f"argument --n-ica: {args.n_ica} exceeds --n-sfa {args.n_sfa} "
                     "(ICA rotates the SFA outputs)")
    only_with(args, parser, "select_units", "select", "the unit counts it chooses among")
    only_with(args, parser, "select_criterion", "select", "the criterion it chooses by")
    neurons = _neurons(args)   # the reservoir run() builds
    what = f" (--quick: {neurons} neurons)" if neurons != args.neurons else ""
    if args.select:
        check_sfa_inputs(parser, "--select-units", max(args.select_units), neurons,
                         args.slow_pool, what)
    # twice the inputs with the slow pool (its running mean is appended to the SFA input)
    check_sfa_inputs(parser, "--n-sfa", args.n_sfa, neurons, args.slow_pool, what)
    if args.slow_pool and (args.faults or args.leak_sweep):
        parser.error("argument --slow-pool: not measured with --faults or --leak-sweep (they "
                     "read the reservoir state without the pool); leave one out")


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
    neurons = _neurons(args)
    restarts = min(args.ica_restarts, 3) if quick else args.ica_restarts
    arena = arenas.two_rooms()
    seeds = seed_list(args)
    n_train = ticks * 7 // 8
    configs = {"paper": tuple(args.leak), "corridor": CORRIDOR_LEAK}
    # SFA / ICA units per configuration (the rest: --n-sfa, --n-ica)
    units_of = {"corridor": (CORRIDOR_UNITS,) * 2, "smc09": (SMC09_UNITS,) * 2}
    per: dict[str, list[dict[str, Any]]] = {k: [] for k in configs}
    sel_rows: list[dict[str, Any]] = []
    keep: dict[str, dict[str, Any]] = {}
    t_fit = t_rec = 0.0
    first = fallback = None   # the first seed with a room cell (run.npz, figures), the first
    skipped: list[int] = []   # seeds whose training part visited one room: no room cell
    sweep_rows: list[dict[str, Any]] = []
    fault_rows: list[dict[str, Any]] = []
    with Progress(len(seeds) * (len(configs) + 3 * args.select), "two-rooms fits") as bar:
        for seed in seeds:
            t0 = time.perf_counter()
            rec, rec_kid, events, kinds, moved = _recordings(args, arena, ticks, n_train, seed)
            t_rec += time.perf_counter() - t0
            rooms, kid_rooms = _room_masks(rec), _room_masks(rec_kid)
            U, U_kid = rec.sensors, rec_kid.sensors
            fallback = fallback or (seed, rec, rec_kid, events, kinds, moved)
            why = room_visits(rooms, slice(0, n_train))
            if why is not None:   # no room cell to fit: the seed is reported unscored
                skipped.append(seed)
                for name in (*configs, *(("selected", "smc09") if args.select else ())):
                    per.setdefault(name, []).append(
                        {"seed": seed, "room_cell_unscored": f"the training part {why}"})
                bar.update(len(configs) + 3 * args.select)
                continue
            first = first or (seed, rec, rec_kid, events, kinds, moved)
            seed_configs = dict(configs)
            if args.select:
                base = RCSFAICA.smc09(n_reservoir=neurons, seed=seed, n_sfa=args.n_sfa,
                                      n_ica=args.n_ica, ica_restarts=restarts,
                                      ica_score=args.ica_score,
                                      ica_algorithm=args.ica_algorithm,
                                      sfa_cutoff=sfa_cutoff(args.sfa_cutoff),
                                      slow_pool=args.slow_pool).params
                bar.update()      # the selection's sweep
                sel_rows.append(select_setting(
                    U, n_train, base, lambda Y, r=rooms: _room_cell_accuracy(Y, r, n_train),
                    args.select_criterion, paper=PAPER_LEAK, paper_units=SMC09_UNITS,
                    units=args.select_units))
                seed_configs["selected"] = tuple(sel_rows[-1]["chosen"])
                seed_configs["smc09"] = PAPER_LEAK
                units_of["selected"] = (sel_rows[-1]["chosen_units"],) * 2
            for name, leak in seed_configs.items():
                units = units_of.get(name, (args.n_sfa, args.n_ica))
                model = RCSFAICA.smc09(n_reservoir=neurons, leak=leak, seed=seed,
                                       n_sfa=units[0], n_ica=units[1],
                                       ica_restarts=restarts, ica_score=args.ica_score,
                                       ica_algorithm=args.ica_algorithm,
                                       sfa_cutoff=sfa_cutoff(args.sfa_cutoff),
                                       slow_pool=args.slow_pool)
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
                if seed == first[0]:
                    keep[name] = res
                    if name == "paper":
                        model.save(out / "place_cells.npz")
                per.setdefault(name, []).append({k: v for k, v in res.items()
                                  if not isinstance(v, np.ndarray | M.BinaryCell)})
                bar.update()
            if args.leak_sweep:
                sweep_rows.append(_leak_sweep_one(args, neurons, restarts, seed, U, rooms,
                                                  n_train, U_kid, kid_rooms, events, moved))
    shown_seed, rec, rec_kid, events, kinds, moved = first or fallback
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
        "corridor_units": CORRIDOR_UNITS,
        "slow_pool": args.slow_pool,
        "ica_restarts": restarts, "ica_score": args.ica_score,
        "ica_algorithm": args.ica_algorithm, "sfa_cutoff": args.sfa_cutoff,
        "room_changes": int(np.sum(np.diff(rec.region.astype(int)) != 0)),
        "region_occupancy": {n: float(np.mean(rec.region == i))
                             for i, n in enumerate(rec.region_names)},
        "leak": list(configs["paper"]),
        # headline numbers (the room cell's model: --leak, --n-sfa, --n-ica; default 0.08/0.15,
        # 2/2 units), unless stated
        "room_cell_test_balanced_accuracy": paper_room["mean"],
        "room_cell_test_balanced_accuracy_sd": paper_room["sd"],
        "room_cell_test_balanced_accuracy_min": paper_room["min"],
        "kidnap_recovery_ticks": paper_kid["mean"],
        "kidnap_recovery_ticks_sd": paper_kid["sd"],
        "kidnap_recovery_ticks_worst_seed": paper_kid["max"],
        # over the seeds whose recovery is reported (each seed's own count: runs)
        "kidnap_unrecovered": int(sum(r.get("kidnap_unrecovered", 0) for r in per["paper"]
                                      if "kidnap_recovery_withheld" not in r)),
        # the seeds with a room cell score, and why the others have none; the seeds whose
        # recovery is left out (a room cell too near chance: RECOVERY_MIN_ACCURACY)
        "seeds_scored": int(np.isfinite(paper_room["per_seed"]).sum()),
        "unscored_seeds": {str(r["seed"]): r["room_cell_unscored"] for r in per["paper"]
                           if "room_cell_unscored" in r},
        "kidnap_recovery_withheld_seeds": {
            str(r["seed"]): r["kidnap_recovery_withheld"] for r in per["paper"]
            if "kidnap_recovery_withheld" in r and "room_cell_unscored" not in r},
        "shown_seed": shown_seed,   # run.npz, place_cells.npz and the figures
        # seeds whose room cell (chosen with training labels) is also the slowest unit
        "room_cell_is_slowest_unit": int(sum(r.get("room_cell_is_slowest", False)
                                             for r in per["paper"])),
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
    if args.select and sel_rows:
        key = "room_cell_test_balanced_accuracy"
        # the picked setting against SMC09's fixed one (4 units, 0.05/0.15), both fitted by
        # the scenario on the whole training part (the seeds with a room cell)
        metrics["selection"] = selection_summary(
            sel_rows, [s for s in seeds if s not in skipped],
            *([r[key] for r in per[n] if r["seed"] not in skipped]
              for n in ("selected", "smc09")))
        metrics["selected"] = {k: summary("selected", k) for k in keys}
        metrics["smc09"] = {k: summary("smc09", k) for k in keys}
    U = rec.sensors
    if not keep:   # no seed has a room cell: nothing to show (the summary says why)
        write_metrics(out, metrics, summary=headline(metrics, args.leak))
        return metrics
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
    write_metrics(out, metrics, summary=headline(metrics, args.leak) + _selection_line(metrics))
    return metrics


def _selection_line(metrics: dict[str, Any]) -> str:
    """With --select: the pick's room cell beside SMC09's fixed settings, one line."""
    sel = metrics.get("selection")
    if sel is None:
        return ""
    return (f"\nlabel-free pick ({sel['criterion']}): room cell {sel['picked_mean']:.3f} vs "
            f"SMC09's fixed settings {sel['paper_mean']:.3f}; the worst group of up to "
            f"{GROUP} seeds {sel['picked_minus_paper_worst_group']:+.3f} (target: >= -0.01)")
