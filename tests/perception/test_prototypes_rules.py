"""The rules of hippo.perception.prototypes on tiny hand-made data: the parameters' bounds
exactly on their edges and one step past, the fit's σ (the median distance of a sample to its
nearest centre) and its floor, empty clusters dropped, the overflow guard exactly at its bound,
the activity equation on hand-set prototypes, recruitment exactly at its threshold and at its
cap, and every refusal of fit, transform, step and load word for word."""

from __future__ import annotations

import math
import re
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from hippo.io import CorruptFileError
from hippo.perception.prototypes import PROTOTYPES_FORMAT, PlacePrototypes, PrototypeParams


def _raises(exc: type[BaseException], msg: str) -> Any:
    """``pytest.raises`` matching the whole message word for word."""
    return pytest.raises(exc, match="^" + re.escape(msg) + "$")


def _hand_set(centres: list[list[float]], sigma: float, **params: Any) -> PlacePrototypes:
    """Prototypes with hand-set centres and σ (as a fit or a load leaves them)."""
    p = PlacePrototypes(PrototypeParams(n_prototypes=len(centres), **params))
    p.centres_, p.sigma_ = np.array(centres, dtype=float), float(sigma)
    p.n_features_in_ = len(centres[0])
    return p


# --- parameters ---------------------------------------------------------------------------

def test_default_parameters():
    # the docstring's defaults (32 centres, recruitment off, seed 0) and the cap of 256 that
    # docs/robustness.md names
    p = PrototypeParams()
    assert (p.n_prototypes, p.recruit_threshold, p.max_prototypes, p.seed) == (32, 0.0, 256, 0)


def test_parameter_bounds_on_their_edges_and_one_step_past():
    assert PrototypeParams(n_prototypes=1).n_prototypes == 1
    with _raises(ValueError, "n_prototypes must be >= 1, got 0"):
        PrototypeParams(n_prototypes=0)
    assert PrototypeParams(recruit_threshold=0.0).recruit_threshold == 0.0
    below_one = math.nextafter(1.0, 0.0)
    assert PrototypeParams(recruit_threshold=below_one).recruit_threshold == below_one
    with _raises(ValueError, "recruit_threshold must lie in [0, 1), got 1.0"):
        PrototypeParams(recruit_threshold=1.0)
    with _raises(ValueError, "recruit_threshold must lie in [0, 1), got -1e-12"):
        PrototypeParams(recruit_threshold=-1e-12)
    assert PrototypeParams(n_prototypes=5, max_prototypes=5).max_prototypes == 5
    with _raises(ValueError, "max_prototypes (4) must be >= n_prototypes (5)"):
        PrototypeParams(n_prototypes=5, max_prototypes=4)


# --- fit ----------------------------------------------------------------------------------

def test_sigma_is_the_median_distance_to_the_nearest_centre():
    # two groups 100 apart: four points at distance 1 around (0, 0), two at distance 3 around
    # (100, 0). The k-means centres are the groups' means, (0, 0) and (100, 0); the distances
    # to them are 1, 1, 1, 1, 3, 3, whose median is 1 (their mean would be 5/3)
    Y = np.array([[-1, 0], [1, 0], [0, -1], [0, 1], [97, 0], [103, 0]], dtype=float)
    p = PlacePrototypes(PrototypeParams(n_prototypes=2, seed=0)).fit(Y)
    assert sorted(map(tuple, p.centres_.tolist())) == [(0.0, 0.0), (100.0, 0.0)]
    assert p.sigma_ == pytest.approx(1.0, rel=1e-12)
    assert p.n_units == 2 and p.n_features_in_ == 2
    # fit_transform is fit, then the activities of the training outputs:
    # exp(-1 / 2) for the four at distance 1, exp(-9 / 2) for the two at distance 3
    a = PlacePrototypes(PrototypeParams(n_prototypes=2, seed=0)).fit_transform(Y)
    assert a.shape == (6, 2)
    np.testing.assert_allclose(a.max(axis=1), np.exp([-0.5] * 4 + [-4.5] * 2), rtol=1e-12)


def test_empty_clusters_are_dropped_and_sigma_is_floored():
    # two distinct outputs cannot fill three clusters: the centres are the two points, every
    # sample sits on its centre (median distance 0) and σ is floored at 1e-6
    Y = np.array([[0.0, 0.0]] * 5 + [[1.0, 0.0]] * 5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")   # scipy's "One of the clusters is empty"
        p = PlacePrototypes(PrototypeParams(n_prototypes=3, seed=0)).fit(Y)
    assert sorted(map(tuple, p.centres_.tolist())) == [(0.0, 0.0), (1.0, 0.0)]
    assert p.sigma_ == 1e-6 and p.n_units == 2


def test_all_outputs_alike_give_one_prototype_without_a_numpy_warning():
    # k-means++ divides 0 by 0 when every row is alike; fit silences that: one centre, the
    # row itself, σ at its floor (scipy's own "empty cluster" UserWarning may pass)
    Y = np.ones((10, 2))
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        warnings.simplefilter("ignore", UserWarning)
        p = PlacePrototypes(PrototypeParams(n_prototypes=3, seed=0)).fit(Y)
    np.testing.assert_array_equal(p.centres_, [[1.0, 1.0]])
    assert p.sigma_ == 1e-6


def test_exactly_n_prototypes_samples_suffice_one_fewer_is_refused():
    # three samples (of 3 values each), three centres: each sample is its own centre
    Y = np.array([[0.0, 0.0, 1.0], [10.0, 0.0, 1.0], [0.0, 10.0, 1.0]])
    p = PlacePrototypes(PrototypeParams(n_prototypes=3, seed=0)).fit(Y)
    assert sorted(map(tuple, p.centres_.tolist())) == sorted(map(tuple, Y.tolist()))
    with _raises(ValueError, "need at least n_prototypes=3 samples, got 2"):
        PlacePrototypes(PrototypeParams(n_prototypes=3)).fit(Y[:2])


def test_fit_refusals_word_for_word():
    with _raises(ValueError, "Y must have shape (T, d), got (6,)"):
        PlacePrototypes(PrototypeParams(n_prototypes=1)).fit(np.zeros(6))
    with _raises(ValueError, "Y must have shape (T, d), got (2, 3, 2)"):
        PlacePrototypes(PrototypeParams(n_prototypes=1)).fit(np.zeros((2, 3, 2)))
    with _raises(ValueError, "Y must be real numbers, got dtype complex128"):
        PlacePrototypes(PrototypeParams(n_prototypes=1)).fit(np.zeros((4, 2), complex))


def test_the_overflow_guard_sits_exactly_at_its_bound():
    # the largest squared distance between two points of values within ±s in d dimensions is
    # (2 s)² d = 4 s² d; find (numpy floats) the largest s for which it is finite, d = 2
    d = 2
    s = math.sqrt(np.finfo(float).max / (4 * d))
    while math.isfinite(s * s * 4.0 * d):
        s = math.nextafter(s, math.inf)
    over, edge = s, math.nextafter(s, 0.0)
    assert math.isfinite(edge * edge * 4.0 * d) and not math.isfinite(over * over * 4.0 * d)
    # three samples (T != d, so T cannot stand in for d), one centre: its mean (0, 1/3)
    Y = np.array([[edge, 0.0], [-edge, 0.0], [0.0, 1.0]])
    p = PlacePrototypes(PrototypeParams(n_prototypes=1)).fit(Y)
    np.testing.assert_allclose(p.centres_, [[0.0, 1.0 / 3.0]], rtol=1e-12)
    Y = np.array([[over, 0.0], [-over, 0.0], [0.0, 1.0]])
    with _raises(ValueError, f"Y holds values up to {over:.3g}, whose squared distances "
                             "overflow float64; rescale it"):
        PlacePrototypes(PrototypeParams(n_prototypes=1)).fit(Y)
    with _raises(ValueError, f"Y holds values up to {over:.3g}, whose squared distances "
                             "overflow float64; rescale it"):
        PlacePrototypes(PrototypeParams(n_prototypes=1)).fit(-Y)   # |Y|, not Y


# --- transform and step -------------------------------------------------------------------

def test_activity_equation_on_hand_set_prototypes():
    # centres (0, 0) and (3, 4), σ = 2.5: a point at a centre has activity 1, one 5 away
    # exp(-25 / (2 · 6.25)) = exp(-2)
    p = _hand_set([[0.0, 0.0], [3.0, 4.0]], 2.5)
    np.testing.assert_allclose(p.transform(np.array([0.0, 0.0])), [[1.0, np.exp(-2.0)]],
                               rtol=1e-15)
    np.testing.assert_allclose(p.transform(np.array([[3.0, 4.0], [0.0, 0.0]])),
                               [[np.exp(-2.0), 1.0], [1.0, np.exp(-2.0)]], rtol=1e-15)
    np.testing.assert_allclose(p.step(np.array([0.0, 0.0])), [1.0, np.exp(-2.0)], rtol=1e-15)


def test_transform_and_step_refusals_word_for_word():
    p = _hand_set([[0.0, 0.0, 0.0]], 1.0)
    pre = ("place-cell outputs must have shape (3,) or (T, 3) (the dimension the prototypes "
           "were fitted on), got ")
    with _raises(ValueError, pre + "(2,)"):     # the shape given, not the row made of it
        p.transform(np.zeros(2))
    with _raises(ValueError, pre + "(2, 2)"):
        p.transform(np.zeros((2, 2)))
    with _raises(ValueError, pre + "(2, 2, 3)"):
        p.transform(np.zeros((2, 2, 3)))
    with _raises(ValueError, "Y must be real numbers, got dtype complex128"):
        p.transform(np.zeros(3, complex))
    with _raises(ValueError, "place-cell output y must have shape (3,), got (2,)"):
        p.step(np.zeros(2))
    with _raises(ValueError, "place-cell output y must have shape (3,), got (1, 3)"):
        p.step(np.zeros((1, 3)))
    with _raises(ValueError, "place-cell output y must be real numbers, got dtype complex128"):
        p.step(np.zeros(3, complex))
    with _raises(ValueError, "place-cell output y contains 1 non-finite value(s) (NaN or inf)"):
        p.step(np.array([0.0, np.nan, 0.0]))


def test_unfitted_prototypes_are_refused_word_for_word(tmp_path):
    msg = "PlacePrototypes is not fitted; call fit() first"
    p = PlacePrototypes()
    for use in (lambda: p.transform(np.zeros((1, 2))), lambda: p.step(np.zeros(2)),
                lambda: p.n_units, lambda: p.save(tmp_path / "p.npz")):
        with _raises(RuntimeError, msg):
            use()


def test_recruitment_exactly_at_its_threshold():
    # one centre at (0, 0), σ = 1: the output (1, 0) has activity exp(-1 / 2)
    a_edge = float(np.exp(-0.5))
    p = _hand_set([[0.0, 0.0]], 1.0, recruit_threshold=a_edge, max_prototypes=5)
    np.testing.assert_array_equal(p.step(np.array([1.0, 0.0])), [a_edge])   # reached: none
    assert p.n_units == 1
    p = _hand_set([[0.0, 0.0]], 1.0, recruit_threshold=math.nextafter(a_edge, 1.0),
                  max_prototypes=5)
    a = p.step(np.array([1, 0]))                      # just below it: recruited at y
    np.testing.assert_array_equal(a, [a_edge, 1.0])
    np.testing.assert_array_equal(p.centres_, [[0.0, 0.0], [1.0, 0.0]])
    assert p.centres_.dtype == np.float64
    # the new centre is in use from the next output on (its squared norm included): at the
    # origin the two activities are 1 and exp(-1 / 2)
    np.testing.assert_array_equal(p.step(np.array([0.0, 0.0])), [1.0, a_edge])
    np.testing.assert_allclose(p.transform(np.array([0.0, 0.0]))[0], [1.0, a_edge],
                               rtol=1e-15)


def test_recruitment_stops_at_the_cap_and_is_off_at_threshold_zero():
    p = _hand_set([[0.0, 0.0]], 1.0, recruit_threshold=0.5, max_prototypes=2)
    assert p.step(np.array([10.0, 0.0])).size == 2            # 1 < 2: recruited
    a = p.step(np.array([-10.0, 0.0]))                        # 2 == cap: not recruited
    # activities exp(-100 / 2) and exp(-400 / 2)
    np.testing.assert_allclose(a, np.exp([-50.0, -200.0]), rtol=1e-12)
    assert p.n_units == 2
    p = _hand_set([[0.0, 0.0]], 1.0)                          # threshold 0: no recruitment
    assert p.step(np.array([1e3, 0.0])).tolist() == [0.0] and p.n_units == 1


# --- save and load ------------------------------------------------------------------------

def _good() -> dict[str, np.ndarray]:
    return {"format": np.array(PROTOTYPES_FORMAT), "centres": np.array([[0.0, 1.0], [2.0, 3.0]]),
            "sigma": np.array(0.5), "n_prototypes": np.array(2),
            "recruit_threshold": np.array(0.25), "max_prototypes": np.array(4),
            "seed": np.array(3)}


def _write(tmp_path: Path, **changes: Any) -> Path:
    arrays = _good()
    for k, v in changes.items():
        if v is None:
            del arrays[k]
        else:
            arrays[k] = np.asarray(v)
    path = tmp_path / "p.npz"
    np.savez(path, **arrays)
    return path


def test_a_hand_written_file_loads_with_its_parameters(tmp_path):
    p = PlacePrototypes.load(_write(tmp_path))
    assert p.params == PrototypeParams(n_prototypes=2, recruit_threshold=0.25,
                                       max_prototypes=4, seed=3)
    np.testing.assert_array_equal(p.centres_, [[0.0, 1.0], [2.0, 3.0]])
    assert p.sigma_ == 0.5 and p.n_units == 2
    # and save writes every field back: the same parameters and numbers
    back = PlacePrototypes.load(p.save(tmp_path / "again.npz"))
    assert back.params == p.params and back.sigma_ == 0.5
    with np.load(tmp_path / "again.npz") as f:
        assert str(f["format"]) == "hippo.PlacePrototypes/1"
        assert sorted(f.files) == sorted(_good())


@pytest.mark.parametrize("fmt", [np.array("hippo.PlacePrototypes/2"),
                                 np.array(b"hippo.PlacePrototypes/1"),
                                 np.array(["hippo.PlacePrototypes/1"])])
def test_another_format_is_refused(tmp_path, fmt):
    path = _write(tmp_path, format=fmt)
    with _raises(CorruptFileError, f"{path} is not a saved PlacePrototypes"):
        PlacePrototypes.load(path)


@pytest.mark.parametrize("changes, msg", [
    (dict(sigma=0.0), "sigma must be finite and > 0, got 0.0"),
    (dict(sigma=math.nextafter(1e-6, 0.0)),
     f"sigma must be >= 1e-6, got {math.nextafter(1e-6, 0.0)}"),
    (dict(sigma=math.nextafter(1e12, math.inf)),
     "sigma holds a value of magnitude 1e+12, beyond 1e+12: no fit produces it"),
    (dict(sigma=[0.5]), "sigma must have shape (), got (1,)"),
    (dict(centres=np.zeros((0, 2))),
     "centres has shape (0, 2): need 1 to max_prototypes=4 rows of >= 1 values"),
    (dict(centres=np.zeros((5, 2))),
     "centres has shape (5, 2): need 1 to max_prototypes=4 rows of >= 1 values"),
    (dict(centres=np.zeros((2, 0))),
     "centres has shape (2, 0): need 1 to max_prototypes=4 rows of >= 1 values"),
    (dict(centres=np.zeros(2)), "centres must have shape (*, *), got (2,)"),
    (dict(centres=[[0.0, -2e12]]),
     "centres holds a value of magnitude 2e+12, beyond 1e+12: no fit produces it"),
    (dict(centres=[[0.0, 1e12 + 0.5]]),
     "centres holds a value of magnitude 1e+12, beyond 1e+12: no fit produces it"),
    (dict(n_prototypes=2.0), "n_prototypes must hold integers, got dtype float64"),
    (dict(n_prototypes=[2]), "n_prototypes must have shape (), got (1,)"),
    (dict(max_prototypes=4.0), "max_prototypes must hold integers, got dtype float64"),
    (dict(max_prototypes=[4]), "max_prototypes must have shape (), got (1,)"),
    (dict(seed=3.0), "seed must hold integers, got dtype float64"),
    (dict(seed=[3]), "seed must have shape (), got (1,)"),
    (dict(recruit_threshold=[0.25]), "recruit_threshold must have shape (), got (1,)"),
    (dict(recruit_threshold=1.0), "recruit_threshold must lie in [0, 1), got 1.0"),
    (dict(max_prototypes=1), "max_prototypes (1) must be >= n_prototypes (2)"),
])
def test_damaged_fields_are_refused_word_for_word(tmp_path, changes, msg):
    path = _write(tmp_path, **changes)
    with _raises(CorruptFileError, f"{path}: {msg}"):
        PlacePrototypes.load(path)


def test_fields_exactly_on_their_bounds_load(tmp_path):
    # σ exactly at fit's floor and at the magnitude bound, centres at the bound and as many
    # rows as max_prototypes allows
    for sigma in (1e-6, 1e12):
        assert PlacePrototypes.load(_write(tmp_path, sigma=sigma)).sigma_ == sigma
    p = PlacePrototypes.load(_write(tmp_path, centres=[[1e12, -1e12]] * 4))
    assert p.n_units == 4 and p.centres_.shape == (4, 2)
    # the fewest: one centre of one value (its own activity 1, one σ = 0.5 off exp(-1 / 2))
    p = PlacePrototypes.load(_write(tmp_path, centres=[[2.5]]))
    assert p.n_units == 1
    np.testing.assert_allclose(p.transform(np.array([[2.5], [3.0]])), [[1.0], [np.exp(-0.5)]],
                               rtol=1e-15)


@pytest.mark.parametrize("key", sorted(_good()))
def test_a_missing_field_is_named(tmp_path, key):
    path = _write(tmp_path, **{key: None})
    with _raises(CorruptFileError, f"{path} lacks required array(s): {key}"):
        PlacePrototypes.load(path)
