"""scikit-learn's parameter contract (hippo/_estimator.py) on a hand-made estimator.

Toy keeps three fields in a frozen dataclass whose __post_init__ raises a TypeError, a
ValueError or an OverflowError (int(inf)) by the field's value; get_params gives every field
(the stored objects themselves), set_params replaces them through dataclasses.replace, names
unknown ones sorted with the valid ones in field order, and re-raises the dataclass's own
refusal as a ValueError naming the estimator, without a chained cause.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import pytest

from hippo._estimator import NotFittedError, ParamsEstimator


@dataclass(frozen=True)
class ToyParams:
    size: int = 3
    rate: float = 0.5
    names: tuple[str, ...] = field(default=("a",))

    def __post_init__(self) -> None:
        if not isinstance(self.size, int):
            raise TypeError(f"size must be an int, got {self.size!r}")
        if self.size < 1:
            raise ValueError(f"size must be >= 1, got {self.size}")
        if math.isinf(self.rate):
            int(self.rate)          # OverflowError: cannot convert float infinity to integer


class Toy(ParamsEstimator):
    def __init__(self, params: ToyParams | None = None, **overrides: object) -> None:
        self.params = ToyParams(**overrides) if params is None else params
        self.fitted_ = None


def refused(message: str):
    return pytest.raises(ValueError, match="^" + re.escape(message) + "$")


def test_get_params_is_every_field_the_object_stored():
    names = ("x", "y")
    est = Toy(ToyParams(size=7, rate=0.25, names=names))
    got = est.get_params()
    assert got == {"size": 7, "rate": 0.25, "names": ("x", "y")}
    assert list(got) == ["size", "rate", "names"] and got["names"] is names
    assert est.get_params(deep=False) == got
    twin = Toy(**got)
    assert twin.params == est.params and twin is not est


def test_set_params_replaces_fields_and_returns_self():
    est = Toy()
    before = est.params
    assert est.set_params(size=4, names=("b",)) is est
    assert est.params == ToyParams(size=4, rate=0.5, names=("b",))
    assert before == ToyParams()                    # a new dataclass, the old one untouched
    assert est.set_params() is est and est.params == ToyParams(size=4, rate=0.5, names=("b",))


def test_unknown_parameters_are_named_sorted_word_for_word():
    est = Toy()
    with refused("invalid parameter(s) ['alpha', 'zeta'] for Toy; "
                 "valid parameters: size, rate, names"):
        est.set_params(zeta=1, size=2, alpha=3)
    assert est.params == ToyParams()                # nothing set, not even size


def test_the_dataclass_refusals_come_back_as_value_errors_naming_the_estimator():
    est = Toy(size=2)
    cases = [({"size": 0}, "size must be >= 1, got 0"),
             ({"size": "3"}, "size must be an int, got '3'"),
             ({"rate": math.inf}, "cannot convert float infinity to integer")]
    for kw, why in cases:
        with refused(f"invalid value for Toy: {why}") as caught:
            est.set_params(**kw)
        assert caught.value.__cause__ is None and caught.value.__suppress_context__
        assert est.params == ToyParams(size=2)
    assert est.set_params(size=1).params.size == 1   # the edge itself is taken


def test_a_fitted_estimator_keeps_its_fitted_attributes():
    est = Toy()
    est.fitted_ = [1.0]
    est.set_params(rate=0.75)
    assert est.fitted_ == [1.0] and est.params.rate == 0.75


def test_not_fitted_is_a_runtime_value_and_attribute_error():
    err = NotFittedError("fit first")
    assert isinstance(err, RuntimeError) and isinstance(err, ValueError)
    assert isinstance(err, AttributeError) and str(err) == "fit first"


def test_the_sklearn_tags_say_a_dense_2d_float_transformer():
    tags = Toy().__sklearn_tags__()
    assert tags.estimator_type is None
    assert tags.target_tags.required is False
    assert tags.transformer_tags is not None
    assert tags.transformer_tags.preserves_dtype == ["float64"]
    assert tags.input_tags.two_d_array is True
    assert tags.classifier_tags is None and tags.regressor_tags is None
