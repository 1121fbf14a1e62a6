"""State layer: hysteresis against flicker, salient events, conjunctive states, bad input."""

import math

import numpy as np
import pytest

from hippo.perception.states import StateKey, StateLayer, StateLayerParams

DT = 0.2


def test_common_scale_by_hand():
    fixed = StateLayer(StateLayerParams(normalize="fixed", place_scale=2.0, smoothing=0.0))
    fixed.step(np.array([1.0, -3.0, 4.0]), dt=DT)
    assert fixed.place_activity == pytest.approx([math.tanh(0.5), 0.0, math.tanh(2.0)])
    # per unit: z = (a - mean) / sqrt(var) with the prior mean 0, var 1; then the EMA update
    unit = StateLayer(StateLayerParams(normalize="unit", norm_tau=2.0, smoothing=0.0))
    unit.step(np.array([3.0]), dt=DT)
    assert unit.place_activity[0] == pytest.approx(math.tanh(3.0 / 2.0))
    unit.step(np.array([3.0]), dt=DT)  # mean 0.1*3 = 0.3, var 0.9*(1 + 0.1*9) = 1.71
    assert unit.place_activity[0] == pytest.approx(math.tanh((3.0 - 0.3) / math.sqrt(1.71) / 2))
    # pooled: one mean and variance for the population: after [3, 1] mean 0.2, var 1.35
    pooled = StateLayer(StateLayerParams(norm_tau=2.0, smoothing=0.0))
    pooled.step(np.array([3.0, 1.0]), dt=DT)
    pooled.step(np.array([3.0, 1.0]), dt=DT)
    z = (np.array([3.0, 1.0]) - 0.2) / math.sqrt(0.9 * (1.0 + 0.1 * 5.0))
    assert pooled.place_activity == pytest.approx(np.tanh(z / 2))
    # the leaky place neuron: x <- k x + (1 - k) target, k = exp(-dt / smoothing)
    leaky = StateLayer(StateLayerParams(normalize="fixed", smoothing=0.4))
    leaky.step(np.array([0.0]), dt=DT)
    leaky.step(np.array([2.0]), dt=DT)
    assert leaky.place_activity[0] == pytest.approx((1 - math.exp(-0.5)) * math.tanh(1.0))


def test_noisy_place_cells_do_not_flicker():
    rng = np.random.default_rng(0)
    layer = StateLayer()
    base = np.array([2.0, 1.8, 0.0, 0.0])  # two overlapping place fields, very noisy
    naive, changes = [], 0
    for _ in range(1000):
        x = base + 0.4 * rng.standard_normal(4)
        ev = layer.step(x, moving=True, dt=DT)
        changes += ev.changed
        naive.append(int(np.argmax(x)))
    naive_switches = int(np.count_nonzero(np.diff(naive)))
    assert naive_switches > 300
    assert changes == 1  # the first winner, then no switch in 200 s


def test_clear_change_switches_within_hold_time():
    rng = np.random.default_rng(1)
    layer = StateLayer()
    for _ in range(50):
        layer.step(np.array([2.5, 0.0, 0.0]) + 0.2 * rng.standard_normal(3), moving=True, dt=DT)
    first = layer.winner
    ticks = 0
    while layer.winner == first:
        ev = layer.step(np.array([0.0, 2.5, 0.0]) + 0.2 * rng.standard_normal(3),
                        moving=True, dt=DT)
        ticks += 1
        assert ticks <= math.ceil(layer.params.hold_time / DT) + 1  # + the leaky rise
    assert ev.changed and ev.previous == first and layer.describe(ev.winner) == "place 1"
    assert ev.since == pytest.approx(ev.t)


def test_event_states_win_at_once_and_carry_context():
    layer = StateLayer()
    place = np.array([3.0, 0.0])
    for _ in range(5):
        layer.step(place, moving=True, dt=DT)
    p0 = layer.find("place", 0)
    ev = layer.step(place, moving=False, dt=DT)  # the robot stops: salient, immediate
    assert ev.changed and layer.key(ev.winner) == StateKey("still", None, p0)
    assert layer.describe(ev.winner) == "still@place 0"
    still = ev.winner
    for _ in range(30):  # standing still, noisy places cannot take over
        assert not layer.step(place + 0.5, moving=False, dt=DT).changed
    ev = layer.step(place, sound=True, moving=False, dt=DT)
    assert ev.changed and ev.previous == still and layer.describe(ev.winner) == "sound"
    # the sound is one tick long: then a place takes over after the hold time
    evs = [layer.step(place, moving=False, dt=DT) for _ in range(4)]
    assert [e.changed for e in evs] == [False, False, True, False]
    assert evs[2].winner == p0
    # moving is transient: after its onset it yields to the places
    ev = layer.step(np.array([0.0, 3.0]), moving=True, dt=DT)
    assert layer.describe(ev.winner) == "moving@place 0"
    names = [layer.describe(layer.step(np.array([0.0, 3.0]), moving=True, dt=DT).winner)
             for _ in range(12)]
    assert names[3] == "moving@place 0" and names[-1] == "place 1"
    # still at another place is another state
    ev = layer.step(np.array([0.0, 3.0]), moving=False, dt=DT)
    assert ev.winner != still and layer.describe(ev.winner) == "still@place 1"


def test_floor_colour_is_a_salient_context():
    layer = StateLayer()
    layer.step(np.array([2.0]), colour=0, moving=True, dt=DT)
    ev = layer.step(np.array([2.0]), colour=3, moving=True, dt=DT)
    assert ev.changed and layer.describe(ev.winner) == "colour 3"
    for _ in range(10):  # on the colour, places cannot beat it
        assert not layer.step(np.array([3.0]), colour=3, moving=True, dt=DT).changed
    ev = layer.step(np.array([3.0]), colour=3, moving=False, dt=DT)
    assert layer.describe(ev.winner) == "still@colour 3"


def test_first_tick_and_recruitment():
    layer = StateLayer(n_place=2)
    assert layer.n_states == 2
    ev = layer.step(np.array([0.1, 0.1]), dt=DT)
    assert ev.changed and ev.previous is None and ev.novel and ev.t == 0.0
    ev = layer.step(np.array([0.1, 0.1, 4.0]), dt=DT)  # a new place cell is recruited
    assert layer.n_states == 3 and layer.key(2) == StateKey("place", 2)
    assert not ev.novel
    sid = layer.recruit("place", 5)
    assert layer.key(sid) == StateKey("place", 5) and layer.n_states == 6
    assert layer.recruit("colour", 2) == layer.find("colour", 2)
    only_moving = StateLayer()
    assert only_moving.describe(only_moving.step(moving=False, dt=DT).winner) == "still"
    layer.reset(keep_states=True)
    assert layer.n_states == 7 and layer.winner is None
    layer.reset()
    assert layer.n_states == 2


def test_bad_input_is_named():
    layer = StateLayer()
    with pytest.raises(ValueError, match="place activities"):
        layer.step(np.array([1.0, np.nan]), dt=DT)
    with pytest.raises(ValueError, match="dt"):
        layer.step(np.ones(2), dt=-DT)
    with pytest.raises(ValueError, match="dt"):
        layer.step(np.ones(2), dt=float("nan"))
    layer.step(np.ones(2), dt=DT)
    with pytest.raises(ValueError, match="shrank"):
        layer.step(np.ones(1), dt=DT)
    with pytest.raises(ValueError, match="unknown state id 42"):
        layer.describe(42)
    with pytest.raises(ValueError, match="unknown state"):
        layer.find("colour", 9)
    with pytest.raises(ValueError, match="colour"):
        layer.step(np.ones(2), colour=1.5, dt=DT)
    with pytest.raises(ValueError, match="sound"):
        layer.step(np.ones(2), sound=float("nan"), dt=DT)
    with pytest.raises(ValueError, match="moving"):
        layer.step(np.ones(2), moving=0.5, dt=DT)
    with pytest.raises(ValueError, match="nothing to compete"):
        StateLayer().step(dt=DT)
    with pytest.raises(ValueError, match="kind"):
        layer.recruit("smell")
    with pytest.raises(ValueError, match="margin"):
        StateLayerParams(margin=2.0)


def test_without_a_moving_state_resuming_returns_to_the_context():
    layer = StateLayer(StateLayerParams(events=("sound", "colour", "still"),
                                        priority=("sound", "still", "colour", "moving")))
    place = np.array([3.0, 0.0])
    layer.step(place, moving=True, dt=DT)
    still = layer.step(place, moving=False, dt=DT).winner
    ev = layer.step(place, moving=True, dt=DT)  # resumes: still@place 0 -> place 0 at once
    assert ev.changed and ev.previous == still and layer.describe(ev.winner) == "place 0"
    # priority: still before colour when both start at one tick
    ev = layer.step(place, colour=2, moving=False, dt=DT)
    assert layer.describe(ev.winner) == "still@place 0"
    with pytest.raises(ValueError, match="priority"):
        StateLayerParams(priority=("sound",))


def test_colour_takes_the_win_back_when_a_transient_event_ends_on_it():
    layer = StateLayer(n_place=3)
    acts = np.array([0.0, 3.0, 0.0])
    layer.step(acts, colour=0, moving=True, dt=0.2)
    colour = layer.step(acts, colour=1, moving=True, dt=0.2).winner
    assert layer.key(colour).kind == "colour"
    sound = layer.step(acts, colour=1, sound=True, moving=True, dt=0.2).winner
    assert layer.key(sound).kind == "sound"
    ev = layer.step(acts, colour=1, sound=False, moving=True, dt=0.2)
    assert ev.changed and ev.winner == colour
    for _ in range(10):  # a strong place cell does not displace the colour while it is on
        assert layer.step(acts, colour=1, moving=True, dt=0.2).winner == colour
    ev = layer.step(acts, colour=0, moving=True, dt=0.2)
    for _ in range(6):
        ev = layer.step(acts, colour=0, moving=True, dt=0.2)
    assert layer.key(ev.winner) == ("place", 1, None)


def test_leaving_the_coloured_floor_hands_over_to_the_most_active_place():
    layer = StateLayer(n_place=3)
    weak = np.array([0.05, 0.0, 0.02])  # weak place cells: none beats a silent colour by margin
    layer.step(weak, colour=0, moving=True, dt=0.2)
    colour = layer.step(weak, colour=2, moving=True, dt=0.2).winner
    assert layer.key(colour) == ("colour", 2, None)
    ev = layer.step(weak, colour=0, moving=True, dt=0.2)
    assert ev.changed and layer.key(ev.winner).kind == "place"
    # the most active one: place 2 when it is the strongest
    layer.step(np.array([0.0, 0.01, 0.05]), colour=3, moving=True, dt=0.2)
    ev = layer.step(np.array([0.0, 0.01, 0.05]), colour=0, moving=True, dt=0.2)
    assert layer.key(ev.winner) == ("place", 2, None)


def _drive_to(layer, acts, ticks, moving=True):
    ev = None
    for _ in range(ticks):
        ev = layer.step(np.asarray(acts, float), moving=moving, dt=DT)
    return ev


def test_a_brief_place_before_a_stop_is_not_its_context():
    layer = StateLayer(StateLayerParams(context_time=1.0))
    _drive_to(layer, [3.0, 0.0, 0.0], 10)
    p0 = layer.find("place", 0)
    # place 1 wins (after the hold time) and the robot stops 0.6 s later: still@place 0
    ev = _drive_to(layer, [0.0, 3.0, 0.0], 4)
    assert layer.describe(ev.winner) == "place 1" and ev.since == pytest.approx(ev.t)
    _drive_to(layer, [0.0, 3.0, 0.0], 2)
    ev = layer.step(np.array([0.0, 3.0, 0.0]), moving=False, dt=DT)
    assert layer.key(ev.winner) == StateKey("still", None, p0)
    # a place that has held the win for context_time is the context of the next stop
    _drive_to(layer, [0.0, 0.0, 3.0], 2)            # moving@place 0, then place 2
    ev = _drive_to(layer, [0.0, 0.0, 3.0], 12)
    assert layer.describe(ev.winner) == "place 2"
    ev = layer.step(np.array([0.0, 0.0, 3.0]), moving=False, dt=DT)
    assert layer.describe(ev.winner) == "still@place 2"


def test_without_context_time_the_latest_place_is_the_context():
    layer = StateLayer()  # context_time 0: the default, HIREL's rule
    _drive_to(layer, [3.0, 0.0], 10)
    _drive_to(layer, [0.0, 3.0], 4)
    ev = layer.step(np.array([0.0, 3.0]), moving=False, dt=DT)
    assert layer.describe(ev.winner) == "still@place 1"


def test_colour_binds_at_once_even_with_context_time():
    layer = StateLayer(StateLayerParams(context_time=5.0))
    _drive_to(layer, [3.0], 10)
    layer.step(np.array([3.0]), colour=2, moving=True, dt=DT)
    ev = layer.step(np.array([3.0]), colour=2, moving=False, dt=DT)
    assert layer.describe(ev.winner) == "still@colour 2"


def test_bind_context_names_the_next_stop():
    layer = StateLayer(StateLayerParams(context_time=1.0))
    _drive_to(layer, [3.0, 0.0], 10)
    _drive_to(layer, [0.0, 3.0], 12)  # place 1 is now the context
    p0, p1 = layer.find("place", 0), layer.find("place", 1)
    layer.bind_context(p0)            # the agent stops *for* place 0
    ev = layer.step(np.array([0.0, 3.0]), moving=False, dt=DT)
    assert layer.key(ev.winner) == StateKey("still", None, p0)
    with pytest.raises(ValueError, match="only a place or colour"):
        layer.bind_context(ev.winner)
    with pytest.raises(ValueError, match="unknown state id"):
        layer.bind_context(99)
    assert p1 != p0
    with pytest.raises(ValueError, match="context_time"):
        StateLayerParams(context_time=-1.0)


def _one_hot_laps(layer, n, rng, routes, n_laps, ticks=10, dt=0.2):
    """Drive ``layer`` with one-hot activities of ``n`` place cells along random routes;
    return, per stay, (unit, winner at the end of the stay)."""
    out = []
    for _ in range(n_laps):
        for unit in routes[int(rng.integers(len(routes)))]:
            a = np.zeros(n)
            a[unit] = 1.0
            for _ in range(ticks):
                ev = layer.step(a, moving=True, dt=dt)
            out.append((unit, ev.winner))
    return out


def test_context_states_split_a_shared_stretch_by_the_way_in():
    from hippo.perception.contexts import ContextParams

    # units: 0 A, 1 B, 2-4 the shared stretch C1-C3, 5 D, 6 E, 7 H
    layer = StateLayer(StateLayerParams(normalize="fixed", place_scale=0.5,
                                        contexts=ContextParams()), n_place=8)
    stays = _one_hot_laps(layer, 8, np.random.default_rng(0), [(0, 2, 3, 4, 5, 7),
                                                            (1, 2, 3, 4, 6, 7)], 80)
    late = stays[len(stays) // 2:]
    at_c3 = {}
    for k, (unit, winner) in enumerate(late[1:], 1):
        if unit == 4:
            at_c3.setdefault(late[k - 3][0], set()).add(winner)  # the route's entry
    assert set(at_c3) == {0, 1}
    (via_a,), (via_b,) = at_c3[0], at_c3[1]
    assert via_a != via_b                                   # two states for one place cell
    assert layer.key(via_a) == layer.key(via_b) == ("place", 4, None)
    assert layer.clone(via_a) is not None and "|" in layer.describe(via_a)
    assert layer.clone(layer.find("place", 4)) is None
    # C1 and C2 need no split: one state each
    assert len({w for u, w in late if u == 2}) == 1
    # the first state of C3 (before the split) lives on as one of the two: what the map
    # learned about it carries over
    first_c3 = next(w for u, w in stays if u == 4)
    assert first_c3 in (via_a, via_b)


def test_context_states_merge_place_cells_that_take_turns():
    from hippo.perception.contexts import ContextParams

    # units: 0 H, 1 A, 2 and 3 take turns on one stretch, 4 D
    layer = StateLayer(StateLayerParams(normalize="fixed", place_scale=0.5,
                                        contexts=ContextParams()), n_place=5)
    stays = _one_hot_laps(layer, 5, np.random.default_rng(1), [(0, 1, 2, 4), (0, 1, 3, 4)], 80)
    late = stays[len(stays) // 2:]
    assert len({w for u, w in late if u in (2, 3)}) == 1    # one state for both cells
    assert layer.contexts.same(2) == layer.contexts.same(3)
    # without contexts: two states
    plain = StateLayer(StateLayerParams(normalize="fixed", place_scale=0.5), n_place=5)
    stays = _one_hot_laps(plain, 5, np.random.default_rng(1), [(0, 1, 2, 4), (0, 1, 3, 4)], 20)
    assert len({w for u, w in stays if u in (2, 3)}) == 2


def test_the_pooled_variance_is_an_average_that_falls_below_its_prior():
    # rate = dt / norm_tau = 0.5; a quiet population ([0.1, 0.1]) pulls the variance from the
    # prior 1 towards its own spread: m1 = 0.05, v1 = 0.5 (1 + 0.5 * 0.01) = 0.5025, and the
    # second tick is standardised by them
    layer = StateLayer(StateLayerParams(norm_tau=0.4, smoothing=0.0))
    a = np.array([0.1, 0.1])
    layer.step(a, dt=DT)
    layer.step(a, dt=DT)
    z = (0.1 - 0.05) / math.sqrt(0.5025)
    assert layer.place_activity == pytest.approx(np.tanh([z, z] / np.float64(2.0)))


def test_a_reset_that_keeps_the_states_restarts_the_normalisation():
    for normalize in ("unit", "pooled"):
        p = StateLayerParams(normalize=normalize, norm_tau=1.0, smoothing=0.0)
        used, fresh = StateLayer(p), StateLayer(p)
        for a in ([5.0, 0.0], [4.0, 1.0], [5.0, 0.5]):
            used.step(np.array(a), dt=DT)
        used.reset(keep_states=True)
        assert used.states == [StateKey("place", 0, None), StateKey("place", 1, None)]
        a = np.array([2.0, 0.5])
        used.step(a, dt=DT)
        fresh.step(a, dt=DT)
        np.testing.assert_array_equal(used.place_activity, fresh.place_activity)


def test_the_first_tick_goes_to_the_strongest_input():
    layer = StateLayer()
    assert layer.key(layer.step(np.array([0.1, 0.9, 0.3]), dt=DT).winner) == (
        StateKey("place", 1, None))
    moving = StateLayer()  # no place cells, no floor, no sound: proprioception alone
    assert moving.key(moving.step(None, moving=True, dt=DT).winner) == (
        StateKey("moving", None, None))
    still = StateLayer()
    assert still.key(still.step(None, moving=False, dt=DT).winner) == (
        StateKey("still", None, None))


def test_a_winning_colour_is_fully_active_while_perceived():
    layer = StateLayer()
    layer.step(np.array([0.1, 0.9]), dt=DT)
    ev = layer.step(np.array([0.1, 0.9]), colour=2, dt=DT)
    assert layer.key(ev.winner) == StateKey("colour", 2, None)
    assert layer.activity[ev.winner] == 1.0


def test_recruit_keeps_the_context_of_a_conjunctive_state():
    layer = StateLayer()
    place = layer.recruit("place", 4)
    sid = layer.recruit("still", None, context=place)
    assert layer.key(sid) == StateKey("still", None, place)
    assert layer.find("still", None, place) == sid
    with pytest.raises(ValueError, match="never seen"):
        layer.find("still")  # "still" without a context is another state


def test_context_params_reach_the_context_states():
    from hippo.perception.contexts import ContextParams

    cp = ContextParams(min_count=9, max_depth=2)
    assert StateLayer(StateLayerParams(contexts=cp)).contexts.params == cp


def test_activity_is_each_ticks_levels_however_late_it_is_read():
    """``activity`` (built only when read) is the dict of that tick: the place states'
    levels and the winner's own; read after a later step it is the later tick's, never a
    stale one, and a dict written in (a restored snapshot) is what is read."""
    layer = StateLayer()
    rng = np.random.default_rng(1)
    for t in range(60):
        acts = rng.random(4)
        ev = layer.step(acts, colour=2 if 20 <= t < 30 else 0, dt=DT)
        if t % 3:
            continue  # not read on every tick: the next read must still be this tick's
        want = dict(zip(layer._place_ids.tolist(), layer.place_activity.tolist()))
        if layer.key(ev.winner).kind == "colour":
            want[ev.winner] = 1.0
        assert layer.activity == want
        assert layer.activity is layer.activity  # built once per tick
    layer.activity = {7: 0.5}
    assert layer.activity == {7: 0.5}


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_place_activities_are_refused_wherever_they_sit(bad: float):
    """With pooled normalisation a float64 vector of the known size is checked by the pooled
    mean's own sum: a NaN or inf at any position is refused with the checker's message and
    leaves the layer as it was (the next good tick gives what it gives without the bad one)."""
    rng = np.random.default_rng(3)
    good = [rng.random(5) for _ in range(6)]
    for pos in range(5):
        layer, clean = StateLayer(), StateLayer()
        for a in good[:3]:
            layer.step(a, dt=DT)
            clean.step(a, dt=DT)
        a = good[3].copy()
        a[pos] = bad
        with pytest.raises(ValueError, match="place activities contains 1 non-finite"):
            layer.step(a, dt=DT)
        assert layer._pool == clean._pool
        for a in good[4:]:
            assert layer.step(a, dt=DT) == clean.step(a, dt=DT)
            np.testing.assert_array_equal(layer.place_activity, clean.place_activity)
        grown = np.append(good[3], bad)  # a vector that grows is checked before it grows
        with pytest.raises(ValueError, match="non-finite"):
            layer.step(grown, dt=DT)
        assert layer._place_ids.size == 5
    big = StateLayer()
    big.step(np.full(3, 0.5), dt=DT)
    with np.errstate(all="ignore"), pytest.raises(ValueError, match="magnitude 1e"):
        big.step(np.full(3, 1e308), dt=DT)  # finite values whose sum overflows: out of range


def test_a_huge_raw_place_activity_does_no_lasting_harm():
    """With raw activities (``fixed``) no statistics are kept: a spike of 1e6 saturates its
    state for a tick, and the next place wins as soon as the spike is gone."""
    layer = StateLayer(StateLayerParams(normalize="fixed"), n_place=3)
    for _ in range(20):
        layer.step(np.array([1.0, 0.0, 0.0]), dt=DT)
    layer.step(np.array([1e6, 0.0, 0.0]), dt=DT)
    for _ in range(50):
        layer.step(np.array([0.0, 1.0, 0.0]), dt=DT)
    assert layer.winner == layer.find("place", 1)


@pytest.mark.parametrize("normalize", ["pooled", "unit"])
def test_one_huge_place_activity_is_refused_and_cannot_freeze_the_winner(normalize: str):
    """Every place source gives activities far below PLACE_MAX in magnitude (cells in [0, 1],
    unit-variance ICA units); one finite outlier of 1e6 used to ruin the pooled statistics so
    that the winner never changed again. It is refused, the layer left as it was."""
    layer = StateLayer(StateLayerParams(normalize=normalize), n_place=3)
    for _ in range(20):
        layer.step(np.array([1.0, 0.0, 0.0]), dt=DT)
    pool = layer._pool
    in_range = r"place activities must lie in \[-1000, 1000\]"
    for bad in (1e6, -1e6, 1e200):
        with np.errstate(over="ignore"), pytest.raises(ValueError, match=in_range):
            layer.step(np.array([bad, 0.0, 0.0]), dt=DT)
        with pytest.raises(ValueError, match="unit 3"):  # a growing vector, before it grows
            layer.step(np.array([1.0, 0.0, 0.0, bad]), dt=DT)
    assert layer._pool == pool and layer._place_ids.size == 3
    for _ in range(50):
        layer.step(np.array([0.0, 1.0, 0.0]), dt=DT)
    assert layer.winner == layer.find("place", 1)
    layer.step(np.array([999.0, 0.0, 0.0]), dt=DT)  # the bound itself is generous
    many = StateLayer(n_place=400)  # sqrt(sum d^2) beyond the bound, each value within it
    many.step(np.full(400, 500.0), dt=DT)
