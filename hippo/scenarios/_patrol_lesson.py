"""What the patrol scenarios share: the course's command-line options and the lesson (the
robot's own exploration, its place cells, one loop on the leash, one reproduced, the waits
taught by blocks), on the public :mod:`hippo.tasks` API; ``--save DIR`` writes the taught
robot, ``--load DIR`` starts from one instead of teaching it again."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from hippo._checks import check_choice
from hippo.agent import Agent
from hippo.cli_args import (
    EXPLORE_MIN,
    MAX_SEED,
    PLACE_CELLS,
    PLACES,
    UNITS,
    WAIT_S,
    add_place_cells,
    check_ground_truth_options,
    check_loaded_options,
    integer,
    loaded_robot_meta,
    number,
    numbers,
    out_dir,
    points,
    snapshot_dir,
)
from hippo.scenarios._meta_checks import (
    bad_field,
    check_number,
    check_option,
    check_whole,
    field,
    finite,
)
from hippo.sim import World
from hippo.snapshot import load_snapshot, save_snapshot
from hippo.tasks import Log, Session
from hippo.tasks.lesson import LEARNED_SECTORS, Lesson
from hippo.tasks.lesson import teach_patrol as teach
from hippo.tasks.patrol import (
    ARENA_CHECKPOINTS,
    HIREL_WAITS,
    ROUTE_KINDS,
    PatrolCourse,
    PatrolPhase,
    check_patrol,
)
from hippo.tasks.patrol_sets import led_route


def add_course_arguments(parser: argparse.ArgumentParser) -> None:
    """--arena, --checkpoints, --waits and the place cells' options."""
    parser.add_argument("--arena", choices=list(ARENA_CHECKPOINTS), default=None,
                        help="the world to patrol (default: patrol-course)")
    parser.add_argument("--checkpoints", type=points((2, 4), "cm"), default=None,
                        help="2 to 4 checkpoints 'x,y;x,y;...' in cm, patrolled in this order "
                             "(on a wall tour: in the order the tour meets them, from the "
                             "first) (default: the arena's own, see ARENA_CHECKPOINTS)")
    parser.add_argument("--waits", type=numbers((2, 4), *WAIT_S, unit="s"), default=None,
                        help="one wait per checkpoint in s, comma-separated (default: HIREL's "
                             "24.1,19.1,11.6 (and 16 for a fourth))")
    parser.add_argument("--route", choices=list(ROUTE_KINDS), default="auto",
                        help="the leash route: the arena's shortest paths through the "
                             "checkpoints, the loop the exploring wall follower runs round "
                             "the arena (tour), or auto: the shortest paths where they make a "
                             "loop a wall tour runs the same way round without running back "
                             "over themselves, else the tour where it passes every checkpoint")
    add_place_cells(parser)
    parser.add_argument("--explore-min", type=number(*EXPLORE_MIN), default=30.0,
                        help="exploration, simulated minutes")
    parser.add_argument("--units", type=integer(*UNITS), default=24,
                        help="ICA units of the place cells")
    # 40 prototypes, not place preference's 32: tuning seeds (learned, full size), passes with
    # a stop at 32 / 40 / 48 / 64: two-rooms 53 / 65 / 68 / 65 %, goal-arena 73 / 82 / 78 /
    # 86 % (0-23, random checkpoints), patrol-course 678/680, 675/680, 668/672, 671/680 with
    # kidnaps 38, 38, 35, 36 of 40 (0-39). Rule fixed before the course runs: the best mean
    # pass rate of the three among the counts that keep the course's kidnap within 1 of 32's
    # (goal-arena's stops misplaced by an aliased place: 41 -> 22). Place preference keeps 32:
    # with 40 it lost 2 rewarded trials on held-out seeds 100-109 (docs/results.md)
    parser.add_argument("--places", type=integer(*PLACES), default=40,
                        help="place prototypes read out from the ICA units (learned cells)")
    parser.add_argument("--heading-sectors", type=integer(1, 16), default=None,
                        help="split each place state by the direction of travel into this "
                             "many sectors (the heading from path integration; 1: no split; "
                             f"default {LEARNED_SECTORS} with learned place cells, 1 with "
                             "ground truth, whose fields do not alias)")
    parser.add_argument("--save", type=out_dir, default=None,
                        help="write the taught robot (after exploration and the lesson) into "
                             "this folder as a hippo snapshot")
    parser.add_argument("--load", type=snapshot_dir, default=None,
                        help="skip exploration and the lesson: start from a robot written with "
                             "--save (its seed, arena, checkpoints, waits and place cells come "
                             "from the snapshot)")


def heading_sectors(args: argparse.Namespace) -> int:
    """``--heading-sectors``, or its default for the place cells asked for."""
    n = getattr(args, "heading_sectors", None)
    if n is not None:
        return int(n)
    return LEARNED_SECTORS if getattr(args, "place_cells", "learned") == "learned" else 1


def check_course_args(args: argparse.Namespace, parser: argparse.ArgumentParser) -> None:
    """The checkpoints lie in free space of the arena, are reachable from each other and are
    at least 40 cm apart along the route; one wait per checkpoint (:func:`check_patrol`);
    no option of learned place cells with ground-truth ones."""
    args.loaded = None
    check_ground_truth_options(args, parser)
    if getattr(args, "load", None) is not None:
        if getattr(args, "save", None) is not None:
            parser.error("argument --save: not allowed with --load (the loaded robot is "
                         "already saved)")
        try:
            args.loaded = load_lesson(args.load)
        except (OSError, ValueError) as e:
            parser.error(f"argument --load: {args.load}: {' '.join(str(e).split())}")
        meta = loaded_robot_meta(args.loaded["meta"], args.loaded["agent"].places)
        check_loaded_options(args, parser, meta, ("place_cells", "seed", "explore_min", "units",
                                                  "places", "route", "reanchor"))
        for opt, key in (("--arena", "arena"), ("--checkpoints", "checkpoints"),
                         ("--waits", "waits")):
            given = getattr(args, key, None)
            if given is not None and _plain(given) != meta[key]:
                parser.error(f"argument {opt}: the loaded robot was taught with {key} "
                             f"{meta[key]}; leave {opt} out with --load")
        # the split of the place states is the loaded brain's own (snapshots before it: 1)
        had = int(args.loaded["agent"].p.heading_sectors)
        given = getattr(args, "heading_sectors", None)
        if given is not None and given != had:
            parser.error(f"argument --heading-sectors: the loaded robot's place states are "
                         f"split in {had}; leave --heading-sectors out with --load")
        args.heading_sectors = had
        for key in _META:
            setattr(args, key, meta[key])
        args.reanchor = meta["reanchor"]
        args.checkpoints = [tuple(c) for c in meta["checkpoints"]]
        args.route = meta_route(meta)
        return
    if getattr(args, "arena", None) is None:
        args.arena = "patrol-course"
    cps = getattr(args, "checkpoints", None)
    cps = ARENA_CHECKPOINTS[args.arena] if cps is None else cps
    if getattr(args, "waits", None) is None:
        args.waits = HIREL_WAITS[:len(cps)]
    try:
        check_patrol(args.arena, cps, args.waits, getattr(args, "route", "auto"))
    except ValueError as e:
        # "got 2 waits for 3 checkpoints", "wait(s) 1.5 s: ..." (not "--checkpoints: wait(s)")
        which = "--waits" if "wait" in str(e).split(" for ")[0] else "--checkpoints"
        parser.error(f"argument {which}: {e}")
    args.checkpoints = [tuple(c) for c in cps]


#: the options a saved lesson fixes (written into its meta, taken from it by --load)
_META = ("seed", "arena", "checkpoints", "waits", "place_cells", "explore_min", "units",
         "places")


def _plain(value: Any) -> Any:
    """Tuples to lists, numbers to floats: the JSON form of an option, to compare."""
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) \
        else value


def meta_route(meta: dict) -> str:
    """The route kind a saved lesson was taught on (before kinds: the shortest paths)."""
    return str(meta.get("route", "shortest"))


def load_lesson(folder: str | Path) -> dict:
    """A snapshot written by ``--save`` of a patrol scenario, checked."""
    state = load_snapshot(folder, dict)
    if state.get("scenario") != "patrol-lesson":
        raise ValueError(f"a snapshot of {state.get('scenario')!r}, not of a patrol lesson")
    if not isinstance(state.get("agent"), Agent) or not isinstance(state.get("world"), World):
        raise ValueError("the snapshot holds no agent and world")
    meta = state.get("meta")
    if not isinstance(meta, dict) or any(k not in meta for k in (*_META, "reproduced",
                                                                  "taught_stops")):
        raise ValueError(f"the snapshot's meta must hold {', '.join(_META)}, reproduced and "
                         "taught_stops")
    _check_meta(meta)
    return state


def _check_meta(meta: dict) -> None:
    """Raise ``ValueError`` naming the field unless a saved lesson's meta is one ``--save``
    could have written: the options within the command line's own bounds, and a course
    :func:`check_patrol` accepts (so a hand-edited snapshot is refused before any work)."""
    if not isinstance(meta["arena"], str) or meta["arena"] not in ARENA_CHECKPOINTS:
        raise ValueError(f"unknown arena {meta['arena']!r} in the snapshot")
    check_whole(meta, "seed", (0, MAX_SEED))
    check_whole(meta, "units", UNITS)
    check_whole(meta, "places", PLACES)
    check_number(meta, "explore_min", EXPLORE_MIN)
    check_option(meta, "place_cells", PLACE_CELLS)
    check_choice(field("route"), meta_route(meta), ROUTE_KINDS)
    cps, waits = meta["checkpoints"], meta["waits"]
    if not isinstance(cps, list) or not 2 <= len(cps) <= 4 or not all(
            isinstance(c, list) and len(c) == 2 and all(finite(v) for v in c) for c in cps):
        raise bad_field(meta, "checkpoints", "2 to 4 points [x, y] in cm")
    lo, hi = WAIT_S
    if not isinstance(waits, list) or not all(finite(w) and lo <= w <= hi for w in waits):
        raise bad_field(meta, "waits", f"a list of waits in [{lo:g}, {hi:g}] s")
    stops_ = meta["taught_stops"]
    if not isinstance(stops_, list) or len(stops_) != len(cps) or not all(
            v is None or (finite(v) and v >= 0) for v in stops_):
        raise bad_field(meta, "taught_stops", f"one stillness (s, or null) per checkpoint "
                                              f"({len(cps)})")
    if not finite(meta["reproduced"]):
        raise bad_field(meta, "reproduced", "a finite number")
    try:
        check_patrol(meta["arena"], cps, waits, meta_route(meta))
    except ValueError as e:
        raise ValueError(f"the snapshot's course: {e}") from None


def save_lesson(folder: str | Path, lesson: Lesson, args: argparse.Namespace) -> None:
    """The taught robot, its world (the teacher detached while saving: it is idle), the last
    observation, the lap counter and what the lesson was."""
    s = lesson.session
    meta = {k: _plain(getattr(args, k)) for k in _META}
    meta["route"] = getattr(args, "route", "auto")
    meta["quick"] = bool(getattr(args, "quick", False))
    model = getattr(lesson.agent.places, "model", None)  # learned cells: their ICA units
    meta.update(seed=int(args.seed),
                units=int(model.params.n_ica) if model is not None else int(args.units),
                reproduced=float(lesson.reproduced), taught_stops=lesson.taught_stops)
    s.world.detach(s.teacher)
    try:
        save_snapshot({"scenario": "patrol-lesson", "meta": meta, "agent": s.agent,
                       "world": s.world, "obs": s.obs, "loop": lesson.course.loop}, folder)
    finally:
        s.world.attach(s.teacher)


def teach_patrol(args: argparse.Namespace, seed: int, *, units: int) -> Lesson:
    """Explore ``args.explore_min`` minutes, fit the place cells, then the lesson
    (:meth:`PatrolCourse.teach`) with ``args.waits``; or, with ``args.load``, the lesson
    saved there (``--save`` writes it)."""
    checkpoints = [tuple(map(float, c)) for c in args.checkpoints]
    names = [f"checkpoint-{k}" for k in range(1, len(checkpoints) + 1)]
    loaded = getattr(args, "loaded", None)
    if loaded is None and getattr(args, "load", None) is not None:
        loaded = load_lesson(args.load)
    if loaded is not None:
        s = Session(loaded["world"], loaded["agent"], Log(n_drives=len(checkpoints)),
                    obs=loaded["obs"], phase=PatrolPhase.CHECKPOINTS)
        kind, route = led_route(args.arena, checkpoints, meta_route(loaded["meta"]),
                                s.agent.params.motor.wall_side)
        course = PatrolCourse(s, route, checkpoints, names)
        course.loop = loaded["loop"]
        meta = loaded["meta"]
        return Lesson(s.world, s.agent, s, course, float(meta["reproduced"]),
                      list(meta["taught_stops"]), kind)
    lesson = teach(args.arena, checkpoints, args.waits, seed=seed,
                   route=getattr(args, "route", "auto"), place_cells=args.place_cells,
                   explore_min=args.explore_min, units=units, places=args.places,
                   heading_sectors=heading_sectors(args), reanchor=args.reanchor)
    if getattr(args, "save", None) is not None:
        save_lesson(args.save, lesson, args)
    return lesson
