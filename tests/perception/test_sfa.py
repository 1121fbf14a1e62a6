"""SFA: recovers a hidden slow signal, whitened outputs ordered by slowness, rank deficiency."""

import numpy as np
import pytest

from hippo.perception.sfa import SFA, SFAMoments, SFAParams, chunk_bounds, quadratic_expansion


def _mixture(T=4000, seed=0, extra_cols=0):
    rng = np.random.default_rng(seed)
    t = np.arange(T)
    slow = np.sin(2 * np.pi * t / 1000)
    fast = [np.sin(2 * np.pi * t / p + rng.uniform(0, 6)) for p in (7.3, 11.1, 17.9)]
    noise = rng.standard_normal((T, 2))
    S = np.column_stack([slow, *fast, *noise.T])
    A = rng.standard_normal((S.shape[1], S.shape[1] + extra_cols))
    return S @ A, slow


def test_recovers_slow_sine():
    X, slow = _mixture()
    y = SFA(n_components=1).fit_transform(X)[:, 0]
    assert abs(np.corrcoef(y, slow)[0, 1]) > 0.99


def test_outputs_white_and_ordered():
    X, _ = _mixture()
    sfa = SFA(n_components=4).fit(X)
    Y = sfa.transform(X)
    np.testing.assert_allclose(Y.mean(axis=0), 0, atol=1e-8)
    np.testing.assert_allclose(np.cov(Y.T, bias=True), np.eye(4), atol=1e-6)
    delta = np.mean(np.diff(Y, axis=0) ** 2, axis=0)
    np.testing.assert_allclose(delta, sfa.slowness_, rtol=1e-6)
    assert np.all(np.diff(sfa.slowness_) >= 0)


def test_survives_duplicated_and_constant_columns():
    X, slow = _mixture()
    X = np.column_stack([X, X[:, 0], np.full(len(X), 3.0)])
    sfa = SFA(n_components=2).fit(X)
    assert sfa.n_whitened_ == X.shape[1] - 2
    assert abs(np.corrcoef(sfa.transform(X)[:, 0], slow)[0, 1]) > 0.99


def test_auto_cutoff_picks_a_candidate():
    X, slow = _mixture()
    sfa = SFA(n_components=1, cutoff="auto").fit(X)
    assert 0 < sfa.cutoff_ < 1 and sfa.cutoff_scores_
    assert abs(np.corrcoef(sfa.transform(X)[:, 0], slow)[0, 1]) > 0.99


def test_quadratic_expansion_finds_slow_square():
    rng = np.random.default_rng(1)
    T = 5000
    t = np.arange(T)
    slow = np.sin(2 * np.pi * t / 1500)
    fast = rng.choice([-1.0, 1.0], size=T)
    X = np.column_stack([slow * fast, rng.standard_normal(T)])  # slow only in the square
    lin = SFA(n_components=1).fit_transform(X)[:, 0]
    quad = SFA(n_components=1, expansion="quadratic").fit_transform(X)[:, 0]
    assert abs(np.corrcoef(quad, slow ** 2)[0, 1]) > 0.99
    assert abs(np.corrcoef(lin, slow ** 2)[0, 1]) < 0.2
    assert quadratic_expansion(np.ones((3, 4))).shape == (3, 4 + 10)


def test_affine_matches_transform():
    X, _ = _mixture(T=800)
    sfa = SFA(n_components=3).fit(X)
    M, b = sfa.affine()
    np.testing.assert_allclose(X @ M + b, sfa.transform(X), atol=1e-9)


def test_bad_input():
    X, _ = _mixture(T=500)
    with pytest.raises(ValueError, match="n_sfa=20 exceeds"):
        SFA(n_components=20).fit(X)
    with pytest.raises(ValueError, match="2-D"):
        SFA().fit(X[:, 0])
    bad = X.copy()
    bad[3, 1] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        SFA().fit(bad)
    with pytest.raises(ValueError, match="cutoff"):
        SFAParams(cutoff=0.0)
    with pytest.raises(ValueError, match="expansion"):
        SFAParams(expansion="cubic")
    with pytest.raises(RuntimeError, match="not fitted"):
        SFA().transform(X)
    sfa = SFA(n_components=2).fit(X)
    with pytest.raises(ValueError, match="features"):
        sfa.transform(X[:, :3])


def test_fit_refuses_complex_strings_and_odd_objects():
    X, _ = _mixture(T=200)
    for bad in (X + 1j, X.astype(str), X.astype(str).astype(object),
                (X + 1j).astype(object)):
        with pytest.raises(ValueError, match="X must hold real numbers"):
            SFA(n_components=2).fit(bad)
    bad = X.astype(object)
    bad[0, 0] = {"foo": "bar"}
    with pytest.raises(TypeError, match="X must hold real numbers"):
        SFA(n_components=2).fit(bad)
    # an object array of numbers is read as numbers (scikit-learn's convention)
    np.testing.assert_array_equal(SFA(n_components=2).fit(X.astype(object)).W_,
                                  SFA(n_components=2).fit(X).W_)


def test_moments_in_chunks_equal_the_two_pass_sums():
    X, _ = _mixture(T=1000, seed=3)
    X = X + 1e6                                       # a large mean must not cancel the variance
    m = SFAMoments(X.shape[1])
    for t0, t1 in [(0, 1), (1, 250), (250, 251), (251, 700), (700, 1000)]:
        m.update(X[t0:t1])
    Xc = X - X.mean(axis=0)
    D = np.diff(X, axis=0)
    assert m.n == 1000 and m.n_diff == 999
    np.testing.assert_allclose(m.mean, X.mean(axis=0), rtol=1e-14)
    np.testing.assert_allclose(m.scatter, Xc.T @ Xc, rtol=1e-9, atol=1e-9 * np.abs(Xc.T @ Xc).max())
    np.testing.assert_allclose(m.diff_scatter, D.T @ D, rtol=1e-9)
    # two halves accumulated apart, then merged in time order
    a, b = SFAMoments(X.shape[1]).update(X[:400]), SFAMoments(X.shape[1]).update(X[400:])
    ab = a.merged(b)
    big = np.abs(m.scatter).max()
    np.testing.assert_allclose(ab.scatter, m.scatter, rtol=1e-9, atol=1e-9 * big)
    np.testing.assert_allclose(ab.diff_scatter, m.diff_scatter, rtol=1e-12)
    assert ab.n_diff == 999
    c = np.ones(X.shape[1])
    np.testing.assert_allclose(a.scatter_about(c), (X[:400] - c).T @ (X[:400] - c), rtol=1e-9)
    with pytest.raises(ValueError, match="shape"):
        m.update(X[:, :2])


def test_float32_input_fits_like_float64():
    X, _ = _mixture()
    X32 = X.astype(np.float32)
    a = SFA(n_components=2).fit(X32)
    b = SFA(n_components=2).fit(X32.astype(np.float64))
    np.testing.assert_allclose(a.slowness_, b.slowness_, rtol=1e-10)
    np.testing.assert_allclose(a.transform(X32), b.transform(X32), atol=1e-9)
    np.testing.assert_allclose(a.fit_transform(X32), a.transform(X32), atol=1e-9)


def _held_out_score(X, cutoff, n):
    """The documented auto-cutoff score, from scratch: z-score X on all of it; on the first 80 %
    whiten (directions with eigenvalue > cutoff * largest) and take the n slowest directions;
    score = sum over units of held-out sum(y_dot^2) / sum(y^2) on the last 20 %."""
    split = int(0.8 * len(X))
    Z = (X - X.mean(axis=0)) / X.std(axis=0)
    Z1, Z2 = Z[:split], Z[split:]
    D1, D2 = np.diff(Z1, axis=0), np.diff(Z2, axis=0)
    d, E = np.linalg.eigh(Z1.T @ Z1 / len(Z1))
    keep = d > cutoff * d.max()
    if keep.sum() < n:
        return None
    S = E[:, keep] / np.sqrt(d[keep])
    _, V = np.linalg.eigh(S.T @ (D1.T @ D1 / len(D1)) @ S)
    W = S @ V[:, :n]
    return float(np.sum(np.sum((D2 @ W) ** 2, axis=0) / np.sum((Z2 @ W) ** 2, axis=0)))


def test_auto_cutoff_scores_are_the_held_out_slowness_and_the_lowest_wins():
    # columns on scales 0.01..100, two near-copies (eigenvalues ~1e-6 and ~1e-10 of the
    # largest): the candidates keep 4, 5 or 6 directions and score differently
    rng = np.random.default_rng(3)
    X, _ = _mixture(T=3000, seed=3)
    X = X[:, :4] * np.array([0.01, 1.0, 10.0, 100.0])
    X = np.column_stack([X, X[:, 1] + 1e-3 * rng.standard_normal(len(X)),
                         X[:, 2] + 1e-4 * rng.standard_normal(len(X))])
    sfa = SFA(n_components=2, cutoff="auto").fit(X)
    want = {c: _held_out_score(X, c, 2) for c in (10.0 ** -k for k in range(3, 13))}
    want = {c: s for c, s in want.items() if s is not None}
    assert len(set(np.round(list(want.values()), 6))) >= 3  # the candidates do differ
    assert sfa.cutoff_scores_.keys() == want.keys()
    for c, s in want.items():
        assert sfa.cutoff_scores_[c] == pytest.approx(s, rel=1e-5), c
    assert sfa.cutoff_ == min(want, key=want.get)


def test_auto_cutoff_score_is_a_ratio_however_quiet_the_held_out_part():
    # the last 20 % at 1 % of the amplitude: held-out sum(y^2) ~ 0.04, far below 1, and the
    # score, a ratio, is the same as at full amplitude
    X, _ = _mixture(T=2000, seed=5)
    X[1600:] = X[1600:].mean(axis=0) + 1e-2 * (X[1600:] - X[1600:].mean(axis=0))
    sfa = SFA(n_components=2, cutoff="auto").fit(X)
    for c, s in sfa.cutoff_scores_.items():
        assert s == pytest.approx(_held_out_score(X, c, 2), rel=1e-6), c
    assert min(sfa.cutoff_scores_.values()) > 1e-3


def test_auto_cutoff_ties_go_to_the_largest_candidate():
    # well-conditioned input: every candidate keeps every direction, all scores are equal, and
    # the most conservative cutoff (1e-3, the first candidate) is kept
    rng = np.random.default_rng(4)
    t = np.arange(2000)
    X = np.column_stack([np.sin(2 * np.pi * t / 500), rng.standard_normal((2000, 3))])
    sfa = SFA(n_components=2, cutoff="auto").fit(X)
    assert len(set(sfa.cutoff_scores_.values())) == 1 and len(sfa.cutoff_scores_) == 10
    assert sfa.cutoff_ == 1e-3


def test_quadratic_sfa_finds_the_slow_square_far_from_zero():
    # the input is centred before the products are taken: with an offset of 1e4 (sd ~1) the
    # products of uncentred inputs would bury x^2 under (1e4)^2 (relative eigenvalue ~1e-10,
    # below the whitening cutoff)
    rng = np.random.default_rng(1)
    t = np.arange(5000)
    slow = np.sin(2 * np.pi * t / 1500)
    X = np.column_stack([slow * rng.choice([-1.0, 1.0], size=5000), rng.standard_normal(5000)])
    quad = SFA(n_components=1, expansion="quadratic").fit_transform(X + 1e4)[:, 0]
    assert abs(np.corrcoef(quad, slow ** 2)[0, 1]) > 0.99


def test_quadratic_expansion_of_one_row_equals_its_row_in_a_batch():
    Z = np.random.default_rng(0).standard_normal((5, 3))
    np.testing.assert_array_equal(quadratic_expansion(Z[2]), quadratic_expansion(Z)[2])
    assert quadratic_expansion(np.array([2.0, 3.0])).tolist() == [2, 3, 4, 6, 9]


def test_chunks_hold_rows_rows_and_the_split_is_a_boundary():
    assert chunk_bounds(10, 3, rows=4) == [0, 4, 8, 10]
    assert chunk_bounds(10, 3, rows=4, split=5) == [0, 4, 5, 8, 10]
    assert chunk_bounds(1000, 10) == [0, 1000]  # ~2 million values per chunk by default
    # the default: 2,000,000 values per chunk, at least 256 rows
    assert chunk_bounds(3_000_000, 1) == [0, 2_000_000, 3_000_000]
    assert chunk_bounds(600, 100_000) == [0, 256, 512, 600]
    assert chunk_bounds(10, 4, split=3) == [0, 3, 10]


def test_moments_of_one_feature_and_of_nothing():
    x = np.array([1.0, 4.0, 2.0, 7.0])
    m = SFAMoments(1)
    assert m.n == 0 and m.first is None and m.last is None    # nothing added yet
    assert m.update(np.zeros((0, 1))) is m and m.n == 0 and m.first is None  # an empty chunk
    m.update(x[:, None])
    assert m.n == 4 and m.n_diff == 3
    assert m.mean[0] == pytest.approx(3.5) and m.scatter[0, 0] == pytest.approx(21.0)
    assert m.diff_scatter[0, 0] == pytest.approx(9 + 4 + 25)
    assert m.first.tolist() == [1.0] and m.last.tolist() == [7.0]
    with pytest.raises(ValueError, match=r"^n_features must be >= 1, got 0$"):
        SFAMoments(0)
    with pytest.raises(ValueError, match=r"^chunk must have shape \(k, 1\), got \(4, 2\)$"):
        m.update(np.zeros((4, 2)))
    with pytest.raises(ValueError, match=r"^moments of different dimensions cannot be merged$"):
        m.merged(SFAMoments(2))


def test_three_samples_are_enough_two_are_not():
    X = np.array([[0.0, 1.0], [1.0, 0.0], [0.0, 0.5]])
    assert SFA(n_components=1).fit(X).transform(X).shape == (3, 1)
    with pytest.raises(ValueError, match="at least 3 samples"):
        SFA(n_components=1).fit(X[:2])
