"""The two-rooms experiment's recordings: the clean exploration run and the same run kidnapped
during the test part (moved to the other room at test ticks 150 and 640, put back at 400 and
980: SMC09 Fig. 7), both cached with ``--cache``. Used by :mod:`hippo.scenarios.two_rooms`."""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path

import numpy as np

from hippo.io import CorruptFileError, load_json, save_json
from hippo.scenarios._common import cached_recording
from hippo.seeds import Seeds
from hippo.sim.arena import Arena
from hippo.sim.controllers import WallFollower, WallFollowerParams
from hippo.sim.record import Recording, record
from hippo.sim.world import World

KIDNAP_AWAY = (150, 640)    # test ticks: moved to the other room (SMC09 Fig. 7)
KIDNAP_BACK = (400, 980)    # test ticks: put back where it was taken from


def _other_room_pose(arena, room: str, rng: np.random.Generator) -> tuple[float, float, float]:
    target = "room_a" if room == "room_b" else "room_b"
    region = next(r for r in arena.regions if r.name == target)
    x0, y0, x1, y1 = region.rects[0]
    return arena.sample_free_pose(rng, margin=4.0, rect=(x0 + 6, y0 + 6, x1 - 6, y1 - 6))


def _room_at(arena, x: float, y: float) -> str:
    name = arena.region_of(x, y)
    if name in ("room_a", "room_b"):
        return name
    return "room_a" if x < arena.width * 0.375 else "room_b"


def kidnapped_recording(arena: Arena, ticks: int, n_train: int, *, seed: int, rho: float
                        ) -> tuple[Recording, list[int], list[str], list[bool]]:
    """The same run as the clean recording, but kidnapped during the test part.

    At test ticks 150 and 640 the robot is moved to a random free pose in the other room; at
    400 and 980 it is put back at the pose it was taken from. Returns the recording, the
    absolute event ticks, the kind of each event, and whether the event really changed the
    robot's room (the wall follower sometimes walks back to its room on its own before it is
    put back; such a "kidnap" changes nothing and is left out of the recovery statistics).
    """
    rng = Seeds(seed).generator("kidnaps")
    kid: list[tuple[int, tuple[float, float, float]]] = []
    events, kinds, moved = [], [], []
    test_len = ticks - n_train
    # one pass of the same run (same world and controller seeds as ``record``) decides the
    # kidnaps as it goes; ``record`` then replays the run with them
    world = World(arena, sensors="ir8", seed=seed)
    world.reset(seed)
    ctrl = WallFollower(WallFollowerParams(rho=rho), sensors=world.sensors, robot=world.robot,
                        rng=Seeds(seed).generator("recording"))
    plan = {}
    for away, back in zip(KIDNAP_AWAY, KIDNAP_BACK):
        if back < test_len:
            plan[n_train + away] = "away"
            plan[n_train + back] = "back"
    obs = world.observe()
    taken: tuple[float, float, float] | None = None
    room = ""
    for k in range(max(plan, default=-1) + 1):
        if k in plan:
            pose = world.pose
            if plan[k] == "away":
                taken, room = pose, _room_at(arena, pose[0], pose[1])
                dest = _other_room_pose(arena, room, rng)
                kinds.append(f"away from {room}")
                moved.append(True)
            else:
                dest = taken
                kinds.append(f"back to {room}")
                moved.append(_room_at(arena, pose[0], pose[1]) != room)
            kid.append((k, dest))
            events.append(k)
            world.place_robot(*dest)
            obs = world.observe()
        obs = world.step(ctrl.act(obs))
    rec = record(arena, ticks, seed=seed, rho=rho, sensors="ir8", kidnaps=kid, progress=False)
    return rec, events, kinds, moved


def _recordings(args: argparse.Namespace, arena, ticks: int, n_train: int, seed: int):
    """The clean and the kidnapped recording of exploration run ``seed`` (cached with
    ``--cache``)."""
    tag = f"two-rooms_t{ticks}_rho{args.rho:g}_s{seed}"
    rec = cached_recording(args.cache, tag, lambda: record(
        arena, ticks, seed=seed, rho=args.rho, sensors="ir8", desc=f"two-rooms seed {seed}"),
        ticks)
    # "_kid2": kidnaps drawn from the named "kidnaps" stream (before: an unnamed key)
    meta_path = Path(args.cache) / f"{tag}_kid2.json" if args.cache else None
    if meta_path is not None and meta_path.exists():
        try:
            return (rec, *_cached_kidnaps(meta_path, ticks))
        except (CorruptFileError, FileNotFoundError) as exc:
            warnings.warn(f"the cached kidnapped recording {meta_path} is unusable ({exc}): "
                          "recording it again", stacklevel=2)
    rec_kid, events, kinds, moved = kidnapped_recording(arena, ticks, n_train, seed=seed,
                                                        rho=args.rho)
    if meta_path is not None:
        rec_kid.save(meta_path.with_suffix(".npz"))
        save_json(meta_path, {"events": events, "kinds": kinds, "moved": moved})
    return rec, rec_kid, events, kinds, moved


def _cached_kidnaps(meta_path: Path, ticks: int) -> tuple[Recording, list, list, list]:
    """The kidnapped recording and its events, kinds and moves read back from the cache,
    checked (``CorruptFileError`` names what is wrong)."""
    meta = load_json(meta_path)
    rec_kid = Recording.load(meta_path.with_suffix(".npz"))
    if not isinstance(meta, dict) or any(not isinstance(meta.get(k), list)
                                         for k in ("events", "kinds", "moved")):
        raise CorruptFileError(f"{meta_path} must hold the lists events, kinds and moved")
    ev, kinds, moved = meta["events"], meta["kinds"], meta["moved"]
    if not (len(ev) == len(kinds) == len(moved)) or len(rec_kid) != ticks \
            or not all(type(e) is int and 0 <= e < ticks for e in ev) \
            or not all(isinstance(k, str) for k in kinds) \
            or not all(isinstance(m, bool) for m in moved):
        raise CorruptFileError(f"{meta_path}: events, kinds and moved do not match each other "
                               f"or a {ticks}-tick recording")
    return rec_kid, ev, kinds, moved
