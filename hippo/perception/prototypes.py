"""Place states from the whole RC-SFA-ICA population: radial-basis prototypes.

ICANN09 reads a place from the single most active ICA unit. In the closed loop that partition
is coarse and aliased: one ICA unit often fires at two distant places. HIREL instead recruits a
new place cell whenever no existing cell is active enough. :class:`PlacePrototypes` does that on
the RC-SFA-ICA output vector ``y`` (unit-variance, decorrelated: distances in it are distances
between slow-feature patterns)::

    a_k(y) = exp(-|y - c_k|² / (2 σ²))            activity of prototype k
    recruit c_new = y  when  max_k a_k(y) < θ     (online, optional)

The prototypes ``c_k`` start as k-means centres of the training outputs (seeded), ``σ`` is the
median distance of a training sample to its nearest centre. Measured on the patrol course
(wall-following tours, 24 units): the winning prototype's mean position is 7–9 cm from the robot
(median) and more than 30 cm away on 1 % of ticks, against 10–13 cm and 5–17 % for the most
active ICA unit.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from scipy.cluster.vq import kmeans2

from hippo._checks import check_array, check_fields, check_finite, check_positive
from hippo._estimator import NotFittedError, ParamsEstimator
from hippo.io import CorruptFileError, load_npz, save_npz

PROTOTYPES_FORMAT = "hippo.PlacePrototypes/1"


@dataclass(frozen=True)
class PrototypeParams:
    """n_prototypes: k-means centres fitted on the training outputs (default 32).
    recruit_threshold: online, a new prototype is recruited when no prototype's activity
    reaches this (0 disables recruitment; default 0). max_prototypes: recruitment cap.
    seed: seeds k-means."""

    n_prototypes: int = 32
    recruit_threshold: float = 0.0
    max_prototypes: int = 256
    seed: int = 0

    def __post_init__(self) -> None:
        check_fields(self)
        if int(self.n_prototypes) < 1:
            raise ValueError(f"n_prototypes must be >= 1, got {self.n_prototypes}")
        if not 0.0 <= self.recruit_threshold < 1.0:
            raise ValueError(f"recruit_threshold must lie in [0, 1), got "
                             f"{self.recruit_threshold}")
        if self.max_prototypes < self.n_prototypes:
            raise ValueError(f"max_prototypes ({self.max_prototypes}) must be >= n_prototypes "
                             f"({self.n_prototypes})")


class PlacePrototypes(ParamsEstimator):
    """Radial-basis place cells over a population code (see the module docstring)."""

    def __init__(self, params: PrototypeParams | None = None, **overrides: Any) -> None:
        self.params = replace(params or PrototypeParams(), **overrides)

    def fit(self, Y: np.ndarray, y: None = None) -> PlacePrototypes:
        """Fit the prototypes to training outputs ``Y`` (T, d)."""
        Y = _real("Y", Y)
        if Y.ndim != 2:
            raise ValueError(f"Y must have shape (T, d), got {Y.shape}")
        k = int(self.params.n_prototypes)
        if Y.shape[0] < k:
            raise ValueError(f"need at least n_prototypes={k} samples, got {Y.shape[0]}")
        span = float(np.max(np.abs(Y), initial=0.0))
        if not np.isfinite(span * span * 4.0 * Y.shape[1]):
            # squared distances overflow float64: k-means++ then draws from NaN probabilities
            # (scipy's kmeans2 crashed the interpreter at |Y| ~ 1e155)
            raise ValueError(f"Y holds values up to {span:.3g}, whose squared distances "
                             "overflow float64; rescale it")
        with np.errstate(invalid="ignore", divide="ignore"):  # all rows alike: k-means++'s 0/0
            centres, _ = kmeans2(Y, k, seed=self.params.seed, minit="++")
        # drop empty clusters (kmeans2 may leave a centre with no member far away)
        near = np.argmin(_sqdist(Y, centres), axis=1)
        centres = centres[np.unique(near)]
        d = np.sqrt(np.min(_sqdist(Y, centres), axis=1))
        self.n_features_in_ = Y.shape[1]
        self.centres_ = centres
        self.sigma_ = float(max(np.median(d), 1e-6))
        return self

    def fit_transform(self, Y: np.ndarray, y: None = None) -> np.ndarray:
        """``fit(Y)``, then the activities of ``Y``."""
        return self.fit(Y).transform(Y)

    @property
    def n_units(self) -> int:
        self._check_fitted()
        return len(self.centres_)  # type: ignore[arg-type]

    def transform(self, Y: np.ndarray) -> np.ndarray:
        """Activities (T, n_prototypes) of a sequence of outputs (no recruitment)."""
        self._check_fitted()
        Y = _real("Y", Y)
        given = Y.shape   # named as given: a row of the wrong length is not reported as (1, n)
        Y = Y[None] if Y.ndim == 1 else Y
        d = self.centres_.shape[1]  # type: ignore[union-attr]
        if Y.ndim != 2 or Y.shape[1] != d:
            raise ValueError(f"place-cell outputs must have shape ({d},) or (T, {d}) (the "
                             f"dimension the prototypes were fitted on), got {given}")
        return np.exp(-_sqdist(Y, self.centres_) / (2 * self.sigma_**2))  # type: ignore[operator]

    def step(self, y: np.ndarray) -> np.ndarray:
        """Activities for one output vector; recruits a prototype on a novel pattern."""
        self._check_fitted()
        d = self.centres_.shape[1]  # type: ignore[union-attr]
        if np.shape(y) != (d,):
            raise ValueError(f"place-cell output y must have shape ({d},), got {np.shape(y)}")
        return self._step(_real("place-cell output y", y))

    def _step(self, y: np.ndarray) -> np.ndarray:
        """:meth:`step` on a checked output vector (a finite float array of the right shape:
        :class:`~hippo.places.LearnedPlaceCells` hands over the model's own output). The
        centres' squared norms are kept from the previous tick (they change only when a
        prototype is recruited). The numbers of :meth:`transform` on one row, by 1-D
        operations (the same products and sums, in the same order)."""
        C = self.centres_
        if getattr(self, "_cc_of", None) is not C:
            self._cc, self._cc_of = (C * C).sum(1), C  # type: ignore[operator]
        d2 = float(np.add.reduce(y * y)) - (2 * y[None] @ C.T)[0] + self._cc  # type: ignore[union-attr]
        a = np.exp(-np.maximum(d2, 0.0) / (2 * self.sigma_**2))  # type: ignore[operator]
        p = self.params
        if (p.recruit_threshold > 0 and np.maximum.reduce(a) < p.recruit_threshold
                and len(self.centres_) < p.max_prototypes):  # type: ignore[arg-type]
            self.centres_ = np.vstack([self.centres_, np.asarray(y, float)[None]])
            a = np.append(a, 1.0)
        return a

    def save(self, path: str | os.PathLike) -> Path:
        self._check_fitted()
        return save_npz(path, {"format": np.array(PROTOTYPES_FORMAT),
                               "centres": self.centres_, "sigma": np.array(self.sigma_),
                               "n_prototypes": np.array(self.params.n_prototypes),
                               "recruit_threshold": np.array(self.params.recruit_threshold),
                               "max_prototypes": np.array(self.params.max_prototypes),
                               "seed": np.array(self.params.seed)})

    @classmethod
    def load(cls, path: str | os.PathLike) -> PlacePrototypes:
        """Read prototypes written by :meth:`save`; every array is checked (format tag, dtypes,
        shapes, finite centres, sigma > 0, parameters as at construction) and a damaged file
        raises :class:`~hippo.io.CorruptFileError` naming the problem."""
        d = load_npz(path, required=("format", "centres", "sigma", "n_prototypes",
                                     "recruit_threshold", "max_prototypes", "seed"))
        fmt = d["format"]
        if fmt.dtype.kind != "U" or fmt.shape != () or str(fmt) != PROTOTYPES_FORMAT:
            raise CorruptFileError(f"{path} is not a saved PlacePrototypes")
        try:
            params = PrototypeParams(
                int(check_array("n_prototypes", d["n_prototypes"], shape=(), dtype="int")),
                float(check_array("recruit_threshold", d["recruit_threshold"], shape=())),
                int(check_array("max_prototypes", d["max_prototypes"], shape=(), dtype="int")),
                int(check_array("seed", d["seed"], shape=(), dtype="int")))
            centres = check_array("centres", d["centres"], shape=(None, None), max_abs=1e12)
            sigma = check_positive("sigma", float(check_array("sigma", d["sigma"], shape=(),
                                                              max_abs=1e12)))
            if sigma < 1e-6:  # fit floors it there
                raise ValueError(f"sigma must be >= 1e-6, got {sigma}")
            if not 1 <= len(centres) <= params.max_prototypes or centres.shape[1] < 1:
                raise ValueError(f"centres has shape {centres.shape}: need 1 to max_prototypes="
                                 f"{params.max_prototypes} rows of >= 1 values")
        except ValueError as exc:
            raise CorruptFileError(f"{path}: {exc}") from exc
        obj = cls(params)
        obj.centres_, obj.sigma_ = centres, sigma
        return obj

    def _check_fitted(self) -> None:
        if getattr(self, "centres_", None) is None:
            raise NotFittedError("PlacePrototypes is not fitted; call fit() first")


def _real(name: str, Y: object) -> np.ndarray:
    """``Y`` as a finite float array; complex values are refused, not cast."""
    arr = np.asarray(Y)
    if np.iscomplexobj(arr):
        raise ValueError(f"{name} must be real numbers, got dtype {arr.dtype}")
    return check_finite(name, arr)


def _sqdist(Y: np.ndarray, C: np.ndarray, cc: np.ndarray | None = None) -> np.ndarray:
    """Squared Euclidean distances between rows of ``Y`` and rows of ``C`` (``cc``: the rows
    of ``C``'s squared norms, if already known)."""
    if cc is None:
        cc = (C * C).sum(1)
    return np.maximum(np.add.reduce(Y * Y, axis=1)[:, None] - 2 * Y @ C.T + cc[None], 0.0)
