"""The world's rules in a 100 x 100 cm box (walls 0.5 cm thick round its edge), by hand.

The robot is the e-puck (radius 3.7 cm, axle 5.3 cm, speed_max 5.08 cm/s) unless said. Sensors
are noise-free models with rays where the expected free length is known: a ray leaves the body
at its rim, so a ray straight at a wall's face ``g`` cm from the centre reads ``g - 3.7`` cm
(less the segment's 0.5 cm radius when ``g`` is measured to its centre line). Odometry is the
tick's displacement in the robot frame at the start of the tick. Every expected number is
worked out in the comments; none is copied from a run of the code.
"""

from __future__ import annotations

import copy
import math
import re
import sys

import numpy as np
import pytest

from hippo.sim.builder import ArenaBuilder
from hippo.sim.robot import RobotParams, SensorModel
from hippo.sim.world import MAX_SUBSTEPS, World

H34 = math.atan2(4.0, 3.0)  # cos 0.6, sin 0.8
FRONT = SensorModel("front", (0.0,), 0.0, 60.0, 0.0)
CROSS = SensorModel("cross", (0.0, 90.0, 180.0, -90.0), 2.0, 42.0, 0.0)


def refused(message: str, kind: type[Exception] = ValueError):
    return pytest.raises(kind, match="^" + re.escape(message) + "$")


def box(w: float = 100.0, h: float = 100.0, name: str = "box"):
    return ArenaBuilder(name, w, h).outer_walls().start(w / 2, h / 2).build()


def world(pose=(50.0, 50.0, 0.0), **kw) -> World:
    w = World(box(), **kw)
    w.reset(0, pose=pose)
    return w


class Probe:
    """A stand-in intervention that records the calls it gets."""

    def __init__(self, active: bool = True, command=None, after=None) -> None:
        self.active = active
        self.command = command
        self.after = after
        self.calls: list[str] = []

    def override(self, left: float, right: float) -> tuple[float, float]:
        self.calls.append(f"override {left:g} {right:g}")
        return self.command if self.command is not None else (left, right)

    def after_step(self) -> None:
        self.calls.append("after")
        if self.after is not None:
            self.after()

    def reset(self) -> None:
        self.calls.append("reset")


# -- construction ---------------------------------------------------------------------------

def test_construction_refusals_word_for_word():
    arena = box()
    with refused("arena must be an Arena (e.g. hippo.sim.arenas.get('two_rooms')), got 'box'"):
        World("box")
    long = "x" * 100
    with refused("arena must be an Arena (e.g. hippo.sim.arenas.get('two_rooms')), got '"
                 + "x" * 79):
        World(long)
    with refused("robot must be RobotParams or None, got dict"):
        World(arena, robot={})
    with refused("seed must be an integer in [0, 9223372036854775807], got -1"):
        World(arena, seed=-1)
    with refused("dt must be finite and > 0, got 0.0"):
        World(arena, dt=0.0)
    with refused("substeps must be an integer in [1, 10000], got 0"):
        World(arena, substeps=0)
    with refused("substeps must be an integer in [1, 10000], got 10001"):
        World(arena, substeps=10001)
    assert World(arena, substeps=MAX_SUBSTEPS).substeps == 10_000
    assert World(arena, seed=None).seed is None


def test_a_new_world_is_reset_with_its_seed():
    w = World(box())
    assert w.seed == 0 and w.teacher is None and w.obstacles == []  # the defaults
    w = World(box(), seed=5)
    assert w.seed == 5 and w.pose == pytest.approx((50.0, 50.0, 0.0))
    rng = np.random.default_rng(5)
    rng.normal(0.0, 0.02, 8)  # the first observation's noise on the 8 readings
    assert w.rng.random() == rng.random()


def test_walls_robot_and_obstacles_are_frictionless_and_inelastic():
    w = world()
    w.add_box((10, 10, 20, 20))
    w.add_ring((70, 70), 5.0)
    shapes = list(w.space.shapes)
    assert len(shapes) == 4 + 1 + 1 + 16  # the walls, the robot, a box, a ring
    assert all((s.friction, s.elasticity) == (0.0, 0.0) for s in shapes)
    walls = [s for s in shapes if s.body is w.space.static_body]
    assert len(walls) == 4 and all(s.radius == 0.5 for s in walls)
    assert {s.filter.categories for s in walls} == {0b010}
    assert w._shape.radius == 3.7 and w._shape.filter.categories == 0b001
    assert w.body.mass == 0.15


def test_the_substeps_keep_the_travel_per_physics_step_under_a_centimetre():
    arena = box()
    five = RobotParams(speed_max=5.0)
    # travel = speed_max dt cm per tick: 5 x 0.2 = 1 -> the 5 asked for
    assert World(arena, robot=five).substeps == 5
    # 5 x 2 = 10 cm: 10 steps, more than 5; 5 x 2.1 = 10.5: 11
    assert World(arena, robot=five, dt=2.0).substeps == 10
    assert World(arena, robot=five, dt=2.1).substeps == 11
    assert World(arena, robot=five, dt=2.0, substeps=12).substeps == 12
    assert World(arena, robot=five, dt=0.2, substeps=1).substeps == 1
    # 5 x 2000 = 10 000, exactly the most a tick may take; 5 x 2000.5 = 10002.5 is refused
    assert World(arena, robot=five, dt=2000.0).substeps == MAX_SUBSTEPS
    with refused("dt=2000.5 s needs 1e+04 physics substeps per tick at speed_max 5 cm/s (at "
                 "most 10000): dt must be <= 2000 s"):
        World(arena, robot=five, dt=2000.5)


def test_attach_and_detach_keep_one_list_and_name_the_last_as_teacher():
    w = world()
    a, b = Probe(), Probe()
    w.attach(a)
    w.attach(b)
    w.attach(a)  # attached once only; the teacher is the last attached
    assert w._interventions == [a, b] and w.teacher is a
    w.detach(a)
    assert w._interventions == [b] and w.teacher is b
    w.detach(a)  # not attached: nothing happens
    assert w._interventions == [b] and w.teacher is b
    w.attach(a)
    w.detach(b)  # not the teacher: the teacher stays
    assert w._interventions == [a] and w.teacher is a
    w.detach(a)
    assert w._interventions == [] and w.teacher is None


# -- reset and the pose checks --------------------------------------------------------------

def test_reset_starts_afresh_at_the_start_pose():
    arena = ArenaBuilder("box", 100, 100).outer_walls().start(30, 20, 1.0).build()
    w = World(arena, seed=5)
    probe = Probe()
    w.attach(probe)
    w.step((2.0, 3.0))
    w.emit_sound()
    w.add_box((70, 70, 80, 80))
    obs = w.reset(7)
    assert w.pose == pytest.approx((30.0, 20.0, 1.0), abs=1e-12)
    assert (w.t, w.tick, w.events, w.obstacles, w.seed) == (0.0, 0, [], [], 7)
    assert w._last_command == (0.0, 0.0) and (w._v, w._omega) == (0.0, 0.0)
    assert probe.calls[-1] == "reset"
    assert (obs.t, obs.tick, obs.sound, obs.moving, obs.floor) == (0.0, 0, False, False, 0)
    assert np.array_equal(obs.odometry, np.zeros(3))
    assert w.truth.pose == pytest.approx((30.0, 20.0, 1.0)) and w.truth.speed == 0.0
    # the noise stream is the seed's, after the 8 readings' noise of the reset's observation
    rng = np.random.default_rng(7)
    rng.normal(0.0, 0.02, 8)
    assert w.rng.random() == rng.random()
    # the sound played before the reset is not heard after it
    assert not w.step((0.0, 0.0)).sound


def test_reset_refuses_a_bad_seed_like_the_constructor():
    w = world()
    w.step((2.0, 2.0))
    for bad, why in ((-1, "an integer in [0, 9223372036854775807], got -1"),
                     (1.5, "an integer, got 1.5 (float)"),
                     (True, "an integer, got True (a bool)"),
                     ("abc", "an integer, got 'abc' (str)")):
        with refused(f"seed must be {why}"):
            w.reset(bad)
    assert w.tick == 1 and w.seed == 0  # nothing was reset


def test_pose_refusals_word_for_word():
    w = world()
    with refused("pose must be three numbers (x, y, heading), got (30.0, 30.0)"):
        w.reset(0, pose=(30.0, 30.0))
    with refused("pose must be three numbers (x, y, heading), got 5"):
        w.reset(0, pose=5)
    with refused("pose must be three numbers (x, y, heading), got ('a', 1, 2)"):
        w.reset(0, pose=("a", 1, 2))
    with refused("heading must be finite (radians), got nan"):
        w.place_robot(30.0, 30.0, math.nan)
    with refused("robot position must be finite, got (inf, 30.0)"):
        w.place_robot(math.inf, 30.0, 0.0)
    with refused("robot position must be finite, got (30.0, nan)"):
        w.place_robot(30.0, math.nan, 0.0)
    with refused("cannot place the robot at (2.0, 50.0) in 'box': it would overlap a wall or "
                 "leave the arena"):
        w.place_robot(2.0, 50.0, 0.0)


def test_the_robot_fits_exactly_its_radius_and_the_walls_half_thickness_from_a_wall():
    w = world()
    # 3.7 + 0.5 = 4.2 cm from the left wall's centre line: free; 0.01 cm closer: not
    w.place_robot(4.2, 50.0, 0.0)
    assert w.pose[0] == 4.2
    with pytest.raises(ValueError, match=r"^cannot place the robot at \(4\.2, 50\.0\)"):
        w.place_robot(4.19, 50.0, 0.0)
    w.place_robot(50.0, 95.8, 0.0)
    with pytest.raises(ValueError, match="cannot place the robot"):
        w.place_robot(50.0, 95.81, 0.0)


def test_place_robot_moves_stops_and_logs():
    w = world(sensors=FRONT)
    w.step((5.0, 3.0))
    w.place_robot(20.0, 30.0, 1.23456)
    assert w.pose == pytest.approx((20.0, 30.0, 1.23456), abs=1e-12)
    assert tuple(w.body.velocity) == (0.0, 0.0) and w.body.angular_velocity == 0.0
    assert w.events[-1] == (0.2, "kidnap", "20.00,30.00,1.2346")
    w.place_robot(25.0, 30.0, -0.5, event="lift")
    assert w.events[-1] == (0.2, "lift", "25.00,30.00,-0.5000")
    # the body is where the space's index has it: a ray from it sees the right wall
    w.place_robot(80.0, 50.0, 0.0)
    assert w.ray_distances()[0] == pytest.approx(99.5 - 80.0 - 3.7, abs=1e-9)


def test_place_robot_keeps_a_radius_from_obstacles():
    w = world(sensors=FRONT)
    w.add_box((60.0, 40.0, 70.0, 60.0), movable=False)
    # 3.7 cm from the box's face: allowed; 3.69: refused
    w.place_robot(56.3, 50.0, 0.0)
    with refused("cannot place the robot at (56.3, 50.0): obstacle there"):
        w.place_robot(56.31, 50.0, 0.0)
    # the other side and beyond a corner: hypot(3, 3) = 4.24 clear of the corner (70, 60)
    w.place_robot(73.7, 50.0, 0.0)
    w.place_robot(73.0, 63.0, 0.0)
    with refused("cannot place the robot at (72.0, 62.0): obstacle there"):  # hypot(2, 2)
        w.place_robot(72.0, 62.0, 0.0)


# -- obstacles ------------------------------------------------------------------------------

def test_box_refusals_word_for_word():
    w = world()
    with refused("box rect must be (x0, y0, x1, y1), got (1, 2, 3)"):
        w.add_box((1, 2, 3))
    with refused("box (10, 10, 10, 20) has no area (it needs x0 < x1 and y0 < y1)"):
        w.add_box((10, 10, 10, 20))
    with refused("box (10, 20, 15, 20) has no area (it needs x0 < x1 and y0 < y1)"):
        w.add_box((10, 20, 15, 20))
    with refused("box (10, 20, 15, 19) has no area (it needs x0 < x1 and y0 < y1)"):
        w.add_box((10, 20, 15, 19))
    for rect in ((-0.5, 10, 20, 20), (10, -0.5, 20, 20), (10, 10, 100.5, 20),
                 (10, 10, 20, 100.5)):
        with refused(f"box {rect!r} lies outside the 100 x 100 arena 'box'"):
            w.add_box(rect)
    with refused("box mass must be finite and > 0, got -2.0"):
        w.add_box((10, 10, 20, 20), mass=-2.0)
    assert w.obstacles == []


def test_a_box_may_touch_the_arena_edges_and_be_thin():
    w = world()
    w.add_box((0, 0, 10, 10))
    w.add_box((90, 90, 100, 100))
    thin = w.add_box((10, 30, 10.5, 40))
    assert len(w.obstacles) == 3
    assert sorted(tuple(v) for v in thin.shapes[0].get_vertices()) == \
        [(-0.25, -5.0), (-0.25, 5.0), (0.25, -5.0), (0.25, 5.0)]


def test_a_box_and_a_placed_robot_may_touch_exactly():
    # a robot of radius 4 at (50, 50): a box whose face is 4 cm away goes in; placed 4 cm
    # from a box's face, the robot goes there (binary-exact distances)
    w = world(robot=RobotParams(radius=4.0))
    w.add_box((54.0, 40.0, 60.0, 60.0), movable=False)
    w.place_robot(36.0, 50.0, 0.0)
    w.add_box((20.0, 40.0, 32.0, 60.0), movable=False)
    w.place_robot(50.0, 50.0, 0.0)
    assert w.pose[:2] == (50.0, 50.0) and len(w.obstacles) == 2


def test_a_box_keeps_the_robot_radius_from_the_robot():
    w = world()  # the robot at (50, 50), radius 3.7
    with refused("box (53.69, 40, 60, 60) overlaps the robot at (50.0, 50.0): put it "
                 "elsewhere or move the robot first"):
        w.add_box((53.69, 40, 60, 60))
    w.add_box((53.7, 40, 60, 60))  # its face exactly 3.7 cm away
    w.add_box((40, 40, 46.3, 60))  # the left side likewise
    w.add_box((40, 20, 60, 46.3))  # below
    w.add_box((40, 53.7, 53.0, 60))  # above
    # a corner: nearest point (52, 52.5) is hypot(2, 2.5) = 3.2 away; (52.7, 52.7) is 3.82
    with pytest.raises(ValueError, match="overlaps the robot"):
        w.add_box((52.0, 52.5, 53.0, 53.0))
    w2 = world()
    w2.add_box((52.7, 52.7, 60, 60))
    w3 = world()
    with pytest.raises(ValueError, match="overlaps the robot"):
        w3.add_box((45, 45, 55, 55))  # round the robot: 0 away


def test_box_bodies_and_shapes():
    w = world()
    movable = w.add_box((10, 20, 30, 26))
    fixed = w.add_box((70, 70, 80, 90), movable=False, mass=0.0)  # the mass of a fixed box unused
    assert movable.kind == fixed.kind == "box" and w.obstacles == [movable, fixed]
    assert movable.body.mass == 2.0
    # the moment of a 20 x 6 box of 2 kg: m (w^2 + h^2) / 12 = 2 x 436 / 12
    assert movable.body.moment == pytest.approx(2 * 436 / 12, rel=1e-12)
    assert tuple(movable.body.position) == (20.0, 23.0)
    assert tuple(fixed.body.position) == (75.0, 80.0)
    assert fixed.body.body_type == fixed.body.KINEMATIC
    assert movable.body.body_type == movable.body.DYNAMIC
    vs = sorted(tuple(v) for v in movable.shapes[0].get_vertices())
    assert vs == [(-10.0, -3.0), (-10.0, 3.0), (10.0, -3.0), (10.0, 3.0)]
    assert w.add_box((10, 50, 20, 60), mass=0.5).body.mass == 0.5
    for s in movable.shapes + fixed.shapes:
        assert (s.friction, s.elasticity) == (0.0, 0.0)
        assert s.filter.categories == 0b100


def test_a_pushed_box_slows_by_floor_friction():
    # no force but the floor: v *= 0.05 ** h per physics step, 0.05 ** 0.2 over the tick
    w = world()
    b = w.add_box((10, 10, 20, 20), mass=1.0)
    b.body.velocity = (10.0, 0.0)
    w.step((0.0, 0.0))
    assert b.body.velocity.x == pytest.approx(10 * 0.05 ** 0.2, rel=1e-9)
    assert b.body.velocity.y == 0.0


def test_ring_refusals_word_for_word():
    w = world()
    with refused("ring centre must be (x, y), got (1, 2, 3)"):
        w.add_ring((1, 2, 3), 5.0)
    with refused("ring centre (120, 50) lies outside the 100 x 100 arena 'box'"):
        w.add_ring((120, 50), 5.0)
    with refused("ring centre (50, -1) lies outside the 100 x 100 arena 'box'"):
        w.add_ring((50, -1), 5.0)
    with refused("ring centre (-1, 50) lies outside the 100 x 100 arena 'box'"):
        w.add_ring((-1, 50), 5.0)
    with refused("ring centre (50, 101) lies outside the 100 x 100 arena 'box'"):
        w.add_ring((50, 101), 5.0)
    with refused("ring radius must be finite and > 0, got -1.0"):
        w.add_ring((50, 50), -1.0)
    with refused("ring segments n must be an integer >= 3, got 2"):
        w.add_ring((50, 50), 6.0, n=2)
    assert w.obstacles == []


def test_a_ring_is_n_segments_round_its_centre():
    w = world(sensors=CROSS)
    ring = w.add_ring((50, 50), 10.0, n=4, kind="fence")
    assert ring.kind == "fence" and tuple(ring.body.position) == (50.0, 50.0)
    assert ring.body.body_type == ring.body.KINEMATIC
    ends = [(tuple(s.a), tuple(s.b)) for s in ring.shapes]
    want = [((10, 0), (0, 10)), ((0, 10), (-10, 0)), ((-10, 0), (0, -10)), ((0, -10), (10, 0))]
    for (a, b), (wa, wb) in zip(ends, want, strict=True):
        assert a == pytest.approx(wa, abs=1e-12) and b == pytest.approx(wb, abs=1e-12)
    assert all(s.radius == 0.5 for s in ring.shapes)
    assert all(s.filter.categories == 0b100 for s in ring.shapes)
    # each ray meets a corner of the square, 10 cm out: the side x + y = 10 is 0.5 cm thick,
    # so the ray along y = 0 stops where (10 - x) / sqrt 2 = 0.5, at x = 10 - 0.5 sqrt 2
    assert w.ray_distances() == pytest.approx([10 - 0.5 * math.sqrt(2) - 3.7] * 4, abs=1e-9)
    # the default: 16 segments, kind "block"
    w.remove_obstacle(ring)
    ring = w.add_ring((50, 50), 10.0)
    assert ring.kind == "block" and len(ring.shapes) == 16
    assert tuple(ring.shapes[1].a) == pytest.approx((10 * math.cos(math.pi / 8),
                                                     10 * math.sin(math.pi / 8)), abs=1e-12)


def test_removing_an_obstacle_clears_the_rays():
    w = world(sensors=FRONT)
    b = w.add_box((70, 40, 80, 60), movable=False)
    assert w.ray_distances()[0] == pytest.approx(70 - 50 - 3.7, abs=1e-9)  # 16.3
    w.remove_obstacle(b)
    assert w.obstacles == []
    # nothing of it is left in the space: the robot's body, its shape and the 4 walls
    assert list(w.space.bodies) == [w.body]
    assert set(w.space.shapes) == {w._shape, *w.space.static_body.shapes}
    assert w.ray_distances()[0] == pytest.approx(99.5 - 50 - 3.7, abs=1e-9)  # 45.8: the wall
    with refused("this obstacle is not in the world"):
        w.remove_obstacle(b)


# -- sensing --------------------------------------------------------------------------------

def test_rays_turn_with_the_body():
    # rays at 0, 90, 180, -90 degrees; the walls' faces at 0.5 and 99.5
    w = world(pose=(30.0, 60.0, 0.0), sensors=CROSS)
    # east 99.5 - 30, north 99.5 - 60, west 30 - 0.5, south 60 - 0.5, each less 3.7, capped 42
    assert w.ray_distances() == pytest.approx([42.0, 35.8, 25.8, 42.0], abs=1e-9)
    w.place_robot(30.0, 60.0, math.pi / 2)  # turned left: the first ray looks north
    assert w.ray_distances() == pytest.approx([35.8, 25.8, 42.0, 42.0], abs=1e-9)
    # heading (0.6, 0.8), range 200: the first ray meets the top face (at x = 59.6) after
    # (99.5 - 60) / 0.8 = 49.375 cm of its line from the centre, the rim 3.7 along it
    w2 = world(pose=(30.0, 60.0, H34), sensors=SensorModel("far", (0.0, 90.0), 0.0, 200.0, 0.0))
    # ray 2 points (-0.8, 0.6): meets the left face after (30 - 0.5) / 0.8 = 36.875 cm
    assert w2.ray_distances() == pytest.approx([49.375 - 3.7, 36.875 - 3.7], abs=1e-9)


def test_readings_scale_the_free_length_to_the_range():
    # u = (d - range_min) / (range_max - range_min), clipped to [0, 1]
    w = world(pose=(30.0, 60.0, 0.0), sensors=CROSS)  # d = 42, 35.8, 25.8, 42; range 2-42
    assert w.sense() == pytest.approx([1.0, 33.8 / 40, 23.8 / 40, 1.0], abs=1e-12)
    w.place_robot(4.5, 60.0, math.pi)  # 0.3 cm from the left face: below range_min -> 0
    assert w.sense()[0] == 0.0


def test_sensor_noise_is_drawn_from_the_world_stream():
    noisy = SensorModel("noisy", (0.0, 90.0, 180.0, -90.0), 2.0, 42.0, 0.05)
    w = World(box(), sensors=noisy, seed=3)
    w.reset(3, pose=(30.0, 60.0, 0.0))  # draws once for its observation
    rng = np.random.default_rng(3)
    rng.normal(0.0, 0.05, 4)
    clean = np.array([1.0, 33.8 / 40, 23.8 / 40, 1.0])
    want = np.clip(clean + rng.normal(0.0, 0.05, 4), 0.0, 1.0)
    assert w.sense() == pytest.approx(want, abs=1e-12)
    # a step standing still: its readings take the next draws (exact odometry draws nothing)
    want = np.clip(clean + rng.normal(0.0, 0.05, 4), 0.0, 1.0)
    assert w.step((0.0, 0.0)).ir == pytest.approx(want, abs=1e-12)


def test_an_observation_reads_the_floor_under_the_robot():
    arena = (ArenaBuilder("floor", 100, 100).outer_walls().zone("goal", (60, 40, 80, 60), 3)
             .start(50, 50).build())
    w = World(arena, seed=0)
    assert w.reset(0, pose=(60.0, 50.0, 0.0)).floor == 3  # on the zone's edge
    assert w.reset(0, pose=(59.9, 50.0, 0.0)).floor == 0


def test_observe_senses_without_moving():
    w = world()
    w.step((4.0, 4.0))
    x, y, _ = w.pose
    obs = w.observe()
    assert (obs.t, obs.tick, obs.sound, obs.moving) == (0.2, 1, False, False)
    assert np.array_equal(obs.odometry, np.zeros(3))
    assert w.truth.speed == 0.0 and w.truth.pose[:2] == (x, y) and w.tick == 1


# -- the step -------------------------------------------------------------------------------

def test_step_refusals_word_for_word():
    w = world()
    for bad in ("ab", b"ab", (1.0,), (1.0, 2.0, 3.0), None, 5.0, {"a": 1, "b": 2}, ("x", 1)):
        with refused(f"action must be a pair of wheel speeds (left, right) in cm/s, got "
                     f"{bad!r}"):
            w.step(bad)
    with refused("wheel commands must be finite, got (nan, 1.0)"):
        w.step((math.nan, 1.0))
    with refused("wheel commands must be finite, got (1.0, -inf)"):
        w.step((1.0, -math.inf))
    assert w.tick == 0 and w.t == 0.0


def test_a_straight_step_goes_along_the_heading_and_reads_forward():
    w = world(pose=(50.0, 50.0, H34))
    obs = w.step(np.array([4.0, 4.0]))
    # 4 cm/s for 0.2 s = 0.8 cm along (0.6, 0.8): (0.48, 0.64); in the robot frame (0.8, 0, 0)
    assert w.pose == pytest.approx((50.48, 50.64, H34), abs=1e-9)
    assert obs.odometry == pytest.approx([0.8, 0.0, 0.0], abs=1e-9)
    assert w.truth.speed == pytest.approx(4.0, abs=1e-9)
    assert obs.moving and (obs.t, obs.tick) == (0.2, 1) and (w.t, w.tick) == (0.2, 1)
    assert w._last_command == (4.0, 4.0)


def test_odometry_is_the_displacement_in_the_starting_frame():
    w = world(pose=(50.0, 50.0, H34))
    obs = w.step((2.0, 4.0))  # an arc: v = 3, omega = 2 / 5.3
    x, y, h = w.pose
    dx, dy = x - 50.0, y - 50.0
    # rotate the displacement by -H34: (0.6 dx + 0.8 dy, -0.8 dx + 0.6 dy)
    assert obs.odometry == pytest.approx([0.6 * dx + 0.8 * dy, -0.8 * dx + 0.6 * dy, h - H34],
                                         abs=1e-9)
    # 5 physics steps of h = 0.04 s, each moving v h along the heading it starts with (the
    # positions are integrated before the velocities), turning omega h = 0.04 x 2 / 5.3 each
    th = 0.04 * 2.0 / 5.3
    fwd = sum(3.0 * 0.04 * math.cos(k * th) for k in range(5))
    side = sum(3.0 * 0.04 * math.sin(k * th) for k in range(5))
    assert obs.odometry == pytest.approx([fwd, side, 5 * th], abs=1e-9)


def test_a_turn_through_pi_is_wrapped_in_the_odometry():
    # spinning left at 2 x 5.08 / 5.3 rad/s from heading 3.1: dtheta 0.1917, not 0.19 - 2 pi
    w = world(pose=(50.0, 50.0, 3.1))
    obs = w.step((-5.08, 5.08))
    assert obs.odometry[2] == pytest.approx(0.2 * 2 * 5.08 / 5.3, abs=1e-9)
    assert w.pose[2] == pytest.approx(3.1 + 0.2 * 2 * 5.08 / 5.3 - 2 * math.pi, abs=1e-9)
    assert not obs.moving  # a turn on the spot does not translate
    assert obs.odometry[:2] == pytest.approx([0.0, 0.0], abs=1e-9)


def test_the_drive_callback_never_fails_silently(monkeypatch):
    # pymunk ignores an exception raised in a body's velocity function (it only reports it
    # to sys.unraisablehook), so a broken drive would go unnoticed: none may be raised
    seen = []
    monkeypatch.setattr(sys, "unraisablehook", seen.append)
    w = world()
    w.add_box((70, 70, 80, 80))
    for cmd in ((3.0, 4.0), (-2.0, 2.0), (0.0, 0.0)):
        w.step(cmd)
    assert seen == []
    assert w.body.angular_velocity == 0.0 and tuple(w.body.velocity) == (0.0, 0.0)


def test_the_wheels_are_limited_before_they_drive():
    w = world()
    w.step((10.0, -10.0))
    assert w._last_command == (5.08, -5.08)
    assert (w._v, w._omega) == (0.0, -2 * 5.08 / 5.3)
    w.step((0.1, 3.0))  # below speed_min the wheel stalls
    assert w._last_command == (0.0, 3.0)


def test_moving_means_faster_than_the_threshold():
    # threshold 0: standing still is not moving, 0.5 cm/s is
    still = RobotParams(moving_threshold=0.0)
    assert not world(robot=still).step((0.0, 0.0)).moving
    assert world(robot=still).step((0.5, 0.5)).moving
    # the default 0.3 cm/s: 0.29 no, 0.31 yes
    assert not world().step((0.29, 0.29)).moving
    assert world().step((0.31, 0.31)).moving


def test_the_clock_is_rounded_to_the_nanosecond():
    w = world(dt=0.1)
    for _ in range(3):
        w.step((0.0, 0.0))
    assert w.t == 0.3 and w.tick == 3  # 0.1 + 0.1 + 0.1 is 0.30000000000000004
    assert w.truth.t == 0.3 and w.truth.tick == 3
    # 1.00000000006 s is 1 s and 0.06 ns: 1.0 to the nanosecond
    w = world(dt=1.00000000006)
    assert w.step((0.0, 0.0)).t == 1.0


def test_a_tick_lasts_at_least_a_nanosecond():
    # the clock counts whole nanoseconds: a tick of 1 ns moves it, a shorter one would leave it
    # at 0 for ever (round(4e-10, 9) is 0) and is refused
    w = world(dt=1e-9)
    w.step((0.0, 0.0))
    w.step((0.0, 0.0))
    assert w.t == 2e-9
    with refused("dt must be >= 1e-9 s (the clock counts nanoseconds), got 9.99e-10"):
        World(box(), dt=9.99e-10)
    with refused("dt must be >= 1e-9 s (the clock counts nanoseconds), got 4e-10"):
        World(box(), dt=4e-10)


def test_odometry_noise_multiplies_each_part_from_the_world_stream():
    quiet = SensorModel("quiet", (0.0,), 0.0, 30.0, 0.0)
    robot = RobotParams(odometry_noise=0.1)
    clean = world(pose=(50.0, 50.0, H34), sensors=quiet).step((2.0, 4.0)).odometry
    w = World(box(), robot=robot, sensors=quiet, seed=4)
    w.reset(4, pose=(50.0, 50.0, H34))
    got = w.step((2.0, 4.0)).odometry
    factor = 1.0 + np.random.default_rng(4).normal(0.0, 0.1, 3)
    assert got == pytest.approx(clean * factor, rel=1e-9, abs=1e-12)


def test_sound_is_heard_once_and_logged():
    w = world()
    w.step((0.0, 0.0))
    w.emit_sound()
    assert w.events == [(0.2, "sound", "")]
    assert w.step((0.0, 0.0)).sound
    assert not w.step((0.0, 0.0)).sound


def test_only_active_interventions_act_and_they_are_asked_in_order():
    w = world()
    first = Probe(command=(2.0, 2.0))
    idle = Probe(active=False, command=(-5.0, -5.0))
    second = Probe(command=(1.0, 3.0))
    for p in (first, idle, second):
        w.attach(p)
    w.step((0.5, 0.5))
    # the first turns (0.5, 0.5) into (2, 2), the second is handed (2, 2) and gives (1, 3)
    assert first.calls == ["override 0.5 0.5", "after"]
    assert second.calls == ["override 2 2", "after"]
    assert idle.calls == []
    assert w._last_command == (1.0, 3.0)


def test_an_override_is_limited_like_the_robot_command():
    w = world()
    w.attach(Probe(command=(9.0, 0.1)))
    w.step((0.0, 0.0))
    assert w._last_command == (5.08, 0.0)


def test_the_truth_is_read_again_after_an_intervention_moved_the_robot():
    w = world()
    w.attach(Probe(after=lambda: w.place_robot(20.0, 30.0, 0.5)))
    w.step((4.0, 4.0))
    assert w.truth.pose == pytest.approx((20.0, 30.0, 0.5), abs=1e-12)
    # the speed and odometry are the tick's own motion, before the move
    assert w.truth.speed == pytest.approx(4.0, abs=1e-9)


# -- snapshots ------------------------------------------------------------------------------

def test_a_world_with_obstacles_or_interventions_is_not_saved():
    message = ("a World with obstacles or an attached teacher cannot be saved in a snapshot yet "
               "(remove them first)")
    w = world()
    b = w.add_box((10, 10, 20, 20))
    with refused(message, TypeError):
        w.__snapshot_state__()
    w.remove_obstacle(b)
    p = Probe()
    w.attach(p)
    with refused(message, TypeError):
        w.__snapshot_state__()
    w.detach(p)
    assert w.__snapshot_state__()["t"] == 0.0


def test_a_restored_world_steps_on_bit_for_bit():
    noisy = SensorModel("noisy", (0.0, 90.0, 180.0, -90.0), 2.0, 42.0, 0.05)
    a = World(box(), robot=RobotParams(odometry_noise=0.05), sensors=noisy, dt=0.25,
              substeps=7, seed=11)
    a.step((3.0, 4.0))
    a.step((5.0, 1.0))
    a.emit_sound()
    st = a.__snapshot_state__()
    assert (st["dt"], st["substeps"], st["seed"], st["t"], st["tick"]) == (0.25, 7, 11, 0.5, 2)
    assert st["sound_pending"] and st["last_command"] == (5.0, 1.0)
    b = World.__snapshot_restore__(copy.deepcopy(st))  # as saved and loaded
    assert (b.dt, b.substeps, b.t, b.tick, b.events) == (0.25, 7, 0.5, 2, a.events)
    assert b.seed == 11 and b._last_command == (5.0, 1.0) and b._sound_pending
    assert b.robot == a.robot and b.sensors == a.sensors
    assert b.pose == a.pose and b.truth == a.truth
    assert tuple(b.body.velocity) == tuple(a.body.velocity)
    assert b.body.angular_velocity == a.body.angular_velocity
    assert (b._v, b._omega) == (a._v, a._omega)
    for cmd in ((1.0, 2.0), (0.0, 0.0), (-3.0, 3.0)):
        oa, ob = a.step(cmd), b.step(cmd)
        assert ob.sound == oa.sound and ob.t == oa.t and ob.tick == oa.tick
        assert np.array_equal(ob.ir, oa.ir) and np.array_equal(ob.odometry, oa.odometry)
        assert b.pose == a.pose


def test_a_restore_refuses_a_random_stream_that_is_not_a_generator():
    st = world().__snapshot_state__()
    st["rng"] = np.random.RandomState(0)
    with refused("rng must be a numpy Generator"):
        World.__snapshot_restore__(st)


def test_reset_without_a_seed_goes_on_with_the_noise_stream():
    # Gymnasium's convention: reset() keeps the stream, reset(seed) starts it again; a world
    # made with seed 0 gives the same noise after reset() on every run
    from hippo.sim import World, arenas

    def readings(world: World) -> np.ndarray:
        return np.array([world.step((0.0, 0.0)).ir for _ in range(3)])

    a, b = World(arenas.get("two-rooms"), seed=0), World(arenas.get("two-rooms"), seed=0)
    first = readings(a)
    assert np.array_equal(first, readings(b))
    a.reset(), b.reset()
    again_a, again_b = readings(a), readings(b)
    assert np.array_equal(again_a, again_b)          # reproducible across reset()
    assert not np.array_equal(again_a, first)        # the stream went on: other noise
    assert a.seed == 0
    a.reset(0)
    assert np.array_equal(readings(a), first)        # reset(0) starts the stream again
    # the stream reset() keeps is the world's own generator (reset(5) makes a new one)
    c = World(arenas.get("two-rooms"), seed=5)
    rng = c.rng
    c.reset()
    assert c.rng is rng and c.seed == 5
    c.reset(5)
    assert c.rng is not rng
