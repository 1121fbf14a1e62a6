"""A saved robot's meta (patrol lesson, place-preference robot) is checked field by field
before any work: a hand-edited snapshot whose checksums were recomputed is refused with the
field named, never half-run."""

import pytest

from hippo.scenarios._patrol_lesson import _check_meta
from hippo.tasks.patrol import ARENA_CHECKPOINTS, HIREL_WAITS


def _meta(**changes):
    meta = {"seed": 3, "arena": "patrol-course",
            "checkpoints": [list(c) for c in ARENA_CHECKPOINTS["patrol-course"]],
            "waits": list(HIREL_WAITS[:3]), "place_cells": "learned", "explore_min": 30.0,
            "units": 24, "places": 40, "route": "auto", "reproduced": 1.0,
            "taught_stops": [24.8, None, 12.0]}
    meta.update(changes)
    return meta


def test_a_meta_save_could_have_written_passes():
    _check_meta(_meta())
    _check_meta(_meta(seed=3.0, units=16.0, place_cells="ground-truth", route="tour",
                      reproduced=-0.4))  # JSON numbers; a route run backwards
    old = _meta()
    del old["route"]   # lessons saved before route kinds: the shortest paths
    _check_meta(old)


@pytest.mark.parametrize("key, value", [
    ("seed", "abc"), ("seed", -1), ("seed", 2.5), ("seed", True),
    ("units", 0), ("units", 201), ("places", 0), ("explore_min", 1.0),
    ("place_cells", "bogus"), ("route", "sideways"),
    ("checkpoints", [[80.0, 11.0]]), ("checkpoints", [[80.0, 11.0], [140.0, "x"]]),
    ("checkpoints", "80,11;140,56"),
    ("waits", [24.1, 19.1]), ("waits", [24.1, -5.0, 11.6]), ("waits", [24.1, float("nan"), 3]),
    ("taught_stops", []), ("taught_stops", [1.0, 2.0, -3.0]),
    ("reproduced", float("inf")), ("reproduced", None),
])
def test_a_bad_field_is_named(key, value):
    with pytest.raises(ValueError, match=key if key != "waits" or len(value) == 3 else "wait"):
        _check_meta(_meta(**{key: value}))


def test_a_course_the_arena_cannot_hold_is_refused():
    # patrol-course's checkpoints in the maze: refused as the snapshot's course, not as a
    # routing failure halfway through the run
    with pytest.raises(ValueError, match="snapshot's course"):
        _check_meta(_meta(arena="maze"))
    with pytest.raises(ValueError, match="unknown arena"):
        _check_meta(_meta(arena="moon"))


def test_a_saved_place_preference_robots_meta_is_checked_too():
    from hippo.scenarios.place_preference import _check_meta as check_pp

    good = {"seed": 4, "place_cells": "learned", "explore_min": 40.0, "explore_rho": 0.0,
            "quick": False}
    check_pp(good)
    for key, value in (("seed", "abc"), ("seed", -1), ("place_cells", "bogus"),
                       ("explore_min", -3.0), ("explore_rho", 7), ("quick", 1)):
        with pytest.raises(ValueError, match=key):
            check_pp({**good, key: value})
