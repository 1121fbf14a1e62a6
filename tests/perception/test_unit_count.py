"""The unit-count rule: regions read from a slowness spectrum, on spectra and walks with known
numbers of regions."""

import numpy as np
import pytest

from hippo.perception.sfa import SFA
from hippo.perception.unit_count import (
    UnitCountParams,
    regions_from_slowness,
    units_from_slowness,
)


def test_gap_after_m_minus_one_slow_modes():
    # two slow modes, then a jump: three regions, six units
    d = np.array([1e-4, 1.3e-4, 9e-4, 1.0e-3, 1.1e-3, 1.2e-3, 1.3e-3, 1.4e-3, 1.5e-3])
    assert regions_from_slowness(d) == 3
    assert units_from_slowness(d) == 6
    assert units_from_slowness(d, UnitCountParams(per_region=3)) == 9
    # four slow modes: five regions
    d5 = np.concatenate([[1e-4, 1.2e-4, 1.5e-4, 2e-4], np.linspace(2e-3, 3e-3, 6)])
    assert regions_from_slowness(d5) == 5


def test_search_range_is_respected():
    # the biggest step lies after unit 1 (two regions) but min_regions = 3 excludes it
    d = np.array([1e-5, 1e-3, 1.1e-3, 5e-3, 5.2e-3, 5.4e-3, 5.6e-3, 5.8e-3, 6e-3])
    assert regions_from_slowness(d) == 2
    assert regions_from_slowness(d, UnitCountParams(min_regions=3)) == 4


def _clustered_walk(m: int, size: int = 10, T: int = 60_000, seed: int = 0) -> np.ndarray:
    """A random walk on m complete graphs of ``size`` nodes joined in a chain by single edges:
    m regions the walker rarely leaves. One-hot node per step, plus a little noise."""
    rng = np.random.default_rng(seed)
    n = m * size
    nbrs = [[c * size + j for j in range(size) if j != i % size] for i in range(n)
            for c in [i // size]]
    for c in range(m - 1):
        a, b = c * size + size - 1, (c + 1) * size
        nbrs[a].append(b)
        nbrs[b].append(a)
    x = np.empty(T, int)
    x[0] = 0
    for t in range(1, T):
        nb = nbrs[x[t - 1]]
        x[t] = nb[rng.integers(len(nb))]
    X = np.zeros((T, n))
    X[np.arange(T), x] = 1.0
    return X + 0.01 * rng.standard_normal(X.shape)


@pytest.mark.parametrize("m", [2, 3, 5])
def test_regions_of_a_clustered_walk(m):
    X = _clustered_walk(m)
    sfa = SFA(n_components=12).fit(X)
    assert regions_from_slowness(sfa.slowness_) == m


def test_bad_spectra_are_refused():
    with pytest.raises(ValueError, match="slowness"):
        regions_from_slowness(np.array([1e-3, 2e-3]))            # shorter than max_regions
    with pytest.raises(ValueError, match="ascending"):
        regions_from_slowness(np.linspace(1, 0.1, 10))
    with pytest.raises(ValueError, match="positive"):
        regions_from_slowness(np.linspace(0, 1, 10))
    with pytest.raises(ValueError, match="slowness"):
        regions_from_slowness(np.array([1.0, np.nan] + [2.0] * 8))
    with pytest.raises(ValueError, match="max_regions"):
        UnitCountParams(min_regions=4, max_regions=3)
    with pytest.raises(ValueError, match="probe"):
        UnitCountParams(probe=4)
