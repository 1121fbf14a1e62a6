"""The figure of a long deployment: failures and health over the hours."""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np

__all__ = ["plot_deployment"]

_KINDS = ("missed", "misplaced", "wait_off", "stuck")


def plot_deployment(segments: Sequence[dict]) -> tuple[plt.Figure, np.ndarray]:
    """Three panels against simulated hours: cumulative checkpoint passes and failures by
    kind; the states, transitions and map edges the robot knows; the process memory (MB).
    ``segments``: the ``segments`` of a deployment's ``metrics.json``."""
    fig, axes = plt.subplots(3, 1, figsize=(7, 8), sharex=True, constrained_layout=True)
    if not segments:
        axes[0].set_title("deployment: no segment finished")
        return fig, axes
    t = np.array([g["t1_h"] for g in segments])
    ax = axes[0]
    ax.plot(t, np.cumsum([g["tasks"] for g in segments]), "k-", label="checkpoint passes")
    ax2 = ax.twinx()
    for kind in _KINDS:
        ax2.step(t, np.cumsum([g[kind] for g in segments]), where="post", label=kind)
    ax.set_ylabel("passes (cumulative)")
    ax2.set_ylabel("failures (cumulative)")
    ax2.legend(loc="upper left", fontsize=8)
    ax.set_title("deployment: tasks and failures")
    for key in ("states", "transitions", "map_edges"):
        axes[1].plot(t, [g["health"][key] for g in segments], ".-", label=key)
    axes[1].set_ylabel("count")
    axes[1].legend(fontsize=8)
    axes[2].plot(t, [g["health"]["rss_mb"] for g in segments], ".-")
    axes[2].set_ylabel("memory (MB)")
    axes[2].set_xlabel("simulated hours")
    return fig, axes
