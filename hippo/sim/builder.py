"""Building an arena: :class:`ArenaBuilder`, a fluent builder of :class:`~hippo.sim.arena.Arena`.

Walls (segments, polylines, boxes, the outer walls), coloured floor zones, named regions,
reference locations, landmarks and the start pose are added one call at a time;
:meth:`ArenaBuilder.build` freezes them into an :class:`~hippo.sim.arena.Arena` and checks
that the start pose is free. The arenas of the experiments are in :mod:`hippo.sim.arenas`.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Sequence

import numpy as np

from hippo._checks import check_finite, check_int, check_real
from hippo.sim.arena import Arena, Point, Rect, Region, Zone
from hippo.sim.robot import RobotParams

#: the default robot's radius (the e-puck's), which a built arena's start must clear; a World
#: checks the start again for its own robot
START_CLEARANCE = RobotParams().radius

__all__ = ["ArenaBuilder"]

#: the largest floor colour id (recordings keep the floor colour as int16; ``Arena.zone_names``
#: lists every id up to the largest)
MAX_COLOUR = 255


def _name(what: str, name: object) -> str:
    """A name: a non-empty ``str`` (an int or None would end up in labels and GraphML)."""
    if not isinstance(name, str) or not name:
        raise ValueError(f"{what} name must be a non-empty string, got {name!r}")
    return name


class ArenaBuilder:
    """Fluent builder for :class:`Arena` (every method returns the builder)."""

    def __init__(self, name: str, width: float, height: float) -> None:
        _name("arena", name)
        if not (math.isfinite(width) and math.isfinite(height) and width > 0 and height > 0):
            raise ValueError(f"arena size must be positive and finite, got {width} x {height}")
        self.name, self.width, self.height = name, float(width), float(height)
        self._walls: list[tuple[Point, Point]] = []
        self._zones: list[Zone] = []
        self._regions: list[Region] = []
        self._locations: list[Point] = []
        self._landmarks: dict[str, Point] = {}
        self._start: tuple[float, float, float] | None = None
        self._boxes: list[tuple[float, float, float, float]] = []

    def wall(self, a: Sequence[float], b: Sequence[float]) -> ArenaBuilder:
        """A straight wall segment from ``a`` to ``b``, inside the arena (edges included)."""
        pa = tuple(float(v) for v in check_finite("wall start", a))
        pb = tuple(float(v) for v in check_finite("wall end", b))
        if len(pa) != 2 or len(pb) != 2:
            raise ValueError("wall end points must be (x, y) pairs")
        self._point("wall start", *pa)
        self._point("wall end", *pb)
        if pa == pb:
            raise ValueError(f"wall from {pa} to {pb} has zero length")
        self._walls.append((pa, pb))  # type: ignore[arg-type]
        return self

    def polyline(self, points: Sequence[Sequence[float]], closed: bool = False) -> ArenaBuilder:
        """Walls joining consecutive points (and the last to the first if ``closed``)."""
        pts = [tuple(p) for p in points]
        for a, b in zip(pts, pts[1:] + (pts[:1] if closed else [])):
            self.wall(a, b)
        return self

    def box(self, rect: Rect) -> ArenaBuilder:
        """A closed rectangular block (pillar) ``(xmin, ymin, xmax, ymax)``."""
        x0, y0, x1, y1 = rect
        self.polyline([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], closed=True)
        self._boxes.append((float(x0), float(y0), float(x1), float(y1)))
        return self

    def outer_walls(self) -> ArenaBuilder:
        """The four walls of the bounding rectangle."""
        return self.box((0.0, 0.0, self.width, self.height))

    def _rect(self, what: str, rect: Rect) -> tuple[float, float, float, float]:
        """``(x0, y0, x1, y1)`` checked: finite, x0 < x1, y0 < y1, inside the arena."""
        r = tuple(float(v) for v in check_finite(what, rect))
        if len(r) != 4:
            raise ValueError(f"{what} must be (x0, y0, x1, y1), got {rect!r}")
        x0, y0, x1, y1 = r
        if not (x0 < x1 and y0 < y1):
            raise ValueError(f"{what} {r} must have x0 < x1 and y0 < y1")
        if x0 < 0 or y0 < 0 or x1 > self.width or y1 > self.height:
            raise ValueError(f"{what} {r} lies outside the {self.width:g} x {self.height:g} "
                             "arena")
        return r

    def _point(self, what: str, x: float, y: float) -> tuple[float, float]:
        p = tuple(float(v) for v in check_finite(what, (x, y)))
        if not (0 <= p[0] <= self.width and 0 <= p[1] <= self.height):
            raise ValueError(f"{what} {p} lies outside the {self.width:g} x {self.height:g} "
                             "arena")
        return p  # type: ignore[return-value]

    def zone(self, name: str, rect: Rect, colour: int = 1) -> ArenaBuilder:
        """A coloured floor rectangle; ``colour`` (an integer in [1, :data:`MAX_COLOUR`]; 0 is the
        plain floor) is what the floor sensor reports. Zone names are distinct."""
        self._unique("zone", name, [z.name for z in self._zones])
        colour = check_int(f"zone {name!r} colour", colour, lo=1, hi=MAX_COLOUR)
        self._zones.append(Zone(name, self._rect(f"zone {name!r}", rect), colour))
        return self

    def region(self, name: str, *rects: Rect) -> ArenaBuilder:
        """A named region made of one or more rectangles (for analysis only); region names are
        distinct."""
        self._unique("region", name, [r.name for r in self._regions])
        if not rects:
            raise ValueError(f"region {name!r} needs at least one rectangle")
        self._regions.append(Region(name, tuple(self._rect(f"region {name!r}", r)
                                                for r in rects)))
        return self

    def location(self, x: float, y: float) -> ArenaBuilder:
        """One labelled reference location (for analysis only)."""
        self._locations.append(self._point("location", x, y))
        return self

    def grid_locations(self, nx: int, ny: int, rect: Rect | None = None) -> ArenaBuilder:
        """An ``nx`` × ``ny`` grid of reference locations over ``rect`` (cell centres)."""
        try:   # (inf overflowed int(), NaN failed inside it, True was taken as 1)
            whole = all(check_real("n", v) == int(v) >= 1 for v in (nx, ny))
        except ValueError:
            whole = False
        if not whole:
            raise ValueError(f"a grid of locations needs nx, ny >= 1, got {nx} x {ny}")
        nx, ny = int(nx), int(ny)
        x0, y0, x1, y1 = (self._rect("grid rectangle", rect) if rect is not None
                          else (0.0, 0.0, self.width, self.height))
        for j in range(ny):
            for i in range(nx):
                self.location(x0 + (i + 0.5) * (x1 - x0) / nx, y0 + (j + 0.5) * (y1 - y0) / ny)
        return self

    def landmark(self, name: str, x: float, y: float) -> ArenaBuilder:
        """A named point a scenario can refer to (goal centre, checkpoint, start place), inside
        the arena; landmark names are distinct."""
        self._unique("landmark", name, self._landmarks)
        self._landmarks[name] = self._point(f"landmark {name!r}", x, y)
        return self

    @staticmethod
    def _unique(what: str, name: object, taken: Collection[object]) -> None:
        """``name`` a valid name not already in ``taken`` (a second one overwrote or shadowed
        the first in silence)."""
        _name(what, name)
        if name in taken:
            raise ValueError(f"{what} {name!r} is already defined; {what} names must be "
                             "distinct")

    def start(self, x: float, y: float, heading: float = 0.0) -> ArenaBuilder:
        """The robot's default start pose."""
        self._start = tuple(float(v) for v in check_finite("start pose", (x, y, heading)))
        return self

    def build(self) -> Arena:
        """Freeze into an :class:`Arena` (checks the start pose is free)."""
        if not self._walls:
            raise ValueError(f"arena {self.name!r} has no walls")
        arena = Arena(
            name=self.name, width=self.width, height=self.height, walls=tuple(self._walls),
            zones=tuple(self._zones), regions=tuple(self._regions),
            locations=np.array(self._locations, float).reshape(-1, 2),
            start_pose=self._start or (self.width / 2, self.height / 2, 0.0),
            landmarks=dict(self._landmarks),
        )
        if not arena.is_free(arena.start_pose[0], arena.start_pose[1], START_CLEARANCE):
            raise ValueError(f"start pose {arena.start_pose} of {self.name!r} is not free")
        self._check_start_outside_boxes(arena.start_pose[0], arena.start_pose[1])
        return arena

    def _check_start_outside_boxes(self, x: float, y: float) -> None:
        """A start inside a box (a pillar) with walls outside it closes the robot in the pillar:
        a ring built round a central box without :meth:`start` started at the arena's centre,
        and a patrol's checkpoints were drawn inside the pillar. A box round every wall (used
        as the outer walls) may hold the start."""
        for x0, y0, x1, y1 in self._boxes:
            r = START_CLEARANCE
            if not (x0 < x - r and x + r < x1 and y0 < y - r and y + r < y1):
                continue
            if any(not (x0 <= px <= x1 and y0 <= py <= y1) for w in self._walls for px, py in w):
                given = "" if self._start is not None else " (the default start, the centre)"
                raise ValueError(f"start ({x:g}, {y:g}){given} of {self.name!r} lies inside "
                                 f"box {(x0, y0, x1, y1)}, a pillar the robot cannot leave; "
                                 "put it on the floor with ArenaBuilder.start(x, y)")
