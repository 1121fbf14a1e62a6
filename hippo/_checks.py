"""Input validation shared by every module: each failure names the problem."""

from __future__ import annotations

import math
from typing import Any

import numpy as np


def check_finite(name: str, value: Any, *, keep_float32: bool = False) -> np.ndarray:
    """Return ``value`` as a float array, or raise ``ValueError`` if it holds NaN or inf.

    With ``keep_float32`` a float32 array is returned as is (no float64 copy of a large
    recording); anything else becomes float64.
    """
    arr = np.asarray(value)
    if not (keep_float32 and arr.dtype == np.float32):
        arr = np.asarray(arr, dtype=float)
    # one reduction on the hot path: a NaN or inf anywhere makes the sum non-finite
    if not math.isfinite(float(np.add.reduce(arr, axis=None))):
        bad = int(np.size(arr) - np.count_nonzero(np.isfinite(arr)))
        if bad:  # (a finite sum can only overflow when every value is finite)
            raise ValueError(f"{name} contains {bad} non-finite value(s) (NaN or inf)")
    return arr


def check_positive(name: str, value: float, *, allow_zero: bool = False) -> float:
    """Raise ``ValueError`` unless ``value`` is a finite number > 0 (or >= 0)."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        rel = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"{name} must be finite and {rel}, got {value!r}")
    return v


def check_range(name: str, value: float, lo: float, hi: float, *,
                closed: str = "both") -> float:
    """Raise ``ValueError`` unless ``value`` lies in the interval.

    ``closed`` says which ends belong to it: ``both``, ``left``, ``right`` or ``neither``.
    """
    v = float(value)
    ok_lo = v >= lo if closed in ("both", "left") else v > lo
    ok_hi = v <= hi if closed in ("both", "right") else v < hi
    if not (math.isfinite(v) and ok_lo and ok_hi):
        lb = "[" if closed in ("both", "left") else "("
        rb = "]" if closed in ("both", "right") else ")"
        raise ValueError(f"{name} must lie in {lb}{lo}, {hi}{rb}, got {value!r}")
    return v


def check_shape(name: str, arr: np.ndarray, shape: tuple[int | None, ...]) -> np.ndarray:
    """Raise ``ValueError`` unless ``arr`` has dims matching ``shape`` (None = any size)."""
    a = np.asarray(arr)
    if a.ndim != len(shape) or any(s is not None and s != d for s, d in zip(shape, a.shape)):
        want = "(" + ", ".join("*" if s is None else str(s) for s in shape) + ")"
        raise ValueError(f"{name} must have shape {want}, got {a.shape}")
    return a
