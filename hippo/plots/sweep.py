"""Figure of a sweep: one metric, mean ± sd over seeds, per parameter combination.

* :func:`plot_sweep_summary` — rows of :func:`hippo.sweep.run_sweep` (one per cell) to a bar
  chart; failed cells are counted in the title, never averaged in.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

__all__ = ["BOOKKEEPING", "numeric_metrics", "plot_sweep_summary"]

#: the columns of a sweep's table about its cells, not measured by them (never a metric)
BOOKKEEPING = frozenset({"cell", "scenario", "seed", "status", "attempts", "seconds", "worker",
                         "error"})


def numeric_metrics(rows: Sequence[Mapping[str, Any]], params: Sequence[str]) -> list[str]:
    """Metric columns holding numbers in at least one successful row, in table order."""
    skip = BOOKKEEPING | set(params)
    names: dict[str, None] = {}
    for r in rows:
        if r.get("status") != "ok":
            continue
        for k, v in r.items():
            if k not in skip and isinstance(v, (int, float)) and not isinstance(v, bool):
                names[k] = None
    return list(names)


def plot_sweep_summary(rows: Sequence[Mapping[str, Any]], params: Sequence[str], *,
                       metric: str | None = None) -> tuple[Figure, Axes]:
    """Mean ± sd over seeds of ``metric`` (default: the first numeric one) per combination of
    ``params``; the title names the seeds and any failed cells."""
    names = numeric_metrics(rows, params)
    if metric is None:
        metric = names[0] if names else None
    elif metric not in names:
        raise ValueError(f"metric {metric!r} is not a numeric metric of this sweep; "
                         f"choose from: {', '.join(names) or '(none)'}")
    groups: dict[tuple[str, ...], list[float]] = {}
    for r in rows:
        key = tuple(str(r.get(p, "")) for p in params)
        vals = groups.setdefault(key, [])
        v = r.get(metric) if metric is not None and r.get("status") == "ok" else None
        if isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v):
            vals.append(float(v))
    fig, ax = plt.subplots(figsize=(max(4.0, 0.9 * len(groups) + 2.0), 3.6))
    labels = ["\n".join(f"{p}={v}" for p, v in zip(params, k)) or "all" for k in groups]
    means = [np.mean(v) if v else np.nan for v in groups.values()]
    sds = [np.std(v, ddof=1) if len(v) > 1 else 0.0 for v in groups.values()]
    x = np.arange(len(groups))
    ax.bar(x, means, yerr=sds, capsize=3, color="#4c72b0", alpha=0.85)
    for i, v in enumerate(groups.values()):
        ax.plot(np.full(len(v), i), v, "k.", ms=4)
    ax.set_xticks(x, labels, fontsize=8)
    ax.set_ylabel(metric or "(no numeric metric)")
    seeds = sorted({int(r["seed"]) for r in rows if "seed" in r})
    failed = sum(1 for r in rows if r.get("status") != "ok")
    scen = ", ".join(sorted({str(r.get("scenario", "")) for r in rows}))
    title = f"{scen}: mean ± sd over seeds {_ranges(seeds)}"
    if failed:
        title += f" ({failed} failed cell{'s' if failed > 1 else ''} left out)"
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    return fig, ax


def _ranges(seeds: Sequence[int]) -> str:
    if not seeds:
        return "-"
    parts, start, prev = [], seeds[0], seeds[0]
    for s in [*seeds[1:], None]:
        if s is not None and s == prev + 1:
            prev = s
            continue
        parts.append(f"{start}" if start == prev else f"{start}-{prev}")
        if s is not None:
            start = prev = s
    return ",".join(parts)
