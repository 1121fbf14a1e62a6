"""The place-cell estimator's parameters (:class:`RCSFAICAParams`) and the papers' presets.

``SMC09`` (Antonelo & Schrauwen, SMC 2009: e-puck, 8 IR sensors, two rooms) and ``ICANN09``
(Antonelo & Schrauwen, ICANN 2009: 17 distance sensors, maze E1) are the one home of the
papers' settings; :meth:`~hippo.perception.place_cells.RCSFAICA.smc09` and
:meth:`~hippo.perception.place_cells.RCSFAICA.icann09` start from them. Each layer's own
parameter class (:class:`~hippo.perception.reservoir_params.ReservoirParams`,
:class:`~hippo.perception.sfa.SFAParams`, :class:`~hippo.perception.ica_params.ICAParams`)
checks its fields; :class:`RCSFAICAParams` builds them (``reservoir_params()``,
``sfa_params()``, ``ica_params()``) and names its own field in their messages.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from hippo._checks import check_choice, check_fields, check_int
from hippo.perception.backends import _check_device, _np_dtype
from hippo.perception.ica_params import ICAParams
from hippo.perception.reservoir_params import ReservoirParams, _leak_param
from hippo.perception.sfa import SFAParams
from hippo.perception.slow_pool import check_slow_pool

__all__ = ["ICANN09", "SMC09", "RCSFAICAParams"]

_RESERVOIR_NAMES = {"n_inputs": "n_inputs", "n_neurons": "n_reservoir", "leak": "leak",
                    "spectral_radius": "spectral_radius", "input_weight": "input_weight",
                    "input_prob": "input_prob", "seed": "seed"}
_SFA_NAMES = {"n_components": "n_sfa", "cutoff": "sfa_cutoff", "expansion": "sfa_expansion"}
_ICA_NAMES = {"n_components": "n_ica", "algorithm": "ica_algorithm", "max_iter": "ica_max_iter",
              "tol": "ica_tol", "n_restarts": "ica_restarts", "score": "ica_score"}


@dataclass(frozen=True)
class RCSFAICAParams:
    """All hyper-parameters of the three layers; defaults are SMC09's (:meth:`RCSFAICA.smc09`)."""

    # input
    n_inputs: int = 8
    downsample: int = 1
    # reservoir (SMC09 eq. 1)
    use_reservoir: bool = True
    n_reservoir: int = 600
    leak: float | tuple[float, ...] = (0.05, 0.15)
    spectral_radius: float = 0.99
    input_weight: float = 2.0
    input_prob: float = 0.075
    # SFA (eq. 2-7)
    n_sfa: int = 4
    sfa_cutoff: float | str = 1e-8
    sfa_expansion: str = "linear"
    # slow pool (:mod:`hippo.perception.slow_pool`): τ in reservoir ticks of a leaky running
    # mean of the SFA input, appended to it; 0 = off
    slow_pool: float = 0.0
    # ICA (eq. 8-10)
    n_ica: int = 4
    ica_algorithm: str = "symmetric"
    ica_restarts: int = 10
    ica_score: str = "kurtosis"
    ica_max_iter: int = 1000
    ica_tol: float = 1e-6
    # training
    washout: int = 0
    seed: int = 0
    dtype: str = "float32"
    device: str = "cpu"
    # input checks (see "Input policy" in the module docstring)
    input_range: tuple[float, float] | None = (0.0, 1.0)
    out_of_range: str = "error"
    min_fit_ticks: int = 100

    def __post_init__(self) -> None:
        object.__setattr__(self, "leak", _leak_param(self.leak))
        if isinstance(self.input_range, list):
            object.__setattr__(self, "input_range", tuple(self.input_range))
        check_fields(self)
        check_int("n_inputs", self.n_inputs, lo=1)
        check_int("downsample", self.downsample, lo=1)
        check_int("washout", self.washout, lo=0)
        check_int("n_reservoir", self.n_reservoir, lo=1)
        check_int("n_sfa", self.n_sfa, lo=1)
        check_int("n_ica", self.n_ica, lo=1)
        if self.n_ica > self.n_sfa:
            raise ValueError(f"n_ica={self.n_ica} exceeds n_sfa={self.n_sfa}")
        check_int("min_fit_ticks", self.min_fit_ticks, lo=3)
        object.__setattr__(self, "slow_pool", check_slow_pool(self.slow_pool))
        if self.input_range is not None:
            lo, hi = self.input_range
            if not lo < hi:
                raise ValueError(f"input_range must be (low, high) with low < high, got "
                                 f"{self.input_range!r}")
        check_choice("out_of_range", self.out_of_range, ("error", "warn", "clip"))
        _np_dtype(self.dtype)
        _check_device(self.device)
        # delegate the remaining checks to the layers' own parameter classes, naming the
        # RCSFAICA field in the message
        for build, names in ((self.reservoir_params, _RESERVOIR_NAMES),
                             (self.sfa_params, _SFA_NAMES), (self.ica_params, _ICA_NAMES)):
            try:
                build()
            except ValueError as exc:
                msg = str(exc)
                ours = [o for theirs, o in names.items() if re.search(rf"\b{theirs}\b", msg)]
                raise ValueError(f"{' / '.join(ours) or 'RCSFAICAParams'}: {msg}") from None

    @property
    def sfa_inputs(self) -> int:
        """Width of SFA's input before any expansion: ``[u; x]``, and their slow pool's mean
        when ``slow_pool`` is on."""
        width = self.n_inputs + (self.n_reservoir if self.use_reservoir else 0)
        return width * (2 if self.slow_pool else 1)

    def transient_updates(self, tol: float = 1e-3) -> int:
        """Reservoir updates until the start from rest is forgotten to ``tol``: a washout.

        The fit starts from ``x(0) = 0`` and from a zero history of the anti-aliasing filter, a
        state the robot never meets again; unless it is washed out, ICA spends units on it (in
        the maze: 4 of 70 units fired only in the first ~20 updates, never on test data). The
        slowest linear mode of eq. 1 decays by ``r = 1 - a + a ρ`` per update (ρ the spectral
        radius, ``a`` the smallest leak), so after ``ceil(ln tol / ln r)`` updates it is below
        ``tol`` of where it started; the filter's ``2·downsample + 1`` taps see the zero
        history for 2 more updates. ICANN09 (``a`` 0.6, ρ 0.9, down-sampled by 25): r = 0.94,
        112 + 2 = 114 updates. Without a reservoir only the filter's updates count.
        """
        if not 0.0 < tol < 1.0:
            raise ValueError(f"tol must lie in (0, 1), got {tol!r}")
        n = 0
        if self.use_reservoir:
            a = float(min(self.leak)) if isinstance(self.leak, tuple) else float(self.leak)
            r = 1.0 - a + a * float(self.spectral_radius)
            if r >= 1.0:
                raise ValueError(f"spectral_radius={self.spectral_radius} leaves no fading "
                                 "memory (1 - a + a·ρ >= 1): the start is never forgotten")
            n = int(np.ceil(np.log(tol) / np.log(r))) if r > 0 else 1
        return n + (2 if self.downsample > 1 else 0)

    def reservoir_params(self) -> ReservoirParams:
        return ReservoirParams(n_inputs=self.n_inputs, n_neurons=self.n_reservoir,
                               spectral_radius=self.spectral_radius, leak=self.leak,
                               input_weight=self.input_weight, input_prob=self.input_prob,
                               seed=self.seed)

    def sfa_params(self) -> SFAParams:
        return SFAParams(n_components=self.n_sfa, cutoff=self.sfa_cutoff,
                         expansion=self.sfa_expansion)

    def ica_params(self) -> ICAParams:
        return ICAParams(n_components=self.n_ica, algorithm=self.ica_algorithm,
                         max_iter=self.ica_max_iter, tol=self.ica_tol,
                         n_restarts=self.ica_restarts, score=self.ica_score, seed=self.seed)


#: SMC09 (e-puck, 8 IR sensors, two rooms): 600 neurons, leaks 0.05/0.15, ρ 0.99, W_in ±2 p 0.075
SMC09 = RCSFAICAParams()
#: ICANN09 (17 distance sensors, maze E1): 400 neurons, leak 0.6, ρ 0.9, W_in ±0.2 p 0.15,
#: 70 SFA / 70 ICA units, input down-sampled by 50
ICANN09 = RCSFAICAParams(n_inputs=17, downsample=50, n_reservoir=400, leak=0.6,
                         spectral_radius=0.9, input_weight=0.2, input_prob=0.15,
                         n_sfa=70, n_ica=70)
