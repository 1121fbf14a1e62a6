"""A taught patrol robot in one call: :func:`teach_patrol` (any arena, built-in or one's own).

The recipe ``hippo run patrol`` uses, on the public API: the route through the checkpoints
(:func:`~hippo.tasks.patrol_sets.choose_route`), the wall to explore along
(:func:`~hippo.tasks.explore.wall_side`), exploration and place cells fitted on it, the agent
with the patrol's settings (place states split by the direction of travel, re-localisation
after a lift, one drive per checkpoint), and the lesson (:meth:`PatrolCourse.teach`: a lap on
the leash, a lap alone, each checkpoint's wait held, a leash for a robot that went astray).
What comes back is a :class:`Lesson`; ``lesson.course.patrol(loops)`` patrols and
``lesson.course.report(...)`` / :func:`~hippo.tasks.patrol_report.pass_report` measure it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from hippo._checks import check_int, check_real, check_wall_side
from hippo.agent import Agent, AgentParams
from hippo.cognitive_map import DriveParams, LocaliserParams, PlannerParams
from hippo.perception.relocate import RelocaliserParams
from hippo.sim import World
from hippo.sim.arena import Arena
from hippo.tasks.explore import PLACE_STATES, explore, make_places, place_model, wall_side
from hippo.tasks.log import Log
from hippo.tasks.passes import stops
from hippo.tasks.patrol import PatrolCourse, PatrolPhase
from hippo.tasks.patrol_sets import _arena, checked_route, tour_of_side
from hippo.tasks.session import Session

__all__ = ["LEARNED_SECTORS", "PATROL_HOP_TIME", "Lesson", "teach_patrol"]

#: learned place states are split by the direction of travel into 4 sectors (the rooms of
#: two-rooms look the same turned round: docs/results.md); ground-truth fields do not alias,
#: and 4 sectors did not help them (tuning seeds: two-rooms 332/376 -> 341/382, goal-arena
#: 179/193 -> 178/193, course 340/340 either way)
LEARNED_SECTORS = 4
#: the patrol's drives are discounted by the learned time to a checkpoint, one hop per 5 s
#: (``PlannerParams.hop_time``; about a place's median stay), not per state crossed: per hop,
#: the way on through a stop at a low-drive checkpoint counted the wait as one hop, and a kidnap
#: stopped there (tuning seeds, kidnap choice: course 16-75 56/60 -> 59/60, goal-arena 0-23
#: 16/24 -> 23/24, two-rooms 22/24 either way; docs/results.md)
PATROL_HOP_TIME = 5.0


@dataclass
class Lesson:
    """A taught patrol robot: its world, place cells, agent, session and course."""

    world: World
    agent: Agent
    session: Session
    course: PatrolCourse
    reproduced: float  # the fraction of the loop it reproduced alone after the leash
    taught_stops: list[float | None]  # per checkpoint, the robot's stillness while blocked
    route_kind: str = "shortest"  # what its route is (hippo.tasks.patrol_sets.choose_route)


def teach_patrol(arena: str | Arena, checkpoints: Sequence[Sequence[float]],
                 waits: Sequence[float], *, seed: int = 0, route: str = "auto",
                 place_cells: str = "learned", explore_min: float = 30.0, units: int = 24,
                 places: int = 40, heading_sectors: int | None = None,
                 reanchor: bool = False, side: int | None = None,
                 hop_time: float | None = PATROL_HOP_TIME) -> Lesson:
    """Explore ``arena`` (a built-in arena's name or an :class:`Arena` of one's own) for
    ``explore_min`` simulated minutes, fit the place cells (``units`` ICA units, ``places``
    prototypes; or ground-truth fields), build the patrol robot and teach it ``waits`` (s) at
    ``checkpoints`` (cm) along the ``route`` (``"auto"``, ``"shortest"`` or ``"tour"``).

    ``heading_sectors`` (default: :data:`LEARNED_SECTORS` with learned cells, 1 with ground
    truth) splits each place state by the direction of travel. ``side`` is the wall the robot
    explores along and follows on its moves (-1 right, +1 left; default:
    :func:`~hippo.tasks.explore.wall_side`'s probe, which takes the wall outside the route's
    loop where its follower goes round: in rings built with ``ArenaBuilder`` the inner wall's
    follower crossed the corridor and ran backwards; where the patrol runs its loop backwards
    or misses most stops, give the other side). ``hop_time`` (s) discounts the drives by the
    learned time to a checkpoint (:data:`PATROL_HOP_TIME`; ``None``: HIREL's ``w`` per state
    crossed, ``PlannerParams.hop_time``). On a wall tour the robot is led (and its
    passes counted) along the tour of the wall it follows, where that tour passes every
    checkpoint (:func:`~hippo.tasks.patrol_sets.tour_of_side`). The checkpoints and waits are
    checked first
    (:func:`~hippo.tasks.patrol_sets.check_patrol`): a ``ValueError`` names the problem
    before any work."""
    arena_obj = _arena(arena)
    checkpoints = [(float(x), float(y)) for x, y in checkpoints]
    if place_cells not in ("learned", "ground-truth"):
        raise ValueError(f"place_cells must be 'learned' or 'ground-truth', got {place_cells!r}")
    check_wall_side("side", side, none_ok=True)
    planner = PlannerParams(w=0.9, noise=0.0, exploration_threshold=0.05, hop_time=hop_time)
    if not 0.1 <= check_real("explore_min", explore_min) <= 1e4:
        raise ValueError(f"explore_min must be 0.1 to 10,000 simulated minutes, got "
                         f"{explore_min!r}")
    for name, v, hi in (("units", units, 600), ("places", places, 256),
                        ("heading_sectors", heading_sectors, 360)):
        if v is not None:
            check_int(name, v, lo=1, hi=hi)
    world = World(arena_obj, sensors="ir8", seed=seed)
    if place_cells == "learned":
        _check_learned(units, explore_min, world.dt, reanchor)
    if place_cells == "ground-truth" and not len(arena_obj.locations):
        raise ValueError(f"arena {arena_obj.name!r} has no reference locations for ground-truth "
                         "place cells (ArenaBuilder.grid_locations)")
    kind, loop = checked_route(arena, checkpoints, waits, route)
    sectors = heading_sectors if heading_sectors is not None else (
        LEARNED_SECTORS if place_cells == "learned" else 1)
    names = [f"checkpoint-{k}" for k in range(1, len(checkpoints) + 1)]
    log = Log(n_drives=len(checkpoints))
    side = wall_side(loop, arena_obj, seed) if side is None else side
    loop = tour_of_side(arena, checkpoints, kind, loop, side)   # led along the wall it follows
    # exploration: place cells only (HIREL learns the map on the leash)
    tour = explore(world, round(explore_min * 60 / world.dt), 0.0, seed, log, side=side)
    cells = make_places(place_cells, arena_obj, tour.sensors, units, seed, places,
                        moving=tour.moving if reanchor else None)
    cells.prime(tour.sensors[-500:])  # the robot's reservoir ran all along: go on from there
    drive = DriveParams(epsilon=0.01, learning_rate=0.5)
    # after a kidnap or a rescue the robot goes on with its task (its drives kept): it first
    # explores until the map recognises a place change (BrainParams.relocalise), so that no
    # stop is chosen from the place code's memory of where it was carried from (kidnap,
    # tuning seeds 0-9: 9/10 with it, 6/10 with the fixed 6 s settling)
    params = AgentParams(states=PLACE_STATES, relocalise=LocaliserParams(),
                         planner=planner,
                         wall_side=side, heading_sectors=sectors)
    agent = Agent(cells, drives=dict.fromkeys(names, drive), params=params,
                  sensors=world.sensors, robot=world.robot, seed=seed)
    s = Session(world, agent, log, obs=tour[-1], phase=PatrolPhase.LEASH)
    course = PatrolCourse(s, loop, checkpoints, names, tour=kind == "tour")
    reproduced = course.teach([float(w) for w in waits])
    taught = stops(s.log.arrays(), checkpoints, world.robot.moving_threshold,
                   taught_phase=PatrolPhase.CHECKPOINTS)
    longest = [max((st["duration"] for st in taught if st["checkpoint"] == k
                    and st["phase"] == PatrolPhase.CHECKPOINTS), default=None)
               for k in range(len(checkpoints))]
    return Lesson(world, agent, s, course, reproduced, longest, kind)


def _check_learned(units: int, explore_min: float, dt: float, reanchor: bool) -> None:
    """Before any work: ``units`` within the learned place cells' SFA input, and an
    exploration of ``explore_min`` long enough for their fit (and, with ``reanchor``, for the
    sequence relocaliser's fit, which counts only the ticks the robot moves)."""
    p = place_model(units).params
    if units > p.sfa_inputs:
        raise ValueError(f"units={units} exceeds the {p.sfa_inputs} inputs of the learned place "
                         f"cells' SFA ({p.n_inputs} IR readings + {p.n_reservoir} reservoir "
                         f"neurons): at most {p.sfa_inputs}")
    # the fit's rule: (ticks // downsample) - washout >= min_fit_ticks
    need, why = (p.min_fit_ticks + p.washout) * p.downsample, "the place cells' fit"
    if reanchor:
        r = RelocaliserParams()
        moving = r.skip + r.window + 2 * r.spread
        if moving > need:
            need, why = moving, "reanchor's sequence matching (of the ticks the robot moves)"
    ticks = round(explore_min * 60 / dt)
    if ticks < need:
        raise ValueError(f"explore_min={explore_min!r} gives {ticks} ticks of exploration; "
                         f"{why} needs at least {need} ({need * dt:g} s): explore_min >= "
                         f"{math.ceil(need * dt / 60 * 100) / 100:g}")
