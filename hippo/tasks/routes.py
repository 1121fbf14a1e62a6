"""Routes and checkpoints: where the robot is along a route, and its laps.

- :class:`Route` — a polyline of waypoints (closed for a loop): :meth:`Route.through` builds
  one from an arena's shortest paths between checkpoints; :meth:`Route.progress` is the
  distance along the route of the point nearest to a position (:meth:`Route.progress_near`
  the same, searched only near a previous progress, for routes that run over themselves);
  :meth:`Route.at` the point and direction at a progress; :meth:`Route.leg` the waypoints
  from one position to another along the route's direction; :meth:`Route.loop_from` a whole
  loop starting ahead of a pose.
- :func:`lead_from` — waypoints to lead the robot through, reached from where it stands along
  the arena's shortest path when a wall is in the way.
- :class:`LapCounter` — laps by route progress (unwrapped over the loop's length), tracked
  from tick to tick.

What a run's log says about passes and stops (:class:`~hippo.tasks.passes.AngleLaps`,
:func:`~hippo.tasks.passes.progress_along`, :func:`~hippo.tasks.passes.route_passes`,
:func:`~hippo.tasks.passes.passes`, :func:`~hippo.tasks.passes.stops`) is in
:mod:`hippo.tasks.passes`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from itertools import pairwise
from typing import Any

import numpy as np
from scipy.spatial import cKDTree

from hippo._checks import check_finite, check_positive, check_real

__all__ = ["MAX_SAMPLES", "LapCounter", "Route", "lead_from"]

#: the most points :meth:`Route.sample` returns (a spacing of 1e-6 cm asked for 400 million
#: points on a 4-m loop, built one by one in Python: a hang)
MAX_SAMPLES = 1_000_000


class Route:
    """Waypoints ``[(x, y), ...]`` in cm; ``closed``: the last one leads back to the first."""

    def __init__(self, waypoints: Sequence[Sequence[float]], *, closed: bool = True) -> None:
        if not isinstance(closed, bool | np.bool_):
            raise TypeError(f"closed must be True or False, got {closed!r}")
        pts = check_finite("waypoints", waypoints)
        if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 2:
            raise ValueError(f"waypoints must be at least two (x, y) points, got {pts.shape}")
        if closed and np.allclose(pts[0], pts[-1]):
            pts = pts[:-1]  # the loop's closing point is implied
        self.points = pts
        self.closed = bool(closed)
        ends = np.vstack([pts[1:], pts[:1]]) if closed else pts[1:]
        self._a, self._d = pts[: len(ends)], ends - pts[: len(ends)]
        seg = np.hypot(self._d[:, 0], self._d[:, 1])
        self._s0 = np.r_[0.0, np.cumsum(seg)[:-1]]
        self._len = seg
        self.length = float(seg.sum())
        if not self.length > 0:
            raise ValueError("waypoints must not all be one point: the route has no length")

    @classmethod
    def through(cls, arena: Any, points: Sequence[Sequence[float]], *, radius: float = 3.7,
                clearance: float = 3.0, keep_off: float = 35.0, detour: float = 4.0) -> Route:
        """The closed route through ``points`` in order: the arena's shortest path (for a disc
        of ``radius`` cm, keeping ``clearance`` cm more from walls where it can, with the graded
        penalty of :meth:`hippo.sim.arena.Arena.shortest_path`: a corridor narrower than that
        is run along its middle, not priced out for a detour) from each point to the next and
        from the last back to the first. A leg takes another way than the legs
        before it where one exists (the shortest path on which cells within 10 cm of them cost
        3 times as much, if at most half of it runs within 15 cm of them): around a ring the
        route is a loop, not out along one side and back along it. Where two points are joined
        by one corridor only, the route runs along it both ways; so may a leg back along a
        corridor wide enough to run more than 10 cm beside the leg before (a 30-cm ring with
        two points: :attr:`winding` 0, and :func:`~hippo.tasks.patrol_sets.choose_route`
        takes a wall tour instead).

        A leg also keeps ``keep_off`` cm from the other points where a way round them is at
        most ``detour`` times as long as its shortest path: a robot led from one checkpoint to
        the next does not pass a third on the way, which it would be taught to pass without
        its stop, and whose passes along the route would then be counted on another stretch
        than the one it is passed on (patrol-course, checkpoints drawn by
        :func:`hippo.tasks.random_patrol`: three of them all in its north-east corner made a
        route out and back along one corridor; with this, a loop round the ring)."""
        arr = check_finite("points", points)
        if arr.ndim != 2 or arr.shape[1] != 2 or len(arr) < 2:
            n = len(arr) if arr.ndim == 2 and arr.shape[1] == 2 else arr.shape
            raise ValueError(f"a route needs at least two points (x, y), got {n}")
        if np.all(arr == arr[0]):
            raise ValueError(f"points must not all be one point: got {len(arr)} copies of "
                             f"({arr[0, 0]:g}, {arr[0, 1]:g})")
        check_positive("radius", radius)
        check_positive("clearance", clearance, allow_zero=True)
        check_positive("keep_off", keep_off, allow_zero=True)
        check_positive("detour", detour)
        pts = [(float(x), float(y)) for x, y in arr]
        wps: list[tuple[float, float]] = []
        for a, b in pairwise([*pts, pts[0]]):
            length, path = arena.shortest_path(a, b, radius, clearance=clearance, graded=True)
            if not path:
                raise ValueError(f"no path from {a} to {b} in arena {arena.name!r}")
            others = [p for p in pts if math.dist(p, a) > keep_off and math.dist(p, b) > keep_off]
            off: dict[str, Any] = {}
            if others:
                around, way = arena.shortest_path(a, b, radius, clearance=clearance, graded=True,
                                                  block=others, block_radius=keep_off)
                if way and around <= detour * length:
                    path, off = way, {"block": others, "block_radius": keep_off}
            if wps:
                _, other = arena.shortest_path(a, b, radius, clearance=clearance, avoid=wps,
                                                graded=True, **off)
                old = np.asarray(wps)
                shared = [np.hypot(*(old - q).T).min() < 15.0 for q in other[1:-1]]
                if other and np.mean(shared or [1.0]) <= 0.5:
                    path = other
            wps.extend([a, *path[1:-1]])
        return cls(wps, closed=True)

    @property
    def waypoints(self) -> list[tuple[float, float]]:
        return [(float(x), float(y)) for x, y in self.points]

    def progress(self, x: float, y: float) -> float:
        """Distance (cm) along the route, from its first waypoint, of the point of the route
        nearest to ``(x, y)``."""
        p = np.array([check_real("x", x), check_real("y", y)]) - self._a
        L2 = np.maximum(self._len**2, 1e-12)
        u = np.clip(np.sum(p * self._d, axis=1) / L2, 0.0, 1.0)
        gap = np.hypot(p[:, 0] - u * self._d[:, 0], p[:, 1] - u * self._d[:, 1])
        k = int(np.argmin(gap))
        return float(self._s0[k] + u[k] * self._len[k])

    def distance(self, x: float, y: float) -> float:
        """Distance (cm) from ``(x, y)`` to the nearest point of the route."""
        px, py, _ = self.at(self.progress(x, y))
        return math.hypot(px - x, py - y)

    def progress_near(self, x: float, y: float, near: float, window: float = 30.0) -> float:
        """Like :meth:`progress`, but only the part of the route within ``window`` cm (along
        it, either way) of progress ``near`` is searched: where a route runs along a corridor
        twice (out and back), the robot stays on the stretch it is on: of the points of that
        part, the one nearest to ``(x, y)`` wins, with 0.2 cm of distance added per cm of
        progress away from ``near`` (where two stretches meet, the one it is on). If no point
        of that part lies within ``window`` cm of ``(x, y)`` (the robot was carried, or not tracked
        for a while), the whole route is searched."""
        x, y, near = check_real("x", x), check_real("y", y), check_real("near", near)
        window = check_positive("window", window)
        dense = self._dense()
        gap = (dense[:, 0] - near + self.length / 2) % self.length - self.length / 2 \
            if self.closed else dense[:, 0] - near
        cand = dense[np.abs(gap) <= window]
        if cand.size == 0:
            return self.progress(x, y)
        d = np.hypot(cand[:, 1] - x, cand[:, 2] - y)
        if d.min() > window:
            return self.progress(x, y)
        # where two stretches meet (a turn-around), the one nearer in progress wins ties
        k = int(np.argmin(d + 0.2 * np.abs(gap[np.abs(gap) <= window])))
        return float(cand[k, 0])

    def _dense(self) -> np.ndarray:
        """(progress, x, y) every 0.5 cm along the route (computed once)."""
        if getattr(self, "_dense_pts", None) is None:
            s = np.arange(0.0, self.length, 0.5)
            self._dense_pts = np.column_stack([s, self._points_at(s)])
        return self._dense_pts

    def _segments_at(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(s, k)``: progress ``s`` wrapped round a closed route (clipped to an open one's
        ends) and the segment ``k`` it lies on."""
        s = np.mod(s, self.length) if self.closed else np.clip(s, 0.0, self.length)
        return s, np.clip(np.searchsorted(self._s0, s, side="right") - 1, 0, len(self._s0) - 1)

    def _points_at(self, s: np.ndarray) -> np.ndarray:
        s, k = self._segments_at(s)
        u = (s - self._s0[k]) / np.maximum(self._len[k], 1e-12)
        return self._a[k] + u[:, None] * self._d[k]

    def at(self, s: float) -> tuple[float, float, float]:
        """``(x, y, heading)``: the point ``s`` cm along the route (modulo its length if
        closed) and the direction of travel there (radians)."""
        s = check_real("s", s)
        x, y = self._points_at(np.array([s]))[0]
        k = int(self._segments_at(np.array([s]))[1][0])
        return float(x), float(y), math.atan2(float(self._d[k, 1]), float(self._d[k, 0]))

    def sample(self, spacing: float) -> list[tuple[float, float]]:
        """Points every ``spacing`` cm along the route from its first waypoint (e.g. the
        labelled locations of an arena built around it)."""
        spacing = check_positive("spacing", spacing)
        if self.length / spacing > MAX_SAMPLES:
            raise ValueError(f"spacing {spacing:g} cm gives {self.length / spacing:.3g} points "
                             f"along this {self.length:.0f}-cm route; at most {MAX_SAMPLES:,} "
                             f"(a spacing of at least {self.length / MAX_SAMPLES:.2g} cm)")
        out = []
        for s in np.arange(0.0, self.length - 1e-9, spacing):
            k = int(np.searchsorted(self._s0, s, side="right") - 1)
            u = (s - self._s0[k]) / max(self._len[k], 1e-12)
            out.append((float(self._a[k, 0] + u * self._d[k, 0]),
                        float(self._a[k, 1] + u * self._d[k, 1])))
        return out

    def nearest(self, x: float, y: float) -> int:
        """Index of the waypoint nearest to ``(x, y)``."""
        x, y = check_real("x", x), check_real("y", y)
        return int(np.argmin(np.hypot(self.points[:, 0] - x, self.points[:, 1] - y)))

    def leg(self, start: Sequence[float], goal: Sequence[float]) -> list[tuple[float, float]]:
        """Waypoints from ``start`` to ``goal`` along the route's direction (the waypoint after
        the one nearest ``start``, up to the one nearest ``goal``), then ``goal`` itself."""
        wp = self.waypoints
        (x0, y0), (x1, y1) = (point_xy(name, p) for name, p in (("start", start), ("goal", goal)))
        i, j = self.nearest(x0, y0), self.nearest(x1, y1)
        n = len(wp)
        return [wp[(i + k) % n] for k in range(1, (j - i) % n + 1)] + [(x1, y1)]

    @property
    def signed_area(self) -> float:
        """The area (cm²) the closed route encloses, counted positive where it runs
        counter-clockwise (the shoelace formula; an out-and-back stretch adds nothing)."""
        x, y = self.points[:, 0], self.points[:, 1]
        return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))

    @property
    def winding(self) -> int:
        """+1 if the route runs counter-clockwise round what it encloses, -1 clockwise, 0 if it
        encloses little: less than a quarter of the square with its length as perimeter (a
        shuttle along a corridor, out and back, encloses a few %; a loop round the ring of
        patrol-course about 100 %, an equilateral triangle 77 %)."""
        a = self.signed_area
        if abs(a) < 0.25 * (self.length / 4.0) ** 2:
            return 0
        return 1 if a > 0 else -1

    @property
    def doubled_length(self) -> float:
        """cm of the route that run back over another part of it the other way (within 12 cm,
        headings more than 120° apart, at least 60 cm away along the route): a loop that goes
        out along a corridor and back again before going on. Progress along such a stretch is
        ambiguous (the nearest point of the route may be either way), so a checkpoint on it can
        go unseen by a pass count (patrol-course, checkpoints out of the loop's order)."""
        if self.length <= 0:
            return 0.0
        step = 3.0
        s = np.arange(0.0, self.length, step)
        p = self._points_at(s)
        k = self._segments_at(s)[1]
        u = self._d[k] / np.maximum(self._len[k], 1e-12)[:, None]
        # the pairs of points within 12 cm (a KD-tree: memory linear in the route's length,
        # not its square; a hair wider, then the exact test)
        i, j = cKDTree(p).query_pairs(12.0 + 1e-6, output_type="ndarray").T
        near = np.hypot(p[i, 0] - p[j, 0], p[i, 1] - p[j, 1]) < 12.0
        ds = np.abs(s[i] - s[j])
        if self.closed:
            ds = np.minimum(ds, self.length - ds)
        back = u[i, 0] * u[j, 0] + u[i, 1] * u[j, 1] < -0.5
        hit = near & back & (ds > 60.0)
        doubled = np.zeros(len(s), dtype=bool)
        doubled[i[hit]] = doubled[j[hit]] = True
        return float(step * np.count_nonzero(doubled))

    def loop_from(self, pose: Sequence[float]) -> list[tuple[float, float]]:
        """One whole loop from the waypoint nearest ``pose`` (or the next one, if that one is
        behind the robot's heading) back to it."""
        wp = self.waypoints
        if len(pose) != 3:
            raise ValueError(f"pose must be (x, y, heading), got {pose!r}")
        x, y, h = pose
        h = check_real("heading", h)
        i0 = self.nearest(x, y)
        if math.cos(math.atan2(wp[i0][1] - y, wp[i0][0] - x) - h) < 0:
            i0 = (i0 + 1) % len(wp)  # the nearest waypoint is behind: lead on, not back
        return wp[i0:] + wp[:i0] + [wp[i0]]


def point_xy(name: str, point: Sequence[float]) -> tuple[float, float]:
    """The first two items of ``point`` as finite floats, named in the error."""
    if np.ndim(point) != 1 or len(point) < 2:
        raise ValueError(f"{name} must be a point (x, y), got {point!r}")
    return check_real(f"{name} x", point[0]), check_real(f"{name} y", point[1])


def checkpoints_xy(checkpoints: Sequence[Sequence[float]]) -> np.ndarray:
    """``checkpoints`` as a finite ``(n, 2)`` float array, ``n >= 1``, or a ``ValueError``."""
    cps = check_finite("checkpoints", checkpoints)
    if cps.ndim != 2 or cps.shape[1] != 2 or len(cps) == 0:
        raise ValueError(f"checkpoints must be one or more points (x, y), got shape {cps.shape}")
    return cps


def lead_from(arena: Any, start: Sequence[float], waypoints: Sequence[Sequence[float]],
              radius: float = 3.7) -> list[tuple[float, float]]:
    """``waypoints`` for a leash starting at ``start``: unchanged when a disc of ``radius`` can
    go straight from ``start`` to the first of them, else with the arena's shortest path to
    it in front. The waypoint of a route nearest the robot can lie behind a wall; a leash
    pulled straight at it holds the robot against that wall (the maze, tuning seed 0: for the
    whole lesson)."""
    x, y = point_xy("start", start)
    if not (0.0 <= x <= arena.width and 0.0 <= y <= arena.height):
        raise ValueError(f"start ({x:g}, {y:g}) lies outside arena {arena.name!r}")
    arr = check_finite("waypoints", waypoints)
    if arr.size and (arr.ndim != 2 or arr.shape[1] != 2):
        raise ValueError(f"waypoints must be an (N, 2) array of (x, y) in cm, got shape "
                         f"{arr.shape}")
    wp = [(float(a), float(b)) for a, b in arr.reshape(-1, 2)]
    if not wp:
        return wp
    x0, y0 = wp[0]
    u = np.linspace(0.0, 1.0, int(math.dist((x, y), (x0, y0)) / 2.0) + 2)
    if all(arena.is_free(x + (x0 - x) * k, y + (y0 - y) * k, radius) for k in u):
        return wp
    _, path = arena.shortest_path((float(x), float(y)), (x0, y0), radius=radius)
    return [(float(px), float(py)) for px, py in path[:-1]] + wp


class LapCounter:
    """Laps along a closed :class:`Route`, from the change of route progress between updates
    (a change of more than half the loop counts the short way round).

    After the first update, progress is searched within ``window`` cm of the last one
    (:meth:`Route.progress_near`), so a route that runs along a corridor both ways is followed
    stretch by stretch; :meth:`reset` after the robot was carried elsewhere. ``travelled`` is
    the unwrapped progress in cm (``turns`` × the route's length, from the first update's
    progress); ``progress`` the progress of the last update."""

    def __init__(self, route: Route, window: float = 30.0) -> None:
        if not route.closed:
            raise ValueError("laps need a closed route")
        if not window > 0:
            raise ValueError(f"window must be > 0 cm, got {window!r}")
        self.route, self.window = route, float(window)
        self._s: float | None = None
        self.turns = 0.0
        self.start: float | None = None
        self._behind: set[tuple[float, float]] = set()   # points the robot came up behind

    @property
    def progress(self) -> float | None:
        return self._s

    @property
    def travelled(self) -> float:
        return self.turns * self.route.length

    def reset(self) -> None:
        """Forget where the robot was (the next update searches the whole route)."""
        self._s = None

    def update(self, x: float, y: float) -> float:
        if self._s is None:
            s = self.route.progress(x, y)
            if self.start is None:
                self.start = s
        else:
            s = self.route.progress_near(x, y, self._s, self.window)
            L = self.route.length
            self.turns += ((s - self._s + L / 2) % L - L / 2) / L
        self._s = s
        return self.turns

    def reached(self, x: float, y: float, point: Sequence[float], radius: float = 20.0, *,
                from_behind: bool = False) -> bool:
        """Update with ``(x, y)``; is the robot at ``point`` (a checkpoint): within ``radius`` cm
        of it, and its progress along the route at or past the point's? A teacher who holds the
        robot *at* a checkpoint uses it: one who holds it as soon as it comes within some
        radius teaches a stop that far before the checkpoint, and every run-up from there.

        With ``from_behind`` it must also have come there going the route's way: since it was
        last more than ``radius`` past the point along the route (or since :meth:`forget`), an
        update found it behind the point. A robot that drives the wrong way round comes to the
        point from beyond it, "past" it all the way."""
        check_positive("radius", radius)
        self.update(x, y)
        L = self.route.length
        behind = (self.route.progress(*point) - self._s + L / 2) % L - L / 2  # type: ignore[operator]
        key = (float(point[0]), float(point[1]))
        if behind > 0.0:
            self._behind.add(key)
        elif behind < -radius:
            self._behind.discard(key)
        if math.dist((x, y), point) >= radius:
            return False
        return behind <= 0.0 and (key in self._behind or not from_behind)

    def forget(self, point: Sequence[float]) -> None:
        """Forget that the robot was behind ``point`` (:meth:`reached` with ``from_behind``):
        from here it has to come to it anew."""
        self._behind.discard((float(point[0]), float(point[1])))
