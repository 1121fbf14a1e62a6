"""What a patrol's passes by its checkpoints gave, from a run's per-tick arrays.

- ``PASS_RADIUS`` — a pass: the robot's progress along the route within this many cm of a
  checkpoint.
- :func:`pass_report` — per checkpoint: the passes during a phase, the stop the robot chose at
  each (the first one counts), extra and misplaced stops, and the waits against the learned
  ones.
- :func:`patrol_rounds` — the patrol measured without its route: rounds with every checkpoint
  served.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence

import numpy as np

from hippo._checks import check_int
from hippo.tasks.passes import route_passes
from hippo.tasks.routes import Route

__all__ = ["PASS_RADIUS", "pass_report", "patrol_rounds"]

#: a pass by a checkpoint: the robot's progress along the route within this many cm of it
PASS_RADIUS = 30.0


def pass_report(arrays: dict, route: Route, checkpoints: Sequence[Sequence[float]],
                all_stops: list[dict], learned: Sequence[float | None], *, phase: int,
                span: tuple[int, int] | None = None) -> list[dict]:
    """Per checkpoint ``k``: its passes during ``phase`` (within ``span`` = ``[i0, i1)`` of the
    arrays, if given), the first stop the robot chose for drive ``k`` in each pass
    (``reproduced_waits_s``), further stops there for it (``extra_stops``), stops there for
    another drive (``misplaced_stops``), and the waits' relative differences from
    ``learned[k]`` (``rel_errors``; none where ``learned[k]`` is None or 0: not learned)."""
    _check_learned(learned, len(checkpoints))
    lo, hi = span if span is not None else (0, len(arrays["t"]))
    lo, hi = check_int("span start", lo, lo=0), check_int("span end", hi, lo=0)
    if hi < lo:
        raise ValueError(f"span must be [i0, i1) with i0 <= i1, got ({lo}, {hi})")
    rows = []
    for k, cp in enumerate(checkpoints):
        runs = [(a, b) for a, b in route_passes(arrays, route, cp, phase=phase,
                                                radius=PASS_RADIUS) if lo <= a and b <= hi]
        here = [st for st in all_stops if st["checkpoint"] == k and st["phase"] == phase
                and lo <= st["i0"] < hi]
        per_pass = [[st["duration"] for st in here if a <= st["i0"] < b and st["drive"] == k]
                    for a, b in runs]
        rep = [d[0] for d in per_pass if d]
        w = learned[k]
        err = [abs(r - w) / w for r in rep] if w else []
        rows.append({"passes": len(runs), "stops_made": len(rep), "reproduced_waits_s": rep,
                     "extra_stops": sum(max(len(d) - 1, 0) for d in per_pass),
                     "misplaced_stops": sum(1 for st in here if st["drive"] != k),
                     "rel_errors": err})
    return rows


def _check_learned(learned: Sequence[float | None], n: int) -> None:
    """One learned wait per checkpoint, each None (not learned) or a finite number >= 0 s: a
    NaN gave NaN relative errors, which no tolerance counts as off (``tally_failures``)."""
    if len(learned) != n:
        raise ValueError(f"learned must give one wait per checkpoint ({n}), got {len(learned)}")
    for k, w in enumerate(learned):
        if w is None:
            continue
        if isinstance(w, bool | np.bool_) or not isinstance(w, numbers.Real) or \
                not (math.isfinite(float(w)) and float(w) >= 0.0):
            raise ValueError(f"learned[{k}] must be a finite wait >= 0 s or None (not learned), "
                             f"got {w!r}")


def patrol_rounds(stop_list: Sequence[dict], n: int, *, phase: int) -> tuple[int, int, int]:
    """The patrol measured without a route: the stops made during ``phase`` (from
    :func:`hippo.tasks.stops`) in the order made; a stop *serves* its checkpoint when the
    robot made it for that checkpoint's drive and the checkpoint was not the last one served;
    a *round* is done each time every one of the ``n`` checkpoints has been served since the
    last round. Returns ``(rounds, stops serving, stops made)``. HIREL's map sets no order
    between checkpoints: a robot that serves them in another order than the route's, or
    shuttles along a corridor the route runs both ways, still patrols (progress along such a
    route cannot tell out from back)."""
    n = check_int("n", n, lo=1)
    here = sorted((st for st in stop_list if st["phase"] == phase), key=lambda st: st["i0"])
    rounds, serving, last, seen = 0, 0, None, set()
    for st in here:
        k = st["checkpoint"]
        if st["drive"] != k or k == last:
            continue
        serving, last = serving + 1, k
        seen.add(k)
        if len(seen) == n:
            rounds, seen = rounds + 1, set()
    return rounds, serving, len(here)
