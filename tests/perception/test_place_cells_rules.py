"""The place-cell estimator's rules by hand (hippo.perception.place_cells), on small models: the
features [u; x(t+1)] with eq. 1 stepped by hand from the reservoir's own weights and the slow
pool m(t) = (1 - 1/tau) m(t-1) + z(t) / tau; the readout SFA then ICA folded into one affine map
(and its value before the first update); the washout; the output statistics (unit variance,
the 99.9th percentile); step's input checks on their edges and one step past with every
out-of-range policy; the down-sampled hold and the update ticks; the presets, overrides and
repr, each refusal word for word."""

from __future__ import annotations

import warnings
from dataclasses import replace
from typing import Any

import numpy as np
import pytest

from hippo._estimator import NotFittedError
from hippo.perception.ica import ICAConvergenceWarning
from hippo.perception.place_cell_params import RCSFAICAParams
from hippo.perception.place_cells import ICANN09, RCSFAICA, SMC09, InputRangeWarning

SMALL = dict(n_inputs=3, n_reservoir=6, n_sfa=2, n_ica=2, ica_restarts=1, min_fit_ticks=10,
             dtype="float64")
ERROR_HINT = ("; the model was fitted on readings in that range and would extrapolate (set "
              "out_of_range='clip' or 'warn' to clip instead)")


def _walk(T: int = 300, n: int = 3, seed: int = 3) -> np.ndarray:
    rng = np.random.default_rng(seed)
    pos = np.cumsum(rng.standard_normal(T)) * 0.05
    return 0.5 + 0.4 * np.sin(pos[:, None] * np.arange(1, n + 1) + np.arange(n))


def _fit(U: np.ndarray | None = None, **kw: Any) -> RCSFAICA:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        return RCSFAICA(**{**SMALL, **kw}).fit(_walk() if U is None else U)


@pytest.fixture
def model() -> RCSFAICA:
    return _fit()


def _eq1(m: RCSFAICA, U: np.ndarray) -> np.ndarray:
    """x(t+1) = tanh((1 - a) x(t) + a (W_in u(t) + W_res x(t))) from x(0) = 0, by hand."""
    w = m.reservoir_.to_arrays()
    W_in, W_res, a = w["W_in"], w["W_res"], w["leak"]
    x = np.zeros(W_res.shape[0])
    out = []
    for u in U:
        x = np.tanh((1.0 - a) * x + a * (W_in @ u + W_res @ x))
        out.append(x)
    return np.array(out)


# ------------------------------------------------------------------------------ features
def test_the_features_are_the_reading_then_the_reservoir_state(model):
    U = _walk(12, seed=5)
    F = model.features(U)
    assert F.shape == (12, 3 + 6)
    assert np.array_equal(F[:, :3], U)
    assert np.allclose(F[:, 3:], _eq1(model, U), rtol=0, atol=1e-12)


def test_the_slow_pool_is_appended_after_u_and_x():
    m = _fit(slow_pool=4.0)
    U = _walk(10, seed=6)
    F = m.features(U)
    assert F.shape == (10, 2 * 9)
    Z = np.concatenate([U, _eq1(m, U)], axis=1)
    assert np.allclose(F[:, :9], Z, rtol=0, atol=1e-12)
    pool = np.zeros(9)
    for t in range(10):
        pool = 0.75 * pool + 0.25 * Z[t]
        assert np.allclose(F[t, 9:], pool, rtol=0, atol=1e-12)


def test_without_a_reservoir_the_features_are_the_readings():
    m = _fit(use_reservoir=False, n_sfa=2, n_ica=2)
    assert m.reservoir_ is None
    U = _walk(8, seed=7)
    assert np.array_equal(m.features(U), U)
    assert m.params.sfa_inputs == 3 and m.sfa_.n_features_in_ == 3


def test_down_sampled_features_are_those_of_the_decimated_readings():
    m = _fit(downsample=2)
    U = _walk(20, seed=8)
    Ud = m._decimator().offline(U)
    assert Ud.shape == (10, 3)
    assert np.array_equal(m.features(U), m.features(Ud, downsampled=True))
    assert np.allclose(m.features(Ud, downsampled=True)[:, 3:], _eq1(m, Ud), rtol=0,
                       atol=1e-12)


# ------------------------------------------------------------------------------- readout
def test_the_readout_is_ica_of_sfa(model):
    X = model.features(_walk(15, seed=9))
    S, Y = model.readout(X, return_sfa=True)
    assert np.array_equal(Y, model.sfa_.transform(X))
    assert np.array_equal(S, model.ica_.transform(Y))
    assert np.array_equal(model.readout(X), S)
    # ICA: W_ica (y - mu)
    assert np.allclose(S, (Y - model.ica_.mean_) @ model.ica_.components_.T, rtol=0,
                       atol=1e-10)


def test_the_compiled_map_is_the_readout_and_its_value_at_zero(model):
    M, b = model.sfa_.affine()
    C = model.ica_.components_.T
    assert np.allclose(model._R, M @ C, rtol=0, atol=1e-12)
    assert np.allclose(model._r0, (b - model.ica_.mean_) @ C, rtol=0, atol=1e-12)
    zero = model.readout(np.zeros((1, 9)))[0]
    assert np.allclose(model._y_init, zero, rtol=0, atol=1e-12)
    assert model._y_init is not model._r0


def test_a_quadratic_model_has_no_affine_map():
    m = _fit(use_reservoir=False, sfa_expansion="quadratic", n_sfa=3, n_ica=2)
    assert m._R is None and m._r0 is None
    assert np.array_equal(m._y_init, m.readout(np.zeros((1, 3)))[0])
    U = _walk(12, seed=10)
    m.reset_state()
    assert np.allclose([m.step(u) for u in U], m.transform(U), rtol=0, atol=1e-10)


def test_step_reproduces_transform_with_a_pool_and_without_a_reservoir():
    for kw in (dict(slow_pool=3.0), dict(use_reservoir=False, slow_pool=2.0),
               dict(use_reservoir=False)):
        m = _fit(**kw)
        U = _walk(25, seed=11)
        m.reset_state()
        assert np.allclose([m.step(u) for u in U], m.transform(U), rtol=0, atol=1e-10), kw


# ----------------------------------------------------------------------------------- fit
def test_the_fit_keeps_its_parts_and_output_statistics(model):
    assert model.n_features_in_ == 3
    assert np.array_equal(model.sfa_slowness_, model.sfa_.slowness_)
    assert model.sfa_slowness_ is not model.sfa_.slowness_
    S = model.transform(_walk())
    # unit variance on the training data; each unit's 99.9th percentile
    assert np.allclose(model.output_std_, 1.0, rtol=0, atol=1e-12)
    assert np.allclose(S.std(axis=0), 1.0, rtol=0, atol=1e-6)
    assert np.allclose(model.output_peak_, np.percentile(S, 99.9, axis=0), rtol=0, atol=1e-6)
    assert model.reservoir_.n_neurons == 6 and model.reservoir_.np_dtype == np.float64


def test_the_washout_leaves_the_first_updates_out_of_sfa():
    U = _walk()
    m = _fit(U, washout=40)
    F = m.features(U)
    # SFA's centring is the mean of the features after the washout
    assert np.allclose(m.sfa_.mean_, F[40:].mean(axis=0), rtol=0, atol=1e-9)
    assert not np.allclose(m.sfa_.mean_, F.mean(axis=0), rtol=0, atol=1e-6)
    Y = m.sfa_.transform(F[40:])
    assert np.allclose(Y.mean(axis=0), 0.0, atol=1e-9)


def test_fit_transform_is_fit_then_transform():
    U = _walk()
    m = RCSFAICA(**SMALL)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        S, Y = m.fit_transform(U, None, return_sfa=True)
    assert np.array_equal(S, m.transform(U)) and np.array_equal(Y, m.sfa_.transform(
        m.features(U)))


def test_a_fit_refuses_what_cannot_give_place_cells():
    with pytest.raises(ValueError, match=r"^U has 9 ticks \(9 reservoir updates"):
        RCSFAICA(**SMALL).fit(_walk(9))
    with pytest.raises(ValueError, match=r"^every sensor in U is constant"):
        RCSFAICA(**SMALL).fit(np.full((50, 3), 0.5))
    with pytest.raises(ValueError, match=r"^sensor sequence U holds readings outside"):
        RCSFAICA(**SMALL).fit(_walk() + 0.5)


# ------------------------------------------------------------------------- step's checks
def test_step_refuses_a_vector_of_another_shape_or_kind(model):
    model.reset_state()
    # (None reads as NaN, a scalar)
    for u, shape in ((np.zeros(2), (2,)), (np.zeros((1, 3)), (1, 3)), (0.5, ()), (None, ())):
        with pytest.raises(ValueError) as exc:
            model.step(u)
        assert str(exc.value) == f"sensor vector u must have shape (3,), got {shape}"
    for u in ("abc", [0.1, [0.2], 0.3], {1: 2}, 1j):
        with pytest.raises(ValueError) as exc:
            model.step(u)
        assert str(exc.value) == f"sensor vector u must be 3 real numbers, got {u!r}"


def test_step_refuses_nan_and_inf_whatever_the_range():
    # (without a range inf was taken: -inf <= inf <= inf, and the reservoir's state became NaN
    # for good)
    for rng in ((0.0, 1.0), None):
        m = _fit(input_range=rng, out_of_range="clip")
        for bad in (np.nan, np.inf, -np.inf):
            u = np.array([0.5, bad, 0.5])
            with pytest.raises(ValueError) as exc:
                m.step(u)
            assert str(exc.value) == f"sensor vector u contains NaN or inf: {u}"


def test_step_takes_readings_on_the_bounds_and_refuses_one_step_past(model):
    model.reset_state()
    model.step(np.array([0.0, 1.0, 0.5]))
    for v in (np.nextafter(0.0, -1.0), np.nextafter(1.0, 2.0)):
        u = np.array([0.5, v, 0.5])
        with pytest.raises(ValueError) as exc:
            model.step(u)
        assert str(exc.value) == (f"sensor vector u = {u} lies outside input_range [0, 1]"
                                  + ERROR_HINT)


def test_step_clips_with_clip_and_warn():
    m = _fit(out_of_range="clip")
    ref = _fit(out_of_range="clip")
    m.reset_state()
    ref.reset_state()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert np.array_equal(m.step(np.array([-3.0, 0.5, 7.0])), ref.step(np.array([0, 0.5, 1])))
    w = _fit(out_of_range="warn")
    w.reset_state()
    ref.reset_state()
    with pytest.warns(InputRangeWarning) as rec:
        out = w.step(np.array([2.0, 0.5, 0.5]))
    assert np.array_equal(out, ref.step(np.array([1.0, 0.5, 0.5])))
    assert str(rec[0].message) == ("sensor vector u = [2.  0.5 0.5] lies outside input_range "
                                   "[0, 1]; clipped to the range")


def test_a_model_without_a_range_takes_any_finite_reading():
    m = _fit(input_range=None)
    m.reset_state()
    out = m.step(np.array([-5.0, 0.5, 9.0]))
    assert np.isfinite(out).all()


def test_step_returns_a_copy(model):
    model.reset_state()
    out = model.step(np.array([0.2, 0.4, 0.6]))
    kept = model._last.copy()
    out[:] = 123.0
    assert np.array_equal(model._last, kept)


# -------------------------------------------------------------------------- down-sampling
def test_down_sampled_steps_hold_the_last_update():
    m = _fit(downsample=3)
    U = _walk(12, seed=12)
    m.reset_state()
    rows = []
    for u in U:
        out = m.step(u)
        rows.append(out.copy())
        out[:] = 99.0     # the held row is a copy too
    rows = np.array(rows)
    # ticks 0 and 1: the value before any update; then updates at ticks 2, 5, 8, 11
    assert np.allclose(rows[0], m._y_init, rtol=0, atol=1e-12)
    assert np.array_equal(rows[0], rows[1])
    for t0 in (2, 5, 8):
        assert np.array_equal(rows[t0], rows[t0 + 1]) and np.array_equal(rows[t0], rows[t0 + 2])
    assert np.allclose(rows, m.transform(U), rtol=0, atol=1e-10)
    S = m.transform(U, upsample=False)
    assert S.shape == (4, 2)
    assert np.allclose(S, rows[[2, 5, 8, 11]], rtol=0, atol=1e-10)


def test_the_sfa_outputs_are_held_too_from_sfa_of_zero():
    m = _fit(downsample=3)
    U = _walk(7, seed=13)
    S, Y = m.transform(U, return_sfa=True)
    y0 = m.sfa_.transform(np.zeros((1, 9)))[0]
    assert np.array_equal(Y[0], y0) and np.array_equal(Y[1], y0)
    S1, Y1 = m.transform(U, return_sfa=True, upsample=False)
    assert Y1.shape == (2, 2) and np.array_equal(Y[2], Y1[0]) and np.array_equal(Y[6], Y1[1])
    assert all(np.array_equal(S[t], S1[0]) for t in (2, 3, 4))
    assert np.array_equal(S[5], S1[1]) and np.array_equal(S[6], S1[1])


def test_the_update_ticks_and_the_filters_delay():
    ticks, delay = RCSFAICA(**SMALL).sample_ticks(5)
    assert ticks.tolist() == [0, 1, 2, 3, 4] and delay == 0.0 and type(delay) is float
    m = RCSFAICA(**{**SMALL, "downsample": 4})
    ticks, delay = m.sample_ticks(13)
    assert ticks.tolist() == [3, 7, 11]
    assert delay == float(m._decimator().delay) and delay > 0


# -------------------------------------------------------------------- unfitted, presets
def test_an_unfitted_model_says_so():
    m = RCSFAICA(**SMALL)
    for call in (m.reset_state, lambda: m.step(np.zeros(3)), lambda: m.transform(np.zeros((4, 3))),
                 lambda: m.readout(np.zeros((1, 9)))):
        with pytest.raises(NotFittedError) as exc:
            call()
        assert str(exc.value) == "RCSFAICA is not fitted yet; call fit(U) first"


def test_presets_and_overrides():
    assert RCSFAICA().params == SMC09
    assert RCSFAICA.smc09().params == SMC09
    assert RCSFAICA.icann09().params == ICANN09
    assert RCSFAICA.smc09(seed=4).params == replace(SMC09, seed=4)
    assert RCSFAICA.icann09(n_ica=3).params == replace(ICANN09, n_ica=3)
    p = RCSFAICAParams(n_inputs=5)
    assert RCSFAICA(p, n_sfa=3, n_ica=2).params == replace(p, n_sfa=3, n_ica=2)
    assert RCSFAICA(p).params is not None and RCSFAICA(p).params == p


def test_repr_word_for_word():
    assert repr(RCSFAICA(**SMALL)) == ("RCSFAICA(n_inputs=3, reservoir=6, leak=(0.05, 0.15), "
                                       "rho=0.99, n_sfa=2, n_ica=2, downsample=1, seed=0)")
    assert repr(RCSFAICA(n_inputs=4, use_reservoir=False, n_sfa=3, n_ica=1, downsample=2,
                         seed=7)) == ("RCSFAICA(n_inputs=4, no reservoir, n_sfa=3, n_ica=1, "
                                      "downsample=2, seed=7)")


# ---------------------------------------------------------------------- held or streamed
def _spy(monkeypatch: pytest.MonkeyPatch) -> list[tuple[int, ...]]:
    calls: list[tuple[int, ...]] = []
    real = RCSFAICA._fit_streamed
    monkeypatch.setattr(RCSFAICA, "_fit_streamed",
                        lambda self, Ud: calls.append(Ud.shape) or real(self, Ud))
    return calls


def test_the_fit_streams_only_past_the_budget(monkeypatch):
    import hippo.perception.place_cells as pc

    calls = _spy(monkeypatch)
    # 300 ticks of 9 float64 features: 21600 bytes; exactly the budget is held
    monkeypatch.setattr(pc, "_HOLD_BYTES", 300 * 9 * 8)
    _fit()
    assert calls == []
    monkeypatch.setattr(pc, "_HOLD_BYTES", 300 * 9 * 8 - 1)
    _fit()
    assert calls == [(300, 3)]
    # float32 states take half as much: 10800 bytes
    monkeypatch.setattr(pc, "_HOLD_BYTES", 300 * 9 * 4)
    _fit(dtype="float32")
    assert calls == [(300, 3)]
    # the budget counts the down-sampled ticks: 150 at downsample 2
    monkeypatch.setattr(pc, "_HOLD_BYTES", 150 * 9 * 8)
    _fit(downsample=2)
    assert calls == [(300, 3)]


def test_stream_given_overrides_the_budget(monkeypatch):
    calls = _spy(monkeypatch)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        RCSFAICA(**SMALL).fit(_walk(), stream=True)
        assert calls == [(300, 3)]
        import hippo.perception.place_cells as pc
        monkeypatch.setattr(pc, "_HOLD_BYTES", 1)
        RCSFAICA(**SMALL).fit(_walk(), stream=False)
    assert calls == [(300, 3)]
    # the other forms hold their features whatever is asked
    _fit(use_reservoir=False, n_sfa=2)
    _fit(use_reservoir=False, sfa_expansion="quadratic", n_sfa=2)
    assert calls == [(300, 3)]


# -------------------------------------------------------------------- dtypes and memory
def test_features_are_in_the_reservoirs_dtype():
    m = _fit(dtype="float32")
    U = _walk(20, seed=14)
    F = m.features(U)
    assert F.dtype == np.float32
    assert np.array_equal(F[:, :3], U.astype(np.float32))
    Ud = m._decimator().offline(U)
    chunk, (x_end, pool_end) = m._chunk(Ud, 0, 20, None)
    assert chunk.dtype == np.float32 and np.array_equal(chunk, F)
    assert np.array_equal(x_end, F[-1, 3:]) and pool_end is None
    X, parts, chunks = m._harvest_summarised(Ud)
    assert X.dtype == np.float32 and np.array_equal(X, F)
    assert chunks[0] == (0, 20, None) and len(parts) == 1


def test_the_held_fit_uses_the_harvests_moments(monkeypatch):
    from hippo.perception.sfa import SFA

    def refit(self, X):  # the moments of the whole harvest are not summed again
        raise AssertionError("SFA fitted from the features again")

    monkeypatch.setattr(SFA, "fit_transform", refit)
    m = _fit()
    assert m.sfa_.n_features_in_ == 9


def test_a_streamed_fit_holds_no_features_and_gives_ica_float32(monkeypatch):
    harvests: list[Any] = []
    slow: list[np.dtype] = []
    real_h, real_s = RCSFAICA._harvest_summarised, RCSFAICA._fit_slow

    def harvest(self, Ud, **kw):
        got = real_h(self, Ud, **kw)
        harvests.append(got[0])
        return got

    monkeypatch.setattr(RCSFAICA, "_harvest_summarised", harvest)
    monkeypatch.setattr(RCSFAICA, "_fit_slow",
                        lambda self, Y: slow.append(Y.dtype) or real_s(self, Y))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        RCSFAICA(**SMALL).fit(_walk(), stream=True)
    assert harvests == [None] and slow == [np.float32]


def test_a_quadratic_readout_over_a_reservoir_steps_through_the_readout():
    m = _fit(sfa_expansion="quadratic", n_sfa=2, n_ica=2)
    assert m._R is None and m._r0 is None
    U = _walk(15, seed=15)
    m.reset_state()
    assert np.allclose([m.step(u) for u in U], m.transform(U), rtol=0, atol=1e-10)


def test_the_compiled_map_centres_on_any_ica_mean():
    # SFA's outputs are centred on the training data, so ICA's mean is ~0 there; move it
    m = _fit()
    m.ica_.mean_ = m.ica_.mean_ + np.array([0.5, -0.25])
    m._compile()
    _, b = m.sfa_.affine()
    C = m.ica_.components_.T
    assert np.allclose(m._r0, (b - m.ica_.mean_) @ C, rtol=0, atol=1e-12)
    U = _walk(10, seed=16)
    m.reset_state()
    assert np.allclose([m.step(u) for u in U], m.readout(m.features(U)), rtol=0, atol=1e-10)


def test_downsampling_by_two_holds_too():
    m = _fit(downsample=2)
    U = _walk(9, seed=17)
    S = m.transform(U)
    assert S.shape == (9, 2)
    assert np.allclose(S[0], m._y_init, rtol=0, atol=0)
    S1 = m.transform(U, upsample=False)
    assert S1.shape == (4, 2)
    assert all(np.array_equal(S[t], S1[(t + 1) // 2 - 1]) for t in range(1, 9))


def test_the_harvest_runs_in_chunks_of_2048_ticks_after_the_washout():
    m = _fit(washout=5)
    U = _walk(4100, seed=18)
    X, parts, chunks = m._harvest_summarised(U)
    # the washout, then 2048 ticks, then the rest; each chunk starts from the state the one
    # before it ended in (the first from zeros)
    assert [(t0, t1) for t0, t1, _ in chunks] == [(0, 5), (5, 2053), (2053, 4100)]
    assert chunks[0][2] is None
    F = m.features(U)
    assert np.array_equal(X, F)
    for t0, _, (x0, pool) in chunks[1:]:
        assert np.array_equal(x0, F[t0 - 1, 3:]) and pool is None
    # one set of moments, of the ticks after the washout
    assert len(parts) == 1 and parts[0].n == 4100 - 5
