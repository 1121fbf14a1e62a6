"""The scenarios' shared helpers (:mod:`hippo.scenarios._common`) on hand-made inputs: the
output folder (stale temporary files, the last run's metrics, the files a run wrote named in
the closing line), the metrics file and its announcement, smoke tests, --sfa-cutoff, the leak
groups and SFA inputs at their bounds and one past, mean and sample sd over seeds by hand,
--seeds as a count and as lists (every refusal word for word), the recording cache on a
stand-in recording, only_with, and --leak."""

from __future__ import annotations

import argparse
import json
import math
import os
import time
import warnings
from pathlib import Path
from types import SimpleNamespace
from typing import Any, ClassVar

import pytest

import hippo.scenarios._common as C
from hippo.io import CorruptFileError


class _Refused(Exception):
    pass


class _Parser:
    """A stand-in parser whose error raises (argparse's exits) with the message."""

    def error(self, message: str) -> None:
        raise _Refused(message)


def _refusal(fn: Any, *args: Any, **kwargs: Any) -> str:
    with pytest.raises(_Refused) as e:
        fn(*args, **kwargs)
    return str(e.value)


# ------------------------------------------------------------------ the output folder and files
def test_prepare_out_makes_the_folder_and_removes_stale_temps_and_the_last_metrics(tmp_path):
    out = tmp_path / "a" / "b"
    assert C.prepare_out(str(out)) == out and out.is_dir()
    stale, young = out / ".metrics.json.x1.tmp", out / ".run.npz.x2.tmp"
    for p in (stale, young, out / "metrics.json", out / "keep.txt"):
        p.write_text("x")
    old = time.time() - 120.0            # older than io.STALE_AGE (60 s): a killed write's
    os.utime(stale, (old, old))
    assert C.prepare_out(out) == out
    assert sorted(p.name for p in out.iterdir()) == [".run.npz.x2.tmp", "keep.txt"]


def test_written_files_names_metrics_first_then_new_files_and_counts_figures(tmp_path):
    out = tmp_path / "o"
    out.mkdir()
    for name in ("old.png", "same.txt", "grow.txt"):
        (out / name).write_text("1")
    (out / "sub").mkdir()
    C.prepare_out(out)
    assert C.written_files(out) == "metrics.json"          # nothing written yet
    (out / "grow.txt").write_text("12")                    # rewritten: another size
    (out / "b.npz").write_text("x")
    (out / "a.json").write_text("x")
    (out / "metrics.json").write_text("{}")
    (out / "sub" / "deep.png").write_text("x")             # not directly in the folder
    assert C.written_files(out) == "metrics.json, a.json, b.npz, grow.txt"
    (out / "fig.png").write_text("x")
    assert C.written_files(out) == "metrics.json, a.json, b.npz, grow.txt, 1 figure"
    (out / "fig2.png").write_text("x")
    assert C.written_files(str(out)) == "metrics.json, a.json, b.npz, grow.txt, 2 figures"


def test_written_files_of_a_folder_not_prepared_is_every_file_there(tmp_path):
    (tmp_path / "x.png").write_text("x")
    (tmp_path / "r.npz").write_text("x")
    (tmp_path / "metrics.json").write_text("{}")
    assert C.written_files(tmp_path) == "metrics.json, r.npz, 1 figure"


def test_write_metrics_writes_the_file_and_announces_in_order(tmp_path, capsys):
    out = C.prepare_out(tmp_path / "o")
    path = C.write_metrics(out, {"a": 1, "quick": True}, summary="headline 0.97")
    assert path == out / "metrics.json"
    assert json.loads(path.read_text()) == {"a": 1, "quick": True}
    cap = capsys.readouterr()
    assert cap.out == ""
    assert cap.err.splitlines() == [
        "headline 0.97",
        "--quick: a smoke test with shortened settings; its numbers are not results",
        f"results written to {out.resolve()} (metrics.json)"]
    C.write_metrics(out, {"quick": False}, summary="")
    assert capsys.readouterr().err.splitlines() == [
        f"results written to {out.resolve()} (metrics.json)"]
    C.write_metrics(out, {"b": 2}, announce=False, summary="not shown")
    assert capsys.readouterr().err == ""
    assert json.loads(path.read_text()) == {"b": 2}


# ------------------------------------------------------------------------- options and checks
def test_smoke_test_is_quick_or_a_robot_taught_quick():
    ns = SimpleNamespace
    assert C.smoke_test(ns(quick=True)) is True
    assert C.smoke_test(ns(quick=False)) is False
    assert C.smoke_test(ns()) is False                          # no --quick, nothing loaded
    assert C.smoke_test(ns(quick=False, loaded=None)) is False
    assert C.smoke_test(ns(loaded={"meta": {"quick": True}})) is True
    assert C.smoke_test(ns(quick=False, loaded={"meta": {"quick": False}})) is False
    assert C.smoke_test(ns(quick=False, loaded={"meta": None})) is False
    assert C.smoke_test(ns(quick=False, loaded={})) is False
    # the robot passed in is read, not args.loaded
    taught_quick = {"meta": {"quick": True}}
    assert C.smoke_test(ns(quick=False, loaded=None), taught_quick) is True
    assert C.smoke_test(ns(quick=False, loaded=taught_quick), {"meta": {}}) is False
    assert C.smoke_test(ns(quick=True, loaded=None), {"meta": {}}) is True


def test_sfa_cutoff_is_auto_or_a_number():
    assert C.sfa_cutoff("auto") == "auto"
    assert C.sfa_cutoff("0.25") == 0.25 and isinstance(C.sfa_cutoff("1"), float)
    with pytest.raises(ValueError):
        C.sfa_cutoff("Auto")


def test_the_neurons_hold_one_group_per_leak_rate():
    ns = SimpleNamespace
    assert C.check_leak_groups(ns(neurons=2, leak=(0.05, 0.15)), _Parser()) is None
    assert C.check_leak_groups(ns(neurons=1, leak=(0.05,)), _Parser()) is None
    assert _refusal(C.check_leak_groups, ns(neurons=1, leak=(0.05, 0.15)), _Parser()) == (
        "argument --neurons: 1 neuron(s) cannot hold the 2 groups of --leak (one group of "
        "neurons per leak rate)")
    assert _refusal(C.check_leak_groups, ns(neurons=2, leak=(0.1, 0.2, 0.3)), _Parser()) == (
        "argument --neurons: 2 neuron(s) cannot hold the 3 groups of --leak (one group of "
        "neurons per leak rate)")


def test_the_sfa_units_fit_in_the_neurons_and_sensors_twice_with_a_slow_pool():
    p = _Parser()
    # 100 neurons + 8 sensors = 108 inputs; with the slow pool 2 * 108 = 216
    assert C.check_sfa_inputs(p, "--n-sfa", 108, 100) is None
    assert _refusal(C.check_sfa_inputs, p, "--n-sfa", 109, 100) == (
        "argument --n-sfa: 109 exceeds the 108 inputs of SFA (100 neurons + 8 sensors)")
    assert C.check_sfa_inputs(p, "--n-sfa", 216, 100, slow_pool=0.1) is None
    assert _refusal(C.check_sfa_inputs, p, "--n-ica", 217, 100, 0.1, " (the default)") == (
        "argument --n-ica: 217 (the default) exceeds the 216 inputs of SFA (100 neurons + 8 "
        "sensors, twice that with the slow pool)")
    assert _refusal(C.check_sfa_inputs, p, "--n-sfa", 109, 100.0, 0.0) == (
        "argument --n-sfa: 109 exceeds the 108 inputs of SFA (100.0 neurons + 8 sensors)")


def test_mean_and_sample_sd_of_the_finite_values_by_hand():
    m, sd = C.mean_sd([1.0, 2.0, 3.0, 4.0])
    # mean 2.5; squared deviations 2.25 + 0.25 + 0.25 + 2.25 = 5, over n - 1 = 3
    assert m == 2.5 and sd == pytest.approx(math.sqrt(5 / 3), rel=1e-15)
    assert C.mean_sd([2.0, math.nan, 4.0, math.inf, -math.inf]) == (3.0, math.sqrt(2.0))
    assert C.mean_sd([7.0]) == (7.0, 0.0)
    assert C.mean_sd([math.nan, 5]) == (5.0, 0.0)
    # None, as a metrics file writes a value not measured (nan), is left out like nan
    assert C.mean_sd([1.0, None, 3.0]) == (2.0, math.sqrt(2.0))
    for none in ([], [math.nan], [math.inf, math.nan]):
        m, sd = C.mean_sd(none)
        assert math.isnan(m) and math.isnan(sd)
    assert all(type(x) is float for x in C.mean_sd([1, 2]))


def test_the_tuning_and_held_out_seeds():
    assert C.TUNING_SEEDS == (0, 1, 2, 3, 4, 5, 6, 7, 8, 9)
    assert C.HELD_OUT_SEEDS == tuple(100 + i for i in range(20))


# ---------------------------------------------------------------------------------- --seeds
def _seeds_refused(text: str) -> str:
    with pytest.raises(argparse.ArgumentTypeError) as e:
        C.parse_seeds(text)
    return str(e.value)


def test_seeds_as_a_count_on_its_bounds_and_one_past():
    assert C.parse_seeds("1") == 1 and C.parse_seeds(" 5 ") == 5
    assert C.parse_seeds("1000") == 1000 and type(C.parse_seeds("1000")) is int
    assert _seeds_refused("0") == "--seeds must be >= 1 or a list, got '0'"
    assert _seeds_refused(" 00") == "--seeds must be >= 1 or a list, got ' 00'"
    assert _seeds_refused("1001") == (
        "--seeds 1001 is a count of runs (at most 1000); for the one seed 1001 give --seed "
        "1001, or --seeds 1001-1001")


def test_seeds_as_ranges_and_lists():
    assert C.parse_seeds("100-102") == [100, 101, 102]
    assert C.parse_seeds("0-2,15") == [0, 1, 2, 15]
    assert C.parse_seeds("7,") == [7]
    assert C.parse_seeds("0-999") == list(range(1000))
    fmt = ("--seeds takes a count (5) or seeds are integers in [0, 4294967295] in plain digits "
           "0-9, as ranges and lists (100-119, 0-9,15), got {!r}")
    for bad in ("abc", "5-3", "-1", "1.5", ""):
        assert _seeds_refused(bad) == fmt.format(bad.strip()), bad


def test_too_many_or_repeated_seeds_are_said_as_such():
    # they read "--seeds takes a count (5) or '1,1' repeats a seed"
    assert _seeds_refused("1,1") == "--seeds: '1,1' repeats a seed"
    assert _seeds_refused("0-1000") == (
        "--seeds: '0-1000' asks for more than 1000 seeds; run such a grid in parts (hippo "
        "sweep skips the cells already done)")


def test_seed_list_from_a_count_or_a_list():
    ns = SimpleNamespace
    assert C.seed_list(ns(seed=5, seeds=3)) == [5, 6, 7]
    assert C.seed_list(ns(seed=5)) == [5]                      # no --seeds: one run
    assert C.seed_list(ns(seed="4", seeds=2)) == [4, 5]
    spec = [100, 3]
    got = C.seed_list(ns(seed=0, seeds=spec))
    assert got == [100, 3] and got is not spec


def test_the_seeds_and_cache_options():
    p = argparse.ArgumentParser()
    C.add_seeds_argument(p, "runs")
    C.add_cache_argument(p)
    assert vars(p.parse_args([])) == {"seeds": 1, "cache": None}
    a = p.parse_args(["--seeds", "0-2,15", "--cache", "c"])
    assert a.seeds == [0, 1, 2, 15] and a.cache == Path("c")
    assert p.parse_args(["--seeds", "4"]).seeds == 4
    helps = {act.dest: act.help for act in p._actions}
    assert helps["seeds"] == (
        "runs: a count N (seeds --seed ... --seed+N-1) or seeds as ranges and lists, e.g. "
        "100-119 or 0-9,15 (tuning seeds 0-9, held-out seeds 100-119)")
    assert helps["cache"] == ("folder to keep and reuse recordings in (.npz), keyed by their "
                              "settings; default: record afresh")


# ---------------------------------------------------------------------------- the cache
class _Rec:
    """A stand-in recording: its length written as text."""

    loads: ClassVar[list[Path]] = []

    def __init__(self, n: int) -> None:
        self.n = n

    def __len__(self) -> int:
        return self.n

    def save(self, path: Path) -> Path:
        Path(path).write_text(str(self.n))
        return Path(path)

    @classmethod
    def load(cls, path: Path) -> _Rec:
        cls.loads.append(Path(path))
        text = Path(path).read_text()
        if not text.isdigit():
            raise CorruptFileError(f"{path}: damaged")
        return cls(int(text))


def _builder(n: int, calls: list[int]) -> Any:
    def build() -> _Rec:
        calls.append(n)
        return _Rec(n)
    return build


def test_without_a_cache_the_recording_is_built_each_time(tmp_path, monkeypatch):
    monkeypatch.setattr(C, "Recording", _Rec)
    calls: list[int] = []
    assert len(C.cached_recording(None, "k", _builder(3, calls), 3)) == 3
    assert len(C.cached_recording(None, "k", _builder(3, calls))) == 3
    assert calls == [3, 3] and list(tmp_path.iterdir()) == []


def test_the_cache_keeps_key_npz_and_reads_it_back(tmp_path, monkeypatch):
    monkeypatch.setattr(C, "Recording", _Rec)
    _Rec.loads = []
    calls: list[int] = []
    cache = tmp_path / "new" / "cache"                   # made on the first write
    a = C.cached_recording(str(cache), "two-rooms-s1", _builder(4, calls), 4)
    assert (cache / "two-rooms-s1.npz").read_text() == "4" and len(a) == 4
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        b = C.cached_recording(cache, "two-rooms-s1", _builder(4, calls), 4)
        c = C.cached_recording(cache, "two-rooms-s1", _builder(9, calls))   # any length
    assert calls == [4] and len(b) == 4 and len(c) == 4
    assert _Rec.loads == [cache / "two-rooms-s1.npz"] * 2
    C.cached_recording(cache, "other", _builder(2, calls), 2)         # another key, another file
    assert calls == [4, 2] and sorted(p.name for p in cache.iterdir()) == [
        "other.npz", "two-rooms-s1.npz"]


def test_a_cache_of_another_length_or_damaged_is_recorded_again_with_a_warning(tmp_path,
                                                                             monkeypatch):
    monkeypatch.setattr(C, "Recording", _Rec)
    calls: list[int] = []
    path = tmp_path / "k.npz"
    path.write_text("5")
    with pytest.warns(UserWarning) as w:
        rec = C.cached_recording(tmp_path, "k", _builder(6, calls), 6)
    assert [str(x.message) for x in w] == [
        f"the cached recording {path} is unusable (5 ticks, not 6): recording it again"]
    assert w[0].filename != C.__file__                  # stacklevel 2: the caller's line
    assert calls == [6] and len(rec) == 6 and path.read_text() == "6"
    path.write_text("zip?")
    with pytest.warns(UserWarning) as w:
        C.cached_recording(tmp_path, "k", _builder(6, calls), 6)
    assert [str(x.message) for x in w] == [
        f"the cached recording {path} is unusable ({path}: damaged): recording it again"]
    assert calls == [6, 6] and path.read_text() == "6"


# ------------------------------------------------------------------------ only_with and --leak
def test_only_with_refuses_an_option_typed_without_its_flag():
    ns = SimpleNamespace
    p = _Parser()
    why = "it sets the slow pool's leak"
    assert C.only_with(ns(pool_leak_given=True, slow_pool=True), p, "pool_leak", "slow_pool",
                       why) is None
    assert C.only_with(ns(pool_leak_given=False, slow_pool=False), p, "pool_leak",
                       "slow_pool", why) is None
    assert C.only_with(ns(slow_pool=False), p, "pool_leak", "slow_pool", why) is None
    assert _refusal(C.only_with, ns(pool_leak_given=True, slow_pool=False), p, "pool_leak",
                    "slow_pool", why) == (
        "argument --pool-leak: only with --slow_pool (it sets the slow pool's leak); add "
        "--slow_pool or leave it out")
    assert _refusal(C.only_with, ns(hold_given=True, kidnap=0), p, "hold", "kidnap",
                    "ticks right again") == (
        "argument --hold: only with --kidnap (ticks right again); add --kidnap or leave it out")


def test_leak_rates_in_the_half_open_unit_interval():
    assert C.parse_leak("0.05,0.15") == (0.05, 0.15)
    assert C.parse_leak("1") == (1.0,) and C.parse_leak("5e-324") == (5e-324,)
    assert C.parse_leak("0.05,") == (0.05,)
    want = "got {!r}; needs 1 or more comma-separated numbers in (0, 1]"
    for bad in ("0", "1.0000000000000002", "-0.1", "0.1,,0.2", "", "a"):
        with pytest.raises(argparse.ArgumentTypeError) as e:
            C.parse_leak(bad)
        assert str(e.value) == want.format(bad), bad
