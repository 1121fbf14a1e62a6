"""RCSFAICA: the three layers as one estimator; offline == online; persistence; bad input."""

import warnings

import numpy as np
import pytest

from hippo.io import CorruptFileError
from hippo.perception import RCSFAICA, RCSFAICAParams, fit_leak_sweep
from hippo.perception.ica import ICAConvergenceWarning


def _walk(T=2500, n=8, seed=0):
    """Sensor-like signals: a slow latent position seen through noisy non-linear sensors."""
    rng = np.random.default_rng(seed)
    pos = np.cumsum(rng.standard_normal(T)) * 0.05
    phases = rng.uniform(0, 2 * np.pi, n)
    U = 0.5 + 0.4 * np.sin(pos[:, None] * np.arange(1, n + 1) + phases)
    return np.clip(U + 0.02 * rng.standard_normal((T, n)), 0, 1)


@pytest.fixture(scope="module")
def fitted():
    U = _walk()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        model = RCSFAICA.smc09(n_reservoir=120, ica_restarts=2, seed=1).fit(U)
    return model, U


def test_fit_transform_shapes_and_scale(fitted):
    model, U = fitted
    Y, Ysfa = model.transform(U, return_sfa=True)
    assert Y.shape == (len(U), 4) and Ysfa.shape == (len(U), 4)
    np.testing.assert_allclose(model.output_std_, 1.0, atol=1e-6)
    assert np.all(model.sfa_slowness_ > 0) and np.all(np.diff(model.sfa_slowness_) >= 0)
    assert model.reservoir_.n_neurons == 120


def test_readout_of_features_is_transform(fitted):
    """``readout(features(U))`` is ``transform(U)`` (the two halves of it); a wrong width is
    refused."""
    model, U = fitted
    Y, Ysfa = model.readout(model.features(U[:500]), return_sfa=True)
    Y2, Ysfa2 = model.transform(U[:500], return_sfa=True)
    np.testing.assert_allclose(Y, Y2, atol=1e-9)
    np.testing.assert_allclose(Ysfa, Ysfa2, atol=1e-9)
    with pytest.raises(ValueError, match="features"):
        model.readout(U[:500])


def test_transform_equals_step(fitted):
    model, U = fitted
    Y = model.transform(U[:600])
    model.reset_state()
    S = np.array([model.step(u) for u in U[:600]])
    np.testing.assert_allclose(S, Y, atol=2e-3 * np.abs(Y).max())


def test_transform_equals_step_downsampled():
    U = _walk(T=3000, n=5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        model = RCSFAICA.icann09(n_inputs=5, n_reservoir=80, n_sfa=6, n_ica=6, downsample=7,
                                 ica_restarts=1, dtype="float64").fit(U)
    Y = model.transform(U)
    model.reset_state()
    S = np.array([model.step(u) for u in U])
    np.testing.assert_allclose(S, Y, atol=1e-6)
    # outputs are held between reservoir updates
    assert np.array_equal(Y[7], Y[12]) and not np.array_equal(Y[12], Y[13])


def test_save_load_round_trip_exact(fitted, tmp_path):
    model, U = fitted
    path = model.save(tmp_path / "pc.npz")
    loaded = RCSFAICA.load(path)
    assert loaded.params == model.params
    np.testing.assert_array_equal(loaded.transform(U[:300]), model.transform(U[:300]))
    loaded.reset_state()
    model.reset_state()
    np.testing.assert_array_equal(loaded.step(U[0]), model.step(U[0]))


@pytest.mark.parametrize(("change", "message"), [
    ({"n_ica": 2}, r"ica_whitening must have shape"),
    ({"leak": 0.3}, r"leak does not match"),
    ({"spectral_radius": 0.5}, r"spectral radius"),
])
def test_a_model_whose_parameters_changed_after_fit_is_not_saved(change, message, tmp_path):
    """set_params after fit changes the parameters, not the fit (scikit-learn's contract): the
    outputs keep the fitted width, and save refuses a file that load would refuse."""
    from hippo.places import LearnedPlaceCells

    U = _walk(T=600, n=8)
    model = RCSFAICA(n_reservoir=40, n_sfa=4, n_ica=4, ica_restarts=1).fit(U)
    model.set_params(**change)
    assert model.transform(U[:5]).shape == (5, 4)
    assert LearnedPlaceCells(model).n_units == 4     # what each step returns
    with pytest.raises(ValueError, match=f"parameters no longer describe its fit.*{message}"):
        model.save(tmp_path / "pc.npz")
    assert not (tmp_path / "pc.npz").exists()
    model.set_params(**{k: getattr(RCSFAICAParams(n_reservoir=40, n_sfa=4, n_ica=4,
                                                  ica_restarts=1), k) for k in change})
    assert RCSFAICA.load(model.save(tmp_path / "pc.npz")).params == model.params


def test_corrupt_file(fitted, tmp_path):
    model, _ = fitted
    bad = tmp_path / "bad.npz"
    bad.write_bytes(b"not a zip file at all")
    with pytest.raises(CorruptFileError, match="not a readable"):
        RCSFAICA.load(bad)
    path = model.save(tmp_path / "pc.npz")
    data = dict(np.load(path))
    del data["sfa_W"]
    np.savez(tmp_path / "partial.npz", **data)
    with pytest.raises(ValueError, match="sfa_W"):
        RCSFAICA.load(tmp_path / "partial.npz")
    np.savez(tmp_path / "other.npz", **{**dict(np.load(path)), "format": np.array("x")})
    with pytest.raises(ValueError, match="not an RCSFAICA"):
        RCSFAICA.load(tmp_path / "other.npz")


def test_no_reservoir_quadratic_ablation():
    U = _walk(T=1500, n=4)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        model = RCSFAICA(n_inputs=4, use_reservoir=False, sfa_expansion="quadratic",
                         n_sfa=5, n_ica=5, ica_restarts=1).fit(U)
    assert model.reservoir_ is None
    Y = model.transform(U)
    model.reset_state()
    np.testing.assert_allclose(np.array([model.step(u) for u in U[:50]]), Y[:50], atol=1e-9)


def test_leak_sweep_matches_individual_fits():
    U = _walk(T=1200)
    leaks = [(0.05, 0.15), 0.3]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        models = fit_leak_sweep(U, leaks, n_reservoir=50, ica_restarts=1, dtype="float64")
        single = RCSFAICA(n_reservoir=50, leak=0.3, ica_restarts=1, dtype="float64").fit(U)
    assert [m.params.leak for m in models] == [(0.05, 0.15), 0.3]
    np.testing.assert_allclose(models[1].sfa_slowness_, single.sfa_slowness_, rtol=1e-6)


def test_leak_sweep_same_result_on_one_or_two_workers():
    U = _walk(T=1500)
    leaks = [0.1, 0.2, 0.4, (0.05, 0.5), 0.9]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        one = fit_leak_sweep(U, leaks, n_reservoir=60, ica_restarts=1, workers=1)
        two = fit_leak_sweep(U, leaks, n_reservoir=60, ica_restarts=1, workers=2)
        again = fit_leak_sweep(U, leaks, n_reservoir=60, ica_restarts=1, workers=2)
    for a, b, c in zip(one, two, again):
        assert a.params.leak == b.params.leak
        np.testing.assert_array_equal(a.transform(U), b.transform(U))   # workers change nothing
        np.testing.assert_array_equal(b.transform(U), c.transform(U))   # same seed, same result
    with pytest.raises(ValueError, match="workers"):
        fit_leak_sweep(U, leaks, n_reservoir=60, workers=0)


@pytest.mark.parametrize("washout,cutoff", [(0, 1e-8), (37, 1e-8), (0, "auto"), (11, "auto")])
def test_fit_summarises_the_harvest_as_sfa_does(washout, cutoff, monkeypatch):
    """fit() harvests and accumulates the SFA moments side by side, chunk by chunk; the result
    is the SFA of the features fitted the plain way."""
    import hippo.perception.place_cells as pc
    from hippo.perception.sfa import SFA

    monkeypatch.setattr(pc, "_HARVEST_CHUNK", 173)        # many chunks, one across the split
    U = _walk(T=1300)
    model = RCSFAICA.smc09(n_reservoir=70, washout=washout, sfa_cutoff=cutoff, ica_restarts=1,
                           dtype="float64")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        model.fit(U)
    X = model.features(U)
    np.testing.assert_allclose(model._harvest_summarised(U)[0], X, atol=1e-12)
    ref = SFA(model.params.sfa_params()).fit(X[washout:])
    assert model.sfa_.cutoff_ == ref.cutoff_ and model.sfa_.n_whitened_ == ref.n_whitened_
    np.testing.assert_allclose(model.sfa_.slowness_, ref.slowness_, rtol=1e-8)
    np.testing.assert_allclose(model.sfa_.transform(X), ref.transform(X), atol=1e-7)


def test_presets():
    assert RCSFAICA.smc09().params.n_reservoir == 600
    p = RCSFAICA.icann09().params
    assert (p.n_inputs, p.n_reservoir, p.leak, p.spectral_radius, p.n_sfa, p.n_ica,
            p.downsample) == (17, 400, 0.6, 0.9, 70, 70, 50)
    assert RCSFAICA.smc09(seed=4).params.seed == 4


def test_bad_input(fitted):
    model, U = fitted
    with pytest.raises(ValueError, match=r"shape \(T, 8\)"):
        model.transform(U[:, :5])
    with pytest.raises(ValueError, match=r"shape \(T, 8\)"):
        RCSFAICA().fit(U[:, 0])
    bad = U.copy()
    bad[10, 2] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        RCSFAICA(n_reservoir=20).fit(bad)
    with pytest.raises(ValueError, match="NaN"):
        model.step(np.array([np.nan] * 8))
    with pytest.raises(ValueError, match="shape"):
        model.step(np.zeros(3))
    with pytest.raises(ValueError, match="n_sfa=700 exceeds"):
        RCSFAICA(n_reservoir=20, n_sfa=700, n_ica=4).fit(U)
    with pytest.raises(ValueError, match="n_ica=5 exceeds n_sfa=4"):
        RCSFAICAParams(n_ica=5)
    with pytest.raises(ValueError, match="spectral_radius"):
        RCSFAICA(spectral_radius=0.0)
    with pytest.raises(ValueError, match="spectral_radius"):
        RCSFAICA(spectral_radius=-0.5)
    with pytest.raises(ValueError, match="ticks"):
        RCSFAICA(n_reservoir=20).fit(U[:2])
    with pytest.raises(RuntimeError, match="not fitted"):
        RCSFAICA().step(U[0])
