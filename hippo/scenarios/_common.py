"""Helpers every scenario uses: the output folder and the metrics file."""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any

import numpy as np

from hippo.io import clean_stale_temps, save_json


def prepare_out(out: str | Path) -> Path:
    """Create the output folder and return it as a Path; temporary files that a run killed
    mid-write left in it are removed (:func:`hippo.io.clean_stale_temps`)."""
    path = Path(out)
    path.mkdir(parents=True, exist_ok=True)
    clean_stale_temps(path)
    return path


def write_metrics(out: Path, metrics: dict[str, Any], *, announce: bool = True,
                  summary: str | None = None) -> Path:
    """Write ``out/metrics.json`` atomically and tell the user where the results are (and,
    with ``summary``, the headline numbers)."""
    path = save_json(Path(out) / "metrics.json", metrics)
    if announce:
        if summary:
            print(summary, file=sys.stderr)
        print(f"results written to {Path(out).resolve()} (metrics.json, figures, run.npz)",
              file=sys.stderr)
    return path


def sfa_cutoff(text: str) -> float | str:
    """Parse ``--sfa-cutoff``: a number, or ``auto``."""
    return text if text == "auto" else float(text)


def mean_sd(values: list[float]) -> tuple[float, float]:
    """Mean and sample sd over seeds of the finite values (sd 0 for one value, nan for none)."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return math.nan, math.nan
    return float(v.mean()), float(v.std(ddof=1)) if v.size > 1 else 0.0
