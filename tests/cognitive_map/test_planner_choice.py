"""The planner's choice (Planner.decide): a drive-led pick, the noise on it (relative to the
best activity), exploration, a state with nowhere to go, and the reproducibility of its random
draws; the goal test of a propagated activity; the planner's parameter checks."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import norm

from hippo.cognitive_map import DriveParams, Drives, Planner, PlannerParams, TransitionGraph
from hippo.cognitive_map.inputs import drive_input


def fork() -> tuple[TransitionGraph, Drives]:
    """State 0 forks to 1 and 2; 1 -> 3 and 2 -> 3 is the goal ``(3, 3)`` ("wait")."""
    g = TransitionGraph()
    for a, b in [(0, 1), (0, 2), (1, 3), (2, 3)]:
        g.add_transition(a, b, (0.0, 10.0))
    g.add_transition(3, 3, "wait")
    d = Drives({"goal": DriveParams(learning_rate=1.0)})
    d.set_level("goal", 1.0)
    return g, d


def test_a_drive_led_pick_is_not_exploration_and_draws_nothing_at_zero_noise():
    g, d = fork()
    d.link("goal", (3, 3))
    g.add_transition(0, 4, (0.0, 10.0))       # a third way out that leads nowhere
    p = Planner(PlannerParams(noise=0.0))
    c = p.decide(g, d, 0, np.random.default_rng(5))
    assert c.transition in {(0, 1), (0, 2)} and not c.explored
    assert c.activity == pytest.approx(p.activity(g, d)[c.transition]) and c.activity > 0
    # a unique best pick at zero noise takes no random draw: the generator is where it was
    rng = np.random.default_rng(5)
    single = p.decide(g, d, 1, rng)
    assert single.transition == (1, 3) and not single.explored
    assert rng.random() == np.random.default_rng(5).random()


def test_noise_is_relative_to_the_best_activity():
    # two moves whose activities are 0.5 * best and 0.45 * ... apart: with noise sd = noise * best
    # the weaker one wins P(N(0, sqrt(2) sd) > gap) of the time
    g = TransitionGraph()
    g.add_transition(0, 1, (0.0, 1.0))
    g.add_transition(0, 2, (0.0, 1.0))
    d = Drives({"a": DriveParams(learning_rate=1.0), "b": DriveParams(learning_rate=1.0)})
    d.link("a", (0, 1))
    d.link("b", (0, 2))
    d.set_level("a", 0.5)
    d.set_level("b", 0.45)
    p = Planner(PlannerParams(noise=0.1, exploration_threshold=0.0))
    act = p.activity(g, d)
    best, gap = act[(0, 1)], act[(0, 1)] - act[(0, 2)]
    assert best == pytest.approx(0.5) and gap == pytest.approx(0.05)
    rng = np.random.default_rng(11)
    picks = [p.decide(g, d, 0, rng).transition for _ in range(2000)]
    weak = sum(t == (0, 2) for t in picks) / len(picks)
    want = norm.sf(gap / (np.sqrt(2) * 0.1 * best))      # 0.24 (0.43 if sd were noise / best)
    assert weak == pytest.approx(want, abs=0.04)
    # no noise: always the best
    p0 = Planner(PlannerParams(noise=0.0, exploration_threshold=0.0))
    assert {p0.decide(g, d, 0, rng).transition for _ in range(50)} == {(0, 1)}


def test_exploration_and_a_dead_end():
    g, d = fork()                          # no goal link: no activity, a random pick
    c = Planner().decide(g, d, 0, np.random.default_rng(0))
    assert c.transition in {(0, 1), (0, 2)} and c.explored and c.activity == 0.0
    g.add_transition(5, 6, (0.0, 1.0))
    dead = Planner().decide(g, d, 6, np.random.default_rng(0))   # state 6 has no way out
    assert dead == type(dead)(None, 0.0, False)
    assert dead.activity == 0.0 and dead.explored is False
    # the planner's own generator is seeded: two planners with one seed explore alike
    a, b = Planner(seed=3), Planner(seed=3)
    assert [a.decide(g, d, 0).transition for _ in range(20)] == \
        [b.decide(g, d, 0).transition for _ in range(20)]
    with pytest.raises(TypeError, match=r"^rng must be a numpy.random.Generator, got str$"):
        Planner().decide(g, d, 0, "abc")
    with pytest.raises(TypeError, match=r"^params must be PlannerParams, got 'x'$"):
        Planner("x")


def test_a_goal_is_a_transition_whose_activity_is_its_own_input():
    g, d = fork()
    d.link("goal", (3, 3))
    act = Planner(PlannerParams(noise=0.0)).activity(g, d)
    assert act.is_goal((3, 3)) and act.is_goal((3, 3), rtol=0.0)     # input == value
    assert not act.is_goal((1, 3))                  # active, but from its successor
    assert act[(1, 3)] > 0 and drive_input(g, d)[g.index().pos[(1, 3)]] == 0
    with pytest.raises(KeyError, match="unknown transition 5->6"):
        act[(5, 6)]


@pytest.mark.parametrize(("field", "value", "message"), [
    ("noise", -0.1, r"^PlannerParams.noise must be finite and >= 0"),
    ("exploration_threshold", 1.5, r"^PlannerParams.exploration_threshold"),
    ("replan_tolerance", -1.0, r"^PlannerParams.replan_tolerance must be finite and >= 0"),
    ("inferred_weight", 0.0, r"^PlannerParams.inferred_weight"),
    ("inferred_weight", 1.5, r"^PlannerParams.inferred_weight"),
])
def test_planner_parameters_out_of_range_are_refused_by_name(field, value, message):
    with pytest.raises(ValueError, match=message):
        PlannerParams(**{field: value})


def test_an_inferred_move_may_weigh_as_much_as_a_real_one():
    assert PlannerParams(inferred_weight=1.0).inferred_weight == 1.0    # (0, 1]: 1 allowed
