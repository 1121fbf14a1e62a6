"""check_observation (the per-tick check of what the robot senses) refuses exactly what the
plain rule refuses: readings outside [0, 1] or not finite, wherever they sit (min and max may
pass over a NaN: the sum catches it), odometry with a non-finite value, flags that are no
bools."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hippo._checks import check_observation
from hippo.types import Observation


def _obs(ir, odo=(0.1, 0.0, 0.01), sound=False, moving=True) -> Observation:
    return Observation(1.0, 5, np.asarray(ir, dtype=float), 0, sound, np.asarray(odo), moving)


def _plain_ok(ir: list[float]) -> bool:
    return all(0.0 <= v <= 1.0 for v in ir)


BAD = [math.nan, math.inf, -math.inf, -1e-12, 1.0 + 1e-12, -0.5, 2.0]
GOOD = [0.0, -0.0, 1.0, 0.5, 5e-324]


@pytest.mark.parametrize("pos", range(8))
@pytest.mark.parametrize("value", BAD + GOOD)
def test_readings_are_refused_as_the_plain_rule_refuses_them(pos: int, value: float):
    rng = np.random.default_rng(pos)
    for base in (rng.random(8), np.zeros(8), np.ones(8)):
        ir = base.copy()
        ir[pos] = value
        if _plain_ok(ir.tolist()):
            got, t = check_observation(_obs(ir), 8, 0.0)
            assert got is not None and t == 1.0
        else:
            with pytest.raises(ValueError, match=r"obs\.ir readings must be finite and in"):
                check_observation(_obs(ir), 8, 0.0)


def test_two_nans_and_a_nan_among_extremes_are_refused():
    for ir in ([0.0, math.nan, 1.0, 0.5, 0.5, 0.5, 0.5, math.nan],
               [math.nan] * 8, [1.0, 0.0, math.nan, 0.0, 1.0, 0.0, 1.0, 0.0]):
        with pytest.raises(ValueError, match=r"obs\.ir readings"):
            check_observation(_obs(ir), 8, 0.0)


@pytest.mark.parametrize("pos", range(3))
@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_odometry_with_a_non_finite_value_is_refused(pos: int, value: float):
    odo = [0.1, -0.2, 0.01]
    odo[pos] = value
    with pytest.raises(ValueError, match=r"obs\.odometry must be 3 finite numbers"):
        check_observation(_obs(np.full(8, 0.5), odo=odo), 8, 0.0)
    check_observation(_obs(np.full(8, 0.5), odo=[1e308, -1e308, 1e308]), 8, 0.0)  # finite


def test_flags_must_be_bools():
    ir = np.full(8, 0.5)
    for ok in (True, False, np.True_, np.False_):
        check_observation(_obs(ir, sound=ok, moving=ok), 8, 0.0)
    for bad in (1, 0, 1.0, None, "yes"):
        with pytest.raises(ValueError, match=r"obs\.sound must be True or False"):
            check_observation(_obs(ir, sound=bad), 8, 0.0)
        with pytest.raises(ValueError, match=r"obs\.moving must be True or False"):
            check_observation(_obs(ir, moving=bad), 8, 0.0)


def test_check_finite_takes_a_float64_array_as_it_is_and_converts_the_rest():
    """The per-tick case (a native float64 ndarray) is returned as is, other inputs as before:
    float32 made float64 unless kept, big-endian made native, lists and ints converted; NaN or
    inf refused with their count either way."""
    from hippo._checks import check_finite
    a = np.linspace(0.0, 1.0, 5)
    assert check_finite("x", a) is a
    f32 = a.astype(np.float32)
    assert check_finite("x", f32).dtype == np.float64
    assert check_finite("x", f32, keep_float32=True) is f32
    be = a.astype(">f8")
    got = check_finite("x", be)
    assert got.dtype == np.float64 and got.dtype.isnative and np.array_equal(got, a)
    assert check_finite("x", [1, 2]).dtype == np.float64
    assert check_finite("x", np.arange(3)).dtype == np.float64
    for bad in (a.copy(), be.copy(), [0.0, 1.0, 2.0, 3.0, 4.0]):
        bad[1], bad[3] = math.nan, math.inf
        with pytest.raises(ValueError, match="x contains 2 non-finite"):
            check_finite("x", bad)


def test_a_wall_side_is_the_integer_minus_one_or_plus_one():
    from hippo._checks import is_wall_side

    for side in (-1, 1, np.int64(-1), np.int8(1)):
        assert is_wall_side(side)
    # equal to 1 or -1, but no side: a bool, a float, a numpy bool; and every other integer
    for other in (True, np.bool_(True), 1.0, -1.0, 0, 2, -2, "1", None):
        assert not is_wall_side(other)


def test_every_place_that_takes_a_wall_side_refuses_in_the_same_words():
    from hippo._checks import check_wall_side
    from hippo.motor import MotorParams

    assert check_wall_side("side", np.int64(1)) == 1
    assert type(check_wall_side("side", np.int64(1))) is int
    assert check_wall_side("side", None, none_ok=True) is None
    with pytest.raises(ValueError) as e:
        check_wall_side("side", None)
    assert str(e.value) == "side must be -1 (right wall) or +1 (left wall), got None"
    with pytest.raises(ValueError) as e:
        check_wall_side("side", 0.5, none_ok=True)
    assert str(e.value) == "side must be -1 (right wall), +1 (left wall) or None, got 0.5"
    # the motor's field (True and 1.0 are refused by type first, as every integer field's)
    assert MotorParams(wall_side=np.int64(1)).wall_side == 1
    for bad in (0, 2, -2):
        with pytest.raises(ValueError) as e:
            MotorParams(wall_side=bad)
        assert str(e.value) == f"wall_side must be -1 (right wall) or +1 (left wall), got {bad}"
    with pytest.raises(ValueError, match=r"^MotorParams.wall_side must be an integer, got True"):
        MotorParams(wall_side=True)
