"""Slow Feature Analysis (Wiskott & Sejnowski 2002; SMC09 eq. 2-7, ICANN09 §2.2).

Find ``y_i = w_iᵀ x`` that vary as slowly as possible,

    minimise  Δ(y_i) = ⟨ẏ_i²⟩_t   subject to  ⟨y_i⟩ = 0,  ⟨y_i²⟩ = 1,  ⟨y_i y_j⟩ = 0 (j < i),

i.e. the generalised eigenproblem ``A W = B W Λ`` with ``A = ⟨ẋ ẋᵀ⟩`` and ``B = ⟨x xᵀ⟩`` on the
z-scored input, keeping the ``n`` smallest eigenvalues (the slowness Δ of each unit).

Solved in two symmetric steps instead of ``scipy.linalg.eigh(A, B)``: reservoir states are so
correlated that ``cond(B)`` reaches 1e8-1e11, and a duplicated input column makes ``B`` singular
(the Cholesky inside ``eigh(A, B)`` then raises). So:

1. whiten: ``B = E D Eᵀ``; keep the directions with ``d_k > cutoff · d_max`` (the others carry no
   variance, only rounding noise and duplicated inputs); ``S = E_k D_k^{-1/2}``;
2. slow rotation: ``Sᵀ A S = V Λ Vᵀ``; the ``n`` smallest eigenpairs give ``W = S V``.

``cutoff`` is a real hyper-parameter (in the maze it moved the localized-unit count from ~24 to
~65 of 70). ``cutoff="auto"`` chooses it without labels: fit on the first 80 % of the data and
keep the candidate whose units are slowest on the held-out last 20 % (over-fitted, noise-borne
slow directions are fast on new data).

``expansion="quadratic"`` adds all products ``x_i x_j`` (i ≤ j) of the z-scored input before SFA
(the non-linear SFA of the no-reservoir ablation, ICANN09 §4).

Derivatives are first differences per sample, ``ẋ(t) = x(t+1) - x(t)``, so Δ is in 1/sample².
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import scipy.linalg

from hippo._checks import check_finite

_AUTO_CANDIDATES = tuple(10.0 ** -k for k in range(3, 13))


@dataclass(frozen=True)
class SFAParams:
    """SFA hyper-parameters (SMC09: 4 units; ICANN09: 70 units)."""

    n_components: int = 4
    #: relative eigenvalue cutoff of the whitening step, or "auto" (held-out slowness)
    cutoff: float | str = 1e-8
    #: "linear" (SMC09/ICANN09 with a reservoir) or "quadratic" (no-reservoir ablation)
    expansion: str = "linear"

    def __post_init__(self) -> None:
        if int(self.n_components) < 1:
            raise ValueError(f"n_components (n_sfa) must be >= 1, got {self.n_components}")
        if self.expansion not in ("linear", "quadratic"):
            raise ValueError(f"expansion must be 'linear' or 'quadratic', got {self.expansion!r}")
        if isinstance(self.cutoff, str):
            if self.cutoff != "auto":
                raise ValueError(f"cutoff must be a number in (0, 1) or 'auto', got "
                                 f"{self.cutoff!r}")
        elif not (0.0 < float(self.cutoff) < 1.0):
            raise ValueError(f"cutoff must lie in (0, 1), got {self.cutoff!r}")


def quadratic_expansion(Z: np.ndarray) -> np.ndarray:
    """``[z, z_i z_j for i <= j]`` for each row of ``Z`` (T, d) -> (T, d + d(d+1)/2)."""
    Z = np.asarray(Z, dtype=float)
    i, j = np.triu_indices(Z.shape[-1])
    return np.concatenate([Z, Z[..., i] * Z[..., j]], axis=-1)


def _moments(X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sums ``Σ x xᵀ`` and ``Σ ẋ ẋᵀ`` (float64; ``X.T @ X`` lets BLAS use a symmetric rank-k
    update)."""
    C = X.T @ X
    D = np.diff(X, axis=0)
    return C, D.T @ D


def _whiten(C: np.ndarray, cutoff: float) -> tuple[np.ndarray, np.ndarray]:
    d, E = scipy.linalg.eigh(C, overwrite_a=False, check_finite=False)
    keep = d > cutoff * max(d[-1], np.finfo(float).tiny)
    return E[:, keep] / np.sqrt(d[keep]), d[::-1]


def _slow(S: np.ndarray, A: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    Aw = S.T @ A @ S
    Aw = 0.5 * (Aw + Aw.T)
    lam, V = scipy.linalg.eigh(Aw, subset_by_index=[0, n - 1], check_finite=False)
    return lam, S @ V


class SFA:
    """Linear (or quadratic) SFA: ``y = Wᵀ (x - μ)/σ`` with ``A W = B W Λ`` (SMC09 eq. 6-7).

    Fitted attributes: ``mean_``, ``scale_`` (z-scoring of the expanded input), ``W_``
    ``(d, n)`` applied to the z-scored input, ``slowness_`` (the eigenvalues Δ, ascending),
    ``n_whitened_`` (directions kept by the cutoff), ``cutoff_`` (the cutoff used; the chosen
    one for ``"auto"``), ``input_eigenvalues_`` (eigenvalues of ``B``, descending).

    Outputs on the training data are zero-mean, unit-variance, decorrelated and ordered by
    slowness; each unit's sign is chosen so that its skewness is >= 0.
    """

    def __init__(self, params: SFAParams | None = None, **overrides: Any) -> None:
        self.params = replace(params or SFAParams(), **overrides)

    # ------------------------------------------------------------------ helpers
    def _expand(self, X: np.ndarray) -> np.ndarray:
        if self.params.expansion == "linear":
            return X
        return quadratic_expansion((X - self.pre_mean_) / self.pre_scale_)

    def _check_X(self, X: Any, name: str = "X") -> np.ndarray:
        X = np.asarray(X)
        if X.ndim != 2:
            raise ValueError(f"{name} must be a 2-D array (time, features), got shape {X.shape}")
        X = check_finite(name, X)
        return X

    # ------------------------------------------------------------------ fit / transform
    def fit(self, X: np.ndarray) -> SFA:
        """Learn the slow features of ``X`` (T, d), rows in time order."""
        X = self._check_X(X)
        n = int(self.params.n_components)
        T, d_in = X.shape
        if T < 3:
            raise ValueError(f"SFA needs at least 3 samples, got {T}")
        self.n_features_in_ = d_in
        if self.params.expansion == "quadratic":
            self.pre_mean_ = X.mean(axis=0)
            sd = X.std(axis=0)
            self.pre_scale_ = np.where(sd > 1e-12 * (1.0 + np.abs(self.pre_mean_)), sd, 1.0)
        Xe = self._expand(X)
        d = Xe.shape[1]
        if n > d:
            raise ValueError(f"n_sfa={n} exceeds the SFA input dimension {d}")
        self.mean_ = Xe.mean(axis=0)
        sd = Xe.std(axis=0)
        # constant columns: scale 1 (they become 0 and the cutoff drops them)
        self.scale_ = np.where(sd > 1e-12 * (1.0 + np.abs(self.mean_)), sd, 1.0)
        Z = (Xe - self.mean_) / self.scale_
        C, A = _moments(Z)
        C /= T
        A /= T - 1
        cutoff = self.params.cutoff
        if cutoff == "auto":
            cutoff = self._select_cutoff(Z, n)
        self.cutoff_ = float(cutoff)
        S, eig = _whiten(C, self.cutoff_)
        self.input_eigenvalues_ = eig
        self.n_whitened_ = S.shape[1]
        if self.n_whitened_ < n:
            raise ValueError(
                f"only {self.n_whitened_} input directions survive the whitening cutoff "
                f"{self.cutoff_:g} but n_sfa={n}; lower the cutoff or n_sfa")
        lam, W = _slow(S, A, n)
        y = Z @ W
        sign = np.where(np.mean(y ** 3, axis=0) < 0, -1.0, 1.0)
        self.W_ = W * sign
        self.slowness_ = lam
        return self

    def _select_cutoff(self, Z: np.ndarray, n: int) -> float:
        split = int(0.8 * Z.shape[0])
        C1, A1 = _moments(Z[:split])
        C2, A2 = _moments(Z[split:])
        d, E = scipy.linalg.eigh(C1 / split, check_finite=False)
        best, best_score = None, np.inf
        scores = {}
        for c in _AUTO_CANDIDATES:
            keep = d > c * d[-1]
            if keep.sum() < n:
                continue
            S = E[:, keep] / np.sqrt(d[keep])
            _, W = _slow(S, A1 / (split - 1), n)
            num = np.einsum("ij,ik,kj->j", W, A2, W)
            den = np.einsum("ij,ik,kj->j", W, C2, W)
            score = float(np.sum(num / np.maximum(den, 1e-300)))
            scores[c] = score
            if score < best_score:
                best, best_score = c, score
        if best is None:
            raise ValueError(f"no whitening cutoff keeps n_sfa={n} directions")
        self.cutoff_scores_ = scores
        return best

    def transform(self, X: np.ndarray) -> np.ndarray:
        """Slow features ``(T, n)`` of ``X`` ``(T, d)``."""
        self._check_fitted()
        X = self._check_X(X)
        if X.shape[1] != self.n_features_in_:
            raise ValueError(f"X has {X.shape[1]} features, SFA was fitted on "
                             f"{self.n_features_in_}")
        return ((self._expand(X) - self.mean_) / self.scale_) @ self.W_

    def fit_transform(self, X: np.ndarray) -> np.ndarray:
        return self.fit(X).transform(X)

    def affine(self) -> tuple[np.ndarray, np.ndarray]:
        """``(M, b)`` with ``transform(X) == X @ M + b`` (linear expansion only)."""
        self._check_fitted()
        if self.params.expansion != "linear":
            raise ValueError("affine() exists only for the linear expansion")
        M = self.W_ / self.scale_[:, None]
        return M, -(self.mean_ / self.scale_) @ self.W_

    def _check_fitted(self) -> None:
        if not hasattr(self, "W_"):
            raise RuntimeError("SFA is not fitted yet; call fit(X) first")

    def __repr__(self) -> str:
        p = self.params
        return f"SFA(n_components={p.n_components}, cutoff={p.cutoff!r}, expansion={p.expansion!r})"
