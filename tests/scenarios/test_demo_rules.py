"""The demo scenario (:mod:`hippo.scenarios.demo`) on a stand-in recording: its options on
their bounds and one past, the recording asked for (the arena's sensors, --quick's 1000
ticks), the files written and the metrics computed by hand from a six-tick recording."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

import hippo.scenarios.demo as D
from hippo.sim import arenas


def _actions() -> dict[str, argparse.Action]:
    p = argparse.ArgumentParser()
    D.add_arguments(p)
    return {a.dest: a for a in p._actions}


def test_the_options_defaults_and_bounds():
    p = argparse.ArgumentParser()
    D.add_arguments(p)
    a = p.parse_args([])
    assert (a.arena, a.ticks, a.rho) == ("two-rooms", 6000, 0.008)
    acts = _actions()
    assert acts["arena"].choices == list(arenas.ARENAS)
    ticks, rho = acts["ticks"].type, acts["rho"].type
    assert ticks("2") == 2 and ticks("10000000") == 10_000_000
    for bad in ("1", "10000001"):
        with pytest.raises(argparse.ArgumentTypeError):
            ticks(bad)
    assert rho("0") == 0.0 and rho("1") == 1.0
    for bad in ("-0.01", "1.01"):
        with pytest.raises(argparse.ArgumentTypeError):
            rho(bad)


def test_the_options_help():
    acts = _actions()
    assert acts["arena"].help == "the arena"
    assert acts["ticks"].help == "control ticks of 0.2 s"
    assert acts["rho"].help == "side-switch probability of the wall follower per tick"


class _Rec:
    """Six ticks: regions 0, 0, 1, 1, 1, 2; labels 3, 3, 5, 0, 5, 3; speeds 1..6 cm/s."""

    def __init__(self, n: int) -> None:
        self.n = n
        self.t = np.array([0.2, 0.4, 0.6, 0.8, 1.0, 12.5])
        self.region = np.array([0, 0, 1, 1, 1, 2])
        self.region_names = ["room_a", "corridor", "room_b"]
        self.label = np.array([3, 3, 5, 0, 5, 3])
        self.speed = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
        self.saved: list[Path] = []

    def save(self, path: Path) -> None:
        self.saved.append(Path(path))
        Path(path).write_bytes(b"x")

    def __len__(self) -> int:
        return self.n


def _run(monkeypatch, tmp_path: Path, *, arena: str, ticks: int, quick: bool,
         rec_len: int = 6) -> tuple[dict, dict[str, Any]]:
    seen: dict[str, Any] = {"figures": []}
    rec = _Rec(rec_len)

    def record(a, n, seed, rho, sensors):
        seen["record"] = (a.name, n, seed, rho, sensors)
        return rec

    def trajectory(a, r):
        assert r is rec
        seen["trajectory"] = a.name
        return "fig-trajectory", None

    def strip(r, start, stop):
        assert r is rec
        seen["strip"] = (start, stop)
        return "fig-strip", None

    def save_figure(fig, path, dpi):
        seen["figures"].append((fig, Path(path).name, dpi))

    clock = iter([10.0, 12.5])
    monkeypatch.setattr(D, "record", record)
    monkeypatch.setattr(D, "plot_trajectory", trajectory)
    monkeypatch.setattr(D, "plot_sensor_strip", strip)
    monkeypatch.setattr(D, "save_figure", save_figure)
    monkeypatch.setattr(D, "time", SimpleNamespace(perf_counter=lambda: next(clock)))
    seen["rec"] = rec
    args = argparse.Namespace(out=str(tmp_path / "out"), arena=arena, ticks=ticks, quick=quick,
                              seed=7, rho=0.25)
    return D.run(args), seen


def test_run_on_a_stand_in_recording(monkeypatch, tmp_path, capsys):
    m, seen = _run(monkeypatch, tmp_path, arena="two-rooms", ticks=5000, quick=False)
    assert seen["record"] == ("two-rooms", 5000, 7, 0.25, "ir8")
    assert seen["rec"].saved == [tmp_path / "out" / "run.npz"]
    assert seen["trajectory"] == "two-rooms"
    # the strip shows at most 1500 ticks: here the recording's 6
    assert seen["strip"] == (0, 6)
    assert seen["figures"] == [("fig-trajectory", "trajectory.png", 120),
                               ("fig-strip", "sensors.png", 120)]
    assert m["arena"] == "two-rooms" and m["ticks"] == 5000 and m["seed"] == 7
    assert m["rho"] == 0.25
    assert m["simulated_s"] == 12.5
    assert m["wall_s"] == 2.5 and m["ticks_per_s"] == 2000.0
    assert m["region_occupancy"] == {"room_a": 2 / 6, "corridor": 3 / 6, "room_b": 1 / 6}
    assert m["locations_visited"] == 3          # labels 0, 3 and 5
    assert m["mean_speed_cm_s"] == 3.5
    assert json.loads((tmp_path / "out" / "metrics.json").read_text()) == m
    err = capsys.readouterr().err
    n_loc = len(arenas.get("two-rooms").locations)
    assert (f"demo: 5000 ticks (12 s simulated) in two-rooms, 3 of {n_loc} labelled "
            "locations visited, mean speed 3.5 cm/s, 2000 ticks/s") in err


def test_quick_caps_the_ticks_at_1000_and_the_strip_at_1500(monkeypatch, tmp_path):
    m, seen = _run(monkeypatch, tmp_path, arena="two-rooms", ticks=5000, quick=True,
                   rec_len=2000)
    assert seen["record"][1] == 1000 and m["ticks"] == 1000
    assert seen["strip"] == (0, 1500)
    m, seen = _run(monkeypatch, tmp_path, arena="two-rooms", ticks=999, quick=True)
    assert seen["record"][1] == 999
    m, seen = _run(monkeypatch, tmp_path, arena="two-rooms", ticks=1001, quick=True,
                   rec_len=1500)
    assert seen["record"][1] == 1000 and seen["strip"] == (0, 1500)


def test_the_maze_is_sensed_by_17_rays(monkeypatch, tmp_path):
    _, seen = _run(monkeypatch, tmp_path, arena="maze-e1", ticks=10, quick=False)
    assert seen["record"] == ("maze-e1", 10, 7, 0.25, "ray17")
