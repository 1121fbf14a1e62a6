"""Figures (matplotlib, Agg backend). Every plotting function returns ``(fig, ax)`` (or
``(fig, axes)``, an array, for figures with several panels); the ``plot_place_preference`` and
``plot_patrol`` writers save a scenario's figures and return their paths.

- ``hippo.plots.sim`` — :func:`draw_arena`, :func:`plot_trajectory`, :func:`plot_sensor_strip`
- ``hippo.plots.perception`` — :func:`plot_place_cell`, :func:`plot_activation_map`,
  :func:`plot_units_over_arena`, :func:`plot_sfa_units`
- ``hippo.plots.timing`` — :func:`plot_fig6`, :func:`plot_reproduction`
- ``hippo.plots.cognitive_map`` — :func:`plot_cognitive_map`, :func:`state_layout`
- ``hippo.plots.agent`` — :func:`plot_map`, :func:`plot_trials`, :func:`plot_wait_profiles`,
  :func:`plot_waits_table`, :func:`state_centres`; writers :func:`plot_place_preference`,
  :func:`plot_patrol`
"""

import matplotlib

if matplotlib.get_backend().lower() not in ("agg", "pdf", "svg", "ps", "cairo"):
    matplotlib.use("Agg")

from hippo.plots.agent import (
    plot_map,
    plot_patrol,
    plot_place_preference,
    plot_trials,
    plot_wait_profiles,
    plot_waits_table,
    state_centres,
)
from hippo.plots.cognitive_map import plot_cognitive_map, state_layout
from hippo.plots.perception import (
    plot_activation_map,
    plot_place_cell,
    plot_sfa_units,
    plot_units_over_arena,
)
from hippo.plots.sim import draw_arena, plot_sensor_strip, plot_trajectory
from hippo.plots.timing import plot_fig6, plot_reproduction

__all__ = [
    "draw_arena", "plot_activation_map", "plot_cognitive_map", "plot_fig6", "plot_map",
    "plot_patrol", "plot_place_cell", "plot_place_preference", "plot_reproduction",
    "plot_sensor_strip", "plot_sfa_units", "plot_trajectory", "plot_trials",
    "plot_units_over_arena", "plot_wait_profiles", "plot_waits_table", "state_centres",
    "state_layout",
]
