"""hippo — hippocampus-inspired navigation for a small simulated robot.

Sub-packages:

- :mod:`hippo.sim` — the robot's 2-D world (pymunk), arenas, controllers, teacher, recordings.
- :mod:`hippo.perception` — reservoir, SFA, ICA, the RC-SFA-ICA place cells, the state layer.
- :mod:`hippo.timing` — spectral timing, NLMS transition cells, non-occurrence.
- :mod:`hippo.cognitive_map` — transition graph, drives, planner.
- :mod:`hippo.types` — the shared vocabulary (Observation vs GroundTruth, Mode, StateKind,
  Transition, wrap_angle); :mod:`hippo.seeds` — one seed, named random streams.
- :mod:`hippo.brain` — the per-tick neural loop, ``Brain.step(obs) -> Tick`` (decisions in
  :mod:`hippo.decision`, place sources in :mod:`hippo.places`).
- :mod:`hippo.motor` — a tick's decision and the senses to wheel speeds.
- :mod:`hippo.agent` — the whole robot: Brain + Motor.
- :mod:`hippo.tasks` — the task library (sessions, exploration, teaching, routes, logs).

``docs/architecture.md`` describes the tick and where to add an arena, a sensor, a neural
module or a task.
"""

__version__ = "0.1.0"
