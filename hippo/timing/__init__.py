"""hippo.timing: when things happen — time-cell batteries, timed transitions, satisfaction.

- :class:`SpectralTiming` (``spectral.py``): one battery of time cells per state; only the
  winner's is active and it restarts at each sensory event.
- :class:`NLMS` and the rule's functions (``nlms.py``): HIREL eq. 1-3.
- :class:`TransitionCells` (``transitions.py``): learn ``(a, b)`` with its delay; predictions,
  learned delays and the ``delay_over`` flag the agent uses to end a wait.
- :class:`Satisfaction` (``satisfaction.py``): HIREL eq. 4-5.
- :class:`NonOccurrence` (``non_occurrence.py``): a predicted event is overdue.
- ``trials.py``: symbolic timed trials without a robot (``run_trial``, ``reproduce``), for
  demos, benchmarks and tests.

One control tick (dt = 0.2 s)::

    battery = timing.step(winner, dt)          # winner from hippo.perception.states.StateLayer
    readouts = cells.step(battery, dt)         # {(a, b): TransitionReadout} out of the winner
    omitted = nonocc.step(readouts, dt)        # keys whose predicted event did not come
"""

from hippo.timing.nlms import NLMS, NLMSParams, learning_modulation, nlms_update, sliding_mean
from hippo.timing.non_occurrence import NonOccurrence, NonOccurrenceParams
from hippo.timing.satisfaction import Satisfaction, SatisfactionParams
from hippo.timing.spectral import BatteryState, SpectralParams, SpectralTiming
from hippo.timing.transitions import (
    DelayRangeWarning,
    TransitionCells,
    TransitionParams,
    TransitionReadout,
)

__all__ = [
    "NLMS",
    "BatteryState",
    "DelayRangeWarning",
    "NLMSParams",
    "NonOccurrence",
    "NonOccurrenceParams",
    "Satisfaction",
    "SatisfactionParams",
    "SpectralParams",
    "SpectralTiming",
    "TransitionCells",
    "TransitionParams",
    "TransitionReadout",
    "learning_modulation",
    "nlms_update",
    "sliding_mean",
]
