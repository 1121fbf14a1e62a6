"""The place-cell estimator's file by hand (hippo.perception.place_cell_files): the keys a file
holds with and without a reservoir, a model whose parameters changed after its fit refused
before anything is written, the arrays no part owns (sorted, cut at 200 characters), the output
statistics' checks (a standard deviation of 0 and one of the smallest positive float), a
parameter a later version dropped, what a loaded model holds, each refusal word for word."""

from __future__ import annotations

import json
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from hippo._estimator import NotFittedError
from hippo.io import CorruptFileError, load_npz, save_npz
from hippo.perception.ica import ICAConvergenceWarning
from hippo.perception.place_cell_files import FORMAT, _split, load_model, save_model
from hippo.perception.place_cells import RCSFAICA

SMALL = dict(n_inputs=3, n_reservoir=6, n_sfa=2, n_ica=2, ica_restarts=1, min_fit_ticks=10)


def _walk(T: int = 300, n: int = 3) -> np.ndarray:
    rng = np.random.default_rng(3)
    pos = np.cumsum(rng.standard_normal(T)) * 0.05
    return 0.5 + 0.4 * np.sin(pos[:, None] * np.arange(1, n + 1) + np.arange(n))


def _fit(**kw: Any) -> RCSFAICA:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        return RCSFAICA(**{**SMALL, **kw}).fit(_walk())


@pytest.fixture
def model() -> RCSFAICA:
    return _fit()


@pytest.fixture
def plain() -> RCSFAICA:
    return _fit(use_reservoir=False)


def _arrays(path: Path) -> dict[str, np.ndarray]:
    return load_npz(path)


def _rewrite(src: Path, dst: Path, **change: Any) -> Path:
    a = _arrays(src)
    for k, v in change.items():
        if v is None:
            a.pop(k)
        else:
            a[k] = v
    return save_npz(dst, a)


# --------------------------------------------------------------------------------- saving
def test_a_file_holds_the_tag_the_parameters_and_each_parts_keys(model, plain, tmp_path):
    a = _arrays(save_model(model, tmp_path / "m.npz"))
    assert str(a["format"]) == FORMAT == "hippo.perception.RCSFAICA/1"
    params = json.loads(str(a["params"]))
    assert params["n_reservoir"] == 6 and params["n_ica"] == 2
    own = {"format", "params", "output_std", "output_peak", "W_in", "W_res", "leak"}
    assert own <= set(a)
    assert set(a) - own == ({f"sfa_{k}" for k in model.sfa_.to_arrays()}
                            | {f"ica_{k}" for k in model.ica_.to_arrays()})
    assert a["output_std"].tolist() == model.output_std_.tolist()
    assert a["output_peak"].tolist() == model.output_peak_.tolist()
    assert np.array_equal(a["W_res"], model.reservoir_.to_arrays()["W_res"])
    # without a reservoir: no reservoir keys
    b = _arrays(save_model(plain, tmp_path / "p.npz"))
    assert not {"W_in", "W_res", "leak"} & set(b)
    assert set(b) == own - {"W_in", "W_res", "leak"} | (set(a) - own)


def test_an_unfitted_model_is_not_saved(tmp_path):
    with pytest.raises(NotFittedError):
        save_model(RCSFAICA(**SMALL), tmp_path / "m.npz")
    assert not (tmp_path / "m.npz").exists()


def test_parameters_changed_after_the_fit_are_refused_before_writing(tmp_path):
    m = _fit()
    m.params = m.params.__class__(**{**SMALL, "n_reservoir": 7})
    with pytest.raises(ValueError) as exc:
        save_model(m, tmp_path / "m.npz")
    msg = str(exc.value)
    assert msg.startswith("cannot save this RCSFAICA: its parameters no longer describe its "
                          "fit (")
    assert msg.endswith("); set_params after fit changes the parameters, not the fitted model: "
                        "fit again first")
    assert exc.value.__cause__ is None and exc.value.__suppress_context__
    assert not (tmp_path / "m.npz").exists()


# ------------------------------------------------------------------------------ the owners
def test_arrays_are_split_by_owner():
    a = {"sfa_W": 1, "ica_mean": 2, "W_in": 3, "W_res": 4, "leak": 5, "output_std": 6,
         "other": 7}
    parts = _split(a, True)
    assert parts == {"sfa": {"sfa_W": 1}, "ica": {"ica_mean": 2},
                     "reservoir": {"W_in": 3, "W_res": 4, "leak": 5},
                     "own": {"output_std": 6, "other": 7}}
    # without a reservoir its keys are no part's: the estimator's own, then refused as stray
    parts = _split(a, False)
    assert parts["reservoir"] == {}
    assert parts["own"] == {"W_in": 3, "W_res": 4, "leak": 5, "output_std": 6, "other": 7}


def test_arrays_no_part_owns_are_refused_sorted(plain, tmp_path):
    src = save_model(plain, tmp_path / "p.npz")
    path = _rewrite(src, tmp_path / "d.npz", W_res=np.ones((2, 2)), W_in=np.ones((3, 2)),
                    zeta=np.ones(1))
    with pytest.raises(CorruptFileError) as exc:
        load_model(RCSFAICA, path)
    assert str(exc.value) == (f"{path}: unknown array(s) W_in, W_res, zeta: no part of the "
                              "model owns them")
    many = {f"x{i:03d}": np.ones(1) for i in range(60)}
    path = _rewrite(src, tmp_path / "e.npz", **many)
    with pytest.raises(CorruptFileError) as exc:
        load_model(RCSFAICA, path)
    listed = ", ".join(sorted(many))[:200]
    assert str(exc.value) == f"{path}: unknown array(s) {listed}: no part of the model owns them"


# ----------------------------------------------------------------------- output statistics
def test_output_std_must_be_positive_everywhere(model, tmp_path):
    src = save_model(model, tmp_path / "m.npz")
    for bad, shown in (([1.0, 0.0], "0"), ([-2.0, 1.0], "-2")):
        path = _rewrite(src, tmp_path / "d.npz", output_std=np.array(bad))
        with pytest.raises(CorruptFileError) as exc:
            load_model(RCSFAICA, path)
        assert str(exc.value) == f"{path}: output_std must be > 0 everywhere, got min {shown}"
    tiny = np.nextafter(0.0, 1.0)
    path = _rewrite(src, tmp_path / "t.npz", output_std=np.array([tiny, 1.0]))
    assert load_model(RCSFAICA, path).output_std_.tolist() == [tiny, 1.0]


def test_output_statistics_of_the_wrong_shape_or_missing(model, tmp_path):
    src = save_model(model, tmp_path / "m.npz")
    path = _rewrite(src, tmp_path / "d.npz", output_peak=np.ones(3))
    with pytest.raises(CorruptFileError) as exc:
        load_model(RCSFAICA, path)
    assert str(exc.value) == f"{path}: output_peak must have shape (2,), got (3,)"
    path = _rewrite(src, tmp_path / "s.npz", output_std=np.ones((2, 1)))
    with pytest.raises(CorruptFileError) as exc:
        load_model(RCSFAICA, path)
    assert str(exc.value) == f"{path}: output_std must have shape (2,), got (2, 1)"
    path = _rewrite(src, tmp_path / "n.npz", output_peak=None)
    with pytest.raises(CorruptFileError) as exc:
        load_model(RCSFAICA, path)
    assert str(exc.value) == f"{path}: the RCSFAICA state lacks array(s) output_peak"


# -------------------------------------------------------------------------------- loading
def test_a_loaded_model_holds_its_parts_and_runs(model, tmp_path):
    back = load_model(RCSFAICA, save_model(model, tmp_path / "m.npz"))
    assert type(back) is RCSFAICA and back.params == model.params
    assert back.n_features_in_ == 3
    assert back.sfa_slowness_.tolist() == back.sfa_.slowness_.tolist()
    assert back.sfa_slowness_ is not back.sfa_.slowness_
    assert back.sfa_slowness_.tolist() == model.sfa_slowness_.tolist()
    assert back.output_peak_.tolist() == model.output_peak_.tolist()
    U = _walk()[:30]
    assert np.array_equal(back.transform(U), model.transform(U))
    # reset and compiled: stepping from the start reproduces the offline run
    model.reset_state()
    assert np.array_equal([back.step(u) for u in U], [model.step(u) for u in U])
    # the class given is the one built
    class Mine(RCSFAICA):
        pass
    assert type(load_model(Mine, tmp_path / "m.npz")) is Mine


def test_a_parameter_a_later_version_dropped_is_ignored(model, tmp_path):
    src = save_model(model, tmp_path / "m.npz")
    params = json.loads(str(_arrays(src)["params"]))
    path = _rewrite(src, tmp_path / "x.npz", params=np.array(json.dumps({**params, "gone": 1})))
    assert load_model(RCSFAICA, path).params == model.params


def test_a_file_of_another_kind_or_with_bad_parameters(model, tmp_path):
    src = save_model(model, tmp_path / "m.npz")
    path = _rewrite(src, tmp_path / "v.npz", format=np.array("hippo.perception.RCSFAICA/2"))
    with pytest.raises(CorruptFileError) as exc:
        load_model(RCSFAICA, path)
    assert str(exc.value) == (f"{path}: an RCSFAICA model of format version "
                              "'hippo.perception.RCSFAICA/2': this hippo reads "
                              "'hippo.perception.RCSFAICA/1'")
    params = json.loads(str(_arrays(src)["params"]))
    path = _rewrite(src, tmp_path / "p.npz", params=np.array(json.dumps({**params, "n_ica": 3})))
    with pytest.raises(CorruptFileError) as exc:
        load_model(RCSFAICA, path)
    assert str(exc.value) == f"{path}: bad parameters (n_ica=3 exceeds n_sfa=2)"
    path = _rewrite(src, tmp_path / "r.npz", W_res=None)
    with pytest.raises(CorruptFileError) as exc:
        load_model(RCSFAICA, path)
    assert str(exc.value).startswith(f"{path}: ")
    assert "W_res" in str(exc.value)


def _broken(error: type[Exception]) -> type[RCSFAICA]:
    """An estimator class whose constructor fails (once ``fails`` is set) with ``error``."""

    class Broken(RCSFAICA):
        fails = False

        def __init__(self, params: Any = None, **kw: Any) -> None:
            if Broken.fails:
                raise error("no")
            super().__init__(params, **kw)

    return Broken


@pytest.mark.parametrize("error", [TypeError, KeyError, IndexError, OverflowError])
def test_other_failures_are_an_inconsistent_model_file(model, tmp_path, error):
    path = save_model(model, tmp_path / "m.npz")
    cls = _broken(error)
    cls.fails = True
    with pytest.raises(CorruptFileError) as exc:
        load_model(cls, path)
    assert str(exc.value) == f"{path}: inconsistent model file ({error('no')})"
    assert isinstance(exc.value.__cause__, error)


@pytest.mark.parametrize("error", [ValueError, TypeError, KeyError, IndexError, OverflowError])
def test_any_failure_to_rebuild_refuses_the_save(tmp_path, error):
    cls = _broken(error)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)
        m = cls(**SMALL).fit(_walk())
    cls.fails = True
    with pytest.raises(ValueError) as exc:
        save_model(m, tmp_path / "m.npz")
    assert str(exc.value) == (f"cannot save this Broken: its parameters no longer describe its "
                              f"fit ({error('no')}); set_params after fit changes the "
                              "parameters, not the fitted model: fit again first")
    assert not (tmp_path / "m.npz").exists()


def test_a_value_error_while_loading_names_the_file(model, tmp_path):
    path = save_model(model, tmp_path / "m.npz")
    cls = _broken(ValueError)
    cls.fails = True
    with pytest.raises(CorruptFileError) as exc:
        load_model(cls, path)
    assert str(exc.value) == f"{path}: no"
    assert type(exc.value.__cause__) is ValueError


def _with_params(src: Path, dst: Path, **change: Any) -> Path:
    params = json.loads(str(_arrays(src)["params"]))
    return _rewrite(src, dst, params=np.array(json.dumps({**params, **change})))


def test_the_sfa_state_must_fit_the_parameters_input_width(model, plain, tmp_path):
    # a slow pool doubles SFA's input, [u; x; m]: 2 (3 + 6) = 18 columns for the 9 saved
    path = _with_params(save_model(model, tmp_path / "m.npz"), tmp_path / "p.npz",
                        slow_pool=2.0)
    with pytest.raises(CorruptFileError) as exc:
        load_model(RCSFAICA, path)
    assert str(exc.value) == f"{path}: sfa_mean must have shape (18,), got (9,)"
    # without a reservoir SFA reads u alone: 4 inputs for the 3 saved
    path = _with_params(save_model(plain, tmp_path / "q.npz"), tmp_path / "r.npz", n_inputs=4)
    with pytest.raises(CorruptFileError) as exc:
        load_model(RCSFAICA, path)
    assert str(exc.value) == f"{path}: sfa_mean must have shape (4,), got (3,)"

