"""The teacher's rules (leash, block, sound) in a 100 x 100 cm box, worked out by hand.

The leash is a pure pursuit: with the heading error ``err`` to the next waypoint the command is
``v = vmax cos(err)^2`` (0 when the waypoint is behind), ``omega = 3 err`` capped at 3 rad/s,
turned into wheels by the drive's inverse ``half = omega axle / 2`` (axle 5.3 cm), ``(v - half,
v + half)``. A waypoint within ``tolerance`` cm (3 by default, the edge included) is reached and
dropped. ``vmax`` is the lead's own speed, else the teacher's ``lead_speed``, else the robot's
``speed_max``. The robot used for the pursuit has speed_max 20 cm/s, so no wheel is capped unless
said.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from hippo.sim.builder import ArenaBuilder
from hippo.sim.robot import RobotParams
from hippo.sim.teacher import Teacher
from hippo.sim.world import World

FAST = RobotParams(speed_max=20.0)
AXLE = 5.3


def refused(message: str):
    return pytest.raises(ValueError, match="^" + re.escape(message) + "$")


def world(robot: RobotParams | None = None, pose=(50.0, 50.0, 0.0)) -> World:
    arena = ArenaBuilder("box", 100, 100).outer_walls().start(50, 50).build()
    w = World(arena, robot=robot, seed=0)
    w.reset(0, pose=pose)
    return w


def wheels(v: float, omega: float) -> tuple[float, float]:
    half = omega * AXLE / 2
    return (v - half, v + half)


def close(got, want) -> None:
    assert got == pytest.approx(want, rel=1e-12, abs=1e-12)


# -- construction and state -----------------------------------------------------------------

def test_a_teacher_attaches_itself_and_starts_idle():
    w = world()
    t = Teacher(w)
    assert w.teacher is t and w._interventions == [t]
    assert (t.leading, t.blocking, t.active) == (False, False, False)
    assert t.tolerance == 3.0 and t.lead_speed is None


def test_the_teacher_refuses_a_bad_speed_or_tolerance():
    w = world()
    with refused("lead_speed must be finite and > 0, got -1.0"):
        Teacher(w, lead_speed=-1.0)
    with refused("lead_speed must be finite and > 0, got 0.0"):
        Teacher(w, lead_speed=0.0)
    with refused("tolerance must be finite and > 0, got nan"):
        Teacher(w, tolerance=math.nan)
    with refused("tolerance must be finite and > 0, got 0"):
        Teacher(w, tolerance=0)
    assert w.teacher is None  # a refused teacher is not attached
    t = Teacher(w, lead_speed=2, tolerance=0.5)
    assert (t.lead_speed, t.tolerance) == (2.0, 0.5)


# -- the leash ------------------------------------------------------------------------------

def test_lead_refusals_word_for_word():
    t = Teacher(world())
    with refused("waypoints must be a non-empty list of (x, y), got shape (0,)"):
        t.lead([])
    with refused("waypoints must be a non-empty list of (x, y), got shape (0, 2)"):
        t.lead(np.zeros((0, 2)))
    with refused("waypoints must be a non-empty list of (x, y), got shape (2,)"):
        t.lead((60.0, 50.0))
    with refused("waypoints must be a non-empty list of (x, y), got shape (1, 3)"):
        t.lead([(60.0, 50.0, 0.0)])
    with refused("waypoints contains 1 non-finite value(s) (NaN or inf)"):
        t.lead([(60.0, math.nan)])
    with refused("lead speed must be finite and > 0, got 0.0"):
        t.lead([(60.0, 50.0)], speed=0.0)
    assert not t.leading and t.world.events == []


def test_a_refused_lead_leaves_the_leash_as_it_was():
    # the speed is checked before the waypoints are taken: a refused lead put no leash on (the
    # next step then failed on a lead speed never set) and did not replace a lead under way
    w = world(FAST)
    t = Teacher(w)
    with refused("lead speed must be finite and > 0, got -2.0"):
        t.lead([(60.0, 50.0)], speed=-2.0)
    assert not t.leading and w.events == []
    w.step((0.0, 0.0))
    assert w._last_command == (0.0, 0.0)
    t.lead([(80.0, 50.0)], speed=1.0)
    with refused("lead speed must be finite and > 0, got nan"):
        t.lead([(50.0, 80.0)], speed=math.nan)
    assert t._waypoints == [(80.0, 50.0)]
    close(t.override(0.0, 0.0), (1.0, 1.0))


def test_lead_logs_its_start_and_a_leash_on_is_active():
    w = world()
    w.step((0.0, 0.0))
    t = Teacher(w)
    t.lead([(60, 50), (70, 50)])
    assert w.events == [(0.2, "lead_start", "2 waypoints")]
    assert t._waypoints == [(60.0, 50.0), (70.0, 50.0)]
    assert all(type(v) is float for p in t._waypoints for v in p)
    assert (t.leading, t.blocking, t.active) == (True, False, True)


def test_stop_leading_logs_once():
    w = world()
    t = Teacher(w)
    t.stop_leading()
    assert w.events == []
    t.lead([(60, 50)])
    t.stop_leading()
    t.stop_leading()
    assert w.events == [(0.0, "lead_start", "1 waypoints"), (0.0, "lead_end", "")]
    assert not t.leading and not t.active


def test_without_a_leash_the_command_passes_through():
    t = Teacher(world(FAST))
    assert t.override(1.25, -2.5) == (1.25, -2.5)


def test_straight_ahead_at_the_speed_chosen():
    # the waypoint 10 cm ahead: err 0, v = vmax, omega 0
    t = Teacher(world(FAST))
    t.lead([(60, 50)])
    close(t.override(0.0, 0.0), (20.0, 20.0))  # the robot's speed_max
    t = Teacher(world(FAST), lead_speed=2.0)
    t.lead([(60, 50)])
    close(t.override(0.0, 0.0), (2.0, 2.0))  # the teacher's lead speed
    t.lead([(60, 50)], speed=1.5)
    close(t.override(0.0, 0.0), (1.5, 1.5))  # the lead's own speed first
    t.lead([(60, 50)])
    close(t.override(0.0, 0.0), (2.0, 2.0))  # a new lead without speed: the teacher's again


def test_pure_pursuit_turns_towards_the_waypoint():
    # the waypoint 10 cm away at 0.5 rad left: v = 4 cos(0.5)^2, omega = 1.5
    t = Teacher(world(FAST), lead_speed=4.0)
    t.lead([(50 + 10 * math.cos(0.5), 50 + 10 * math.sin(0.5))])
    close(t.override(0.0, 0.0), wheels(4.0 * math.cos(0.5) ** 2, 1.5))
    # 0.5 rad to the right: the same speed, omega -1.5
    t.lead([(50 + 10 * math.cos(0.5), 50 - 10 * math.sin(0.5))])
    close(t.override(0.0, 0.0), wheels(4.0 * math.cos(0.5) ** 2, -1.5))


def test_the_turn_is_capped_at_3_rad_per_s_either_way():
    # err 1.2: 3 err = 3.6 capped at 3; err -1.2: -3
    t = Teacher(world(FAST), lead_speed=4.0)
    t.lead([(50 + 10 * math.cos(1.2), 50 + 10 * math.sin(1.2))])
    close(t.override(0.0, 0.0), wheels(4.0 * math.cos(1.2) ** 2, 3.0))
    t.lead([(50 + 10 * math.cos(1.2), 50 - 10 * math.sin(1.2))])
    close(t.override(0.0, 0.0), wheels(4.0 * math.cos(1.2) ** 2, -3.0))


def test_a_waypoint_behind_is_turned_to_in_place():
    # err 2.0: cos < 0, so v = 0 (not vmax cos^2 > 0); omega capped at 3
    t = Teacher(world(FAST), lead_speed=4.0)
    t.lead([(50 + 10 * math.cos(2.0), 50 + 10 * math.sin(2.0))])
    close(t.override(0.0, 0.0), wheels(0.0, 3.0))


def test_the_heading_error_is_wrapped():
    # heading 3.0, waypoint at -3.0 rad: the error is 2 pi - 6 = 0.283 left, not -6 rad
    t = Teacher(world(FAST, pose=(50.0, 50.0, 3.0)), lead_speed=4.0)
    t.lead([(50 + 10 * math.cos(-3.0), 50 + 10 * math.sin(-3.0))])
    err = 2 * math.pi - 6.0
    close(t.override(0.0, 0.0), wheels(4.0 * math.cos(err) ** 2, 3 * err))


def test_the_default_robot_caps_the_wheels():
    # speed_max 5.08: err 0.5 gives omega 1.5, half = 3.975, room 1.105 < v = 5.08 cos(0.5)^2
    t = Teacher(world())
    t.lead([(50 + 10 * math.cos(0.5), 50 + 10 * math.sin(0.5))])
    close(t.override(0.0, 0.0), (1.105 - 3.975, 1.105 + 3.975))


def test_a_waypoint_at_the_tolerance_is_reached_and_one_beyond_is_not():
    # 3 cm ahead exactly: dropped, the next one (10 cm, straight up) is pursued
    t = Teacher(world(FAST), lead_speed=4.0)
    t.lead([(53.0, 50.0), (50.0, 60.0)])
    close(t.override(0.0, 0.0), wheels(4.0 * math.cos(math.pi / 2) ** 2, 3.0))
    assert t._waypoints == [(50.0, 60.0)]
    # 3 cm and a bit: still pursued (straight ahead)
    t.lead([(53.000001, 50.0), (50.0, 60.0)])
    close(t.override(0.0, 0.0), (4.0, 4.0))
    assert len(t._waypoints) == 2
    # with a tolerance of 4 the waypoint 3.5 cm ahead is reached
    t = Teacher(world(FAST), lead_speed=4.0, tolerance=4.0)
    t.lead([(53.5, 50.0), (50.0, 60.0)])
    t.override(0.0, 0.0)
    assert t._waypoints == [(50.0, 60.0)]


def test_several_waypoints_can_be_reached_in_one_tick():
    t = Teacher(world(FAST), lead_speed=4.0)
    t.lead([(51.0, 50.0), (50.0, 52.0), (49.0, 49.0), (60.0, 50.0)])
    close(t.override(0.0, 0.0), (4.0, 4.0))
    assert t._waypoints == [(60.0, 50.0)]


def test_the_last_waypoint_reached_ends_the_lead_and_stops_the_robot():
    w = world(FAST)
    t = Teacher(w, lead_speed=4.0)
    t.lead([(51.0, 50.0), (52.0, 51.0)])
    assert t.override(3.0, 3.0) == (0.0, 0.0)
    assert w.events[-1] == (0.0, "lead_end", "")
    assert not t.leading and not t.active


def test_the_leash_drives_the_world():
    # led straight east at 2 cm/s, the robot's own (0, 0) ignored: 0.4 cm in one 0.2 s tick
    w = world(FAST)
    t = Teacher(w, lead_speed=2.0)
    t.lead([(80.0, 50.0)])
    w.step((0.0, 0.0))
    assert w._last_command == (2.0, 2.0)
    assert w.pose[0] == pytest.approx(50.4, abs=1e-9)


# -- the block ------------------------------------------------------------------------------

def test_block_refuses_a_bad_duration():
    t = Teacher(world())
    for bad in (0.0, -1.0, math.inf):
        with refused(f"block duration must be finite and > 0, got {bad!r}"):
            t.block(bad)
    assert not t.blocking and t.world.obstacles == []


def test_block_puts_a_ring_round_the_robot_and_logs_it():
    w = world(pose=(40.0, 30.0, 1.0))
    w.step((0.0, 0.0))
    t = Teacher(w)
    t.block(1.25)
    (ring,) = w.obstacles
    assert ring.kind == "block" and len(ring.shapes) == 16
    assert tuple(ring.body.position) == (40.0, 30.0)
    # radius = the robot's 3.7 + the gap's 2.5 = 6.2 (the first segment starts at angle 0)
    assert tuple(ring.shapes[0].a) == pytest.approx((6.2, 0.0), abs=1e-12)
    assert t._block_until == pytest.approx(1.45, abs=1e-12)
    assert w.events == [(0.2, "block_start", "1.250")]
    assert (t.leading, t.blocking, t.active) == (False, True, True)


def test_the_gap_sets_the_ring_radius():
    w = world()
    t = Teacher(w)
    t.block(1.0, gap=1.0)
    assert tuple(w.obstacles[0].shapes[0].a) == pytest.approx((4.7, 0.0), abs=1e-12)


def test_a_new_block_replaces_the_old_one():
    w = world()
    t = Teacher(w)
    t.block(5.0)
    first = w.obstacles[0]
    t.block(2.0)
    assert first not in w.obstacles and len(w.obstacles) == 1
    assert [e[1] for e in w.events] == ["block_start", "block_end", "block_start"]
    assert t._block_until == 2.0


def test_unblock_removes_the_ring_and_logs_once():
    w = world()
    t = Teacher(w)
    t.unblock()
    assert w.events == []
    t.block(1.0)
    t.unblock()
    t.unblock()
    assert w.obstacles == [] and not t.blocking
    assert w.events == [(0.0, "block_start", "1.000"), (0.0, "block_end", "")]


def test_the_block_ends_at_its_time_within_a_nanosecond():
    w = world()
    t = Teacher(w)
    t.block(1.0)
    w.t = 1.0 - 2e-9
    t.after_step()
    assert t.blocking
    w.t = 1.0 - 1e-9
    t.after_step()
    assert not t.blocking and w.events[-1] == (1.0 - 1e-9, "block_end", "")
    t.after_step()  # nothing left to end
    assert [e[1] for e in w.events] == ["block_start", "block_end"]


def test_a_block_lasts_its_ticks_in_the_world():
    # blocked at t = 0.2 for 0.4 s: ends at the step to t = 0.6 (0.2 + 0.4 is 0.6000000000000001,
    # the clock reads 0.6: within the nanosecond)
    w = world()
    t = Teacher(w)
    w.step((0.0, 0.0))
    t.block(0.4)
    w.step((0.0, 0.0))
    assert t.blocking
    w.step((0.0, 0.0))
    assert not t.blocking and w.events[-1] == (0.6, "block_end", "")


# -- sound and reset ------------------------------------------------------------------------

def test_sound_is_heard_in_the_next_observation_only():
    w = world()
    t = Teacher(w)
    t.sound()
    assert w.events == [(0.0, "sound", "")]
    assert w.step((0.0, 0.0)).sound
    assert not w.step((0.0, 0.0)).sound


def test_a_world_reset_resets_the_teacher():
    w = world()
    t = Teacher(w)
    t.lead([(60, 50)])
    t.block(3.0)
    w.reset(0)
    assert (t.leading, t.blocking, t.active) == (False, False, False)
    assert t._block_until == 0.0 and w.obstacles == []
