"""The reservoir's hyper-parameters (:class:`ReservoirParams`, with the SMC09 and ICANN09
presets) and the leak specification they hold: one rate for every neuron, one per contiguous
group, or one per neuron (:func:`expand_leak` turns any of them into the per-neuron vector).

The reservoir itself is :class:`hippo.perception.reservoir.Reservoir`.
"""

from __future__ import annotations

import numbers
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from hippo._checks import check_fields, check_finite, check_int, check_positive, check_range

__all__ = ["LeakSpec", "ReservoirParams", "expand_leak"]

LeakSpec = float | Sequence[float] | np.ndarray


@dataclass(frozen=True)
class ReservoirParams:
    """Reservoir hyper-parameters; defaults are SMC09's (e-puck, two rooms)."""

    n_inputs: int = 8
    n_neurons: int = 600
    spectral_radius: float = 0.99
    #: one float (all neurons), k floats (k equal contiguous groups), or a length-N vector
    leak: float | tuple[float, ...] = (0.05, 0.15)
    #: magnitude w of the ternary input weights (±w)
    input_weight: float = 2.0
    #: probability of +w, and separately of -w (so 2p of the weights are non-zero)
    input_prob: float = 0.075
    seed: int = 0

    def __post_init__(self) -> None:
        object.__setattr__(self, "leak", _leak_param(self.leak))
        check_fields(self)
        check_int("ReservoirParams.n_inputs", self.n_inputs, lo=1)
        check_int("ReservoirParams.n_neurons", self.n_neurons, lo=1)
        check_positive("spectral_radius", self.spectral_radius)
        check_positive("input_weight", self.input_weight, allow_zero=True)
        check_range("input_prob", self.input_prob, 0.0, 0.5)
        expand_leak(self.leak, int(self.n_neurons))  # validates

    @classmethod
    def smc09(cls, **overrides: Any) -> ReservoirParams:
        """SMC09: 8 IR inputs, 600 neurons, leaks 0.05/0.15 (halves), ρ(W)=0.99, W_in ±2 p=0.075."""
        return cls(**{**dict(n_inputs=8, n_neurons=600, spectral_radius=0.99, leak=(0.05, 0.15),
                             input_weight=2.0, input_prob=0.075), **overrides})

    @classmethod
    def icann09(cls, **overrides: Any) -> ReservoirParams:
        """ICANN09: 17 inputs, 400 neurons, leak 0.6, ρ(W)=0.9, W_in ±0.2 with p=0.15."""
        return cls(**{**dict(n_inputs=17, n_neurons=400, spectral_radius=0.9, leak=0.6,
                             input_weight=0.2, input_prob=0.15), **overrides})


def _leak_param(leak: Any) -> Any:
    """A leak given as a list or a 1-D array becomes a tuple of floats (hashable, frozen)."""
    if isinstance(leak, list | np.ndarray) and np.ndim(leak) == 1:
        return tuple(float(v) if isinstance(v, numbers.Real) and not isinstance(v, bool)
                     else v for v in leak)
    return leak


def expand_leak(leak: LeakSpec, n_neurons: int) -> np.ndarray:
    """Per-neuron leak vector (float64, length ``n_neurons``) from a leak specification.

    A scalar applies to every neuron; ``k`` values split the neurons into ``k`` contiguous groups
    of (nearly) equal size (SMC09's "0.05 for half of the reservoir and 0.15 for the other half"
    is ``(0.05, 0.15)``); a vector of length ``n_neurons`` is used as is. Every rate must lie in
    (0, 1].
    """
    arr = np.atleast_1d(check_finite("leak", leak))
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f"leak must be a number or a 1-D sequence, got shape {arr.shape}")
    if np.any(arr <= 0) or np.any(arr > 1):
        raise ValueError(f"leak rates must lie in (0, 1], got {arr.min():g}..{arr.max():g}")
    if arr.size == n_neurons:
        return arr.copy()
    if arr.size > n_neurons:
        raise ValueError(f"leak has {arr.size} values but the reservoir has {n_neurons} neurons")
    groups = np.array_split(np.arange(n_neurons), arr.size)
    out = np.empty(n_neurons)
    for value, idx in zip(arr, groups):
        out[idx] = value
    return out
