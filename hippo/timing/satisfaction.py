"""Satisfaction prediction: which transitions lead to a satisfying state (HIREL eq. 4-5).

Public API
----------
- :class:`SatisfactionParams` — ``alpha``, ``gamma``, ``theta``.
- :class:`Satisfaction` — ``step(transitions, satisfaction, dt) -> X^P`` (one prediction per
  drive); ``predict(transitions)``; ``weights`` (drives x transitions); ``keys`` (the
  transition keys, in column order); ``reset(keep_weights=False)``.

``transitions`` maps a transition key ``(a, b)`` to its activity ``X^T`` (e.g. 1 for the
transition just performed, or the transition cells' predictions); a key seen for the first time
gets a column of zero weights. ``satisfaction`` is ``X^S``, one value per drive (1 at a reward).
Example::

    sat = Satisfaction(n_drives=1)
    xp = sat.step({(still, sound): 1.0}, satisfaction=[1.0], dt=0.2)
"""

from __future__ import annotations

from collections.abc import Hashable, Mapping
from dataclasses import dataclass

import numpy as np

from hippo._checks import check_fields, check_finite, check_positive

__all__ = ["Satisfaction", "SatisfactionParams"]


@dataclass(frozen=True)
class SatisfactionParams:
    """Parameters of HIREL eq. 4-5 (the paper gives no values; these are hippo's).

    alpha: learning rate, 1/s (default 2.5: a transition active during one 0.2 s tick of
        satisfaction reaches half weight).
    gamma: decay rate, 1/s, paid while the transition is active (default 0.02: a transition
        that stops satisfying loses its weight over ~50 s of activity).
    theta: threshold subtracted from the prediction (default 0.2).
    """

    alpha: float = 2.5
    gamma: float = 0.02
    theta: float = 0.2

    def __post_init__(self) -> None:
        check_fields(self)
        check_positive("alpha", self.alpha)
        check_positive("gamma", self.gamma, allow_zero=True)
        check_positive("theta", self.theta, allow_zero=True)


class Satisfaction:
    r"""Transition-to-satisfaction association (Hirel et al., eq. 4-5).

    .. math:: \frac{dW^{TP}_{ij}}{dt} = \alpha\,(1 - W^{TP}_{ij})\,X^T_j\,X^S_i
              - \gamma\,X^T_j, \qquad
              X^P_i = \sum_k W^{TP}_{ik}\,X^T_k - \theta

    :math:`i` indexes drives (satisfaction signals), :math:`j` transitions. A transition
    active when drive :math:`i` is satisfied gains weight toward 1; an active transition
    without satisfaction loses weight at rate :math:`\gamma`. Weights are kept at or above 0
    (an inhibitory weight would mean "prevents satisfaction", which the model does not
    represent). :math:`X^P` uses the weights before the Euler step; it is returned as the
    equation gives it (negative when nothing is predicted).
    """

    def __init__(self, n_drives: int, params: SatisfactionParams | None = None) -> None:
        if int(n_drives) != n_drives or n_drives < 1:
            raise ValueError(f"n_drives must be an integer >= 1, got {n_drives!r}")
        self.n_drives = int(n_drives)
        self.params = params or SatisfactionParams()
        self.reset()

    def reset(self, *, keep_weights: bool = False) -> None:
        """Zero the prediction (and, unless ``keep_weights``, forget every association)."""
        if not keep_weights or not hasattr(self, "weights"):
            self.weights = np.zeros((self.n_drives, 0))
            self.keys: list[Hashable] = []
            self._col: dict[Hashable, int] = {}
        self.prediction = np.full(self.n_drives, -self.params.theta)

    def _activity(self, transitions: Mapping[Hashable, float], recruit: bool) -> np.ndarray:
        if not isinstance(transitions, Mapping):
            raise ValueError(f"transitions must be a mapping key -> activity, got "
                             f"{type(transitions).__name__}")
        if recruit:
            new = [k for k in transitions if k not in self._col]
            for k in new:
                self._col[k] = len(self.keys)
                self.keys.append(k)
            if new:
                self.weights = np.hstack([self.weights, np.zeros((self.n_drives, len(new)))])
        x = np.zeros(len(self.keys))
        for k, v in transitions.items():
            if k in self._col:
                x[self._col[k]] = float(check_finite(f"activity of transition {k!r}", v))
        return x

    def predict(self, transitions: Mapping[Hashable, float]) -> np.ndarray:
        """Eq. 5 without learning: ``X^P = W^TP X^T - theta`` (unknown keys contribute 0)."""
        return self.weights @ self._activity(transitions, recruit=False) - self.params.theta

    def step(self, transitions: Mapping[Hashable, float], satisfaction: np.ndarray,
             dt: float) -> np.ndarray:
        """One tick: eq. 5 with the current weights, then an Euler step of eq. 4."""
        dt = check_positive("dt", dt)
        xs = check_finite("satisfaction", satisfaction).reshape(-1)
        if xs.shape != (self.n_drives,):
            raise ValueError(f"satisfaction must have {self.n_drives} value(s), got {xs.size}")
        xt = self._activity(transitions, recruit=True)
        p = self.params
        self.prediction = self.weights @ xt - p.theta
        dw = p.alpha * (1.0 - self.weights) * xt[None, :] * xs[:, None] - p.gamma * xt[None, :]
        self.weights = np.maximum(self.weights + dt * dw, 0.0)
        return self.prediction.copy()
