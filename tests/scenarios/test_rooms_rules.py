"""The rooms scenario (:mod:`hippo.scenarios.rooms`) on hand-made inputs and stand-ins: its
options' defaults and bounds, --units' words, the checks across options (the unit counts
against the SFA inputs on their bound and one past, with the default's, --units auto's and
--quick's words; --select with auto; --arenas against --seeds), the flats' seeds, the room
labels, the kidnaps of the unseen test run (their ticks every 500 from 150, the rooms drawn
from stream "kidnaps", the pose 5 cm inside the room, the run continuing from the end of
training), the room cells' mean for --select, the decoder's model, and one flat's evaluation on
stand-ins for the flat, the recording and the fits, worked out by hand (the room cells'
balanced accuracies, the decoder's recalls, the ceiling, the kidnaps that count), and run's
summary over flats and its closing line."""

from __future__ import annotations

import argparse
import math
import warnings
from dataclasses import dataclass, replace
from types import SimpleNamespace
from typing import Any, ClassVar

import numpy as np
import pytest

import hippo.scenarios.rooms as R
from hippo.perception import ICAConvergenceWarning
from hippo.perception import metrics as M
from hippo.perception.unit_count import UnitCountParams
from hippo.runner import parse_scenario_args, scenario_parser
from hippo.scenarios._common import sfa_cutoff
from hippo.seeds import Seeds


def test_the_constants():
    assert (R.KIDNAP_EVERY, R.SLOW_POOL, R.DECODER_PER_ROOM) == (500, 50.0, 12)
    assert R.TARGETS == {"gap_to_ceiling": 0.05, "decoder_balanced_accuracy": 0.85}


def _parse(argv: list[str]) -> argparse.Namespace:
    return parse_scenario_args("rooms", argv)[0]


def _refused(capsys, argv: list[str]) -> str:
    with pytest.raises(SystemExit) as e:
        _parse(argv)
    assert e.value.code == 2
    err = capsys.readouterr().err
    head, tail = "hippo run rooms: error: ", " (see hippo run rooms --help)\n"
    assert err.startswith(head) and err.endswith(tail)
    return err[len(head):-len(tail)]


def test_the_defaults():
    a = _parse([])
    assert (a.n_rooms, a.arenas, a.seeds, a.cache, a.ticks_per_room) == (3, None, 1, None, 8000)
    assert (a.rho, a.neurons, a.units, a.leak, a.slow_pool) == (0.008, 600, 0, (0.05, 0.15), 50)
    assert (a.ica_restarts, a.sfa_cutoff, a.decoder_features, a.hold) == (10, 1e-8, None, 5)
    assert (a.ceiling, a.select, a.figures) == (True, False, True)
    assert a.select_criterion == "bimodal-stable" == R.DEFAULT_CRITERION


@pytest.mark.parametrize(("option", "ok", "bad"), [
    ("--n-rooms", ["2", "20"], ["1", "21"]),
    ("--arenas", ["1", "1000"], ["0", "1001"]),
    ("--ticks-per-room", ["2000", "10000000"], ["1999", "10000001"]),
    ("--neurons", ["2", "20000"], ["0", "20001"]),
    ("--ica-restarts", ["1", "1000"], ["0", "1001"]),
    ("--decoder-features", ["0", "500"], ["-1", "501"]),
    ("--hold", ["1", "10000"], ["0", "10001"]),
    ("--rho", ["0", "1"], ["-5e-324", "1.0000000000000002"]),
    ("--leak", ["1", "5e-324,1"], ["0", "0.1,0", "1.0000000000000002"]),
])
def test_the_options_bounds(capsys, option, ok, bad):
    for v in ok:
        assert _parse([option, v]) is not None
    for v in bad:
        assert _refused(capsys, [option, v]).startswith(f"argument {option}: ")


def test_the_help():
    parser, _ = scenario_parser("rooms")
    helps = {a.option_strings[0]: a.help for a in parser._actions if a.option_strings}
    assert {k: helps[k] for k in list(helps)[4:] if k not in ("--cache",)} == {
        "--n-rooms": "rooms per flat",
        "--arenas": "number of generated flats (one per seed)",
        "--seeds": "flats to generate (one flat, run and reservoir per seed): a count N (seeds "
                   "--seed ... --seed+N-1) or seeds as ranges and lists, e.g. 100-119 or "
                   "0-9,15 (tuning seeds 0-9, held-out seeds 100-119)",
        "--ticks-per-room": "recorded ticks per room of the flat",
        "--rho": "wall-side switch probability",
        "--neurons": "reservoir size",
        "--units": "SFA and ICA units (default 0: twice the number of rooms; 'auto': two per "
                   "region of the SFA slowness spectrum, without labels)",
        "--leak": "leak rates, one per group of neurons (split evenly; default: SMC09's halves "
                  "0.05,0.15)",
        "--slow-pool": "time constant of a slow pool, a leaky running mean of the reservoir "
                       "state appended to the SFA input (default 50, chosen on tuning flats "
                       "0-9; 0: off, SMC09's model)",
        "--ica-restarts": "FastICA restarts, best kept without labels",
        "--sfa-cutoff": "relative whitening cutoff in (0, 1), or 'auto'",
        "--decoder-features": "slow features the decoder over rooms reads (default 12 per "
                              "room; 0: the room cells' own units)",
        "--hold": "recovered = right for this many consecutive ticks",
        "--ceiling": "also report the supervised ceiling",
        "--select": "choose the leak pair (16 pairs) and the unit count (n or 2 n for n rooms, "
                    "unless --units K) per flat from the recording alone, by a label-free "
                    "criterion, instead of --leak; report it",
        "--select-criterion": "label-free criterion of --select",
        "--figures": "write PNGs"}
    metavars = {a.option_strings[0]: a.metavar for a in parser._actions if a.option_strings}
    assert (metavars["--units"], metavars["--slow-pool"], metavars["--decoder-features"]) == (
        "K|auto", "TICKS", "K")
    text = " ".join(parser.format_help().split())
    assert ("--sfa-cutoff SFA_CUTOFF relative whitening cutoff in (0, 1), or 'auto' (default: "
            "1e-8)") in text
    a = _parse(["--no-ceiling", "--no-figures", "--select"])
    assert (a.ceiling, a.figures, a.select) == (False, False, True)
    assert _parse(["--ceiling", "--no-select"]).ceiling is True


@pytest.mark.parametrize(("text", "value"), [("auto", "auto"), (" auto ", "auto"), ("0", 0),
                                             ("500", 500), ("7", 7)])
def test_units_takes_a_count_or_auto(text, value):
    assert R._units(text) == value


@pytest.mark.parametrize("text", ["-1", "501", "many", "2.5", "AUTO"])
def test_units_refuses_the_rest_word_for_word(text):
    with pytest.raises(argparse.ArgumentTypeError) as e:
        R._units(text)
    assert str(e.value) == f"got {text!r}; needs an integer in [0, 500] or 'auto'"
    assert e.value.__cause__ is None and e.value.__suppress_context__


def test_no_neurons_are_refused_by_their_type(capsys):
    # one leak rate: not the leak groups' check, the option's own bound
    msg = _refused(capsys, ["--leak", "0.1", "--neurons", "0"])
    assert msg.startswith("argument --neurons: ") and "cannot hold" not in msg


def test_the_checks_across_options(capsys):
    assert _refused(capsys, ["--neurons", "1"]) == (
        "argument --neurons: 1 neuron(s) cannot hold the 2 groups of --leak (one group of "
        "neurons per leak rate)")
    assert _refused(capsys, ["--select-criterion", "slowness"]) == (
        "argument --select-criterion: only with --select (the criterion it chooses by); add "
        "--select or leave it out")
    assert _parse(["--select", "--select-criterion", "slowness"]).select
    assert _refused(capsys, ["--select", "--units", "auto"]) == (
        "argument --units: 'auto' and --select each choose the unit count without labels; "
        "leave one out")
    assert _parse(["--select", "--units", "4"]).units == 4
    assert _parse(["--units", "auto"]).units == "auto"
    assert _refused(capsys, ["--arenas", "3", "--seeds", "0,1"]) == (
        "argument --arenas: 3 flats need as many seeds; --seeds gives 2")
    assert _parse(["--arenas", "3", "--seeds", "0-2"]).arenas == 3
    assert _parse(["--arenas", "3", "--seeds", "2"]).arenas == 3     # a count: seed ...


def test_the_unit_counts_against_the_sfa_inputs(capsys):
    small = ["--neurons", "2", "--leak", "0.1"]
    # 2 neurons + 8 sensors, doubled by the slow pool: 20 inputs; 2 per room by default
    assert _parse([*small, "--n-rooms", "10"]).n_rooms == 10
    assert _refused(capsys, [*small, "--n-rooms", "11"]) == (
        "argument --units: 22 (the default: 2 per room) exceeds the 20 inputs of SFA "
        "(2 neurons + 8 sensors, twice that with the slow pool)")
    assert _parse([*small, "--slow-pool", "0", "--n-rooms", "5"]).n_rooms == 5
    assert _refused(capsys, [*small, "--slow-pool", "0", "--n-rooms", "6"]) == (
        "argument --units: 12 (the default: 2 per room) exceeds the 10 inputs of SFA "
        "(2 neurons + 8 sensors)")
    assert _parse([*small, "--units", "20", "--n-rooms", "19"]).units == 20
    assert _refused(capsys, [*small, "--units", "21"]) == (
        "argument --units: 21 exceeds the 20 inputs of SFA (2 neurons + 8 sensors, twice that "
        "with the slow pool)")
    probe = UnitCountParams().probe
    assert _refused(capsys, [*small, "--slow-pool", "0", "--units", "auto"]) == (
        f"argument --units: {probe} (the probe fit of --units auto) exceeds the 10 inputs of "
        "SFA (2 neurons + 8 sensors)")
    # --quick: at most 150 neurons, (150 + 8) x 2 = 316 inputs
    assert _parse(["--quick", "--neurons", "200", "--units", "316"]).units == 316
    assert _refused(capsys, ["--quick", "--neurons", "200", "--units", "317"]) == (
        "argument --units: 317 exceeds the 316 inputs of SFA (150 neurons + 8 sensors, twice "
        "that with the slow pool)")
    assert _parse(["--neurons", "200", "--units", "416"]).units == 416
    # --decoder-features when given (its default is capped by the inputs instead)
    assert _parse([*small, "--decoder-features", "20"]).decoder_features == 20
    assert _refused(capsys, [*small, "--decoder-features", "21"]) == (
        "argument --decoder-features: 21 exceeds the 20 inputs of SFA (2 neurons + 8 sensors, "
        "twice that with the slow pool)")
    assert _parse([*small, "--n-rooms", "2"]).decoder_features is None


def _ns(**kw: Any) -> argparse.Namespace:
    return argparse.Namespace(**{"seed": 4, "seeds": 1, "arenas": None, **kw})


def test_the_flats_seeds():
    assert R._seeds(_ns()) == [4]
    assert R._seeds(_ns(seeds=3)) == [4, 5, 6]
    assert R._seeds(_ns(seeds=[9, 2, 7])) == [9, 2, 7]
    assert R._seeds(_ns(arenas=3)) == [4, 5, 6]                  # --arenas over a count
    assert R._seeds(_ns(arenas=2, seeds=5)) == [4, 5]
    assert R._seeds(_ns(arenas=2, seeds=[9, 2, 7])) == [9, 2]
    assert R._seeds(_ns(arenas=3, seeds=[9, 2, 7])) == [9, 2, 7]
    with pytest.raises(SystemExit) as e:
        R._seeds(_ns(arenas=4, seeds=[9, 2, 7]))
    assert str(e.value) == "--arenas 4 needs as many seeds, --seeds gives 3"


class Rec:
    """A stand-in recording: regions per tick (-1: none), sensors, poses."""

    def __init__(self, region: list[int], names: list[str], sensors=None) -> None:
        self.region, self.region_names = np.array(region), names
        n = len(region)
        self.sensors = np.arange(n * 2.0).reshape(n, 2) if sensors is None else sensors
        self.x, self.y = np.arange(n) + 0.5, np.arange(n) + 100.25
        self.heading = np.arange(n) / 10

    def __len__(self) -> int:
        return len(self.region)


def test_room_labels_index_the_rooms_given():
    rec = Rec([0, 1, 2, -1, 2, 0], ["room_0", "corridor", "room_1"])
    assert R.room_labels(rec, ["room_1", "room_0"]).tolist() == [1, -1, 0, -1, 0, 1]
    assert R.room_labels(rec, ["room_0"]).tolist() == [0, -1, -1, -1, -1, 0]
    # a region named "none" is no room either; no region at all reads as "none"
    assert R.room_labels(Rec([-1, 0], ["x"]), ["none"]).tolist() == [0, -1]


def test_the_kidnapped_test_run(monkeypatch):
    drawn: list[tuple] = []
    arena = SimpleNamespace(name="flat7", regions=[
        SimpleNamespace(name="room_0", rects=[(0.0, 0.0, 40.0, 30.0)]),
        SimpleNamespace(name="room_1", rects=[(50.0, 10.0, 90.0, 60.0)])])

    def sample(rng, margin, rect):
        drawn.append((margin, rect))
        return (rect[0], rect[1], float(len(drawn)))

    arena.sample_free_pose = sample
    calls = []
    monkeypatch.setattr(R, "cached_recording", lambda cache, tag, build, ticks: calls.append(
        (cache, tag, ticks)) or build())
    monkeypatch.setattr(R, "record", lambda *a, **k: calls.append((a, k)) or "RUN")
    rec = Rec([0] * 10, ["room_0"])
    run, events = R._kidnapped_run(arena, rec, 6, 1151, 3, 0.25, ["room_0", "room_1"], "C")
    # every 500 test ticks from 150 while inside the run: 150, 650, 1150
    assert run == "RUN" and events == [150, 650, 1150]
    rng = Seeds(3).generator("kidnaps")
    rooms = []
    for _ in events:
        rooms.append(int(rng.integers(2)))       # the stand-in's pose draws nothing
    rects = {0: (5.0, 5.0, 35.0, 25.0), 1: (55.0, 15.0, 85.0, 55.0)}
    assert drawn == [(4.0, rects[r]) for r in rooms]
    kid = [(e, (rects[r][0], rects[r][1], float(i + 1))) for i, (e, r) in
           enumerate(zip(events, rooms))]
    assert calls == [("C", "flat7_kid_t1151_rho0.25", 1151),
                     ((arena, 1151), dict(seed=3 + 7919, rho=0.25, sensors="ir8", kidnaps=kid,
                                          start_pose=(5.5, 105.25, 0.5), progress=False))]
    assert all(type(v) is float for v in calls[1][1]["start_pose"])
    assert R._kidnapped_run(arena, rec, 6, 1150, 3, 0.25, ["room_0"], None)[1] == [150, 650]
    assert R._kidnapped_run(arena, rec, 6, 150, 3, 0.25, ["room_0"], None)[1] == []
    assert R._kidnapped_run(arena, rec, 6, 151, 3, 0.25, ["room_0"], None)[1] == [150]


class Cell:
    """A stand-in room cell: unit ``r`` above 0."""

    def __init__(self, r: int) -> None:
        self.unit = r

    def predict(self, Y: np.ndarray) -> np.ndarray:
        return Y[:, self.unit] > 0


#: 15 training ticks, 5 test ticks: rooms 0, 1 and the corridor (-1)
LAB = np.array([0, 0, 0, -1, 1, 1, 1, -1, 0, 0, 1, 1, -1, 0, 1, 1, 0, -1, 0, 1])


def _outputs(lab: np.ndarray, miss: tuple[int, ...] = ()) -> np.ndarray:
    Y = np.column_stack([lab == 0, lab == 1]).astype(float)
    Y[list(miss), 1] = 0.0          # room 1's unit silent at these ticks
    return Y


@pytest.fixture
def cells(monkeypatch):
    fits: list[tuple] = []

    def fit(Y, target, mask):
        fits.append((Y, target, mask))
        return Cell(int(np.argmax([np.sum(Y[target, j]) for j in range(Y.shape[1])])))

    monkeypatch.setattr(M, "fit_binary_cell", fit)
    return fits


def test_room_cells_mean_for_select(cells):
    # room 0: test ticks 15 16 18 19 (17 in the corridor) predicted F T T F, all right: 1.0;
    # room 1 silent at tick 19: T F F F against T F F T: (1/2 + 2/2) / 2 = 0.75
    assert R._room_cells_mean(_outputs(LAB, (19,)), LAB, 15, 2) == 0.875
    assert len(cells) == 2
    Y, target, mask = cells[1]
    assert _same(Y, _outputs(LAB, (19,))[:15]) and _same(target, LAB[:15] == 1)
    assert _same(mask, LAB[:15] >= 0)
    # the corridor is left out: room 0's unit firing there (tick 17) changes nothing
    Y = _outputs(LAB, (19,))
    Y[17, 0] = 1.0
    assert R._room_cells_mean(Y, LAB, 15, 2) == 0.875
    # a room the training part never entered has no cell (room 2), nor one entered alone
    assert R._room_cells_mean(_outputs(LAB), LAB, 15, 3) == 1.0 and len(cells) == 6
    alone = np.array([0, 0, -1, 0, 1, 0])
    assert math.isnan(R._room_cells_mean(_outputs(alone), alone, 4, 2))


def _same(a, b) -> bool:
    return np.array_equal(np.asarray(a), np.asarray(b))


@dataclass(frozen=True)
class Params:
    n_sfa: int = 6
    n_ica: int = 6
    leak: tuple = (0.05, 0.15)
    sfa_inputs: int = 40
    kw: tuple = ()


class Fits:
    """A stand-in RCSFAICA: smc09's settings, the unit counts, the fitted rows."""

    made: ClassVar[list[Fits]] = []
    Y: ClassVar[np.ndarray]

    def __init__(self, params: Params, n_sfa: int | None = None, n_ica: int | None = None,
                 ica_restarts: int | None = None) -> None:
        self.params = replace(params, **({"n_sfa": n_sfa} if n_sfa else {}),
                              **({"n_ica": n_ica} if n_ica else {}))
        self.restarts, self.fitted, self.seen = ica_restarts, None, []
        Fits.made.append(self)

    @classmethod
    def smc09(cls, **kw: Any) -> Fits:
        return cls(Params(kw=tuple(sorted(kw.items()))))

    def set_params(self, leak: tuple) -> Fits:
        self.params = replace(self.params, leak=leak)
        return self

    def fit(self, U: np.ndarray) -> Fits:
        warnings.warn("no convergence", ICAConvergenceWarning, stacklevel=1)
        self.fitted = U
        return self

    def transform(self, U: np.ndarray) -> np.ndarray:
        """Y; a decoder's own fit (one ICA start) 10 higher."""
        self.seen.append(U)
        Y = self.Y[: len(U)] if len(U) <= len(self.Y) else np.zeros((len(U), 2))
        return Y + (10.0 if self.restarts == 1 else 0.0)

    def features(self, U: np.ndarray) -> tuple:
        return ("features", U)


def test_the_decoders_model(monkeypatch):
    monkeypatch.setattr(R, "RCSFAICA", Fits)
    Fits.made = []
    model = Fits(Params(n_sfa=6, sfa_inputs=40))
    U = np.zeros((4, 2))
    args = argparse.Namespace(decoder_features=None)
    # 12 per room: 36 for 3 rooms, within the 40 inputs, refitted with one ICA start
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        dec = R._decoder_model(args, model, U, 3)
    assert dec is not model and dec.params.n_sfa == dec.params.n_ica == 36
    assert dec.restarts == 1 and dec.fitted is U
    assert R._decoder_model(args, model, U, 4).params.n_sfa == 40     # 48 capped at 40
    assert R._decoder_model(argparse.Namespace(decoder_features=0), model, U, 3) is model
    assert R._decoder_model(argparse.Namespace(decoder_features=6), model, U, 3) is model
    assert R._decoder_model(argparse.Namespace(decoder_features=7), model, U,
                            3).params.n_sfa == 7
    small = Fits(Params(n_sfa=6, sfa_inputs=6))
    assert R._decoder_model(args, small, U, 3) is small        # capped at its own 6


#: the kidnapped run's rooms and decoded rooms; events at test ticks 0 2 3 4 5 7 8
LAB_K = [0, 0, 1, 1, -1, 0, 0, 1]
DEC_K = [0, 1, 1, 0, 0, 0, 1, 1]
EVENTS = [0, 2, 3, 4, 5, 7, 8]


def _flat(monkeypatch, cells, lab=LAB, dec=(1, 0, 0, 0), rec_t=(2.0, np.nan, 4.0),
          **over: Any):
    """One flat of 2 rooms, 10 ticks per room, on stand-ins; ``dec``: the decoded rooms at the
    test part's room ticks 15 16 18 19."""
    Fits.made = []
    calls: dict[str, list] = {k: [] for k in ("cached", "record", "cent", "decode", "ridge",
                                              "kid", "recovery", "world", "select")}
    names = ["room_0", "room_1", "corridor"]
    region = [2 if v < 0 else v for v in lab]
    Fits.Y = _outputs(lab, (19,))
    decoded = np.zeros(len(lab), dtype=int)
    decoded[[15, 16, 18, 19]] = dec
    run = Rec([2 if v < 0 else v for v in LAB_K], names, sensors=np.full((8, 2), 7.0))
    arena = SimpleNamespace(name="flat3")

    def cached(cache, tag, build, ticks):
        calls["cached"].append((cache, tag, ticks))
        return build()

    def decode(Y, cent):
        calls["decode"].append((Y, cent))
        return decoded if len(calls["decode"]) == 1 else np.array(DEC_K)

    def ridge(X, target, n, mask, folds, gap):
        calls["ridge"].append((X, target, n, mask, folds, gap))
        pred = np.where(lab >= 0, lab, 0)
        pred[0] = 1                                   # one mistake, at tick 0 (room 0)
        return SimpleNamespace(predicted=pred, balanced_accuracy=0.66)

    def kidnapped(arena_, rec, n_train, test_len, seed, rho, rooms, cache):
        calls["kid"].append((arena_, rec, n_train, test_len, seed, rho, rooms, cache))
        return run, EVENTS

    def world(U, params):
        calls["world"].append((U, params))
        return Fits(params, n_sfa=5, n_ica=5).fit(U), 3

    def select(U, n_train, params, score, criterion, paper, paper_units, units):
        calls["select"].append((U, n_train, params, score, criterion, paper, paper_units,
                                units))
        return {"chosen": [0.02, 0.3], "chosen_units": 4, "score": score(Fits.Y)}

    monkeypatch.setattr(R, "random_flat", lambda n, seed: calls["world"].append((n, seed))
                        or arena)
    monkeypatch.setattr(R, "room_names", lambda a: ["room_0", "room_1"])
    monkeypatch.setattr(R, "cached_recording", cached)
    monkeypatch.setattr(R, "record", lambda *a, **k: calls["record"].append((a, k))
                        or Rec(region, names))
    monkeypatch.setattr(R, "RCSFAICA", Fits)
    monkeypatch.setattr(R, "fit_for_world", world)
    monkeypatch.setattr(R, "select_setting", select)
    monkeypatch.setattr(M, "fit_centroid_decoder", lambda Y, lab_, n: calls["cent"].append(
        (Y, lab_, n)) or "CENT")
    monkeypatch.setattr(M, "decode_nearest_centroid", decode)
    monkeypatch.setattr(M, "ridge_ceiling", ridge)
    monkeypatch.setattr(M, "recovery_times", lambda correct, events, hold: calls[
        "recovery"].append((correct, events, hold)) or np.array(rec_t))
    monkeypatch.setattr(R, "_kidnapped_run", kidnapped)
    args = argparse.Namespace(n_rooms=2, ticks_per_room=10, neurons=600, rho=0.25,
                              leak=[0.05, 0.15], ica_restarts=10, sfa_cutoff="1e-08",
                              slow_pool=50.0, units=0, cache="C", decoder_features=0,
                              hold=3, ceiling=True, select=False, select_criterion="slowness")
    for k, v in over.pop("args", {}).items():
        setattr(args, k, v)
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # only ICA's convergence warning is silenced
        out = R._one_flat(args, 5, over.pop("quick", False))
    return out, calls, arena, run


def test_one_flat_by_hand(monkeypatch, cells):
    out, calls, arena, run = _flat(monkeypatch, cells)
    assert calls["cached"][0] == ("C", "flat3_t20_rho0.25", 20)
    assert calls["record"] == [((arena, 20), dict(seed=5, rho=0.25, sensors="ir8",
                                                  progress=False))]
    smc, fitted = Fits.made[:2]
    assert dict(smc.params.kw) == dict(n_reservoir=600, leak=(0.05, 0.15), seed=5,
                                       ica_restarts=10, sfa_cutoff=sfa_cutoff("1e-08"),
                                       slow_pool=50.0)
    # 2 units per room, fitted on the first 3/4 (15 ticks); decoder_features 0: its own units
    assert (fitted.params.n_sfa, fitted.params.n_ica) == (4, 4) and len(Fits.made) == 2
    assert _same(fitted.fitted, np.arange(40.0).reshape(20, 2)[:15])
    assert {k: out[k] for k in ("seed", "arena", "ticks", "units", "regions_from_spectrum",
                                "leak", "decoder_features", "rooms_scored")} == {
        "seed": 5, "arena": "flat3", "ticks": 20, "units": 4, "regions_from_spectrum": None,
        "leak": [0.05, 0.15], "decoder_features": 4, "rooms_scored": 2}
    # occupancy: 8 of 20 ticks in each room
    assert out["room_occupancy"] == [0.4, 0.4]
    # the room cells (see test_room_cells_mean_for_select): 1.0 and 0.75
    assert out["room_cell_balanced_accuracy"] == [1.0, 0.75] and out["room_cell_mean"] == 0.875
    assert out["room_cell_units"] == [0, 1]
    Y, target, mask = cells[1]
    assert _same(Y, Fits.Y[:15]) and _same(target, LAB[:15] == 1)
    assert _same(mask, LAB[:15] >= 0)
    # the centroids from the training part's room ticks; decoded 1 0 0 0 at test ticks
    # 15 16 18 19 (rooms 1 0 0 1): room 0 2 of 2, room 1 1 of 2
    (cY, clab, cn), = calls["cent"]
    assert _same(cY, Fits.Y[:15][LAB[:15] >= 0]) and _same(clab, LAB[:15][LAB[:15] >= 0])
    assert cn == 2 and calls["decode"][0][1] == "CENT" and _same(calls["decode"][0][0], Fits.Y)
    assert out["decoder_balanced_accuracy"] == 0.75
    # the ceiling: the one mistake at tick 0 costs each room 1/16
    X, tgt, n, m, folds, gap = calls["ridge"][0]
    assert X == ("features", calls["record"] and X[1]) and _same(X[1], np.arange(40.0)
                                                                 .reshape(20, 2))
    assert _same(tgt, np.where(LAB >= 0, LAB, 0)) and _same(m, LAB >= 0)
    assert (n, folds, gap) == (2, 5, 50)
    assert out["ceiling_room_balanced_accuracy"] == [15 / 16, 15 / 16]
    assert out["ceiling_room_mean"] == 15 / 16 and out["gap_to_ceiling"] == 15 / 16 - 0.875
    assert out["ceiling_decoder_balanced_accuracy"] == 0.66
    # the kidnaps: the test run from the end of training, 5 ticks; the reservoir carried on
    assert calls["kid"] == [(arena, calls["kid"][0][1], 15, 5, 5, 0.25, ["room_0", "room_1"],
                             "C")]
    assert isinstance(calls["kid"][0][1], Rec) and _same(calls["kid"][0][1].sensors,
                                                         np.arange(40.0).reshape(20, 2))
    seen = fitted.seen[-1]
    assert _same(seen, np.concatenate([np.arange(30.0).reshape(15, 2), run.sensors]))
    assert _same(calls["decode"][1][0], np.zeros((8, 2))) and calls["decode"][1][1] == "CENT"
    # events: 0 is no event, 3 stays in room 1, 4 lands in the corridor, 8 is past the run
    correct, events, hold = calls["recovery"][0]
    assert events == [2, 5, 7] and hold == 3
    assert correct.tolist() == [True, False, True, False, True, True, False, True]
    assert (out["kidnap_events"], out["kidnap_recovery_ticks"], out["kidnap_recovery_ticks_max"],
            out["kidnap_unrecovered"]) == (3, 3.0, 4.0, 1)
    assert "selection" not in out


def test_one_flat_without_ceiling_and_recovery_and_a_one_room_test(monkeypatch, cells):
    lab = LAB.copy()
    lab[15:] = [0, 0, -1, 0, 0]                      # the test part inside room 0
    out, calls, _, _ = _flat(monkeypatch, cells, lab=lab, rec_t=(np.nan, np.nan),
                             args={"ceiling": False})
    assert calls["ridge"] == [] and "ceiling_room_mean" not in out
    assert math.isnan(out["decoder_balanced_accuracy"])
    assert math.isnan(out["kidnap_recovery_ticks"]) and math.isnan(
        out["kidnap_recovery_ticks_max"]) and out["kidnap_unrecovered"] == 2


def test_one_flat_leaves_out_rooms_without_a_cell(monkeypatch, cells):
    lab = np.array([0, 0, 0, -1, 0, 0, 0, -1, 0, 0, 0, 0, -1, 0, 0, 1, 0, -1, 0, 1])
    out, _, _, _ = _flat(monkeypatch, cells, lab=lab)
    # room 1 never entered in training; room 0 then alone: neither has a cell
    assert out["room_cell_units"] == [-1, -1] and out["rooms_scored"] == 0
    assert all(math.isnan(v) for v in out["room_cell_balanced_accuracy"])
    assert math.isnan(out["room_cell_mean"]) and cells == []


def test_one_flat_quick_auto_and_select(monkeypatch, cells):
    out, calls, _, _ = _flat(monkeypatch, cells, quick=True, args={
        "units": "auto", "neurons": 600, "ica_restarts": 10, "ticks_per_room": 4000,
        "decoder_features": None})
    # --quick: 3000 ticks per room at most, 150 neurons, 3 ICA starts
    assert calls["cached"][0] == ("C", "flat3_t6000_rho0.25", 6000)
    kw = dict(Fits.made[0].params.kw)
    assert (kw["n_reservoir"], kw["ica_restarts"]) == (150, 3)
    U, params = calls["world"][1]
    assert params is Fits.made[0].params
    assert out["units"] == 5 and out["regions_from_spectrum"] == 3
    # the decoder's own fit: 12 per room = 24 features
    assert out["decoder_features"] == 24
    out, calls, _, _ = _flat(monkeypatch, cells, args={"select": True, "units": 0})
    (U, n_train, params, _, criterion, paper, paper_units, units), = calls["select"]
    assert (n_train, criterion, paper, paper_units, units) == (15, "slowness", (0.05, 0.15),
                                                              4, (2, 4))
    assert (params.n_sfa, params.n_ica) == (4, 4) and U.shape == (20, 2)
    # the chosen pair and unit count are fitted; the score is the room cells' mean
    assert out["leak"] == [0.02, 0.3] and out["units"] == 4
    assert out["selection"]["score"] == 0.875
    _, calls, _, _ = _flat(monkeypatch, cells, args={"select": True, "units": 6})
    assert calls["select"][0][6:] == (6, (6,))
    # --units auto without --quick: the first 15 ticks; a decoder of its own (7 features):
    # the centroids from its outputs, not the cells'
    out, calls, _, _ = _flat(monkeypatch, cells, args={"units": "auto", "decoder_features": 7})
    assert _same(calls["world"][1][0], np.arange(30.0).reshape(15, 2))
    assert out["decoder_features"] == 7
    assert _same(calls["cent"][0][0], Fits.Y[:15][LAB[:15] >= 0] + 10.0)
    assert _same(calls["decode"][0][0], Fits.Y + 10.0)


def test_run_summarises_the_flats(monkeypatch, tmp_path):
    rows = [
        dict(room_cell_mean=0.8, decoder_balanced_accuracy=0.9, ceiling_room_mean=0.95,
             ceiling_decoder_balanced_accuracy=0.9, gap_to_ceiling=0.15,
             kidnap_recovery_ticks=10.0, kidnap_recovery_ticks_max=20.0, kidnap_unrecovered=1,
             rooms_scored=3, decoder_features=36, units=6),
        dict(room_cell_mean=0.6, decoder_balanced_accuracy=float("nan"), ceiling_room_mean=0.85,
             ceiling_decoder_balanced_accuracy=0.7, gap_to_ceiling=0.25,
             kidnap_recovery_ticks=30.0, kidnap_recovery_ticks_max=40.0, kidnap_unrecovered=2,
             rooms_scored=3, decoder_features=36, units=5),
    ]
    seen, written, figs = [], [], []

    def one(args, seed, quick):
        seen.append((seed, quick))
        return dict(rows[len(seen) - 1])

    monkeypatch.setattr(R, "_one_flat", one)
    monkeypatch.setattr(R, "write_metrics", lambda out, m, summary: written.append(
        (out, summary)))
    monkeypatch.setattr(R, "_figure", lambda *a: figs.append(a))
    clock = iter([10.0, 12.75])
    monkeypatch.setattr(R, "time", SimpleNamespace(perf_counter=lambda: next(clock)))
    # a program's Namespace without --select's options
    args = argparse.Namespace(out=str(tmp_path), quick=True, seed=4, seeds=[4, 9], arenas=None,
                              n_rooms=3, units=0, leak=(0.05, 0.15), slow_pool=50.0,
                              figures=True, ceiling=True)
    m = R.run(args)
    assert m["timing_s"] == {"total": 2.75}
    args.select = False
    monkeypatch.setattr(R, "time", SimpleNamespace(perf_counter=lambda: 0.0))
    assert seen == [(4, True), (9, True)]
    assert m["room_cell_mean"] == pytest.approx(0.7, rel=1e-15)
    assert m["decoder_balanced_accuracy"] == 0.9                     # the nan left out
    s = m["summary"]["room_cell_mean"]
    assert s["sd"] == pytest.approx(math.sqrt(0.02), rel=1e-12)
    assert (s["min"], s["max"], s["per_seed"]) == (0.6, 0.8, [0.8, 0.6])
    d = m["summary"]["decoder_balanced_accuracy"]
    assert (d["min"], d["max"], d["sd"]) == (0.9, 0.9, 0.0)
    assert m["kidnap_recovery_ticks"] == 20.0 and m["kidnap_recovery_ticks_max"] == 30.0
    assert m["kidnap_unrecovered"] == 3 and m["units"] == 6 and m["leak"] == [0.05, 0.15]
    assert (m["scenario"], m["quick"], m["n_rooms"], m["seeds"], m["slow_pool"]) == (
        "rooms", True, 3, [4, 9], 50.0)
    assert m["flats"] == rows and m["targets"] == R.TARGETS and "selection" not in m
    assert figs == [(tmp_path, rows, 3, [4, 9])]
    assert written[0] == (tmp_path, (
        "rooms: 3 per flat, 2 flats: room cell 0.700, decoder 0.900 (reading 36 slow features)"
        ", ceiling 0.900"))
    # a room not scored, and no ceiling: the note
    rows[1]["rooms_scored"] = 2
    seen.clear()
    args.ceiling, args.figures, args.units = False, False, "auto"
    m = R.run(args)
    assert m["units"] == [6, 5] and len(figs) == 1
    assert written[1][1] == (
        "rooms: 3 per flat, 2 flats: room cell 0.700, decoder 0.900 (reading 36 slow features)"
        " (5 of 6 rooms scored: a room that the training part never entered (or entered "
        "alone), or the test part never entered, has no room cell; a test part inside one "
        "room has no decoder score; record longer with --ticks-per-room)")
    # flats that read different counts: the line gives the least to the most, not the first's
    rows[0]["decoder_features"], rows[1]["decoder_features"] = 36, 24
    rows[1]["rooms_scored"] = 3
    seen.clear()
    R.run(args)
    assert written[2][1] == ("rooms: 3 per flat, 2 flats: room cell 0.700, decoder 0.900 "
                             "(reading 24-36 slow features)")


def test_run_with_select_and_no_decoder_score(monkeypatch, tmp_path):
    rows = [dict(room_cell_mean=0.5, decoder_balanced_accuracy=float("nan"),
                 kidnap_unrecovered=0, rooms_scored=2, decoder_features=24, units=4,
                 selection={"chosen": [0.1, 0.2]})]
    monkeypatch.setattr(R, "_one_flat", lambda args, seed, quick: dict(rows[0]))
    summaries = []
    monkeypatch.setattr(R, "selection_summary", lambda sels, seeds: summaries.append(
        (sels, seeds)) or "SUMMARY")
    written = []
    monkeypatch.setattr(R, "write_metrics", lambda out, m, summary: written.append(summary))
    args = argparse.Namespace(out=str(tmp_path), quick=False, seed=4, seeds=1, arenas=None,
                              n_rooms=2, units=0, leak=(0.05, 0.15), slow_pool=0.0,
                              select=True, figures=False, ceiling=False)
    m = R.run(args)
    assert summaries == [([{"chosen": [0.1, 0.2]}], [4])] and m["selection"] == "SUMMARY"
    assert m["leak"] == "chosen per flat by --select (see selection.chosen)"
    assert m["units"] == [4] and "selection" not in m["flats"][0]
    k = m["summary"]["kidnap_recovery_ticks"]
    assert math.isnan(k["mean"]) and math.isnan(k["min"]) and math.isnan(k["max"])
    assert written[0].endswith("(reading 24 slow features) (2 of 2 rooms scored: a room that "
                               "the training part never entered (or entered alone), or the "
                               "test part never entered, has no room cell; a test part inside "
                               "one room has no decoder score; record longer with "
                               "--ticks-per-room)")


def test_the_figure_by_flat(monkeypatch, tmp_path):
    import matplotlib
    import matplotlib.pyplot as plt

    matplotlib.use("Agg")
    saved = []

    def save(fig, path, dpi):
        ax = fig.axes[0]
        saved.append((path, dpi, tuple(fig.get_size_inches()), ax))
        figs.append(fig)

    figs: list = []
    monkeypatch.setattr(R, "save_figure", save)
    rows = [dict(room_cell_mean=0.8, decoder_balanced_accuracy=0.9, ceiling_room_mean=0.95),
            dict(room_cell_mean=0.6, decoder_balanced_accuracy=0.7, ceiling_room_mean=0.85)]
    with matplotlib.rc_context({"font.size": 13, "lines.linewidth": 3.0}):
        R._figure(tmp_path, rows, 4, [7, 12])
    (path, dpi, size, ax), = saved
    assert path == tmp_path / "rooms.png" and dpi == 110
    assert not plt.fignum_exists(figs[0].number)            # closed once saved
    assert size == (5.0, 3.6)                    # max(5, 0.45 x 2 + 2 = 2.9)
    bars = [v for p in ax.patches for v in (p.get_x(), p.get_width(), p.get_height())]
    assert bars == pytest.approx([-0.4, 0.4, 0.8, 0.6, 0.4, 0.6, 0.0, 0.4, 0.9,
                                  1.0, 0.4, 0.7], rel=1e-12, abs=1e-15)
    ceiling, chance = ax.lines
    assert ceiling.get_xdata().tolist() == [0, 1] and list(ceiling.get_ydata()) == [0.95, 0.85]
    assert (ceiling.get_marker(), ceiling.get_color(), ceiling.get_linestyle()) == (
        "_", "k", "None")
    assert (ceiling.get_markersize(), ceiling.get_markeredgewidth()) == (14, 2)
    assert list(chance.get_ydata()) == [0.25, 0.25] and chance.get_linestyle() == ":"
    assert (chance.get_color(), chance.get_linewidth()) == ("0.6", 0.8)
    assert [t.get_text() for t in ax.get_xticklabels()] == ["7", "12"]
    assert ax.get_xticklabels()[0].get_fontsize() == 7
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("flat seed", "balanced accuracy (test)")
    assert ax.get_ylim() == (0, 1.02)
    assert ax.get_title() == "room cells in generated 4-room flats"
    assert ax.title.get_fontsize() == 10
    legend = ax.get_legend()
    assert [t.get_text() for t in legend.get_texts()] == [
        "ceiling (ridge, per room)", "room cells (mean)", "decoder over rooms"]
    assert legend.get_texts()[0].get_fontsize() == 7 and legend._loc == 4   # lower right
    # 12 flats: 0.45 x 12 + 2 = 7.4 wide; no ceiling: no line but chance
    saved.clear()
    rows = [dict(room_cell_mean=0.5, decoder_balanced_accuracy=0.5)] * 12
    R._figure(tmp_path, rows, 3, list(range(12)))
    (_, _, size, ax), = saved
    assert size == pytest.approx((7.4, 3.6), rel=1e-12) and len(ax.lines) == 1
    assert list(ax.lines[0].get_ydata()) == [1 / 3, 1 / 3]
    # one flat: the ceiling read from it
    saved.clear()
    R._figure(tmp_path, [dict(room_cell_mean=0.5, decoder_balanced_accuracy=0.5,
                              ceiling_room_mean=0.75)], 2, [3])
    (_, _, _, ax), = saved
    assert len(ax.lines) == 2 and list(ax.lines[0].get_ydata()) == [0.75]
