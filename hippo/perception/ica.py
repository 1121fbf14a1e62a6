"""FastICA with the cube non-linearity (Hyvärinen & Oja 2000; SMC09 eq. 8-10, ICANN09 §2.3).

Model ``x = A s`` with independent non-Gaussian sources ``s``; estimate ``s = W x``. After
centring and whitening (``z = Vᵀ(x - μ)``, ``⟨z zᵀ⟩ = I``) each row ``w`` of ``W`` follows the
fixed point

    w⁺ = E{z g(wᵀz)} - E{g'(wᵀz)} w,      w = w⁺ / ‖w⁺‖

with ``g(u) = u³``, ``g'(u) = 3u²`` (the papers' contrast ``G`` with ``g = u³``, i.e. the
kurtosis-based FastICA). Rows are kept orthonormal either all at once (symmetric decorrelation
``W ← (W Wᵀ)^{-1/2} W``, the default) or one after the other (deflation, Gram-Schmidt).

Additions beyond the papers:

* each unit's sign is chosen so that its **peak response is positive** (``|max| >= |min|`` on the
  training data), as place cells fire positively;
* ``n_restarts`` random initialisations, the best kept by an **unsupervised** score of the
  training outputs (``"kurtosis"``: Σ|excess kurtosis|, the objective the cube non-linearity
  climbs; ``"sparseness"``: Σ(1 - E|s|); ``"slowness"``: minus the smallest Δ(s_i) = ⟨ṡ_i²⟩,
  i.e. prefer the rotation with the slowest single unit). ICA on the same SFA outputs lands in
  different local optima, so restarts are cheap insurance; they run on parallel threads
  (``workers``), with the same result as one after the other;
* whitening is skipped when the input is already white (SFA outputs are, on their training data).

Outputs are unit-variance on the data the ICA was fitted on (``output_std_`` = 1), so the
ICANN09 threshold "responds ≥ 4.5" means 4.5 training standard deviations.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import scipy.linalg

from hippo._checks import check_fields, check_finite
from hippo._estimator import NotFittedError, ParamsEstimator
from hippo._threads import parallel_map

SCORES = ("kurtosis", "sparseness", "slowness")


class ICAConvergenceWarning(UserWarning):
    """FastICA stopped at ``max_iter`` before the fixed point converged."""


@dataclass(frozen=True)
class ICAParams:
    """FastICA hyper-parameters (SMC09: 4 units; ICANN09: 70 units)."""

    #: number of independent components (None: as many as inputs)
    n_components: int | None = None
    #: "symmetric" (default) or "deflation"
    algorithm: str = "symmetric"
    max_iter: int = 1000
    tol: float = 1e-6
    #: random initialisations; the best by ``score`` is kept
    n_restarts: int = 1
    score: str = "kurtosis"
    #: "auto" (skip when the input is already white), True, or False
    whiten: bool | str = "auto"
    seed: int = 0
    #: threads the restarts run on (None: the usable cores); the result does not depend on it
    workers: int | None = None

    def __post_init__(self) -> None:
        check_fields(self)
        if self.n_components is not None and int(self.n_components) < 1:
            raise ValueError(f"n_components (n_ica) must be >= 1, got {self.n_components}")
        if self.algorithm not in ("symmetric", "deflation"):
            raise ValueError(f"algorithm must be 'symmetric' or 'deflation', got "
                             f"{self.algorithm!r}")
        if int(self.max_iter) < 1:
            raise ValueError(f"max_iter must be >= 1, got {self.max_iter}")
        if not float(self.tol) > 0:
            raise ValueError(f"tol must be > 0, got {self.tol}")
        if int(self.n_restarts) < 1:
            raise ValueError(f"n_restarts must be >= 1, got {self.n_restarts}")
        if self.score not in SCORES:
            raise ValueError(f"score must be one of {SCORES}, got {self.score!r}")
        if self.workers is not None and int(self.workers) < 1:
            raise ValueError(f"workers must be >= 1 or None, got {self.workers}")
        if self.whiten not in ("auto", True, False):
            raise ValueError(f"whiten must be 'auto', True or False, got {self.whiten!r}")


def _sym_decorrelate(W: np.ndarray) -> np.ndarray:
    s, u = scipy.linalg.eigh(W @ W.T, check_finite=False)
    s = np.clip(s, np.finfo(float).tiny, None)
    return (u / np.sqrt(s)) @ u.T @ W


def _fastica_symmetric(Z: np.ndarray, W: np.ndarray, max_iter: int, tol: float
                       ) -> tuple[np.ndarray, int, bool, float]:
    """Z: (k, T) white; W: (k, k) initial. Returns W, iterations, converged, last change.

    First the papers' fixed point ``W⁺ = E{g(Wz) zᵀ} - diag(E{g'(Wz)}) W`` with symmetric
    decorrelation. It can oscillate for ever when some directions are nearly Gaussian; if it has
    not converged after ``min(200, max_iter // 2)`` iterations it continues from where it is with
    the stabilised Newton step (Hyvärinen 1999) ``w⁺ = w - μ (E{z g(y)} - β w) / (E{g'(y)} - β)``,
    ``β = E{y g(y)}``, halving μ whenever the change has not reached a new low for 25
    iterations (down to 1/64).
    """
    T = Z.shape[1]
    W = _sym_decorrelate(W)
    switch = min(200, max_iter // 2)
    lim = best = np.inf
    mu, since_best = 1.0, 0
    for it in range(1, max_iter + 1):
        Y = W @ Z
        Y2 = Y * Y
        gY = Y2 * Y                                   # g(y) = y³ (u*u*u: far faster than u**3)
        if it <= switch:
            W1 = _sym_decorrelate(gY @ Z.T / T - 3.0 * Y2.mean(axis=1)[:, None] * W)
        else:
            beta = np.einsum("ij,ij->i", gY, Y) / T   # E{y g(y)} = E{y⁴}
            denom = 3.0 * Y2.mean(axis=1) - beta      # E{g'(y)} - β = -(excess kurtosis)
            denom = np.where(np.abs(denom) < 1e-12, 1e-12, denom)
            step = (gY @ Z.T / T - beta[:, None] * W) / denom[:, None]
            W1 = _sym_decorrelate(W - mu * step)
        lim = float(np.max(np.abs(np.abs(np.einsum("ij,ij->i", W1, W)) - 1.0)))
        W = W1
        if lim < tol:
            return W, it, True, lim
        if it > switch:
            if lim < best:
                best, since_best = lim, 0
            else:
                since_best += 1
                if since_best >= 25 and mu > 1 / 64:
                    mu, since_best, best = mu / 2, 0, lim
    return W, max_iter, False, lim


def _fastica_deflation(Z: np.ndarray, W: np.ndarray, max_iter: int, tol: float
                       ) -> tuple[np.ndarray, int, bool, float]:
    T = Z.shape[1]
    k = W.shape[0]
    out = np.zeros_like(W)
    n_iter, converged, worst = 0, True, 0.0
    for p in range(k):
        w = W[p] / np.linalg.norm(W[p])
        lim = np.inf
        ok = False
        used = 0
        while used < max_iter:
            used += 1
            y = w @ Z
            y2 = y * y
            w1 = Z @ (y2 * y) / T - 3.0 * y2.mean() * w
            w1 -= out[:p].T @ (out[:p] @ w1)
            w1 /= np.linalg.norm(w1)
            lim = abs(abs(float(w1 @ w)) - 1.0)
            w = w1
            if lim < tol:
                ok = True
                break
        out[p] = w
        n_iter = max(n_iter, used)
        converged &= ok
        worst = max(worst, lim)
    return out, n_iter, converged, worst


def score_outputs(S: np.ndarray, criterion: str) -> float:
    """Unsupervised quality of ICA outputs ``S`` (T, k), unit variance; higher is better."""
    if criterion == "kurtosis":
        S2 = S * S
        return float(np.sum(np.abs((S2 * S2).mean(axis=0) - 3.0)))
    if criterion == "sparseness":
        return float(np.sum(1.0 - np.abs(S).mean(axis=0)))
    if criterion == "slowness":
        return -float(np.min(np.mean(np.diff(S, axis=0) ** 2, axis=0)))
    raise ValueError(f"unknown score {criterion!r}; choose from {SCORES}")


class FastICA(ParamsEstimator):
    """FastICA, cube non-linearity: ``w⁺ = E{z (wᵀz)³} - 3 E{(wᵀz)²} w`` (SMC09 eq. 8-10).

    Fitted attributes: ``mean_`` (d,), ``whitening_`` (d, k) with ``z = (x - mean_) @
    whitening_``, ``rotation_`` (k, k) orthogonal, ``components_`` (k, d) with ``s = (x - mean_)
    @ components_.T``, ``n_iter_``, ``converged_``, ``score_``, ``restart_scores_``,
    ``output_std_`` (ones: outputs are unit-variance on the training data).
    """

    def __init__(self, params: ICAParams | None = None, **overrides: Any) -> None:
        self.params = replace(params or ICAParams(), **overrides)

    def fit(self, X: np.ndarray, y: None = None) -> FastICA:
        """Estimate the unmixing of ``X`` (T, d), rows are samples."""
        X = np.asarray(X)
        if X.ndim != 2:
            raise ValueError(f"X must be a 2-D array (time, features), got shape {X.shape}")
        X = check_finite("X", X)
        p = self.params
        T, d = X.shape
        k = d if p.n_components is None else int(p.n_components)
        if k > d:
            raise ValueError(f"n_ica={k} exceeds the ICA input dimension {d}")
        if T < 2:
            raise ValueError(f"ICA needs at least 2 samples, got {T}")
        self.n_features_in_ = d
        self.mean_ = X.mean(axis=0)
        Xc = X - self.mean_
        C = Xc.T @ Xc / T
        white = (np.max(np.abs(C - np.eye(d))) < 1e-6
                 and np.max(np.abs(self.mean_)) < 1e-6 and k == d)
        if p.whiten is False or (p.whiten == "auto" and white):
            if k != d:
                raise ValueError("whiten=False needs n_components equal to the input dimension")
            self.whitening_ = np.eye(d)
            self.whitened_ = False
        else:
            ev, E = scipy.linalg.eigh(C, check_finite=False)
            ev, E = ev[::-1][:k], E[:, ::-1][:, :k]
            if ev[-1] <= 1e-12 * max(ev[0], 1e-300):
                raise ValueError(f"the ICA input has fewer than n_ica={k} non-degenerate "
                                 "directions")
            self.whitening_ = E / np.sqrt(ev)
            self.whitened_ = True
        Z = (Xc @ self.whitening_).T.copy()  # (k, T)

        rng = np.random.default_rng(p.seed)
        solver = _fastica_symmetric if p.algorithm == "symmetric" else _fastica_deflation
        starts = [rng.standard_normal((k, k)) for _ in range(int(p.n_restarts))]

        def restart(W0: np.ndarray) -> tuple[float, np.ndarray, int, bool, float]:
            W, n_iter, ok, lim = solver(Z, W0, int(p.max_iter), float(p.tol))
            return score_outputs((W @ Z).T, p.score), W, n_iter, ok, lim

        best = None
        scores, failed = [], 0
        for s, W, n_iter, ok, lim in parallel_map(restart, starts, p.workers):
            failed += not ok
            scores.append(s)
            if best is None or s > best[0]:
                best = (s, W, n_iter, ok, lim)
        score, W, n_iter, ok, lim = best
        if failed:
            warnings.warn(
                f"FastICA ({p.algorithm}) did not converge in {failed} of {p.n_restarts} "
                f"restart(s) within max_iter={p.max_iter} iterations; the kept one ran "
                f"{n_iter} iterations, last change {lim:.2e} (tol {p.tol:g})",
                ICAConvergenceWarning, stacklevel=2)
        # sign: peak response positive
        S = W @ Z
        flip = np.abs(S.min(axis=1)) > np.abs(S.max(axis=1))
        W = np.where(flip[:, None], -W, W)
        self.rotation_ = W
        self.components_ = W @ self.whitening_.T
        self.n_iter_ = n_iter
        self.converged_ = ok
        self.score_ = score
        self.restart_scores_ = np.asarray(scores)
        self.output_std_ = np.ones(k)
        return self

    def transform(self, X: np.ndarray) -> np.ndarray:
        """Independent components ``(T, k)`` of ``X`` ``(T, d)``."""
        if not hasattr(self, "components_"):
            raise NotFittedError("FastICA is not fitted yet; call fit(X) first")
        X = np.asarray(X)
        if X.ndim != 2 or X.shape[1] != self.n_features_in_:
            raise ValueError(f"X must have shape (T, {self.n_features_in_}), got {X.shape}")
        X = check_finite("X", X)
        return (X - self.mean_) @ self.components_.T

    def fit_transform(self, X: np.ndarray, y: None = None) -> np.ndarray:
        """``fit(X)``, then the components of ``X`` (``y`` is ignored, as in scikit-learn)."""
        return self.fit(X).transform(X)

    def __repr__(self) -> str:
        p = self.params
        return (f"FastICA(n_components={p.n_components}, algorithm={p.algorithm!r}, "
                f"n_restarts={p.n_restarts}, score={p.score!r}, seed={p.seed})")
