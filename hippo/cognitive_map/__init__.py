"""hippo.cognitive_map — HIREL's cognitive map: transition graph, drives, planner.

Typical use inside the agent::

    from hippo.cognitive_map import Drives, DriveParams, Planner, PlannerParams, TransitionGraph

    graph = TransitionGraph()
    drives = Drives({"sound": DriveParams(epsilon=0.02)})
    planner = Planner(PlannerParams(w=0.9, noise=0.01), seed=0)

    last = graph.add_transition(prev, new, (heading, distance), delay)   # winner changed
    drives.reward("sound", last)                                         # reward arrived
    drives.step(dt, inhibited={"sound"} if non_occurrence else ())       # every tick
    t = planner.choose(graph, drives, current_state, rng)                # decision point
    action = graph.action(t)                                             # Action(move|wait)
"""

from hippo.cognitive_map.drives import DriveParams, Drives
from hippo.cognitive_map.graph import (
    MOVE,
    WAIT,
    Action,
    Transition,
    TransitionGraph,
    TransitionIndex,
)
from hippo.cognitive_map.localise import LocaliserParams, MapLocaliser
from hippo.cognitive_map.planner import (
    Activity,
    Choice,
    Planner,
    PlannerParams,
    drive_input,
    propagate,
    propagate_reference,
)
from hippo.cognitive_map.quality import next_state_bits, states_per_place, transitions_of

__all__ = [
    "MOVE",
    "WAIT",
    "Action",
    "Activity",
    "Choice",
    "DriveParams",
    "Drives",
    "LocaliserParams",
    "MapLocaliser",
    "Planner",
    "PlannerParams",
    "Transition",
    "TransitionGraph",
    "TransitionIndex",
    "drive_input",
    "next_state_bits",
    "propagate",
    "propagate_reference",
    "states_per_place",
    "transitions_of",
]
