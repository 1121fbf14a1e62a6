"""hippo.tasks: the building blocks of a task, for scenarios and users alike.

- :class:`Session` (``session.py``) — an agent in a world with its teacher and its log; runs
  the closed loop (``run``), walks the robot on the leash (``lead``), holds it (``block``),
  picks it up and puts it down (``put``), writes ``run.npz`` (``save``).
- :func:`explore`, :class:`Tour`, :func:`make_places`, :func:`learn_map`, :func:`wall_side`,
  :func:`wall_tour`, ``PLACE_STATES`` (``explore.py``) — the robot's own tour, the place
  cells fitted on it, the map learned from it, the wall to explore along for a route, the
  loop the exploring wall follower runs as a route.
- :class:`Experimenter` (``teaching.py``) — the reward sound after a stop in a zone.
- :class:`Route`, :class:`LapCounter`, :func:`lead_from` (``routes.py``) — routes through an
  arena's checkpoints, progress along them, laps.
- :class:`AngleLaps`, :func:`progress_along`, :func:`route_passes`, :func:`passes`,
  :func:`stops` (``passes.py``) — checkpoint passes and stops read from a run's log.
- :class:`PatrolCourse`, :class:`PatrolPhase`, :func:`patrol_route`, :func:`check_patrol`,
  :func:`pass_report`, :func:`random_patrol`, ``ARENA_CHECKPOINTS``, ``HIREL_WAITS``
  (``patrol.py``) — a timed patrol on any arena: its lesson, its laps, what each pass by a
  checkpoint gave, and checkpoint sets nobody chose (for held-out tests).
- :func:`teach_patrol`, :class:`Lesson` (``lesson.py``) — a taught patrol robot in one call, on
  any arena (a built-in one's name or an ``Arena`` of one's own): what ``hippo run patrol``
  does before its patrol.
- :class:`Log`, :func:`event_arrays`, :func:`enum_names` (``log.py``) — the per-tick log and
  its files.

A task is a short phase script on these: ``scenarios/patrol_new_arena.py`` (a patrol in an
arena of one's own, on :func:`teach_patrol`) and ``scenarios/patrol_square.py`` (the same
from the building blocks) in the repository.
"""

from hippo.tasks.explore import (
    PAUSE_RATE,
    PLACE_STATES,
    Tour,
    explore,
    learn_map,
    make_places,
    wall_side,
    wall_tour,
)
from hippo.tasks.lesson import LEARNED_SECTORS, Lesson, teach_patrol
from hippo.tasks.log import Log, enum_names, event_arrays
from hippo.tasks.passes import AngleLaps, passes, progress_along, route_passes, stops
from hippo.tasks.patrol import (
    ARENA_CHECKPOINTS,
    HIREL_WAITS,
    PatrolCourse,
    PatrolPhase,
    PatrolWarning,
    check_patrol,
    pass_report,
    patrol_route,
    random_patrol,
)
from hippo.tasks.routes import LapCounter, Route, lead_from
from hippo.tasks.session import Session
from hippo.tasks.teaching import Experimenter

__all__ = [
    "ARENA_CHECKPOINTS", "HIREL_WAITS", "LEARNED_SECTORS", "PAUSE_RATE", "PLACE_STATES",
    "AngleLaps", "Experimenter", "LapCounter", "Lesson", "Log", "PatrolCourse", "PatrolPhase",
    "PatrolWarning", "Route", "Session", "Tour", "check_patrol", "enum_names", "event_arrays",
    "explore", "lead_from", "learn_map", "make_places", "pass_report", "passes", "patrol_route",
    "progress_along", "random_patrol", "route_passes", "stops", "teach_patrol", "wall_side",
    "wall_tour",
]
