"""How many slow features and ICA units a world needs, read from the SFA slowness spectrum.

SFA on a long exploration approximates the slowest eigenfunctions of the robot's motion through
the world (Franzius, Sprekeler & Wiskott 2007). A world of ``m`` regions the robot rarely
leaves (rooms joined by doorways) has ``m - 1`` slow modes — which room the robot is in — set
apart from the faster modes of the position within a room by a gap in the slowness spectrum
``Δ_1 ≤ Δ_2 ≤ …`` (SMC09 eq. 2-7; Δ_i = ⟨ẏ_i²⟩ of unit ``i``). The gap is the largest step
of ``log Δ``:

    m - 1 = argmax_{i ∈ [lo, hi)} log(Δ_{i+1} / Δ_i),        units = per_region · m

with ``per_region = 2`` (SMC09: 4 units for 2 rooms). No labels are used: only the slowness the
SFA fit reports for its probe units (``RCSFAICA.sfa_slowness_``).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from hippo._checks import check_array, check_fields, check_int
from hippo.perception.ica import ICAConvergenceWarning
from hippo.perception.place_cell_params import RCSFAICAParams
from hippo.perception.place_cells import RCSFAICA

__all__ = ["UnitCountParams", "fit_for_world", "regions_from_slowness", "units_from_slowness"]


@dataclass(frozen=True)
class UnitCountParams:
    """The spectrum rule: regions searched in ``[min_regions, max_regions]``, ``per_region``
    units each; ``probe`` SFA units are fitted to read the spectrum from."""

    min_regions: int = 2
    max_regions: int = 8
    per_region: int = 2
    probe: int = 24

    def __post_init__(self) -> None:
        check_fields(self)
        check_int("min_regions", self.min_regions, lo=2)
        check_int("max_regions", self.max_regions, lo=self.min_regions)
        check_int("per_region", self.per_region, lo=1)
        check_int("probe", self.probe, lo=self.max_regions)


def regions_from_slowness(slowness: np.ndarray, params: UnitCountParams | None = None) -> int:
    """The number of regions ``m`` whose ``m - 1`` slow modes stand apart from the rest of the
    spectrum: the largest step of ``log Δ`` after unit ``m - 1``, for ``m`` in
    ``[min_regions, max_regions]``."""
    p = params or UnitCountParams()
    d = check_array("slowness", slowness, shape=(None,))
    if d.size < p.max_regions:
        raise ValueError(f"slowness needs at least max_regions={p.max_regions} values (units "
                         f"1 … m), got {d.size}")
    if not np.all(d > 0):
        raise ValueError(f"slowness must be positive, got min {d.min():g}")
    if np.any(np.diff(d) < 0):
        raise ValueError("slowness must be sorted ascending (slowest unit first)")
    step = np.diff(np.log(d))                   # step[i] = log Δ_{i+2} / Δ_{i+1} (1-based)
    m = np.arange(p.min_regions, p.max_regions + 1)
    return int(m[np.argmax(step[m - 2])])


def units_from_slowness(slowness: np.ndarray, params: UnitCountParams | None = None) -> int:
    """SFA and ICA units for the world: ``per_region`` × :func:`regions_from_slowness`."""
    p = params or UnitCountParams()
    return p.per_region * regions_from_slowness(slowness, p)


def fit_for_world(U: np.ndarray, params: RCSFAICAParams | None = None,
                  count: UnitCountParams | None = None) -> tuple[RCSFAICA, int]:
    """Fit RC-SFA-ICA with as many SFA and ICA units as the world asks for.

    A probe fit (``count.probe`` SFA units, one ICA unit, one restart) reads the slowness
    spectrum; the model is then fitted with :func:`units_from_slowness` units. Returns the model
    and the number of regions the spectrum showed."""
    p = params or RCSFAICAParams()
    c = count or UnitCountParams()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ICAConvergenceWarning)   # the probe's ICA is unused
        probe = RCSFAICA(p, n_sfa=c.probe, n_ica=1, ica_restarts=1).fit(U)
    m = regions_from_slowness(probe.sfa_slowness_, c)
    k = c.per_region * m
    return RCSFAICA(p, n_sfa=k, n_ica=k).fit(U), m
