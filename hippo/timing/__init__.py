"""hippo.timing: when things happen — time-cell batteries, timed transitions, non-occurrence.

- :class:`SpectralTiming` (``spectral.py``): one battery of time cells per state; only the
  winner's is active and it restarts at each sensory event.
- :class:`NLMS` and the rule's functions (``nlms.py``): HIREL eq. 1-3.
- :class:`TransitionCells` (``transitions.py``): learn ``(a, b)`` with its delay; predictions,
  learned delays and the ``delay_over`` flag the agent uses to end a wait; their parameters
  and per-tick records in ``transition_params.py``.
- :class:`TimingChain` (``chain.py``): batteries -> transition cells -> non-occurrence, wired
  once (the brain and the symbolic trials step it).
- :class:`NonOccurrence` (``non_occurrence.py``): a predicted event is overdue.
- ``trials.py``: symbolic timed trials without a robot (``run_trial``, ``reproduce``), for
  demos, benchmarks and tests.

One control tick (dt = 0.2 s)::

    battery = timing.step(winner, dt)          # winner from hippo.perception.states.StateLayer
    readouts = cells.step(battery, dt)         # {(a, b): TransitionReadout} out of the winner
    omitted = nonocc.step(readouts, dt)        # keys whose predicted event did not come

(``TimingChain.step(winner, dt)`` does exactly these three calls.)
"""

from hippo.timing.chain import TimingChain, TimingStep
from hippo.timing.nlms import NLMS, NLMSParams, learning_modulation, nlms_update, sliding_mean
from hippo.timing.non_occurrence import NonOccurrence, NonOccurrenceParams
from hippo.timing.spectral import BatteryState, SpectralParams, SpectralTiming
from hippo.timing.transition_params import DelayRangeWarning, TransitionParams, TransitionReadout
from hippo.timing.transitions import TransitionCells

__all__ = [
    "NLMS",
    "BatteryState",
    "DelayRangeWarning",
    "NLMSParams",
    "NonOccurrence",
    "NonOccurrenceParams",
    "SpectralParams",
    "SpectralTiming",
    "TimingChain",
    "TimingStep",
    "TransitionCells",
    "TransitionParams",
    "TransitionReadout",
    "learning_modulation",
    "nlms_update",
    "sliding_mean",
]
