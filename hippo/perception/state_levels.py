"""Each state's activity on the state layer's common scale [0, 1] (HIREL sec. II).

The competition of :class:`~hippo.perception.states.StateLayer` compares activities on one
scale; :class:`StateLevels` computes them:

* a **place** unit's activity ``a_i`` is standardised (``normalize``: ``"pooled"``, by the
  running mean and variance of the whole place population, time constant ``norm_tau``, prior
  mean 0 and variance 1; ``"unit"``, by each unit's own; ``"fixed"``, not at all), squashed
  as ``tanh(max(z_i, 0) / place_scale)`` and low-pass filtered with time constant
  ``smoothing`` (a leaky state neuron); the vector may grow between ticks (new place cells);
* an **event state** (sound, floor colour, still, moving) is 1 while its input is on, and a
  transient one only for ``transient_time`` after its onset.

It is a part of :class:`~hippo.perception.states.StateLayer` (which inherits it), and works on
that class's state: its parameters, its place states and their running statistics, the
winner, the time and the onsets of the event states.
"""

from __future__ import annotations

import math

import numpy as np

from hippo._checks import check_finite

__all__ = ["PLACE_MAX", "StateLevels"]

#: the largest place activity magnitude accepted. Every place source gives far less (template
#: and ground-truth cells and prototypes lie in [0, 1], ICA units have unit variance on their
#: training data, the timing demo adds noise of sd <= 10); one outlier beyond it would ruin the
#: pooled running statistics for good (the winner would never change again).
PLACE_MAX = 1e3


def _refuse_outlier(a: np.ndarray) -> None:
    """``ValueError`` naming the largest place activity beyond ``PLACE_MAX`` (if any)."""
    big = float(np.abs(a).max()) if a.size else 0.0
    if big > PLACE_MAX:
        raise ValueError(f"place activities must lie in [-{PLACE_MAX:g}, {PLACE_MAX:g}], got "
                         f"one of magnitude {big:.3g} (unit {int(np.abs(a).argmax())}): no "
                         "place source gives it, and it would ruin the running statistics")


class StateLevels:
    """The activities of :class:`~hippo.perception.states.StateLayer`'s states on the common
    scale (see the module docstring); it reads and updates that class's state."""

    def _places(self, place: object, dt: float) -> np.ndarray:
        p = self.params
        if place is None:
            a = np.zeros(0)
        elif (p.normalize == "pooled" and type(place) is np.ndarray and place.ndim == 1
              and place.dtype == np.float64 and 0 < place.size == self._place_ids.size):
            a = place  # checked by the pooled mean's sum below: a NaN or inf makes it so
        else:
            a = check_finite("place activities", place)
            if a.ndim != 1:
                raise ValueError(f"place activities must be a 1-D vector, got shape {a.shape}")
            if p.normalize == "unit" or (p.normalize == "pooled"
                                         and a.size != self._place_ids.size):
                _refuse_outlier(a)   # the pooled branch below bounds the rest for less; raw
                # ("fixed") activities keep no statistics an outlier could ruin
        if a.size < self._place_ids.size:
            raise ValueError(f"place activity vector shrank from {self._place_ids.size} to "
                             f"{a.size} units; place states are never removed")
        if a.size > self._place_ids.size:
            self._add_places(a.size - self._place_ids.size)
        rate = min(dt / p.norm_tau, 1.0)
        if p.normalize == "unit":
            z = (a - self._mean) / np.sqrt(self._var)
            d = a - self._mean
            self._mean = self._mean + rate * d
            self._var = np.maximum((1.0 - rate) * (self._var + rate * d * d), 1e-12)
        elif p.normalize == "pooled" and a.size:
            mean, var = self._pool
            d = a - mean
            total = float(np.add.reduce(d))
            if not math.isfinite(total):  # names a NaN or inf (finite values that overflow pass)
                check_finite("place activities", a)
            sq = float(np.add.reduce(d * d))
            # |a_i| <= |d_i| + |mean| <= sqrt(sq) + |mean|: the exact check only past that bound
            if not math.sqrt(sq) + abs(mean) <= PLACE_MAX:
                _refuse_outlier(a)
            z = d / math.sqrt(var)
            # the means as np.mean takes them (sum / count), without its wrapper
            m = mean + rate * (total / d.size)
            v = max((1.0 - rate) * (var + rate * (sq / d.size)), 1e-12)
            self._pool = (m, v)
        else:
            z = a
        target = np.tanh(np.maximum(z, 0.0) / p.place_scale)
        if p.smoothing > 0 and self.winner is not None:
            k = math.exp(-dt / p.smoothing)
            target = k * self.place_activity + (1.0 - k) * target
        return target

    def _event_level(self, sid: int, sound: bool, colour: int | None,
                     moving: bool | None) -> float:
        k = self._keys[sid]
        if k.kind == "sound":
            on = sound
        elif k.kind == "colour":
            on = colour == k.index
        elif k.kind == "still":
            on = moving is False
        else:
            on = moving is True
        if on and k.kind in self.params.transient:
            on = self.t - self._onset_t.get(sid, -math.inf) < self.params.transient_time - 1e-9
        return 1.0 if on else 0.0
