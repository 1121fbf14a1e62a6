"""One seed, named random streams: every random choice of a run comes from here.

A run has one integer ``seed``. :class:`Seeds` turns it into independent
``numpy.random.Generator`` streams, one per named consumer, so that adding a consumer or
drawing more from one never shifts another::

    seeds = Seeds(0)
    world = World(arena, seed=seeds.world)                # sensor and odometry noise
    rng = seeds.generator("exploration")                  # the exploring wall follower

Each stream is ``numpy.random.default_rng(SeedSequence([seed, key]))`` with a fixed ``key`` per
name (:data:`STREAMS`): a ``SeedSequence`` of the pair, so streams are independent and the
same seed always gives the same run. The keys are the ones hippo's scenarios have always used,
so their numbers did not change when the streams got names; a new consumer takes a new key
in :data:`STREAMS`.
"""

from __future__ import annotations

import numpy as np

__all__ = ["STREAMS", "Seeds"]

#: stream name -> its key under the run's seed (one place for every key)
STREAMS: dict[str, int] = {
    "recording": 1,       # the wall follower of hippo.sim.record
    "exploration": 3,     # the exploring wall follower of hippo.tasks.explore
    "pauses": 4,          # when and how long the exploration pauses
    "brain": 7,           # the brain's choices (exploring known moves, planner ties)
    "motor-explore": 8,   # the motor layer's exploring wall follower
    "motor-steer": 9,     # the motor layer's wall-guided steering
}


class Seeds:
    """The named random streams of one run (see the module docstring)."""

    def __init__(self, seed: int) -> None:
        if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
            raise ValueError(f"seed must be an integer >= 0, got {seed!r}")
        self.seed = int(seed)

    @property
    def world(self) -> int:
        """The world's seed (its own generator: sensor and odometry noise)."""
        return self.seed

    def sequence(self, name: str) -> np.random.SeedSequence:
        """The ``SeedSequence`` of stream ``name``."""
        if name not in STREAMS:
            raise KeyError(f"unknown random stream {name!r}; known: {', '.join(STREAMS)} "
                           "(a new consumer adds its name and key to hippo.seeds.STREAMS)")
        return np.random.SeedSequence([self.seed, STREAMS[name]])

    def generator(self, name: str) -> np.random.Generator:
        """A fresh generator of stream ``name`` (the same numbers on every call)."""
        return np.random.default_rng(self.sequence(name))
