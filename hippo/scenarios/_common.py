"""Helpers every scenario uses: the output folder and the metrics file."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

from hippo.io import save_json


def prepare_out(out: str | Path) -> Path:
    """Create the output folder and return it as a Path."""
    path = Path(out)
    path.mkdir(parents=True, exist_ok=True)
    return path


def write_metrics(out: Path, metrics: dict[str, Any], *, announce: bool = True) -> Path:
    """Write ``out/metrics.json`` atomically and tell the user where the results are."""
    path = save_json(Path(out) / "metrics.json", metrics)
    if announce:
        print(f"results written to {Path(out).resolve()} (metrics.json, figures, run.npz)",
              file=sys.stderr)
    return path
