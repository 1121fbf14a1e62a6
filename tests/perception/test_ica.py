"""FastICA: separates non-Gaussian sources, seeded, sign-normalised, restarts, warnings."""

import warnings

import numpy as np
import pytest

from hippo.perception.ica import FastICA, ICAConvergenceWarning, ICAParams, score_outputs


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
    ica = FastICA(algorithm=algorithm, seed=1).fit(X)
    assert amari_index(ica.components_ @ A) < 0.05
    assert ica.converged_ and ica.n_iter_ >= 1
    Y = ica.transform(X)
    np.testing.assert_allclose(Y.std(axis=0), 1.0, atol=1e-6)
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
    assert not ica.whitened_
    assert FastICA(seed=0).fit(X).whitened_


def test_restarts_keep_best_score():
    S, A = _sources()
    ica = FastICA(seed=0, n_restarts=4, score="kurtosis").fit(S @ A.T)
    assert ica.restart_scores_.shape == (4,)
    assert ica.score_ == ica.restart_scores_.max()
    for crit in ("kurtosis", "sparseness", "slowness"):
        assert np.isfinite(score_outputs(S / S.std(axis=0), crit))


def test_convergence_warning_names_iterations():
    S, A = _sources()
    with pytest.warns(ICAConvergenceWarning, match="max_iter=2"):
        FastICA(max_iter=2, tol=1e-12).fit(S @ A.T)


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
    with pytest.raises(ValueError, match="non-finite"):
        FastICA().fit(np.full((10, 2), np.nan))
    with pytest.raises(ValueError, match="shape"):
        FastICA(seed=0).fit(S).transform(S[:, :2])


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
