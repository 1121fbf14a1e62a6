"""A long deployment of the learned patrol, its failures counted the RatSLAM way.

The robot learns the patrol as in ``hippo run patrol`` (its own exploration and place cells,
one loop on the leash, one alone, the checkpoint waits taught by blocks), then patrols alone
for ``--hours`` simulated hours, every drive kept up. Every pass by a checkpoint is a task
(Milford & Wyeth, IJRR 2010: 1,143 delivery tasks, one failure, 37 hours); a failure is a pass
without its stop (``missed``), a stop it chose in the wrong place or for the wrong checkpoint
(``misplaced``), a wait more than 5 % off the wait it learned (``wait_off``), or no progress
along the route for 3 minutes (``stuck``: the operator then puts it back on the route, 20 cm
ahead). See :mod:`hippo.tasks.deployment`. ``success_rate`` is the share of passes served (a
stop whose wait is within 5 %); ``failures_total`` and ``tasks_per_failure`` count every kind.
``laps`` are signed laps along the route (negative: run backwards).

The run is cut into segments of ``--segment-min`` simulated minutes, each ending at the route's
quiet point (no stop straddles two). After each segment the failures are tallied, the robot's
health is sampled (states, transitions, map edges, drive levels, largest weight, memory: none
may grow without bound) and the whole run is checkpointed into ``OUT/resume``. ``--resume``
continues a run that was killed from its last checkpoint, with the same results as a run
never stopped; a finished run removes its checkpoints.

Writes ``metrics.json`` (totals, failures per kind and per hour, the segments), the figure
``deployment.png`` and ``run.npz`` of the last segment.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from hippo.cli_args import number
from hippo.io import save_figure, save_json
from hippo.progress import Progress
from hippo.resume import Checkpoints
from hippo.scenarios._common import prepare_out, smoke_test, write_metrics
from hippo.scenarios._patrol_lesson import (
    add_course_arguments,
    check_course_args,
    heading_sectors,
    teach_patrol,
)
from hippo.tasks import Log, Session
from hippo.tasks.deployment import (
    FAILURE_KINDS,
    DeploymentParams,
    StuckWatch,
    health,
    tally_failures,
)
from hippo.tasks.patrol import PatrolCourse, PatrolPhase
from hippo.tasks.patrol_sets import led_route

Phase = PatrolPhase


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_course_arguments(parser)
    parser.add_argument("--hours", type=number(0.1, 1000.0), default=8.0,
                        help="simulated hours of autonomous patrol (--quick: at most 0.5); "
                             "each segment ends where the route is farthest from every "
                             "checkpoint, up to a lap later, so a robot that stalls runs over "
                             "(the hours run are reported)")
    parser.add_argument("--segment-min", type=number(5.0, 600.0), default=30.0,
                        help="tally, health sample and checkpoint every this many simulated "
                             "minutes")
    parser.add_argument("--resume", action="store_true",
                        help="continue from the last checkpoint in OUT/resume (a run that was "
                             "killed); without it a run starts afresh")


def check_args(args: argparse.Namespace, parser: argparse.ArgumentParser) -> None:
    """The course's checks, and no ``--save`` with ``--resume``: a resumed run continues from
    its checkpoint without teaching, so it had no robot to save and wrote nothing."""
    if getattr(args, "resume", False) and getattr(args, "save", None) is not None:
        parser.error("argument --save: not allowed with --resume (a resumed run teaches no "
                     "robot to save); save with the run that teaches it")
    check_course_args(args, parser)


def _meta(args: argparse.Namespace, hours: float, units: int) -> dict:
    return {"scenario": "deployment", "seed": int(args.seed), "arena": args.arena,
            "checkpoints": [list(map(float, c)) for c in args.checkpoints],
            "waits": [float(w) for w in args.waits], "place_cells": args.place_cells,
            "explore_min": float(args.explore_min), "units": int(units),
            "places": int(args.places), "route": getattr(args, "route", "auto"),
            "heading_sectors": heading_sectors(args), "reanchor": bool(args.reanchor),
            "hours": float(hours),
            "segment_min": float(args.segment_min),
            # a robot taught with --quick (--load) stays a smoke test when loaded without it
            "quick": smoke_test(args)}


def run(args: argparse.Namespace) -> dict:
    if getattr(args, "checkpoints", None) is None or getattr(args, "waits", None) is None:
        check_args(args, argparse.ArgumentParser(prog="hippo run deployment"))
    out = prepare_out(args.out)
    quick = bool(args.quick)
    hours = min(args.hours, 0.5) if quick else float(args.hours)
    units = min(args.units, 16) if quick else args.units
    meta = _meta(args, hours, units)
    ckpt = Checkpoints(out / "resume")
    t0 = time.perf_counter()
    state = ckpt.load(dict) if getattr(args, "resume", False) else None
    if state is None:
        if getattr(args, "resume", False):
            print(f"--resume: no checkpoint in {ckpt.folder}; starting afresh",
                  file=sys.stderr)
        ckpt.clear()
        lesson = teach_patrol(args, int(args.seed), units=units)
        s, course = lesson.session, lesson.course
        s.world.detach(s.teacher)  # the teacher stays away from now on
        course.drives_up()
        course.laps()
        state = {"learned": course.learned_waits(), "reproduced": lesson.reproduced,
                 "t_start": s.t, "segments": [], "health0": health(s.agent, 0.0)}
        state["wall_s"] = time.perf_counter() - t0   # a run killed before its first segment
        ckpt.save(_checkpoint(meta, s, course, state))
    else:
        if state.get("meta") != meta:
            was = state.get("meta") or {}
            diff = "; ".join(f"{k}: {was.get(k)!r} there, {meta.get(k)!r} now"
                             for k in sorted(set(was) | set(meta)) if was.get(k) != meta.get(k))
            raise SystemExit(f"--resume: the checkpoint in {ckpt.folder} was made with other "
                             f"options ({diff}); give the same options, or leave out "
                             "--resume to start afresh")
        s = Session(state["world"], state["agent"], Log(n_drives=len(args.checkpoints)),
                    obs=state["obs"])
        s.world.detach(s.teacher)
        _, loop = led_route(args.arena, args.checkpoints, getattr(args, "route", "auto"),
                            s.agent.params.motor.wall_side)   # the route the lesson was given
        course = PatrolCourse(s, loop, args.checkpoints, [f"checkpoint-{k}" for k in
                                                          range(1, len(args.checkpoints) + 1)])
        course.loop = state["loop"]
        state = state["run"]
        print(f"resuming from {ckpt.latest()} ({len(state['segments'])} segments done, "
              f"{(s.t - state['t_start']) / 3600:.2f} of {hours:g} h)")
    t_end = state["t_start"] + hours * 3600.0
    n_seg = int(np.ceil(hours * 60.0 / args.segment_min - 1e-9))
    p = DeploymentParams()
    wall_before = float(state.get("wall_s", 0.0))   # the processes before a resume
    with Progress(n_seg, "deployment") as bar:
        bar.update(len(state["segments"]))
        while s.t < t_end - 1e-6 and len(state["segments"]) < n_seg:
            seg = _segment(s, course, state, p, min(s.t + args.segment_min * 60.0, t_end))
            state["segments"].append(seg)
            # wall time of every process that ran this deployment, for a resumed run too
            state["wall_s"] = wall_before + time.perf_counter() - t0
            ckpt.save(_checkpoint(meta, s, course, state))
            save_json(out / "segments.json", state["segments"])
            bar.update()
    s.save(out, Phase)  # run.npz: the last segment
    metrics = _metrics(meta, state, s, wall_before + time.perf_counter() - t0)
    from hippo.plots.deployment import plot_deployment

    fig, _ = plot_deployment(state["segments"])
    save_figure(fig, out / "deployment.png")
    ckpt.clear()
    f = metrics["failures"]
    write_metrics(out, metrics, summary=(
        f"deployment ({args.arena}, {args.place_cells} place cells): "
        f"{metrics['hours']:.1f} h, {metrics['tasks']} checkpoint passes, "
        f"{metrics['failures_total']} failures ("
        + ", ".join(f"{k} {f[k]}" for k in FAILURE_KINDS)
        + f"); states {metrics['health_start']['states']} -> {metrics['health_end']['states']}"
        f", memory {metrics['health_start']['rss_mb']:.0f} -> "
        f"{metrics['health_end']['rss_mb']:.0f} MB"))
    return metrics


def _checkpoint(meta: dict, s: Session, course: PatrolCourse, state: dict) -> dict:
    return {"meta": meta, "agent": s.agent, "world": s.world, "obs": s.obs,
            "loop": course.loop, "run": state}


def _segment(s: Session, course: PatrolCourse, state: dict, p: DeploymentParams,
             t_stop: float) -> dict:
    """Patrol until ``t_stop``, then on to the route's quiet point; rescue the robot when it
    is stuck; tally the segment's failures and sample the robot's health."""
    s.log = Log(n_drives=len(course.names))
    s.phase, s.trial = Phase.DEPLOYMENT, len(state["segments"])
    t0, turns0 = s.t, course.laps()
    watch = StuckWatch(p.stuck_s, p.stuck_cm)
    watch.reset(s.t, course.loop.travelled)
    stuck = [0]

    def until(target):
        def check(o) -> bool:
            course.laps()
            if watch.update(o.t, course.loop.travelled):
                stuck[0] += 1
                _rescue(s, course)
                watch.reset(s.t, course.loop.travelled)
            return target()
        return check

    s.run(int((t_stop - s.t) / s.world.dt) + 1, until=until(lambda: s.t >= t_stop))
    end = course.laps_to_quiet(0)
    s.run(int(course.lap_s / s.world.dt), until=until(lambda: course.loop.turns >= end))
    tally = tally_failures(s.log.arrays(), course.route, course.checkpoints, state["learned"],
                           s.world.robot.moving_threshold, phase=Phase.DEPLOYMENT,
                           tolerance=p.tolerance)
    return {"t0_h": (t0 - state["t_start"]) / 3600.0, "t1_h": (s.t - state["t_start"]) / 3600.0,
            "laps": float(course.loop.turns - turns0), "stuck": stuck[0],
            **{k: v for k, v in tally.items() if k not in ("rel_errors",)},
            "health": health(s.agent, s.t - state["t_start"])}


def _rescue(s: Session, course: PatrolCourse) -> None:
    """The operator puts the robot back on the route 20 cm ahead of where it was."""
    route, loop = course.route, course.loop
    x, y, heading = route.at((loop.progress or 0.0) + 20.0)
    s.put(x, y, heading, event="rescue", keep_drives=True)
    loop.reset()
    course.laps()


def _metrics(meta: dict, state: dict, s: Session, wall: float) -> dict:
    segs = state["segments"]
    failures = {k: int(sum(g[k] for g in segs)) for k in FAILURE_KINDS}
    tasks = int(sum(g["tasks"] for g in segs))
    hours = float(segs[-1]["t1_h"]) if segs else 0.0
    total = int(sum(failures.values()))
    waits = [[w for g in segs for w in g["waits_s"][k]] for k in range(len(meta["waits"]))]
    first, last = state["health0"], segs[-1]["health"] if segs else state["health0"]
    return {**meta, "hours": hours, "tasks": tasks, "failures": failures,
            "failures_total": total, "failures_per_hour": total / hours if hours else None,
            "tasks_per_failure": tasks / total if total else None,
            # the passes served (a stop, its wait within tolerance); misplaced stops and
            # stuck spells happen outside passes and count in failures_total only
            "success_rate": (1.0 - (failures["missed"] + failures["wait_off"]) / tasks
                             if tasks else None),
            "extra_stops": int(sum(g["extra_stops"] for g in segs)),
            "laps": float(sum(g["laps"] for g in segs)),
            "reproduced_loop_fraction": round(float(state["reproduced"]), 9),
            "learned_waits_s": state["learned"],
            "waits_s": [{"mean": float(np.mean(w)) if w else None,
                         "sd": float(np.std(w)) if w else None, "n": len(w)} for w in waits],
            "health_start": first, "health_end": last,
            "states_growth_after_first_hour": _growth(segs, "states"),
            "transitions_growth_after_first_hour": _growth(segs, "transitions"),
            "segments": segs, "simulated_s": float(s.t), "wall_s": wall}


def _growth(segs: list[dict], key: str) -> int | None:
    """How many ``key`` were added after the first simulated hour (None: shorter runs)."""
    after = [g["health"][key] for g in segs if g["t1_h"] >= 1.0]
    return int(after[-1] - after[0]) if len(after) >= 2 else None
