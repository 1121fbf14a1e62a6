"""Path integration's rules on hand-made odometry.

A tick's odometry ``(dx, dy, dθ)`` is in the robot frame at the start of the tick:
``x += cos θ dx − sin θ dy``, ``y += sin θ dx + cos θ dy``, ``θ += dθ`` wrapped to (−π, π].
The headings below have cos and sin known by hand (θ = atan2(4, 3): cos 0.6, sin 0.8), so every
expected pose is worked out in the comments.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from hippo.sim.odometry import PathIntegrator

H34 = math.atan2(4.0, 3.0)  # cos 0.6, sin 0.8


def refused(message: str):
    return pytest.raises(ValueError, match="^" + re.escape(message) + "$")


def test_the_default_start_is_the_origin_heading_east():
    assert PathIntegrator().pose == (0.0, 0.0, 0.0)
    pi = PathIntegrator((5.0, -2.0, 1.0))
    pi.reset()
    assert pi.pose == (0.0, 0.0, 0.0)


def test_a_step_forward_goes_along_the_heading():
    pi = PathIntegrator((1.0, 2.0, H34))
    # dx = 5 forward at cos 0.6, sin 0.8: x += 3, y += 4
    x, y, h = pi.step(np.array([5.0, 0.0, 0.0]))
    assert (x, y) == pytest.approx((4.0, 6.0), abs=1e-12)
    assert h == pytest.approx(H34, abs=1e-15)


def test_a_step_sideways_goes_left_of_the_heading():
    pi = PathIntegrator((1.0, 2.0, H34))
    # dy = 5 to the left: x -= sin 5 = 4, y += cos 5 = 3
    x, y, _ = pi.step(np.array([0.0, 5.0, 0.0]))
    assert (x, y) == pytest.approx((-3.0, 5.0), abs=1e-12)


def test_both_parts_add_and_the_turn_comes_after_the_move():
    pi = PathIntegrator((0.0, 0.0, H34))
    # dx = 10, dy = -5: x = 0.6 * 10 + 0.8 * 5 = 10, y = 0.8 * 10 - 0.6 * 5 = 5; the turn of
    # this tick does not rotate its own move
    x, y, h = pi.step(np.array([10.0, -5.0, 0.5]))
    assert (x, y) == pytest.approx((10.0, 5.0), abs=1e-12)
    assert h == pytest.approx(H34 + 0.5, abs=1e-15)
    # the next move uses the turned heading: dx = 2 at H34 + 0.5
    x2, y2, _ = pi.step(np.array([2.0, 0.0, 0.0]))
    assert x2 == pytest.approx(10.0 + 2 * math.cos(H34 + 0.5), abs=1e-12)
    assert y2 == pytest.approx(5.0 + 2 * math.sin(H34 + 0.5), abs=1e-12)


def test_the_heading_is_wrapped_to_minus_pi_pi():
    pi = PathIntegrator((0.0, 0.0, 3.0))
    assert pi.step(np.array([0.0, 0.0, 0.5]))[2] == pytest.approx(3.5 - 2 * math.pi, abs=1e-15)
    pi = PathIntegrator((0.0, 0.0, -3.0))
    assert pi.step(np.array([0.0, 0.0, -0.5]))[2] == pytest.approx(2 * math.pi - 3.5, abs=1e-15)
    pi = PathIntegrator((0.0, 0.0, 0.0))
    assert pi.step(np.array([0.0, 0.0, -math.pi]))[2] == math.pi  # -pi is written pi


def test_step_returns_the_pose_and_the_pose_is_floats():
    pi = PathIntegrator((1, 2, 0))
    assert all(type(v) is float for v in pi.pose)
    got = pi.step([1, 1, 0])
    assert got == pi.pose == (pi.x, pi.y, pi.heading)
    assert got == pytest.approx((2.0, 3.0, 0.0), abs=1e-15)


def test_advance_is_step_on_numbers():
    a, b = PathIntegrator((1.0, 2.0, H34)), PathIntegrator((1.0, 2.0, H34))
    assert a.advance(10.0, -5.0, 0.5) == b.step(np.array([10.0, -5.0, 0.5]))


def test_reset_starts_again_where_asked():
    pi = PathIntegrator()
    pi.step(np.array([3.0, 0.0, 1.0]))
    pi.reset((7.0, 8.0, -1.5))
    assert pi.pose == (7.0, 8.0, -1.5)


def test_refusals_word_for_word():
    with refused("pose must be 3 numbers (x, y, heading), got shape (4,)"):
        PathIntegrator((1.0, 2.0, 3.0, 4.0))
    with refused("pose must be 3 numbers (x, y, heading), got shape (1, 3)"):
        PathIntegrator([[1.0, 2.0, 3.0]])
    with refused("pose contains 1 non-finite value(s) (NaN or inf)"):
        PathIntegrator((1.0, 2.0, math.inf))
    pi = PathIntegrator((1.0, 2.0, 0.5))
    with refused("odometry must be 3 numbers (dx, dy, dtheta), got shape (4,)"):
        pi.step(np.zeros(4))
    with refused("odometry contains 2 non-finite value(s) (NaN or inf)"):
        pi.step(np.array([math.nan, 0.0, -math.inf]))
    with refused("pose must be 3 numbers (x, y, heading), got shape (2,)"):
        pi.reset((0.0, 0.0))
    assert pi.pose == (1.0, 2.0, 0.5)  # a refused reset or step leaves the pose
