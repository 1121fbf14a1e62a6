"""Folding a repeat into a transition's attributes (hippo/cognitive_map/merge.py), on
hand-written attribute dicts: the heading's exact circular mean S_{n+1} = S_n + (cos t, sin t)
(with S_n = n R_n (cos h_n, sin h_n)), the running means of the distance and the delay, the
majority kind (a tie keeps move), the strength back to 1 and the time last used."""

from __future__ import annotations

import math

import pytest

from hippo.cognitive_map.actions import MOVE, WAIT, Action
from hippo.cognitive_map.merge import merge_repeat


def attrs(**kw) -> dict:
    d = {"count": 1, "n_wait": 0, "heading": 0.0, "heading_r": 1.0, "distance": 10.0,
         "action": MOVE, "n_delay": 0, "delay": None, "strength": 0.25, "last_used": 3.0}
    d.update(kw)
    return d


def test_a_move_joins_the_circular_mean_of_the_moves_before():
    # three moves with mean heading 0 and resultant length 1/3: S = (1, 0); a fourth at pi/2
    # makes S = (1, 1): heading pi/4, R = sqrt(2) / 4; the distance 10 -> 10 + (30 - 10) / 4
    d = attrs(count=3, heading_r=1.0 / 3.0)
    merge_repeat(d, Action.move(math.pi / 2, 30.0), None, None)
    assert d["heading"] == pytest.approx(math.pi / 4, abs=1e-15)
    assert d["heading_r"] == pytest.approx(math.sqrt(2) / 4, abs=1e-15)
    assert d["distance"] == 15.0 and d["count"] == 4 and d["n_wait"] == 0
    assert d["action"] == MOVE


def test_waits_before_do_not_count_as_moves_in_the_mean():
    # count 5 with 3 waits: two moves, R = 1/2 at heading pi: S = (-1, 0); a move at -pi/2
    # gives S = (-1, -1): heading -3 pi / 4, R = sqrt(2) / 3, distance 4 + (10 - 4) / 3 = 6
    d = attrs(count=5, n_wait=3, heading=math.pi, heading_r=0.5, distance=4.0, action=WAIT)
    merge_repeat(d, Action.move(-math.pi / 2, 10.0), None, None)
    assert d["heading"] == pytest.approx(-3 * math.pi / 4, abs=1e-15)
    assert d["heading_r"] == pytest.approx(math.sqrt(2) / 3, abs=1e-15)
    assert d["distance"] == pytest.approx(6.0, abs=1e-15)
    # 6 samples, 3 waits: a tie, which keeps move
    assert (d["count"], d["n_wait"], d["action"]) == (6, 3, MOVE)


def test_the_mean_heading_is_wrapped_and_its_length_never_exceeds_1():
    # the same heading again and again: R stays 1 exactly (min(1, .) absorbs rounding up)
    for h in (0.1 * k for k in range(-31, 32)):
        d = attrs(heading=Action.move(h, 1.0).heading)
        for _ in range(4):
            merge_repeat(d, Action.move(h, 1.0), None, None)
            assert d["heading_r"] <= 1.0
            assert -math.pi < d["heading"] <= math.pi
    # opposite headings cancel: R = 0 (to rounding), and the distance is still averaged
    d = attrs(heading=0.5, distance=2.0)
    merge_repeat(d, Action.move(0.5 - math.pi, 4.0), None, None)
    assert d["heading_r"] == pytest.approx(0.0, abs=1e-15) and d["distance"] == 3.0


def test_a_rounded_resultant_above_1_is_capped_at_1():
    # n moves at heading h and one more: |S| = (n + 1) exactly, but n cos h + cos h and
    # n sin h + sin h round, and for many h |S| / (n + 1) comes out above 1: capped at 1
    over = [(n, h) for n in range(2, 10) for h in (0.001 * k for k in range(1, 3000))
            if math.hypot(n * math.cos(h) + math.cos(h),
                          n * math.sin(h) + math.sin(h)) / (n + 1) > 1.0]
    assert len(over) > 100
    for n, h in over[::50]:
        d = attrs(count=n, heading=h)
        merge_repeat(d, Action.move(h, 1.0), None, None)
        assert d["heading_r"] == 1.0 and d["count"] == n + 1


def test_the_first_move_after_waits_sets_heading_r_and_distance():
    for before in ({"count": 2, "n_wait": 2, "heading": None, "heading_r": None,
                    "distance": None},       # waits only: no move yet
                   {"count": 1, "n_wait": 0, "heading": None, "heading_r": None,
                    "distance": None}):      # a move count with no heading: taken afresh
        d = attrs(**before)
        merge_repeat(d, Action.move(-1.0, 7.5), None, None)
        assert (d["heading"], d["heading_r"], d["distance"]) == (-1.0, 1.0, 7.5)
    d = attrs(count=2, n_wait=2, heading=0.3, heading_r=0.8, distance=5.0)   # n_move 0
    merge_repeat(d, Action.move(2.0, 1.0), None, None)
    assert (d["heading"], d["heading_r"], d["distance"]) == (2.0, 1.0, 1.0)


def test_a_wait_counts_as_a_wait_and_leaves_the_move_attributes():
    d = attrs(count=2, n_wait=1, heading=0.7, heading_r=0.9, distance=12.0)
    merge_repeat(d, Action.wait(), None, None)
    assert (d["count"], d["n_wait"]) == (3, 2)
    assert (d["heading"], d["heading_r"], d["distance"]) == (0.7, 0.9, 12.0)
    assert d["action"] == WAIT            # 2 waits of 3: the majority
    d = attrs(count=1, n_wait=0)
    merge_repeat(d, Action.wait(), None, None)
    assert (d["count"], d["n_wait"], d["action"]) == (2, 1, MOVE)   # 1 of 2: a tie, move
    merge_repeat(d, Action.wait(), None, None)
    assert (d["count"], d["n_wait"], d["action"]) == (3, 2, WAIT)
    merge_repeat(d, Action.move(0.0, 10.0), None, None)
    assert (d["count"], d["n_wait"], d["action"]) == (4, 2, MOVE)   # 2 of 4: a tie


def test_the_delay_is_a_running_mean_over_the_samples_that_had_one():
    d = attrs()
    merge_repeat(d, Action.wait(), None, None)
    assert (d["n_delay"], d["delay"]) == (0, None)          # no delay: nothing changes
    merge_repeat(d, Action.wait(), 4.0, None)
    assert (d["n_delay"], d["delay"]) == (1, 4.0)           # the first: taken as it is
    merge_repeat(d, Action.wait(), 10.0, None)
    assert (d["n_delay"], d["delay"]) == (2, 7.0)           # 4 + (10 - 4) / 2
    merge_repeat(d, Action.wait(), 1.0, None)
    assert (d["n_delay"], d["delay"]) == (3, 5.0)           # 7 + (1 - 7) / 3
    merge_repeat(d, Action.wait(), None, None)
    assert (d["n_delay"], d["delay"]) == (3, 5.0)
    merge_repeat(d, Action.wait(), 0.0, None)                # a zero delay is a delay
    assert (d["n_delay"], d["delay"]) == (4, 3.75)


def test_the_strength_goes_back_to_1_and_the_time_is_kept_when_given():
    d = attrs(strength=0.25, last_used=3.0)
    merge_repeat(d, Action.wait(), None, None)
    assert d["strength"] == 1.0 and d["last_used"] == 3.0
    d["strength"] = 0.5
    merge_repeat(d, Action.move(0.0, 10.0), None, 8.5)
    assert d["strength"] == 1.0 and d["last_used"] == 8.5
    merge_repeat(d, Action.wait(), None, 0.0)                # time 0 is a time
    assert d["last_used"] == 0.0
