"""A task session: the robot (an agent) in a world, its teacher, and the log of the run.

:class:`Session` runs the closed loop tick by tick and logs every tick under the current
``phase`` and ``trial`` (a task's phases are an ``IntEnum``; their names go into ``run.npz``).
A phase script is a few calls::

    s = Session(world, agent, log, obs=tour[-1])
    s.phase = Phase.LEASH
    s.lead(route)                                   # the teacher walks the robot along route
    s.block(8.0)                                    # ... and holds it there 8 s
    s.agent.reward("food")                          # linked to the next transition
    s.run(seconds=120, until=lambda o: o.floor == 1)

The ground truth goes to the agent only when its place cells are the ground-truth comparison.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence
from typing import Any

from hippo._checks import check_int, check_real
from hippo.progress import Progress
from hippo.sim.teacher import Teacher
from hippo.sim.world import World
from hippo.tasks.log import Log
from hippo.types import Observation, wrap_angle

__all__ = ["LeashWarning", "Session"]


class LeashWarning(UserWarning):
    """A lead that did not bring the robot to its route's end within its limit."""


class Session:
    """Run ``agent`` in ``world`` and log it (see the module docstring).

    obs: the observation the agent acts on first (default: the world senses where it is).
    teacher: the world's teacher (default: a new :class:`Teacher` attached to ``world``).
    """

    def __init__(self, world: World, agent: Any, log: Log | None = None, *,
                 obs: Observation | None = None, teacher: Teacher | None = None,
                 phase: int = 0, trial: int = 0) -> None:
        self.world = world
        self.agent = agent
        self.log = log if log is not None else Log(n_drives=len(agent.drives.names))
        if teacher is None:
            teacher = world.teacher if isinstance(world.teacher, Teacher) else Teacher(world)
        self.teacher = teacher
        self.obs = obs if obs is not None else world.observe()
        self.phase, self.trial = phase, trial
        self._needs_truth = getattr(agent.places, "kind", "") == "ground-truth"

    @property
    def truth(self) -> Any:
        """The ground truth of the last observation (analysis and the teacher only)."""
        return self.world.truth

    @property
    def t(self) -> float:
        return float(self.obs.t)

    def ticks(self, seconds: float) -> int:
        """Whole ticks in ``seconds`` (rounded down; a quotient within 1e-9 of a whole number
        is that number: 0.6 s at ``dt`` 0.2 is 3 ticks, though 0.6 / 0.2 is 2.9999999999999996
        in floating point)."""
        return math.floor(seconds / self.world.dt + 1e-9)

    def run(self, ticks: int | None = None, *, seconds: float | None = None,
            until: Callable[[Observation], bool] | None = None,
            bar: Progress | None = None) -> Observation:
        """Step the closed loop for ``ticks`` ticks (or ``seconds``), or until ``until(obs)``
        is true after a tick; returns the last observation."""
        if (ticks is None) == (seconds is None):
            raise ValueError("give either ticks or seconds")
        if ticks is not None:
            n = check_int("ticks", ticks, lo=0)
        else:
            if check_real("seconds", seconds) < 0:
                raise ValueError(f"seconds must be >= 0, got {seconds!r}")
            n = self.ticks(seconds)  # type: ignore[arg-type]
        world, agent, log = self.world, self.agent, self.log
        obs = self.obs
        for _ in range(n):
            obs = world.step(agent.step(obs, world.truth if self._needs_truth else None))
            log.add(obs, world.truth, agent, self.phase, self.trial)
            if bar is not None:
                bar.update()
            if until is not None and until(obs):
                break
        self.obs = obs
        return obs

    # -- the teacher --------------------------------------------------------------------------
    def lead(self, route: Sequence[Sequence[float]], limit: int = 6000) -> Observation:
        """Walk the robot on the leash through ``route`` (at most ``limit`` ticks). A lead that
        has not reached the route's end by then drops the leash (a :class:`LeashWarning` says
        where): it kept pulling through every later phase."""
        self.teacher.lead(route)
        obs = self.run(limit, until=lambda o: not self.teacher.leading)
        if self.teacher.leading:
            self.teacher.stop_leading()
            x, y = self.world.truth.pose[:2]
            warnings.warn(f"the leash was dropped after {limit} ticks with the robot at "
                          f"({x:.0f}, {y:.0f}), short of the route's end {tuple(route[-1])}",
                          LeashWarning, stacklevel=2)
        return obs

    def block(self, seconds: float, extra: float = 1.0) -> Observation:
        """Hold the robot where it is for ``seconds`` (the teacher's block), then go on."""
        self.teacher.block(seconds)
        return self.run(self.ticks(seconds + extra), until=lambda o: not self.teacher.blocking)

    def put(self, x: float, y: float, heading: float, *, event: str = "kidnap",
            keep_drives: bool = False) -> None:
        """Pick the robot up and put it down at ``(x, y, heading)``; the agent knows it was
        lifted and how much it was turned (not where it is). ``keep_drives``: the drives a
        finished wait holds stay held (a kidnap in the middle of a task), see
        :meth:`hippo.brain.Brain.lifted`; False: a new trial.

        The turn is counted from the heading the agent last integrated: :attr:`obs`, the
        observation it has not acted on yet, holds one more tick of odometry (its rotation
        would otherwise be lost at every lift, and the heading estimate would drift by up to
        half a radian per kidnap: place preference, tuning seed 0, 0.85 rad after 8 trials)."""
        heading = check_real("heading", heading)   # before anything moves
        turned = wrap_angle(heading - self.world.truth.pose[2] + float(self.obs.odometry[2]))
        self.world.place_robot(x, y, heading, event=event)
        self.agent.lifted(heading_change=turned, keep_drives=keep_drives)

    def save(self, out: Any, phases: Any = None) -> dict:
        """Write ``run.npz`` and ``map.graphml`` into ``out`` (see :meth:`Log.save`)."""
        return self.log.save(out, self.agent, self.world, phases=phases)
