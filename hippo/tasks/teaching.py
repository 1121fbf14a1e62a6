"""The experimenter's side of a task: rewards that depend on what the robot does.

:class:`Experimenter` plays the reward sound once the robot has been still on a coloured
floor zone for ``delay`` s (HIREL's place preference). Call it every tick with the observation
(it is a ``Session.run`` ``until`` predicate that never stops the run by itself).
"""

from __future__ import annotations

from typing import Any

from hippo.types import Observation

__all__ = ["Experimenter"]


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
