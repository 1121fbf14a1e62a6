"""Drives (HIREL sec. II): motivations that build up, are satisfied by rewards, can be inhibited.

Each named drive ``d`` (e.g. ``"sound"``, ``"checkpoint-2"``) has a level in [0, 1]:

- **build-up** (HIREL: "Drives build up over time (with a speed regulated by the ε parameter)"),
  one explicit Euler step per tick::

      d ← d + ε (1 − d) dt          (needs ε·dt ≤ 1, so d stays ≤ 1)

  After ``n`` steps from ``d0``: ``d_n = 1 − (1 − d0)(1 − ε dt)^n`` (→ ``1 − (1 − d0) e^{−ε t}``
  as dt → 0).
- **satisfaction**: a reward for drive ``d`` resets it to 0 (:meth:`Drives.satisfy`).
- **inhibition**: while the non-occurrence detector signals that the predicted satisfaction did
  not come, the drive is held at 0 (:meth:`Drives.step` ``inhibited=...``, or the persistent
  :meth:`Drives.inhibit` / :meth:`Drives.release`); when released it rises again from 0.

**Goal links.** HIREL: "The reward signal satisfying a particular drive triggers the association
in the cognitive map between this drive and the last transition performed." Each drive keeps a
weight ``W_g`` in [0, 1] per goal transition ``g`` (any number of goals per drive). The learning
rule is the event form of HIREL's satisfaction rule (eq. 4,
``dW/dt = α (1 − W) X^T X^S − γ X^T``):

- on a reward after transition ``g`` (:meth:`Drives.link`, :meth:`Drives.reward`):
  ``W_g ← W_g + α (1 − W_g)`` (a new link starts at 0, so after ``k`` rewards
  ``W_g = 1 − (1 − α)^k``);
- when ``g`` was performed and the predicted reward did not come (:meth:`Drives.extinguish`):
  ``W_g ← (1 − γ) W_g``; a link below ``min_weight`` is dropped.

Both keep ``W`` in [0, 1]. This is eq. 4's one home: the brain links a drive on every reward
(:meth:`Drives.reward`) and, when a wait for a predicted reward ends by non-occurrence, calls
:meth:`Drives.extinguish` (a no-op with the default ``extinction = 0``). The drive input of a
transition to the planner is ``max_d level(d) · W_{d, g}`` (see
:mod:`hippo.cognitive_map.planner`).
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from hippo._checks import check_fields, check_positive, check_range
from hippo.cognitive_map.graph import Transition
from hippo.cognitive_map.keys import as_transition
from hippo.io import CorruptFileError, load_json, save_json

DRIVES_FORMAT = "hippo.cognitive_map.Drives/1"
_DRIVE_KEYS = {"name", "params", "level", "inhibited", "links"}


@dataclass(frozen=True)
class DriveParams:
    """Parameters of one drive.

    epsilon:       build-up rate ε (1/s): ``d += ε (1 − d) dt``.
    learning_rate: α of the goal-link rule ``W += α (1 − W)`` on reward, in (0, 1].
    extinction:    γ of ``W ← (1 − γ) W`` when a goal transition goes unrewarded, in [0, 1].
    min_weight:    links weaker than this are dropped after extinction.
    initial:       level at creation, in [0, 1].
    """

    epsilon: float = 0.01
    learning_rate: float = 0.5
    extinction: float = 0.0
    min_weight: float = 0.01
    initial: float = 0.0

    def __post_init__(self) -> None:
        check_fields(self)
        check_positive("DriveParams.epsilon", self.epsilon, allow_zero=True)
        check_range("DriveParams.learning_rate", self.learning_rate, 0.0, 1.0, closed="right")
        check_range("DriveParams.extinction", self.extinction, 0.0, 1.0)
        check_range("DriveParams.min_weight", self.min_weight, 0.0, 1.0)
        check_range("DriveParams.initial", self.initial, 0.0, 1.0)


class Drives:
    """A set of named drives with levels, inhibition and goal links.

    ``Drives({"sound": DriveParams(epsilon=0.02), "checkpoint-1": DriveParams()})`` or
    ``Drives(["sound"])`` (default parameters); more with :meth:`add`.

    ``links_version`` grows whenever a goal link changes (the planner re-propagates then).
    """

    def __init__(self, drives: Mapping[str, DriveParams | None] | Iterable[str] = ()) -> None:
        self._params: dict[str, DriveParams] = {}
        self._level: dict[str, float] = {}
        self._links: dict[str, dict[Transition, float]] = {}
        self._inhibited: set[str] = set()
        self.links_version = 0
        items = drives.items() if isinstance(drives, Mapping) else ((n, None) for n in drives)
        for name, params in items:
            self.add(name, params)

    # ---------------------------------------------------------------- queries
    def __contains__(self, name: object) -> bool:
        return name in self._params

    def __iter__(self) -> Iterator[str]:
        return iter(self._params)

    def __len__(self) -> int:
        return len(self._params)

    def __repr__(self) -> str:
        body = ", ".join(f"{n}={v:.3f}" for n, v in self._level.items())
        return f"Drives({body})"

    @property
    def names(self) -> list[str]:
        return list(self._params)

    def _check(self, name: str) -> str:
        if name not in self._params:
            known = ", ".join(repr(n) for n in self._params) or "none"
            raise KeyError(f"unknown drive {name!r} (known: {known})")
        return name

    def params(self, name: str) -> DriveParams:
        return self._params[self._check(name)]

    def level(self, name: str) -> float:
        return self._level[self._check(name)]

    @property
    def levels(self) -> dict[str, float]:
        """A copy of every drive's level."""
        return dict(self._level)

    def is_inhibited(self, name: str) -> bool:
        """True while :meth:`inhibit` holds ``name`` down (per-tick inhibition is not kept)."""
        return self._check(name) in self._inhibited

    def links(self, name: str) -> dict[Transition, float]:
        """A copy of the goal links of drive ``name``: transition → weight."""
        return dict(self._links[self._check(name)])

    @property
    def goals(self) -> dict[Transition, dict[str, float]]:
        """Every goal transition with the drives linked to it and their weights."""
        out: dict[Transition, dict[str, float]] = {}
        for name, links in self._links.items():
            for t, w in links.items():
                out.setdefault(t, {})[name] = w
        return out

    # ---------------------------------------------------------------- changes
    def add(self, name: str, params: DriveParams | None = None) -> None:
        """Add a drive (``ValueError`` if it exists or the name is not a non-empty string)."""
        if not isinstance(name, str) or not name:
            raise ValueError(f"a drive name must be a non-empty string, got {name!r}")
        if name in self._params:
            raise ValueError(f"drive {name!r} already exists")
        params = DriveParams() if params is None else params
        if not isinstance(params, DriveParams):
            raise TypeError(f"params of drive {name!r} must be DriveParams, got {params!r}")
        self._params[name] = params
        self._level[name] = params.initial
        self._links[name] = {}

    def set_level(self, name: str, level: float) -> None:
        self._level[self._check(name)] = check_range(f"level of drive {name!r}", level, 0.0, 1.0)

    def step(self, dt: float, inhibited: Iterable[str] = ()) -> None:
        """Advance every drive by ``dt`` seconds: ``d += ε (1 − d) dt``, or hold at 0 if inhibited.

        ``inhibited`` names the drives that the non-occurrence signal inhibits during this tick
        (on top of those held by :meth:`inhibit`). Every drive's step is checked before any
        level changes.
        """
        dt = check_positive("dt", dt, allow_zero=True)
        held = self._inhibited
        if inhibited:
            held = held | {self._check(n) for n in inhibited}
        params = self._params
        for name, p in params.items():   # every step checked before any level changes
            if p.epsilon * dt > 1.0 and name not in held:
                raise ValueError(
                    f"epsilon*dt = {p.epsilon * dt:g} > 1 for drive {name!r}: the Euler step "
                    "would overshoot 1; use a smaller dt")
        level = self._level
        for name, p in params.items():
            if name in held:
                level[name] = 0.0
            else:
                d = level[name]
                level[name] = d + p.epsilon * dt * (1.0 - d)

    def satisfy(self, name: str) -> None:
        """The reward for ``name`` arrived: its level drops to 0 (then rises again)."""
        self._level[self._check(name)] = 0.0

    def inhibit(self, name: str) -> None:
        """Hold ``name`` at 0 until :meth:`release` (HIREL's non-occurrence inhibition)."""
        self._inhibited.add(self._check(name))
        self._level[name] = 0.0

    def release(self, name: str) -> None:
        """End the inhibition of ``name``: it rises again from 0 at its own rate."""
        self._inhibited.discard(self._check(name))

    def link(self, name: str, transition: Transition, reward: float = 1.0) -> float:
        """Strengthen the link of drive ``name`` to ``transition``: ``W += α·reward·(1 − W)``.

        ``reward`` in [0, 1] scales the step. Returns the new weight.
        """
        links = self._links[self._check(name)]
        t = as_transition(transition)
        r = check_range("reward", reward, 0.0, 1.0)
        w = links.get(t, 0.0)
        w += self._params[name].learning_rate * r * (1.0 - w)
        links[t] = min(1.0, w)
        self.links_version += 1
        return links[t]

    def reward(self, name: str, transition: Transition | None, reward: float = 1.0) -> None:
        """A reward for ``name`` after ``transition``: :meth:`satisfy` and :meth:`link` it.

        ``transition=None`` (no transition performed yet) only satisfies.
        """
        self.satisfy(name)
        if transition is not None:
            self.link(name, transition, reward)

    def extinguish(self, name: str, transition: Transition) -> float:
        """``transition`` was performed but the reward for ``name`` did not come: ``W ← (1 − γ) W``.

        The link is dropped when it falls below ``min_weight``. Returns the new weight (0 if none).
        """
        links = self._links[self._check(name)]
        t = as_transition(transition)
        if t not in links:
            return 0.0
        p = self._params[name]
        w = links[t] * (1.0 - p.extinction)
        if w < p.min_weight:
            del links[t]
            w = 0.0
        else:
            links[t] = w
        self.links_version += 1
        return w

    def unlink(self, name: str, transition: Transition) -> None:
        """Remove the link of ``name`` to ``transition`` (no error if absent)."""
        if self._links[self._check(name)].pop(as_transition(transition), None) is not None:
            self.links_version += 1

    def prune(self, known: Iterable[Transition] | Any) -> int:
        """Drop links to transitions not in ``known`` (e.g. a graph after forgetting).

        Returns how many links were dropped.
        """
        keep = set(known)
        n = 0
        for links in self._links.values():
            for t in [t for t in links if t not in keep]:
                del links[t]
                n += 1
        if n:
            self.links_version += 1
        return n

    # ---------------------------------------------------------------- persistence
    def to_dict(self) -> dict[str, Any]:
        return {
            "format": DRIVES_FORMAT,
            "drives": [
                {"name": n, "params": asdict(p), "level": self._level[n],
                 "inhibited": n in self._inhibited,
                 "links": [[t[0], t[1], w] for t, w in self._links[n].items()]}
                for n, p in self._params.items()
            ],
        }

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Drives:
        """Rebuild drives from :meth:`to_dict`'s form, checking every field's type and range
        (``ValueError`` naming the bad one)."""
        if not isinstance(data, Mapping) or data.get("format") != DRIVES_FORMAT:
            got = data.get("format") if isinstance(data, Mapping) else type(data).__name__
            raise ValueError(f"not saved drives (format {got!r}, want {DRIVES_FORMAT!r})")
        items = data.get("drives")
        if not isinstance(items, list):
            raise ValueError(f"'drives' must be a list, got {type(items).__name__}")
        d = cls()
        for item in items:
            if not isinstance(item, Mapping) or set(item) != _DRIVE_KEYS:
                raise ValueError(f"a drive entry must have exactly the keys {sorted(_DRIVE_KEYS)}"
                                 f", got {item!r:.120}")
            name = item["name"]
            if not isinstance(item["params"], Mapping):
                raise ValueError(f"params of drive {name!r} must be an object")
            d.add(name, DriveParams(**item["params"]))
            level = item["level"]
            if isinstance(level, bool) or not isinstance(level, int | float):
                raise ValueError(f"level of drive {name!r} must be a number, got {level!r}")
            d.set_level(name, level)
            if not isinstance(item["inhibited"], bool):
                raise ValueError(f"inhibited of drive {name!r} must be true or false, got "
                                 f"{item['inhibited']!r}")
            if item["inhibited"]:
                d._inhibited.add(name)
            if not isinstance(item["links"], list):
                raise ValueError(f"links of drive {name!r} must be a list")
            for link in item["links"]:
                if not isinstance(link, list) or len(link) != 3:
                    raise ValueError(f"a link of drive {name!r} must be [a, b, weight], got "
                                     f"{link!r}")
                a, b, w = link
                if isinstance(w, bool) or not isinstance(w, int | float):
                    raise ValueError(f"link weight must be a number, got {w!r}")
                t = as_transition((a, b))
                if t in d._links[name]:
                    raise ValueError(f"drive {name!r} links {t} twice")
                d._links[name][t] = check_range("link weight", w, 0.0, 1.0)
        return d

    def save(self, path: str | os.PathLike) -> Path:
        """Write levels, parameters and links as JSON, atomically."""
        return save_json(path, self.to_dict())

    @classmethod
    def load(cls, path: str | os.PathLike) -> Drives:
        """Read drives written by :meth:`save`; a damaged file raises
        :class:`~hippo.io.CorruptFileError` naming the problem."""
        data = load_json(path)
        try:
            return cls.from_dict(data)
        except (KeyError, TypeError, ValueError, OverflowError) as exc:
            raise CorruptFileError(f"{path}: bad drives content ({exc})") from exc
