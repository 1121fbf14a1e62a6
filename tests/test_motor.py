"""The motor layer: a stalled move gets free along the blocking wall the way nearer its heading."""

import math

import numpy as np
import pytest

from hippo.motor import Motor, MotorParams
from hippo.sim import ArenaBuilder, World
from hippo.ticks import Tick
from hippo.types import Mode, Observation, wrap_angle

# a box 100 x 60 cm; the robot at (50, 50) has the north wall 6.3 cm from its body
BOX = ArenaBuilder("box", 100, 60).outer_walls().start(50, 50, math.pi / 2).build()


@pytest.mark.parametrize("heading_deg", [20, 60, 90, 120, 160])
@pytest.mark.parametrize("target_deg", [0, 30, 60, 120, 150, 180, -150])
def test_unstick_way_runs_along_the_wall_the_way_nearer_the_moves_heading(heading_deg,
                                                                                target_deg):
    world = World(BOX, seed=0)
    heading, target = math.radians(heading_deg), math.radians(target_deg)
    world.reset(0, pose=(50, 50, heading))
    motor, obs = Motor(), world.observe()
    along, side = motor.unstick_way(obs, heading, target)
    # the north wall's normal is 90°: east (0°) is nearer a target with cos > 0, else west;
    # the nearest ray gives the normal to within half the gap between rays (about 25°)
    east = math.cos(target) > 0
    assert abs(wrap_angle(along - (0.0 if east else math.pi))) < math.radians(25)
    # going east the wall is on the robot's left (side +1), going west on its right
    assert side == (1 if east else -1)
    # the answer is relative: the same pose in a frame turned by 1 rad turns it by 1 rad
    turned, _ = motor.unstick_way(obs, heading + 1.0, target + 1.0)
    assert wrap_angle(turned - along - 1.0) == pytest.approx(0.0, abs=1e-9)


def _after_the_first_stall(heading_deg: float, target_deg: float, wall_side: int) -> float:
    """A move from (50, 50) with heading ``target``: x travelled in the 4 s after it stalls."""
    world = World(BOX, seed=0)
    obs = world.reset(0, pose=(50, 50, math.radians(heading_deg)))
    motor = Motor(MotorParams(wall_side=wall_side), dt=world.dt)
    target, x0, stalled_at = math.radians(target_deg), None, None
    for k in range(60):
        tick = Tick(obs.t, 0, False, Mode.MOVE, None, target, world.truth.pose[2], 0.0, 1e9,
                    False, ())
        before = motor._unstick_until
        obs = world.step(motor.act(obs, tick).wheels)
        if stalled_at is None and motor._unstick_until != before:
            stalled_at, x0 = k, world.truth.pose[0]
        if stalled_at is not None and k == stalled_at + 20:
            return world.truth.pose[0] - x0
    raise AssertionError("the move never stalled")


@pytest.mark.parametrize(("heading_deg", "target_deg", "wall_side"),
                         [(90, 40, -1), (90, 40, 1), (90, 140, 1), (110, 110, 1), (70, 70, -1)])
def test_a_stalled_move_gets_free_along_the_wall_toward_its_heading(heading_deg, target_deg,
                                                                    wall_side):
    """Whichever side the explorer follows: that side alone used to pick the way (seed 14 of
    the goal-arena patrol ran its tour backwards after one such stall)."""
    dx = _after_the_first_stall(heading_deg, target_deg, wall_side)
    assert dx * math.cos(math.radians(target_deg)) > 0 and abs(dx) > 5.0


def test_a_move_head_on_into_the_wall_gets_free_the_way_the_robot_was_going():
    """With the move's heading straight at the wall (no way nearer it), the robot's recent
    direction of travel decides: it continues its tour (seed 10 of the goal-arena patrol went
    back round after a head-on stall against the outer wall)."""
    world = World(BOX, seed=0)
    heading = math.radians(90)
    obs = world.reset(0, pose=(50, 50, heading))
    motor = Motor()
    g = motor.explorer.geom
    normal = float(g.angles[int(np.argmin(g.distances(obs.ir)))])
    at_the_wall = heading + normal
    east, side = motor.unstick_way(obs, heading, at_the_wall, travel=math.radians(20))
    assert abs(wrap_angle(east)) < math.radians(25) and side == 1
    west, side = motor.unstick_way(obs, heading, at_the_wall, travel=math.radians(160))
    assert abs(wrap_angle(west - math.pi)) < math.radians(25) and side == -1
    # the sum of the two sines decides: a move's heading well east of the normal outweighs
    # a travel just west of it, and the other way round
    east, _ = motor.unstick_way(obs, heading, at_the_wall - 1.0, travel=at_the_wall + 0.3)
    assert abs(wrap_angle(east)) < math.radians(25)
    west, _ = motor.unstick_way(obs, heading, at_the_wall - 0.3, travel=at_the_wall + 1.0)
    assert abs(wrap_angle(west - math.pi)) < math.radians(25)


def test_the_travel_memory_follows_the_last_20_cm_and_ignores_turning_on_the_spot():
    motor = Motor()
    assert motor.travel is None

    def tick(heading: float) -> Tick:
        return Tick(0.0, 0, False, Mode.WAIT, None, None, heading, 0.0, None, False, ())

    def go(dx: float, dy: float, dtheta: float, heading: float) -> None:
        motor.act(Observation(0.0, 0, np.ones(8), 0, False, np.array([dx, dy, dtheta]), False),
                  tick(heading))

    for _ in range(30):            # 30 cm east, facing east
        go(1.0, 0.0, 0.0, 0.0)
    assert motor.travel == pytest.approx(0.0, abs=1e-9)
    go(0.0, 0.0, math.pi / 2, math.pi / 2)   # a turn on the spot leaves it alone
    assert motor.travel == pytest.approx(0.0, abs=1e-9)
    for _ in range(10):            # 10 cm north: the memory turns, 10 cm short of forgetting
        go(1.0, 0.0, 0.0, math.pi / 2)
    assert 0.2 < motor.travel < math.pi / 2 - 0.2
    for _ in range(90):            # 90 more: east is forgotten (it fades by e every 20 cm)
        go(1.0, 0.0, 0.0, math.pi / 2)
    assert motor.travel == pytest.approx(math.pi / 2, abs=0.01)
    # odometry is in the robot's frame at the start of the tick: sideways slip counts too
    for _ in range(100):
        go(0.0, -1.0, 0.0, 0.0)    # facing east, slipping south
    assert motor.travel == pytest.approx(-math.pi / 2, abs=0.01)




def test_unstick_way_refuses_a_heading_that_is_not_a_number():
    world = World(BOX, seed=0)
    obs = world.reset(0, pose=(50, 50, 1.0))
    motor = Motor()
    for bad in (math.nan, math.inf, "north", None):
        with pytest.raises(ValueError, match="heading must be"):
            motor.unstick_way(obs, bad, 0.0)
        with pytest.raises(ValueError, match="target must be"):
            motor.unstick_way(obs, 0.0, bad)
    with pytest.raises(ValueError, match="travel must be finite"):
        motor.unstick_way(obs, 0.0, 0.0, travel=math.nan)


def test_the_turn_to_get_free_is_bounded_when_the_heading_estimate_does_not_follow():
    """The turn on the spot ends at the unstick heading or after half a turn's time: a heading
    estimate that does not move (a robot held, odometry lost) cannot hold it there for good."""
    motor = Motor()
    ir = np.full(8, 0.9)
    ir[0] = 0.05                  # a wall ahead, just right of the nose
    still = np.zeros(3)
    runs, run, t = [], 0, 0.0     # lengths of the runs of turning-on-the-spot commands
    freed = False
    for _ in range(200):
        obs = Observation(t, 0, ir, 0, False, still, False)
        tick = Tick(t, 0, False, Mode.MOVE, None, 1.2, 0.0, 0.0, 1e9, False, ())
        left, right = motor.act(obs, tick).wheels
        if left == -right != 0.0:
            run += 1
        elif run:
            runs.append(run)
            run = 0
        freed |= bool(runs) and t >= motor._unstick_until   # a stall's window came to an end
        t = round(t + 0.2, 9)
    # stalled after 1 s, each stall turns for at most pi / (1.5 rad/s) + 3 ticks, then the
    # unstick window (4 s) runs out and the move steers again, until it stalls again
    assert len(runs) >= 3 and max(runs) == int(math.pi / (1.5 * 0.2)) + 3 and freed
