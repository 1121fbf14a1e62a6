"""The motor layer (:mod:`hippo.motor`) on synthetic observations and ticks: which controller
acts for each decision, when a stalled move hands over to the wall follower and for how long,
and when a move that takes too long is given up.

The two followers are replaced by stubs that answer with their own name, so each test reads
which controller the motor layer chose; the stall and give-up clocks are the motor's own. All
times are multiples of dt = 0.25 s, exact in binary, so the boundaries are tested exactly.
"""

import math

import numpy as np
import pytest

from hippo.motor import Motor, MotorCommand, MotorParams
from hippo.ticks import Tick
from hippo.types import Mode, Observation

DT = 0.25
CLEAR, PRESSED = np.ones(8), np.zeros(8)   # ir: nothing in range; touching all round
EXPLORE, STEER = (1.0, 1.0), (2.0, 2.0)     # the stubs' wheels


class _Explorer:
    def act(self, obs):
        return EXPLORE


class _Steer:
    def __init__(self):
        self.calls = []

    def act(self, obs, heading, target):
        self.calls.append((heading, target))
        return STEER


def motor(**params) -> Motor:
    m = Motor(MotorParams(**params), dt=DT)
    m.explorer, m.steer = _Explorer(), _Steer()
    return m


def obs(t: float, odometry=(1.0, 0.0, 0.0), ir=CLEAR) -> Observation:
    """An observation at ``t`` after a tick that moved the robot by ``odometry``."""
    return Observation(t, round(t / DT), ir, 0, False, np.array(odometry, float), True)


def tick(t: float, mode=Mode.MOVE, target: float | None = 0.5, since: float = 0.0,
         limit: float | None = 100.0, settling: bool = False) -> Tick:
    return Tick(t, 0, False, mode, None, target, 0.25, since, limit, settling, ())


STILL = (0.0, 0.0, 0.0)


def test_each_decision_has_its_controller():
    m = motor()
    assert m.act(obs(1.0), tick(1.0, Mode.WAIT)) == MotorCommand(0.0, 0.0)
    assert m.act(obs(1.0), tick(1.0, Mode.EXPLORE)).wheels == EXPLORE
    for mode in (Mode.MOVE, Mode.APPROACH):
        cmd = m.act(obs(1.0), tick(1.0, mode, target=0.5))
        assert cmd.wheels == STEER and not cmd.gave_up
    assert m.steer.calls[-1] == (0.25, 0.5)      # from the brain's heading to the move's
    # a move without a heading (lost) explores
    assert m.act(obs(1.0), tick(1.0, Mode.MOVE, target=None)).wheels == EXPLORE
    # boxed in (every forward ray touching), a move stands still
    assert m.act(obs(1.0, ir=PRESSED), tick(1.0, Mode.MOVE)) == MotorCommand(0.0, 0.0)
    assert m.boxed_in(obs(1.0, ir=PRESSED)) and not m.boxed_in(obs(1.0))
    # a settling robot (just lifted) explores whatever the decision, boxed in or not
    for mode in (Mode.WAIT, Mode.MOVE, Mode.APPROACH):
        assert m.act(obs(1.0, ir=PRESSED), tick(1.0, mode, settling=True)).wheels == EXPLORE


def test_a_stall_of_exactly_stall_time_hands_over_to_the_wall_follower_for_unstick_time():
    """stall_time = 1 s is 4 ticks of 0.25 s: the first three still steer, the fourth follows
    the wall, and the wall follower keeps the robot until exactly unstick_time = 4 s later."""
    m = motor(stall_time=1.0, unstick_time=4.0)
    for k in range(1, 4):
        assert m.act(obs(k * DT, STILL), tick(k * DT)).wheels == STEER
    assert m.act(obs(1.0, STILL), tick(1.0)).wheels == EXPLORE    # stalled for 1 s
    for k in range(5, 20):                                          # moving again, unsticking
        cmd = m.act(obs(k * DT), tick(k * DT))
        assert cmd.wheels == EXPLORE and not cmd.gave_up
    assert m.act(obs(5.0), tick(5.0)).wheels == STEER               # 1 + 4 s: steers again


def test_the_stall_count_restarts_after_a_hand_over_and_after_moving():
    m = motor(stall_time=1.0, unstick_time=4.0)
    # three stalled ticks, one moving, three stalled: never 1 s stalled in a row
    for k, odo in enumerate([STILL] * 3 + [(1.0, 0.0, 0.0)] + [STILL] * 3, start=1):
        assert m.act(obs(k * DT, odo), tick(k * DT)).wheels == STEER
    # stalled 1 s (hand-over at t = 3 s, to t = 7 s), then 3 more stalled ticks (0.75 s: no
    # second hand-over), then moving: the robot steers again exactly at 7 s
    for k in range(8, 12):
        m.act(obs(k * DT, STILL), tick(k * DT))
    for k in range(12, 15):
        assert m.act(obs(k * DT, STILL), tick(k * DT)).wheels == EXPLORE
    for k in range(15, 28):
        assert m.act(obs(k * DT), tick(k * DT)).wheels == EXPLORE
    assert m.act(obs(7.0), tick(7.0)).wheels == STEER


@pytest.mark.parametrize(("odometry", "stalled"), [
    ((0.0, 0.0, 1.0), True),                 # turning on the spot: dθ is no speed
    ((0.09375, 0.125, 0.0), False),          # 0.15625 cm in 0.25 s: 0.625 cm/s (3-4-5)
    ((0.09375, 0.0, 0.0), True),             # its forward part alone: 0.375 cm/s
    ((0.0, 0.125, 0.0), True),               # its sideways part alone: 0.5 cm/s
    ((0.0, -0.15, 0.0), False),              # 0.6 cm/s exactly: not under stall_speed
])
def test_own_speed_is_the_odometry_distance_over_dt(odometry, stalled):
    """stall_speed = 0.6 cm/s; the own speed is |(dx, dy)| / dt, whatever the direction."""
    m = motor(stall_speed=0.6, stall_time=DT)       # one tick under stall_speed hands over
    assert m.act(obs(1.0, odometry), tick(1.0)).wheels == (EXPLORE if stalled else STEER)


def test_zero_stall_time_and_zero_unstick_time():
    # stall_time 0: every tick counts as stalled for long enough, even moving; with
    # unstick_time 0 the hand-over lasts no time and the move steers
    m = motor(stall_time=0.0, unstick_time=0.0)
    assert m.act(obs(1.0, STILL), tick(1.0)).wheels == STEER
    m = motor(stall_time=0.0, unstick_time=1.0)
    assert m.act(obs(1.0), tick(1.0)).wheels == EXPLORE


def test_a_move_past_its_limit_is_given_up_exactly_then():
    """A move chosen at 10 s with a 5 s limit steers up to 15 s and is given up after it (the
    robot explores); a stall hand-over past the limit still only unsticks."""
    m = motor()
    for t in (10.0, 12.5, 15.0):
        cmd = m.act(obs(t), tick(t, since=10.0, limit=5.0))
        assert cmd.wheels == STEER and not cmd.gave_up
    cmd = m.act(obs(15.25), tick(15.25, since=10.0, limit=5.0))
    assert cmd == MotorCommand(*EXPLORE, gave_up=True)
    # an approach is given up the same way
    cmd = m.act(obs(15.25), tick(15.25, Mode.APPROACH, since=10.0, limit=5.0))
    assert cmd.gave_up
    # waiting, exploring, boxed in or settling never gives up
    for mode in (Mode.WAIT, Mode.EXPLORE):
        assert not m.act(obs(20.0), tick(20.0, mode, since=10.0, limit=5.0)).gave_up
    assert not m.act(obs(20.0, ir=PRESSED), tick(20.0, since=10.0, limit=5.0)).gave_up
    assert not m.act(obs(20.0), tick(20.0, since=10.0, limit=5.0, settling=True)).gave_up
    m = motor(stall_time=DT)
    cmd = m.act(obs(20.0, STILL), tick(20.0, since=10.0, limit=5.0))
    assert cmd == MotorCommand(*EXPLORE, gave_up=False)


def test_motor_command_defaults_to_not_given_up():
    cmd = MotorCommand(1.5, -2.0)
    assert cmd.wheels == (1.5, -2.0) and cmd.gave_up is False


def test_the_move_speed_and_the_followers_seeds_reach_the_controllers():
    """A move straight along its heading in the open goes at MotorParams.speed; the two
    followers' speed drift follows their own seeds (same seed, same wheels)."""
    m = Motor(MotorParams(speed=3.0), dt=DT)
    assert m.act(obs(1.0), tick(1.0, target=0.25)).wheels == pytest.approx((3.0, 3.0))

    def explore(seed: int) -> list[tuple[float, float]]:
        m = Motor(dt=DT, rng_explore=seed)
        return [m.act(obs(k * DT), tick(k * DT, Mode.EXPLORE)).wheels for k in range(20)]

    def steer(seed: int) -> list[tuple[float, float]]:
        # a wall on the followed (right) side and the heading within tolerance: the steering
        # follower (with its own speed drift) drives
        m = Motor(dt=DT, rng_steer=seed)
        ir = CLEAR.copy()
        ir[2] = 1 / 26            # a wall 5 cm to the right (-90°): the follower's target
        return [m.act(obs(k * DT, ir=ir), tick(k * DT, target=0.25)).wheels for k in range(20)]

    for run in (explore, steer):
        assert run(3) == run(3) and run(3) != run(4)
        assert not any(math.isnan(v) for w in run(3) for v in w)


@pytest.mark.parametrize(("field", "value"), [
    ("speed", 0.0), ("speed", -1.0), ("stall_speed", -0.5), ("stall_time", -1.0),
    ("unstick_time", -1.0), ("wall_tolerance", 0.0), ("wall_side", 0), ("explore_rho", 1.5),
])
def test_bad_motor_params_are_refused_naming_the_field(field, value):
    with pytest.raises(ValueError, match=rf"^{field} must"):
        MotorParams(**{field: value})
    with pytest.raises(ValueError, match=r"^dt must"):
        Motor(dt=0.0)


def test_the_default_motor_ticks_at_the_worlds_step():
    """Motor's default dt is the World's 0.2 s: with the default stall_time (1 s) a stalled
    move steers for four ticks and hands over on the fifth."""
    m = Motor()
    m.explorer, m.steer = _Explorer(), _Steer()
    wheels = [m.act(obs(k * 0.2, STILL), tick(k * 0.2)).wheels for k in range(1, 6)]
    assert wheels == [STEER] * 4 + [EXPLORE]


def test_zero_stall_speed_stall_time_and_unstick_time_are_allowed():
    p = MotorParams(stall_speed=0.0, stall_time=0.0, unstick_time=0.0, wall_side=1)
    assert (p.stall_speed, p.stall_time, p.unstick_time, p.wall_side) == (0.0, 0.0, 0.0, 1)
