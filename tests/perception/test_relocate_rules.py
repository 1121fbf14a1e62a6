"""The rules of hippo.perception.relocate on small hand-made explorations: the parameters'
bounds exactly on their edges and one step past (every message word for word), the shortest
exploration accepted, the start never matched exactly up to ``skip``, what a true match may cost
(``max_cost``: another pass exactly ``2 spread`` ticks on is the same pass, one tick further it is
another), a cost exactly at it, the rivals' place codes exactly ``spread`` ticks either side,
a pause exactly before a window's last reading, giving up exactly after ``max_ticks``, and the
state handed over as float64 from a float32 reservoir."""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np
import pytest

from hippo.perception.relocate import RelocaliserParams, SequenceRelocaliser
from hippo.perception.reservoir import Reservoir
from hippo.perception.reservoir_params import ReservoirParams


def _raises(exc: type[BaseException], msg: str) -> Any:
    """``pytest.raises`` matching the whole message word for word."""
    return pytest.raises(exc, match="^" + re.escape(msg) + "$")


def _reservoir(dtype: str = "float64") -> Reservoir:
    return Reservoir(ReservoirParams(n_inputs=3, n_neurons=20, leak=(0.1, 0.3), seed=1),
                     dtype=dtype)


def _fitted(U: np.ndarray, winners: np.ndarray | None = None, dtype: str = "float64",
            **kw: Any) -> SequenceRelocaliser:
    """A relocaliser fitted on ``U`` (every tick moving; a new place every 20 ticks)."""
    T = len(U)
    winners = np.arange(T) // 20 if winners is None else winners
    kw.setdefault("skip", 0)
    return SequenceRelocaliser(RelocaliserParams(**kw)).fit(_reservoir(dtype), winners, U,
                                                            np.ones(T, bool))


def _uniform(seed: int, T: int = 400) -> np.ndarray:
    return np.random.default_rng(seed).uniform(0, 1, (T, 3))


# --- parameters ---------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["window", "spread", "every"])
def test_counts_of_at_least_one_on_their_edge(name):
    assert getattr(RelocaliserParams(**{name: 1}), name) == 1
    with _raises(ValueError, f"{name} must be an integer >= 1, got 0"):
        RelocaliserParams(**{name: 0})


def test_max_ticks_and_skip_on_their_edges():
    # max_ticks at least window: equal is fine, one fewer is refused (with max_ticks = 0 the
    # integer check speaks first)
    assert RelocaliserParams(window=5, max_ticks=5).max_ticks == 5
    with _raises(ValueError, "max_ticks (4) must be at least window (5)"):
        RelocaliserParams(window=5, max_ticks=4)
    with _raises(ValueError, "max_ticks must be an integer >= 1, got 0"):
        RelocaliserParams(max_ticks=0)
    assert RelocaliserParams(skip=0).skip == 0
    with _raises(ValueError, "skip must be an integer >= 0, got -1"):
        RelocaliserParams(skip=-1)


def test_ratio_and_quantile_on_their_edges():
    assert RelocaliserParams(ratio=1.0).ratio == 1.0
    below = math.nextafter(1.0, 0.0)
    with _raises(ValueError, f"ratio must be >= 1, got {below!r}"):
        RelocaliserParams(ratio=below)
    with _raises(ValueError, "RelocaliserParams.ratio must be a finite real number, got nan "
                             "(float)"):
        RelocaliserParams(ratio=math.nan)
    # quantile in (0, 1]: 1 is the largest, 0 is refused, and so is anything above 1
    assert RelocaliserParams(quantile=1.0).quantile == 1.0
    assert RelocaliserParams(quantile=5e-324).quantile == 5e-324
    with _raises(ValueError, "quantile must lie in (0.0, 1.0], got 0.0"):
        RelocaliserParams(quantile=0.0)
    above = math.nextafter(1.0, 2.0)
    with _raises(ValueError, f"quantile must lie in (0.0, 1.0], got {above!r}"):
        RelocaliserParams(quantile=above)


def test_params_of_another_kind_are_refused_word_for_word():
    with _raises(TypeError, "params must be RelocaliserParams, got 3"):
        SequenceRelocaliser(3)  # type: ignore[arg-type]


def test_a_new_relocaliser_is_not_looking_and_has_not_matched():
    rel = SequenceRelocaliser()
    assert rel.active is False and rel.matched_after is None
    rel.start()
    assert rel.active is True
    rel.stop()
    assert rel.active is False


# --- fit ----------------------------------------------------------------------------------

def test_the_shortest_exploration_accepted():
    # skip + window + 2 spread = 10 + 5 + 2 · 3 = 21 moving ticks (spread != window, so the
    # terms cannot stand in for each other)
    U = _uniform(0, 21)
    _fitted(U, skip=10, spread=3)
    with _raises(ValueError, "the exploration has 20 moving ticks; sequence matching needs at "
                             "least 21"):
        _fitted(U[:20], skip=10, spread=3)


def test_no_stretch_passed_twice_means_any_match_is_good():
    # window + 2 spread = 15 ticks: the stretch ends lie 0..10 ticks apart, never more than
    # 2 spread = 10, so no stretch has another pass and max_cost is inf
    U = _uniform(1, 15)
    rel = _fitted(U, spread=5)
    assert rel.max_cost == math.inf
    assert rel.match(U[3:8]) == 7


def test_non_finite_readings_are_named():
    U = _uniform(2)
    U[7, 2] = np.inf
    with _raises(ValueError, "sensors contains 1 non-finite value(s) (NaN or inf)"):
        _fitted(U)


# --- what a match costs -------------------------------------------------------------------

def test_the_start_is_never_matched_exactly_up_to_skip():
    # skip = 100: a stretch ending at moving tick 99 lies in the start, one ending at 100 not.
    # ratio 1: only exact copies are rivals (random readings have none)
    U = _uniform(3)
    rel = _fitted(U, skip=100, ratio=1.0)
    assert rel.match(U[96:101]) == 100
    assert rel.match(U[95:100]) != 99
    # with skip = 0 the very first stretch (ending at tick window - 1 = 4) is matched
    assert _fitted(U, ratio=1.0).match(U[0:5]) == 4


@pytest.mark.parametrize("offset, repeated", [(10, False), (11, True)])
def test_another_pass_lies_more_than_two_spreads_on(offset, repeated):
    # the readings of ticks 50-54 are seen again `offset` ticks later, spread = 5. Random
    # readings otherwise: every other pair of stretches differs (cost > 0). max_cost is the
    # quantile 1e-9 of each stretch's best cost against stretches more than 2 spread = 10 ticks
    # away, i.e. (nearly) the smallest of them: 0 when the repeat is another pass (11 ticks
    # on), > 0 when it is the same pass (exactly 10 ticks on)
    U = _uniform(4, 120)
    U[50 + offset:55 + offset] = U[50:55]
    rel = _fitted(U, spread=5, quantile=1e-9)
    if repeated:
        assert rel.max_cost < 1e-9
    else:
        assert rel.max_cost > 1e-3


def _brute_max_cost(U: np.ndarray, M: int, spread: int, skip: int, q: float) -> float:
    """max_cost by the module docstring's rule, with loops: for each of 200 stretch ends evenly
    spaced from skip + M - 1 to the last tick, the smallest C(k) = Σ_m ‖u - v‖² over the
    stretches ending more than 2 spread ticks away (and not in the start), then the quantile."""
    T = len(U)
    ends = sorted({int(e) for e in np.linspace(skip + M - 1, T - 1, 200)})
    best = []
    for e in ends:
        recent = U[e - M + 1:e + 1]
        costs = [float(np.sum((U[k - M + 1:k + 1] - recent) ** 2))
                 for k in range(max(M - 1, skip), T) if abs(k - e) > 2 * spread]
        if costs:
            best.append(min(costs))
    return float(np.quantile(best, q))


def test_max_cost_is_the_quantile_of_the_explorations_own_best_costs():
    # 260 moving ticks past the skip: more stretches than the 200 sampled, so which ends are
    # taken matters. Three noisy laps of one 150-tick loop (another lap costs noise only)
    rng = np.random.default_rng(5)
    loop = rng.uniform(0, 1, (150, 3))
    U = np.vstack([loop + rng.normal(0, 0.05, loop.shape) for _ in range(3)])[:300]
    rel = _fitted(U, skip=40, spread=6, quantile=0.7)
    assert rel.max_cost == pytest.approx(_brute_max_cost(U, 5, 6, 40, 0.7), rel=1e-12)


def test_the_last_stretch_is_among_those_sampled():
    # quantile 1: max_cost is the largest best cost. The last reading is (5, 5, 5), at least 4
    # from any other reading (all in [0, 1]) in each of its 3 values, so the last stretch costs
    # at least 3 · 4² = 48 against any other; every other stretch has a partner of readings in
    # [0, 1] costing at most 5 · 3 · 1 = 15
    U = _uniform(11, 120)
    U[-1] = 5.0
    rel = _fitted(U, spread=5, quantile=1.0)
    assert rel.max_cost >= 48.0
    U[-1] = 0.5          # an ordinary last reading: every best cost is at most 15
    assert _fitted(U, spread=5, quantile=1.0).max_cost <= 15.0


def test_a_cost_exactly_at_max_cost_is_a_match():
    # four identical laps: every stretch costs exactly 0 against its other laps, so max_cost
    # is 0, and a lap's own readings (cost 0, the same place code on every lap) are matched
    lap = _uniform(6, 60)
    U = np.vstack([lap] * 4)
    rel = _fitted(U, winners=np.tile(np.arange(60) // 20, 4), spread=5)
    assert rel.max_cost == 0.0
    assert rel.match(lap[30:35]) == 34


# --- rivals -------------------------------------------------------------------------------

@pytest.mark.parametrize("shared_at, unique", [(0, True), (105, True), (106, False),
                                               (95, True), (94, False)])
def test_a_rival_is_no_rival_exactly_within_spread_of_the_match(shared_at, unique):
    # the stretch ending at tick 100 (skip 0: tick 4 for shared_at = 0) is copied exactly to
    # the one ending at 300; the copy's place code (77) is also the code at tick `shared_at`.
    # The copy is no rival when that tick lies within spread = 5 ticks of the match's end
    # (95..105, or 0..9 for the first stretch), a rival otherwise
    U = _uniform(7)
    end = 4 if shared_at == 0 else 100
    U[296:301] = U[end - 4:end + 1]
    winners = np.arange(400) // 20
    winners[300] = winners[shared_at] = 77
    rel = _fitted(U, winners=winners, spread=5, ratio=1.0)
    assert rel.match(U[end - 4:end + 1]) == (end if unique else None)


# --- observing after a lift ---------------------------------------------------------------

def test_a_pause_just_before_the_last_reading_of_a_window_starts_it_again():
    U = _uniform(8)
    rel = _fitted(U)
    rel.start()
    assert rel.observe(U[100], True) is None
    assert rel.observe(U[100], False) is None          # a pause: the window starts again
    for u in U[101:105]:                                # 4 moving readings: no window yet
        assert rel.observe(u, True) is None
    x = rel.observe(U[105], True)                       # 5: the stretch ending at 105
    np.testing.assert_allclose(x, _reservoir().run(U[:105])[-1], atol=1e-12)
    assert rel.matched_after == 6 and rel.active is False


def test_it_gives_up_exactly_after_max_ticks():
    U = np.tile(_uniform(9, 10), (40, 1))               # a 10-tick cycle at 40 places
    rel = _fitted(U, winners=np.arange(400) // 10, max_ticks=12)
    rel.start()
    for u in U[:11]:
        assert rel.observe(u, True) is None
    assert rel.active is True                           # 11 moving ticks: still looking
    assert rel.observe(U[11], True) is None
    assert rel.active is False and rel.matched_after is None   # 12: given up


@pytest.mark.parametrize("tick", [40, 45])
def test_the_state_handed_over_is_float64_from_a_float32_reservoir(tick):
    # every = 20: tick 40 is a kept state (no re-run), tick 45 is re-run from it
    U = _uniform(10)
    rel = _fitted(U, dtype="float32", every=20)
    x = rel.state_before(tick)
    assert x.dtype == np.float64 and x.shape == (20,)
    np.testing.assert_allclose(x, _reservoir("float32").run(U[:tick])[-1], rtol=1e-5,
                               atol=1e-6)
