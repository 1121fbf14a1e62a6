"""A timed patrol as a library: checkpoints on a route through any arena, the lesson (a loop on
the leash, a loop reproduced, the waits taught by blocks), autonomous laps, and what each pass
by a checkpoint gave.

- ``ARENA_CHECKPOINTS``, ``HIREL_WAITS``, :func:`patrol_route`, :func:`choose_route`,
  :func:`check_patrol`, :func:`random_patrol` — the checkpoints, their waits and the route
  through them (from :mod:`hippo.tasks.patrol_sets`).
- :class:`PatrolPhase` — the phases of the patrol scenarios (their names go into ``run.npz``).
- :class:`PatrolCourse` — the phases on a :class:`~hippo.tasks.Session`: :meth:`teach`,
  :meth:`patrol`, :meth:`adapt`, :meth:`kidnap`, and the lap bookkeeping behind them.
- :func:`pass_report`, :func:`patrol_rounds` — what the passes gave (from
  :mod:`hippo.tasks.patrol_report`).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from enum import IntEnum
from typing import Any

import numpy as np

from hippo._checks import check_int
from hippo.progress import Progress
from hippo.tasks.patrol_report import PASS_RADIUS, pass_report, patrol_rounds
from hippo.tasks.patrol_sets import (
    ARENA_CHECKPOINTS,
    HIREL_WAITS,
    ROUTE_KINDS,
    TOUR_REACH,
    check_patrol,
    choose_route,
    patrol_route,
    random_patrol,
)
from hippo.tasks.routes import LapCounter, Route, checkpoints_xy, lead_from
from hippo.tasks.session import Session
from hippo.tasks.teaching import lessons_again
from hippo.types import Mode, StateKind

__all__ = [
    "ARENA_CHECKPOINTS", "HIREL_WAITS", "ROUTE_KINDS", "TOUR_REACH", "PatrolCourse", "PatrolPhase",
    "PatrolWarning", "check_patrol", "choose_route", "pass_report", "patrol_rounds", "patrol_route",
    "random_patrol",
]

#: a lesson's run from one checkpoint to the next on a wall tour longer than ``DETOUR_RATIO``
#: x the route's leg + ``DETOUR_SLACK`` cm went out of its way (:meth:`PatrolCourse.detour`):
#: read off the tuning lessons (two-rooms and goal-arena 0-23: run / leg median 0.99; a robot
#: that wandered taught two-rooms seed 17 a 140-cm run-up for a 103-cm leg, and the run-up
#: gate then held every stop there until the robot had left the place). Not on the shortest
#: paths: the robot crosses rooms along their walls, 2-4 x those legs (two-rooms 10, 22)
DETOUR_RATIO = 1.25
DETOUR_SLACK = 10.0


class PatrolWarning(UserWarning):
    """A patrol that completed fewer than half its loops."""


class PatrolPhase(IntEnum):
    EXPLORATION = 0
    LEASH = 1
    REPRODUCTION = 2
    CHECKPOINTS = 3
    PATROL = 4
    ADAPTATION = 5
    KIDNAP = 6
    DEPLOYMENT = 7


class PatrolCourse:
    """The patrol's phases on one session: the robot, its teacher, the route and checkpoints.

    ``names[k]`` is the drive of ``checkpoints[k]``. Laps are counted by progress along the
    route (:class:`LapCounter`); a phase that counts laps ends at the route's *quiet point*,
    the point farthest (along the route) from every checkpoint, so that a stop at a checkpoint
    never straddles the end of a phase."""

    def __init__(self, s: Session, route: Route, checkpoints: Sequence[Sequence[float]],
                 names: Sequence[str], *, tour: bool = False) -> None:
        self.s, self.agent, self.dt = s, s.agent, s.world.dt
        self.route = route
        cps = checkpoints_xy(checkpoints)
        if isinstance(names, str) or len(names) != len(cps) or len(set(names)) != len(names):
            raise ValueError(f"names must be one distinct drive name per checkpoint "
                             f"({len(cps)}), got {names!r}")
        self.checkpoints = [(float(x), float(y)) for x, y in cps]
        self.names = list(names)
        self.loop = LapCounter(route)
        L = route.length
        s_cp = np.array([route.progress(*c) for c in self.checkpoints])
        grid = np.arange(0.0, L, 1.0)
        far = np.min(np.abs((grid[:, None] - s_cp[None, :] + L / 2) % L - L / 2), axis=1)
        self.quiet = float(grid[int(np.argmax(far))])
        self._s_cp = s_cp   # each checkpoint's progress along the route
        #: the checkpoints (indices) in the order the route passes them, from the first
        self.order = sorted(range(len(s_cp)), key=lambda k: (s_cp[k] - s_cp[0]) % L)
        self.relocalised_s: float | None = None   # the kidnap's time to re-localise
        self.tour = tour   # the route is the wall tour the robot explored along (its own way)

    @property
    def lap_s(self) -> float:
        """Time allowed for one lap: 3 x the route at 5 cm/s, at least 600 s."""
        return max(600.0, 3.0 * self.route.length / 5.0)

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

    def from_here(self, waypoints: list[tuple[float, float]]) -> list[tuple[float, float]]:
        """``waypoints`` for the leash from where the robot is (:func:`lead_from`)."""
        return lead_from(self.s.world.arena, self.s.truth.pose[:2], waypoints)

    def near(self, point: Sequence[float], radius: float) -> bool:
        return math.dist(self.s.truth.pose[:2], point) < radius

    def reached(self, checkpoint: Sequence[float]) -> bool:
        """Has the robot come to ``checkpoint`` (:meth:`LapCounter.reached`: level with it
        along the route, within ``PASS_RADIUS``)? The lesson blocks it there, not some way
        before it: every taught stop and run-up counts from there. (Within 20 cm, tuning seed
        25's (131, 41), across the corridor from the robot's wall, was never reached; the
        lesson led it round again and taught a run-up a lap too long.)"""
        return self.loop.reached(*self.s.truth.pose[:2], checkpoint, radius=PASS_RADIUS,
                                 from_behind=True)

    def set_off_for(self, checkpoint: Sequence[float]) -> None:
        """From here the robot is to come to ``checkpoint`` going the route's way round:
        :meth:`reached` holds it there once it has come up behind it, not when it comes to it
        the wrong way round (held-out seed 241: after checkpoint 2's lesson the robot turned
        back, came to checkpoint 3 from beyond, and was held 26-30 cm from it on a place it
        never passes going the right way)."""
        self.loop.forget(checkpoint)

    def learned_waits(self) -> list[float | None]:
        """Per checkpoint, the median learned delay of the transitions its drive is linked to
        (the wait the robot will make there), or None."""
        cells, drives = self.agent.cells, self.agent.drives
        out: list[float | None] = []
        for n in self.names:
            delays = [cells.learned_delay(t) for t in drives.links(n) if t in cells.transitions]
            out.append(float(np.median(delays)) if delays else None)
        return out

    def teach(self, waits: Sequence[float]) -> float:
        """Settle, one loop on the leash, one loop reproduced alone, then the checkpoints
        taught by blocks (in the order the route passes them, :attr:`order`, and the first
        once more); returns the fraction of the loop reproduced."""
        if len(waits) != len(self.checkpoints):   # before the leash, not at the lesson
            raise ValueError(f"waits must give one wait per checkpoint "
                             f"({len(self.checkpoints)}), got {len(waits)}")
        s, agent, dt = self.s, self.agent, self.dt
        # let the place cells settle on the course before the leash (not moved: no re-anchoring)
        agent.lifted(moved=False)
        s.run(int(agent.p.settle_time / dt) + 1)
        # one loop on the leash, counter-clockwise from the nearest waypoint ahead
        s.teacher.lead(self.from_here(self.route.loop_from(s.truth.pose)))
        self.laps()
        with Progress(1, "leash") as bar:
            s.run(6000, until=lambda o: not s.teacher.leading)
            bar.update()
        # reproduction: no drive leads anywhere yet (an active one makes the robot explore:
        # on patrol-course the exploring wall follower runs the loop)
        agent.drives.step(0.0)
        s.phase, start_turns = PatrolPhase.REPRODUCTION, self.laps()
        with Progress(1, "reproduction") as bar:
            s.run(int(max(400.0, 3.0 * self.route.length / 5.0) / dt),
                  until=self.lap_until(start_turns + 1.0))
            reproduced = self.loop.turns - start_turns
            bar.update()
        # checkpoints: block the robot at each for its wait, reward its drive as it ends; the
        # first once more at the end, so that every taught stop follows another and the robot
        # knows its run-up from the wait before (BrainParams.runup_tolerance); the drive of
        # the checkpoint ahead is held meanwhile (the teacher chooses that stop). A robot not
        # there in twice the route's time at 5 cm/s (and 60 s) is led there on the leash: its
        # run is no run-up, and the lessons up to it are given again after the rest, in order
        # (held-out seeds 140-159: each of the 6 seeds that failed had such a lesson)
        s.phase = PatrolPhase.CHECKPOINTS
        order, again = [*self.order, 0], set()
        since: tuple[int, tuple[float, float]] | None = None  # log row, pose at the last reward
        with Progress(len(order), "checkpoints") as bar:
            for i, k in enumerate(order):
                c = self.checkpoints[k]
                s.trial = k
                agent.drives.inhibit(self.names[k])
                self.laps()
                ahead = (self.route.progress(*c) - self.loop.progress) % self.route.length  # type: ignore[operator]
                self.set_off_for(c)
                s.run(int((60.0 + 2.0 * ahead / 5.0) / dt),
                      until=lambda o, c=c: self.reached(c))
                alone = self.reached(c)
                if not alone:
                    if agent.mode == Mode.WAIT:
                        # a robot in a stop of its own is not pulled away mid-wait: it would
                        # learn the cut-short stillness as that stop's wait (patrol-course,
                        # checkpoints out of the loop's order, seed 333: 24 s taught, 15.6 s
                        # learned after a lead cut its stop at 11 s)
                        s.run(int(2.0 * max(waits) / dt) + 1,
                              until=lambda o: agent.mode != Mode.WAIT)
                    s.lead(self.from_here(self.route.leg(s.truth.pose, c)))
                    lessons_again(order, i, again)
                elif (self.tour and since is not None and k not in again
                      and self.detour(order[i - 1], k, s.log.path_length(*since))):
                    # it came by itself after a detour: no run-up, and the lesson is given
                    # again (but the first checkpoint's: that one then has none)
                    alone = False
                    lessons_again(order, i, again)
                s.block(waits[k])
                agent.reward(self.names[k], runup=alone)
                since = (len(s.log), (float(s.truth.pose[0]), float(s.truth.pose[1])))
                s.run(int(10 / dt),
                      until=lambda o: self.state_kind() not in (None, StateKind.STILL))
                agent.drives.release(self.names[k])
                bar.update()
        return reproduced

    def detour(self, a: int, b: int, ran: float) -> bool:
        """Did a robot that ran ``ran`` cm from checkpoint ``a`` to checkpoint ``b`` go out of
        its way: more than ``DETOUR_RATIO`` times the route's leg between them and
        ``DETOUR_SLACK`` cm more? On a wall tour (``tour``) the teacher takes such a run for
        no run-up, as one that needed the leash, and gives the lesson again."""
        leg = float(self._s_cp[b] - self._s_cp[a]) % self.route.length
        return ran > DETOUR_RATIO * leg + DETOUR_SLACK

    def drives_up(self) -> None:
        """Every drive up to 1, but that of the checkpoint the lesson served last (the first
        one: the robot has just left it), which keeps its level: at 1 it made the robot stop
        there once more a few dozen cm on."""
        for d in self.names[1:]:
            self.agent.drives.set_level(d, 1.0)

    def patrol(self, loops: int) -> float:
        """Every drive up (:meth:`drives_up`), ``loops`` laps alone; returns the laps
        completed. A :class:`PatrolWarning` says when fewer than half were (negative: the robot
        went round backwards)."""
        check_int("loops", loops, lo=1)
        s = self.s
        self.drives_up()
        s.phase, start_turns = PatrolPhase.PATROL, self.laps()
        # the first lap ends at the quiet point after a whole loop (or a little more)
        end = self.laps_to_quiet(1)
        with Progress(loops, "patrol") as bar:
            for k in range(loops):
                s.trial = k
                s.run(int(self.lap_s / self.dt), until=self.lap_until(end + k))
                bar.update()
        laps = min(self.loop.turns - start_turns, float(loops))
        if laps < 0.5 * loops:
            warnings.warn(f"the robot completed {laps:.2f} of {loops} loops"
                          + (", round the route backwards" if laps < 0 else "")
                          + ": where a corridor lets the wall follower take either wall, the "
                          "other side may hold (teach_patrol(..., side=...); the patrol "
                          "tutorial's known limitation)", PatrolWarning, stacklevel=2)
        return laps

    def adapt(self, waits: Sequence[float], arena: Any) -> tuple[float, float, int, int]:
        """A longer block at checkpoint 1, an early leash restart at checkpoint 2, then a loop
        and a bit alone; returns the two taught waits and the log rows of that loop."""
        if min(len(self.checkpoints), len(waits)) < 2:
            raise ValueError(f"adapt needs two checkpoints and their waits, got "
                             f"{len(self.checkpoints)} and {len(waits)}")
        s, agent, dt = self.s, self.agent, self.dt
        longer = waits[0] + 8.0
        c1, c2 = self.checkpoints[0], self.checkpoints[1]
        # the teacher holds the robot when it stops at checkpoint 1 by itself: its stillness
        # lasts `longer` s instead of the learned wait (if it passes without stopping, it is
        # held where the checkpoint was taught, as in teaching)
        s.phase, s.trial = PatrolPhase.ADAPTATION, 0
        self.set_off_for(c1)

        def at_c1(o: Any) -> bool:
            there = self.reached(c1)   # asked every tick: it follows the approach
            return self.near(c1, 30.0) and (there or self.state_kind() == StateKind.STILL
                                             or agent.mode in (Mode.APPROACH, Mode.WAIT))
        s.run(int(400 / dt), until=at_c1)
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
        """Put the robot down on the route 75 cm before the checkpoint whose drive is lowest
        (it was served last), facing along the loop: does it head on to a checkpoint with a
        high drive instead of stopping at the one it was put before?"""
        s, agent, names = self.s, self.agent, self.names
        levels = {n: agent.drives.level(n) for n in names}
        low = min(names, key=levels.get)  # type: ignore[arg-type]
        # 75 cm before it along the route (the place code settles over the first 30 cm),
        # facing along the route
        kx, ky, heading = self.route.at(
            self.route.progress(*self.checkpoints[names.index(low)]) - 75.0)
        s.phase, s.trial = PatrolPhase.KIDNAP, 0
        s.put(kx, ky, heading, keep_drives=True)   # a perturbation, not a new trial
        self.loop.reset()
        t_kid = s.t
        obs = s.run(int(300 / self.dt), until=lambda o: agent.mode == Mode.WAIT)
        loc = agent.brain.localiser
        self.relocalised_s = None if loc is None else loc.time_to_localise
        stop = None
        if agent.mode == Mode.WAIT:
            d = [math.dist(s.truth.pose[:2], c) for c in self.checkpoints]
            served = agent.snapshot()["wait_drive"]
            stop = {"nearest_checkpoint": names[int(np.argmin(d))],
                    "distance_cm": float(min(d)), "t_after_kidnap_s": float(obs.t - t_kid),
                    "drive": names[served] if served >= 0 else None}
            s.run(int(5 / self.dt))
        return levels, low, stop
