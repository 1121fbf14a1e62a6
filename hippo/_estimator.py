"""scikit-learn's parameter contract for hippo's estimators, without depending on scikit-learn.

hippo's estimators keep their hyper-parameters in one frozen dataclass, ``self.params``, and
take them as ``Estimator(params=None, **overrides)``. :class:`ParamsEstimator` exposes every
field of that dataclass as a scikit-learn parameter:

- ``get_params(deep=True)`` returns ``{field: value}`` (each value the very object stored, so
  :func:`sklearn.base.clone` can check that a rebuilt estimator kept it);
- ``set_params(**kw)`` replaces fields (validated by the dataclass) and returns ``self``;
- ``Estimator(**est.get_params())`` rebuilds an unfitted twin, which is what ``clone`` does.

The parameters are flat (``n_reservoir``, ``leak``, ``n_ica``, ...): no estimator holds
another estimator as a parameter, so ``deep`` changes nothing.
"""

from __future__ import annotations

from dataclasses import fields, replace
from typing import Any, TypeVar

E = TypeVar("E", bound="ParamsEstimator")


class NotFittedError(RuntimeError, ValueError, AttributeError):
    """An estimator was used before ``fit`` (a ``RuntimeError``, and a ``ValueError`` and
    ``AttributeError`` like scikit-learn's ``NotFittedError``)."""


class ParamsEstimator:
    """``get_params`` / ``set_params`` over the frozen dataclass ``self.params``."""

    params: Any

    def get_params(self, deep: bool = True) -> dict[str, Any]:
        """The estimator's parameters, ``{name: value}`` (``deep`` is accepted for
        scikit-learn; hippo's parameters hold no nested estimators)."""
        return {f.name: getattr(self.params, f.name) for f in fields(self.params)}

    def set_params(self: E, **params: Any) -> E:
        """Set parameters by name and return ``self`` (the parameter class checks values).

        A fitted estimator keeps its fitted attributes until the next ``fit``, as in
        scikit-learn.
        """
        if not params:
            return self
        valid = [f.name for f in fields(self.params)]
        bad = sorted(set(params) - set(valid))
        if bad:
            raise ValueError(f"invalid parameter(s) {bad} for {type(self).__name__}; "
                             f"valid parameters: {', '.join(valid)}")
        try:
            self.params = replace(self.params, **params)
        except (TypeError, ValueError, OverflowError) as exc:
            raise ValueError(f"invalid value for {type(self).__name__}: {exc}") from None
        return self

    def __sklearn_tags__(self) -> Any:
        """Tags for scikit-learn's estimator checks: an unsupervised transformer on dense 2-D
        float input (imported lazily: scikit-learn is needed only by those checks)."""
        from sklearn.utils import InputTags, Tags, TargetTags, TransformerTags

        return Tags(estimator_type=None, target_tags=TargetTags(required=False),
                    transformer_tags=TransformerTags(preserves_dtype=["float64"]),
                    input_tags=InputTags(two_d_array=True))
