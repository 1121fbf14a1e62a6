"""The whole robot: a :class:`~hippo.brain.Brain` (the neural loop) and a
:class:`~hippo.motor.Motor` (its wheels), one :meth:`Agent.step` per control tick::

    tick = brain.step(obs)           perceive, learn, decide (hippo.brain, hippo.decision)
    command = motor.act(obs, tick)   explore, steer to a heading, avoid, unstick, wait
    if command.gave_up: brain.abandon()

The place sources live in :mod:`hippo.places` (re-exported here): learned RC-SFA-ICA place cells
by default, Gaussian fields on the true position only to measure what perception costs.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hippo._checks import check_observation
from hippo.brain import Brain, BrainParams, Tick
from hippo.cognitive_map import DriveParams
from hippo.motor import Motor, MotorParams
from hippo.places import GroundTruthPlaceCells, LearnedPlaceCells, PlaceSource
from hippo.seeds import Seeds
from hippo.sim.robot import RobotParams, SensorModel, get_sensor_model
from hippo.types import GroundTruth, Mode, Observation, Transition

__all__ = ["Agent", "AgentParams", "GroundTruthPlaceCells", "LearnedPlaceCells", "Mode",
           "PlaceSource", "Transition"]

_BRAIN = frozenset(f.name for f in dataclasses.fields(BrainParams))
_MOTOR = frozenset(f.name for f in dataclasses.fields(MotorParams))


@dataclass(frozen=True, init=False)
class AgentParams:
    """The brain's and the motor layer's parameters (:class:`BrainParams`,
    :class:`MotorParams`).

    Built nested (``AgentParams(brain=BrainParams(...), motor=MotorParams(...))``) or from the
    fields' names directly (``AgentParams(settle_time=4.0, explore_rho=0.01)``: each name goes
    to the part that has it); reading ``params.settle_time`` reads that part's field.
    """

    brain: BrainParams = field(default_factory=BrainParams)
    motor: MotorParams = field(default_factory=MotorParams)

    def __init__(self, brain: BrainParams | None = None, motor: MotorParams | None = None,
                 **fields: Any) -> None:
        unknown = sorted(set(fields) - _BRAIN - _MOTOR)
        if unknown:
            raise TypeError(f"AgentParams got unknown parameter(s) {unknown}; the brain's are "
                            f"{sorted(_BRAIN)}, the motor's {sorted(_MOTOR)}")
        b = {k: v for k, v in fields.items() if k in _BRAIN}
        m = {k: v for k, v in fields.items() if k in _MOTOR}
        brain = dataclasses.replace(brain or BrainParams(), **b)
        motor = dataclasses.replace(motor or MotorParams(), **m)
        object.__setattr__(self, "brain", brain)
        object.__setattr__(self, "motor", motor)

    def __getattr__(self, name: str) -> Any:
        if name in _BRAIN:
            return getattr(self.brain, name)
        if name in _MOTOR:
            return getattr(self.motor, name)
        raise AttributeError(f"'AgentParams' object has no attribute {name!r}")


#: brain attributes an Agent shows under its own name (read-only views)
_VIEWS = frozenset({
    "places", "layer", "timing", "spectral", "cells", "nonocc", "graph", "drives", "planner",
    "pi", "rng", "t", "state", "mode", "current", "readouts", "non_occurrence",
    "last_transition", "entered_at", "decide", "kind", "describe", "lifted", "reward",
    "snapshot",
})


class Agent:
    """HIREL's architecture on any place source, driving an e-puck; one :meth:`step` a tick.

    The brain's parts are shown under the agent's name (``agent.graph``, ``agent.drives``,
    ``agent.layer``, ``agent.cells``, ``agent.state``, ``agent.mode`` ...), and so are its
    :meth:`~hippo.brain.Brain.lifted`, :meth:`~hippo.brain.Brain.reward`,
    :meth:`~hippo.brain.Brain.describe` and :meth:`~hippo.brain.Brain.snapshot`.

    Parameters
    ----------
    places : a :class:`PlaceSource` (:class:`LearnedPlaceCells` in every scenario by default).
    drives : drive name -> :class:`DriveParams`. The drive ``"sound"`` is satisfied by the
        reward sound; others by :meth:`reward` (e.g. the teacher's end of a checkpoint block).
    params : :class:`AgentParams`.
    sensors, robot : the robot the motor layer drives.
    seed : the run's seed: the agent's random streams (:mod:`hippo.seeds`: ``brain``,
        ``motor-explore``, ``motor-steer``).
    """

    _last_tick: int | None = None   # (a snapshot saved before the clock check has none)

    def __init__(self, places: PlaceSource, *, drives: Mapping[str, DriveParams] | None = None,
                 params: AgentParams | None = None, sensors: str | SensorModel = "ir8",
                 robot: RobotParams | None = None, seed: int = 0) -> None:
        self.params = params or AgentParams()
        self.robot = robot or RobotParams()
        self.sensors = get_sensor_model(sensors)
        seeds = Seeds(seed)
        self.motor = Motor(self.params.motor, dt=self.params.brain.dt, sensors=self.sensors,
                           robot=self.robot, rng_explore=seeds.generator("motor-explore"),
                           rng_steer=seeds.generator("motor-steer"))
        self.brain = Brain(places, drives=drives, params=self.params.brain,
                           occlusion=self.motor.avoid, seed=seed)
        self.last_tick: Tick | None = None
        self._last_t = -math.inf  # the clock must run forward (check_observation)
        self._last_tick = None  # ... at BrainParams.dt per tick (_check_clock)

    @property
    def p(self) -> AgentParams:
        return self.params

    @p.setter
    def p(self, params: AgentParams) -> None:
        """Swap the parameters (the brain and the motor layer read the new ones)."""
        self.params = params
        self.brain.p = params.brain
        self.motor.p = params.motor

    def __getattr__(self, name: str) -> Any:
        if name in _VIEWS:
            return getattr(self.__dict__["brain"], name)
        raise AttributeError(f"'Agent' object has no attribute {name!r}")

    def step(self, obs: Observation, truth: GroundTruth | None = None) -> tuple[float, float]:
        """Perceive, learn, decide and act for one tick; returns wheel speeds (cm/s).

        ``truth`` (``World.truth``) is needed only by ground-truth place cells."""
        last_t = self._last_t
        ir, t = check_observation(obs, self.sensors.n, last_t)
        self._check_clock(getattr(obs, "tick", None), last_t, t)
        self._last_t = t   # (a refused observation moves neither the time nor the tick)
        tick = self.brain._step(obs, truth, ir)
        command = self.motor.act(obs, tick)
        if command.gave_up:
            self.brain.abandon()
        self.last_tick = tick
        return command.wheels

    def _check_clock(self, tick: Any, last_t: float, t: float) -> None:
        """Refuse a world whose clock runs at another step than the brain's ``dt``: the drives,
        time cells and learned delays integrate ``BrainParams.dt`` on every tick, so a
        ``World(dt=0.5)`` would stretch every delay 2.5 times in silence. The step is the time
        per tick between two observations the agent saw (ticks it did not see, such as the
        pauses ``learn_map`` leaves out, divide out; a repeated tick or a clock that does not
        count ticks is not checked). The tick is kept once it passes (``t`` is this
        observation's time, ``last_t`` the previous one's)."""
        last, now = self._last_tick, (
            tick if type(tick) is int or isinstance(tick, np.integer) else None)
        if last is not None and now is not None and now > last:
            step = (t - last_t) / (now - last)
            dt = self.params.brain.dt
            if abs(step - dt) > 1e-6 * dt + 1e-8:
                raise ValueError(
                    f"the observations' clock runs {step:.6g} s per tick (obs.t {last_t:.6g} at "
                    f"tick {last}, {t:.6g} at tick {now}), but the agent's BrainParams.dt is "
                    f"{dt:g} s: give the World and the agent the same step (World(dt={dt:g}), or "
                    f"AgentParams(dt=<the world's dt>))")
        self._last_tick = now
