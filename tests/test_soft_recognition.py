"""Soft recognition (:mod:`hippo.soft_recognition`) on a hand-made map: which wanted stop a
moving robot approaches when the stop's place is coactive, with several drives."""

import numpy as np

from hippo.agent import Agent, AgentParams
from hippo.cognitive_map import Action, DriveParams
from hippo.sim import ArenaBuilder, World
from hippo.types import Mode


class _Places:
    """A place source the tests bypass (they set the layer's activity themselves)."""

    kind = "stub"
    n_units = 3

    def step(self, obs, truth=None):
        return np.array([1.0, 0.0, 0.0])

    def reset(self) -> None:
        pass

    def prime(self, sensors) -> None:
        pass


def agent_with_stops(drives: list[str], **params) -> tuple[Agent, int, dict[str, tuple]]:
    """An agent in place Q of a map ``Q -> P_k -> still@P_k -> moving@P_k``, one stop place
    ``P_k`` (place unit k + 1) for each drive that has a name other than ``idle``; every drive
    at level 1 except ``idle`` (level 0: not wanted). Returns the agent, Q and each drive's
    stop ``(P_k, still@P_k)``."""
    arena = ArenaBuilder("corridor", 200, 30).outer_walls().start(15, 15, 0.0).build()
    world = World(arena, seed=0)
    agent = Agent(_Places(), drives={d: DriveParams() for d in drives}, sensors=world.sensors,
                  robot=world.robot, seed=0, params=AgentParams(**params))
    layer, graph = agent.layer, agent.graph
    q = layer.recruit("place", 0)
    stops = {}
    for k, name in enumerate(d for d in drives if d != "idle"):
        c = layer.recruit("place", k + 1)
        still, moving = layer.recruit("still", None, c), layer.recruit("moving", None, c)
        graph.add_transition(q, c, Action.move(0.0, 20.0), 4.0)
        graph.add_transition(c, still, Action.wait(), 3.0)
        graph.add_transition(still, moving, Action.wait(), 10.0)
        agent.drives.reward(name, (still, moving))
        agent.drives.set_level(name, 1.0)
        stops[name] = (c, still)
    agent.brain.state = q
    agent.brain.decide.mode, agent.brain.decide.current = Mode.MOVE, (q, stops[drives[-1]][0])
    return agent, q, stops


def test_coactive_zero_disables_soft_recognition():
    """coactive = 0 turns the rule off, even for a stop place exactly as active as the winner
    (with coactive 0.6 that place is recognised)."""
    for coactive, approach in ((0.0, False), (0.6, True)):
        agent, q, stops = agent_with_stops(["cp"], coactive=coactive)
        agent.layer.place_activity = np.array([0.9, 0.9])
        agent.brain.decide.recognise_stop()
        assert (agent.mode == Mode.APPROACH) is approach
        assert agent.current == (stops["cp"] if approach else (q, stops["cp"][0]))


def test_a_drive_not_wanted_does_not_hide_the_next_ones():
    """The drives are asked in order; one that is not wanted (level 0) is skipped, and the
    next drive's coactive stop is approached."""
    agent, _q, stops = agent_with_stops(["idle", "cp"], coactive=0.6)
    assert agent.brain.drives.names[0] == "idle"
    agent.layer.place_activity = np.array([0.9, 0.6])
    agent.brain.decide.recognise_stop()
    assert agent.mode == Mode.APPROACH and agent.current == stops["cp"]


def test_a_drive_whose_stop_is_not_due_does_not_hide_the_next_ones():
    """Drive ``cp``'s stop is not due (the run since the last wait, for ``x``, is 90 cm short
    of its run-up); drive ``other`` is outside that taught chain (no bound): its coactive stop
    is approached, although ``cp``'s place is as coactive."""
    agent, _q, stops = agent_with_stops(["cp", "other"], coactive=0.6, runup_window=30.0)
    brain = agent.brain
    brain.runups, brain.runup_after = {"cp": 100.0, "x": 50.0}, {"cp": "x", "x": "cp"}
    brain.last_wait_drive, brain.wait_ended_at = "x", brain.odometer - 10.0
    assert brain.decide._not_due("cp") and not brain.decide._not_due("other")
    agent.layer.place_activity = np.array([0.9, 0.6, 0.6])
    brain.decide.recognise_stop()
    assert agent.mode == Mode.APPROACH and agent.current == stops["other"]
    # cp alone is not approached there
    agent, _q, stops = agent_with_stops(["cp"], coactive=0.6, runup_window=30.0)
    brain = agent.brain
    brain.runups, brain.runup_after = {"cp": 100.0, "x": 50.0}, {"cp": "x", "x": "cp"}
    brain.last_wait_drive, brain.wait_ended_at = "x", brain.odometer - 10.0
    agent.layer.place_activity = np.array([0.9, 0.6])
    brain.decide.recognise_stop()
    assert agent.mode == Mode.MOVE


def _stop_by(alias: bool) -> Agent:
    """A robot moving from Q towards C (``Q -> C`` met twice, 4 s after entering Q) enters B
    instead, 4 s after entering Q (``alias``: B stands in for C; else C is merely coactive and
    B was entered with no place before it), approaches C's stop, and stops 3 s (C's delay to
    its stop) after entering B."""
    agent, q, stops = agent_with_stops(["cp"], coactive=0.6)
    brain, decide, graph = agent.brain, agent.brain.decide, agent.graph
    c, _still = stops["cp"]
    b = agent.layer.recruit("place", 2)
    graph.add_transition(q, c, Action.move(0.0, 20.0), 4.0)      # met twice
    graph.add_transition(q, b, Action.move(0.0, 20.0), 4.0)
    brain.t, brain.state, brain.entered_at = 10.0, b, 9.0
    if alias:
        brain._entries[q], brain._ctx_before = (5.0, (0.0, 0.0, 0.0)), q
        agent.layer.place_activity = np.array([0.0, 0.1, 0.9])   # C far from coactive
        assert brain.came_from == q and decide.alias_of(b, c)
    else:
        agent.layer.place_activity = np.array([0.0, 0.6, 0.9])   # C coactive
        assert brain.came_from is None
    decide.recognise_stop()
    assert agent.mode == Mode.APPROACH and agent.current == stops["cp"]
    assert decide._approach_t0 == (9.0 if alias else 10.0)   # from entering B / recognising C
    brain.t = (9.0 if alias else 10.0) + 3.0
    decide.check_wait()
    assert agent.mode == Mode.WAIT
    return agent


def test_a_stop_approached_by_an_alias_is_timed_one_by_coactivity_is_not():
    """A stand-in entered when C was due times the stop from its entry as if it were C: the
    stop is a measurement of C's delay to its stop. A stop recognised by coactivity comes
    some time after C was entered, unknown: the map and the transition cells learn no delay
    from it (``untimed_stop``)."""
    from hippo.types import StateKind
    assert not _stop_by(alias=True).decide.untimed_stop(StateKind.STILL)
    assert _stop_by(alias=False).decide.untimed_stop(StateKind.STILL)


def test_a_drive_with_two_stops_approaches_the_one_whose_place_is_coactive():
    """Drive ``cp`` rewarded at two stops, the first one's place far from coactive, the
    second one's coactive: the second stop is approached."""
    agent, _q, stops = agent_with_stops(["cp", "other"], coactive=0.6)
    d, still_d = stops["other"]
    agent.drives.reward("cp", next(iter(agent.graph.outgoing(still_d))))
    agent.drives.set_level("cp", 1.0)               # (a reward satisfies the drive)
    agent.drives.set_level("other", 0.0)
    assert list(agent.brain.decide._taught_stops("cp")) == [stops["cp"], stops["other"]]
    agent.layer.place_activity = np.array([0.9, 0.1, 0.6])
    agent.brain.decide.recognise_stop()
    assert agent.mode == Mode.APPROACH and agent.current == (d, still_d)


def test_a_stop_place_the_place_cells_do_not_code_is_skipped():
    """A map place whose unit lies past the place layer's activity (here unit 1 of 1 unit)
    cannot be coactive: no approach, and no error."""
    agent, q, stops = agent_with_stops(["cp"], coactive=0.6)
    agent.layer.place_activity = np.array([0.9])
    agent.brain.decide.recognise_stop()
    assert agent.mode == Mode.MOVE and agent.current == (q, stops["cp"][0])


def test_companions_of_another_stop_do_not_touch_this_one():
    """Companions are kept per stop: with a table only for ``other``'s stop, ``cp``'s stop
    (its place not coactive) has no companion and is not approached."""
    agent, q, stops = agent_with_stops(["cp", "other"], coactive=0.6, companions=2)
    agent.drives.set_level("other", 0.0)
    agent.brain.decide._companions = {stops["other"]: {q: (5, 1.0)}}
    agent.layer.place_activity = np.array([0.9, 0.1, 0.1])
    agent.brain.decide.recognise_stop()
    assert agent.mode == Mode.MOVE
