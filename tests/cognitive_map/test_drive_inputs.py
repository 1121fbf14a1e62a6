"""The planner's inputs (hippo.cognitive_map.inputs): HIREL's drive input
``I(n) = max_d level(d) · W_{d,n}`` with the exploration threshold, the inferred moves' mask,
and the checks of inputs given by hand."""

from __future__ import annotations

import numpy as np
import pytest

from hippo.cognitive_map import DriveParams, Drives, TransitionGraph
from hippo.cognitive_map.inputs import drive_input, effective_levels, inferred_mask, input_array


def line() -> TransitionGraph:
    g = TransitionGraph()
    g.add_transition(0, 1, (0.0, 10.0))
    g.add_transition(1, 2, (0.0, 10.0))
    g.add_transition(2, 2, "wait")
    return g


def drives(**levels: float) -> Drives:
    d = Drives({n: DriveParams(learning_rate=0.5) for n in levels})
    for n, v in levels.items():
        d.set_level(n, v)
    return d


def test_the_input_is_the_largest_level_times_link_weight():
    g, d = line(), drives(hunger=0.5, thirst=0.8)
    d.link("hunger", (2, 2))                 # W = 0.5 after one reward at learning rate 0.5
    d.link("thirst", (2, 2))
    d.link("thirst", (2, 2))                 # W = 0.75
    d.link("hunger", (0, 1))
    d.link("hunger", (0, 1))
    d.link("hunger", (0, 1))                 # W = 0.875
    pos = g.index().pos
    I = drive_input(g, d)
    assert I[pos[(2, 2)]] == pytest.approx(max(0.5 * 0.5, 0.8 * 0.75))   # 0.6, not 0.25
    assert I[pos[(0, 1)]] == pytest.approx(0.5 * 0.875)
    assert I[pos[(1, 2)]] == 0.0                                        # no link: no input
    # the order of the drives does not matter: the maximum, not the last one
    d.set_level("thirst", 0.2)
    assert drive_input(g, d)[pos[(2, 2)]] == pytest.approx(0.5 * 0.5)


def test_a_drive_below_the_exploration_threshold_gives_no_input():
    g, d = line(), drives(hunger=0.04)
    d.link("hunger", (2, 2))
    k = g.index().pos[(2, 2)]
    assert drive_input(g, d)[k] == pytest.approx(0.02)
    assert drive_input(g, d, threshold=0.05)[k] == 0.0
    d.set_level("hunger", 0.05)                              # at the threshold: active
    assert drive_input(g, d, threshold=0.05)[k] == pytest.approx(0.025)
    assert effective_levels(d, 0.05) == {"hunger": 0.05}
    assert effective_levels(d, 0.06) == {"hunger": 0.0}
    assert effective_levels(d) == {"hunger": 0.05}           # default: every positive level
    # links to transitions the graph does not hold are ignored
    d.link("hunger", (7, 8))
    assert drive_input(g, d).shape == (len(g),)


def test_the_mask_marks_inferred_moves_only():
    g = line()
    assert not inferred_mask(g).any() and inferred_mask(g).shape == (3,)
    back = g.infer_reverse((0, 1))
    mask = inferred_mask(g)
    assert mask.dtype == bool and mask.sum() == 1 and mask[g.index().pos[back]]


def test_inputs_given_by_hand_are_checked():
    g = line()
    pos = g.index().pos
    arr = input_array(g, [1, 0, 0])
    assert arr.dtype == np.float64 and arr.tolist() == [1.0, 0.0, 0.0]
    by_name = input_array(g, {(2, 2): 0.5})
    assert by_name[pos[(2, 2)]] == 0.5 and by_name.sum() == 0.5
    with pytest.raises(ValueError, match=r"^drive inputs must have shape \(3,\), got \(2,\)$"):
        input_array(g, [0.1, 0.2])
    with pytest.raises(ValueError, match=r"^drive inputs contains 1 non-finite value"):
        input_array(g, [0.1, np.nan, 0.2])
    with pytest.raises(ValueError, match=r"^drive inputs must lie in \[0, 1\]"):
        input_array(g, [0.1, 1.5, 0.2])
    with pytest.raises(KeyError, match="unknown transition 5->6"):
        input_array(g, {(5, 6): 0.5})
