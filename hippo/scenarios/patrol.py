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
only way between two checkpoints the route runs along it both ways. Laps and passes are
measured by progress along that route (``hippo.tasks.LapCounter``, ``route_passes``), and
each phase that counts laps ends at the point of the route farthest from every checkpoint,
so that no stop straddles the end of a phase.

Metrics. Each pass of the robot by a checkpoint during the patrol (its progress along the
route within 30 cm of the checkpoint's, once per lap) is a chance to stop there:
``checkpoint_stops_expected`` counts the passes, ``checkpoint_stops_made`` the passes with a
stop the robot chose for that checkpoint's drive (its first one; ``extra_stops`` counts further
stops in the same pass, ``misplaced_stops`` stops made there for another checkpoint's drive).
``reproduced_waits_s`` are the durations of the counted stops, ``max_rel_error`` their
worst relative difference from the learned wait.

``run.npz`` holds per-tick ``t, x, y, heading, speed, zone, sound, winner, drives, wait_drive,
mode, prediction, non_occurrence, phase, trial``, the names of the phases and modes
(``phase_names``, ``mode_names``) and the teacher's events.
"""

from __future__ import annotations

import argparse
import math
import time
from enum import IntEnum

import numpy as np

from hippo.agent import Agent, AgentParams
from hippo.cli_args import add_place_cells, integer, number, numbers, points
from hippo.cognitive_map import DriveParams, PlannerParams
from hippo.progress import Progress
from hippo.scenarios._common import prepare_out, write_metrics
from hippo.sim import World, arenas
from hippo.tasks import (
    PLACE_STATES,
    LapCounter,
    Log,
    Route,
    Session,
    explore,
    make_places,
    route_passes,
    stops,
)
from hippo.types import Mode, StateKind

#: the arenas a patrol runs in, with their default checkpoints (cm): patrol-course's are its
#: landmarks checkpoint-1..3 on the corridor loop; the others' were placed in distinct parts
#: of each arena (room A and both ends of room B; three corridors of the goal arena; three
#: maze cells on a 650 cm round trip from the start)
ARENA_CHECKPOINTS: dict[str, list[tuple[float, float]]] = {
    "patrol-course": [(80.0, 11.0), (140.0, 56.0), (50.0, 105.0)],
    "two-rooms": [(15.0, 65.0), (90.0, 20.0), (100.0, 70.0)],
    "goal-arena": [(85.0, 15.0), (132.0, 76.0), (45.0, 136.0)],
    "maze": [(20.0, 20.0), (140.0, 140.0), (220.0, 60.0)],
}
#: HIREL's three checkpoint waits (s); with n checkpoints the first n are the defaults
HIREL_WAITS = [24.1, 19.1, 11.6, 16.0]


class Phase(IntEnum):
    EXPLORATION = 0
    LEASH = 1
    REPRODUCTION = 2
    CHECKPOINTS = 3
    PATROL = 4
    ADAPTATION = 5
    KIDNAP = 6


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--arena", choices=list(ARENA_CHECKPOINTS), default="patrol-course",
                        help="the world to patrol")
    parser.add_argument("--checkpoints", type=points((2, 4), "cm"), default=None,
                        help="2 to 4 checkpoints 'x,y;x,y;...' in cm, patrolled in this order "
                             "(default: the arena's own, see ARENA_CHECKPOINTS)")
    parser.add_argument("--waits", type=numbers((2, 4), 0.5, 120.0, unit="s"), default=None,
                        help="one wait per checkpoint in s, comma-separated (default: HIREL's "
                             "24.1,19.1,11.6 (and 16 for a fourth))")
    parser.add_argument("--loops", type=integer(1, 100), default=5,
                        help="autonomous patrol loops")
    add_place_cells(parser)
    parser.add_argument("--explore-min", type=number(5.0, 600.0), default=30.0,
                        help="exploration, simulated minutes")
    parser.add_argument("--units", type=integer(1, 200), default=24,
                        help="ICA units of the place cells")
    parser.add_argument("--places", type=integer(1, 500), default=32,
                        help="place prototypes read out from the ICA units (learned cells)")


def check_args(args: argparse.Namespace, parser: argparse.ArgumentParser) -> None:
    """The checkpoints lie in free space of the arena, are reachable from each other and are
    at least 40 cm apart along the route; one wait per checkpoint."""
    arena = arenas.get(args.arena)
    cps = ARENA_CHECKPOINTS[args.arena] if args.checkpoints is None else args.checkpoints
    if args.waits is None:
        args.waits = HIREL_WAITS[:len(cps)]
    if len(args.waits) != len(cps):
        parser.error(f"argument --waits: got {len(args.waits)} waits for {len(cps)} "
                     "checkpoints; give one wait per checkpoint")
    for x, y in cps:
        if not arena.is_free(x, y, 6.0):
            parser.error(f"argument --checkpoints: ({x:g}, {y:g}) is not free floor of arena "
                         f"{args.arena!r} ({arena.width:g} x {arena.height:g} cm; a checkpoint "
                         "needs 6 cm clear of every wall)")
    try:
        route = _route(args.arena, cps)
    except ValueError as e:
        parser.error(f"argument --checkpoints: {e}")
    s = sorted(route.progress(x, y) for x, y in cps)
    gaps = np.diff([*s, s[0] + route.length])
    if gaps.min() < 40.0:
        parser.error(f"argument --checkpoints: two checkpoints are {gaps.min():.0f} cm apart "
                     "along the route; they need 40 cm (a pass is 30 cm either side)")
    args.checkpoints = [tuple(c) for c in cps]


def _route(arena_name: str, checkpoints: list) -> Route:
    """The leash route: the corridor loop of patrol-course with its own checkpoints, else the
    arena's shortest paths through the checkpoints and back."""
    if arena_name == "patrol-course" and [tuple(c) for c in checkpoints] == \
            ARENA_CHECKPOINTS["patrol-course"]:
        return Route(arenas.loop_waypoints())
    return Route.through(arenas.get(arena_name), checkpoints, clearance=8.0)


def run(args: argparse.Namespace) -> dict:
    if not hasattr(args, "arena"):
        args.arena = "patrol-course"
    if getattr(args, "checkpoints", None) is None or getattr(args, "waits", None) is None:
        args.checkpoints = getattr(args, "checkpoints", None)
        check_args(args, argparse.ArgumentParser(prog="hippo run patrol"))
    out = prepare_out(args.out)
    seed = int(args.seed)
    quick = bool(args.quick)
    waits = list(args.waits)
    loops = min(args.loops, 2) if quick else int(args.loops)
    explore_min = args.explore_min
    units = min(args.units, 16) if quick else args.units
    arena = arenas.get(args.arena)
    world = World(arena, sensors="ir8", seed=seed)
    dt = world.dt
    checkpoints = [tuple(map(float, c)) for c in args.checkpoints]
    n_cp = len(checkpoints)
    log = Log(n_drives=n_cp)
    t0 = time.perf_counter()
    names = [f"checkpoint-{k}" for k in range(1, n_cp + 1)]
    loop_route = _route(args.arena, checkpoints)

    # 1. exploration: place cells only (HIREL learns the map on the leash)
    tour = explore(world, round(explore_min * 60 / dt), 0.0, seed, log)
    sensors = tour.sensors
    places = make_places(args.place_cells, arena, sensors, units, seed, args.places)
    places.prime(sensors[-500:])  # the robot's reservoir ran all along: continue from its state
    drive = DriveParams(epsilon=0.01, learning_rate=0.5)
    params = AgentParams(states=PLACE_STATES,
                         planner=PlannerParams(w=0.9, noise=0.0, exploration_threshold=0.05))
    agent = Agent(places, drives=dict.fromkeys(names, drive), params=params,
                  sensors=world.sensors, robot=world.robot, seed=seed)
    s = Session(world, agent, log, obs=tour[-1], phase=Phase.LEASH)
    course = _Course(s, loop_route, checkpoints, names)
    reproduced = course.teach(waits)
    # the learned delays are read before the patrol (which re-learns them)
    learned_delays = {}
    for n in names:
        delays = [agent.cells.learned_delay(t) for t in agent.drives.links(n)
                  if t in agent.cells.transitions]
        learned_delays[n] = float(np.median(delays)) if delays else None
    completed = course.patrol(loops)
    longer, shorter, i_adapt, i_adapt_end = course.adapt(waits, arena)
    levels, low, kidnap_stop = course.kidnap()
    obs = s.obs
    wall = time.perf_counter() - t0

    arrays = s.save(out, Phase)
    all_stops = stops(arrays, checkpoints, world.robot.moving_threshold,
                      taught_phase=Phase.CHECKPOINTS)
    learned = [_longest_stop(all_stops, k, phase=Phase.CHECKPOINTS) for k in range(n_cp)]
    rows = []
    for k in range(n_cp):
        # at each pass by the checkpoint the first stop counts; further stops there are extra
        runs = route_passes(arrays, loop_route, checkpoints[k], phase=Phase.PATROL)
        here = [st for st in all_stops if st["checkpoint"] == k and st["phase"] == Phase.PATROL]
        # a stop made here for another checkpoint's drive (a place that stands for both) is
        # a recognition error, reported apart from the timing of this checkpoint's waits
        per_pass = [[st["duration"] for st in here if a <= st["i0"] < b and st["drive"] == k]
                    for a, b in runs]
        misplaced = sum(1 for st in here if st["drive"] != k)
        rep = [d[0] for d in per_pass if d]
        learned_wait = learned_delays[names[k]]
        err = [abs(r - learned_wait) / learned_wait for r in rep] if learned_wait else []
        rows.append({"checkpoint": names[k], "taught_block_s": waits[k],
                     "taught_stop_s": learned[k]["duration"] if learned[k] else None,
                     "learned_wait_s": learned_wait, "reproduced_waits_s": rep,
                     "passes": len(runs), "stops_made": len(rep),
                     "extra_stops": sum(max(len(d) - 1, 0) for d in per_pass),
                     "misplaced_stops": misplaced,
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
        "waits_s": waits, "loops": loops,
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

    plot_patrol(out, arena, agent, arrays, rows, checkpoints)
    waits = "; ".join(
        f"{r['checkpoint']}: learned {r['learned_wait_s']:.1f} s, reproduced "
        + (f"{r['mean_s']:.1f} ± {r['sd_s']:.2f} s" if r["mean_s"] is not None else "none")
        for r in rows if r["learned_wait_s"] is not None)
    write_metrics(out, metrics, summary=(
        f"patrol ({args.arena}, {args.place_cells} place cells): stopped at "
        f"{metrics['checkpoint_stops_made']} of {metrics['checkpoint_stops_expected']} "
        f"checkpoint passes; {waits}"))
    return metrics



class _Course:
    """The patrol's phases on one session: the robot, its teacher, the loop and checkpoints."""

    def __init__(self, s: Session, route: Route, checkpoints: list, names: list[str]) -> None:
        self.s, self.agent, self.dt = s, s.agent, s.world.dt
        self.route, self.checkpoints, self.names = route, checkpoints, names
        # laps by progress along the route; a phase that counts laps ends at the route's
        # quiet point, the farthest (along the route) from every checkpoint, so that a stop
        # at a checkpoint never straddles the end of a phase
        self.loop = LapCounter(route)
        L = route.length
        s_cp = np.array([route.progress(*c) for c in checkpoints])
        grid = np.arange(0.0, L, 1.0)
        far = np.min(np.abs((grid[:, None] - s_cp[None, :] + L / 2) % L - L / 2), axis=1)
        self.quiet = float(grid[int(np.argmax(far))])

    def laps(self) -> float:
        return self.loop.update(*self.s.truth.pose[:2])

    def lap_until(self, target: float):
        return lambda o: self.laps() >= target

    def laps_to_quiet(self, loops: int, point: float | None = None) -> float:
        """The lap count at which ``loops`` whole laps from the next quiet point (or the next
        ``point``, a progress along the route) are done."""
        turns = self.laps()
        L = self.route.length
        target = self.quiet if point is None else point
        ahead = ((target - self.loop.progress) % L) / L  # type: ignore[operator]
        return turns + ahead + loops

    def just_past_last(self) -> float:
        """The progress 10 cm past the checkpoint before the quiet point."""
        L = self.route.length
        s_cp = [self.route.progress(*c) for c in self.checkpoints]
        last = min(s_cp, key=lambda v: (self.quiet - v) % L)  # the nearest before it
        return last + 10.0

    def state_kind(self) -> StateKind | None:
        agent = self.agent
        return agent.kind(agent.state) if agent.state is not None else None

    def near(self, point, radius: float) -> bool:
        return math.dist(self.s.truth.pose[:2], point) < radius

    def teach(self, waits: list[float]) -> float:
        """Settle, one loop on the leash, one loop reproduced alone, then the checkpoints
        taught by blocks; returns the fraction of the loop reproduced."""
        s, agent, dt = self.s, self.agent, self.dt
        # let the place cells settle on the course before the leash
        agent.lifted()
        s.run(int(agent.p.settle_time / dt) + 1)
        # one loop on the leash, counter-clockwise from the nearest waypoint ahead
        s.teacher.lead(self.route.loop_from(s.truth.pose))
        self.laps()
        with Progress(1, "leash") as bar:
            s.run(6000, until=lambda o: not s.teacher.leading)
            bar.update()
        # reproduction: no drive is active, the only known way on is the taught loop
        agent.drives.step(0.0)
        s.phase, start_turns = Phase.REPRODUCTION, self.laps()
        with Progress(1, "reproduction") as bar:
            s.run(int(max(400.0, 3.0 * self.route.length / 5.0) / dt),
                  until=self.lap_until(start_turns + 1.0))
            reproduced = self.loop.turns - start_turns
            bar.update()
        # checkpoints: block the robot at each for its wait, reward its drive as it ends
        s.phase = Phase.CHECKPOINTS
        with Progress(len(self.checkpoints), "checkpoints") as bar:
            for k, c in enumerate(self.checkpoints):
                s.trial = k
                s.run(int(300 / dt), until=lambda o, c=c: self.near(c, 12.0))
                s.block(waits[k])
                agent.reward(self.names[k])
                s.run(int(10 / dt),
                      until=lambda o: self.state_kind() not in (None, StateKind.STILL))
                bar.update()
        return reproduced

    def patrol(self, loops: int) -> float:
        """Every drive up, ``loops`` laps alone; returns the laps completed."""
        s = self.s
        for d in self.names:
            self.agent.drives.set_level(d, 1.0)
        s.phase, start_turns = Phase.PATROL, self.laps()
        # the first lap ends at the quiet point after a whole loop (or a little more)
        end = self.laps_to_quiet(1)
        lap_s = max(600.0, 3.0 * self.route.length / 5.0)  # 3 x a lap at 5 cm/s, at least
        with Progress(loops, "patrol") as bar:
            for k in range(loops):
                s.trial = k
                s.run(int(lap_s / self.dt), until=self.lap_until(end + k))
                bar.update()
        return min(self.loop.turns - start_turns, float(loops))

    def adapt(self, waits: list[float], arena) -> tuple[float, float, int, int]:
        """A longer block at checkpoint 1, an early leash restart at checkpoint 2, then a loop
        and a bit alone; returns the two taught waits and the log rows of that loop."""
        s, agent, dt = self.s, self.agent, self.dt
        longer = waits[0] + 8.0
        c1, c2 = self.checkpoints[0], self.checkpoints[1]
        # the teacher holds the robot when it stops at checkpoint 1 by itself: its stillness
        # lasts `longer` s instead of the learned wait (if it passes without stopping, it is
        # held where the checkpoint was taught, as in teaching)
        s.phase, s.trial = Phase.ADAPTATION, 0
        s.run(int(400 / dt), until=lambda o: self.near(c1, 30.0) and (
            self.state_kind() == StateKind.STILL or agent.mode in (Mode.APPROACH, Mode.WAIT)
            or self.near(c1, 12.0)))
        if agent.mode == Mode.APPROACH:  # about to stop: let it
            s.run(int(20 / dt), until=lambda o: agent.mode != Mode.APPROACH)
        s.block(longer, extra=10.0)
        s.trial = 1
        s.run(int(400 / dt),
              until=lambda o: self.state_kind() == StateKind.STILL and self.near(c2, 30.0))
        shorter = waits[1] / 2
        s.run(int(shorter / dt))
        # the leash restarts it early: led 30 cm on along the route
        ahead = self.route.at(self.route.progress(*c2) + 30.0)
        _, path = arena.shortest_path(s.truth.pose[:2], ahead[:2])
        s.lead(path, limit=2000)
        s.trial = 2
        i_adapt = len(s.log)
        # one loop and a bit: it starts just past checkpoint 2, which it must meet again, and
        # ends 10 cm past the checkpoint before the quiet point, once it has served it (the one
        # served last, whose drive is then lowest: the kidnap's test)
        lap_s = max(800.0, 4.0 * self.route.length / 5.0)
        s.run(int(lap_s / dt),
              until=self.lap_until(self.laps_to_quiet(1, self.just_past_last())))
        return longer, shorter, i_adapt, len(s.log)

    def kidnap(self) -> tuple[dict[str, float], str, dict | None]:
        """Put the robot down on the path two waypoints before the checkpoint whose drive is
        lowest (it was served last), facing along the loop: does it head on to a checkpoint
        with a high drive instead of stopping at the one it was put before?"""
        s, agent, names = self.s, self.agent, self.names
        levels = {n: agent.drives.level(n) for n in names}
        low = min(names, key=levels.get)
        # 75 cm before it along the route (the place code settles over the first 30 cm),
        # facing along the route
        kx, ky, heading = self.route.at(
            self.route.progress(*self.checkpoints[names.index(low)]) - 75.0)
        s.phase, s.trial = Phase.KIDNAP, 0
        s.put(kx, ky, heading)
        self.loop.reset()
        t_kid = s.t
        obs = s.run(int(300 / self.dt), until=lambda o: agent.mode == Mode.WAIT)
        stop = None
        if agent.mode == Mode.WAIT:
            d = [math.dist(s.truth.pose[:2], c) for c in self.checkpoints]
            served = agent.snapshot()["wait_drive"]
            stop = {"nearest_checkpoint": names[int(np.argmin(d))],
                    "distance_cm": float(min(d)), "t_after_kidnap_s": float(obs.t - t_kid),
                    "drive": names[served] if served >= 0 else None}
            s.run(int(5 / self.dt))
        return levels, low, stop

def _longest_stop(stops: list[dict], k: int, *, phase: int) -> dict | None:
    """The longest stop at checkpoint ``k`` during ``phase`` (the taught wait)."""
    cands = [s for s in stops if s["checkpoint"] == k and s["phase"] == phase]
    return max(cands, key=lambda s: s["duration"]) if cands else None
