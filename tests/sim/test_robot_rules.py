"""The robot's rules on hand-worked cases: the sensor models' and RobotParams' refusals word for
word (each bound on its edge and one step past), the sensor-model lookup, the wheel limits and
the differential drive's kinematics (v = (vl + vr) / 2, omega = (vr - vl) / axle) and its
inverse with the turn capped first.

Every expected number is worked out by hand from those equations (the working is in the
comments); none is copied from a run of the code.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from hippo.sim.robot import (
    IR8,
    MAX_SPEED,
    RAY17,
    SENSOR_MODELS,
    RobotParams,
    SensorModel,
    get_sensor_model,
)


def refused(message: str):
    """pytest.raises(ValueError) on the whole message, word for word."""
    return pytest.raises(ValueError, match="^" + re.escape(message) + "$")


# -- SensorModel ---------------------------------------------------------------------------

def test_sensor_model_range_bounds_on_their_edges():
    # range_min = 0 is allowed (0 <= min), a hair below is not; min == max is refused
    assert SensorModel("m", (0.0,), 0.0, 1.0).range_min == 0.0
    with refused("sensor range must satisfy 0 <= min < max, got [-0.001, 30.0]"):
        SensorModel("m", (0.0,), -0.001, 30.0)
    with refused("sensor range must satisfy 0 <= min < max, got [5.0, 5.0]"):
        SensorModel("m", (0.0,), 5.0, 5.0)
    with refused("sensor range must satisfy 0 <= min < max, got [6.0, 5.0]"):
        SensorModel("m", (0.0,), 6.0, 5.0)
    assert SensorModel("m", (0.0,), 4.999, 5.0).range_max == 5.0


def test_sensor_model_noise_and_rays():
    assert SensorModel("m", (0.0,), noise_sd=0.0).noise_sd == 0.0  # noiseless is allowed
    with refused("sensor noise_sd must be >= 0"):
        SensorModel("m", (0.0,), noise_sd=-1e-9)
    with refused("a sensor model needs at least one ray"):
        SensorModel("m", ())
    # the defaults: 4-30 cm, noise 0.02
    m = SensorModel("m", (10.0, -20.0, 90.0))
    assert (m.range_min, m.range_max, m.noise_sd) == (4.0, 30.0, 0.02)
    assert m.n == 3
    # degrees to radians by hand: 10° = pi/18, -20° = -pi/9, 90° = pi/2
    np.testing.assert_allclose(m.angles, [math.pi / 18, -math.pi / 9, math.pi / 2], rtol=1e-15)


def test_the_two_built_in_models():
    # SMC09's e-puck: ps0..ps7 clockwise from front-right, 4-30 cm, noise 0.02
    assert IR8.angles_deg == (-17.0, -46.0, -90.0, -152.0, 152.0, 90.0, 46.0, 17.0)
    assert (IR8.name, IR8.range_min, IR8.range_max, IR8.noise_sd) == ("ir8", 4.0, 30.0, 0.02)
    # ICANN09: 17 rays 11.25° apart over -90..90, 4-50 cm, noise 0.01
    assert RAY17.angles_deg == tuple(-90.0 + 11.25 * i for i in range(17))
    assert (RAY17.name, RAY17.range_min, RAY17.range_max, RAY17.noise_sd) == (
        "ray17", 4.0, 50.0, 0.01)
    assert SENSOR_MODELS == {"ir8": IR8, "ray17": RAY17}


def test_get_sensor_model_by_name_by_object_and_its_refusals():
    assert get_sensor_model("ir8") is IR8
    assert get_sensor_model("ray17") is RAY17
    own = SensorModel("own", (0.0, 45.0))
    assert get_sensor_model(own) is own  # passed through, not looked up by its name
    with refused("unknown sensor model 'IR8'; choose from ir8, ray17"):
        get_sensor_model("IR8")
    with refused("sensors must be a sensor model name (ir8, ray17) or a SensorModel, got 8"):
        get_sensor_model(8)  # type: ignore[arg-type]
    with refused("sensors must be a sensor model name (ir8, ray17) or a SensorModel, "
                 "got None"):
        get_sensor_model(None)  # type: ignore[arg-type]


# -- RobotParams ---------------------------------------------------------------------------

def test_robot_params_defaults_are_the_e_puck():
    r = RobotParams()
    assert (r.radius, r.axle, r.mass, r.speed_min, r.speed_max) == (3.7, 5.3, 0.15, 0.198, 5.08)
    assert (r.odometry_noise, r.moving_threshold) == (0.0, 0.3)
    assert MAX_SPEED == 1000.0


@pytest.mark.parametrize("name", ["radius", "axle", "mass", "speed_max"])
def test_each_size_must_be_finite_and_positive(name):
    for bad in (0.0, -1.0, -math.ulp(0.0)):
        with refused(f"RobotParams.{name} must be > 0, got {bad}"):
            RobotParams(**{name: bad})
    # NaN and inf are refused first, by the field check (a float field takes finite numbers)
    for bad in (math.nan, math.inf):
        with refused(f"RobotParams.{name} must be a finite real number, got {bad} (float)"):
            RobotParams(**{name: bad})
    # a tiny positive value passes this check (speed_max then needs speed_min below it)
    extra = {"speed_min": 0.0} if name == "speed_max" else {}
    assert getattr(RobotParams(**{name: 1e-6}, **extra), name) == 1e-6


def test_speed_max_bound_on_its_edge_and_one_step_past():
    assert RobotParams(speed_max=MAX_SPEED).speed_max == 1000.0
    with refused("RobotParams.speed_max must be <= 1000 cm/s, got 1000.5 (the e-puck's is "
                 "5.08)"):
        RobotParams(speed_max=1000.5)


def test_speed_min_bounds():
    assert RobotParams(speed_min=0.0).speed_min == 0.0
    assert RobotParams(speed_min=5.07).speed_min == 5.07  # just below speed_max 5.08
    for bad in (-0.001, 5.08, 6.0):
        with refused("RobotParams needs 0 <= speed_min < speed_max"):
            RobotParams(speed_min=bad)


def test_noise_and_moving_threshold_bounds():
    r = RobotParams(odometry_noise=0.0, moving_threshold=0.0)
    assert (r.odometry_noise, r.moving_threshold) == (0.0, 0.0)
    for kw in ({"odometry_noise": -1e-9}, {"moving_threshold": -1e-9}):
        with refused("RobotParams.odometry_noise and moving_threshold must be >= 0"):
            RobotParams(**kw)


# -- wheel limits --------------------------------------------------------------------------

def test_limit_wheels_clips_stalls_and_keeps_sign_and_order():
    r = RobotParams()  # speed_min 0.198, speed_max 5.08
    assert r.limit_wheels(10.0, -10.0) == (5.08, -5.08)
    assert r.limit_wheels(-7.0, 3.0) == (-5.08, 3.0)  # left stays left
    assert r.limit_wheels(5.08, -5.08) == (5.08, -5.08)  # on the clip: kept
    # exactly speed_min moves, a hair below stalls to 0 (either sign)
    assert r.limit_wheels(0.198, -0.198) == (0.198, -0.198)
    assert r.limit_wheels(0.1979, -0.1979) == (0.0, 0.0)
    assert r.limit_wheels(0.0, 1.0) == (0.0, 1.0)
    # with speed_min 0 a zero command stays 0 and nothing stalls
    assert RobotParams(speed_min=0.0).limit_wheels(0.001, -0.001) == (0.001, -0.001)


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_limit_wheels_refuses_a_non_finite_command(bad):
    r = RobotParams()
    with refused(f"wheel command must be finite, got {bad}"):
        r.limit_wheels(1.0, bad)
    with refused(f"wheel command must be finite, got {bad}"):
        r.limit_wheels(bad, 1.0)


# -- kinematics ----------------------------------------------------------------------------

def test_body_velocity_is_the_differential_drive():
    r = RobotParams(axle=4.0)
    # v = (1 + 3) / 2 = 2; omega = (3 - 1) / 4 = 0.5
    assert r.body_velocity(1.0, 3.0) == (2.0, 0.5)
    # reversed: v = 2, omega = (1 - 3) / 4 = -0.5 (turning right)
    assert r.body_velocity(3.0, 1.0) == (2.0, -0.5)
    # spin in place: v = 0, omega = (2 - (-2)) / 4 = 1
    assert r.body_velocity(-2.0, 2.0) == (0.0, 1.0)
    # the e-puck's axle: omega = (4 - 2) / 5.3
    v, omega = RobotParams().body_velocity(2.0, 4.0)
    assert v == 3.0 and omega == pytest.approx(2.0 / 5.3, rel=1e-15)


def test_wheels_for_inverts_the_drive_within_the_limits():
    r = RobotParams(axle=4.0, speed_max=5.0)
    # omega = 1: half = 0.5 * 1 * 4 = 2 (each wheel differs from v by 2); room = 5 - 2 = 3
    assert r.wheels_for(2.0, 1.0) == (0.0, 4.0)  # v = 2 fits: (2 - 2, 2 + 2)
    assert r.wheels_for(10.0, 1.0) == (1.0, 5.0)  # v capped at room 3: (3 - 2, 3 + 2)
    assert r.wheels_for(-10.0, 1.0) == (-5.0, -1.0)  # v capped at -3
    assert r.wheels_for(3.0, 1.0) == (1.0, 5.0)  # v exactly at the room
    # turn first: omega = 10 asks half = 20, capped at 5; no room left, v = 0
    assert r.wheels_for(4.0, 10.0) == (-5.0, 5.0)
    assert r.wheels_for(4.0, -10.0) == (5.0, -5.0)
    # omega = 2.5 gives half = 5 exactly: the cap, no room
    assert r.wheels_for(1.0, 2.5) == (-5.0, 5.0)
    # straight: both wheels v, up to speed_max
    assert r.wheels_for(4.5, 0.0) == (4.5, 4.5)
    assert r.wheels_for(7.0, 0.0) == (5.0, 5.0)
    # the round trip through body_velocity gives back (v, omega) when nothing is capped
    assert r.body_velocity(*r.wheels_for(1.5, -0.5)) == (1.5, -0.5)
