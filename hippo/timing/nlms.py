"""The NLMS learning rule of HIREL eq. 1-3, as reusable functions and a small layer.

Public API
----------
- :class:`NLMSParams` — ``alpha``, ``sigma1``, ``sigma2``, ``gamma`` (paper) and ``leak`` (hippo).
- :func:`sliding_mean` (eq. 3), :func:`learning_modulation` (eq. 2), :func:`nlms_update` (eq. 1,
  one Euler step) — used by :class:`hippo.timing.transitions.TransitionCells` on the rows that
  are active at a tick.
- :class:`NLMS` — a fixed-size layer ``X = W X^CS`` learning ``X -> X^US``:
  ``step(cs, us, dt) -> prediction``; ``predict(cs)``; ``reset()``.

Example::

    layer = NLMS(n_out=2, n_in=5)
    x = layer.step(cs=np.ones(5), us=np.array([1.0, 0.0]), dt=0.2)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hippo._checks import check_fields, check_finite, check_positive, check_range

__all__ = ["NLMS", "NLMSParams", "learning_modulation", "nlms_update", "sliding_mean"]


@dataclass(frozen=True)
class NLMSParams:
    """Parameters of the NLMS rule (HIREL gives no values; these are hippo's, for dt = 0.2 s).

    alpha: learning rate, 1/s (default 10: at an event ``eta = gamma = 0.5`` so one Euler step
        of 0.2 s has step size ``alpha*dt*eta = 1``, the one-shot NLMS step).
    sigma1: added to ``sum(X_CS**2)`` so that weights do not diverge for a silent CS
        (default 1e-6, far below a battery's squared norm ~2.5).
    sigma2: minimal learning modulation (default 0: a minimal learning rate keeps pushing the
        rising edge of every prediction down, and in closed loop, where the robot's own
        reproductions are learned again, that shifts the learned delay later at every loop,
        by ~0.2 % per loop at 60 s with sigma2 = 0.002. Set > 0 for the paper's exact rule).
    gamma: weight of the past in the sliding mean of the US (eq. 3, per step; default 0.5, a
        mean over ~2 ticks, so that ``eta`` is large only at the onset of a US).
    leak: hippo's addition, default 0.25 (0 gives HIREL eq. 1 exactly): weight decay gated by
        the US and by ``eta``, ``- lambda X^US_i W_ij`` inside eq. 1. When the predicted state
        arrives its synapses compete: the pattern of the current delay is renewed while the
        trace of an older delay fades, so a changed delay is re-learned in one or two trials in
        both directions (a shorter delay never replays the old one, so the error term alone
        would never erase it). The learned prediction then peaks at ``1/(1+leak)``.
    """

    alpha: float = 10.0
    sigma1: float = 1e-6
    sigma2: float = 0.0
    gamma: float = 0.5
    leak: float = 0.25

    def __post_init__(self) -> None:
        check_fields(self)
        check_positive("alpha", self.alpha)
        check_positive("sigma1", self.sigma1)
        check_positive("sigma2", self.sigma2, allow_zero=True)
        check_range("gamma", self.gamma, 0.0, 1.0, closed="left")
        check_positive("leak", self.leak, allow_zero=True)


def sliding_mean(m_prev: np.ndarray, us: np.ndarray, gamma: float) -> np.ndarray:
    """HIREL eq. 3: ``m^US(t) = gamma m^US(t-dt) + (1 - gamma) X^US(t)``."""
    return gamma * m_prev + (1.0 - gamma) * us


def learning_modulation(us: np.ndarray | float, m_us: np.ndarray | float,
                        sigma2: float) -> np.ndarray | float:
    """HIREL eq. 2: ``eta = |X^US - m^US| + sigma2`` (``m^US`` already updated with ``X^US(t)``);
    on arrays or on plain floats."""
    return abs(us - m_us) + sigma2


def nlms_update(w: np.ndarray, cs: np.ndarray, us: np.ndarray, eta: np.ndarray,
                params: NLMSParams, dt: float) -> tuple[np.ndarray, np.ndarray]:
    r"""One Euler step of HIREL eq. 1 (plus hippo's US-gated leak); returns ``(W_new, X)``.

    .. math:: \frac{dW_{ij}}{dt} = \alpha\,\eta_i\left[\frac{(X^{US}_i - X_i)\,X^{CS}_j}
              {\sum_k (X^{CS}_k)^2 + \sigma_1} - \lambda\,X^{US}_i W_{ij}\right],
              \qquad X_i = \sum_j W_{ij} X^{CS}_j

    ``w`` is ``(n_out, n_in)``, ``cs`` ``(n_in,)``, ``us`` and ``eta`` ``(n_out,)``. ``X`` is the
    prediction computed with the weights before the step. Without a US on any row (the
    transition cells between events) the leak term is 0 and is not computed: the same numbers
    (subtracting a zero changes no weight).
    """
    x = w @ cs
    norm = float(cs @ cs) + params.sigma1
    err = (us - x)[:, None] * cs / norm  # the outer product
    if np.count_nonzero(us):  # (any US; ndarray.any costs ~5 x as much on a few rows)
        err = err - params.leak * us[:, None] * w
    dw = params.alpha * eta[:, None] * err
    return w + dt * dw, x


class NLMS:
    r"""A layer of ``n_out`` cells learning to predict a US from a CS (HIREL eq. 1-3).

    .. math:: X_i = \sum_j W_{ij} X^{CS}_j, \quad
              \frac{dW_{ij}}{dt} = \alpha\,\eta_i\,\frac{(X^{US}_i - X_i)\,X^{CS}_j}
              {\sum_k (X^{CS}_k)^2 + \sigma_1}\ (-\ \alpha\,\eta_i\,\lambda X^{US}_i W_{ij}),

    :math:`\eta_i = |X^{US}_i - m^{US}_i| + \sigma_2`,
    :math:`m^{US}_i(t) = \gamma\,m^{US}_i(t-dt) + (1-\gamma)\,X^{US}_i(t)`
    (Hirel, Gaussier, Quoy & Banquet, eq. 1-3; the leak term is hippo's, off with ``leak=0``).
    """

    def __init__(self, n_out: int, n_in: int, params: NLMSParams | None = None) -> None:
        if int(n_out) != n_out or n_out < 1 or int(n_in) != n_in or n_in < 1:
            raise ValueError(f"n_out and n_in must be integers >= 1, got {n_out!r}, {n_in!r}")
        self.params = NLMSParams() if params is None else params
        if not isinstance(self.params, NLMSParams):
            raise TypeError(f"params must be NLMSParams, got {self.params!r}")
        self.n_out, self.n_in = int(n_out), int(n_in)
        self.reset()

    def reset(self) -> None:
        """Zero weights and sliding means (the layer as constructed)."""
        self.weights = np.zeros((self.n_out, self.n_in))
        self.m_us = np.zeros(self.n_out)
        self.eta = np.zeros(self.n_out)

    def predict(self, cs: np.ndarray) -> np.ndarray:
        """``X = W X^CS`` without learning."""
        cs = check_finite("cs", cs)
        if cs.shape != (self.n_in,):
            raise ValueError(f"cs must have shape ({self.n_in},), got {cs.shape}")
        return self.weights @ cs

    def step(self, cs: np.ndarray, us: np.ndarray, dt: float) -> np.ndarray:
        """One tick: eq. 3, eq. 2, then an Euler step of eq. 1. Returns ``X`` before the step.

        ``ValueError`` when the Euler step is unstable, ``alpha*dt*(gamma + sigma2) >= 2`` (the
        bound on ``alpha*dt*eta`` for a US in [0, 1]; the weights would diverge), as
        :class:`hippo.timing.transitions.TransitionCells` refuses it.
        """
        cs = check_finite("cs", cs)
        us = check_finite("us", us)
        dt = check_positive("dt", dt)
        p = self.params
        if p.alpha * dt * (p.gamma + p.sigma2) >= 2.0:
            raise ValueError(f"NLMS step alpha*dt*eta = {p.alpha * dt * (p.gamma + p.sigma2):.3g}"
                             " >= 2 is unstable; lower params.alpha or dt")
        if cs.shape != (self.n_in,):
            raise ValueError(f"cs must have shape ({self.n_in},), got {cs.shape}")
        if us.shape != (self.n_out,):
            raise ValueError(f"us must have shape ({self.n_out},), got {us.shape}")
        self.m_us = sliding_mean(self.m_us, us, p.gamma)
        self.eta = learning_modulation(us, self.m_us, p.sigma2)
        self.weights, x = nlms_update(self.weights, cs, us, self.eta, p, dt)
        return x
