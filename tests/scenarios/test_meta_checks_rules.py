"""The saved meta's field checks (:mod:`hippo.scenarios._meta_checks`) on hand-made meta dicts:
how a field is named, what is a finite number, whole numbers exactly on each bound and one
step past it (JSON's ``3.0`` taken, ``2.5`` refused), the numbers and choices through
:mod:`hippo._checks`, every refusal word for word."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hippo.scenarios._meta_checks import (
    bad_field,
    check_number,
    check_option,
    check_whole,
    field,
    finite,
)


def test_a_field_is_named_as_the_snapshots_meta_key():
    assert field("seed") == "the snapshot's meta seed"
    assert field("explore_min") == "the snapshot's meta explore_min"


def test_finite_is_a_finite_int_or_float_and_not_a_bool():
    for v in (0, -3, 2**70, 0.0, -0.0, 5e-324, 1.7976931348623157e308, np.float64(2.5)):
        assert finite(v) is True, v
    for v in (True, False, math.inf, -math.inf, math.nan, "3", None, [1], 1j,
              np.float64(math.nan)):
        assert finite(v) is False, v


def test_an_integer_past_the_floats_range_is_not_finite():
    # JSON holds any integer; 2**1024 is past the largest float (2 - 2**-52) * 2**1023
    assert finite(2**1023) is True and finite(-(2**1023)) is True
    for v in (2**1024, -(2**1024), 10**400):
        assert finite(v) is False
    big = 10**400
    with pytest.raises(ValueError) as e:
        check_whole({"seed": big}, "seed", (0, 2**32 - 1))
    assert str(e.value) == (f"the snapshot's meta seed={big!r} is not a whole number in "
                            "[0, 4294967295]")
    for v in (2**1024, -(2**1024)):
        with pytest.raises(ValueError) as e:
            check_number({"explore_min": v}, "explore_min", (5.0, 600.0))
        assert str(e.value) == (f"the snapshot's meta explore_min must lie in [5.0, 600.0], "
                                f"got {v!r}")
    # inside the floats' range: refused by the range itself, as the float it reads
    with pytest.raises(ValueError) as e:
        check_number({"explore_min": 2**1023}, "explore_min", (5.0, 600.0))
    assert str(e.value) == ("the snapshot's meta explore_min must lie in [5.0, 600.0], got "
                            "8.98846567431158e+307")


def test_bad_field_names_the_key_its_value_and_what_it_should_be():
    e = bad_field({"units": "24"}, "units", "a whole number in [1, 200]")
    assert isinstance(e, ValueError)
    assert str(e) == "the snapshot's meta units='24' is not a whole number in [1, 200]"


def _whole_refused(v: object, bounds: tuple[int, int] = (1, 200)) -> str:
    with pytest.raises(ValueError) as e:
        check_whole({"units": v}, "units", bounds)
    return str(e.value)


def test_a_whole_number_on_each_bound_is_taken_and_one_past_refused():
    for v in (1, 200, 1.0, 200.0, 24, 24.0, -0.0 + 1):
        assert check_whole({"units": v}, "units", (1, 200)) is None
    assert check_whole({"seed": 0}, "seed", (0, 2**32 - 1)) is None
    assert check_whole({"seed": 2**32 - 1}, "seed", (0, 2**32 - 1)) is None
    assert check_whole({"seed": -0.0}, "seed", (0, 2**32 - 1)) is None
    want = "the snapshot's meta units={!r} is not a whole number in [1, 200]"
    for v in (0, 201, 0.0, 201.0, 1 - 2**-53, 200 + 2**-45, 2.5, 1.5):
        assert _whole_refused(v) == want.format(v), v
    with pytest.raises(ValueError, match=r"^the snapshot's meta seed=4294967296 is not a whole "
                                         r"number in \[0, 4294967295\]$"):
        check_whole({"seed": 2**32}, "seed", (0, 2**32 - 1))
    with pytest.raises(ValueError, match=r"^the snapshot's meta seed=-1 is not"):
        check_whole({"seed": -1}, "seed", (0, 2**32 - 1))


def test_a_whole_number_is_no_bool_text_or_non_finite_value():
    for v in (True, False, "24", None, math.inf, -math.inf, math.nan, [24]):
        assert _whole_refused(v, (0, 200)) == (
            f"the snapshot's meta units={v!r} is not a whole number in [0, 200]"), v


def test_a_number_on_each_bound_is_taken_and_one_step_past_refused():
    for v in (5.0, 600.0, 5, 600, 30.0):
        assert check_number({"explore_min": v}, "explore_min", (5.0, 600.0)) is None
    for v in (np.nextafter(5.0, 0.0), np.nextafter(600.0, 1e9), 0.0, -30.0):
        with pytest.raises(ValueError) as e:
            check_number({"explore_min": float(v)}, "explore_min", (5.0, 600.0))
        assert str(e.value) == (f"the snapshot's meta explore_min must lie in [5.0, 600.0], "
                                f"got {float(v)!r}")


def test_a_number_is_a_real_and_finite_one():
    with pytest.raises(ValueError) as e:
        check_number({"explore_min": "30"}, "explore_min", (5.0, 600.0))
    assert str(e.value) == "the snapshot's meta explore_min must be a real number, got '30' (str)"
    with pytest.raises(ValueError) as e:
        check_number({"explore_min": True}, "explore_min", (5.0, 600.0))
    assert str(e.value) == ("the snapshot's meta explore_min must be a real number, got True "
                            "(bool)")
    with pytest.raises(ValueError) as e:
        check_number({"explore_min": math.inf}, "explore_min", (5.0, 600.0))
    assert str(e.value) == "the snapshot's meta explore_min must be finite, got inf"


def test_an_option_is_one_of_its_choices_of_the_same_type():
    assert check_option({"place_cells": "learned"}, "place_cells",
                        ("learned", "ground-truth")) is None
    assert check_option({"place_cells": "ground-truth"}, "place_cells",
                        ("learned", "ground-truth")) is None
    with pytest.raises(ValueError) as e:
        check_option({"place_cells": "Learned"}, "place_cells", ("learned", "ground-truth"))
    assert str(e.value) == ("the snapshot's meta place_cells must be one of 'learned', "
                            "'ground-truth'; got 'Learned'")
    with pytest.raises(ValueError) as e:
        check_option({"quick": 1}, "quick", (False, True))
    assert str(e.value) == "the snapshot's meta quick must be one of False, True; got 1"
