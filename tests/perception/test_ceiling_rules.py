"""The supervised ceiling's rules with known answers: contiguous blocks, the nested choice of
the ridge penalty against an independent re-implementation (explicit training rows, the
ridge solved as an augmented least-squares problem), the unpenalised constant column (a huge
penalty predicts each fold's majority class), training blocks with no samples in the mask
(a zero read-out, class 0), classes absent from the mask (a NaN recall, no warning), the
defaults, the edges of every check and every error text word for word."""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest

from hippo.perception.ceiling import ridge_ceiling, time_blocks


def _exactly(exc: type[Exception], text: str):
    return pytest.raises(exc, match="^" + re.escape(text) + "$")


def _reference(X: np.ndarray, lab: np.ndarray, C: int, mask: np.ndarray, bounds: np.ndarray,
               gap: int, alphas: tuple[float, ...]) -> tuple[np.ndarray, np.ndarray]:
    """The documented procedure written out plainly: predictions and the chosen penalties."""
    T, folds = len(X), len(bounds) - 1
    sd = X.std(axis=0)
    sd[sd < 1e-12] = 1.0
    Z = np.column_stack([(X - X.mean(axis=0)) / sd, np.ones(T)])
    d = Z.shape[1]
    Y = np.eye(C)[np.where(mask, lab, 0)]

    def core(j: int) -> list[int]:
        return [t for t in range(bounds[j] + gap, bounds[j + 1] - gap) if mask[t]]

    def fit(train: list[int], alpha: float) -> np.ndarray:
        rows = [t for j in train for t in core(j)]
        # min |Z w - y|^2 + alpha |w without the constant's weight|^2, as one least squares
        A = np.vstack([Z[rows], np.sqrt(alpha) * np.eye(d)[:-1]])
        B = np.vstack([Y[rows], np.zeros((d - 1, C))])
        return np.linalg.lstsq(A, B, rcond=None)[0]

    def accuracy(j: int, W: np.ndarray) -> float:
        rows = [t for t in range(bounds[j], bounds[j + 1]) if mask[t]]
        if not rows:
            return np.nan
        return float(np.mean(np.argmax(Z[rows] @ W, axis=1) == lab[rows]))

    pred, chosen = np.full(T, -1), np.zeros(folds)
    for k in range(folds):
        rest = [j for j in range(folds) if j != k]
        best, best_score = alphas[0], -np.inf
        for alpha in alphas:
            s = np.array([accuracy(j, fit([i for i in rest if i != j], alpha)) for j in rest])
            mean = np.mean(s[np.isfinite(s)]) if np.isfinite(s).any() else -np.inf
            if mean > best_score:
                best, best_score = alpha, mean
        chosen[k] = best
        block = np.arange(bounds[k], bounds[k + 1])
        pred[block] = np.argmax(Z[block] @ fit(rest, best), axis=1)
    pred[~mask] = -1
    return pred, chosen


# ------------------------------------------------------------------ blocks
def test_time_blocks_by_hand():
    np.testing.assert_array_equal(time_blocks(4, 2), [0, 2, 4])          # T = 2 folds: allowed
    np.testing.assert_array_equal(time_blocks(14, 3), [0, 5, 9, 14])     # 4.67 -> 5, 9.33 -> 9
    with _exactly(ValueError, "3 samples are too few for 2 folds"):
        time_blocks(3, 2)
    with _exactly(ValueError, "folds must be an integer >= 2, got 1"):
        time_blocks(10, 1)


# ------------------------------------------------------------------ the read-out
def test_nested_ridge_matches_an_independent_implementation():
    """Few samples, 60 features on scales from 0.01 to 10, a weak signal in two of them and a
    partial mask: the penalty chosen varies between folds, and every prediction and penalty is
    the one the plain re-implementation finds."""
    rng = np.random.default_rng(11)
    T, d = 180, 60
    lab = rng.integers(0, 3, T)
    scale = np.logspace(-2, 1, d)
    X = rng.normal(size=(T, d)) * scale
    X[:, 5] += 2.0 * scale[5] * (lab == 1)
    X[:, 40] -= 2.0 * scale[40] * (lab == 2)
    mask = rng.random(T) < 0.85
    alphas = (1e-3, 1.0, 30.0, 1e3)
    c = ridge_ceiling(X, np.where(mask, lab, -1), 3, mask=mask, folds=4, gap=3, alphas=alphas)
    pred, chosen = _reference(X, lab, 3, mask, np.array([0, 45, 90, 135, 180]), 3, alphas)
    assert len(set(chosen)) > 1 and chosen[0] != alphas[0]   # the choice matters here
    np.testing.assert_array_equal(c.alpha, chosen)
    np.testing.assert_array_equal(c.predicted, pred)
    assert c.predicted.dtype.kind == "i" and c.folds == 4 and type(c.folds) is int
    recall = [np.mean(pred[mask & (lab == k)] == k) for k in range(3)]
    np.testing.assert_allclose(c.per_class_recall, recall, rtol=1e-15)
    assert c.balanced_accuracy == pytest.approx(np.mean(recall), rel=1e-15)
    assert c.accuracy == pytest.approx(np.mean(pred[mask] == lab[mask]), rel=1e-15)
    assert 0.5 < c.accuracy < 0.7                         # a weak signal
    # a 0/1 integer mask is read as the boolean one
    c01 = ridge_ceiling(X, np.where(mask, lab, -1), 3, mask=mask.astype(int), folds=4, gap=3,
                        alphas=alphas)
    np.testing.assert_array_equal(c01.predicted, c.predicted)


def test_the_constant_column_is_not_penalised():
    """With a penalty of 1e9 the features' weights vanish and the unpenalised constant
    column learns the training blocks' class frequencies: every sample gets the majority
    class 0 (70 % of every block), although feature 0 separates the classes (a penalised
    constant would let it through)."""
    rng = np.random.default_rng(2)
    lab = (np.arange(200) % 10 >= 7).astype(int)                  # 7 of every 10 are class 0
    X = rng.normal(size=(200, 3))
    X[:, 0] += 6.0 * lab
    c = ridge_ceiling(X, lab, 2, folds=4, gap=2, alphas=(1e9,))
    np.testing.assert_array_equal(c.predicted, np.zeros(200, int))
    np.testing.assert_array_equal(c.per_class_recall, [1.0, 0.0])
    assert c.balanced_accuracy == 0.5 and c.accuracy == 0.7
    # the same feature at a small penalty: every sample right
    assert ridge_ceiling(X, lab, 2, folds=4, gap=2, alphas=(1e-2,)).accuracy == 1.0


def test_features_are_centred_whatever_their_offset():
    """z-scoring removes a feature's offset: 1e10 added to one feature (its values still held
    to ~1e-6, far below its noise) gives the same read-out as without it. Uncentred, a column
    of 1e10 against the constant column would leave the ridge's normal equations singular to
    working precision."""
    rng = np.random.default_rng(9)
    lab = (np.arange(200) % 4 < 2).astype(int)
    X = rng.normal(size=(200, 3))
    X[:, 0] += 3.0 * lab
    plain = ridge_ceiling(X, lab, 2, folds=4, gap=2)
    X[:, 0] += 1e10
    shifted = ridge_ceiling(X, lab, 2, folds=4, gap=2)
    np.testing.assert_array_equal(shifted.predicted, plain.predicted)
    np.testing.assert_array_equal(shifted.alpha, plain.alpha)
    assert 0.85 < plain.accuracy < 1.0


def test_a_near_constant_feature_is_not_rescaled():
    """A feature x = 0.5 + a (y - p) with a = 1e-13 (its sd, 4.6e-14, below 1e-12, so it is
    divided by 1, not by its sd) and p = 0.3 of the samples in class 1, 3 of every 10, so each
    block of 50 is alike. By hand, with S = sum of (y - p)^2 over the 150 training samples
    = 150 p (1 - p) and r = alpha / (a^2 S): the class-1 weight is w = a S / (a^2 S + alpha)
    (the class-0 weight -w), and a class-1 sample (z = a (1 - p)) gets class 1 iff
    2 w z > 1 - 2p, i.e. 1.4 / (1 + r) > 0.4, r < 2.5; class-0 samples (z < 0) always get 0.
    With alpha = a^2 S (r = 1) every sample is right; the feature divided by 2 instead would
    give r = 4 and no class-1 sample right."""
    lab = (np.arange(200) % 10 >= 7).astype(int)
    a, p = 1e-13, 0.3
    x = 0.5 + a * (lab - p)
    assert x.std() < 1e-12
    c = ridge_ceiling(x[:, None], lab, 2, folds=4, gap=0, alphas=(a * a * 150 * p * (1 - p),))
    np.testing.assert_array_equal(c.predicted, lab)
    # five times the penalty (r = 5 > 2.5): class 1 is never predicted
    c5 = ridge_ceiling(x[:, None], lab, 2, folds=4, gap=0,
                       alphas=(5 * a * a * 150 * p * (1 - p),))
    np.testing.assert_array_equal(c5.predicted, np.zeros(200, int))


def test_training_blocks_without_samples_give_a_zero_read_out_and_no_warning():
    """Only block 0 (of 4 blocks of 10) is in the mask: its fold trains on nothing (the
    penalised system is singular, its least-squares solution 0: every score 0, class 0);
    no inner fold has a sample to score, so the first penalty is kept. Class 2 never occurs
    in the mask: its recall is NaN, left out of the balanced accuracy, without a warning."""
    lab = np.array([0, 1] * 5 + [-1] * 30)
    mask = np.arange(40) < 10
    X = np.random.default_rng(4).normal(size=(40, 2))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        c = ridge_ceiling(X, lab, 3, mask=mask, folds=4, gap=0, alphas=(2.0, 3.0))
    np.testing.assert_array_equal(c.predicted, [0] * 10 + [-1] * 30)
    np.testing.assert_array_equal(c.per_class_recall, [1.0, 0.0, np.nan])
    assert c.balanced_accuracy == 0.5 and c.accuracy == 0.5
    np.testing.assert_array_equal(c.alpha, [2.0] * 4)


def test_defaults_are_five_folds_and_a_gap_of_50():
    """505 samples: five blocks of 101, a gap of 50 leaves one training sample per block
    (51 would leave none); 500 samples: blocks of 100, a gap of 50 leaves none."""
    rng = np.random.default_rng(6)
    lab = (np.arange(505) % 4 < 2).astype(int)
    X = rng.normal(size=(505, 2))
    X[:, 0] += 5.0 * lab
    c = ridge_ceiling(X, lab)
    assert c.folds == 5 and c.alpha.shape == (5,)
    explicit = ridge_ceiling(X, lab, 2, folds=5, gap=50)
    np.testing.assert_array_equal(c.predicted, explicit.predicted)
    np.testing.assert_array_equal(c.alpha, explicit.alpha)
    with _exactly(ValueError, "gap=51 leaves no training samples in a block of 101 samples"):
        ridge_ceiling(X, lab, gap=51)
    with _exactly(ValueError, "gap=50 leaves no training samples in a block of 100 samples"):
        ridge_ceiling(X[:500], lab[:500])
    assert ridge_ceiling(X[:500], lab[:500], gap=49).folds == 5


def test_the_gap_error_names_the_block_that_has_no_samples_left():
    """14 samples in 3 folds: blocks of 5, 4 and 5. A gap of 2 leaves one sample in the first
    block and none in the second: the error gives the second block's size, 4."""
    X = np.random.default_rng(0).normal(size=(14, 2))
    lab = np.arange(14) % 2
    with _exactly(ValueError, "gap=2 leaves no training samples in a block of 4 samples"):
        ridge_ceiling(X, lab, 2, folds=3, gap=2)
    assert ridge_ceiling(X, lab, 2, folds=3, gap=1).folds == 3


# ------------------------------------------------------------------ checks
def test_checks_and_their_edges_word_for_word():
    rng = np.random.default_rng(1)
    X = rng.normal(size=(40, 3))
    lab = np.arange(40) % 2
    with _exactly(ValueError, "labels must be an integer array of shape (40,), got float64 "
                              "(40,)"):
        ridge_ceiling(X, lab.astype(float))
    with _exactly(ValueError, "X must be (T, units), got shape (40, 3, 1)"):
        ridge_ceiling(X[:, :, None], lab)
    bad = X.copy()
    bad[3, 1] = np.inf
    with _exactly(ValueError, "X contains 1 non-finite value(s) (NaN or inf)"):
        ridge_ceiling(bad, lab)
    with _exactly(ValueError, "mask must have shape (40,), got (39,)"):
        ridge_ceiling(X, lab, mask=np.ones(39, bool))
    with _exactly(ValueError, "mask selects no samples: nothing to fit or score"):
        ridge_ceiling(X, lab, mask=np.zeros(40, bool))
    with _exactly(ValueError, "labels inside the mask must be >= 0"):
        ridge_ceiling(X, lab - 1, gap=0)
    with _exactly(ValueError, "n_classes must be an integer, got 2.5 (float)"):
        ridge_ceiling(X, lab, 2.5)  # type: ignore[arg-type]
    with _exactly(ValueError, "the ceiling needs at least 2 classes, got 1"):
        ridge_ceiling(X, np.zeros(40, int))
    with _exactly(ValueError, "labels inside the mask must lie in [0, n_classes=2), got 2"):
        ridge_ceiling(X, lab * 2, 2)
    three = np.isin(np.arange(40), [1, 15, 30])                  # 3 samples, 3 classes: allowed
    c = ridge_ceiling(X, np.where(three, np.arange(40) % 3, -1), 3, mask=three, folds=2, gap=0)
    assert c.per_class_recall.shape == (3,)
    with _exactly(ValueError, "4 classes (n_classes, or the largest label + 1) for 3 samples "
                              "in the mask: there can be at most one class per sample"):
        ridge_ceiling(X, lab, 4, mask=three, folds=2, gap=0)
    assert ridge_ceiling(X, lab, gap=0).folds == 5                 # gap 0 allowed
    with _exactly(ValueError, "gap must be an integer >= 0, got -1"):
        ridge_ceiling(X, lab, gap=-1)
    with _exactly(ValueError, "alphas must be a real number, got 'a' (str)"):
        ridge_ceiling(X, lab, gap=0, alphas=("a",))
    with _exactly(ValueError, "alphas must be finite ridge penalties > 0, got (1.0, 0.0)"):
        ridge_ceiling(X, lab, gap=0, alphas=(1.0, 0.0))
    with _exactly(ValueError, "alphas must be a sequence of ridge penalties, got 1.0"):
        ridge_ceiling(X, lab, gap=0, alphas=1.0)  # type: ignore[arg-type]
