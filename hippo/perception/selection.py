"""Choosing RC-SFA-ICA settings from the recording alone (no labels): held-out slowness.

SMC09: "there is no automated way yet" to choose the leak rates. The criterion here is SFA's
own objective measured where the model did not learn: the recording is cut in time, the model
is fitted on the first part, and each slow feature's normalised slowness is measured on the
held-out block that follows::

    Δ_val(y_i) = < (y_i(t+1) - y_i(t))² >_val / var_val(y_i)

A setting that found slow structure of the *world* keeps its features slow on new data; one
that fitted slow accidents of the training run (a wall followed for a long time, a stretch in
one room) does not. The score is the mean of ``Δ_val`` over the slow features (lower is
better); dividing by the held-out variance keeps a feature that goes flat on new data from
looking slow.

Status: the criterion is built and unit-tested; how well it ranks settings against labelled
place-cell accuracy must be measured per arena (``rank_correlation``), see the README row.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.stats import spearmanr

from hippo._checks import check_finite
from hippo.perception.leak_sweep import fit_leak_sweep
from hippo.perception.place_cells import RCSFAICA, RCSFAICAParams


def normalised_slowness(Y: np.ndarray) -> np.ndarray:
    """``<ẏ²> / var(y)`` of each column of ``Y`` (T, k), with ``ẏ`` the one-tick difference.

    For ``y = sin(2πt/P)`` this is ``2 (1 - cos(2π/P)) ≈ (2π/P)²``; for white noise, 2."""
    Y = check_finite("Y", Y)
    if Y.ndim != 2 or Y.shape[0] < 3:
        raise ValueError(f"Y must be (T >= 3, k), got shape {Y.shape}")
    var = Y.var(axis=0)
    d = np.mean(np.diff(Y, axis=0) ** 2, axis=0)
    return np.where(var > 1e-12, d / np.maximum(var, 1e-12), np.inf)


def heldout_slowness(model: RCSFAICA, U: np.ndarray, n_fit: int) -> float:
    """Mean normalised slowness of ``model``'s SFA outputs on ``U[n_fit:]`` (the model was
    fitted on ``U[:n_fit]``; the reservoir runs through the whole of ``U`` so the held-out block
    starts from the state the fit ended in)."""
    if not 0 < n_fit < len(U) - 2:
        raise ValueError(f"n_fit must leave a held-out block, got {n_fit} of {len(U)} ticks")
    _, Ysfa = model.transform(U, return_sfa=True)
    return float(np.mean(normalised_slowness(Ysfa[n_fit:])))


@dataclass
class Selection:
    """Result of :func:`select_leak`: the candidates, their scores (lower is better), the
    index of the best, and the models fitted on the fitting part."""

    candidates: list[Any]
    scores: np.ndarray
    best: int
    models: list[RCSFAICA]

    @property
    def best_candidate(self) -> Any:
        return self.candidates[self.best]


def select_leak(U: np.ndarray, leaks: Sequence[Any], params: RCSFAICAParams | None = None, *,
                val_fraction: float = 0.2, **overrides: Any) -> Selection:
    """Fit one model per leak configuration on the first ``1 - val_fraction`` of ``U`` (one
    reservoir, :func:`fit_leak_sweep`) and pick the one whose slow features stay slowest on
    the held-out rest (:func:`heldout_slowness`). No labels are used."""
    if not 0.05 <= val_fraction <= 0.5:
        raise ValueError(f"val_fraction must lie in [0.05, 0.5], got {val_fraction}")
    U = check_finite("sensor sequence U", U)
    n_fit = round(len(U) * (1 - val_fraction))
    models = fit_leak_sweep(U[:n_fit], leaks, params, **overrides)
    scores = np.array([heldout_slowness(m, U, n_fit) for m in models])
    return Selection(list(leaks), scores, int(np.argmin(scores)), models)


def rank_correlation(criterion: Sequence[float], accuracy: Sequence[float]) -> float:
    """Spearman correlation between a criterion where *lower is better* and a labelled
    accuracy: +1 means the criterion ranks the settings exactly as the labels do."""
    c = np.asarray(criterion, float)
    a = np.asarray(accuracy, float)
    if c.shape != a.shape or c.ndim != 1 or c.size < 3:
        raise ValueError("criterion and accuracy must be 1-D of the same length >= 3")
    ok = np.isfinite(c) & np.isfinite(a)
    if ok.sum() < 3:
        return float("nan")
    return float(spearmanr(-c[ok], a[ok]).statistic)
