"""The per-tick log of a run and its files: ``run.npz`` (arrays and events) and the map.

:class:`Log` keeps one row per tick: the ground truth (``t, x, y, heading, speed``), the senses
a figure needs (``zone, sound``), the task's ``phase`` and ``trial``, and the agent's
:meth:`~hippo.brain.Brain.snapshot` (``winner, mode, prediction, non_occurrence,
sound_prediction, sound_non_occurrence, drives, wait_drive``). :meth:`Log.save` writes them
with the names of the phases and modes (``phase_names``, ``mode_names``: ``phase_names[k]``
is the name of phase ``k``), the drives, and the teacher's events (:func:`event_arrays`).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path
from typing import Any

import numpy as np

from hippo.io import save_npz
from hippo.types import GroundTruth, Mode, Observation

__all__ = ["Log", "enum_names", "event_arrays"]

#: the columns of a log, in order
COLUMNS = ("t", "x", "y", "heading", "speed", "zone", "sound", "winner", "mode", "prediction",
           "non_occurrence", "sound_prediction", "sound_non_occurrence", "phase", "trial",
           "drives", "wait_drive")
_AGENT = ("winner", "mode", "prediction", "non_occurrence", "sound_prediction",
          "sound_non_occurrence", "drives", "wait_drive")


def enum_names(enum: type[Enum]) -> np.ndarray:
    """``names[k]`` = the lower-case name of the member with value ``k`` (an int enum whose
    values are 0..n-1), as stored in ``run.npz``."""
    members = sorted(enum, key=lambda m: int(m.value))  # type: ignore[arg-type]
    if [int(m.value) for m in members] != list(range(len(members))):  # type: ignore[arg-type]
        raise ValueError(f"{enum.__name__} values must be 0..{len(members) - 1}")
    return np.array([m.name.lower() for m in members])


def event_arrays(events: Iterable[tuple[float, str, str]]) -> dict[str, np.ndarray]:
    """The world's event log ``[(t, kind, detail)]`` as ``event_t``, ``event_kind`` and
    ``event_detail`` arrays (fixed-width strings, no pickle in ``.npz``: at least 16 and 64
    characters wide, wider where a kind or a detail is longer, never cut)."""
    ev = list(events)
    kinds, details = [str(e[1]) for e in ev], [str(e[2]) for e in ev]
    return {"event_t": np.array([e[0] for e in ev], float),
            "event_kind": np.array(kinds, dtype=f"<U{max([16, *map(len, kinds)])}"),
            "event_detail": np.array(details, dtype=f"<U{max([64, *map(len, details)])}")}


@dataclass
class Log:
    """Per-tick arrays of the whole run (``n_drives`` columns of drive levels)."""

    n_drives: int = 1
    cols: dict[str, list] = field(default_factory=lambda: {k: [] for k in COLUMNS})

    def __len__(self) -> int:
        return len(self.cols["t"])

    def add(self, obs: Observation, truth: GroundTruth, agent: Any | None, phase: int,
            trial: int) -> None:
        """One tick: what the world says (``truth``, the senses) and what ``agent`` did."""
        c = self.cols
        x, y, h = truth.pose
        c["t"].append(obs.t)
        c["x"].append(x)
        c["y"].append(y)
        c["heading"].append(h)
        c["speed"].append(truth.speed)
        c["zone"].append(obs.floor)
        c["sound"].append(obs.sound)
        c["phase"].append(int(phase))
        c["trial"].append(trial)
        if agent is None:
            c["winner"].append(-1)
            c["mode"].append(int(Mode.EXPLORE))
            c["prediction"].append(0.0)
            c["non_occurrence"].append(False)
            c["sound_prediction"].append(0.0)
            c["sound_non_occurrence"].append(False)
            c["drives"].append([0.0] * self.n_drives)
            c["wait_drive"].append(-1)
        else:
            s = agent.snapshot()
            for k in _AGENT:
                c[k].append(s[k])

    def column(self, name: str, start: int = 0, stop: int | None = None) -> np.ndarray:
        """One column (rows ``start:stop``) as an array."""
        return np.asarray(self.cols[name][start:stop])

    def arrays(self) -> dict[str, np.ndarray]:
        return {k: np.asarray(v) for k, v in self.cols.items()}

    def path_length(self, start: int, origin: tuple[float, float],
                    until_t: float | None = None) -> float:
        """Length (cm) of the robot's path from ``origin`` through the rows ``start:`` (up to
        and including the row at time ``until_t``).

        A row is written after its tick's step, so the first row is already one step away
        from where the robot stood: ``origin`` (where it was put) starts the path. Without it
        a straight run is up to one step short, and its ratio to the shortest path fell below 1.
        """
        xs, ys, ts = (self.column(c, start) for c in ("x", "y", "t"))
        if until_t is not None:
            keep = ts <= until_t
            xs, ys = xs[keep], ys[keep]
        xs = np.concatenate(([float(origin[0])], xs))
        ys = np.concatenate(([float(origin[1])], ys))
        return float(np.sum(np.hypot(np.diff(xs), np.diff(ys))))

    def save(self, out: Path, agent: Any, world: Any, *, phases: type[Enum] | None = None,
             drive_names: Sequence[str] | None = None) -> dict[str, np.ndarray]:
        """Write ``out/run.npz`` (per-tick arrays, phase and mode names, the drives' names and
        the teacher's events) and ``out/map.graphml``; returns the per-tick arrays."""
        Path(out).mkdir(parents=True, exist_ok=True)
        arrays = self.arrays()
        names = list(drive_names) if drive_names is not None else agent.drives.names
        extra = {"drive_names": np.array(names), "mode_names": enum_names(Mode)}
        if phases is not None:
            extra["phase_names"] = enum_names(phases)
        save_npz(Path(out) / "run.npz", {**arrays, **extra, **event_arrays(world.events)})
        agent.graph.to_graphml(Path(out) / "map.graphml")
        return arrays
