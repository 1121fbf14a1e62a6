"""The state layer's vocabulary: its parameters (:class:`StateLayerParams`), the key of a
state (:class:`StateKey`), the outcome of a tick (:class:`StateEvent`) and the checks of the
event inputs. The layer itself is :class:`hippo.perception.states.StateLayer`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from hippo._checks import check_fields, check_finite, check_positive, check_range
from hippo.perception.contexts import ContextParams

__all__ = ["EVENT_KINDS", "StateEvent", "StateKey", "StateLayerParams"]

#: kinds of event (salient) states, in order of priority when several start at one tick
EVENT_KINDS = ("sound", "colour", "still", "moving")
_KINDS = ("place", *EVENT_KINDS)
_CONTEXT_KINDS = ("place", "colour")


class StateKey(NamedTuple):
    """Identity of a state: its kind, unit index or colour id, and context state id. A place
    split by context (``StateLayerParams.contexts``) has one state per context, all with the
    key of the place; :meth:`StateLayer.clone` tells them apart."""

    kind: str
    index: int | None = None
    context: int | None = None


@dataclass(frozen=True)
class StateLayerParams:
    """Parameters of the state layer.

    margin: how much (common scale, 0-1) a place must exceed the winner by (default 0.15).
    hold_time: for how long, seconds (default 0.6 s = 3 ticks at dt = 0.2 s).
    normalize: ``"pooled"`` (default) standardises place activities by the running mean and
        variance of the whole population; ``"unit"`` by each unit's own; ``"fixed"``: raw.
    place_scale: the standardised (or raw) activity mapped to tanh(1) = 0.76 (default 2.0).
    norm_tau: time constant of the running statistics, seconds (default 300 s).
    smoothing: time constant of the place neurons' low-pass filter, seconds (default 0.4 s:
        halves the noise for one extra tick of latency; 0 disables it).
    recruit_threshold: ``StateEvent.novel`` is True when no place activity reaches this
        (default 0.3): the place cell learner may recruit a new cell (HIREL learns place cells
        online above a minimum activity threshold).
    events: which event kinds are states (default all of ``EVENT_KINDS``). Without
        ``"moving"``, the robot resuming its movement hands the win from ``still@s`` straight
        back to its context ``s`` (the wait transition is then ``still@s -> s``).
    priority: order of the event kinds when several start at one tick (default
        ``("sound", "colour", "still", "moving")``).
    conjunctive: event kinds bound to the current context (default ``("still", "moving")``).
    transient: event kinds whose activity falls to 0 ``transient_time`` after onset
        (default ``("moving",)``, ``transient_time`` 1.0 s).
    context_time: a place becomes the context of conjunctive events only once it has held
        the win this long (s; default 0: at once). A place that wins only briefly before the
        robot stops (noisy learned place cells between two fields, or the obstacle that stopped
        the robot seen by its distance sensors) is then not what the stop is bound to: the
        place before it is. Colours bind at once (a floor colour is not noisy).
    contexts: split places into context states by the way the robot came in, and merge places
        that take turns (:mod:`hippo.perception.contexts`); None (default): one state per
        place cell. A place that wins is then reported as its context state (key ``("place",
        unit, None)``, :meth:`StateLayer.clone` its context id); while it holds, the
        competition uses the strongest unit of the places merged with it.
    """

    margin: float = 0.15
    hold_time: float = 0.6
    normalize: str = "pooled"
    place_scale: float = 2.0
    norm_tau: float = 300.0
    smoothing: float = 0.4
    recruit_threshold: float = 0.3
    events: tuple[str, ...] = EVENT_KINDS
    priority: tuple[str, ...] = EVENT_KINDS
    conjunctive: tuple[str, ...] = ("still", "moving")
    transient: tuple[str, ...] = ("moving",)
    transient_time: float = 1.0
    context_time: float = 0.0
    contexts: ContextParams | None = None

    def __post_init__(self) -> None:
        check_fields(self)
        check_range("margin", self.margin, 0.0, 1.0)
        check_positive("hold_time", self.hold_time, allow_zero=True)
        if self.normalize not in ("pooled", "unit", "fixed"):
            raise ValueError(f"normalize must be 'pooled', 'unit' or 'fixed', "
                             f"got {self.normalize!r}")
        check_positive("place_scale", self.place_scale)
        check_positive("norm_tau", self.norm_tau)
        check_positive("smoothing", self.smoothing, allow_zero=True)
        check_range("recruit_threshold", self.recruit_threshold, 0.0, 1.0)
        if sorted(self.priority) != sorted(EVENT_KINDS):
            raise ValueError(f"priority must order all of {EVENT_KINDS}, got {self.priority}")
        for name in ("events", "conjunctive", "transient"):
            bad = [k for k in getattr(self, name) if k not in EVENT_KINDS]
            if bad:
                raise ValueError(f"{name} lists unknown event kind(s) {bad}; "
                                 f"choose from {EVENT_KINDS}")
        check_positive("transient_time", self.transient_time)
        check_positive("context_time", self.context_time, allow_zero=True)


@dataclass(frozen=True, init=False)
class StateEvent:
    """Outcome of one tick of the state layer.

    t: time of this tick (sum of the dt so far, s). winner: the winning state id.
    changed: the winner changed at this tick — a sensory event (also True at the first tick).
    previous: the state that lost at this event (None otherwise). since: when the winner won.
    novel: no place cell reaches ``recruit_threshold``.
    """

    t: float
    winner: int
    changed: bool
    previous: int | None
    since: float
    novel: bool

    def __init__(self, t: float, winner: int, changed: bool, previous: int | None, since: float,
                 novel: bool) -> None:
        # one a tick: the fields written straight into the instance's dict (a frozen
        # dataclass's own __init__ calls object.__setattr__ once per field)
        d = self.__dict__
        d["t"], d["winner"], d["changed"] = t, winner, changed
        d["previous"], d["since"], d["novel"] = previous, since, novel


def _flag(name: str, value: object) -> bool | None:
    if value is None or value is True or value is False:  # the usual case (every tick)
        return value  # type: ignore[return-value]
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, str | bytes) or np.ndim(value) != 0:  # float() would read "1", [1]
        raise ValueError(f"{name} must be a boolean (or 0/1), got {value!r}")
    v = float(check_finite(name, value))
    if v not in (0.0, 1.0):
        raise ValueError(f"{name} must be a boolean (or 0/1), got {value!r}")
    return v == 1.0


def _colour(value: object) -> int | None:
    if value is None:
        return None
    if type(value) is int and value >= 0:  # the usual case, checked without numpy
        return None if value == 0 else value
    if isinstance(value, bool | np.bool_ | str | bytes) or np.ndim(value) != 0:
        raise ValueError(f"colour must be an integer colour id, got {value!r}")
    v = float(check_finite("colour", value))
    if v != int(v) or v < 0:
        raise ValueError(f"colour must be an integer colour id >= 0, got {value!r}")
    return None if v == 0 else int(v)
