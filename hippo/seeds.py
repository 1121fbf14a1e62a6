"""One seed, named random streams: every random choice of a run comes from here.

A run has one integer ``seed``. :class:`Seeds` turns it into independent
``numpy.random.Generator`` streams, one per named consumer, so that adding a consumer or
drawing more from one never shifts another::

    seeds = Seeds(0)
    world = World(arena, seed=seeds.world)                # sensor and odometry noise
    rng = seeds.generator("exploration")                  # the exploring wall follower

Each stream is ``numpy.random.default_rng(SeedSequence([seed, key]))`` with a fixed ``key`` per
name (:data:`STREAMS`): a ``SeedSequence`` of the pair, so streams are independent and the
same seed always gives the same run. Keys 1-9 are the ones hippo's scenarios used before the
streams got names, so those runs did not change; the two-rooms kidnaps (which had shared key 7
with the brain) and the timing demo's trials (keys 0, 1, 2 … per delay, shared with the
recording and the exploration) took keys of their own. A new consumer takes a new key in
:data:`STREAMS`; ``sequence(name, i)`` gives independent sub-streams (one per trial or
condition) of one name.
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
    "fault-sets": 11,     # which sensors die in a scenario's fault curve
    "sensor-faults": 13,  # the noise of injected sensor faults (one sub-stream per condition)
    "kidnaps": 23,        # where and when a place-cell scenario kidnaps the robot
    "timing-trials": 29,  # the jitter of the timing demo's trials (one sub-stream per delay)
    "timing-pipeline": 31,  # the timing demo's place-preference trials through the brain
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

    def sequence(self, name: str, *sub: int) -> np.random.SeedSequence:
        """The ``SeedSequence`` of stream ``name``; ``sub`` indices name independent
        sub-streams of it (one per condition or trial), the children ``spawn`` would make.
        (Not ``[seed, key, i]``: a ``SeedSequence`` ignores trailing zero words, so sub-stream
        0 would be the stream itself.)"""
        if name not in STREAMS:
            raise KeyError(f"unknown random stream {name!r}; known: {', '.join(STREAMS)} "
                           "(a new consumer adds its name and key to hippo.seeds.STREAMS)")
        bad = [i for i in sub if isinstance(i, bool) or not isinstance(i, int | np.integer)
               or i < 0]
        if bad:
            raise ValueError(f"sub-stream indices must be integers >= 0, got {bad}")
        return np.random.SeedSequence([self.seed, STREAMS[name]],
                                      spawn_key=tuple(map(int, sub)))

    def generator(self, name: str, *sub: int) -> np.random.Generator:
        """A fresh generator of stream ``name`` (sub-stream ``sub``; the same numbers on
        every call)."""
        return np.random.default_rng(self.sequence(name, *sub))
