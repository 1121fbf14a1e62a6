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
  i.e. prefer the rotation with the slowest single unit; :mod:`~hippo.perception.ica_scores`).
  ICA on the same SFA outputs lands in different local optima, so restarts are cheap
  insurance; they run on parallel threads (``workers``), with the same result as one after the
  other; scores within ``tol`` (relative) of each other tie, and the earlier restart is kept;
* whitening is skipped when the input's covariance is already the identity (SFA outputs' is, on
  their training data; the input is centred either way);
* the expectations are sums over **chunks** of ``_CHUNK`` samples, each whitened when it is
  used: the fit holds no array of the input's length besides the input itself (which may be
  float32), so a fit on 10⁶ ticks needs the memory of one on 10⁴. Up to ``_CHUNK`` samples the
  whitened input is computed once and the numbers are those of the one-array form.

Outputs are unit-variance on the data the ICA was fitted on (``output_std_`` = 1), so the
ICANN09 threshold "responds ≥ 4.5" means 4.5 training standard deviations. The
hyper-parameters are :class:`~hippo.perception.ica_params.ICAParams`.

A fitted FastICA saves and loads its own state (:meth:`FastICA.to_arrays` /
:meth:`FastICA.from_arrays`, :meth:`FastICA.save` / :meth:`FastICA.load`:
:mod:`~hippo.perception.part_files`).
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import numpy as np
import scipy.linalg

from hippo._checks import check_finite
from hippo._estimator import NotFittedError, ParamsEstimator
from hippo._threads import parallel_map
from hippo.perception.ica_params import ICAParams
from hippo.perception.ica_scores import _score_chunks
from hippo.perception.ica_scores import score_outputs as score_outputs
from hippo.perception.part_files import PartArrays, PartFile


class ICAConvergenceWarning(UserWarning):
    """FastICA stopped at ``max_iter`` before the fixed point converged."""


def _sym_decorrelate(W: np.ndarray) -> np.ndarray:
    """``(W Wᵀ)^{-1/2} W``. LAPACK ``dsyevr`` is called as ``scipy.linalg.eigh`` calls it (the
    same numbers) without its checks, which cost 3 x the k x k solve itself."""
    k = W.shape[0]
    if k not in _SYEVR_LWORK:
        lw, liw, _ = scipy.linalg.lapack.dsyevr_lwork(k, lower=1)
        _SYEVR_LWORK[k] = (int(lw), int(liw))
    lw, liw = _SYEVR_LWORK[k]
    s, u, _, _, info = scipy.linalg.lapack.dsyevr(W @ W.T, compute_v=1, lower=1, lwork=lw,
                                                  liwork=liw)
    if info != 0:  # pragma: no cover - a symmetric k x k matrix of finite values
        raise np.linalg.LinAlgError(f"dsyevr failed (info={info})")
    s = np.maximum(s, np.finfo(float).tiny)
    return (u / np.sqrt(s)) @ u.T @ W


#: LAPACK work sizes of ``dsyevr`` by matrix size, as ``scipy.linalg.eigh`` computes them
_SYEVR_LWORK: dict[int, tuple[int, int]] = {}


def _mean_cov(X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Mean (d,) and covariance ``⟨(x - μ)(x - μ)ᵀ⟩`` (d, d) of ``X`` (T, d) in float64,
    chunk by chunk."""
    T, d = X.shape
    if T <= _CHUNK:
        mean = X.mean(axis=0, dtype=np.float64)
        Xc = X - mean
        return mean, Xc.T @ Xc / T
    mean = np.zeros(d)
    for t0 in range(0, T, _CHUNK):
        mean += np.asarray(X[t0:t0 + _CHUNK], dtype=np.float64).sum(axis=0)
    mean /= T
    C = np.zeros((d, d))
    for t0 in range(0, T, _CHUNK):
        Xc = X[t0:t0 + _CHUNK] - mean  # float64 from float32 input too (the mean is float64)
        C += Xc.T @ Xc
    return mean, C / T


#: samples per chunk of the ICA expectations (k x _CHUNK float64 temporaries per step)
_CHUNK = 65536


class _White:
    """The whitened input ``z = whiteningᵀ(x - mean)`` of a recording ``X`` (T, d), served
    in chunks of columns ``(k, ≤ _CHUNK)`` float64. Held whole when it is one chunk, else
    each chunk is whitened when it is used (nothing of length T is allocated)."""

    def __init__(self, X: np.ndarray, mean: np.ndarray, whitening: np.ndarray) -> None:
        self.X, self.mean, self.V = X, mean, whitening
        self.T = X.shape[0]
        self.bounds = [*range(0, self.T, _CHUNK), self.T]
        self._held = self._whiten(0, self.T) if self.T <= _CHUNK else None

    def _whiten(self, t0: int, t1: int) -> np.ndarray:
        # float64 from float32 input too (the mean is float64)
        return ((self.X[t0:t1] - self.mean) @ self.V).T.copy()

    def __iter__(self):
        if self._held is not None:
            yield self._held
            return
        for t0, t1 in zip(self.bounds[:-1], self.bounds[1:]):
            yield self._whiten(t0, t1)


def _moments(Z: _White, W: np.ndarray, beta: bool = False
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """``E{g(Wz) zᵀ}`` (k, k), ``E{(Wz)²}`` (k,) and, with ``beta``, ``E{y g(y)}`` (k,) for
    ``g(y) = y³``: sums over the chunks of ``Z``, divided by T."""
    gz, y2, yg = np.zeros(W.shape), np.zeros(len(W)), np.zeros(len(W))
    for z in Z:
        Y = W @ z
        Y2 = Y * Y
        gY = Y2 * Y                                   # g(y) = y³ (u*u*u: far faster than u**3)
        gz += gY @ z.T
        y2 += Y2.sum(axis=1)
        if beta:
            yg += np.einsum("ij,ij->i", gY, Y)
    T = Z.T
    return gz / T, y2 / T, (yg / T if beta else None)


def _fastica_symmetric(Z: _White, W: np.ndarray, max_iter: int, tol: float
                       ) -> tuple[np.ndarray, int, bool, float]:
    """Z: the white input (k, T) in chunks; W: (k, k) initial. Returns W, iterations,
    converged, last change.

    First the papers' fixed point ``W⁺ = E{g(Wz) zᵀ} - diag(E{g'(Wz)}) W`` with symmetric
    decorrelation. It can oscillate for ever when some directions are nearly Gaussian; if it has
    not converged after ``min(200, max_iter // 2)`` iterations it continues from where it is with
    the stabilised Newton step (Hyvärinen 1999) ``w⁺ = w - μ (E{z g(y)} - β w) / (E{g'(y)} - β)``,
    ``β = E{y g(y)}``, halving μ whenever the change has not reached a new low for 25
    iterations (down to 1/64).
    """
    W = _sym_decorrelate(W)
    switch = min(200, max_iter // 2)
    lim = np.inf
    step_size = _NewtonStepSize()
    for it in range(1, max_iter + 1):
        newton = it > switch
        if not newton:
            gz, y2, _ = _moments(Z, W)
            W1 = _sym_decorrelate(gz - 3.0 * y2[:, None] * W)
        else:
            gz, y2, beta = _moments(Z, W, beta=True)   # beta = E{y g(y)} = E{y⁴}
            denom = 3.0 * y2 - beta                   # E{g'(y)} - β = -(excess kurtosis)
            denom = np.where(np.abs(denom) < 1e-12, 1e-12, denom)
            step = (gz - beta[:, None] * W) / denom[:, None]
            W1 = _sym_decorrelate(W - step_size.mu * step)
        lim = float(np.max(np.abs(np.abs(np.einsum("ij,ij->i", W1, W)) - 1.0)))
        W = W1
        if lim < tol:
            return W, it, True, lim
        if newton:
            step_size.update(lim)
    return W, max_iter, False, lim


class _NewtonStepSize:
    """μ of the stabilised Newton phase: 1 at first, halved whenever the change has not
    reached a new low for ``patience`` iterations in a row (the low then restarts from the
    current change), never below ``floor``."""

    def __init__(self, patience: int = 25, floor: float = 1 / 64) -> None:
        self.patience, self.floor = patience, floor
        self.mu, self.best, self.since_best = 1.0, np.inf, 0

    def update(self, change: float) -> None:
        """Count one more iteration with this ``change``."""
        if change < self.best:
            self.best, self.since_best = change, 0
        else:
            self.since_best += 1
            if self.since_best >= self.patience and self.mu > self.floor:
                self.mu, self.since_best, self.best = self.mu / 2, 0, change


def _fastica_deflation(Z: _White, W: np.ndarray, max_iter: int, tol: float
                       ) -> tuple[np.ndarray, int, bool, float]:
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
            gz, y2, _ = _moments(Z, w[None, :])
            w1 = gz[0] - 3.0 * y2[0] * w
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


class FastICA(PartFile, ParamsEstimator):
    """FastICA, cube non-linearity: ``w⁺ = E{z (wᵀz)³} - 3 E{(wᵀz)²} w`` (SMC09 eq. 8-10).

    Fitted attributes: ``mean_`` (d,), ``whitening_`` (d, k) with ``z = (x - mean_) @
    whitening_``, ``rotation_`` (k, k) orthogonal, ``components_`` (k, d) with ``s = (x - mean_)
    @ components_.T``, ``n_iter_``, ``converged_``, ``score_``, ``restart_scores_``,
    ``output_std_`` (ones: outputs are unit-variance on the training data), ``whitened_``
    (False when the whitening was skipped: ``whitening_`` is the identity).

    Its saved state (:meth:`to_arrays`, :meth:`save`): ``mean``, ``whitening``, ``rotation``
    (``components_`` is rebuilt from them bit for bit); the fit's diagnostics are not saved.
    """

    FILE_FORMAT = "hippo.perception.FastICA/1"
    _PARAMS = ICAParams

    def __init__(self, params: ICAParams | None = None, **overrides: Any) -> None:
        self.params = replace(params or ICAParams(), **overrides)

    def fit(self, X: np.ndarray, y: None = None) -> FastICA:
        """Estimate the unmixing of ``X`` (T, d), rows are samples (float64, or float32 kept
        as is: it is read chunk by chunk, never copied whole)."""
        X = np.asarray(X)
        if X.ndim != 2:
            raise ValueError(f"X must be a 2-D array (time, features), got shape {X.shape}")
        X = check_finite("X", X, keep_float32=True)
        p = self.params
        T, d = X.shape
        k = d if p.n_components is None else int(p.n_components)
        if k > d:
            raise ValueError(f"n_ica={k} exceeds the ICA input dimension {d}")
        if T < 2:
            raise ValueError(f"ICA needs at least 2 samples, got {T}")
        self.n_features_in_ = d
        with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused below
            self.mean_, C = _mean_cov(X)
        if not np.isfinite(C).all():
            raise ValueError(f"X is too large: its covariance overflows float64 (|X| up to "
                             f"{np.max(np.abs(X)):.3g}); rescale it")
        # white: unit covariance (the input is centred with mean_ either way)
        white = np.max(np.abs(C - np.eye(d))) < 1e-6 and k == d
        if p.whiten is False or (p.whiten == "auto" and white):
            if k != d:
                raise ValueError("whiten=False needs n_components equal to the input dimension")
            self.whitening_ = np.eye(d)
            self.whitened_ = False
        else:
            ev, E = scipy.linalg.eigh(C, check_finite=False)
            ev, E = ev[::-1][:k], E[:, ::-1][:, :k]
            # an eigenvector's sign is arbitrary (rounding in C can flip it): make each
            # one's largest entry positive, so the whitened input does not hang on rounding
            E = E * np.sign(E[np.argmax(np.abs(E), axis=0), np.arange(k)])
            if ev[-1] <= 1e-12 * max(ev[0], 1e-300):
                raise ValueError(f"the ICA input has fewer than n_ica={k} non-degenerate "
                                 "directions")
            self.whitening_ = E / np.sqrt(ev)
            self.whitened_ = True
        Z = _White(X, self.mean_, self.whitening_)  # z = whiteningᵀ(x - mean), (k, T) in chunks

        rng = np.random.default_rng(p.seed)
        solver = _fastica_symmetric if p.algorithm == "symmetric" else _fastica_deflation
        starts = [rng.standard_normal((k, k)) for _ in range(int(p.n_restarts))]

        def restart(W0: np.ndarray) -> tuple[float, np.ndarray, int, bool, float]:
            W, n_iter, ok, lim = solver(Z, W0, int(p.max_iter), float(p.tol))
            return _score_chunks(((W @ z).T for z in Z), p.score), W, n_iter, ok, lim

        best = None
        scores, failed = [], 0
        for s, W, n_iter, ok, lim in parallel_map(restart, starts, p.workers):
            failed += not ok
            scores.append(s)
            # restarts that reach the same optimum (up to a permutation) tie to within the
            # solver's tolerance: a later restart must beat the kept one by more than ``tol``
            # (relative), so the choice does not hang on the order of a sum
            if best is None or s > best[0] + float(p.tol) * abs(best[0]):
                best = (s, W, n_iter, ok, lim)
        score, W, n_iter, ok, lim = best
        if failed:
            warnings.warn(
                f"FastICA ({p.algorithm}) did not converge in {failed} of {p.n_restarts} "
                f"restart(s) within max_iter={p.max_iter} iterations; the kept one ran "
                f"{n_iter} iterations, last change {lim:.2e} (tol {p.tol:g})",
                ICAConvergenceWarning, stacklevel=2)
        # sign: peak response positive
        lo, hi = np.full(k, np.inf), np.full(k, -np.inf)
        for z in Z:
            S = W @ z
            lo, hi = np.minimum(lo, S.min(axis=1)), np.maximum(hi, S.max(axis=1))
        flip = np.abs(lo) > np.abs(hi)
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
        self._check_fitted()
        X = np.asarray(X)
        if X.ndim != 2 or X.shape[1] != self.n_features_in_:
            raise ValueError(f"X must have shape (T, {self.n_features_in_}), got {X.shape}")
        X = check_finite("X", X)
        return (X - self.mean_) @ self.components_.T

    def fit_transform(self, X: np.ndarray, y: None = None) -> np.ndarray:
        """``fit(X)``, then the components of ``X`` (``y`` is ignored, as in scikit-learn)."""
        return self.fit(X).transform(X)

    def to_arrays(self, prefix: str = "") -> dict[str, np.ndarray]:
        """The fitted state as arrays (copies), each key led by ``prefix``."""
        self._check_fitted()
        state = {"mean": self.mean_, "whitening": self.whitening_, "rotation": self.rotation_}
        return {prefix + k: np.array(v) for k, v in state.items()}  # copies, same layout

    @classmethod
    def from_arrays(cls, params: ICAParams, arrays: Mapping[str, Any], prefix: str = "", *,
                    n_features_in: int | None = None) -> FastICA:
        """A fitted FastICA from :meth:`to_arrays`' output (keys led by ``prefix``), checked
        (keys, shapes against ``params`` and the input width ``n_features_in`` if given,
        finite, ``rotation`` orthonormal); a ``ValueError`` names the key."""
        a = PartArrays("FastICA", arrays, prefix, ("mean", "whitening", "rotation"))
        mean = a.get("mean", (n_features_in,))
        d = mean.shape[0]
        k = d if params.n_components is None else int(params.n_components)
        if k > d:
            raise ValueError(f"{prefix}mean has {d} values: fewer inputs than n_components={k}")
        ica = cls(params)
        ica.mean_, ica.whitening_ = mean, a.get("whitening", (d, k))
        ica.rotation_ = a.get("rotation", (k, k))
        if not np.allclose(ica.rotation_ @ ica.rotation_.T, np.eye(k), atol=1e-6):
            raise ValueError(f"{prefix}rotation is not orthonormal (FastICA's unmixing is)")
        ica.components_ = ica.rotation_ @ ica.whitening_.T
        ica.n_features_in_, ica.output_std_ = d, np.ones(k)
        ica.whitened_ = not np.array_equal(ica.whitening_, np.eye(d))
        return ica

    def _check_fitted(self) -> None:
        if not hasattr(self, "components_"):
            raise NotFittedError("FastICA is not fitted yet; call fit(X) first")

    def __repr__(self) -> str:
        p = self.params
        return (f"FastICA(n_components={p.n_components}, algorithm={p.algorithm!r}, "
                f"n_restarts={p.n_restarts}, score={p.score!r}, seed={p.seed})")


#: rows per chunk when the ICA outputs' statistics are taken
_OUT_CHUNK = 65536


def output_stats(ica: FastICA, Y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Standard deviation and 99.9th percentile of each ICA output on its training input
    ``Y`` (T, n_sfa), one output at a time (one float64 column of length T alive, not the
    whole (T, n_ica) output)."""
    k = ica.components_.shape[0]
    std, peak = np.empty(k), np.empty(k)
    col = np.empty(Y.shape[0])
    for j in range(k):
        for t0 in range(0, Y.shape[0], _OUT_CHUNK):
            # float64 from float32 input too (the mean is float64)
            col[t0:t0 + _OUT_CHUNK] = (Y[t0:t0 + _OUT_CHUNK] - ica.mean_) @ ica.components_[j]
        std[j] = col.std()
        peak[j] = np.percentile(col, 99.9, overwrite_input=True)
    return std, peak
