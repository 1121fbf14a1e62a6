"""scikit-learn's estimator contract on hippo's estimators (scikit-learn is a test dependency).

``clone``, ``get_params``/``set_params`` and pipelines must work on every estimator; scikit-learn's
own ``check_estimator`` suite runs on each, and the checks that do not apply are listed here
with the reason (they are expected to fail; see docs/sklearn.md).
"""

from __future__ import annotations

from dataclasses import fields

import numpy as np
import pytest

sklearn = pytest.importorskip("sklearn")
from sklearn.base import clone  # noqa: E402
from sklearn.pipeline import make_pipeline  # noqa: E402
from sklearn.utils.estimator_checks import parametrize_with_checks  # noqa: E402

from hippo.perception import RCSFAICA, SFA, FastICA, PlacePrototypes  # noqa: E402


def estimators():
    return [RCSFAICA(n_reservoir=30, n_sfa=2, n_ica=2, ica_restarts=2, seed=1),
            SFA(n_components=2), FastICA(n_components=2, n_restarts=2, seed=3),
            PlacePrototypes(n_prototypes=3, seed=2)]


#: checks whose *wording* differs: hippo raises ValueError naming the argument, the value and
#: what is allowed, in its own words; these checks match scikit-learn's own messages
WORDING = {
    name: "hippo refuses this input with a ValueError in its own words; the check matches "
          "scikit-learn's wording"
    for name in ("check_n_features_in_after_fitting", "check_complex_data",
                 "check_estimators_empty_data_messages", "check_fit2d_1sample",
                 "check_fit2d_1feature", "check_fit2d_predict1d")
}
COMMON = {
    **WORDING,
    "check_do_not_raise_errors_in_init_or_set_params":
        "hippo validates parameters when they are set (a frozen dataclass with checks), so a "
        "bad value fails at construction rather than at fit",
    "check_estimator_sparse_tag": "dense arrays only (sensor recordings are dense); sparse "
                                  "input is refused by the shape check, not with a word on "
                                  "sparsity",
    "check_estimator_sparse_array": "dense arrays only (see check_estimator_sparse_tag)",
    "check_estimator_sparse_matrix": "dense arrays only (see check_estimator_sparse_tag)",
}
#: RCSFAICA's input width is a parameter: the reservoir's input weights are built for
#: ``n_inputs`` sensors (8 IR by default); these checks fit on another number of features
FIXED_WIDTH = (
    "check_fit_score_takes_y", "check_estimators_overwrite_params",
    "check_dont_overwrite_parameters", "check_estimators_fit_returns_self",
    "check_readonly_memmap_input", "check_positive_only_tag_during_fit",
    "check_estimators_dtypes", "check_dtype_object", "check_pipeline_consistency",
    "check_estimators_nan_inf", "check_estimators_pickle", "check_f_contiguous_array_estimator",
    "check_transformer_data_not_an_array", "check_transformer_general",
    "check_transformer_preserve_dtypes", "check_methods_sample_order_invariance",
    "check_methods_subset_invariance", "check_dict_unchanged", "check_fit_idempotent",
    "check_fit_check_is_fitted", "check_n_features_in",
)


def expected_failures(estimator) -> dict[str, str]:
    if isinstance(estimator, PlacePrototypes):  # no n_components: one feature is fine
        return {k: v for k, v in COMMON.items() if k != "check_fit2d_1feature"}
    if isinstance(estimator, RCSFAICA):
        return {**COMMON, **dict.fromkeys(FIXED_WIDTH, "n_inputs is fixed at construction "
                                                      "(the reservoir's input weights)")}
    return COMMON


@parametrize_with_checks(estimators(), expected_failed_checks=expected_failures)
def test_sklearn_estimator_checks(estimator, check):
    check(estimator)


@pytest.mark.parametrize("est", estimators(), ids=lambda e: type(e).__name__)
def test_params_are_the_dataclass_fields_and_clone_round_trips(est):
    names = [f.name for f in fields(est.params)]
    assert list(est.get_params()) == names
    assert est.get_params(deep=True) == est.get_params(deep=False)
    twin = clone(est)
    assert twin is not est and type(twin) is type(est)
    assert twin.params == est.params
    # the twin is rebuilt from the parameters alone
    assert type(est)(**est.get_params()).params == est.params


@pytest.mark.parametrize("est", estimators(), ids=lambda e: type(e).__name__)
def test_set_params_chains_checks_names_and_values(est):
    name = "seed" if "seed" in est.get_params() else "n_components"
    old = est.get_params()[name]
    assert est.set_params(**{name: old + 1}) is est
    assert est.get_params()[name] == old + 1
    with pytest.raises(ValueError, match=r"invalid parameter.*'bogus'"):
        est.set_params(bogus=1)
    before = est.get_params()
    first = next(iter(before))
    with pytest.raises(ValueError):
        est.set_params(**{first: -5})  # every first field is a size that must be >= 1
    assert est.get_params() == before  # a refused value leaves the estimator as it was


def test_clone_of_a_fitted_estimator_is_unfitted():
    rng = np.random.default_rng(0)
    X = np.cumsum(rng.normal(size=(400, 4)), axis=0)
    sfa = SFA(n_components=2).fit(X)
    twin = clone(sfa)
    assert hasattr(sfa, "W_") and not hasattr(twin, "W_")
    with pytest.raises(ValueError, match="not fitted"):  # also a RuntimeError, AttributeError
        twin.transform(X)


def test_estimators_compose_in_a_pipeline():
    """SFA then FastICA in scikit-learn's Pipeline equals the two steps by hand."""
    rng = np.random.default_rng(1)
    t = np.arange(2000) * 0.01
    sources = np.c_[np.sin(t), np.sign(np.sin(3.1 * t)), np.cos(0.7 * t)]
    X = sources @ rng.normal(size=(3, 5)) + 0.01 * rng.normal(size=(2000, 5))
    pipe = make_pipeline(SFA(n_components=3), FastICA(n_components=3, seed=0))
    Y = pipe.fit_transform(X)
    by_hand = FastICA(n_components=3, seed=0).fit_transform(SFA(n_components=3).fit_transform(X))
    np.testing.assert_allclose(Y, by_hand, atol=1e-10)
    assert Y.shape == (2000, 3)
    assert pipe.get_params()["sfa__n_components"] == 3  # nested names reach the parameters
