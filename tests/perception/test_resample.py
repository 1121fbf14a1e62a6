"""The causal decimator: its factor and its input are checked; offline and online agree."""

import numpy as np
import pytest

from hippo.perception.resample import Decimator, antialias_taps


def test_decimator_refuses_a_bad_factor_and_bad_input():
    for factor in (2.7, 0, -1, True, "2"):
        with pytest.raises(ValueError, match="downsample factor"):
            Decimator(factor)
    with pytest.raises(ValueError, match="numtaps"):
        antialias_taps(2, numtaps=4.5)
    for factor in (1, 2):
        d = Decimator(factor)
        with pytest.raises(ValueError, match=r"input U contains 20 non-finite"):
            d.offline(np.full((10, 2), np.nan))
        with pytest.raises(ValueError, match=r"input U must be \(T, n\)"):
            d.offline(np.ones(10))
        with pytest.raises(ValueError, match="reading u contains 1 non-finite"):
            d.push([np.nan, 1.0])
        with pytest.raises(ValueError, match="reading u must be 1-D"):
            d.push(np.ones((2, 2)))
    d = Decimator(2)
    d.push(np.ones(2))
    with pytest.raises(ValueError, match=r"reading u must be \(2,\) as before"):
        d.push(np.ones(3))


def test_decimator_offline_equals_online():
    U = np.random.default_rng(0).uniform(size=(23, 3))
    d = Decimator(np.int64(3))
    online = [y for y in (d.push(u) for u in U) if y is not None]
    np.testing.assert_allclose(d.offline(U), online, rtol=0, atol=1e-15)
    assert d.offline(U).shape == (7, 3) and np.array_equal(Decimator(1).push(U[0]), U[0])
