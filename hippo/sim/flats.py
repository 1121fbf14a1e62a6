"""Generated worlds: multi-room flats nobody drew by hand.

``random_flat(n_rooms, seed)`` lays out ``n_rooms`` rooms in a row, each joined to the next by a
corridor, built with :class:`~hippo.sim.builder.ArenaBuilder`. Everything that tells rooms apart
lies **within the e-puck's 30 cm infra-red range** (the feasibility study's rule: rooms that map
onto each other by a symmetry, or differ only in size, are nearly the same to any sensor
history):

* sizes: widths 30-75 cm (a 30 cm room shows both long walls at once), heights 60-100 cm,
  widths at least 8 cm apart (up to six rooms; closer with more);
* corners: each chamfered (8-14 cm) or square, at random;
* walls: the top and bottom walls carry 0-2 features each, a *buttress* (a 6-10 cm deep
  bump into the room) or an *alcove* (an 8-12 cm deep, 18-26 cm wide notch out of it);
* corridors: 20-35 cm long, 20-26 cm wide, at a random height of each room's side wall.

No two rooms share the same pattern of corners and wall features. Regions ``room_1`` …
``room_n`` (with their alcoves) and ``corridor_1`` … ``corridor_{n-1}`` label the flat for
analysis; labelled locations lie on a 15 cm grid of free points in every room and at each
corridor's midpoint. :func:`reachable_regions` checks on a free-space grid that the robot can
reach every region from its start; the generator redraws (deterministically) until it can.
:func:`room_signatures` measures how different the rooms look to rotation-invariant range
scans (a necessary condition for place cells to tell them apart).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from itertools import pairwise

import numpy as np
from scipy import ndimage

from hippo.sim.arena import Arena
from hippo.sim.builder import ArenaBuilder

_PAD = 15.0          # free margin around the flat (alcoves stick out of the room boxes)
_DOOR_MARGIN = 16.0  # door edges keep this far from a room's corners (chamfers fit)


@dataclass(frozen=True)
class RoomSpec:
    """One generated room: its box, chamfer size per corner (bl, br, tr, tl; 0 = square),
    and wall features ``(edge, kind, start, width, depth)`` with edge ``"bottom"``/``"top"``."""

    box: tuple[float, float, float, float]
    chamfers: tuple[float, float, float, float]
    features: tuple[tuple[str, str, float, float, float], ...]

    @property
    def pattern(self) -> tuple:
        """What tells this room apart besides its size: corners and feature kinds by edge."""
        corners = tuple(c > 0 for c in self.chamfers)
        feats = tuple(sorted((e, k) for e, k, *_ in self.features))
        return corners, feats


def _draw_room(rng: np.random.Generator, width: float, height: float) -> tuple:
    chamfers = tuple(float(rng.uniform(8, 14)) if rng.random() < 0.5 else 0.0
                     for _ in range(4))
    feats = []
    for edge, (cl, cr) in (("bottom", (chamfers[0], chamfers[1])),
                           ("top", (chamfers[3], chamfers[2]))):
        lo, hi = cl + 4.0, width - cr - 4.0   # usable span along the edge (room coordinates)
        n = int(rng.integers(0, 3))
        spans: list[tuple[float, float]] = []
        for _ in range(n):
            kind = "alcove" if rng.random() < 0.5 else "buttress"
            fw = float(rng.uniform(18, 26) if kind == "alcove" else rng.uniform(8, 14))
            depth = float(rng.uniform(8, 12) if kind == "alcove" else rng.uniform(6, 10))
            if hi - lo < fw:
                continue
            for _try in range(20):
                s = float(rng.uniform(lo, hi - fw))
                if all(s + fw + 10 <= a or s >= b + 10 for a, b in spans):
                    spans.append((s, s + fw))
                    feats.append((edge, kind, s, fw, depth))
                    break
    return chamfers, tuple(feats)


def _edge_points(x0: float, x1: float, y: float, inward: float, feats, room_x0: float
                 ) -> list[tuple[float, float]]:
    """Points along a horizontal wall from x0 to x1 (either direction) at height y, with its
    features; ``inward`` is +1 if the room lies at larger y."""
    pts = []
    step = 1.0 if x1 > x0 else -1.0
    for _edge, kind, s, fw, depth in sorted(feats, key=lambda f: step * f[2]):
        a, b = room_x0 + s, room_x0 + s + fw
        if step < 0:
            a, b = b, a
        d = depth * inward * (1.0 if kind == "buttress" else -1.0)
        pts += [(a, y), (a, y + d), (b, y + d), (b, y)]
    return pts


def _room_walls(b: ArenaBuilder, spec: RoomSpec, doors: list[tuple[str, float, float]]) -> None:
    """Walls of one room: its outline with chamfers and features, broken at the doors
    ``(side, y_lo, y_hi)`` on the left/right walls."""
    x0, y0, x1, y1 = spec.box
    cbl, cbr, ctr, ctl = spec.chamfers
    bottom = [f for f in spec.features if f[0] == "bottom"]
    top = [f for f in spec.features if f[0] == "top"]
    left = sorted((lo, hi) for side, lo, hi in doors if side == "left")
    right = sorted((lo, hi) for side, lo, hi in doors if side == "right")
    seq: list[tuple[float, float] | None] = []
    # bottom edge, left to right
    seq += [(x0, y0 + cbl)] if cbl else []
    seq += [(x0 + cbl, y0)]
    seq += _edge_points(x0, x1, y0, +1, bottom, x0)
    seq += [(x1 - cbr, y0)] + ([(x1, y0 + cbr)] if cbr else [])
    for lo, hi in right:                          # right edge, upwards
        seq += [(x1, lo), None, (x1, hi)]
    seq += [(x1, y1 - ctr)] if ctr else []
    seq += [(x1 - ctr, y1)]
    seq += _edge_points(x1, x0, y1, -1, top, x0)  # top edge, right to left
    seq += [(x0 + ctl, y1)] + ([(x0, y1 - ctl)] if ctl else [])
    for lo, hi in reversed(left):                 # left edge, downwards
        seq += [(x0, hi), None, (x0, lo)]
    seq.append(seq[0])
    for p, q in pairwise(seq):
        if p is not None and q is not None and p != q:
            b.wall(p, q)


def random_flat(n_rooms: int, seed: int, *, name: str | None = None) -> Arena:
    """A flat of ``n_rooms`` (≥ 2) distinct rooms in a row, joined by corridors (see module
    doc). The same ``(n_rooms, seed)`` always gives the same flat."""
    return flat_with_rooms(n_rooms, seed, name=name)[0]


def flat_with_rooms(n_rooms: int, seed: int, *, name: str | None = None
                    ) -> tuple[Arena, list[RoomSpec]]:
    """:func:`random_flat` and the :class:`RoomSpec` of each of its rooms."""
    if isinstance(n_rooms, bool) or not isinstance(n_rooms, int | np.integer) or n_rooms < 2:
        raise ValueError(f"n_rooms must be an integer >= 2, got {n_rooms!r}")
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise ValueError(f"seed must be an integer >= 0, got {seed!r}")
    for attempt in range(100):
        drawn = _draw_flat(int(n_rooms), np.random.default_rng([int(seed), attempt]),
                           name or f"flat-{n_rooms}r-s{seed}")
        if drawn is not None and all(reachable_regions(drawn[0]).values()):
            return drawn
    raise RuntimeError(f"no reachable flat of {n_rooms} rooms found for seed {seed}")


def _canonical(spec: RoomSpec) -> set[tuple]:
    """The room's shape (size, corners, wall features) under the 8 symmetries of a rectangle,
    rounded to 2 cm: two rooms are congruent if these sets intersect."""
    x0, y0, x1, y1 = spec.box
    w, h = x1 - x0, y1 - y0
    # geometry as points in room coordinates: corner chamfers (their size) and features
    # (kind, width and depth, each rounded on its own)
    pts: list[tuple[float, float, tuple[float, ...]]] = []
    for (cx, cy), c in zip(((0, 0), (w, 0), (w, h), (0, h)), spec.chamfers):
        if c:
            pts.append((cx, cy, (0.0, c, 0.0)))
    for edge, kind, s0, fw, depth in spec.features:
        y = 0.0 if edge == "bottom" else h
        pts.append((s0 + fw / 2, y, (100.0 if kind == "alcove" else -100.0, fw, depth)))
    out = set()
    for rot in range(4):
        for mirror in (False, True):
            P = []
            for x, y, tag in pts:
                X, Y, Wc, Hc = (w - x if mirror else x), y, w, h
                for _ in range(rot):          # 90 degrees counter-clockwise in the box
                    X, Y, Wc, Hc = Hc - Y, X, Hc, Wc
                P.append((round(X / 2), round(Y / 2), *(round(v / 2) for v in tag)))
            size = (w, h) if rot % 2 == 0 else (h, w)
            out.add(((round(size[0] / 2), round(size[1] / 2)), tuple(sorted(P))))
    return out


def congruent(a: RoomSpec, b: RoomSpec) -> bool:
    """Do two rooms have the same shape up to rotation and mirroring (to ~2 cm)?"""
    return bool(_canonical(a) & _canonical(b))


def _draw_flat(n: int, rng: np.random.Generator, name: str
               ) -> tuple[Arena, list[RoomSpec]] | None:
    # n widths in [30, 75], at least `gap` apart (8 cm up to 6 rooms), in random order
    gap = min(8.0, 45.0 / (n - 1))
    base = np.sort(rng.uniform(0.0, 45.0 - gap * (n - 1), n)) + gap * np.arange(n)
    widths = [float(30.0 + w) for w in rng.permutation(base)]
    heights = [float(rng.uniform(60, 100)) for _ in range(n)]
    specs_local = []
    patterns: set = set()
    for w, h in zip(widths, heights):
        for _try in range(50):
            ch, feats = _draw_room(rng, w, h)
            pat = (tuple(c > 0 for c in ch), tuple(sorted((e, k) for e, k, *_ in feats)))
            if pat not in patterns:
                patterns.add(pat)
                specs_local.append((ch, feats))
                break
        else:
            return None
    corridors = [(float(rng.uniform(20, 35)), float(rng.uniform(20, 26))) for _ in range(n - 1)]
    # vertical placement: each corridor's band must fit inside both rooms it joins
    y0s = [0.0]
    bands = []
    for i, (_length, cw) in enumerate(corridors):
        lo = y0s[i] + _DOOR_MARGIN
        hi = y0s[i] + heights[i] - _DOOR_MARGIN - cw
        yb = float(rng.uniform(lo, hi))
        bands.append((yb, yb + cw))
        # next room: its box must contain the band with margins
        nlo = yb + cw + _DOOR_MARGIN - heights[i + 1]
        nhi = yb - _DOOR_MARGIN
        y0s.append(float(rng.uniform(nlo, nhi)))
    shift = _PAD - min(y0s)
    y0s = [y + shift for y in y0s]
    bands = [(a + shift, b + shift) for a, b in bands]
    x = _PAD
    boxes = []
    for i in range(n):
        boxes.append((x, y0s[i], x + widths[i], y0s[i] + heights[i]))
        x += widths[i] + (corridors[i][0] if i < n - 1 else 0.0)
    W = x + _PAD
    H = max(b[3] for b in boxes) + _PAD
    b = ArenaBuilder(name, W, H)
    specs = [RoomSpec(box, ch, feats) for box, (ch, feats) in zip(boxes, specs_local)]
    for i, spec in enumerate(specs):
        doors = []
        if i > 0:
            doors.append(("left", *bands[i - 1]))
        if i < n - 1:
            doors.append(("right", *bands[i]))
        _room_walls(b, spec, doors)
    for i, (lo, hi) in enumerate(bands):
        xa, xb = boxes[i][2], boxes[i + 1][0]
        b.wall((xa, lo), (xb, lo)).wall((xa, hi), (xb, hi))
    for i, spec in enumerate(specs):
        x0, y0, x1, y1 = spec.box
        rects = [spec.box]
        for edge, kind, s, fw, depth in spec.features:
            if kind == "alcove":
                yy = (y0 - depth, y0) if edge == "bottom" else (y1, y1 + depth)
                rects.append((x0 + s, yy[0], x0 + s + fw, yy[1]))
        b.region(f"room_{i + 1}", *rects)
    for i, (lo, hi) in enumerate(bands):
        b.region(f"corridor_{i + 1}", (boxes[i][2], lo, boxes[i + 1][0], hi))
    x0, y0, x1, y1 = boxes[0]
    b.start((x0 + x1) / 2, (y0 + y1) / 2, float(rng.uniform(-np.pi, np.pi)))
    try:
        arena = b.build()
    except ValueError:
        return None
    locs = []
    for x0, y0, x1, y1 in boxes:
        for xx in np.arange(x0 + 7.5, x1, 15.0):
            for yy in np.arange(y0 + 7.5, y1, 15.0):
                if arena.is_free(xx, yy, 4.7):
                    locs.append((xx, yy))
    for i, (lo, hi) in enumerate(bands):
        locs.append(((boxes[i][2] + boxes[i + 1][0]) / 2, (lo + hi) / 2))
    arena = replace(arena, locations=np.array(locs, float))
    object.__setattr__(arena, "landmarks", {**arena.landmarks,
                                            **{f"room_{i + 1}": ((s.box[0] + s.box[2]) / 2,
                                                                 (s.box[1] + s.box[3]) / 2)
                                               for i, s in enumerate(specs)}})
    return arena, specs


def room_names(arena: Arena) -> list[str]:
    """The rooms of a generated flat, in order (``room_1`` …)."""
    return [r for r in arena.region_names if r.startswith("room_")]


def reachable_regions(arena: Arena, radius: float = 3.7, margin: float = 1.0,
                      cell: float = 2.0) -> dict[str, bool]:
    """For each region: can a disc of ``radius + margin`` get there from the start pose?

    Free space is the grid of centres where the disc fits (:meth:`Arena.free_grid`); the
    component of the start (8-connected) must touch a free cell inside the region."""
    xs, ys, free = arena.free_grid(radius + margin, cell)
    lab, _ = ndimage.label(free, structure=np.ones((3, 3), int))
    i = int(np.argmin(np.abs(xs - arena.start_pose[0])))
    j = int(np.argmin(np.abs(ys - arena.start_pose[1])))
    comp = lab[i, j]
    out = {}
    for reg in arena.regions:
        inside = np.zeros_like(free)
        for x0, y0, x1, y1 in reg.rects:
            inside |= ((xs[:, None] >= x0) & (xs[:, None] <= x1)
                       & (ys[None, :] >= y0) & (ys[None, :] <= y1))
        out[reg.name] = bool(comp > 0 and np.any(inside & (lab == comp)))
    return out


def _ray_lengths(walls: np.ndarray, pts: np.ndarray, angles: np.ndarray, rmax: float
                 ) -> np.ndarray:
    """Free length (capped at ``rmax``) of rays from ``pts`` (P, 2) at ``angles`` (A,) against
    wall segments (n, 4): (P, A)."""
    d = np.stack([np.cos(angles), np.sin(angles)], axis=1)             # (A, 2)
    a, e = walls[:, :2], walls[:, 2:] - walls[:, :2]                   # (n, 2)
    out = np.full((len(pts), len(angles)), rmax)
    for k in range(len(walls)):
        # p + t d = a + s e  ->  solve for t, s
        den = d[:, 0] * e[k, 1] - d[:, 1] * e[k, 0]                    # (A,)
        ok = np.abs(den) > 1e-12
        w = a[k][None, :] - pts                                        # (P, 2)
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (w[:, None, 0] * e[k, 1] - w[:, None, 1] * e[k, 0]) / den[None, :]
            s = (w[:, None, 0] * d[None, :, 1] - w[:, None, 1] * d[None, :, 0]) / den[None, :]
        hit = ok[None, :] & (t >= 0) & (s >= 0) & (s <= 1)
        out = np.where(hit, np.minimum(out, t), out)
    return out


def room_signatures(arena: Arena, *, n_poses: int = 200, n_rays: int = 36, rmax: float = 30.0,
                    seed: int = 0) -> dict[str, np.ndarray]:
    """A rotation-invariant picture of each room as the robot's rays see it: at ``n_poses``
    random free points of the room, the ``n_rays`` ray lengths (capped at the IR range
    ``rmax``) sorted; the signature is their mean (n_rays,). Two rooms with equal signatures
    look alike to instantaneous range readings."""
    rng = np.random.default_rng(seed)
    walls = arena.wall_array()
    angles = np.linspace(0, 2 * np.pi, n_rays, endpoint=False)
    out = {}
    for reg in arena.regions:
        if not reg.name.startswith("room"):
            continue
        x0, y0, x1, y1 = reg.rects[0]
        pts = []
        for _ in range(50 * n_poses):
            p = (rng.uniform(x0, x1), rng.uniform(y0, y1))
            if arena.is_free(p[0], p[1], 4.2):
                pts.append(p)
                if len(pts) == n_poses:
                    break
        scans = np.sort(_ray_lengths(walls, np.array(pts), angles, rmax), axis=1)
        out[reg.name] = scans.mean(axis=0)
    return out
