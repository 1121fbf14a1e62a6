"""The supervised ceiling: what a ridge read-out of the same state reaches, cross-validated
in contiguous blocks of time (:func:`ridge_ceiling`, :class:`Ceiling`, :func:`time_blocks`).

The place cells learn without labels; the ceiling uses them, to show what the sensors (or the
reservoir state) allow next to what the unsupervised read-out finds. The state carries memory,
so samples next to a test block are left out of its training blocks (``gap``), and each fold's
ridge penalty is chosen inside its own training blocks (nested). The place-cell metrics
(:mod:`hippo.perception.metrics`) re-export these names.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hippo._checks import check_int, check_real
from hippo.perception.metric_checks import _check_Y


@dataclass
class Ceiling:
    """What a supervised linear read-out of the same state reaches (see :func:`ridge_ceiling`).

    ``predicted`` holds the cross-validated class of every sample (-1 outside ``mask``);
    ``balanced_accuracy`` is the mean over classes of the recall (0.5 = chance for two
    classes), ``accuracy`` the plain fraction right; ``alpha`` the ridge penalty chosen in each
    outer fold.
    """

    predicted: np.ndarray
    balanced_accuracy: float
    accuracy: float
    per_class_recall: np.ndarray
    alpha: np.ndarray
    folds: int


def time_blocks(T: int, folds: int) -> np.ndarray:
    """Boundaries ``(folds + 1,)`` of ``folds`` contiguous blocks of ``range(T)``."""
    folds = check_int("folds", folds, lo=2)
    if T < 2 * folds:
        raise ValueError(f"{T} samples are too few for {folds} folds")
    return np.linspace(0, T, folds + 1).round().astype(int)


def _check_alphas(alphas: tuple[float, ...]) -> tuple[float, ...]:
    """``alphas`` as a non-empty tuple of finite penalties > 0."""
    try:
        vals = tuple(alphas)
    except TypeError:
        raise ValueError(f"alphas must be a sequence of ridge penalties, got {alphas!r}") from None
    if not vals or not all(check_real("alphas", a) > 0 for a in vals):
        raise ValueError(f"alphas must be finite ridge penalties > 0, got {alphas!r}")
    return vals


def ridge_ceiling(X: np.ndarray, labels: np.ndarray, n_classes: int | None = None, *,
                  mask: np.ndarray | None = None, folds: int = 5, gap: int = 50,
                  alphas: tuple[float, ...] = (1e-2, 1e-1, 1.0, 10.0, 100.0)) -> Ceiling:
    """The supervised ceiling: a ridge read-out of the state ``X`` (T, d), cross-validated in
    time.

    The recording is cut into ``folds`` contiguous blocks; each block is predicted by a ridge
    regression (one-hot targets, argmax; a constant column that is not penalised) trained on the
    other blocks, without the ``gap`` samples at each end of every training block (the state
    carries memory, so samples right next to the test block would leak it). The penalty of each
    outer fold is chosen among ``alphas`` by the same blocked cross-validation inside its
    training blocks (nested: the test block never picks its own penalty). Features are
    z-scored over the whole recording (no labels involved). Only samples in ``mask`` (default:
    all) are fitted and scored.
    """
    X = _check_Y(X, name="X")
    lab = np.asarray(labels)
    if lab.shape != (X.shape[0],) or not np.issubdtype(lab.dtype, np.integer):
        raise ValueError(f"labels must be an integer array of shape ({X.shape[0]},), got "
                         f"{lab.dtype} {lab.shape}")
    m = np.ones(lab.size, bool) if mask is None else np.asarray(mask, bool)
    if m.shape != lab.shape:
        raise ValueError(f"mask must have shape {lab.shape}, got {m.shape}")
    n_fit = int(m.sum())
    if n_fit == 0:
        raise ValueError("mask selects no samples: nothing to fit or score")
    if np.any(lab[m] < 0):
        raise ValueError("labels inside the mask must be >= 0")
    if n_classes is None:
        C = int(lab[m].max()) + 1
    else:
        C = check_int("n_classes", n_classes)
        if C >= 2 and lab[m].max() >= C:
            raise ValueError(f"labels inside the mask must lie in [0, n_classes={C}), got "
                             f"{lab[m].max()}")
    if C < 2:
        raise ValueError(f"the ceiling needs at least 2 classes, got {C}")
    if C > n_fit:  # surely a mistake, and a (T, classes) target matrix that may not fit
        raise ValueError(f"{C} classes (n_classes, or the largest label + 1) for {n_fit} "
                         "samples in the mask: there can be at most one class per sample")
    alphas = _check_alphas(alphas)
    gap = check_int("gap", gap, lo=0)
    T = X.shape[0]
    bounds = time_blocks(T, folds)
    folds = len(bounds) - 1
    mu, sd = X.mean(axis=0), X.std(axis=0)
    sd[sd < 1e-12] = 1.0
    Z = np.column_stack([(X - mu) / sd, np.ones(T)])
    d = Z.shape[1]
    Yt = np.zeros((T, C))
    Yt[np.flatnonzero(m), lab[m]] = 1.0
    # per block: sums over its core (training use) and its full extent (testing)
    G, R = np.zeros((folds, d, d)), np.zeros((folds, d, C))
    for k in range(folds):
        a, b = bounds[k] + gap, bounds[k + 1] - gap
        if b <= a:
            raise ValueError(f"gap={gap} leaves no training samples in a block of "
                             f"{bounds[k + 1] - bounds[k]} samples")
        sel = np.flatnonzero(m[a:b]) + a
        G[k] = Z[sel].T @ Z[sel]
        R[k] = Z[sel].T @ Yt[sel]
    pen = np.eye(d)
    pen[-1, -1] = 0.0

    def solve(train: list[int], alpha: float) -> np.ndarray:
        A = G[train].sum(axis=0) + alpha * pen
        try:
            return np.linalg.solve(A, R[train].sum(axis=0))
        except np.linalg.LinAlgError:  # no samples in the training blocks' masks
            return np.linalg.lstsq(A, R[train].sum(axis=0), rcond=None)[0]

    def predict(k: int, W: np.ndarray) -> np.ndarray:
        return np.argmax(Z[bounds[k]:bounds[k + 1]] @ W, axis=1)

    def score(k: int, W: np.ndarray) -> float:
        sl = slice(bounds[k], bounds[k + 1])
        mk = m[sl]
        if not mk.any():
            return np.nan
        return float(np.mean(predict(k, W)[mk] == lab[sl][mk]))

    pred = np.full(T, -1)
    chosen = np.zeros(folds)
    for k in range(folds):
        rest = [j for j in range(folds) if j != k]
        inner = []
        for alpha in alphas:
            s = [score(j, solve([i for i in rest if i != j], alpha)) for j in rest]
            inner.append(np.nanmean(s) if np.isfinite(s).any() else -np.inf)
        chosen[k] = alphas[int(np.argmax(inner))]
        pred[bounds[k]:bounds[k + 1]] = predict(k, solve(rest, chosen[k]))
    pred[~m] = -1
    recall = np.array([np.mean(pred[m & (lab == c)] == c) if np.any(m & (lab == c)) else np.nan
                       for c in range(C)])
    return Ceiling(predicted=pred, balanced_accuracy=float(np.nanmean(recall)),
                   accuracy=float(np.mean(pred[m] == lab[m])), per_class_recall=recall,
                   alpha=chosen, folds=int(folds))
