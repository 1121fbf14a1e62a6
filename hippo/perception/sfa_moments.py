"""The running sums that SFA learns from (:class:`SFAMoments`), fed chunk by chunk.

SFA (:mod:`hippo.perception.sfa`) needs of its data only the mean, the scatter ``Σ x xᵀ`` and the
derivative scatter ``Σ ẋ ẋᵀ``; they are accumulated here in float64, chunk by chunk
(:func:`chunk_bounds`), so a float32 recording is never copied whole and ``RCSFAICA.fit`` can
summarise reservoir states while the reservoir is still running.
"""

from __future__ import annotations

import numpy as np

#: rows per chunk when accumulating moments: bounds the float64 working copies to ~16 MB
_CHUNK_VALUES = 2_000_000


def chunk_bounds(T: int, d: int, *, split: int | None = None, rows: int | None = None) -> list[int]:
    """Row boundaries ``[0, ..., T]`` of the chunks in which a ``(T, d)`` series is accumulated
    (``rows`` per chunk, by default ~2 million values; ``split``, when given, is a boundary)."""
    rows = int(rows) if rows else max(256, _CHUNK_VALUES // max(d, 1))
    b = set(range(0, T, rows)) | {T}
    if split is not None:
        b.add(int(split))
    return sorted(b)


class SFAMoments:
    """Running sums of a time series, fed in consecutive chunks: all that SFA needs of the data.

    After ``update(X_1)``, ``update(X_2)``, … (rows in time order, each chunk continuing the
    previous one) it holds ``n`` samples, their ``mean``, the centred ``scatter``
    ``Σ (x - mean)(x - mean)ᵀ`` and the derivative scatter ``diff_scatter = Σ ẋ ẋᵀ`` over the
    ``n_diff = n - 1`` first differences, including those across chunk boundaries. Chunks are
    centred on their own mean and combined with Chan, Golub & LeVeque's (1979) pairwise update, so
    a large mean does not cancel the variance; differences are taken in float64 before any
    centring. Feeding one chunk or many gives the same sums to rounding.

    This lets a reservoir be harvested and summarised chunk by chunk (``RCSFAICA.fit`` overlaps
    the two), and keeps only chunk-sized float64 copies in memory.
    """

    def __init__(self, n_features: int) -> None:
        d = int(n_features)
        if d < 1:
            raise ValueError(f"n_features must be >= 1, got {n_features}")
        self.n = 0
        self.mean = np.zeros(d)
        self.scatter = np.zeros((d, d))
        self.n_diff = 0
        self.diff_scatter = np.zeros((d, d))
        self.first: np.ndarray | None = None
        self.last: np.ndarray | None = None

    @property
    def n_features(self) -> int:
        return self.mean.shape[0]

    def update(self, X: np.ndarray) -> SFAMoments:
        """Add the rows of ``X`` (k, d), which follow the rows already added."""
        X = np.asarray(X)
        if X.ndim != 2 or X.shape[1] != self.n_features:
            raise ValueError(f"chunk must have shape (k, {self.n_features}), got {X.shape}")
        if X.shape[0] == 0:
            return self
        chunk = SFAMoments(self.n_features)
        Xd = np.array(X, dtype=np.float64)            # own float64 copy, centred in place below
        D = np.diff(Xd, axis=0)
        chunk.diff_scatter, chunk.n_diff = D.T @ D, D.shape[0]
        chunk.first, chunk.last = Xd[0].copy(), Xd[-1].copy()
        chunk.n, chunk.mean = Xd.shape[0], Xd.mean(axis=0)
        Xd -= chunk.mean
        chunk.scatter = Xd.T @ Xd
        self._absorb(chunk)
        return self

    def _absorb(self, part: SFAMoments) -> None:
        """Append the moments of ``part``, the series that follows this one: the difference
        across the boundary, then Chan's pairwise update of mean and scatter."""
        if part.n == 0:
            return
        self.diff_scatter += part.diff_scatter
        self.n_diff += part.n_diff
        if self.last is not None:
            b = part.first - self.last
            self.diff_scatter += np.outer(b, b)
            self.n_diff += 1
        else:
            self.first = part.first
        n, k = self.n, part.n
        delta = part.mean - self.mean
        self.mean = self.mean + delta * (k / (n + k))
        self.scatter += part.scatter + np.outer(delta, delta) * (n * k / (n + k))
        self.n = n + k
        self.last = part.last

    def merged(self, later: SFAMoments) -> SFAMoments:
        """The moments of this series followed by ``later`` (a new object)."""
        if later.n_features != self.n_features:
            raise ValueError("moments of different dimensions cannot be merged")
        out = SFAMoments(self.n_features)
        out._absorb(self)
        out._absorb(later)
        return out

    def scatter_about(self, center: np.ndarray) -> np.ndarray:
        """``Σ (x - center)(x - center)ᵀ``."""
        delta = self.mean - center
        return self.scatter + self.n * np.outer(delta, delta)
