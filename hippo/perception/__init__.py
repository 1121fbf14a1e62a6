"""hippo.perception: place cells that learn themselves (RC-SFA-ICA, SMC09 / ICANN09).

* :class:`Reservoir` — leaky ESN with per-neuron leak rates (SMC09 eq. 1), torch, batched.
* :class:`SFA` — linear (or quadratic) slow feature analysis with a whitening cutoff.
* :class:`FastICA` — cube-nonlinearity FastICA with restarts scored without labels.
* :class:`RCSFAICA` — the three layers as one estimator: ``fit`` / ``transform`` / ``step``.
* :mod:`hippo.perception.metrics` — place fields, localization, decoding, recovery time.
"""

from hippo.perception.ica import FastICA, ICAConvergenceWarning, ICAParams
from hippo.perception.place_cells import (
    ICANN09,
    RCSFAICA,
    SMC09,
    RCSFAICAParams,
    fit_leak_sweep,
)
from hippo.perception.resample import Decimator
from hippo.perception.reservoir import Reservoir, ReservoirParams, expand_leak
from hippo.perception.sfa import SFA, SFAParams

__all__ = [
    "ICANN09",
    "RCSFAICA",
    "SFA",
    "SMC09",
    "Decimator",
    "FastICA",
    "ICAConvergenceWarning",
    "ICAParams",
    "RCSFAICAParams",
    "Reservoir",
    "ReservoirParams",
    "SFAParams",
    "expand_leak",
    "fit_leak_sweep",
]
