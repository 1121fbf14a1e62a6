"""Choosing RC-SFA-ICA settings from the recording alone (no labels).

SMC09: "there is no automated way yet" to choose the leak rates. Each candidate setting is
fitted on the first part of the recording (80 % by default) and scored on the held-out block
that follows, without labels (lower is better):

* ``"slowness"``: SFA's own objective where the model did not learn, the mean over the slow
  features of ``Δ_val(y_i) = < (y_i(t+1) - y_i(t))² >_val / var_val(y_i)``;
* ``"prediction"``: how badly a ridge map from the slow features predicts the next input;
* ``"stability"``: ``1 -`` the mean absolute correlation of matched slow features (Hungarian) of two
  SFA fits on the two halves of the fitting part, on the held-out block;
* ``"slow-stable"`` (the default): held-out slowness times instability.

A setting that found slow structure of the *world* finds the same features in either half of
the run and keeps them slow on new data. Slowness alone prefers the slowest reservoir, whose
features are slow whatever they code; stability alone prefers a reservoir with little memory,
whose features are stable instantaneous functions of the sensors; the product asks for both.

Status (measured with ``benchmarks/selection_criteria.py``; 16 leak pairs 0.03-0.11 x
0.14-0.3; labelled accuracy: the room cell's test balanced accuracy, in flats the mean over
rooms). TUNING two-rooms seeds 0-2, Spearman with the labels per seed: slowness
+0.06/-0.37/-0.74, next-input prediction -0.06/+0.38/+0.74, stability +0.35/+0.67/+0.52; on
tuning flat 0 the signs turned (slowness +0.89, stability -0.80). Slow-stable was chosen:
+0.32/+0.06/-0.17, flat +0.84; its pick minus SMC09's 0.05/0.15: +0.009/+0.012/+0.001/-0.012.
HELD-OUT two-rooms seeds 100-104: Spearman +0.16/-0.82/-0.71/-0.46/-0.60, pick minus SMC09
+0.007/-0.017/-0.009/-0.010/-0.051 (group -0.016: target missed); held-out flats 100-101:
Spearman +0.96/+0.23, pick minus SMC09 +0.014/-0.034 (group -0.010). The criterion does not
rank settings reliably in two rooms; no candidate ranked both worlds the same way.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.optimize import linear_sum_assignment
from scipy.stats import spearmanr

from hippo._checks import check_finite
from hippo.perception.leak_sweep import SweepFeatures, sweep_features
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


def prediction_error(Y: np.ndarray, U: np.ndarray, n_fit: int, n_end: int | None = None, *,
                     horizon: int = 1, ridge: float = 1e-3) -> float:
    """How badly the slow features predict the input ``horizon`` ticks later, on held-out rows.

    A ridge map ``[y(t); 1] -> u(t + h)`` is fitted on rows ``< n_fit`` and scored on rows
    ``n_fit … n_end - h``: the mean over inputs of the residual variance over the input's
    variance (1 = no better than its mean; lower is better)."""
    Y = check_finite("Y", Y)
    U = check_finite("U", U)
    n_end = len(U) if n_end is None else n_end
    if Y.shape[0] != U.shape[0] or not 0 < n_fit < n_end - horizon - 2 or n_end > len(U):
        raise ValueError(f"n_fit ({n_fit}) and n_end ({n_end}) must leave a held-out block of "
                         f"Y {Y.shape} and U {U.shape} for horizon {horizon}")
    Z = np.column_stack([Y, np.ones(len(Y))])
    Zf, Tf = Z[:n_fit - horizon], U[horizon:n_fit]
    W = np.linalg.solve(Zf.T @ Zf + ridge * len(Zf) * np.eye(Z.shape[1]), Zf.T @ Tf)
    Zv, Tv = Z[n_fit:n_end - horizon], U[n_fit + horizon:n_end]
    var = Tv.var(axis=0)
    ok = var > 1e-12
    return float(np.mean(np.mean((Zv @ W - Tv) ** 2, axis=0)[ok] / var[ok]))


def instability(Ya: np.ndarray, Yb: np.ndarray) -> float:
    """``1 - `` the mean absolute correlation of matched units (Hungarian matching) between two
    fits' outputs ``Ya``, ``Yb`` (T, k) on the same held-out rows: 0 when two fits on different
    data (bootstrap halves, restarts) find the same units, near 1 when they share nothing."""
    Ya, Yb = check_finite("Ya", Ya), check_finite("Yb", Yb)
    if Ya.shape != Yb.shape or Ya.ndim != 2 or Ya.shape[0] < 3:
        raise ValueError(f"Ya and Yb must be (T >= 3, k) of one shape, got {Ya.shape}, "
                         f"{Yb.shape}")
    k = Ya.shape[1]
    C = np.nan_to_num(np.abs(np.corrcoef(Ya.T, Yb.T)[:k, k:]))
    r, c = linear_sum_assignment(-C)
    return float(1.0 - C[r, c].mean())


@dataclass
class Selection:
    """Result of :func:`select_leak`: the candidates, their scores (lower is better), the
    index of the best, the models fitted on the fitting part (empty for ``"stability"``), the
    harvested ``features`` and the number of fitting rows (see :meth:`refit`)."""

    candidates: list[Any]
    scores: np.ndarray
    best: int
    models: list[RCSFAICA]
    features: SweepFeatures | None = None
    criterion: str = "slow-stable"
    n_fit: int = 0

    def refit(self, b: int, n_rows: int) -> RCSFAICA:
        """Configuration ``b`` fitted on the first ``n_rows`` rows of ``features`` (at least
        the fitting rows; their SFA moments are reused)."""
        F = self.features
        if F is None or not self.n_fit <= n_rows <= len(F.X[b]):
            raise ValueError(f"n_rows must lie in [{self.n_fit}, rows of the sweep], got {n_rows}")
        h = self.n_fit // 2
        mom = F.moments(b, 0, h).merged(F.moments(b, h, self.n_fit))
        if n_rows > self.n_fit:
            mom = mom.merged(F.moments(b, self.n_fit, n_rows))
        return F.fit(b, 0, n_rows, mom)

    @property
    def best_candidate(self) -> Any:
        return self.candidates[self.best]


def select_leak(U: np.ndarray, leaks: Sequence[Any], params: RCSFAICAParams | None = None, *,
                criterion: str = "slow-stable", val_fraction: float = 0.2,
                n_rows: int | None = None,
                **overrides: Any) -> Selection:
    """Harvest ``U`` under every leak configuration over one reservoir
    (:func:`sweep_features`), fit each on the first ``1 - val_fraction`` of the first
    ``n_rows`` rows (default: all of ``U``) and pick the best by ``criterion`` on the held-out
    rest (:func:`score_sweep`). No labels are used, and rows from ``n_rows`` on are never read
    (they may be a test part: the harvested features are kept for it in ``features``)."""
    U = check_finite("sensor sequence U", U)
    F = sweep_features(U, leaks, params, **overrides)
    n = len(F.X[0]) if n_rows is None else int(n_rows)
    scores, models = score_sweep(F, n, criterion, val_fraction=val_fraction)
    n_fit = round(n * (1 - val_fraction))
    return Selection(list(leaks), scores, int(np.argmin(scores)), models, F, criterion, n_fit)


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


#: the label-free criteria :func:`score_sweep` knows (all "lower is better")
CRITERIA = ("slowness", "prediction", "stability", "slow-stable")


def score_sweep(F: SweepFeatures, n_rows: int, criterion: str = "slow-stable", *,
                val_fraction: float = 0.2, horizon: int = 1,
                ) -> tuple[np.ndarray, list[RCSFAICA]]:
    """Score every configuration of a harvested sweep ``F`` from its first ``n_rows`` rows
    alone (rows from ``n_rows`` on are never read: they may be a test part). Each
    configuration is fitted on the first ``1 - val_fraction`` of those rows and scored on the
    rest: ``"slowness"`` (:func:`normalised_slowness` of the SFA outputs), ``"prediction"``
    (:func:`prediction_error` of the input ``horizon`` ticks on), or ``"stability"``
    (:func:`instability` of the slow features of two SFA fits on the two halves of the
    fitting rows, matched unit to unit), or ``"slow-stable"`` (the product of the two:
    held-out slowness times instability: each alone fails one way, slowness prefers the
    slowest reservoir, stability one with almost no memory; the product still prefers a
    reservoir much slower than the world, e.g. leak 0.01 or 0.002 over 0.05 on a source
    switching every 300 ticks). Returns the scores (lower is better) and the models
    fitted on the fitting rows (none for ``"stability"`` and ``"slow-stable"``, which need SFA
    alone)."""
    if criterion not in CRITERIA:
        raise ValueError(f"criterion must be one of {CRITERIA}, got {criterion!r}")
    if not 0.05 <= val_fraction <= 0.5:
        raise ValueError(f"val_fraction must lie in [0.05, 0.5], got {val_fraction}")
    n_rows = int(n_rows)
    n_fit = round(n_rows * (1 - val_fraction))
    if not 20 <= n_fit < n_rows - horizon - 2 or n_rows > len(F.X[0]):
        raise ValueError(f"n_rows ({n_rows}) must leave fitting and held-out rows in the "
                         f"{len(F.X[0])} rows of the sweep")
    scores, models = [], []
    val = slice(n_fit, n_rows)
    n_u = F.base.n_inputs
    for b in range(len(F.leaks)):
        h = n_fit // 2
        A, B = F.moments(b, 0, h), F.moments(b, h, n_fit)
        if criterion in ("stability", "slow-stable"):    # SFA alone: no ICA
            Xv = F.X[b][val]
            s = instability(F.fit_sfa(b, 0, h, A).transform(Xv),
                            F.fit_sfa(b, h, n_fit, B).transform(Xv))
            if criterion == "slow-stable":
                Yv = F.fit_sfa(b, 0, n_fit, A.merged(B)).transform(Xv)
                s *= float(np.mean(normalised_slowness(Yv)))
            scores.append(s)
            continue
        m = F.fit(b, 0, n_fit, A.merged(B))
        Ysfa = m._readout(F.X[b][:n_rows], return_sfa=True)[1]
        if criterion == "slowness":
            scores.append(float(np.mean(normalised_slowness(Ysfa[val]))))
        else:
            scores.append(prediction_error(Ysfa, F.X[b][:n_rows, :n_u], n_fit, horizon=horizon))
        models.append(m)
    return np.array(scores), models
