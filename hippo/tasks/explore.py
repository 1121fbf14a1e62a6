"""Exploration and map learning: the robot's own tour, and the map learned from it.

- :func:`explore` — SMC09's wall follower with occasional pauses; returns the :class:`Tour`
  (what the robot sensed, and where it was, tick by tick).
- :func:`make_places` — the place-cell source fitted on a tour: RC-SFA-ICA read out by
  radial-basis prototypes (learned, the default) or Gaussian fields (ground truth).
- :func:`learn_map` — replay a tour through an agent: states, timed transitions, the map.
- :func:`wall_side` — the wall to explore along for a task on a route: the one that takes the
  robot round the route the way it runs.
- :func:`wall_tour` — the loop the exploring wall follower runs round an arena, as a route.
- :data:`PLACE_STATES` — state-layer settings for place activities in [0, 1].
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hippo._checks import check_real, check_wall_side
from hippo.perception.place_cells import RCSFAICA
from hippo.perception.prototypes import PlacePrototypes, PrototypeParams
from hippo.perception.relocate import SequenceRelocaliser
from hippo.perception.states import StateLayerParams
from hippo.places import GroundTruthPlaceCells, LearnedPlaceCells, PlaceSource
from hippo.progress import Progress, working
from hippo.seeds import Seeds
from hippo.sim import arenas
from hippo.sim.arena import Arena
from hippo.sim.controllers import WallFollower, WallFollowerParams
from hippo.sim.world import World
from hippo.tasks.log import Log
from hippo.tasks.routes import LapCounter, Route
from hippo.types import GroundTruth, Observation

__all__ = ["OUTER_MAX_BACK", "OUTER_MIN_LAPS", "PAUSE_RATE", "PLACE_STATES", "Tour",
           "arena_tour", "explore", "learn_map", "make_places", "wall_side", "wall_tour"]

#: probability per exploration tick of a pause (2-30 s): about one pause a minute
PAUSE_RATE = 0.003

#: state-layer settings for place activities in [0, 1] (prototypes, Gaussian fields)
PLACE_STATES = StateLayerParams(normalize="fixed", place_scale=0.5, context_time=1.0)


@dataclass
class Tour:
    """An exploration, tick by tick: the observations and the matching ground truth."""

    observations: list[Observation] = field(default_factory=list)
    truths: list[GroundTruth] = field(default_factory=list)

    def __len__(self) -> int:
        return len(self.observations)

    def __getitem__(self, i: int) -> Observation:
        return self.observations[i]

    def __iter__(self):
        return iter(self.observations)

    @property
    def sensors(self) -> np.ndarray:
        """The sensor readings, (T, n_sensors)."""
        return np.array([o.ir for o in self.observations])

    @property
    def moving(self) -> np.ndarray:
        """Ticks on which the robot moved (proprioception), (T,) bool."""
        return np.array([o.moving for o in self.observations], dtype=bool)


def explore(world: World, ticks: int, rho: float, seed: int, log: Log | None = None,
            desc: str = "exploration", pause_rate: float = PAUSE_RATE, phase: int = 0,
            side: int = -1) -> Tour:
    """Drive the robot with the wall follower, pausing now and then; return the :class:`Tour`.

    With probability ``pause_rate`` per tick the robot stands still for 2-30 s (uniform). A
    robot that will wait at goals and checkpoints must have stood still while it learned its
    place cells: the slow features then treat a stop as part of the place, not as a new
    input (without pauses, a wait left the learned places off for the next minute).
    ``side``: the wall followed first (-1 right, +1 left; ``rho`` switches it at random).
    Each tick is logged in ``log`` (no agent yet) under ``phase``."""
    ctrl = WallFollower(WallFollowerParams(rho=rho), sensors=world.sensors, robot=world.robot,
                        rng=Seeds(seed).generator("exploration"), side=side)
    rng = Seeds(seed).generator("pauses")
    obs = world.observe()
    tour = Tour()
    pause = 0
    with Progress(ticks, desc) as bar:
        for _ in range(ticks):
            if pause > 0:
                pause -= 1
                obs = world.step((0.0, 0.0))
            else:
                if pause_rate > 0 and rng.random() < pause_rate:
                    pause = int(rng.uniform(2.0, 30.0) / world.dt)
                obs = world.step(ctrl.act(obs))
            tour.observations.append(obs)
            tour.truths.append(world.truth)
            if log is not None:
                log.add(obs, world.truth, None, phase, -1)
            bar.update()
    return tour


def learn_map(agent: Any, tour: Tour, desc: str = "map learning") -> None:
    """Replay the exploration through ``agent``: it learns its states, their timed transitions
    and the cognitive map from the robot's own run.

    The exploration's pauses are left out (ticks where the robot neither moved nor turned):
    they train the place cells on standing still, but a stop made for no reason is no event of
    the task. Replayed, every pause would leave a wait in the map for the planner to route
    through (measured: with --delay 3.3 the robot then stopped on its way at pause places and
    reached the goal in 52 of 60 rewarded trials instead of 60)."""
    needs_truth = getattr(agent.places, "kind", "") == "ground-truth"
    with Progress(len(tour), desc) as bar:
        for o, truth in zip(tour.observations, tour.truths):
            if o.moving or np.any(o.odometry):
                agent.step(o, truth if needs_truth else None)
            bar.update()


def place_model(units: int, seed: int = 0) -> RCSFAICA:
    """The learned place cells' RC-SFA-ICA before its fit (:func:`make_places` fits it):
    ``units`` slow features and ICA units over 8 IR readings and a 400-neuron reservoir (its
    ``params.sfa_inputs`` bound ``units``, ``params.min_fit_ticks`` the exploration)."""
    return RCSFAICA(n_reservoir=400, leak=(0.1, 0.3), spectral_radius=0.9, n_sfa=units,
                    n_ica=units, ica_restarts=3, seed=seed)


def make_places(kind: str, arena: Arena, sensors: np.ndarray, units: int, seed: int,
                n_places: int = 32, moving: np.ndarray | None = None) -> PlaceSource:
    """The place-cell source: RC-SFA-ICA fitted on the exploration (``units`` ICA units read
    out by ``n_places`` radial-basis prototypes over the ICA population vector), or ground
    truth (Gaussian fields at the arena's labelled locations).

    The reservoir is faster than SMC09's room detector (leaks 0.1 / 0.3 and spectral radius
    0.9 instead of 0.05 / 0.15 and 0.99): its slowest mode then forgets in about 20 s instead
    of several minutes, so what the closed loop does to the sensors (a leash off the explored
    line, a block, a wait) fades within a corridor. Measured over seeds 0-9: the patrol stops
    at 87 % of checkpoint passes instead of 74 %, place preference succeeds in 119 of 120
    rewarded trials instead of 116.

    ``moving`` (T,) — which exploration ticks the robot moved (:attr:`Tour.moving`): given, the
    learned cells keep the exploration for re-anchoring after a lift
    (:class:`~hippo.perception.relocate.SequenceRelocaliser`).
    """
    if kind == "ground-truth":
        return GroundTruthPlaceCells(arena.locations, sigma=8.0)
    if kind != "learned":
        raise ValueError(f"place cells must be 'learned' or 'ground-truth', got {kind!r}")
    model = place_model(units, seed)
    with working("fitting place cells"):
        Y = model.fit_transform(sensors)
        protos = PlacePrototypes(PrototypeParams(n_prototypes=n_places, seed=seed)).fit(Y)
        rel = None if moving is None else SequenceRelocaliser().fit(
            model.reservoir_, np.argmax(protos.transform(Y), axis=1), sensors, moving)
    model.reset_state()
    return LearnedPlaceCells(model, protos, relocaliser=rel)


#: the laps of a route's way round, in :func:`wall_side`'s probe, that make the wall outside
#: the route's loop the one to follow, and the largest share of the follower's progress along
#: the route that may run backwards: a follower that goes round, not one that turns back at
#: a nook and shuttles (goal-arena's right wall: 0.3-1.7 laps, 29-46 % of its progress
#: backwards; the outer walls of rings built with ArenaBuilder: 0-1.5 %).
#: docs/results.md, "the wall outside the loop"
OUTER_MIN_LAPS = 1.0
OUTER_MAX_BACK = 0.1


def wall_side(route: Route, arena: Arena, seed: int = 0, probe_s: float = 600.0) -> int:
    """The wall (-1 right, +1 left) a robot that will run ``route`` explores along, and
    follows on its moves (:attr:`hippo.motor.MotorParams.wall_side`).

    Place cells learned on one direction of travel along one wall code that motion; the other
    direction, along another wall, is input they never saw (patrol-course, clockwise routes
    through random checkpoints, tuning seeds 0, 5 and 7: the robot explored along the right
    wall, counter-clockwise, and ran its patrol backwards). Which way a wall follower goes
    round depends on the wall it finds (the outer wall of ``patrol-course``, the inner ring of
    ``goal-arena``), so the experimenter tries both: ``probe_s`` s of :func:`explore` from the
    arena's start in a world of its own (seeded by ``seed``) per side, counting laps of the
    route its way round.

    The wall outside the loop (the left one on a clockwise route) wins if its follower runs at
    least ``OUTER_MIN_LAPS`` laps the route's way with at most ``OUTER_MAX_BACK`` of its
    progress backwards; else the side that goes farther round it wins. Where both sides go round
    (a ring whose corridor the follower can cross), the inner wall's loop is shorter and makes
    more laps, but a follower of an inner block loses its wall at every convex corner, where a
    move's heading can carry it across the corridor onto the outer wall, which it then follows
    the other way round, into places never learned that way (rings and boxes built with
    ``ArenaBuilder``, learned cells, draws whose side this changes: 81 of 522 passes with a
    stop on the inner wall, 187 of 290 on the outer; docs/results.md).
    A route that encloses little (:attr:`Route.winding` 0: out and back) is run both ways; it
    keeps the right wall, as does a route neither side goes round its way (ties too)."""
    if route.winding == 0:
        return -1
    laps, back = {}, {}
    for side in (-1, 1):
        world = World(arena, seed=seed)
        lap = LapCounter(route)
        lap.update(*world.truth.pose[:2])
        tour = explore(world, round(probe_s / world.dt), 0.0, seed, pause_rate=0.0,
                       desc=f"probing the {'left' if side > 0 else 'right'} wall", side=side)
        steps = np.diff([0.0] + [lap.update(*truth.pose[:2]) for truth in tour.truths])
        laps[side] = lap.turns
        moved = np.abs(steps).sum()
        back[side] = -steps[steps < 0].sum() / moved if moved > 0 else 1.0
    outer = -route.winding
    if laps[outer] >= OUTER_MIN_LAPS and back[outer] <= OUTER_MAX_BACK:
        return outer
    return 1 if laps[1] > max(laps[-1], 0.0) else -1


def wall_tour(arena: Arena, side: int = -1, *, seed: int = 0, max_s: float = 1500.0,
              settle_s: float = 30.0, spacing: float = 3.0) -> Route | None:
    """The loop the exploring wall follower (``side``: -1 right, +1 left) runs round ``arena``,
    as a closed :class:`Route` with a point every ``spacing`` cm; None if the follower has not
    come back to where it was ``settle_s`` s after the start (within 4 cm, facing the same way)
    within ``max_s`` s.

    It is the line the robot learns its place cells on (:func:`explore`): a task along it
    stays on what they saw. In a tree of rooms (``two-rooms``) the shortest paths between
    checkpoints run out and back through the same doorway and across rooms the exploration
    never crossed; the tour is one loop round every wall, each doorway once each way."""
    for name, v, lo in (("max_s", max_s, ">"), ("settle_s", settle_s, ">="),
                        ("spacing", spacing, ">")):
        try:
            x = check_real(name, v)
        except ValueError:   # (a bool, a string, NaN or inf: named below in the same words)
            x = math.nan
        if not (x > 0 or (lo == ">=" and x == 0)):
            raise ValueError(f"wall_tour's {name} must be a finite number {lo} 0, got {v!r}")
    world = World(arena, seed=seed)
    tour = explore(world, round(max_s / world.dt), 0.0, seed, pause_rate=0.0, side=side,
                   desc="wall tour")
    pose = np.array([t.pose for t in tour.truths])
    xy = pose[:, :2]
    run = np.r_[0.0, np.cumsum(np.hypot(*np.diff(xy, axis=0).T))]
    i0 = min(round(settle_s / world.dt), len(xy) - 1)
    back = np.flatnonzero((run - run[i0] > 100.0) & (np.hypot(*(xy - xy[i0]).T) < 4.0)
                          & (np.cos(pose[:, 2] - pose[i0, 2]) > 0.8))
    if not back.size:
        return None
    j = int(back[0])
    along = run[i0:j + 1] - run[i0]
    grid = np.arange(0.0, along[-1], spacing)
    pts = np.column_stack([np.interp(grid, along, xy[i0:j + 1, k]) for k in (0, 1)])
    return Route(pts, closed=True)


def arena_tour(arena: str | Arena, side: int = -1) -> Route | None:
    """:func:`wall_tour` of ``arena`` (a built-in arena's name, or an :class:`Arena` of one's
    own) along wall ``side`` (-1 right, +1 left; cached: the tour is the arena's, not a
    run's)."""
    check_wall_side("side", side)
    if isinstance(arena, str):
        return _arena_tour(arena, side)
    if not isinstance(arena, Arena):
        raise TypeError(f"arena must be an arena's name or an Arena, got "
                        f"{type(arena).__name__}")
    key = (id(arena), side)
    hit = _OWN_TOURS.get(key)
    if hit is None or hit[0] is not arena:
        if len(_OWN_TOURS) >= 16:
            _OWN_TOURS.pop(next(iter(_OWN_TOURS)))
        hit = _OWN_TOURS[key] = (arena, wall_tour(arena, side))
    return hit[1]


#: the tours of arenas built by users (keyed by identity; the arena is kept with its tour)
_OWN_TOURS: dict[tuple[int, int], tuple[Arena, Route | None]] = {}


@functools.lru_cache(maxsize=16)
def _arena_tour(name: str, side: int) -> Route | None:
    return wall_tour(arenas.get(name), side)
