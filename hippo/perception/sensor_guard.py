"""Dead-sensor detection and imputation in front of the place cells.

A place code learned from 8 IR sensors depends on every one of them: a sensor stuck at 0 reads
"touching a wall" for ever, and the reservoir carries that false wall everywhere. The guard sits
between the sensors and the reservoir and does two things, causally (tick by tick, from the
last ``window`` readings only):

**Detection.** Over the last ``window`` ticks, sensor ``i`` is

* *stuck* if its readings did not change (range ``max - min < stuck_tol``): a live IR sensor
  always carries its own noise, even at a wall or with nothing in range;
* *noise-only* if its mean squared tick-to-tick change ``e_i`` exceeds ``noise_ratio`` times
  the median of all sensors' ``e`` *and* ``noise_floor``: live readings change smoothly as the
  robot moves, pure noise does not. (Noise added to every sensor raises the median with it, so
  it is not mistaken for dead sensors.)

At most ``max_dead`` sensors are flagged (the most suspect ones).

**Imputation.** A flagged sensor's reading is replaced by its conditional mean given the live
sensors under the Gaussian fitted to the (clean) training readings::

    û_D = μ_D + Σ_DA Σ_AA⁻¹ (u_A - μ_A)

(the best linear estimate from the other sensors; neighbouring IR rays are strongly
correlated), clipped to [0, 1]. With nothing flagged the readings pass through unchanged, so
the guard costs nothing on a healthy robot.

The choice of this design over training with random sensor dropout was made by measurement on
the tuning seeds (see ``hippo run two-rooms --faults``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hippo._checks import check_fields, check_finite, check_int

#: the longest detection window (ticks; 5.5 h of 0.2 s ticks): the online guard keeps and
#: scans that many readings every tick
MAX_WINDOW = 100_000


@dataclass(frozen=True)
class SensorGuardParams:
    """Detection window (ticks) and thresholds; see the module docstring."""

    window: int = 25
    stuck_tol: float = 1e-6
    noise_ratio: float = 8.0
    noise_floor: float = 0.02
    max_dead: int = 4
    ridge: float = 1e-4

    def __post_init__(self) -> None:
        check_fields(self)
        check_int("window", self.window, lo=2, hi=MAX_WINDOW)
        for name in ("stuck_tol", "noise_ratio", "noise_floor", "ridge"):
            v = getattr(self, name)
            if v < 0:
                raise ValueError(f"{name} must be finite and >= 0, got {v}")
        check_int("max_dead", self.max_dead, lo=0)


class SensorGuard:
    """Detect dead or noise-only sensors and impute them from the live ones (see module doc).

    ``fit(U)`` learns the mean and covariance of clean readings; ``flags(U)`` and
    ``clean(U)`` work on a whole recording (causally, so row ``t`` depends on rows ``≤ t``
    only); ``step(u)`` does the same online, one reading per tick.
    """

    def __init__(self, params: SensorGuardParams | None = None) -> None:
        self.params = SensorGuardParams() if params is None else params
        if not isinstance(self.params, SensorGuardParams):
            raise TypeError(f"params must be SensorGuardParams, got {type(params).__name__}")

    def fit(self, U: np.ndarray) -> SensorGuard:
        U = self._check(U, fitted=False)
        if U.shape[0] < 2:
            raise ValueError("SensorGuard.fit needs at least 2 readings")
        if U.shape[1] < 1:
            raise ValueError("SensorGuard.fit needs at least 1 sensor, got U of shape "
                             f"{U.shape}")
        self.mean_ = U.mean(axis=0)
        C = np.cov(U, rowvar=False).reshape(U.shape[1], U.shape[1])
        self.cov_ = C + self.params.ridge * np.eye(U.shape[1])
        self.n_sensors_ = U.shape[1]
        self._cache: dict[tuple[int, ...], np.ndarray] = {}
        self.reset()
        return self

    def _check(self, U: np.ndarray, fitted: bool = True) -> np.ndarray:
        U = check_finite("sensor matrix U", U)
        if U.ndim != 2:
            raise ValueError(f"sensor matrix U must be (T, n_sensors), got shape {U.shape}")
        if fitted:
            if not hasattr(self, "mean_"):
                raise RuntimeError("SensorGuard is not fitted yet; call fit(U) first")
            if U.shape[1] != self.n_sensors_:
                raise ValueError(f"U has {U.shape[1]} sensors, the guard was fitted on "
                                 f"{self.n_sensors_}")
        return U

    # ------------------------------------------------------------------ detection
    def _flag_rows(self, rng_: np.ndarray, energy: np.ndarray, full: np.ndarray) -> np.ndarray:
        """Flags (T, n) from windowed ranges and change energies; ``full`` marks rows whose
        window is complete (earlier rows are never flagged)."""
        p = self.params
        stuck = rng_ < p.stuck_tol
        med = np.median(energy, axis=1, keepdims=True)
        noisy = (energy > p.noise_ratio * med) & (energy > p.noise_floor)
        score = np.where(stuck | noisy, 1.0 + energy, 0.0)
        flags = (stuck | noisy) & full[:, None]
        over = flags.sum(axis=1) > p.max_dead
        if over.any():
            order = np.argsort(-score[over], axis=1, kind="stable")
            keep = np.zeros_like(flags[over])
            np.put_along_axis(keep, order[:, :p.max_dead], True, axis=1)
            flags[over] &= keep
        return flags

    def flags(self, U: np.ndarray) -> np.ndarray:
        """(T, n) bool: sensor flagged dead at tick ``t`` (from readings ``t-window+1 .. t``)."""
        U = self._check(U)
        W = int(self.params.window)
        T, n = U.shape
        if T < W:
            return np.zeros((T, n), bool)
        win = np.lib.stride_tricks.sliding_window_view(U, W, axis=0)     # (T-W+1, n, W)
        rng_ = np.zeros((T, n))
        energy = np.zeros((T, n))
        rng_[W - 1:] = win.max(axis=2) - win.min(axis=2)
        energy[W - 1:] = np.mean(np.diff(win, axis=2) ** 2, axis=2)
        full = np.arange(T) >= W - 1
        rng_[~full] = np.inf
        return self._flag_rows(rng_, energy, full)

    # ------------------------------------------------------------------ imputation
    def _gain(self, dead: tuple[int, ...]) -> np.ndarray:
        """Σ_DA Σ_AA⁻¹ for the dead set ``dead`` (cached)."""
        if dead not in self._cache:
            D = list(dead)
            A = [i for i in range(self.n_sensors_) if i not in dead]
            S = self.cov_
            if A:
                self._cache[dead] = np.linalg.solve(S[np.ix_(A, A)], S[np.ix_(A, D)]).T
            else:
                self._cache[dead] = np.zeros((len(D), 0))
        return self._cache[dead]

    def impute(self, U: np.ndarray, flags: np.ndarray) -> np.ndarray:
        """Replace the flagged readings by their conditional mean given the live ones."""
        U = self._check(U)
        flags = np.asarray(flags, bool)
        if flags.shape != U.shape:
            raise ValueError(f"flags must have shape {U.shape}, got {flags.shape}")
        out = U.copy()
        rows = np.flatnonzero(flags.any(axis=1))
        if rows.size == 0:
            return out
        patterns, inverse = np.unique(flags[rows], axis=0, return_inverse=True)
        for k, pat in enumerate(patterns):
            r = rows[inverse.ravel() == k]
            D = tuple(np.flatnonzero(pat).tolist())
            A = [i for i in range(self.n_sensors_) if i not in D]
            est = self.mean_[list(D)] + (U[np.ix_(r, A)] - self.mean_[A]) @ self._gain(D).T
            out[np.ix_(r, list(D))] = np.clip(est, 0.0, 1.0)
        return out

    def clean(self, U: np.ndarray) -> np.ndarray:
        """Detect and impute over a whole recording (causal: as :meth:`step` would)."""
        U = self._check(U)
        return self.impute(U, self.flags(U))

    # ------------------------------------------------------------------ online
    def reset(self) -> None:
        """Forget the reading history (start of a run)."""
        self._hist: list[np.ndarray] = []

    def step(self, u: np.ndarray) -> np.ndarray:
        """One reading in, the guarded reading out (same as ``clean`` row by row)."""
        u = check_finite("reading", u)
        if not hasattr(self, "mean_"):
            raise RuntimeError("SensorGuard is not fitted yet; call fit(U) first")
        if u.shape != (self.n_sensors_,):
            raise ValueError(f"reading must have shape ({self.n_sensors_},), got {u.shape}")
        W = int(self.params.window)
        self._hist.append(u.copy())
        if len(self._hist) > W:
            self._hist.pop(0)
        if len(self._hist) < W:
            return u.copy()
        H = np.array(self._hist)
        rng_ = (H.max(axis=0) - H.min(axis=0))[None, :]
        energy = np.mean(np.diff(H, axis=0) ** 2, axis=0)[None, :]
        f = self._flag_rows(rng_, energy, np.ones(1, bool))
        return self.impute(u[None, :], f)[0]
