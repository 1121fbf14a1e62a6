"""FastICA: separates non-Gaussian sources, seeded, sign-normalised, restarts, warnings."""

import os
import re
import warnings

import numpy as np
import pytest

from hippo.perception.ica import FastICA, ICAConvergenceWarning, score_outputs
from hippo.perception.ica_params import ICAParams
from hippo.perception.place_cell_params import RCSFAICAParams


def amari_index(P: np.ndarray) -> float:
    """0 for a scaled permutation, larger for worse separations."""
    P = np.abs(P)
    n = P.shape[0]
    r = (P / P.max(axis=1, keepdims=True)).sum(axis=1) - 1
    c = (P / P.max(axis=0, keepdims=True)).sum(axis=0) - 1
    return float((r.sum() + c.sum()) / (2 * n * (n - 1)))


def _sources(T=5000, seed=0):
    rng = np.random.default_rng(seed)
    S = np.column_stack([rng.laplace(size=T), rng.uniform(-1, 1, T),
                         np.sign(np.sin(np.arange(T) / 13.0)), rng.exponential(size=T) - 1])
    A = rng.standard_normal((4, 4))
    return S, A


@pytest.mark.parametrize("algorithm", ["symmetric", "deflation"])
def test_separates_sources(algorithm):
    S, A = _sources()
    X = S @ A.T + 5.0
    with warnings.catch_warnings():
        warnings.simplefilter("error", ICAConvergenceWarning)  # converged: no warning
        ica = FastICA(algorithm=algorithm, seed=1).fit(X)
    assert amari_index(ica.components_ @ A) < 0.05
    assert ica.converged_ and ica.n_iter_ >= 1
    Y = ica.transform(X)
    np.testing.assert_allclose(Y.std(axis=0), 1.0, atol=1e-6)
    assert np.array_equal(ica.output_std_, np.ones(4))
    assert np.all(Y.max(axis=0) >= -Y.min(axis=0))  # peak response positive


def test_seed_gives_same_result():
    S, A = _sources()
    X = S @ A.T
    a = FastICA(seed=3, n_restarts=3).fit(X)
    b = FastICA(seed=3, n_restarts=3).fit(X)
    np.testing.assert_array_equal(a.components_, b.components_)


def test_skips_whitening_for_white_input():
    S, A = _sources()
    X = S @ A.T
    Xc = X - X.mean(axis=0)
    d, E = np.linalg.eigh(Xc.T @ Xc / len(X))
    Z = Xc @ E / np.sqrt(d)
    ica = FastICA(seed=0).fit(Z)
    assert ica.whitened_ is False and np.array_equal(ica.whitening_, np.eye(4))
    assert FastICA(seed=0).fit(X).whitened_ is True


def test_restarts_keep_best_score():
    S, A = _sources()
    ica = FastICA(seed=0, n_restarts=4, score="kurtosis").fit(S @ A.T)
    assert ica.restart_scores_.shape == (4,)
    # the best, ties (within tol = 1e-6 relative) going to the earlier restart
    best = ica.restart_scores_.max()
    assert ica.score_ == pytest.approx(best, rel=1e-6) and ica.score_ in ica.restart_scores_
    first = np.flatnonzero(ica.restart_scores_ >= best - 1e-6 * abs(best))[0]
    assert ica.score_ == ica.restart_scores_[first]
    for crit in ("kurtosis", "sparseness", "slowness"):
        assert np.isfinite(score_outputs(S / S.std(axis=0), crit))
    with pytest.raises(ValueError, match=r"^unknown score 'peakiness'; choose from \("):
        score_outputs(S, "peakiness")


def test_convergence_warning_names_iterations():
    S, A = _sources()
    with pytest.warns(ICAConvergenceWarning, match="max_iter=2"):
        FastICA(max_iter=2, tol=1e-12).fit(S @ A.T)
    with pytest.warns(ICAConvergenceWarning, match=r"did not converge in 3 of 3 restart\(s\)"):
        FastICA(max_iter=2, tol=1e-12, n_restarts=3).fit(S @ A.T)


def test_the_convergence_warning_points_at_the_caller_s_line():
    import hippo.perception.ica as ica_mod

    S, A = _sources(T=1000)
    with pytest.warns(ICAConvergenceWarning) as record:
        FastICA(max_iter=2, tol=1e-12).fit(S @ A.T)
    assert record[0].filename != ica_mod.__file__  # not at hippo's own line
    # (under mutmut, whose trampoline adds a frame between the caller and fit, it points there)
    if "MUTANT_UNDER_TEST" not in os.environ:
        assert record[0].filename == __file__


def test_fewer_components_than_inputs():
    S, A = _sources()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        ica = FastICA(n_components=2, seed=0).fit(S @ A.T)
    assert ica.transform(S @ A.T).shape == (len(S), 2)


def test_bad_input():
    S, _ = _sources(T=200)
    with pytest.raises(ValueError, match="n_ica=5 exceeds"):
        FastICA(n_components=5).fit(S)
    with pytest.raises(ValueError, match="algorithm"):
        ICAParams(algorithm="parallel")
    with pytest.raises(ValueError, match=r"^X contains 20 non-finite"):
        FastICA().fit(np.full((10, 2), np.nan))
    ica = FastICA(seed=0).fit(S)
    for bad in (S[:, :2], S[:, 0]):
        with pytest.raises(ValueError, match=r"^X must have shape \(T, 4\), got"):
            ica.transform(bad)
    with pytest.raises(ValueError, match=r"^whiten=False needs n_components equal to the input"):
        FastICA(whiten=False, n_components=2).fit(S)


def test_restarts_are_capped_like_the_command_line():
    for bad in (10**9, 1001, 0, 2.5):
        with pytest.raises(ValueError, match="n_restarts"):
            FastICA(n_restarts=bad)
    with pytest.raises(ValueError, match=r"ica_restarts: n_restarts must lie in \[1, 1000\]"):
        RCSFAICAParams(ica_restarts=10**9)
    assert ICAParams(n_restarts=1000).n_restarts == 1000


def test_restarts_on_threads_give_the_same_result():
    rng = np.random.default_rng(5)
    S = np.column_stack([rng.laplace(size=3000), rng.uniform(-1, 1, 3000), rng.laplace(size=3000)])
    X = S @ rng.standard_normal((3, 3))
    one = FastICA(n_components=3, n_restarts=5, seed=2, workers=1).fit(X)
    two = FastICA(n_components=3, n_restarts=5, seed=2, workers=2).fit(X)
    np.testing.assert_array_equal(one.components_, two.components_)
    np.testing.assert_array_equal(one.restart_scores_, two.restart_scores_)
    with pytest.raises(ValueError, match="workers"):
        ICAParams(workers=0)


@pytest.mark.parametrize("algorithm", ["symmetric", "deflation"])
@pytest.mark.parametrize("score", ["kurtosis", "sparseness", "slowness"])
def test_chunked_expectations_equal_the_one_array_form(monkeypatch, algorithm, score):
    """Expectations summed over chunks (whitened as used) give the one-array fit: the sums
    differ by rounding, so the fixed point may stop an iteration earlier or later, within the
    solver's tol (1e-6); the same from float32 input (read chunk by chunk, never copied)."""
    import hippo.perception.ica as ica_mod

    rng = np.random.default_rng(5)
    S = np.column_stack([rng.laplace(size=5000), rng.uniform(-1, 1, 5000),
                         np.sign(rng.standard_normal(5000)) * rng.exponential(size=5000)])
    X = (S @ rng.standard_normal((3, 3)).T) + 2.0
    whole = FastICA(algorithm=algorithm, score=score, n_restarts=3, seed=4).fit(X)
    monkeypatch.setattr(ica_mod, "_CHUNK", 700)  # 8 chunks, the last one short
    for Xi in (X, X.astype(np.float32)):
        chunked = FastICA(algorithm=algorithm, score=score, n_restarts=3, seed=4).fit(Xi)
        f32 = Xi.dtype == np.float32
        np.testing.assert_allclose(chunked.mean_, whole.mean_, rtol=1e-6 if f32 else 1e-12)
        np.testing.assert_allclose(chunked.components_, whole.components_, rtol=1e-4, atol=1e-5)
        np.testing.assert_allclose(chunked.restart_scores_, whole.restart_scores_, rtol=1e-5)


def test_score_of_chunks_equals_the_score_of_the_whole():
    from hippo.perception.ica import _score_chunks

    S = np.random.default_rng(0).standard_normal((1000, 3))
    for crit in ("kurtosis", "sparseness", "slowness"):
        parts = [S[:1], S[1:400], S[400:]]
        assert _score_chunks(parts, crit) == pytest.approx(score_outputs(S, crit), rel=1e-12)
        # the slowness of chunks counts the steps across their borders
    assert score_outputs(S, "slowness") == pytest.approx(
        -np.min(np.mean(np.diff(S, axis=0) ** 2, axis=0)), rel=1e-12)


def test_the_stabilised_newton_phase_keeps_the_separation(monkeypatch):
    # a solver that never converges: after max_iter // 2 fixed-point iterations, the other half
    # are Hyvärinen's stabilised Newton steps w <- w - mu (E{z g(y)} - beta w) / (E{g'(y)} -
    # beta); sub-Gaussian sources (uniform, square wave: E{g'} - beta > 0) stay separated as
    # well as super-Gaussian ones (a step of the wrong sign drives the sub-Gaussian ones
    # apart). (tol = 1e-300 is no way to never converge: on some machines the fixed point is
    # reached exactly, a change of 0.0, after 10 iterations, before any Newton step.)
    import hippo.perception.ica as ica_module

    solve = ica_module._fastica_symmetric
    monkeypatch.setattr(ica_module, "_fastica_symmetric",
                        lambda Z, W, max_iter, tol: solve(Z, W, max_iter, -1.0))
    S, A = _sources(T=4000, seed=2)
    X = S @ A.T
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        ica = FastICA(seed=1, max_iter=120).fit(X)
    assert not ica.converged_ and ica.n_iter_ == 120
    assert amari_index(ica.components_ @ A) < 0.05


def test_transform_before_fit_says_to_fit():
    from hippo._estimator import NotFittedError

    with pytest.raises(NotFittedError, match=r"^FastICA is not fitted yet; call fit\(X\) first"):
        FastICA().transform(np.zeros((3, 2)))


def test_transform_names_non_finite_input():
    S, A = _sources(T=1000)
    ica = FastICA(seed=0).fit(S @ A.T)
    X = S @ A.T
    X[3, 1] = np.nan
    with pytest.raises(ValueError, match=r"^X\b"):
        ica.transform(X)


def test_the_three_scores_follow_their_formulas():
    # kurtosis: sum_j |E{s_j^4} - 3|; sparseness: sum_j (1 - E|s_j|); slowness: -min_j E{ds_j^2}
    S = np.array([[1.0, 2.0], [-1.0, 0.0], [1.0, -2.0], [-1.0, 0.0]])
    assert score_outputs(S, "kurtosis") == pytest.approx(abs(1 - 3) + abs(8 - 3))
    assert score_outputs(S, "sparseness") == pytest.approx((1 - 1) + (1 - 1))
    assert score_outputs(S * 0.5, "sparseness") == pytest.approx((1 - 0.5) + (1 - 0.5))
    assert score_outputs(S, "slowness") == pytest.approx(-min(4.0, 16 / 3))
    # both outputs above 3: E{s^4} = 8 each
    assert score_outputs(np.array([[2.0, 2.0], [0, 0], [-2, -2], [0, 0]]), "kurtosis") == 10.0


def test_the_units_of_the_input_do_not_matter():
    # whitening is relative: the same sources at 1e-7 the scale separate the same way
    S, A = _sources(T=3000)
    X = S @ A.T
    big = FastICA(seed=1).fit(X)
    small = FastICA(seed=1).fit(X * 1e-7)
    np.testing.assert_allclose(small.components_ * 1e-7, big.components_, rtol=1e-6, atol=1e-9)


def test_degenerate_input_directions_are_refused():
    S, A = _sources(T=1000)
    X = S @ A.T
    X = np.column_stack([X, X[:, 0] + X[:, 1]])  # 5 columns, 4 directions
    with pytest.raises(ValueError, match="fewer than n_ica=5 non-degenerate directions"):
        FastICA(seed=0).fit(X)
    assert FastICA(seed=0, n_components=4).fit(X).components_.shape == (4, 5)


def test_symmetric_decorrelation_is_scipy_eigh_bit_for_bit(monkeypatch):
    # the direct LAPACK call gives the numbers of scipy.linalg.eigh, and (W Wᵀ)^{-1/2} W is
    # orthonormal
    import scipy.linalg

    import hippo.perception.ica as ica_mod
    from hippo.perception.ica import _sym_decorrelate

    # from an empty memo of LAPACK work sizes (a new process), then from the memo
    monkeypatch.setattr(ica_mod, "_SYEVR_LWORK", {})
    rng = np.random.default_rng(1)
    for k in (1, 2, 4, 8, 70):
        for _ in range(5):
            W = rng.standard_normal((k, k))
            s, u = scipy.linalg.eigh(W @ W.T, check_finite=False)
            ref = (u / np.sqrt(np.clip(s, np.finfo(float).tiny, None))) @ u.T @ W
            out = _sym_decorrelate(W)
            assert np.array_equal(out, ref)
            assert np.allclose(out @ out.T, np.eye(k), atol=1e-8)


def test_the_newton_step_size_halves_after_25_iterations_without_a_new_low():
    from hippo.perception.ica import _NewtonStepSize

    # a change that never falls: the first one is the low, then every 25 iterations without a
    # new low halve mu (the count restarting), down to 1/64
    size, mus = _NewtonStepSize(), []
    for _ in range(400):
        size.update(1.0)
        mus.append(size.mu)
    halved = [i + 1 for i in range(1, 400) if mus[i] < mus[i - 1]]
    assert halved == [26, 51, 76, 101, 126, 151]
    assert [mus[i - 1] for i in halved] == [1 / 2, 1 / 4, 1 / 8, 1 / 16, 1 / 32, 1 / 64]
    # a falling change keeps mu = 1
    size = _NewtonStepSize()
    for change in 0.99 ** np.arange(300):
        size.update(change)
    assert size.mu == 1.0
    # a new low restarts the count: 24 stalls, a new low, 24 stalls keep mu; one more halves it
    size = _NewtonStepSize()
    for change in [1.0] * 25 + [0.5] + [0.9] * 24:
        size.update(change)
    assert size.mu == 1.0
    size.update(0.9)
    assert size.mu == 0.5


def _white(T=2000, seed=3):
    """White 4-D input (k, T) mixed from the test sources."""
    S, A = _sources(T=T, seed=seed)
    Xc = S @ A.T
    Xc = Xc - Xc.mean(axis=0)
    d, E = np.linalg.eigh(Xc.T @ Xc / T)
    return (Xc @ E / np.sqrt(d)).T


def test_the_symmetric_solver_runs_fixed_point_steps_then_newton_steps():
    # max_iter = 6: min(200, 6 // 2) = 3 steps of the papers' fixed point
    # W+ = E{g(Wz) zᵀ} - 3 diag(E{(Wz)²}) W, then 3 stabilised Newton steps (mu = 1)
    # W+ = W - (E{g(y) zᵀ} - β W) / (3 E{y²} - β), β = E{y⁴}; each decorrelated (W Wᵀ)^-1/2 W
    from hippo.perception.ica import _fastica_symmetric, _White

    z = _white()
    T = z.shape[1]
    W0 = np.random.default_rng(0).standard_normal((4, 4))

    def sym(W):
        s, u = np.linalg.eigh(W @ W.T)
        return u @ np.diag(s ** -0.5) @ u.T @ W

    W = sym(W0)
    for it in range(6):
        Y = W @ z
        g, m2 = (Y ** 3) @ z.T / T, np.mean(Y ** 2, axis=1)
        if it < 3:
            W = sym(g - 3 * m2[:, None] * W)
        else:
            beta = np.mean(Y ** 4, axis=1)
            W = sym(W - (g - beta[:, None] * W) / (3 * m2 - beta)[:, None])
    got, n_iter, ok, _ = _fastica_symmetric(_White(z.T, np.zeros(4), np.eye(4)), W0, 6, 1e-300)
    assert n_iter == 6 and not ok
    np.testing.assert_allclose(got, W, atol=1e-9)


def test_the_newton_step_size_counts_the_newton_iterations_only(monkeypatch):
    # tol = 0 never converges: with max_iter = 500 the first min(200, 250) iterations are
    # fixed-point steps, and the step size sees the changes of the other 300; on Gaussian
    # input the change stalls, so mu is halved
    import hippo.perception.ica as ica_mod

    seen = []

    class Recorded(ica_mod._NewtonStepSize):
        def update(self, change):
            super().update(change)
            seen.append(self.mu)

    monkeypatch.setattr(ica_mod, "_NewtonStepSize", Recorded)
    z = np.random.default_rng(4).standard_normal((3, 1000))
    W0 = np.random.default_rng(5).standard_normal((3, 3))
    _, n_iter, ok, _ = ica_mod._fastica_symmetric(ica_mod._White(z.T, np.zeros(3), np.eye(3)),
                                                  W0, 500, 0.0)
    assert n_iter == 500 and not ok
    assert len(seen) == 300 and seen[0] == 1.0 and min(seen) < 1.0


def test_already_white_input_is_only_centred():
    # unit covariance: whitening is skipped, the mean is still taken off
    z = _white().T
    a = FastICA(seed=2).fit(z)
    b = FastICA(seed=2).fit(z + 5.0)
    assert not a.whitened_ and not b.whitened_
    np.testing.assert_allclose(b.mean_, 5.0, atol=1e-12)
    np.testing.assert_allclose(b.components_, a.components_, atol=1e-8)
    np.testing.assert_allclose(b.transform(z + 5.0), a.transform(z), atol=1e-8)


def test_the_whitening_eigenvectors_have_their_largest_entry_positive():
    # the documented sign convention of the whitening (an eigenvector's sign is arbitrary)
    S, A = _sources(T=2000)
    ica = FastICA(seed=0).fit(S @ A.T)
    V = ica.whitening_
    assert ica.whitened_
    assert np.all(V[np.argmax(np.abs(V), axis=0), np.arange(V.shape[1])] > 0)


@pytest.mark.parametrize("chunk", [65536, 700])
def test_float32_input_statistics_are_taken_in_float64(monkeypatch, chunk):
    # the mean and covariance of a float32 recording are those of its values in float64,
    # in one piece and chunk by chunk
    import hippo.perception.ica as ica_mod

    monkeypatch.setattr(ica_mod, "_CHUNK", chunk)
    X = (3.0 + np.random.default_rng(6).random((3000, 4))).astype(np.float32)
    m32, C32 = ica_mod._mean_cov(X)
    m64, C64 = ica_mod._mean_cov(X.astype(np.float64))
    assert m32.dtype == C32.dtype == np.float64
    np.testing.assert_allclose(m32, m64, rtol=1e-13)
    np.testing.assert_allclose(C32, C64, rtol=1e-11)


def test_a_float32_recording_is_not_copied_whole(monkeypatch):
    # the fit reads a float32 input chunk by chunk: its peak memory stays well below the
    # float64 copy of the input (numpy reports its buffers to tracemalloc)
    import tracemalloc

    import hippo.perception.ica as ica_mod

    monkeypatch.setattr(ica_mod, "_CHUNK", 4000)
    S, A = _sources(T=100_000, seed=1)
    X = (S @ A.T).astype(np.float32)
    tracemalloc.start()
    try:
        FastICA(seed=0, max_iter=20, tol=1e-3).fit(X)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < X.nbytes  # a float64 copy alone is 2 * X.nbytes


def test_two_samples_are_enough_one_is_not():
    # the smallest fit: two samples of one input, whitened to -1 and +1
    ica = FastICA().fit(np.array([[0.0], [1.0]]))
    np.testing.assert_allclose(np.abs(ica.transform(np.array([[0.0], [1.0]]))), 1.0)
    with pytest.raises(ValueError, match="at least 2 samples, got 1"):
        FastICA().fit(np.array([[0.0]]))


def test_the_symmetric_default_converges_where_deflation_wanders():
    # two Gaussian sources span a plane with no preferred direction: deflation's unit in it
    # has no fixed point and runs to max_iter; the symmetric default (all rows at once)
    # converges in a few iterations
    rng = np.random.default_rng(0)
    T = 3000
    S = np.column_stack([rng.laplace(size=T), rng.uniform(-1, 1, T), rng.standard_normal(T),
                         rng.standard_normal(T)])
    X = S @ rng.standard_normal((4, 4)).T
    with warnings.catch_warnings():
        warnings.simplefilter("error", ICAConvergenceWarning)
        sym = FastICA(seed=0).fit(X)
    assert sym.params.algorithm == "symmetric" and sym.converged_ and sym.n_iter_ < 20
    with pytest.warns(ICAConvergenceWarning, match=r"FastICA \(deflation\) did not converge"):
        FastICA(algorithm="deflation", seed=0).fit(X)


def test_chunked_expectations_equal_the_one_array_form_in_the_newton_phase(monkeypatch):
    # tol 1e-300, max_iter 40: 20 fixed-point steps, then 20 stabilised Newton steps, whose
    # β = E{y g(y)} is summed over the chunks too
    import hippo.perception.ica as ica_mod

    S, A = _sources(T=5000, seed=4)
    X = S @ A.T
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        whole = FastICA(seed=0, tol=1e-300, max_iter=40).fit(X)
        monkeypatch.setattr(ica_mod, "_CHUNK", 700)
        chunked = FastICA(seed=0, tol=1e-300, max_iter=40).fit(X)
    np.testing.assert_allclose(chunked.components_, whole.components_, rtol=1e-6, atol=1e-8)


@pytest.mark.parametrize("chunk", [65536, 700])
def test_output_stats_are_the_std_and_99_9th_percentile_of_the_outputs(monkeypatch, chunk):
    # on float32 input too, in float64, in one piece and chunk by chunk
    import hippo.perception.ica as ica_mod

    monkeypatch.setattr(ica_mod, "_OUT_CHUNK", chunk)
    S, A = _sources(T=3000, seed=5)
    X = S @ A.T
    ica = FastICA(seed=0).fit(X)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        two = FastICA(seed=0, n_components=2).fit(X)  # 2 outputs of 4 inputs
    for model in (ica, two):
        for Xi in (X, X.astype(np.float32)):
            out = model.transform(Xi.astype(np.float64))
            std, peak = ica_mod.output_stats(model, Xi)
            np.testing.assert_allclose(std, out.std(axis=0), rtol=1e-12)
            np.testing.assert_allclose(peak, np.percentile(out, 99.9, axis=0), rtol=1e-12)


def test_fit_transform_is_fit_then_transform():
    S, A = _sources(T=1000)
    X = S @ A.T
    np.testing.assert_array_equal(FastICA(seed=3).fit_transform(X),
                                  FastICA(seed=3).fit(X).transform(X))


def test_a_later_restart_must_beat_the_kept_one_by_tol_relative():
    # tol = 0.1: every restart's score (about 12) is within 10 % of the first one's, which is
    # kept; a threshold of tol / score (not relative) would have taken a later restart
    S, A = _sources(T=3000)
    ica = FastICA(seed=1, n_restarts=8, tol=0.1).fit(S @ A.T)
    first, later = ica.restart_scores_[0], ica.restart_scores_[1:]
    assert np.all(later <= first * 1.1) and ica.score_ == first
    assert later.max() > first + 0.1 / first


def test_one_chunk_of_input_is_whitened_once(monkeypatch):
    # up to _CHUNK samples the whitened input is computed once and held for every iteration
    import hippo.perception.ica as ica_mod

    calls = []
    real = ica_mod._White._whiten

    def whiten(self, t0, t1):
        calls.append((t0, t1))
        return real(self, t0, t1)

    monkeypatch.setattr(ica_mod._White, "_whiten", whiten)
    monkeypatch.setattr(ica_mod, "_CHUNK", 2000)  # exactly one chunk
    S, A = _sources(T=2000)
    ica = FastICA(seed=0, n_restarts=2).fit(S @ A.T)
    assert ica.n_iter_ > 1 and calls == [(0, 2000)]


def test_an_input_whose_covariance_overflows_is_named():
    # one clear error, no numpy overflow warnings before it
    S, A = _sources(T=1000)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=r"^X is too large: its covariance overflows"):
            FastICA(seed=0).fit(S @ A.T * 1e160)


def test_repr_names_the_parameters():
    assert repr(FastICA(n_components=3, seed=2)) == (
        "FastICA(n_components=3, algorithm='symmetric', n_restarts=1, score='kurtosis', seed=2)")


def test_deflation_counts_its_iterations_and_reports_its_last_change():
    # max_iter = 3, tol 1e-300: every unit runs exactly 3 fixed-point steps; the warning gives
    # the largest last change over the units (below 1: the unit vectors moved, not flipped)
    S, A = _sources(T=2000)
    with pytest.warns(ICAConvergenceWarning, match=r"ran 3 iterations, last change (\S+)") as rec:
        ica = FastICA(algorithm="deflation", max_iter=3, tol=1e-300).fit(S @ A.T)
    assert ica.n_iter_ == 3 and not ica.converged_
    last = float(re.search(r"last change (\S+) ", str(rec[0].message)).group(1))
    assert 0 < last < 1
