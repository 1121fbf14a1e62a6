"""The two-rooms evaluation helpers (:mod:`hippo.scenarios._two_rooms_report`) on hand-made
inputs: which rooms a part visited, the room and corridor cells, the supervised read-out and
the kidnapping recovery on a stand-in model whose outputs are drawn by hand (the accuracies,
the slowness and the recovery ticks worked out in the comments), the recovery withheld at
the accuracy bound and one step below, the headline's every branch word for word, the leak
key, the sweep's per-seed fit on stand-ins and its summary by hand, the room masks, the fault
conditions drawn as the documented rule says and their summary by hand."""

from __future__ import annotations

import argparse
import math
import warnings
from types import SimpleNamespace
from typing import Any, ClassVar

import matplotlib
import numpy as np
import pytest

import hippo.scenarios._two_rooms_report as R
from hippo.perception import ICAConvergenceWarning
from hippo.seeds import Seeds
from hippo.sim.faults import SensorFaults

A, B, C = "A", "B", "C"
U_REC, U_KID = np.zeros((20, 8)), np.zeros((14, 8))      # the recordings (never read)


def _rooms(seq: list[str]) -> dict[str, np.ndarray]:
    s = np.array(seq)
    return {"room_b": s == B, "room": (s == A) | (s == B), "corridor": s == C}


def test_the_constants():
    assert R.TARGETS == {"room_cell_test_balanced_accuracy": 0.97, "kidnap_recovery_ticks": 15}
    assert R.RECOVERY_MIN_ACCURACY == 0.6
    assert R.SWEEP_SLOW == (0.03, 0.05, 0.08, 0.11) and R.SWEEP_FAST == (0.14, 0.15, 0.2, 0.3)
    assert R.FAULT_MODES == ("stuck0", "stuck1", "noise")
    assert R.NOISE_LEVELS == (0.01, 0.02, 0.05, 0.1)
    assert R.FAULT_TARGETS == {1: 0.90, 2: 0.80, "noise_0.1": 0.93}


def test_room_visits_says_which_rooms_a_part_missed():
    rooms = _rooms([A, C, B, C, C, A, A, B, C, C])
    assert R.room_visits(rooms, slice(0, 3)) is None
    assert R.room_visits(rooms, slice(0, 2)) == "visited only room A"
    assert R.room_visits(rooms, slice(2, 4)) == "visited only room B"
    assert R.room_visits(rooms, slice(3, 5)) == "visited neither room"
    assert R.room_visits(rooms, slice(8, 10)) == "visited neither room"
    assert R.room_visits(rooms, slice(5, 8)) is None
    # room B counts as a room, never as room A
    assert R.room_visits(_rooms([B, B]), slice(0, 2)) == "visited only room B"


def test_slowness_is_the_mean_squared_step_over_the_variance():
    Y = np.array([[-1.0, -1.0], [-1.0, 1.0], [1.0, -1.0], [1.0, 1.0]])
    # unit 0: steps 0, 2, 0 -> 4/3; var 1.  unit 1: steps 2, -2, 2 -> 12/3 = 4; var 1
    assert R._slowness(Y) == pytest.approx([4 / 3, 4.0], rel=1e-15)
    # a constant unit: steps 0 over a floor of 1e-300, not nan
    assert R._slowness(np.array([[2.0], [2.0], [2.0]])).tolist() == [0.0]
    Z = np.array([[0.0], [3.0], [0.0], [3.0]])      # steps 9 each, var 2.25
    assert R._slowness(Z) == pytest.approx([4.0], rel=1e-15)
    # each column over its own variance: steps 9 over 2.25 and 1 over 0.25
    W = np.array([[0.0, 0.0], [3.0, 1.0], [0.0, 0.0], [3.0, 1.0]])
    assert R._slowness(W) == pytest.approx([4.0, 4.0], rel=1e-15)


# the recording of the evaluation tests: 10 training ticks, 10 test ticks
TRAIN = [A, A, A, C, B, B, B, C, A, B]
TEST = [B, B, A, A, C, B, A, A, C, B]


def _outputs(seq: list[str], errors: tuple[int, ...] = ()) -> np.ndarray:
    """Unit 0: +1 in room B, -1 in room A, 0 in the corridor (+0.25 at the ticks in
    ``errors``); unit 1: +1 in the corridor, -1 elsewhere."""
    y0 = np.array([1.0 if r == B else -1.0 if r == A else 0.0 for r in seq])
    y0[list(errors)] = 0.25
    y1 = np.array([1.0 if r == C else -1.0 for r in seq])
    return np.column_stack([y0, y1])


class _Model:
    """A stand-in of the fitted RCSFAICA: its outputs for U and for the kidnapped U."""

    def __init__(self, Y: np.ndarray, Yk: np.ndarray | None = None) -> None:
        self.Y, self.Yk = Y, Yk
        self.sfa_slowness_ = np.array([0.25, 0.5])
        self.sfa_ = SimpleNamespace(n_whitened_=np.int64(7))
        self.ica_ = SimpleNamespace(converged_=np.bool_(True))

    def transform(self, U: np.ndarray, return_sfa: bool = False) -> Any:
        if U is U_REC:
            assert return_sfa
            return self.Y, self.Y[:, :1]          # the SFA outputs: unit 0 alone
        assert U is U_KID and not return_sfa
        return self.Yk


# the kidnapped recording: events at 0, 5 and 10, hold 2; "right" means the room cell
# (unit 0 > 0: room B) agrees with the room, or the robot is in the corridor
#   tick     0  1  2  3  4  5  6  7  8  9 10 11 12 13
#   right    F  T  T  T  T  F  T  F  T  T  F  T  F  T      (tick 3 in the corridor)
# event 0: first two right in a row at 1 -> 1 tick; event 5: at 8 -> 3 ticks;
# event 10 (until the end, 13): never -> nan
KID = [A, A, A, C, A, A, A, A, A, A, A, A, A, A]
WRONG = (0, 3, 5, 7, 10, 12)


def _kidnapped() -> tuple[np.ndarray, dict[str, np.ndarray]]:
    Yk = _outputs(KID)
    Yk[list(WRONG), 0] = 1.0                     # read as room B
    return Yk, _rooms(KID)


def _evaluate(Y: np.ndarray, moved: list[bool] | None = None, seq: list[str] | None = None,
              **kw: Any) -> dict[str, Any]:
    Yk, kid_rooms = _kidnapped()
    rooms = _rooms(seq or TRAIN + TEST)
    if moved is None:
        return R._evaluate(_Model(Y), U_REC, rooms, 10, None, None, [], [], 2)
    return R._evaluate(_Model(Y, Yk), U_REC, rooms, 10, U_KID, kid_rooms, [0, 5, 10], moved,
                       kw.get("hold", 2))


def test_the_room_and_corridor_cells_by_hand():
    # the test part's rooms: B at 10, 11, 15, 19, A at 12, 13, 16, 17; tick 12 (room A)
    # reads 0.25: room B; the room cell (unit 0, threshold 0 between -1 and 1) gets 4 of 4 B
    # and 3 of 4 A right: (1 + 3/4) / 2 = 0.875; the corridor cell (unit 1) every tick
    Y = _outputs(TRAIN + TEST, errors=(12,))
    out = _evaluate(Y)
    assert out["room_cell_unit"] == 0 and out["corridor_cell_unit"] == 1
    assert out["room_cell"].threshold == 0.0 and out["room_cell"].polarity == 1
    assert out["room_cell_train_balanced_accuracy"] == 1.0
    assert out["room_cell_test_balanced_accuracy"] == 0.875
    assert out["corridor_cell_test_balanced_accuracy"] == 1.0
    # the supervised read-out of unit 0 fitted on the training rooms is unit 0 itself, its
    # threshold chosen on the training rooms (0; with the corridor's 0s it would be 0.5,
    # and tick 12 read right)
    assert out["sfa_supervised_readout_test_balanced_accuracy"] == pytest.approx(0.875)
    # training slowness: unit 0 (8/9) / 0.8 = 10/9, unit 1 (16/9) / 0.64 = 25/9: unit 0
    assert out["room_cell_is_slowest"] is True
    assert out["sfa_slowness"] == [0.25, 0.5] and out["sfa_whitened_dims"] == 7
    assert type(out["sfa_whitened_dims"]) is int and out["ica_converged"] is True
    assert out["Y"] is Y and np.array_equal(out["Ysfa"], Y[:, :1])
    assert "room_cell_unscored" not in out and "kidnap_recovery_ticks" not in out
    assert set(out) == {"room_cell_unit", "room_cell_is_slowest",
                        "room_cell_train_balanced_accuracy", "room_cell_test_balanced_accuracy",
                        "corridor_cell_unit", "corridor_cell_test_balanced_accuracy",
                        "sfa_supervised_readout_test_balanced_accuracy", "sfa_slowness",
                        "sfa_whitened_dims", "ica_converged", "Y", "Ysfa", "room_cell",
                        "corridor_cell"}


def test_the_room_cell_not_the_slowest_unit():
    # unit 1 made the room cell: room B +1, room A -1, corridor -1; unit 0 the slower one
    # (it holds still: one step in ten)
    seq = TRAIN + TEST
    y1 = np.array([1.0 if r == B else -1.0 for r in seq])
    y0 = np.array([0.0] * 5 + [1.0] * 15)
    out = _evaluate(np.column_stack([y0, y1]))
    assert out["room_cell_unit"] == 1 and out["room_cell_is_slowest"] is False


def test_the_room_cell_the_slowest_unit_other_than_the_first():
    # unit 0 flips every tick (slowness 4), unit 1 is the room cell: training slowness
    # (12/9) / 0.96 = 1.39, the slowest
    seq = TRAIN + TEST
    y0 = np.array([(-1.0) ** t for t in range(20)])
    y1 = np.array([1.0 if r == B else -1.0 for r in seq])
    out = _evaluate(np.column_stack([y0, y1]))
    assert out["room_cell_unit"] == 1 and out["room_cell_is_slowest"] is True


def test_the_cells_are_fitted_on_every_training_tick():
    # room B only at the first training tick: without it the cell had one class
    seq = [B, A, A, C, A, A, C, A, A, A, *TEST]
    out = _evaluate(_outputs(seq), seq=seq)
    assert out["room_cell_test_balanced_accuracy"] == 1.0


def test_the_supervised_read_out_is_fitted_on_the_training_rooms_only():
    # SFA unit 0 = +1 in room B, -1 in room A but +5 in the training corridor: the least
    # squares fit over the rooms alone is exact (w = 1, 0); with the corridor it would tilt
    Y = _outputs(TRAIN + TEST)
    Y[[3, 7], 0] = 5.0
    Y[[14, 18], 0] = 5.0
    out = _evaluate(Y)
    assert out["sfa_supervised_readout_test_balanced_accuracy"] == 1.0
    assert out["room_cell_test_balanced_accuracy"] == 1.0


def test_a_test_part_in_one_room_is_not_scored():
    seq = [*TRAIN, A, A, C, A, A, C, A, A, A, A]
    Y = _outputs(seq)
    out = _evaluate(Y, seq=seq)
    assert math.isnan(out["room_cell_test_balanced_accuracy"])
    assert out["room_cell_unscored"] == "the test part visited only room A"
    out = _evaluate(Y, moved=[True, True, True], seq=seq)
    assert math.isnan(out["kidnap_recovery_ticks"])
    assert math.isnan(out["kidnap_recovery_ticks_max"])
    assert out["kidnap_recovery_withheld"] == "room cell not scored on the test part"
    assert out["kidnap_recovery_ticks_each"] == [1.0, 3.0, pytest.approx(math.nan, nan_ok=True)]


def test_the_kidnapping_recovery_by_hand():
    Y = _outputs(TRAIN + TEST, errors=(12,))
    out = _evaluate(Y, moved=[True, True, True])
    each = out["kidnap_recovery_ticks_each"]
    assert each[:2] == [1.0, 3.0] and math.isnan(each[2]) and type(each) is list
    assert out["kidnap_recovery_ticks"] == 2.0 and out["kidnap_recovery_ticks_max"] == 3.0
    assert out["kidnap_unrecovered"] == 1 and type(out["kidnap_unrecovered"]) is int
    assert "kidnap_recovery_withheld" not in out
    Yk, _ = _kidnapped()
    assert np.array_equal(out["Y_kid"], Yk)
    # a lift that did not move the robot is left out: 3 ticks, mean and max
    out = _evaluate(Y, moved=[False, True, True])
    assert out["kidnap_recovery_ticks"] == 3.0 and out["kidnap_recovery_ticks_max"] == 3.0
    assert out["kidnap_unrecovered"] == 1
    out = _evaluate(Y, moved=[True, True, False])
    assert (out["kidnap_recovery_ticks"], out["kidnap_unrecovered"]) == (2.0, 0)
    # flags written 0 and 1 (as a JSON file of another tool may): the same
    out = _evaluate(Y, moved=[0, 1, 1])
    assert out["kidnap_recovery_ticks"] == 3.0 and out["kidnap_unrecovered"] == 1
    # no real move recovered: nan, not an error, and no warning of an empty mean
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = _evaluate(Y, moved=[False, False, True])
    assert math.isnan(out["kidnap_recovery_ticks"]) and math.isnan(
        out["kidnap_recovery_ticks_max"])
    assert out["kidnap_unrecovered"] == 1
    # hold 3: event 0 first right three in a row at 1 (1, 2, 3 with the corridor) -> 1;
    # event 5 never (6 of 5..9 right, then 8, 9 only two) -> nan
    out = _evaluate(Y, moved=[True, True, True], hold=3)
    assert out["kidnap_recovery_ticks_each"][0] == 1.0
    assert math.isnan(out["kidnap_recovery_ticks_each"][1])


def test_the_recovery_is_withheld_below_the_accuracy_bound(monkeypatch):
    Y = _outputs(TRAIN + TEST, errors=(12,))                    # room cell 0.875
    monkeypatch.setattr(R, "RECOVERY_MIN_ACCURACY", 0.875)
    out = _evaluate(Y, moved=[True, True, True])
    assert out["kidnap_recovery_ticks"] == 2.0 and "kidnap_recovery_withheld" not in out
    monkeypatch.setattr(R, "RECOVERY_MIN_ACCURACY", 0.8750000000000001)
    out = _evaluate(Y, moved=[True, True, True])
    assert math.isnan(out["kidnap_recovery_ticks"]) and math.isnan(
        out["kidnap_recovery_ticks_max"])
    assert out["kidnap_recovery_withheld"] == (
        "room cell 0.88 balanced accuracy, below 0.8750000000000001: too near chance")
    assert out["kidnap_recovery_ticks_each"][:2] == [1.0, 3.0]       # still listed
    assert out["kidnap_unrecovered"] == 1


def test_the_room_cell_is_fitted_on_every_training_tick():
    # room B only at tick 0 of the training part: the cell needs it (both classes)
    Y = np.array([[1.0], [-1.0], [-1.0], [0.0], [1.0], [-1.0]])
    assert R._room_cell_accuracy(Y, _rooms([B, A, A, C, B, A]), 4) == 1.0


def test_the_room_cell_accuracy_of_outputs():
    Y = _outputs(TRAIN + TEST, errors=(12,))
    assert R._room_cell_accuracy(Y, _rooms(TRAIN + TEST), 10) == 0.875
    # with tick 12 right, two of room B's four test ticks read as room A: (2/4 + 1) / 2
    Y = _outputs(TRAIN + TEST)
    Y[[10, 11], 0] = -1.0
    assert R._room_cell_accuracy(Y, _rooms(TRAIN + TEST), 10) == 0.75


# ------------------------------------------------------------------------------ the headline
def _m(**changes: Any) -> dict[str, Any]:
    m = {"seeds": [1, 2, 3], "seeds_scored": 3, "kidnap_recovery_ticks": 12.4,
         "kidnap_recovery_withheld_seeds": [], "kidnap_unrecovered": 0,
         "room_cell_test_balanced_accuracy": 0.9712, "corridor_cell_test_balanced_accuracy":
         0.8349, "unscored_seeds": {}}
    m.update(changes)
    return m


TAIL = " (targets: 0.97, 15 ticks)"


def test_the_headline_of_a_run_every_seed_scored():
    assert R.headline(_m(), (0.05, 0.15)) == (
        "two rooms (3 seed(s), leaks 0.05, 0.15): room cell 0.97 balanced accuracy on the test "
        "part, corridor cell 0.83 (leaks 0.11, 0.14); after a kidnapping the room cell is right "
        "again after 12 ticks" + TAIL)
    assert R.headline(_m(kidnap_unrecovered=2, kidnap_recovery_ticks=12.5), (1.0,)) == (
        "two rooms (3 seed(s), leaks 1): room cell 0.97 balanced accuracy on the test part, "
        "corridor cell 0.83 (leaks 0.11, 0.14); after a kidnapping the room cell is right "
        "again after 12 ticks (2 kidnap(s) never recovered, left out of the mean)" + TAIL)


def test_the_headline_of_seeds_not_scored_and_recovery_withheld():
    nan = math.nan
    text = R.headline(_m(seeds_scored=2, kidnap_recovery_ticks=nan,
                         kidnap_recovery_withheld_seeds=[3], kidnap_unrecovered=1,
                         unscored_seeds={"2": "the test part visited only room A"}),
                      (0.05, 0.15))
    assert text == (
        "two rooms (3 seed(s), leaks 0.05, 0.15): room cell 0.97 balanced accuracy on the test "
        "part (2 of 3 seeds scored), corridor cell 0.83 (leaks 0.11, 0.14); after a kidnapping "
        "recovery not reported (1 kidnap(s) never recovered) (1 seed(s) left out: a room cell "
        "below 0.6 balanced accuracy is too near chance for its recovery to mean anything)"
        + TAIL + "\nnot scored: seed 2: the test part visited only room A (record longer with "
        "--ticks, or give a lower --rho)")
    text = R.headline(_m(seeds_scored=0, room_cell_test_balanced_accuracy=nan,
                         corridor_cell_test_balanced_accuracy=nan, kidnap_recovery_ticks=nan),
                      (0.05, 0.15))
    assert text == (
        "two rooms (3 seed(s), leaks 0.05, 0.15): room cell not scored (0 of 3 seeds scored), "
        "corridor cell not scored (leaks 0.11, 0.14); after a kidnapping recovery not reported"
        + TAIL)
    # every seed scored, nothing withheld, no recovery: "no recovery"
    assert R.headline(_m(kidnap_recovery_ticks=nan, kidnap_unrecovered=4), (0.05, 0.15)) == (
        "two rooms (3 seed(s), leaks 0.05, 0.15): room cell 0.97 balanced accuracy on the test "
        "part, corridor cell 0.83 (leaks 0.11, 0.14); after a kidnapping no recovery (4 "
        "kidnap(s) never recovered)" + TAIL)


def test_the_headline_groups_unscored_seeds_by_reason_ten_at_most():
    why = {str(s): "the test part visited only room B" for s in range(11)}
    why["20"] = "the test part visited neither room"
    text = R.headline(_m(seeds=list(range(21)), seeds_scored=9, unscored_seeds=why), (0.05,))
    lines = text.split("\n")
    assert lines[0].endswith(TAIL) and "(9 of 21 seeds scored)" in lines[0]
    assert lines[1:] == [
        "not scored: seeds 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, ...: the test part visited only room B "
        "(record longer with --ticks, or give a lower --rho)",
        "not scored: seed 20: the test part visited neither room (record longer with --ticks, or "
        "give a lower --rho)"]
    two = R.headline(_m(seeds_scored=1, unscored_seeds={"1": "y", "3": "y"}), (0.05,))
    assert two.split("\n")[1] == ("not scored: seeds 1, 3: y (record longer with --ticks, or "
                                  "give a lower --rho)")
    why = {str(s): "x" for s in range(10)}
    text = R.headline(_m(seeds=list(range(10)), seeds_scored=0, unscored_seeds=why), (0.05,))
    assert text.split("\n")[1] == ("not scored: seeds 0, 1, 2, 3, 4, 5, 6, 7, 8, 9: x (record "
                                   "longer with --ticks, or give a lower --rho)")


# ------------------------------------------------------------------------------- the sweep
def test_the_leak_key():
    assert R._leak_key((0.05, 0.15)) == "leak_0.05_0.15"
    assert R._leak_key((1.0,)) == "leak_1" and R._leak_key((1e-5, 0.3)) == "leak_1e-05_0.3"


def test_the_sweep_of_one_seed_on_stand_ins(monkeypatch):
    calls: dict[str, Any] = {}

    class _RCSFAICA:
        @staticmethod
        def smc09(**kw: Any) -> SimpleNamespace:
            calls["smc09"] = kw
            return SimpleNamespace(params="base")

    def fit_leak_sweep(U: Any, leaks: Any, base: Any) -> list[str]:
        calls["fit"] = (U, leaks, base)
        warnings.warn("did not converge", ICAConvergenceWarning, stacklevel=1)
        warnings.warn("something else", RuntimeWarning, stacklevel=1)
        return [f"model{i}" for i in range(len(leaks))]

    clock = iter([100.0, 102.5, 200.0, 201.0])
    monkeypatch.setattr(R, "time", SimpleNamespace(perf_counter=lambda: next(clock)))

    def evaluate(model: str, *a: Any) -> dict[str, float]:
        calls.setdefault("evaluate", []).append((model, *a))
        i = int(model[5:])
        return {"room_cell_test_balanced_accuracy": i / 100, "kidnap_recovery_ticks": float(i)}

    monkeypatch.setattr(R, "RCSFAICA", _RCSFAICA)
    monkeypatch.setattr(R, "fit_leak_sweep", fit_leak_sweep)
    monkeypatch.setattr(R, "_evaluate", evaluate)
    args = argparse.Namespace(n_sfa=6, n_ica=4, ica_score="kurtosis", ica_algorithm="fastica",
                              sfa_cutoff="auto", hold=5)
    U = np.arange(12.0).reshape(6, 2)
    with pytest.warns(RuntimeWarning, match="something else") as w:
        out = R._leak_sweep_one(args, 50, 3, 7, U, "rooms", 4, "U_kid", "kid", [1], [True])
    assert [type(x.message) for x in w] == [RuntimeWarning]    # only ICA's is silenced
    assert calls["smc09"] == {"n_reservoir": 50, "seed": 7, "n_sfa": 6, "n_ica": 4,
                              "ica_restarts": 3, "ica_score": "kurtosis",
                              "ica_algorithm": "fastica", "sfa_cutoff": "auto"}
    fitted_on, leaks, base = calls["fit"]
    assert np.array_equal(fitted_on, U[:4]) and base == "base"
    assert leaks == [(a, b) for a in (0.03, 0.05, 0.08, 0.11) for b in (0.14, 0.15, 0.2, 0.3)]
    assert calls["evaluate"][5] == ("model5", U, "rooms", 4, "U_kid", "kid", [1], [True], 5)
    assert out["scores"] == {lk: (i / 100, float(i)) for i, lk in enumerate(leaks)}
    assert out["seconds"] == 2.5
    args.sfa_cutoff = "0.001"
    with pytest.warns(RuntimeWarning):
        R._leak_sweep_one(args, 50, 3, 7, U, "rooms", 4, "U_kid", "kid", [1], [True])
    assert calls["smc09"]["sfa_cutoff"] == 0.001


def test_the_sweep_summary_by_hand():
    leaks = [(a, b) for a in R.SWEEP_SLOW for b in R.SWEEP_FAST]
    s1 = {lk: (0.9, 20.0) for lk in leaks}
    s2 = {lk: (0.9, 20.0) for lk in leaks}
    s1[(0.05, 0.15)], s2[(0.05, 0.15)] = (0.96, 10.0), (0.98, 14.0)     # mean 0.97, 12
    s1[(0.03, 0.14)], s2[(0.03, 0.14)] = (0.97, 15.0), (0.97, 15.0)     # both on the bounds
    s1[(0.11, 0.3)], s2[(0.11, 0.3)] = (0.99, 15.0), (0.99, 17.0)       # 16 ticks: over
    s1[(0.08, 0.2)], s2[(0.08, 0.2)] = (0.97, math.nan), (0.95, 10.0)   # mean 0.96: under
    out = R._sweep_summary([{"scores": s1, "seconds": 1.5}, {"scores": s2, "seconds": 2.0}])
    assert out["seconds"] == 3.5
    rows = {tuple(r["leak"]): r for r in out["rows"]}
    assert [r["leak"] for r in out["rows"]] == [list(lk) for lk in leaks]
    r = rows[(0.05, 0.15)]
    assert r["room_cell_test_balanced_accuracy"] == pytest.approx(0.97)
    assert r["room_cell_test_balanced_accuracy_sd"] == pytest.approx(0.02 / math.sqrt(2))
    assert r["kidnap_recovery_ticks"] == 12.0
    assert r["kidnap_recovery_ticks_sd"] == pytest.approx(math.sqrt(8.0))
    assert rows[(0.03, 0.14)]["meets_targets"] is True
    assert rows[(0.11, 0.3)]["meets_targets"] is False
    r = rows[(0.08, 0.2)]
    assert r["kidnap_recovery_ticks"] == 10.0 and r["kidnap_recovery_ticks_sd"] == 0.0
    assert r["meets_targets"] is False
    assert rows[(0.03, 0.15)]["meets_targets"] is False
    assert rows[(0.03, 0.15)]["room_cell_test_balanced_accuracy_sd"] == 0.0


def test_the_room_masks_of_a_recording():
    rec = SimpleNamespace(region_names=["room_a", "corridor", "room_b"],
                          region=np.array([0, 1, 2, 3, 2, 0]))      # 3: no region
    m = R._room_masks(rec)
    assert m["room_b"].tolist() == [False, False, True, False, True, False]
    assert m["room"].tolist() == [True, False, True, False, True, True]
    assert m["corridor"].tolist() == [False, True, False, False, False, False]


# ------------------------------------------------------------------------------- the faults
def _sets(n: int, seed: int, quick: bool) -> list[tuple[int, ...]]:
    """The documented rule: every single sensor (the first 2 with --quick), then 3 (2) random
    pairs and 3 (2) random triples drawn without replacement from stream 'fault-sets'."""
    rng = Seeds(seed).generator("fault-sets")
    k = 2 if quick else 3
    singles = [(i,) for i in range(n)][: 2 if quick else n]
    pairs = [tuple(sorted(rng.choice(n, 2, replace=False).tolist())) for _ in range(k)]
    triples = [tuple(sorted(rng.choice(n, 3, replace=False).tolist())) for _ in range(k)]
    return singles + pairs + triples


@pytest.mark.parametrize("quick", [False, True])
def test_the_fault_conditions_follow_the_rule(quick):
    out = R._fault_conditions(8, 5, quick)
    sets = _sets(8, 5, quick)
    assert len(sets) == (6 if quick else 14)
    assert out[0] == SensorFaults()
    want = [SensorFaults.of([(i, mode) for i in s]) for s in sets for mode in R.FAULT_MODES]
    assert out[1:-4] == want
    assert out[-4:] == [SensorFaults.of(sensor_noise=sd) for sd in (0.01, 0.02, 0.05, 0.1)]
    assert len(out) == 1 + 3 * len(sets) + 4
    assert all(len(set(f.indices)) == len(f.indices) for f in out)
    assert R._fault_conditions(8, 5, quick) == out            # the same for the same seed
    assert R._fault_conditions(4, 5, quick)[1:-4] == [
        SensorFaults.of([(i, mode) for i in s]) for s in _sets(4, 5, quick)
        for mode in R.FAULT_MODES]


def _row(seed: int, variant: str, n_dead: int, mode: str, noise: float, acc: float
         ) -> dict[str, Any]:
    return {"seed": seed, "variant": variant, "n_dead": n_dead, "mode": mode, "noise": noise,
            "room_cell_test_balanced_accuracy": acc}


def test_the_fault_summary_by_hand():
    rows = []
    for v, off in (("raw", 0.0), ("guard", 0.1)):
        for seed, base in ((1, 0.9), (2, 0.7)):
            rows.append(_row(seed, v, 0, "none", 0.0, base))
            for k in (1, 2, 3):
                for j, mode in enumerate(R.FAULT_MODES):
                    rows.append(_row(seed, v, k, mode, 0.0, base - 0.1 * k - 0.01 * j + off))
            for sd in R.NOISE_LEVELS:
                rows.append(_row(seed, v, 0, "none", sd, base - sd + off))
    rows.append(_row(1, "raw", 1, "stuck0", 0.0, math.nan))      # a condition not scored
    s = R._fault_summary(rows)
    assert s["targets"] == {"1": 0.9, "2": 0.8, "noise_0.1": 0.93} and s["rows"] is rows
    raw = s["raw"]
    assert raw["dead"]["0"] == {"mean": pytest.approx(0.8), "worst_seed": 0.7,
                                "per_seed": [0.9, 0.7]}
    # one dead sensor, seed 1: (0.8 + 0.79 + 0.78) / 3, seed 2: (0.6 + 0.59 + 0.58) / 3
    d1 = raw["dead"]["1"]
    assert d1["per_seed"] == pytest.approx([0.79, 0.59])
    assert d1["mean"] == pytest.approx(0.69) and d1["worst_seed"] == pytest.approx(0.59)
    assert raw["dead_by_mode"]["2"]["stuck1"]["per_seed"] == pytest.approx([0.69, 0.49])
    assert raw["dead_by_mode"]["3"]["noise"]["mean"] == pytest.approx((0.58 + 0.38) / 2)
    assert set(raw["dead_by_mode"]) == {"1", "2", "3"}
    assert set(raw["dead_by_mode"]["1"]) == set(R.FAULT_MODES)
    assert raw["noise"]["0.05"]["per_seed"] == pytest.approx([0.85, 0.65])
    assert list(raw["noise"]) == ["0.01", "0.02", "0.05", "0.1"]
    g = s["guard"]
    assert g["dead"]["1"]["per_seed"] == pytest.approx([0.89, 0.69])
    assert g["noise"]["0.1"]["worst_seed"] == pytest.approx(0.7)
    assert g["dead"]["0"]["per_seed"] == [0.9, 0.7]       # no offset: base rows only
    # a seed without rows of a kind is left out of that kind
    s = R._fault_summary([_row(1, "raw", 0, "none", 0.0, 0.8), _row(2, "raw", 0, "none", 0.0,
                                                                     0.6),
                          _row(2, "raw", 1, "stuck0", 0.0, 0.5),
                          _row(1, "guard", 0, "none", 0.0, 0.9)] +
                         [_row(1, "raw", 0, "none", sd, 0.4) for sd in R.NOISE_LEVELS] +
                         [_row(1, "raw", k, m, 0.0, 0.3) for k in (2, 3) for m in R.FAULT_MODES]
                         + [_row(1, "guard", k, m, 0.0, 0.3) for k in (1, 2, 3)
                            for m in R.FAULT_MODES]
                         + [_row(1, "guard", 0, "none", sd, 0.4) for sd in R.NOISE_LEVELS]
                         + [_row(1, "raw", 1, m, 0.0, 0.2) for m in R.FAULT_MODES[1:]])
    assert s["raw"]["dead"]["0"]["per_seed"] == [0.8, 0.6]
    assert s["raw"]["dead"]["1"]["per_seed"] == [0.2, 0.5]
    assert s["raw"]["dead_by_mode"]["1"]["stuck0"]["per_seed"] == [0.5]
    assert s["guard"]["dead"]["0"]["per_seed"] == [0.9]


class _Guard:
    """A stand-in SensorGuard (window 2): clean adds 10 to every reading it is given."""

    made: ClassVar[list[_Guard]] = []

    def __init__(self) -> None:
        self.params = SimpleNamespace(window=2)
        self.fitted: np.ndarray | None = None
        self.cleaned: list[np.ndarray] = []
        _Guard.made.append(self)

    def fit(self, U: np.ndarray) -> _Guard:
        self.fitted = U.copy()
        return self

    def clean(self, U: np.ndarray) -> np.ndarray:
        self.cleaned.append(U.copy())
        return U + 10.0


class _Reservoir:
    """One neuron: the sum of the readings plus x0 (the state the training part ended in)."""

    def __init__(self) -> None:
        self.runs: list[tuple[np.ndarray, Any]] = []

    def run(self, U: np.ndarray, x0: Any = None) -> np.ndarray:
        self.runs.append((U.copy(), x0))
        return U.sum(axis=1, keepdims=True) + (0.0 if x0 is None else x0)


def test_the_fault_curve_on_stand_ins(monkeypatch):
    _Guard.made = []
    monkeypatch.setattr(R, "SensorGuard", _Guard)
    conditions = [SensorFaults(), SensorFaults.of([(0, "stuck1")]),
                  SensorFaults.of([(0, "stuck0"), (1, "stuck0")]),
                  SensorFaults.of(sensor_noise=0.05)]
    asked: list[Any] = []
    monkeypatch.setattr(R, "_fault_conditions", lambda *a: asked.append(a) or conditions)
    # 8 ticks of 2 sensors, 4 of training; the test part: room B, A, B, corridor
    U = np.array([[0.1, 0.2], [0.3, 0.1], [0.2, 0.2], [0.4, 0.3],
                  [0.9, 0.1], [0.1, 0.2], [0.8, 0.3], [0.6, 0.5]])
    rooms = _rooms([A, A, B, B, B, A, B, C])
    res = _Reservoir()
    # the SFA output is Z's columns (sensor 0, sensor 1, neuron); ICA keeps sensor 0 and the
    # neuron; the room cell reads sensor 0 > 0.5 as room B
    model = SimpleNamespace(reservoir_=res, sfa_=SimpleNamespace(transform=lambda Z: Z),
                            ica_=SimpleNamespace(transform=lambda Z: Z[:, [0, 2]]))
    cell = SimpleNamespace(predict=lambda Y: Y[:, 0] > 0.5)
    rows = R._fault_curve(model, U, rooms, 4, cell, 3, True)
    assert asked == [(2, 3, True)]
    (guard,) = _Guard.made
    assert np.array_equal(guard.fitted, U[:4])
    # the training run, then per condition the raw and the guarded test part from x_end =
    # the last training tick's 0.4 + 0.3 = 0.7
    assert np.array_equal(res.runs[0][0], U[:4]) and res.runs[0][1] is None
    assert all(x0 == pytest.approx([0.7]) for _, x0 in res.runs[1:]) and len(res.runs) == 9
    # the guard sees the last 2 training readings before the faulty test part
    assert np.array_equal(guard.cleaned[0], U[2:])
    assert np.array_equal(guard.cleaned[1], np.vstack([U[2:4], [[1.0, 0.1], [1.0, 0.2],
                                                                [1.0, 0.3], [1.0, 0.5]]]))
    assert np.array_equal(res.runs[2][0], U[4:] + 10.0)       # guarded: cleaned, window cut
    # rooms of the test part (the corridor, read as room B at 0.6, left out): B, A, B;
    # sensor 0 reads 0.9, 0.1, 0.8: raw clean all right (1.0); sensor 0 stuck at 1: A read
    # as B -> (1 + 0) / 2 = 0.5; stuck at 0: B never -> 0.5; guarded, every reading + 10 >
    # 0.5: 0.5
    acc = [r["room_cell_test_balanced_accuracy"] for r in rows]
    assert acc[:6] == [1.0, 0.5, 0.5, 0.5, 0.5, 0.5]
    assert [(r["variant"], r["n_dead"], r["mode"], r["sensors"], r["noise"]) for r in rows] == [
        ("raw", 0, "none", [], 0.0), ("guard", 0, "none", [], 0.0),
        ("raw", 1, "stuck1", [0], 0.0), ("guard", 1, "stuck1", [0], 0.0),
        ("raw", 2, "stuck0", [0, 1], 0.0), ("guard", 2, "stuck0", [0, 1], 0.0),
        ("raw", 0, "none", [], 0.05), ("guard", 0, "none", [], 0.05)]
    assert all(r["seed"] == 3 for r in rows)
    # the noisy condition (the 4th, j = 3) drawn from stream "sensor-faults", 3
    noisy = conditions[3].apply(U[4:], seed=Seeds(3).generator("sensor-faults", 3))
    assert np.array_equal(res.runs[7][0], noisy)
    assert not np.array_equal(noisy, conditions[3].apply(
        U[4:], seed=Seeds(3).generator("sensor-faults", 2)))
    # a float32 reservoir: the readings joined to it as float32 too
    seen: list[np.dtype] = []
    res32 = SimpleNamespace(run=lambda U, x0=None: res.run(U, x0).astype(np.float32))
    model32 = SimpleNamespace(reservoir_=res32,
                              sfa_=SimpleNamespace(transform=lambda Z: seen.append(Z.dtype) or Z),
                              ica_=model.ica_)
    R._fault_curve(model32, U, rooms, 4, cell, 3, True)
    assert seen == [np.dtype(np.float32)] * 8


def _captured(monkeypatch: pytest.MonkeyPatch) -> list[tuple[Any, Any, Any]]:
    saved: list[tuple[Any, Any, Any]] = []
    monkeypatch.setattr(R, "save_figure", lambda fig, path, dpi: saved.append((fig, path, dpi)))
    return saved


def test_the_sweep_figure_marks_the_settings_that_meet_the_targets(monkeypatch, tmp_path):
    import matplotlib.pyplot as plt

    saved = _captured(monkeypatch)
    rows = [{"leak": [a, b], "room_cell_test_balanced_accuracy": 0.9 + 0.001 * i,
             "kidnap_recovery_ticks": 20.0 - i, "meets_targets": (a, b) == (0.05, 0.15)}
            for i, (a, b) in enumerate((a, b) for a in R.SWEEP_SLOW for b in R.SWEEP_FAST)]
    with matplotlib.rc_context({"font.size": 7}):     # the sizes are the figure's own
        R._sweep_figure(tmp_path, rows)
    ((fig, path, dpi),) = saved
    assert path == tmp_path / "leak_sweep.png" and dpi == 110
    assert fig._suptitle.get_text() == ("leak sweep (bold: room cell >= 0.97 and recovery <= 15 "
                                        "ticks); SMC09: 0.05/0.15")
    ax0, ax1 = fig.axes[:2]
    assert ax0.get_title() == "room cell: balanced accuracy (test)"
    assert ax1.get_title() == "kidnapping: ticks to recover"
    assert [t.get_text() for t in ax0.get_xticklabels()] == ["0.14", "0.15", "0.2", "0.3"]
    assert [t.get_text() for t in ax0.get_yticklabels()] == ["0.03", "0.05", "0.08", "0.11"]
    assert ax0.get_xlabel() == "leak of the fast half" and ax0.get_ylabel() == (
        "leak of the slow half")
    # row i (slow leak), column j (fast leak): candidate 4 i + j; (0.05, 0.15) is 5 at (1, 1)
    Z = ax0.images[0].get_array()
    assert Z[1, 1] == pytest.approx(0.905) and Z[3, 0] == pytest.approx(0.912)
    assert ax1.images[0].get_array()[0, 3] == 17.0
    assert ax0.images[0].get_cmap().name == "viridis"
    assert ax1.images[0].get_cmap().name == "viridis_r"
    texts = {(t.get_position(), t.get_text()): t for t in ax0.texts}
    assert texts[((1, 1), "0.905")].get_fontweight() == "bold"
    assert texts[((3, 0), "0.903")].get_fontweight() == "normal"
    assert {t.get_text() for t in ax1.texts} >= {"20", "5", "15"}
    # white text on the dark end of viridis, black on the light end
    low = texts[((0, 0), "0.9")]
    high = texts[((3, 3), "0.915")]
    assert low.get_color() == "w" and high.get_color() == "k"
    # the text is white where the cell's luma 0.299 R + 0.587 G + 0.114 B is below 0.55: at
    # candidate 8 (0.908, 8/15 of the colour scale) viridis is a green whose luma is below
    # it, though its green weighted as red would not be
    r, g, b = plt.get_cmap("viridis")(8 / 15)[:3]
    assert 0.299 * r + 0.587 * g + 0.114 * b < 0.55 < 0.299 * g + 0.587 * g + 0.114 * b
    assert texts[((0, 2), "0.908")].get_color() == "w"
    for (xy, text), t in texts.items():
        r, g, b = plt.get_cmap("viridis")((float(text) - 0.9) / 0.015)[:3]
        assert t.get_color() == ("w" if 0.299 * r + 0.587 * g + 0.114 * b < 0.55 else "k"), xy
    assert ax0.title.get_fontsize() == 10 and ax1.title.get_fontsize() == 10
    assert fig._suptitle.get_fontsize() == 10
    assert tuple(fig.get_size_inches()) == (10.0, 4.2)
    assert len(fig.axes) == 4                                     # two maps, two colour bars
    cb0, cb1 = fig.axes[2:]
    # each colour bar beside its own map, 0.85 of its height
    assert ax0.get_position().x1 < cb0.get_position().x0 < ax1.get_position().x0
    assert ax1.get_position().x1 < cb1.get_position().x0
    for ax, cb in ((ax0, cb0), (ax1, cb1)):
        assert cb.get_position().height / ax.get_position().height == pytest.approx(0.85)
        assert ax.images[0].origin == "lower" and ax.get_aspect() == "auto"
        assert ax.images[0].colorbar.ax is cb
    for t in ax0.texts:
        assert (t.get_fontsize(), t.get_ha(), t.get_va()) == (8, "center", "center")
    assert not plt.fignum_exists(fig.number)                      # closed
    plt.close("all")


def test_the_fault_figure_plots_the_means(monkeypatch, tmp_path):
    import matplotlib.pyplot as plt

    saved = _captured(monkeypatch)

    def stat(x: float) -> dict[str, float]:
        return {"mean": x}

    def variant(off: float) -> dict[str, Any]:
        return {"dead": {"0": stat(0.9 + off)},
                "dead_by_mode": {str(k): {m: stat(0.9 - 0.1 * k - 0.01 * j + off)
                                          for j, m in enumerate(R.FAULT_MODES)}
                                 for k in (1, 2, 3)},
                "noise": {f"{sd:g}": stat(0.9 - sd + off) for sd in R.NOISE_LEVELS}}

    with matplotlib.rc_context({"font.size": 7}):     # the sizes are the figure's own
        R._fault_figure(tmp_path, {"raw": variant(0.0), "guard": variant(0.05)}, [3, 4, 5])
    ((fig, path, dpi),) = saved
    assert path == tmp_path / "faults.png" and dpi == 110
    assert fig._suptitle.get_text() == "room cell under sensor faults (seeds 3-5; red: targets)"
    ax0, ax1 = fig.axes
    lines = {ln.get_label(): ln for ln in ax0.lines}
    assert list(lines.get("stuck1, raw").get_ydata()) == pytest.approx([0.9, 0.79, 0.69, 0.59])
    assert list(lines["noise, guarded"].get_ydata()) == pytest.approx([0.95, 0.83, 0.73, 0.63])
    assert lines["stuck0, raw"].get_linestyle() == "--"
    assert lines["stuck0, guarded"].get_linestyle() == "-"
    targets = [(list(ln.get_xdata()), list(ln.get_ydata())) for ln in ax0.lines
               if ln.get_marker() == "_"]
    assert targets == [([1], [0.9]), ([2], [0.8])]
    noise = {ln.get_label(): ln for ln in ax1.lines}
    assert list(noise["raw"].get_xdata()) == [0.01, 0.02, 0.05, 0.1]
    assert list(noise["guarded"].get_ydata()) == pytest.approx([0.94, 0.93, 0.9, 0.85])
    assert [ln.get_ydata()[0] for ln in ax1.lines if ln.get_label().startswith("_")] == [0.93]
    assert ax0.get_xlabel() == "dead sensors (of 8), dying at the start of the test part"
    assert ax1.get_xlabel() == "added sensor noise s.d."
    assert ax0.get_ylabel() == "room cell: balanced accuracy (test)"
    assert list(ax0.get_xticks()) == [0, 1, 2, 3]
    assert tuple(fig.get_size_inches()) == (10.0, 4.0) and len(fig.axes) == 2
    assert ax0.get_position().x1 < ax1.get_position().x0          # side by side
    assert ax0.get_position().y0 == ax1.get_position().y0
    assert ax0.get_shared_y_axes().joined(ax0, ax1)
    assert fig._suptitle.get_fontsize() == 10
    for mode, c in zip(R.FAULT_MODES, ("C0", "C1", "C2")):
        for v in ("raw", "guarded"):
            assert lines[f"{mode}, {v}"].get_color() == c
            assert lines[f"{mode}, {v}"].get_marker() == "o"
    assert list(lines["stuck0, raw"].get_xdata()) == [0, 1, 2, 3]
    for ln in ax0.lines:
        if ln.get_marker() == "_":
            assert (ln.get_color(), ln.get_markersize(), ln.get_markeredgewidth()) == (
                "r", 18, 2)
    assert noise["raw"].get_linestyle() == "--" and noise["guarded"].get_linestyle() == "-"
    assert noise["raw"].get_marker() == "o" and noise["guarded"].get_color() == "k"
    assert not plt.fignum_exists(fig.number)                      # closed
    assert [t.get_text() for t in ax0.get_xticklabels()] == ["0", "1", "2", "3"]
    (target,) = [ln for ln in ax1.lines if ln.get_label().startswith("_")]
    assert target.get_linewidth() == 0.8 and target.get_color() == "r"
    assert ax0.get_legend().get_texts()[0].get_fontsize() == 7
    assert ax1.get_legend().get_texts()[0].get_fontsize() == 8
    saved.clear()
    R._fault_figure(tmp_path, {"raw": variant(0.0), "guard": variant(0.05)}, [3, 5, 9])
    assert saved[0][0]._suptitle.get_text() == (
        "room cell under sensor faults (seeds 3,5,9; red: targets)")
    plt.close("all")


def test_the_figures_get_the_room_and_corridor_cells_parts(monkeypatch, tmp_path):
    import hippo.plots.perception as plots

    calls: list[tuple[tuple[Any, ...], dict[str, Any]]] = []

    def plot_place_cell(*a: Any, **k: Any) -> tuple[str, None]:
        calls.append((a, k))
        return f"fig{len(calls)}", None

    monkeypatch.setattr(plots, "plot_place_cell", plot_place_cell)
    saved = _captured(monkeypatch)
    closed: list[Any] = []
    import matplotlib.pyplot as plt
    monkeypatch.setattr(plt, "close", closed.append)

    class _Rec(SimpleNamespace):
        def __len__(self) -> int:
            return len(self.label)

    names = ["room_a", "corridor", "room_b"]
    rec = _Rec(positions=np.arange(12.0).reshape(6, 2), label=np.arange(6),
               region_names=names, region=np.array([0, 2, 2, 1, 2, 1]))
    kid = _Rec(positions=-np.arange(12.0).reshape(6, 2), label=np.arange(6) + 10,
               region_names=names, region=np.array([2, 0, 0, 2, 0, 1]))
    Y = np.arange(18.0).reshape(6, 3)
    paper = {"room_cell": SimpleNamespace(unit=2, polarity=-1), "Y": Y,
             "room_cell_test_balanced_accuracy": 0.91234, "Y_kid": Y + 100.0,
             "kidnap_recovery_ticks_each": [3.0, 5.0]}
    corridor = {"corridor_cell": SimpleNamespace(unit=1, polarity=1), "Y": -Y,
                "corridor_cell_test_balanced_accuracy": 0.8766}
    R._figures(tmp_path, "arena", rec, kid, 4, [4, 5], {"paper": paper, "corridor": corridor},
               (0.05, 0.15))
    assert [(p.name, d) for _, p, d in saved] == [
        ("fig5_room_cell_train.png", 110), ("fig6_room_cell_test.png", 110),
        ("fig7_kidnapping.png", 110), ("fig8_corridor_cell_test.png", 110)]
    assert [f for f, _, _ in saved] == ["fig1", "fig2", "fig3", "fig4"] and closed == [
        "fig1", "fig2", "fig3", "fig4"]
    (a5, k5), (a6, k6), (a7, k7), (a8, k8) = calls
    assert a5[0] == "arena" and np.array_equal(a5[1], rec.positions[:4])
    assert np.array_equal(a5[2], np.arange(4)) and np.array_equal(a5[3], -Y[:4, 2])
    assert k5 == {"title": "room cell (ICA unit 3) on training data, leaks 0.05/0.15"}
    assert np.array_equal(a6[1], rec.positions[4:]) and np.array_equal(a6[3], -Y[4:, 2])
    assert k6["title"] == "room cell (ICA unit 3) on test data: balanced accuracy 0.912"
    assert k6["t"].tolist() == [4, 5] and k6["truth"].tolist() == [True, False]
    assert k6["truth_label"] == "in room B"
    assert np.array_equal(a7[1], kid.positions[4:]) and a7[2].tolist() == [14, 15]
    assert np.array_equal(a7[3], -(Y[4:, 2] + 100.0))
    assert k7["t"].tolist() == [0, 1] and k7["events"] == [0, 1]
    assert k7["title"] == "kidnapping: recovery [3.0, 5.0] ticks"
    assert k7["truth"].tolist() == [False, False] and k7["truth_label"] == "in room B"
    assert np.array_equal(a8[3], -Y[4:, 1]) and k8["t"].tolist() == [4, 5]
    assert [a[0] for a, _ in calls] == ["arena"] * 4
    assert np.array_equal(a6[2], [4, 5]) and np.array_equal(a8[1], rec.positions[4:])
    assert np.array_equal(a8[2], [4, 5])
    assert k8["title"] == ("corridor cell (ICA unit 2), leaks 0.11/0.14: balanced accuracy "
                           "0.877")
    assert k8["truth"].tolist() == [False, True] and k8["truth_label"] == "in corridor"
    # without a kidnapping: no fig7
    calls.clear()
    saved.clear()
    del paper["Y_kid"]
    R._figures(tmp_path, "arena", rec, None, 4, [], {"paper": paper, "corridor": corridor},
               (1.0,))
    assert [p.name for _, p, _ in saved] == ["fig5_room_cell_train.png",
                                             "fig6_room_cell_test.png",
                                             "fig8_corridor_cell_test.png"]
    assert calls[0][1]["title"].endswith("leaks 1")
