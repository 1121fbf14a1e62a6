"""Edges of the map's contract found by mutation testing: what ``version`` counts, where decay
draws its line, a plan's length limit, and names in errors."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hippo.cognitive_map import DriveParams, Drives, Planner, TransitionGraph
from hippo.cognitive_map.synthetic import transitions_from_state_edges


def test_version_grows_on_every_new_state():
    g = TransitionGraph()
    versions = [g.version]
    for s in (1, 2, 3):
        g.add_state(s)
        versions.append(g.version)
    assert versions == sorted(set(versions))  # strictly growing
    g.add_state(2)  # already known: nothing changed
    assert g.version == versions[-1]


def test_decay_keeps_a_strength_exactly_at_the_threshold():
    # "drop those below threshold": 1 -> 0.5 -> 0.25 = threshold stays, 0.125 goes
    g = transitions_from_state_edges([(1, 2)], both_ways=False)
    assert g.decay(0.5, threshold=0.25) == []
    assert g.decay(0.5, threshold=0.25) == [] and g.transitions == [(1, 2)]
    assert g.decay(0.5, threshold=0.25) == [(1, 2)] and g.transitions == []


def test_mark_used_names_a_bad_time():
    g = transitions_from_state_edges([(1, 2)], both_ways=False)
    with pytest.raises(ValueError, match=r"^time\b"):
        g.mark_used((1, 2), time=math.nan)


def test_a_plan_stops_after_max_steps():
    g = transitions_from_state_edges((i, i + 1) for i in range(8))
    d = Drives({"goal": DriveParams(learning_rate=1.0)})
    d.link("goal", (7, 8))
    d.set_level("goal", 1.0)
    full = Planner().plan(g, d, 0)
    assert full == [(i, i + 1) for i in range(8)]
    assert Planner().plan(g, d, 0, max_steps=3) == full[:3]
    for bad, match in ((math.nan, "an integer, got nan"),
                       ("3", "an integer, got '3'"),
                       (2.7, "an integer, got 2.7"), (0, "an integer >= 1, got 0"),
                       (True, r"an integer, got True \(a bool\)")):
        with pytest.raises(ValueError, match=f"^max_steps must be {match}"):
            Planner().plan(g, d, 0, max_steps=bad)


@pytest.mark.parametrize(("seed", "match"), [
    (1.5, r"^seed must be an integer, got 1.5"), (-1, r"^seed must be an integer in \[0, "),
    (2**63, r"^seed must be an integer in \[0, "), ("1", r"^seed must be an integer, got '1'"),
])
def test_a_bad_planner_seed_is_named(seed, match):
    with pytest.raises(ValueError, match=match):
        Planner(seed=seed)
    for good in (0, 2**63 - 1):  # a valid seed seeds the generator as before
        assert Planner(seed=good).rng.random() == np.random.default_rng(good).random()


def test_a_move_heading_is_kept_in_minus_pi_to_pi():
    from hippo.cognitive_map import Action

    assert Action.move(-math.pi, 5.0).heading == math.pi  # the (-pi, pi] convention
    assert Action.move(math.pi, 5.0).heading == math.pi
    assert Action.move(-3.0, 5.0).heading == -3.0
    assert Action.move(0.0, 0.0).distance == 0.0  # a zero-length move is allowed
    with pytest.raises(ValueError, match=r"^distance\b"):
        Action.move(0.0, -1.0)
    with pytest.raises(ValueError, match=r"^heading\b"):
        Action("move", math.nan, 1.0)
    for heading, distance in ((1.0, None), (None, 1.0)):
        with pytest.raises(ValueError, match=r"^a move action needs both a heading"):
            Action("move", heading, distance)


def test_same_as_sees_an_attribute_that_differs():
    g, h = (transitions_from_state_edges([(1, 2), (2, 3)]) for _ in range(2))
    assert g.same_as(h)
    h.add_transition(1, 2, (0.0, 1.0), delay=3.0)  # one more sample, with a delay
    assert set(g.transitions) == set(h.transitions) and not g.same_as(h)


def test_the_index_arrays_spell_out_its_transitions():
    g = transitions_from_state_edges([(1, 2), (2, 5)])
    idx = g.index()
    assert [(int(a), int(b)) for a, b in zip(idx.a, idx.b)] == list(idx.nodes)
    assert all(idx.pos[t] == i for i, t in enumerate(idx.nodes))


def test_add_transition_names_a_bad_time():
    g = TransitionGraph()
    with pytest.raises(ValueError, match=r"^time\b"):
        g.add_transition(1, 2, (0.0, 1.0), time=math.inf)
