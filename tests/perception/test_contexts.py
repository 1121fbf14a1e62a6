"""Context-split states on synthetic sequences with known answers."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import chi2

from hippo.cognitive_map.quality import next_state_bits
from hippo.perception.contexts import ContextParams, ContextStates, g_test


def aliased_corridor(n_laps: int, seed: int, dwell: float = 2.0, t0: float = 0.0):
    """Two routes that share the stretch C1-C2-C3: A C1 C2 C3 D H and B C1 C2 C3 E H.

    Which exit (D or E) follows C3 is fixed by the route's entry (A or B), three places back;
    the route is chosen at random at H."""
    rng = np.random.default_rng(seed)
    t, out = t0, []
    for _ in range(n_laps):
        route = ("A", "C1", "C2", "C3", "D") if rng.integers(2) == 0 else \
            ("B", "C1", "C2", "C3", "E")
        for p in (*route, "H"):
            t += dwell * math.exp(0.05 * rng.standard_normal())
            out.append((p, t))
    return out


def run(contexts: ContextStates, seq):
    return [(p, contexts.observe(p, t)) for p, t in seq]


def test_g_test_known_answers():
    # perfectly dependent 2x2 table: G = 2 * 12 * ln 2, one degree of freedom
    assert g_test(np.array([[6, 0], [0, 6]])) == pytest.approx(chi2.sf(24 * math.log(2), 1))
    assert g_test(np.array([[5, 5], [5, 5]])) == pytest.approx(1.0)
    assert g_test(np.array([[4, 0], [3, 0]])) == 1.0  # one successor: nothing to test
    with pytest.raises(ValueError, match="counts >= 0"):
        g_test(np.array([[1, -1], [0, 2]]))


def test_aliased_corridor_splits_the_shared_stretch_exactly_where_needed():
    cs = ContextStates()
    run(cs, aliased_corridor(60, seed=0))
    # C3 needs the entry three places back; C1 and C2 (always followed by C2, C3) need nothing
    assert len(cs.states_of("C3")) == 2
    assert cs.states_of("C1") == [cs.context_of("C1")] and len(cs.states_of("C2")) == 1
    exits = {}
    for c in cs.states_of("C3"):
        ((j, entry),) = cs.key(c).history
        assert j == 2  # split on q3 (index 2): the route's entry
        exits[next(iter(entry))] = cs.predict(c)
    assert exits == {"A": {"D": 1.0}, "B": {"E": 1.0}}
    assert cs.context_of("C3", ("C2", "C1", "A")) != cs.context_of("C3", ("C2", "C1", "B"))
    # A and B (and D and E) look alike one step around but not three: never merged
    assert cs.n_place_merges == 0


def test_split_states_predict_the_next_place_where_the_place_cannot():
    cs = ContextStates()
    train = run(cs, aliased_corridor(80, seed=1))
    test = run(cs, aliased_corridor(40, seed=2, t0=1e4))
    assert cs.n_splits >= 1
    ctx_tr = [c for _, c in train[:-1]]
    nxt_tr = [p for p, _ in train[1:]]
    at_c3 = [k for k, (p, _) in enumerate(test[:-1]) if p == "C3"]
    ctx_te = [test[k][1] for k in at_c3]
    plc_te = ["C3"] * len(at_c3)
    nxt_te = [test[k + 1][0] for k in at_c3]
    split_bits = next_state_bits(ctx_tr, nxt_tr, ctx_te, nxt_te)
    place_bits = next_state_bits([p for p, _ in train[:-1]], nxt_tr, plc_te, nxt_te)
    assert split_bits < 0.1       # the exit is known
    assert place_bits > 0.9       # a fair coin: 1 bit


def test_dwell_time_splits_a_place_with_one_successor():
    # A -> C -> X and B -> C -> X: the same successor, but the robot stays 6 s in C after A
    # and 2 s after B (where it enters C decides how much of C is left)
    rng = np.random.default_rng(3)
    cs, t = ContextStates(), 0.0
    for _ in range(40):
        first = "A" if rng.integers(2) == 0 else "B"
        for p, d in ((first, 2.0), ("C", 6.0 if first == "A" else 2.0), ("X", 2.0), ("H", 2.0)):
            cs.observe(p, t)
            t += d * math.exp(0.05 * rng.standard_normal())
    assert len(cs.states_of("C")) == 2
    assert cs.context_of("C", ("A",)) != cs.context_of("C", ("B",))
    assert all(cs.predict(c) == {"X": 1.0} for c in cs.states_of("C"))


def test_same_futures_do_not_split():
    # a memoryless walk: the next place never depends on the past
    rng = np.random.default_rng(4)
    cs, t = ContextStates(), 0.0
    places = list("ABCD")
    for _ in range(400):
        t += 2.0
        cs.observe(places[int(rng.integers(4))], t)
    assert cs.n_splits == 0
    assert cs.n_states == 4


def test_contexts_merge_when_they_stop_differing_and_memory_stays_bounded():
    params = ContextParams(memory=24, min_count=6)
    cs = ContextStates(params)
    seq = aliased_corridor(40, seed=5)
    run(cs, seq)
    old = cs.states_of("C3")
    assert len(old) == 2
    # the world changes: both routes now leave the shared stretch by D
    t = seq[-1][1]
    rng = np.random.default_rng(6)
    for _ in range(60):
        route = ("A",) if rng.integers(2) == 0 else ("B",)
        for p in (*route, "C1", "C2", "C3", "D", "H"):
            t += 2.0
            cs.observe(p, t)
    assert cs.n_merges >= 1
    assert len(cs.states_of("C3")) == 1
    survivor = cs.states_of("C3")[0]
    assert {cs.resolve(c) for c in old} == {survivor}
    assert cs.predict(survivor) == {"D": 1.0}
    assert all(len(d) <= params.memory for d in cs._data.values())


def test_reset_forgets_history_but_keeps_contexts():
    cs = ContextStates()
    run(cs, aliased_corridor(60, seed=0))
    n = cs.n_states
    cs.reset()
    cid = cs.observe("C3", 1e6)  # no history after a kidnap: the default context
    assert cid in cs.states_of("C3")
    assert cs.n_states == n


def test_bad_input_is_named():
    with pytest.raises(ValueError, match="min_count"):
        ContextParams(min_count=1)
    with pytest.raises(ValueError, match="alpha_merge"):
        ContextParams(alpha=0.1, alpha_merge=0.01)
    with pytest.raises(ValueError, match="memory"):
        ContextParams(memory=5)
    cs = ContextStates()
    with pytest.raises(ValueError, match="place"):
        cs.observe(None, 0.0)
    cs.observe("A", 5.0)
    with pytest.raises(ValueError, match="backwards"):
        cs.observe("B", 1.0)
    with pytest.raises(ValueError, match="unknown context id"):
        cs.resolve(99)


def test_places_that_take_turns_merge_into_one_state():
    # two prototypes share one stretch and win on alternate laps at random: H A {B|C} D H ...
    rng = np.random.default_rng(7)
    cs, t, seq = ContextStates(), 0.0, []
    for _ in range(60):
        for p in ("H", "A", "B" if rng.integers(2) == 0 else "C", "D"):
            t += 2.0 * math.exp(0.05 * rng.standard_normal())
            seq.append((p, cs.observe(p, t)))
    assert cs.n_place_merges == 1
    assert cs.same("B") == cs.same("C") and sorted(cs.members("B")) == ["B", "C"]
    assert cs.context_of("B") == cs.context_of("C")
    # after the merge, what follows A is certain: the merged state
    merged = cs.context_of("A")
    assert cs.predict(merged) == {cs.same("B"): 1.0}
    # every id issued for B or C before the merge resolves to the merged state
    assert {cs.resolve(c) for p, c in seq if p in "BC"} == {cs.context_of("B")}


def test_places_that_differ_in_the_dwell_after_them_do_not_merge():
    # as above, but after C the robot stays 3x longer in D: C is not the same as B
    rng = np.random.default_rng(8)
    cs, t = ContextStates(), 0.0
    for _ in range(60):
        mid = "B" if rng.integers(2) == 0 else "C"
        for p, d in (("H", 2.0), ("A", 2.0), (mid, 2.0), ("D", 6.0 if mid == "C" else 2.0)):
            cs.observe(p, t)
            t += d * math.exp(0.05 * rng.standard_normal())
    assert cs.n_place_merges == 0
    assert len(cs.states_of("D")) == 2  # and D splits by the way in


def test_a_place_that_wins_only_on_some_passes_merges_into_the_next_one():
    # P -> X -> Y on some passes, P -> Y on others (a field that wins briefly at the start of
    # Y's stretch): X joins Y, and what follows P becomes certain
    rng = np.random.default_rng(9)
    cs, t = ContextStates(), 0.0
    for _ in range(60):
        route = ("H", "P", "X", "Y", "Z") if rng.integers(2) == 0 else ("H", "P", "Y", "Z")
        for p in route:
            t += 2.0 * math.exp(0.05 * rng.standard_normal())
            cs.observe(p, t)
    assert cs.same("X") == "Y"
    assert cs.predict(cs.context_of("P")) == {"Y": 1.0}
    # off: two states
    cs = ContextStates(ContextParams(merge_bypasses=False))
    for _ in range(60):
        for p in ("H", "P", "X", "Y", "Z") if rng.integers(2) == 0 else ("H", "P", "Y", "Z"):
            t += 2.0
            cs.observe(p, t)
    assert cs.same("X") == "X"
