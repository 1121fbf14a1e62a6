"""``--select`` of the place-cell scenarios: leak rates chosen from the recording alone.

Per seed, the 16 leak pairs of the two-rooms sweep are harvested over one reservoir and scored
by a label-free criterion on the training part only (:func:`~hippo.perception.selection.
select_leak`: fitted on its first 80 %, scored on the held-out 20 %). The chosen pair is then
fitted and evaluated like any other setting. For analysis only, every candidate is also fitted
on the whole training part and scored with labels on the test part, so the criterion's rank
correlation with the labelled accuracy is reported next to the choice."""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from hippo.perception import ICAConvergenceWarning
from hippo.perception.place_cell_params import RCSFAICAParams
from hippo.perception.selection import (
    CRITERIA,
    DEFAULT_CRITERION,
    rank_correlation,
    select_leak,
)
from hippo.scenarios._common import mean_sd

SLOW = (0.03, 0.05, 0.08, 0.11)     # leak of the first half of the neurons
FAST = (0.14, 0.15, 0.2, 0.3)       # leak of the second half
CANDIDATES = [(a, b) for a in SLOW for b in FAST]
#: held-out seeds are compared with the fixed settings in groups of this many
GROUP = 5

__all__ = ["CANDIDATES", "CRITERIA", "DEFAULT_CRITERION", "select_setting", "selection_summary"]


def select_setting(U: np.ndarray, n_train: int, base: RCSFAICAParams,
                   labelled: Callable[[np.ndarray], float], criterion: str = DEFAULT_CRITERION,
                   paper: tuple[float, float] = (0.05, 0.15), paper_units: int | None = None,
                   units: Sequence[int] | None = None) -> dict[str, Any]:
    """Choose a leak pair (and, with ``units``, a number of SFA/ICA units among them) for the
    recording ``U`` from its first ``n_train`` ticks alone; then (analysis) score every
    candidate fitted on those ticks with ``labelled(Y)``, ``Y`` the candidate's outputs over
    all of ``U`` (``paper``'s score, with ``paper_units`` units, default ``base``'s, is kept
    beside the chosen one's when it is a candidate: both fitted the same way)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        sel = select_leak(U, CANDIDATES, base, criterion=criterion, n_rows=n_train,
                          units=units)
        X = sel.features.X
        acc = [labelled(sel.refit(c, n_train).readout(X[c % len(CANDIDATES)]))
               for c in range(len(sel.candidates))]
    sel.features = None     # frees the harvested features
    # no candidate scored (the test part never left one room): no best by labels
    i = int(np.nanargmax(acc)) if np.isfinite(acc).any() else sel.best
    ks = sel.units or [base.n_ica] * len(acc)
    try:
        k_paper = base.n_ica if paper_units is None else paper_units
        p = ks.index(k_paper) + CANDIDATES.index(tuple(paper))   # its block, then its pair
        paper_acc = acc[p]
    except ValueError:       # the paper's pair or units are not among the candidates
        paper_acc = float("nan")
    return {"criterion": criterion, "chosen": list(sel.best_candidate),
            "chosen_units": int(ks[sel.best]),
            "candidates": [[*map(float, c), int(k)] for c, k in zip(sel.candidates, ks)],
            "scores": sel.scores.tolist(), "labelled_accuracy": acc,
            "spearman": rank_correlation(sel.scores, acc),
            "chosen_accuracy_in_sweep": acc[sel.best],
            "paper_accuracy_in_sweep": paper_acc,
            "best_by_labels": list(sel.candidates[i]), "best_units_by_labels": int(ks[i]),
            "best_accuracy_in_sweep": acc[i]}


def selection_summary(rows: list[dict[str, Any]], seeds: list[int],
                      picked: list[float] | None = None, paper: list[float] | None = None
                      ) -> dict[str, Any]:
    """Rank correlation over seeds and the picked setting's labelled accuracy next to the
    fixed paper setting's, overall and per group of ``GROUP`` seeds: from the scenario's own
    fits when given, else from the candidates' fits (``*_accuracy_in_sweep``)."""
    if picked is None or paper is None:
        picked = [r["chosen_accuracy_in_sweep"] for r in rows]
        paper = [r["paper_accuracy_in_sweep"] for r in rows]
    rho = [r["spearman"] for r in rows]
    diff = np.asarray(picked, float) - np.asarray(paper, float)
    groups = []
    for g in range(0, len(seeds), GROUP):
        sl = slice(g, g + GROUP)
        groups.append({"seeds": seeds[sl], "picked": float(np.nanmean(picked[sl])),
                       "paper": float(np.nanmean(paper[sl])),
                       "picked_minus_paper": float(np.nanmean(diff[sl]))})
    return {
        "criterion": rows[0]["criterion"], "candidates": [list(c) for c in CANDIDATES],
        "seeds": seeds, "chosen": [r["chosen"] for r in rows],
        "chosen_units": [r.get("chosen_units") for r in rows],
        "spearman_per_seed": rho, "spearman_mean": mean_sd(rho)[0],
        "spearman_sd": mean_sd(rho)[1],
        "picked_accuracy": list(picked), "paper_accuracy": list(paper),
        "picked_mean": mean_sd(list(picked))[0], "paper_mean": mean_sd(list(paper))[0],
        "picked_minus_paper_worst_seed": float(np.nanmin(diff)),
        "groups": groups,
        # the worst scored group, whatever the order (a group with no scored seed is nan)
        "picked_minus_paper_worst_group": min(
            (g["picked_minus_paper"] for g in groups if not math.isnan(g["picked_minus_paper"])),
            default=math.nan),
        "oracle_accuracy_mean": mean_sd([r["best_accuracy_in_sweep"] for r in rows])[0],
        "runs": rows,
    }
