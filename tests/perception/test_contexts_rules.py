"""Known-answer tests of hippo/perception/contexts.py's rules on short hand-written place
sequences: the instances (h, n, d) of the module docstring, ids issued in order and retired into
their survivors, a split exactly when a second value reaches min_count, the grouping of alike
values, nested splits and their keys, the dwell test's Weber and tolerance bounds exactly on
their edges, merges back, and every error word for word."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import chi2_contingency, norm

from hippo.perception.context_tree import ContextKey, _Inst
from hippo.perception.contexts import ContextParams, ContextStates


def walk(cs: ContextStates, places, t0: float = 0.0, dt: float = 2.0) -> float:
    """Observe ``places`` dt seconds apart from t0; the time of the last one."""
    t = t0
    for p in places:
        cs.observe(p, t)
        t += dt
    return t - dt


def inst(**kw) -> _Inst:
    base = {"history": ("H",), "next": "D", "dwell": 2.0, "future": ["D"], "future_dwell": []}
    return _Inst(**(base | kw))


# ------------------------------------------------------------------------------ construction
def test_construction_takes_context_params_or_nothing():
    assert ContextStates().params == ContextParams()
    assert ContextStates(None).params == ContextParams()
    p = ContextParams(min_count=3, memory=6)
    cs = ContextStates(p)
    assert cs.params is p
    assert (cs.n_splits, cs.n_merges, cs.n_place_merges, cs.n_states) == (0, 0, 0, 0)
    assert cs.current is None
    with pytest.raises(TypeError) as err:
        ContextStates({"min_count": 3})  # type: ignore[arg-type]
    assert str(err.value) == "params must be ContextParams, got {'min_count': 3}"


def test_observe_refuses_bad_places_and_times_word_for_word():
    cs = ContextStates()
    for bad in (None, [1, 2], {"a": 1}):
        with pytest.raises(ValueError) as err:
            cs.observe(bad, 0.0)
        assert str(err.value) == f"place must be a hashable, non-None label, got {bad!r}"
    for bad in (math.nan, math.inf, -math.inf):
        with pytest.raises(ValueError) as err:
            cs.observe("A", bad)
        assert str(err.value) == f"t must be a finite time in seconds, got {bad!r}"
    assert cs.current is None and cs.n_states == 0  # nothing was taken
    cs.observe("A", 5.0)
    with pytest.raises(ValueError) as err:
        cs.observe("B", 4.0)
    assert str(err.value) == "time went backwards: entered at 5.0, now 4.0"
    assert cs.observe("B", 5.0) == 1  # the same time is not backwards


# ------------------------------------------------------------------------------ the instances
def test_ids_are_issued_in_order_and_a_repeated_place_is_no_new_stay():
    cs = ContextStates()
    assert cs.observe("A", 0.0) == 0 and cs.current == 0
    assert cs.observe("B", 1.0) == 1
    assert cs.observe("A", 2.0) == 0
    assert cs.observe("A", 3.0) == 0  # still in A: the stay goes on
    assert cs.observe("C", 4.0) == 2 and cs.current == 2
    assert cs.n_states == 3 and cs.states_of("A") == [0]
    # A's stays: A -> B (1 s), A -> C (2 s from its entry at 2 s, not from the repeat at 3 s)
    assert cs.predict(0) == {"B": 0.5, "C": 0.5}
    assert [(i.next, i.dwell) for i in cs._data["A"]] == [("B", 1.0), ("C", 2.0)]
    assert cs.predict(1) == {"A": 1.0}
    assert cs.predict(2) == {}  # C's stay has not ended


def test_an_instance_holds_the_places_before_after_and_the_stays_after():
    # entries at t = 0, 1, 3, 6, 10, 15, 21: the stays in A..F last 1, 2, 3, 4, 5, 6 s
    cs = ContextStates()
    for p, t in zip("ABCDEFG", (0, 1, 3, 6, 10, 15, 21), strict=True):
        cs.observe(p, float(t))
    (c,) = cs._data["C"]
    # the stay in C: entered after B then A (most recent first), left to D after 3 s; the
    # places after it as they came, and the stays in D, E, F (G's has not ended)
    assert c.history == ("B", "A") and c.next == "D" and c.dwell == 3.0
    assert c.future == ["D", "E", "F", "G"] and c.future_dwell == [4.0, 5.0, 6.0]
    (a,) = cs._data["A"]
    assert a.history == () and a.next == "B" and a.dwell == 1.0


def test_the_future_is_kept_up_to_merge_horizon_and_the_stays_in_it():
    cs = ContextStates(ContextParams(merge_horizon=2))
    for p, t in zip("ABCDEFG", (0, 1, 3, 6, 10, 15, 21), strict=True):
        cs.observe(p, float(t))
    (b,) = cs._data["B"]
    assert b.future == ["C", "D"] and b.future_dwell == [3.0]
    # and only merge_horizon instances wait for their future
    assert len(cs._pending) == 2
    cs = ContextStates(ContextParams(merge_horizon=3))
    walk(cs, "ABCDEFGHIJ")
    assert len(cs._pending) == 3
    assert [len(i.future) for i in cs._data["B"]] == [3]


def test_the_history_kept_is_the_longer_of_max_depth_and_merge_horizon():
    seq = "ABCDEFGHIJKLMNOP"
    for kw, n in (({}, 8), ({"max_depth": 5, "merge_horizon": 2}, 5),
                  ({"max_depth": 2, "merge_horizon": 4}, 4), ({"max_depth": 0}, 8)):
        cs = ContextStates(ContextParams(**kw))
        walk(cs, seq)
        (last,) = cs._data["O"]
        assert last.history == tuple(reversed(seq[:14]))[:n]


def test_reset_forgets_the_way_in_and_the_open_stay_only():
    cs = ContextStates()
    walk(cs, "AB", t0=10.0)
    cs.reset()
    assert cs.current is None
    assert cs.observe("C", 1.0) == 2  # an earlier time is no error after a kidnap
    cs.observe("A", 2.0)
    # B's stay was open at the reset: never learned; C's stay has no way in
    assert cs.predict(1) == {} and cs.predict(0) == {"B": 1.0}
    assert cs._data["C"][0].history == ()
    assert cs.states_of("A") == [0] and cs.n_states == 3


# ------------------------------------------------------------------------------ ids
def test_resolve_takes_issued_integer_ids_only():
    cs = ContextStates()
    walk(cs, "ABC")
    assert cs.resolve(2) == 2 and cs.resolve(0) == 0
    r = cs.resolve(np.int64(1))
    assert r == 1 and type(r) is int
    for bad in (3, -1, True, False, 1.0, "1", None):
        with pytest.raises(ValueError) as err:
            cs.resolve(bad)  # type: ignore[arg-type]
        assert str(err.value) == f"unknown context id {bad!r} (3 ids issued)"
    with pytest.raises(ValueError):
        cs.key(3)
    assert cs.key(1) == ContextKey("B", ())
    assert cs.describe(1) == "B"


def test_context_of_a_new_place_issues_its_id():
    cs = ContextStates()
    walk(cs, "AB")
    assert cs.context_of("Z") == 2 and cs.states_of("Z") == [2]
    assert cs.context_of("Z", ("A", "B")) == 2  # unsplit: any history
    assert cs.context_of("A") == 0


# ------------------------------------------------------------------------------ splits
def laps(*routes: str, n: int = 6) -> list[str]:
    """n laps of each route in turn (H between laps)."""
    return [p for r in routes for _ in range(n) for p in ("H", *r.split())]


def test_a_split_comes_exactly_when_a_second_value_reaches_min_count():
    # C after A1 (6 laps), after A2 (6 laps) goes to D; after B to E. A1 and A2 alone never
    # split C (one group); the 6th B is the 6th instance of a second value: G-test of
    # [[12, 0], [0, 6]] (p ~ 1e-6 < alpha), before it B has 5 (< min_count: no group)
    cs = ContextStates(ContextParams(merge_places=False))
    t = walk(cs, laps("A1 C D", "A2 C D"))
    assert cs.states_of("C") == [2]
    assert [cs.observe("H", t + 2), cs.observe("B", t + 4)] == [0, 5]
    t = walk(cs, ["C", "E"], t0=t + 6)
    for k in range(2, 7):
        assert len(cs.states_of("C")) == 1, k
        t = walk(cs, ["H", "B", "C", "E"], t0=t + 2)
    # ids: H 0, A1 1, C 2, D 3, A2 4, B 5, E 6; the split's children 7 ({A1 A2}) and 8 ({B})
    assert cs.states_of("C") == [7, 8]
    assert cs.key(7) == ContextKey("C", ((0, frozenset({"A1", "A2"})),))
    assert cs.key(8) == ContextKey("C", ((0, frozenset({"B"})),))
    assert cs.describe(7) == "C|1:{A1 A2}" and cs.describe(8) == "C|1:B"
    # the unsplit id is retired into the first group (of the most frequent value, ties by repr)
    assert cs.resolve(2) == 7 and cs.describe(2) == "C|1:{A1 A2}"
    assert cs.predict(7) == {"D": 1.0} and cs.predict(8) == {"E": 1.0}
    assert cs.predict(2) == {"D": 1.0}
    # routing: by the place before; a value never seen and no history go to the largest group
    assert [cs.context_of("C", h) for h in (("B",), ("A2",), ("A1", "B"), ("Q",), ())] == \
        [8, 7, 7, 7, 7]
    assert cs.n_merges == 0


def test_min_count_is_the_number_of_instances_a_value_needs():
    cs = ContextStates(ContextParams(merge_places=False, min_count=7))
    t = walk(cs, laps("A C D", n=7) + laps("B C E", n=6))
    assert len(cs.states_of("C")) == 1  # B has 6 < 7
    walk(cs, ["H", "B", "C", "E"], t0=t + 2)
    assert len(cs.states_of("C")) == 2


def test_a_split_needs_history_within_max_depth():
    # C is followed by X after P-A and by Y after Q-A: only the place two steps back tells
    seq = laps("P A C X", "Q A C Y", n=8) * 2
    for depth, n in ((0, 1), (1, 1), (2, 2), (3, 2)):
        cs = ContextStates(ContextParams(merge_places=False, max_depth=depth))
        walk(cs, seq)
        assert len(cs.states_of("C")) == n, depth
    # split on q2 (index 1) by P or Q
    assert cs.key(cs.context_of("C", ("A", "P"))).history == ((1, frozenset({"P"})),)
    assert cs.key(cs.context_of("C", ("A", "Q"))).history == ((1, frozenset({"Q"})),)
    assert cs.describe(cs.context_of("C", ("A", "Q"))) == "C|2:Q"


def test_nested_splits_accumulate_their_history_in_the_key():
    # C after B goes to Z; after A to X or Y by the place before A (P or Q). Six laps P-A-C-X
    # then six B-C-Z: C splits on q1 ({A} | {B}; q2 is P or H, as telling as q1, but q1 comes
    # first); six laps Q-A-C-Y then split the A-leaf on q2 ({P} | {Q}); the B-leaf stays one
    cs = ContextStates(ContextParams(merge_places=False))
    walk(cs, laps("P A C X", "B C Z"))
    assert {cs.describe(c) for c in cs.states_of("C")} == {"C|1:A", "C|1:B"}
    walk(cs, laps("Q A C Y"), t0=1e3)
    got = {cs.describe(c) for c in cs.states_of("C")}
    assert got == {"C|1:A,2:P", "C|1:A,2:Q", "C|1:B"}
    cp = cs.context_of("C", ("A", "P"))
    assert cs.key(cp).history == ((0, frozenset({"A"})), (1, frozenset({"P"})))
    assert cs.predict(cp) == {"X": 1.0}
    assert cs.predict(cs.context_of("C", ("A", "Q"))) == {"Y": 1.0}
    assert cs.predict(cs.context_of("C", ("B", "Q"))) == {"Z": 1.0}
    assert cs.n_splits >= 2 and cs.n_states == sum(len(cs.states_of(p)) for p in cs._trees)


def test_contexts_merge_back_into_the_oldest_id_with_the_history_trimmed():
    # split C on q1 as above, then make B's way out D too: with memory 12 the E's are
    # forgotten and the children merge back at alpha_merge into the oldest child, 7
    cs = ContextStates(ContextParams(merge_places=False, memory=12))
    t = walk(cs, laps("A1 C D", "A2 C D", "B C E"))
    assert cs.states_of("C") == [7, 8]
    walk(cs, laps("A1 C D", "B C D", n=12), t0=t + 2)
    assert cs.n_merges == 1 and cs.states_of("C") == [7]
    assert cs.key(7) == ContextKey("C", ()) and cs.describe(7) == "C"
    assert [cs.resolve(c) for c in (2, 7, 8)] == [7, 7, 7]
    assert cs.describe(8) == "C" and cs.predict(8) == {"D": 1.0}


# ------------------------------------------------------------------------------ the tests
def test_the_dwell_test_is_strict_on_the_tolerance_and_on_z_standard_errors():
    # one stay each, no spread: se = sqrt(w^2 + w^2); z = 0 leaves the tolerance alone:
    # |ln 1.5 - ln 1| equals log1p(0.5) exactly, which is not "more than"
    cs = ContextStates(ContextParams(dwell_tolerance=0.5))
    assert not cs._differ_dwell([1.0], [1.5], 0.0)
    assert not cs._differ_dwell([1.5], [1.0], 0.0)
    assert cs._differ_dwell([1.0], [1.5000001], 0.0)
    assert cs._differ_dwell([1.5000001], [1.0], 0.0)
    # tolerance 0, weber 0.5, two equal stays a side: se = sqrt(0.25/2 + 0.25/2) = 0.5 and
    # diff = ln 3; at z = 2 ln 3, z se = ln 3 exactly: not different; one step below: different
    cs = ContextStates(ContextParams(dwell_tolerance=0.0, weber=0.5))
    z = 2 * float(np.log(3.0))
    assert not cs._differ_dwell([1.0, 1.0], [3.0, 3.0], z)
    assert cs._differ_dwell([1.0, 1.0], [3.0, 3.0], float(np.nextafter(z, 0.0)))
    assert not cs._differ_dwell([2.0, 2.0], [2.0, 2.0], 0.0)  # diff 0 is not > 0


def test_the_dwell_tests_spread_is_the_population_sd_floored_at_weber():
    cs = ContextStates(ContextParams(dwell_tolerance=0.0, weber=0.1))
    # log-dwells 0 and 2 (variance 1 with ddof 0) against two of k (variance 0 -> 0.1^2):
    # se = sqrt(1 / 2 + 0.01 / 2) = 0.7106; z = 1: |1 - k| 0.70 is within, 0.72 beyond
    a = [1.0, math.exp(2.0)]
    assert not cs._differ_dwell(a, [math.exp(1.70)] * 2, 1.0)
    assert cs._differ_dwell(a, [math.exp(1.72)] * 2, 1.0)
    assert cs._differ_dwell([math.exp(1.72)] * 2, a, 1.0)
    # no spread at all: se = sqrt(0.01 / 2 + 0.01 / 2) = 0.1
    assert not cs._differ_dwell([1.0] * 2, [math.exp(0.09)] * 2, 1.0)
    assert cs._differ_dwell([1.0] * 2, [math.exp(0.11)] * 2, 1.0)
    # three a side: se = sqrt(0.01 / 3 * 2) = 0.0816
    assert not cs._differ_dwell([1.0] * 3, [math.exp(0.08)] * 3, 1.0)
    assert cs._differ_dwell([1.0] * 3, [math.exp(0.083)] * 3, 1.0)


def test_a_stay_of_zero_seconds_counts_as_a_nanosecond():
    cs = ContextStates()
    assert not cs._differ_dwell([0.0] * 6, [1e-9] * 6, 0.0)
    assert not cs._differ_dwell([0.0] * 6, [1e-10] * 6, 0.0)
    assert cs._differ_dwell([0.0] * 6, [1.0] * 6, cs._z)


def test_split_and_merge_use_alpha_and_alpha_merge():
    cs = ContextStates(ContextParams(dwell_tolerance=0.0))
    # z of a two-sided test at alpha, independently: the 1 - alpha / 2 quantile
    assert cs._z == pytest.approx(norm.ppf(1 - 1e-3 / 2), rel=1e-12)
    assert cs._z_merge == pytest.approx(norm.ppf(1 - 0.05 / 2), rel=1e-12)
    # successors [[6, 0], [3, 3]]: p between alpha and alpha_merge
    _, p, _, _ = chi2_contingency([[6, 0], [3, 3]], correction=False, lambda_="log-likelihood")
    assert 1e-3 < p < 0.05
    a = [inst(next="D") for _ in range(6)]
    b = [inst(next="D") for _ in range(3)] + [inst(next="E") for _ in range(3)]
    assert not cs._different(a, b) and cs._different(a, b, merge=True)
    # dwell: six equal stays a side, se = sqrt(2 * 0.01 / 6) (the weber floor); a log-ratio
    # just past z se differs, just within does not, with z at alpha (split) or alpha_merge
    se = math.sqrt(2 * 0.01 / 6)
    a = [inst(dwell=1.0)] * 6
    for merge, alpha in ((False, 1e-3), (True, 0.05)):
        z = float(norm.ppf(1 - alpha / 2))
        for f, want in ((1.000001, True), (0.999999, False)):
            b = [inst(dwell=math.exp(f * z * se))] * 6
            assert cs._different(a, b, merge=merge) == want, (merge, f)
    # merged places read as their state: B's successor C is D's after a merge
    cs._same["C"] = "D"
    assert not cs._different([inst(next="D")] * 6, [inst(next="C")] * 6)
    assert cs._different([inst(next="D")] * 6, [inst(next="E")] * 6)


def test_predict_counts_the_kept_instances_of_the_context():
    # A's stays end in B, C, B, B: frequencies 3/4 and 1/4 (too few to split anything)
    cs = ContextStates()
    walk(cs, "ABACABAB")
    assert cs.predict(0) == {"B": 0.75, "C": 0.25}
    assert cs.predict(1) == {"A": 1.0}
    # memory: only the last memory stays are kept (12 with min_count 6)
    # (max_depth 0: no split); A's last 12 stays are 6 to B and 6 to C
    cs = ContextStates(ContextParams(memory=12, max_depth=0, merge_places=False))
    walk(cs, "AB" * 10 + "AC" * 6 + "A")
    assert len(cs._data["A"]) == 12 and cs.predict(0) == {"B": 0.5, "C": 0.5}


def test_predict_takes_any_hashable_labels():
    # places may be any hashable, non-None labels (observe's rule): tuples, and a mix of types
    # A's stays end in ("b", 2), ("c", 3), ("b", 2): 2/3 and 1/3
    cs = ContextStates()
    walk(cs, [("a", 1), ("b", 2), ("a", 1), ("c", 3), ("a", 1), ("b", 2)])
    assert cs.predict(0) == {("b", 2): 2 / 3, ("c", 3): 1 / 3}
    # 1's stays end in "x", 2, "x": 2/3 and 1/3
    cs = ContextStates()
    walk(cs, [1, "x", 1, 2, 1, "x"])
    assert cs.predict(0) == {"x": 2 / 3, 2: 1 / 3}
    # sortable labels come in ascending order (as before)
    cs = ContextStates()
    walk(cs, [5, 9, 5, 7, 5, 8, 5, 7])
    assert list(cs.predict(0)) == [7, 8, 9] and cs.predict(0)[7] == 0.5


def test_a_split_is_significant_strictly_below_alpha():
    # [[6, 0], [0, 6]]: G = 24 ln 2 on one degree of freedom; at alpha equal to its p-value
    # the successors do not differ, at the next float up they do
    from scipy.stats import chi2

    cs = ContextStates()
    p = float(chi2.sf(24 * math.log(2), 1))
    a, b = [inst(next="D")] * 6, [inst(next="E")] * 6
    assert not cs._differ_in(a, b, lambda i: i.next, p)
    assert cs._differ_in(a, b, lambda i: i.next, float(np.nextafter(p, 1.0)))


def test_the_largest_group_comes_first_ties_by_repr():
    # Z before C 7 times (to Y), A 6 times (to D): {Z}, the larger, is the first child, the
    # default for unseen values and the survivor of the unsplit id
    cs = ContextStates(ContextParams(merge_places=False))
    walk(cs, laps("Z C Y", n=7) + laps("A C D"))
    # ids: H 0, Z 1, C 2, Y 3, A 4, D 5; children 6 ({Z}) and 7 ({A})
    assert cs.states_of("C") == [6, 7] and cs.resolve(2) == 6
    assert cs.describe(6) == "C|1:Z" and cs.context_of("C", ("Q",)) == 6
    # a tie (6 and 6) goes by repr: 'A' < 'B' although B came first
    cs = ContextStates(ContextParams(merge_places=False))
    walk(cs, laps("B C E", "A C D"))
    # ids: H 0, B 1, C 2, E 3, A 4, D 5; children 6 ({A}) and 7 ({B})
    assert cs.states_of("C") == [6, 7] and cs.describe(6) == "C|1:A" and cs.resolve(2) == 6


def nested(memory: int = 256) -> ContextStates:
    """C split on q1 ({A} | {B}) after 6 laps B-C-Z and 6 P-A-C-X."""
    cs = ContextStates(ContextParams(merge_places=False, memory=memory))
    walk(cs, laps("B C Z", "P A C X"))
    return cs


def test_each_split_counts_once():
    cs = nested()
    assert len(cs.states_of("C")) == 2 and cs.n_splits >= 1
    t = walk(cs, [*laps("Q A C Y", n=5), "H", "Q", "A", "C"], t0=1e3)
    n = cs.n_splits
    cs.observe("Y", t + 2)  # C's stay after the 6th Q ends: the A-leaf splits on q2
    assert cs.n_splits == n + 1 and len(cs.states_of("C")) == 3


def test_a_leaf_splits_when_a_sibling_fell_below_min_count():
    # memory 16: C's 6 + 6 + 6 stays push two of B's out (B keeps 4 < min_count): the
    # siblings cannot be merged (too few), and the A-leaf still splits on q2
    cs = nested(memory=16)
    walk(cs, laps("Q A C Y"), t0=1e3)
    assert sum(i.history[0] == "B" for i in cs._data["C"]) == 4
    assert {cs.describe(c) for c in cs.states_of("C")} == {"C|1:A,2:P", "C|1:A,2:Q", "C|1:B"}
    assert cs.n_merges == 0


def test_children_merge_back_only_when_no_test_reaches_alpha_merge():
    # C split on q1; its kept stays replaced by hand: after A 6 to D, after B 3 to D and 3 to
    # E. G-test p ~ 0.023: below alpha_merge (0.05), so they still differ (not below alpha,
    # 1e-3, so they would not split now): no merge
    cs = nested()
    root = cs._trees["C"]
    ids = cs.states_of("C")
    cs._data["C"].clear()
    cs._data["C"].extend([inst(history=("A", "P"), next="D")] * 6
                         + [inst(history=("B", "H"), next="D")] * 3
                         + [inst(history=("B", "H"), next="E")] * 3)
    assert cs._merge("C", root) is False
    assert cs.n_merges == 0 and cs.states_of("C") == ids
    # after B 5 to D and 1 to E (p ~ 0.3): merged into the older id
    cs._data["C"].clear()
    cs._data["C"].extend([inst(history=("A", "P"), next="D")] * 6
                         + [inst(history=("B", "H"), next="D")] * 5
                         + [inst(history=("B", "H"), next="E")])
    assert cs._merge("C", root) is True
    assert cs.n_merges == 1 and cs.states_of("C") == [min(ids)]


def test_nested_contexts_merge_back_level_by_level_trimming_the_key():
    cs = nested()
    walk(cs, laps("Q A C Y"), t0=1e3)
    assert len(cs.states_of("C")) == 3
    root = cs._trees["C"]
    a_node = root.child("A")
    assert not a_node.leaf
    kids = [c.cid for c in a_node.children()]
    # every stay now goes to X, whatever the way in
    cs._data["C"].clear()
    for h in (("A", "P"), ("A", "Q"), ("B", "H")):
        cs._data["C"].extend([inst(history=h, next="X")] * 6)
    assert cs._merge("C", a_node) is True
    k = min(kids)
    assert cs.n_merges == 1 and cs.key(k) == ContextKey("C", ((0, frozenset({"A"})),))
    assert cs.describe(max(kids)) == "C|1:A"
    assert cs._merge("C", root) is True
    assert cs.n_merges == 2 and cs.states_of("C") == [min(k, *(c for c in cs.states_of("C")))]
    assert cs.describe(cs.states_of("C")[0]) == "C" and cs.predict(k) == {"X": 1.0}


def test_places_of_mixed_label_types_split_and_describe():
    # C after "A1" or 1 goes to 7, after "B" to "E": the successors (7 and "E") cannot be
    # ordered by value, the group {1, "A1"} is written in str order ("1" < "A1")
    cs = ContextStates(ContextParams(merge_places=False))
    walk(cs, [p for r in (("A1", "C", 7), (1, "C", 7), ("B", "C", "E")) for _ in range(6)
              for p in ("H", *r)])
    # ids: H 0, A1 1, C 2, 7 3, 1 4, B 5, E 6; children 7 ({1 A1}: repr '1' < "'A1'") and 8
    assert cs.states_of("C") == [7, 8]
    assert cs.describe(7) == "C|1:{1 A1}" and cs.describe(8) == "C|1:B"
    assert cs.predict(7) == {7: 1.0} and cs.predict(8) == {"E": 1.0}


def test_a_leaf_is_not_split_again_on_a_step_its_path_used():
    # C splits on q1 ({A} | {B}); G, never seen then, follows the first child {A}. Six laps
    # G-C-Y later, G's stays differ from A's but only by q1, which that leaf's path used; the
    # steps after it (q2 = H; q3 the previous lap's end, five of each) cannot split it
    cs = ContextStates(ContextParams(merge_places=False))
    walk(cs, laps("A C X", "B C Z"))
    a_leaf = cs.context_of("C", ("A",))
    assert len(cs.states_of("C")) == 2
    walk(cs, laps("G C Y"), t0=1e3)
    assert len(cs.states_of("C")) == 2 and cs.context_of("C", ("G",)) == a_leaf
    assert cs.predict(a_leaf) == {"X": 0.5, "Y": 0.5}
    assert cs.describe(a_leaf) == "C|1:A"
