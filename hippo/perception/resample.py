"""Causal input down-sampling with an anti-aliasing filter, and zero-order-hold up-sampling.

ICANN09 down-samples the 17 sensor signals by ``dt = 50`` (Matlab ``resample``: an
anti-aliasing low-pass, then every 50th sample) because the robot moves slowly compared with
the sensor rate, and up-samples the SFA/ICA outputs back to the original rate.

Here the low-pass is a **causal** Hamming-windowed-sinc FIR (cut-off at the new Nyquist
frequency, ``2·factor + 1`` taps by default, group delay ``factor`` input ticks) so the very
same computation runs offline (:meth:`Decimator.offline`) and online, one tick at a time
(:meth:`Decimator.push`): the closed-loop agent sees exactly what the model was trained on.
Output samples are taken at ticks ``factor-1, 2·factor-1, ...`` (after each block of
``factor`` inputs); up-sampling holds each output until the next one (:func:`hold`).
"""

from __future__ import annotations

import numpy as np
import scipy.signal

from hippo._checks import check_finite, check_int


def antialias_taps(factor: int, numtaps: int | None = None) -> np.ndarray:
    """Low-pass FIR taps for down-sampling by ``factor`` (unit DC gain)."""
    factor = check_int("downsample factor", factor, lo=1)
    if factor == 1:
        return np.ones(1)
    n = 2 * factor + 1 if numtaps is None else check_int("numtaps", numtaps, lo=1)
    taps = scipy.signal.firwin(n, 1.0 / factor, window="hamming")
    return taps / taps.sum()


class Decimator:
    """Causal FIR low-pass + keep every ``factor``-th sample; offline and online agree.

    ``y[k] = Σ_j h[j] u[t_k - j]`` with ``t_k = (k+1)·factor - 1`` and ``u[t] = 0`` for ``t < 0``.
    """

    def __init__(self, factor: int, numtaps: int | None = None) -> None:
        self.factor = check_int("downsample factor", factor, lo=1)
        self.taps = antialias_taps(self.factor, numtaps)
        # applied to a window ordered oldest -> newest
        self._rev = self.taps[::-1].copy()
        #: group delay of the low-pass in input ticks: down-sampled sample ``k`` represents the
        #: input around tick ``sample_ticks()[k] - delay``
        self.delay = (self.taps.size - 1) / 2
        self.reset()

    def sample_ticks(self, T: int) -> np.ndarray:
        """Input ticks at which the down-sampled samples are taken (``factor-1, 2·factor-1,
        ...`` below ``T``)."""
        return np.arange(T // self.factor) * self.factor + self.factor - 1

    def reset(self) -> None:
        """Forget the online history (zeros, as the offline filter assumes)."""
        self._buf: np.ndarray | None = None
        self._t = 0

    def offline(self, U: np.ndarray) -> np.ndarray:
        """Down-sampled ``(T // factor, n)`` version of ``U`` ``(T, n)``."""
        U = check_finite("input U", U)
        if U.ndim != 2:
            raise ValueError(f"input U must be (T, n) (one row a tick), got shape {U.shape}")
        if self.factor == 1:
            return U.copy()
        T, n = U.shape
        L = self.taps.size
        K = T // self.factor
        padded = np.concatenate([np.zeros((L - 1, n)), U], axis=0)
        ends = np.arange(K) * self.factor + self.factor - 1 + (L - 1)  # index in padded
        idx = ends[:, None] - np.arange(L - 1, -1, -1)[None, :]        # oldest -> newest
        return np.matmul(self._rev, padded[idx])

    def push(self, u: np.ndarray) -> np.ndarray | None:
        """Feed one input tick; return the new down-sampled sample at decimation instants,
        else ``None``."""
        u = check_finite("reading u", u)
        if u.ndim != 1 or (self._buf is not None and u.size != self._buf.shape[1]):
            want = "1-D" if self._buf is None else f"({self._buf.shape[1]},) as before"
            raise ValueError(f"reading u must be {want}, got shape {u.shape}")
        if self.factor == 1:
            return u
        L = self.taps.size
        if self._buf is None:
            self._buf = np.zeros((L, u.size))
        buf = self._buf
        buf[:-1] = buf[1:]
        buf[-1] = u
        self._t += 1
        if self._t % self.factor == 0:
            return np.matmul(self._rev, buf[None])[0]
        return None


def hold(Y: np.ndarray, T: int, factor: int, initial: np.ndarray) -> np.ndarray:
    """Zero-order-hold ``Y`` ``(K, k)`` (one row per decimation instant) back to ``T`` ticks.

    Tick ``t`` gets the most recent output computed at or before ``t``; ticks before the first
    instant get ``initial``.
    """
    Y = np.asarray(Y)
    factor = check_int("factor", factor, lo=1)
    if factor == 1:
        return Y[:T].copy()
    out = np.empty((T, Y.shape[1]), dtype=Y.dtype)
    k = (np.arange(T) + 1) // factor - 1
    first = k >= 0
    out[~first] = initial
    out[first] = Y[np.minimum(k[first], Y.shape[0] - 1)]
    return out
