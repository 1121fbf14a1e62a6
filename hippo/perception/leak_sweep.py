"""A leak sweep: many leak configurations fitted over one reservoir, harvested together."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from hippo._threads import n_workers, parallel_map
from hippo.perception.backends import _num_threads as _torch_threads
from hippo.perception.place_cell_params import RCSFAICAParams
from hippo.perception.place_cells import RCSFAICA
from hippo.perception.reservoir import Reservoir, expand_leak

__all__ = ["fit_leak_sweep"]

#: leak configurations harvested together by ``fit_leak_sweep``
_SWEEP_BATCH = 16


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
