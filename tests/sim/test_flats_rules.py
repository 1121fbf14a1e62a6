"""The generated flats' rules by hand (hippo.sim.flats): a room's draws on a scripted stream
(each range asked for, the chamfer and kind coin at 0.5, the usable span cl + 4 .. w - cr - 4,
a feature too wide skipped, the 10 cm gap exactly taken and just missed, 20 tries), the wall
outline of small rooms written out segment by segment (chamfers, buttresses and alcoves either
way along, doors), congruence under rotation and mirroring and its 2 cm rounding, the layout's
invariants on generated flats (widths, gaps, heights, corridors, doors 16 cm from corners, the
15 cm pad, regions, start, landmarks, the location grid), reachability on hand-made arenas, ray
lengths and a room's signature at one pose by hand, every refusal word for word."""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
import pytest

from hippo.sim import flats
from hippo.sim.builder import ArenaBuilder
from hippo.sim.flats import (
    RoomSpec,
    _draw_room,
    _edge_points,
    _ray_lengths,
    _room_walls,
    congruent,
    flat_with_rooms,
    random_flat,
    reachable_regions,
    room_names,
    room_signatures,
)


class Script:
    """A stand-in random generator returning scripted values, recording what was asked."""

    def __init__(self, *values: float) -> None:
        self.values = list(values)
        self.asked: list[tuple[str, float, float]] = []

    def _next(self) -> float:
        return self.values.pop(0)

    def random(self) -> float:
        self.asked.append(("random", 0, 1))
        return self._next()

    def uniform(self, a: float, b: float) -> float:
        self.asked.append(("uniform", a, b))
        v = self._next()
        assert a <= v <= b
        return v

    def integers(self, a: int, b: int) -> int:
        self.asked.append(("integers", a, b))
        return int(self._next())


# ----------------------------------------------------------------------------- one room
def test_a_room_drawn_from_a_script():
    rng = Script(0.3, 11.0, 0.7, 0.5, 0.9,        # chamfers: bl 11 (coin < 0.5), others square
                 2,                                # bottom: two features
                 0.2, 18.0, 12.0, 15.0,            # alcove 18 wide, 12 deep, at 15 (span 15..56)
                 0.9, 8.0, 8.0, 42.99, 43.0,       # buttress 8, 8 deep: 42.99 too close, 43 ok
                 1,                                # top: one feature
                 0.5, 14.0, 6.0, 42.0)             # coin 0.5 is a buttress; at the span's end
    ch, feats = _draw_room(rng, 60.0, 80.0)
    assert ch == (11.0, 0.0, 0.0, 0.0)
    assert feats == (("bottom", "alcove", 15.0, 18.0, 12.0),
                     ("bottom", "buttress", 43.0, 8.0, 8.0),
                     ("top", "buttress", 42.0, 14.0, 6.0))
    assert rng.values == []
    assert [a for a in rng.asked if a[0] != "random"] == [
        ("uniform", 8, 14), ("integers", 0, 3),
        ("uniform", 18, 26), ("uniform", 8, 12), ("uniform", 15.0, 38.0),
        ("uniform", 8, 14), ("uniform", 6, 10), ("uniform", 15.0, 48.0), ("uniform", 15.0, 48.0),
        ("integers", 0, 3), ("uniform", 8, 14), ("uniform", 6, 10), ("uniform", 4.0, 42.0)]


def test_a_feature_wider_than_the_span_is_skipped_and_twenty_tries_at_most():
    # width 30, bottom chamfers 12 and 12: span 16 .. 14, nothing fits, no placement drawn
    rng = Script(0.1, 12.0, 0.1, 12.0, 0.9, 0.9, 1, 0.9, 8.0, 6.0, 0, )
    ch, feats = _draw_room(rng, 30.0, 60.0)
    assert ch == (12.0, 12.0, 0.0, 0.0) and feats == () and rng.values == []
    # a span exactly the feature's width: placed at its start
    rng = Script(0.9, 0.9, 0.9, 0.9, 1, 0.9, 8.0, 6.0, 4.0, 0)
    assert _draw_room(rng, 16.0, 60.0)[1] == (("bottom", "buttress", 4.0, 8.0, 6.0),)
    # the second feature finds no place in 20 tries and is dropped
    rng = Script(0.9, 0.9, 0.9, 0.9, 2, 0.9, 8.0, 6.0, 20.0, 0.9, 8.0, 6.0, *([25.0] * 20), 0)
    assert _draw_room(rng, 60.0, 60.0)[1] == (("bottom", "buttress", 20.0, 8.0, 6.0),)
    assert rng.values == []
    # a feature placed before an earlier one: its end 10 cm before that one's start, exactly
    rng = Script(0.9, 0.9, 0.9, 0.9, 2, 0.9, 8.0, 6.0, 40.0, 0.9, 8.0, 6.0, 22.01, 22.0, 0)
    assert _draw_room(rng, 60.0, 60.0)[1] == (("bottom", "buttress", 40.0, 8.0, 6.0),
                                              ("bottom", "buttress", 22.0, 8.0, 6.0))
    assert rng.values == []


def test_the_pattern_is_corners_and_sorted_kinds():
    spec = RoomSpec((0, 0, 50, 70), (0.0, 9.0, 0.0, 12.0),
                    (("top", "buttress", 5, 8, 6), ("bottom", "alcove", 10, 20, 9),
                     ("bottom", "buttress", 35, 8, 6)))
    assert spec.pattern == ((False, True, False, True),
                            (("bottom", "alcove"), ("bottom", "buttress"), ("top", "buttress")))


# ------------------------------------------------------------------------------- walls
def test_edge_points_either_way_along():
    f1, f2 = ("bottom", "buttress", 10.0, 8.0, 6.0), ("bottom", "alcove", 30.0, 20.0, 9.0)
    assert _edge_points(0, 60, 5.0, +1, [f2, f1], 0.0) == [
        (10.0, 5.0), (10.0, 11.0), (18.0, 11.0), (18.0, 5.0),
        (30.0, 5.0), (30.0, -4.0), (50.0, -4.0), (50.0, 5.0)]
    # right to left along a top wall (room below): the later feature first, ends swapped
    assert _edge_points(102, 2, 80.0, -1, [f1, f2], 2.0) == [
        (52.0, 80.0), (52.0, 89.0), (32.0, 89.0), (32.0, 80.0),
        (20.0, 80.0), (20.0, 74.0), (12.0, 74.0), (12.0, 80.0)]
    assert _edge_points(0, 60, 0.0, +1, [], 0.0) == []
    # ordered by where they start, not by their width
    f3, f4 = ("top", "alcove", 5.0, 20.0, 9.0), ("top", "buttress", 40.0, 8.0, 6.0)
    assert _edge_points(60, 0, 50.0, -1, [f3, f4], 0.0) == [
        (48.0, 50.0), (48.0, 44.0), (40.0, 44.0), (40.0, 50.0),
        (25.0, 50.0), (25.0, 59.0), (5.0, 59.0), (5.0, 50.0)]


class Walls:
    def __init__(self) -> None:
        self.walls: list[tuple[tuple[float, float], tuple[float, float]]] = []

    def wall(self, p: Any, q: Any) -> Walls:
        self.walls.append((tuple(p), tuple(q)))
        return self


def test_the_outline_of_a_square_room():
    b = Walls()
    _room_walls(b, RoomSpec((0, 0, 40, 60), (0.0, 0.0, 0.0, 0.0), ()), [])  # type: ignore
    assert b.walls == [((0, 0), (40, 0)), ((40, 0), (40, 60)), ((40, 60), (0, 60)),
                       ((0, 60), (0, 0))]


def test_the_outline_with_chamfers_features_and_doors():
    spec = RoomSpec((10, 20, 60, 100), (5.0, 6.0, 7.0, 8.0),
                    (("bottom", "buttress", 20.0, 8.0, 6.0), ("top", "alcove", 15.0, 20.0, 9.0)))
    b = Walls()
    _room_walls(b, spec, [("right", 40.0, 60.0), ("left", 70.0, 80.0),  # type: ignore
                          ("left", 30.0, 45.0)])
    assert b.walls == [
        ((10, 25), (15, 20)),                                  # chamfer bl 5
        ((15, 20), (30.0, 20)), ((30.0, 20), (30.0, 26)), ((30.0, 26), (38.0, 26)),
        ((38.0, 26), (38.0, 20)), ((38.0, 20), (54, 20)),      # buttress 30..38, 6 deep
        ((54, 20), (60, 26)),                                  # chamfer br 6
        ((60, 26), (60, 40.0)), ((60, 60.0), (60, 93)),        # the right door 40..60
        ((60, 93), (53, 100)),                                 # chamfer tr 7
        ((53, 100), (45.0, 100)), ((45.0, 100), (45.0, 109)), ((45.0, 109), (25.0, 109)),
        ((25.0, 109), (25.0, 100)), ((25.0, 100), (18, 100)),  # alcove 25..45, 9 deep
        ((18, 100), (10, 92)),                                 # chamfer tl 8
        ((10, 92), (10, 80.0)), ((10, 70.0), (10, 45.0)),      # left doors, downwards
        ((10, 30.0), (10, 25))]


# -------------------------------------------------------------------------- congruence
def test_congruence_under_the_eight_symmetries_and_its_rounding():
    a = RoomSpec((0, 0, 40, 60), (10.0, 0.0, 0.0, 0.0), (("bottom", "alcove", 5.0, 20.0, 9.0),))
    mirror = RoomSpec((0, 0, 40, 60), (0.0, 10.0, 0.0, 0.0),
                      (("bottom", "alcove", 15.0, 20.0, 9.0),))
    half_turn = RoomSpec((5, 5, 45, 65), (0.0, 0.0, 10.0, 0.0),
                         (("top", "alcove", 15.0, 20.0, 9.0),))
    assert congruent(a, mirror) and congruent(a, half_turn) and congruent(a, a)
    quarter = RoomSpec((0, 0, 60, 40), (0.0, 10.0, 0.0, 0.0), ())
    assert congruent(RoomSpec((0, 0, 40, 60), (10.0, 0.0, 0.0, 0.0), ()), quarter)
    # kinds differ: an alcove is not a buttress
    assert not congruent(a, RoomSpec(a.box, a.chamfers, (("bottom", "buttress", 5.0, 20.0,
                                                          9.0),)))
    # sizes rounded to 2 cm: 60 and 61 agree (30.5 rounds to 30), 63 does not (32)
    assert congruent(a, RoomSpec((0, 0, 40, 61), a.chamfers, a.features))
    assert not congruent(a, RoomSpec((0, 0, 40, 63), a.chamfers, a.features))
    assert not congruent(a, RoomSpec(a.box, (14.0, 0.0, 0.0, 0.0), a.features))
    # an alcove 22 wide and 7 deep at the same place is another shape (width plus depth, 29,
    # is the same: it was taken for the same shape before)
    assert not congruent(a, RoomSpec(a.box, a.chamfers, (("bottom", "alcove", 4.0, 22.0, 7.0),)))
    # width and depth each rounded to 2 cm: 19.6 x 8.4 is 20 x 9 (halves 9.8 and 10 round to
    # 10, 4.2 and 4.5 to 4), 11.2 deep is not (5.6 rounds to 6)
    assert congruent(a, RoomSpec(a.box, a.chamfers, (("bottom", "alcove", 5.2, 19.6, 8.4),)))
    assert not congruent(a, RoomSpec(a.box, a.chamfers, (("bottom", "alcove", 5.0, 20.0, 11.2),)))


# ------------------------------------------------------------------------------ layout
@pytest.mark.parametrize("n,seed", [(2, 0), (3, 4), (4, 1), (7, 2)])
def test_the_layout_rules_on_generated_flats(n, seed):
    arena, specs = flat_with_rooms(n, seed)
    assert arena.name == f"flat-{n}r-s{seed}" and len(specs) == n
    gap = min(8.0, 45.0 / (n - 1))
    widths = [s.box[2] - s.box[0] for s in specs]
    heights = [s.box[3] - s.box[1] for s in specs]
    assert all(30 <= w <= 75 for w in widths) and all(60 <= h <= 100 for h in heights)
    assert np.min(np.diff(np.sort(widths))) >= gap - 1e-9
    assert len({s.pattern for s in specs}) == n
    assert specs[0].box[0] == 15.0 and min(s.box[1] for s in specs) == pytest.approx(15.0)
    assert arena.width == pytest.approx(specs[-1].box[2] + 15.0)
    assert arena.height == pytest.approx(max(s.box[3] for s in specs) + 15.0)
    assert room_names(arena) == [f"room_{i + 1}" for i in range(n)]
    regions = {r.name: r for r in arena.regions}
    assert set(regions) == {f"room_{i + 1}" for i in range(n)} | {
        f"corridor_{i + 1}" for i in range(n - 1)}
    mids = []
    for i in range(n - 1):
        (cx0, lo, cx1, hi), = regions[f"corridor_{i + 1}"].rects
        assert 20 <= cx1 - cx0 <= 35 and 20 <= hi - lo <= 26
        assert (cx0, cx1) == (specs[i].box[2], specs[i + 1].box[0])
        for s in (specs[i], specs[i + 1]):          # the door keeps 16 cm from the corners
            assert s.box[1] + 16 - 1e-9 <= lo and hi <= s.box[3] - 16 + 1e-9
        mids.append(((cx0 + cx1) / 2, (lo + hi) / 2))
    for i, s in enumerate(specs):
        rects = regions[f"room_{i + 1}"].rects
        assert tuple(rects[0]) == pytest.approx(s.box)
        x0, y0, x1, y1 = s.box
        alcoves = [(x0 + st, y0 - d, x0 + st + fw, y0) if e == "bottom"
                   else (x0 + st, y1, x0 + st + fw, y1 + d)
                   for e, k, st, fw, d in s.features if k == "alcove"]
        np.testing.assert_allclose(np.reshape(rects[1:], (-1, 4)), np.reshape(alcoves, (-1, 4)))
        assert arena.landmarks[f"room_{i + 1}"] == pytest.approx(((x0 + x1) / 2, (y0 + y1) / 2))
    x0, y0, x1, y1 = specs[0].box
    assert tuple(arena.start_pose[:2]) == pytest.approx(((x0 + x1) / 2, (y0 + y1) / 2))
    assert -math.pi <= arena.start_pose[2] <= math.pi
    # locations: the free points of a 15 cm grid from 7.5 cm in each box, then the corridors
    want = [(xx, yy) for x0, y0, x1, y1 in (s.box for s in specs)
            for xx in np.arange(x0 + 7.5, x1, 15.0) for yy in np.arange(y0 + 7.5, y1, 15.0)
            if arena.is_free(xx, yy, 4.7)] + mids
    np.testing.assert_allclose(arena.locations, want)
    assert all(reachable_regions(arena).values())


@pytest.mark.parametrize("n,seed", [(2, 0), (7, 2)])
def test_widths_and_heights_are_the_documented_first_draws(n, seed):
    _, specs = flat_with_rooms(n, seed)
    rng = np.random.default_rng([seed, 0])          # the first attempt's stream
    gap = 8.0 if n <= 6 else 45.0 / (n - 1)
    base = np.sort(rng.uniform(0.0, 45.0 - gap * (n - 1), n)) + gap * np.arange(n)
    widths = 30.0 + rng.permutation(base)
    heights = rng.uniform(60, 100, n)
    np.testing.assert_allclose([s.box[2] - s.box[0] for s in specs], widths, rtol=1e-12)
    np.testing.assert_allclose([s.box[3] - s.box[1] for s in specs], heights, rtol=1e-12)


def test_corridors_are_20_to_35_long_and_20_to_26_wide():
    lengths, widths = [], []
    for n, seed in ((3, 0), (4, 1), (5, 2), (6, 3)):
        for r in random_flat(n, seed).regions:
            if r.name.startswith("corridor"):
                (x0, y0, x1, y1), = r.rects
                lengths.append(x1 - x0)
                widths.append(y1 - y0)
    assert min(lengths) >= 20 and max(lengths) <= 35 and max(lengths) > 26
    assert min(widths) >= 20 and max(widths) <= 26


def test_same_seed_same_flat_and_the_name():
    a, _ = flat_with_rooms(3, 5)
    b = random_flat(3, 5, name="mine")
    assert b.name == "mine" and np.array_equal(a.wall_array(), b.wall_array())
    assert random_flat(np.int64(2), np.int64(0)).name == "flat-2r-s0"


@pytest.mark.parametrize("fn", [random_flat, flat_with_rooms])
def test_refusals_word_for_word(fn):
    for bad in (1, 0, -3, 2.0, True, "3", None):
        with pytest.raises(ValueError, match="^" + __import__("re").escape(
                f"n_rooms must be an integer >= 2, got {bad!r}") + "$"):
            fn(bad, 0)
    for bad in (-1, 1.0, False, "0", None):
        with pytest.raises(ValueError, match="^" + __import__("re").escape(
                f"seed must be an integer >= 0, got {bad!r}") + "$"):
            fn(2, bad)
    fn(2, 0)


def test_no_flat_in_a_hundred_draws_says_so(monkeypatch):
    calls: list[Any] = []

    def never(n: int, rng: Any, name: str) -> None:
        calls.append(rng)

    monkeypatch.setattr(flats, "_draw_flat", never)
    with pytest.raises(RuntimeError, match=r"^no reachable flat of 3 rooms found for seed 7$"):
        flat_with_rooms(3, 7)
    assert len(calls) == 100
    first = np.random.default_rng([7, 0]).random()
    last = np.random.default_rng([7, 99]).random()
    assert calls[0].random() == first and calls[-1].random() == last


# ------------------------------------------------------------------------ reachability
def _corridor(width: float) -> Any:
    """Two 40 x 42 rooms joined by a 20 cm corridor ``width`` wide (centred on the free grid's
    row y = 21)."""
    lo, hi = 21 - width / 2, 21 + width / 2
    return (ArenaBuilder("c", 100, 42).outer_walls()
            .wall((40, 0), (40, lo)).wall((40, hi), (40, 42))
            .wall((60, 0), (60, lo)).wall((60, hi), (60, 42))
            .wall((40, lo), (60, lo)).wall((40, hi), (60, hi))
            .region("a", (0, 0, 40, 42)).region("b", (60, 0, 100, 42)).start(20, 21)).build()


def test_reachability_through_a_corridor_by_the_discs_size():
    arena = _corridor(12.0)             # 6 cm from the centre line to each wall
    assert reachable_regions(arena) == {"a": True, "b": True}            # 4.7 fits
    assert reachable_regions(arena, radius=5.0, margin=0.0) == {"a": True, "b": True}
    assert reachable_regions(arena, radius=6.5, margin=0.0) == {"a": True, "b": False}
    assert reachable_regions(arena, radius=5.5, margin=1.0) == {"a": True, "b": False}


def test_reachability_on_a_coarser_grid():
    # cell 7: the rows nearest the corridor's centre, 17.5 and 24.5, are 2.5 cm from its walls
    assert reachable_regions(_corridor(12.0), cell=7.0) == {"a": True, "b": False}


def test_a_region_reached_only_on_its_edge():
    # a wall at x = 14: a disc of 4.7 (+ the walls' 0.5) fits from x = 19.2, the grid's
    # column 21 first; "left" ends exactly on that column, "low" on the row y = 21
    arena = (ArenaBuilder("e", 60, 40).outer_walls().wall((14, 0), (14, 40))
             .region("left", (5, 0, 21, 40)).region("short", (5, 0, 20.9, 40))
             .start(40, 20)).build()
    assert reachable_regions(arena) == {"left": True, "short": False}
    arena = (ArenaBuilder("e", 40, 60).outer_walls().wall((0, 14), (40, 14))
             .region("low", (0, 5, 40, 21)).region("lower", (0, 5, 40, 20.9))
             .start(20, 40)).build()
    assert reachable_regions(arena) == {"low": True, "lower": False}


def test_a_start_in_a_wall_reaches_nothing():
    arena = (ArenaBuilder("w", 60, 40).outer_walls().box((25, 0, 35, 40))
             .region("a", (0, 0, 25, 40)).region("b", (35, 0, 60, 40)).start(10, 20)).build()
    assert reachable_regions(arena) == {"a": True, "b": False}
    object.__setattr__(arena, "start_pose", (30.0, 20.0, 0.0))           # inside the box
    assert reachable_regions(arena) == {"a": False, "b": False}


# ---------------------------------------------------------------------------- the rays
def test_ray_lengths_by_hand():
    walls = np.array([[10.0, -5.0, 10.0, 5.0]])
    pts = np.array([[0.0, 0.0], [4.0, 0.0]])
    angles = np.array([0.0, math.atan2(5, 10), math.atan2(5.01, 10), math.pi, math.pi / 2])
    out = _ray_lengths(walls, pts, angles, 30.0)
    np.testing.assert_allclose(out[0], [10.0, math.hypot(10, 5), 30.0, 30.0, 30.0],
                               rtol=1e-12)
    np.testing.assert_allclose(out[1], [6.0, 6.0 / math.cos(math.atan2(5, 10)),
                                        6.0 / math.cos(math.atan2(5.01, 10)), 30.0, 30.0],
                               rtol=1e-12)
    assert _ray_lengths(walls, pts, np.array([0.0]), 8.0)[0, 0] == 8.0    # capped
    two = np.array([[10.0, -5.0, 10.0, 5.0], [7.0, -1.0, 7.0, 1.0]])
    assert _ray_lengths(two, pts[:1], np.array([0.0]), 30.0)[0, 0] == 7.0  # the nearer
    back = np.array([[-3.0, -1.0, -3.0, 1.0]])       # behind the ray: t < 0
    assert _ray_lengths(back, pts[:1], np.array([0.0]), 30.0)[0, 0] == 30.0
    slant = np.array([[10.0, -10.0, 0.0, 10.0]])     # crosses y = 0 at x = 5 (s = 1/2)
    assert _ray_lengths(slant, pts[:1], np.array([0.0]), 30.0)[0, 0] == pytest.approx(5.0)
    start = np.array([[10.0, 0.0, 10.0, 5.0]])       # the ray meets the wall's end: s = 0
    assert _ray_lengths(start, pts[:1], np.array([0.0]), 30.0)[0, 0] == 10.0
    touch = np.array([[0.0, 0.0, 0.0, 5.0]])         # starting on the wall: t = 0
    assert _ray_lengths(touch, pts[:1], np.array([0.0]), 30.0)[0, 0] == 0.0


def test_a_rooms_signature_at_one_pose_by_hand():
    arena = (ArenaBuilder("sq", 60, 40).outer_walls().region("room_1", (0, 0, 60, 40))
             .region("hall", (0, 0, 10, 10)).start(30, 20)).build()
    rng = np.random.default_rng(3)
    while True:
        x, y = rng.uniform(0, 60), rng.uniform(0, 40)
        if arena.is_free(x, y, 4.2):
            break
    sig = room_signatures(arena, n_poses=1, n_rays=4, rmax=30.0, seed=3)
    assert set(sig) == {"room_1"}                 # regions not named room... are left out
    want = sorted(min(d, 30.0) for d in (60 - x, 40 - y, x, y))
    np.testing.assert_allclose(sig["room_1"], want, rtol=1e-9)
    # the mean over poses of the sorted scans
    sig2 = room_signatures(arena, n_poses=2, n_rays=4, rmax=30.0, seed=3)
    rng = np.random.default_rng(3)
    scans = []
    while len(scans) < 2:
        x, y = rng.uniform(0, 60), rng.uniform(0, 40)
        if arena.is_free(x, y, 4.2):
            scans.append(sorted(min(d, 30.0) for d in (60 - x, 40 - y, x, y)))
    np.testing.assert_allclose(sig2["room_1"], np.mean(scans, axis=0), rtol=1e-9)


def test_a_parallel_wall_is_missed_without_a_warning():
    walls = np.array([[0.0, 2.0, 10.0, 2.0], [5.0, 0.0, 9.0, 0.0]])   # along the ray, and on it
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = _ray_lengths(walls, np.array([[0.0, 0.0]]), np.array([0.0]), 30.0)
    assert out[0, 0] == 30.0


def test_signature_defaults():
    arena = (ArenaBuilder("sq", 60, 40).outer_walls().region("room_1", (0, 0, 60, 40))
             .start(30, 20)).build()
    sig = room_signatures(arena)["room_1"]
    assert sig.shape == (36,)
    np.testing.assert_array_equal(
        sig, room_signatures(arena, n_poses=200, n_rays=36, rmax=30.0, seed=0)["room_1"])
    assert np.all(np.diff(sig) >= 0) and sig[-1] <= 30.0


class Stand:
    """A stand-in arena: a hand-made free grid on the points 1, 3, 5 either way."""

    def __init__(self, free: list[list[int]], rects: list[tuple[float, ...]]) -> None:
        self.free = np.array(free, bool)
        self.start_pose = (1.0, 1.0, 0.0)
        self.regions = [type("R", (), {"name": "r", "rects": rects})()]

    def free_grid(self, radius: float, cell: float) -> tuple[np.ndarray, np.ndarray, Any]:
        return np.array([1.0, 3.0, 5.0]), np.array([1.0, 3.0, 5.0]), self.free


def test_reachability_is_8_connected_and_counts_every_rect():
    diagonal = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    assert reachable_regions(Stand(diagonal, [(4, 4, 6, 6)])) == {"r": True}  # type: ignore
    apart = [[1, 0, 0], [0, 0, 0], [0, 0, 1]]
    assert reachable_regions(Stand(apart, [(4, 4, 6, 6)])) == {"r": False}  # type: ignore
    # a region of two rects: reached in the first only
    assert reachable_regions(Stand(apart, [(0, 0, 2, 2), (4, 4, 6, 6)])) == {  # type: ignore
        "r": True}


def test_room_patterns_are_redrawn_until_new(monkeypatch):
    a = ((10.0, 0.0, 0.0, 0.0), ())
    b = ((0.0, 10.0, 0.0, 0.0), ())
    drawn: list[Any] = []

    def script(rng: Any, width: float, height: float) -> tuple:
        drawn.append(width)
        return a if len(drawn) < 3 else b

    monkeypatch.setattr(flats, "_draw_room", script)
    out = flats._draw_flat(2, np.random.default_rng(0), "x")
    assert out is not None and len(drawn) == 3
    assert [sp.chamfers for sp in out[1]] == [a[0], b[0]]
    drawn.clear()
    monkeypatch.setattr(flats, "_draw_room", lambda rng, w, h: (drawn.append(w), a)[1])
    assert flats._draw_flat(2, np.random.default_rng(0), "x") is None
    assert len(drawn) == 1 + 50                     # the second room gives up after 50 draws
