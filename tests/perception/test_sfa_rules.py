"""SFA's documented rules, each on designed input with a known answer: the sign convention
(positive third moment), the z-scoring of constant and near-constant columns, the pre-scaling
of the quadratic expansion, the whitening cutoff and spectrum, ``cutoff="auto"``'s candidates,
and the exact texts of its errors."""

import tracemalloc

import numpy as np
import pytest

from hippo._estimator import NotFittedError
from hippo.perception.sfa import SFA, _whiten, quadratic_expansion

CHUNK = 65536  # rows per chunk of the sign's sum of cubes


def _signed(y):
    """``_sign`` on designed training outputs ``y``: (the outputs, W_ after), W_ = 1, 2, ..."""
    sfa = SFA(n_components=y.shape[1])
    sfa.W_ = np.arange(1.0, 1.0 + 2 * y.shape[1]).reshape(2, -1)
    return sfa._sign(y.copy()), sfa.W_


# ------------------------------------------------------------------ sign: <y^3> >= 0
def test_each_unit_is_flipped_to_a_positive_sum_of_cubes():
    y = np.array([
        # negative only through row 0 (its sum is positive: +3)
        [-3.0, 1, 1, 1, 1, 1, 1],
        # sum(y) = -3 < 0 < sum(y^3) = 21: kept
        [3.0, -1, -1, -1, -1, -1, -1],
        # all zero: kept
        [0.0] * 7,
        # a small positive skew, <y^3> = 0.125 / 7: kept
        [1.0, -1, 0.5, 0, 0, 0, 0],
        # symmetric, sum of cubes exactly 0: kept
        [1.0, -1, 2, -2, 0, 0, 0],
        # plainly negative
        [-2.0, 0.5, 0.5, 0, 0, 0, 0],
    ]).T
    want = np.array([-1.0, 1, 1, 1, 1, -1])
    out, W = _signed(y)
    np.testing.assert_array_equal(out, y * want)
    np.testing.assert_array_equal(W, np.arange(1.0, 13.0).reshape(2, 6) * want)


def test_the_sum_of_cubes_covers_every_chunk_once():
    T = 3 * CHUNK + 5
    y = np.zeros((T, 4))
    # decided by the middle chunk alone (the first and the last say +)
    y[[5, CHUNK + 10, 2 * CHUNK + 7], 0] = [1.0, -2.0, 1.0]
    # decided by row CHUNK, the first row of the second chunk
    y[[0, CHUNK, 100_000], 1] = [1.0, -2.0, 1.0]
    # row CHUNK counted once: 2 - 1.1^3 > 0 (counted twice it would be negative)
    y[[0, 1, CHUNK], 2] = [1.0, 1.0, -1.1]
    # decided by the last row
    y[[0, T - 1], 3] = [1.0, -2.0]
    out, _ = _signed(y)
    np.testing.assert_array_equal(out, y * np.array([-1.0, -1.0, 1.0, -1.0]))


def test_float32_outputs_are_cubed_in_float64():
    # the streamed fit passes float32 outputs: 1e13 cubed overflows float32 (inf - inf = nan)
    y = np.zeros((6, 2), dtype=np.float32)
    y[:3, 0] = [1e13, -1e13, -1e13]
    y[:3, 1] = [-1e13, 1e13, 1e13]
    out, _ = _signed(y)
    assert out.dtype == np.float32
    np.testing.assert_array_equal(out, y * np.array([-1.0, 1.0], dtype=np.float32))


def test_fitted_units_have_a_positive_third_moment():
    rng = np.random.default_rng(0)
    t = np.arange(3000)
    S = np.column_stack([np.sin(2 * np.pi * t / 900) ** 3, -np.abs(np.sin(2 * np.pi * t / 700)),
                         rng.standard_normal((3000, 3))])
    X = S @ rng.standard_normal((5, 5))
    for sign in (1.0, -1.0):
        sfa = SFA(n_components=3)
        Y = sfa.fit_transform(sign * X)
        assert (np.sum(Y ** 3, axis=0) > 0).all()
        np.testing.assert_allclose(sfa.transform(sign * X), Y, atol=1e-10)


# ------------------------------------------------------------------ z-scoring
def test_scale_is_the_sd_and_near_constant_columns_keep_scale_one():
    rng = np.random.default_rng(1)
    T = 2000
    base = rng.standard_normal((T, 3)) * np.array([0.5, 2.0, 7.0]) + np.array([1.0, -3.0, 20.0])
    huge = 1e6 + 1e-8 * rng.standard_normal(T)   # sd 1e-8 < 1e-12 (1 + 1e6): scale 1
    tiny = np.tile([1.5e-12, -1.5e-12], T // 2)   # mean 0, sd 1.5e-12 > 1e-12: its own sd
    X = np.column_stack([base, huge, tiny, np.full(T, 3.0)])
    sfa = SFA(n_components=1).fit(X)
    np.testing.assert_allclose(sfa.mean_, X.mean(axis=0), rtol=1e-12, atol=1e-20)
    np.testing.assert_allclose(sfa.scale_[:3], X[:, :3].std(axis=0), rtol=1e-10)
    assert sfa.scale_[3] == 1.0 and sfa.scale_[5] == 1.0
    assert sfa.scale_[4] == pytest.approx(1.5e-12, rel=1e-6)
    # the huge column varies by ~1e-8 after z-scoring and the constant not at all: both dropped
    assert sfa.n_whitened_ == 4


def test_a_sd_of_exactly_1e_12_times_one_plus_the_mean_counts_as_constant():
    # +-1e-12 about a mean of 0 (4 rows): the sd is 1e-12 to the last bit, at the threshold
    # 1e-12 (1 + |mean|): treated as constant, scale 1
    x = np.array([1e-12, -1e-12, 1e-12, -1e-12])
    assert np.sqrt(np.mean(x ** 2)) == 1e-12
    sfa = SFA(n_components=1).fit(np.column_stack([x, [1.0, 2.0, 3.0, 5.0]]))
    assert sfa.mean_[0] == 0.0 and sfa.scale_[0] == 1.0
    quad = SFA(n_components=1, expansion="quadratic")
    quad.accumulate(x[:, None])
    assert quad.pre_mean_[0] == 0.0 and quad.pre_scale_[0] == 1.0
    quad.accumulate(2 * x[:, None])        # sd 2e-12: its own
    assert quad.pre_scale_[0] == pytest.approx(2e-12, rel=1e-12)


def test_input_eigenvalues_are_the_correlation_spectrum_largest_first():
    rng = np.random.default_rng(2)
    X = rng.standard_normal((1000, 4)) @ rng.standard_normal((4, 4)) + 5.0
    sfa = SFA(n_components=2).fit(X)
    want = np.linalg.eigvalsh(np.corrcoef(X.T))[::-1]
    np.testing.assert_allclose(sfa.input_eigenvalues_, want, rtol=1e-9)


def test_whitening_keeps_eigenvalues_strictly_above_cutoff_times_the_largest():
    C = np.diag([4.0, 1.0, 0.3, 4e-8])
    # 1e-8 * 4 == 4e-8 and 0.25 * 4 == 1.0 to the last bit: a tie is dropped
    for cutoff, kept in [(1e-8, 3), (1.1e-8, 3), (0.05, 3), (0.1, 2), (0.25, 1), (0.26, 1)]:
        S, eig = _whiten(C, cutoff)
        assert S.shape == (4, kept), cutoff
        np.testing.assert_allclose(S.T @ C @ S, np.eye(kept), atol=1e-12)
        np.testing.assert_array_equal(eig, [4.0, 1.0, 0.3, 4e-8])


def test_exactly_n_surviving_directions_are_enough():
    rng = np.random.default_rng(3)
    a, b = rng.standard_normal((2, 500))
    X = np.column_stack([a, a, b])
    assert SFA(n_components=2).fit(X).n_whitened_ == 2
    with pytest.raises(ValueError, match=r"^only 2 input directions survive the whitening cutoff "
                                         r"1e-08 but n_sfa=3; lower the cutoff or n_sfa$"):
        SFA(n_components=3).fit(X)
    with pytest.raises(ValueError, match=r"^no whitening cutoff keeps n_sfa=3 directions$"):
        SFA(n_components=3, cutoff="auto").fit(X)


def test_n_components_may_equal_the_input_dimension():
    rng = np.random.default_rng(4)
    X = rng.standard_normal((300, 2))
    assert SFA(n_components=2).fit(X).W_.shape == (2, 2)
    assert SFA(n_components=5, expansion="quadratic").fit(X).W_.shape == (5, 5)
    with pytest.raises(ValueError, match=r"^n_sfa=6 exceeds the SFA input dimension 5$"):
        SFA(n_components=6, expansion="quadratic").fit(X)


# ------------------------------------------------------------------ cutoff="auto"
def _fast_and_a_slow_difference(T=2000, delta=1.5e-3, seed=5):
    """Columns ``a`` and ``a + delta u``: white noise and a near-copy whose difference is a slow
    sine. The difference direction's correlation eigenvalue is ~delta^2 / 4, ~2.8e-7 of the
    largest (~2): cutoffs 1e-3 .. 1e-6 keep only the fast direction, 1e-7 .. 1e-12 both."""
    rng = np.random.default_rng(seed)
    a = rng.standard_normal(T)
    u = np.sin(2 * np.pi * np.arange(T) / 800)
    return np.column_stack([a, a + delta * u])


def test_auto_cutoff_candidates_keep_directions_relative_to_the_largest_eigenvalue():
    X = _fast_and_a_slow_difference()
    sfa = SFA(n_components=1, cutoff="auto").fit(X)
    scores = sfa.cutoff_scores_
    assert len(scores) == 10
    for c in (1e-3, 1e-4, 1e-5, 1e-6):   # the fast direction only: white noise, Δ ~ 2
        assert 1.5 < scores[c] < 2.5, c
    for c in (1e-7, 1e-12):              # the slow difference is kept and wins
        assert scores[c] < 0.01, c
    assert sfa.cutoff_ == 1e-7


def test_auto_cutoff_skips_candidates_that_keep_fewer_than_n_directions():
    X = _fast_and_a_slow_difference()
    sfa = SFA(n_components=2, cutoff="auto").fit(X)
    # 1e-3 .. 1e-6 keep one direction (< n = 2) and are skipped; the others keep exactly two
    assert sorted(sfa.cutoff_scores_) == [10.0 ** -k for k in range(12, 6, -1)]
    assert len(set(sfa.cutoff_scores_.values())) == 1
    assert sfa.cutoff_ == 1e-7 and sfa.n_whitened_ == 2


def test_auto_split_and_the_moments_accumulated():
    X = np.random.default_rng(6).standard_normal((101, 3))
    assert SFA().auto_split(101) is None
    assert SFA(cutoff="auto").auto_split(101) == 80
    (whole,) = SFA(n_components=1).accumulate(X)
    assert whole.n == 101
    first, rest = SFA(n_components=1, cutoff="auto").accumulate(X)
    assert (first.n, rest.n) == (80, 21)
    np.testing.assert_allclose(first.mean, X[:80].mean(axis=0), rtol=1e-12)


# ------------------------------------------------------------------ the quadratic expansion
def test_quadratic_pre_scaling_in_float64_with_constant_and_near_constant_columns():
    rng = np.random.default_rng(7)
    T = 1000
    X = np.column_stack([5.0 + 3.0 * rng.standard_normal(T),   # sd 3: scaled by its sd
                         1e6 + 1e-8 * rng.standard_normal(T),   # sd < 1e-12 (1 + 1e6): by 1
                         np.tile([1.5e-12, -1.5e-12], T // 2),  # sd 1.5e-12 > 1e-12: by its sd
                         np.full(T, 7.0)])                      # constant: by 1
    sfa = SFA(n_components=1, expansion="quadratic")
    sfa.accumulate(X)
    np.testing.assert_allclose(sfa.pre_mean_, X.mean(axis=0), rtol=1e-15, atol=1e-25)
    assert sfa.pre_scale_.shape == (4,)
    assert sfa.pre_scale_[0] == pytest.approx(X[:, 0].std(), rel=1e-12)
    assert sfa.pre_scale_[2] == pytest.approx(1.5e-12, rel=1e-6)
    assert sfa.pre_scale_[1] == 1.0 and sfa.pre_scale_[3] == 1.0


def test_quadratic_pre_scaling_of_float32_input_far_from_zero():
    # float32 means and sds of values near 1e4 are off by ~1e-3; accumulated in float64 not
    rng = np.random.default_rng(8)
    X32 = (1e4 + rng.standard_normal((4000, 2)) * np.array([1.0, 0.1])).astype(np.float32)
    sfa = SFA(n_components=1, expansion="quadratic")
    sfa.accumulate(X32)
    X = X32.astype(np.float64)
    np.testing.assert_allclose(sfa.pre_mean_, X.mean(axis=0), rtol=1e-14)
    np.testing.assert_allclose(sfa.pre_scale_, X.std(axis=0), rtol=1e-9)


def test_quadratic_expansion_sees_z_scored_input():
    # (x - mean) / sd: the linear part has mean 0 and sd 1, the squares mean 1
    rng = np.random.default_rng(9)
    X = np.column_stack([5.0 + 3.0 * rng.standard_normal(2000),
                         -2.0 + 0.5 * rng.laplace(size=2000)])
    sfa = SFA(n_components=1, expansion="quadratic").fit(X)
    np.testing.assert_allclose(sfa.mean_[:2], 0.0, atol=1e-12)
    np.testing.assert_allclose(sfa.scale_[:2], 1.0, rtol=1e-12)
    np.testing.assert_allclose(sfa.mean_[[2, 4]], 1.0, rtol=1e-12)   # z_0^2 and z_1^2


def test_quadratic_expansion_of_small_integers_does_not_wrap():
    Z = np.array([[100, 3]], dtype=np.int8)
    np.testing.assert_array_equal(quadratic_expansion(Z), [[100, 3, 10_000, 300, 9]])


# ------------------------------------------------------------------ memory, texts
def test_a_float32_input_is_not_copied_whole():
    rng = np.random.default_rng(10)
    sfa = SFA(n_components=1).fit(rng.standard_normal((500, 16)))
    X32 = rng.standard_normal((250_000, 16), dtype=np.float32)   # 16 MB; a float64 copy: 32 MB
    tracemalloc.start()
    try:
        sfa.transform(X32)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 2 * X32.nbytes, peak


def test_exact_error_texts():
    X = np.random.default_rng(11).standard_normal((200, 3))
    with pytest.raises(NotFittedError, match=r"^SFA is not fitted yet; call fit\(X\) first$"):
        SFA().transform(X)
    with pytest.raises(ValueError, match=r"^affine\(\) exists only for the linear expansion$"):
        SFA(n_components=1, expansion="quadratic").fit(X).affine()
    with pytest.raises(ValueError, match=r"^the quadratic expansion needs the data to scale its "
                                         r"input$"):
        SFA(expansion="quadratic")._prepare_shape(200, 3)   # a streamed fit holds no X
    sfa = SFA(n_components=1)
    with pytest.raises(ValueError, match=r"^moments of 100 samples do not describe X \(200 "
                                         r"rows\)$"):
        sfa._fit_moments(sfa.accumulate(X[:100]), X)
    assert repr(SFA(n_components=3, cutoff="auto")) == (
        "SFA(n_components=3, cutoff='auto', expansion='linear')")


def test_moments_that_overflow_are_refused():
    a = 4.47e153                  # a^2 = 2e307: four of them sum to 8e307, twelve overflow
    t = np.arange(100.0)
    cases = [
        np.random.default_rng(12).standard_normal((200, 3)) * 1e160,  # everything overflows
        np.column_stack([[a, -a, a, -a], [0.0, 1.0, 3.0, 2.0]]),  # only sum(dx^2) = 12 a^2
        np.column_stack([t * 3.2e152, np.sin(t)]),    # only sum(x^2) ~ 1e310 (sum(dx^2) 1e307)
    ]
    for X in cases:               # (LAPACK's LinAlgError before)
        with np.errstate(over="ignore", invalid="ignore"), pytest.raises(
                ValueError, match=r"^X's second moments overflow float64 \(values too large "
                                  r"to square and sum\); rescale X$"):
            SFA(n_components=1).fit(X)
