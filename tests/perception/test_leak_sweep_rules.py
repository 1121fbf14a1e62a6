"""The leak sweep's rules by hand (hippo.perception.leak_sweep), on small reservoirs: the
features [u; x] of every configuration against eq. 1 stepped by hand from the sweep's one
reservoir with that configuration's leak (across the batch of 16 too), the slow pool after them,
the down-sampled readings; the leak matrix row by row; the moments of any block of rows against
the sums written out (across the 4096-row chunks, negative bounds, kept); SFA and the whole
model of one configuration on a block equal to a model fitted on that block by hand; the
refusals word for word, and fit_leak_sweep refusing exactly what RCSFAICA.fit refuses, in its
words (outside input_range whatever out_of_range says, too short after the washout and
down-sampling, every sensor stuck), the edges taken."""

from __future__ import annotations

import re
import warnings
from typing import Any

import numpy as np
import pytest
from small_sweeps import SMALL, quiet, walk

import hippo.perception.leak_sweep as ls
from hippo.perception.leak_sweep import fit_leak_sweep, sweep_features
from hippo.perception.place_cell_params import RCSFAICAParams
from hippo.perception.place_cells import RCSFAICA
from hippo.perception.reservoir import Reservoir
from hippo.perception.sfa import SFA


def _eq1(res: Reservoir, a: np.ndarray, U: np.ndarray) -> np.ndarray:
    """x(t+1) = tanh((1 - a) x(t) + a (W_in u(t) + W_res x(t))) from x(0) = 0, by hand."""
    W_in, W_res = res.W_in, res.W_res
    x = np.zeros(W_res.shape[0])
    out = []
    for u in U:
        x = np.tanh((1.0 - a) * x + a * (W_in @ u + W_res @ x))
        out.append(x)
    return np.array(out)


# ------------------------------------------------------------------------------ features
def test_each_configuration_is_the_reading_then_eq1_with_its_own_leak():
    U = walk(15)
    leaks = [0.3, (0.1, 0.9), [0.2, 0.4, 0.6, 0.8, 1.0, 0.5]]
    F = sweep_features(U, leaks, **SMALL)
    rows = [np.full(6, 0.3), np.array([0.1] * 3 + [0.9] * 3),
            np.array([0.2, 0.4, 0.6, 0.8, 1.0, 0.5])]
    assert F.leaks == leaks and F.A.shape == (3, 6)
    for b, a in enumerate(rows):
        assert np.array_equal(F.A[b], a)
        assert F.X[b].shape == (15, 3 + 6)
        assert np.array_equal(F.X[b][:, :3], U)
        np.testing.assert_allclose(F.X[b][:, 3:], _eq1(F.reservoir, a, U), atol=1e-12)
    # the one reservoir is the one a fit with these parameters builds
    ref = RCSFAICA(**SMALL)._build_reservoir()
    assert np.array_equal(F.reservoir.W_in, ref.W_in)
    assert np.array_equal(F.reservoir.W_res, ref.W_res)


def test_more_than_a_batch_of_16_each_with_its_own_leak():
    U = walk(8)
    leaks = [0.05 * (k + 1) for k in range(18)]      # batches of 16 and 2
    F = sweep_features(U, leaks, **SMALL)
    assert len(F.X) == 18
    for b in (0, 15, 16, 17):
        np.testing.assert_allclose(F.X[b][:, 3:], _eq1(F.reservoir, np.full(6, leaks[b]), U),
                                   atol=1e-12)


def test_the_slow_pool_follows_u_and_x():
    U = walk(10)
    tau = 4.0
    F = sweep_features(U, [0.5], slow_pool=tau, **SMALL)
    Z = np.column_stack([U, _eq1(F.reservoir, np.full(6, 0.5), U)])
    m = np.zeros(9)
    M = []
    for z in Z:
        m = (1 - 1 / tau) * m + z / tau
        M.append(m)
    assert F.X[0].shape == (10, 18)
    np.testing.assert_allclose(F.X[0], np.column_stack([Z, M]), atol=1e-12)


def test_down_sampled_the_rows_are_the_decimated_readings():
    U = walk(20)
    F = sweep_features(U, [0.4], downsample=2, **SMALL)
    Ud = RCSFAICA(downsample=2, **SMALL)._decimator().offline(U)
    assert F.X[0].shape == (10, 9)
    assert np.array_equal(F.X[0][:, :3], Ud)
    np.testing.assert_allclose(F.X[0][:, 3:], _eq1(F.reservoir, np.full(6, 0.4), Ud),
                               atol=1e-12)


def test_the_harvest_runs_on_one_blas_thread(monkeypatch):
    seen: list[Any] = []
    run = Reservoir.run

    def spy(self: Reservoir, U: Any, **kw: Any) -> np.ndarray:
        seen.append(kw.get("threads"))
        return run(self, U, **kw)

    monkeypatch.setattr(Reservoir, "run", spy)
    sweep_features(walk(5), [0.1] * 17, **SMALL)
    assert seen == [1, 1]


def test_sweep_refusals_word_for_word():
    with pytest.raises(ValueError, match=r"^a leak sweep needs use_reservoir=True$"):
        sweep_features(walk(20), [0.1], **{**SMALL, "use_reservoir": False})
    with pytest.raises(ValueError, match=r"^leaks is empty$"):
        sweep_features(walk(20), [], **SMALL)
    with pytest.raises(ValueError, match=r"^leaks is empty$"):
        fit_leak_sweep(walk(20), (), **SMALL)
    with pytest.raises(ValueError, match="workers"):
        sweep_features(walk(20), [0.1], workers=0, **SMALL)
    # params and overrides: the overrides win
    F = sweep_features(walk(20), [0.1], RCSFAICAParams(n_reservoir=9, **{
        k: v for k, v in SMALL.items() if k != "n_reservoir"}), n_reservoir=5)
    assert F.base.n_reservoir == 5 and F.X[0].shape == (20, 8)


def test_a_harvest_alone_follows_the_out_of_range_policy():
    U = walk(20)
    U[3, 1] = 1.5
    with pytest.raises(ValueError, match=r"would extrapolate"):
        sweep_features(U, [0.1], **SMALL)
    F = sweep_features(U, [0.1], out_of_range="clip", **SMALL)
    assert F.X[0][3, 1] == 1.0


# ------------------------------------------------------------------------------- moments
def _sums(X: np.ndarray) -> tuple[int, np.ndarray, np.ndarray, int, np.ndarray]:
    D = np.diff(X, axis=0)
    C = X - X.mean(axis=0)
    return len(X), X.mean(axis=0), C.T @ C, len(D), D.T @ D


@pytest.mark.parametrize("t0,t1,lo,hi", [(0, None, 0, 9000), (4000, 8500, 4000, 8500),
                                         (-100, None, 8900, 9000), (10, -10, 10, 8990),
                                         (4096, 4097, 4096, 4097)])
def test_moments_of_a_block_are_its_sums(t0, t1, lo, hi):
    F = sweep_features(walk(9000), [0.2], **SMALL)
    m = F.moments(0, t0, t1)
    n, mean, S, nd, DS = _sums(F.X[0][lo:hi])
    assert m.n == n and m.n_diff == nd
    np.testing.assert_allclose(m.mean, mean, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(m.scatter, S, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(m.diff_scatter, DS, rtol=1e-9, atol=1e-12)
    assert F.moments(0, lo, hi) is m          # kept under the normalised bounds


def test_moments_are_per_configuration():
    F = sweep_features(walk(50), [0.2, 0.9], **SMALL)
    a, b = F.moments(0), F.moments(1)
    np.testing.assert_allclose(b.mean, F.X[1].mean(axis=0), atol=1e-14)
    assert not np.allclose(a.mean, b.mean)


# ---------------------------------------------------------------------------------- fits
def test_fit_on_a_block_is_a_model_fitted_on_that_block():
    U = walk(300)
    F = sweep_features(U, [0.5, (0.1, 0.3)], **SMALL)
    with quiet():
        m = F.fit(1, 20, 250)
        prefix = F.fit(1, 0, 250)
        alone = RCSFAICA(**SMALL, leak=(0.1, 0.3)).fit(U[:250])     # a prefix is the recording's
        ref = RCSFAICA(**SMALL, leak=(0.1, 0.3))
        ref.reservoir_, ref.n_features_in_ = alone.reservoir_, 3
        ref._fit_features(F.X[1][20:250])
    np.testing.assert_allclose(prefix.transform(U), alone.transform(U), atol=1e-8)
    assert m.params.leak == (0.1, 0.3) and type(m.params.leak[0]) is float
    assert m.n_features_in_ == 3
    assert np.array_equal(m.reservoir_.W_in, F.reservoir.W_in)
    assert np.array_equal(m.reservoir_.W_res, F.reservoir.W_res)
    assert np.array_equal(m.reservoir_.to_arrays()["leak"], F.A[1])
    assert m.reservoir_.params.spectral_radius == 0.99
    np.testing.assert_allclose(m.sfa_slowness_, ref.sfa_slowness_, rtol=1e-9)
    np.testing.assert_allclose(m.readout(F.X[1]), ref.readout(F.X[1]), atol=1e-9)
    # the leak written back is a float for a scalar leak
    with quiet():
        m0 = F.fit(0, 0, 200)
    assert m0.params.leak == 0.5 and type(m0.params.leak) is float


def test_fit_with_the_blocks_moments_is_the_fit_without():
    F = sweep_features(walk(300), [0.5], **SMALL)
    with quiet():
        a = F.fit(0, 0, 200)
        b = F.fit(0, 0, 200, F.moments(0, 0, 100).merged(F.moments(0, 100, 200)))
    np.testing.assert_allclose(b.sfa_slowness_, a.sfa_slowness_, rtol=1e-9)


def test_fit_sfa_is_sfa_of_the_block():
    F = sweep_features(walk(300), [0.5], **SMALL)
    X = F.X[0][30:260]
    sfa = F.fit_sfa(0, 30, 260)
    ref = SFA(F.base.sfa_params()).fit(X)
    np.testing.assert_allclose(sfa.transform(X), ref.transform(X), atol=1e-8)
    given = F.fit_sfa(0, 30, 260, F.moments(0, 30, 260))
    np.testing.assert_allclose(given.transform(X), sfa.transform(X), atol=1e-12)
    other = F.fit_sfa(0, 30, 260, F.moments(0, 0, 230))   # the moments given are what count
    assert not np.allclose(other.transform(X), sfa.transform(X), atol=1e-6)


def test_moments_with_a_washout_are_refused_word_for_word():
    F = sweep_features(walk(300), [0.5], washout=5, **SMALL)
    with pytest.raises(ValueError, match=r"^moments are given for the rows after the washout: "
                                         r"washout=0 only$"):
        F.fit(0, 0, 200, F.moments(0, 0, 200))
    with quiet():
        F.fit(0, 0, 200)                        # without moments the washout is fine


# ------------------------------------------------------------------------- fit_leak_sweep
def test_fit_leak_sweep_is_each_configuration_fitted_alone():
    U = walk(300)
    with quiet():
        models = fit_leak_sweep(U, [0.5, (0.1, 0.3)], workers=1, **SMALL)
        alone = [RCSFAICA(**SMALL, leak=lk).fit(U) for lk in (0.5, (0.1, 0.3))]
    assert [m.params.leak for m in models] == [0.5, (0.1, 0.3)]
    for m, a in zip(models, alone):
        np.testing.assert_allclose(m.transform(U), a.transform(U), atol=1e-8)


def test_fit_leak_sweep_threads(monkeypatch):
    seen: list[Any] = []
    pm = ls.parallel_map

    def spy(f: Any, items: Any, k: int) -> Any:
        seen.append(k)
        return pm(f, items, k)

    monkeypatch.setattr(ls, "parallel_map", spy)
    with quiet():
        fit_leak_sweep(walk(200), [0.5, 0.7], workers=3, **SMALL)
        fit_leak_sweep(walk(200), [0.5, 0.7, 0.9], workers=2, **SMALL)
    assert seen == [2, 2]                 # min(workers, configurations)


def _fit_error(U: np.ndarray, **kw: Any) -> str:
    with pytest.raises(ValueError) as e:
        RCSFAICA(**{**SMALL, **kw}).fit(U)
    return str(e.value)


@pytest.mark.parametrize("policy", ["error", "clip", "warn"])
def test_fit_leak_sweep_refuses_readings_out_of_range_as_fit_does(policy):
    U = walk(200)
    U[7, 2] = 1.25
    words = _fit_error(U, out_of_range=policy)
    assert words.endswith("; place cells are learned from sensor readings scaled to "
                          "input_range: rescale U, or set input_range to its true range")
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # no clip warning either: refused first
        with pytest.raises(ValueError, match="^" + re.escape(words) + "$"):
            fit_leak_sweep(U, [0.5], out_of_range=policy, **SMALL)
    # the same recording is taken with its true range
    with quiet():
        fit_leak_sweep(U, [0.5], input_range=(0.0, 1.25), **SMALL)


def test_fit_leak_sweep_takes_readings_exactly_on_the_bounds():
    U = walk(200)
    U[3, 0], U[4, 1] = 0.0, 1.0
    with quiet():
        fit_leak_sweep(U, [0.5], **SMALL)
    U[4, 1] = np.nextafter(1.0, 2.0)
    with pytest.raises(ValueError, match=r"holds readings outside input_range \[0, 1\]"):
        fit_leak_sweep(U, [0.5], **SMALL)


@pytest.mark.parametrize("kw,T", [({}, 9), ({"washout": 4}, 13), ({"downsample": 3}, 29),
                                  ({"downsample": 2, "washout": 3}, 25)])
def test_fit_leak_sweep_refuses_a_recording_too_short_as_fit_does(kw, T):
    # min_fit_ticks = 10 updates: T // downsample - washout = 9 is one short
    assert T // kw.get("downsample", 1) - kw.get("washout", 0) == 9
    U = walk(T)
    words = _fit_error(U, **kw)
    assert words.startswith(f"U has {T} ticks (9 reservoir updates after a washout of ")
    with pytest.raises(ValueError, match="^" + re.escape(words) + "$"):
        fit_leak_sweep(U, [0.5], **{**SMALL, **kw})
    # one tick-block more: exactly min_fit_ticks updates, taken
    with quiet():
        fit_leak_sweep(walk(T + kw.get("downsample", 1)), [0.5], **{**SMALL, **kw})


def test_fit_leak_sweep_refuses_every_sensor_stuck_as_fit_does():
    U = np.full((60, 3), 0.5)
    words = _fit_error(U)
    assert words.startswith("every sensor in U is constant (values [0.5]): stuck")
    with pytest.raises(ValueError, match="^" + re.escape(words) + "$"):
        fit_leak_sweep(U, [0.5, 0.9], **SMALL)
    # a sweep's harvest alone is still taken (nothing is fitted)
    assert sweep_features(U, [0.5], **SMALL).X[0].shape == (60, 9)


def test_the_features_are_in_the_reservoirs_dtype():
    U = walk(20)
    F = sweep_features(U, [0.4], **{**SMALL, "dtype": "float32"})
    assert F.X[0].dtype == np.float32
    assert np.array_equal(F.X[0][:, :3], U.astype(np.float32))
    assert sweep_features(U, [0.4], **SMALL).X[0].dtype == np.float64


def test_defaults_fit_every_row():
    F = sweep_features(walk(300), [0.5], **SMALL)
    with quiet():
        whole, part = F.fit_sfa(0), F.fit_sfa(0, 0, 300)
        m_whole, m_part = F.fit(0), F.fit(0, 0, 300)
    np.testing.assert_allclose(whole.transform(F.X[0]), part.transform(F.X[0]), atol=1e-12)
    np.testing.assert_allclose(m_whole.readout(F.X[0]), m_part.readout(F.X[0]), atol=1e-12)


def test_fit_uses_the_moments_given():
    F = sweep_features(walk(300), [0.5], **SMALL)
    with quiet():
        own = F.fit(0, 30, 260)
        other = F.fit(0, 30, 260, F.moments(0, 0, 230))     # another block's, same length
    assert not np.allclose(other.sfa_slowness_, own.sfa_slowness_, rtol=1e-6)


def test_fit_leak_sweep_fits_on_one_torch_thread(monkeypatch):
    seen: list[Any] = []
    tt = ls._torch_threads

    def spy(n: Any) -> Any:
        seen.append(n)
        return tt(n)

    monkeypatch.setattr(ls, "_torch_threads", spy)
    with quiet():
        fit_leak_sweep(walk(200), [0.5], **SMALL)
    assert seen == [1]


def test_bad_workers_are_refused_before_the_harvest(monkeypatch):
    runs: list[int] = []
    run = Reservoir.run

    def spy(self: Reservoir, U: Any, **kw: Any) -> np.ndarray:
        runs.append(1)
        return run(self, U, **kw)

    monkeypatch.setattr(Reservoir, "run", spy)
    with pytest.raises(ValueError, match="workers"):
        fit_leak_sweep(walk(200), [0.5], workers=0, **SMALL)
    assert runs == []
