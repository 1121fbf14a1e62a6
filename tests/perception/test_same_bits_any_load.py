"""Same seed, same bits, however busy the machine: the fit and the leak sweep must not take
their BLAS thread count from the load average (products split over threads sum in another
order; ICA's rotation moved by 1e-10 between a quiet and a busy machine)."""

from __future__ import annotations

import os

import numpy as np
import pytest

from hippo.perception import RCSFAICA, fit_leak_sweep


@pytest.fixture(scope="module")
def U() -> np.ndarray:
    # slowly wandering readings in [0, 1] (a smoothed random walk), 4,000 ticks of 8 sensors
    rng = np.random.default_rng(3)
    walk = np.cumsum(rng.normal(size=(4000, 8)), axis=0)
    walk = (walk - walk.min(axis=0)) / np.ptp(walk, axis=0)
    return walk


def _under_load(monkeypatch, load: float) -> None:
    monkeypatch.setattr(os, "getloadavg", lambda: (load, load, load))


def test_a_fit_is_the_same_on_a_quiet_and_a_busy_machine(monkeypatch, U):
    out = []
    for load in (0.0, 8.0):   # all cores free / none free
        _under_load(monkeypatch, load)
        # the closed loop's place cells (hippo.tasks.make_places): 24 SFA and ICA units
        m = RCSFAICA(n_reservoir=400, leak=(0.1, 0.3), spectral_radius=0.9, n_sfa=24, n_ica=24,
                     ica_restarts=3, seed=0).fit(U)
        out.append(m.transform(U[:500]))
    np.testing.assert_array_equal(out[0], out[1])


def test_a_leak_sweep_is_the_same_on_a_quiet_and_a_busy_machine(monkeypatch, U):
    leaks = [(0.05, 0.15), (0.08, 0.15), (0.1, 0.3)]
    out = []
    for load in (0.0, 8.0):
        _under_load(monkeypatch, load)
        models = fit_leak_sweep(U, leaks, seed=0, ica_restarts=2)
        out.append([m.transform(U[:300]) for m in models])
    for a, b in zip(*out, strict=True):
        np.testing.assert_array_equal(a, b)
    # and the number of workers changes no number either
    one = fit_leak_sweep(U, leaks, seed=0, ica_restarts=2, workers=1)
    for a, m in zip(out[0], one, strict=True):
        np.testing.assert_array_equal(a, m.transform(U[:300]))
