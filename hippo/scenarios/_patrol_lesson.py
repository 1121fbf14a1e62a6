"""What the patrol scenarios share: the course's command-line options and the lesson (the
robot's own exploration, its place cells, one loop on the leash, one reproduced, the waits
taught by blocks), on the public :mod:`hippo.tasks` API."""

from __future__ import annotations

import argparse
from dataclasses import dataclass

from hippo.agent import Agent, AgentParams
from hippo.cli_args import add_place_cells, integer, number, numbers, points
from hippo.cognitive_map import DriveParams, PlannerParams
from hippo.sim import World, arenas
from hippo.tasks import PLACE_STATES, Log, Session, explore, make_places
from hippo.tasks.patrol import (
    ARENA_CHECKPOINTS,
    HIREL_WAITS,
    PatrolCourse,
    PatrolPhase,
    check_patrol,
    patrol_route,
)


def add_course_arguments(parser: argparse.ArgumentParser) -> None:
    """--arena, --checkpoints, --waits and the place cells' options."""
    parser.add_argument("--arena", choices=list(ARENA_CHECKPOINTS), default="patrol-course",
                        help="the world to patrol")
    parser.add_argument("--checkpoints", type=points((2, 4), "cm"), default=None,
                        help="2 to 4 checkpoints 'x,y;x,y;...' in cm, patrolled in this order "
                             "(default: the arena's own, see ARENA_CHECKPOINTS)")
    parser.add_argument("--waits", type=numbers((2, 4), 0.5, 120.0, unit="s"), default=None,
                        help="one wait per checkpoint in s, comma-separated (default: HIREL's "
                             "24.1,19.1,11.6 (and 16 for a fourth))")
    add_place_cells(parser)
    parser.add_argument("--explore-min", type=number(5.0, 600.0), default=30.0,
                        help="exploration, simulated minutes")
    parser.add_argument("--units", type=integer(1, 200), default=24,
                        help="ICA units of the place cells")
    parser.add_argument("--places", type=integer(1, 500), default=32,
                        help="place prototypes read out from the ICA units (learned cells)")


def check_course_args(args: argparse.Namespace, parser: argparse.ArgumentParser) -> None:
    """The checkpoints lie in free space of the arena, are reachable from each other and are
    at least 40 cm apart along the route; one wait per checkpoint (:func:`check_patrol`)."""
    if not hasattr(args, "arena"):
        args.arena = "patrol-course"
    cps = getattr(args, "checkpoints", None)
    cps = ARENA_CHECKPOINTS[args.arena] if cps is None else cps
    if getattr(args, "waits", None) is None:
        args.waits = HIREL_WAITS[:len(cps)]
    try:
        check_patrol(args.arena, cps, args.waits)
    except ValueError as e:
        which = "--waits" if "waits" in str(e).split(" for ")[0] else "--checkpoints"
        parser.error(f"argument {which}: {e}")
    args.checkpoints = [tuple(c) for c in cps]


@dataclass
class Lesson:
    """A taught patrol robot: its world, place cells, agent, session and course."""

    world: World
    agent: Agent
    session: Session
    course: PatrolCourse
    reproduced: float  # the fraction of the loop it reproduced alone after the leash


def teach_patrol(args: argparse.Namespace, seed: int, *, units: int) -> Lesson:
    """Explore ``args.explore_min`` minutes, fit the place cells, then the lesson
    (:meth:`PatrolCourse.teach`) with ``args.waits``."""
    arena = arenas.get(args.arena)
    world = World(arena, sensors="ir8", seed=seed)
    checkpoints = [tuple(map(float, c)) for c in args.checkpoints]
    names = [f"checkpoint-{k}" for k in range(1, len(checkpoints) + 1)]
    log = Log(n_drives=len(checkpoints))
    # exploration: place cells only (HIREL learns the map on the leash)
    tour = explore(world, round(args.explore_min * 60 / world.dt), 0.0, seed, log)
    places = make_places(args.place_cells, arena, tour.sensors, units, seed, args.places)
    places.prime(tour.sensors[-500:])  # the robot's reservoir ran all along: go on from there
    drive = DriveParams(epsilon=0.01, learning_rate=0.5)
    params = AgentParams(states=PLACE_STATES,
                         planner=PlannerParams(w=0.9, noise=0.0, exploration_threshold=0.05))
    agent = Agent(places, drives=dict.fromkeys(names, drive), params=params,
                  sensors=world.sensors, robot=world.robot, seed=seed)
    s = Session(world, agent, log, obs=tour[-1], phase=PatrolPhase.LEASH)
    course = PatrolCourse(s, patrol_route(args.arena, checkpoints), checkpoints, names)
    reproduced = course.teach(list(args.waits))
    return Lesson(world, agent, s, course, reproduced)
