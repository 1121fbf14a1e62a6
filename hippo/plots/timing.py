"""Figures of the timing system: HIREL Fig. 6 without the robot, and Weber-scaled predictions.

* :func:`plot_fig6` — (a) a rewarded trial: the prediction of the reward after the robot
  stopped rises to its peak, the reward comes, the prediction stops; (b) an extinction trial:
  the reward is omitted, the non-occurrence neuron fires shortly after the learned delay and
  the robot would resume; (c) predictions for several learned delays side by side; (d) the same
  against elapsed time / delay: one curve (Weber's law, the scalar property).
* :func:`plot_reproduction` — learned versus reproduced waits (the benchmark, HIREL Table I).

Inputs are :class:`hippo.timing.trials.TrialTrace` objects (or anything with ``tau``,
``prediction``, ``delay_over``, ``end`` and ``fired``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.ticker import FormatStrFormatter, NullFormatter

from hippo.timing.trials import TrialTrace

__all__ = ["plot_fig6", "plot_reproduction"]


def _trial_panel(ax: Axes, trace: TrialTrace, delay: float, title: str, *,
                 event_label: str) -> None:
    tau = np.concatenate([[0.0], trace.tau])
    pred = np.concatenate([[0.0], trace.prediction])
    stop = trace.end if trace.end is not None else (trace.fired[0] if trace.fired else tau[-1])
    if trace.end is not None:  # the event: the prediction stops
        tau, pred = np.append(tau, trace.end), np.append(pred, 0.0)
    ax.axvspan(0.0, stop, color="0.9", lw=0, label="waiting (still)")
    ax.plot(tau, pred, color="C0", lw=2, label="prediction of the reward")
    ax.axvline(delay, color="k", ls=":", lw=1, label=f"learned delay {delay:g} s")
    if trace.end is not None:
        ax.axvline(trace.end, color="C2", lw=2, label=f"{event_label} at {trace.end:.1f} s")
    for i, t in enumerate(trace.fired):
        ax.axvline(t, color="C3", lw=2,
                   label=f"non-occurrence at {t:.1f} s" if i == 0 else None)
    over = np.flatnonzero(trace.delay_over)
    if over.size:
        ax.plot(trace.tau[over[0]], trace.prediction[over[0]], "v", color="C1", ms=8,
                label=f"delay over at {trace.tau[over[0]]:.1f} s")
    ax.set_xlim(0, max(tau[-1], 1.5 * delay))
    ax.set_ylim(-0.02, 1.05)
    ax.set_xlabel("time since the robot stopped (s)")
    ax.set_ylabel("activity")
    ax.set_title(title, loc="left", fontsize=10)
    ax.legend(fontsize=7, loc="upper left")


def plot_fig6(rewarded: TrialTrace, extinction: TrialTrace, delay: float,
              by_delay: Mapping[float, TrialTrace], *, title: str = ""
              ) -> tuple[Figure, np.ndarray]:
    """HIREL Fig. 6 without the robot, plus learned predictions for several delays.

    rewarded, extinction: trials after learning ``delay`` (the event came / was omitted).
    by_delay: for each learned delay, a trial without the event (the full prediction).
    """
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5), layout="constrained")
    _trial_panel(axes[0, 0], rewarded, delay, "a) rewarded trial: the sound comes, the "
                 "prediction stops", event_label="sound")
    _trial_panel(axes[0, 1], extinction, delay, "b) extinction trial: no sound, "
                 "non-occurrence fires", event_label="sound")
    ax, ax2 = axes[1]
    cmap = plt.get_cmap("viridis")
    delays = sorted(by_delay)
    for i, d in enumerate(delays):
        tr = by_delay[d]
        c = cmap(i / max(len(delays) - 1, 1))
        ax.plot(tr.tau, tr.prediction, color=c, lw=1.8, label=f"{d:g} s")
        ax.axvline(d, color=c, ls=":", lw=1)
        peak = tr.prediction.max() if tr.prediction.size else 1.0
        ax2.plot(tr.tau / d, tr.prediction / peak, color=c, lw=1.5, label=f"{d:g} s")
    ax.set_xlabel("time since entering the state (s)")
    ax.set_ylabel("prediction")
    ax.set_title("c) learned predictions for several delays (Weber: wider when longer)",
                 loc="left", fontsize=10)
    ax.legend(title="learned delay", fontsize=7)
    ax2.axvline(1.0, color="k", ls=":", lw=1)
    ax2.set_xlim(0, 2)
    ax2.set_xlabel("elapsed time / learned delay")
    ax2.set_ylabel("prediction / peak")
    ax2.set_title("d) the same, rescaled: one shape (scalar property)", loc="left",
                  fontsize=10)
    ax2.legend(fontsize=7)
    if title:
        fig.suptitle(title)
    return fig, axes


def plot_reproduction(learned: Sequence[float], reproduced: Sequence[Sequence[float]], *,
                      reference: Mapping[float, tuple[float, float]] | None = None,
                      title: str = "") -> tuple[Figure, np.ndarray]:
    """Reproduced waits (mean +- sd over trials) against the learned delays, log-log.

    reference: optional ``{learned: (mean, sd)}`` of another system (e.g. HIREL Table I).
    """
    x = np.asarray(learned, dtype=float)
    mean = np.array([np.nanmean(r) for r in reproduced])
    sd = np.array([np.nanstd(r) for r in reproduced])
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
    lim = [0.8 * x.min(), 1.25 * x.max()]
    ax.plot(lim, lim, color="0.6", lw=1, label="perfect")
    ax.errorbar(x, mean, yerr=sd, fmt="o", color="C0", label="hippo")
    ax2.axhspan(-3, 3, color="C2", alpha=0.15, label="goal: 3 %")
    ax2.errorbar(x, 100 * (mean / x - 1), yerr=100 * sd / x, fmt="o", color="C0",
                 label="hippo")
    if reference:
        rx = np.array(sorted(reference))
        rm = np.array([reference[k][0] for k in rx])
        rs = np.array([reference[k][1] for k in rx])
        ax.errorbar(rx, rm, yerr=rs, fmt="s", color="C3", label="HIREL robot")
        ax2.errorbar(rx, 100 * (rm / rx - 1), yerr=100 * rs / rx, fmt="s", color="C3",
                     label="HIREL robot")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("learned delay (s)")
    ax.set_ylabel("reproduced wait (s)")
    ax.legend(fontsize=8)
    ax2.set_xscale("log")
    ax2.axhline(0, color="0.6", lw=1)
    for a in (ax, ax2):
        a.set_xticks(x)
        a.xaxis.set_major_formatter(FormatStrFormatter("%g"))
        a.xaxis.set_minor_formatter(NullFormatter())
    ax.set_yticks(x)
    ax.yaxis.set_major_formatter(FormatStrFormatter("%g"))
    ax.yaxis.set_minor_formatter(NullFormatter())
    ax2.set_xlabel("learned delay (s)")
    ax2.set_ylabel("error (%)")
    ax2.legend(fontsize=8)
    if title:
        fig.suptitle(title)
    return fig, np.array([ax, ax2])
