"""The decider's wait rules (:mod:`hippo.waits`) on a hand-made map: when a soft approach
stops, what the robot does when a wait is over, which drive a stop serves."""

import numpy as np
from test_soft_recognition import agent_with_stops

from hippo.cognitive_map import Action
from hippo.types import Mode, StateKind


def test_a_soft_approach_stops_the_lead_before_the_maps_delay():
    """A stop recognised by coactivity at t = 10 s is timed by the map's delay of C's stop
    (3 s) less the lead (the cells' latency 0.4 s and stop_lead 0.5 ticks of 0.2 s: 0.5 s):
    the robot stops 2.5 s after the recognition."""
    for t, stops in ((12.45, False), (12.55, True)):
        agent, _q, st = agent_with_stops(["cp"], coactive=0.6)
        brain = agent.brain
        p = brain.p
        assert (p.transitions.latency, p.stop_lead, p.dt) == (0.4, 0.5, 0.2)
        brain.t = 10.0
        agent.layer.place_activity = np.array([0.9, 0.6])
        brain.decide.recognise_stop()
        assert agent.mode == Mode.APPROACH and agent.current == st["cp"]
        brain.t = t
        brain.decide.check_wait()
        assert (agent.mode == Mode.WAIT) is stops


def test_when_a_wait_is_over_the_robot_moves_on_from_the_stops_place():
    """The wait ``still@C -> moving@C`` ends (the robot moves again, in moving@C): the drive it
    served is inhibited and the next move is chosen out of C (C -> D), not out of moving@C. A
    stop the robot makes after that is not the finished wait's."""
    agent, _q, st = agent_with_stops(["cp"], coactive=0.6)
    brain, decide, graph = agent.brain, agent.brain.decide, agent.graph
    c, still = st["cp"]
    moving = next(iter(graph.outgoing(still)))[1]
    d = agent.layer.recruit("place", 2)
    graph.add_transition(c, d, Action.move(1.0, 20.0), 4.0)
    decide.current = (still, moving)       # stopped: waiting for the wait to end
    decide._wait_on((still, moving))
    brain.state = moving

    class _Over:
        strength, delay_over, elapsed_fraction = 1.0, True, 1.0

    brain.readouts = {(still, moving): _Over()}
    decide.check_wait()
    assert agent.drives.is_inhibited("cp")
    assert agent.current == (c, d) and agent.mode in (Mode.MOVE, Mode.APPROACH)
    assert decide.intended_source(still, StateKind.STILL, c, 5.0) == (c, 5.0)


def test_the_drive_a_stop_serves():
    """wait_drive: the drive linked to the stop being approached or waited for; none (-1) for
    a move, or while merely moving towards the stop."""
    agent, q, st = agent_with_stops(["cp"], coactive=0.6)
    decide = agent.brain.decide
    decide.mode, decide.current = Mode.APPROACH, st["cp"]
    assert decide.wait_drive() == 0
    decide.mode = Mode.MOVE
    assert decide.wait_drive() == -1
    decide.mode, decide.current = Mode.APPROACH, (q, st["cp"][0])   # no drive's wait
    assert decide.wait_drive() == -1


def test_of_two_drives_linked_to_one_stop_the_run_ups_pick_the_due_one():
    """Taught order x -> a -> b, run-ups a 100 cm, b 50 cm, runup_window 30 cm: from a wait for
    x, a stop 130 cm on (exactly the window past a's run-up) serves a; 131 cm on, b (its
    stop due at 150 cm)."""
    agent, _q, _st = agent_with_stops(["a", "b", "x"], runup_window=30.0)
    brain = agent.brain
    brain.runups, brain.runup_after = {"a": 100.0, "b": 50.0}, {"a": "x", "b": "a"}
    brain.last_wait_drive = "x"
    for ran, served in ((130.0, ["a"]), (131.0, ["b"]), (200.0, ["a", "b"])):
        brain.wait_ended_at = brain.odometer - ran
        assert brain.decide._by_runup(["a", "b"]) == served


class _Readout:
    def __init__(self, strength: float, delay_over: bool = False, fraction: float = 0.0):
        self.strength, self.delay_over, self.elapsed_fraction = strength, delay_over, fraction


def test_an_approach_in_the_stops_place_is_timed_by_the_transition_cells():
    """Approaching C's stop in C itself (C won), the robot stops when the cells' readout of
    ``C -> still@C`` (strong enough: min_strength) says its delay is over, not before, and
    the stop is timed; or, untimed, when a strong readout of a move out of C (C -> D) has
    run leave_fraction of its delay: the robot would usually have left C by then."""
    def check(readouts: dict) -> tuple[Mode, bool]:
        agent, _q, st = agent_with_stops(["cp"], coactive=0.6)
        brain, decide = agent.brain, agent.brain.decide
        c, still = st["cp"]
        d = agent.layer.recruit("place", 2)
        agent.graph.add_transition(c, d, Action.move(1.0, 20.0), 4.0)
        brain.t, brain.state = 10.0, c
        decide.mode, decide.current, decide._approach_t0 = Mode.APPROACH, (c, still), 10.0
        decide._entry_timed = True
        brain.readouts = {({"stop": (c, still), "move": (c, d)})[k]: r
                          for k, r in readouts.items()}
        decide.check_wait()
        return agent.mode, decide.stop_untimed

    p = agent_with_stops(["cp"])[0].brain.p
    weak, strong, leave = 0.5 * p.transitions.min_strength, p.transitions.min_strength, \
        p.leave_fraction
    assert check({"stop": _Readout(strong)}) == (Mode.APPROACH, False)
    assert check({"stop": _Readout(strong, delay_over=True)}) == (Mode.WAIT, False)
    assert check({"stop": _Readout(strong), "move": _Readout(strong, fraction=leave)}) \
        == (Mode.WAIT, True)
    assert check({"stop": _Readout(strong),
                  "move": _Readout(strong, fraction=0.9 * leave)})[0] == Mode.APPROACH
    assert check({"stop": _Readout(strong),
                  "move": _Readout(weak, fraction=leave)})[0] == Mode.APPROACH
