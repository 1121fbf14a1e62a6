"""``--select`` (:mod:`hippo.scenarios._selection`) on a stand-in leak selection: the 16
candidate pairs, what select_leak is given, the labelled score of every candidate from its
refit on the training ticks and the features of its own leak pair, the best by labels, the
paper's pair found in its unit block, the dict field by field; and the summary over seeds
(means, differences and groups of five computed by hand)."""

from __future__ import annotations

import math
import warnings
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

import hippo.scenarios._selection as S
from hippo.perception import ICAConvergenceWarning

N = 16


def test_the_candidates_are_the_slow_times_fast_pairs_slow_outermost():
    assert S.SLOW == (0.03, 0.05, 0.08, 0.11) and S.FAST == (0.14, 0.15, 0.2, 0.3)
    assert len(S.CANDIDATES) == N
    assert S.CANDIDATES[:5] == [(0.03, 0.14), (0.03, 0.15), (0.03, 0.2), (0.03, 0.3),
                                (0.05, 0.14)]
    assert S.CANDIDATES[-1] == (0.11, 0.3)
    assert S.CANDIDATES.index((0.05, 0.15)) == 5          # the paper's pair
    assert S.GROUP == 5
    assert S.__all__ == ["CANDIDATES", "CRITERIA", "DEFAULT_CRITERION", "select_setting",
                         "selection_summary"]


class _Model:
    def __init__(self, c: int, n: int) -> None:
        self.c, self.n = c, n

    def readout(self, X: np.ndarray) -> tuple[int, int, Any]:
        return (self.c, self.n, X)


class _Sel:
    """A stand-in Selection: candidate c's features are X[c % 16]; refit records its calls."""

    def __init__(self, units: list[int], best: int, scores: list[float]) -> None:
        n = N * (len(units) or 1)
        self.candidates = list(S.CANDIDATES) * (len(units) or 1)
        self.units = [k for k in units for _ in range(N)]
        self.best, self.scores = best, np.asarray(scores, float)
        self.features = SimpleNamespace(X=[f"X{b}" for b in range(N)])
        self.refits: list[tuple[int, int]] = []
        assert len(self.scores) == n

    @property
    def best_candidate(self) -> Any:
        return self.candidates[self.best]

    def refit(self, c: int, n_rows: int) -> _Model:
        self.refits.append((c, n_rows))
        return _Model(c, n_rows)


def _scores(n: int, best: int) -> list[float]:
    """n distinct scores, the lowest (best) at ``best``."""
    return [-1.0 if c == best else float(c) for c in range(n)]


def _run(monkeypatch: pytest.MonkeyPatch, sel: _Sel, accuracy: Any, **kwargs: Any
         ) -> tuple[dict[str, Any], dict[str, Any], list[Any]]:
    calls: dict[str, Any] = {}
    seen: list[Any] = []

    def select_leak(U: Any, leaks: Any, base: Any, **kw: Any) -> _Sel:
        calls.update(U=U, leaks=leaks, base=base, **kw)
        warnings.warn("did not converge", ICAConvergenceWarning, stacklevel=1)
        return sel

    def labelled(Y: Any) -> float:
        seen.append(Y)
        return accuracy(Y[0])

    monkeypatch.setattr(S, "select_leak", select_leak)
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # the ICA warning is silenced inside
        out = S.select_setting("U", 1200, SimpleNamespace(n_ica=4), labelled, **kwargs)
    return out, calls, seen


def test_every_candidate_is_refitted_and_scored_on_its_own_features(monkeypatch):
    scores = [float(c) for c in range(N)]                   # candidate 0 scores best (lowest)
    sel = _Sel([], best=0, scores=scores)
    acc = [0.5 + 0.01 * c for c in range(N)]                # labels prefer the last one
    out, calls, seen = _run(monkeypatch, sel, lambda c: acc[c], criterion="bimodality")
    assert calls == {"U": "U", "leaks": S.CANDIDATES, "base": SimpleNamespace(n_ica=4),
                     "criterion": "bimodality", "n_rows": 1200, "units": None}
    assert sel.refits == [(c, 1200) for c in range(N)]
    assert seen == [(c, 1200, f"X{c}") for c in range(N)]
    assert sel.features is None                             # freed
    # the criterion ranks exactly against the labels: Spearman of -score with acc is -1
    assert out == {
        "criterion": "bimodality", "chosen": [0.03, 0.14], "chosen_units": 4,
        "candidates": [[a, b, 4] for a, b in S.CANDIDATES], "scores": scores,
        "labelled_accuracy": acc, "spearman": pytest.approx(-1.0, abs=1e-12),
        "chosen_accuracy_in_sweep": 0.5, "paper_accuracy_in_sweep": 0.55,
        "best_by_labels": [0.11, 0.3], "best_units_by_labels": 4,
        "best_accuracy_in_sweep": acc[15]}
    assert type(out["chosen_units"]) is int and all(type(v) is float
                                                    for v in out["candidates"][3][:2])


def test_the_paper_pair_is_found_in_its_unit_block(monkeypatch):
    # units 2 then 4: candidate c is pair c % 16 with units[c // 16]
    scores = _scores(2 * N, 22)                             # best: (0.05, 0.2) with 4 units
    sel = _Sel([2, 4], best=22, scores=scores)
    acc = [0.6] * (2 * N)
    acc[5], acc[N + 5], acc[30] = 0.7, 0.8, 0.9             # (0.05, 0.15) with 2, with 4
    out, calls, seen = _run(monkeypatch, sel, lambda c: acc[c], units=(2, 4))
    assert calls["units"] == (2, 4) and calls["criterion"] == S.DEFAULT_CRITERION
    assert [y[2] for y in seen] == [f"X{c % N}" for c in range(2 * N)]
    assert out["chosen"] == [0.05, 0.2] and out["chosen_units"] == 4
    assert out["candidates"][N + 5] == [0.05, 0.15, 4] and out["candidates"][5][2] == 2
    assert out["paper_accuracy_in_sweep"] == 0.8            # base.n_ica 4: the second block
    assert out["chosen_accuracy_in_sweep"] == 0.6 and sel.scores[22] == -1.0
    assert out["best_by_labels"] == [0.11, 0.2] and out["best_units_by_labels"] == 4
    assert out["best_accuracy_in_sweep"] == 0.9
    out, _, _ = _run(monkeypatch, _Sel([2, 4], 22, scores), lambda c: acc[c], units=(2, 4),
                     paper_units=2)
    assert out["paper_accuracy_in_sweep"] == 0.7
    out, _, _ = _run(monkeypatch, _Sel([2, 4], 22, scores), lambda c: acc[c], units=(2, 4),
                     paper=(0.08, 0.3), paper_units=2)
    assert out["paper_accuracy_in_sweep"] == acc[11]        # (0.08, 0.3) is pair 11


def test_only_the_ica_convergence_warning_is_silenced(monkeypatch):
    sel = _Sel([], 0, _scores(N, 0))

    def select_leak(*a: Any, **kw: Any) -> _Sel:
        warnings.warn("did not converge", ICAConvergenceWarning, stacklevel=1)
        warnings.warn("something else", RuntimeWarning, stacklevel=1)
        return sel

    monkeypatch.setattr(S, "select_leak", select_leak)
    with pytest.warns(RuntimeWarning, match="something else") as w:
        S.select_setting("U", 10, SimpleNamespace(n_ica=4), lambda Y: 0.5 + Y[0] / 100)
    assert [type(x.message) for x in w] == [RuntimeWarning]


def test_a_paper_setting_not_among_the_candidates_has_no_score(monkeypatch):
    acc = [0.5 + 0.01 * c for c in range(N)]
    for kwargs in ({"paper": (0.05, 0.16)}, {"paper_units": 3}):
        out, _, _ = _run(monkeypatch, _Sel([], 2, _scores(N, 2)), lambda c: acc[c], **kwargs)
        assert math.isnan(out["paper_accuracy_in_sweep"])
    out, _, _ = _run(monkeypatch, _Sel([2, 4], 2, _scores(2 * N, 2)), lambda c: c / 32,
                     units=(2, 4), paper_units=8)
    assert math.isnan(out["paper_accuracy_in_sweep"])


def test_without_any_labelled_score_the_best_by_labels_is_the_choice(monkeypatch):
    out, _, _ = _run(monkeypatch, _Sel([], 7, _scores(N, 7)), lambda c: math.nan)
    assert out["best_by_labels"] == list(S.CANDIDATES[7]) and out["chosen"] == out[
        "best_by_labels"]
    assert math.isnan(out["best_accuracy_in_sweep"]) and math.isnan(out["spearman"])
    # one scored candidate is the best by labels, the others unscored
    out, _, _ = _run(monkeypatch, _Sel([], 7, _scores(N, 7)),
                     lambda c: 0.3 if c == 9 else math.nan)
    assert out["best_by_labels"] == list(S.CANDIDATES[9]) and out["best_accuracy_in_sweep"] == 0.3


def _row(chosen: float, paper: float, rho: float, best: float, units: int | None = 4
         ) -> dict[str, Any]:
    r = {"criterion": "bimodal-stable", "chosen": [0.03, 0.14], "spearman": rho,
         "chosen_accuracy_in_sweep": chosen, "paper_accuracy_in_sweep": paper,
         "best_accuracy_in_sweep": best}
    if units is not None:
        r["chosen_units"] = units
    return r


def test_the_summary_over_seeds_by_hand():
    rows = [_row(0.9, 0.8, 0.5, 0.95), _row(0.7, 0.75, 0.1, 0.8, units=None),
            _row(0.8, 0.8, 0.3, 0.85), _row(0.6, 0.7, -0.1, 0.9), _row(1.0, 0.9, 0.2, 1.0),
            _row(0.5, 0.6, 0.0, 0.7), _row(0.7, 0.6, 0.4, 0.75)]
    seeds = [100, 101, 102, 103, 104, 105, 106]
    s = S.selection_summary(rows, seeds)
    picked = [0.9, 0.7, 0.8, 0.6, 1.0, 0.5, 0.7]
    paper = [0.8, 0.75, 0.8, 0.7, 0.9, 0.6, 0.6]
    diff = [a - b for a, b in zip(picked, paper)]
    assert s["criterion"] == "bimodal-stable"
    assert s["candidates"] == [list(c) for c in S.CANDIDATES] and s["seeds"] == seeds
    assert s["chosen"] == [[0.03, 0.14]] * 7
    assert s["chosen_units"] == [4, None, 4, 4, 4, 4, 4]
    rho = [0.5, 0.1, 0.3, -0.1, 0.2, 0.0, 0.4]
    assert s["spearman_per_seed"] == rho
    assert s["spearman_mean"] == pytest.approx(1.4 / 7, rel=1e-12)
    m = 0.2
    assert s["spearman_sd"] == pytest.approx(math.sqrt(sum((r - m) ** 2 for r in rho) / 6))
    assert s["picked_accuracy"] == picked and s["paper_accuracy"] == paper
    assert s["picked_mean"] == pytest.approx(5.2 / 7) and s["paper_mean"] == pytest.approx(
        5.15 / 7)
    assert s["picked_minus_paper_worst_seed"] == pytest.approx(-0.1)      # seeds 103, 105
    g1 = sum(diff[:5]) / 5                                                # 0.05 / 5
    g2 = sum(diff[5:]) / 2                                                # 0
    assert [g["seeds"] for g in s["groups"]] == [seeds[:5], seeds[5:]]
    assert s["groups"][0]["picked"] == pytest.approx(4.0 / 5)
    assert s["groups"][0]["paper"] == pytest.approx(3.95 / 5)
    assert s["groups"][0]["picked_minus_paper"] == pytest.approx(g1)
    assert s["groups"][1]["picked"] == pytest.approx(0.6)
    assert s["groups"][1]["paper"] == pytest.approx(0.6)
    assert s["groups"][1]["picked_minus_paper"] == pytest.approx(g2, abs=1e-15)
    assert s["picked_minus_paper_worst_group"] == pytest.approx(min(g1, g2), abs=1e-15)
    assert s["oracle_accuracy_mean"] == pytest.approx(5.95 / 7)
    assert s["runs"] is rows
    assert all(type(s[k]) is float for k in ("picked_minus_paper_worst_seed",
                                             "picked_minus_paper_worst_group"))


def test_the_scenarios_own_fits_replace_the_sweeps_and_nan_is_left_out():
    rows = [_row(0.0, 0.0, 0.5, 0.9), _row(0.0, 0.0, math.nan, 0.8)]
    rows[1]["criterion"] = "bimodality"          # the first run's criterion is reported
    s = S.selection_summary(rows, [3, 4], picked=[0.9, math.nan], paper=[0.7, 0.8])
    assert s["criterion"] == "bimodal-stable"
    assert s["picked_accuracy"][0] == 0.9 and math.isnan(s["picked_accuracy"][1])
    assert s["picked_mean"] == 0.9 and s["paper_mean"] == pytest.approx(0.75)
    assert s["spearman_mean"] == 0.5 and s["spearman_sd"] == 0.0
    assert s["picked_minus_paper_worst_seed"] == pytest.approx(0.2)
    assert s["groups"][0]["picked"] == 0.9 and s["groups"][0]["paper"] == pytest.approx(0.75)
    assert s["groups"][0]["picked_minus_paper"] == pytest.approx(0.2)
    # only one of picked and paper given: the sweep's accuracies are read for both
    s = S.selection_summary(rows, [3, 4], picked=[0.9, 0.9])
    assert s["picked_accuracy"] == [0.0, 0.0] and s["paper_accuracy"] == [0.0, 0.0]
    s = S.selection_summary(rows, [3, 4], paper=[0.9, 0.9])
    assert s["picked_accuracy"] == [0.0, 0.0] and s["paper_accuracy"] == [0.0, 0.0]


@pytest.mark.parametrize("unscored_first", [True, False])
def test_the_worst_group_is_the_worst_scored_one_in_any_order(unscored_first):
    # two groups of five: one with no scored seed (nan), one whose picked - paper is 0.1;
    # the worst group is 0.1 whichever comes first (Python's min gave nan or 0.1 by order)
    nan5, scored5 = [math.nan] * 5, [0.8] * 5
    picked = nan5 + scored5 if unscored_first else scored5 + nan5
    paper = [math.nan] * 5 + [0.7] * 5 if unscored_first else [0.7] * 5 + [math.nan] * 5
    rows = [_row(0.0, 0.0, 0.1, 0.9) for _ in range(10)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)   # nanmean of the all-nan group
        s = S.selection_summary(rows, list(range(10)), picked=picked, paper=paper)
    assert s["picked_minus_paper_worst_group"] == pytest.approx(0.1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        s = S.selection_summary(rows[:5], list(range(5)), picked=nan5, paper=nan5)
    assert math.isnan(s["picked_minus_paper_worst_group"])
