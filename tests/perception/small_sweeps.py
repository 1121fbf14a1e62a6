"""Shared inputs of the leak sweep's and the label-free selection's rules tests: a small
float64 model, a smooth random walk read by ``n`` sinusoidal sensors, and ICA's convergence
warning silenced (one restart on a few hundred ticks need not converge)."""

from __future__ import annotations

import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np

from hippo.perception.ica import ICAConvergenceWarning

SMALL: dict[str, Any] = dict(n_inputs=3, n_reservoir=6, n_sfa=2, n_ica=2, ica_restarts=1,
                             min_fit_ticks=10, dtype="float64")


def walk(T: int = 300, n: int = 3, seed: int = 3) -> np.ndarray:
    """``T`` readings of ``n`` sensors in [0.1, 0.9] along a smooth random walk."""
    rng = np.random.default_rng(seed)
    pos = np.cumsum(rng.standard_normal(T)) * 0.05
    return 0.5 + 0.4 * np.sin(pos[:, None] * np.arange(1, n + 1) + np.arange(n))


@contextmanager
def quiet() -> Iterator[None]:
    """ICA's convergence warning silenced."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        yield
