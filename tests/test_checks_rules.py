"""The shared input checks (hippo/_checks.py): every refusal word for word, each bound exactly
on its edge and one step past it, what comes back (its type, a copy or the same array), and
the type-hint rules of ``check_fields`` on a dataclass with one field of each kind."""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any, Literal

import numpy as np
import pytest

from hippo._checks import (
    _describe,
    as_array,
    check_array,
    check_choice,
    check_fields,
    check_finite,
    check_int,
    check_observation,
    check_path,
    check_positive,
    check_range,
    check_real,
    check_seed,
    check_shape,
    is_wall_side,
)


def refused(message: str, exc: type[Exception] = ValueError):
    return pytest.raises(exc, match="^" + re.escape(message) + "$")


def test_as_array_names_what_numpy_cannot_read():
    a = [1.0, 2.0]
    np.testing.assert_array_equal(as_array("x", a), a)
    with pytest.raises(ValueError) as e:
        as_array("ragged", [[1, 2], [3]])
    assert str(e.value).startswith("ragged must be an array of numbers, got list that numpy "
                                   "cannot read as one (")


def test_check_finite_names_an_array_numpy_cannot_read():
    with pytest.raises(ValueError) as e:
        check_finite("ragged", [[1.0, 2.0], [3.0]])
    assert str(e.value).startswith("ragged must be an array of numbers, got list that numpy "
                                   "cannot read as one (")


def test_check_observation_names_odometry_that_is_no_numbers():
    from types import SimpleNamespace

    obs = SimpleNamespace(ir=np.zeros(8), t=1.0, odometry=["a", 1, 2], floor=0, sound=False,
                          moving=False)
    with refused("obs.odometry must be (dx, dy, dtheta), got ['a', 1, 2]"):
        check_observation(obs, 8, 0.0)
    obs.odometry = [[0.0, 1.0], [2.0]]
    with refused("obs.odometry must be (dx, dy, dtheta), got [[0.0, 1.0], [2.0]]"):
        check_observation(obs, 8, 0.0)


def test_check_finite_returns_float64_or_the_float32_kept_and_counts_the_bad_values():
    a = np.array([1.0, 2.0])
    assert check_finite("x", a) is a                     # already float64: no copy
    f32 = np.array([1.0, 2.0], np.float32)
    assert check_finite("x", f32, keep_float32=True) is f32
    got = check_finite("x", f32)
    assert got.dtype == np.float64 and got is not f32
    got = check_finite("x", [1, 2])
    assert got.dtype == np.float64 and got.tolist() == [1.0, 2.0]
    # finite values whose sum overflows are finite (numpy warns of the overflow: silenced)
    with np.errstate(over="ignore"):
        assert check_finite("x", [1e308, 1e308]).tolist() == [1e308, 1e308]
    with refused("x contains 2 non-finite value(s) (NaN or inf)"):
        check_finite("x", [1.0, math.nan, -math.inf])
    with refused("x contains 1 non-finite value(s) (NaN or inf)"):
        check_finite("x", np.array([math.inf, 1.0], np.float32), keep_float32=True)
    with refused("x must hold real numbers, got complex values (dtype complex128)"):
        check_finite("x", [1 + 0j])


@pytest.mark.parametrize("bad", [np.array(["a"]), np.array([{}], dtype=object)])
def test_check_finite_refuses_what_is_no_real_number_with_the_conversions_own_error(bad):
    try:
        np.asarray(bad, dtype=float)
    except (TypeError, ValueError) as exc:
        want = exc
    with pytest.raises(type(want)) as e:
        check_finite("x", bad)
    assert type(e.value) is type(want)
    assert str(e.value) == f"x must hold real numbers, got dtype {bad.dtype} ({want})"


def test_check_positive_edges_and_refusals():
    assert check_positive("x", 2.5) == 2.5
    for v in (5, np.float64(2.0), np.int64(3), np.float32(0.5), Fraction(1, 4)):
        got = check_positive("x", v)
        assert got == float(v) and type(got) is float
    assert check_positive("x", 5e-324) == 5e-324                    # the smallest > 0
    assert check_positive("x", 0.0, allow_zero=True) == 0.0
    assert check_positive("x", 0, allow_zero=True) == 0.0
    for v in (0, 0.0, -1e-300, math.inf, math.nan):
        with refused(f"x must be finite and > 0, got {v!r}"):
            check_positive("x", v)
    for v in (-5e-324, math.inf, -math.inf, math.nan):
        with refused(f"x must be finite and >= 0, got {v!r}"):
            check_positive("x", v, allow_zero=True)


@pytest.mark.parametrize("bad", ["5", "abc", b"1", True, np.bool_(True), None, [1.0], "nan"])
def test_check_positive_and_check_range_take_numbers_only(bad):
    # a string float() reads ("5") and a bool (True = 1) are no numbers; None and a list fail
    # inside float(): each is named the same way
    with refused(f"x must be a number, got {bad!r}"):
        check_positive("x", bad)
    with refused(f"x must be a number, got {bad!r}"):
        check_range("x", bad, 0.0, 10.0)


def test_check_range_on_each_end_of_each_kind_of_interval():
    for closed, lb, rb in (("both", "[", "]"), ("left", "[", ")"), ("right", "(", "]"),
                           ("neither", "(", ")")):
        assert check_range("x", 0.5, 0, 1, closed=closed) == 0.5
        for v, ok in ((0, lb == "["), (1, rb == "]"), (-1e-300, False),
                      (1 + 2**-52, False), (math.nan, False)):
            if ok:
                got = check_range("x", v, 0, 1, closed=closed)
                assert got == v and type(got) is float
            else:
                with refused(f"x must lie in {lb}0, 1{rb}, got {v!r}"):
                    check_range("x", v, 0, 1, closed=closed)
    # an infinite bound: inf itself is still refused (not finite)
    assert check_range("x", 1e308, 0.0, math.inf) == 1e308
    with refused("x must lie in [0.0, inf], got inf"):
        check_range("x", math.inf, 0.0, math.inf)
    assert check_range("x", np.int64(3), 3, 3) == 3.0


def test_check_shape_with_any_size_dims():
    a = np.zeros((3, 2))
    assert check_shape("x", a, (3, 2)) is a
    assert check_shape("x", a, (None, 2)) is a and check_shape("x", a, (None, None)) is a
    got = check_shape("x", [1, 2, 3], (3,))
    assert isinstance(got, np.ndarray) and got.tolist() == [1, 2, 3]
    with refused("x must have shape (*, 3), got (3, 2)"):
        check_shape("x", a, (None, 3))
    with refused("x must have shape (3,), got (3, 2)"):
        check_shape("x", a, (3,))
    with refused("x must have shape (*,), got (1, 3)"):
        check_shape("x", np.zeros((1, 3)), (None,))
    with refused("x must have shape (3, 2, *), got (3, 2)"):
        check_shape("x", a, (3, 2, None))
    with refused("x must have shape (2, 2), got (3, 2)"):
        check_shape("x", a, (2, 2))


def test_check_int_bounds_and_refusals_word_for_word():
    for v in (0, np.int64(7), np.uint8(200), 2**70):
        got = check_int("n", v)
        assert got == v and type(got) is int
    assert check_int("n", 1, lo=1) == 1 and check_int("n", 5, hi=5) == 5
    assert check_int("n", 3, lo=3, hi=3) == 3
    with refused("n must be an integer >= 1, got 0"):
        check_int("n", 0, lo=1)
    with refused("n must be an integer <= 5, got 6"):
        check_int("n", 6, hi=5)
    with refused("n must be an integer in [1, 5], got 0"):
        check_int("n", 0, lo=1, hi=5)
    with refused("n must be an integer in [1, 5], got np.int64(6)"):
        check_int("n", np.int64(6), lo=1, hi=5)
    with refused("n must be an integer in [-2, 0], got -3"):
        check_int("n", -3, lo=-2, hi=0)
    for b in (True, np.bool_(False)):
        with refused(f"n must be an integer, got {b!r} (a bool)"):
            check_int("n", b)
    for v, kind in ((10.0, "float"), ("10", "str"), (None, "NoneType"),
                    (np.float64(2.0), "float64")):
        with refused(f"n must be an integer, got {v!r} ({kind})"):
            check_int("n", v)


def test_check_seed_is_an_integer_in_0_to_2_63_minus_1():
    assert check_seed("seed", 0) == 0
    assert check_seed("seed", 2**63 - 1) == 9223372036854775807
    for v in (-1, 2**63):
        with refused(f"seed must be an integer in [0, 9223372036854775807], got {v}"):
            check_seed("seed", v)


def test_check_path():
    assert check_path("out", "a/b") == Path("a/b")
    assert check_path("out", Path("c")) == Path("c")
    assert check_path("out", ".") == Path(".")

    class Where(os.PathLike):
        def __fspath__(self) -> str:
            return "d/e"
    assert check_path("out", Where()) == Path("d/e")
    for v, kind in ((5, "int"), (None, "NoneType"), (b"x", "bytes")):
        with refused(f"out must be a path (str or os.PathLike), got {kind}", TypeError):
            check_path("out", v)
    with refused("out must not be an empty path (use '.' for the current folder)"):
        check_path("out", "")


def test_check_choice_compares_values_of_the_same_type():
    assert check_choice("mode", "b", ("a", "b")) == "b"
    assert check_choice("n", 2, iter([1, 2])) == 2               # any iterable, read once
    with refused("mode must be one of 'a', 'b'; got 'c'"):
        check_choice("mode", "c", ["a", "b"])
    for v in (True, 1.0, np.int64(1)):
        with refused(f"n must be one of 1, 2; got {v!r}"):
            check_choice("n", v, [1, 2])


def test_check_real_and_is_wall_side():
    for v in (1, 2.5, np.float32(0.5), np.int64(-3), Fraction(1, 2)):
        got = check_real("x", v)
        assert got == float(v) and type(got) is float
    for v, kind in ((True, "bool"), (np.bool_(False), "bool"), ("1", "str"), (None, "NoneType"),
                    (1j, "complex")):
        with refused(f"x must be a real number, got {v!r} ({kind})"):
            check_real("x", v)
    for v in (math.inf, -math.inf, math.nan):
        with refused(f"x must be finite, got {v!r}"):
            check_real("x", v)
    for v in (-1, 1, np.int64(1), np.int8(-1)):
        assert is_wall_side(v) is True
    for v in (0, 2, -2, True, np.bool_(True), 1.0, -1.0, "1", None):
        assert is_wall_side(v) is False


def test_check_array_kinds_shapes_finiteness_and_magnitude():
    got = check_array("x", [1, 2])
    assert got.dtype == np.float64 and got.tolist() == [1.0, 2.0]
    got = check_array("x", np.array([1, 2], np.uint8), dtype="int")
    assert got.dtype == np.int64 and got.tolist() == [1, 2]
    b = np.array([True, False])
    got = check_array("x", b, dtype="bool")
    assert got.dtype == bool and got.tolist() == [True, False] and got is not b
    assert check_array("x", b, dtype="bool", max_abs=0.5).tolist() == [True, False]
    with refused("x must hold real numbers, got dtype <U1"):
        check_array("x", ["a"])
    with refused("x must hold real numbers, got dtype bool"):
        check_array("x", b)
    with refused("x must hold integers, got dtype float64"):
        check_array("x", [1.0], dtype="int")
    with refused("x must hold integers, got dtype bool"):
        check_array("x", b, dtype="int")
    with refused("x must hold booleans, got dtype int64"):
        check_array("x", np.array([1]), dtype="bool")
    with refused("x must have shape (*, 2), got (3,)"):
        check_array("x", [1, 2, 3], shape=(None, 2))
    with refused("x contains 2 non-finite value(s) (NaN or inf)"):
        check_array("x", [math.nan, 1.0, math.inf])
    assert np.isnan(check_array("x", [math.nan], finite=False)[0])
    # magnitude: exactly max_abs is taken, the next float beyond it is not
    assert check_array("x", [-10.0, 3.0], max_abs=10.0).tolist() == [-10.0, 3.0]
    with refused("x holds a value of magnitude 10, beyond 10: no fit produces it"):
        check_array("x", [1.0, -np.nextafter(10.0, 11.0)], max_abs=10.0)
    with refused("x holds a value of magnitude 1.23e+04, beyond 100: no fit produces it"):
        check_array("x", np.array([12345]), dtype="int", max_abs=100)
    assert check_array("x", np.zeros(0), max_abs=1.0).size == 0


@dataclass
class _Sub:
    a: int = 0


@dataclass
class _Spec:
    n: int = 1
    x: float = 1.0
    flag: bool = False
    name: str = "a"
    mode: Literal["a", "b"] = "a"
    level: Literal[1, 2] = 1
    opt: int | None = None
    pair: tuple[int, str] = (1, "a")
    triple: tuple[float, float, float] = (0.0, 0.0, 0.0)
    many: tuple[float, ...] = ()
    sub: _Sub | None = None
    nothing: None = None
    seed: int | None = None
    anything: Any = None

    def __post_init__(self) -> None:
        check_fields(self)


def test_check_fields_takes_each_field_of_its_hint():
    s = _Spec(n=np.int64(2), x=3, flag=np.bool_(True), mode="b", level=2, opt=4,
              pair=(np.int64(2), "b"), triple=(1, 2.5, np.float32(3.0)), many=(1.0, 2, 3.5),
              sub=_Sub(), seed=0, anything=object())
    assert s.n == 2 and s.seed == 0
    assert _Spec(seed=2**63 - 1).seed == 2**63 - 1


@pytest.mark.parametrize(("field", "value", "want"), [
    ("n", 1.5, "an integer"), ("n", True, "an integer"),
    ("x", math.nan, "a finite real number"), ("x", True, "a finite real number"),
    ("x", "1", "a finite real number"),
    ("flag", 1, "a bool"), ("name", 3, "a string"),
    ("mode", "c", "one of 'a', 'b'"), ("level", True, "one of 1, 2"),
    ("level", 1.0, "one of 1, 2"),
    ("opt", "x", "an integer or None"),
    ("pair", ("a", 1), "a tuple (an integer, a string)"),
    ("pair", (1, 2), "a tuple (an integer, a string)"),
    ("pair", (1,), "a tuple (an integer, a string)"),
    ("pair", [1, "a"], "a tuple (an integer, a string)"),
    ("triple", (0.0, 0.0), "a tuple (a finite real number, a finite real number, "
                           "a finite real number)"),
    ("triple", (0.0, math.nan, 0.0), "a tuple (a finite real number, a finite real number, "
                                     "a finite real number)"),
    ("many", (1.0, "x"), "a tuple of a finite real number"),
    ("sub", 3, "_Sub or None"), ("nothing", 0, "None"),
    ("seed", 1.0, "an integer or None"),
])
def test_check_fields_names_the_class_field_value_and_what_is_allowed(field, value, want):
    with refused(f"_Spec.{field} must be {want}, got {value!r} ({type(value).__name__})"):
        _Spec(**{field: value})


def test_check_fields_checks_a_seed_s_range():
    for v in (-1, 2**63):
        with refused(f"_Spec.seed must be an integer in [0, 9223372036854775807], got {v}"):
            _Spec(seed=v)


def test_check_fields_reads_the_hints_of_a_class_it_has_not_seen():
    # a class made here is new on every run: its hints are read, not found in the cache
    @dataclass
    class Fresh:
        k: int = 0
        r: float = 1.0

        def __post_init__(self) -> None:
            check_fields(self)

    assert Fresh(k=3).k == 3
    with refused("Fresh.k must be an integer, got 0.5 (float)"):
        Fresh(k=0.5)   # type: ignore[arg-type]
    with refused("Fresh.r must be a finite real number, got inf (float)"):
        Fresh(r=math.inf)


def test_describe_an_unnamed_hint_by_its_text():
    assert _describe(list[int]) == "list"
    assert _describe("Route") == "Route"
    assert _describe(3) == "3"
    assert _describe(int | str | None) == "an integer or a string or None"
    assert _describe(tuple[tuple[int, ...], bool]) == "a tuple (a tuple of an integer, a bool)"
