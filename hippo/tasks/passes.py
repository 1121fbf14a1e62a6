"""Passes and stops read from a run's per-tick arrays (``Log.arrays()``).

- :class:`AngleLaps` — laps by the angle swept around a point inside the loop.
- :func:`progress_along` — unwrapped progress along a route, tracked tick by tick as
  :class:`~hippo.tasks.routes.LapCounter` does.
- :func:`route_passes`, :func:`passes` — the passes by a checkpoint along the route (one per
  lap), or by distance to it.
- :func:`stops` — the stops the agent chose to make near checkpoints (or the teacher's blocks
  in the lesson).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from hippo._checks import check_positive
from hippo.tasks.routes import LapCounter, Route, checkpoints_xy, point_xy
from hippo.types import Mode, wrap_angle

__all__ = ["AngleLaps", "passes", "progress_along", "route_passes", "stops"]


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
    cx, cy = point_xy("centre", centre)
    check_positive("radius", radius)
    check_positive("gap", gap, allow_zero=True)
    idx = np.flatnonzero(arrays["phase"] == int(phase))
    if idx.size == 0:
        return []
    near = np.hypot(arrays["x"][idx] - cx, arrays["y"][idx] - cy) < radius
    runs: list[list[int]] = []
    for i in idx[near]:
        if runs and i - runs[-1][1] <= gap:
            runs[-1][1] = int(i) + 1
        else:
            runs.append([int(i), int(i) + 1])
    return [(a, b) for a, b in runs if a != idx[0]]


def progress_along(route: Route, x: np.ndarray, y: np.ndarray, window: float = 30.0
                   ) -> np.ndarray:
    """Unwrapped progress (cm) along closed ``route`` of the positions ``(x[i], y[i])``, tracked
    from the first (its progress on the route) as :class:`LapCounter` does."""
    if len(x) != len(y):
        raise ValueError(f"x and y must be as long, got {len(x)} and {len(y)} positions")
    laps = LapCounter(route, window)
    out = np.empty(len(x))
    for i, (a, b) in enumerate(zip(x, y, strict=True)):
        laps.update(float(a), float(b))
        out[i] = laps.start + laps.travelled  # type: ignore[operator]
    return out


def route_passes(arrays: dict, route: Route, checkpoint: Sequence[float], *, phase: int,
                 radius: float = 30.0) -> list[tuple[int, int]]:
    """Index ranges ``[a, b)`` of the passes by ``checkpoint`` during ``phase``, by progress
    along ``route``: each time the robot's progress comes within ``radius`` cm (along the
    route) of the checkpoint's, one pass per lap, however the robot dawdles or wiggles there.
    A pass under way when the phase starts, or not finished when it ends, does not count."""
    check_positive("radius", radius)
    if not route.closed:
        raise ValueError("route passes need a closed route (one pass per lap)")
    cx, cy = point_xy("checkpoint", checkpoint)
    idx = np.flatnonzero(arrays["phase"] == int(phase))
    if idx.size == 0:
        return []
    p = progress_along(route, arrays["x"][idx], arrays["y"][idx])
    L = route.length
    s_k = route.progress(cx, cy)
    out = []
    n0 = math.floor((p.min() - s_k - radius) / L)
    n1 = math.ceil((p.max() - s_k + radius) / L)
    for n in range(n0, n1 + 1):
        near = np.flatnonzero(np.abs(p - (s_k + n * L)) < radius)
        if near.size == 0 or near[0] == 0 or near[-1] == len(p) - 1:
            continue
        out.append((int(idx[near[0]]), int(idx[near[-1]]) + 1))
    return out


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
    cps = checkpoints_xy(checkpoints)
    check_positive("threshold", threshold, allow_zero=True)
    check_positive("min_s", min_s, allow_zero=True)
    if not float(radius) > 0:   # math.inf: stops anywhere, each at its nearest checkpoint
        raise ValueError(f"radius must be > 0 cm (inf: anywhere), got {radius!r}")
    n_cp = len(cps)
    still = arrays["speed"] <= threshold
    waiting = arrays["mode"] == int(Mode.WAIT)
    # a stop's length is its ticks x the tick (rounded to 1 ns): the same for the same ticks
    # whatever the clock's magnitude (a log that starts hours into a run gives the same)
    t = arrays["t"]
    tick = round(float(np.median(np.diff(t))), 9) if len(t) > 1 else 0.0
    out = []
    i, n = 0, len(still)
    while i < n:
        if not still[i]:
            i += 1
            continue
        j = i
        while j < n and still[j]:
            j += 1
        dur = (j - i) * tick
        x, y = arrays["x"][i], arrays["y"][i]
        d = [math.hypot(x - cx, y - cy) for cx, cy in checkpoints]
        k = int(np.argmin(d))
        phase = int(arrays["phase"][i])
        taught = taught_phase is not None and phase == int(taught_phase)
        if taught:
            k = int(arrays["trial"][i])
            if not 0 <= k < n_cp:
                raise ValueError(f"the stop at tick {i} (taught_phase {phase}) is in trial {k}, "
                                 f"which names no checkpoint (there are {n_cp})")
        chosen = taught or bool(np.any(waiting[i:j]))
        if dur >= min_s and d[k] < radius and chosen:
            drives = arrays["wait_drive"][i:j]
            drives = drives[drives >= 0]
            drive = int(np.bincount(drives).argmax()) if drives.size else -1
            out.append({"i0": i, "duration": dur, "checkpoint": k, "phase": phase,
                        "trial": int(arrays["trial"][i]), "drive": drive})
        i = j
    return out
