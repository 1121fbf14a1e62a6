"""Shared set-up for the timing tests (trials come from hippo.timing.trials)."""

from __future__ import annotations

import numpy as np

from hippo.timing import NonOccurrence, SpectralTiming, TransitionCells
from hippo.timing.chain import TimingChain
from hippo.timing.trials import TrialTrace, run_trial

DT = 0.2


def make(seed: int = 0):
    timing = SpectralTiming()
    return timing, TransitionCells(timing), NonOccurrence(), np.random.default_rng(seed)


def trial(timing, cells, a: int, b: int, delay: float | None, *, rng=None, jitter=0.1,
          nonocc=None, self_end=False, t_max=None) -> TrialTrace:
    """A trial ``a -> b`` at ``delay`` (None: omitted), then state 99 for 4 s."""
    return run_trial(TimingChain.of(timing, cells, nonocc), a, b, delay, dt=DT,
                     jitter=jitter if rng else 0.0, rng=rng, self_end=self_end, t_max=t_max,
                     other=99)
