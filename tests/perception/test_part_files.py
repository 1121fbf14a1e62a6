"""Each part of RC-SFA-ICA saves and loads its own state; RCSFAICA composes them.

Round trips are bit-identical on transform (and on the reservoir's run and step); the fitted
state's invariants hold after a load; damaged states and files are refused naming the problem;
files in the layout main wrote before the parts saved themselves (a frozen copy of that writer
is below) load and give the same outputs bit for bit.
"""

from __future__ import annotations

import json
import warnings
from dataclasses import asdict

import numpy as np
import pytest

from hippo._estimator import NotFittedError
from hippo.io import CorruptFileError, save_npz
from hippo.perception import RCSFAICA
from hippo.perception.ica import FastICA, ICAConvergenceWarning
from hippo.perception.ica_params import ICAParams
from hippo.perception.reservoir import Reservoir
from hippo.perception.reservoir_params import ReservoirParams
from hippo.perception.sfa import SFA, SFAParams


def _mixture(T=3000, d=7, seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(T)
    S = np.column_stack([np.sin(2 * np.pi * t / 900), np.sign(np.sin(2 * np.pi * t / 410)),
                         *rng.laplace(size=(d - 2, T))])
    return S @ rng.standard_normal((d, d))


def _walk(T=1500, n=8, seed=0):
    rng = np.random.default_rng(seed)
    pos = np.cumsum(rng.standard_normal(T)) * 0.05
    U = 0.5 + 0.4 * np.sin(pos[:, None] * np.arange(1, n + 1) + rng.uniform(0, 6, n))
    return np.clip(U + 0.02 * rng.standard_normal((T, n)), 0, 1)


def _fit(model, X):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        return model.fit(X)


# ------------------------------------------------------------------ round trips
@pytest.mark.parametrize("params", [SFAParams(n_components=3),
                                    SFAParams(n_components=4, cutoff="auto"),
                                    SFAParams(n_components=5, expansion="quadratic")],
                         ids=["linear", "auto", "quadratic"])
def test_sfa_round_trip_is_bit_identical(params, tmp_path):
    X = _mixture(d=5 if params.expansion == "quadratic" else 7)
    sfa = SFA(params).fit(X)
    loaded = SFA.load(sfa.save(tmp_path / "sfa.npz"))
    assert loaded.params == sfa.params
    np.testing.assert_array_equal(loaded.transform(X), sfa.transform(X))
    for name in ("mean_", "scale_", "W_", "slowness_"):
        np.testing.assert_array_equal(getattr(loaded, name), getattr(sfa, name))
    assert (loaded.cutoff_, loaded.n_whitened_) == (sfa.cutoff_, sfa.n_whitened_)
    # in memory too, under a prefix
    again = SFA.from_arrays(params, sfa.to_arrays("x_"), "x_")
    np.testing.assert_array_equal(again.transform(X[:50]), sfa.transform(X[:50]))


def test_sfa_invariants_hold_after_load(tmp_path):
    """On its training data the loaded SFA's outputs are zero-mean, unit-variance,
    decorrelated, ordered by slowness, and each unit's Δ is its stored slowness."""
    X = _mixture()
    loaded = SFA.load(SFA(n_components=4).fit(X).save(tmp_path / "sfa.npz"))
    Y = loaded.transform(X)
    np.testing.assert_allclose(Y.mean(axis=0), 0, atol=1e-8)
    np.testing.assert_allclose(np.cov(Y.T, bias=True), np.eye(4), atol=1e-6)
    np.testing.assert_allclose(np.mean(np.diff(Y, axis=0) ** 2, axis=0), loaded.slowness_,
                               rtol=1e-6)
    assert np.all(np.diff(loaded.slowness_) >= 0)


@pytest.mark.parametrize("params", [ICAParams(n_restarts=2), ICAParams(n_components=3),
                                    ICAParams(algorithm="deflation", whiten=True)],
                         ids=["symmetric", "k<d", "deflation"])
def test_ica_round_trip_is_bit_identical(params, tmp_path):
    X = _mixture(d=4)
    ica = _fit(FastICA(params), X)
    loaded = FastICA.load(ica.save(tmp_path / "ica.npz"))
    assert loaded.params == ica.params
    np.testing.assert_array_equal(loaded.components_, ica.components_)
    np.testing.assert_array_equal(loaded.transform(X), ica.transform(X))
    assert loaded.whitened_ == ica.whitened_
    again = FastICA.from_arrays(params, ica.to_arrays("ica_"), "ica_")
    np.testing.assert_array_equal(again.transform(X[:50]), ica.transform(X[:50]))


def test_ica_invariants_hold_after_load(tmp_path):
    """The loaded unmixing is orthonormal in the white space, and its outputs on the training
    data are unit-variance and decorrelated, with peak responses positive."""
    X = _mixture(d=4)
    loaded = FastICA.load(_fit(FastICA(n_restarts=2), X).save(tmp_path / "ica.npz"))
    R = loaded.rotation_
    np.testing.assert_allclose(R @ R.T, np.eye(4), atol=1e-9)
    S = loaded.transform(X)
    np.testing.assert_allclose(np.cov(S.T, bias=True), np.eye(4), atol=1e-6)
    assert np.all(np.abs(S.max(axis=0)) >= np.abs(S.min(axis=0)))


def test_ica_on_white_input_round_trips_unwhitened(tmp_path):
    X = SFA(n_components=4).fit_transform(_mixture())
    ica = _fit(FastICA(), X)
    assert not ica.whitened_
    loaded = FastICA.load(ica.save(tmp_path / "ica.npz"))
    assert not loaded.whitened_
    np.testing.assert_array_equal(loaded.transform(X), ica.transform(X))


@pytest.mark.parametrize("dtype", ["float32", "float64"])
def test_reservoir_round_trip_is_bit_identical(dtype, tmp_path):
    params = ReservoirParams(n_neurons=30, leak=(0.1, 0.4), seed=3)
    res = Reservoir(params, dtype=dtype)
    loaded = Reservoir.load(res.save(tmp_path / "res.npz"), dtype=dtype)
    assert loaded.params == params and loaded.dtype == dtype
    U = _walk(200)
    np.testing.assert_array_equal(loaded.run(U), res.run(U))
    res.reset()
    np.testing.assert_array_equal([loaded.step(u).copy() for u in U[:20]],
                                  [res.step(u).copy() for u in U[:20]])


def test_reservoir_from_weights_round_trips(tmp_path):
    """A reservoir its seed cannot rebuild (given weights) is saved whole."""
    rng = np.random.default_rng(0)
    W = rng.standard_normal((12, 12))
    res = Reservoir.from_weights(rng.choice([-1.0, 0.0, 1.0], (12, 3)), 0.7 * W, 0.3)
    loaded = Reservoir.load(res.save(tmp_path / "res.npz"))
    U = rng.uniform(size=(60, 3))
    np.testing.assert_array_equal(loaded.run(U), res.run(U))


# ------------------------------------------------------------------ bad states and files
def _sfa():
    return SFA(n_components=3).fit(_mixture())


def _ica():
    return _fit(FastICA(n_components=3), _mixture(d=4))


def test_unfitted_parts_refuse_to_export(tmp_path):
    for part in (SFA(), FastICA()):
        with pytest.raises(NotFittedError, match="not fitted"):
            part.to_arrays()
        with pytest.raises(ValueError, match="not fitted"):
            part.save(tmp_path / "x.npz")
    assert not (tmp_path / "x.npz").exists()
    with pytest.raises(ValueError, match=r"lacks array.*mean.*scale.*W.*slowness"):
        SFA.from_arrays(SFAParams(), {})  # the state of an unfitted SFA: nothing


def test_a_state_that_would_not_load_is_not_saved(tmp_path):
    sfa = _sfa().set_params(n_components=4)  # the fitted W_ has 3 columns
    with pytest.raises(ValueError, match=r"W must have shape \(7, 4\)"):
        sfa.save(tmp_path / "sfa.npz")
    assert not (tmp_path / "sfa.npz").exists()


def _bad(arrays, **change):
    out = dict(arrays)
    for k, v in change.items():
        if v is None:
            del out[k]
        else:
            out[k] = v(out[k]) if callable(v) else v
    return out


@pytest.mark.parametrize(("change", "message"), [
    ({"W": None}, r"SFA state lacks array\(s\) W"),
    ({"slowness": None, "scale": None}, r"lacks array\(s\) scale, slowness"),
    ({"extra": np.zeros(3)}, r"unknown array\(s\) extra"),
    ({"W": lambda a: a[:, :2]}, r"W must have shape \(7, 3\)"),
    ({"mean": lambda a: a[:-1]}, r"scale must have shape \(6,\)"),
    ({"W": lambda a: np.where(a == a.flat[4], np.nan, a)}, r"W contains 1 non-finite"),
    ({"scale": lambda a: -a}, r"scale must be > 0"),
    ({"W": lambda a: a * 1e20}, r"W holds a value of magnitude"),
    ({"W": lambda a: a.astype(str)}, r"W must hold real numbers"),
    ({"cutoff": np.array(2.0)}, r"cutoff=2 must lie in \(0, 1\)"),
    ({"n_whitened": np.array(1)}, r"n_whitened=1 must lie in \[3, 7\]"),
    ({"n_whitened": np.array(4.0)}, r"n_whitened must hold integers"),
    ({"n_whitened": np.array([5])}, r"^n_whitened must have shape \(\), got \(1,\)$"),
    ({"slowness": lambda a: a[:2]}, r"^slowness must have shape \(3,\), got \(2,\)$"),
    ({"cutoff": np.array([1e-8])}, r"^cutoff must have shape \(\), got \(1,\)$"),
    ({"cutoff": np.array(0.0)}, r"^cutoff=0 must lie in \(0, 1\)$"),
    ({"cutoff": np.array(1.0)}, r"^cutoff=1 must lie in \(0, 1\)$"),
    ({"cutoff": np.array(1.5)}, r"^cutoff=1.5 must lie in \(0, 1\)$"),
    # scale at exactly 1e-12 (1 + |mean|) is refused, as fit would have set it to 1
    ({"mean": lambda a: np.r_[0.0, a[1:]], "scale": lambda a: np.r_[1e-12, a[1:]]},
     r"^scale must be > 0 everywhere \(above 1e-12 of the feature's mean, as fit leaves it\)$"),
    ({"mean": lambda a: np.r_[1e6, a[1:]], "scale": lambda a: np.r_[1e-7, a[1:]]},
     r"^scale must be > 0 everywhere \(above 1e-12 of the feature's mean"),
])
def test_sfa_state_refuses_damage(change, message):
    with pytest.raises(ValueError, match=message):
        SFA.from_arrays(SFAParams(n_components=3), _bad(_sfa().to_arrays(), **change))


def test_sfa_state_at_the_edges_of_what_fit_leaves_loads():
    arrays = _sfa().to_arrays()
    # a scale just above 1e-12 (1 + |mean|); n_whitened = n_components
    edge = _bad(arrays, mean=lambda a: np.r_[0.0, a[1:]], scale=lambda a: np.r_[1.5e-12, a[1:]],
                n_whitened=np.array(3))
    sfa = SFA.from_arrays(SFAParams(n_components=3), edge)
    assert sfa.scale_[0] == 1.5e-12 and sfa.n_whitened_ == 3


def _quadratic_arrays():
    X = _mixture(T=600, d=3)
    return SFA(n_components=2, expansion="quadratic").fit(X).to_arrays()


@pytest.mark.parametrize(("change", "kw", "message"), [
    ({}, {"n_features_in": 4}, r"^pre_mean must have shape \(4,\), got \(3,\)$"),
    ({"pre_scale": lambda a: a[:2]}, {}, r"^pre_scale must have shape \(3,\), got \(2,\)$"),
    ({"pre_scale": lambda a: np.r_[a[:2], 0.0]}, {}, r"^pre_scale must be > 0 everywhere$"),
    ({"mean": lambda a: a[:-1]}, {}, r"^mean must have shape \(9,\), got \(8,\)$"),
    ({"n_whitened": np.array(10)}, {}, r"^n_whitened=10 must lie in \[2, 9\]$"),
])
def test_quadratic_sfa_state_refuses_damage(change, kw, message):
    with pytest.raises(ValueError, match=message):
        SFA.from_arrays(SFAParams(n_components=2, expansion="quadratic"),
                        _bad(_quadratic_arrays(), **change), **kw)


def test_sfa_state_must_fit_the_given_input_width_and_expansion():
    arrays = _sfa().to_arrays()
    with pytest.raises(ValueError, match=r"mean must have shape \(9,\)"):
        SFA.from_arrays(SFAParams(n_components=3), arrays, n_features_in=9)
    with pytest.raises(ValueError, match=r"lacks array\(s\) pre_mean, pre_scale"):
        SFA.from_arrays(SFAParams(n_components=3, expansion="quadratic"), arrays)
    with pytest.raises(ValueError, match=r"W must have shape \(7, 4\)"):
        SFA.from_arrays(SFAParams(n_components=4), arrays)


@pytest.mark.parametrize(("change", "message"), [
    ({"rotation": None}, r"FastICA state lacks array\(s\) rotation"),
    ({"W": np.eye(3)}, r"unknown array\(s\) W"),
    ({"rotation": lambda a: 2 * a}, r"rotation is not orthonormal"),
    ({"whitening": lambda a: a.T.copy()}, r"whitening must have shape \(4, 3\)"),
    ({"mean": lambda a: a[:2]}, r"mean has 2 values: fewer inputs than n_components=3"),
    ({"mean": lambda a: a + np.r_[np.inf, 0, 0, 0]}, r"mean contains 1 non-finite"),
])
def test_ica_state_refuses_damage(change, message):
    with pytest.raises(ValueError, match=message):
        FastICA.from_arrays(ICAParams(n_components=3), _bad(_ica().to_arrays(), **change))


@pytest.mark.parametrize(("change", "message"), [
    ({"leak": lambda a: a * 0 + 0.3}, r"leak does not match the parameters' leak"),
    ({"W_res": lambda a: 3 * a}, r"W_res has spectral radius 2\.97"),
    ({"W_in": lambda a: a.T.copy()}, r"W_in must have shape \(20, 8\)"),
    ({"W_in": None}, r"Reservoir state lacks array\(s\) W_in"),
])
def test_reservoir_state_refuses_damage(change, message):
    params = ReservoirParams(n_neurons=20)
    with pytest.raises(ValueError, match=message):
        Reservoir.from_arrays(params, _bad(Reservoir(params).to_arrays(), **change))


def _damaged_file(tmp_path, path, **change):
    with np.load(path) as z:
        arrays = _bad({k: z[k] for k in z.files}, **change)
    np.savez(tmp_path / "bad.npz", **arrays)
    return tmp_path / "bad.npz"


def test_a_file_of_another_kind_or_version_is_refused(tmp_path):
    sfa_file = _sfa().save(tmp_path / "sfa.npz")
    ica_file = _ica().save(tmp_path / "ica.npz")
    res_file = Reservoir(ReservoirParams(n_neurons=5)).save(tmp_path / "res.npz")
    model = RCSFAICA(n_reservoir=20, ica_restarts=1).fit(_walk())
    model_file = model.save(tmp_path / "model.npz")
    with pytest.raises(CorruptFileError, match=r"not a saved SFA \(format 'hippo.perception"
                                               r"\.FastICA/1'"):
        SFA.load(ica_file)
    for loader, wrong in ((FastICA.load, sfa_file), (Reservoir.load, sfa_file),
                          (SFA.load, res_file), (SFA.load, model_file)):
        with pytest.raises(CorruptFileError, match=r"not a saved"):
            loader(wrong)
    with pytest.raises(CorruptFileError, match="not an RCSFAICA model"):
        RCSFAICA.load(sfa_file)
    newer = _damaged_file(tmp_path, sfa_file, format=np.array("hippo.perception.SFA/2"))
    with pytest.raises(CorruptFileError, match=r"format version 'hippo.perception.SFA/2': "
                                               r"this hippo reads 'hippo.perception.SFA/1'"):
        SFA.load(newer)


@pytest.mark.parametrize(("change", "message"), [
    ({"params": np.array("{not json")}, r"unreadable parameters"),
    ({"params": np.array("[1]")}, r"not a JSON object"),
    ({"params": np.array('{"n_components": 3, "colour": 1}')},
     r"unknown SFAParams parameter\(s\) colour"),
    ({"params": np.array('{"n_components": "3"}')}, r"n_components"),
    ({"params": np.array('{"n_components": 5}')}, r"W must have shape \(7, 5\)"),
    ({"params": None}, r"lacks required array\(s\): params"),
    ({"W": lambda a: np.where(a == a.flat[0], np.nan, a)}, r"W contains 1 non-finite"),
    ({"stray": np.ones(2)}, r"unknown array\(s\) stray"),
])
def test_a_damaged_part_file_names_the_problem(tmp_path, change, message):
    path = _damaged_file(tmp_path, _sfa().save(tmp_path / "sfa.npz"), **change)
    with pytest.raises(CorruptFileError, match=message) as err:
        SFA.load(path)
    assert "bad.npz" in str(err.value)


def test_a_model_file_with_an_array_no_part_owns_is_refused(tmp_path):
    plain = RCSFAICA(use_reservoir=False, ica_restarts=1).fit(_walk())
    path = _damaged_file(tmp_path, plain.save(tmp_path / "m.npz"), W_in=np.ones((3, 8)))
    with pytest.raises(CorruptFileError, match=r"unknown array\(s\) W_in"):
        RCSFAICA.load(path)
    path = _damaged_file(tmp_path, plain.save(tmp_path / "m.npz"), sfa_colour=np.ones(2))
    with pytest.raises(CorruptFileError, match=r"SFA state has unknown array\(s\) sfa_colour"):
        RCSFAICA.load(path)


# ------------------------------------------------------------------ the composite file
def _legacy_save(model, path):
    """Frozen copy of main's writer (ba7ff6b, place_cell_files.save_model) from before the
    parts saved themselves: it reads their private attributes."""
    arrays = {
        "format": np.array("hippo.perception.RCSFAICA/1"),
        "params": np.array(json.dumps(asdict(model.params))),
        "sfa_mean": model.sfa_.mean_, "sfa_scale": model.sfa_.scale_, "sfa_W": model.sfa_.W_,
        "sfa_slowness": model.sfa_.slowness_, "sfa_cutoff": np.array(model.sfa_.cutoff_),
        "sfa_n_whitened": np.array(model.sfa_.n_whitened_),
        "ica_mean": model.ica_.mean_, "ica_whitening": model.ica_.whitening_,
        "ica_rotation": model.ica_.rotation_,
        "output_std": model.output_std_, "output_peak": model.output_peak_,
    }
    if model.params.sfa_expansion == "quadratic":
        arrays["sfa_pre_mean"] = model.sfa_.pre_mean_
        arrays["sfa_pre_scale"] = model.sfa_.pre_scale_
    if model.reservoir_ is not None:
        arrays.update(W_in=model.reservoir_.W_in, W_res=model.reservoir_.W_res,
                      leak=model.reservoir_.leak)
    return save_npz(path, arrays)


_MODELS = {
    "reservoir": dict(n_reservoir=24, ica_restarts=1),
    "quadratic": dict(use_reservoir=False, n_sfa=3, n_ica=3, ica_restarts=1,
                      sfa_expansion="quadratic"),
    "auto+pool+downsample": dict(n_reservoir=16, ica_restarts=2, sfa_cutoff="auto",
                                 slow_pool=5.0, downsample=2, n_sfa=3, n_ica=2),
    "float64": dict(n_reservoir=12, ica_restarts=1, dtype="float64", leak=0.3),
}


@pytest.mark.parametrize("kw", _MODELS.values(), ids=_MODELS.keys())
def test_files_in_main_s_layout_load_bit_identically(kw, tmp_path):
    U = _walk()
    model = _fit(RCSFAICA(**kw), U)
    legacy = _legacy_save(model, tmp_path / "legacy.npz")
    new = model.save(tmp_path / "new.npz")
    with np.load(legacy) as a, np.load(new) as b:  # the on-disk layout is unchanged
        assert sorted(a.files) == sorted(b.files)
        for k in a.files:
            assert a[k].dtype == b[k].dtype, k
            np.testing.assert_array_equal(a[k], b[k], err_msg=k)
    for path in (legacy, new):
        loaded = RCSFAICA.load(path)
        np.testing.assert_array_equal(loaded.transform(U), model.transform(U))
        loaded.reset_state()
        model.reset_state()
        np.testing.assert_array_equal([loaded.step(u) for u in U[:40]],
                                      [model.step(u) for u in U[:40]])


def test_an_old_file_without_the_sfa_diagnostics_loads_and_saves_again(tmp_path):
    """Files from before sfa_cutoff / sfa_n_whitened were written: they load (the two read as
    unknown) and the model saves again to a file that loads (they are left out)."""
    U = _walk()
    model = _fit(RCSFAICA(n_reservoir=20, ica_restarts=1), U)
    path = _damaged_file(tmp_path, model.save(tmp_path / "m.npz"), sfa_cutoff=None,
                         sfa_n_whitened=None)
    old = RCSFAICA.load(path)
    assert np.isnan(old.sfa_.cutoff_) and old.sfa_.n_whitened_ == -1
    again = RCSFAICA.load(old.save(tmp_path / "again.npz"))
    np.testing.assert_array_equal(again.transform(U), model.transform(U))


def test_the_model_file_is_its_parts_states(tmp_path):
    """Each part of a loaded model is what that part's own loader makes of its keys."""
    U = _walk()
    model = _fit(RCSFAICA(n_reservoir=20, ica_restarts=1), U)
    with np.load(model.save(tmp_path / "m.npz")) as z:
        arrays = {k: z[k] for k in z.files}
    p = model.params
    sfa = SFA.from_arrays(p.sfa_params(), {k: v for k, v in arrays.items()
                                           if k.startswith("sfa_")}, "sfa_")
    ica = FastICA.from_arrays(p.ica_params(), {k: v for k, v in arrays.items()
                                               if k.startswith("ica_")}, "ica_")
    res = Reservoir.from_arrays(p.reservoir_params(), {k: arrays[k]
                                                      for k in ("W_in", "W_res", "leak")})
    X = model.features(U)
    np.testing.assert_array_equal(ica.transform(sfa.transform(X)),
                                  model.ica_.transform(model.sfa_.transform(X)))
    np.testing.assert_array_equal(res.run(U), model.reservoir_.run(U))
