"""RC-SFA-ICA: place cells that learn themselves from distance sensors (SMC09, ICANN09).

Three layers (SMC09 Fig. 1), only the upper two learn, one after the other:

    x(t+1)   = tanh((1-a) x(t) + a (W_in u(t) + W_res x(t)))     reservoir   (eq. 1)
    y_sfa(t) = W_sfaᵀ z([u(t); x(t+1)])                          linear SFA  (eq. 6-7)
    y_ica(t) = W_ica (y_sfa(t) - μ)                               FastICA     (eq. 8-10)

(``z`` is the z-scoring learned on the training data.) The estimator follows scikit-learn:
``__init__`` only stores parameters, :meth:`RCSFAICA.fit` learns, fitted attributes end in
``_``, :meth:`RCSFAICA.transform` runs a whole recording offline from ``x(0) = 0``. For the
closed loop, :meth:`RCSFAICA.step` takes one sensor vector per control tick and returns the
place-cell activities; after :meth:`RCSFAICA.reset_state`, stepping through ``U`` reproduces
``transform(U)`` to float rounding.

Output scale: ICA outputs are **unit variance on the training data** (``output_std_`` = 1), so
units are comparable with each other and ICANN09's "responds ≥ 4.5" reads as 4.5 training
standard deviations. ``output_peak_`` (each unit's 99.9th percentile on the training data) lets
a state layer normalise activities to roughly [.., 1].

Fitting runs on both cores: the reservoir is harvested chunk by chunk while a second thread
adds each finished chunk to the SFA moments (:class:`~hippo.perception.sfa.SFAMoments`), so SFA
costs little more than the harvest; :func:`fit_leak_sweep` harvests many leak configurations
as one batch and fits them on parallel threads.

Optional input down-sampling (``downsample > 1``, ICANN09: 50) uses a causal anti-aliasing
FIR (:mod:`hippo.perception.resample`); the reservoir then ticks once per ``downsample`` inputs
and outputs are held in between.
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import asdict, dataclass, fields, replace
from itertools import pairwise
from pathlib import Path
from typing import Any

import numpy as np

from hippo._checks import check_finite
from hippo._threads import n_workers, parallel_map, single_threaded_blas
from hippo.io import CorruptFileError, load_npz, save_npz
from hippo.perception.ica import FastICA, ICAParams
from hippo.perception.resample import Decimator, hold
from hippo.perception.reservoir import Reservoir, ReservoirParams, expand_leak
from hippo.perception.reservoir import _num_threads as _torch_threads
from hippo.perception.sfa import SFA, SFAMoments, SFAParams, chunk_bounds

FORMAT = "hippo.perception.RCSFAICA/1"
#: reservoir ticks per chunk when the harvest and the SFA moments run side by side
_HARVEST_CHUNK = 2048
#: a fit holds the reservoir states up to this size, and streams them beyond (``fit(stream=)``)
_HOLD_BYTES = 256 * 2**20
#: leak configurations harvested together by ``fit_leak_sweep``
_SWEEP_BATCH = 16


@dataclass(frozen=True)
class RCSFAICAParams:
    """All hyper-parameters of the three layers; defaults are SMC09's (:meth:`RCSFAICA.smc09`)."""

    # input
    n_inputs: int = 8
    downsample: int = 1
    # reservoir (SMC09 eq. 1)
    use_reservoir: bool = True
    n_reservoir: int = 600
    leak: float | tuple[float, ...] = (0.05, 0.15)
    spectral_radius: float = 0.99
    input_weight: float = 2.0
    input_prob: float = 0.075
    # SFA (eq. 2-7)
    n_sfa: int = 4
    sfa_cutoff: float | str = 1e-8
    sfa_expansion: str = "linear"
    # ICA (eq. 8-10)
    n_ica: int = 4
    ica_algorithm: str = "symmetric"
    ica_restarts: int = 10
    ica_score: str = "kurtosis"
    ica_max_iter: int = 1000
    ica_tol: float = 1e-6
    # training
    washout: int = 0
    seed: int = 0
    dtype: str = "float32"
    device: str = "cpu"

    def __post_init__(self) -> None:
        if isinstance(self.leak, list):
            object.__setattr__(self, "leak", tuple(self.leak))
        if int(self.n_inputs) < 1:
            raise ValueError(f"n_inputs must be >= 1, got {self.n_inputs}")
        if int(self.downsample) < 1:
            raise ValueError(f"downsample must be >= 1, got {self.downsample}")
        if int(self.washout) < 0:
            raise ValueError(f"washout must be >= 0, got {self.washout}")
        if int(self.n_ica) > int(self.n_sfa):
            raise ValueError(f"n_ica={self.n_ica} exceeds n_sfa={self.n_sfa}")
        # delegate the remaining checks to the layers' own parameter classes
        self.reservoir_params()
        self.sfa_params()
        self.ica_params()

    def reservoir_params(self) -> ReservoirParams:
        return ReservoirParams(n_inputs=self.n_inputs, n_neurons=self.n_reservoir,
                               spectral_radius=self.spectral_radius, leak=self.leak,
                               input_weight=self.input_weight, input_prob=self.input_prob,
                               seed=self.seed)

    def sfa_params(self) -> SFAParams:
        return SFAParams(n_components=self.n_sfa, cutoff=self.sfa_cutoff,
                         expansion=self.sfa_expansion)

    def ica_params(self) -> ICAParams:
        return ICAParams(n_components=self.n_ica, algorithm=self.ica_algorithm,
                         max_iter=self.ica_max_iter, tol=self.ica_tol,
                         n_restarts=self.ica_restarts, score=self.ica_score, seed=self.seed)


#: SMC09 (e-puck, 8 IR sensors, two rooms): 600 neurons, leaks 0.05/0.15, ρ 0.99, W_in ±2 p 0.075
SMC09 = RCSFAICAParams()
#: ICANN09 (17 distance sensors, maze E1): 400 neurons, leak 0.6, ρ 0.9, W_in ±0.2 p 0.15,
#: 70 SFA / 70 ICA units, input down-sampled by 50
ICANN09 = RCSFAICAParams(n_inputs=17, downsample=50, n_reservoir=400, leak=0.6,
                         spectral_radius=0.9, input_weight=0.2, input_prob=0.15,
                         n_sfa=70, n_ica=70)


class RCSFAICA:
    """Reservoir → linear SFA → FastICA place cells (SMC09 Fig. 1; ICANN09 Fig. 1).

    ``RCSFAICA(params, **overrides)`` stores ``params`` (a :class:`RCSFAICAParams`, default
    SMC09) with ``overrides`` applied. Use :meth:`smc09` / :meth:`icann09` for the papers'
    settings.

    Fitted attributes: ``reservoir_`` (:class:`Reservoir` or None), ``sfa_`` (:class:`SFA`),
    ``ica_`` (:class:`FastICA`), ``n_features_in_``, ``output_std_``, ``output_peak_``,
    ``sfa_slowness_`` (Δ of each SFA unit).

    Example (closed loop)::

        pc = RCSFAICA.smc09(seed=1).fit(recording.sensors)    # (T, 8) exploration run
        pc.reset_state()
        for obs in world:                                     # one control tick each
            activity = pc.step(obs.ir)                        # (n_ica,), unit-variance units
    """

    def __init__(self, params: RCSFAICAParams | None = None, **overrides: Any) -> None:
        self.params = replace(params or RCSFAICAParams(), **overrides)

    @classmethod
    def smc09(cls, **overrides: Any) -> RCSFAICA:
        """SMC09 settings (two rooms, e-puck IR): see :data:`SMC09`."""
        return cls(SMC09, **overrides)

    @classmethod
    def icann09(cls, **overrides: Any) -> RCSFAICA:
        """ICANN09 settings (maze E1, 17 sensors): see :data:`ICANN09`."""
        return cls(ICANN09, **overrides)

    def get_params(self) -> dict[str, Any]:
        return asdict(self.params)

    # ------------------------------------------------------------------ input handling
    def _check_U(self, U: Any) -> np.ndarray:
        U = np.asarray(U)
        n = self.params.n_inputs
        if U.ndim != 2 or U.shape[1] != n:
            raise ValueError(f"sensor sequence U must have shape (T, {n}), got {U.shape}")
        if not np.issubdtype(U.dtype, np.number) or np.issubdtype(U.dtype, np.complexfloating):
            raise ValueError(f"sensor sequence U must be real numbers, got dtype {U.dtype}")
        return check_finite("sensor sequence U", U)

    def features(self, U: np.ndarray, *, downsampled: bool = False) -> np.ndarray:
        """SFA input ``[u(t); x(t+1)]`` for a recording ``U`` (at the down-sampled rate),
        from ``x(0) = 0``. Set ``downsampled=True`` if ``U`` is already down-sampled."""
        U = self._check_U(U)
        Ud = U if downsampled else self._decimator().offline(U)
        if self.reservoir_ is None:
            return Ud
        X = self.reservoir_.run(Ud)
        return np.concatenate([Ud.astype(X.dtype), X], axis=1)

    def _decimator(self) -> Decimator:
        return Decimator(int(self.params.downsample))

    def _build_reservoir(self) -> Reservoir | None:
        p = self.params
        if not p.use_reservoir:
            return None
        return Reservoir(p.reservoir_params(), dtype=p.dtype, device=p.device)

    # ------------------------------------------------------------------ learning
    def fit(self, U: np.ndarray, *, stream: bool | None = None) -> RCSFAICA:
        """Learn SFA then ICA on a recording ``U`` (T, n_inputs) of sensor values.

        ``stream``: never hold the whole reservoir state sequence (T, n_inputs + N). The
        harvest is summarised chunk by chunk into the SFA moments, keeping only each chunk's
        starting state; after SFA is solved the reservoir runs once more from those states and
        each chunk is projected at once onto the ``n_sfa`` slow features, which are all ICA
        sees. Peak memory is then flat in T (the cost: the reservoir runs twice). Same numbers
        as the held fit to float rounding. Default (None): stream when the states would take
        more than 256 MB. Applies to the linear SFA of a reservoir (the other forms hold
        their features).
        """
        U = self._check_U(U)
        p = self.params
        need = (p.washout + 3) * p.downsample
        if U.shape[0] < need:
            raise ValueError(f"U has {U.shape[0]} ticks; at least {need} are needed "
                             f"(washout {p.washout}, downsample {p.downsample})")
        self.reservoir_ = self._build_reservoir()
        self.n_features_in_ = p.n_inputs
        Ud = self._decimator().offline(U)
        if self.reservoir_ is None or p.sfa_expansion != "linear":
            return self._fit_features(self.features(Ud, downsampled=True))
        d = p.n_inputs + self.reservoir_.n_neurons
        if stream is None:
            stream = Ud.shape[0] * d * self.reservoir_.np_dtype().itemsize > _HOLD_BYTES
        if stream:
            return self._fit_streamed(Ud)
        X, parts, _ = self._harvest_summarised(Ud)
        return self._fit_features(X, parts)

    def _harvest_summarised(self, Ud: np.ndarray, *, hold: bool = True
                            ) -> tuple[np.ndarray | None, list[SFAMoments], list[tuple]]:
        """Features ``[u; x]`` of ``Ud`` and their SFA moments (after the washout), computed side
        by side: the reservoir runs chunk by chunk on this thread while a second thread adds each
        finished chunk to the moments (both with single-threaded BLAS). Same numbers as
        ``features`` then ``SFA.accumulate``, in about the time of the harvest alone.

        Also returns the chunks ``(t0, t1, x0)`` with the reservoir state each starts from.
        With ``hold=False`` the features are not kept (None is returned for them): each chunk
        lives until its moments are added, at most two chunks at a time."""
        p = self.params
        res = self.reservoir_
        n_u = p.n_inputs
        T = Ud.shape[0]
        d = n_u + res.n_neurons
        if hold:
            X = np.empty((T, d), dtype=res.np_dtype)
            X[:, :n_u] = Ud
        w = int(p.washout)
        split = SFA(p.sfa_params()).auto_split(T - w)
        parts = [SFAMoments(d) for _ in range(1 if split is None else 2)]
        bounds = sorted({0, *(w + b for b in chunk_bounds(T - w, d, split=split,
                                                           rows=_HARVEST_CHUNK))})
        x = None
        chunks = []
        with single_threaded_blas(), ThreadPoolExecutor(1) as pool:
            pending = []
            for t0, t1 in pairwise(bounds):
                chunks.append((t0, t1, x))
                S = res.run(Ud[t0:t1], x0=x)
                if hold:
                    F = X[t0:t1]
                    F[:, n_u:] = S
                else:
                    F = np.empty((t1 - t0, d), dtype=res.np_dtype)
                    F[:, :n_u] = Ud[t0:t1]
                    F[:, n_u:] = S
                x = S[-1].copy()
                if t0 >= w:
                    part = parts[0 if split is None or t1 - w <= split else 1]
                    if not hold and len(pending) >= 1:  # bound the chunks alive to two
                        pending.pop(0).result()
                    pending.append(pool.submit(part.update, F))
                del S, F
            for job in pending:
                job.result()
        return (X if hold else None), parts, chunks

    def _fit_streamed(self, Ud: np.ndarray) -> RCSFAICA:
        """Fit without holding the state sequence (see ``fit(stream=True)``)."""
        p = self.params
        res = self.reservoir_
        n_u, w = p.n_inputs, int(p.washout)
        _, parts, chunks = self._harvest_summarised(Ud, hold=False)
        self.sfa_ = SFA(p.sfa_params())
        self.sfa_._prepare_shape(Ud.shape[0] - w, n_u + res.n_neurons)
        self.sfa_._solve(parts, Ud.shape[0] - w)
        Y = np.empty((Ud.shape[0] - w, int(p.n_sfa)))
        with single_threaded_blas():  # the same chunks from the same states: the same states
            for t0, t1, x0 in chunks:
                if t0 < w:
                    continue
                F = np.concatenate([Ud[t0:t1].astype(res.np_dtype),
                                    res.run(Ud[t0:t1], x0=x0)], axis=1)
                Y[t0 - w:t1 - w] = self.sfa_._project(F)
        return self._fit_slow(self.sfa_._sign(Y))

    def _fit_features(self, X: np.ndarray, moments: list[SFAMoments] | None = None) -> RCSFAICA:
        """Fit SFA and ICA on the features ``X`` (washout included); ``moments``, when given,
        are the SFA moments of ``X`` after the washout."""
        p = self.params
        X = X[p.washout:]
        self.sfa_ = SFA(p.sfa_params())
        if moments is None:
            Y = self.sfa_.fit_transform(X)
        else:
            self.sfa_._prepare(X)
            Y = self.sfa_._fit_moments(moments, X)
        return self._fit_slow(Y)

    def _fit_slow(self, Y: np.ndarray) -> RCSFAICA:
        """With SFA fitted: ICA on its training outputs ``Y`` (T, n_sfa), then the readout."""
        p = self.params
        self.sfa_slowness_ = self.sfa_.slowness_.copy()
        self.ica_ = FastICA(p.ica_params())
        S = self.ica_.fit_transform(Y)
        self.output_std_ = S.std(axis=0)
        self.output_peak_ = np.percentile(S, 99.9, axis=0)
        self._compile()
        self.reset_state()
        return self

    def _compile(self) -> None:
        """Fold SFA and ICA into one affine readout of the feature vector (linear case)."""
        d = self.sfa_.n_features_in_
        if self.params.sfa_expansion == "linear":
            M, b = self.sfa_.affine()
            C = self.ica_.components_.T
            self._R = np.ascontiguousarray(M @ C)
            self._r0 = (b - self.ica_.mean_) @ C
            self._y_init = self._r0.copy()
        else:
            self._R = None
            self._r0 = None
            self._y_init = self._readout(np.zeros((1, d)))[0]

    def _readout(self, X: np.ndarray, return_sfa: bool = False):
        Y = self.sfa_.transform(X)
        S = self.ica_.transform(Y)
        return (S, Y) if return_sfa else S

    # ------------------------------------------------------------------ offline
    def transform(self, U: np.ndarray, *, return_sfa: bool = False, upsample: bool = True):
        """Place-cell activities ``(T, n_ica)`` for a recording ``U`` (T, n_inputs), run from a
        zero reservoir state (the online state is untouched). With ``return_sfa`` also the SFA
        outputs ``(T, n_sfa)``. With down-sampling, outputs are held between updates, as
        :meth:`step` gives them; ``upsample=False`` returns one row per reservoir update instead
        (taken at the ticks :meth:`sample_ticks` names)."""
        self._check_fitted()
        U = self._check_U(U)
        X = self.features(U)
        S, Y = self._readout(X, return_sfa=True)
        f = int(self.params.downsample)
        if f > 1 and upsample:
            T = U.shape[0]
            S = hold(S, T, f, self._y_init)
            y0 = self.sfa_.transform(np.zeros((1, X.shape[1])))[0]
            Y = hold(Y, T, f, y0)
        return (S, Y) if return_sfa else S

    def sample_ticks(self, T: int) -> tuple[np.ndarray, float]:
        """Ticks of the reservoir updates for a recording of ``T`` ticks, and the delay (in
        ticks) of the anti-aliasing filter: update ``k`` reflects the input around tick
        ``ticks[k] - delay``. Without down-sampling: ``(arange(T), 0)``."""
        dec = self._decimator()
        return dec.sample_ticks(T), float(dec.delay) if dec.factor > 1 else 0.0

    def fit_transform(self, U: np.ndarray, **kw: Any):
        return self.fit(U).transform(U, **kw)

    # ------------------------------------------------------------------ online
    def reset_state(self) -> None:
        """Start the online loop afresh: reservoir state 0, empty down-sampling history."""
        self._check_fitted()
        if self.reservoir_ is not None:
            self.reservoir_.reset()
        self._dec = self._decimator()
        self._last = self._y_init.copy()

    def step(self, u: np.ndarray) -> np.ndarray:
        """One control tick: feed the sensor vector ``u`` (n_inputs,), return the place-cell
        activities (n_ica,) (a new array)."""
        self._check_fitted()
        n = self.params.n_inputs
        u = np.asarray(u, dtype=float)
        if u.shape != (n,):
            raise ValueError(f"sensor vector u must have shape ({n},), got {u.shape}")
        if not np.isfinite(u).all():
            raise ValueError("sensor vector u contains NaN or inf")
        if self.params.downsample > 1:
            ud = self._dec.push(u)
            if ud is None:
                return self._last.copy()
            u = ud
        res = self.reservoir_
        if res is not None and self._R is not None:
            z = res._mirror.z
            z[: res.n_inputs] = u
            res._advance()
            out = z @ self._R + self._r0
        else:
            z = u if res is None else np.concatenate([u, res.step(u)])
            out = self._readout(z[None, :])[0]
        self._last = out
        return out.copy()

    # ------------------------------------------------------------------ persistence
    def save(self, path: str | os.PathLike) -> Path:
        """Write the fitted model to ``path`` (.npz, atomic, no pickle)."""
        self._check_fitted()
        arrays: dict[str, Any] = {
            "format": np.array(FORMAT),
            "params": np.array(json.dumps(asdict(self.params))),
            "sfa_mean": self.sfa_.mean_, "sfa_scale": self.sfa_.scale_, "sfa_W": self.sfa_.W_,
            "sfa_slowness": self.sfa_.slowness_, "sfa_cutoff": np.array(self.sfa_.cutoff_),
            "sfa_n_whitened": np.array(self.sfa_.n_whitened_),
            "ica_mean": self.ica_.mean_, "ica_whitening": self.ica_.whitening_,
            "ica_rotation": self.ica_.rotation_,
            "output_std": self.output_std_, "output_peak": self.output_peak_,
        }
        if self.params.sfa_expansion == "quadratic":
            arrays["sfa_pre_mean"] = self.sfa_.pre_mean_
            arrays["sfa_pre_scale"] = self.sfa_.pre_scale_
        if self.reservoir_ is not None:
            arrays.update(W_in=self.reservoir_.W_in, W_res=self.reservoir_.W_res,
                          leak=self.reservoir_.leak)
        return save_npz(path, arrays)

    @classmethod
    def load(cls, path: str | os.PathLike) -> RCSFAICA:
        """Read a model written by :meth:`save`; a damaged file raises ``CorruptFileError``
        (a ``ValueError``) naming the problem."""
        req = ("format", "params", "sfa_mean", "sfa_scale", "sfa_W", "sfa_slowness",
               "ica_mean", "ica_whitening", "ica_rotation", "output_std", "output_peak")
        a = load_npz(path, required=req)
        if str(a["format"]) != FORMAT:
            raise CorruptFileError(f"{path} is not an RCSFAICA model (format {a['format']!s})")
        try:
            raw = json.loads(str(a["params"]))
            known = {f.name for f in fields(RCSFAICAParams)}
            if isinstance(raw.get("leak"), list):
                raw["leak"] = tuple(raw["leak"])
            params = RCSFAICAParams(**{k: v for k, v in raw.items() if k in known})
        except (json.JSONDecodeError, TypeError, ValueError) as exc:
            raise CorruptFileError(f"{path} has unreadable parameters ({exc})") from exc
        self = cls(params)
        try:
            if params.use_reservoir:
                for k in ("W_in", "W_res", "leak"):
                    if k not in a:
                        raise CorruptFileError(f"{path} lacks required array(s): {k}")
                self.reservoir_ = Reservoir.from_weights(
                    a["W_in"], a["W_res"], a["leak"], spectral_radius=params.spectral_radius,
                    dtype=params.dtype, device=params.device)
            else:
                self.reservoir_ = None
            sfa = SFA(params.sfa_params())
            sfa.mean_, sfa.scale_, sfa.W_ = a["sfa_mean"], a["sfa_scale"], a["sfa_W"]
            sfa.slowness_ = a["sfa_slowness"]
            sfa.cutoff_ = float(a.get("sfa_cutoff", np.nan))
            sfa.n_whitened_ = int(a.get("sfa_n_whitened", -1))
            if params.sfa_expansion == "quadratic":
                sfa.pre_mean_, sfa.pre_scale_ = a["sfa_pre_mean"], a["sfa_pre_scale"]
                sfa.n_features_in_ = sfa.pre_mean_.shape[0]
            else:
                sfa.n_features_in_ = sfa.mean_.shape[0]
            ica = FastICA(params.ica_params())
            ica.mean_, ica.whitening_, ica.rotation_ = (a["ica_mean"], a["ica_whitening"],
                                                        a["ica_rotation"])
            ica.components_ = ica.rotation_ @ ica.whitening_.T
            ica.n_features_in_ = ica.mean_.shape[0]
            ica.output_std_ = a["output_std"]
            n_feat = params.n_inputs + (params.n_reservoir if params.use_reservoir else 0)
            if (sfa.n_features_in_ != n_feat or sfa.W_.shape[1] != params.n_sfa
                    or ica.components_.shape != (params.n_ica, params.n_sfa)):
                raise CorruptFileError(f"{path}: array shapes do not match its parameters")
        except KeyError as exc:
            raise CorruptFileError(f"{path} lacks required array {exc}") from exc
        except ValueError as exc:
            if isinstance(exc, CorruptFileError):
                raise
            raise CorruptFileError(f"{path} holds inconsistent arrays ({exc})") from exc
        self.sfa_, self.ica_ = sfa, ica
        self.sfa_slowness_ = sfa.slowness_.copy()
        self.n_features_in_ = params.n_inputs
        self.output_std_, self.output_peak_ = a["output_std"], a["output_peak"]
        self._compile()
        self.reset_state()
        return self

    # ------------------------------------------------------------------ misc
    def _check_fitted(self) -> None:
        if not hasattr(self, "ica_"):
            raise RuntimeError("RCSFAICA is not fitted yet; call fit(U) first")

    def __repr__(self) -> str:
        p = self.params
        res = (f"reservoir={p.n_reservoir}, leak={p.leak}, rho={p.spectral_radius}"
               if p.use_reservoir else "no reservoir")
        return (f"RCSFAICA(n_inputs={p.n_inputs}, {res}, n_sfa={p.n_sfa}, n_ica={p.n_ica}, "
                f"downsample={p.downsample}, seed={p.seed})")


def fit_leak_sweep(U: np.ndarray, leaks: Sequence[Any], params: RCSFAICAParams | None = None,
                   *, workers: int | None = None, **overrides: Any) -> list[RCSFAICA]:
    """Fit one :class:`RCSFAICA` per leak configuration over **one** reservoir (same weights).

    The configurations are harvested together, up to 16 at a time (one matrix-matrix product
    per tick for the batch, BLAS on ``workers`` threads); then ``workers`` threads (default: the
    usable cores), each with single-threaded BLAS, fit SFA and ICA for one configuration after
    another. ``leaks`` is a sequence of leak specs (each a float, k floats, or N floats). Returns
    the fitted models, in the order of ``leaks``, whose ``params.leak`` is the configuration
    (as given).
    """
    base = replace(params or RCSFAICAParams(), **overrides)
    if not base.use_reservoir:
        raise ValueError("a leak sweep needs use_reservoir=True")
    if len(leaks) == 0:
        raise ValueError("leaks is empty")
    template = RCSFAICA(base)
    U = template._check_U(U)
    res = template._build_reservoir()
    N = base.n_reservoir
    A = np.stack([expand_leak(lk, N) for lk in leaks])
    Ud = template._decimator().offline(U)
    k = min(n_workers(workers), len(leaks))
    states: list[np.ndarray] = []
    for g in range(0, len(leaks), _SWEEP_BATCH):
        S = res.run(Ud, leak=A[g:g + _SWEEP_BATCH], threads=k)  # (b, T, N)
        states.extend(S)

    def fit_one(b: int) -> RCSFAICA:
        lk = leaks[b]
        lk_param = float(lk) if np.ndim(lk) == 0 else tuple(float(v) for v in np.ravel(lk))
        m = RCSFAICA(base, leak=lk_param)
        m.reservoir_ = Reservoir.from_weights(res.W_in, res.W_res, A[b],
                                              spectral_radius=base.spectral_radius,
                                              dtype=base.dtype, device=base.device)
        m.n_features_in_ = base.n_inputs
        Xb = states[b]
        return m._fit_features(np.concatenate([Ud.astype(Xb.dtype), Xb], axis=1))

    with _torch_threads(1):
        return parallel_map(fit_one, range(len(leaks)), k)
