"""The checks the place-cell metrics (:mod:`hippo.perception.metrics`,
:mod:`hippo.perception.ceiling`) make of their inputs: a response matrix ``Y`` (T, units),
finite, one row a sample (a 1-D series is one unit), and location labels, 1-D integers in
``[0, n)``."""

from __future__ import annotations

import numpy as np

from hippo._checks import check_finite


def _check_Y(Y: np.ndarray, T: int | None = None, name: str = "Y") -> np.ndarray:
    # real numbers, named (np.asarray(Y, dtype=float) kept complex values' real part)
    Y = check_finite(name, Y)
    if Y.ndim == 1:
        Y = Y[:, None]
    if Y.ndim != 2:
        raise ValueError(f"{name} must be (T, units), got shape {Y.shape}")
    if T is not None and Y.shape[0] != T:
        raise ValueError(f"{name} has {Y.shape[0]} rows, expected {T}")
    return Y


def _check_labels(labels: np.ndarray, n: int | None = None) -> np.ndarray:
    lab = np.asarray(labels)
    if lab.ndim != 1 or not np.issubdtype(lab.dtype, np.integer):
        raise ValueError(f"labels must be a 1-D integer array, got {lab.dtype} {lab.shape}")
    if n is not None and lab.size and (lab.min() < 0 or lab.max() >= n):
        raise ValueError(f"labels must lie in [0, {n}), got {lab.min()}..{lab.max()}")
    return lab
