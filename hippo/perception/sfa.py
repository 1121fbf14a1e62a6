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

The data enter only through their moments (mean, ``Σ x xᵀ``, ``Σ ẋ ẋᵀ``), accumulated chunk by
chunk in float64 by :class:`~hippo.perception.sfa_moments.SFAMoments` (so a float32 recording is
never copied whole, and ``RCSFAICA.fit`` can summarise reservoir states while the reservoir is
still running).

A fitted SFA saves and loads its own state (:meth:`SFA.to_arrays` / :meth:`SFA.from_arrays`,
:meth:`SFA.save` / :meth:`SFA.load`: :mod:`~hippo.perception.part_files`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from itertools import pairwise
from typing import Any

import numpy as np
import scipy.linalg

from hippo._checks import as_array, check_fields, check_finite
from hippo._estimator import NotFittedError, ParamsEstimator
from hippo._threads import single_threaded_blas
from hippo.perception.part_files import PartArrays, PartFile
from hippo.perception.sfa_moments import SFAMoments, chunk_bounds

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
        check_fields(self)
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


def _whiten(C: np.ndarray, cutoff: float) -> tuple[np.ndarray, np.ndarray]:
    d, E = scipy.linalg.eigh(C, overwrite_a=False, check_finite=False, driver="evd")
    keep = d > cutoff * max(d[-1], np.finfo(float).tiny)
    return E[:, keep] / np.sqrt(d[keep]), d[::-1]


def _slow(S: np.ndarray, A: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    Aw = S.T @ A @ S
    Aw = 0.5 * (Aw + Aw.T)
    lam, V = scipy.linalg.eigh(Aw, subset_by_index=[0, n - 1], check_finite=False)
    return lam, S @ V


class SFA(PartFile, ParamsEstimator):
    """Linear (or quadratic) SFA: ``y = Wᵀ (x - μ)/σ`` with ``A W = B W Λ`` (SMC09 eq. 6-7).

    Fitted attributes: ``mean_``, ``scale_`` (z-scoring of the expanded input), ``W_``
    ``(d, n)`` applied to the z-scored input, ``slowness_`` (the eigenvalues Δ, ascending),
    ``n_whitened_`` (directions kept by the cutoff), ``cutoff_`` (the cutoff used; the chosen
    one for ``"auto"``), ``input_eigenvalues_`` (eigenvalues of ``B``, descending).

    Outputs on the training data are zero-mean, unit-variance, decorrelated and ordered by
    slowness; each unit's sign is chosen so that its skewness is >= 0.

    Its saved state (:meth:`to_arrays`, :meth:`save`): ``mean``, ``scale``, ``W``,
    ``slowness``, ``cutoff``, ``n_whitened`` and, for the quadratic expansion, ``pre_mean``,
    ``pre_scale``. ``input_eigenvalues_`` and ``cutoff_scores_`` describe the fit and are
    not saved.
    """

    FILE_FORMAT = "hippo.perception.SFA/1"
    _PARAMS = SFAParams

    def __init__(self, params: SFAParams | None = None, **overrides: Any) -> None:
        self.params = replace(params or SFAParams(), **overrides)

    # ------------------------------------------------------------------ helpers
    def _expand(self, X: np.ndarray) -> np.ndarray:
        if self.params.expansion == "linear":
            return X
        return quadratic_expansion((X - self.pre_mean_) / self.pre_scale_)

    def _check_X(self, X: Any, name: str = "X") -> np.ndarray:
        X = as_array(name, X)
        if X.ndim != 2:
            raise ValueError(f"{name} must be a 2-D array (time, features), got shape {X.shape}")
        # complex values and strings are refused, not cast; an object array may hold numbers
        # (scikit-learn's convention), its other objects fail the cast to float below
        bad = None if X.dtype.kind != "O" else next(
            (v for v in X.flat if isinstance(v, str | bytes | complex | np.complexfloating)), None)
        if X.dtype.kind not in "biufO" or bad is not None:
            held = "" if bad is None else f" holding {bad!r:.40} ({type(bad).__name__})"
            raise ValueError(f"{name} must hold real numbers, got dtype {X.dtype}{held}")
        return check_finite(name, X, keep_float32=True)

    # ------------------------------------------------------------------ fit / transform
    def fit(self, X: np.ndarray, y: None = None) -> SFA:
        """Learn the slow features of ``X`` (T, d), rows in time order."""
        X = self._check_X(X)
        self._fit_moments(self.accumulate(X), X)
        return self

    def accumulate(self, X: np.ndarray) -> list[SFAMoments]:
        """``X`` (T, d) summarised chunk by chunk: the moments ``fit`` learns from. One
        :class:`SFAMoments`, or two (the first 80 % and the rest) for ``cutoff="auto"``."""
        X = self._check_X(X)
        self._prepare(X)
        T = X.shape[0]
        split = self.auto_split(T)
        parts = [SFAMoments(self.n_expanded_) for _ in range(1 if split is None else 2)]
        bounds = chunk_bounds(T, self.n_expanded_, split=split)
        for t0, t1 in pairwise(bounds):
            parts[0 if split is None or t1 <= split else 1].update(self._expand(X[t0:t1]))
        return parts

    def auto_split(self, T: int) -> int | None:
        """Where ``cutoff="auto"`` splits ``T`` training samples (None for a fixed cutoff)."""
        return int(0.8 * T) if self.params.cutoff == "auto" else None

    def _prepare(self, X: np.ndarray) -> None:
        """Shape checks and the input scaling of the quadratic expansion."""
        self._prepare_shape(*X.shape, X=X)

    def _prepare_shape(self, T: int, d_in: int, X: np.ndarray | None = None) -> None:
        """:meth:`_prepare` from the shape alone (the linear expansion needs no data: a
        streamed fit never holds ``X``)."""
        n = int(self.params.n_components)
        if self.params.expansion == "quadratic" and X is None:
            raise ValueError("the quadratic expansion needs the data to scale its input")
        if T < 3:
            raise ValueError(f"SFA needs at least 3 samples, got {T}")
        self.n_features_in_ = d_in
        if self.params.expansion == "quadratic":
            self.pre_mean_ = X.mean(axis=0, dtype=np.float64)
            sd = X.std(axis=0, dtype=np.float64)
            self.pre_scale_ = np.where(sd > 1e-12 * (1.0 + np.abs(self.pre_mean_)), sd, 1.0)
            self.n_expanded_ = d_in + d_in * (d_in + 1) // 2
        else:
            self.n_expanded_ = d_in
        if n > self.n_expanded_:
            raise ValueError(f"n_sfa={n} exceeds the SFA input dimension {self.n_expanded_}")

    def _fit_moments(self, parts: list[SFAMoments], X: np.ndarray) -> np.ndarray:
        """Solve SFA from the moments of ``X`` (from :meth:`accumulate`); returns the training
        outputs."""
        self._solve(parts, X.shape[0])
        return self._sign(self._project(X))

    def _sign(self, y: np.ndarray) -> np.ndarray:
        """Sign-normalise the units on their training outputs ``y`` (positive skew, ``⟨y³⟩``
        summed over chunks of 65,536 rows in float64); flips ``y`` in place and returns it."""
        cube = np.zeros(y.shape[1])
        for t0 in range(0, y.shape[0], 65536):
            c = np.asarray(y[t0:t0 + 65536], dtype=np.float64)
            cube += (c ** 3).sum(axis=0)
        sign = np.where(cube / y.shape[0] < 0, -1.0, 1.0)
        self.W_ = self.W_ * sign
        y *= sign.astype(y.dtype)
        return y

    def _solve(self, parts: list[SFAMoments], T: int) -> None:
        """The slow directions ``W_`` (before :meth:`_sign`) from the moments of ``T`` samples.

        Solved on one BLAS thread: the eigensolvers' reductions are summed in another order
        on two threads (``W_`` moved by up to 1.7e-11 at N = 600), and the free cores, so the
        thread count, depend on the machine's load: same data, same bits, on any load."""
        with single_threaded_blas():
            self._solve_moments(parts, T)

    def _solve_moments(self, parts: list[SFAMoments], T: int) -> None:
        n = int(self.params.n_components)
        total = parts[0] if len(parts) == 1 else parts[0].merged(parts[1])
        if total.n != T:
            raise ValueError(f"moments of {total.n} samples do not describe X ({T} rows)")
        if not (np.isfinite(total.scatter).all() and np.isfinite(total.diff_scatter).all()):
            raise ValueError("X's second moments overflow float64 (values too large to square "
                             "and sum); rescale X")
        self.mean_ = total.mean
        sd = np.sqrt(np.maximum(np.diag(total.scatter) / total.n, 0.0))
        # constant columns: scale 1 (they become 0 and the cutoff drops them)
        self.scale_ = np.where(sd > 1e-12 * (1.0 + np.abs(self.mean_)), sd, 1.0)
        inv = 1.0 / np.outer(self.scale_, self.scale_)
        C = total.scatter * inv / total.n
        A = total.diff_scatter * inv / total.n_diff
        cutoff = self.params.cutoff
        if cutoff == "auto":
            cutoff = self._select_cutoff(parts, inv, n)
        self.cutoff_ = float(cutoff)
        S, eig = _whiten(C, self.cutoff_)
        self.input_eigenvalues_ = eig
        self.n_whitened_ = S.shape[1]
        if self.n_whitened_ < n:
            raise ValueError(
                f"only {self.n_whitened_} input directions survive the whitening cutoff "
                f"{self.cutoff_:g} but n_sfa={n}; lower the cutoff or n_sfa")
        lam, W = _slow(S, A, n)
        self.W_ = W
        self.slowness_ = lam

    def _select_cutoff(self, parts: list[SFAMoments], inv: np.ndarray, n: int) -> float:
        first, rest = parts
        C1 = first.scatter_about(self.mean_) * inv / first.n
        A1 = first.diff_scatter * inv / first.n_diff
        C2 = rest.scatter_about(self.mean_) * inv
        A2 = rest.diff_scatter * inv
        d, E = scipy.linalg.eigh(C1, check_finite=False)
        best, best_score = None, np.inf
        scores = {}
        for c in _AUTO_CANDIDATES:
            keep = d > c * d[-1]
            if keep.sum() < n:
                continue
            S = E[:, keep] / np.sqrt(d[keep])
            _, W = _slow(S, A1, n)
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

    def _project(self, X: np.ndarray) -> np.ndarray:
        """``z(expand(X)) @ W_``, chunk by chunk (no full-size float64 copy)."""
        out = np.empty((X.shape[0], self.W_.shape[1]))
        bounds = chunk_bounds(X.shape[0], self.mean_.shape[0])
        M = self.W_ / self.scale_[:, None]                 # z(x) @ W == x @ M - mean @ M
        b = self.mean_ @ M
        for t0, t1 in pairwise(bounds):
            out[t0:t1] = np.asarray(self._expand(X[t0:t1]), dtype=np.float64) @ M
        out -= b
        return out

    def transform(self, X: np.ndarray) -> np.ndarray:
        """Slow features ``(T, n)`` of ``X`` ``(T, d)``."""
        self._check_fitted()
        X = self._check_X(X)
        if X.shape[1] != self.n_features_in_:
            raise ValueError(f"X has {X.shape[1]} features, SFA was fitted on "
                             f"{self.n_features_in_}")
        return self._project(X)

    def fit_transform(self, X: np.ndarray, y: None = None) -> np.ndarray:
        """``fit(X)``, then the slow features of ``X`` (computed once)."""
        X = self._check_X(X)
        return self._fit_moments(self.accumulate(X), X)

    def affine(self) -> tuple[np.ndarray, np.ndarray]:
        """``(M, b)`` with ``transform(X) == X @ M + b`` (linear expansion only)."""
        self._check_fitted()
        if self.params.expansion != "linear":
            raise ValueError("affine() exists only for the linear expansion")
        M = self.W_ / self.scale_[:, None]
        return M, -(self.mean_ / self.scale_) @ self.W_

    # ------------------------------------------------------------------ state
    def to_arrays(self, prefix: str = "") -> dict[str, np.ndarray]:
        """The fitted state as arrays (copies), each key led by ``prefix``. ``cutoff`` and
        ``n_whitened`` are left out when unknown (a model loaded from an old file)."""
        self._check_fitted()
        out = {"mean": self.mean_, "scale": self.scale_, "W": self.W_,
               "slowness": self.slowness_, "cutoff": self.cutoff_, "n_whitened": self.n_whitened_}
        if not np.isfinite(self.cutoff_):
            del out["cutoff"]
        if self.n_whitened_ < 0:
            del out["n_whitened"]
        if self.params.expansion == "quadratic":
            out.update(pre_mean=self.pre_mean_, pre_scale=self.pre_scale_)
        return {prefix + k: np.array(v) for k, v in out.items()}

    @classmethod
    def from_arrays(cls, params: SFAParams, arrays: Mapping[str, Any], prefix: str = "", *,
                    n_features_in: int | None = None) -> SFA:
        """A fitted SFA from :meth:`to_arrays`' output (keys led by ``prefix``), checked:
        every key present and known, shapes consistent with ``params`` (and with
        ``n_features_in``, the input width, when given), finite, ``scale`` and ``pre_scale``
        > 0. Raises ``ValueError`` naming the key."""
        quad = params.expansion == "quadratic"
        a = PartArrays("SFA", arrays, prefix, ("mean", "scale", "W", "slowness",
                                               *(("pre_mean", "pre_scale") if quad else ())),
                       optional=("cutoff", "n_whitened"))
        sfa, n = cls(params), int(params.n_components)
        if quad:
            sfa.pre_mean_ = a.get("pre_mean", (n_features_in,))
            d_in = sfa.pre_mean_.shape[0]
            sfa.pre_scale_ = a.get("pre_scale", (d_in,))
            if not (sfa.pre_scale_ > 0).all():
                raise ValueError(f"{prefix}pre_scale must be > 0 everywhere")
            d = d_in + d_in * (d_in + 1) // 2
        else:
            d = d_in = a.get("mean", (n_features_in,)).shape[0]
        sfa.mean_, sfa.scale_ = a.get("mean", (d,)), a.get("scale", (d,))
        if not (sfa.scale_ > 1e-12 * (1.0 + np.abs(sfa.mean_))).all():
            raise ValueError(f"{prefix}scale must be > 0 everywhere (above 1e-12 of the "
                             "feature's mean, as fit leaves it)")
        sfa.W_, sfa.slowness_ = a.get("W", (d, n)), a.get("slowness", (n,))
        sfa.cutoff_ = float(a.get("cutoff", ())) if a.has("cutoff") else float("nan")
        if a.has("cutoff") and not 0.0 < sfa.cutoff_ < 1.0:
            raise ValueError(f"{prefix}cutoff={sfa.cutoff_:g} must lie in (0, 1)")
        sfa.n_whitened_ = int(a.get("n_whitened", (), "int")) if a.has("n_whitened") else -1
        if a.has("n_whitened") and not n <= sfa.n_whitened_ <= d:
            raise ValueError(f"{prefix}n_whitened={sfa.n_whitened_} must lie in [{n}, {d}]")
        sfa.n_features_in_, sfa.n_expanded_ = d_in, d
        return sfa

    def _check_fitted(self) -> None:
        if not hasattr(self, "W_"):
            raise NotFittedError("SFA is not fitted yet; call fit(X) first")

    def __repr__(self) -> str:
        p = self.params
        return f"SFA(n_components={p.n_components}, cutoff={p.cutoff!r}, expansion={p.expansion!r})"
