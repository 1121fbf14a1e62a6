"""The two-rooms scenario (:mod:`hippo.scenarios.two_rooms`) on stand-ins of the recordings,
the model and its evaluation: the options (defaults, bounds), check_args' refusals word for
word on each edge, the ceiling's read-out asked for, the --select line, and run()'s models,
seeds, summaries over seeds and metrics computed by hand from the stand-ins' numbers."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from types import SimpleNamespace
from typing import Any, ClassVar

import numpy as np
import pytest
from stand_ins import Refused, RefusingParser

import hippo.scenarios.two_rooms as TR


def _parser() -> RefusingParser:
    p = RefusingParser(prog="two-rooms")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--quick", action="store_true")
    TR.add_arguments(p)
    return p


def _refusal(argv: list[str]) -> str:
    p = _parser()
    a = p.parse_args(argv)
    with pytest.raises(Refused) as e:
        TR.check_args(a, p)
    return str(e.value)


def _ok(argv: list[str]) -> argparse.Namespace:
    p = _parser()
    a = p.parse_args(argv)
    TR.check_args(a, p)
    return a


def test_constants():
    assert TR.PAPER_LEAK == (0.05, 0.15) and TR.SMC09_UNITS == 4
    assert TR.ROOM_LEAK == (0.08, 0.15) and TR.ROOM_UNITS == 2 and TR.CORRIDOR_UNITS == 4
    assert TR.MIN_TICKS == 4000 and TR.CORRIDOR_LEAK == (0.11, 0.14)


def test_the_options_defaults_and_bounds():
    a = _ok([])
    assert (a.ticks, a.rho, a.neurons, a.n_sfa, a.n_ica, a.seeds, a.cache) == (
        18120, 0.008, 600, 2, 2, 1, None)
    assert (a.ceiling, a.faults, a.ica_restarts, a.ica_score, a.ica_algorithm) == (
        True, False, 10, "kurtosis", "symmetric")
    assert (a.sfa_cutoff, a.leak, a.slow_pool, a.leak_sweep, a.select) == (
        1e-8, (0.08, 0.15), 0.0, False, False)
    assert (a.select_units, a.hold, a.figures) == ((2, 4), 5, True)
    assert _ok(["--no-ceiling", "--no-figures"]).ceiling is False
    acts = {x.dest: x for x in _parser()._actions}
    assert acts["ica_score"].choices == ["kurtosis", "sparseness", "slowness"]
    assert acts["ica_algorithm"].choices == ["symmetric", "deflation"]
    for dest, ok, bad in (("ticks", ("4000", "10000000"), ("3999", "10000001")),
                          ("neurons", ("1", "20000"), ("0", "20001")),
                          ("n_sfa", ("1", "500"), ("0", "501")),
                          ("n_ica", ("1", "500"), ("0", "501")),
                          ("ica_restarts", ("1", "1000"), ("0", "1001")),
                          ("hold", ("1", "10000"), ("0", "10001")),
                          ("rho", ("0", "1"), ("-0.01", "1.01"))):
        f = acts[dest].type
        assert [float(f(v)) for v in ok] == [float(v) for v in ok]
        for v in bad:
            with pytest.raises(argparse.ArgumentTypeError):
                f(v)
    assert "at least 4000" in acts["ticks"].help


def test_check_args_refusals_on_each_edge():
    assert _refusal(["--neurons", "1"]) == ("argument --neurons: 1 neuron(s) cannot hold the 2 "
                                            "groups of --leak (one group of neurons per leak "
                                            "rate)")
    _ok(["--neurons", "2"])
    _ok(["--n-sfa", "3", "--n-ica", "3"])
    assert _refusal(["--n-sfa", "3", "--n-ica", "4"]) == (
        "argument --n-ica: 4 exceeds --n-sfa 3 (ICA rotates the SFA outputs)")
    assert _refusal(["--select-units", "2,3"]) == (
        "argument --select-units: only with --select (the unit counts it chooses among); add "
        "--select or leave it out")
    assert _refusal(["--select-criterion", "slowness"]).startswith(
        "argument --select-criterion: only with --select (the criterion it chooses by)")
    _ok(["--select", "--select-units", "2,18", "--neurons", "10"])
    assert _refusal(["--select", "--select-units", "2,19", "--neurons", "10"]) == (
        "argument --select-units: 19 exceeds the 18 inputs of SFA (10 neurons + 8 sensors)")
    # the selection's sweep appends the slow pool's running mean too (twice the inputs)
    _ok(["--select", "--select-units", "2,36", "--neurons", "10", "--slow-pool", "5"])
    assert _refusal(["--select", "--select-units", "2,37", "--neurons", "10",
                     "--slow-pool", "5"]) == (
        "argument --select-units: 37 exceeds the 36 inputs of SFA (10 neurons + 8 sensors, "
        "twice that with the slow pool)")
    _ok(["--n-sfa", "18", "--n-ica", "1", "--neurons", "10"])
    assert _refusal(["--n-sfa", "19", "--n-ica", "1", "--neurons", "10"]) == (
        "argument --n-sfa: 19 exceeds the 18 inputs of SFA (10 neurons + 8 sensors)")
    # the slow pool's running mean doubles the SFA input: 36 units taken, 37 refused (were
    # refused past 18)
    _ok(["--n-sfa", "36", "--n-ica", "1", "--neurons", "10", "--slow-pool", "5"])
    assert _refusal(["--n-sfa", "37", "--n-ica", "1", "--neurons", "10", "--slow-pool", "5"]) == (
        "argument --n-sfa: 37 exceeds the 36 inputs of SFA (10 neurons + 8 sensors, twice that "
        "with the slow pool)")
    # without --select its unit counts are not checked against the inputs
    a = _parser().parse_args(["--neurons", "10"])
    a.select_units = (2, 40)
    TR.check_args(a, _parser())
    # --quick runs a reservoir of at most 120 neurons: checked against that, not --neurons
    _ok(["--quick", "--n-sfa", "128", "--n-ica", "1"])
    assert _refusal(["--quick", "--n-sfa", "129", "--n-ica", "1"]) == (
        "argument --n-sfa: 129 (--quick: 120 neurons) exceeds the 128 inputs of SFA (120 neurons "
        "+ 8 sensors)")
    assert _refusal(["--quick", "--neurons", "120", "--n-sfa", "129", "--n-ica", "1"]) == (
        "argument --n-sfa: 129 exceeds the 128 inputs of SFA (120 neurons + 8 sensors)")
    _ok(["--quick", "--neurons", "100", "--n-sfa", "108", "--n-ica", "1"])
    _ok(["--n-sfa", "129", "--n-ica", "1"])
    _ok(["--quick", "--select", "--select-units", "2,128"])
    assert _refusal(["--quick", "--select", "--select-units", "2,129"]) == (
        "argument --select-units: 129 (--quick: 120 neurons) exceeds the 128 inputs of SFA "
        "(120 neurons + 8 sensors)")
    assert TR.QUICK_NEURONS == 120
    for other in ("--faults", "--leak-sweep"):
        assert _refusal(["--slow-pool", "10", other]) == (
            "argument --slow-pool: not measured with --faults or --leak-sweep (they read the "
            "reservoir state without the pool); leave one out")
        _ok([other])
    _ok(["--slow-pool", "10"])


def test_room_ceiling_asks_for_the_ridge_read_out(monkeypatch):
    seen = {}
    model = SimpleNamespace(features=lambda U: U * 2.0)

    def ridge(X, y, k, mask, folds, gap):
        seen.update(X=X, y=y, k=k, mask=mask, folds=folds, gap=gap)
        return "ceiling"

    monkeypatch.setattr(TR.M, "ridge_ceiling", ridge)
    U = np.arange(6.0).reshape(3, 2)
    rooms = {"room_b": np.array([True, False, True]), "room": np.array([True, True, False])}
    assert TR.room_ceiling(model, U, rooms) == "ceiling"
    np.testing.assert_array_equal(seen["X"], U * 2.0)
    np.testing.assert_array_equal(seen["y"], [1, 0, 1])
    assert seen["y"].dtype.kind == "i"
    assert seen["mask"] is rooms["room"]
    assert (seen["k"], seen["folds"], seen["gap"]) == (2, 5, 50)


def test_the_options_help():
    acts = {x.dest: x for x in _parser()._actions}
    assert acts["rho"].help == "wall-side switch probability per tick"
    assert acts["n_ica"].help == "ICA units of the room-cell model (at most --n-sfa; SMC09: 4)"
    assert acts["select"].help == ("also choose the leak pair per seed from the recording alone "
                                   "(label-free criterion over the 16-pair grid) and report it "
                                   "beside SMC09's")
    assert acts["select_units"].help == ("SFA/ICA unit counts --select chooses among (default: "
                                         "2, the room cell's, and 4, SMC09's)")
    f = acts["select_units"].type
    assert f("1,500") == [1, 500]
    for bad in ("0,2", "2,501"):
        with pytest.raises(argparse.ArgumentTypeError):
            f(bad)


def test_selection_line():
    assert TR._selection_line({}) == ""
    m = {"selection": {"criterion": "slowness", "picked_mean": 0.91234, "paper_mean": 0.9,
                       "picked_minus_paper_worst_group": -0.0123}}
    assert TR._selection_line(m) == (
        "\nlabel-free pick (slowness): room cell 0.912 vs SMC09's fixed settings 0.900; the "
        f"worst group of up to {TR.GROUP} seeds -0.012 (target: >= -0.01)")
    m["selection"]["picked_minus_paper_worst_group"] = 0.02
    assert TR._selection_line(m).endswith(" seeds +0.020 (target: >= -0.01)")


# ------------------------------------------------------------------------------ run
class _Model:
    made: ClassVar[list[dict]] = []

    def __init__(self, kw: dict) -> None:
        self.kw = kw
        self.params = SimpleNamespace(base=kw)
        self.fitted: Any = None

    @classmethod
    def smc09(cls, **kw: Any) -> _Model:
        m = cls(kw)
        cls.made.append(kw)
        return m

    def fit(self, U: np.ndarray) -> None:
        self.fitted = U.copy()

    def save(self, path: Path) -> None:
        Path(path).write_bytes(b"m")


def _rec(regions: list[int]) -> Any:
    return SimpleNamespace(t=np.arange(len(regions)) * 0.2, x=np.zeros(len(regions)),
                           y=np.ones(len(regions)), label=np.zeros(len(regions), int),
                           region=np.array(regions), region_names=["room_a", "corridor",
                                                                   "room_b"],
                           sensors=np.arange(len(regions) * 2.0).reshape(-1, 2))


def _stand_ins(monkeypatch, tmp_path: Path, argv: list[str], *,
               one_room_seeds: tuple[int, ...] = ()) -> tuple[argparse.Namespace, dict]:
    seen: dict[str, Any] = {"evaluate": [], "saved": {}, "figures": [], "recordings": []}
    _Model.made = []
    # 8 ticks: training 0-6 (7/8), test 7; regions a a b b c b a b: 3 changes... by hand below
    regions = [0, 0, 2, 2, 1, 2, 0, 2]

    def recordings(args, arena, ticks, n_train, seed):
        seen["recordings"].append((arena.name, ticks, n_train, seed))
        rec = _rec(regions if seed not in one_room_seeds else [0] * 8)
        return rec, _rec([2] * 8), [1, 3], ["lift", "put"], [True, False]

    scores = {0: (0.9, 10.0, 0.8), 1: (0.8, math.nan, 0.6), 2: (0.7, 20.0, 0.7),
              3: (math.nan, math.nan, 0.5)}

    def evaluate(model, U, rooms, n_train, U_kid, kid_rooms, events, moved, hold):
        seed = model.kw["seed"]
        assert kid_rooms["room_b"].all() and not rooms["room_b"][0]   # the kidnapped run's
        assert U_kid.shape == (8, 2)
        seen["evaluate"].append((model.kw["leak"], seed, n_train, events, moved, hold))
        acc, kid, cor = scores[seed]
        res = {"room_cell_test_balanced_accuracy": acc, "kidnap_recovery_ticks": kid,
               "kidnap_recovery_ticks_max": kid, "corridor_cell_test_balanced_accuracy": cor,
               "sfa_supervised_readout_test_balanced_accuracy": acc + 0.05,
               "room_cell": f"cell{seed}-{model.kw['leak']}", "Y": np.full((8, 1), seed + 0.5),
               "Ysfa": np.zeros((8, 1)), "room_cell_is_slowest": seed != 1,
               "kidnap_unrecovered": seed + 1, "corridor_cell": "x"}
        if seed >= 2:
            res["kidnap_recovery_withheld"] = "near chance"
        if seed == 3:       # a test part in one room: no score, so no recovery withheld either
            res["room_cell_unscored"] = "the test part visited only room A"
        return res

    def save_npz(path, arrays):
        seen["saved"][Path(path).name] = arrays

    def headline(m, leak):
        seen["headline"] = (m["seeds"], tuple(leak))
        return "HEADLINE"

    monkeypatch.setattr(TR, "_recordings", recordings)
    monkeypatch.setattr(TR, "_evaluate", evaluate)
    monkeypatch.setattr(TR, "RCSFAICA", _Model)
    monkeypatch.setattr(TR, "room_ceiling",
                        lambda model, U, rooms: SimpleNamespace(
                            balanced_accuracy=0.95 + model.kw["seed"] / 100))
    monkeypatch.setattr(TR, "save_npz", save_npz)
    monkeypatch.setattr(TR, "headline", headline)
    monkeypatch.setattr(TR, "_figures", lambda out, arena, rec, rec_kid, n_train, events, keep,
                        leak: seen["figures"].append(("figures", n_train, sorted(keep), leak)))
    monkeypatch.setattr(TR, "_sweep_figure",
                        lambda out, rows: seen["figures"].append(("sweep", rows)))
    monkeypatch.setattr(TR, "_fault_figure",
                        lambda out, f, seeds: seen["figures"].append(("faults", f, seeds)))
    monkeypatch.setattr(TR, "_fault_curve", lambda model, U, rooms, n_train, cell, seed, quick: [
        {"seed": seed, "cell": cell, "quick": quick, "n_train": n_train}])
    monkeypatch.setattr(TR, "_fault_summary", lambda rows: {"rows": rows})
    def sweep_one(args, neurons, restarts, seed, U, rooms, n_train, U_kid, kid_rooms, events,
                  moved):
        assert n_train == 7 and not rooms["room_b"][0] and rooms["room_b"][2]
        assert kid_rooms["room_b"].all() and (events, moved) == ([1, 3], [True, False])
        return {"seed": seed, "neurons": neurons, "restarts": restarts}

    monkeypatch.setattr(TR, "_leak_sweep_one", sweep_one)
    clock = iter(range(10_000))
    monkeypatch.setattr(TR, "time", SimpleNamespace(perf_counter=lambda: float(next(clock))))

    class _Progress:
        def __init__(self, total: int, desc: str) -> None:
            seen["progress"] = [total, desc, 0]

        def __enter__(self) -> _Progress:
            return self

        def __exit__(self, *exc: Any) -> None:
            pass

        def update(self, n: int = 1) -> None:
            seen["progress"][2] += n

    monkeypatch.setattr(TR, "Progress", _Progress)
    monkeypatch.setattr(TR, "_sweep_summary", lambda rows: {
        "rows": [{"leak": [0.1, 0.2], "meets_targets": True, "n": len(rows)},
                 {"leak": [0.3, 0.4], "meets_targets": False}], "seconds": 7.5})
    p = _parser()
    args = p.parse_args([*argv, "--ticks", "8000"])
    args.ticks = 8      # beneath the option's bound: the stand-in recordings are 8 ticks
    args.out = str(tmp_path / "out")
    return args, seen


def test_run_over_three_seeds(monkeypatch, tmp_path):
    args, seen = _stand_ins(monkeypatch, tmp_path, ["--seeds", "3", "--seed", "0"])
    m = TR.run(args)
    assert seen["recordings"] == [("two-rooms", 8, 7, s) for s in (0, 1, 2)]
    # per seed the room cell's model (--leak, --n-sfa / --n-ica) and the corridor's (4 / 4)
    assert [(kw["leak"], kw["seed"], kw["n_sfa"], kw["n_ica"]) for kw in _Model.made] == [
        ((0.08, 0.15), 0, 2, 2), ((0.11, 0.14), 0, 4, 4), ((0.08, 0.15), 1, 2, 2),
        ((0.11, 0.14), 1, 4, 4), ((0.08, 0.15), 2, 2, 2), ((0.11, 0.14), 2, 4, 4)]
    kw = _Model.made[0]
    assert kw == {"n_reservoir": 600, "leak": (0.08, 0.15), "seed": 0, "n_sfa": 2, "n_ica": 2,
                  "ica_restarts": 10, "ica_score": "kurtosis", "ica_algorithm": "symmetric",
                  "sfa_cutoff": 1e-8, "slow_pool": 0.0}
    assert [e[2:] for e in seen["evaluate"]] == [(7, [1, 3], [True, False], 5)] * 6
    assert m["seeds"] == [0, 1, 2] and m["reservoir_seeds"] == [0, 1, 2]
    assert (m["ticks"], m["train_ticks"], m["test_ticks"]) == (8, 7, 1)
    assert (m["neurons"], m["n_sfa"], m["n_ica"], m["rho"]) == (600, 2, 2, 0.008)
    assert m["corridor_units"] == 4 and m["ica_restarts"] == 10 and m["quick"] is False
    assert m["scenario"] == "two-rooms" and m["paper"] == "SMC09" and m["seed"] == 0
    # regions 0 0 2 2 1 2 0 2: five changes; a 3/8, corridor 1/8, b 4/8
    assert m["room_changes"] == 5
    assert m["region_occupancy"] == {"room_a": 3 / 8, "corridor": 1 / 8, "room_b": 4 / 8}
    assert m["leak"] == [0.08, 0.15]
    # accuracies 0.9, 0.8, 0.7: mean 0.8, sample sd 0.1, min 0.7
    assert m["room_cell_test_balanced_accuracy"] == pytest.approx(0.8)
    assert m["room_cell_test_balanced_accuracy_sd"] == pytest.approx(0.1)
    assert m["room_cell_test_balanced_accuracy_min"] == 0.7
    # recovery 10, nan, 20: mean 15, sd sqrt(50), worst 20
    assert m["kidnap_recovery_ticks"] == 15.0
    assert m["kidnap_recovery_ticks_sd"] == pytest.approx(math.sqrt(50.0))
    assert m["kidnap_recovery_ticks_worst_seed"] == 20.0
    # unrecovered 1 and 2 (seed 2's recovery is withheld)
    assert m["kidnap_unrecovered"] == 3
    assert m["seeds_scored"] == 3 and m["unscored_seeds"] == {}
    assert m["kidnap_recovery_withheld_seeds"] == {"2": "near chance"}
    assert m["shown_seed"] == 0 and m["room_cell_is_slowest_unit"] == 2
    assert m["corridor_cell_test_balanced_accuracy"] == pytest.approx(0.7)
    assert m["corridor_cell_test_balanced_accuracy_sd"] == pytest.approx(0.1)
    assert m["room_ceiling_balanced_accuracy"] == pytest.approx(0.96)
    assert m["kidnap_events"] == [{"tick": -6, "kind": "lift", "changed_room": True},
                                  {"tick": -4, "kind": "put", "changed_room": False}]
    room = m["leak_0.08_0.15"]
    assert set(room) == {"room_cell_test_balanced_accuracy", "kidnap_recovery_ticks",
                         "kidnap_recovery_ticks_max", "corridor_cell_test_balanced_accuracy",
                         "sfa_supervised_readout_test_balanced_accuracy",
                         "room_ceiling_balanced_accuracy"}
    k = room["kidnap_recovery_ticks"]
    assert (k["mean"], k["min"], k["max"]) == (15.0, 10.0, 20.0)
    assert k["per_seed"][0] == 10.0 and math.isnan(k["per_seed"][1])
    assert m["leak_0.11_0.14"]["room_ceiling_balanced_accuracy"]["per_seed"][0] != (
        m["leak_0.11_0.14"]["room_ceiling_balanced_accuracy"]["per_seed"][0])   # nan: none
    assert math.isnan(m["leak_0.11_0.14"]["room_ceiling_balanced_accuracy"]["min"])
    assert m["runs"]["paper"][0]["seed"] == 0 and "Y" not in m["runs"]["paper"][0]
    assert "room_cell" in m["runs"]["paper"][0] and isinstance(
        m["runs"]["paper"][0]["room_cell"], str)
    assert m["targets"] is TR.TARGETS
    # one clock tick per recording, one per fit (two fits a seed)
    assert m["timing_s"] == {"record": 3.0, "fit_total": 6.0}
    assert seen["progress"] == [6, "two-rooms fits", 6]
    assert "leak_sweep" not in m and "faults" not in m and "selection" not in m
    saved = seen["saved"]["run.npz"]
    np.testing.assert_array_equal(saved["Y"], np.full((8, 1), 0.5))
    assert saved["n_train"] == 7
    np.testing.assert_array_equal(saved["kidnap_ticks"], [1, 3])
    np.testing.assert_array_equal(saved["Y_kid"], np.zeros(0))
    np.testing.assert_array_equal(saved["Ysfa"], np.zeros((8, 1)))
    np.testing.assert_array_equal(saved["t"], np.arange(8) * 0.2)
    np.testing.assert_array_equal(saved["x"], np.zeros(8))
    np.testing.assert_array_equal(saved["y"], np.ones(8))
    np.testing.assert_array_equal(saved["label"], np.zeros(8, int))
    np.testing.assert_array_equal(saved["region"], [0, 0, 2, 2, 1, 2, 0, 2])
    np.testing.assert_array_equal(saved["x_kid"], np.zeros(8))
    np.testing.assert_array_equal(saved["y_kid"], np.ones(8))
    np.testing.assert_array_equal(saved["label_kid"], np.zeros(8, int))
    np.testing.assert_array_equal(saved["Y_corridor_leaks"], np.full((8, 1), 0.5))
    np.testing.assert_array_equal(saved["sensors"], np.arange(16.0).reshape(8, 2))
    assert set(saved) == {"t", "x", "y", "label", "region", "sensors", "n_train", "Y", "Ysfa",
                          "Y_kid", "x_kid", "y_kid", "label_kid", "kidnap_ticks",
                          "Y_corridor_leaks"}
    assert seen["figures"] == [("figures", 7, ["corridor", "paper"], (0.08, 0.15))]
    assert (tmp_path / "out" / "place_cells.npz").exists()
    assert seen["headline"] == ([0, 1, 2], (0.08, 0.15))


def test_run_leaves_a_one_room_seed_unscored(monkeypatch, tmp_path):
    args, seen = _stand_ins(monkeypatch, tmp_path, ["--seeds", "0-2"], one_room_seeds=(0,))
    m = TR.run(args)
    assert [kw["seed"] for kw in _Model.made] == [1, 1, 2, 2]
    assert m["unscored_seeds"] == {"0": "the training part visited only room A"}
    assert m["seeds_scored"] == 2 and m["shown_seed"] == 1
    assert set(m["runs"]) == {"paper", "corridor"}      # no --select: no rows of its models
    assert m["runs"]["corridor"][0] == {"seed": 0, "room_cell_unscored":
                                        "the training part visited only room A"}
    assert m["room_cell_test_balanced_accuracy"] == pytest.approx(0.75)
    np.testing.assert_array_equal(seen["saved"]["run.npz"]["Y"], np.full((8, 1), 1.5))


def test_run_with_no_seed_scored_writes_only_the_metrics(monkeypatch, tmp_path, capsys):
    args, seen = _stand_ins(monkeypatch, tmp_path, [], one_room_seeds=(0,))
    m = TR.run(args)
    assert _Model.made == [] and seen["saved"] == {} and seen["figures"] == []
    assert m["shown_seed"] == 0 and m["room_changes"] == 0
    assert (tmp_path / "out" / "metrics.json").exists()
    assert "HEADLINE" in capsys.readouterr().err


def test_run_quick_caps_and_options(monkeypatch, tmp_path):
    args, seen = _stand_ins(monkeypatch, tmp_path, [
        "--quick", "--neurons", "200", "--ica-restarts", "5", "--no-ceiling", "--no-figures",
        "--ica-score", "slowness", "--ica-algorithm", "deflation", "--sfa-cutoff", "auto",
        "--hold", "3", "--slow-pool", "4"])
    args.ticks = 9000
    monkeypatch.setattr(TR, "_recordings", lambda a, arena, ticks, n_train, seed: (
        seen.setdefault("ticks", (ticks, n_train)) and None) or (
        _rec([0, 0, 2, 2, 1, 2, 0, 2]), _rec([2] * 8), [1], ["lift"], [True]))
    m = TR.run(args)
    assert seen["ticks"] == (8000, 7000)
    kw = _Model.made[0]
    assert (kw["n_reservoir"], kw["ica_restarts"], kw["ica_score"], kw["ica_algorithm"],
            kw["sfa_cutoff"], kw["slow_pool"]) == (120, 3, "slowness", "deflation", "auto", 4.0)
    assert m["quick"] is True and m["neurons"] == 120 and m["ica_restarts"] == 3
    assert [e[-1] for e in seen["evaluate"]] == [3, 3]
    assert math.isnan(m["room_ceiling_balanced_accuracy"])
    assert seen["figures"] == []
    args, seen = _stand_ins(monkeypatch, tmp_path, ["--quick", "--neurons", "100",
                                                    "--ica-restarts", "2"])
    args.ticks = 7999
    TR.run(args)
    assert (_Model.made[0]["n_reservoir"], _Model.made[0]["ica_restarts"]) == (100, 2)


def test_run_with_faults_and_the_leak_sweep(monkeypatch, tmp_path):
    args, seen = _stand_ins(monkeypatch, tmp_path, ["--seeds", "2", "--faults", "--leak-sweep"])
    m = TR.run(args)
    assert m["faults"] == {"rows": [
        {"seed": 0, "cell": "cell0-(0.08, 0.15)", "quick": False, "n_train": 7},
        {"seed": 1, "cell": "cell1-(0.08, 0.15)", "quick": False, "n_train": 7}]}
    assert m["leak_sweep"][0]["n"] == 2
    assert m["leak_sweep_meeting_targets"] == [[0.1, 0.2]]
    assert m["timing_s"]["leak_sweep"] == 7.5
    kinds = [f[0] for f in seen["figures"]]
    assert kinds == ["figures", "sweep", "faults"]
    assert seen["figures"][2][2] == [0, 1]


def test_run_with_select(monkeypatch, tmp_path):
    args, seen = _stand_ins(monkeypatch, tmp_path, ["--seeds", "3", "--select",
                                                    "--select-criterion", "slowness",
                                                    "--slow-pool", "4", "--sfa-cutoff", "auto"],
                            one_room_seeds=(0,))
    picks = []

    def select_setting(U, n_train, base, score, criterion, paper, paper_units, units):
        picks.append((n_train, base.base["leak"] if "leak" in base.base else None, criterion,
                      paper, paper_units, units, score(np.zeros((8, 1)))))
        return {"chosen": [0.2, 0.3], "chosen_units": 3}

    def selection_summary(rows, seeds, picked, paper):
        seen["summary"] = (len(rows), seeds, picked, paper)
        return {"criterion": "slowness", "picked_mean": 0.5, "paper_mean": 0.4,
                "picked_minus_paper_worst_group": 0.1}

    monkeypatch.setattr(TR, "select_setting", select_setting)
    monkeypatch.setattr(TR, "selection_summary", selection_summary)
    monkeypatch.setattr(TR, "_room_cell_accuracy", lambda Y, rooms, n: 0.625)
    m = TR.run(args)
    assert picks == [(7, None, "slowness", (0.05, 0.15), 4, (2, 4), 0.625)] * 2
    assert _Model.made[0] == {"n_reservoir": 600, "seed": 1, "n_sfa": 2, "n_ica": 2,
                              "ica_restarts": 10, "ica_score": "kurtosis",
                              "ica_algorithm": "symmetric", "sfa_cutoff": "auto",
                              "slow_pool": 4.0}
    assert _Model.made[0]["slow_pool"] == 4.0 and _Model.made[0]["sfa_cutoff"] == "auto"
    assert seen["progress"] == [3 * (2 + 3), "two-rooms fits", 15]
    for name in ("paper", "corridor", "selected", "smc09"):
        assert m["runs"][name][0] == {"seed": 0, "room_cell_unscored":
                                       "the training part visited only room A"}
    # the base for the selection, then paper, corridor, selected, smc09
    fitted = [(kw.get("leak"), kw["n_sfa"], kw["n_ica"]) for kw in _Model.made[:5]]
    assert fitted == [(None, 2, 2), ((0.08, 0.15), 2, 2), ((0.11, 0.14), 4, 4),
                      ((0.2, 0.3), 3, 3), ((0.05, 0.15), 4, 4)]
    assert seen["summary"] == (2, [1, 2], [0.8, 0.7], [0.8, 0.7])
    assert m["selection"]["criterion"] == "slowness"
    assert m["selected"]["room_cell_test_balanced_accuracy"]["mean"] == pytest.approx(0.75)
    assert m["smc09"]["kidnap_recovery_ticks"]["per_seed"][2] == 20.0


def test_run_with_select_from_a_scored_first_seed(monkeypatch, tmp_path):
    args, _ = _stand_ins(monkeypatch, tmp_path, ["--seeds", "1", "--select"])
    monkeypatch.setattr(TR, "select_setting", lambda *a, **k: {"chosen": [0.2, 0.3],
                                                               "chosen_units": 3})
    monkeypatch.setattr(TR, "selection_summary", lambda *a: {
        "criterion": "c", "picked_mean": 0.5, "paper_mean": 0.4,
        "picked_minus_paper_worst_group": 0.1})
    m = TR.run(args)
    assert m["runs"]["selected"][0]["seed"] == 0 and m["runs"]["smc09"][0]["seed"] == 0


def test_a_seed_whose_test_part_is_unscored_has_no_recovery_withheld(monkeypatch, tmp_path):
    args, _ = _stand_ins(monkeypatch, tmp_path, ["--seeds", "4"])
    m = TR.run(args)
    assert m["unscored_seeds"] == {"3": "the test part visited only room A"}
    assert m["kidnap_recovery_withheld_seeds"] == {"2": "near chance"}
    assert m["seeds_scored"] == 3
