"""HIREL III-B security patrol: learn a loop on a leash, learn how long to wait at each
checkpoint, reproduce it alone.

Phases (each with a progress bar):

1. **exploration** — place cells from an unsupervised wall-following tour of ``patrol_course()``
   (RC-SFA-ICA on the robot's own sensors; ``--place-cells ground-truth`` for comparison).
2. **leash** — the teacher leads one loop; the robot learns places and transitions.
3. **reproduction** — the robot reproduces the loop alone (no drive: the only known way on).
4. **checkpoints** — on the next loop the teacher blocks the robot at three checkpoints for
   ``--waits`` seconds; each checkpoint's wait is tied to the place where it happened and to its
   own drive.
5. **patrol** — ``--loops`` loops alone: at each checkpoint the drive makes the robot stop, the
   learned delay ends the wait, and it moves on.
6. **adaptation** — the teacher holds the robot longer when it stops at checkpoint 1, and
   restarts it early with the leash at checkpoint 2, then one more loop: the waits follow.
7. **kidnap** — the robot is put down on the route 75 cm before the checkpoint it served last (its
   drive is lowest) and heads on to a checkpoint whose drive is high.

Any arena, any checkpoints. ``--arena`` picks the world (``patrol-course``, HIREL's loop, by
default; ``two-rooms``, ``goal-arena``, ``maze``), ``--checkpoints`` two to four points in it
(each arena has default ones) and ``--waits`` one wait per checkpoint. The leash route runs
through the checkpoints in order along the arena's shortest paths and back to the first (on
``patrol-course`` with its default checkpoints: the corridor loop); where a corridor is the
only way between two checkpoints the route runs along it both ways, and a leg goes round a
third checkpoint where a way round exists (a loop round a ring). Where those paths make no
loop, ``--route auto`` (the default) takes the loop the exploring wall follower runs round
the arena instead, if it passes every checkpoint (``two-rooms``: ``hippo.tasks.wall_tour``;
``--route shortest`` or ``tour`` choose); so does a loop no wall goes round its way
(``goal-arena`` clockwise: the checkpoints are then patrolled the other way round). The
robot explores along the wall that takes it the way the route runs, and follows that wall on
its moves
(``hippo.tasks.wall_side``; ``route_winding`` and ``wall_side`` in ``metrics.json``). Laps
and passes are measured by progress along that route (``hippo.tasks.LapCounter``,
``route_passes``), and each phase that counts laps ends at the point of the route farthest
from every checkpoint, so that no stop straddles the end of a phase.

Metrics. Each pass of the robot by a checkpoint during the patrol (its progress along the
route within 30 cm of the checkpoint's, once per lap) is a chance to stop there:
``checkpoint_stops_expected`` counts the passes, ``checkpoint_stops_made`` the passes with a
stop the robot chose for that checkpoint's drive (its first one; ``extra_stops`` counts further
stops in the same pass, ``misplaced_stops`` stops made there for another checkpoint's drive).
``reproduced_waits_s`` are the durations of the counted stops, ``max_rel_error`` their
worst relative difference from the learned wait. ``reproduced_loop_fraction`` (the loop
reproduced alone after the leash) and ``loops_completed`` (the patrol's) are signed laps along
the route: negative when the robot went round it backwards; ``loop_completion`` is
``loops_completed / --loops`` clipped to [0, 1].

``run.npz`` holds per-tick ``t, x, y, heading, speed, zone, sound, winner, drives, wait_drive,
mode, prediction, non_occurrence, phase, trial``, the names of the phases and modes
(``phase_names``, ``mode_names``) and the teacher's events.
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np

from hippo.cli_args import integer
from hippo.scenarios._common import prepare_out, smoke_test, write_metrics
from hippo.scenarios._patrol_lesson import add_course_arguments, check_course_args, teach_patrol
from hippo.sim import arenas
from hippo.tasks import Route, stops
from hippo.tasks.patrol import PatrolPhase, PatrolWarning, pass_report

Phase = PatrolPhase


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_course_arguments(parser)
    parser.add_argument("--loops", type=integer(1, 100), default=5,
                        help="autonomous patrol loops")


check_args = check_course_args


def _wait_summary(r: dict) -> str:
    """One checkpoint's waits for the summary line: the wait asked for (``--waits``), learned
    (flagged when more than 5 % off it), reproduced, or why there is none."""
    asked, learned = r["taught_block_s"], r["learned_wait_s"]
    text = f"{r['checkpoint']}: wait {asked:g} s"
    if r["taught_stop_s"] is None:
        return text + ", never taught"
    if learned is None:
        return text + ", not learned"
    text += f", learned {learned:.1f} s"
    if abs(learned - asked) > 0.05 * asked:   # (learned / asked - 1 is 5 % + 4e-17 at 21 / 20)
        text += f" ({100 * (learned / asked - 1.0):+.0f} %)"
    if not r["passes"]:
        return text + ", never passed on the patrol"
    return text + ", reproduced " + (f"{r['mean_s']:.1f} ± {r['sd_s']:.2f} s"
                                     if r["mean_s"] is not None else "none")


def route_note(route: Route, kind: str = "shortest") -> str:
    """What the summary says about a route the patrol is known not to hold on: one that runs
    out and back (:attr:`Route.winding` 0) and is not a wall tour (``kind``, from
    :func:`hippo.tasks.patrol_sets.choose_route`: a tree's tour runs every corridor both ways too,
    along the line the robot explored), else nothing."""
    if route.winding != 0 or kind == "tour":
        return ""
    return ("\nnote: this route runs out and back (it encloses little: Route.winding 0); the "
            "robot does not reproduce such routes yet (a known limitation: the patrol "
            "tutorial, section 4)")


def run(args: argparse.Namespace) -> dict:
    if getattr(args, "checkpoints", None) is None or getattr(args, "waits", None) is None:
        check_args(args, argparse.ArgumentParser(prog="hippo run patrol"))
    out = prepare_out(args.out)
    seed = int(args.seed)
    quick = bool(args.quick)
    waits = list(args.waits)
    loops = min(args.loops, 2) if quick else int(args.loops)
    units = min(args.units, 16) if quick else args.units
    arena = arenas.get(args.arena)
    checkpoints = [tuple(map(float, c)) for c in args.checkpoints]
    t0 = time.perf_counter()
    lesson = teach_patrol(args, seed, units=units)
    world, agent, s, course = lesson.world, lesson.agent, lesson.session, lesson.course
    places, names, loop_route = agent.places, course.names, course.route
    reproduced = lesson.reproduced
    # the learned delays are read before the patrol (which re-learns them)
    learned_waits = course.learned_waits()
    with warnings.catch_warnings():   # the summary gives the loops (loops_note)
        warnings.simplefilter("ignore", PatrolWarning)
        completed = course.patrol(loops)
    longer, shorter, i_adapt, i_adapt_end = course.adapt(waits, arena)
    levels, low, kidnap_stop = course.kidnap()
    obs = s.obs
    wall = time.perf_counter() - t0

    arrays = s.save(out, Phase)
    all_stops = stops(arrays, checkpoints, world.robot.moving_threshold,
                      taught_phase=Phase.CHECKPOINTS)
    rows = []
    report = pass_report(arrays, loop_route, checkpoints, all_stops, learned_waits,
                         phase=Phase.PATROL)
    for k, r in enumerate(report):
        rep, err = r.pop("reproduced_waits_s"), r.pop("rel_errors")
        rows.append({"checkpoint": names[k], "taught_block_s": waits[k],
                     "taught_stop_s": lesson.taught_stops[k],
                     "learned_wait_s": learned_waits[k], "reproduced_waits_s": rep, **r,
                     "mean_s": float(np.mean(rep)) if rep else None,
                     "sd_s": float(np.std(rep)) if rep else None,
                     "max_rel_error": float(max(err)) if err else None})
    adapt = {}
    adapt_stops = [st for st in all_stops if i_adapt <= st["i0"] < i_adapt_end]
    for k, key, taught_s in ((0, "longer_block", longer), (1, "leash_restart", shorter)):
        after = [st["duration"] for st in adapt_stops if st["checkpoint"] == k]
        adapt[key] = {"before_s": rows[k]["mean_s"], "taught_s": taught_s,
                      "after_s": after[0] if after else None}
    metrics = {
        "place_cells": args.place_cells, "seed": seed, "arena": args.arena,
        "checkpoints_cm": [list(c) for c in checkpoints], "route_cm": loop_route.length,
        "route_kind": lesson.route_kind,
        "route_winding": loop_route.winding, "wall_side": int(agent.p.wall_side),
        "waits_s": waits, "loops": loops,
        # a robot taught with --quick stays a smoke test when loaded without it
        "quick": smoke_test(args),
        "place_units": places.n_units,
        "heading_sectors": int(agent.p.heading_sectors),
        # the drives' discount: seconds per hop, None per state crossed (a robot saved before)
        "planner_hop_time": agent.p.planner.hop_time,
        "reanchor": getattr(places, "relocaliser", None) is not None,
        "loaded_from": str(args.load) if getattr(args, "load", None) is not None else None,
        # signed laps along the route (negative: run backwards), rounded off at 1e-9
        "reproduced_loop_fraction": round(float(reproduced), 9),
        "loops_completed": round(float(completed), 9),
        "loop_completion": float(np.clip(completed / loops, 0.0, 1.0)),
        "checkpoints": rows,
        "adaptation": adapt,
        "checkpoint_stops_made": int(sum(r["stops_made"] for r in rows)),
        "checkpoint_stops_expected": int(sum(r["passes"] for r in rows)),
        "extra_stops": int(sum(r["extra_stops"] for r in rows)),
        "misplaced_stops": int(sum(r["misplaced_stops"] for r in rows)),
        "kidnap": {"drive_levels": levels, "highest_drive": max(levels, key=levels.get),
                   "put_before": low, "first_stop": kidnap_stop,
                   # the map recognised a place change (None: no localiser, or not within
                   # the run to the first stop)
                   "relocalised_after_s": course.relocalised_s,
                   "passed_the_low_drive": bool(kidnap_stop is not None
                                                and kidnap_stop["nearest_checkpoint"] != low
                                                and kidnap_stop["distance_cm"] < 30.0)},
        "states": agent.layer.n_states, "transitions": len(agent.graph),
        "simulated_s": float(obs.t), "wall_s": wall,
        "realtime_factor": float(obs.t) / wall,
    }
    from hippo.plots.agent import plot_patrol

    plot_patrol(out, arena, agent, arrays, rows, checkpoints)
    waits = "; ".join(_wait_summary(r) for r in rows)
    shuttle = route_note(loop_route, lesson.route_kind)
    write_metrics(out, metrics, summary=(
        f"patrol ({args.arena}, {args.place_cells} place cells): stopped at "
        f"{metrics['checkpoint_stops_made']} of {metrics['checkpoint_stops_expected']} "
        f"checkpoint passes{loops_note(metrics)}; {waits}{shuttle}"))
    return metrics


def loops_note(m: dict) -> str:
    """The loops and stray stops beside the pass count: a patrol that went round a fraction of
    its loops, or backwards, scores only the passes it made."""
    text = f" over {m['loops_completed']:.2f} of {m['loops']} loops"
    if m["extra_stops"] or m["misplaced_stops"]:
        text += f" ({m['extra_stops']} extra, {m['misplaced_stops']} misplaced stops)"
    if m["loop_completion"] < 0.9:
        text += (" - the robot went round backwards" if m["loops_completed"] < 0 else
                 " - the loops were not completed") + ", so few passes were counted"
    return text
