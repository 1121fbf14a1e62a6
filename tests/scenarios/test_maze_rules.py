"""The maze scenario (:mod:`hippo.scenarios.maze`) on hand-made inputs and stand-ins: its
options' defaults and bounds, --washout's words, the checks across options on their bounds and
one step past (the samples left by --downsample, the training updates left by the washout, a
stand-in automatic washout and which option it blames, --quick's 60,000 ticks, the units against
the SFA inputs), the analysis on a stand-in model (the labels at the centre of the window,
clipped to the recording, the training part after the washout, the windows as long as the test
part, the closed loop's held read-out worked out tick by tick), the supervised ceiling, the
statistics over seeds, and run's wiring on stand-ins for the recording, the fits and the
figures (the fits asked for, the metrics and the summary line by hand)."""

from __future__ import annotations

import argparse
import math
import warnings
from dataclasses import dataclass, replace
from types import SimpleNamespace
from typing import Any, ClassVar

import numpy as np
import pytest

import hippo.scenarios.maze as Z
from hippo.cli_args import sfa_cutoff as cli_sfa_cutoff
from hippo.perception import ICAConvergenceWarning
from hippo.perception import metrics as M
from hippo.runner import parse_scenario_args, scenario_parser
from hippo.scenarios._common import sfa_cutoff


def test_the_constants():
    assert Z.TARGETS == {"localized_units": 60, "location_decoding_within_one_step_test": 0.85}
    assert (Z.MIN_TICKS, Z.MIN_SAMPLES, Z.MIN_FIT) == (5000, 200, 100)


def _parse(argv: list[str]) -> argparse.Namespace:
    return parse_scenario_args("maze", argv)[0]


def _refused(capsys, argv: list[str]) -> str:
    with pytest.raises(SystemExit) as e:
        _parse(argv)
    assert e.value.code == 2
    err = capsys.readouterr().err
    head, tail = "hippo run maze: error: ", " (see hippo run maze --help)\n"
    assert err.startswith(head) and err.endswith(tail)
    return err[len(head):-len(tail)]


def test_the_defaults():
    a = _parse([])
    assert (a.ticks, a.rho, a.downsample, a.neurons, a.units) == (350_000, 0.0, 25, 400, 70)
    assert (a.leak, a.spectral_radius, a.seeds, a.cache) == (0.6, 0.99, 1, None)
    assert (a.ceiling, a.ablation, a.figures) == (True, True, True)
    assert (a.ica_restarts, a.ica_score, a.washout) == (3, "kurtosis", "auto")
    assert a.sfa_cutoff == cli_sfa_cutoff("2e-6") and a.threshold == M.ICANN09_THRESHOLD == 4.5


@pytest.mark.parametrize(("option", "ok", "bad"), [
    ("--ticks", ["5000", "100000000"], ["4999", "100000001"]),
    ("--downsample", ["1", "1000"], ["0", "1001"]),
    ("--neurons", ["1", "20000"], ["0", "20001"]),
    ("--units", ["1", "17"], ["0", "501"]),
    ("--leak", ["1", "5e-324"], ["0", "1.0000000000000002"]),
    ("--spectral-radius", ["5e-324", "0.9999999999999999"], ["0", "1"]),
    ("--ica-restarts", ["1", "1000"], ["0", "1001"]),
    ("--threshold", ["5e-324", "1000"], ["0", "1000.0000000000001"]),
    ("--rho", ["0", "1"], ["-5e-324", "1.0000000000000002"]),
    ("--ica-score", ["kurtosis", "sparseness", "slowness"], ["bogus"]),
])
def test_the_options_bounds(capsys, option, ok, bad):
    base = ["--washout", "0"] + (["--units", "1"] if option != "--units" else [])
    for v in ok:
        assert _parse([*base, option, v]) is not None
    for v in bad:
        assert _refused(capsys, [*base, option, v]).startswith(f"argument {option}: ")


def test_the_help():
    parser, _ = scenario_parser("maze")
    helps = {a.option_strings[0]: a.help for a in parser._actions if a.option_strings}
    assert {k: helps[k] for k in list(helps)[4:]} == {
        "--ticks": "recorded control ticks of 0.2 s (at least 5000)",
        "--rho": "wall-side switch probability (0: a full tour)",
        "--downsample": "input down-sampling factor (ICANN09: 50 for a 2x slower tour; 25 keeps "
                        "its ~260 samples per maze tour)",
        "--neurons": "reservoir size",
        "--units": "SFA and ICA units",
        "--leak": "reservoir leak rate",
        "--spectral-radius": "reservoir spectral radius (ICANN09: 0.9, 'arbitrarily chosen'; "
                             "0.99, SMC09's, decodes better here)",
        "--seeds": helps["--seeds"],
        "--cache": helps["--cache"],
        "--ceiling": "also report the supervised ceiling (ridge on the reservoir state)",
        "--ica-restarts": "FastICA restarts, best kept by --ica-score (no labels)",
        "--ica-score": "label-free score that picks the ICA restart",
        "--sfa-cutoff": "relative whitening cutoff in (0, 1), or 'auto' (the SFA default 1e-8 "
                        "gives fewer localized units here)",
        "--washout": "reservoir updates left out at the start of the fit, or 'auto': until the "
                     "start from rest has faded to 1e-3 (1150 here); 0: none (ICA then spends "
                     "~4 units on the start-up transient)",
        "--threshold": "localization threshold in training s.d. (ICANN09: 4.5)",
        "--ablation": "also fit the no-reservoir, quadratic-SFA ablation",
        "--figures": "write PNGs"}
    assert helps["--seeds"].startswith("reservoirs to repeat over (the exploration run is "
                                       "--seed's): a count N")
    # the automatic washout the help names, at the defaults (leak 0.6, radius 0.99, by 25):
    # r = 1 - 0.6 + 0.6 x 0.99 = 0.994, ceil(ln 1e-3 / ln 0.994) = 1148, + 2 for the filter
    assert math.ceil(math.log(1e-3) / math.log(1 - 0.6 + 0.6 * 0.99)) + 2 == 1150
    args = _parse([])
    assert replace(Z.ICANN09, leak=args.leak, spectral_radius=args.spectral_radius,
                   downsample=args.downsample).transient_updates() == 1150
    a = _parse(["--no-ceiling", "--no-ablation", "--no-figures"])
    assert (a.ceiling, a.ablation, a.figures) == (False, False, False)
    a = _parse(["--ceiling", "--ablation", "--figures"])
    assert (a.ceiling, a.ablation, a.figures) == (True, True, True)
    assert _parse(["--neurons", "20000", "--units", "500", "--no-ablation"]).units == 500


def test_units_past_500_are_refused_before_the_inputs(capsys):
    argv = ["--neurons", "20000", "--units", "501", "--no-ablation"]
    assert _refused(capsys, argv).startswith("argument --units: ")
    assert "exceeds" not in _refused(capsys, argv)


@pytest.mark.parametrize(("text", "value"), [("auto", "auto"), (" auto ", "auto"), ("0", 0),
                                             ("10000000", 10_000_000), ("114", 114)])
def test_washout_takes_auto_or_a_count(text, value):
    assert Z._washout(text) == value


@pytest.mark.parametrize("text", ["-1", "10000001", "soon", "1.5", "Auto", ""])
def test_washout_refuses_the_rest_word_for_word(text):
    with pytest.raises(argparse.ArgumentTypeError) as e:
        Z._washout(text)
    assert str(e.value) == (f"got {text!r}; needs a number of reservoir updates >= 0, "
                            "or 'auto'")
    assert e.value.__cause__ is None and e.value.__suppress_context__


@pytest.fixture
def auto(monkeypatch):
    """A stand-in for ICANN09 whose transient_updates gives ``auto.value`` and notes the
    leak, spectral radius and down-sampling it was given."""
    seen: list[tuple] = []

    @dataclass(frozen=True)
    class Params:
        leak: float = -1.0
        spectral_radius: float = -1.0
        downsample: int = -1

        def transient_updates(self) -> int:
            seen.append((self.leak, self.spectral_radius, self.downsample))
            return state.value

    state = SimpleNamespace(value=0, seen=seen)
    monkeypatch.setattr(Z, "ICANN09", Params())
    return state


def test_the_samples_left_by_downsampling(capsys, auto):
    # 5000 ticks // 25 = 200 samples: taken; // 26 = 192: refused
    assert _parse(["--ticks", "5000", "--downsample", "25"]).ticks == 5000
    assert _refused(capsys, ["--ticks", "5000", "--downsample", "26"]) == (
        "argument --ticks: 5000 ticks down-sampled by 26 leave 192 samples; at least 200 are "
        "needed (more ticks or a smaller --downsample)")
    # --quick: at most 60,000 ticks; 60000 // 300 = 200, // 301 = 199
    assert _parse(["--quick", "--ticks", "70000", "--downsample", "300"]).ticks == 70000
    assert _refused(capsys, ["--quick", "--ticks", "70000", "--downsample", "301"]) == (
        "argument --ticks: 60000 (--quick) ticks down-sampled by 301 leave 199 samples; at "
        "least 200 are needed (more ticks or a smaller --downsample)")
    # --quick with fewer ticks keeps them: 5000 // 26 = 192
    assert _refused(capsys, ["--quick", "--ticks", "5000", "--downsample", "26"]) == (
        "argument --ticks: 5000 (--quick) ticks down-sampled by 26 leave 192 samples; at "
        "least 200 are needed (more ticks or a smaller --downsample)")


def test_a_given_washout_must_leave_100_training_updates(capsys, auto):
    # 6000 ticks: 5000 training ticks // 25 = 200 updates; a washout of 100 leaves 100
    assert _parse(["--ticks", "6000", "--washout", "100"]).washout == 100
    assert _refused(capsys, ["--ticks", "6000", "--washout", "101"]) == (
        "argument --washout: a washout of 101 leaves fewer than 100 of the 200 training "
        "updates of 6000 ticks (a smaller --downsample or --washout, or more --ticks)")
    # --quick: 60,000 ticks, 50,000 // 25 = 2000 updates, whatever --ticks says
    assert _refused(capsys, ["--quick", "--washout", "1901"]) == (
        "argument --washout: a washout of 1901 leaves fewer than 100 of the 2000 training "
        "updates of 60000 (--quick) ticks (a smaller --downsample or --washout, or more "
        "--ticks)")
    assert _parse(["--quick", "--washout", "1900"]).washout == 1900
    assert auto.seen == []          # a given washout asks for no automatic one


def test_an_automatic_washout_blames_the_option_set(capsys, auto):
    auto.value = 100
    assert _parse(["--ticks", "6000", "--leak", "0.5", "--spectral-radius", "0.8"])
    assert auto.seen == [(0.5, 0.8, 25)]
    auto.value = 101
    assert _refused(capsys, ["--ticks", "6000"]) == (
        "argument --ticks: a washout of 101 (auto) leaves fewer than 100 of the 200 training "
        "updates of 6000 ticks (a smaller --downsample or --washout, or more --ticks)")
    # 6000 ticks // 30: 166 updates; --downsample named before --ticks
    auto.value = 66
    assert _parse(["--ticks", "6000", "--downsample", "30"]).downsample == 30
    auto.value = 67
    assert _refused(capsys, ["--ticks", "6000", "--downsample", "30"]) == (
        "argument --downsample: a washout of 67 (auto) leaves fewer than 100 of the 166 "
        "training updates of 6000 ticks (a smaller --downsample or --washout, or more --ticks)")
    assert auto.seen[-1] == (0.6, 0.99, 30)
    # neither set: the washout itself
    auto.value = 1901
    assert _refused(capsys, ["--quick"]) == (
        "argument --washout: a washout of 1901 (auto) leaves fewer than 100 of the 2000 "
        "training updates of 60000 (--quick) ticks (a smaller --downsample or --washout, or "
        "more --ticks)")


def test_the_units_against_the_sfa_inputs(capsys, auto):
    assert _parse(["--neurons", "10", "--units", "27"]).units == 27
    assert _refused(capsys, ["--neurons", "10", "--units", "28"]) == (
        "argument --units: 28 exceeds the 27 inputs of SFA (--neurons + 17 rays)")


def test_the_units_against_the_ablations_inputs(capsys, auto):
    # the ablation's SFA reads the 17 rays expanded quadratically: 17 + 17 x 18 / 2 = 170
    assert 17 + 17 * 18 // 2 == 170
    assert _parse(["--units", "170"]).units == 170
    assert _refused(capsys, ["--units", "171"]) == (
        "argument --units: 171 exceeds the 170 inputs of the ablation's SFA (the 17 rays, "
        "quadratic); fewer --units, or --no-ablation")
    # --quick fits 20 units of at most 100 neurons whatever --units and --neurons ask: it is
    # those that must fit the inputs
    assert _parse(["--quick", "--units", "171"]).units == 171
    assert _parse(["--quick", "--neurons", "10", "--units", "30"]).units == 30
    assert _parse(["--quick", "--neurons", "3", "--units", "30"]).units == 30
    assert _refused(capsys, ["--quick", "--neurons", "2", "--units", "30"]) == (
        "argument --units: 20 (--quick: 20 units of 2 neurons) exceeds the 19 inputs of SFA "
        "(--neurons + 17 rays)")
    assert _parse(["--units", "171", "--no-ablation"]).units == 171
    # the reservoir's inputs are checked first
    assert _refused(capsys, ["--neurons", "10", "--units", "171"]) == (
        "argument --units: 171 exceeds the 27 inputs of SFA (--neurons + 17 rays)")


def test_stats_over_seeds():
    s = Z._stats([1, 2, 3, 4])
    assert s["mean"] == 2.5 and s["sd"] == pytest.approx(math.sqrt(5 / 3), rel=1e-15)
    assert s["per_seed"] == [1.0, 2.0, 3.0, 4.0] and all(type(v) is float for v in s["per_seed"])
    assert set(s) == {"mean", "sd", "per_seed"}


# _analyse: 27 ticks, down-sampled by 3: 8 samples at ticks 3 k + 2, 3 units
TICKS = np.array([2, 5, 8, 11, 14, 17, 20, 23])
#: unit winning each sample
WIN = [0, 1, 2, 0, 1, 2, 0, 1]
NB5 = np.abs(np.subtract.outer(np.arange(5), np.arange(5))) <= 1    # a line of 5 places


class Model:
    def __init__(self, delay: float, washout: int = 1) -> None:
        self.delay = delay
        self.params = SimpleNamespace(washout=washout, downsample=3)
        self.Yd = np.eye(3)[WIN] * 2.0
        self.Ysd = np.arange(16.0).reshape(8, 2)
        self.sfa_ = SimpleNamespace(n_whitened_=np.int64(11), cutoff_=np.float32(0.5))
        self.ica_ = SimpleNamespace(converged_=np.bool_(True), n_iter_=np.int32(9))

    def transform(self, U, return_sfa: bool, upsample: bool):
        assert return_sfa is True and upsample is False and U.shape == (27, 2)
        return self.Yd, self.Ysd

    def sample_ticks(self, T: int):
        assert T == 27
        return TICKS, self.delay


@pytest.fixture
def metrics(monkeypatch):
    calls: dict[str, list] = {"loc": [], "dec": [], "winner": [], "centroid": []}
    counts = iter(range(10, 100))

    def localized(Y, lab, nb, threshold):
        calls["loc"].append((Y, lab, nb, threshold))
        return SimpleNamespace(count=next(counts), peak=np.array([4.5, 4.4999, 5.0]),
                               preferred=np.array([2, 2, 1]),
                               localized=np.array([True, True, True]))

    def accuracy(Y, lab, mapping, nb):
        calls["dec"].append((Y, lab, mapping, nb))
        return len(calls["dec"]) / 10, len(calls["dec"]) / 100

    def winner(Y, lab, n):
        calls["winner"].append((Y, lab, n))
        return np.array([3, -1, 4])

    def centroid(Y, lab, n):
        calls["centroid"].append((Y, lab, n))
        return "CENTROIDS"

    monkeypatch.setattr(M, "localized_units", localized)
    monkeypatch.setattr(M, "decoding_accuracy", accuracy)
    monkeypatch.setattr(M, "fit_winner_decoder", winner)
    monkeypatch.setattr(M, "fit_centroid_decoder", centroid)
    return calls


def _same(a, b) -> bool:
    return np.array_equal(np.asarray(a), np.asarray(b))


def test_analyse_labels_splits_and_the_online_read_out(metrics):
    model, U = Model(delay=1.2), np.zeros((27, 2))
    labels = np.arange(27) % 5
    res = Z._analyse(model, U, labels, 18, NB5, 5, 4.5)
    # the window's centre: round(3 k + 2 - 1.2) = 3 k + 1
    aligned = [1, 4, 7, 10, 13, 16, 19, 22]
    assert _same(res["_aligned"], aligned) and _same(res["_lab"], [1, 4, 2, 0, 3, 1, 4, 2])
    # tick 18 falls before sample 6 (tick 20): training samples 1..5 after a washout of 1
    assert res["_k_tr"] == 6 and res["_ticks"] is TICKS
    Yd, lab = model.Yd, res["_lab"]
    loc = metrics["loc"]
    assert _same(loc[0][0], Yd[6:8]) and _same(loc[0][1], lab[6:8])      # the test part
    assert _same(loc[1][0], Yd[1:6]) and _same(loc[1][1], lab[1:6])      # the training part
    # windows of 2 samples from the washout: 1-2 and 3-4 (5-6 would reach the test part)
    assert _same(loc[2][0], Yd[1:3]) and _same(loc[3][0], Yd[3:5]) and len(loc) == 4
    assert all(c[2] is NB5 and c[3] == 4.5 for c in loc)
    assert res["localized_units"] == 10 and res["localized_units_train"] == 11
    assert res["localized_units_train_windows"] == 12.5
    assert res["units_peak_over_threshold"] == 2         # 4.5 and 5.0 reach 4.5, 4.4999 not
    assert res["locations_coded"] == 2                   # places 2, 2 and 1
    (w_Y, w_lab, w_n), = metrics["winner"]
    assert _same(w_Y, Yd[1:6]) and _same(w_lab, lab[1:6]) and w_n == 5
    assert _same(metrics["centroid"][0][0], Yd[1:6]) and metrics["centroid"][0][2] == 5
    assert _same(metrics["centroid"][0][1], lab[1:6])
    assert _same(loc[2][1], lab[1:3]) and _same(loc[3][1], lab[3:5])
    d = metrics["dec"]
    assert _same(d[0][0], Yd[6:8]) and _same(d[0][1], lab[6:8]) and _same(d[0][2], [3, -1, 4])
    assert _same(d[1][0], Yd[1:6]) and _same(d[1][1], lab[1:6])
    assert _same(d[2][0], Yd[6:8]) and d[2][2] == "CENTROIDS" and all(c[3] is NB5 for c in d)
    assert (res["location_decoding_accuracy_test"],
            res["location_decoding_within_one_step_test"]) == (0.1, 0.01)
    assert (res["location_decoding_accuracy_train"],
            res["location_decoding_within_one_step_train"]) == (0.2, 0.02)
    assert (res["population_decoding_accuracy_test"],
            res["population_decoding_within_one_step_test"]) == (0.3, 0.03)
    # online: tick t holds sample (t + 1) // 3 - 1; ticks 18..26 hold 5 5 6 6 6 7 7 7 and 8,
    # past the last sample, the last one (7). Winners 2 2 0 0 0 1 1 1 1 -> places
    # 4 4 3 3 3 -1 -1 -1 -1 against labels 3 4 0 1 2 3 4 0 1: exactly 1 of 9 (tick 19), within
    # one step 3 of 9 (ticks 18, 19, 22); a unit of no place (-1) is never right
    assert res["location_decoding_accuracy_test_online"] == pytest.approx(1 / 9, rel=1e-15)
    assert res["location_decoding_within_one_step_test_online"] == pytest.approx(1 / 3,
                                                                                rel=1e-15)
    assert (res["sfa_whitened_dims"], res["sfa_cutoff"], res["ica_converged"],
            res["ica_iterations"]) == (11, 0.5, True, 9)
    assert [type(res[k]) for k in ("sfa_whitened_dims", "sfa_cutoff", "ica_converged",
                                   "ica_iterations", "localized_units")] == [
        int, float, bool, int, int]
    assert res["_Yd"] is Yd and res["_Ysd"] is model.Ysd and res["_loc"].count == 10


@pytest.mark.parametrize(("delay", "aligned"), [
    (2.6, [0, 2, 5, 8, 11, 14, 17, 20]),      # round(-0.6) = -1, clipped to the first tick
    (-1.6, [4, 7, 10, 13, 16, 19, 22, 25]),
    (-4.6, [7, 10, 13, 16, 19, 22, 25, 26]),  # round(27.6) = 28, clipped to the last (26)
])
def test_analyse_clips_the_windows_centre_to_the_recording(metrics, delay, aligned):
    res = Z._analyse(Model(delay), np.zeros((27, 2)), np.arange(27) % 5, 18, NB5, 5, 4.5)
    assert _same(res["_aligned"], aligned)
    assert _same(res["_lab"], np.array(aligned) % 5)


def test_analyse_without_a_window_and_with_another_washout(metrics):
    # washout 4: training samples 4 and 5; the test part (2 samples) leaves no whole window
    # from 4 that ends before sample 6 except 4-5
    res = Z._analyse(Model(1.2, washout=4), np.zeros((27, 2)), np.arange(27) % 5, 18, NB5, 5,
                     4.5)
    assert len(metrics["loc"]) == 3 and res["localized_units_train_windows"] == 12
    with warnings.catch_warnings():
        warnings.simplefilter("error")     # no mean of an empty list ("Mean of empty slice")
        res = Z._analyse(Model(1.2, washout=5), np.zeros((27, 2)), np.arange(27) % 5, 18, NB5,
                         5, 4.5)
    assert math.isnan(res["localized_units_train_windows"])
    assert _same(metrics["loc"][-1][0], Model(1.2).Yd[5:6])   # the training part: sample 5


def test_the_ceiling_reads_the_reservoirs_features(monkeypatch):
    seen = []

    def ridge(X, lab, n, folds, gap):
        seen.append((X, lab, n, folds, gap))
        return SimpleNamespace(accuracy=0.625, predicted=np.array([0, 1, 4, 2]))

    monkeypatch.setattr(M, "ridge_ceiling", ridge)
    model = SimpleNamespace(features=lambda U: ("X", U))
    lab = np.array([0, 3, 4, 0])
    out = Z._ceiling(model, "U", {"_lab": lab}, NB5, 5)
    assert seen == [(("X", "U"), lab, 5, 5, 20)]
    # predicted 0 1 4 2 against 0 3 4 0: within one step at 0-0, 4-4 (1-3 and 2-0 are 2 away)
    assert out == {"ceiling_location_decoding_accuracy": 0.625,
                   "ceiling_location_decoding_within_one_step": 0.5}


class Fits:
    """A stand-in RCSFAICA: icann09's settings, the washout, the fitted rows, the files saved."""

    made: ClassVar[list[Fits]] = []

    def __init__(self, params, washout: int | None = None, kw: dict | None = None) -> None:
        self.params, self.washout, self.kw = params, washout, kw
        self.fitted: np.ndarray | None = None
        self.saved: list = []
        Fits.made.append(self)

    @classmethod
    def icann09(cls, **kw: Any) -> Fits:
        updates = 7 if kw.get("use_reservoir", True) else 3
        return cls(SimpleNamespace(transient_updates=lambda: updates), kw=kw)

    def fit(self, U: np.ndarray) -> Fits:
        warnings.warn("no convergence", ICAConvergenceWarning, stacklevel=1)
        self.fitted = U
        return self

    def save(self, path) -> None:
        self.saved.append(path)


RESULTS = [  # what the stand-in _analyse gives per fit: seed 3, seed 8, the ablation
    dict(localized_units=50, location_decoding_accuracy_test=0.5,
         location_decoding_within_one_step_test=0.8, population_decoding_accuracy_test=0.6,
         population_decoding_within_one_step_test=0.95, ica_converged=True),
    dict(localized_units=60, location_decoding_accuracy_test=0.7,
         location_decoding_within_one_step_test=0.9, population_decoding_accuracy_test=0.8,
         population_decoding_within_one_step_test=0.97, ica_converged=False),
    dict(localized_units=20, location_decoding_accuracy_test=0.25,
         location_decoding_within_one_step_test=0.4, population_decoding_accuracy_test=0.3,
         population_decoding_within_one_step_test=0.5, ica_converged=True),
]


def _run(monkeypatch, tmp_path, **over: Any):
    Fits.made = []
    calls: dict[str, list] = {k: [] for k in ("cached", "record", "analyse", "ceiling",
                                              "figures", "npz", "metrics", "nb")}
    arena = SimpleNamespace(locations=[(0, 0)] * 5, wall_array=lambda: "WALLS")
    T = over.pop("T", 125)
    rec = SimpleNamespace(sensors=np.arange(T * 17.0).reshape(T, 17),
                          label=(np.arange(T) // 10 % 5).astype(float), t=np.arange(T) * 0.2,
                          x=3.0 * np.arange(T), y=4.0 * np.arange(T))

    def cached(cache, key, build, ticks):
        calls["cached"].append((cache, key, ticks))
        return build()

    def analyse(model, U, labels, n_train, nb, n_loc, threshold):
        i = len(calls["analyse"])
        calls["analyse"].append((model, U, labels, n_train, nb, n_loc, threshold))
        return {**RESULTS[i], "_Yd": f"Yd{i}", "_Ysd": f"Ysd{i}", "_ticks": f"ticks{i}",
                "_aligned": f"aligned{i}"}

    monkeypatch.setattr(Z, "arenas", SimpleNamespace(maze_e1=lambda: arena))
    monkeypatch.setattr(M, "location_neighbors",
                        lambda locs, walls: calls["nb"].append((locs, walls)) or NB5)
    monkeypatch.setattr(Z, "cached_recording", cached)
    monkeypatch.setattr(Z, "record", lambda *a, **k: calls["record"].append((a, k)) or rec)
    monkeypatch.setattr(Z, "RCSFAICA", Fits)
    monkeypatch.setattr(Z, "_analyse", analyse)
    monkeypatch.setattr(Z, "_ceiling", lambda model, U, res, nb, n: calls["ceiling"].append(
        (model, U, res["_Yd"], nb, n)) or {"ceiling_location_decoding_accuracy": 0.9})

    class Bar:
        def __init__(self, total: int, desc: str) -> None:
            calls.setdefault("bar", []).append([total, desc, 0])

        def __enter__(self) -> Bar:
            return self

        def __exit__(self, *exc: object) -> None:
            return None

        def update(self) -> None:
            calls["bar"][-1][2] += 1

    monkeypatch.setattr(Z, "Progress", Bar)
    monkeypatch.setattr(Z, "_figures", lambda *a: calls["figures"].append(a))
    monkeypatch.setattr(Z, "save_npz", lambda path, arrays: calls["npz"].append((path, arrays)))
    monkeypatch.setattr(Z, "write_metrics", lambda out, m, summary: calls["metrics"].append(
        (out, summary, m)))
    args = argparse.Namespace(
        out=str(tmp_path), quick=False, ticks=T, rho=0.25, downsample=5, neurons=150, units=4,
        leak=0.5, spectral_radius=0.9, seed=3, seeds=[3, 8], cache="CACHE", ceiling=True,
        ica_restarts=2, ica_score="sparseness", sfa_cutoff="2e-06", washout="auto",
        threshold=4.25, ablation=True, figures=True)
    for k, v in over.items():
        setattr(args, k, v)
    # the clock: the recording 2.5 s, the fits 1.25, 0.5 and 3 s
    clock = iter([100.0, 102.5, 110.0, 111.25, 120.0, 120.5, 130.0, 133.0])
    monkeypatch.setattr(Z, "time", SimpleNamespace(perf_counter=lambda: next(clock)))
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # only ICA's convergence warning is silenced
        m = Z.run(args)
    return m, calls, arena, rec


def test_run_fits_each_reservoir_and_the_ablation(monkeypatch, tmp_path):
    m, calls, arena, rec = _run(monkeypatch, tmp_path)
    assert calls["nb"] == [(arena.locations, "WALLS")]
    assert calls["cached"] == [("CACHE", "maze_t125_rho0.25_s3", 125)]
    assert calls["record"] == [((arena, 125), dict(seed=3, rho=0.25, sensors="ray17",
                                                   desc="maze"))]
    common = dict(n_inputs=17, downsample=5, n_sfa=4, n_ica=4, ica_restarts=2,
                  ica_score="sparseness", sfa_cutoff=sfa_cutoff("2e-06"))
    made = Fits.made
    # icann09's settings, then the same params with the washout; fitted on the first 100 ticks
    # (125 * 5 // 6 = 104, down to a multiple of 5)
    assert [f.kw for f in made[0::2]] == [
        dict(n_reservoir=150, leak=0.5, spectral_radius=0.9, seed=3, **common),
        dict(n_reservoir=150, leak=0.5, spectral_radius=0.9, seed=8, **common),
        dict(use_reservoir=False, sfa_expansion="quadratic", seed=3, **common)]
    fitted = made[1::2]
    assert [f.washout for f in fitted] == [7, 7, 3]
    assert all(f.params is g.params for f, g in zip(fitted, made[0::2]))
    assert all(_same(f.fitted, rec.sensors[:100]) for f in fitted)
    assert [c[0] for c in calls["analyse"]] == fitted
    for c in calls["analyse"]:
        assert c[1] is rec.sensors and c[3:] == (100, NB5, 5, 4.25)
        assert _same(c[2], np.arange(125) // 10 % 5) and c[2].dtype.kind == "i"
    # the ceiling for the reservoirs only; the first reservoir saved, and kept for the figures
    assert [c[0] for c in calls["ceiling"]] == fitted[:2]
    assert all(c[1] is rec.sensors for c in calls["ceiling"])
    assert calls["bar"] == [[3, "maze fits", 3]]
    assert [c[2:] for c in calls["ceiling"]] == [("Yd0", NB5, 5), ("Yd1", NB5, 5)]
    assert fitted[0].saved == [tmp_path / "place_cells.npz"] and fitted[1].saved == []
    assert m["washout_updates"] == {"rc_sfa_ica": 7, "no_reservoir_quadratic": 3}
    (fig,) = calls["figures"]
    assert fig[0] == tmp_path and fig[1] is arena and fig[2] is rec and fig[4:] == (4.25, 5)
    assert [fig[3][k]["_Yd"] for k in ("rc_sfa_ica", "no_reservoir_quadratic")] == ["Yd0", "Yd2"]
    (path, arrays), = calls["npz"]
    assert path == tmp_path / "run.npz"
    assert arrays["n_train"] == 100 and arrays["t"] is rec.t and arrays["label"] is rec.label
    assert (arrays["x"], arrays["y"]) == (rec.x, rec.y)
    assert [arrays[k] for k in ("sample_ticks", "aligned_ticks", "Y", "Ysfa", "Y_ablation")] \
        == ["ticks0", "aligned0", "Yd0", "Ysd0", "Yd2"]


def test_run_metrics_and_summary_by_hand(monkeypatch, tmp_path):
    m, calls, _, _ = _run(monkeypatch, tmp_path)
    assert {k: m[k] for k in (
        "scenario", "paper", "quick", "seed", "ticks", "train_ticks", "test_ticks",
        "downsample", "samples", "neurons", "units", "leak", "spectral_radius", "rho",
        "ica_restarts", "ica_score", "threshold", "reservoir_seeds", "recording_seed")} == {
        "scenario": "maze", "paper": "ICANN09", "quick": False, "seed": 3, "ticks": 125,
        "train_ticks": 100, "test_ticks": 25, "downsample": 5, "samples": 25, "neurons": 150,
        "units": 4, "leak": 0.5, "spectral_radius": 0.9, "rho": 0.25, "ica_restarts": 2,
        "ica_score": "sparseness", "threshold": 4.25, "reservoir_seeds": [3, 8],
        "recording_seed": 3}
    # labels tick // 10 % 5: the first 100 ticks visit all 5, the last 25 (ticks 100-124)
    # places 0, 1 and 2
    assert (m["locations_visited_train"], m["locations_visited_test"]) == (5, 3)
    assert m["cm_per_tick"] == 5.0                      # steps of (3, 4)
    assert m["localized_units"] == 55.0
    assert m["localized_units_sd"] == pytest.approx(math.sqrt(50), rel=1e-15)
    assert m["location_decoding_accuracy_test"] == pytest.approx(0.6, rel=1e-15)
    assert m["location_decoding_accuracy_test_sd"] == pytest.approx(math.sqrt(0.02), rel=1e-12)
    assert m["location_decoding_within_one_step_test"] == pytest.approx(0.85, rel=1e-15)
    assert m["location_decoding_within_one_step_test_sd"] == pytest.approx(math.sqrt(0.005),
                                                                            rel=1e-12)
    assert m["population_decoding_accuracy_test"] == pytest.approx(0.7, rel=1e-15)
    assert m["population_decoding_within_one_step_test"] == pytest.approx(0.96, rel=1e-15)
    # the summaries: numbers only (bools and the arrays' underscored keys left out)
    assert set(m["rc_sfa_ica"]) == {*RESULTS[0]} - {"ica_converged"} | {
        "ceiling_location_decoding_accuracy"}
    assert m["rc_sfa_ica"]["localized_units"]["per_seed"] == [50.0, 60.0]
    assert m["runs"]["rc_sfa_ica"][1] == {**RESULTS[1], "ceiling_location_decoding_accuracy": 0.9}
    assert m["runs"]["no_reservoir_quadratic"] == [RESULTS[2]]
    assert m["ablation_no_reservoir"]["localized_units"] == {"mean": 20.0, "sd": 0.0,
                                                             "per_seed": [20.0]}
    assert (m["ablation_localized_units"], m["ablation_location_decoding_accuracy_test"],
            m["ablation_location_decoding_within_one_step_test"]) == (20.0, 0.25, 0.4)
    assert m["targets"] == Z.TARGETS
    assert m["timing_s"] == {"record": 2.5, "fit_rc_sfa_ica": [1.25, 0.5],
                             "fit_no_reservoir_quadratic": [3.0]}
    (out, summary, written), = calls["metrics"]
    assert out == tmp_path and written is m
    assert summary == (
        "maze (2 reservoir(s)): 55.0 of 4 units localized; location decoded on the test part "
        "0.60 exactly, 0.85 within one step by the winning unit, 0.70 and 0.96 by the nearest "
        "centroid; without the reservoir 20.0 units, 0.25 (targets: >= 60 units, >= 0.85 "
        "within one step)")


def test_run_without_ablation_ceiling_and_figures_and_a_given_washout(monkeypatch, tmp_path):
    m, calls, _, _ = _run(monkeypatch, tmp_path, ablation=False, ceiling=False, figures=False,
                          washout=2, seeds=1)
    assert [f.washout for f in Fits.made[1::2]] == [2] and len(Fits.made) == 2
    assert calls["ceiling"] == [] and calls["figures"] == []
    assert "Y_ablation" not in calls["npz"][0][1]
    assert not any(k.startswith("ablation") for k in m)
    assert m["washout_updates"] == {"rc_sfa_ica": 2} and m["reservoir_seeds"] == [3]
    assert calls["metrics"][0][1] == (
        "maze (1 reservoir(s)): 50.0 of 4 units localized; location decoded on the test part "
        "0.50 exactly, 0.80 within one step by the winning unit, 0.60 and 0.95 by the nearest "
        "centroid (targets: >= 60 units, >= 0.85 within one step)")


def test_run_quick_caps_the_ticks_neurons_units_and_restarts(monkeypatch, tmp_path):
    m, calls, _, _ = _run(monkeypatch, tmp_path, quick=True, T=60_000, ticks=70_000,
                          neurons=101, units=21, ica_restarts=5, ablation=False)
    assert calls["cached"] == [("CACHE", "maze_t60000_rho0.25_s3", 60_000)]
    kw = Fits.made[0].kw
    assert (kw["n_reservoir"], kw["n_sfa"], kw["n_ica"], kw["ica_restarts"]) == (100, 20, 20, 1)
    assert (m["quick"], m["ticks"], m["neurons"], m["units"], m["ica_restarts"]) == (
        True, 60_000, 100, 20, 1)
    assert m["train_ticks"] == 50_000 and m["samples"] == 12_000
    m, _, _, _ = _run(monkeypatch, tmp_path, quick=True, T=5000, ticks=5000, neurons=99,
                      units=19, ablation=False)
    assert (m["ticks"], m["neurons"], m["units"], m["ica_restarts"]) == (5000, 99, 19, 1)
    # without --quick nothing is capped
    m, calls, _, _ = _run(monkeypatch, tmp_path, T=60_001, ticks=60_001, neurons=101,
                          units=21, ica_restarts=5, ablation=False)
    assert calls["cached"] == [("CACHE", "maze_t60001_rho0.25_s3", 60_001)]
    assert (m["ticks"], m["neurons"], m["units"], m["ica_restarts"]) == (60_001, 101, 21, 5)


def test_figures_draw_the_test_part_of_each_fit(monkeypatch, tmp_path):
    import matplotlib
    import matplotlib.pyplot as plt

    import hippo.plots.perception as P

    matplotlib.use("Agg")
    calls: dict[str, list] = {k: [] for k in ("map", "arena", "sfa", "order", "fields", "save")}

    made: list = []

    def figure(kind):
        def draw(*a, **k):
            calls[kind].append((a, k))
            made.append(plt.figure())
            return made[-1], None
        return draw

    monkeypatch.setattr(P, "plot_activation_map", figure("map"))
    monkeypatch.setattr(P, "plot_units_over_arena", figure("arena"))
    monkeypatch.setattr(P, "plot_sfa_units", figure("sfa"))
    monkeypatch.setattr(M, "spatial_order", lambda Y, lab, n, threshold: calls["order"].append(
        (Y, lab, n, threshold)) or [len(calls["order"])])
    monkeypatch.setattr(M, "place_fields_grid", lambda xy, Y, bins, extent: calls[
        "fields"].append((xy, Y, bins, extent)) or (f"F{len(calls['fields'])}", 0, 0, 0))
    monkeypatch.setattr(Z, "save_figure", lambda fig, path, dpi: calls["save"].append(
        (plt.fignum_exists(fig.number), path.name, dpi)))
    arena = SimpleNamespace(width=40.0, height=30.0)
    rec = SimpleNamespace(x=np.arange(10.0), y=np.arange(10.0) * 2)

    def kept(n_sfa: int, units: int, acc: float) -> dict[str, Any]:
        return {"_k_tr": 2, "_ticks": np.arange(5), "_Yd": np.arange(10.0).reshape(5, 2),
                "_lab": np.array([4, 3, 2, 1, 0]), "_aligned": np.array([1, 3, 5, 7, 9]),
                "_Ysd": np.ones((5, n_sfa)), "localized_units": units,
                "location_decoding_accuracy_test": acc,
                "location_decoding_within_one_step_test": 0.755}

    keep = {"rc_sfa_ica": kept(15, 12, 0.5), "no_reservoir_quadratic": kept(30, 3, 0.125)}
    Z._figures(tmp_path, arena, rec, keep, 4.25, 5)
    assert calls["save"] == [(True, "fig3_activation_map.png", 110),
                             (True, "place_fields.png", 110),
                             (True, "fig2a_sfa_units.png", 110),
                             (True, "fig3_activation_map_ablation.png", 110),
                             (True, "place_fields_ablation.png", 110)]
    assert len(made) == 5 and not any(plt.fignum_exists(f.number) for f in made)  # closed
    title = "RC-SFA-ICA: 12 localized units, decoding 0.50 exact / 0.76 within one step (test)"
    abl = ("no reservoir, quadratic SFA: 3 localized units, decoding 0.12 exact / 0.76 within "
           "one step (test)")
    Yte, lab = keep["rc_sfa_ica"]["_Yd"][2:], np.array([2, 1, 0])
    (a, k), _ = calls["map"]
    assert _same(a[0], [5, 7, 9]) and _same(a[1], lab) and _same(a[2], Yte) and a[3] == [1]
    assert k == dict(threshold=4.25, n_locations=5, title=title)
    assert calls["map"][1][1]["title"] == abl and calls["map"][1][0][3] == [2]
    o = calls["order"][0]
    assert _same(o[0], Yte) and _same(o[1], lab) and o[2:] == (5, 4.25)
    # the positions at the aligned ticks 5, 7, 9: (5, 10), (7, 14), (9, 18)
    xy, Y, bins, extent = calls["fields"][0]
    assert _same(xy, [[5, 10], [7, 14], [9, 18]]) and _same(Y, Yte)
    assert (bins, extent) == (32, (0, 40.0, 0, 30.0))
    (a, k), (a2, k2) = calls["arena"]
    assert a == (arena, "F1", (0, 40.0, 0, 30.0)) and k == dict(units=[1], title=title)
    assert a2[1] == "F2" and k2 == dict(units=[2], title=abl)
    (a, k), = calls["sfa"]
    assert a[0] is arena and _same(a[1], xy) and _same(a[2], lab) and _same(a[3], np.ones((3,
                                                                                         15)))
    assert a[4] == [0, 11, 14] and _same(k["t"], [5, 7, 9])


@pytest.mark.parametrize(("n_sfa", "units"), [(30, [0, 11, 23]), (24, [0, 11, 23]),
                                              (12, [0, 11, 11]), (11, [0, 10, 10])])
def test_figures_sfa_units_shown_and_no_ablation(monkeypatch, tmp_path, n_sfa, units):
    import matplotlib
    import matplotlib.pyplot as plt

    import hippo.plots.perception as P

    matplotlib.use("Agg")
    shown, saved, made = [], [], []

    def new() -> tuple:
        made.append(plt.figure())
        return made[-1], None

    monkeypatch.setattr(P, "plot_activation_map", lambda *a, **k: new())
    monkeypatch.setattr(P, "plot_units_over_arena", lambda *a, **k: new())
    monkeypatch.setattr(P, "plot_sfa_units", lambda *a, **k: shown.append(a[4]) or new())
    monkeypatch.setattr(M, "spatial_order", lambda *a, **k: [0])
    monkeypatch.setattr(M, "place_fields_grid", lambda *a, **k: (None, 0, 0, 0))
    monkeypatch.setattr(Z, "save_figure", lambda fig, path, dpi: saved.append(path.name))
    k = {"_k_tr": 1, "_ticks": np.arange(3), "_Yd": np.ones((3, 2)), "_lab": np.zeros(3, int),
         "_aligned": np.arange(3), "_Ysd": np.ones((3, n_sfa)), "localized_units": 1,
         "location_decoding_accuracy_test": 0.0, "location_decoding_within_one_step_test": 0.0}
    Z._figures(tmp_path, SimpleNamespace(width=1.0, height=1.0),
               SimpleNamespace(x=np.zeros(3), y=np.zeros(3)), {"rc_sfa_ica": k}, 4.5, 2)
    assert shown == [units]
    assert saved == ["fig3_activation_map.png", "place_fields.png", "fig2a_sfa_units.png"]
    assert len(made) == 3 and not any(plt.fignum_exists(f.number) for f in made)
