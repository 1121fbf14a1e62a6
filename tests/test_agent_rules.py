"""AgentParams, Agent and its clock check: known answers worked out by hand.

Each expected value is read off the module's text or worked out independently: the seeds from
``np.random.SeedSequence([seed, key])`` with the keys of hippo.seeds.STREAMS written out here
(brain 7, motor-explore 8, motor-steer 9); the clock's step as (t2 - t1) / (tick2 - tick1) by
hand; the error messages word for word from their specification.
"""

from __future__ import annotations

import dataclasses
import re
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from hippo.agent import Agent, AgentParams
from hippo.brain import BrainParams
from hippo.motor import MotorCommand, MotorParams
from hippo.sim.robot import RobotParams, get_sensor_model
from hippo.types import Observation


class _Places:
    """A place source that always reports place 0 (no ground truth, no fit)."""

    kind = "stub"
    n_units = 2

    def step(self, obs: Any, truth: Any = None) -> np.ndarray:
        return np.array([1.0, 0.0])

    def reset(self) -> None:
        pass

    def prime(self, sensors: np.ndarray) -> None:
        pass


def _obs(t: float, tick: Any, n: int = 8) -> Observation:
    """A still robot seeing nothing near (readings 0.1), at time ``t`` and ``tick``."""
    return Observation(t, tick, np.full(n, 0.1), 0, False, np.zeros(3), False)


def _first(rng: np.random.Generator) -> float:
    return float(rng.random())


# ---- AgentParams ------------------------------------------------------------------------

def test_unknown_parameters_are_named_sorted_with_every_known_name():
    brain = sorted(f.name for f in dataclasses.fields(BrainParams))
    motor = sorted(f.name for f in dataclasses.fields(MotorParams))
    with pytest.raises(TypeError) as err:
        AgentParams(zz_top=1, aa_first=2, settle_time=3.0)
    assert str(err.value) == (f"AgentParams got unknown parameter(s) ['aa_first', 'zz_top']; "
                              f"the brain's are {brain}, the motor's {motor}")
    # one unknown alone is named the same way (a list of one)
    with pytest.raises(TypeError, match=re.escape("unknown parameter(s) ['x'];")):
        AgentParams(x=1)


def test_flat_names_override_the_nested_parts_field_by_field():
    base_b = BrainParams(settle_time=4.0)
    base_m = MotorParams(explore_rho=0.01)
    p = AgentParams(brain=base_b, motor=base_m, turn_limit=1.5, speed=3.0)
    # each flat name replaces one field of its own part; the nested fields stay
    assert p.brain == BrainParams(settle_time=4.0, turn_limit=1.5)
    assert p.motor == MotorParams(explore_rho=0.01, speed=3.0)
    # the given parts themselves are not changed (they are frozen; replace makes new ones)
    assert base_b.turn_limit == BrainParams().turn_limit
    # no flat names: the parts given are the parts kept; none given: the defaults
    q = AgentParams(brain=base_b, motor=base_m)
    assert q.brain == base_b and q.motor == base_m
    assert AgentParams() == AgentParams(brain=BrainParams(), motor=MotorParams())
    assert AgentParams(speed=3.0).brain == BrainParams()
    assert AgentParams(settle_time=4.0).motor == MotorParams()


def test_reading_a_field_reads_its_part_and_an_unknown_name_is_refused():
    p = AgentParams(settle_time=4.0, explore_rho=0.01)
    assert p.settle_time == 4.0 and p.explore_rho == 0.01
    assert p.dt == BrainParams().dt and p.speed == MotorParams().speed
    with pytest.raises(AttributeError) as err:
        _ = p.nope
    assert str(err.value) == "'AgentParams' object has no attribute 'nope'"
    assert not hasattr(p, "nope")


def test_agent_params_are_frozen():
    p = AgentParams()
    with pytest.raises(dataclasses.FrozenInstanceError):
        p.brain = BrainParams()  # type: ignore[misc]


# ---- Agent: its parts -----------------------------------------------------------------

def test_the_agent_keeps_what_it_is_given():
    params = AgentParams(dt=0.1, settle_time=2.0)
    robot = RobotParams()
    model = get_sensor_model("ray17")
    agent = Agent(_Places(), params=params, robot=robot, sensors=model)
    assert agent.params is params and agent.p is params
    assert agent.robot is robot and agent.sensors is model
    # the motor layer drives the same robot and sensors, at the brain's dt
    assert agent.motor.robot is robot and agent.motor.sensors is model
    assert agent.motor.dt == 0.1 and agent.motor.p is params.motor
    assert agent.brain.p is params.brain
    # the brain's occlusion test is the motor's obstacle avoidance (one answer per tick)
    assert agent.brain.occlusion is agent.motor.avoid
    assert agent.last_tick is None and agent._last_tick is None


def test_the_defaults():
    agent = Agent(_Places())
    assert agent.params == AgentParams()
    assert agent.robot == RobotParams()
    assert agent.sensors is get_sensor_model("ir8") and agent.sensors.n == 8
    assert agent.motor.dt == 0.2


@pytest.mark.parametrize("seed", [0, 5])
def test_the_random_streams_come_from_the_run_seed(seed):
    """brain 7, motor-explore 8, motor-steer 9 (hippo.seeds.STREAMS): each stream's first
    draw is that of SeedSequence([seed, key]), built here directly."""
    agent = Agent(_Places(), seed=seed) if seed else Agent(_Places())

    def expected(key: int) -> float:
        return _first(np.random.default_rng(np.random.SeedSequence([seed, key])))

    assert _first(agent.brain.rng) == expected(7)
    assert _first(agent.motor.explorer.rng) == expected(8)
    assert _first(agent.motor.steer.follower.rng) == expected(9)


def test_swapping_the_parameters_reaches_the_brain_and_the_motor():
    agent = Agent(_Places())
    new = AgentParams(settle_time=1.0, speed=2.0)
    agent.p = new
    assert agent.params is new and agent.p is new
    assert agent.brain.p is new.brain and agent.motor.p is new.motor


_NAMES = ("places", "layer", "timing", "spectral", "cells", "nonocc", "graph", "drives",
          "planner", "pi", "rng", "t", "state", "mode", "current", "readouts", "non_occurrence",
          "last_transition", "entered_at", "decide", "kind", "describe", "lifted", "reward",
          "snapshot")


@pytest.mark.parametrize("name", _NAMES)
def test_each_view_is_the_brains_own(name):
    places = _Places()
    agent = Agent(places)
    ours, theirs = getattr(agent, name), getattr(agent.brain, name)
    if callable(theirs) and hasattr(theirs, "__self__"):   # a bound method: the same one
        assert ours == theirs and ours.__self__ is agent.brain
    else:
        assert ours is theirs
    assert agent.places is places


def test_anything_else_is_no_attribute_of_the_agent():
    agent = Agent(_Places())
    for name in ("nope", "odometer", "runups", "abandon"):   # brain attributes not shown
        with pytest.raises(AttributeError) as err:
            getattr(agent, name)
        assert str(err.value) == f"'Agent' object has no attribute {name!r}"


# ---- Agent.step -------------------------------------------------------------------------

def test_step_returns_the_motors_wheels_and_gives_up_through_the_brain():
    agent = Agent(_Places())
    seen: list[Any] = []
    abandoned: list[bool] = []
    agent.brain.abandon = lambda: abandoned.append(True)   # type: ignore[method-assign]

    def act(obs: Observation, tick: Any) -> MotorCommand:
        seen.append(tick)
        return MotorCommand(3.0, -4.0, gave_up=len(seen) == 2)

    agent.motor.act = act   # type: ignore[method-assign]
    assert agent.step(_obs(0.0, 0)) == (3.0, -4.0)
    assert abandoned == [] and agent.last_tick is seen[0]
    assert agent.step(_obs(0.2, 1)) == (3.0, -4.0)
    assert abandoned == [True] and agent.last_tick is seen[1]
    assert seen[1].t == 0.2


def test_the_first_observation_may_come_at_any_time():
    """The clock starts at -inf: a first observation at a negative time is no error."""
    agent = Agent(_Places())
    agent.step(_obs(-5.0, 0))
    assert agent.brain.t == -5.0
    with pytest.raises(ValueError, match=re.escape("earlier than the previous tick's -5.0")):
        agent.step(_obs(-6.0, 1))


def test_the_readings_are_checked_against_the_agents_sensor_model():
    agent = Agent(_Places(), sensors="ray17")
    agent.step(_obs(0.0, 0, n=17))
    with pytest.raises(ValueError, match=re.escape("obs.ir must have shape (17,), got (8,)")):
        agent.step(_obs(0.2, 1, n=8))


# ---- the clock check --------------------------------------------------------------------

def test_a_clock_at_another_step_is_refused_word_for_word():
    """Ticks 3 and 5 at t = 1 and 2 s: (2 - 1) / (5 - 3) = 0.5 s per tick, not 0.2."""
    agent = Agent(_Places())
    agent.step(_obs(1.0, 3))
    with pytest.raises(ValueError) as err:
        agent.step(_obs(2.0, 5))
    assert str(err.value) == (
        "the observations' clock runs 0.5 s per tick (obs.t 1 at tick 3, 2 at tick 5), but the "
        "agent's BrainParams.dt is 0.2 s: give the World and the agent the same step "
        "(World(dt=0.2), or AgentParams(dt=<the world's dt>))")


def test_the_step_divides_out_the_ticks_not_seen():
    """Ticks 3 and 8 at t = 1.0 and 2.0 s: 1.0 / 5 = 0.2 s per tick, the brain's dt."""
    agent = Agent(_Places())
    agent.step(_obs(1.0, 3))
    agent.step(_obs(2.0, 8))
    assert agent.brain.t == 2.0


@pytest.mark.parametrize(("off", "refused"), [
    (1e-7, False), (-1e-7, False), (2e-7, False), (-2e-7, False),   # within 2.1e-7
    (2.2e-7, True), (-2.2e-7, True), (3e-7, True), (1e-3, True),   # one step past
])
def test_the_clock_tolerance_is_1e_6_dt_plus_1e_8(off, refused):
    """dt = 0.2: the step may be off by 1e-6 * 0.2 + 1e-8 = 2.1e-7 s per tick."""
    agent = Agent(_Places())
    agent.step(_obs(10.0, 0))
    if refused:
        with pytest.raises(ValueError, match="clock runs"):
            agent.step(_obs(10.0 + 0.2 + off, 1))
    else:
        agent.step(_obs(10.0 + 0.2 + off, 1))


def test_the_clock_tolerance_scales_with_dt():
    """dt = 0.02: the tolerance is 1e-6 * 0.02 + 1e-8 = 3e-8 s per tick."""
    ok = Agent(_Places(), params=AgentParams(dt=0.02))
    ok.step(_obs(0.0, 0))
    ok.step(_obs(0.02 + 2.8e-8, 1))
    bad = Agent(_Places(), params=AgentParams(dt=0.02))
    bad.step(_obs(0.0, 0))
    with pytest.raises(ValueError, match=r"clock runs 0\.02 s per tick .* BrainParams\.dt is "
                                         r"0\.02 s"):
        bad.step(_obs(0.02 + 3.2e-8, 1))


@pytest.mark.parametrize("kind", [int, np.int64, np.int32])
def test_integer_ticks_of_any_kind_are_checked(kind):
    agent = Agent(_Places())
    agent.step(_obs(0.0, kind(0)))
    with pytest.raises(ValueError, match=r"clock runs 0\.5 s per tick"):
        agent.step(_obs(0.5, kind(1)))


@pytest.mark.parametrize("tick", [None, 1.0, True, "1"])
def test_a_clock_that_does_not_count_ticks_is_not_checked(tick):
    """Only int and numpy integer ticks are counted (not bool, float, text or none)."""
    agent = Agent(_Places())
    agent.step(_obs(0.0, 0))
    agent.step(_obs(0.7, tick))
    assert agent._last_tick is None
    # ... and the next counted tick has nothing to compare with
    agent.step(_obs(5.0, 2))
    assert agent._last_tick == 2


def test_a_repeated_or_earlier_tick_is_not_checked():
    agent = Agent(_Places())
    agent.step(_obs(1.0, 3))
    agent.step(_obs(1.5, 3))          # the same tick again (no step to divide by)
    agent.step(_obs(2.0, 2))          # an earlier tick: nothing to compare
    assert agent._last_tick == 2
    # the next ticks compare with the last one seen: tick 2 at 2.0 s, tick 4 at 2.4 s
    agent.step(_obs(2.4, 4))
    with pytest.raises(ValueError, match=r"obs\.t 2\.4 at tick 4, 3 at tick 5"):
        agent.step(_obs(3.0, 5))


def test_an_observation_without_a_tick_is_taken_unchecked():
    """The tick is read only if the observation has one (check_observation does not ask for
    it): a duck-typed observation without it runs, its clock unchecked."""
    agent = Agent(_Places())
    agent.step(_obs(0.0, 0))
    bare = SimpleNamespace(t=0.9, ir=np.full(8, 0.1), floor=0, sound=False,
                           odometry=np.zeros(3), moving=False)
    agent.step(bare)   # type: ignore[arg-type]
    assert agent.brain.t == 0.9 and agent._last_tick is None


def test_a_refused_clock_moves_nothing_so_the_same_observation_is_refused_again():
    """Bug found by this round: the clock check kept the refused observation's time and tick
    before refusing it, so the same observation sent again (a caller that catches the error
    and retries) was compared with itself, a repeated tick, and taken. Ticks 0 and 1 at 0 and
    0.5 s: 0.5 s per tick, refused however often it comes; the brain never sees it."""
    agent = Agent(_Places())
    agent.step(_obs(0.0, 0))
    for _ in range(2):
        with pytest.raises(ValueError, match=r"clock runs 0\.5 s per tick \(obs\.t 0 at tick 0, "
                                             r"0\.5 at tick 1\)"):
            agent.step(_obs(0.5, 1))
        assert agent.brain.t == 0.0 and agent._last_tick == 0 and agent._last_t == 0.0
    agent.step(_obs(0.2, 1))    # the right time for tick 1 is still taken
    assert agent.brain.t == 0.2
