"""Recordings: run a controller for N ticks and keep what the robot sensed and where it was.

A :class:`Recording` holds per-tick arrays (time, sensor matrix, pose, speed, floor colour,
nearest labelled location, region) and the event log, and round-trips through ``.npz``.
The command ``hippo record`` lives in :mod:`hippo.cli` (it also draws figures).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

from hippo._checks import check_array, check_int, check_positive, check_seed
from hippo.io import CorruptFileError, load_npz, save_npz
from hippo.progress import Progress
from hippo.seeds import Seeds
from hippo.sim import arenas as arena_registry
from hippo.sim.arena import Arena
from hippo.sim.controllers import WallFollower, WallFollowerParams
from hippo.sim.robot import RobotParams, SensorModel
from hippo.sim.world import World


@dataclass
class Recording:
    """Per-tick arrays of one run (length T) plus metadata and the event log."""

    arena: str
    sensor_model: str
    dt: float
    seed: int
    t: np.ndarray
    sensors: np.ndarray          #: (T, n_sensors) readings in [0, 1]
    x: np.ndarray
    y: np.ndarray
    heading: np.ndarray
    speed: np.ndarray
    floor: np.ndarray            #: floor colour id per tick
    label: np.ndarray            #: index of the nearest labelled location
    region: np.ndarray           #: index into region_names (-1: none)
    region_names: list[str] = field(default_factory=list)
    event_t: np.ndarray = field(default_factory=lambda: np.zeros(0))
    event_kind: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype="<U16"))
    event_detail: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype="<U64"))

    def __len__(self) -> int:
        return len(self.t)

    @property
    def positions(self) -> np.ndarray:
        return np.stack([self.x, self.y], axis=1)

    def slice(self, start: int, stop: int) -> Recording:
        """The ticks ``start:stop``, as Python slices them (negative indices count from the
        end), and the events from the first kept tick's time to the last's (none if no tick
        is kept)."""
        sl = slice(start, stop)
        kept = range(len(self.t))[sl]
        t0, t1 = (self.t[kept[0]], self.t[kept[-1]]) if len(kept) else (np.inf, -np.inf)
        keep = (self.event_t >= t0) & (self.event_t <= t1)
        per_tick = {f.name: getattr(self, f.name)[sl] for f in fields(self)
                    if isinstance(getattr(self, f.name), np.ndarray)
                    and not f.name.startswith("event_")}
        return Recording(self.arena, self.sensor_model, self.dt, self.seed, **per_tick,
                         region_names=list(self.region_names), event_t=self.event_t[keep],
                         event_kind=self.event_kind[keep], event_detail=self.event_detail[keep])

    def save(self, path: str | Path) -> Path:
        """Write to ``.npz`` atomically (no pickle)."""
        arrays = {f.name: getattr(self, f.name) for f in fields(self)}
        arrays["region_names"] = np.array(self.region_names, dtype=str)
        arrays["format"] = np.array(RECORDING_FORMAT)
        return save_npz(path, arrays)

    @classmethod
    def load(cls, path: str | Path) -> Recording:
        """Read a recording written by :meth:`save`. Every array is checked (dtype, shape,
        length T, finiteness, sensors in [0, 1], time increasing, ``dt > 0``, region indices
        within ``region_names``); a damaged file raises :class:`~hippo.io.CorruptFileError`."""
        names = [f.name for f in fields(cls)]
        data = load_npz(path, required=["format"])   # the kind first, then its arrays
        fmt = data["format"]
        if fmt.dtype.kind != "U" or fmt.shape != () or str(fmt) != RECORDING_FORMAT:
            found = str(fmt)[:60] if fmt.dtype.kind == "U" and fmt.shape == () else "no text"
            raise CorruptFileError(f"{path} is not a hippo recording (its format tag is "
                                   f"{found!r}, a recording's {RECORDING_FORMAT!r})")
        missing = [k for k in names if k not in data]
        if missing:
            raise CorruptFileError(f"{path} lacks required array(s): {', '.join(missing)}")
        try:
            kw = _checked_fields(data)
        except ValueError as exc:
            raise CorruptFileError(f"{path}: {exc}") from exc
        return cls(**kw)


RECORDING_FORMAT = "hippo.Recording/1"


def _text(name: str, v: np.ndarray) -> str:
    if v.dtype.kind != "U" or v.shape != ():
        raise ValueError(f"{name} must be a text scalar, got dtype {v.dtype} shape {v.shape}")
    return str(v)


def _checked_fields(data: dict[str, np.ndarray]) -> dict[str, object]:
    """The fields of a saved recording, each checked for dtype, shape and range."""
    kw: dict[str, object] = {"arena": _text("arena", data["arena"]),
                             "sensor_model": _text("sensor_model", data["sensor_model"])}
    kw["dt"] = check_positive("dt", float(check_array("dt", data["dt"], shape=())))
    kw["seed"] = check_seed("seed", int(check_array("seed", data["seed"], shape=(), dtype="int")))
    t = check_array("t", data["t"], shape=(None,))
    T = len(t)
    if T > 1 and not (np.diff(t) > 0).all():
        raise ValueError("t must increase from tick to tick")
    kw["t"] = t
    sensors = check_array("sensors", data["sensors"], shape=(T, None))
    if sensors.shape[1] < 1 or (sensors.size and (sensors.min() < 0 or sensors.max() > 1)):
        raise ValueError(f"sensors must be (T, n >= 1) readings in [0, 1], got shape "
                         f"{sensors.shape}")
    kw["sensors"] = sensors
    for k in ("x", "y", "heading", "speed"):
        kw[k] = check_array(k, data[k], shape=(T,))
    names = data["region_names"]
    if names.ndim != 1 or (names.size and names.dtype.kind != "U"):
        raise ValueError(f"region_names must be a list of text, got dtype {names.dtype}")
    kw["region_names"] = [str(n) for n in names]
    for k in ("floor", "label", "region"):
        v = check_array(k, data[k], shape=(T,), dtype="int")
        if v.size and (v.min() < -1 or v.max() > np.iinfo(np.int16).max):
            raise ValueError(f"{k} holds an index outside [-1, 32767]")
        kw[k] = v.astype(np.int16)
    if T and kw["region"].max() >= len(names):  # type: ignore[union-attr]
        raise ValueError(f"region indices exceed the {len(names)} region_names")
    kw["event_t"] = check_array("event_t", data["event_t"], shape=(None,))
    E = len(kw["event_t"])  # type: ignore[arg-type]
    for k in ("event_kind", "event_detail"):
        v = data[k]
        if v.shape != (E,) or (E and v.dtype.kind != "U"):
            raise ValueError(f"{k} must be {E} text values, got dtype {v.dtype} shape {v.shape}")
        kw[k] = v
    return kw


def record(arena: Arena | str, ticks: int, *, seed: int = 0, rho: float = 0.008,
           sensors: str | SensorModel = "ir8", robot: RobotParams | None = None,
           controller: object | None = None, dt: float = 0.2,
           kidnaps: Sequence[tuple[int, tuple[float, float, float]]] = (),
           start_pose: tuple[float, float, float] | None = None,
           progress: bool = True, desc: str = "recording") -> Recording:
    """Drive the robot for ``ticks`` control periods and record everything.

    The default controller is SMC09's :class:`WallFollower` with switching probability ``rho``;
    pass any object with ``act(obs) -> (left, right)`` instead. ``kidnaps`` is a list of
    ``(tick, (x, y, heading))``: before that tick (in ``[0, ticks)``, each at most once) the
    robot is moved there and keeps going.
    """
    if isinstance(arena, str):
        arena = arena_registry.get(arena)
    ticks = check_int("ticks", ticks, lo=1)
    kid: dict[int, tuple[float, float, float]] = {}
    for tick, pose in kidnaps:
        tick = check_int("kidnap tick", tick, lo=0, hi=ticks - 1)
        if tick in kid:
            raise ValueError(f"two kidnaps at tick {tick}")
        kid[tick] = pose
    world = World(arena, robot=robot, sensors=sensors, dt=dt, seed=seed)
    world.reset(seed, pose=start_pose)
    if controller is None:
        controller = WallFollower(WallFollowerParams(rho=rho), sensors=world.sensors,
                                  robot=world.robot, rng=Seeds(seed).generator("recording"))
    n = world.sensors.n
    S = np.empty((ticks, n))
    P = np.empty((ticks, 5))
    floor = np.empty(ticks, dtype=np.int16)
    obs = world.observe()
    with Progress(ticks, desc, enabled=None if progress else False) as bar:
        for k in range(ticks):
            if k in kid:
                world.place_robot(*kid[k])
                obs = world.observe()
            obs = world.step(controller.act(obs))
            truth = world.truth
            S[k] = obs.ir
            P[k] = (obs.t, *truth.pose, truth.speed)
            floor[k] = obs.floor
            if k % 1000 == 999:
                bar.update(1000)
        if ticks > bar.n:
            bar.update(ticks - bar.n)
    x, y = P[:, 1], P[:, 2]
    region = np.array([arena.region_index(a, b) for a, b in zip(x, y)], dtype=np.int16)
    ev = world.events
    return Recording(
        arena=arena.name, sensor_model=world.sensors.name, dt=world.dt, seed=seed, t=P[:, 0],
        sensors=S, x=x, y=y, heading=P[:, 3], speed=P[:, 4], floor=floor,
        label=arena.nearest_location(x, y).astype(np.int16), region=region,
        region_names=arena.region_names,
        event_t=np.array([e[0] for e in ev], float),
        event_kind=np.array([e[1] for e in ev], dtype="<U16"),
        event_detail=np.array([e[2] for e in ev], dtype="<U64"))
