"""The experimenter's side of a task: rewards that depend on what the robot does.

:class:`Experimenter` plays the reward sound once the robot has been still on a coloured
floor zone for ``delay`` s (HIREL's place preference). Call it every tick with the observation
(it is a ``Session.run`` ``until`` predicate that never stops the run by itself).

:func:`lessons_again` — the patrol lesson's order grows when a checkpoint's lesson needed the
leash.
"""

from __future__ import annotations

from typing import Any

from hippo.types import Observation

__all__ = ["Experimenter", "lessons_again"]


class Experimenter:
    """Plays the sound (``teacher.sound()``) once the robot has been still in the zone of
    floor colour ``colour`` for ``delay`` s; ``rewarding = False`` withholds it (extinction).

    ``still_since``: when the current stop in the zone began (None: not stopped there);
    ``sounded``: the sound was played since the last :meth:`reset`.
    """

    def __init__(self, teacher: Any, delay: float, colour: int = 1) -> None:
        self.teacher, self.delay, self.colour = teacher, delay, colour
        self.still_since: float | None = None
        self.rewarding = True
        self.sounded = False

    def reset(self, rewarding: bool | None = None) -> None:
        """A new trial: no stop seen, no sound played (and ``rewarding`` if given)."""
        self.sounded, self.still_since = False, None
        if rewarding is not None:
            self.rewarding = rewarding

    def __call__(self, obs: Observation) -> bool:
        still = obs.floor == self.colour and not obs.moving
        if still and self.still_since is None:
            self.still_since = obs.t
        elif not still:
            self.still_since = None
        if (self.rewarding and not self.sounded and self.still_since is not None
                and obs.t - self.still_since >= self.delay - 1e-9):
            self.teacher.sound()
            self.sounded = True
        return False


def lessons_again(order: list[int], at: int, again: set[int]) -> None:
    """The lesson at position ``at`` of a patrol's teaching ``order`` needed the leash (the
    robot went astray). ``order`` starts as the chain ``[c0, c1, ..., c(n-1), c0]`` (the
    checkpoints the way the route passes them, the first once more); the lessons of the chain
    from ``c1`` up to the failed one are appended once more, in order, but for those already
    pending after ``at``, so that it is taught again after the one before it, as its run-up
    needs. Once per checkpoint (``again`` keeps which); nothing for ``c0``, taught twice
    anyway. (Appending ``c1..k`` whole for each failure taught ``c1`` twice in a row when
    ``c1`` and ``c2`` both needed the leash: ``c1``'s run-up became a whole lap, tuning seed
    4 of goal-arena.)"""
    k, first = order[at], order[0]
    if k == first or k in again:
        return
    again.add(k)
    chain = order[:order.index(first, 1)]
    pending = order[at + 1:]
    order += [j for j in chain[1:chain.index(k) + 1] if j not in pending]
