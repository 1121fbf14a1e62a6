"""Map quality the CSCG way: held-out bits per step, states per true place."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hippo.cognitive_map.quality import next_state_bits, states_per_place, transitions_of


def test_bits_follow_the_smoothed_formula_on_a_tiny_case():
    # train: a->b twice, b->a once; symbols {a, b}: m(a) = 1.5/4, m(b) = 2.5/4; prior 1
    bits = next_state_bits(["a", "a", "b"], ["b", "b", "a"], ["a", "b", "c"], ["b", "b", "a"])
    p_ab = (2 + 2.5 / 4) / (2 + 1)
    p_bb = (0 + 2.5 / 4) / (1 + 1)
    p_ca = 1.5 / 4  # unseen state: the marginal
    want = -(math.log2(p_ab) + math.log2(p_bb) + math.log2(p_ca)) / 3
    assert bits == pytest.approx(want)


def test_a_deterministic_cycle_costs_almost_nothing_and_a_coin_one_bit():
    cyc = list(range(5)) * 200
    s, n = transitions_of(cyc)
    assert next_state_bits(s, n, s, n) < 0.02
    rng = np.random.default_rng(0)
    coin = rng.integers(2, size=4000).tolist()
    s, n = transitions_of(coin)
    assert next_state_bits(s[:2000], n[:2000], s[2000:], n[2000:]) == pytest.approx(1.0, abs=0.02)


def test_transitions_of_pairs_states_with_next_observations():
    assert transitions_of([1, 2, 3], ["x", "y", "z"]) == ([1, 2], ["y", "z"])
    with pytest.raises(ValueError, match="same length"):
        transitions_of([1, 2], ["x"])


def test_states_per_place_counts_the_states_that_cover_a_place():
    places = ["p"] * 10 + ["q"] * 10
    states = [1] * 10 + [2] * 5 + [3] * 4 + [4]
    assert states_per_place(states, places) == {"p": 1, "q": 2}
    assert states_per_place(states, places, coverage=1.0) == {"p": 1, "q": 3}
    with pytest.raises(ValueError, match="coverage"):
        states_per_place(states, places, coverage=0.0)


def test_bad_lengths_are_named():
    with pytest.raises(ValueError, match="train_states"):
        next_state_bits([1, 2], [1], [1], [1])
    with pytest.raises(ValueError, match="at least one"):
        next_state_bits([], [], [1], [1])


def test_a_next_symbol_seen_only_in_the_test_sequence_is_in_the_marginal():
    # K counts the symbols of training AND test: train a->x, a->y; test a->z (never trained).
    # K = 3, N = 2: m(z) = 0.5 / (2 + 1.5) = 1/7; P(z | a) = (0 + 1/7) / (2 + 1) = 1/21
    bits = next_state_bits(["a", "a"], ["x", "y"], ["a"], ["z"])
    assert bits == pytest.approx(math.log2(21))
    # a weaker prior trusts the counts more: the unseen z costs more bits
    assert next_state_bits(["a", "a"], ["x", "y"], ["a"], ["z"], prior=0.5) > bits


def test_a_bad_prior_or_coverage_or_length_is_named():
    with pytest.raises(ValueError, match=r"^prior\b"):
        next_state_bits([1], [1], [1], [1], prior=0.0)
    with pytest.raises(ValueError, match="next_state_bits needs"):
        next_state_bits([1], [1], [], [])
    with pytest.raises(ValueError, match=r"test_states \(2\) and test_next \(1\)"):
        next_state_bits([1], [1], [1, 2], [1])
    with pytest.raises(ValueError, match="coverage"):
        states_per_place([1], ["p"], coverage=1.01)
    with pytest.raises(ValueError, match=r"states \(2\) and places \(1\).*same length"):
        states_per_place([1, 2], ["p"])
