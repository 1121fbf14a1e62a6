"""Non-occurrence detection: a predicted event did not come (HIREL sec. II and Fig. 6b).

Public API
----------
- :class:`NonOccurrenceParams` — ``min_peak``, ``rel_tolerance``, ``abs_tolerance``,
  ``fall_fraction``.
- :class:`NonOccurrence` — ``step(predictions, dt) -> list[key]`` (keys whose non-occurrence
  neuron fired at this tick); ``active`` (keys signalling now, latched until their prediction
  ends); ``peak`` (peak prediction since each key's prediction started); ``reset()``.

``predictions`` maps a key (any hashable; transitions use ``(a, b)``) to either

* a :class:`~hippo.timing.transition_params.TransitionReadout` — **timed rule**: fire when the
  transition is predicted (``strength >= min_peak``) and the population readout of the elapsed
  time passes the learned delay by a tolerance, ``elapsed_fraction >= 1 + max(rel_tolerance,
  abs_tolerance / learned_delay)``; or
* a plain number, the prediction level — **HIREL's rule**: fire when the prediction has peaked
  above ``min_peak`` and fallen back below ``fall_fraction`` of its peak.

A key's trace starts when it appears in ``predictions`` and ends when it disappears from them
(its source state lost the competition: the event came, or another one did), so an event that
comes on time silences the detector. Example (extinction trial)::

    for key in nonocc.step(cells.step(battery, dt), dt):
        drives.inhibit(drive_of[key])    # the reward predicted by `key` did not come
"""

from __future__ import annotations

import math
from collections.abc import Hashable, Mapping
from dataclasses import dataclass

import numpy as np

from hippo._checks import check_fields, check_positive, check_range

__all__ = ["NonOccurrence", "NonOccurrenceParams"]


@dataclass(frozen=True)
class NonOccurrenceParams:
    """Parameters of the non-occurrence neurons.

    min_peak: a prediction counts only if its peak (or, timed, its strength) reaches this
        (default 0.2).
    rel_tolerance, abs_tolerance: timed rule; the event may be late by
        ``max(rel_tolerance * T, abs_tolerance)`` before the neuron fires (defaults 0.05 and
        0.6 s: three ticks, so an event that comes on time, give or take tick jitter, never
        fires it, while a missed 7 s reward is signalled 0.6 s after the delay).
    fall_fraction: HIREL's rule; fire when the prediction falls below this fraction of its
        peak (default 0.5).
    """

    min_peak: float = 0.2
    rel_tolerance: float = 0.05
    abs_tolerance: float = 0.6
    fall_fraction: float = 0.5

    def __post_init__(self) -> None:
        check_fields(self)
        check_positive("min_peak", self.min_peak)
        check_positive("rel_tolerance", self.rel_tolerance, allow_zero=True)
        check_positive("abs_tolerance", self.abs_tolerance, allow_zero=True)
        check_range("fall_fraction", self.fall_fraction, 0.0, 1.0, closed="neither")


def _finite(key: Hashable, value: object) -> float:
    """A prediction as a float, or ``ValueError`` naming its key (one scalar check per key).
    A number only: a string such as ``"0.5"`` or a bool, which ``float`` would take, is none."""
    try:
        if isinstance(value, str | bytes | bool | np.bool_):
            raise TypeError
        x = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ValueError(f"prediction of {key!r} must be a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"prediction of {key!r} is non-finite (NaN or inf): {x!r}")
    return x


class NonOccurrence:
    r"""Non-occurrence neurons, one per predicted event, firing when the event is overdue.

    HIREL: "the system also detects when a predicted drive satisfaction does not occur and
    consequently inhibits the corresponding drive"; the neurons fire when the prediction
    :math:`X` "has peaked and falls back" without the event:
    :math:`N = [\max_{s\le t} X(s) \ge \theta_{peak}] \wedge [X(t) < f\,\max_{s\le t} X(s)]`.
    Because the prediction falls back only well after the learned delay (HIREL's robot
    restarted up to 32 % late), transitions use the timed rule instead: the neuron compares
    the population readout of the elapsed time with the delay stored in the transition's
    synapses, :math:`N = [\hat\tau / \hat T \ge 1 + \max(r, a/\hat T)]`, which fires a fixed,
    small tolerance after the learned delay. Either way the neuron fires once and its signal
    stays on (``active``) until the prediction ends.
    """

    def __init__(self, params: NonOccurrenceParams | None = None) -> None:
        self.params = params or NonOccurrenceParams()
        self.reset()

    def reset(self) -> None:
        """Forget every trace and signal."""
        self.peak: dict[Hashable, float] = {}
        self._active: set[Hashable] = set()
        self.fired: list[Hashable] = []

    @property
    def active(self) -> frozenset[Hashable]:
        """Keys whose non-occurrence signal is on (from firing until their prediction ends)."""
        return frozenset(self._active)

    def step(self, predictions: Mapping[Hashable, object], dt: float) -> list[Hashable]:
        """One tick; returns the keys whose neuron fired now (also in ``self.fired``)."""
        check_positive("dt", dt)
        if type(predictions) is not dict and not isinstance(predictions, Mapping):
            raise ValueError(f"predictions must be a mapping key -> prediction, got "
                             f"{type(predictions).__name__}")
        p = self.params
        if not self.peak.keys() <= predictions.keys():  # (most ticks: no trace ended)
            for gone in [k for k in self.peak if k not in predictions]:
                del self.peak[gone]
                self._active.discard(gone)
        fired = []
        peaks, active = self.peak, self._active
        for key, value in predictions.items():
            timed = hasattr(value, "elapsed_fraction")
            x = value.prediction if timed else value  # type: ignore[union-attr]
            if type(x) is not float or not math.isfinite(x):  # (a float: checked in place)
                x = _finite(key, x)
            peak = max(peaks.get(key, -math.inf), x)
            peaks[key] = peak
            if key in active:
                continue
            if timed:
                t_hat = float(value.learned_delay)  # type: ignore[union-attr]
                frac = float(value.elapsed_fraction)  # type: ignore[union-attr]
                strong = float(value.strength) >= p.min_peak  # type: ignore[union-attr]
                overdue = (strong and t_hat > 0 and not math.isnan(frac)
                           and frac >= 1.0 + max(p.rel_tolerance, p.abs_tolerance / t_hat))
            else:
                overdue = peak >= p.min_peak and x < p.fall_fraction * peak
            if overdue:
                self._active.add(key)
                fired.append(key)
        self.fired = fired
        return fired
