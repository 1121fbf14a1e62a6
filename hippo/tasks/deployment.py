"""A long deployment counted the RatSLAM way: failures over many hours of autonomous work.

Milford & Wyeth (IJRR 2010) report a robot's reliability as the failures over a long deployment
(1,143 delivery tasks, one failure, 37 hours). :func:`tally_failures` does the same for a
stretch of a patrol's per-tick arrays. Each pass by a checkpoint is a task; a failure is

- ``missed``    — a pass by a checkpoint without a stop for its drive;
- ``misplaced`` — a stop the robot chose (its ``WAIT`` mode) farther than ``PASS_RADIUS`` from
  every checkpoint, or at one checkpoint for another's drive (or for none);
- ``wait_off``  — a counted stop whose length is off the wait learned for that checkpoint by more
  than ``tolerance`` (5 %);
- ``stuck``     — no ``stuck_cm`` of progress along the route in ``stuck_s`` seconds (counted
  online by :class:`StuckWatch`; the operator then puts the robot back on the route).

:func:`health` samples what must stay bounded over hours: states, transitions and map edges,
the drive levels, the transition cells' weights, the process memory.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from hippo._checks import check_positive, check_real
from hippo.tasks.passes import stops
from hippo.tasks.patrol import PASS_RADIUS, pass_report
from hippo.tasks.routes import Route

__all__ = ["FAILURE_KINDS", "DeploymentParams", "StuckWatch", "health", "tally_failures"]

FAILURE_KINDS = ("missed", "misplaced", "wait_off", "stuck")


@dataclass(frozen=True)
class DeploymentParams:
    """How failures are counted.

    tolerance: a wait off the learned one by more than this fraction is a failure (5 %).
    stuck_s, stuck_cm: no ``stuck_cm`` cm of progress along the route in ``stuck_s`` s is
        stuck (180 s: the longest wait a patrol can be taught, 120 s, and a minute more).
    """

    tolerance: float = 0.05
    stuck_s: float = 180.0
    stuck_cm: float = 10.0

    def __post_init__(self) -> None:
        check_positive("tolerance", self.tolerance)
        check_positive("stuck_s", self.stuck_s)
        check_positive("stuck_cm", self.stuck_cm)


class StuckWatch:
    """Online: has the robot's best progress along the route (cm, unwrapped) risen by
    ``stuck_cm`` within the last ``stuck_s`` seconds? Going the wrong way round, circling on
    the spot and pushing at a wall all leave it flat."""

    def __init__(self, stuck_s: float, stuck_cm: float) -> None:
        self.stuck_s = check_positive("stuck_s", stuck_s)
        self.stuck_cm = check_positive("stuck_cm", stuck_cm)
        self.reset(math.nan, -math.inf)

    def reset(self, t: float, travelled: float) -> None:
        """Start watching afresh at time ``t`` from progress ``travelled``."""
        self._best, self._since = travelled, t

    def update(self, t: float, travelled: float) -> bool:
        """True once the robot is stuck (then :meth:`reset` it after helping it on)."""
        t, travelled = check_real("t", t), check_real("travelled", travelled)
        if math.isnan(self._since) or travelled >= self._best + self.stuck_cm:
            self._best, self._since = travelled, t
            return False
        return t - self._since >= self.stuck_s


def tally_failures(arrays: dict, route: Route, checkpoints: Sequence[Sequence[float]],
                   learned: Sequence[float | None], threshold: float, *, phase: int,
                   tolerance: float = 0.05) -> dict[str, Any]:
    """The passes (tasks) and failures of ``phase`` in a run's per-tick ``arrays`` (see the
    module docstring; ``threshold``: the speed below which the robot is still). Returns
    ``tasks``, ``missed``, ``misplaced``, ``wait_off``, ``extra_stops``, ``stops``, the
    reproduced waits per checkpoint and their relative errors."""
    check_positive("tolerance", tolerance)
    near = stops(arrays, checkpoints, threshold)
    everywhere = stops(arrays, checkpoints, threshold, radius=math.inf)
    rows = pass_report(arrays, route, checkpoints, near, learned, phase=phase)
    misplaced = 0
    for st in everywhere:
        if st["phase"] != phase:
            continue
        i, k = st["i0"], st["checkpoint"]
        d = math.dist((arrays["x"][i], arrays["y"][i]), checkpoints[k])
        if d >= PASS_RADIUS or st["drive"] != k:
            misplaced += 1
    return {
        "tasks": sum(r["passes"] for r in rows),
        "missed": sum(r["passes"] - r["stops_made"] for r in rows),
        "misplaced": misplaced,
        "wait_off": sum(sum(e > tolerance for e in r["rel_errors"]) for r in rows),
        "extra_stops": sum(r["extra_stops"] for r in rows),
        "stops": sum(1 for st in everywhere if st["phase"] == phase),
        "waits_s": [r["reproduced_waits_s"] for r in rows],
        "rel_errors": [r["rel_errors"] for r in rows],
    }


def _rss_mb() -> float:
    """The process's resident memory now (MB), from /proc where there is one (elsewhere its
    peak, ``ru_maxrss``: bytes on macOS, KiB on the BSDs and Linux)."""
    try:
        with open("/proc/self/statm") as f:
            pages = int(f.read().split()[1])
        import os

        return pages * os.sysconf("SC_PAGE_SIZE") / 1e6
    except (OSError, ValueError, IndexError):
        import resource
        import sys

        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        return peak / 1e6 if sys.platform == "darwin" else peak * 1024 / 1e6


def health(agent: Any, t: float) -> dict[str, Any]:
    """What must stay bounded over a long run, ``t`` s into it: the states and transitions
    the robot knows, the map's edges, its drive levels, the largest transition-cell weight
    and whether every weight is finite, and the process memory (MB)."""
    w = np.asarray(getattr(agent.cells, "_w", np.zeros(0)))
    levels = agent.drives.levels
    return {"t_h": t / 3600.0, "states": int(agent.layer.n_states),
            "transitions": len(agent.cells.transitions), "map_edges": len(agent.graph),
            "drive_min": float(min(levels.values())) if levels else None,
            "drive_max": float(max(levels.values())) if levels else None,
            "weight_max": float(np.abs(w).max()) if w.size else 0.0,
            "finite": bool(np.isfinite(w).all()), "rss_mb": round(_rss_mb(), 1)}
