"""hippo — hippocampus-inspired navigation for a small simulated robot.

Sub-packages:

- :mod:`hippo.sim` — the robot's 2-D world (pymunk), arenas, controllers, teacher, recordings.
- :mod:`hippo.perception` — reservoir, SFA, ICA, the RC-SFA-ICA place cells, the state layer.
- :mod:`hippo.timing` — spectral timing, NLMS transition cells, non-occurrence.
- :mod:`hippo.cognitive_map` — transition graph, drives, planner.
- :mod:`hippo.agent` — the closed loop joining them.
"""

__version__ = "0.1.0"
