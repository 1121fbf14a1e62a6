"""The low-level controllers' rules on hand-set sensor readings.

The readings come from a sensor model with the e-puck's eight ray angles and a 4-36 cm range,
so that a reading r is the distance d = 4 + 32 r cm exactly in binary (every distance below is
a multiple of 1/32 cm). Each expected wheel speed is worked out by hand from the module's
equations (the working is in the comments) and the drive's inverse

    half = omega * axle / 2 (capped at speed_max),   v capped at speed_max - |half|,
    (left, right) = (v - half, v + half)

with the e-puck's axle of 5.3 cm; nothing is copied from a run of the code. Rays of the e-puck,
by index: 0: -17°, 1: -46°, 2: -90°, 3: -152°, 4: 152°, 5: 90°, 6: 46°, 7: 17°.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from hippo.sim.controllers import (
    AvoidanceParams,
    GoToHeading,
    ObstacleAvoidance,
    Stop,
    WallFollower,
    WallFollowerParams,
    WallGuidedHeading,
    _SensorGeometry,
)
from hippo.sim.robot import IR8, RobotParams, SensorModel
from hippo.types import Observation

M = SensorModel("m8", IR8.angles_deg, 4.0, 36.0, 0.0)
AXLE = 5.3
# a wall follower that keeps 1 cm/s, never switches side and draws nothing
STEADY = WallFollowerParams(rho=0.0, speed_drift=0.0, speed_min=1.0, speed_max=1.0)
# a robot fast enough that no wheel is capped in the go-to-heading cases
FAST = RobotParams(speed_max=20.0)


def refused(message: str):
    return pytest.raises(ValueError, match="^" + re.escape(message) + "$")


def obs(readings) -> Observation:
    return Observation(0.0, 0, readings, 0, False, np.zeros(3), False)


def seen(model: SensorModel = M, **near: float) -> Observation:
    """Every ray clear (reading 1) but the rays named r<i>, which see an obstacle d cm away."""
    ir = np.ones(model.n)
    for key, d in near.items():
        ir[int(key[1:])] = (d - model.range_min) / (model.range_max - model.range_min)
    return obs(ir)


def wheels(v: float, half: float) -> tuple[float, float]:
    return (v - half, v + half)


def close(got: tuple[float, float], want: tuple[float, float]) -> None:
    assert got == pytest.approx(want, rel=1e-12, abs=1e-12)


def follower(side: int = -1, params: WallFollowerParams = STEADY, **kw) -> WallFollower:
    return WallFollower(params, sensors=M, side=side, **kw)


# -- the sensor geometry --------------------------------------------------------------------

EDGES = (0, 5, -5, 6, -6, 25, -25, 26, -26, 30, -30, 31, -31, 60, -60, 61, -61, 65, -65, 64,
         -64, 90, -90, 120, -120, 121, -121, 180)


def test_ray_groups_include_their_edges_and_leave_the_next_degree_out():
    g = _SensorGeometry(SensorModel("edges", tuple(float(a) for a in EDGES)), RobotParams())

    def rays(mask):
        return sorted(EDGES[i] for i in np.flatnonzero(mask))

    # front |a| <= 30; front-left 5 < a <= 60; front-right -60 <= a < -5
    assert rays(g.front) == sorted([0, 5, -5, 6, -6, 25, -25, 26, -26, 30, -30])
    assert rays(g.front_left) == [6, 25, 26, 30, 31, 60]
    assert rays(g.front_right) == [-60, -31, -30, -26, -25, -6]
    # left 30 <= a <= 120; right -120 <= a <= -30
    assert rays(g.left) == [30, 31, 60, 61, 64, 65, 90, 120]
    assert rays(g.right) == [-120, -90, -65, -64, -61, -60, -31, -30]
    # diagonals 25 < |a| < 65
    assert rays(g.diag_left) == [26, 30, 31, 60, 61, 64]
    assert rays(g.diag_right) == [-64, -61, -60, -31, -30, -26]
    # the rays closest to perpendicular: 90 and -90
    assert (EDGES[g.perp_left], EDGES[g.perp_right]) == (90, -90)
    np.testing.assert_array_equal(g.angles, np.deg2rad(np.array(EDGES, float)))


def test_e_puck_groups():
    g = _SensorGeometry("ir8", RobotParams())
    assert g.model is IR8
    assert np.flatnonzero(g.front).tolist() == [0, 7]
    assert np.flatnonzero(g.front_left).tolist() == [6, 7]
    assert np.flatnonzero(g.front_right).tolist() == [0, 1]
    assert (g.perp_left, g.perp_right) == (5, 2)
    assert np.flatnonzero(g.diag_left).tolist() == [6]
    assert np.flatnonzero(g.diag_right).tolist() == [1]


def test_distances_side_diagonal_and_in_range():
    robot = RobotParams()
    g = _SensorGeometry(M, robot)
    assert g.robot is robot
    # d = 4 + 32 r
    np.testing.assert_array_equal(g.distances([0.0, 0.5, 1.0, 0.25]), [4.0, 20.0, 36.0, 12.0])
    d = np.array([10.0, 11.0, 12.0, 13.0, 14.0, 15.0, 16.0, 17.0])
    assert g.side_distance(d, 1) == 15.0 and g.side_distance(d, -1) == 12.0
    assert g.diagonal_distance(d, 1) == 16.0 and g.diagonal_distance(d, -1) == 11.0
    # no diagonal rays: nothing seen there
    g2 = _SensorGeometry(SensorModel("lr", (90.0, -90.0), 4.0, 36.0), robot)
    assert g2.diagonal_distance(np.array([5.0, 5.0]), 1) == math.inf
    assert g2.diagonal_distance(np.array([5.0, 5.0]), -1) == math.inf
    # in range: closer than range_max - 0.5 = 35.5 on a ray of the mask
    far = np.full(8, 35.5)
    assert not g.in_range(far, g.left)
    near = far.copy()
    near[5] = 35.46875
    assert g.in_range(near, g.left) and not g.in_range(near, g.right)


# -- WallFollowerParams and the wall follower's set-up --------------------------------------

def test_wall_follower_params_defaults_and_refusals():
    p = WallFollowerParams()
    assert (p.rho, p.target, p.gain, p.front_slow, p.front_stop, p.search_radius) == (
        0.008, 5.0, 0.12, 12.0, 4.5, 10.0)
    assert (p.speed_min, p.speed_max, p.speed_drift) == (2.5, 5.08, 0.15)
    assert WallFollowerParams(rho=0.0).rho == 0.0 and WallFollowerParams(rho=1.0).rho == 1.0
    with refused("rho must lie in [0.0, 1.0], got 1.0001"):
        WallFollowerParams(rho=1.0001)
    with refused("rho must lie in [0.0, 1.0], got -0.0001"):
        WallFollowerParams(rho=-0.0001)
    assert WallFollowerParams(speed_min=3.0, speed_max=3.0).speed_min == 3.0  # equal: allowed
    for lo, hi in ((0.0, 1.0), (-1.0, 1.0), (3.0, 2.9)):
        with refused("WallFollowerParams needs 0 < speed_min <= speed_max"):
            WallFollowerParams(speed_min=lo, speed_max=hi)


def test_wall_follower_set_up():
    f = WallFollower()
    assert f.params == WallFollowerParams() and f.geom.model is IR8
    assert f.geom.robot == RobotParams()
    assert (f.side, f.speed, f.switches) == (-1, 5.08, 0)
    # the default generator is seeded with 0
    assert f.rng.random() == np.random.default_rng(0).random()
    robot = RobotParams(axle=4.0)
    g = WallFollower(STEADY, sensors=M, robot=robot, rng=7, side=1)
    assert (g.side, g.speed, g.geom.model, g.geom.robot) == (1, 1.0, M, robot)
    assert g.rng.random() == np.random.default_rng(7).random()
    for side in (0, 2, -2, True, 1.0):   # True == 1 and 1.0 == 1, but neither is a side
        with refused(f"side must be -1 (right wall) or +1 (left wall), got {side!r}"):
            WallFollower(side=side)
    w = WallFollower(side=np.int64(-1))
    assert w.side == -1 and type(w.side) is int


class Script:
    """A stand-in generator that plays given draws and logs which were asked for."""

    def __init__(self, uniform=(), normal=()) -> None:
        self.uniform, self.normal, self.calls = list(uniform), list(normal), []

    def random(self) -> float:
        self.calls.append("random")
        return self.uniform.pop(0)

    def standard_normal(self) -> float:
        self.calls.append("normal")
        return self.normal.pop(0)


def test_side_switches_exactly_below_rho_and_draws_nothing_at_rho_zero():
    f = follower(params=WallFollowerParams(rho=0.25, speed_drift=0.0, speed_min=1.0,
                                           speed_max=1.0))
    f.rng = Script(uniform=[0.25, 0.2499, 0.9, 0.0])
    clear = seen()
    # searching for a wall: omega = side * v / search_radius = side * 0.1
    close(f.act(clear), wheels(1.0, -0.1 * AXLE / 2))  # 0.25 is not < 0.25: no switch
    assert (f.side, f.switches) == (-1, 0)
    close(f.act(clear), wheels(1.0, 0.1 * AXLE / 2))  # 0.2499 < 0.25: now following the left
    assert (f.side, f.switches) == (1, 1)
    f.act(clear)
    f.act(clear)  # 0.0 < 0.25: back to the right
    assert (f.side, f.switches) == (-1, 2)
    assert f.rng.calls == ["random"] * 4  # no speed drift: no normal draw
    g = follower()  # rho = 0 and no drift: the generator is never asked
    g.rng = Script()
    g.act(clear)
    assert g.rng.calls == []


def test_rho_one_switches_every_tick():
    f = follower(params=WallFollowerParams(rho=1.0, speed_drift=0.0), rng=3)
    sides = []
    for _ in range(4):
        f.act(seen())
        sides.append(f.side)
    assert sides == [1, -1, 1, -1] and f.switches == 4


def test_speed_drift_is_a_clipped_relative_random_walk():
    p = WallFollowerParams(rho=0.0, speed_drift=0.5, speed_min=1.0, speed_max=4.0)
    f = follower(params=p)
    f.rng = Script(normal=[-0.5, -2.0, 10.0, 0.25])
    clear = seen()
    # 4 * (1 + 0.5 * -0.5) = 3; searching: omega = -v / 10
    close(f.act(clear), wheels(3.0, -0.3 * AXLE / 2))
    assert f.speed == 3.0
    f.act(clear)  # 3 * (1 - 1) = 0, clipped up to speed_min 1
    assert f.speed == 1.0
    f.act(clear)  # 1 * (1 + 5) = 6, clipped down to speed_max 4
    assert f.speed == 4.0
    f.act(clear)  # 4 * 1.125 = 4.5 -> 4
    assert f.speed == 4.0
    assert f.rng.calls == ["normal"] * 4  # rho = 0: no uniform draw
    # with both: the switch is drawn before the speed
    q = follower(params=WallFollowerParams(rho=0.5, speed_drift=0.5, speed_min=1.0,
                                           speed_max=4.0))
    q.rng = Script(uniform=[0.9], normal=[0.0])
    q.act(clear)
    assert q.rng.calls == ["random", "normal"] and q.speed == 4.0


# -- the wall follower's rules (v = 1 cm/s, side -1 = the right wall unless said) -------------

def test_wall_ahead_closer_than_front_stop_turns_in_place():
    # front 4.4375 < 4.5: omega = -side * 1.5, v = 0; half = 1.5 * 5.3 / 2 = 3.975
    close(follower(-1).act(seen(r0=4.4375)), (-3.975, 3.975))
    close(follower(1).act(seen(r7=4.4375)), (3.975, -3.975))
    close(follower(-1).act(seen(r7=4.0)), (-3.975, 3.975))


def test_wall_ahead_between_front_stop_and_front_slow_slows_and_turns():
    # front exactly 4.5: k = (12 - 4.5) / 7.5 = 1; v = 1 * (1 - 0.7) = 0.3;
    # omega = 0.6 + 1.2 = 1.8, half = 1.8 * 5.3 / 2 = 4.77
    close(follower(-1).act(seen(r0=4.5)), wheels(0.3, 4.77))
    # front 8.25: k = 3.75 / 7.5 = 0.5; v = 1 - 0.35 = 0.65; omega = 0.6 + 0.6 = 1.2, half 3.18
    close(follower(-1).act(seen(r7=8.25)), wheels(0.65, 3.18))
    close(follower(1).act(seen(r0=8.25)), wheels(0.65, -3.18))
    # front 11.875, 1/32 cm below front_slow: k = 0.125 / 7.5 = 1/60;
    # v = 1 - 0.7/60, omega = 0.6 + 1.2/60 = 0.62, half = 0.62 * 5.3 / 2 = 1.643
    close(follower(-1).act(seen(r0=11.875)), wheels(1 - 0.7 / 60, 1.643))


def test_wall_ahead_at_front_slow_is_ignored():
    # front exactly 12: not < 12, so the follower searches: omega = -1 / 10, half = -0.265
    close(follower(-1).act(seen(r0=12.0)), wheels(1.0, -0.265))


def test_following_keeps_the_target_gap():
    # gap 7 on the right: omega = -1 * 0.12 * (7 - 5) = -0.24, half = -0.636
    close(follower(-1).act(seen(r2=7.0)), wheels(1.0, -0.636))
    # on the left (ray 5): omega = +0.24
    close(follower(1).act(seen(r5=7.0)), wheels(1.0, 0.636))
    # a wall on the other side only: still searching, omega = +1 / 10 for the left
    close(follower(1).act(seen(r2=7.0)), wheels(1.0, 0.265))
    # closer than the target: gap 4: omega = -0.12 * (4 - 5) = 0.12, half = 0.318
    close(follower(-1).act(seen(r2=4.0)), wheels(1.0, 0.318))


def test_a_wall_closing_in_on_the_diagonal_turns_away():
    # diagonal 7 < 1.6 * 5 = 8: omega = -0.24 - (-1) * 0.12 * (8 - 7) = -0.12, half = -0.318
    close(follower(-1).act(seen(r2=7.0, r1=7.0)), wheels(1.0, -0.318))
    close(follower(1).act(seen(r5=7.0, r6=7.0)), wheels(1.0, 0.318))
    # diagonal exactly 8: no correction
    close(follower(-1).act(seen(r2=7.0, r1=8.0)), wheels(1.0, -0.636))
    # 1/32 cm closer: omega = -0.24 + 0.12 / 32 = -0.23625
    close(follower(-1).act(seen(r2=7.0, r1=7.96875)), wheels(1.0, -0.23625 * AXLE / 2))
    # a diagonal beyond 8 (here 10) is not a wall closing in: no correction either way
    close(follower(-1).act(seen(r2=7.0, r1=10.0)), wheels(1.0, -0.636))
    # the other side's diagonal is not read
    close(follower(-1).act(seen(r2=7.0, r6=5.0)), wheels(1.0, -0.636))


def test_turn_rate_is_capped_at_1_2():
    # gap 30: omega = -0.12 * 25 = -3, capped at -1.2: half = -3.18
    close(follower(-1).act(seen(r2=30.0)), wheels(1.0, -3.18))
    close(follower(1).act(seen(r5=30.0)), wheels(1.0, 3.18))
    # target 20, gap 4: omega = -0.12 * (4 - 20) = 1.92, capped at 1.2
    p = WallFollowerParams(rho=0.0, speed_drift=0.0, speed_min=1.0, speed_max=1.0, target=20.0)
    close(follower(-1, params=p).act(seen(r2=4.0, r1=36.0)), wheels(1.0, 3.18))


def test_wall_in_range_below_range_max_minus_1():
    # gap exactly 35 = range_max - 1: no wall, search (omega = -0.1)
    close(follower(-1).act(seen(r2=35.0)), wheels(1.0, -0.265))
    # 1/16 cm closer: a wall; omega = -0.12 * 29.9375, capped at -1.2
    close(follower(-1).act(seen(r2=34.9375)), wheels(1.0, -3.18))


def test_search_radius_and_params_are_used():
    p = WallFollowerParams(rho=0.0, speed_drift=0.0, speed_min=2.0, speed_max=2.0,
                           search_radius=4.0, gain=0.5, target=6.0)
    # searching: omega = -2 / 4 = -0.5, half = -1.325
    close(follower(-1, params=p).act(seen()), wheels(2.0, -1.325))
    # gap 7: omega = -0.5 * (7 - 6) = -0.5
    close(follower(-1, params=p).act(seen(r2=7.0)), wheels(2.0, -1.325))
    q = WallFollowerParams(rho=0.0, speed_drift=0.0, speed_min=1.0, speed_max=1.0,
                           front_slow=20.0, front_stop=10.0)
    # front 15: k = (20 - 15) / 10 = 0.5 -> v 0.65, omega 1.2
    close(follower(-1, params=q).act(seen(r0=15.0)), wheels(0.65, 3.18))
    close(follower(-1, params=q).act(seen(r0=9.0)), (-3.975, 3.975))


def test_no_front_and_no_diagonal_rays():
    model = SensorModel("lr", (90.0, -90.0), 4.0, 36.0, 0.0)
    f = WallFollower(STEADY, sensors=model, side=-1)
    # nothing ahead and no diagonal: only the gap 7 counts
    close(f.act(seen(model, r1=7.0)), wheels(1.0, -0.636))
    close(f.act(seen(model, r1=4.0)), wheels(1.0, 0.318))


# -- obstacle avoidance ---------------------------------------------------------------------

def avoid(params: AvoidanceParams | None = None, model: SensorModel = M, **kw):
    return ObstacleAvoidance(params, sensors=model, **kw)


def test_avoidance_set_up():
    p = AvoidanceParams()
    assert (p.slow, p.stop, p.turn_gain) == (10.0, 1.5, 1.6)
    a = ObstacleAvoidance()
    assert a.params == p and a.geom.model is IR8 and a.geom.robot == RobotParams()
    assert a.speed == 5.08 and a._turn == 0.0
    assert a._forward == [0, 1, 2, 5, 6, 7]  # within ±100°: not the two rear rays
    robot = RobotParams(speed_max=3.0)
    assert avoid(robot=robot).speed == 3.0 and avoid(robot=robot).geom.robot is robot
    assert avoid(speed=0.0).speed == 0.0 and avoid(speed=2.0).speed == 2.0
    edge = SensorModel("e", (100.0, -100.0, 100.5, -100.5, 180.0))
    assert avoid(model=edge)._forward == [0, 1]


def test_boxed_in_when_every_forward_ray_is_within_range_min_plus_stop():
    a = avoid()
    # range_min + stop = 5.5 cm on all six forward rays; the rear rays see nothing
    box = {f"r{i}": 5.5 for i in (0, 1, 2, 5, 6, 7)}
    assert a.boxed_in(seen(**box))
    assert avoid().boxed_in(seen(**{k: 4.0 for k in box}))
    for i in (0, 1, 2, 5, 6, 7):  # one forward ray 1/32 cm further: free
        assert not avoid().boxed_in(seen(**{**box, f"r{i}": 5.53125}))
    assert not avoid().boxed_in(seen(r3=4.0, r4=4.0))
    # a larger stop: 4 + 3 = 7
    assert avoid(AvoidanceParams(stop=3.0)).boxed_in(seen(**{k: 7.0 for k in box}))
    assert not avoid(AvoidanceParams(stop=3.0)).boxed_in(seen(**{k: 7.03125 for k in box}))
    # readings as a tuple are read too
    assert avoid().boxed_in(obs(tuple(seen(**box).ir.tolist())))
    assert not avoid().boxed_in(obs(tuple(np.ones(8).tolist())))


def test_boxed_in_keeps_the_answer_for_the_observation_and_array_asked_last():
    a = avoid()
    ir = seen(**{f"r{i}": 5.5 for i in (0, 1, 2, 5, 6, 7)}).ir
    first = obs(ir)
    assert a.boxed_in(first)
    ir[:] = 1.0  # the same observation and array, changed in place: the kept answer
    assert a.boxed_in(first)
    # another observation around the same array: asked afresh
    assert not a.boxed_in(first.with_ir(ir))
    # the same observation with another array: asked afresh
    b = avoid()
    o = obs(np.ones(8))
    assert not b.boxed_in(o)
    object.__setattr__(o, "ir", np.zeros(8))
    assert b.boxed_in(o)
    assert b.boxed_in(o)  # and kept


def test_modulate_when_boxed_in_or_clear():
    box = seen(**{f"r{i}": 5.0 for i in (0, 1, 2, 5, 6, 7)})
    assert avoid().modulate(3.0, 0.7, box) == (0.0, 0.0)
    a = avoid()
    a._turn = 1.0
    assert a.modulate(3.0, 0.7, seen()) == (3.0, 0.7) and a._turn == 0.0
    # a side obstacle (90°) is not ahead
    assert avoid().modulate(3.0, 0.7, seen(r5=5.0, r2=5.0)) == (3.0, 0.7)


def test_modulate_turns_away_and_slows():
    # front-left 6 (ray 7 at 17°): turn = -1 (more room on the right);
    # k = (10 - 6) / (10 - 5.5) = 8/9; omega = 0.9 / 9 - 1.6 * 8/9 = -11.9 / 9; v = 3 / 9
    a = avoid()
    v, w = a.modulate(3.0, 0.9, seen(r7=6.0))
    assert (v, w) == pytest.approx((1 / 3, -11.9 / 9), rel=1e-12) and a._turn == -1.0
    # the same on the right (ray 0 at -17°): turn +1, omega = 0.1 + 12.8/9
    b = avoid()
    assert b.modulate(3.0, 0.9, seen(r0=6.0)) == pytest.approx((1 / 3, 13.7 / 9), rel=1e-12)
    # the 46° rays count as front-left and front-right
    assert avoid().modulate(3.0, 0.9, seen(r6=6.0)) == pytest.approx((1 / 3, -11.9 / 9))
    assert avoid().modulate(3.0, 0.9, seen(r1=6.0)) == pytest.approx((1 / 3, 13.7 / 9))
    # a tie: fl = fr, turn -1
    assert avoid().modulate(3.0, 0.9, seen(r0=6.0, r7=6.0)) == pytest.approx((1 / 3,
                                                                              -11.9 / 9))


def test_the_turn_is_kept_while_the_obstacle_stays_in_view():
    a = avoid()
    a.modulate(3.0, 0.0, seen(r0=6.0))  # turn +1
    # the obstacle now on the left: the turn stays +1: omega = 1.6 * 8/9
    assert a.modulate(3.0, 0.0, seen(r7=6.0)) == pytest.approx((1 / 3, 12.8 / 9))
    assert a._turn == 1.0
    a.modulate(3.0, 0.0, seen())  # out of view: forgotten
    assert a._turn == 0.0
    assert a.modulate(3.0, 0.0, seen(r7=6.0)) == pytest.approx((1 / 3, -12.8 / 9))


def test_avoidance_weight_on_its_edges():
    # front exactly slow = 10: untouched, and a turn in memory is forgotten
    a = avoid()
    a._turn = 1.0
    assert a.modulate(3.0, 0.9, seen(r7=10.0)) == (3.0, 0.9) and a._turn == 0.0
    # 1/32 cm closer: k = (1/32) / 4.5 = 1/144
    k = 1 / 144
    assert avoid().modulate(3.0, 0.9, seen(r7=9.96875)) == pytest.approx(
        (3.0 * (1 - k), (1 - k) * 0.9 - k * 1.6), rel=1e-12)
    # closer than range_min + stop (but not boxed in): k = 6 / 4.5 clipped to 1
    assert avoid().modulate(3.0, 0.9, seen(r7=4.0)) == pytest.approx((0.0, -1.6), abs=1e-15)
    # exactly range_min + stop = 5.5: k = 1
    assert avoid().modulate(3.0, 0.9, seen(r7=5.5)) == pytest.approx((0.0, -1.6), abs=1e-15)
    # slow at or below stop_at (k's denominator 0 or negative) is refused when built: ir8's
    # minimum range 4 cm + stop 1.5 cm = 5.5 cm
    for slow in (5.5, 5.0):
        with pytest.raises(ValueError, match=re.escape(
                f"AvoidanceParams.slow ({slow:g} cm) must exceed the sensors' minimum range + "
                "stop (5.5 cm): closer obstacles all read the same")):
            avoid(AvoidanceParams(slow=slow))
    assert avoid(AvoidanceParams(slow=5.5 + 1 / 32)).params.slow == 5.53125
    for bad in ({"slow": 0.0}, {"stop": -0.5}, {"turn_gain": -1.0}):
        with pytest.raises(ValueError, match="AvoidanceParams needs slow > 0, stop >= 0"):
            AvoidanceParams(**bad)
    with pytest.raises(ValueError, match="AvoidanceParams"):
        AvoidanceParams(slow=float("nan"))


def test_avoidance_params_are_used():
    p = AvoidanceParams(slow=20.0, stop=0.5, turn_gain=1.0)
    # stop_at = 4.5; front 12 on the left: k = 8 / 15.5; omega = -k; v = 2 (1 - k)
    k = 8 / 15.5
    assert avoid(p).modulate(2.0, 0.0, seen(r7=12.0)) == pytest.approx((2 * (1 - k), -k))


def test_a_ray_straight_ahead_and_no_forward_rays():
    ahead = SensorModel("ahead", (0.0, 180.0), 4.0, 36.0, 0.0)
    # only the front group sees it: k = 8/9, no side has room (inf = inf): turn -1
    a = avoid(model=ahead)
    assert a.modulate(3.0, 0.9, seen(ahead, r0=6.0)) == pytest.approx((1 / 3, -11.9 / 9))
    sides = SensorModel("sides", (90.0, -90.0), 4.0, 36.0, 0.0)
    assert avoid(model=sides).modulate(3.0, 0.9, seen(sides, r0=6.0, r1=6.0)) == (3.0, 0.9)
    assert avoid(model=sides).modulate(3.0, 0.9, seen(sides, r0=5.0, r1=5.0)) == (0.0, 0.0)


def test_avoidance_act_drives_at_its_speed():
    # clear: (3, 3)
    close(avoid(speed=3.0).act(seen()), (3.0, 3.0))
    # ray 7 at 6: v = 1/3, omega = -12.8/9, half = -12.8/9 * 5.3 / 2 = -3.7689 (room 1.31)
    close(avoid(speed=3.0).act(seen(r7=6.0)), wheels(1 / 3, -12.8 / 9 * AXLE / 2))
    close(avoid().act(seen()), (5.08, 5.08))


# -- go to heading --------------------------------------------------------------------------

def test_go_to_heading_set_up():
    g = GoToHeading()
    assert g.robot == RobotParams() and g.speed == 5.08 and g.gain == 2.0
    assert g.avoid.params == AvoidanceParams() and g.avoid.geom.model is IR8
    p = AvoidanceParams(slow=20.0)
    h = GoToHeading(sensors=M, robot=FAST, speed=4.0, gain=1.0, avoidance=p)
    assert (h.robot, h.speed, h.gain, h.avoid.params, h.avoid.geom.model) == (
        FAST, 4.0, 1.0, p, M)
    assert h.avoid.geom.robot is FAST
    assert GoToHeading(robot=FAST).speed == 20.0


def test_go_to_heading_rules():
    g = GoToHeading(sensors=M, robot=FAST, speed=4.0)
    clear = seen()
    # err = pi/3: v = 4 * cos(pi/3)^2 = 1, omega = 2 pi / 3
    close(g.act(clear, 0.0, math.pi / 3), wheels(4 * 0.25, math.pi / 3 * AXLE))
    # err = 2 rad: cos < 0, v = 0; omega = 4 capped at 2.5, half = 6.625
    close(g.act(clear, 0.0, 2.0), (-6.625, 6.625))
    close(g.act(clear, 0.0, -2.0), (6.625, -6.625))
    close(g.act(clear, 1.0, -1.0), (6.625, -6.625))  # err = target - heading = -2
    # on target: straight at speed
    close(g.act(clear, 0.5, 0.5), (4.0, 4.0))
    # wrapped: from 3 to -3 is +0.2832 rad (2 pi - 6), not -6
    err = 2 * math.pi - 6
    close(g.act(clear, 3.0, -3.0), wheels(4 * math.cos(err) ** 2, err * AXLE))
    # gain 1: err 1 -> omega 1
    h = GoToHeading(sensors=M, robot=FAST, speed=4.0, gain=1.0)
    close(h.act(clear, 0.0, 1.0), wheels(4 * math.cos(1.0) ** 2, 0.5 * AXLE))
    # exactly the cap: gain 2, err 1.25 -> omega 2.5
    close(g.act(clear, 0.0, 1.25), wheels(4 * math.cos(1.25) ** 2, 1.25 * AXLE))


def test_go_to_heading_avoids():
    g = GoToHeading(sensors=M, robot=FAST, speed=4.0)
    # on target, obstacle front-left at 6: v = 4/9, omega = -12.8/9
    close(g.act(seen(r7=6.0), 0.0, 0.0), wheels(4 / 9, -12.8 / 9 * AXLE / 2))
    # its own avoidance params: slow 20, front 12 -> k = 8 / 14.5 (stop_at 5.5)
    h = GoToHeading(sensors=M, robot=FAST, speed=4.0, avoidance=AvoidanceParams(slow=20.0))
    k = 8 / 14.5
    close(h.act(seen(r7=12.0), 0.0, 0.0), wheels(4 * (1 - k), -1.6 * k * AXLE / 2))


# -- wall-guided heading --------------------------------------------------------------------

def guided(**kw) -> WallGuidedHeading:
    kw.setdefault("params", STEADY)
    return WallGuidedHeading(sensors=M, robot=FAST, speed=1.0, **kw)


def test_wall_guided_set_up():
    base = WallFollowerParams(rho=0.5, target=7.0, speed_min=1.0)
    w = WallGuidedHeading(sensors=M, robot=FAST, side=1, speed=2.5, tolerance=0.4,
                          params=base, rng=5)
    assert w.follower.params == WallFollowerParams(rho=0.0, target=7.0, speed_min=1.0)
    assert (w.follower.side, w.follower.geom.model, w.follower.geom.robot) == (1, M, FAST)
    assert w.follower.rng.random() == np.random.default_rng(5).random()
    assert (w.steer.speed, w.steer.robot, w.steer.avoid.geom.model) == (2.5, FAST, M)
    assert w.tolerance == 0.4
    d = WallGuidedHeading()
    assert d.tolerance == 1.2 and d.follower.side == -1
    assert d.follower.params == WallFollowerParams(rho=0.0)
    assert d.follower.rng.random() == np.random.default_rng(0).random()
    assert d.steer.speed == 5.08 and d.steer.avoid.geom.model is IR8


def test_wall_guided_follows_the_wall_only_near_the_heading():
    wall = seen(r2=7.0)  # the right wall 7 cm away
    follow = wheels(1.0, -0.636)  # the follower: omega -0.24 (see above)
    # steering with err 1: v = cos(1)^2 (speed 1), omega = 2
    steer = wheels(math.cos(1.0) ** 2, AXLE)
    close(guided().act(wall, 0.0, 1.0), follow)  # |err| 1 < 1.2
    close(guided().act(wall, 0.0, -1.0), follow)
    close(guided(tolerance=1.0).act(wall, 0.0, 1.0), steer)  # exactly the tolerance: steer
    close(guided(tolerance=1.0).act(wall, 0.0, 0.999), follow)
    # the error is target - heading: from 1 to 1 is 0 (follow), from 0.5 to -0.5 is -1 (steer
    # at tolerance 1)
    close(guided().act(wall, 1.0, 1.0), follow)
    close(guided(tolerance=1.0).act(wall, 0.5, -0.5), wheels(math.cos(1.0) ** 2, -AXLE))
    # wrapped: 3 -> -3 is 0.28 rad
    close(guided(tolerance=0.3).act(wall, 3.0, -3.0), follow)
    # the wall on the other side only: steer
    close(guided().act(seen(r5=7.0), 0.0, 1.0), steer)
    close(guided(side=1).act(seen(r5=7.0), 0.0, 1.0), wheels(1.0, 0.636))


def test_wall_guided_wall_range_edge_and_no_switching():
    steer = wheels(math.cos(1.0) ** 2, AXLE)
    close(guided().act(seen(r2=35.0), 0.0, 1.0), steer)  # range_max - 1: no wall
    close(guided().act(seen(r2=34.9375), 0.0, 1.0), wheels(1.0, -3.18))  # followed, capped
    w = guided(params=WallFollowerParams(rho=1.0, speed_drift=0.0))
    for _ in range(5):
        w.act(seen(r2=7.0), 0.0, 0.0)
    assert w.follower.side == -1 and w.follower.switches == 0


def test_stop_stands_still():
    assert Stop().act(seen(r0=4.0)) == (0.0, 0.0)


def test_speeds_gains_and_tolerances_are_finite_numbers():
    for make, name, bad in ((lambda v: GoToHeading(speed=v), "speed", float("nan")),
                            (lambda v: GoToHeading(gain=v), "gain", -1.0),
                            (lambda v: ObstacleAvoidance(speed=v), "speed", float("inf")),
                            (lambda v: WallGuidedHeading(tolerance=v), "tolerance", 0.0),
                            (lambda v: WallGuidedHeading(speed=v), "speed", -0.5)):
        rel = "> 0" if name == "tolerance" else ">= 0"
        with refused(f"{name} must be finite and {rel}, got {bad!r}"):
            make(bad)
    # on their edges: a robot told to stand (speed 0) with no steering gain gives v = 0 and
    # omega = 0 (every ray clear, so no avoidance), both wheels 0; an int taken as its float
    assert GoToHeading(sensors=M, speed=0, gain=0).act(seen(), 0.0, 1.0) == (0.0, 0.0)
    assert WallGuidedHeading(tolerance=1).tolerance == 1.0
