"""Figures of the closed loop: the learned map over the arena (HIREL Fig. 5a / 7a), trajectories
(Fig. 5b / 7b), and speed with the reward prediction in rewarded and extinction trials (Fig. 6)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from hippo.plots.cognitive_map import plot_cognitive_map
from hippo.plots.sim import draw_arena

if TYPE_CHECKING:
    from hippo.agent import Agent
    from hippo.sim.arena import Arena


def state_centres(winner: np.ndarray, x: np.ndarray, y: np.ndarray) -> dict[int, tuple[float,
                                                                                        float]]:
    """Mean true position of the robot while each state was the winner (analysis only)."""
    out = {}
    for s in np.unique(winner):
        if s < 0:
            continue
        m = winner == s
        out[int(s)] = (float(x[m].mean()), float(y[m].mean()))
    return out


def plot_map(arena: Arena, agent: Agent, arrays: Mapping[str, np.ndarray], *,
             title: str | None = None) -> Figure:
    """The learned cognitive map over the arena, states at their mean true position."""
    pos = state_centres(arrays["winner"], arrays["x"], arrays["y"])
    act = agent.planner.activity(agent.graph, agent.drives) if len(agent.graph) else None
    fig, ax = plt.subplots(figsize=(7, 7 * arena.height / arena.width + 0.8),
                           layout="constrained")
    draw_arena(arena, ax, locations=False)
    plot_cognitive_map(agent.graph, act, agent.drives, ax=ax, positions=pos,
                       title=title or f"learned map: {len(pos)} states, {len(agent.graph)} "
                                      "transitions")
    return fig


def plot_trials(arena: Arena, arrays: Mapping[str, np.ndarray], phase: int,
                title: str) -> Figure:
    """Trajectories of each trial of ``phase`` (start: cross)."""
    fig, ax = plt.subplots(figsize=(6, 6 * arena.height / arena.width + 0.4),
                           layout="constrained")
    draw_arena(arena, ax, locations=False)
    trials = np.unique(arrays["trial"][arrays["phase"] == phase])
    cmap = plt.get_cmap("tab10")
    for i, k in enumerate(trials):
        m = (arrays["phase"] == phase) & (arrays["trial"] == k)
        ax.plot(arrays["x"][m], arrays["y"][m], lw=1, color=cmap(i % 10))
        ax.plot(arrays["x"][m][0], arrays["y"][m][0], "x", ms=9, mew=2, color=cmap(i % 10))
    ax.set_title(title)
    return fig


def plot_wait_profiles(arrays: Mapping[str, np.ndarray], trials: Sequence[Mapping[str, Any]],
                       delay: float) -> Figure:
    """HIREL Fig. 6: speed and reward prediction around the stop, rewarded vs extinction."""
    fig, axes = plt.subplots(2, 2, figsize=(10, 5.5), sharex=True, layout="constrained")
    t = arrays["t"]
    for col, (rewarded, name) in enumerate(((True, "rewarded trials"),
                                            (False, "extinction trials"))):
        for k, r in enumerate(trials):
            if r["rewarded"] != rewarded or "still_t" not in r:
                continue
            m = (arrays["trial"] == k) & (arrays["phase"] == (2 if rewarded else 3))
            tt = t[m] - r["still_t"]
            keep = (tt > -8) & (tt < delay + 12)
            axes[0, col].plot(tt[keep], arrays["speed"][m][keep], lw=1)
            axes[1, col].plot(tt[keep], arrays["prediction"][m][keep], lw=1)
            no = arrays["non_occurrence"][m][keep]
            if np.any(no):
                axes[1, col].plot(tt[keep][no], arrays["prediction"][m][keep][no], "rv", ms=6)
        for ax in axes[:, col]:
            ax.axvline(0, color="0.6", ls=":")
            ax.axvline(delay, color="tab:red", ls="--", lw=1)
        axes[0, col].set_title(name)
        axes[1, col].set_xlabel("time since the robot stopped in the goal zone (s)")
    axes[0, 0].set_ylabel("speed (cm/s)")
    axes[1, 0].set_ylabel("prediction of the\nchosen transition")
    return fig


def plot_place_preference(out: Path, arena: Arena, agent: Agent,
                          arrays: Mapping[str, np.ndarray], trials: Sequence[Mapping[str, Any]],
                          delay: float) -> list[Path]:
    """Write the place-preference figures into ``out``; returns their paths."""
    paths = []
    for name, fig in (
        ("map.png", plot_map(arena, agent, arrays)),
        ("trajectories.png", plot_trials(arena, arrays, 2, "rewarded trials: paths to the goal")),
        ("waits.png", plot_wait_profiles(arrays, trials, delay)),
    ):
        fig.savefig(out / name, dpi=110)
        plt.close(fig)
        paths.append(out / name)
    return paths
