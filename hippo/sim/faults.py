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

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from hippo._checks import check_finite, check_int, check_real, check_seed

#: the ways a sensor can be dead
FAULT_MODES = ("stuck0", "stuck1", "noise")


def _check_pair(item: tuple[Any, ...] | list[Any]) -> tuple[int, str]:
    """One ``(index, mode)`` dead-sensor entry, checked: exactly two items, an integer index
    >= 0, a known mode."""
    if len(item) != 2:
        raise ValueError(f"dead_sensors entries must be (index, mode), got {item!r}")
    i = check_int("dead sensor index", item[0], lo=0)
    mode = item[1]
    if not isinstance(mode, str) or mode not in FAULT_MODES:
        raise ValueError(f"dead sensor mode for sensor {i} must be one of "
                         f"{', '.join(FAULT_MODES)}; got {mode!r}")
    return i, str(mode)


@dataclass(frozen=True)
class SensorFaults:
    """Which sensors are dead and how (``dead``: (index, mode) pairs), the s.d. of the noise
    added to all live readings, and the first faulty tick."""

    dead: tuple[tuple[int, str], ...] = ()
    sensor_noise: float = 0.0
    start: int = 0

    def __post_init__(self) -> None:
        if not isinstance(self.dead, tuple):
            raise ValueError(f"dead must be a tuple of (index, mode) pairs, got {self.dead!r}")
        seen = set()
        for item in self.dead:
            if not isinstance(item, tuple):
                raise ValueError(f"dead_sensors entries must be (index, mode) tuples, got "
                                 f"{item!r}")
            i, _ = _check_pair(item)
            if i in seen:
                raise ValueError(f"sensor {i} is listed as dead twice")
            seen.add(i)
        if check_real("sensor_noise", self.sensor_noise) < 0:
            raise ValueError(f"sensor_noise must be a finite s.d. >= 0, got {self.sensor_noise!r}")
        check_int("start", self.start, lo=0)

    @classmethod
    def of(cls, dead_sensors: Mapping[int, str] | Sequence[Any] | None = None, *,
           sensor_noise: float = 0.0, start: int = 0) -> SensorFaults:
        """Build from ``dead_sensors`` as ``{index: mode}``, a sequence of ``(index, mode)``
        pairs, or a sequence of indices (mode ``"stuck0"``). Indices must be integers (not
        bools, floats or strings), modes one of :data:`FAULT_MODES`."""
        if dead_sensors is None:
            pairs: list[tuple[int, str]] = []
        elif isinstance(dead_sensors, Mapping):
            pairs = [_check_pair((i, m)) for i, m in dead_sensors.items()]
        elif isinstance(dead_sensors, str | bytes) or not isinstance(dead_sensors, Iterable):
            raise ValueError("dead_sensors must be {index: mode}, a sequence of (index, mode) "
                             f"pairs or a sequence of indices, got {dead_sensors!r}")
        else:
            pairs = [_check_pair(d) if isinstance(d, tuple | list) else _check_pair((d, "stuck0"))
                     for d in dead_sensors]
        return cls(tuple(sorted(pairs)), check_real("sensor_noise", sensor_noise),
                   check_int("start", start, lo=0))

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
        rng = _rng(seed)
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


def _rng(seed: int | np.random.Generator) -> np.random.Generator:
    """The generator of a fault's noise: ``seed`` itself, or one made from an integer seed."""
    if isinstance(seed, np.random.Generator):
        return seed
    return np.random.default_rng(check_seed("seed", seed))


class FaultInjector:
    """Apply :class:`SensorFaults` online, one reading per call (tick counted from 0)."""

    def __init__(self, faults: SensorFaults, seed: int | np.random.Generator = 0) -> None:
        if not isinstance(faults, SensorFaults):
            raise TypeError(f"faults must be SensorFaults (e.g. SensorFaults.of({{1: "
                            f"'stuck0'}})), got {type(faults).__name__}")
        self.faults = faults
        self.rng = _rng(seed)
        self.tick = 0

    def __call__(self, u: np.ndarray) -> np.ndarray:
        u = np.asarray(u, dtype=float)
        if u.ndim != 1:
            raise ValueError(f"a reading must be a 1-D sensor vector, got shape {u.shape}")
        # refused before the start tick as after it, and a refused reading counts no tick
        u = check_finite("sensor matrix U", u)
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
