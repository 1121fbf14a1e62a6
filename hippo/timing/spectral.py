"""Spectral timing: one battery of time cells per state (HIREL, after Grossberg & Schmajuk).

Public API
----------
- :class:`SpectralParams` — battery size, range of centres, Weber fraction, readout threshold.
- :class:`SpectralTiming` — ``step(winner, dt) -> BatteryState``; ``reset()``;
  ``tuning(tau)`` (the battery at elapsed time ``tau``); ``battery(state)`` (zeros unless
  ``state`` is the current winner); ``readout(v)`` (population readout of a time, in seconds,
  from battery activity *or* from learned synaptic weights over the battery);
  ``elapsed_readout()`` (the readout of the current battery, remembered per elapsed time).
- :class:`BatteryState` — what one tick produced: current winner, its elapsed time and battery,
  and, at a sensory event, the previous state with its battery at the moment of the event
  (that battery is the conditioned stimulus the transition cells learn from).

Example::

    timing = SpectralTiming()
    bs = timing.step(winner=3, dt=0.2)      # bs.changed is True at a change of winner
    bs.activity                              # the winner's battery, shape (n_cells,)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from hippo._checks import check_fields, check_finite, check_positive, check_range
from hippo.types import check_state_id  # the one state-id rule (re-exported here)

__all__ = ["BatteryState", "SpectralParams", "SpectralTiming", "check_state_id"]


@dataclass(frozen=True)
class SpectralParams:
    """Parameters of the time-cell batteries.

    n_cells: cells per battery (default 128: log spacing of 0.05, half the Weber fraction,
        so neighbouring bumps overlap and the population readout is smooth).
    mu_min, mu_max: smallest and largest centre, seconds (default 0.2 s = one control tick, and
        120 s, twice the longest delay the tasks need so that 60 s sits inside the battery).
    weber: Weber fraction ``k``; cell ``j`` has width ``sigma_j = k * mu_j`` (default 0.1: the
        learned prediction's full width at half maximum is ~0.32 of its delay).
    min_width: floor on ``sigma_j``, seconds (default 0.1 s, half a tick, so that the short
        cells are still sampled by a 0.2 s control loop; Weber's law holds above 1 s).
    readout_fraction: a population readout uses the cells within the contiguous peak of the
        pattern that exceed this fraction of its maximum (default 0.5).
    """

    n_cells: int = 128
    mu_min: float = 0.2
    mu_max: float = 120.0
    weber: float = 0.1
    min_width: float = 0.1
    readout_fraction: float = 0.5

    def __post_init__(self) -> None:
        check_fields(self)
        if int(self.n_cells) != self.n_cells or self.n_cells < 4:
            raise ValueError(f"n_cells must be an integer >= 4, got {self.n_cells!r}")
        check_positive("mu_min", self.mu_min)
        check_positive("mu_max", self.mu_max)
        if not self.mu_max > self.mu_min:
            raise ValueError(f"mu_max ({self.mu_max}) must exceed mu_min ({self.mu_min})")
        check_positive("weber", self.weber)
        check_positive("min_width", self.min_width, allow_zero=True)
        check_range("readout_fraction", self.readout_fraction, 0.0, 1.0, closed="left")


@dataclass(frozen=True, eq=False, init=False)
class BatteryState:
    """The battery after one tick.

    state: the current winner; tau: seconds since it became the winner; activity: its battery.
    changed: a sensory event happened at this tick (the winner changed, or the first tick).
    previous, previous_tau, previous_activity: at an event, the state that lost, how long it had
    been the winner (the delay of the transition) and its battery at that moment; ``None`` / nan
    when there was no event or no previous state.
    """

    state: int
    tau: float
    activity: np.ndarray
    changed: bool
    previous: int | None = None
    previous_tau: float = math.nan
    previous_activity: np.ndarray | None = field(default=None, repr=False)

    def __init__(self, state: int, tau: float, activity: np.ndarray, changed: bool,
                 previous: int | None = None, previous_tau: float = math.nan,
                 previous_activity: np.ndarray | None = None) -> None:
        # one a tick: the fields written straight into the instance's dict (a frozen
        # dataclass's own __init__ calls object.__setattr__ once per field)
        d = self.__dict__
        d["state"], d["tau"], d["activity"], d["changed"] = state, tau, activity, changed
        d["previous"], d["previous_tau"], d["previous_activity"] = (
            previous, previous_tau, previous_activity)


_CALIBRATIONS: dict[SpectralParams, tuple[np.ndarray, np.ndarray]] = {}


def _calibration(timing: SpectralTiming) -> tuple[np.ndarray, np.ndarray]:
    """Readout code of the battery at 4096 log-spaced times (cached per parameter set)."""
    p = timing.params
    if p not in _CALIBRATIONS:
        grid = np.geomspace(p.mu_min, p.mu_max, 4096)
        codes = timing._codes(timing.tuning(grid))
        codes = np.maximum.accumulate(codes)
        keep = np.concatenate(([True], np.diff(codes) > 1e-12))
        _CALIBRATIONS[p] = (codes[keep], grid[keep])
    return _CALIBRATIONS[p]


class SpectralTiming:
    r"""A battery of ``m`` time cells per state; only the current winner's battery is active.

    Cell ``j`` of the winner's battery responds to the time :math:`\tau` since that state won:

    .. math:: X_j(\tau) = \exp\!\left(-\frac{(\tau-\mu_j)^2}{2\sigma_j^2}\right),\qquad
              \sigma_j = \max(k\,\mu_j,\ \sigma_{min}),

    centres :math:`\mu_j` log-spaced over ``[mu_min, mu_max]`` (HIREL sec. II, "spectral
    decomposition of time" [Grossberg & Schmajuk 1989]; the form is DESIGN.md's). Each change of
    winner restarts the battery at :math:`\tau = 0`.

    Why Gaussian bumps over :math:`\tau` rather than tuning to a decaying trace: with log-spaced
    centres and widths proportional to the centre, the pattern is scale invariant (the battery
    at :math:`c\tau` is the battery at :math:`\tau` shifted along the cell axis), its norm
    :math:`\sum_j X_j^2` is the same at every delay, and a one-shot NLMS association therefore
    peaks at the learned delay with a width proportional to it (Weber's law) — the properties
    recorded hippocampal time cells show (centres even on a log axis, widths growing linearly).

    Population readout (hippo's addition for precise timing): :meth:`readout` maps a pattern
    ``v`` over the cells to a time in seconds: the activity-weighted mean of :math:`\log\mu_j`
    over the contiguous peak of ``v`` above ``readout_fraction * max(v)``, calibrated once so
    that ``readout(tuning(tau)) == tau``. Applied to learned weights ``W ∝ X(T)`` it returns
    ``T`` exactly, whatever the bias of the raw mean, because both go through the same map.
    """

    def __init__(self, params: SpectralParams | None = None) -> None:
        self.params = params or SpectralParams()
        p = self.params
        self.mu = np.geomspace(p.mu_min, p.mu_max, int(p.n_cells))
        self.sigma = np.maximum(p.weber * self.mu, p.min_width)
        self._log_mu = np.log(self.mu)
        self._cell_index = np.arange(self.mu.size)
        self._elapsed_memo: dict[float, float] = {}
        self._battery_memo: dict[float, np.ndarray] = {}
        self._cal_code, self._cal_tau = _calibration(self)
        self.reset()

    @property
    def n_cells(self) -> int:
        """Cells per battery."""
        return int(self.mu.size)

    def reset(self) -> None:
        """No winner yet: every battery silent, the next ``step`` is a sensory event."""
        self.state: int | None = None
        self.tau = 0.0
        self.activity = np.zeros(self.n_cells)

    def tuning(self, tau: float | np.ndarray) -> np.ndarray:
        """Battery activity at elapsed time ``tau`` (shape ``(n_cells,)``, or ``(len(tau), n)``)."""
        t = check_finite("tau", tau)
        if np.any(t < 0):
            raise ValueError(f"tau must be >= 0 (time since the state won), got {tau!r}")
        return self._tuning(t)

    def _tuning(self, t: float | np.ndarray) -> np.ndarray:
        """:meth:`tuning` without the checks (``t`` is finite and >= 0: the inner loop's own)."""
        if not isinstance(t, float):  # an array of times: one row each
            t = np.asarray(t)[..., None]
        return np.exp(-0.5 * ((t - self.mu) / self.sigma) ** 2)

    def _battery_at(self, tau: float) -> np.ndarray:
        """:meth:`_tuning` of one elapsed time, remembered per ``tau`` as a read-only array: the
        battery clock repeats the same sums of ``dt`` after every event, so most ticks look
        the value up instead of computing it (the same numbers)."""
        got = self._battery_memo.get(tau)
        if got is None:
            if len(self._battery_memo) >= 4096:
                self._battery_memo.clear()
            got = self._battery_memo[tau] = self._tuning(tau)
            got.flags.writeable = False
        return got

    def step(self, winner: int, dt: float) -> BatteryState:
        """Advance by ``dt`` seconds with ``winner`` as the state; restart at a change of winner.

        Returns the :class:`BatteryState`; at an event it also carries the previous state's
        battery at the moment of the event, ``X(previous_tau)``.
        """
        winner = check_state_id("winner", winner)
        dt = check_positive("dt", dt)
        if self.state is None:  # first state ever: an event without a predecessor
            self.state, self.tau = winner, 0.0
            self.activity = self._battery_at(0.0)
            return BatteryState(winner, 0.0, self.activity, True)
        if winner == self.state:
            self.tau += dt
            self.activity = self._battery_at(self.tau)
            return BatteryState(winner, self.tau, self.activity, False)
        previous, previous_tau = self.state, self.tau + dt
        previous_activity = self._battery_at(previous_tau)
        self.state, self.tau = winner, 0.0
        self.activity = self._battery_at(0.0)
        return BatteryState(winner, 0.0, self.activity, True, previous, previous_tau,
                            previous_activity)

    def battery(self, state: int) -> np.ndarray:
        """The battery of ``state``: its activity if it is the winner, else zeros (any id >= 0:
        every state's battery is silent until it wins; which ids exist is the transition
        cells' record, not this one's)."""
        state = check_state_id("state", state)
        if state == self.state:
            return self.activity.copy()
        return np.zeros(self.n_cells)

    def _codes(self, v: np.ndarray) -> np.ndarray:
        r"""Readout code of each row of ``v`` (k, n_cells); nan for a silent row.

        For a row with peak cell :math:`i^*` and threshold :math:`\theta = f\,v_{i^*}`, the
        cells :math:`[lo, hi]` of the contiguous run around :math:`i^*` with :math:`v_j > \theta`
        give the code :math:`c = \sum_{j=lo}^{hi} (v_j - \theta)\log\mu_j /
        \sum_{j=lo}^{hi} (v_j - \theta)`. All rows at once: ``lo`` is one past the last cell
        at or below threshold left of the peak, ``hi`` one before the first such cell right of it.
        """
        v = np.atleast_2d(v)
        k, m = v.shape
        peak = v.argmax(axis=1)
        vmax = v[np.arange(k), peak]
        th = self.params.readout_fraction * vmax
        below = v <= th[:, None]
        j = self._cell_index
        left = below & (j < peak[:, None])
        right = below & (j > peak[:, None])
        # the last such cell left of the peak and the first right of it, by argmax over the
        # booleans (a row without one gets argmax 0, which no crossing gives: cell m - 1 is
        # never left of the peak, cell 0 never right of it)
        back = left[:, ::-1].argmax(axis=1)
        lo = np.where(back == 0, 0, m - back)
        first = right.argmax(axis=1)
        hi = np.where(first == 0, m, first) - 1
        w = np.where((j >= lo[:, None]) & (j <= hi[:, None]), v - th[:, None], 0.0)
        total = w.sum(axis=1)
        silent = ~(vmax > 0.0)
        total[silent] = 1.0
        code = (w @ self._log_mu) / total
        code[silent] = math.nan
        return code

    def _code(self, v: np.ndarray) -> float:
        """:meth:`_codes` of one row ``v`` (n_cells,), the same number by fewer array
        operations: the run around the peak is found by walking out from it (the per-tick
        form: most ticks re-read one transition)."""
        peak = int(v.argmax())
        vmax = v.item(peak)
        if not vmax > 0.0:
            return math.nan
        th = self.params.readout_fraction * vmax
        # the run around the peak: walk out from it to the first cell at or below threshold on
        # each side (plain float comparisons; the run is a few cells wide)
        at, n = v.item, v.size
        lo, hi = peak, peak + 1
        while lo > 0 and not at(lo - 1) <= th:
            lo -= 1
        while hi < n and not at(hi) <= th:
            hi += 1
        w = np.zeros(v.size)
        np.subtract(v[lo:hi], th, out=w[lo:hi])
        # the sums of _codes, over the whole row (its zeros too) and in its shapes
        return float((w[None] @ self._log_mu)[0] / np.add.reduce(w))

    def _readout(self, v: np.ndarray) -> float:
        """:meth:`readout` of one row ``v`` (n_cells,), unchecked: the inner loop's form."""
        return float(np.interp(self._code(v), self._cal_code, self._cal_tau))

    def _readouts(self, v: np.ndarray) -> np.ndarray:
        """:meth:`readout` of each row of ``v`` (k, n_cells), unchecked: the inner loop's form."""
        return np.interp(self._codes(v), self._cal_code, self._cal_tau)

    def elapsed_readout(self) -> float:
        """:meth:`readout` of the current battery: the winner's elapsed time as the cells tell it.

        The battery is ``tuning(tau)``, so its readout depends on ``tau`` alone; the values are
        remembered per ``tau`` (the battery clock repeats the same sums of ``dt`` after every
        event), which takes the readout out of the per-tick cost. nan when no state has won.
        """
        if self.state is None:
            return math.nan
        got = self._elapsed_memo.get(self.tau)
        if got is None:
            if len(self._elapsed_memo) >= 65536:
                self._elapsed_memo.clear()
            got = self._elapsed_memo[self.tau] = self._readout(self.activity)
        return got

    def readout(self, v: np.ndarray) -> float:
        """Population readout of a time (s) from a pattern over the cells; nan if ``v`` is silent.

        ``v`` may be a battery (the elapsed time) or learned weights from a battery (the delay
        they encode). Calibrated so that ``readout(tuning(tau)) == tau`` inside the battery's
        range; times beyond the range saturate at ``mu_min`` / ``mu_max``.
        """
        v = check_finite("pattern", v)
        if v.shape != (self.n_cells,):
            raise ValueError(f"pattern must have shape ({self.n_cells},), got {v.shape}")
        return self._readout(v)
