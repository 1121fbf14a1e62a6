"""Generated flats: deterministic, every region reachable, no two rooms alike."""

import numpy as np
import pytest

from hippo.sim.builder import ArenaBuilder
from hippo.sim.flats import (
    RoomSpec,
    congruent,
    flat_with_rooms,
    random_flat,
    reachable_regions,
    room_names,
)


@pytest.mark.parametrize("n_rooms", [2, 3, 5])
def test_flat_reachable_and_labelled(n_rooms):
    for seed in range(3):
        arena = random_flat(n_rooms, seed)
        assert room_names(arena) == [f"room_{i + 1}" for i in range(n_rooms)]
        assert [r for r in arena.region_names if r.startswith("corridor")] == \
            [f"corridor_{i + 1}" for i in range(n_rooms - 1)]
        assert all(reachable_regions(arena).values())
        # labelled locations lie in free space, and every room has some
        for name in room_names(arena):
            inside = [arena.region_of(x, y) == name for x, y in arena.locations]
            assert sum(inside) >= 3
        assert all(arena.is_free(x, y, 3.7) for x, y in arena.locations)


def test_same_seed_same_flat_other_seed_other_flat():
    a, b, c = random_flat(3, 7), random_flat(3, 7), random_flat(3, 8)
    assert a.walls == b.walls and np.array_equal(a.locations, b.locations)
    assert a.walls != c.walls


def test_no_two_rooms_congruent():
    for n_rooms in (3, 4, 5):
        for seed in range(10):
            _, rooms = flat_with_rooms(n_rooms, seed)
            widths = sorted(r.box[2] - r.box[0] for r in rooms)
            assert np.min(np.diff(widths)) >= 8.0
            for i in range(n_rooms):
                for j in range(i + 1, n_rooms):
                    assert not congruent(rooms[i], rooms[j]), (n_rooms, seed, i, j)


def test_congruence_sees_through_rotation_and_mirror():
    a = RoomSpec((0, 0, 40, 70), (10, 0, 0, 0), (("top", "alcove", 5, 20, 10),))
    mirrored = RoomSpec((100, 0, 140, 70), (0, 10, 0, 0), (("top", "alcove", 15, 20, 10),))
    rotated = RoomSpec((0, 0, 40, 70), (0, 0, 10, 0), (("bottom", "alcove", 15, 20, 10),))
    other = RoomSpec((0, 0, 40, 70), (10, 0, 0, 0), (("top", "buttress", 5, 10, 8),))
    assert congruent(a, a) and congruent(a, mirrored) and congruent(a, rotated)
    assert not congruent(a, other)
    assert not congruent(a, RoomSpec((0, 0, 50, 70), a.chamfers, a.features))


def test_reachability_sees_a_blocked_door():
    b = (ArenaBuilder("blocked", 100, 40).outer_walls().wall((50, 0), (50, 40))
         .region("left", (0, 0, 50, 40)).region("right", (50, 0, 100, 40)).start(20, 20))
    assert reachable_regions(b.build()) == {"left": True, "right": False}
    b2 = (ArenaBuilder("open", 100, 40).outer_walls().wall((50, 0), (50, 25))
          .region("left", (0, 0, 50, 40)).region("right", (50, 0, 100, 40)).start(20, 20))
    assert reachable_regions(b2.build()) == {"left": True, "right": True}


def test_bad_arguments():
    for bad in (1, 2.5, True):
        with pytest.raises(ValueError, match="n_rooms"):
            random_flat(bad, 0)
    with pytest.raises(ValueError, match="seed"):
        random_flat(3, -1)
