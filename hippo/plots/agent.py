"""Figures of the closed loop: the learned map over the arena (HIREL Fig. 5a / 7a), trajectories
(Fig. 5b / 7b), and speed with the reward prediction in rewarded and extinction trials (Fig. 6)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from hippo.io import save_figure
from hippo.plots.cognitive_map import plot_cognitive_map
from hippo.plots.sim import draw_arena

if TYPE_CHECKING:
    from hippo.agent import Agent
    from hippo.sim.arena import Arena


def state_centres(winner: np.ndarray, x: np.ndarray, y: np.ndarray) -> dict[int, tuple[float,
                                                                                        float]]:
    """Where the robot was while each state was the winner (analysis only): the logged
    position nearest to their mean, so a state is drawn where the robot really was (a mean
    of positions around a corner can fall inside a wall or an obstacle)."""
    out = {}
    for s in np.unique(winner):
        if s < 0:
            continue
        m = winner == s
        px, py = x[m], y[m]
        k = int(np.argmin((px - px.mean()) ** 2 + (py - py.mean()) ** 2))
        out[int(s)] = (float(px[k]), float(py[k]))
    return out


def plot_map(arena: Arena, agent: Agent, arrays: Mapping[str, np.ndarray], *,
             title: str | None = None) -> tuple[Figure, Axes]:
    """The learned cognitive map over the arena, states at their mean true position."""
    pos = state_centres(arrays["winner"], arrays["x"], arrays["y"])
    act = agent.planner.activity(agent.graph, agent.drives) if len(agent.graph) else None
    fig, ax = plt.subplots(figsize=(7, 7 * arena.height / arena.width + 0.8),
                           layout="constrained")
    draw_arena(arena, ax, locations=False)
    shown = sum(t[0] in pos and t[1] in pos for t in agent.graph)
    plot_cognitive_map(agent.graph, act, agent.drives, ax=ax, positions=pos, restrict=True,
                       title=title or f"learned map: {len(pos)} of {agent.layer.n_states} "
                       f"states (those that won, where the robot was),\n{shown} of "
                       f"{len(agent.graph)} transitions")
    ax.set_xlim(-2, arena.width + 2)
    ax.set_ylim(-2, arena.height + 2)
    return fig, ax


def plot_trials(arena: Arena, arrays: Mapping[str, np.ndarray], phase: int,
                title: str) -> tuple[Figure, Axes]:
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
    return fig, ax


def plot_wait_profiles(arrays: Mapping[str, np.ndarray], trials: Sequence[Mapping[str, Any]],
                       delay: float) -> tuple[Figure, np.ndarray]:
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
            pred = arrays["sound_prediction"][m][keep]
            axes[1, col].plot(tt[keep], pred, lw=1)
            no = arrays["sound_non_occurrence"][m][keep]
            if np.any(no):
                axes[1, col].plot(tt[keep][no], pred[no], "rv", ms=7, label="non-occurrence")
        for ax in axes[:, col]:
            ax.axvline(0, color="0.6", ls=":")
            ax.axvline(delay, color="tab:red", ls="--", lw=1)
        axes[0, col].set_title(name)
        axes[1, col].set_xlabel("time since the robot stopped in the goal zone (s)")
    axes[0, 0].set_ylabel("speed (cm/s)")
    axes[1, 0].set_ylabel("prediction of the sound")
    for ax in axes[1]:
        if ax.get_legend_handles_labels()[0]:
            handles, labels = ax.get_legend_handles_labels()
            ax.legend(handles[:1], labels[:1], fontsize=8, loc="upper right")
    return fig, axes


def plot_place_preference(out: Path, arena: Arena, agent: Agent,
                          arrays: Mapping[str, np.ndarray], trials: Sequence[Mapping[str, Any]],
                          delay: float) -> list[Path]:
    """Write the place-preference figures into ``out``; returns their paths (a writer: the
    figures themselves come from :func:`plot_map`, :func:`plot_trials`,
    :func:`plot_wait_profiles`)."""
    paths = []
    for name, (fig, _) in (
        ("map.png", plot_map(arena, agent, arrays)),
        ("trajectories.png", plot_trials(arena, arrays, 2, "rewarded trials: paths to the goal")),
        ("waits.png", plot_wait_profiles(arrays, trials, delay)),
    ):
        save_figure(fig, out / name, dpi=110)
        plt.close(fig)
        paths.append(out / name)
    return paths


def plot_waits_table(rows: Sequence[Mapping[str, Any]]) -> tuple[Figure, Axes]:
    """HIREL Table I as a figure: learned wait vs each reproduced wait, per checkpoint (a
    learned wait of None, none learned, is left blank; 0 s is drawn)."""
    fig, ax = plt.subplots(figsize=(6, 3.6), layout="constrained")
    for k, r in enumerate(rows):
        rep = r["reproduced_waits_s"]
        learned = np.nan if r["learned_wait_s"] is None else r["learned_wait_s"]
        ax.plot([k - 0.25, k + 0.25], [learned] * 2, "k-", lw=2,
                label="learned" if k == 0 else None)
        ax.plot(np.full(len(rep), k) + np.linspace(-0.15, 0.15, max(len(rep), 1))[:len(rep)],
                rep, "o", color="tab:blue", label="reproduced" if k == 0 else None)
        ax.plot(k, r["taught_block_s"], "r_", ms=20, label="teacher's block" if k == 0 else None)
    ax.set_xticks(range(len(rows)), [r["checkpoint"] for r in rows])
    ax.set_ylabel("wait (s)")
    ax.legend(fontsize=8)
    ax.set_title("checkpoint waits: learned vs reproduced")
    return fig, ax


def plot_patrol(out: Path, arena: Arena, agent: Agent, arrays: Mapping[str, np.ndarray],
                rows: Sequence[Mapping[str, Any]],
                checkpoints: Sequence[Sequence[float]] | None = None) -> list[Path]:
    """Write the patrol figures into ``out`` (HIREL Fig. 7a, 7b and Table I); returns their
    paths. ``checkpoints`` default to the arena's landmarks ``checkpoint-1..3``."""
    if checkpoints is None:
        checkpoints = [arena.landmarks[f"checkpoint-{k}"] for k in (1, 2, 3)]
    fig_b, ax = plt.subplots(figsize=(7, 5.5), layout="constrained")
    draw_arena(arena, ax, locations=False)
    for phase, colour, label in ((1, "k", "taught (leash)"), (4, "tab:blue", "reproduced")):
        m = arrays["phase"] == phase
        ax.plot(arrays["x"][m], arrays["y"][m], color=colour, lw=1.2 if phase == 1 else 0.6,
                alpha=1.0 if phase == 1 else 0.6, label=label)
    for k, (x, y) in enumerate(checkpoints, start=1):
        ax.plot(x, y, "s", color="tab:red", ms=9)
        ax.annotate(str(k), (x, y), xytext=(5, 5), textcoords="offset points", color="tab:red")
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title("patrol: taught and reproduced trajectories")
    paths = []
    for name, (fig, _) in (("map.png", plot_map(arena, agent, arrays)),
                           ("trajectories.png", (fig_b, ax)),
                           ("waits_table.png", plot_waits_table(rows))):
        save_figure(fig, out / name, dpi=110)
        plt.close(fig)
        paths.append(out / name)
    return paths
