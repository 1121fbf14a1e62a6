"""The two-rooms recordings (:mod:`hippo.scenarios._two_rooms_recordings`) on stand-ins: the
other room's pose (its rectangle 6 cm in, margin 4), the room a pose is in (the 0.375 width
split on its bound), the kidnaps planned during the test part (only the pairs whose return
falls inside it, on the bound and one tick past), their kinds and whether they moved the robot,
decided on a stand-in world and replayed by a stand-in ``record``; the cache: the kidnapped
recording written and read back, a damaged one recorded again with the warning word for word,
and every refusal of the cached events word for word."""

from __future__ import annotations

import argparse
from pathlib import Path
from types import SimpleNamespace
from typing import Any, ClassVar

import numpy as np
import pytest

import hippo.scenarios._two_rooms_recordings as T
from hippo.io import CorruptFileError, save_json
from hippo.seeds import Seeds

ROOM_A, ROOM_B = (0.0, 0.0, 30.0, 90.0), (50.0, 10.0, 110.0, 70.0)


class Arena:
    """Room A left of x = 40, room B right of x = 60, the corridor between; width 80."""

    width = 80.0

    def __init__(self) -> None:
        self.regions = [SimpleNamespace(name="room_a", rects=[ROOM_A]),
                        SimpleNamespace(name="room_b", rects=[ROOM_B])]
        self.asked: list[tuple[Any, float, tuple]] = []
        self.where: list[tuple[float, float]] = []

    def sample_free_pose(self, rng, margin: float, rect: tuple) -> tuple[float, float, float]:
        self.asked.append((rng, margin, rect))
        return (90.0, 40.0, 1.5) if rect[0] > 40 else (15.0, 45.0, -1.5)

    def region_of(self, x: float, y: float) -> str | None:
        self.where.append((x, y))
        return "room_a" if x < 40 else "room_b" if x > 60 else "corridor"


class Rec:
    def __init__(self, n: int, tag: str = "") -> None:
        self.n, self.tag, self.saved = n, tag, []

    def __len__(self) -> int:
        return self.n

    def save(self, path: Path) -> None:
        self.saved.append(path)


def test_the_kidnap_ticks_are_smc09s():
    assert T.KIDNAP_AWAY == (150, 640) and T.KIDNAP_BACK == (400, 980)


def test_the_other_rooms_pose_is_drawn_6_cm_inside_it():
    arena, rng = Arena(), np.random.default_rng(0)
    assert T._other_room_pose(arena, "room_a", rng) == (90.0, 40.0, 1.5)
    assert T._other_room_pose(arena, "room_b", rng) == (15.0, 45.0, -1.5)
    # anything that is not room B goes to room B
    assert T._other_room_pose(arena, "corridor", rng) == (90.0, 40.0, 1.5)
    assert arena.asked == [(rng, 4.0, (56.0, 16.0, 104.0, 64.0)),
                           (rng, 4.0, (6.0, 6.0, 24.0, 84.0)),
                           (rng, 4.0, (56.0, 16.0, 104.0, 64.0))]


def test_the_room_at_a_pose_splits_the_corridor_at_0375_of_the_width():
    arena = Arena()
    assert T._room_at(arena, 10.0, 3.0) == "room_a" and T._room_at(arena, 70.0, 4.0) == "room_b"
    assert arena.where == [(10.0, 3.0), (70.0, 4.0)]
    arena.width = 128.0                       # the split at 48.0, inside the corridor
    assert T._room_at(arena, 47.99, 0.0) == "room_a"
    assert T._room_at(arena, 48.0, 0.0) == "room_b"
    # a room's region is kept wherever it lies
    arena.region_of = lambda x, y: "room_a"
    assert T._room_at(arena, 100.0, 0.0) == "room_a"
    arena.region_of = lambda x, y: "room_b"
    assert T._room_at(arena, 1.0, 0.0) == "room_b"
    arena.region_of = lambda x, y: None       # no region at all: the same split
    assert T._room_at(arena, 47.0, 0.0) == "room_a" and T._room_at(arena, 49.0, 0.0) == "room_b"


class World:
    """Starts at (10, 5, 0) in room A; ``walk`` moves it at the given ticks."""

    made: ClassVar[list[World]] = []
    walk: ClassVar[dict[int, tuple[float, float, float]]] = {}

    def __init__(self, arena, sensors: str, seed: int) -> None:
        self.args, self.k, self.pose = (arena, sensors, seed), 0, (10.0, 5.0, 0.0)
        self.sensors, self.robot = object(), object()
        self.resets: list[int] = []
        self.placed: list[tuple[int, tuple]] = []
        World.made.append(self)

    def reset(self, seed: int) -> None:
        self.resets.append(seed)

    def observe(self) -> tuple:
        return ("obs", self.k, self.pose)

    def place_robot(self, x: float, y: float, h: float) -> None:
        self.placed.append((self.k, (x, y, h)))
        self.pose = (x, y, h)

    def step(self, action: tuple) -> tuple:
        assert action[0] == "act"
        self.k += 1
        self.pose = self.walk.get(self.k, self.pose)
        return self.observe()


class Follower:
    made: ClassVar[list[Follower]] = []

    def __init__(self, params, sensors, robot, rng) -> None:
        self.params, self.sensors, self.robot, self.rng = params, sensors, robot, rng
        self.seen: list[tuple] = []
        Follower.made.append(self)

    def act(self, obs: tuple) -> tuple:
        self.seen.append(obs)
        return ("act", obs)


def _kidnap(monkeypatch, ticks: int, n_train: int, walk=None, seed: int = 3):
    World.made, Follower.made = [], []
    monkeypatch.setattr(World, "walk", walk or {})
    recorded: list[tuple] = []
    monkeypatch.setattr(T, "World", World)
    monkeypatch.setattr(T, "WallFollower", Follower)
    monkeypatch.setattr(T, "record", lambda *a, **k: recorded.append((a, k)) or "REC")
    arena = Arena()
    out = T.kidnapped_recording(arena, ticks, n_train, seed=seed, rho=0.25)
    return arena, out, recorded


def test_the_kidnaps_are_decided_on_the_run_and_replayed(monkeypatch):
    # walking back to room A (x = 20) at tick 300, before the return at 10 + 400; then on
    # to room B (x = 70) at tick 500
    arena, (rec, events, kinds, moved), recorded = _kidnap(
        monkeypatch, 1000 + 10 + 1, 10, walk={300: (20.0, 5.0, 0.0), 500: (70.0, 30.0, 0.2)})
    assert rec == "REC"
    assert events == [160, 410, 650, 990]
    assert kinds == ["away from room_a", "back to room_a", "away from room_b", "back to room_b"]
    # the first return finds it back in room A on its own: no move; the second moves it
    assert moved == [True, False, True, True]
    # the rooms read at each event, at x and y of the pose
    assert arena.where == [(10.0, 5.0), (20.0, 5.0), (70.0, 30.0), (15.0, 45.0)]
    w, f = World.made[0], Follower.made[0]
    assert w.args == (arena, "ir8", 3) and w.resets == [3]
    assert f.params.rho == 0.25 and f.sensors is w.sensors and f.robot is w.robot
    assert f.rng.random() == Seeds(3).generator("recording").random()
    # away: to the other room's pose; back: to where it was taken from, not where it walked
    dests = [(90.0, 40.0, 1.5), (10.0, 5.0, 0.0), (15.0, 45.0, -1.5), (70.0, 30.0, 0.2)]
    assert w.placed == list(zip(events, dests))
    # the steps run up to the last event, the robot acting on the observation after the move
    assert w.k == 991 and len(f.seen) == 991
    assert f.seen[160] == ("obs", 160, (90.0, 40.0, 1.5))
    assert f.seen[159] == ("obs", 159, (10.0, 5.0, 0.0))
    # the other room's poses from the "kidnaps" stream, 6 cm inside room B, then room A
    rng = arena.asked[0][0]
    assert [a[1:] for a in arena.asked] == [(4.0, (56.0, 16.0, 104.0, 64.0)),
                                            (4.0, (6.0, 6.0, 24.0, 84.0))]
    assert arena.asked[1][0] is rng
    assert rng.random() == Seeds(3).generator("kidnaps").random()
    assert recorded == [((arena, 1011), dict(seed=3, rho=0.25, sensors="ir8",
                                             kidnaps=list(zip(events, dests)),
                                             progress=False))]


@pytest.mark.parametrize(("test_len", "events"), [
    (981, [160, 410, 650, 990]),          # the second return at 980 < 981: both pairs
    (980, [160, 410]),                    # at 980 exactly: only the first pair
    (401, [160, 410]),
    (400, []),                            # the first return at 400 not inside: none
])
def test_only_pairs_whose_return_falls_in_the_test_part_are_planned(monkeypatch, test_len,
                                                                    events):
    _, (_, got, kinds, moved), recorded = _kidnap(monkeypatch, 10 + test_len, 10)
    assert got == events and len(kinds) == len(moved) == len(events)
    assert World.made[0].k == (max(events) + 1 if events else 0)
    assert recorded[0][1]["kidnaps"] == [(e, p) for e, (_, p) in
                                         zip(events, World.made[0].placed)]


def _args(cache) -> argparse.Namespace:
    return argparse.Namespace(cache=cache, rho=0.008)


def _stub_recordings(monkeypatch):
    calls: dict[str, list] = {"cached": [], "record": [], "kid": []}

    def cached(cache, tag, build, ticks):
        calls["cached"].append((cache, tag, ticks))
        return build()

    def kidnapped(arena, ticks, n_train, *, seed, rho):
        calls["kid"].append((arena, ticks, n_train, seed, rho))
        return Rec(ticks, "kid"), [700, 950], ["away from room_a", "back to room_a"], [True, False]

    monkeypatch.setattr(T, "cached_recording", cached)
    monkeypatch.setattr(T, "record", lambda *a, **k: calls["record"].append((a, k)) or Rec(a[1]))
    monkeypatch.setattr(T, "kidnapped_recording", kidnapped)
    return calls


def test_recordings_without_a_cache(monkeypatch):
    calls = _stub_recordings(monkeypatch)
    rec, kid, events, kinds, moved = T._recordings(_args(None), "ARENA", 1600, 600, 2)
    assert calls["cached"] == [(None, "two-rooms_t1600_rho0.008_s2", 1600)]
    assert calls["record"] == [(("ARENA", 1600), dict(seed=2, rho=0.008, sensors="ir8",
                                                      desc="two-rooms seed 2"))]
    assert calls["kid"] == [("ARENA", 1600, 600, 2, 0.008)]
    assert len(rec) == 1600 and kid.tag == "kid" and kid.saved == []
    assert (events, kinds, moved) == ([700, 950], ["away from room_a", "back to room_a"],
                                      [True, False])


def test_recordings_with_a_cache_are_written_then_read_back(monkeypatch, tmp_path):
    calls = _stub_recordings(monkeypatch)
    out = T._recordings(_args(str(tmp_path)), "ARENA", 1600, 600, 2)
    meta = tmp_path / "two-rooms_t1600_rho0.008_s2_kid2.json"
    assert calls["cached"] == [(str(tmp_path), "two-rooms_t1600_rho0.008_s2", 1600)]
    assert out[1].saved == [tmp_path / "two-rooms_t1600_rho0.008_s2_kid2.npz"]
    assert meta.exists() and len(calls["kid"]) == 1
    loaded: list[Path] = []
    monkeypatch.setattr(T.Recording, "load", lambda p: loaded.append(p) or Rec(1600, "cached"))
    again = T._recordings(_args(str(tmp_path)), "ARENA", 1600, 600, 2)
    assert len(calls["kid"]) == 1 and loaded == [meta.with_suffix(".npz")]
    assert again[1].tag == "cached" and again[2:] == out[2:]


@pytest.mark.parametrize("error", [CorruptFileError("bad bytes"), FileNotFoundError("gone")])
def test_an_unusable_cached_kidnap_is_recorded_again_with_a_warning(monkeypatch, tmp_path,
                                                                   error):
    calls = _stub_recordings(monkeypatch)
    meta = tmp_path / "two-rooms_t1600_rho0.008_s2_kid2.json"
    save_json(meta, {"events": [], "kinds": [], "moved": []})

    def fail(path, ticks):
        raise error

    monkeypatch.setattr(T, "_cached_kidnaps", fail)
    with pytest.warns(UserWarning) as got:
        out = T._recordings(_args(str(tmp_path)), "ARENA", 1600, 600, 2)
    assert [str(w.message) for w in got] == [
        f"the cached kidnapped recording {meta} is unusable ({error}): recording it again"]
    assert got[0].filename != T.__file__          # stacklevel 2: the caller's line
    assert len(calls["kid"]) == 1 and out[2] == [700, 950]
    assert out[1].saved == [meta.with_suffix(".npz")]


def _cached(monkeypatch, tmp_path, meta, n: int = 50):
    path = tmp_path / "k_kid2.json"
    save_json(path, meta)
    monkeypatch.setattr(T.Recording, "load", lambda p: Rec(n, str(p)))
    return path


def test_cached_kidnaps_are_read_back(monkeypatch, tmp_path):
    meta = {"events": [0, 49], "kinds": ["a", "b"], "moved": [True, False]}
    path = _cached(monkeypatch, tmp_path, meta)
    rec, ev, kinds, moved = T._cached_kidnaps(path, 50)
    assert rec.tag == str(tmp_path / "k_kid2.npz") and len(rec) == 50
    assert (ev, kinds, moved) == ([0, 49], ["a", "b"], [True, False])
    path = _cached(monkeypatch, tmp_path, {"events": [], "kinds": [], "moved": []})
    assert T._cached_kidnaps(path, 50)[1:] == ([], [], [])


@pytest.mark.parametrize("meta", [
    [1, 2, 3],
    {"events": [1], "kinds": ["a"]},
    {"events": [1], "kinds": "a", "moved": [True]},
    {"events": 1, "kinds": ["a"], "moved": [True]},
    {"events": [1], "kinds": ["a"], "moved": None},
])
def test_cached_kidnaps_need_three_lists(monkeypatch, tmp_path, meta):
    path = _cached(monkeypatch, tmp_path, meta)
    with pytest.raises(CorruptFileError) as e:
        T._cached_kidnaps(path, 50)
    assert str(e.value) == f"{path} must hold the lists events, kinds and moved"


@pytest.mark.parametrize(("meta", "n"), [
    ({"events": [-1], "kinds": ["a"], "moved": [True]}, 50),
    ({"events": [50], "kinds": ["a"], "moved": [True]}, 50),
    ({"events": [1.0], "kinds": ["a"], "moved": [True]}, 50),
    ({"events": [True], "kinds": ["a"], "moved": [True]}, 50),   # a bool is no tick
    ({"events": [1], "kinds": [2], "moved": [True]}, 50),
    ({"events": [1], "kinds": ["a"], "moved": [1]}, 50),
    ({"events": [1], "kinds": ["a"], "moved": [True]}, 49),      # the recording's length
    ({"events": [1, 2], "kinds": ["a"], "moved": [True]}, 50),
    ({"events": [1], "kinds": ["a", "b"], "moved": [True]}, 50),
    ({"events": [1], "kinds": ["a"], "moved": [True, True]}, 50),
])
def test_cached_kidnaps_that_do_not_match_are_refused(monkeypatch, tmp_path, meta, n):
    path = _cached(monkeypatch, tmp_path, meta, n)
    with pytest.raises(CorruptFileError) as e:
        T._cached_kidnaps(path, 50)
    assert str(e.value) == (f"{path}: events, kinds and moved do not match each other or a "
                            "50-tick recording")
