"""Sequence matching that re-anchors the reservoir after a lift (hippo.perception.relocate)."""

import numpy as np
import pytest

from hippo.perception.relocate import RelocaliserParams, SequenceRelocaliser
from hippo.perception.reservoir import Reservoir
from hippo.perception.reservoir_params import ReservoirParams


def _reservoir() -> Reservoir:
    return Reservoir(ReservoirParams(n_inputs=3, n_neurons=20, leak=(0.1, 0.3), seed=1),
                     dtype="float64")


def _fitted(U, winners=None, moving=None, **kw):
    T = len(U)
    winners = np.arange(T) // 20 if winners is None else winners   # a new place every 20 ticks
    moving = np.ones(T, bool) if moving is None else moving
    kw.setdefault("skip", 0)
    return SequenceRelocaliser(RelocaliserParams(**kw)).fit(_reservoir(), winners, U, moving)


def _feed(rel, U, moving=True):
    """Feed readings until the relocaliser answers; (state, ticks fed)."""
    for i, u in enumerate(U):
        x = rel.observe(u, moving)
        if x is not None:
            return x, i + 1
    return None, len(U)


def test_a_stretch_of_the_exploration_is_found_and_the_state_before_it_returned():
    U = np.random.default_rng(0).uniform(0, 1, (400, 3))
    rel = _fitted(U, every=50)
    rel.start()
    x, n = _feed(rel, U[237:260])
    assert n == 5 and rel.matched_after == 5 and not rel.active
    # the match ends at tick 241; the state to jump to is the one after tick 240, which this
    # tick's reading then moves on
    expected = _reservoir().run(U[:241])[-1]
    np.testing.assert_allclose(x, expected, atol=1e-12)


@pytest.mark.parametrize("tick", [0, 1, 49, 50, 51, 99, 100, 399])
def test_the_state_before_a_tick_equals_the_full_run_across_kept_states(tick):
    U = np.random.default_rng(1).uniform(0, 1, (400, 3))
    rel = _fitted(U, every=50)
    expected = np.zeros(20) if tick == 0 else _reservoir().run(U[:tick])[-1]
    np.testing.assert_allclose(rel.state_before(tick), expected, atol=1e-12)


def test_a_stretch_seen_at_two_places_is_refused_until_the_readings_tell_them_apart():
    rng = np.random.default_rng(2)
    U = rng.uniform(0, 1, (400, 3))
    U[300:308] = U[100:108]          # one stretch of 8 readings at two places
    rel = _fitted(U)
    rel.start()
    x, n = _feed(rel, U[100:120])
    # windows inside the shared stretch (ending at ticks 104-107) are ambiguous: the match is
    # taken at the first window that reaches past it
    assert x is not None and n == 9
    np.testing.assert_allclose(x, _reservoir().run(U[:108])[-1], atol=1e-12)


def test_the_same_stretch_on_another_lap_of_the_same_place_is_no_rival():
    rng = np.random.default_rng(3)
    lap = rng.uniform(0, 1, (100, 3))
    U = np.vstack([lap, lap + 1e-3, lap - 1e-3])      # three laps, nearly the same readings
    winners = np.tile(np.arange(100) // 20, 3)         # and the same place code each lap
    rel = _fitted(U, winners=winners)
    rel.start()
    x, n = _feed(rel, lap[40:60])
    assert n == 5 and x is not None


def test_an_ambiguous_stream_gives_up_after_max_ticks():
    U = np.tile(np.random.default_rng(4).uniform(0, 1, (10, 3)), (40, 1))  # a 10-tick cycle
    rel = _fitted(U, winners=np.arange(400) // 10, max_ticks=30)   # ... at 40 places
    rel.start()
    x, _n = _feed(rel, U[:40])
    assert x is None and not rel.active and rel.matched_after is None
    assert rel.observe(U[0], True) is None


def test_a_pause_starts_the_window_again():
    U = np.random.default_rng(5).uniform(0, 1, (400, 3))
    rel = _fitted(U)
    rel.start()
    for u in U[200:204]:
        assert rel.observe(u, True) is None
    assert rel.observe(U[204], False) is None      # standing still: not part of a window
    _x, n = _feed(rel, U[205:230])
    assert n == 5 and rel.matched_after == 9


def test_pauses_of_the_exploration_are_left_out_of_the_template():
    U = np.random.default_rng(6).uniform(0, 1, (400, 3))
    moving = np.ones(400, bool)
    moving[150:170] = False                         # a pause in the exploration
    rel = _fitted(U, moving=moving)
    rel.start()
    # the robot's own readings run straight through where the exploration paused
    x, n = _feed(rel, np.vstack([U[146:150], U[170:190]]))
    assert n == 5
    np.testing.assert_allclose(x, _reservoir().run(U[:170])[-1], atol=1e-12)


def test_nothing_happens_before_a_lift():
    U = np.random.default_rng(7).uniform(0, 1, (400, 3))
    rel = _fitted(U)
    assert not rel.active and rel.observe(U[10], True) is None


@pytest.mark.parametrize("kw", [dict(window=0), dict(ratio=0.5), dict(spread=1.5),
                                dict(max_ticks=3, window=5), dict(every=0)])
def test_impossible_parameters_are_refused(kw):
    with pytest.raises(ValueError):
        RelocaliserParams(**kw)


def test_bad_exploration_is_refused():
    U = np.random.default_rng(8).uniform(0, 1, (400, 3))
    with pytest.raises(ValueError, match="moving ticks"):
        _fitted(U, moving=np.zeros(400, bool))
    with pytest.raises(ValueError, match="winners"):
        _fitted(U, winners=np.zeros(10))
    bad = U.copy()
    bad[3, 1] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        _fitted(bad)


def test_the_start_from_rest_is_never_matched():
    U = np.random.default_rng(9).uniform(0, 1, (400, 3))
    rel = _fitted(U, skip=100, ratio=1.0)
    assert _fitted(U, ratio=1.0).match(U[60:65]) == 64     # found without the skip ...
    for a in range(0, 95, 5):                               # ... never inside it with it
        k = rel.match(U[a:a + 5])
        assert k is None or k >= 100
    rel.start()
    x, n = _feed(rel, U[150:160])
    assert n == 5 and x is not None


def test_learned_place_cells_jump_after_a_lift_to_the_exploration_state():
    from hippo.perception.place_cells import RCSFAICA
    from hippo.places import LearnedPlaceCells
    from hippo.types import Observation

    rng = np.random.default_rng(10)
    U = rng.uniform(0, 1, (600, 8))
    model = RCSFAICA(n_reservoir=40, n_sfa=3, n_ica=3, seed=1, ica_restarts=1).fit(U)
    rel = SequenceRelocaliser(RelocaliserParams(skip=50)).fit(
        model.reservoir_, np.arange(600) // 20, U, np.ones(600, bool))
    cells = LearnedPlaceCells(model, relocaliser=rel)
    expected = model.transform(U)          # from rest, along the exploration

    def obs(u, moving=True):
        return Observation(tick=0, t=0.0, ir=u, floor=0, sound=False, odometry=(1.0, 0.0, 0.0),
                           moving=moving)

    cells.prime(rng.uniform(0, 1, (100, 8)))     # a memory of somewhere else
    for u in U[300:305]:                         # no lift: the memory stays
        assert not np.allclose(cells.step(obs(u)), expected[U.tolist().index(u.tolist())])
    cells.lifted()
    out = [cells.step(obs(u)) for u in U[400:410]]
    assert cells.anchored is False and rel.matched_after == 5
    # from the jump on (the 5th reading), the cells give what they gave while exploring
    np.testing.assert_allclose(out[4:], expected[404:410], atol=1e-5)
    assert not np.allclose(out[3], expected[403], atol=1e-3)
    cells.reset()
    assert not rel.active


def test_readings_unlike_any_explored_are_no_match_however_unique():
    rng = np.random.default_rng(11)
    lap = rng.uniform(0, 1, (100, 3))
    U = np.vstack([lap + rng.normal(0, 0.01, lap.shape) for _ in range(5)])   # five laps
    rel = _fitted(U, winners=np.tile(np.arange(100) // 20, 5))
    # a true match costs what the laps cost against each other: noise, 5 x 3 x 2 x 1e-4
    assert 1e-4 < rel.max_cost < 1e-2
    rel.start()
    assert _feed(rel, lap[30:60] + 0.3)[0] is None      # every reading 0.3 off
    rel.start()
    assert _feed(rel, lap[30:60])[1] == 5               # the lap itself is found at once



def test_the_brain_starts_the_match_only_when_the_robot_was_moved():
    from hippo.brain import Brain
    from hippo.perception.place_cells import RCSFAICA
    from hippo.places import LearnedPlaceCells

    U = np.random.default_rng(13).uniform(0, 1, (600, 8))
    model = RCSFAICA(n_reservoir=40, n_sfa=3, n_ica=3, seed=1, ica_restarts=1).fit(U)
    rel = SequenceRelocaliser(RelocaliserParams(skip=50)).fit(
        model.reservoir_, np.arange(600) // 20, U, np.ones(600, bool))
    brain = Brain(LearnedPlaceCells(model, relocaliser=rel))
    brain.lifted(moved=False)              # put back where it was: nothing to find
    assert not rel.active
    brain.lifted(keep_drives=True)         # a kidnap
    assert rel.active


def test_a_model_with_state_beyond_the_reservoir_is_refused():
    from hippo.perception.place_cells import RCSFAICA
    from hippo.places import LearnedPlaceCells

    U = np.random.default_rng(14).uniform(0, 1, (600, 8))
    model = RCSFAICA(n_reservoir=40, n_sfa=3, n_ica=3, seed=1, ica_restarts=1,
                     slow_pool=20.0).fit(U)
    rel = SequenceRelocaliser(RelocaliserParams(skip=50)).fit(
        model.reservoir_, np.arange(600) // 20, U, np.ones(600, bool))
    with pytest.raises(ValueError, match="slow pool"):
        LearnedPlaceCells(model, relocaliser=rel)
    with pytest.raises(TypeError, match="SequenceRelocaliser"):
        LearnedPlaceCells(model, relocaliser=object())
