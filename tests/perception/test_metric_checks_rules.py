"""The metrics' input checks by hand (hippo.perception.metric_checks): a response matrix Y
(T, units), a 1-D series as one unit, the row count, finiteness, real numbers only; labels
1-D integers in [0, n), each bound exactly and one step past; every refusal word for word."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from hippo.perception.metric_checks import _check_labels, _check_Y


# ----------------------------------------------------------------------------- responses Y
def test_a_matrix_is_kept_as_float64_values():
    Y = _check_Y([[1, 2], [3, 4], [5, 6]])
    assert Y.dtype == np.float64 and Y.shape == (3, 2)
    assert Y.tolist() == [[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]]
    f32 = np.array([[0.5], [0.25]], dtype=np.float32)
    out = _check_Y(f32)
    assert out.dtype == np.float64 and out.tolist() == [[0.5], [0.25]]
    # booleans (binary cells) read as 0 and 1
    assert _check_Y(np.array([True, False])).tolist() == [[1.0], [0.0]]


def test_a_series_is_one_unit():
    Y = _check_Y(np.array([0.0, 1.5, -2.0]))
    assert Y.shape == (3, 1) and Y[:, 0].tolist() == [0.0, 1.5, -2.0]
    # an empty series is one unit of no samples
    assert _check_Y(np.zeros(0)).shape == (0, 1)


@pytest.mark.parametrize("shape", [(), (2, 2, 2), (1, 1, 1, 1)])
def test_other_dimensions_are_refused_word_for_word(shape):
    with pytest.raises(ValueError) as exc:
        _check_Y(np.zeros(shape))
    assert str(exc.value) == f"Y must be (T, units), got shape {shape}"
    with pytest.raises(ValueError) as exc:
        _check_Y(np.zeros(shape), name="X")
    assert str(exc.value) == f"X must be (T, units), got shape {shape}"


def test_the_row_count_must_be_t():
    assert _check_Y(np.zeros((4, 2)), 4).shape == (4, 2)
    assert _check_Y(np.zeros(4), 4).shape == (4, 1)
    for T in (3, 5):
        with pytest.raises(ValueError) as exc:
            _check_Y(np.zeros((4, 2)), T)
        assert str(exc.value) == f"Y has 4 rows, expected {T}"
    with pytest.raises(ValueError) as exc:
        _check_Y(np.zeros(4), 0, name="X")
    assert str(exc.value) == "X has 4 rows, expected 0"
    # T = 0 is a row count like any other
    assert _check_Y(np.zeros((0, 3)), 0).shape == (0, 3)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_responses_are_refused(bad):
    Y = np.zeros((3, 2))
    Y[1, 0] = bad
    with pytest.raises(ValueError) as exc:
        _check_Y(Y)
    assert str(exc.value) == "Y contains 1 non-finite value(s) (NaN or inf)"
    Y[2, 1] = bad
    with pytest.raises(ValueError) as exc:
        _check_Y(Y, name="X")
    assert str(exc.value) == "X contains 2 non-finite value(s) (NaN or inf)"


def test_complex_responses_are_refused_not_cut_to_their_real_part():
    # (np.asarray(Y, dtype=float) kept the real part with only numpy's ComplexWarning)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError) as exc:
            _check_Y(np.array([1 + 2j, 3 + 0j]))
    assert str(exc.value) == "Y must hold real numbers, got complex values (dtype complex128)"


def test_text_and_ragged_responses_are_refused_naming_y():
    with pytest.raises(ValueError) as exc:
        _check_Y(np.array(["a", "b"]), name="X")
    assert str(exc.value).startswith("X must hold real numbers, got dtype <U1 (")
    with pytest.raises(ValueError) as exc:
        _check_Y([[1.0, 2.0], [3.0]])
    assert str(exc.value).startswith("Y must be an array of numbers, got list that numpy "
                                     "cannot read as one (")


# ----------------------------------------------------------------------------------- labels
def test_labels_in_range_are_returned_as_given():
    lab = np.array([0, 2, 1, 2])
    out = _check_labels(lab, 3)
    assert out.tolist() == [0, 2, 1, 2] and out.dtype == lab.dtype
    # unsigned and narrow integers are integers too; no n: any integers
    assert _check_labels(np.array([1, 2], dtype=np.uint8), 3).tolist() == [1, 2]
    assert _check_labels([-5, 7]).tolist() == [-5, 7]
    # empty labels pass any n (no min or max to read)
    assert _check_labels(np.zeros(0, dtype=int), 1).size == 0
    assert _check_labels(np.zeros(0, dtype=int), 0).size == 0


def test_the_label_bounds_on_their_edges_and_one_past():
    # 0 and n - 1 are in [0, n); -1 and n are not
    assert _check_labels([0, 4], 5).tolist() == [0, 4]
    with pytest.raises(ValueError) as exc:
        _check_labels([-1, 4], 5)
    assert str(exc.value) == "labels must lie in [0, 5), got -1..4"
    with pytest.raises(ValueError) as exc:
        _check_labels([0, 5], 5)
    assert str(exc.value) == "labels must lie in [0, 5), got 0..5"
    with pytest.raises(ValueError) as exc:
        _check_labels([3], 3)
    assert str(exc.value) == "labels must lie in [0, 3), got 3..3"
    # n = 0 holds no label at all
    with pytest.raises(ValueError) as exc:
        _check_labels([0], 0)
    assert str(exc.value) == "labels must lie in [0, 0), got 0..0"


@pytest.mark.parametrize(("labels", "described"), [
    (np.array([0.0, 1.0]), "float64 (2,)"),
    (np.array([True, False]), "bool (2,)"),
    (np.array([[0, 1]]), "int64 (1, 2)"),
    (np.array(1), "int64 ()"),
    (np.array(["0", "1"]), "<U1 (2,)"),
])
def test_labels_of_another_kind_or_shape_are_refused_word_for_word(labels, described):
    with pytest.raises(ValueError) as exc:
        _check_labels(labels, 3)
    assert str(exc.value) == f"labels must be a 1-D integer array, got {described}"
