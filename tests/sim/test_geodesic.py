"""Geodesic distances: the grid path pulled taut, never shorter than the true shortest path."""

from __future__ import annotations

import math

import pytest

from hippo.sim import ArenaBuilder, arenas


def test_open_box_is_the_straight_line():
    box = ArenaBuilder("box", 100, 60).outer_walls().build()
    assert box.geodesic_distance((10, 10), (90, 50)) == pytest.approx(math.hypot(80, 40))
    # into a rectangle: to its nearest point
    assert box.geodesic_distance((10, 10), (80, 40, 95, 55)) == pytest.approx(math.hypot(70, 30))
    assert box.geodesic_distance((85, 45), (80, 40, 95, 55)) == 0.0  # already inside


def test_around_a_wall_end_is_close_to_the_tangent_path():
    arena = ArenaBuilder("w", 100, 60).outer_walls().wall((50, 0), (50, 40)).start(20, 10).build()
    r = 3.7 + arena.wall_radius  # a disc of the robot's radius, off the wall's thickness
    # analytic optimum from P = (20, 10) to Q = (80, 10) over the wall end C = (50, 40): tangent
    # from P to the circle of radius r around C, the arc over the top, tangent down to Q; the
    # angle PCQ is 90°, so the arc spans 2π - π/2 - 2 acos(r/d)
    d = math.dist((20, 10), (50, 40))
    optimum = 2 * math.sqrt(d * d - r * r) + r * (2 * math.pi - math.pi / 2
                                                  - 2 * math.acos(r / d))
    g = arena.geodesic_distance((20, 10), (80, 10))
    grid = arena.shortest_path((20, 10), (80, 10), clearance=0.0)[0]
    assert optimum <= g <= 1.02 * optimum
    assert g < grid  # the grid's 45° moves are gone


def test_goal_arena_trials_are_between_the_straight_line_and_the_grid():
    ga = arenas.goal_arena()
    zone = ga.zones[0].rect
    for name in ("south", "east", "north", "west"):
        s = ga.landmarks[f"start-{name}"]
        g = ga.geodesic_distance(s, zone)
        straight = math.dist(s, (min(max(s[0], zone[0]), zone[2]),
                                 min(max(s[1], zone[1]), zone[3])))
        assert straight <= g < ga.shortest_path(s, zone, clearance=0.0)[0]
