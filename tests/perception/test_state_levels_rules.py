"""The state layer's common scale by hand (hippo.perception.state_levels): a place's level
tanh(max(z, 0) / place_scale) with z standardised by the pooled, per-unit or no running
statistics (their updates worked out tick by tick), the leaky filter exp(-dt / smoothing), the
outlier bound PLACE_MAX on its edge and one step past, growing and shrinking vectors, and the
event states' levels with the transient's cut-off at transient_time - 1e-9."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hippo.perception.state_levels import PLACE_MAX
from hippo.perception.state_params import StateKey
from hippo.perception.states import StateLayer, StateLayerParams

DT = 0.2
OUTLIER = ("place activities must lie in [-1000, 1000], got one of magnitude {} (unit {}): no "
           "place source gives it, and it would ruin the running statistics")


def layer(n: int = 2, **kw: object) -> StateLayer:
    return StateLayer(StateLayerParams(**kw), n_place=n)


# ------------------------------------------------------------------------------- pooled
def test_pooled_levels_and_statistics_tick_by_tick():
    lay = layer(2)
    rate = DT / 300.0
    got = lay._places(np.array([1.0, 3.0]), DT)
    # prior mean 0, variance 1: z = a, level tanh(z / 2)
    assert np.allclose(got, [math.tanh(0.5), math.tanh(1.5)], rtol=0, atol=1e-15)
    m = rate * (1.0 + 3.0) / 2
    v = (1.0 - rate) * (1.0 + rate * (1.0 + 9.0) / 2)
    assert lay._pool[0] == pytest.approx(m, rel=1e-15)
    assert lay._pool[1] == pytest.approx(v, rel=1e-15)
    # the next tick is standardised by those: a = m (z 0) and m + 2 sd (z 2)
    got = lay._places(np.array([m, m + 2.0 * math.sqrt(v)]), DT)
    assert got[0] == 0.0 and got[1] == pytest.approx(math.tanh(1.0), abs=1e-14)
    d2 = 4.0 * v  # the squared deviations: 0 and (2 sd)^2
    assert lay._pool[0] == pytest.approx(m + rate * math.sqrt(v), rel=1e-14)
    assert lay._pool[1] == pytest.approx((1.0 - rate) * (v + rate * d2 / 2), rel=1e-14)


def test_negative_z_gives_level_zero_and_place_scale_divides():
    got = layer(3, place_scale=4.0)._places(np.array([-1.0, 0.0, 2.0]), DT)
    assert got.tolist()[:2] == [0.0, 0.0]
    assert got[2] == pytest.approx(math.tanh(0.5), abs=1e-15)


def test_the_rate_is_capped_at_one():
    # dt = 2 norm_tau: rate min(2, 1) = 1: the mean jumps to the tick's mean, the variance to
    # (1 - 1)(...) floored at 1e-12
    lay = layer(2, norm_tau=1.0)
    lay._places(np.array([1.0, 5.0]), 2.0)
    assert lay._pool == (3.0, 1e-12)
    lay = layer(2, norm_tau=1.0)
    lay._places(np.array([1.0, 5.0]), 1.0)
    assert lay._pool == (3.0, 1e-12)
    # dt = norm_tau / 2: rate 1/2
    lay = layer(2, norm_tau=1.0)
    lay._places(np.array([1.0, 5.0]), 0.5)
    assert lay._pool == (1.5, 0.5 * (1.0 + 0.5 * 13.0))


def test_no_place_cells_give_an_empty_level_vector():
    lay = layer(0)
    out = lay._places(None, DT)
    assert out.shape == (0,) and lay._pool == (0.0, 1.0)
    out = lay._places(np.zeros(0), DT)
    assert out.shape == (0,) and lay._pool == (0.0, 1.0)
    # no units has no outlier to name, whatever the normalisation
    for normalize in ("unit", "fixed"):
        lay = layer(0, normalize=normalize)
        assert lay._places(np.zeros(0), DT).shape == (0,)
        assert lay._places([], DT).shape == (0,)


# --------------------------------------------------------------------------- per unit
def test_unit_statistics_tick_by_tick():
    lay = layer(2, normalize="unit")
    rate = DT / 300.0
    got = lay._places(np.array([2.0, -4.0]), DT)
    assert got[0] == pytest.approx(math.tanh(1.0), abs=1e-15) and got[1] == 0.0
    assert np.allclose(lay._mean, [2.0 * rate, -4.0 * rate], rtol=1e-15, atol=0)
    var = [(1.0 - rate) * (1.0 + rate * 4.0), (1.0 - rate) * (1.0 + rate * 16.0)]
    assert np.allclose(lay._var, var, rtol=1e-15, atol=0)
    # next tick: unit 0 two of its own sd above its own mean
    a0 = lay._mean[0] + 2.0 * math.sqrt(lay._var[0])
    got = lay._places(np.array([a0, lay._mean[1]]), DT)
    assert got[0] == pytest.approx(math.tanh(1.0), abs=1e-14) and got[1] == 0.0
    assert lay._pool == (0.0, 1.0)   # the pooled statistics are not touched


def test_unit_variance_is_floored_at_1e_12():
    lay = layer(1, normalize="unit", norm_tau=1.0)
    lay._places(np.array([3.0]), 1.0)
    assert lay._mean.tolist() == [3.0] and lay._var.tolist() == [1e-12]


def test_fixed_levels_are_the_raw_activities_squashed():
    lay = layer(3, normalize="fixed", place_scale=0.5)
    got = lay._places(np.array([0.25, -3.0, 5000.0]), DT)
    assert got[0] == pytest.approx(math.tanh(0.5), abs=1e-15)
    assert got[1] == 0.0 and got[2] == 1.0
    assert lay._pool == (0.0, 1.0) and lay._mean.tolist() == [0.0, 0.0, 0.0]


# ----------------------------------------------------------------------------- smoothing
def test_the_leaky_filter_once_there_is_a_winner():
    lay = layer(2, smoothing=0.4, normalize="fixed")
    lay.winner = 0
    lay.place_activity = np.array([0.5, 0.0])
    target = np.tanh(np.array([2.0, 4.0]) / 2.0)
    k = math.exp(-DT / 0.4)
    got = lay._places(np.array([2.0, 4.0]), DT)
    assert np.allclose(got, k * np.array([0.5, 0.0]) + (1.0 - k) * target, rtol=0, atol=1e-15)
    # no winner yet: the target as it is
    lay.winner = None
    assert np.allclose(lay._places(np.array([2.0, 4.0]), DT), target, rtol=0, atol=1e-15)
    # smoothing 0: no filter
    lay = layer(2, smoothing=0.0, normalize="fixed")
    lay.winner = 0
    lay.place_activity = np.array([0.5, 0.0])
    assert np.allclose(lay._places(np.array([2.0, 4.0]), DT), target, rtol=0, atol=1e-15)


# -------------------------------------------------------------------- growing, shrinking
def test_a_vector_may_grow_and_never_shrink():
    lay = layer(2)
    lay._places(np.array([0.5, 0.5, 0.5]), DT)
    assert lay._place_ids.size == 3
    assert lay._places([0.1, 0.2, 0.3, 0.4], DT).shape == (4,)   # a list, growing
    with pytest.raises(ValueError) as exc:
        lay._places(np.array([0.5, 0.5]), DT)
    assert str(exc.value) == ("place activity vector shrank from 4 to 2 units; place states "
                              "are never removed")
    with pytest.raises(ValueError) as exc:
        lay._places(None, DT)
    assert str(exc.value) == ("place activity vector shrank from 4 to 0 units; place states "
                              "are never removed")


def test_other_shapes_and_non_finite_values_are_refused():
    with pytest.raises(ValueError) as exc:
        layer(2)._places(np.zeros((2, 2)), DT)
    assert str(exc.value) == "place activities must be a 1-D vector, got shape (2, 2)"
    with pytest.raises(ValueError) as exc:
        layer(1)._places(np.float64(0.5), DT)
    assert str(exc.value) == "place activities must be a 1-D vector, got shape ()"
    # as many values as place states, in another shape (the pooled fast path takes 1-D only)
    for normalize in ("pooled", "unit", "fixed"):
        with pytest.raises(ValueError) as exc:
            layer(4, normalize=normalize)._places(np.zeros((2, 2)), DT)
        assert str(exc.value) == "place activities must be a 1-D vector, got shape (2, 2)"
    for normalize in ("pooled", "unit", "fixed"):
        for n in (2, 1):   # the same size (the pooled fast path) and a grown one
            a = np.array([0.5, np.nan])
            with pytest.raises(ValueError) as exc:
                layer(n, normalize=normalize)._places(a, DT)
            assert str(exc.value) == "place activities contains 1 non-finite value(s) (NaN or inf)"
    with pytest.raises(ValueError) as exc, np.errstate(invalid="ignore"):
        layer(2)._places(np.array([np.inf, -np.inf]), DT)
    assert str(exc.value) == "place activities contains 2 non-finite value(s) (NaN or inf)"


# ------------------------------------------------------------------------------- outliers
def test_place_max_on_its_edge_and_one_step_past():
    assert PLACE_MAX == 1e3
    past = np.nextafter(1e3, 2e3)
    for normalize in ("pooled", "unit"):
        for n in (3, 0):   # pooled: the fast path (same size) and the checked one (growing)
            for a in ([1e3, 0.0, -1e3], [1e3, 1e3, 1e3], [-1e3, -1e3, 0.0]):
                layer(n, normalize=normalize)._places(np.array(a), DT)
            with pytest.raises(ValueError) as exc:
                layer(n, normalize=normalize)._places(np.array([0.0, 0.0, -past]), DT)
            assert str(exc.value) == OUTLIER.format("1e+03", 2)
            with pytest.raises(ValueError) as exc:
                layer(n, normalize=normalize)._places(np.array([-2500.0, 7.0, 0.0]), DT)
            assert str(exc.value) == OUTLIER.format("2.5e+03", 0)
    # raw ("fixed") activities keep no statistics: any finite value
    assert layer(1, normalize="fixed")._places(np.array([1e6]), DT).tolist() == [1.0]


def test_the_pooled_bound_counts_the_running_mean():
    # mean 400: a = [1000] deviates by 600 (sqrt(sq) = 600 <= 1000 - 400) and passes; a = [1001]
    # is past the bound and refused by the exact check
    lay = layer(1)
    lay._pool = (400.0, 1.0)
    lay._places(np.array([1000.0]), DT)
    lay._pool = (400.0, 1.0)
    with pytest.raises(ValueError) as exc:
        lay._places(np.array([1001.0]), DT)
    assert str(exc.value) == OUTLIER.format("1e+03", 0)
    # a negative mean counts by its magnitude: mean -400, a = 999: d = 1399
    lay._pool = (-400.0, 1.0)
    lay._places(np.array([999.0]), DT)


def test_finite_activities_whose_sum_overflows_are_refused_as_outliers():
    with pytest.raises(ValueError) as exc, np.errstate(over="ignore"):
        layer(2)._places(np.array([1e308, 1e308]), DT)
    assert str(exc.value) == OUTLIER.format("1e+308", 0)


# ----------------------------------------------------------------------------- event levels
def _event(lay: StateLayer, kind: str, index: int | None = None) -> int:
    return lay._register(StateKey(kind, index, None))


def test_event_levels_follow_their_inputs():
    lay = layer(0, transient=())
    snd, col2, still, mov = (_event(lay, "sound"), _event(lay, "colour", 2),
                             _event(lay, "still"), _event(lay, "moving"))
    assert lay._event_level(snd, True, None, None) == 1.0
    assert lay._event_level(snd, False, 2, True) == 0.0
    assert lay._event_level(col2, False, 2, None) == 1.0
    assert lay._event_level(col2, True, 3, None) == 0.0
    assert lay._event_level(col2, True, None, None) == 0.0
    assert lay._event_level(still, False, None, False) == 1.0
    # not sensed (None) is neither still nor moving
    assert lay._event_level(still, False, None, None) == 0.0
    assert lay._event_level(still, False, None, True) == 0.0
    assert lay._event_level(mov, False, None, True) == 1.0
    assert lay._event_level(mov, False, None, None) == 0.0
    assert lay._event_level(mov, False, None, False) == 0.0


def test_a_transient_state_is_on_until_transient_time_minus_1e_9():
    lay = layer(0)   # moving is transient, for 1.0 s
    mov = _event(lay, "moving")
    lay._onset_t[mov] = 2.0
    lay.t = 2.0
    assert lay._event_level(mov, False, None, True) == 1.0
    lay.t = 2.0 + 0.999999998          # 2e-9 s short of 1 s: still on
    assert lay._event_level(mov, False, None, True) == 1.0
    lay.t = 3.0                        # at 1 s: off (and 1 s - 1e-9 is off too)
    assert lay._event_level(mov, False, None, True) == 0.0
    lay._onset_t[mov] = 0.0
    lay.t = 1.0 - 1e-9                 # exactly transient_time - 1e-9 after the onset: off
    assert lay._event_level(mov, False, None, True) == 0.0
    lay.t = 1.0 - 2e-9
    assert lay._event_level(mov, False, None, True) == 1.0
    # no onset recorded: off
    del lay._onset_t[mov]
    assert lay._event_level(mov, False, None, True) == 0.0
    # an input that is off stays off whatever the onset
    lay._onset_t[mov] = 2.0
    assert lay._event_level(mov, False, None, False) == 0.0
    # a kind not listed as transient stays on
    snd = _event(lay, "sound")
    lay.t = 100.0
    assert lay._event_level(snd, True, None, None) == 1.0


def test_transient_time_and_kinds_are_the_parameters():
    lay = layer(0, transient=("sound",), transient_time=0.5)
    snd, mov = _event(lay, "sound"), _event(lay, "moving")
    lay._onset_t[snd] = 0.0
    lay.t = 0.4
    assert lay._event_level(snd, True, None, None) == 1.0
    lay.t = 0.5
    assert lay._event_level(snd, True, None, None) == 0.0
    # moving is no longer transient
    assert lay._event_level(mov, False, None, True) == 1.0
