"""Known-answer tests of hippo/perception/place_merges.py's rules: a usual way in and out
(exactly half of the stays, and one less), the bypass (exactly min_count direct entries, and one
less), the pair merge (exactly min_count stays on both sides, which place is kept, the stay's
own dwell), the past-and-future test step by step up to merge_horizon, and the join's ids and
keys. Sequences are walked with merging off, then one merge decision is asked for by hand."""

from __future__ import annotations

import math

import pytest
from scipy.stats import norm

from hippo.perception.context_tree import ContextKey, _Inst
from hippo.perception.contexts import ContextParams, ContextStates


def walk(cs: ContextStates, steps, t0: float = 0.0) -> float:
    """Observe places in turn; a step is a place (a 2 s stay) or (place, stay in seconds)."""
    t = t0
    for s in steps:
        p, d = (s, 2.0) if isinstance(s, str) else s
        cs.observe(p, t)
        t += d
    return t


def laps(*routes: str, n: int = 1) -> list[str]:
    """n laps of each route in turn, H before each."""
    return [p for r in routes for _ in range(n) for p in ("H", *r.split())]


def built(steps, **kw) -> ContextStates:
    """Context states that saw ``steps`` with merging off, then turned on (``kw``: params)."""
    cs = ContextStates(ContextParams(**(kw | {"merge_places": False})))
    walk(cs, steps)
    cs.params = ContextParams(**kw)
    return cs


# ------------------------------------------------------------------------------ bypasses
def test_a_bypass_needs_a_usual_way_in_of_at_least_half_the_stays():
    # X entered from P on 3 of its 6 stays (Q1, Q2, Q3 once each), always left to Y; Y entered
    # straight from P 6 times (min_count): X is bypassed on the way P -> Y and joins Y
    base = laps("P X Y Z", n=3) + laps("Q1 X Y Z", "Q2 X Y Z", "Q3 X Y Z")
    cs = built(base + laps("P Y Z", n=6))
    cs._merge_places("X")
    assert cs.same("X") == "Y" and cs.n_place_merges == 1
    # one less (2 of 6, still the most frequent way in): no usual way in, no merge
    base = laps("P X Y Z", n=2) + laps(*(f"Q{k} X Y Z" for k in range(1, 5)))
    cs = built(base + laps("P Y Z", n=6))
    cs._merge_places("X")
    assert cs.same("X") == "X" and cs.n_place_merges == 0
    # 7 stays: 4 from P is more than half (3.5), 3 is less
    for n_p, merged in ((4, True), (3, False)):
        base = laps("P X Y Z", n=n_p) + laps(*(f"Q{k} X Y Z" for k in range(7 - n_p)))
        cs = built(base + laps("P Y Z", n=6))
        cs._merge_places("X")
        assert (cs.same("X") == "Y") == merged, n_p


def test_a_bypass_needs_a_usual_way_out_of_at_least_half_the_stays():
    # X always entered from P; left to Y on 3 of 6 stays (W1, W2, W3 once each): merged; on 2
    # of 6: not
    for n_y, merged in ((3, True), (2, False)):
        base = laps("P X Y Z", n=n_y) + laps(*(f"P X W{k} Z" for k in range(6 - n_y)))
        cs = built(base + laps("P Y Z", n=6))
        cs._merge_places("X")
        assert (cs.same("X") == "Y") == merged, n_y


def test_a_bypass_needs_min_count_direct_entries_from_the_usual_way_in():
    base = laps("P X Y Z", n=6)
    for n_direct, merged in ((6, True), (5, False)):
        cs = built(base + laps("P Y Z", n=n_direct))
        cs._merge_places("X")
        assert (cs.same("X") == "Y") == merged, n_direct
    # min_count 7 (and 7 stays in X): 6 direct entries are too few, 7 enough
    for n_direct, merged in ((7, True), (6, False)):
        cs = built(laps("P X Y Z", n=7) + laps("P Y Z", n=n_direct), min_count=7)
        cs._merge_places("X")
        assert (cs.same("X") == "Y") == merged, n_direct
    # Y is entered more often from R than from P: P is not Y's usual way in
    cs = built(base + laps("P Y Z", n=6) + laps("R Y Z", n=7))
    cs._merge_places("X")
    assert cs.same("X") == "X"
    # bypasses off: no merge
    cs = built(base + laps("P Y Z", n=6), merge_bypasses=False)
    cs._merge_places("X")
    assert cs.same("X") == "X"
    # merging off altogether: no merge
    cs = built(base + laps("P Y Z", n=6), merge_places=False)
    cs._merge_places("X")
    assert cs.same("X") == "X"


def test_the_usual_way_is_the_most_frequent_ties_to_the_largest_repr():
    # X's ways in: P twice; ways out: W once, Y once (a tie: 'Y' > 'W' is taken, and it is one
    # of two stays, half); Y is entered straight from P twice (min_count 2): X joins Y
    cs = built(["H", "P", "X", "W", "Z", "H", "P", "X", "Y", "Z", "H", "P", "Y", "Z", "H", "P",
                "Y", "Z"], min_count=2, memory=4)
    cs._merge_places("X")
    assert cs.same("X") == "Y"
    # the same with the tie the other way round ('W' entered second): still Y
    cs = built(["H", "P", "X", "Y", "Z", "H", "P", "X", "W", "Z", "H", "P", "Y", "Z", "H", "P",
                "Y", "Z"], min_count=2, memory=4)
    cs._merge_places("X")
    assert cs.same("X") == "Y"


def test_a_usual_way_out_seen_once_before_its_place_is_made_is_no_error():
    # A X D A X N: X's ways out tie (D, N) and N, the larger repr, is being entered now (its
    # tree is made after X's stay is learned): nothing to merge, and no error
    cs = ContextStates(ContextParams(min_count=2, memory=4))
    walk(cs, "AXDAXN")
    assert cs.n_place_merges == 0 and cs.same("X") == "X"


# ------------------------------------------------------------------------------ pair merges
def pair(n_b: int, n_c: int, **kw) -> ContextStates:
    """B and C entered from A and left to D, n_b and n_c times (merge_horizon 1: only the way
    in, the way out and the stay after are compared); S, seen once at the start, has no way in."""
    return built(["S", *laps("A B D", n=n_b), *laps("A C D", n=n_c)], merge_horizon=1, **kw)


def test_a_pair_merges_with_exactly_min_count_stays_each_into_the_other_on_a_tie():
    cs = pair(6, 6)
    ids = {p: cs.context_of(p) for p in "BC"}
    cs._merge_places("C")
    # a tie in stays: C (whose stay ended) joins B, under the older id (B's)
    assert cs.same("C") == "B" and cs.n_place_merges == 1
    assert cs.context_of("C") == cs.context_of("B") == ids["B"] == min(ids.values())
    assert cs.resolve(ids["C"]) == ids["B"]
    assert cs.key(ids["B"]) == ContextKey("B", ()) and cs.describe(ids["C"]) == "B"
    assert sorted(cs.members("C")) == ["B", "C"] and "C" not in cs._trees
    assert len(cs._data["B"]) == 12 and "C" not in cs._data
    # five stays of C: too few
    cs = pair(6, 5)
    cs._merge_places("C")
    assert cs.same("C") == "C" and cs.n_place_merges == 0
    cs = pair(5, 6)
    cs._merge_places("C")
    assert cs.same("C") == "C" and cs.n_place_merges == 0


def test_the_place_with_more_stays_is_kept():
    cs = pair(6, 7)
    cs._merge_places("C")
    assert cs.same("B") == "C" and cs.key(cs.context_of("B")) == ContextKey("C", ())
    cs = pair(7, 6)
    cs._merge_places("C")
    assert cs.same("C") == "B"


def test_a_pair_must_share_the_usual_way_out_and_their_own_stay():
    # C leaves to D and E 3 times each (a tie: E, the larger repr), B to D 4 times and E 3:
    # their usual ways out differ (and the counts alone would not tell them apart)
    cs = built(["S", *laps("A C D", "A C E", n=3), *laps("A B D", n=4), *laps("A B E", n=3)],
               merge_horizon=1)
    cs._merge_places("C")
    assert cs.n_place_merges == 0
    # the stay in C lasts 6 s, in B 2 s: not merged (z at alpha_merge); 2.4 s: within 50 %
    for d, merged in ((6.0, False), (2.4, True)):
        steps = ["S", *[x for _ in range(6) for x in ("H", "A", ("B", 2.0), "D")],
                 *[x for _ in range(6) for x in ("H", "A", ("C", d), "D")]]
        cs = built(steps, merge_horizon=1)
        cs._merge_places("C")
        assert (cs.n_place_merges == 1) == merged, d


def test_a_second_place_merge_is_counted():
    cs = built(["S", *laps("A B D", "A C D", "A F D", n=6)], merge_horizon=1)
    cs._merge_places("C")
    cs._merge_places("F")
    assert cs.n_place_merges == 2 and cs.same("F") == cs.same("C") == "B"


def test_a_merged_place_starts_unsplit_and_may_split_on_its_way_in():
    # after C joins B, B is entered from A (then D) and from G (then E): it splits on q1
    cs = pair(6, 6)
    cs._merge_places("C")
    cs.params = ContextParams(merge_places=False, merge_horizon=1)  # no merge of G and A
    walk(cs, laps("G C E", "A C D", n=6), t0=1e3)
    keys = sorted(cs.key(c).history for c in cs.states_of("B"))
    assert keys == [((0, frozenset({"A"})),), ((0, frozenset({"G"})),)]


def test_a_join_retires_every_context_of_both_places_into_the_oldest():
    # C split into contexts 7 ({A1 A2}) and 8 ({B}) of 9 ids (H 0, A1 1, C 2, D 3, A2 4, B 5,
    # E 6); joining D (id 3) into C makes one unsplit state under id 3
    cs = built(laps("A1 C D", "A2 C D", "B C E", n=6))
    assert cs.states_of("C") == [7, 8]
    cs._join("C", "D")
    assert cs.states_of("C") == [3] and cs.same("D") == "C" and "D" not in cs._trees
    assert [cs.resolve(c) for c in (2, 3, 7, 8)] == [3, 3, 3, 3]
    assert cs.key(7) == ContextKey("C", ()) and cs.describe(8) == "C"
    # its stays are C's 18 (12 to D, now C itself, 6 to E) and D's 12 (to H)
    assert cs.predict(3) == {"C": 12 / 30, "E": 6 / 30, "H": 12 / 30}
    assert cs.n_states == 7 - 1 and cs.n_place_merges == 1


# ------------------------------------------------------------------------------ the past/future
def inst(history, future, future_dwell=(), dwell: float = 2.0) -> _Inst:
    return _Inst(tuple(history), future[0], dwell, list(future), list(future_dwell))


def test_past_and_future_need_min_count_stays_at_every_step():
    cs = ContextStates(ContextParams(merge_horizon=3))
    full = [inst("ABC", "DEF", (2.0, 2.0))] * 6
    assert not cs._differ_around(full, full)
    # five stays with a third step of history (or future): not seen enough yet
    short_h = [inst("ABC", "DEF", (2.0, 2.0))] * 5 + [inst("AB", "DEF", (2.0, 2.0))]
    short_f = [inst("ABC", "DEF", (2.0, 2.0))] * 5 + [inst("ABC", "DE", (2.0,))]
    for short in (short_h, short_f):
        assert cs._differ_around(full, short) and cs._differ_around(short, full)
    # with one more full stay each has six: alike again
    for short in (short_h, short_f):
        assert not cs._differ_around(full, [*short, inst("ABC", "DEF", (2.0, 2.0))])
    # a step beyond the horizon is not read
    assert not cs._differ_around(full, [inst("ABCX", "DEFX", (2.0, 2.0))] * 6)
    assert not cs._differ_around(full, [inst("ABC", "DEF", (2.0, 2.0, 9.0))] * 6)


def test_past_and_future_differ_at_any_step_up_to_the_horizon():
    cs = ContextStates(ContextParams(merge_horizon=3))
    a = [inst("ABC", "DEF", (2.0, 2.0))] * 6
    for b in ([inst("ABQ", "DEF", (2.0, 2.0))] * 6, [inst("QBC", "DEF", (2.0, 2.0))] * 6,
              [inst("ABC", "DEQ", (2.0, 2.0))] * 6, [inst("ABC", "QEF", (2.0, 2.0))] * 6):
        assert cs._differ_around(a, b) and cs._differ_around(b, a)
    # a merged place reads as its state
    cs._same["Q"] = "C"
    assert not cs._differ_around(a, [inst("ABQ", "DEF", (2.0, 2.0))] * 6)


def test_the_stays_after_differ_only_with_min_count_of_them_on_both_sides():
    cs = ContextStates(ContextParams(merge_horizon=3))
    a = [inst("ABC", "DEF", (2.0, 2.0))] * 6
    # the second stay after lasts 6 s, not 2 s: different (ln 3 against se = 0.058)
    b = [inst("ABC", "DEF", (2.0, 6.0))] * 6
    assert cs._differ_around(a, b) and cs._differ_around(b, a)
    b = [inst("ABC", "DEF", (6.0, 2.0))] * 6
    assert cs._differ_around(a, b)
    # only five of them known (the sixth stay has not ended): not compared
    b = [inst("ABC", "DEF", (2.0, 6.0))] * 5 + [inst("ABC", "DEF", (2.0,))]
    assert not cs._differ_around(a, b) and not cs._differ_around(b, a)
    # within the tolerance (2.4 s against 2 s): alike
    assert not cs._differ_around(a, [inst("ABC", "DEF", (2.0, 2.4))] * 6)


def test_merging_is_scored_at_alpha_merge_step_by_step():
    # the way in 3 steps back: C on 6 of 6 stays against 3 of 6 (the rest Q); a G-test p of
    # about 0.02, below alpha_merge 0.05 (and above alpha 1e-3): different when merging
    cs = ContextStates(ContextParams(merge_horizon=3))
    a = [inst("ABC", "DEF", (2.0, 2.0))] * 6
    b = [inst("ABC", "DEF", (2.0, 2.0))] * 3 + [inst("ABQ", "DEF", (2.0, 2.0))] * 3
    assert cs._differ_around(a, b)
    cs = ContextStates(ContextParams(merge_horizon=3, alpha_merge=0.01))
    assert not cs._differ_around(a, b)


def test_the_pair_dwell_z_is_the_merge_z():
    # a stay of 2 s against exp(f z_merge se) * 2 s, se = sqrt(2 * 0.01 / 6) (no spread)
    z = float(norm.ppf(0.975))  # two-sided at alpha_merge 0.05
    se = math.sqrt(2 * 0.01 / 6)
    for f, merged in ((1.01, False), (0.99, True)):
        d = 2.0 * math.exp(f * z * se)
        steps = ["S", *[x for _ in range(6) for x in ("H", "A", ("B", 2.0), "D")],
                 *[x for _ in range(6) for x in ("H", "A", ("C", d), "D")]]
        cs = built(steps, merge_horizon=1, dwell_tolerance=0.0)
        cs._merge_places("C")
        assert (cs.n_place_merges == 1) == merged, f


@pytest.mark.parametrize("n", [6, 7])
def test_merges_happen_in_a_walk_with_merging_on(n):
    # the same pair, walked with merging on: merged once both have min_count stays
    cs = ContextStates(ContextParams(merge_horizon=1, min_count=n))
    t = walk(cs, ["S", *laps("A B D", n=n), *laps("A C D", n=n - 1)])
    assert cs.n_place_merges == 0
    walk(cs, laps("A C D"), t0=t)
    assert cs.n_place_merges == 1 and cs.same("C") == "B"
