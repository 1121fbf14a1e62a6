"""Head-direction context of the place states: one state per place and direction of travel.

A wall follower in a room that looks the same turned by 180° (both rooms of ``two-rooms``: a
rectangle and an octagon, each with one doorway and, in the octagon, an alcove opposite) sees
the same sequence of walls twice per lap. No place code read from the distance sensors alone
can tell the two halves apart without remembering the doorway for half a lap, and the closed
loop's place code forgets in about 20 s. Measured on the patrol's place code (24 ICA units, 40
prototypes, 30-min exploration along the right wall, fit on the first 3/4, tuning seeds 0-2):
of the moving ticks of the last quarter, 12-14 % are won by a prototype more than 30 cm from
where it wins in the fit (the same place on the far side of the room), 1-3.5 % once each
prototype is split by the direction of travel in 4 sectors (goal-arena: 6-15 % -> 4-10 %;
patrol-course, a ring without that symmetry: 0.4-4 % either way).

The direction is the robot's own heading estimate (path integration: the compass HIREL's moves
already use, never an input of the place cells). Each place activity ``a_k`` goes to the state
input of its sector ``b`` (``n`` sectors of ``2π / n``)::

    s[k·n + b] = a_k,   s[k·n + b'] = 0  for b' ≠ b

The sector follows the heading with hysteresis: it changes only when the heading is more than
half a sector plus ``margin`` away from the current sector's centre, and only while the robot
translates (turning on the spot, as at the end of a wait, does not make a new state).
"""

from __future__ import annotations

import math

import numpy as np

from hippo._checks import check_int, check_positive

__all__ = ["HeadingSectors"]


def _finite(name: str, value: float, unit: str, *, lo: float = -math.inf) -> float:
    """``value`` unless it is no finite number >= ``lo`` (a ``ValueError`` naming ``name``)."""
    try:
        ok = lo <= value < math.inf  # (NaN fails the comparison)
    except TypeError:
        ok = False
    if not ok or isinstance(value, bool):
        rel = "" if lo == -math.inf else f" >= {lo:g}"
        raise ValueError(f"{name} must be a finite number{rel} ({unit}), got {value!r}")
    return value


class HeadingSectors:
    """Splits place activities by the sector of the direction of travel (module docstring).

    ``n`` sectors (``n`` >= 1; 1 passes activities through), ``margin`` rad of hysteresis
    (below half a sector), ``min_step`` cm: the translation in one tick under which the robot
    counts as turning on the spot (its sector is kept)."""

    def __init__(self, n: int, margin: float = math.radians(10.0), min_step: float = 0.1) -> None:
        n = check_int("heading sectors", n, lo=1)
        check_positive("margin", margin, allow_zero=True)
        check_positive("min_step", min_step, allow_zero=True)
        self.n = n
        self.width = 2.0 * math.pi / self.n
        if margin >= self.width / 2:
            raise ValueError(f"margin must be below half a sector ({self.width / 2:.3f} rad), "
                             f"got {margin}")
        self.margin = float(margin)
        self.min_step = float(min_step)
        self.sector: int | None = None

    def reset(self) -> None:
        """Forget the sector (after a lift): the next tick takes the heading's own."""
        self.sector = None

    def nearest(self, heading: float) -> int:
        """The sector whose centre is nearest ``heading`` (sector ``b`` is centred on
        ``b · 2π / n``)."""
        return self._nearest(_finite("heading", heading, "rad"))

    def _nearest(self, heading: float) -> int:
        return math.floor(heading / self.width + 0.5) % self.n

    def update(self, heading: float, step: float) -> int:
        """The sector after a tick that ran ``step`` cm with heading ``heading`` (rad)."""
        _finite("heading", heading, "rad")   # checked once a tick, here
        _finite("step", step, "cm", lo=0.0)
        if self.sector is None:
            self.sector = self._nearest(heading)
        elif step >= self.min_step:
            off = math.remainder(heading - self.sector * self.width, 2.0 * math.pi)
            if abs(off) > self.width / 2 + self.margin:
                self.sector = self._nearest(heading)
        return self.sector

    def split(self, acts: np.ndarray, heading: float, step: float) -> np.ndarray:
        """``s`` (``len(acts) · n``,) for place activities ``acts`` (module docstring)."""
        b = self.update(heading, step)
        if self.n == 1:
            return acts
        out = np.zeros(acts.shape[0] * self.n)
        out[b::self.n] = acts
        return out
