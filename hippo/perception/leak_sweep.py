"""A leak sweep: many leak configurations fitted over one reservoir, harvested together."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from hippo._threads import n_workers, parallel_map
from hippo.perception.backends import _num_threads as _torch_threads
from hippo.perception.place_cell_params import RCSFAICAParams
from hippo.perception.place_cells import RCSFAICA
from hippo.perception.reservoir import Reservoir
from hippo.perception.reservoir_params import expand_leak
from hippo.perception.sfa import SFA
from hippo.perception.sfa_moments import SFAMoments
from hippo.perception.slow_pool import with_pool

__all__ = ["SweepFeatures", "fit_leak_sweep", "sweep_features"]

#: leak configurations harvested together by ``fit_leak_sweep``
_SWEEP_BATCH = 16


@dataclass
class SweepFeatures:
    """The features ``[u; x]`` (``[u; x; m]`` with a slow pool) of one recording under each leak
    configuration of a sweep (one reservoir, same weights): ``X[b]`` is ``(T', d)`` for
    ``leaks[b]``, one row per reservoir update (``T' = T`` without down-sampling). :meth:`fit`
    fits configuration ``b`` on any block of rows, so a fit on a prefix equals a fit on that
    prefix of the recording."""

    base: RCSFAICAParams
    leaks: list[Any]
    reservoir: Reservoir
    A: np.ndarray
    X: list[np.ndarray]
    _moments: dict[tuple[int, int, int], SFAMoments] = field(default_factory=dict, repr=False)

    def moments(self, b: int, t0: int = 0, t1: int | None = None) -> SFAMoments:
        """SFA's moments of the rows ``t0:t1`` of configuration ``b`` (merge the moments of
        consecutive blocks with :meth:`SFAMoments.merged` to fit on their union for the cost of
        the eigenproblem alone). Kept: asking again costs nothing."""
        t0, t1, _ = slice(t0, t1).indices(len(self.X[b]))
        if (b, t0, t1) not in self._moments:
            m = SFAMoments(self.X[b].shape[1])
            for c in range(t0, t1, 4096):
                m.update(self.X[b][c:min(c + 4096, t1)])
            self._moments[b, t0, t1] = m
        return self._moments[b, t0, t1]

    def fit_sfa(self, b: int, t0: int = 0, t1: int | None = None,
                moments: SFAMoments | None = None) -> SFA:
        """SFA alone (no ICA) of configuration ``b`` fitted on the rows ``t0:t1``."""
        X = self.X[b][t0:t1]
        sfa = SFA(self.base.sfa_params())
        sfa._prepare(X)
        sfa._fit_moments([moments if moments is not None else self.moments(b, t0, t1)], X)
        return sfa

    def fit(self, b: int, t0: int = 0, t1: int | None = None,
            moments: SFAMoments | None = None) -> RCSFAICA:
        """An :class:`RCSFAICA` of configuration ``b`` fitted on the rows ``t0:t1`` (with
        ``moments``, those rows' SFA moments: see :meth:`moments`)."""
        if self.base.washout and moments is not None:
            raise ValueError("moments are given for the rows after the washout: washout=0 only")
        lk = self.leaks[b]
        lk_param = float(lk) if np.ndim(lk) == 0 else tuple(float(v) for v in np.ravel(lk))
        m = RCSFAICA(self.base, leak=lk_param)
        res = self.reservoir
        m.reservoir_ = Reservoir.from_weights(res.W_in, res.W_res, self.A[b],
                                              spectral_radius=self.base.spectral_radius,
                                              dtype=self.base.dtype, device=self.base.device)
        m.n_features_in_ = self.base.n_inputs
        return m._fit_features(self.X[b][t0:t1], None if moments is None else [moments])


def sweep_features(U: np.ndarray, leaks: Sequence[Any], params: RCSFAICAParams | None = None,
                   *, workers: int | None = None, **overrides: Any) -> SweepFeatures:
    """Harvest ``U`` under every leak configuration over **one** reservoir, up to 16 at a time
    (one matrix-matrix product per tick for the batch, on one BLAS thread: on two threads the
    product sums in another order, float32 states moved by up to 4e-7, and the free cores
    follow the machine's load; ``workers`` is accepted for symmetry and changes no number)."""
    return _sweep(U, leaks, replace(params or RCSFAICAParams(), **overrides), workers)


def _sweep(U: np.ndarray, leaks: Sequence[Any], base: RCSFAICAParams, workers: int | None,
           *, fitting: bool = False) -> SweepFeatures:
    """:func:`sweep_features` with ``base``; ``fitting``: refuse ``U`` as
    :meth:`RCSFAICA.fit` does (readings outside ``input_range`` whatever ``out_of_range``
    says, too few updates after the washout, every sensor stuck), in its words."""
    if not base.use_reservoir:
        raise ValueError("a leak sweep needs use_reservoir=True")
    if len(leaks) == 0:
        raise ValueError("leaks is empty")
    template = RCSFAICA(base)
    U = template._check_U(U, fitting=fitting)
    if fitting:
        template._check_trainable(U)
    res = template._build_reservoir()
    N = base.n_reservoir
    A = np.stack([expand_leak(lk, N) for lk in leaks])
    Ud = template._decimator().offline(U)
    n_workers(workers)  # checked: the same argument as fit_leak_sweep's
    X: list[np.ndarray] = []
    for g in range(0, len(leaks), _SWEEP_BATCH):
        S = res.run(Ud, leak=A[g:g + _SWEEP_BATCH], threads=1)  # (b, T, N)
        X.extend(with_pool(np.concatenate([Ud.astype(Sb.dtype), Sb], axis=1), base.slow_pool)[0]
                 for Sb in S)
        del S
    return SweepFeatures(base, list(leaks), res, A, X)


def fit_leak_sweep(U: np.ndarray, leaks: Sequence[Any], params: RCSFAICAParams | None = None,
                   *, workers: int | None = None, **overrides: Any) -> list[RCSFAICA]:
    """Fit one :class:`RCSFAICA` per leak configuration over **one** reservoir (same weights).

    The configurations are harvested together, up to 16 at a time (one matrix-matrix product
    per tick for the batch, one BLAS thread); then ``workers`` threads (default: the
    usable cores), each with single-threaded BLAS, fit SFA and ICA for one configuration after
    another. ``leaks`` is a sequence of leak specs (each a float, k floats, or N floats). Returns
    the fitted models, in the order of ``leaks``, whose ``params.leak`` is the configuration
    (as given). The recording is refused as :meth:`RCSFAICA.fit` refuses it, in the same words.
    """
    F = _sweep(U, leaks, replace(params or RCSFAICAParams(), **overrides), workers, fitting=True)
    k = min(n_workers(workers), len(leaks))
    with _torch_threads(1):
        return parallel_map(F.fit, range(len(leaks)), k)
