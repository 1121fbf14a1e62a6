"""FastICA's hyper-parameters (:class:`ICAParams`), checked field by field.

The estimator itself is :class:`hippo.perception.ica.FastICA`; ``score`` names one of the
unsupervised scores its restarts are ranked by (:mod:`~hippo.perception.ica_scores`).
"""

from __future__ import annotations

from dataclasses import dataclass

from hippo._checks import check_fields
from hippo.perception.ica_scores import SCORES

__all__ = ["MAX_RESTARTS", "ICAParams"]

#: the most random restarts (the command line's cap, ``--ica-restarts``)
MAX_RESTARTS = 1000


@dataclass(frozen=True)
class ICAParams:
    """FastICA hyper-parameters (SMC09: 4 units; ICANN09: 70 units)."""

    #: number of independent components (None: as many as inputs)
    n_components: int | None = None
    #: "symmetric" (default) or "deflation"
    algorithm: str = "symmetric"
    max_iter: int = 1000
    tol: float = 1e-6
    #: random initialisations; the best by ``score`` is kept
    n_restarts: int = 1
    score: str = "kurtosis"
    #: "auto" (skip when the input's covariance is the identity), True, or False
    whiten: bool | str = "auto"
    seed: int = 0
    #: threads the restarts run on (None: the usable cores); the result does not depend on it
    workers: int | None = None

    def __post_init__(self) -> None:
        check_fields(self)
        if self.n_components is not None and int(self.n_components) < 1:
            raise ValueError(f"n_components (n_ica) must be >= 1, got {self.n_components}")
        if self.algorithm not in ("symmetric", "deflation"):
            raise ValueError(f"algorithm must be 'symmetric' or 'deflation', got "
                             f"{self.algorithm!r}")
        if int(self.max_iter) < 1:
            raise ValueError(f"max_iter must be >= 1, got {self.max_iter}")
        if not float(self.tol) > 0:
            raise ValueError(f"tol must be > 0, got {self.tol}")
        if not 1 <= self.n_restarts <= MAX_RESTARTS:
            raise ValueError(f"n_restarts must lie in [1, {MAX_RESTARTS}] (each restart is a "
                             f"whole FastICA fit), got {self.n_restarts}")
        if self.score not in SCORES:
            raise ValueError(f"score must be one of {SCORES}, got {self.score!r}")
        if self.workers is not None and int(self.workers) < 1:
            raise ValueError(f"workers must be >= 1 or None, got {self.workers}")
        if self.whiten not in ("auto", True, False):
            raise ValueError(f"whiten must be 'auto', True or False, got {self.whiten!r}")
