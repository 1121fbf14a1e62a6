"""Drawing an arena and the robot into an RGB array (matplotlib's Agg canvas, no window).

The figure with the walls, floor zones and task marks is drawn once; each frame only moves the
robot's disc and heading line, so a frame costs a few milliseconds.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from hippo.sim.arena import Arena


class ArenaRenderer:
    """Renders ``arena`` with the robot at a pose, as an ``(H, W, 3)`` ``uint8`` array.

    Parameters
    ----------
    arena : the arena to draw (walls, floor zones).
    robot_radius : radius of the robot's disc, cm.
    marks : named points to draw as labelled crosses (goal centre, checkpoints).
    width_px : width of the image in pixels; the height follows the arena's aspect ratio.
    """

    def __init__(self, arena: Arena, robot_radius: float = 3.7,
                 marks: dict[str, Sequence[float]] | None = None, width_px: int = 480) -> None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
        from matplotlib.patches import Circle

        from hippo.plots.sim import draw_arena

        dpi = 100
        w_in = width_px / dpi
        h_in = w_in * (arena.height + 4) / (arena.width + 4)
        self.figure = Figure(figsize=(w_in, h_in), dpi=dpi)
        self.canvas = FigureCanvasAgg(self.figure)
        ax = self.figure.add_axes((0, 0, 1, 1))
        draw_arena(arena, ax, locations=False)
        ax.set_axis_off()
        for name, (x, y) in (marks or {}).items():
            ax.plot([x], [y], "x", color="tab:purple", ms=6, mew=1.5)
            ax.annotate(name, (x, y), xytext=(3, 3), textcoords="offset points", fontsize=7,
                        color="tab:purple")
        self._disc = Circle((0.0, 0.0), robot_radius, facecolor="tab:blue", edgecolor="k",
                            lw=0.8, zorder=5)
        ax.add_patch(self._disc)
        (self._nose,) = ax.plot([], [], "-", color="w", lw=1.5, zorder=6)
        self._radius = robot_radius
        self.axes = ax

    def frame(self, pose: Sequence[float]) -> np.ndarray:
        """The image with the robot at ``pose = (x, y, heading)``."""
        x, y, h = (float(v) for v in pose[:3])
        self._disc.center = (x, y)
        self._nose.set_data([x, x + self._radius * math.cos(h)],
                            [y, y + self._radius * math.sin(h)])
        self.canvas.draw()
        return np.asarray(self.canvas.buffer_rgba())[..., :3].copy()

    def close(self) -> None:
        """Release the figure."""
        self.figure.clear()
