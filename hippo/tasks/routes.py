"""Routes and checkpoints: where the robot is along a route, laps, passes and stops.

- :class:`Route` — a polyline of waypoints (closed for a loop): :meth:`Route.progress` is the
  distance along the route of the point nearest to a position; :meth:`Route.leg` the
  waypoints from one position to another along the route's direction; :meth:`Route.loop_from`
  a whole loop starting ahead of a pose.
- :class:`LapCounter` — laps by route progress (unwrapped over the loop's length).
- :class:`AngleLaps` — laps by the angle swept around a point inside the loop.
- :func:`passes`, :func:`stops` — from a run's per-tick arrays (``Log.arrays()``): the passes
  by a checkpoint, the stops the agent chose to make near checkpoints.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from hippo._checks import check_finite
from hippo.types import Mode, wrap_angle

__all__ = ["AngleLaps", "LapCounter", "Route", "passes", "stops"]


class Route:
    """Waypoints ``[(x, y), ...]`` in cm; ``closed``: the last one leads back to the first."""

    def __init__(self, waypoints: Sequence[Sequence[float]], *, closed: bool = True) -> None:
        pts = check_finite("waypoints", waypoints)
        if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 2:
            raise ValueError(f"waypoints must be at least two (x, y) points, got {pts.shape}")
        if closed and np.allclose(pts[0], pts[-1]):
            pts = pts[:-1]  # the loop's closing point is implied
        self.points = pts
        self.closed = closed
        ends = np.vstack([pts[1:], pts[:1]]) if closed else pts[1:]
        self._a, self._d = pts[: len(ends)], ends - pts[: len(ends)]
        seg = np.hypot(self._d[:, 0], self._d[:, 1])
        self._s0 = np.r_[0.0, np.cumsum(seg)[:-1]]
        self._len = seg
        self.length = float(seg.sum())

    @property
    def waypoints(self) -> list[tuple[float, float]]:
        return [(float(x), float(y)) for x, y in self.points]

    def progress(self, x: float, y: float) -> float:
        """Distance (cm) along the route, from its first waypoint, of the point of the route
        nearest to ``(x, y)``."""
        p = np.array([x, y], float) - self._a
        L2 = np.maximum(self._len**2, 1e-12)
        u = np.clip(np.sum(p * self._d, axis=1) / L2, 0.0, 1.0)
        gap = np.hypot(p[:, 0] - u * self._d[:, 0], p[:, 1] - u * self._d[:, 1])
        k = int(np.argmin(gap))
        return float(self._s0[k] + u[k] * self._len[k])

    def sample(self, spacing: float) -> list[tuple[float, float]]:
        """Points every ``spacing`` cm along the route from its first waypoint (e.g. the
        labelled locations of an arena built around it)."""
        if not spacing > 0:
            raise ValueError(f"spacing must be > 0 cm, got {spacing!r}")
        out = []
        for s in np.arange(0.0, self.length - 1e-9, spacing):
            k = int(np.searchsorted(self._s0, s, side="right") - 1)
            u = (s - self._s0[k]) / max(self._len[k], 1e-12)
            out.append((float(self._a[k, 0] + u * self._d[k, 0]),
                        float(self._a[k, 1] + u * self._d[k, 1])))
        return out

    def nearest(self, x: float, y: float) -> int:
        """Index of the waypoint nearest to ``(x, y)``."""
        return int(np.argmin(np.hypot(self.points[:, 0] - x, self.points[:, 1] - y)))

    def leg(self, start: Sequence[float], goal: Sequence[float]) -> list[tuple[float, float]]:
        """Waypoints from ``start`` to ``goal`` along the route's direction (the waypoint after
        the one nearest ``start``, up to the one nearest ``goal``), then ``goal`` itself."""
        wp = self.waypoints
        i, j = self.nearest(*start[:2]), self.nearest(*goal[:2])
        n = len(wp)
        return [wp[(i + k) % n] for k in range(1, (j - i) % n + 1)] + [
            (float(goal[0]), float(goal[1]))]

    def loop_from(self, pose: Sequence[float]) -> list[tuple[float, float]]:
        """One whole loop from the waypoint nearest ``pose`` (or the next one, if that one is
        behind the robot's heading) back to it."""
        wp = self.waypoints
        x, y, h = pose
        i0 = self.nearest(x, y)
        if math.cos(math.atan2(wp[i0][1] - y, wp[i0][0] - x) - h) < 0:
            i0 = (i0 + 1) % len(wp)  # the nearest waypoint is behind: lead on, not back
        return wp[i0:] + wp[:i0] + [wp[i0]]


class LapCounter:
    """Laps along a closed :class:`Route`, from the change of route progress between updates
    (a change of more than half the loop counts the short way round)."""

    def __init__(self, route: Route) -> None:
        if not route.closed:
            raise ValueError("laps need a closed route")
        self.route = route
        self._s: float | None = None
        self.turns = 0.0

    def update(self, x: float, y: float) -> float:
        s = self.route.progress(x, y)
        if self._s is not None:
            L = self.route.length
            self.turns += ((s - self._s + L / 2) % L - L / 2) / L
        self._s = s
        return self.turns


class AngleLaps:
    """Laps as the angle swept around ``centre`` (a point inside the loop), in turns."""

    def __init__(self, centre: Sequence[float]) -> None:
        self.cx, self.cy = (float(v) for v in centre)
        self.angle: float | None = None
        self.turns = 0.0

    def update(self, x: float, y: float) -> float:
        a = math.atan2(y - self.cy, x - self.cx)
        if self.angle is not None:
            self.turns += wrap_angle(a - self.angle) / (2 * math.pi)
        self.angle = a
        return self.turns


def passes(arrays: dict, centre: Sequence[float], *, phase: int, radius: float = 30.0,
           gap: int = 25) -> list[tuple[int, int]]:
    """Index ranges ``[a, b)`` of the passes by ``centre`` (within ``radius`` cm) during
    ``phase``; runs at most ``gap`` ticks apart are one pass, and a pass under way when the
    phase starts (the robot is still where the previous phase left it) does not count."""
    idx = np.flatnonzero(arrays["phase"] == int(phase))
    if idx.size == 0:
        return []
    near = np.hypot(arrays["x"][idx] - centre[0], arrays["y"][idx] - centre[1]) < radius
    runs: list[list[int]] = []
    for i in idx[near]:
        if runs and i - runs[-1][1] <= gap:
            runs[-1][1] = int(i) + 1
        else:
            runs.append([int(i), int(i) + 1])
    return [(a, b) for a, b in runs if a != idx[0]]


def stops(arrays: dict, checkpoints: Sequence[Sequence[float]], threshold: float, *,
          taught_phase: int | None = None, radius: float = 30.0, min_s: float = 1.0
          ) -> list[dict]:
    """Every stretch of >= ``min_s`` s without translation (speed <= ``threshold``) within
    ``radius`` cm of a checkpoint.

    In ``taught_phase`` any such stop counts (the teacher's block; the checkpoint is the
    trial's); elsewhere only stops the agent chose (it was in its ``WAIT`` mode), not stalls
    at walls. Each stop: ``i0`` (first tick), ``duration``, ``checkpoint``, ``phase``,
    ``trial``, ``drive`` (the drive it waited for most, -1: none).
    """
    still = arrays["speed"] <= threshold
    waiting = arrays["mode"] == int(Mode.WAIT)
    out = []
    i, n = 0, len(still)
    while i < n:
        if not still[i]:
            i += 1
            continue
        j = i
        while j < n and still[j]:
            j += 1
        dur = float(arrays["t"][j - 1] - arrays["t"][i] + (arrays["t"][1] - arrays["t"][0]))
        x, y = arrays["x"][i], arrays["y"][i]
        d = [math.hypot(x - cx, y - cy) for cx, cy in checkpoints]
        k = int(np.argmin(d))
        phase = int(arrays["phase"][i])
        taught = taught_phase is not None and phase == int(taught_phase)
        if taught:
            k = int(arrays["trial"][i])
        chosen = taught or bool(np.any(waiting[i:j]))
        if dur >= min_s and d[k] < radius and chosen:
            drives = arrays["wait_drive"][i:j]
            drives = drives[drives >= 0]
            drive = int(np.bincount(drives).argmax()) if drives.size else -1
            out.append({"i0": i, "duration": dur, "checkpoint": k, "phase": phase,
                        "trial": int(arrays["trial"][i]), "drive": drive})
        i = j
    return out
