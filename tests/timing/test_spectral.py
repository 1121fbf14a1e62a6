"""Spectral timing batteries: bumps at mu_j, Weber widths, one active battery, restarts."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hippo.timing import SpectralParams, SpectralTiming


@pytest.fixture(scope="module")
def timing():
    return SpectralTiming()


def test_tuning_equals_hand_computed_gaussian(timing):
    j = int(np.searchsorted(timing.mu, 7.0))
    mu = timing.mu[j]
    # sigma = 0.1 mu above 1 s: at tau = 1.1 mu the cell is one sigma away -> exp(-1/2)
    assert timing.tuning(1.1 * mu)[j] == pytest.approx(math.exp(-0.5), rel=1e-12)
    assert timing.tuning(mu)[j] == pytest.approx(1.0)
    # below 1 s the width floor (0.1 s) applies: cell at 0.5 s, tau = 0.7 s is 2 sigma away
    k = int(np.argmin(np.abs(timing.mu - 0.5)))
    assert timing.tuning(timing.mu[k] + 0.2)[k] == pytest.approx(math.exp(-2.0), rel=1e-12)


def test_centres_log_spaced_and_cover_60s(timing):
    ratios = timing.mu[1:] / timing.mu[:-1]
    assert np.allclose(ratios, ratios[0])
    assert timing.mu[0] <= 0.2 and timing.mu[-1] >= 90.0


def test_each_cell_peaks_at_its_centre(timing):
    for j in (20, 50, 80, 110):
        tau = np.linspace(0.5 * timing.mu[j], 1.5 * timing.mu[j], 20001)
        x = timing.tuning(tau)[:, j]
        assert tau[np.argmax(x)] == pytest.approx(timing.mu[j], rel=1e-4)


def test_widths_grow_in_proportion_to_centre(timing):
    fwhm = []
    cells = [j for j in range(0, timing.n_cells, 10) if timing.mu[j] > 1.5]
    for j in cells:
        tau = np.linspace(0.5 * timing.mu[j], 1.5 * timing.mu[j], 40001)
        above = tau[timing.tuning(tau)[:, j] >= 0.5]
        fwhm.append(above[-1] - above[0])
    ratio = np.array(fwhm) / timing.mu[cells]
    assert np.allclose(ratio, 2 * math.sqrt(2 * math.log(2)) * 0.1, rtol=1e-3)
    assert np.all(np.diff(fwhm) > 0)


def test_only_winner_battery_is_active_and_event_restarts():
    t = SpectralTiming()
    first = t.step(3, 0.2)
    assert first.changed and first.previous is None
    for _ in range(9):
        bs = t.step(3, 0.2)
    assert not bs.changed and bs.tau == pytest.approx(1.8)
    assert np.allclose(t.battery(3), t.tuning(1.8))
    assert not np.any(t.battery(5))
    ev = t.step(5, 0.2)  # the event: 5 wins, 3's battery stops at 2.0 s
    assert ev.changed and ev.previous == 3 and ev.state == 5
    assert ev.previous_tau == pytest.approx(2.0)
    assert np.allclose(ev.previous_activity, t.tuning(2.0))
    assert ev.tau == 0.0 and np.array_equal(ev.activity, t.tuning(0.0))
    assert not np.any(t.battery(3)) and np.any(t.battery(5))
    bs = t.step(5, 0.2)
    assert bs.tau == pytest.approx(0.2) and not bs.changed
    t.reset()
    assert t.state is None and not np.any(t.activity)


def test_readout_recovers_elapsed_time_and_learned_delay(timing):
    for tau in (0.5, 2.0, 7.0, 11.6, 24.1, 45.0, 60.0, 90.0):
        assert timing.readout(timing.tuning(tau)) == pytest.approx(tau, rel=1e-3)
        # weights proportional to a battery (any gain) read out as its time
        assert timing.readout(3.7 * timing.tuning(tau)) == pytest.approx(tau, rel=1e-3)
    # the strongest of two bumps wins the readout
    v = timing.tuning(7.0) + 0.6 * timing.tuning(20.0)
    assert timing.readout(v) == pytest.approx(7.0, rel=1e-2)
    assert math.isnan(timing.readout(np.zeros(timing.n_cells)))


def test_bad_input_is_named(timing):
    with pytest.raises(ValueError, match="dt"):
        SpectralTiming().step(1, -0.2)
    with pytest.raises(ValueError, match="dt"):
        SpectralTiming().step(1, float("nan"))
    with pytest.raises(ValueError, match="winner"):
        SpectralTiming().step(-1, 0.2)
    with pytest.raises(ValueError, match="winner"):
        SpectralTiming().step(2.5, 0.2)
    with pytest.raises(ValueError, match="tau"):
        timing.tuning(-1.0)
    with pytest.raises(ValueError, match="non-finite"):
        timing.readout(np.full(timing.n_cells, np.nan))
    with pytest.raises(ValueError, match="shape"):
        timing.readout(np.ones(3))
    with pytest.raises(ValueError, match="mu_max"):
        SpectralParams(mu_min=10.0, mu_max=5.0)
    with pytest.raises(ValueError, match="weber"):
        SpectralParams(weber=0.0)


@settings(max_examples=40, deadline=None)
@given(tau=st.floats(0.3, 90.0), gain=st.floats(1e-3, 1e3))
def test_readout_of_any_scaled_battery_is_its_time(tau, gain):
    timing = SpectralTiming()
    assert timing.readout(gain * timing.tuning(tau)) == pytest.approx(tau, rel=2e-3)


def test_readout_names_a_bad_pattern():
    timing = SpectralTiming()
    bad = timing.tuning(3.0).copy()
    bad[5] = np.nan
    with pytest.raises(ValueError, match=r"^pattern\b"):
        timing.readout(bad)
    with pytest.raises(ValueError, match=r"pattern must have shape \(128,\)"):
        timing.readout(np.ones(5))


def test_tuning_names_a_bad_time():
    with pytest.raises(ValueError, match=r"^tau\b"):
        SpectralTiming().tuning(math.nan)


def test_reset_starts_the_clock_again_at_zero():
    timing = SpectralTiming()
    assert timing.tau == 0.0
    for _ in range(5):
        timing.step(0, 0.2)
    timing.reset()
    assert timing.tau == 0.0 and timing.state is None
