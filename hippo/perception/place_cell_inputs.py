"""The place-cell estimator's input policy: which sensor readings it takes (RCSFAICA).

Readings are expected in ``input_range`` (default ``(0, 1)``, the scale of
:class:`~hippo.sim.World`'s IR readings; ``None`` accepts any finite value). A recording to fit
on must lie in the range, have at least ``min_fit_ticks`` reservoir updates after the washout,
and have some sensor that varies (a stuck or disconnected set carries no information about
place). A fitted model meeting readings outside the range follows ``out_of_range``:
``"error"`` raises ``ValueError``, ``"warn"`` clips them and emits :class:`InputRangeWarning`,
``"clip"`` clips them silently; a reading is never extrapolated. NaN and inf are always
refused.

:class:`SensorInputs` holds these checks as a part of
:class:`~hippo.perception.place_cells.RCSFAICA` (which inherits it); it reads the estimator's
``params``.
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from hippo._checks import as_array, check_finite

__all__ = ["InputRangeWarning", "SensorInputs"]


class InputRangeWarning(RuntimeWarning):
    """Readings outside the model's ``input_range`` were clipped (``out_of_range='warn'``)."""


class SensorInputs:
    """The checks of :class:`~hippo.perception.place_cells.RCSFAICA`'s sensor readings (see the
    module docstring)."""

    def _check_U(self, U: Any, *, fitting: bool = False) -> np.ndarray:
        U = as_array("sensor sequence U", U)
        n = self.params.n_inputs
        if U.ndim != 2 or U.shape[1] != n:
            raise ValueError(f"sensor sequence U must have shape (T, {n}), got {U.shape}")
        if (not np.issubdtype(U.dtype, np.number) or np.issubdtype(U.dtype, np.complexfloating)
                or U.dtype.kind == "b"):
            raise ValueError(f"sensor sequence U must be real numbers, got dtype {U.dtype}")
        U = check_finite("sensor sequence U", U, keep_float32=True)
        rng = self.params.input_range
        if rng is not None and U.size and (U.min() < rng[0] or U.max() > rng[1]):
            msg = (f"sensor sequence U holds readings outside input_range [{rng[0]:g}, "
                   f"{rng[1]:g}] (min {U.min():g}, max {U.max():g})")
            if fitting:
                raise ValueError(msg + "; place cells are learned from sensor readings scaled to "
                                 "input_range: rescale U, or set input_range to its true range")
            U = self._out_of_range(U, msg, stacklevel=4)  # a warning names transform's caller
        return U

    def _out_of_range(self, u: np.ndarray, msg: str, stacklevel: int = 3) -> np.ndarray:
        """Apply the ``out_of_range`` policy to inputs outside ``input_range`` (a warning names
        the line ``stacklevel`` frames up: step's caller by default)."""
        policy = self.params.out_of_range
        if policy == "error":
            raise ValueError(msg + "; the model was fitted on readings in that range and would "
                             "extrapolate (set out_of_range='clip' or 'warn' to clip instead)")
        if policy == "warn":
            warnings.warn(msg + "; clipped to the range", InputRangeWarning,
                          stacklevel=stacklevel)
        lo, hi = self.params.input_range  # type: ignore[misc]
        return np.clip(u, lo, hi)

    def _check_trainable(self, U: np.ndarray) -> None:
        """Refuse recordings that cannot yield place cells: too short, or no sensor varies."""
        p = self.params
        # the decimator updates at ticks f - 1, 2 f - 1, ...: T // f of them (a partial last
        # block gives none)
        n_updates = U.shape[0] // p.downsample - p.washout
        if n_updates < p.min_fit_ticks:
            raise ValueError(
                f"U has {U.shape[0]} ticks ({n_updates} reservoir updates after a washout of "
                f"{p.washout} and down-sampling by {p.downsample}); fitting needs at least "
                f"min_fit_ticks={p.min_fit_ticks} updates of exploration")
        spread = U.max(axis=0) - U.min(axis=0)
        if not (spread > 1e-9).any():
            raise ValueError(
                f"every sensor in U is constant (values {np.unique(U[0]).tolist()[:4]}): stuck "
                "or disconnected sensors carry no information about place")
