"""Recordings' rules on hand-made arrays and on short runs whose answers are known by hand.

A hand-made Recording of three ticks at t = 0.5, 1.0, 1.5 s with events at 0.25, 1.0, 1.5 and
2.0 s checks the slices' event windows (both ends inclusive, nothing outside the kept ticks),
and every refusal of the checked load word for word on its edge and one step past it. Runs
use a stand-in controller that keeps the wheels still (or records what it is shown): the robot
then stays where it was put, so its pose, speed, region, nearest location and floor colour
come from the arena's definition (two-rooms: room_a is x < 30, the corridor 30-60 for
37 < y < 53, room_b x > 60; its labelled locations include (21, 45) = index 5 and
(38, 45) = index 10; goal-arena's goal zone is (0, 70)-(24, 82), colour 1).
"""

from __future__ import annotations

import importlib
import math
import re
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
import pytest

from hippo.io import CorruptFileError
from hippo.seeds import Seeds
from hippo.sim import arenas
from hippo.sim.controllers import WallFollower, WallFollowerParams
from hippo.sim.record import RECORDING_FORMAT, Recording, record
from hippo.sim.robot import RobotParams
from hippo.sim.world import World

record_module = importlib.import_module("hippo.sim.record")


def _rec(**kw: Any) -> Recording:
    fields: dict[str, Any] = dict(
        arena="two-rooms", sensor_model="ir8", dt=0.5, seed=7,
        t=np.array([0.5, 1.0, 1.5]),
        sensors=np.array([[0.0, 0.5], [1.0, 0.25], [0.75, 1.0]]),
        x=np.array([1.0, 2.0, 3.0]), y=np.array([4.0, 5.0, 6.0]),
        heading=np.array([0.0, 0.5, -0.5]), speed=np.array([0.0, 1.0, 2.0]),
        floor=np.array([0, 1, 0], np.int16), label=np.array([3, 4, 5], np.int16),
        region=np.array([-1, 0, 1], np.int16), region_names=["a", "b"],
        event_t=np.array([0.25, 1.0, 1.5, 2.0]),
        event_kind=np.array(["early", "at1", "at15", "late"], dtype="<U16"),
        event_detail=np.array(["d0", "d1", "d2", "d3"], dtype="<U64"))
    fields.update(kw)
    return Recording(**fields)


def refused(message: str, kind: type[Exception] = CorruptFileError):
    return pytest.raises(kind, match="^" + re.escape(message) + "$")


# -- the recording's views and slices ---------------------------------------------------------

def test_length_and_positions():
    r = _rec()
    assert len(r) == 3
    np.testing.assert_array_equal(r.positions, [[1, 4], [2, 5], [3, 6]])


@pytest.mark.parametrize("start, stop, ticks, kinds", [
    (1, 3, [1, 2], ["at1", "at15"]),         # both ends of the window are kept
    (0, 3, [0, 1, 2], ["at1", "at15"]),      # 0.25 s before the first tick, 2.0 s after the last
    (1, 2, [1], ["at1"]),                    # a window of one instant: t0 = t1 = 1.0
    (0, 1, [0], []),
    (2, 3, [2], ["at15"]),
    (3, 3, [], []),                          # nothing kept, no events either
    (0, 0, [], []),
    (2, 1, [], []),
    (0, -1, [0, 1], ["at1"]),                # a negative stop counts from the end
    (-2, 3, [1, 2], ["at1", "at15"]),
    (1, 10, [1, 2], ["at1", "at15"]),        # a stop past the end keeps the last tick's events
])
def test_a_slice_keeps_its_ticks_and_the_events_within_them(start, stop, ticks, kinds):
    r = _rec()
    s = r.slice(start, stop)
    np.testing.assert_array_equal(s.t, r.t[ticks])
    for name in ("sensors", "x", "y", "heading", "speed", "floor", "label", "region"):
        np.testing.assert_array_equal(getattr(s, name), getattr(r, name)[ticks])
    assert list(s.event_kind) == kinds
    keep = [list(r.event_kind).index(k) for k in kinds]
    np.testing.assert_array_equal(s.event_t, r.event_t[keep])
    assert list(s.event_detail) == [r.event_detail[i] for i in keep]
    assert (s.arena, s.sensor_model, s.dt, s.seed) == ("two-rooms", "ir8", 0.5, 7)
    assert s.region_names == ["a", "b"]


def test_a_slice_has_its_own_region_names():
    r = _rec()
    r.slice(0, 2).region_names.append("c")
    assert r.region_names == ["a", "b"]


# -- the file and its checks ------------------------------------------------------------------

def test_save_and_load_give_back_every_field(tmp_path: Path):
    r = _rec()
    path = r.save(tmp_path / "rec.npz")
    assert path == tmp_path / "rec.npz"
    with np.load(path) as data:
        assert str(data["format"]) == RECORDING_FORMAT == "hippo.Recording/1"
        assert list(data["region_names"]) == ["a", "b"]
    back = Recording.load(path)
    assert (back.arena, back.sensor_model, back.dt, back.seed) == ("two-rooms", "ir8", 0.5, 7)
    assert back.region_names == ["a", "b"]
    for name in ("t", "sensors", "x", "y", "heading", "speed", "floor", "label", "region",
                 "event_t", "event_kind", "event_detail"):
        np.testing.assert_array_equal(getattr(back, name), getattr(r, name))
    for name in ("floor", "label", "region"):
        assert getattr(back, name).dtype == np.int16


def _arrays(**kw: Any) -> dict[str, Any]:
    r = _rec()
    arrays: dict[str, Any] = {f: getattr(r, f) for f in (
        "arena", "sensor_model", "dt", "seed", "t", "sensors", "x", "y", "heading", "speed",
        "floor", "label", "region", "event_t", "event_kind", "event_detail")}
    arrays["region_names"] = np.array(["a", "b"])
    arrays["format"] = np.array(RECORDING_FORMAT)
    arrays.update(kw)
    return {k: v for k, v in arrays.items() if v is not None}


def _file(tmp_path: Path, **kw: Any) -> Path:
    path = tmp_path / "r.npz"
    np.savez(path, **_arrays(**kw))
    return path


def test_the_format_tag_is_checked_first(tmp_path: Path):
    path = _file(tmp_path, format=None, arena=None)
    with refused(f"{path} lacks required array(s): format"):
        Recording.load(path)
    path = _file(tmp_path, format=np.array("hippo.Recording/2"), arena=None)
    with refused(f"{path} is not a hippo recording (its format tag is 'hippo.Recording/2', "
                 "a recording's 'hippo.Recording/1')"):
        Recording.load(path)
    for tag in (np.array(1.0), np.array([RECORDING_FORMAT])):
        path = _file(tmp_path, format=tag)
        with refused(f"{path} is not a hippo recording (its format tag is 'no text', "
                     "a recording's 'hippo.Recording/1')"):
            Recording.load(path)
    path = _file(tmp_path, format=np.array("x" * 59 + "yz"))
    with refused(f"{path} is not a hippo recording (its format tag is {'x' * 59 + 'y'!r}, "
                 "a recording's 'hippo.Recording/1')"):
        Recording.load(path)


def test_missing_arrays_are_named_in_field_order(tmp_path: Path):
    path = _file(tmp_path, event_detail=None, y=None, region_names=None)
    with refused(f"{path} lacks required array(s): y, region_names, event_detail"):
        Recording.load(path)


@pytest.mark.parametrize("change, message", [
    (dict(arena=np.array(3)), "arena must be a text scalar, got dtype int64 shape ()"),
    (dict(sensor_model=np.array(["ir8"])),
     "sensor_model must be a text scalar, got dtype <U3 shape (1,)"),
    (dict(dt=np.array(0.0)), "dt must be finite and > 0, got 0.0"),
    (dict(dt=np.array([0.5])), "dt must have shape (), got (1,)"),
    (dict(seed=np.array(7.0)), "seed must hold integers, got dtype float64"),
    (dict(seed=np.array(-1)), "seed must be an integer in [0, 9223372036854775807], got -1"),
    (dict(t=np.zeros((3, 1))), "t must have shape (*,), got (3, 1)"),
    (dict(t=np.array([0.5, np.inf, 1.5])), "t contains 1 non-finite value(s) (NaN or inf)"),
    (dict(t=np.array([0.5, 0.5, 1.5])), "t must increase from tick to tick"),
    (dict(t=np.array([1.0, 0.5]), sensors=np.zeros((2, 1)), x=np.zeros(2), y=np.zeros(2),
          heading=np.zeros(2), speed=np.zeros(2), floor=np.zeros(2, int), label=np.zeros(2, int),
          region=np.zeros(2, int)), "t must increase from tick to tick"),
    (dict(t=np.array([0.5, 1.5, 1.0])), "t must increase from tick to tick"),
    (dict(sensors=np.zeros((3, 0))),
     "sensors must be (T, n >= 1) readings in [0, 1], got shape (3, 0)"),
    (dict(sensors=np.array([[0.0], [-5e-324], [1.0]])),
     "sensors must be (T, n >= 1) readings in [0, 1], got shape (3, 1)"),
    (dict(sensors=np.array([[0.0], [1.0 + 2**-52], [1.0]])),
     "sensors must be (T, n >= 1) readings in [0, 1], got shape (3, 1)"),
    (dict(sensors=np.zeros((2, 2))), "sensors must have shape (3, *), got (2, 2)"),
    (dict(x=np.zeros(2)), "x must have shape (3,), got (2,)"),
    (dict(y=np.zeros(4)), "y must have shape (3,), got (4,)"),
    (dict(heading=np.array([0.0, np.nan, 0.0])),
     "heading contains 1 non-finite value(s) (NaN or inf)"),
    (dict(speed=np.zeros((3, 1))), "speed must have shape (3,), got (3, 1)"),
    (dict(region_names=np.array([["a", "b"]])),
     "region_names must be a list of text, got dtype <U1"),
    (dict(region_names=np.array([1.0, 2.0])),
     "region_names must be a list of text, got dtype float64"),
    (dict(floor=np.array([0, -2, 0])), "floor holds an index outside [-1, 32767]"),
    (dict(label=np.array([0, 32768, 0])), "label holds an index outside [-1, 32767]"),
    (dict(region=np.array([0, -2, 0])), "region holds an index outside [-1, 32767]"),
    (dict(floor=np.array([0.0, 1.0, 0.0])), "floor must hold integers, got dtype float64"),
    (dict(label=np.zeros(2, int)), "label must have shape (3,), got (2,)"),
    (dict(region=np.array([-1, 2, 0])), "region indices exceed the 2 region_names"),
    (dict(event_t=np.array([[0.25]])), "event_t must have shape (*,), got (1, 1)"),
    (dict(event_kind=np.array(["a", "b", "c"])),
     "event_kind must be 4 text values, got dtype <U1 shape (3,)"),
    (dict(event_detail=np.zeros(4)),
     "event_detail must be 4 text values, got dtype float64 shape (4,)"),
])
def test_each_damaged_field_is_refused_in_its_words(tmp_path: Path, change, message):
    path = _file(tmp_path, **change)
    with refused(f"{path}: {message}"):
        Recording.load(path)


@pytest.mark.parametrize("change", [
    dict(sensors=np.array([[0.0], [1.0], [0.5]])),      # readings exactly on 0 and 1
    dict(floor=np.array([-1, 32767, 0]), label=np.array([-1, 0, 32767])),
    dict(region=np.array([-1, 1, 1])),                  # the last region name's index
    dict(t=np.array([0.5, np.nextafter(0.5, 1), 1.5])),
    dict(event_t=np.zeros(0), event_kind=np.zeros(0), event_detail=np.zeros(0)),
    dict(region_names=np.zeros(0), region=np.array([-1, -1, -1])),
])
def test_values_on_the_edges_are_taken(tmp_path: Path, change):
    back = Recording.load(_file(tmp_path, **change))
    for k, v in change.items():
        if k != "region_names":
            np.testing.assert_array_equal(getattr(back, k), v)


def test_one_tick_and_no_ticks_load(tmp_path: Path):
    one = dict(t=np.array([2.0]), sensors=np.array([[0.5]]), x=np.zeros(1), y=np.zeros(1),
               heading=np.zeros(1), speed=np.zeros(1), floor=np.zeros(1, int),
               label=np.zeros(1, int), region=np.array([1]))
    assert len(Recording.load(_file(tmp_path, **one))) == 1
    none = {k: v[:0] for k, v in one.items()}
    none["sensors"] = np.zeros((0, 2))
    back = Recording.load(_file(tmp_path, **none, region_names=np.zeros(0)))
    assert len(back) == 0 and back.sensors.shape == (0, 2) and back.region_names == []


def test_the_dtype_of_a_text_scalar_is_named(tmp_path: Path):
    path = _file(tmp_path, sensor_model=np.array(1.5))
    with refused(f"{path}: sensor_model must be a text scalar, got dtype float64 shape ()"):
        Recording.load(path)


# -- record: runs whose answers are known by hand ---------------------------------------------

class _Still:
    """Keeps the wheels still and remembers every observation it is shown."""

    def __init__(self) -> None:
        self.seen: list[Any] = []

    def act(self, obs: Any) -> tuple[float, float]:
        self.seen.append(obs)
        return (0.0, 0.0)


def test_a_still_robot_is_recorded_where_it_stands():
    c = _Still()
    r = record("two-rooms", 5, controller=c, progress=False, start_pose=(20.0, 44.0, 0.5),
               dt=0.25, seed=3)
    assert (r.arena, r.sensor_model, r.dt, r.seed) == ("two-rooms", "ir8", 0.25, 3)
    np.testing.assert_array_equal(r.t, [0.25, 0.5, 0.75, 1.0, 1.25])
    np.testing.assert_array_equal(r.x, [20.0] * 5)
    np.testing.assert_array_equal(r.y, [44.0] * 5)
    np.testing.assert_array_equal(r.heading, [0.5] * 5)
    np.testing.assert_array_equal(r.speed, [0.0] * 5)
    np.testing.assert_array_equal(r.region, [0] * 5)         # room_a
    np.testing.assert_array_equal(r.label, [5] * 5)          # (21, 45), sqrt 2 away
    np.testing.assert_array_equal(r.floor, [0] * 5)
    assert r.region_names == ["room_a", "corridor", "room_b"]
    for k in ("floor", "label", "region"):
        assert getattr(r, k).dtype == np.int16
    # each tick's readings are what the controller is shown at the next tick
    assert len(c.seen) == 5 and c.seen[0].t == 0.0
    for k in range(4):
        np.testing.assert_array_equal(r.sensors[k], c.seen[k + 1].ir)
    assert r.sensors.shape == (5, 8)
    assert len(r.event_t) == len(r.event_kind) == len(r.event_detail)


def test_the_floor_colour_and_the_sensor_model_are_recorded():
    r = record("goal-arena", 2, controller=_Still(), progress=False, sensors="ray17",
               start_pose=(12.0, 76.0, 0.0))
    np.testing.assert_array_equal(r.floor, [1, 1])
    assert r.sensor_model == "ray17" and r.sensors.shape == (2, 17)
    assert r.dt == 0.2
    np.testing.assert_array_equal(r.t, [0.2, 0.4])


def test_an_arena_object_records_like_its_name():
    a = arenas.get("two-rooms")
    kw: dict[str, Any] = dict(progress=False, start_pose=(20.0, 44.0, 0.0), seed=5)
    by_name = record("two-rooms", 3, controller=_Still(), **kw)
    by_object = record(a, 3, controller=_Still(), **kw)
    np.testing.assert_array_equal(by_name.sensors, by_object.sensors)
    assert by_object.arena == "two-rooms"


def test_a_kidnap_moves_the_robot_before_its_tick_and_the_controller_sees_it():
    c = _Still()
    r = record("two-rooms", 4, controller=c, progress=False, start_pose=(20.0, 44.0, 0.0),
               kidnaps=[(2, (38.0, 45.0, math.pi / 2))])
    np.testing.assert_array_equal(r.x, [20.0, 20.0, 38.0, 38.0])
    np.testing.assert_array_equal(r.y, [44.0, 44.0, 45.0, 45.0])
    np.testing.assert_array_equal(r.region, [0, 0, 1, 1])       # room_a, then the corridor
    np.testing.assert_array_equal(r.label, [5, 5, 10, 10])      # (21, 45), then (38, 45)
    # the controller is shown the new place's observation at the kidnap's tick
    assert c.seen[2].t == 0.4
    assert not np.array_equal(c.seen[2].ir, r.sensors[1])
    np.testing.assert_array_equal(list(r.event_kind), ["kidnap"])
    np.testing.assert_array_equal(r.event_t, [0.4])
    np.testing.assert_array_equal(list(r.event_detail), ["38.00,45.00,1.5708"])
    assert r.event_kind.dtype == np.dtype("<U16") and r.event_detail.dtype == np.dtype("<U64")


@pytest.mark.parametrize("robot", [None, RobotParams(radius=5.0, axle=7.0, speed_max=4.0)])
def test_the_default_controller_is_the_wall_follower_with_rho_and_its_own_stream(robot):
    r = record("two-rooms", 40, seed=4, rho=0.3, progress=False, robot=robot)
    world = World(arenas.get("two-rooms"), seed=4, robot=robot)
    world.reset(4)
    obs = world.observe()   # (record senses once more after the reset)
    wf = WallFollower(WallFollowerParams(rho=0.3), sensors=world.sensors, robot=world.robot,
                      rng=Seeds(4).generator("recording"))
    xs = []
    for _ in range(40):
        obs = world.step(wf.act(obs))
        xs.append(world.truth.pose[0])
    np.testing.assert_array_equal(r.x, xs)
    other = record("two-rooms", 40, seed=4, rho=0.0, progress=False, robot=robot)
    assert not np.array_equal(other.x, r.x)


def test_the_default_seed_is_zero():
    r = record("two-rooms", 30, progress=False)
    assert r.seed == 0
    np.testing.assert_array_equal(r.x, record("two-rooms", 30, seed=0, progress=False).x)


def test_ticks_must_be_a_whole_number_of_at_least_one():
    with refused("ticks must be an integer >= 1, got 0", ValueError):
        record("two-rooms", 0, progress=False)
    with refused("ticks must be an integer, got 1.0 (float)", ValueError):
        record("two-rooms", 1.0, progress=False)  # type: ignore[arg-type]
    assert len(record("two-rooms", 1, controller=_Still(), progress=False)) == 1


class _Bar:
    made: ClassVar[list[_Bar]] = []

    def __init__(self, total: int, desc: str, *, enabled: bool | None = None) -> None:
        self.total, self.desc, self.enabled = total, desc, enabled
        self.n, self.updates = 0, []
        _Bar.made.append(self)

    def update(self, n: int) -> None:
        self.n += n
        self.updates.append(n)

    def __enter__(self) -> _Bar:
        return self

    def __exit__(self, *exc: object) -> None:
        pass


@pytest.mark.parametrize("ticks, updates", [
    (999, [999]), (1000, [1000]), (1001, [1000, 1]), (2500, [1000, 1000, 500])])
def test_the_bar_counts_every_thousand_ticks_and_the_rest(monkeypatch, ticks, updates):
    monkeypatch.setattr(record_module, "Progress", _Bar)
    _Bar.made.clear()
    record("two-rooms", ticks, controller=_Still(), desc="exploring")
    record("two-rooms", 3, controller=_Still(), progress=False)
    first, second = _Bar.made
    assert (first.total, first.desc, first.enabled, first.updates) == (
        ticks, "exploring", None, updates)
    assert (second.total, second.desc, second.enabled, second.updates) == (
        3, "recording", False, [3])


def test_kidnaps_must_fall_within_the_run_once_each():
    """A kidnap at or past the last tick, or before the first, used to be dropped silently,
    and a second kidnap at the same tick replaced the first."""
    pose = (38.0, 45.0, 0.0)
    with refused("kidnap tick must be an integer in [0, 3], got 4", ValueError):
        record("two-rooms", 4, controller=_Still(), progress=False, kidnaps=[(4, pose)])
    with refused("kidnap tick must be an integer in [0, 3], got -1", ValueError):
        record("two-rooms", 4, controller=_Still(), progress=False, kidnaps=[(-1, pose)])
    with refused("kidnap tick must be an integer, got 1.5 (float)", ValueError):
        record("two-rooms", 4, controller=_Still(), progress=False, kidnaps=[(1.5, pose)])
    with refused("two kidnaps at tick 2", ValueError):
        record("two-rooms", 4, controller=_Still(), progress=False,
               kidnaps=[(2, pose), (1, pose), (2, (20.0, 44.0, 0.0))])
    first = record("two-rooms", 4, controller=_Still(), progress=False,
                   start_pose=(20.0, 44.0, 0.0), kidnaps=[(0, pose), (3, (21.0, 45.0, 0.0))])
    np.testing.assert_array_equal(first.x, [38.0, 38.0, 38.0, 21.0])
    np.testing.assert_array_equal(first.event_t, [0.0, 0.6])


def test_the_bar_is_updated_at_every_thousandth_tick(monkeypatch):
    """The updates come after ticks 1000 and 2000 (k = 999, 1999), then the rest."""
    done: list[int] = []

    class Counting(_Still):
        def act(self, obs: Any) -> tuple[float, float]:
            done.append(1)
            return super().act(obs)

    class Bar(_Bar):
        def update(self, n: int) -> None:
            super().update(n)
            self.updates[-1] = (n, len(done))

    monkeypatch.setattr(record_module, "Progress", Bar)
    _Bar.made.clear()
    record("two-rooms", 2001, controller=Counting())
    assert _Bar.made[0].updates == [(1000, 1000), (1000, 2000), (1, 2001)]
