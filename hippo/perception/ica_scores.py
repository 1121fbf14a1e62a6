"""Unsupervised scores of ICA outputs: how FastICA picks the best of its restarts.

For outputs ``S`` (T, k), unit variance, higher is better:

* ``"kurtosis"``: ``Σ_i |E{s_i⁴} - 3|``, the excess kurtosis the cube non-linearity climbs;
* ``"sparseness"``: ``Σ_i (1 - E|s_i|)``;
* ``"slowness"``: ``-min_i Δ(s_i)``, ``Δ(s) = ⟨ṡ²⟩`` (prefer the rotation with the slowest
  single unit).

Each is a sum over row chunks, so a long output is scored without holding it whole.
"""

from __future__ import annotations

import numpy as np

SCORES = ("kurtosis", "sparseness", "slowness")


def score_outputs(S: np.ndarray, criterion: str) -> float:
    """Unsupervised quality of ICA outputs ``S`` (T, k), unit variance; higher is better."""
    return _score_chunks([S], criterion)


def _score_chunks(chunks, criterion: str) -> float:
    """:func:`score_outputs` of the outputs given as consecutive row chunks ``(t, k)``."""
    if criterion not in SCORES:
        raise ValueError(f"unknown score {criterion!r}; choose from {SCORES}")
    total, n, last = 0.0, 0, None
    for S in chunks:
        if criterion == "kurtosis":
            S2 = S * S
            part = (S2 * S2).sum(axis=0)
        elif criterion == "sparseness":
            part = np.abs(S).sum(axis=0)
        else:
            D = np.diff(S, axis=0) if last is None else np.diff(np.vstack([last, S]), axis=0)
            part = (D * D).sum(axis=0)
            last = S[-1:]
        total = total + part
        n += S.shape[0]
    if criterion == "kurtosis":
        return float(np.sum(np.abs(total / n - 3.0)))
    if criterion == "sparseness":
        return float(np.sum(1.0 - total / n))
    return -float(np.min(total / (n - 1)))
