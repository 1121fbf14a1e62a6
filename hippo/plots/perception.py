"""Figures of the place cells: SMC09 Figs. 5-8 and ICANN09 Figs. 2-3.

* :func:`plot_place_cell` — one unit's response over the arena (top) and over time against the
  labelled location (bottom), colour from blue (low) through green to red (peak) (SMC09 Figs.
  5, 6, 8); kidnapping events as vertical lines (Fig. 7).
* :func:`plot_activation_map` — the occupancy grid (location over time) next to the spatially
  ordered ICA activation map (ICANN09 Fig. 3).
* :func:`plot_units_over_arena` — small multiples of many units' mean response on a grid.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from hippo._checks import check_int
from hippo.plots.sim import draw_arena

if TYPE_CHECKING:
    from hippo.sim.arena import Arena

CMAP = "jet"  # the papers' colours: blue low, green intermediate, red peak


def plot_place_cell(arena: Arena, xy: np.ndarray, labels: np.ndarray, y: np.ndarray, *,
                    t: np.ndarray | None = None, title: str = "",
                    events: Sequence[int] = (), event_label: str = "kidnap",
                    truth: np.ndarray | None = None, truth_label: str = ""
                    ) -> tuple[Figure, np.ndarray]:
    """SMC09 Figs. 5-8 for one unit ``y`` (T,): map on top, location-vs-time below."""
    y = np.asarray(y, dtype=float)
    t = np.arange(len(y)) if t is None else np.asarray(t)
    lo, hi = np.percentile(y, [1, 99])
    fig = plt.figure(figsize=(9, 8.5), layout="constrained")
    gs = fig.add_gridspec(2, 1, height_ratios=[arena.height / arena.width * 1.6, 1])
    ax = fig.add_subplot(gs[0])
    draw_arena(arena, ax, labels=True)
    order = np.argsort(y)  # draw peaks last
    sc = ax.scatter(xy[order, 0], xy[order, 1], c=y[order], s=6, cmap=CMAP, vmin=lo, vmax=hi,
                    zorder=2)
    fig.colorbar(sc, ax=ax, label="unit output", shrink=0.8)
    ax.set_title(title)
    ax2 = fig.add_subplot(gs[1])
    ax2.scatter(t, np.asarray(labels) + 1, c=y, s=5, cmap=CMAP, vmin=lo, vmax=hi)
    ax2.set_xlabel("tick")
    ax2.set_ylabel("location (labelled)")
    ax2.set_xlim(t[0], t[-1])
    tw = ax2.twinx()
    tw.plot(t, y, "k--", lw=0.7)
    tw.set_ylabel("unit output")
    if truth is not None:
        top = float(np.max(labels)) + 2
        ax2.fill_between(t, 0, top, where=np.asarray(truth, bool), color="0.88", zorder=0,
                         step="mid", label=truth_label, lw=0)
        ax2.set_ylim(0, top)
    for i, e in enumerate(events):
        ax2.axvline(t[e], color="m", lw=1.2, label=event_label if i == 0 else None)
    if len(events) or truth is not None:
        ax2.legend(loc="upper left", fontsize=8)
    return fig, np.array([ax, ax2])


def plot_activation_map(t: np.ndarray, labels: np.ndarray, Y: np.ndarray, order: np.ndarray, *,
                        threshold: float = 4.5, n_locations: int | None = None,
                        title: str = "") -> tuple[Figure, np.ndarray]:
    """ICANN09 Fig. 3: occupancy grid (left) and spatially ordered ICA activation map (right).

    Each dot on the right is a unit (ranked by its preferred location) at a tick where it
    responds at or above ``threshold``; darker = stronger.
    """
    t = np.asarray(t)
    Y = np.asarray(Y)[:, order]
    L = int(n_locations or (np.max(labels) + 1))
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 5), sharex=True, layout="constrained")
    a1.plot(t, np.asarray(labels) + 1, ".", ms=1.5, color="k")
    a1.set_ylim(0.5, L + 0.5)
    a1.set_xlabel("tick")
    a1.set_ylabel("robot location")
    a1.set_title("occupancy grid")
    ti, ui = np.nonzero(Y >= threshold)
    v = Y[ti, ui]
    a2.scatter(t[ti], ui + 1, c=v, s=2, cmap="Greys", vmin=threshold * 0.6,
               vmax=max(np.percentile(v, 95) if v.size else threshold, threshold + 1e-6))
    a2.set_ylim(0.5, Y.shape[1] + 0.5)
    a2.set_xlabel("tick")
    a2.set_ylabel("ICA unit (ordered by preferred location)")
    a2.set_title(f"ICA activation map (output ≥ {threshold:g})")
    if title:
        fig.suptitle(title)
    return fig, np.array([a1, a2])


def plot_units_over_arena(arena: Arena, fields: np.ndarray, extent: tuple[float, ...], *,
                          units: Sequence[int] | None = None, ncols: int = 10,
                          title: str = "") -> tuple[Figure, np.ndarray]:
    """Small multiples: each unit's mean response on a spatial grid (``fields`` (k, ny, nx))."""
    units = list(range(fields.shape[0])) if units is None else list(units)
    ncols = check_int("ncols", ncols, lo=1)
    nrows = max(1, int(np.ceil(len(units) / ncols)))
    fig, axes = plt.subplots(nrows, ncols, figsize=(1.6 * ncols, 1.6 * nrows),
                             layout="constrained", squeeze=False)
    for ax in axes.ravel():
        ax.set_axis_off()
    segs = [[a, b] for a, b in arena.walls]
    for ax, j in zip(axes.ravel(), units):
        f = fields[j]
        ax.imshow(f, origin="lower", extent=extent, cmap=CMAP, vmin=np.nanmin(f),
                  vmax=np.nanmax(f), interpolation="nearest")
        for a, b in segs:
            ax.plot([a[0], b[0]], [a[1], b[1]], color="w", lw=0.4)
        ax.set_title(str(j + 1), fontsize=7, pad=1)
    if title:
        fig.suptitle(title)
    return fig, axes


def plot_sfa_units(arena: Arena, xy: np.ndarray, labels: np.ndarray, Ysfa: np.ndarray,
                   units: Sequence[int], *, t: np.ndarray | None = None
                   ) -> tuple[Figure, np.ndarray]:
    """ICANN09 Fig. 2(a): a few SFA units over time (left) and over the arena (right)."""
    t = np.arange(len(xy)) if t is None else np.asarray(t)
    fig, axes = plt.subplots(len(units), 2, figsize=(11, 2.8 * len(units)),
                             layout="constrained", squeeze=False,
                             gridspec_kw={"width_ratios": [2, 1]})
    for row, j in zip(axes, units):
        y = Ysfa[:, j]
        lo, hi = np.percentile(y, [1, 99])
        row[0].scatter(t, np.asarray(labels) + 1, c=y, s=3, cmap=CMAP, vmin=lo, vmax=hi)
        row[0].set_ylabel("location")
        tw = row[0].twinx()
        tw.plot(t, y, "k-", lw=0.5)
        tw.set_ylabel(f"SFA unit {j + 1}")
        draw_arena(arena, row[1], locations=False)
        row[1].scatter(xy[:, 0], xy[:, 1], c=y, s=2, cmap=CMAP, vmin=lo, vmax=hi, zorder=2)
        row[1].set_xlabel("")
        row[1].set_ylabel("")
    axes[-1, 0].set_xlabel("tick")
    return fig, axes
