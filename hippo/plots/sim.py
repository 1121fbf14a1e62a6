"""Figures of the world: the arena with a trajectory (SMC09 Fig. 4) and a sensor strip."""

from __future__ import annotations

from typing import TYPE_CHECKING

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle

from hippo._checks import check_int

if TYPE_CHECKING:
    from hippo.sim.arena import Arena
    from hippo.sim.record import Recording

ZONE_COLOURS = ["none", "tab:red", "tab:green", "tab:blue", "tab:orange", "tab:purple"]


def draw_arena(arena: Arena, ax: Axes | None = None, *, locations: bool = True,
               labels: bool = False) -> tuple[Figure, Axes]:
    """Walls (black), coloured zones, and the labelled reference locations (grey triangles).

    A zone's colour 1, 2, ... takes ZONE_COLOURS[1:] in turn (colour 6 red again, as 1)."""
    if ax is None:
        _, ax = plt.subplots(figsize=(6, 6 * arena.height / arena.width))
    for z in arena.zones:
        x0, y0, x1, y1 = z.rect
        k = z.colour
        colour = ZONE_COLOURS[1 + (k - 1) % (len(ZONE_COLOURS) - 1)] if k else "none"
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, alpha=0.35, color=colour, lw=0))
    segs = [[a, b] for a, b in arena.walls]
    ax.add_collection(LineCollection(segs, colors="k", linewidths=2))
    if locations and len(arena.locations):
        ax.plot(*arena.locations.T, "^", color="0.55", ms=4, zorder=1)
        if labels:
            for i, (x, y) in enumerate(arena.locations):
                ax.annotate(str(i + 1), (x, y), fontsize=6, color="0.4", xytext=(2, 2),
                            textcoords="offset points")
    ax.set_xlim(-2, arena.width + 2)
    ax.set_ylim(-2, arena.height + 2)
    ax.set_aspect("equal")
    ax.set_xlabel("x (cm)")
    ax.set_ylabel("y (cm)")
    return ax.figure, ax


def plot_trajectory(arena: Arena, rec: Recording | None = None, *, xy: np.ndarray | None = None,
                    colour: np.ndarray | None = None, ax: Axes | None = None,
                    title: str | None = None, cmap: str = "viridis") -> tuple[Figure, Axes]:
    """The arena with the robot's path, coloured by time (or by ``colour``, e.g. a unit)."""
    if xy is None:
        if rec is None:
            raise ValueError("give a Recording or an (T, 2) array of positions")
        xy = rec.positions
    fig, ax = draw_arena(arena, ax)
    c = np.arange(len(xy)) if colour is None else np.asarray(colour)
    pts = xy.reshape(-1, 1, 2)
    lc = LineCollection(np.concatenate([pts[:-1], pts[1:]], axis=1), array=c[:-1], cmap=cmap,
                        linewidths=0.8)
    ax.add_collection(lc)
    ax.figure.colorbar(lc, ax=ax, label="tick" if colour is None else "activity", shrink=0.8)
    ax.set_title(title or f"{arena.name}: {len(xy)} ticks")
    return fig, ax


def plot_sensor_strip(rec: Recording, start: int = 0, stop: int | None = None,
                      ax: Axes | None = None) -> tuple[Figure, Axes]:
    """Sensor readings over time as an image (rows: sensors, dark = near a wall)."""
    stop = len(rec) if stop is None else stop
    if len(rec) == 0:
        raise ValueError("the recording has no ticks to draw")
    start = check_int("start", start, lo=0, hi=len(rec) - 1)
    stop = check_int("stop", stop, lo=start + 1, hi=len(rec))
    if ax is None:
        _, ax = plt.subplots(figsize=(10, 3), layout="constrained")  # nothing clipped
    S = rec.sensors[start:stop].T
    im = ax.imshow(S, aspect="auto", cmap="gray", vmin=0, vmax=1, interpolation="nearest",
                   extent=(rec.t[start], rec.t[stop - 1], S.shape[0] - 0.5, -0.5))
    ax.figure.colorbar(im, ax=ax, label="reading", pad=0.01)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("sensor")
    ax.set_title("sensor readings (0 = touching, 1 = nothing in range)")
    return ax.figure, ax
