"""hippo.perception: place cells that learn themselves (RC-SFA-ICA, SMC09 / ICANN09).

* :class:`Reservoir` — leaky ESN with per-neuron leak rates (SMC09 eq. 1), batched;
  numpy on the CPU, torch on CUDA.
* :class:`SFA` — linear (or quadratic) slow feature analysis with a whitening cutoff;
  :class:`SFAMoments` — the running sums it learns from, fed chunk by chunk.
* :class:`FastICA` — cube-nonlinearity FastICA with restarts scored without labels.
* :class:`RCSFAICA` — the three layers as one estimator: ``fit`` / ``transform`` / ``step``;
  each layer saves and loads its own state (``to_arrays`` / ``from_arrays``, ``save`` /
  ``load``: :mod:`hippo.perception.part_files`), and ``RCSFAICA.save`` composes them.
* :class:`PlacePrototypes` — radial-basis place cells over the RC-SFA-ICA population vector.
* :class:`StateLayer` — the multimodal winner-take-all state layer (places, colour, sound,
  proprioception) with hysteresis.
* :class:`ContextStates` — places split by the way the robot came in, and merged when they take
  turns (online, USM-style; CSCG's clones), usable alone or inside the state layer.
* :mod:`hippo.perception.metrics` — place fields, localization, decoding, recovery time.
* :mod:`hippo.perception.unit_count` — how many SFA/ICA units a world needs, read from the
  SFA slowness spectrum without labels.
"""

from hippo.perception.contexts import ContextParams, ContextStates
from hippo.perception.ica import FastICA, ICAConvergenceWarning
from hippo.perception.ica_params import ICAParams
from hippo.perception.leak_sweep import fit_leak_sweep
from hippo.perception.place_cell_params import ICANN09, SMC09, RCSFAICAParams
from hippo.perception.place_cells import RCSFAICA
from hippo.perception.prototypes import PlacePrototypes, PrototypeParams
from hippo.perception.resample import Decimator
from hippo.perception.reservoir import Reservoir
from hippo.perception.reservoir_params import ReservoirParams, expand_leak
from hippo.perception.sfa import SFA, SFAParams
from hippo.perception.sfa_moments import SFAMoments
from hippo.perception.states import StateEvent, StateKey, StateLayer, StateLayerParams

__all__ = [
    "ICANN09",
    "RCSFAICA",
    "SFA",
    "SMC09",
    "ContextParams",
    "ContextStates",
    "Decimator",
    "FastICA",
    "ICAConvergenceWarning",
    "ICAParams",
    "PlacePrototypes",
    "PrototypeParams",
    "RCSFAICAParams",
    "Reservoir",
    "ReservoirParams",
    "SFAMoments",
    "SFAParams",
    "StateEvent",
    "StateKey",
    "StateLayer",
    "StateLayerParams",
    "expand_leak",
    "fit_leak_sweep",
]
