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

Input policy: sensor readings are expected in ``input_range`` (default ``(0, 1)``, the scale of
:class:`~hippo.sim.World`'s IR readings; ``None`` accepts any finite value). :meth:`RCSFAICA.fit`
refuses a recording with readings outside it, with fewer than ``min_fit_ticks`` reservoir updates
after the washout (default 100, 20 s at 0.2 s), or whose every sensor is constant (stuck): none
can yield place cells. A fitted model meeting readings outside the range in :meth:`step` or
:meth:`transform` follows ``out_of_range``: ``"error"`` (default) raises ``ValueError``,
``"warn"`` clips them to the range and emits :class:`InputRangeWarning`, ``"clip"`` clips them
silently. A reading is never extrapolated (a linear readout of readings ×1e6 would give
activities of ±1e4). NaN and inf are always refused.

Optional input down-sampling (``downsample > 1``, ICANN09: 50) uses a causal anti-aliasing
FIR (:mod:`hippo.perception.resample`); the reservoir then ticks once per ``downsample`` inputs
and outputs are held in between.
"""

from __future__ import annotations

import json
import os
import re
import warnings
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import asdict, dataclass, fields, replace
from itertools import pairwise
from pathlib import Path
from typing import Any

import numpy as np

from hippo._checks import check_array, check_choice, check_fields, check_finite, check_int
from hippo._estimator import NotFittedError, ParamsEstimator
from hippo._threads import n_workers, parallel_map, single_threaded_blas
from hippo.io import CorruptFileError, load_npz, save_npz
from hippo.perception.ica import FastICA, ICAParams
from hippo.perception.resample import Decimator, hold
from hippo.perception.reservoir import (
    Reservoir,
    ReservoirParams,
    _check_device,
    _leak_param,
    _np_dtype,
    expand_leak,
)
from hippo.perception.reservoir import _num_threads as _torch_threads
from hippo.perception.sfa import SFA, SFAMoments, SFAParams, chunk_bounds

FORMAT = "hippo.perception.RCSFAICA/1"


_RESERVOIR_NAMES = {"n_inputs": "n_inputs", "n_neurons": "n_reservoir", "leak": "leak",
                    "spectral_radius": "spectral_radius", "input_weight": "input_weight",
                    "input_prob": "input_prob", "seed": "seed"}
_SFA_NAMES = {"n_components": "n_sfa", "cutoff": "sfa_cutoff", "expansion": "sfa_expansion"}
_ICA_NAMES = {"n_components": "n_ica", "algorithm": "ica_algorithm", "max_iter": "ica_max_iter",
              "tol": "ica_tol", "n_restarts": "ica_restarts", "score": "ica_score"}
#: no fitted array holds a larger magnitude; a loaded one that does is damaged
_MAX_ABS = 1e12
_REQUIRED = ("format", "params", "sfa_mean", "sfa_scale", "sfa_W", "sfa_slowness", "ica_mean",
             "ica_whitening", "ica_rotation", "output_std", "output_peak")


class InputRangeWarning(RuntimeWarning):
    """Readings outside the model's ``input_range`` were clipped (``out_of_range='warn'``)."""

#: reservoir ticks per chunk when the harvest and the SFA moments run side by side
_HARVEST_CHUNK = 2048
#: a fit holds the reservoir states up to this size, and streams them beyond (``fit(stream=)``)
_HOLD_BYTES = 256 * 2**20
#: rows per chunk when the ICA outputs' statistics are taken
_OUT_CHUNK = 65536
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
    # input checks (see "Input policy" in the module docstring)
    input_range: tuple[float, float] | None = (0.0, 1.0)
    out_of_range: str = "error"
    min_fit_ticks: int = 100

    def __post_init__(self) -> None:
        object.__setattr__(self, "leak", _leak_param(self.leak))
        if isinstance(self.input_range, list):
            object.__setattr__(self, "input_range", tuple(self.input_range))
        check_fields(self)
        check_int("n_inputs", self.n_inputs, lo=1)
        check_int("downsample", self.downsample, lo=1)
        check_int("washout", self.washout, lo=0)
        check_int("n_reservoir", self.n_reservoir, lo=1)
        check_int("n_sfa", self.n_sfa, lo=1)
        check_int("n_ica", self.n_ica, lo=1)
        if self.n_ica > self.n_sfa:
            raise ValueError(f"n_ica={self.n_ica} exceeds n_sfa={self.n_sfa}")
        check_int("min_fit_ticks", self.min_fit_ticks, lo=3)
        if self.input_range is not None:
            lo, hi = self.input_range
            if not lo < hi:
                raise ValueError(f"input_range must be (low, high) with low < high, got "
                                 f"{self.input_range!r}")
        check_choice("out_of_range", self.out_of_range, ("error", "warn", "clip"))
        _np_dtype(self.dtype)
        _check_device(self.device)
        # delegate the remaining checks to the layers' own parameter classes, naming the
        # RCSFAICA field in the message
        for build, names in ((self.reservoir_params, _RESERVOIR_NAMES),
                             (self.sfa_params, _SFA_NAMES), (self.ica_params, _ICA_NAMES)):
            try:
                build()
            except ValueError as exc:
                msg = str(exc)
                ours = [o for theirs, o in names.items() if re.search(rf"\b{theirs}\b", msg)]
                raise ValueError(f"{' / '.join(ours) or 'RCSFAICAParams'}: {msg}") from None

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


class RCSFAICA(ParamsEstimator):
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

    # ------------------------------------------------------------------ input handling
    def _check_U(self, U: Any, *, fitting: bool = False) -> np.ndarray:
        U = np.asarray(U)
        n = self.params.n_inputs
        if U.ndim != 2 or U.shape[1] != n:
            raise ValueError(f"sensor sequence U must have shape (T, {n}), got {U.shape}")
        if (not np.issubdtype(U.dtype, np.number) or np.issubdtype(U.dtype, np.complexfloating)
                or U.dtype.kind == "b"):
            raise ValueError(f"sensor sequence U must be real numbers, got dtype {U.dtype}")
        U = check_finite("sensor sequence U", U, keep_float32=True)
        rng = self.params.input_range
        if rng is not None and U.size and (U.min() < rng[0] or U.max() > rng[1]):
            msg = (f"sensor sequence U holds readings outside input_range [{rng[0]:g}, "
                   f"{rng[1]:g}] (min {U.min():g}, max {U.max():g})")
            if fitting:
                raise ValueError(msg + "; place cells are learned from sensor readings scaled to "
                                 "input_range: rescale U, or set input_range to its true range")
            U = self._out_of_range(U, msg)
        return U

    def _out_of_range(self, u: np.ndarray, msg: str) -> np.ndarray:
        """Apply the ``out_of_range`` policy to inputs outside ``input_range``."""
        policy = self.params.out_of_range
        if policy == "error":
            raise ValueError(msg + "; the model was fitted on readings in that range and would "
                             "extrapolate (set out_of_range='clip' or 'warn' to clip instead)")
        if policy == "warn":
            warnings.warn(msg + "; clipped to the range", InputRangeWarning, stacklevel=3)
        lo, hi = self.params.input_range  # type: ignore[misc]
        return np.clip(u, lo, hi)

    def _check_trainable(self, U: np.ndarray) -> None:
        """Refuse recordings that cannot yield place cells: too short, or no sensor varies."""
        p = self.params
        n_updates = -(-U.shape[0] // p.downsample) - p.washout
        if n_updates < p.min_fit_ticks:
            raise ValueError(
                f"U has {U.shape[0]} ticks ({n_updates} reservoir updates after a washout of "
                f"{p.washout} and down-sampling by {p.downsample}); fitting needs at least "
                f"min_fit_ticks={p.min_fit_ticks} updates of exploration")
        spread = U.max(axis=0) - U.min(axis=0)
        if not (spread > 1e-9).any():
            raise ValueError(
                f"every sensor in U is constant (values {np.unique(U[0]).tolist()[:4]}): stuck "
                "or disconnected sensors carry no information about place")

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
    def fit(self, U: np.ndarray, y: None = None, *, stream: bool | None = None) -> RCSFAICA:
        """Learn SFA then ICA on a recording ``U`` (T, n_inputs) of sensor values.

        ``stream``: never hold the whole reservoir state sequence (T, n_inputs + N). The
        harvest is summarised chunk by chunk into the SFA moments, keeping only each chunk's
        starting state; after SFA is solved the reservoir runs once more from those states and
        each chunk is projected at once onto the ``n_sfa`` slow features, which are all ICA
        sees (kept as float32, 16 bytes a tick at n_sfa = 4; ICA reads them chunk by chunk).
        Peak memory is then flat in T but for that (the cost: the reservoir runs twice). Same
        numbers as the held fit to float rounding (ICA: within its ``tol``). Default (None):
        stream when the states would take more than 256 MB. Applies to the linear SFA of a
        reservoir (the other forms hold their features).
        """
        U = self._check_U(U, fitting=True)
        self._check_trainable(U)
        p = self.params
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
        # the ICA input, the only array of length T: n_sfa float32 columns (16 bytes a tick)
        Y = np.empty((Ud.shape[0] - w, int(p.n_sfa)), dtype=np.float32)
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
        self.ica_ = FastICA(p.ica_params()).fit(Y)
        self.output_std_, self.output_peak_ = _output_stats(self.ica_, Y)
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

    def fit_transform(self, U: np.ndarray, y: None = None, **kw: Any):
        """``fit(U)``, then ``transform(U, **kw)`` (``y`` is ignored, as in scikit-learn)."""
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
        try:
            u = np.asarray(u, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"sensor vector u must be {n} real numbers, got {u!r}") from None
        if u.shape != (n,):
            raise ValueError(f"sensor vector u must have shape ({n},), got {u.shape}")
        # one cheap check per tick: NaN fails both comparisons
        rng = self.params.input_range
        lo, hi = (-np.inf, np.inf) if rng is None else rng
        if not (u.min() >= lo and u.max() <= hi):
            if not np.isfinite(u).all():
                raise ValueError(f"sensor vector u contains NaN or inf: {u}")
            u = self._out_of_range(u, f"sensor vector u = {u} lies outside input_range "
                                      f"[{lo:g}, {hi:g}]")
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
        """Read a model written by :meth:`save`.

        Nothing in the file is trusted: the format tag, the parameters (type- and range-checked
        like the constructor's), and every array's dtype, shape (consistent with the
        parameters and with each other) and finiteness, the reservoir's leak and spectral radius
        against its parameters, scales and standard deviations > 0. A damaged file raises
        :class:`~hippo.io.CorruptFileError` (a ``ValueError``) naming the problem; nothing is
        half-loaded (the model is built only once every check passed).
        """
        a = load_npz(path, required=_REQUIRED)
        try:
            return cls._from_arrays(a)
        except CorruptFileError as exc:
            raise CorruptFileError(f"{path}: {exc}") from exc
        except (ValueError, TypeError, KeyError, IndexError, OverflowError) as exc:
            raise CorruptFileError(f"{path}: inconsistent model file ({exc})") from exc

    @classmethod
    def _from_arrays(cls, a: dict[str, np.ndarray]) -> RCSFAICA:
        fmt = a["format"]
        if fmt.dtype.kind != "U" or fmt.shape != () or str(fmt) != FORMAT:
            raise CorruptFileError(f"not an RCSFAICA model (format {str(fmt)[:80]!r})")
        if a["params"].dtype.kind != "U" or a["params"].shape != ():
            raise CorruptFileError("the parameters are not a JSON string")
        try:
            raw = json.loads(str(a["params"]))
        except json.JSONDecodeError as exc:
            raise CorruptFileError(f"unreadable parameters ({exc})") from exc
        if not isinstance(raw, dict):
            raise CorruptFileError(f"the parameters are not a JSON object: {str(raw)[:80]}")
        known = {f.name for f in fields(RCSFAICAParams)}
        if isinstance(raw.get("input_range"), list):
            raw["input_range"] = tuple(raw["input_range"])
        try:
            params = RCSFAICAParams(**{k: v for k, v in raw.items() if k in known})
        except (TypeError, ValueError) as exc:
            raise CorruptFileError(f"bad parameters ({exc})") from exc
        p = params

        def arr(key: str, shape: tuple[int | None, ...], dtype: str = "float") -> np.ndarray:
            if key not in a:
                raise CorruptFileError(f"lacks required array {key!r}")
            try:
                return check_array(key, a[key], shape=shape, dtype=dtype, max_abs=_MAX_ABS)
            except ValueError as exc:
                raise CorruptFileError(str(exc)) from None

        def positive(key: str, v: np.ndarray) -> np.ndarray:
            if not (v > 0).all():
                raise CorruptFileError(f"{key} must be > 0 everywhere, got min {v.min():g}")
            return v

        n_u, n_sfa, n_ica = p.n_inputs, p.n_sfa, p.n_ica
        reservoir = None
        if p.use_reservoir:
            N = p.n_reservoir
            W_in = arr("W_in", (N, n_u))
            W_res = arr("W_res", (N, N))
            leak = arr("leak", (N,))
            if not np.array_equal(leak, expand_leak(p.leak, N)):
                raise CorruptFileError(f"leak does not match the parameters' leak {p.leak}")
            radius = float(np.max(np.abs(np.linalg.eigvals(W_res)))) if N else 0.0
            if not abs(radius - p.spectral_radius) <= 1e-6 * max(1.0, p.spectral_radius):
                raise CorruptFileError(f"W_res has spectral radius {radius:.6g}, its parameters "
                                       f"say {p.spectral_radius}")
            reservoir = Reservoir.from_weights(W_in, W_res, leak,
                                               spectral_radius=p.spectral_radius,
                                               dtype=p.dtype, device=p.device)
        d_in = n_u + (p.n_reservoir if p.use_reservoir else 0)
        sfa = SFA(p.sfa_params())
        if p.sfa_expansion == "quadratic":
            sfa.pre_mean_ = arr("sfa_pre_mean", (d_in,))
            sfa.pre_scale_ = positive("sfa_pre_scale", arr("sfa_pre_scale", (d_in,)))
            d = d_in + d_in * (d_in + 1) // 2
        else:
            d = d_in
        sfa.n_features_in_ = d_in
        sfa.mean_ = arr("sfa_mean", (d,))
        sfa.scale_ = arr("sfa_scale", (d,))
        if not (sfa.scale_ > 1e-12 * (1.0 + np.abs(sfa.mean_))).all():
            raise CorruptFileError("sfa_scale must be > 0 everywhere (above 1e-12 of the "
                                   "feature's mean, as fit leaves it)")
        sfa.W_ = arr("sfa_W", (d, n_sfa))
        sfa.slowness_ = arr("sfa_slowness", (n_sfa,))
        cutoff = arr("sfa_cutoff", ()) if "sfa_cutoff" in a else np.array(np.nan)
        sfa.cutoff_ = float(cutoff)
        if "sfa_n_whitened" in a:
            nw = int(arr("sfa_n_whitened", (), dtype="int"))
            if not n_sfa <= nw <= d:
                raise CorruptFileError(f"sfa_n_whitened={nw} must lie in [{n_sfa}, {d}]")
            sfa.n_whitened_ = nw
        else:
            sfa.n_whitened_ = -1
        ica = FastICA(p.ica_params())
        ica.mean_ = arr("ica_mean", (n_sfa,))
        ica.whitening_ = arr("ica_whitening", (n_sfa, n_ica))
        ica.rotation_ = arr("ica_rotation", (n_ica, n_ica))
        if not np.allclose(ica.rotation_ @ ica.rotation_.T, np.eye(n_ica), atol=1e-6):
            raise CorruptFileError("ica_rotation is not orthonormal (FastICA's unmixing is)")
        ica.components_ = ica.rotation_ @ ica.whitening_.T
        ica.n_features_in_ = n_sfa
        output_std = positive("output_std", arr("output_std", (n_ica,)))
        output_peak = arr("output_peak", (n_ica,))
        ica.output_std_ = output_std
        self = cls(params)
        self.reservoir_ = reservoir
        self.sfa_, self.ica_ = sfa, ica
        self.sfa_slowness_ = sfa.slowness_.copy()
        self.n_features_in_ = n_u
        self.output_std_, self.output_peak_ = output_std, output_peak
        self._compile()
        self.reset_state()
        return self

    # ------------------------------------------------------------------ misc
    def _check_fitted(self) -> None:
        if not hasattr(self, "ica_"):
            raise NotFittedError("RCSFAICA is not fitted yet; call fit(U) first")

    def __repr__(self) -> str:
        p = self.params
        res = (f"reservoir={p.n_reservoir}, leak={p.leak}, rho={p.spectral_radius}"
               if p.use_reservoir else "no reservoir")
        return (f"RCSFAICA(n_inputs={p.n_inputs}, {res}, n_sfa={p.n_sfa}, n_ica={p.n_ica}, "
                f"downsample={p.downsample}, seed={p.seed})")


def _output_stats(ica: FastICA, Y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Standard deviation and 99.9th percentile of each ICA output on its training input
    ``Y`` (T, n_sfa), one output at a time (one float64 column of length T alive, not the
    whole (T, n_ica) output)."""
    k = ica.components_.shape[0]
    std, peak = np.empty(k), np.empty(k)
    col = np.empty(Y.shape[0])
    for j in range(k):
        for t0 in range(0, Y.shape[0], _OUT_CHUNK):
            y = np.asarray(Y[t0:t0 + _OUT_CHUNK], dtype=np.float64)
            col[t0:t0 + _OUT_CHUNK] = (y - ica.mean_) @ ica.components_[j]
        std[j] = col.std()
        peak[j] = np.percentile(col, 99.9, overwrite_input=True)
    return std, peak


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
