"""Arenas: wall segments, coloured floor zones, named regions and labelled reference locations.

An :class:`Arena` is plain geometry (centimetres); :class:`~hippo.sim.world.World` turns it into a
pymunk space. Reference locations and regions are for analysis only and never reach the robot.
Build a new arena with :class:`~hippo.sim.builder.ArenaBuilder`::

    arena = (ArenaBuilder("box", 100, 60)
             .outer_walls()
             .wall((50, 0), (50, 40))
             .zone("goal", (80, 40, 95, 55), colour=1)
             .region("left", (0, 0, 50, 60)).region("right", (50, 0, 100, 60))
             .grid_locations(5, 3)
             .build())
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from itertools import pairwise

import numpy as np
from scipy import ndimage

Point = tuple[float, float]
Rect = tuple[float, float, float, float]  # xmin, ymin, xmax, ymax


@dataclass(frozen=True)
class Zone:
    """A rectangle of coloured floor; ``colour`` is the id the floor sensor reads (0 = plain)."""

    name: str
    rect: Rect
    colour: int

    def contains(self, x: float, y: float) -> bool:
        x0, y0, x1, y1 = self.rect
        return x0 <= x <= x1 and y0 <= y <= y1


@dataclass(frozen=True)
class Region:
    """A named part of the arena (a room, a corridor) made of one or more rectangles."""

    name: str
    rects: tuple[Rect, ...]

    def contains(self, x: float, y: float) -> bool:
        return any(r[0] <= x <= r[2] and r[1] <= y <= r[3] for r in self.rects)


@dataclass(frozen=True)
class Arena:
    """Static geometry of a world. Coordinates in cm; headings in radians (0 = +x, CCW)."""

    name: str
    width: float
    height: float
    walls: tuple[tuple[Point, Point], ...]
    zones: tuple[Zone, ...] = ()
    regions: tuple[Region, ...] = ()
    locations: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    start_pose: tuple[float, float, float] = (10.0, 10.0, 0.0)
    wall_radius: float = 0.5
    #: named points a scenario may use (goal centre, checkpoints, start places)
    landmarks: dict[str, Point] = field(default_factory=dict)

    # -- analysis helpers ------------------------------------------------------------------
    @property
    def region_names(self) -> list[str]:
        return [r.name for r in self.regions]

    @property
    def zone_names(self) -> list[str]:
        """Names by colour id: index 0 is plain floor."""
        names = ["floor"] + [""] * max((z.colour for z in self.zones), default=0)
        for z in self.zones:
            names[z.colour] = z.name
        return names

    def region_of(self, x: float, y: float) -> str:
        """Name of the first region containing ``(x, y)``, or ``"none"``."""
        for r in self.regions:
            if r.contains(x, y):
                return r.name
        return "none"

    def region_index(self, x: float, y: float) -> int:
        """Index into :attr:`region_names`, or -1 outside every region."""
        for i, r in enumerate(self.regions):
            if r.contains(x, y):
                return i
        return -1

    def zone_of(self, x: float, y: float) -> int:
        """Floor colour under ``(x, y)``: the colour id of the first zone containing it, else 0."""
        for z in self.zones:
            if z.contains(x, y):
                return z.colour
        return 0

    def nearest_location(self, x: float | np.ndarray, y: float | np.ndarray) -> np.ndarray:
        """Index of the nearest labelled reference location for each point."""
        if len(self.locations) == 0:
            return np.full(np.shape(x), -1, dtype=int)
        p = np.stack([np.asarray(x, float), np.asarray(y, float)], axis=-1)
        d = np.linalg.norm(p[..., None, :] - self.locations, axis=-1)
        return np.argmin(d, axis=-1)

    def wall_array(self) -> np.ndarray:
        """Walls as an ``(n, 4)`` array ``x0, y0, x1, y1`` (``(0, 4)`` without walls)."""
        return np.array([[a[0], a[1], b[0], b[1]] for a, b in self.walls],
                        dtype=float).reshape(-1, 4)

    def distance_to_walls(self, x: float, y: float) -> float:
        """Euclidean distance from a point to the nearest wall segment's centre line (inf in
        an arena without walls)."""
        w = self.wall_array()
        if not len(w):
            return math.inf
        a, b = w[:, :2], w[:, 2:]
        p = np.array([x, y], float)
        ab = b - a
        t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab),
                                                                   1e-12), 0, 1)
        closest = a + t[:, None] * ab
        return float(np.min(np.linalg.norm(p - closest, axis=1)))

    def is_free(self, x: float, y: float, radius: float) -> bool:
        """True if a disc of ``radius`` at ``(x, y)`` lies inside the arena and clear of walls."""
        if not (radius <= x <= self.width - radius and radius <= y <= self.height - radius):
            return False
        return self.distance_to_walls(x, y) >= radius + self.wall_radius

    # -- free-space grid and geodesic distances ----------------------------------------------
    def free_grid(self, radius: float, cell: float = 2.0) -> tuple[np.ndarray, np.ndarray,
                                                                   np.ndarray]:
        """Boolean occupancy grid of centres where a disc of ``radius`` fits (xs, ys, free)."""
        xs = np.arange(cell / 2, self.width, cell)
        ys = np.arange(cell / 2, self.height, cell)
        gx, gy = np.meshgrid(xs, ys, indexing="ij")
        pts = np.stack([gx.ravel(), gy.ravel()], 1)
        w = self.wall_array()
        a, b = w[:, :2], w[:, 2:]
        ab = b - a
        den = np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-12)
        dmin = np.full(len(pts), np.inf)
        for k in range(len(w)):
            t = np.clip(((pts - a[k]) @ ab[k]) / den[k], 0, 1)
            d = np.linalg.norm(pts - (a[k] + t[:, None] * ab[k]), axis=1)
            dmin = np.minimum(dmin, d)
        inside = ((pts[:, 0] >= radius) & (pts[:, 0] <= self.width - radius)
                  & (pts[:, 1] >= radius) & (pts[:, 1] <= self.height - radius))
        free = (dmin >= radius + self.wall_radius) & inside
        return xs, ys, free.reshape(gx.shape)

    def shortest_path(self, start: Point, goal: Rect | Point, radius: float = 3.7,
                      cell: float = 2.0, clearance: float = 3.0, *, thin: bool = True,
                      avoid: Sequence[Point] = (), avoid_radius: float = 10.0,
                      graded: bool = False, block: Sequence[Point] = (),
                      block_radius: float = 25.0) -> tuple[float, list[Point]]:
        """Shortest collision-free path from ``start`` to a point or rectangle.

        Dijkstra on an 8-connected grid of cells where a disc of ``radius + clearance`` fits
        (cells where only ``radius`` fits are allowed at a cost penalty, so paths keep off walls
        when they can; so are cells within ``avoid_radius`` cm of a point of ``avoid``, e.g. a
        path already taken, so that a loop does not run back along it where another way
        exists). Returns (length in cm of the grid path, waypoints: every third grid cell, or
        every cell with ``thin=False``); (inf, []) if unreachable.

        ``graded``: the penalty grows with the clearance a cell lacks, ``1 + 2 (1 - e / c)``
        for a cell ``e`` cm farther from the walls than ``radius`` (``c`` = ``clearance``),
        instead of 3 wherever ``e < c``. The middle of a corridor narrower than
        ``2 (radius + clearance)`` then costs little more than open floor, so a narrow
        corridor is not priced out for a long detour (on ``patrol-course``'s 22 cm south
        corridor: 1.2 instead of 3), while hugging a wall still costs 3.

        ``block``: points the path must keep ``block_radius`` cm from (each on its own, not
        joined): cells nearer to one are not free.
        """
        xs, ys, free = self.free_grid(radius, cell)
        if len(block):
            bl = np.asarray(block, float).reshape(-1, 2)
            gap2 = (xs[:, None, None] - bl[None, None, :, 0]) ** 2 \
                + (ys[None, :, None] - bl[None, None, :, 1]) ** 2
            free = free & (gap2.min(axis=2) >= block_radius**2)
        _, _, roomy = self.free_grid(radius + clearance, cell)
        nx, ny = free.shape
        if graded and clearance > 0:
            extra = ndimage.distance_transform_edt(free) * cell - cell / 2
            penalty = 1.0 + 2.0 * np.clip(1.0 - extra / clearance, 0.0, 1.0)
            penalty[roomy] = 1.0
        else:
            penalty = np.where(roomy, 1.0, 3.0)
        if len(avoid):
            # the cells within avoid_radius of the path to avoid (its points joined by lines)
            av = np.asarray(avoid, float).reshape(-1, 2)
            seg = np.linspace(av[:-1], av[1:], 8, axis=0).reshape(-1, 2) if len(av) > 1 else av
            on = np.ones(free.shape, bool)
            on[np.clip(np.round((seg[:, 0] - xs[0]) / cell).astype(int), 0, nx - 1),
               np.clip(np.round((seg[:, 1] - ys[0]) / cell).astype(int), 0, ny - 1)] = False
            near = ndimage.distance_transform_edt(on) * cell < avoid_radius
            penalty = penalty * np.where(near, 3.0, 1.0)

        def idx(p: Point) -> tuple[int, int]:
            return int(np.argmin(np.abs(xs - p[0]))), int(np.argmin(np.abs(ys - p[1])))

        if len(goal) == 2:
            goal_mask = np.zeros_like(free)
            goal_mask[idx(goal)] = True  # type: ignore[arg-type]
        else:
            x0, y0, x1, y1 = goal  # type: ignore[misc]
            goal_mask = ((xs[:, None] >= x0) & (xs[:, None] <= x1)
                         & (ys[None, :] >= y0) & (ys[None, :] <= y1)) & free
        si = idx(start)
        dist = np.full(free.shape, np.inf)
        length = np.full(free.shape, np.inf)
        prev: dict[tuple[int, int], tuple[int, int]] = {}
        dist[si] = length[si] = 0.0
        heap = [(0.0, si)]
        steps = [(dx, dy, cell * float(np.hypot(dx, dy))) for dx in (-1, 0, 1)
                 for dy in (-1, 0, 1) if dx or dy]
        end = None
        while heap:
            d, (i, j) = heapq.heappop(heap)
            if d > dist[i, j]:
                continue
            if goal_mask[i, j]:
                end = (i, j)
                break
            for dx, dy, c in steps:
                a, b = i + dx, j + dy
                if 0 <= a < nx and 0 <= b < ny and free[a, b]:
                    cost = c * penalty[a, b]
                    if d + cost < dist[a, b]:
                        dist[a, b] = d + cost
                        length[a, b] = length[i, j] + c
                        prev[(a, b)] = (i, j)
                        heapq.heappush(heap, (d + cost, (a, b)))
        if end is None:
            return float("inf"), []
        path = [end]
        while path[-1] != si:
            path.append(prev[path[-1]])
        pts = [(float(xs[i]), float(ys[j])) for i, j in reversed(path)]
        if not thin:
            return float(length[end]), pts
        return float(length[end]), pts[::3] + ([pts[-1]] if (len(pts) - 1) % 3 else [])

    def geodesic_distance(self, start: Point, goal_rect: Rect | Point, radius: float = 3.7,
                          cell: float = 2.0) -> float:
        """Length (cm) of the shortest path that a disc of ``radius`` can travel from ``start``
        to a point or into a rectangle (``inf`` if unreachable).

        The grid path of :meth:`shortest_path` is pulled taut: from each vertex the path goes
        straight to the farthest later vertex the disc can reach in a straight line (the
        segment keeps ``radius`` + the walls' half-thickness from every wall), it starts at
        ``start`` itself and ends where it first enters the rectangle. A grid path alone is
        up to 8 % longer than the straight line (its moves are multiples of 45°), which made a
        robot's real path look shorter than "the shortest".
        """
        _, pts = self.shortest_path(start, goal_rect, radius, cell, clearance=0.0, thin=False)
        if not pts:
            return float("inf")
        pts[0] = (float(start[0]), float(start[1]))
        if len(goal_rect) == 2:
            pts[-1] = (float(goal_rect[0]), float(goal_rect[1]))  # type: ignore[misc]
        reach = radius + self.wall_radius
        walls = self.wall_array()
        taut = [pts[0]]
        i = 0
        while i < len(pts) - 1:
            j = len(pts) - 1
            while j > i + 1 and not _segment_clear(pts[i], pts[j], walls, reach):
                j -= 1
            taut.append(pts[j])
            i = j
        if len(goal_rect) == 4:
            # into a rectangle: from the first vertex that sees it, straight to its nearest point
            x0, y0, x1, y1 = goal_rect  # type: ignore[misc]
            for k, (px, py) in enumerate(taut):
                near = (min(max(px, x0), x1), min(max(py, y0), y1))
                if _segment_clear((px, py), near, walls, reach):
                    taut = [*taut[:k + 1], near]
                    break
        return float(sum(np.hypot(q[0] - p[0], q[1] - p[1]) for p, q in pairwise(taut)))

    def sample_free_pose(self, rng: np.random.Generator, radius: float = 3.7,
                         margin: float = 2.0, rect: Rect | None = None) -> tuple[float, float,
                                                                                 float]:
        """A uniformly random collision-free pose (optionally inside ``rect``)."""
        x0, y0, x1, y1 = rect if rect is not None else (0.0, 0.0, self.width, self.height)
        for _ in range(10_000):
            x, y = rng.uniform(x0, x1), rng.uniform(y0, y1)
            if self.is_free(x, y, radius + margin):
                return float(x), float(y), float(rng.uniform(-np.pi, np.pi))
        raise RuntimeError(f"no free pose found in {self.name} inside {rect}")


def _segment_clear(p: Point, q: Point, walls: np.ndarray, reach: float) -> bool:
    """True if every point of the segment ``p``-``q`` is at least ``reach`` from every wall
    (walls as an (n, 4) array): the minimum distance between two segments is reached at an
    end point of one of them unless they cross."""
    a, b = walls[:, :2], walls[:, 2:]
    P, Q = np.asarray(p, float), np.asarray(q, float)

    def point_to_walls(x: np.ndarray) -> np.ndarray:
        ab = b - a
        t = np.clip(np.einsum("ij,ij->i", x - a, ab)
                    / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-12), 0.0, 1.0)
        return np.linalg.norm(x - (a + t[:, None] * ab), axis=1)

    def point_to_segment(x: np.ndarray) -> np.ndarray:  # wall end points x (n, 2) to p-q
        d = Q - P
        t = np.clip((x - P) @ d / max(float(d @ d), 1e-12), 0.0, 1.0)
        return np.linalg.norm(x - (P + t[:, None] * d), axis=1)

    def cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
        return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]

    d = Q - P
    s1 = cross(d, a - P) * cross(d, b - P)
    s2 = cross(b - a, P - a) * cross(b - a, Q - a)
    if np.any((s1 < 0) & (s2 < 0)):  # the segment crosses a wall
        return False
    dist = np.minimum.reduce([point_to_walls(P), point_to_walls(Q), point_to_segment(a),
                              point_to_segment(b)])
    return bool(np.all(dist >= reach - 1e-9))
