"""RC-SFA-ICA: place cells that learn themselves from distance sensors (SMC09, ICANN09).

Three layers (SMC09 Fig. 1), only the upper two learn, one after the other:

    x(t+1)   = tanh((1-a) x(t) + a (W_in u(t) + W_res x(t)))     reservoir   (eq. 1)
    y_sfa(t) = W_sfaᵀ z([u(t); x(t+1)])                          linear SFA  (eq. 6-7)
    y_ica(t) = W_ica (y_sfa(t) - μ)                               FastICA     (eq. 8-10)

(``z`` is the z-scoring learned on the training data.) With ``slow_pool = τ > 0`` SFA reads
``[u; x; m]``, ``m`` a leaky running mean of ``[u; x]`` over ``τ`` ticks
(:mod:`~hippo.perception.slow_pool`).
The estimator follows scikit-learn: ``__init__`` only stores parameters, :meth:`RCSFAICA.fit`
learns, fitted attributes end in ``_``, :meth:`RCSFAICA.transform` runs a whole recording
offline from ``x(0) = 0``. For the closed loop, :meth:`RCSFAICA.step` takes one sensor vector
per control tick and returns the place-cell activities; after :meth:`RCSFAICA.reset_state`,
stepping through ``U`` reproduces ``transform(U)`` to float rounding.

Output scale: ICA outputs are **unit variance on the training data** (``output_std_`` = 1), so
units are comparable with each other and ICANN09's "responds ≥ 4.5" reads as 4.5 training
standard deviations. ``output_peak_`` (each unit's 99.9th percentile on the training data) lets
a state layer normalise activities to roughly [.., 1].

Fitting runs on both cores: the reservoir is harvested chunk by chunk while a second thread
adds each finished chunk to the SFA moments (:mod:`~hippo.perception.sfa_moments`), so SFA
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
activities of ±1e4). NaN and inf are always refused (the checks:
:mod:`~hippo.perception.place_cell_inputs`).

Optional input down-sampling (``downsample > 1``, ICANN09: 50) uses a causal anti-aliasing
FIR (:mod:`hippo.perception.resample`); the reservoir then ticks once per ``downsample`` inputs
and outputs are held in between.
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import replace
from itertools import pairwise
from pathlib import Path
from typing import Any

import numpy as np

from hippo._estimator import NotFittedError, ParamsEstimator
from hippo._threads import single_threaded_blas
from hippo.perception.ica import FastICA, output_stats
from hippo.perception.place_cell_files import FORMAT, load_model, save_model
from hippo.perception.place_cell_inputs import InputRangeWarning, SensorInputs
from hippo.perception.place_cell_params import ICANN09, SMC09, RCSFAICAParams
from hippo.perception.resample import Decimator, hold
from hippo.perception.reservoir import Reservoir
from hippo.perception.sfa import SFA
from hippo.perception.sfa_moments import SFAMoments, chunk_bounds
from hippo.perception.slow_pool import SlowPool, with_pool

__all__ = [
    "FORMAT",
    "ICANN09",
    "RCSFAICA",
    "SMC09",
    "InputRangeWarning",
    "RCSFAICAParams",
]


#: reservoir ticks per chunk when the harvest and the SFA moments run side by side
_HARVEST_CHUNK = 2048
#: a fit holds the reservoir states up to this size, and streams them beyond (``fit(stream=)``)
_HOLD_BYTES = 256 * 2**20
#: the bounds of step's range check without ``input_range``: every finite reading, not inf
_FLOAT_MAX = float(np.finfo(np.float64).max)


class RCSFAICA(SensorInputs, ParamsEstimator):
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
    def features(self, U: np.ndarray, *, downsampled: bool = False) -> np.ndarray:
        """SFA input ``[u(t); x(t+1)]`` (and its slow pool ``m(t)`` with ``slow_pool``) for a
        recording ``U`` (at the down-sampled rate), from ``x(0) = 0``, ``m(-1) = 0``. Set
        ``downsampled=True`` if ``U`` is already down-sampled."""
        U = self._check_U(U)
        Ud = U if downsampled else self._decimator().offline(U)
        if self.reservoir_ is not None:
            X = self.reservoir_.run(Ud)
            Ud = np.concatenate([Ud.astype(X.dtype), X], axis=1)
        return with_pool(Ud, self.params.slow_pool)[0]

    def _chunk(self, Ud: np.ndarray, t0: int, t1: int, state: tuple | None,
               out: np.ndarray | None = None) -> tuple[np.ndarray, tuple]:
        """Features of ``Ud[t0:t1]`` (into ``out`` if given) continuing from ``state`` (the
        reservoir state and the pool's, None: zeros); returns them and the state at the end."""
        res = self.reservoir_
        x0, m0 = state or (None, None)
        S = res.run(Ud[t0:t1], x0=x0)
        Z = np.concatenate([Ud[t0:t1].astype(res.np_dtype), S], axis=1)
        F, m = with_pool(Z, self.params.slow_pool, m0)
        if out is not None:
            out[...] = F
        return (F if out is None else out), (S[-1].copy(), m)

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

        BLAS runs on one thread throughout: products split over more threads sum in
        another order, and the free cores follow the machine's load (same seed, same bits:
        ICA's rotation moved by 1e-10 between a busy and a quiet machine).
        """
        with single_threaded_blas():
            return self._fit(U, stream)

    def _fit(self, U: np.ndarray, stream: bool | None) -> RCSFAICA:
        U = self._check_U(U, fitting=True)
        self._check_trainable(U)
        p = self.params
        self.reservoir_ = self._build_reservoir()
        self.n_features_in_ = p.n_inputs
        Ud = self._decimator().offline(U)
        if self.reservoir_ is None or p.sfa_expansion != "linear":
            return self._fit_features(self.features(Ud, downsampled=True))
        d = p.sfa_inputs
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

        Also returns the chunks ``(t0, t1, state)`` with the state each starts from (the
        reservoir's and the slow pool's, None: zeros).
        With ``hold=False`` the features are not kept (None is returned for them): each chunk
        lives until its moments are added, at most two chunks at a time."""
        p = self.params
        res = self.reservoir_
        T = Ud.shape[0]
        d = p.sfa_inputs
        if hold:
            X = np.empty((T, d), dtype=res.np_dtype)
        w = int(p.washout)
        split = SFA(p.sfa_params()).auto_split(T - w)
        parts = [SFAMoments(d) for _ in range(1 if split is None else 2)]
        bounds = sorted({0, *(w + b for b in chunk_bounds(T - w, d, split=split,
                                                           rows=_HARVEST_CHUNK))})
        state = None
        chunks = []
        with single_threaded_blas(), ThreadPoolExecutor(1) as pool:
            pending = []
            for t0, t1 in pairwise(bounds):
                chunks.append((t0, t1, state))
                F, state = self._chunk(Ud, t0, t1, state, X[t0:t1] if hold else None)
                if t0 >= w:
                    part = parts[0 if split is None or t1 - w <= split else 1]
                    if not hold and len(pending) >= 1:  # bound the chunks alive to two
                        pending.pop(0).result()
                    pending.append(pool.submit(part.update, F))
                del F
            for job in pending:
                job.result()
        return (X if hold else None), parts, chunks

    def _fit_streamed(self, Ud: np.ndarray) -> RCSFAICA:
        """Fit without holding the state sequence (see ``fit(stream=True)``)."""
        p = self.params
        w = int(p.washout)
        _, parts, chunks = self._harvest_summarised(Ud, hold=False)
        self.sfa_ = SFA(p.sfa_params())
        d = p.sfa_inputs
        self.sfa_._prepare_shape(Ud.shape[0] - w, d)
        self.sfa_._solve(parts, Ud.shape[0] - w)
        # the ICA input, the only array of length T: n_sfa float32 columns (16 bytes a tick)
        Y = np.empty((Ud.shape[0] - w, int(p.n_sfa)), dtype=np.float32)
        with single_threaded_blas():  # the same chunks from the same states: the same states
            for t0, t1, state in chunks:
                if t0 >= w:
                    Y[t0 - w:t1 - w] = self.sfa_._project(self._chunk(Ud, t0, t1, state)[0])
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
        self.output_std_, self.output_peak_ = output_stats(self.ica_, Y)
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
            self._y_init = self.readout(np.zeros((1, d)))[0]

    def readout(self, X: np.ndarray, return_sfa: bool = False):
        """Place-cell activities for SFA inputs ``X`` (T, d) as :meth:`features` gives them
        (``[u; x]``, with the slow pool ``[u; x; m]``): ICA of SFA, row by row. With
        ``return_sfa`` also the SFA outputs."""
        self._check_fitted()
        Y = self.sfa_.transform(X)      # checks X's shape and values
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
        S, Y = self.readout(X, return_sfa=True)
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
        """Start the online loop afresh: reservoir state 0, slow pool 0, empty down-sampling
        history."""
        self._check_fitted()
        res, tau = self.reservoir_, self.params.slow_pool
        if res is not None:
            res.reset()
        d = self.params.n_inputs + (0 if res is None else res.n_neurons)
        self._pool = SlowPool(tau, d) if tau else None
        self._dec = self._decimator()
        self._last = self._y_init.copy()

    def step(self, u: np.ndarray) -> np.ndarray:
        """One tick: feed the sensors ``u`` (n_inputs,), get the activities (n_ica,), a copy."""
        self._check_fitted()
        n = self.params.n_inputs
        try:
            u = np.asarray(u, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"sensor vector u must be {n} real numbers, got {u!r}") from None
        if u.shape != (n,):
            raise ValueError(f"sensor vector u must have shape ({n},), got {u.shape}")
        # one cheap check per tick, float comparisons over the few readings: NaN fails them,
        # and so does inf without a range (the bounds are then the largest finite floats)
        rng = self.params.input_range
        lo, hi = (-_FLOAT_MAX, _FLOAT_MAX) if rng is None else rng
        if not all(lo <= v <= hi for v in u.tolist()):
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
            # (z cast first: the numbers of the mixed float32 x float64 product, 2 x faster)
            out = np.asarray(z, dtype=self._R.dtype) @ self._R[:z.size] + self._r0
            if self._pool is not None:
                out += self._pool.step(z) @ self._R[z.size:]
        else:
            z = u if res is None else np.concatenate([u, res.step(u)])
            if self._pool is not None:
                z = np.concatenate([z, self._pool.step(z)])
            out = self.readout(z[None, :])[0]
        self._last = out
        return out.copy()

    # ------------------------------------------------------------------ persistence
    def save(self, path: str | os.PathLike) -> Path:
        """Write the fitted model to ``path`` (.npz, atomic, no pickle): its parameters and
        its parts' own states (:mod:`hippo.perception.place_cell_files`)."""
        return save_model(self, path)

    @classmethod
    def load(cls, path: str | os.PathLike) -> RCSFAICA:
        """Read a model written by :meth:`save`, trusting nothing: the format tag, the
        parameters (checked like the constructor's), then each part loads its own state and
        checks it against them. A damaged file raises :class:`~hippo.io.CorruptFileError`
        naming the problem; nothing is half-loaded."""
        return load_model(cls, path)

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
