"""The slow pool: a leaky running mean of the SFA input, appended to it (``slow_pool`` of
:class:`~hippo.perception.place_cell_params.RCSFAICAParams`).

With ``z(t) = [u(t); x(t+1)]`` the SFA input of RC-SFA-ICA (SMC09 eq. 1, 6-7) and
``τ = slow_pool`` (reservoir ticks; the rate of the reservoir updates, one a control tick
without down-sampling), the pool is a leaky integrator of ``z`` from ``m(-1) = 0``:

    m(t) = (1 - 1/τ) m(t-1) + (1/τ) z(t)                                         (pool)
    SFA input = [z(t); m(t)]                        (twice the width; τ = 0: just z(t))

so on a step input ``z = c`` from ``t = 0``, ``m(t) = c (1 - (1 - 1/τ)^(t+1))``. SMC09's leaky
reservoir forgets within a few tens of ticks (time constants ``1/a`` of 7-20 ticks at leaks
0.05-0.15); a room visit in a generated flat lasts hundreds. The pool keeps an exponentially
fading memory of the state over ``τ`` ticks (an ESN's "slow" leaky-integrator units, Jaeger et
al. 2007, Neural Networks 20: 335-352, with the leak taken out of the recurrent loop), which
SFA can then read as a slow feature. ``τ = 0`` (default) is off: the features, the fit and the
outputs are exactly those without a pool.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from scipy.signal import lfilter

__all__ = ["SlowPool", "check_slow_pool", "with_pool"]


def check_slow_pool(value: Any, name: str = "slow_pool") -> float:
    """``value`` as a time constant: 0 (off) or a finite real number ≥ 1 (ticks); else a
    ValueError naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise ValueError(f"{name} must be a number of ticks (0 = off), got {value!r}")
    v = float(value)
    if not (v == 0.0 or (math.isfinite(v) and v >= 1.0)):
        shown = value.item() if isinstance(value, np.generic) else value   # not np.float64(..)
        raise ValueError(f"{name} must be 0 (off) or a time constant >= 1 tick, got {shown!r}")
    return v


def with_pool(Z: np.ndarray, tau: float, m0: np.ndarray | None = None
              ) -> tuple[np.ndarray, np.ndarray | None]:
    """``[Z, M]`` for features ``Z`` (T, d) and the pool ``M`` (T, d) run from ``m0`` (default:
    zeros), with the pool's last row (the state to continue from); ``tau = 0``: ``(Z, None)``.
    Computed in float64, returned in ``Z``'s dtype. ``tau`` must be 0 or >= 1 (below 1 the
    pool oscillates or diverges)."""
    tau = check_slow_pool(tau, "tau")
    if not tau:
        return Z, None
    beta = 1.0 / float(tau)
    Z64 = np.asarray(Z, dtype=np.float64)
    zi = None if m0 is None else ((1.0 - beta) * np.asarray(m0, dtype=np.float64))[None, :]
    if zi is None:
        M = lfilter([beta], [1.0, beta - 1.0], Z64, axis=0)
    else:
        M, _ = lfilter([beta], [1.0, beta - 1.0], Z64, axis=0, zi=zi)
    last = M[-1].copy() if len(M) else (np.zeros(Z.shape[1]) if m0 is None
                                        else np.asarray(m0, dtype=np.float64).copy())
    return np.concatenate([Z, M.astype(Z.dtype, copy=False)], axis=1), last


class SlowPool:
    """The pool's online state for :meth:`RCSFAICA.step`: ``m`` (d,), float64, from zeros."""

    def __init__(self, tau: float, d: int) -> None:
        if not check_slow_pool(tau):
            raise ValueError("slow_pool: an online pool needs a time constant >= 1 tick, got 0")
        self.beta = 1.0 / float(tau)
        self.m = np.zeros(int(d))

    def reset(self) -> None:
        """``m = 0`` (as at the start of :meth:`RCSFAICA.transform`)."""
        self.m[:] = 0.0

    def step(self, z: np.ndarray) -> np.ndarray:
        """One tick of the pool equation; returns ``m(t)`` (a view: copy it if you keep it)."""
        self.m *= 1.0 - self.beta
        self.m += self.beta * np.asarray(z, dtype=np.float64)
        return self.m
