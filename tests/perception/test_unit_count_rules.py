"""The unit-count rule on hand-made spectra: the search range's both ends (a largest step
exactly at max_regions counts, one past it does not), ties in the spectrum and in the steps,
the parameters' edges and every error text; and fit_for_world's two fits (the probe's units,
one ICA unit and one restart, its convergence warning silenced; then per_region x m units),
checked on a stand-in model that records how it is built and returns a chosen spectrum.

In each spectrum below the steps of log Δ are set by hand (factors 10 or 100 against 1.1), so
the largest step, and with it m - 1, is read off directly."""

from __future__ import annotations

import re
import warnings
from typing import ClassVar

import numpy as np
import pytest

import hippo.perception.unit_count as uc
from hippo.perception.ica import ICAConvergenceWarning
from hippo.perception.place_cell_params import RCSFAICAParams
from hippo.perception.unit_count import (
    UnitCountParams,
    fit_for_world,
    regions_from_slowness,
    units_from_slowness,
)


def _exactly(exc: type[Exception], text: str):
    return pytest.raises(exc, match="^" + re.escape(text) + "$")


def _spectrum(n: int, jumps: dict[int, float]) -> np.ndarray:
    """n ascending slownesses growing by 1.1 per unit, by ``jumps[i]`` from unit i to i + 1
    (1-based), so the step after unit i is log(jumps[i])."""
    f = np.full(n - 1, 1.1)
    for i, x in jumps.items():
        f[i - 1] = x
    return 1e-4 * np.concatenate([[1.0], np.cumprod(f)])


# ------------------------------------------------------------------ the rule
def test_the_largest_step_exactly_at_max_regions_counts():
    """Default range m in [2, 8]: a jump after unit 7 (m - 1 = 7) gives 8 regions."""
    d = _spectrum(10, {7: 100.0})
    assert regions_from_slowness(d) == 8
    assert units_from_slowness(d) == 16


def test_a_larger_step_just_past_max_regions_is_not_searched():
    """The largest jump after unit 8 (m = 9, outside [2, 8]) is ignored; the next largest,
    after unit 3, gives 4 regions. max_regions = 9 takes it."""
    d = _spectrum(10, {8: 100.0, 3: 10.0})
    assert regions_from_slowness(d) == 4
    assert regions_from_slowness(d, UnitCountParams(max_regions=9, probe=24)) == 9


def test_the_fewest_values_and_ties():
    """Exactly max_regions values are enough; equal slownesses are sorted; equal steps go to
    the fewer regions (the first largest)."""
    d = np.array([1.0, 1, 10, 10, 10, 100, 100, 100])  # equal jumps after units 2 and 5
    step = np.diff(np.log(d))
    assert step[1] == step[4] == step.max()       # log 100 - log 10 = log 10, exactly
    assert regions_from_slowness(d) == 3
    flat = np.array([1e-3] * 3 + [1e-2] * 5)     # ties everywhere but one jump after unit 3
    assert regions_from_slowness(flat) == 4


def test_units_use_the_given_parameters_throughout():
    """min_regions = 3 leaves out the jump after unit 1: 4 regions, 3 units each."""
    d = _spectrum(9, {1: 100.0, 3: 10.0})
    p = UnitCountParams(min_regions=3, per_region=3)
    assert regions_from_slowness(d) == 2
    assert units_from_slowness(d, p) == 12


def test_bad_spectra_are_refused_word_for_word():
    with _exactly(ValueError, "slowness needs at least max_regions=8 values (units 1 … m), "
                              "got 7"):
        regions_from_slowness(_spectrum(7, {}))
    with _exactly(ValueError, "slowness must have shape (*,), got (2, 8)"):
        regions_from_slowness(np.tile(_spectrum(8, {}), (2, 1)))
    with _exactly(ValueError, "slowness contains 1 non-finite value(s) (NaN or inf)"):
        regions_from_slowness(np.r_[_spectrum(8, {})[:7], np.inf])
    with _exactly(ValueError, "slowness must be positive, got min 0"):
        regions_from_slowness(np.r_[0.0, _spectrum(8, {})[1:]])
    with _exactly(ValueError, "slowness must be sorted ascending (slowest unit first)"):
        regions_from_slowness(_spectrum(8, {})[::-1])


def test_parameter_edges_word_for_word():
    assert UnitCountParams(min_regions=2, max_regions=2, per_region=1, probe=2).probe == 2
    with _exactly(ValueError, "min_regions must be an integer >= 2, got 1"):
        UnitCountParams(min_regions=1)
    with _exactly(ValueError, "max_regions must be an integer >= 5, got 4"):
        UnitCountParams(min_regions=5, max_regions=4)
    with _exactly(ValueError, "per_region must be an integer >= 1, got 0"):
        UnitCountParams(per_region=0)
    with _exactly(ValueError, "probe must be an integer >= 8, got 7"):
        UnitCountParams(probe=7)


# ------------------------------------------------------------------ fit_for_world
class _Stand:
    """Stands in for RCSFAICA: records (params, overrides, U) of each model fitted; a probe
    (one ICA unit) warns that its ICA did not converge and gives the spectrum ``SPECTRUM``; the
    final model warns too (that warning must reach the caller)."""

    # the largest jump after unit 8 (9 regions), the next after unit 4 (5 regions)
    SPECTRUM = _spectrum(10, {8: 100.0, 4: 10.0})
    built: ClassVar[list[tuple[object, dict, object]]] = []

    def __init__(self, params: object = None, **overrides: object) -> None:
        self.params, self.overrides = params, overrides

    def fit(self, U: object) -> _Stand:
        _Stand.built.append((self.params, self.overrides, U))
        warnings.warn("not converged", ICAConvergenceWarning, stacklevel=2)
        if self.overrides.get("n_ica") == 1:
            warnings.warn("the probe's other warning", UserWarning, stacklevel=2)
            self.sfa_slowness_ = self.SPECTRUM
        return self


@pytest.fixture
def stand(monkeypatch: pytest.MonkeyPatch) -> type[_Stand]:
    _Stand.built = []
    monkeypatch.setattr(uc, "RCSFAICA", _Stand)
    return _Stand


def test_fit_for_world_probes_then_fits_per_region_units(stand):
    U = np.zeros((3, 2))
    params = RCSFAICAParams(n_reservoir=20, seed=7)
    count = UnitCountParams(max_regions=9, per_region=3, probe=10)
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        model, m = fit_for_world(U, params, count)
    # read with count (max_regions 9): 9 regions, not the default range's 5
    assert m == 9 and model.overrides == {"n_sfa": 27, "n_ica": 27}
    (p1, probe, U1), (p2, final, U2) = stand.built
    assert p1 is params and p2 is params and U1 is U and U2 is U
    assert probe == {"n_sfa": 10, "n_ica": 1, "ica_restarts": 1}
    assert final == {"n_sfa": 27, "n_ica": 27} and type(final["n_sfa"]) is int
    # the probe's convergence warning is silenced, its other warnings and the model's are not
    kinds = [w.category for w in seen]
    assert kinds == [UserWarning, ICAConvergenceWarning]


def test_fit_for_world_defaults(stand):
    U = np.zeros((3, 2))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        _, m = fit_for_world(U)
    (p1, probe, _), (p2, final, _) = stand.built
    assert p1 == RCSFAICAParams() and p2 == RCSFAICAParams()
    assert probe == {"n_sfa": 24, "n_ica": 1, "ica_restarts": 1}      # UnitCountParams()
    assert m == 5 and final == {"n_sfa": 10, "n_ica": 10}          # max_regions 8: 5
