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
7. **kidnap** — the robot is put down on the path before the checkpoint it served last (its
   drive is lowest) and heads on to a checkpoint whose drive is high.

Metrics. Each pass of the robot within 30 cm of a checkpoint during the patrol is a chance to
stop there: ``checkpoint_stops_expected`` counts the passes, ``checkpoint_stops_made`` the passes
with a stop the robot chose for that checkpoint's drive (its first one; ``extra_stops`` counts
further stops in the same pass, ``misplaced_stops`` stops made there for another checkpoint's
drive). ``reproduced_waits_s`` are the durations of the counted stops, ``max_rel_error`` their
worst relative difference from the learned wait.

``run.npz`` holds per-tick ``t, x, y, heading, speed, zone, sound, winner, drives, wait_drive,
mode, prediction, non_occurrence, phase, trial`` and the teacher's events.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from hippo.agent import Agent, AgentParams
from hippo.cognitive_map import DriveParams, PlannerParams
from hippo.progress import Progress
from hippo.scenarios._common import prepare_out, write_metrics
from hippo.scenarios.place_preference import STATES, Log, explore, make_places, run_agent
from hippo.sim import World, arenas, wrap_angle

PHASES = ("exploration", "leash", "reproduction", "checkpoints", "patrol", "adaptation",
          "kidnap")


def _waits(text: str) -> list[float]:
    try:
        w = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"--waits takes numbers separated by commas, got "
                                         f"{text!r}") from None
    if len(w) != 3 or not all(math.isfinite(v) and 0.5 <= v <= 120 for v in w):
        raise argparse.ArgumentTypeError(f"--waits needs three waits between 0.5 and 120 s, "
                                         f"got {text!r}")
    return w


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--waits", type=_waits, default=[24.1, 19.1, 11.6],
                        help="checkpoint waits in s (default: HIREL's 24.1,19.1,11.6)")
    parser.add_argument("--loops", type=int, default=5, help="autonomous patrol loops")
    parser.add_argument("--place-cells", choices=["learned", "ground-truth"], default="learned")
    parser.add_argument("--explore-min", type=float, default=30.0, help="exploration, minutes")
    parser.add_argument("--units", type=int, default=24, help="ICA units of the place cells")
    parser.add_argument("--places", type=int, default=32,
                        help="place prototypes read out from the ICA units (learned cells)")


class Loop:
    """Counts laps of the robot around the course (by the angle around its centre)."""

    def __init__(self, centre: tuple[float, float]) -> None:
        self.cx, self.cy = centre
        self.angle = None
        self.turns = 0.0

    def update(self, x: float, y: float) -> float:
        a = math.atan2(y - self.cy, x - self.cx)
        if self.angle is not None:
            self.turns += ((a - self.angle + math.pi) % (2 * math.pi) - math.pi) / (2 * math.pi)
        self.angle = a
        return self.turns


def run(args: argparse.Namespace) -> dict:
    out = prepare_out(args.out)
    seed = int(args.seed)
    quick = bool(args.quick)
    waits = list(args.waits)
    loops = min(args.loops, 2) if quick else int(args.loops)
    if loops < 1:
        raise SystemExit("--loops must be >= 1")
    explore_min = args.explore_min
    units = min(args.units, 16) if quick else args.units
    arena = arenas.patrol_course()
    world = World(arena, sensors="ir8", seed=seed)
    dt = world.dt
    log = Log(n_drives=3)
    t0 = time.perf_counter()
    checkpoints = [arena.landmarks[f"checkpoint-{k}"] for k in (1, 2, 3)]
    names = [f"checkpoint-{k}" for k in (1, 2, 3)]

    # 1. exploration: place cells only (HIREL learns the map on the leash)
    ticks = round(explore_min * 60 / dt)
    explored = explore(world, ticks, 0.0, seed, log, "exploration")
    sensors = np.array([o.ir for o in explored])
    places = make_places(args.place_cells, arena, sensors, units, seed, args.places)
    places.prime(sensors[-500:])  # the robot's reservoir ran all along: continue from its state
    drive = DriveParams(epsilon=0.01, learning_rate=0.5)
    params = AgentParams(states=STATES,
                         planner=PlannerParams(w=0.9, noise=0.0, exploration_threshold=0.05))
    agent = Agent(places, drives=dict.fromkeys(names, drive), params=params,
                  sensors=world.sensors, robot=world.robot, seed=seed)
    obs = explored[-1]
    loop = Loop((74.0, 56.0))

    def lap_until(target: float):
        def until(o) -> bool:
            return loop.update(o.pose[0], o.pose[1]) >= target
        return until

    # let the place cells settle on the course before the leash
    agent.lifted()
    obs = run_agent(world, agent, obs, int(agent.p.settle_time / dt) + 1, log, 1, 0)

    # 2. one loop on the leash, counter-clockwise from the nearest waypoint
    wp = arenas.loop_waypoints()[:-1]
    i0 = int(np.argmin([math.hypot(x - obs.pose[0], y - obs.pose[1]) for x, y in wp]))
    x, y, h = obs.pose
    if math.cos(math.atan2(wp[i0][1] - y, wp[i0][0] - x) - h) < 0:
        i0 = (i0 + 1) % len(wp)  # the nearest waypoint is behind: lead on, not back
    route = wp[i0:] + wp[:i0] + [wp[i0]]
    world.teacher.lead(route)
    loop.update(*obs.pose[:2])
    with Progress(1, "leash") as bar:
        obs = run_agent(world, agent, obs, 6000, log, 1, 0,
                        until=lambda o: not world.teacher.leading)
        bar.update()

    # 3. reproduction: no drive is active, the only known way on is the taught loop
    agent.drives.step(0.0)
    start_turns = loop.update(*obs.pose[:2])
    with Progress(1, "reproduction") as bar:
        obs = run_agent(world, agent, obs, int(400 / dt), log, 2, 0,
                        until=lap_until(start_turns + 1.0))
        reproduced = loop.turns - start_turns
        bar.update()

    # 4. checkpoints: block the robot at each checkpoint for its wait, reward its drive after
    taught: list[dict] = []
    with Progress(3, "checkpoints") as bar:
        for k, (cx, cy) in enumerate(checkpoints):
            obs = run_agent(world, agent, obs, int(300 / dt), log, 3, k,
                            until=lambda o, cx=cx, cy=cy: math.hypot(o.pose[0] - cx,
                                                                     o.pose[1] - cy) < 12.0)
            world.teacher.block(waits[k])
            tb = obs.t
            obs = run_agent(world, agent, obs, int((waits[k] + 1) / dt), log, 3, k,
                            until=lambda o: not world.teacher.blocking)
            agent.reward(names[k])
            obs = run_agent(world, agent, obs, int(10 / dt), log, 3, k,
                            until=lambda o: agent.state is not None
                            and agent.layer.key(agent.state).kind != "still")
            taught.append({"block_s": waits[k], "block_t": tb})
            bar.update()

    # 5. autonomous patrol (the learned delays are read before it: the patrol re-learns them)
    learned_delays = {}
    for n in names:
        delays = [agent.cells.learned_delay(t) for t in agent.drives.links(n)
                  if t in agent.cells.transitions]
        learned_delays[n] = float(np.median(delays)) if delays else None
    for d in names:
        agent.drives.set_level(d, 1.0)
    start_turns = loop.update(*obs.pose[:2])
    with Progress(loops, "patrol") as bar:
        for k in range(loops):
            obs = run_agent(world, agent, obs, int(600 / dt), log, 4, k,
                            until=lap_until(start_turns + k + 1.0))
            bar.update()
    completed = loop.turns - start_turns

    # 6. adaptation: a longer block at checkpoint 1, an early leash restart at checkpoint 2
    adapt = {}
    longer = waits[0] + 8.0
    (c1x, c1y), (c2x, c2y) = checkpoints[0], checkpoints[1]
    # the teacher holds the robot when it stops at checkpoint 1 by itself: its stillness
    # lasts `longer` s instead of the learned wait (if it passes without stopping, it is held
    # where the checkpoint was taught, as in teaching)
    def at_c1(o) -> bool:
        d = math.hypot(o.pose[0] - c1x, o.pose[1] - c1y)
        still = agent.state is not None and agent.layer.key(agent.state).kind == "still"
        return d < 30.0 and (still or agent.mode in ("approach", "wait") or d < 12.0)

    obs = run_agent(world, agent, obs, int(400 / dt), log, 5, 0, until=at_c1)
    if agent.mode == "approach":  # about to stop: let it
        obs = run_agent(world, agent, obs, int(20 / dt), log, 5, 0,
                        until=lambda o: agent.mode != "approach")
    world.teacher.block(longer)
    obs = run_agent(world, agent, obs, int((longer + 10) / dt), log, 5, 0,
                    until=lambda o: not world.teacher.blocking)
    obs = run_agent(world, agent, obs, int(400 / dt), log, 5, 1,
                    until=lambda o: agent.state is not None
                    and agent.layer.key(agent.state).kind == "still"
                    and math.hypot(o.pose[0] - c2x, o.pose[1] - c2y) < 30.0)
    shorter = waits[1] / 2
    obs = run_agent(world, agent, obs, int(shorter / dt), log, 5, 1)
    _, path = arena.shortest_path(obs.pose[:2], (c2x + 0.0, c2y + 30.0))
    world.teacher.lead(path)
    obs = run_agent(world, agent, obs, 2000, log, 5, 1, until=lambda o: not world.teacher.leading)
    start_turns = loop.update(*obs.pose[:2])
    i_adapt = len(log.cols["t"])
    # one loop and a bit: it starts just past checkpoint 2, which it must meet again
    obs = run_agent(world, agent, obs, int(800 / dt), log, 5, 2,
                    until=lap_until(start_turns + 1.25))
    i_adapt_end = len(log.cols["t"])

    # 7. kidnap: the robot is put down on the path two waypoints before the checkpoint whose
    # drive is lowest (it was served last), facing along the loop. Does it head on to a
    # checkpoint with a high drive instead of stopping at the one it was put before?
    levels = {n: agent.drives.level(n) for n in names}
    low = min(names, key=levels.get)
    wp = arenas.loop_waypoints()[:-1]
    cx, cy = checkpoints[names.index(low)]
    i_cp = int(np.argmin([math.hypot(x - cx, y - cy) for x, y in wp]))
    (kx, ky), (nx, ny) = wp[(i_cp - 2) % len(wp)], wp[(i_cp - 1) % len(wp)]
    heading = math.atan2(ny - ky, nx - kx)
    world.place_robot(kx, ky, heading, event="kidnap")
    agent.lifted(wrap_angle(heading - obs.pose[2]))
    t_kid = obs.t
    obs = run_agent(world, agent, obs, int(300 / dt), log, 6, 0,
                    until=lambda o: agent.mode == "wait")
    kidnap_stop = None
    if agent.mode == "wait":
        d = [math.hypot(obs.pose[0] - x, obs.pose[1] - y) for x, y in checkpoints]
        served = agent.snapshot()["wait_drive"]
        kidnap_stop = {"nearest_checkpoint": names[int(np.argmin(d))],
                       "distance_cm": float(min(d)), "t_after_kidnap_s": float(obs.t - t_kid),
                       "drive": names[served] if served >= 0 else None}
        obs = run_agent(world, agent, obs, int(5 / dt), log, 6, 0)
    wall = time.perf_counter() - t0

    arrays = log.save(out, agent, world)
    stops = _stops(arrays, checkpoints, world.robot.moving_threshold)
    learned = [_longest_stop(stops, k, phase=3) for k in range(3)]
    rows = []
    for k in range(3):
        # at each pass by the checkpoint the first stop counts; further stops there are extra
        passes = _passes(arrays, checkpoints[k], phase=4)
        here = [s for s in stops if s["checkpoint"] == k and s["phase"] == 4]
        # a stop made here for another checkpoint's drive (a place that stands for both) is
        # a recognition error, reported apart from the timing of this checkpoint's waits
        per_pass = [[s["duration"] for s in here if a <= s["i0"] < b and s["drive"] == k]
                    for a, b in passes]
        misplaced = sum(1 for s in here if s["drive"] != k)
        rep = [d[0] for d in per_pass if d]
        learned_wait = learned_delays[names[k]]
        err = [abs(r - learned_wait) / learned_wait for r in rep] if learned_wait else []
        rows.append({"checkpoint": names[k], "taught_block_s": waits[k],
                     "taught_stop_s": learned[k]["duration"] if learned[k] else None,
                     "learned_wait_s": learned_wait, "reproduced_waits_s": rep,
                     "passes": len(passes), "stops_made": len(rep),
                     "extra_stops": sum(max(len(d) - 1, 0) for d in per_pass),
                     "misplaced_stops": misplaced,
                     "mean_s": float(np.mean(rep)) if rep else None,
                     "sd_s": float(np.std(rep)) if rep else None,
                     "max_rel_error": float(max(err)) if err else None})
    adapt_stops = [s for s in stops if i_adapt <= s["i0"] < i_adapt_end]
    for k, key, taught_s in ((0, "longer_block", longer), (1, "leash_restart", shorter)):
        after = [s["duration"] for s in adapt_stops if s["checkpoint"] == k]
        adapt[key] = {"before_s": rows[k]["mean_s"], "taught_s": taught_s,
                      "after_s": after[0] if after else None}
    metrics = {
        "place_cells": args.place_cells, "seed": seed, "waits_s": waits, "loops": loops,
        "quick": quick, "place_units": places.n_units,
        "reproduced_loop_fraction": float(reproduced),
        "loops_completed": float(completed),
        "loop_completion": float(min(completed / loops, 1.0)),
        "checkpoints": rows,
        "adaptation": adapt,
        "checkpoint_stops_made": int(sum(r["stops_made"] for r in rows)),
        "checkpoint_stops_expected": int(sum(r["passes"] for r in rows)),
        "extra_stops": int(sum(r["extra_stops"] for r in rows)),
        "misplaced_stops": int(sum(r["misplaced_stops"] for r in rows)),
        "kidnap": {"drive_levels": levels, "highest_drive": max(levels, key=levels.get),
                   "put_before": low, "first_stop": kidnap_stop,
                   "passed_the_low_drive": bool(kidnap_stop is not None
                                                and kidnap_stop["nearest_checkpoint"] != low
                                                and kidnap_stop["distance_cm"] < 30.0)},
        "states": agent.layer.n_states, "transitions": len(agent.graph),
        "simulated_s": float(obs.t), "wall_s": wall,
        "realtime_factor": float(obs.t) / wall,
    }
    from hippo.plots.agent import plot_patrol

    plot_patrol(out, arena, agent, arrays, rows)
    waits = "; ".join(
        f"{r['checkpoint']}: learned {r['learned_wait_s']:.1f} s, reproduced "
        + (f"{r['mean_s']:.1f} ± {r['sd_s']:.2f} s" if r["mean_s"] is not None else "none")
        for r in rows if r["learned_wait_s"] is not None)
    write_metrics(out, metrics, summary=(
        f"patrol ({args.place_cells} place cells): stopped at "
        f"{metrics['checkpoint_stops_made']} of {metrics['checkpoint_stops_expected']} "
        f"checkpoint passes; {waits}"))
    return metrics


def _stops(arrays: dict, checkpoints: list, threshold: float) -> list[dict]:
    """Every stretch of >= 1 s without translation near a checkpoint (< 30 cm).

    In the teaching phase (3) any such stop counts (the teacher's block); elsewhere only stops
    the agent chose (it was in its "wait" mode), not stalls at walls.
    """
    still = arrays["speed"] <= threshold
    waiting = arrays["mode"] == 3
    out = []
    i, n = 0, len(still)
    while i < n:
        if not still[i]:
            i += 1
            continue
        j = i
        while j < n and still[j]:
            j += 1
        dur = float(arrays["t"][j - 1] - arrays["t"][i] + (arrays["t"][1] - arrays["t"][0]))
        x, y = arrays["x"][i], arrays["y"][i]
        d = [math.hypot(x - cx, y - cy) for cx, cy in checkpoints]
        k = int(np.argmin(d))
        phase = int(arrays["phase"][i])
        if phase == 3:
            k = int(arrays["trial"][i])
        chosen = phase == 3 or bool(np.any(waiting[i:j]))
        if dur >= 1.0 and d[k] < 30.0 and chosen:
            drives = arrays["wait_drive"][i:j]
            drives = drives[drives >= 0]
            drive = int(np.bincount(drives).argmax()) if drives.size else -1
            out.append({"i0": i, "duration": dur, "checkpoint": k, "phase": phase,
                        "trial": int(arrays["trial"][i]), "drive": drive})
        i = j
    return out


def _passes(arrays: dict, centre: tuple[float, float], *, phase: int, radius: float = 30.0,
            gap: int = 25) -> list[tuple[int, int]]:
    """Index ranges ``[a, b)`` of the passes by ``centre`` (within ``radius`` cm) during
    ``phase``; runs at most ``gap`` ticks apart are one pass, and a pass under way when the
    phase starts (the robot is still where the previous phase left it) does not count."""
    idx = np.flatnonzero(arrays["phase"] == phase)
    if idx.size == 0:
        return []
    near = np.hypot(arrays["x"][idx] - centre[0], arrays["y"][idx] - centre[1]) < radius
    runs: list[list[int]] = []
    for i in idx[near]:
        if runs and i - runs[-1][1] <= gap:
            runs[-1][1] = int(i) + 1
        else:
            runs.append([int(i), int(i) + 1])
    return [(a, b) for a, b in runs if a != idx[0]]


def _longest_stop(stops: list[dict], k: int, *, phase: int) -> dict | None:
    """The longest stop at checkpoint ``k`` during ``phase`` (the taught wait)."""
    cands = [s for s in stops if s["checkpoint"] == k and s["phase"] == phase]
    return max(cands, key=lambda s: s["duration"]) if cands else None
