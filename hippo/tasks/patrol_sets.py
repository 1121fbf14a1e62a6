"""A patrol's checkpoints, their waits and the leash route through them, on any arena.

- ``ARENA_CHECKPOINTS`` — default checkpoints of the built-in arenas; ``HIREL_WAITS`` — HIREL's
  taught waits (s).
- :func:`patrol_route`, :func:`choose_route` — the leash route through the checkpoints (and
  what it is); :func:`check_patrol` — the checks a user's checkpoints and waits must pass
  (free floor, reachable, 40 cm apart along the route, one wait each).
- :func:`random_patrol` — checkpoints and waits nobody chose (for held-out tests).

Each takes the arena as a built-in arena's name (``"goal-arena"``) or as an
:class:`~hippo.sim.arena.Arena` of one's own (:class:`~hippo.sim.ArenaBuilder`).
"""

from __future__ import annotations

from collections.abc import Sequence
from numbers import Real
from typing import Any

import numpy as np
from scipy import ndimage

from hippo._checks import check_int, check_seed
from hippo.sim import arenas
from hippo.sim.arena import Arena, _segment_clear
from hippo.tasks.explore import arena_tour
from hippo.tasks.patrol_report import PASS_RADIUS
from hippo.tasks.routes import Route, checkpoints_xy

__all__ = ["ARENA_CHECKPOINTS", "HIREL_WAITS", "MAX_WAIT_S", "MIN_WAIT_S", "ROUTE_KINDS",
           "TOUR_REACH", "check_patrol", "choose_route", "led_route", "patrol_route",
           "random_patrol", "tour_of_side"]

#: the arenas a patrol runs in, with their default checkpoints (cm): patrol-course's are its
#: landmarks checkpoint-1..3 on the corridor loop; the others' were placed in distinct parts
#: of each arena (room A and both ends of room B; three corridors of the goal arena; three
#: maze cells on a 650 cm round trip from the start)
ARENA_CHECKPOINTS: dict[str, list[tuple[float, float]]] = {
    "patrol-course": [(80.0, 11.0), (140.0, 56.0), (50.0, 105.0)],
    "two-rooms": [(15.0, 65.0), (90.0, 20.0), (100.0, 70.0)],
    "goal-arena": [(85.0, 15.0), (132.0, 76.0), (45.0, 136.0)],
    "maze": [(20.0, 20.0), (140.0, 140.0), (220.0, 60.0)],
}
#: HIREL's three checkpoint waits (s); with n checkpoints the first n are the defaults
HIREL_WAITS = [24.1, 19.1, 11.6, 16.0]
#: the shortest checkpoint wait (s) a patrol takes: with ground truth a 1-s wait was learned as
#: 0.8 s and never reproduced, 0.5 s never taught (patrol-course, seed 0, --quick); 1.2 s
#: worked there, and 2 s leaves a margin for learned place cells
MIN_WAIT_S = 2.0
#: the longest: the timing battery's longest delay (``SpectralParams.mu_max``, 120 s); a longer
#: wait is learned as 120 s
MAX_WAIT_S = 120.0
#: a shortest route that runs back over itself for longer than this (cm,
#: :attr:`Route.doubled_length`) gives way to a wall tour through every checkpoint: on the
#: doubled stretch the pass count cannot tell which way the robot goes (patrol-course,
#: checkpoints 12,100;145,20;145,100;60,10: the robot stopped at checkpoint 3 on every lap,
#: and no pass of it was counted)
DOUBLED_MAX = 30.0
#: how a patrol route is built (:func:`patrol_route`)
ROUTE_KINDS = ("auto", "shortest", "tour")
#: a wall tour is a patrol's route only if it passes this close to every checkpoint (chosen
#: when the lesson held the robot within 20 cm of a checkpoint; it now allows PASS_RADIUS)
TOUR_REACH = 20.0



def _arena(arena: str | Arena) -> Arena:
    """The :class:`Arena` itself, or the built-in one of that name."""
    if isinstance(arena, Arena):
        return arena
    if isinstance(arena, str):
        return arenas.get(arena)
    raise TypeError(f"arena must be an arena's name or an Arena, got {type(arena).__name__}")


def patrol_route(arena: str | Arena, checkpoints: Sequence[Sequence[float]],
                 kind: str = "auto") -> Route:
    """The leash route of :func:`choose_route`."""
    return choose_route(arena, checkpoints, kind)[1]


def choose_route(arena: str | Arena, checkpoints: Sequence[Sequence[float]],
                 kind: str = "auto") -> tuple[str, Route]:
    """``(what it is, the leash route)``: ``"course"``, patrol-course's corridor loop for its
    own checkpoints with ``kind`` ``"auto"``; else by ``kind``: ``"shortest"``, the shortest
    paths through the checkpoints and back (:meth:`Route.through`, 8 cm clear of walls where it
    can); ``"tour"``, a wall follower's loop (:func:`hippo.tasks.wall_tour`, right wall first)
    within ``TOUR_REACH`` cm of every checkpoint; ``"auto"``: the shortest paths if they make a
    loop (:attr:`Route.winding` not 0) that one of the arena's two wall tours runs the same way
    round and runs back over itself for at most ``DOUBLED_MAX`` cm (checkpoints out of the
    loop's order), else a tour that goes round something and passes every checkpoint, else the
    shortest.
    The robot moves along a wall (:func:`hippo.tasks.wall_side`), and in ``goal-arena`` no wall
    goes round clockwise (the right wall follower turns back at the south nook), so a clockwise
    route was run backwards (tuning seeds 0-15, learned cells: 65 of 149 passes with a stop,
    against 190 of 254 with the tour, visited the other way). Two-rooms' shortest paths run out
    and back (a maze's, and its tours, too)."""
    if kind not in ROUTE_KINDS:
        raise ValueError(f"route kind must be one of {', '.join(ROUTE_KINDS)}, got {kind!r}")
    name = arena.name if isinstance(arena, Arena) else arena   # the built-in one as an Arena too
    if kind == "auto" and name == "patrol-course" and \
            [tuple(map(float, c)) for c in checkpoints] == ARENA_CHECKPOINTS["patrol-course"]:
        return "course", Route(arenas.loop_waypoints())
    arena_obj = _arena(arena)
    route = None
    if kind != "tour":
        route = Route.through(arena_obj, checkpoints, clearance=8.0)
        if kind == "shortest":
            return "shortest", route
    tours = [t for t in (arena_tour(arena, side) for side in (-1, 1)) if t is not None]
    if route is not None and route.winding != 0 and any(t.winding == route.winding
                                                        for t in tours) \
            and route.doubled_length <= DOUBLED_MAX:
        return "shortest", route
    for tour in tours:
        if all(tour.distance(*c) <= TOUR_REACH for c in checkpoints) and \
                (kind == "tour" or tour.winding != 0):
            return "tour", tour
    if route is not None:
        return "shortest", route
    far = min(([c for c in checkpoints if t.distance(*c) > TOUR_REACH] for t in tours),
              key=len, default=list(checkpoints))
    raise ValueError(f"no wall tour of arena {arena_obj.name!r} passes within {TOUR_REACH:g} cm of "
                     f"checkpoint(s) {', '.join(f'({x:g}, {y:g})' for x, y in far)}")


def tour_of_side(arena: str | Arena, checkpoints: Sequence[Sequence[float]], kind: str,
                 route: Route, side: int) -> Route:
    """The route a robot following wall ``side`` is led and counted along: on a wall tour
    (``kind`` ``"tour"``), the tour of wall ``side`` where ``route`` is the other wall's and
    this one passes every checkpoint within ``TOUR_REACH`` cm the same way round; else
    ``route``. In a ring both walls' tours pass the checkpoints, 20-30 cm apart, and the
    lesson led the robot along the right wall's while it had explored along the left one
    (:func:`~hippo.tasks.explore.wall_side`); the places it learned on the leash were then
    not those of its own laps. Rule 50 (docs/results.md): on the 9 draws of arenas built with
    ``ArenaBuilder`` it changes (seeds 4-15), 97/141 -> 118/155 passes with a stop; no draw of
    the built-in arenas changes."""
    if kind != "tour":
        return route
    own = arena_tour(arena, side)
    if own is None or own is route or own.winding != route.winding:
        return route
    if all(own.distance(*c) <= TOUR_REACH for c in checkpoints_xy(checkpoints)):
        return own
    return route


def led_route(arena: str | Arena, checkpoints: Sequence[Sequence[float]], kind: str,
              side: int) -> tuple[str, Route]:
    """:func:`choose_route`, then :func:`tour_of_side` for a robot following wall ``side``:
    the route a lesson led it along, found again for a saved lesson or a resumed run."""
    what, route = choose_route(arena, checkpoints, kind)
    return what, tour_of_side(arena, checkpoints, what, route, side)


def _home_floor(arena: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The arena's free-floor grid ``(xs, ys, mask)``: cells the robot reaches from the start."""
    radius = 3.7
    xs, ys, free = arena.free_grid(radius)
    parts, _ = ndimage.label(free)
    home = parts == parts[np.argmin(np.abs(xs - arena.start_pose[0])),
                          np.argmin(np.abs(ys - arena.start_pose[1]))]
    # open: from a reachable cell by the arena's edge, a straight line out crosses no wall
    band = radius + 2.0 * (xs[1] - xs[0] if len(xs) > 1 else 2.0)
    walls = arena.wall_array()
    rim = ((xs < band) | (xs > arena.width - band))[:, None] | \
        ((ys < band) | (ys > arena.height - band))[None, :]
    for i, j in np.argwhere(home & rim):
        x, y = float(xs[i]), float(ys[j])
        for out in ((-1.0, y), (arena.width + 1.0, y), (x, -1.0), (x, arena.height + 1.0)):
            if abs(out[0] - x) + abs(out[1] - y) < band + 1.0 and \
                    _segment_clear((x, y), out, walls, 0.0):
                raise ValueError(f"arena {arena.name!r} is open: the robot can reach its edge "
                                 f"near ({x:.0f}, {y:.0f}) where no wall stands (close it, "
                                 "e.g. with ArenaBuilder.outer_walls())")
    return xs, ys, home


def check_patrol(arena_spec: str | Arena, checkpoints: Sequence[Sequence[float]],
                 waits: Sequence[float], kind: str = "auto") -> Route:
    """Raise ``ValueError`` naming the problem unless the checkpoints lie on free floor of the
    arena (6 cm clear of every wall) that the robot can reach from the arena's start, are
    reachable from each other and are at least 40 cm apart along the route, two to four of
    them with one wait each (``MIN_WAIT_S`` to ``MAX_WAIT_S``); returns the route."""
    return checked_route(arena_spec, checkpoints, waits, kind)[1]


def checked_route(arena_spec: str | Arena, checkpoints: Sequence[Sequence[float]],
                  waits: Sequence[float], kind: str = "auto") -> tuple[str, Route]:
    """:func:`check_patrol`'s checks, returning :func:`choose_route`'s ``(what it is, the
    route)`` (the route is built once for both)."""
    arena = _arena(arena_spec)
    arena_name = arena.name
    checkpoints, waits = _course(checkpoints, waits)
    if not 2 <= len(checkpoints) <= 4:
        raise ValueError(f"a patrol has 2 to 4 checkpoints, got {len(checkpoints)}")
    if len(waits) != len(checkpoints):
        raise ValueError(f"got {len(waits)} waits for {len(checkpoints)} checkpoints; give "
                         "one wait per checkpoint")
    short = [float(w) for w in waits if not float(w) >= MIN_WAIT_S]
    if short:
        raise ValueError(f"wait(s) {', '.join(f'{w:g}' for w in short)} s: a checkpoint's wait "
                         f"must be at least {MIN_WAIT_S:g} s (a shorter stop is not reproduced)")
    long = [float(w) for w in waits if not float(w) <= MAX_WAIT_S]
    if long:
        raise ValueError(f"wait(s) {', '.join(f'{w:g}' for w in long)} s: a checkpoint's wait "
                         f"must be at most {MAX_WAIT_S:g} s (the timing battery's longest delay)")
    xs, ys, home = _home_floor(arena)
    for x, y in checkpoints:
        if not arena.is_free(x, y, 6.0):
            raise ValueError(f"checkpoint ({x:g}, {y:g}) is not free floor of arena "
                             f"{arena_name!r} ({arena.width:g} x {arena.height:g} cm; a "
                             "checkpoint needs 6 cm clear of every wall)")
        if not home[np.argmin(np.abs(xs - x)), np.argmin(np.abs(ys - y))]:
            raise ValueError(f"checkpoint ({x:g}, {y:g}) cannot be reached from the start of "
                             f"arena {arena_name!r} (it lies inside walls, or behind a gap "
                             "narrower than the robot)")
    route_kind, route = choose_route(arena_spec, checkpoints, kind)
    s = sorted(route.progress(x, y) for x, y in checkpoints)
    gaps = np.diff([*s, s[0] + route.length])
    if gaps.min() < 40.0:
        raise ValueError(f"two checkpoints are {gaps.min():.0f} cm apart along the route; "
                         f"they need 40 cm (a pass is {PASS_RADIUS:g} cm either side)")
    return route_kind, route


def _course(checkpoints: Any, waits: Any) -> tuple[list[tuple[float, float]], list[float]]:
    """The checkpoints as ``(x, y)`` floats and the waits as floats, or a ``ValueError`` naming
    what is wrong: points that are not ``(x, y)`` (``(x, y, heading)`` failed in an unpacking),
    NaN or inf in them, two checkpoints on one spot (a route of no length), a wait that is no
    number (``None``, ``"9"``), waits that are not a list."""
    pts = [(float(x), float(y)) for x, y in checkpoints_xy(checkpoints)]
    for b, q in enumerate(pts):
        a = pts.index(q)
        if a != b:
            raise ValueError(f"checkpoints {a + 1} and {b + 1} are the same point "
                             f"({q[0]:g}, {q[1]:g}); each checkpoint must have a spot of its own")
    if isinstance(waits, str) or not hasattr(waits, "__len__") or np.ndim(waits) != 1:
        raise ValueError(f"waits must be a list of waits in s (one per checkpoint), got "
                         f"{waits!r:.80}")
    bad = [w for w in waits if isinstance(w, bool | np.bool_) or not isinstance(w, Real)]
    if bad:
        raise ValueError(f"waits must be numbers of seconds, got {bad[0]!r}")
    return pts, [float(w) for w in waits]


def random_patrol(arena_spec: str | Arena, n: int, seed: int, *,
                  waits: tuple[float, float] = (8.0, 30.0),
                  clearance: float = 10.0, tries: int = 2000
                  ) -> tuple[list[tuple[float, float]], list[float]]:
    """``n`` checkpoints and their waits nobody chose: points drawn at random (generator
    ``seed``) on the floor the robot can reach (``clearance`` cm from every wall, on a 2 cm
    grid), at least 40 cm apart, until a set passes :func:`check_patrol` (40 cm apart along
    its route); waits drawn uniformly from ``waits`` (s, to 0.1 s). For held-out tests of a
    patrol in any arena."""
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or not 2 <= n <= 4:
        raise ValueError(f"n must be 2 to 4 checkpoints, got {n!r}")
    if np.ndim(waits) != 1 or len(waits) != 2:
        raise ValueError(f"waits must be (low, high) in s, got {waits!r:.80}")
    lo, hi = (float(v) for v in waits)
    if not MIN_WAIT_S <= lo <= hi <= MAX_WAIT_S:
        raise ValueError(f"waits must be (low, high) with {MIN_WAIT_S:g} <= low <= high <= "
                         f"{MAX_WAIT_S:g} s, got {tuple(waits)!r}")
    tries = check_int("tries", tries, lo=1)
    if not 0.0 <= float(clearance) < 1e6:
        raise ValueError(f"clearance must be a finite number of cm >= 0, got {clearance!r}")
    arena = _arena(arena_spec)
    rng = np.random.default_rng(check_seed("seed", seed))
    xs, ys, home = _home_floor(arena)
    _, _, roomy = arena.free_grid(clearance)
    i, j = np.nonzero(roomy & home)
    if len(i) < n:
        raise ValueError(f"arena {arena.name!r} has {len(i)} points of floor {clearance:g} cm "
                         f"clear of every wall; {n} checkpoints need more (a smaller clearance)")
    floor = np.column_stack([xs[i], ys[j]])
    for _ in range(tries):
        pick = floor[rng.choice(len(floor), size=n, replace=False)]
        w = [float(np.round(v, 1)) for v in rng.uniform(*waits, size=n)]
        gaps = np.hypot(*(pick[:, None] - pick[None]).transpose(2, 0, 1))
        if gaps[np.triu_indices(n, 1)].min() < 40.0:
            continue
        cps = [(float(x), float(y)) for x, y in pick]
        try:
            check_patrol(arena_spec, cps, w)
        except ValueError:
            continue
        return cps, w
    raise ValueError(f"no {n} checkpoints 40 cm apart along a route found in arena "
                     f"{arena.name!r} after {tries} tries")
