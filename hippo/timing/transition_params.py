"""The transition cells' vocabulary: their parameters (:class:`TransitionParams`), one
transition's readout at one tick (:class:`TransitionReadout`) and the warning for a delay longer
than the battery can time (:class:`DelayRangeWarning`). The cells themselves are
:class:`hippo.timing.transitions.TransitionCells`, which re-exports these names."""

from __future__ import annotations

from dataclasses import dataclass, field

from hippo._checks import check_fields, check_positive
from hippo.timing.nlms import NLMSParams

__all__ = ["DelayRangeWarning", "TransitionParams", "TransitionReadout"]

Key = tuple[int, int]


class DelayRangeWarning(RuntimeWarning):
    """A transition took longer than the battery's longest time cell (``mu_max``): the delay
    learned from it saturates near ``mu_max`` (HIREL's batteries span a finite range)."""


@dataclass(frozen=True)
class TransitionParams:
    """Parameters of the transition cells.

    nlms: the learning rule (see :class:`NLMSParams`; defaults learn a pairing in one event).
    min_strength: a transition counts as predicted (``delay_over`` may fire) only if its
        prediction at the learned delay reaches this (default 0.2; a learned one peaks ~0.8).
    anticipation: seconds by which the delay-over flag anticipates the learned delay to land
        on the nearest tick (default 0.1 s, half of the 0.2 s control tick).
    latency: seconds between the tick at which the flag is read and the tick at which the
        resulting action shows in the senses (default 0.2 s: an agent acting on the flag at
        tick n is seen moving at tick n+1). The flag rises at ``T - anticipation - latency``
        so that the *observed* end of the wait, which is what is learned again, falls on the
        tick nearest ``T``; with a latency mis-set the closed loop drifts by the error each loop.
    """

    nlms: NLMSParams = field(default_factory=NLMSParams)
    min_strength: float = 0.2
    anticipation: float = 0.1
    latency: float = 0.2

    def __post_init__(self) -> None:
        check_fields(self)
        if not isinstance(self.nlms, NLMSParams):
            raise ValueError(f"nlms must be NLMSParams, got {type(self.nlms).__name__}")
        check_positive("min_strength", self.min_strength)
        check_positive("anticipation", self.anticipation, allow_zero=True)
        check_positive("latency", self.latency, allow_zero=True)


@dataclass(frozen=True, init=False)
class TransitionReadout:
    """One transition at one tick (only transitions out of the current winner are read out).

    prediction: ``X_ab = sum_j W_ab,j X^a_j(tau)``, the transition cell's activity.
    strength: the prediction the learned weights give at the learned delay.
    learned_delay: population readout of the delay stored in the weights, seconds.
    elapsed_fraction: readout of the elapsed time from the battery / learned delay.
    delay_over: the learned delay is over (see :mod:`hippo.timing.transitions`).
    """

    key: Key
    prediction: float
    strength: float
    learned_delay: float
    elapsed_fraction: float
    delay_over: bool

    def __init__(self, key: Key, prediction: float, strength: float, learned_delay: float,
                 elapsed_fraction: float, delay_over: bool) -> None:
        # several are built every tick: the fields written straight into the instance's dict
        # (a frozen dataclass's own __init__ calls object.__setattr__ once per field)
        d = self.__dict__
        d["key"], d["prediction"], d["strength"] = key, prediction, strength
        d["learned_delay"], d["elapsed_fraction"], d["delay_over"] = (
            learned_delay, elapsed_fraction, delay_over)
