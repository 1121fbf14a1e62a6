import math

import numpy as np
import pytest

from hippo.io import CorruptFileError
from hippo.sim import (
    ArenaBuilder,
    PathIntegrator,
    Recording,
    RobotParams,
    SensorModel,
    Teacher,
    WallFollower,
    WallFollowerParams,
    World,
    arenas,
    record,
)
from hippo.sim.controllers import GoToHeading

EXACT8 = SensorModel("exact8", (-17.0, -46.0, -90.0, -152.0, 152.0, 90.0, 46.0, 17.0), 4.0, 30.0,
                     0.0)


def box(w=100.0, h=100.0):
    return ArenaBuilder("box", w, h).outer_walls().start(w / 2, h / 2).build()


@pytest.mark.parametrize("dist,heading", [(10.0, 0.0), (15.0, 0.0), (20.0, 0.3), (12.0, -0.2)])
def test_sensor_reading_equals_analytic_distance(dist, heading):
    arena = box()
    world = World(arena, sensors=EXACT8, seed=0)
    # robot centre at `dist` from the right wall (x = 100), walls are 0.5 cm thick (radius)
    x = 100.0 - 0.5 - dist
    world.reset(0, pose=(x, 50.0, heading))
    d = world.ray_distances()
    r = world.robot.radius
    for k, a in enumerate(np.deg2rad(EXACT8.angles_deg)):
        phi = heading + a
        if math.cos(phi) <= 0.05:
            continue  # this ray looks away from the right wall
        sx = x + r * math.cos(phi)
        sy = 50.0 + r * math.sin(phi)
        expect = (99.5 - sx) / math.cos(phi)
        if not (0 <= sy + expect * math.sin(phi) <= 100):
            continue  # would hit the top or bottom wall first
        expect = min(expect, 30.0)
        assert d[k] == pytest.approx(expect, abs=1e-6)
        u = world.sense()[k]
        assert u == pytest.approx(np.clip((expect - 4) / 26, 0, 1), abs=1e-6)


def test_readings_are_scaled_and_clipped():
    world = World(box(), sensors=EXACT8, seed=0)
    world.reset(0, pose=(50, 50, 0))
    assert np.all(world.sense() == 1.0)  # nothing within 30 cm in the middle of a 1 m box
    world.reset(0, pose=(99.5 - 3.7 - 1.0, 50, 0))  # 1 cm from the wall: closer than 4 cm
    assert world.sense()[0] == 0.0 and world.sense()[7] == 0.0


def _min_clearance(arena, xs, ys):
    return min(arena.distance_to_walls(x, y) for x, y in zip(xs, ys))


@pytest.mark.parametrize("speed_factor", [1.0, 10.0])
@pytest.mark.parametrize("arena_name", ["two-rooms", "maze-e1"])
def test_robot_never_crosses_a_wall(arena_name, speed_factor):
    arena = arenas.get(arena_name)
    robot = RobotParams(speed_max=5.08 * speed_factor)
    for seed in range(3):
        rng = np.random.default_rng(seed)
        world = World(arena, robot=robot, seed=seed)
        xs, ys = [], []
        cmd = np.zeros(2)
        for _ in range(600):
            if rng.random() < 0.1:
                cmd = rng.uniform(-1, 1, 2) * robot.speed_max
            world.step(cmd)
            xs.append(world.truth.pose[0])
            ys.append(world.truth.pose[1])
        # the body (radius 3.7) may be pressed onto a wall (radius 0.5) but never through it
        assert _min_clearance(arena, xs, ys) > robot.radius + arena.wall_radius - 0.75
        assert all(0 < x < arena.width for x in xs) and all(0 < y < arena.height for y in ys)


def test_same_seed_gives_bit_identical_recording():
    a = record("two-rooms", 800, seed=3, progress=False)
    b = record("two-rooms", 800, seed=3, progress=False)
    c = record("two-rooms", 800, seed=4, progress=False)
    np.testing.assert_array_equal(a.sensors, b.sensors)
    np.testing.assert_array_equal(a.x, b.x)
    assert not np.array_equal(a.sensors, c.sensors)


def test_odometry_integrates_true_motion_in_free_space():
    world = World(box(300, 300), seed=0)
    obs = world.reset(0, pose=(150, 150, 0.4))
    pi = PathIntegrator(world.truth.pose)
    assert obs.t == world.truth.t == 0.0
    for k in range(150):
        left, right = 3.0 + 2 * math.sin(k / 20), 3.0 + 2 * math.cos(k / 15)
        obs = world.step((left, right))
        pi.step(obs.odometry)
    x, y, h = world.truth.pose
    assert pi.x == pytest.approx(x, abs=1e-6) and pi.y == pytest.approx(y, abs=1e-6)
    assert math.cos(pi.heading - h) == pytest.approx(1.0, abs=1e-9)


def test_path_integration_refuses_a_bad_pose_or_odometry():
    with pytest.raises(ValueError, match=r"pose contains 1 non-finite"):
        PathIntegrator((math.nan, 0.0, 0.0))
    with pytest.raises(ValueError, match=r"pose must be 3 numbers \(x, y, heading\), got shape"):
        PathIntegrator((1.0, 2.0))
    pi = PathIntegrator((1.0, 2.0, 0.5))
    with pytest.raises(ValueError, match=r"odometry must be 3 numbers \(dx, dy, dtheta\), got "
                                         r"shape \(2,\)"):
        pi.step(np.array([1.0, 0.0]))
    with pytest.raises(ValueError, match="odometry contains 1 non-finite"):
        pi.step(np.array([1.0, np.inf, 0.0]))
    assert pi.pose == (1.0, 2.0, 0.5)  # unchanged by the refused steps


def test_differential_drive_kinematics():
    world = World(box(300, 300), seed=0)
    world.reset(0, pose=(150, 150, 0.0))
    obs = world.step((4.0, 4.0))  # straight: 4 cm/s for 0.2 s
    assert world.truth.pose[0] - 150 == pytest.approx(0.8, abs=1e-3)
    world.reset(0, pose=(150, 150, 0.0))
    obs = world.step((-2.0, 2.0))  # spin in place: omega = 4 / 5.3 rad/s
    assert world.truth.pose[2] == pytest.approx(0.2 * 4.0 / 5.3, abs=1e-3)
    assert math.hypot(world.truth.pose[0] - 150, world.truth.pose[1] - 150) < 1e-3
    assert not obs.moving


def test_wheel_limits():
    r = RobotParams()
    assert r.limit_wheels(10.0, -10.0) == (5.08, -5.08)
    assert r.limit_wheels(0.1, -0.15) == (0.0, 0.0)  # below 0.198 cm/s the stepper stalls
    left, right = r.wheels_for(5.0, 1.0)
    assert max(abs(left), abs(right)) <= 5.08 + 1e-12
    assert (right - left) / r.axle == pytest.approx(1.0)


def test_wall_follower_visits_both_rooms():
    rec = record("two-rooms", 6000, seed=0, rho=0.008, progress=False)
    occupancy = {n: np.mean(rec.region == i) for i, n in enumerate(rec.region_names)}
    assert occupancy["room_a"] > 0.1 and occupancy["room_b"] > 0.1 and occupancy["corridor"] > 0
    changes = np.sum(np.diff(rec.region[rec.region != 1]) != 0)
    assert changes >= 4


def test_wall_follower_switches_and_loops():
    ctrl = WallFollower(WallFollowerParams(rho=0.008), rng=1)
    record("two-rooms", 2000, seed=1, controller=ctrl, progress=False)
    assert 5 <= ctrl.switches <= 35  # expected 16 switches in 2000 ticks at rho = 0.008


def test_wall_follower_covers_most_of_the_maze():
    rec = record("maze-e1", 20000, seed=0, rho=0.0, sensors="ray17", progress=False)
    assert len(np.unique(rec.label)) >= 56


def test_block_stops_the_robot_and_it_resumes():
    arena = arenas.two_rooms()
    world = World(arena, seed=0)
    obs = world.reset(0)
    ctrl = WallFollower(WallFollowerParams(rho=0.0), rng=0)
    for _ in range(50):
        obs = world.step(ctrl.act(obs))
    teacher = Teacher(world)
    teacher.block(6.0)
    x0, y0, _ = world.truth.pose
    speeds = []
    for _ in range(25):  # 5 s of block
        obs = world.step(ctrl.act(obs))
        speeds.append(world.truth.speed)
    assert math.hypot(world.truth.pose[0] - x0, world.truth.pose[1] - y0) < 3.0
    assert not obs.moving
    for _ in range(30):
        obs = world.step(ctrl.act(obs))
    assert not teacher.blocking
    assert any(k == "block_end" for _, k, _ in world.events)
    assert math.hypot(world.truth.pose[0] - x0, world.truth.pose[1] - y0) > 5.0 and obs.moving


def test_leash_leads_to_waypoints_and_releases():
    arena = arenas.patrol_course()
    world = World(arena, seed=0)
    world.reset(0)
    teacher = Teacher(world)
    teacher.lead(arenas.loop_waypoints()[:5])
    for _ in range(800):
        world.step((0.0, 0.0))  # the robot's own command is overridden
        if not teacher.leading:
            break
    assert not teacher.leading
    tx, ty = arenas.loop_waypoints()[4]
    assert math.hypot(world.truth.pose[0] - tx, world.truth.pose[1] - ty) < 4.0


def test_sound_appears_once_in_next_observation():
    world = World(box(), seed=0)
    world.reset(0)
    Teacher(world).sound()
    assert world.step((0, 0)).sound
    assert not world.step((0, 0)).sound


def test_floor_colour_sensor():
    arena = arenas.goal_arena()
    world = World(arena, seed=0)
    gx, gy = arena.landmarks["goal"]
    obs = world.reset(0, pose=(gx, gy, 0.0))
    assert obs.floor == 1
    obs = world.reset(0)
    assert obs.floor == 0


def test_go_to_heading_turns_to_target():
    world = World(box(300, 300), seed=0)
    obs = world.reset(0, pose=(150, 150, 0.0))
    ctl = GoToHeading()
    for _ in range(30):
        obs = world.step(ctl.act(obs, world.truth.pose[2], 2.0))
    assert math.cos(world.truth.pose[2] - 2.0) > 0.99


def test_kidnap_moves_robot_and_logs():
    world = World(arenas.two_rooms(), seed=0)
    world.reset(0)
    world.place_robot(90, 20, 0.0)
    assert world.pose[:2] == pytest.approx((90, 20))
    assert world.events[-1][1] == "kidnap"


def test_recording_round_trip(tmp_path):
    rec = record("two-rooms", 300, seed=0, progress=False,
                 kidnaps=[(100, (90.0, 20.0, 0.0))])
    path = rec.save(tmp_path / "r.npz")
    back = Recording.load(path)
    for name in ("t", "sensors", "x", "y", "heading", "speed", "floor", "label", "region",
                 "event_t", "event_kind", "event_detail"):
        np.testing.assert_array_equal(getattr(back, name), getattr(rec, name))
    assert back.region_names == rec.region_names and back.arena == rec.arena
    assert "kidnap" in back.event_kind


def test_bad_inputs_give_clear_errors(tmp_path):
    world = World(arenas.two_rooms(), seed=0)
    with pytest.raises(ValueError, match="finite"):
        world.step((float("nan"), 1.0))
    with pytest.raises(ValueError, match="finite"):
        world.step((float("inf"), 1.0))
    with pytest.raises(ValueError, match="overlap a wall"):
        world.place_robot(30.0, 10.0, 0.0)  # on room A's right wall
    with pytest.raises(ValueError, match="overlap a wall"):
        world.reset(0, pose=(1.0, 1.0, 0.0))
    with pytest.raises(ValueError, match="unknown arena"):
        arenas.get("three-rooms")
    with pytest.raises(ValueError, match="unknown sensor"):
        World(arenas.two_rooms(), sensors="sonar")
    with pytest.raises(ValueError, match="pair of wheel speeds"):
        world.step(3.0)


def test_corrupt_or_truncated_recording(tmp_path):
    rec = record("two-rooms", 200, seed=0, progress=False)
    path = rec.save(tmp_path / "r.npz")
    data = path.read_bytes()
    trunc = tmp_path / "trunc.npz"
    trunc.write_bytes(data[: len(data) // 2])
    with pytest.raises(CorruptFileError):
        Recording.load(trunc)
    junk = tmp_path / "junk.npz"
    junk.write_bytes(b"not a zip file at all")
    with pytest.raises(CorruptFileError):
        Recording.load(junk)
    other = tmp_path / "other.npz"
    np.savez(other, a=np.zeros(3))
    with pytest.raises(CorruptFileError, match="lacks required"):
        Recording.load(other)
    # a file of another kind is named by its format tag, not by the arrays it lacks
    from hippo.perception import RCSFAICA

    model = RCSFAICA(n_reservoir=20, ica_restarts=1).fit(rec.sensors)
    with pytest.raises(CorruptFileError, match=r"format tag is 'hippo\.perception\.RCSFAICA"):
        Recording.load(model.save(tmp_path / "model.npz"))


def test_failed_save_leaves_nothing(tmp_path):
    from hippo.io import save_npz

    with pytest.raises(TypeError):
        save_npz(tmp_path / "x.npz", {"a": np.array([{"x": 1}], dtype=object)})
    assert list(tmp_path.iterdir()) == []


def test_builder_validation():
    with pytest.raises(ValueError, match="zero length"):
        ArenaBuilder("a", 10, 10).wall((1, 1), (1, 1))
    with pytest.raises(ValueError, match="positive"):
        ArenaBuilder("a", 0, 10)
    with pytest.raises(ValueError, match="not free"):
        ArenaBuilder("a", 50, 50).outer_walls().start(1, 1).build()
    # found by trying inputs nobody listed: each was accepted and failed later, or never
    with pytest.raises(ValueError, match="positive and finite"):
        ArenaBuilder("a", float("nan"), 60)
    b = ArenaBuilder("a", 50, 40)
    with pytest.raises(ValueError, match="outside the 50 x 40 arena"):
        b.region("far", (40, 0, 60, 10))
    with pytest.raises(ValueError, match="x0 < x1"):
        b.zone("goal", (20, 0, 10, 10))
    with pytest.raises(ValueError, match="nx, ny >= 1"):
        b.grid_locations(0, 0)
    with pytest.raises(ValueError, match="location"):
        b.location(float("nan"), 3)
    b.region("left", (0, 0, 25, 40)).grid_locations(2, 2, (0, 0, 50, 40))
    assert b._locations == [(12.5, 10.0), (37.5, 10.0), (12.5, 30.0), (37.5, 30.0)]


def test_builder_refuses_a_non_finite_start_or_landmark():
    # a NaN heading turned the robot's pose NaN in silence (third fuzzing pass)
    for pose in ((50, 50, math.nan), (50, math.inf, 0.0)):
        with pytest.raises(ValueError, match="start pose"):
            ArenaBuilder("b", 100, 100).outer_walls().start(*pose)
    with pytest.raises(ValueError, match="landmark 'goal'"):
        ArenaBuilder("b", 100, 100).outer_walls().landmark("goal", math.nan, 3.0)


def test_arenas_have_their_labelled_locations():
    assert len(arenas.two_rooms().locations) == 25
    assert len(arenas.maze_e1().locations) == 64
    ga = arenas.goal_arena()
    assert ga.geodesic_distance(ga.start_pose[:2], ga.zones[0].rect) < float("inf")
    pc = arenas.patrol_course()
    assert all(pc.is_free(*pc.landmarks[f"checkpoint-{i}"], 6.0) for i in (1, 2, 3))


def test_robot_crosses_goal_zone_well_under_the_reward_delay():
    rec = record("goal-arena", 4000, seed=0, rho=0.0, progress=False)
    runs, n = [], 0
    for f in rec.floor:
        if f == 1:
            n += 1
        elif n:
            runs.append(n)
            n = 0
    assert len(runs) >= 2  # the wall follower's tour passes the goal zone
    assert max(runs) * rec.dt < 0.7 * 7.0  # even at the follower's drifting (slower) speed


def test_obstacles_with_bad_geometry_are_refused_and_leave_the_world_as_it_was():
    """The fourth fuzzing pass: a NaN box aborted the interpreter inside Chipmunk; mass 0 failed
    at the next step; infinite, outside and over-the-robot boxes and empty rings went in."""
    world = World(box(), seed=0)   # the robot stands at (50, 50), radius 3.7
    for rect, kwargs, match in (
            ((math.nan, 0.0, 1.0, 1.0), {}, r"box rect contains 1 non-finite"),
            ((10.0, 10.0, 20.0, 20.0), {"mass": math.nan}, r"box mass must be finite and > 0"),
            ((10.0, 10.0, 20.0, 20.0), {"mass": 0.0}, r"box mass must be finite and > 0"),
            ((0.0, 0.0, math.inf, 1.0), {}, r"non-finite"),
            ((1000.0, 1000.0, 1010.0, 1010.0), {}, r"lies outside the 100 x 100 arena 'box'"),
            ((45.0, 45.0, 55.0, 55.0), {}, r"overlaps the robot at \(50\.0, 50\.0\)"),
            ((52.0, 40.0, 60.0, 60.0), {"movable": False}, r"overlaps the robot"),
            ((20.0, 20.0, 10.0, 30.0), {}, r"has no area"),
            ((10.0, 10.0, 20.0), {}, r"box rect must be \(x0, y0, x1, y1\)")):
        with pytest.raises(ValueError, match=match):
            world.add_box(rect, **kwargs)
    for centre, radius, kwargs, match in (
            ((50.0, 50.0), 0.0, {}, r"ring radius must be finite and > 0"),
            ((50.0, 50.0), math.nan, {}, r"ring radius"),
            ((50.0, 50.0), math.inf, {}, r"ring radius"),
            ((math.nan, 50.0), 5.0, {}, r"ring centre contains 1 non-finite"),
            ((500.0, 50.0), 5.0, {}, r"ring centre \(500\.0, 50\.0\) lies outside"),
            ((50.0, 50.0), 6.0, {"n": 2}, r"ring segments n must be an integer >= 3")):
        with pytest.raises(ValueError, match=match):
            world.add_ring(centre, radius, **kwargs)
    assert world.obstacles == []
    # good ones still go in, and the robot steps on untouched beside them
    world.add_box((10.0, 10.0, 20.0, 20.0), mass=1.5)
    world.add_box((53.8, 40.0, 60.0, 60.0), movable=False)  # 0.1 cm clear of the robot's rim
    world.add_ring((50.0, 50.0), 6.0)
    world.step((0.0, 0.0))
    assert len(world.obstacles) == 3 and world.pose[:2] == pytest.approx((50.0, 50.0))


def test_a_non_finite_heading_is_refused_where_it_is_given():
    """The fourth fuzzing pass: place_robot and reset took an infinite heading, and the next
    step failed with "math domain error"."""
    world = World(box(), seed=0)
    world.step((2.0, 2.0))
    before = world.pose
    for h in (math.inf, -math.inf, math.nan):
        with pytest.raises(ValueError, match="heading must be finite"):
            world.place_robot(30.0, 30.0, h)
        with pytest.raises(ValueError, match="heading must be finite"):
            world.reset(0, pose=(30.0, 30.0, h))
    with pytest.raises(ValueError, match=r"pose must be three numbers \(x, y, heading\)"):
        world.reset(0, pose=(30.0, 30.0))
    # nothing moved, no half-rebuilt world: it steps on from where it was
    assert world.pose == before and world.tick == 1
    world.step((2.0, 2.0))
    assert world.tick == 2 and math.isfinite(world.pose[2])


def test_a_tick_never_needs_more_than_max_substeps():
    """Fifth fuzzing pass: World(dt=1e7) asked for 50.8 million physics substeps per tick and
    RobotParams(speed_max=1e7) took 4 s per step; both are refused, naming the value."""
    from hippo.sim.robot import MAX_SPEED
    from hippo.sim.world import MAX_SUBSTEPS

    arena = arenas.two_rooms()
    for dt in (1e7, 1e308, MAX_SUBSTEPS / 5.08 * 1.01):
        with pytest.raises(ValueError, match=r"dt=.* physics substeps per tick.*dt must be <="):
            World(arena, dt=dt)
    with pytest.raises(ValueError, match=r"substeps must be an integer in \[1, 10000\]"):
        World(arena, substeps=10**9)
    for speed in (1e7, MAX_SPEED * 1.01, math.inf):
        with pytest.raises(ValueError, match=r"RobotParams\.speed_max"):
            RobotParams(speed_max=speed)
    with pytest.raises(ValueError, match=r"dt=11 s needs 1.1e\+04 physics substeps"):
        World(arena, robot=RobotParams(speed_max=MAX_SPEED), dt=11)
    # the settings in use are unchanged: 5 substeps at dt 0.2, more only as travel needs
    assert World(arena).substeps == 5 and World(arena, dt=1.0).substeps == 6
    assert World(arena, dt=1000.0).substeps == 5080


def test_builder_refuses_what_it_had_coerced_or_overwritten():
    """Fifth fuzzing pass: colour=1.5 became 1 and True 1; a landmark far outside the arena,
    a repeated landmark (overwritten), zone or region name, a wall outside the arena and a
    non-string arena name were all accepted."""
    from hippo.sim.flats import random_flat

    def walled():
        return ArenaBuilder("b", 100, 80).outer_walls()

    for colour in (1.5, True, math.nan, "2", 2**70, 0, -1, 256):
        with pytest.raises(ValueError, match="zone 'g' colour must be an integer"):
            walled().zone("g", (1, 1, 5, 5), colour=colour)
    assert walled().zone("g", (1, 1, 5, 5), colour=255).build().zones[0].colour == 255
    with pytest.raises(ValueError, match=r"landmark 'L' \(1000000.0, -5.0\) lies outside"):
        walled().landmark("L", 1e6, -5)
    with pytest.raises(ValueError, match="landmark 'L' is already defined"):
        walled().landmark("L", 1, 5).landmark("L", 2, 2)
    with pytest.raises(ValueError, match="zone 'g' is already defined"):
        walled().zone("g", (1, 1, 5, 5)).zone("g", (6, 6, 9, 9), colour=2)
    with pytest.raises(ValueError, match="region 'r' is already defined"):
        walled().region("r", (1, 1, 5, 5)).region("r", (6, 6, 9, 9))
    with pytest.raises(ValueError, match=r"wall end \(200.0, 0.0\) lies outside the 100 x 80"):
        walled().wall((0, 0), (200, 0))
    with pytest.raises(ValueError, match="wall start"):
        walled().wall((-1, 10), (10, 10))
    for name in (3, None, ""):
        with pytest.raises(ValueError, match="arena name must be a non-empty string"):
            ArenaBuilder(name, 100, 80)
    with pytest.raises(ValueError, match="landmark name must be a non-empty string"):
        walled().landmark(7, 1, 1)
    # every built-in arena and generated flats still build (walls on the edges are inside)
    for name in arenas.ARENAS:
        arenas.get(name)
    for n_rooms, seed in ((2, 0), (3, 5), (6, 1)):
        random_flat(n_rooms, seed)
