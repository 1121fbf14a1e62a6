"""The per-tick log's rules on hand-made rows: every column of a row with and without an
agent, the columns cut by rows, the path length by hand, the saved file's names, the event
arrays and the enum names (each expected value written out by hand from the inputs)."""

from __future__ import annotations

from enum import Enum, IntEnum
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from hippo.tasks.log import COLUMNS, Log, enum_names, event_arrays
from hippo.types import GroundTruth, Mode, Observation


def _obs(t: float, floor: int = 0, sound: bool = False) -> Observation:
    return Observation(t=t, tick=round(t * 5), ir=np.zeros(8), floor=floor, sound=sound,
                       odometry=np.zeros(3), moving=True)


def _truth(t: float, x: float, y: float, h: float = 0.0, speed: float = 0.0) -> GroundTruth:
    return GroundTruth(t=t, tick=round(t * 5), pose=(x, y, h), speed=speed)


class _Agent:
    """A stand-in agent: a fixed snapshot, drive names and a map that records its file."""

    def __init__(self) -> None:
        self.written: list[Path] = []
        self.drives = SimpleNamespace(names=["food", "water"])
        self.graph = SimpleNamespace(to_graphml=self.written.append)

    def snapshot(self) -> dict[str, Any]:
        return {"winner": 7, "mode": int(Mode.WAIT), "prediction": 0.25,
                "non_occurrence": True, "sound_prediction": 0.5,
                "sound_non_occurrence": True, "drives": [0.1, 0.9], "wait_drive": 1}


class Phase(IntEnum):
    FIRST = 0
    SECOND = 1
    THIRD = 2


def test_a_row_without_an_agent_holds_the_world_and_the_explorer_defaults():
    log = Log(n_drives=3)
    log.add(_obs(0.2, floor=2, sound=True), _truth(0.2, 11.0, 12.0, 0.5, 3.5), None,
            Phase.SECOND, 4)
    assert len(log) == 1
    row = {k: v[0] for k, v in log.cols.items()}
    # written out from the inputs above; the agent's columns are the no-agent defaults
    assert row == {"t": 0.2, "x": 11.0, "y": 12.0, "heading": 0.5, "speed": 3.5, "zone": 2,
                   "sound": True, "phase": 1, "trial": 4, "winner": -1,
                   "mode": int(Mode.EXPLORE), "prediction": 0.0, "non_occurrence": False,
                   "sound_prediction": 0.0, "sound_non_occurrence": False,
                   "drives": [0.0, 0.0, 0.0], "wait_drive": -1}
    assert type(row["phase"]) is int and type(row["mode"]) is int
    assert set(log.cols) == set(COLUMNS) and len(COLUMNS) == 17


def test_a_row_with_an_agent_holds_its_snapshot():
    log = Log(n_drives=2)
    log.add(_obs(0.4), _truth(0.4, 1.0, 2.0), _Agent(), 0, 0)
    row = {k: v[0] for k, v in log.cols.items()}
    assert {k: row[k] for k in _Agent().snapshot()} == _Agent().snapshot()
    assert (row["t"], row["x"], row["y"]) == (0.4, 1.0, 2.0)


def test_column_and_arrays_cut_by_rows():
    log = Log()
    for i in range(5):
        log.add(_obs(0.2 * i), _truth(0.2 * i, 10.0 * i, -1.0 * i), None, i % 2, i)
    np.testing.assert_array_equal(log.column("x"), [0.0, 10.0, 20.0, 30.0, 40.0])
    np.testing.assert_array_equal(log.column("x", 2), [20.0, 30.0, 40.0])
    np.testing.assert_array_equal(log.column("trial", 1, 3), [1, 2])
    a = log.arrays()
    assert set(a) == set(COLUMNS)
    np.testing.assert_array_equal(a["phase"], [0, 1, 0, 1, 0])
    assert a["drives"].shape == (5, 1)


def test_path_length_by_hand():
    # rows at (3, 4), (3, 8), (6, 12) from the origin (0, 0): 5 + 4 + 5 = 14 cm
    log = Log()
    for t, (x, y) in zip((1.0, 2.0, 3.0), ((3.0, 4.0), (3.0, 8.0), (6.0, 12.0))):
        log.add(_obs(t), _truth(t, x, y), None, 0, 0)
    assert log.path_length(0, (0.0, 0.0)) == pytest.approx(14.0)
    # up to and including the row at t = 2: 5 + 4; just before it: 5 only
    assert log.path_length(0, (0.0, 0.0), 2.0) == pytest.approx(9.0)
    assert log.path_length(0, (0.0, 0.0), 1.999) == pytest.approx(5.0)
    # from row 1, starting at (3, 4): 4 + 5
    assert log.path_length(1, (3.0, 4.0)) == pytest.approx(9.0)
    # the origin's coordinates are taken as given (x first, then y)
    assert log.path_length(2, (6.0, 0.0)) == pytest.approx(12.0)
    assert isinstance(log.path_length(0, (0.0, 0.0)), float)


def test_save_writes_the_arrays_the_names_and_the_events(tmp_path):
    log = Log(n_drives=2)
    agent = _Agent()
    for i in range(3):
        log.add(_obs(0.2 * i), _truth(0.2 * i, float(i), 0.0), agent, Phase.THIRD, 0)
    world = SimpleNamespace(events=[(0.4, "sound", ""), (1.0, "block_start", "3.000")])
    out = tmp_path / "deep" / "run"                   # parents made
    arrays = log.save(out, agent, world, phases=Phase)
    assert agent.written == [out / "map.graphml"]
    with np.load(out / "run.npz") as z:
        assert list(z["phase_names"]) == ["first", "second", "third"]
        assert list(z["mode_names"]) == ["explore", "move", "approach", "wait"]
        assert list(z["drive_names"]) == ["food", "water"]
        np.testing.assert_array_equal(z["event_t"], [0.4, 1.0])
        assert list(z["event_kind"]) == ["sound", "block_start"]
        assert list(z["event_detail"]) == ["", "3.000"]
        np.testing.assert_array_equal(z["x"], [0.0, 1.0, 2.0])
        np.testing.assert_array_equal(z["phase"], [2, 2, 2])
    np.testing.assert_array_equal(arrays["x"], [0.0, 1.0, 2.0])
    assert set(arrays) == set(COLUMNS)
    # names given override the agent's; no phases: no phase names
    log.save(tmp_path / "b", agent, SimpleNamespace(events=[]), drive_names=("a", "b"))
    with np.load(tmp_path / "b" / "run.npz") as z:
        assert list(z["drive_names"]) == ["a", "b"] and "phase_names" not in z.files
        assert z["event_t"].shape == (0,)
    # into a folder that exists: overwritten
    log.save(tmp_path / "b", agent, SimpleNamespace(events=[]), drive_names=("c", "d"))
    with np.load(tmp_path / "b" / "run.npz") as z:
        assert list(z["drive_names"]) == ["c", "d"]


def test_event_arrays_types_and_widths():
    ev = event_arrays(iter([(1, "k" * 3, "d" * 5)]))     # a generator is read once
    assert ev["event_t"].dtype == np.float64 and ev["event_t"][0] == 1.0
    assert ev["event_kind"].dtype == np.dtype("<U16") and ev["event_kind"][0] == "kkk"
    assert ev["event_detail"].dtype == np.dtype("<U64") and ev["event_detail"][0] == "d" * 5
    assert set(ev) == {"event_t", "event_kind", "event_detail"}
    # longer ones widen the column (a kind of 17, a detail of 65 characters): nothing is cut
    ev = event_arrays([(1, "k" * 16, "d" * 64), (2, "k" * 17, "d" * 65)])
    assert ev["event_kind"].dtype == np.dtype("<U17") and list(ev["event_kind"]) == [
        "k" * 16, "k" * 17]
    assert ev["event_detail"].dtype == np.dtype("<U65") and ev["event_detail"][1] == "d" * 65
    empty = event_arrays([])
    assert empty["event_kind"].dtype == np.dtype("<U16") and empty["event_kind"].shape == (0,)


def test_enum_names_by_value_and_the_refusal_word_for_word():
    class Shuffled(IntEnum):       # declared out of order: named by value
        B = 1
        C = 2
        A = 0

    assert list(enum_names(Shuffled)) == ["a", "b", "c"]

    class Plain(Enum):             # not an int enum: its members do not compare, their values do
        UP = 1
        DOWN = 0

    assert list(enum_names(Plain)) == ["down", "up"]

    class Gap(IntEnum):
        A = 0
        B = 2

    with pytest.raises(ValueError) as e:
        enum_names(Gap)
    assert str(e.value) == "Gap values must be 0..1"

    class FromOne(IntEnum):
        A = 1
        B = 2

    with pytest.raises(ValueError, match=r"^FromOne values must be 0\.\.1$"):
        enum_names(FromOne)
