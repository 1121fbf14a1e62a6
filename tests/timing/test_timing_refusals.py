"""What the transition cells and the trial runner refuse, and the exact reason they give: the
NLMS stability bound alpha * dt * (gamma + sigma2) < 2, unknown states, wrong types, the
trial's arguments."""

from __future__ import annotations

import numpy as np
import pytest

from hippo.timing import NLMSParams, SpectralTiming, TimingChain, TransitionCells, TransitionParams
from hippo.timing.trials import reproduce, run_trial

DT = 0.2


def cells_with(**nlms: float) -> tuple[SpectralTiming, TransitionCells]:
    timing = SpectralTiming()
    return timing, TransitionCells(timing, TransitionParams(nlms=NLMSParams(**nlms)))


@pytest.mark.parametrize(("alpha", "gamma", "sigma2", "stable"), [
    (10.0, 0.5, 0.0, True),     # the defaults: step 1.0
    (10.0, 0.5, 0.5, False),    # step exactly 2: unstable (the bound is strict)
    (10.0, 0.4, 0.5, True),     # 1.8
    (10.0, 0.5, 0.6, False),    # gamma + sigma2 = 1.1: 2.2 (gamma - sigma2 would be stable)
    (12.5, 0.5, 0.5, False),    # 2.5: above 2, below 3
])
def test_the_nlms_step_must_stay_below_two(alpha, gamma, sigma2, stable):
    timing, cells = cells_with(alpha=alpha, gamma=gamma, sigma2=sigma2)
    step = alpha * DT * (gamma + sigma2)
    battery = timing.step(0, DT)
    if stable:
        cells.step(battery, DT)
        return
    with pytest.raises(ValueError) as err:
        cells.step(battery, DT)
    assert str(err.value) == (f"NLMS step alpha*dt*eta = {step:.3g} >= 2 is unstable; "
                              "lower nlms.alpha or dt")


def test_a_bad_tick_length_is_refused_by_name():
    timing, cells = cells_with()
    with pytest.raises(ValueError, match=r"^dt must be finite and > 0, got 0"):
        cells.step(timing.step(0, DT), 0.0)


def test_unknown_states_and_wrong_types_are_refused_with_the_reason():
    timing, cells = cells_with()
    cells.step(timing.step(0, DT), DT)
    cells.step(timing.step(1, DT), DT)
    assert cells.successors(0) == [1] and cells.successors(1) == []   # seen, followed by none
    with pytest.raises(ValueError) as err:
        cells.expected(7, np.array([1.0]))
    assert str(err.value) == "unknown state id 7: these transition cells never saw it"
    with pytest.raises(ValueError, match=r"^transition target"):
        cells.learned_delay((0, -3))
    with pytest.raises(ValueError) as err:
        TransitionCells("timing")
    assert str(err.value) == "timing must be a SpectralTiming, got str"
    with pytest.raises(ValueError, match=r"^TransitionParams.nlms .*'fast' \(str\)"):
        TransitionParams(nlms="fast")


def test_a_state_id_beyond_int64_is_refused_before_it_reaches_an_array():
    chain = TimingChain()
    with pytest.raises(ValueError, match=r"^winner must be a state id <= 2\*\*63 - 1"):
        chain.step(2**70, DT)
    chain.step(2**63 - 1, DT)  # the largest id works through the battery and the cells
    chain.step(1, DT)
    chain.step(2**63 - 1, DT)
    assert chain.cells.successors(2**63 - 1) == [1]


def test_a_trial_refuses_bad_arguments_with_the_reason():
    timing = SpectralTiming()
    chain = TimingChain.of(timing, TransitionCells(timing))
    rng = np.random.default_rng(0)
    with pytest.raises(TypeError) as err:
        run_trial(chain, 0, 1, rng=rng)
    assert str(err.value) == "run_trial(chain, a, b, delay, ...) takes a, b and delay"
    with pytest.raises(ValueError, match=r"^dt must be finite and > 0"):
        run_trial(chain, 0, 1, 2.0, dt=0.0, rng=rng)
    for jitter in (1.0, 1.5, -0.1):          # [0, 1)
        with pytest.raises(ValueError, match=r"^jitter"):
            run_trial(chain, 0, 1, 2.0, jitter=jitter, rng=rng)
    with pytest.raises(ValueError) as err:
        run_trial(chain, 0, 1, 2.0)
    assert str(err.value) == "jitter > 0 needs rng, a numpy.random.Generator"
    with pytest.raises(ValueError, match=r"^delay must be finite and > 0"):
        run_trial(chain, 0, 1, -2.0, rng=rng)
    run_trial(chain, 0, 1, 2.0, rng=rng)     # the chain now stands in state 1 (then 'after')
    with pytest.raises(ValueError) as err:
        run_trial(chain, 1, 0, 2.0, rng=rng)
    assert str(err.value) == ("state 1 is already the winner: a trial starts by entering it "
                              "(end the previous trial in another state, e.g. with other=...)")


@pytest.mark.parametrize(("seed", "match"), [
    (-1, r"^seed must be an integer in \[0, "), (1.5, r"^seed must be an integer, got 1.5"),
])
def test_reproduce_names_a_bad_seed(seed, match):
    # fifth fuzzing pass: numpy's SeedSequence message, naming no argument
    with pytest.raises(ValueError, match=match):
        reproduce(2.0, seed=seed, teacher=1, loops=1)
    a, b = reproduce(2.0, seed=4, teacher=1, loops=1), reproduce(2.0, seed=4, teacher=1, loops=1)
    assert a.waits == b.waits and a.learned == b.learned
