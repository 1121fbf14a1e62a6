"""Sensor faults: dead sensors and extra noise, injected into a recording or tick by tick.

A fault changes what the robot *reads*, never the world. The modes of a dead sensor:

* ``"stuck0"`` — reads 0 for ever (a short circuit: "touching a wall");
* ``"stuck1"`` — reads 1 for ever (a silent sensor: "nothing in range");
* ``"noise"``  — reads independent uniform noise on [0, 1] (a sensor that carries no signal).

``sensor_noise`` adds zero-mean Gaussian noise of that s.d. to every live reading (on top of
the sensor model's own noise), and the result is clipped to [0, 1] like a real reading.
Faults start at tick ``start`` (default 0: from the beginning), so a sensor can die mid-run.

Offline (a recording)::

    U_bad = SensorFaults.of({2: "stuck0"}, sensor_noise=0.05).apply(rec.sensors, seed=1)
    rec_bad = with_faults(rec, dead_sensors={2: "stuck0"}, seed=1)

Online (one reading per tick, e.g. between ``World.step`` and the place cells)::

    inj = FaultInjector(SensorFaults.of([(0, "stuck1")]), seed=1)
    ir = inj(obs.ir)
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from hippo._checks import check_finite

#: the ways a sensor can be dead
FAULT_MODES = ("stuck0", "stuck1", "noise")


@dataclass(frozen=True)
class SensorFaults:
    """Which sensors are dead and how (``dead``: (index, mode) pairs), the s.d. of the noise
    added to all live readings, and the first faulty tick."""

    dead: tuple[tuple[int, str], ...] = ()
    sensor_noise: float = 0.0
    start: int = 0

    def __post_init__(self) -> None:
        seen = set()
        for item in self.dead:
            if len(item) != 2:
                raise ValueError(f"dead_sensors entries must be (index, mode), got {item!r}")
            i, mode = item
            if not isinstance(i, int | np.integer) or i < 0:
                raise ValueError(f"dead sensor index must be an integer >= 0, got {i!r}")
            if mode not in FAULT_MODES:
                raise ValueError(f"dead sensor mode for sensor {i} must be one of "
                                 f"{', '.join(FAULT_MODES)}; got {mode!r}")
            if i in seen:
                raise ValueError(f"sensor {i} is listed as dead twice")
            seen.add(i)
        noise = float(self.sensor_noise)
        if not np.isfinite(noise) or noise < 0:
            raise ValueError(f"sensor_noise must be a finite s.d. >= 0, got {self.sensor_noise!r}")
        if int(self.start) < 0:
            raise ValueError(f"start must be a tick >= 0, got {self.start!r}")

    @classmethod
    def of(cls, dead_sensors: Mapping[int, str] | Sequence[Any] | None = None, *,
           sensor_noise: float = 0.0, start: int = 0) -> SensorFaults:
        """Build from ``dead_sensors`` as ``{index: mode}``, a sequence of ``(index, mode)``
        pairs, or a sequence of indices (mode ``"stuck0"``)."""
        if dead_sensors is None:
            pairs: list[tuple[int, str]] = []
        elif isinstance(dead_sensors, Mapping):
            pairs = [(int(i), str(m)) for i, m in dead_sensors.items()]
        else:
            pairs = [(int(d), "stuck0") if np.ndim(d) == 0 else (int(d[0]), str(d[1]))
                     for d in dead_sensors]
        return cls(tuple(sorted(pairs)), float(sensor_noise), int(start))

    @property
    def indices(self) -> list[int]:
        return [i for i, _ in self.dead]

    def apply(self, U: np.ndarray, seed: int | np.random.Generator = 0) -> np.ndarray:
        """A faulty copy of the sensor matrix ``U`` (T, n) (values in [0, 1])."""
        U = check_finite("sensor matrix U", U)
        if U.ndim != 2:
            raise ValueError(f"sensor matrix U must be (T, n_sensors), got shape {U.shape}")
        bad = [i for i in self.indices if i >= U.shape[1]]
        if bad:
            raise ValueError(f"dead sensor(s) {bad} out of range for {U.shape[1]} sensors")
        rng = np.random.default_rng(seed)
        out = U.copy()
        s = min(int(self.start), U.shape[0])
        part = out[s:]
        if self.sensor_noise > 0:
            part += rng.normal(0.0, self.sensor_noise, part.shape)
            np.clip(part, 0.0, 1.0, out=part)
        for i, mode in self.dead:
            if mode == "stuck0":
                part[:, i] = 0.0
            elif mode == "stuck1":
                part[:, i] = 1.0
            else:
                part[:, i] = rng.uniform(0.0, 1.0, part.shape[0])
        return out


class FaultInjector:
    """Apply :class:`SensorFaults` online, one reading per call (tick counted from 0)."""

    def __init__(self, faults: SensorFaults, seed: int | np.random.Generator = 0) -> None:
        self.faults = faults
        self.rng = np.random.default_rng(seed)
        self.tick = 0

    def __call__(self, u: np.ndarray) -> np.ndarray:
        u = np.asarray(u, dtype=float)
        if u.ndim != 1:
            raise ValueError(f"a reading must be a 1-D sensor vector, got shape {u.shape}")
        t = self.tick
        self.tick += 1
        if t < self.faults.start:
            return u.copy()
        return replace(self.faults, start=0).apply(u[None, :], self.rng)[0]


def with_faults(recording: Any, dead_sensors: Mapping[int, str] | Sequence[Any] | None = None,
                *, sensor_noise: float = 0.0, start: int = 0,
                seed: int | np.random.Generator = 0) -> Any:
    """A copy of a :class:`~hippo.sim.record.Recording` whose sensors carry the faults (pose,
    labels and events unchanged)."""
    faults = SensorFaults.of(dead_sensors, sensor_noise=sensor_noise, start=start)
    return replace(recording, sensors=faults.apply(recording.sensors, seed))
