"""The label-free selection's rules by hand (hippo.perception.selection): normalised slowness,
Otsu's separability and bimodality on small signals worked out by hand (two levels 1, four
even steps 0.8, the constant and near-constant edge at 1e-12 of the scale and past it), the
held-out prediction error of a ridge map with nothing to go on (the training targets' mean
shrunk by 1 + ridge), the instability of matched units (permuted, sign-flipped, orthogonal,
constant), Spearman against labels; score_sweep's and select_leak's split, each criterion
as the composition its docstring names, the unit counts, refit and with_units; every refusal
word for word on its edge and one step past."""

from __future__ import annotations

import re
import warnings
from typing import Any

import numpy as np
import pytest
from small_sweeps import SMALL, quiet, walk

from hippo.perception.leak_sweep import sweep_features
from hippo.perception.place_cell_params import RCSFAICAParams
from hippo.perception.place_cells import RCSFAICA
from hippo.perception.selection import (
    CRITERIA,
    DEFAULT_CRITERION,
    bimodality,
    heldout_slowness,
    instability,
    normalised_slowness,
    prediction_error,
    rank_correlation,
    score_sweep,
    select_leak,
    separability,
    with_units,
)
from hippo.perception.sfa_moments import SFAMoments


# ------------------------------------------------------------------------------ slowness
def test_normalised_slowness_by_hand():
    Y = np.array([[0.0, 1.0, 5.0], [1.0, 0.0, 5.0], [2.0, 1.0, 5.0], [3.0, 0.0, 5.0]])
    # column 0: diffs 1, 1, 1 -> 1; var of 0..3 = 1.25 -> 0.8
    # column 1: diffs 1 each -> 1; var 0.25 -> 4; column 2 constant -> inf
    np.testing.assert_allclose(normalised_slowness(Y), [0.8, 4.0, np.inf], rtol=1e-15)


def test_normalised_slowness_variance_floor():
    # var = 0.25 e^2: e = 2e-6 gives var 1e-12 (not above the floor: inf), 4e-6 a number
    s = normalised_slowness(np.array([[0.0, 0.0], [2e-6, 4e-6], [0.0, 0.0], [2e-6, 4e-6]]))
    assert s[0] == np.inf and s[1] == pytest.approx(4.0, rel=1e-9)


def test_normalised_slowness_refusals():
    for bad in (np.zeros((2, 1)), np.zeros(5), np.zeros((3, 1, 1))):
        with pytest.raises(ValueError, match="^" + re.escape(
                f"Y must be (T >= 3, k), got shape {bad.shape}") + "$"):
            normalised_slowness(bad)
    assert normalised_slowness(np.array([[0.0], [1.0], [0.0]]))[0] == pytest.approx(
        1.0 / (2.0 / 9.0))
    with pytest.raises(ValueError, match="Y"):
        normalised_slowness(np.array([[0.0], [np.nan], [1.0]]))


# ------------------------------------------------------------------------- separability
def test_separability_by_hand():
    assert separability(np.array([1.0, 0.0, 1.0, 0.0])) == 1.0
    # 0, 1, 2, 3: var 1.25, the best split in the middle explains 1/4 * 2^2 = 1 -> 0.8
    assert separability(np.array([3.0, 0.0, 2.0, 1.0])) == pytest.approx(0.8, rel=1e-12)
    # 0, 0, 0, 3: var 27/16, split after the third: 3/4 * 1/4 * 3^2 = 27/16 -> 1
    assert separability(np.array([0.0, 0.0, 3.0, 0.0])) == pytest.approx(1.0, rel=1e-12)
    # 0, 1, 3: var 14/9; split 0 | 1, 3: 1/3 * 2/3 * 2^2 = 8/9; 0, 1 | 3: 2/9 * 2.5^2 = 25/18
    assert separability(np.array([0.0, 1.0, 3.0])) == pytest.approx((25 / 18) / (14 / 9))
    assert separability(np.array([[0.0, 1.0], [3.0, 2.0]])) == pytest.approx(0.8)  # raveled


def test_separability_of_a_constant_and_the_near_constant_edge():
    assert separability(np.full(5, 7.0)) == 0.0
    assert separability(np.array([0.0, 1e-12])) == 0.0               # spread 1e-12 * 1
    assert separability(np.array([0.0, 2e-12])) == pytest.approx(1.0)
    assert separability(np.array([1e12, 1e12 + 1.0])) == 0.0         # 1e-12 * 1e12 = 1
    assert separability(np.array([1e12, 1e12 + 2.0])) == pytest.approx(1.0)
    assert separability(np.array([-1e12, -1e12 + 1.0])) == 0.0       # by its magnitude
    assert separability(np.array([-1e12, -1e12 + 2.0])) == pytest.approx(1.0)
    assert separability(np.array([-1e12 - 1.0, -1e12])) == 0.0       # the top's magnitude


def test_separability_never_exceeds_one():
    rng = np.random.default_rng(0)
    for _ in range(50):
        y = np.repeat(rng.normal(size=2) * 10.0 ** rng.integers(-3, 6), rng.integers(1, 9, 2))
        assert 0.0 <= separability(y) <= 1.0


def test_separability_refusals():
    with pytest.raises(ValueError, match=r"^y needs at least 2 values, got 1$"):
        separability(np.array([1.0]))
    with pytest.raises(ValueError, match=r"^y needs at least 2 values, got 0$"):
        separability(np.array([]))
    assert separability(np.array([0.0, 1.0])) == 1.0


def test_bimodality_is_one_minus_the_mean_separability():
    Y = np.array([[0.0, 0.0, 4.0], [0.0, 1.0, 4.0], [1.0, 2.0, 4.0], [1.0, 3.0, 4.0]])
    assert bimodality(Y) == pytest.approx(1 - (1.0 + 0.8 + 0.0) / 3, rel=1e-12)
    assert bimodality(np.array([[0.0], [1.0]])) == 0.0
    for bad in (np.zeros((1, 2)), np.zeros(4)):
        with pytest.raises(ValueError, match="^" + re.escape(
                f"Y must be (T >= 2, k), got shape {bad.shape}") + "$"):
            bimodality(bad)


# ---------------------------------------------------------------------- prediction error
def test_prediction_error_with_nothing_to_go_on_by_hand():
    # Y = 0: the map predicts the fitting targets' mean / (1 + ridge); U: t and a constant
    T = 20
    U = np.column_stack([np.arange(T, dtype=float), np.full(T, 0.3)])
    Y = np.zeros((T, 2))
    # targets u(1..9), mean 5 -> 10/3; held out u(11..19): mean 15, var 20/3
    want = (20 / 3 + (15 - 10 / 3) ** 2) / (20 / 3)
    assert prediction_error(Y, U, 10, ridge=0.5) == pytest.approx(want, rel=1e-12)
    # horizon 2: targets u(2..9) mean 5.5 -> 11/3; held out rows 10..17 against u(12..19)
    want2 = (5.25 + (15.5 - 11 / 3) ** 2) / 5.25
    assert prediction_error(Y, U, 10, horizon=2, ridge=0.5) == pytest.approx(want2, rel=1e-12)
    # n_end 16: held out u(11..15), mean 13, var 2
    want3 = (2 + (13 - 10 / 3) ** 2) / 2
    assert prediction_error(Y, U, 10, 16, ridge=0.5) == pytest.approx(want3, rel=1e-12)


def test_prediction_error_of_a_perfect_linear_predictor_is_zero():
    U = walk(60)
    Y = np.vstack([U[1:] * 2.0 - 1.0, U[-1:]])   # y(t) = 2 u(t + 1) - 1
    assert prediction_error(Y, U, 30, ridge=0.0) == pytest.approx(0.0, abs=1e-20)
    assert prediction_error(Y, U, 30, ridge=1e-3) > 1e-9    # the ridge shrinks the map


def test_prediction_error_refusals_on_their_edges():
    U = np.column_stack([np.arange(20.0), np.arange(20.0) ** 2])
    Y = U * 0.5

    def words(n_fit: int, n_end: int, Ys: tuple, h: int = 1) -> str:
        return "^" + re.escape(f"n_fit ({n_fit}) and n_end ({n_end}) must leave a held-out "
                               f"block of Y {Ys} and U (20, 2) for horizon {h}") + "$"

    prediction_error(Y, U, 16)                               # 16 < 20 - 1 - 2
    with pytest.raises(ValueError, match=words(17, 20, (20, 2))):
        prediction_error(Y, U, 17)
    prediction_error(Y, U, 15, horizon=2)
    with pytest.raises(ValueError, match=words(16, 20, (20, 2), 2)):
        prediction_error(Y, U, 16, horizon=2)
    prediction_error(Y, U, 10, 14)                           # 10 < 14 - 3
    with pytest.raises(ValueError, match=words(11, 14, (20, 2))):
        prediction_error(Y, U, 11, 14)
    with pytest.raises(ValueError, match=words(0, 20, (20, 2))):
        prediction_error(Y, U, 0)
    # no fitting row left (n_fit = horizon) was a LinAlgError 'Singular matrix'
    with pytest.raises(ValueError, match=words(1, 20, (20, 2))):
        prediction_error(Y, U, 1)
    with pytest.raises(ValueError, match=words(3, 20, (20, 2), 3)):
        prediction_error(Y, U, 3, horizon=3)
    assert np.isfinite(prediction_error(Y, U, 2))             # one fitting row
    assert np.isfinite(prediction_error(Y, U, 4, horizon=3))
    with pytest.raises(ValueError, match=words(5, 21, (20, 2))):
        prediction_error(Y, U, 5, 21)
    with pytest.raises(ValueError, match=words(5, 20, (19, 2))):
        prediction_error(Y[:19], U, 5)
    with pytest.raises(ValueError, match=r"^ridge must be finite and >= 0, got -0.1$"):
        prediction_error(Y, U, 5, ridge=-0.1)
    prediction_error(Y, U, 5, ridge=0.0)
    with pytest.raises(ValueError, match="horizon"):
        prediction_error(Y, U, 5, horizon=0)
    with pytest.raises(ValueError, match="ridge"):
        prediction_error(Y, U, 5, ridge=float("nan"))


# --------------------------------------------------------------------------- instability
def test_instability_by_hand():
    a1, a2 = np.array([1.0, -1, 1, -1]), np.array([1.0, 1, -1, -1])
    b1 = np.array([1.0, -1, -1, 1])                  # orthogonal to a1 and a2
    Ya = np.column_stack([a1, a2])
    assert instability(Ya, Ya) == pytest.approx(0.0, abs=1e-15)
    assert instability(Ya, np.column_stack([-a2, 3 * a1])) == pytest.approx(0.0, abs=1e-15)
    # a1 matches b2 = a1 (1), a2 is left with b1 (0): 1 - 1/2
    assert instability(Ya, np.column_stack([b1, a1])) == pytest.approx(0.5, abs=1e-15)
    # a constant unit correlates with nothing (nan counted as 0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        assert instability(Ya, np.column_stack([np.ones(4), a2])) == pytest.approx(0.5)
    # the matching maximises the total: a greedy pick of the largest (0.9) would give 0.9 + 0
    x = np.array([1.0, 2, 3, 4, 5, 6, 7, 8]) - 4.5
    rng = np.random.default_rng(1)
    n1, n2 = rng.normal(size=8), rng.normal(size=8)
    Ya2 = np.column_stack([x, x + n1])
    Yb2 = np.column_stack([x + 0.1 * n2, x])
    C = np.abs(np.corrcoef(Ya2.T, Yb2.T)[:2, 2:])
    best = max(C[0, 0] + C[1, 1], C[0, 1] + C[1, 0]) / 2
    assert instability(Ya2, Yb2) == pytest.approx(1 - best, rel=1e-12)


def test_instability_refusals():
    for A, B in ((np.zeros((4, 2)), np.zeros((4, 3))), (np.zeros((2, 2)), np.zeros((2, 2))),
                 (np.zeros(4), np.zeros(4))):
        with pytest.raises(ValueError, match="^" + re.escape(
                f"Ya and Yb must be (T >= 3, k) of one shape, got {A.shape}, {B.shape}") + "$"):
            instability(A, B)


def test_rank_correlation():
    assert rank_correlation([3.0, 2.0, 1.0], [0.1, 0.2, 0.3]) == pytest.approx(1.0)
    assert rank_correlation([1.0, 2.0, 3.0], [0.1, 0.2, 0.3]) == pytest.approx(-1.0)
    # non-finite pairs are left out: three left, ranked as the labels
    assert rank_correlation([3.0, np.nan, 2.0, 1.0], [0.1, 0.9, 0.2, 0.3]) == pytest.approx(1.0)
    assert np.isnan(rank_correlation([3.0, np.inf, 2.0], [0.1, 0.2, 0.3]))
    for c, a in (([1, 2], [1, 2]), ([1, 2, 3], [1, 2, 3, 4]), ([[1, 2, 3]], [[1, 2, 3]])):
        with pytest.raises(ValueError, match=r"^criterion and accuracy must be 1-D of the "
                                             r"same length >= 3$"):
            rank_correlation(c, a)


# ------------------------------------------------------------------- held-out slowness
def test_heldout_slowness_and_its_edges():
    U = walk(120)
    with quiet():
        m = RCSFAICA(**SMALL).fit(U[:80])
    _, Ysfa = m.transform(U, return_sfa=True)
    assert heldout_slowness(m, U, 80) == pytest.approx(
        float(np.mean(normalised_slowness(Ysfa[80:]))), rel=1e-12)
    heldout_slowness(m, U, 117)
    for n_fit in (0, 118):
        with pytest.raises(ValueError, match=r"^n_fit must leave a held-out block, got "
                                             f"{n_fit} of 120 ticks$"):
            heldout_slowness(m, U, n_fit)
    heldout_slowness(m, U, 1)


# ----------------------------------------------------------------------------- sweeps
@pytest.fixture(scope="module")
def F() -> Any:
    return sweep_features(walk(200), [0.5, (0.1, 0.3)], **SMALL)


@pytest.mark.parametrize("criterion", CRITERIA)
def test_each_criterion_is_its_composition(F, criterion):
    n_rows, n_fit, h = 150, 120, 60
    with quiet():
        scores, models = score_sweep(F, n_rows, criterion)
    assert scores.shape == (2,)
    assert len(models) == (0 if criterion in ("stability", "slow-stable") else 2)
    val = slice(n_fit, n_rows)
    for b in range(2):
        Xv = F.X[b][val]
        with quiet():
            if criterion in ("stability", "slow-stable"):
                want = instability(F.fit_sfa(b, 0, h).transform(Xv),
                                   F.fit_sfa(b, h, n_fit).transform(Xv))
                if criterion == "slow-stable":
                    want *= np.mean(normalised_slowness(F.fit_sfa(b, 0, n_fit).transform(Xv)))
            else:
                m = F.fit(b, 0, n_fit)
                np.testing.assert_allclose(models[b].readout(Xv), m.readout(Xv), atol=1e-8)
                if criterion == "bimodality":
                    want = bimodality(m.readout(Xv))
                elif criterion == "bimodal-stable":
                    want = bimodality(m.readout(Xv)) * instability(
                        F.fit(b, 0, h).readout(Xv), F.fit(b, h, n_fit).readout(Xv))
                else:
                    Ysfa = m.readout(F.X[b][:n_rows], return_sfa=True)[1]
                    want = (np.mean(normalised_slowness(Ysfa[val])) if criterion == "slowness"
                            else prediction_error(Ysfa, F.X[b][:n_rows, :3], n_fit))
        assert scores[b] == pytest.approx(want, rel=1e-6, abs=1e-9)


def test_prediction_scores_the_horizon(F):
    with quiet():
        s1, _ = score_sweep(F, 150, "prediction", horizon=1)
        s5, _ = score_sweep(F, 150, "prediction", horizon=5)
        m = F.fit(0, 0, 120)
    Ysfa = m.readout(F.X[0][:150], return_sfa=True)[1]
    assert s5[0] == pytest.approx(prediction_error(Ysfa, F.X[0][:150, :3], 120, horizon=5),
                                  rel=1e-6)
    assert s5[0] != pytest.approx(s1[0], rel=1e-6)


def test_score_sweep_refusals_on_their_edges(F):
    with pytest.raises(ValueError, match="^" + re.escape(
            f"criterion must be one of {CRITERIA}, got 'fast'") + "$"):
        score_sweep(F, 150, "fast")
    for vf in (0.049, 0.501):
        with pytest.raises(ValueError, match="^" + re.escape(
                f"val_fraction must lie in [0.05, 0.5], got {vf}") + "$"):
            score_sweep(F, 150, "bimodality", val_fraction=vf)
    with quiet():
        score_sweep(F, 150, "bimodality", val_fraction=0.05)
        score_sweep(F, 150, "bimodality", val_fraction=0.5)
        score_sweep(F, 25, "stability")                # n_fit = 20, 20 < 25 - 3
        score_sweep(F, 80, "stability", val_fraction=0.05)    # 76 < 77
        score_sweep(F, 200, "stability")                  # every row

    def words(n: int) -> str:
        return "^" + re.escape(f"n_rows ({n}) must leave fitting and held-out rows in the 200 "
                               "rows of the sweep") + "$"

    for n, kw in ((24, {}), (60, {"val_fraction": 0.05}), (80, {"val_fraction": 0.05,
                                                                 "horizon": 2}), (201, {})):
        with pytest.raises(ValueError, match=words(n)):
            score_sweep(F, n, "stability", **kw)
    for units in ([], [1, 1]):
        with pytest.raises(ValueError, match="^" + re.escape(
                f"units must be distinct unit counts, got {units}") + "$"):
            score_sweep(F, 150, "stability", units=units)


def test_units_outer_leaks_inner(F):
    with quiet():
        s, models = score_sweep(F, 150, "bimodality", units=[1, 2])
        s1, _ = score_sweep(with_units(F, 1), 150, "bimodality")
        s2, _ = score_sweep(F, 150, "bimodality")
    np.testing.assert_allclose(s, np.concatenate([s1, s2]), rtol=1e-9)
    assert [m.params.n_ica for m in models] == [1, 1, 2, 2]


def test_with_units_edges(F):
    G = with_units(F, 9)                         # d = 3 + 6 SFA inputs
    assert (G.base.n_sfa, G.base.n_ica) == (9, 9) and G.X is F.X and G._moments is F._moments
    assert F.base.n_sfa == 2
    for k in (0, 10):
        with pytest.raises(ValueError, match="^" + re.escape(
                f"units must lie in [1, 9] (the SFA inputs), got {k}") + "$"):
            with_units(F, k)
    assert with_units(F, 1).base.n_ica == 1


# --------------------------------------------------------------------------- select_leak
def test_select_leak_picks_the_lowest_score_and_refits():
    U = walk(200)
    leaks = [0.5, (0.1, 0.3)]
    with quiet():
        sel = select_leak(U, leaks, n_rows=150, units=[1, 2], **SMALL)
        F = sweep_features(U, leaks, **SMALL)
        s, _ = score_sweep(F, 150, DEFAULT_CRITERION, units=[1, 2])
    assert sel.criterion == DEFAULT_CRITERION and sel.n_fit == 120
    assert sel.candidates == leaks * 2 and sel.units == [1, 1, 2, 2]
    np.testing.assert_allclose(sel.scores, s, rtol=1e-9)
    assert sel.best == int(np.argmin(s))
    assert sel.best_candidate == sel.candidates[sel.best]
    assert sel.best_units == sel.units[sel.best]
    for c in range(4):
        with quiet():
            r = sel.refit(c, 170)
            ref = with_units(F, sel.units[c]).fit(c % 2, 0, 170)
        assert r.params.n_ica == sel.units[c] and r.params.leak == leaks[c % 2]
        np.testing.assert_allclose(r.readout(F.X[c % 2]), ref.readout(F.X[c % 2]), atol=1e-7)
    with quiet():
        sel.refit(0, 120)
        sel.refit(0, 200)
    for n in (119, 201):
        with pytest.raises(ValueError, match="^" + re.escape(
                f"n_rows must lie in [120, rows of the sweep], got {n}") + "$"):
            sel.refit(0, n)


def test_select_leak_defaults():
    U = walk(100)
    with quiet():
        sel = select_leak(U, [0.5], criterion="stability", val_fraction=0.3, **SMALL)
    assert sel.n_fit == 70 and sel.units == [] and sel.best_units is None
    assert sel.models == [] and sel.candidates == [0.5]
    with pytest.raises(ValueError, match="sensor sequence U"):
        select_leak(np.full((100, 3), np.nan), [0.5], **SMALL)


def test_non_finite_inputs_are_named():
    nan3 = np.array([[0.0], [np.nan], [1.0]])
    one = np.array([[0.0], [1.0], [2.0]])
    cases = [("Y", lambda: normalised_slowness(nan3)), ("Y", lambda: bimodality(nan3)),
             ("y", lambda: separability(nan3[:, 0])),
             ("Ya", lambda: instability(nan3, one)), ("Yb", lambda: instability(one, nan3)),
             ("Y", lambda: prediction_error(nan3, one, 1)),
             ("U", lambda: prediction_error(one, nan3, 1))]
    for name, call in cases:
        with pytest.raises(ValueError, match="^" + re.escape(
                f"{name} contains 1 non-finite value(s) (NaN or inf)") + "$"):
            call()


def test_rank_correlation_takes_missing_values_as_none():
    assert rank_correlation([3, None, 2, 1], [0.1, 0.5, 0.2, 0.3]) == pytest.approx(1.0)
    assert rank_correlation([3, 2, 1, 0], [0.1, None, 0.2, 0.3]) == pytest.approx(1.0)


def _count_rows(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    rows: list[int] = []
    update = SFAMoments.update

    def spy(self: SFAMoments, X: np.ndarray) -> SFAMoments:
        rows.append(len(X))
        return update(self, X)

    monkeypatch.setattr(SFAMoments, "update", spy)
    return rows


@pytest.mark.parametrize("criterion", CRITERIA)
def test_each_fitting_row_is_summed_once(monkeypatch, criterion):
    F = sweep_features(walk(200), [0.5, (0.1, 0.3)], **SMALL)
    rows = _count_rows(monkeypatch)
    with quiet():
        score_sweep(F, 150, criterion)
    assert sum(rows) == 2 * 120                 # the two halves' moments, merged for the rest
    assert set(F._moments) == {(b, t0, t1) for b in (0, 1) for t0, t1 in ((0, 60), (60, 120))}


def test_refit_sums_only_the_new_rows(monkeypatch):
    U = walk(200)
    with quiet():
        sel = select_leak(U, [0.5, 0.9], n_rows=150, **SMALL)
    rows = _count_rows(monkeypatch)
    with quiet():
        sel.refit(1, 170)
    assert sum(rows) == 170 - 120


def test_select_leak_takes_its_params():
    params = RCSFAICAParams(**{**SMALL, "n_reservoir": 5})
    with quiet():
        sel = select_leak(walk(100), [0.5], params, criterion="stability")
    assert sel.features is not None and sel.features.base == params
    assert sel.features.X[0].shape == (100, 8)


def test_with_units_of_a_one_leak_sweep():
    F1 = sweep_features(walk(30), [0.5], **SMALL)
    with pytest.raises(ValueError, match=r"^units must lie in \[1, 9\] \(the SFA inputs\), "
                                         r"got 0$"):
        with_units(F1, 0)
