"""Multimodal winner-take-all state layer: which sensory state is current (HIREL sec. II, Fig. 1).

Public API
----------
- :class:`StateLayerParams` — margin and hold time of the hysteresis, place-cell scaling,
  recruitment threshold, which event states are conjunctive or transient.
- :class:`StateLayer` — ``step(place, *, colour, sound, moving, dt) -> StateEvent``;
  ``reset(keep_states=False)``; ``recruit(kind, index, context) -> id``;
  ``bind_context(id)`` (the context of the next conjunctive events);
  ``find(kind, index, context) -> id``; ``key(id) -> StateKey``; ``describe(id) -> str``;
  ``states`` (all keys, index = state id); ``winner``; ``t``; ``place_activity``.
- :class:`StateEvent` — one tick's outcome: ``winner`` (int state id), ``changed`` (a sensory
  event: the winner changed at this tick), ``previous``, ``t``, ``since``, ``novel``.
- :class:`StateKey` — ``(kind, index, context)``: ``("place", 3, None)``, ``("colour", 2,
  None)``, ``("sound", None, None)``, ``("still", None, 5)`` = "still at state 5".

State ids are integers given in order of first appearance; they never change until
``reset()``. Use them as the nodes of transitions ``(a, b)``.

Competition
-----------
Every state has an activity on a common scale [0, 1] (:mod:`~hippo.perception.state_levels`):

* **place** ``i``: ``tanh(max(z_i, 0) / place_scale)``, low-pass filtered with time constant
  ``smoothing`` (a leaky state neuron), where ``z_i`` is the unit's activity standardised by
  the running mean and variance of the whole place population (``normalize="pooled"``, time
  constant ``norm_tau``; prior mean 0, variance 1, so whitened inputs such as ICA units work
  from the first tick). Pooling is a divisive gain control shared by all units: a dead unit
  stays silent and a long stay at one place does not adapt its cell away, which per-unit
  statistics (``"unit"``) would do; ``"fixed"`` uses the raw activity. Any source of place
  activity works (learned ICA units, template cells, ...); the vector may grow between ticks
  (new place cells are recruited).
* **event states** — ``sound``, floor ``colour`` (0 = plain floor, no state) and proprioception
  ``still`` / ``moving``: 1 while their input is on. They are *salient*: the onset of their
  input (sound starts, a colour appears, the robot stops or starts) makes them win at once.
  ``still`` and ``moving`` are conjunctive by default: they are bound to the context (the last
  place or colour state that won), so "still at the goal" and "still at checkpoint 2" are
  different states with different timed transitions. ``moving`` is transient: its activity
  falls to 0 ``transient_time`` after its onset so that place cells take over while driving.

Place states compete by level with hysteresis: a place beats the winner only when its activity
exceeds the winner's by ``margin`` for ``hold_time`` seconds in a row, so noisy place cells do
not flicker, and a clear change of input changes the winner within a few ticks
(``ceil(hold_time / dt)`` plus the filter's rise, 4 ticks by default). Event states win
only at onsets; a place replaces one once its input is off (its activity is then 0)::

    layer = StateLayer()
    ev = layer.step(place_acts, colour=obs.floor, sound=obs.sound, moving=obs.moving, dt=0.2)
    if ev.changed:
        print(f"t={ev.t:.1f}s: {layer.describe(ev.previous)} -> {layer.describe(ev.winner)}")
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from hippo._checks import check_positive
from hippo.perception.contexts import ContextStates
from hippo.perception.state_levels import StateLevels
from hippo.perception.state_params import (
    _CONTEXT_KINDS,
    _KINDS,
    EVENT_KINDS,
    StateEvent,
    StateKey,
    StateLayerParams,
    _colour,
    _flag,
)

__all__ = ["EVENT_KINDS", "StateEvent", "StateKey", "StateLayer", "StateLayerParams"]

class StateLayer(StateLevels):
    r"""Winner-take-all over place, colour, sound and proprioceptive states (HIREL Fig. 1).

    With :math:`x_s(t) \in [0, 1]` the activities on the common scale and :math:`w` the
    winner, a place :math:`c` takes over when

    .. math:: x_c(s) > x_w(s) + \text{margin} \quad \forall s \in [t - \text{hold}, t],

    and an event state :math:`e` takes over at once at the onset of its input
    (:math:`u_e(t) = 1,\ u_e(t - dt) = 0`).

    The competition (see the module docstring) implements HIREL's "a winner-take-all (WTA)
    competition takes place between the state neurons. Any change in the winning state
    triggers the spectral timing memory": every change of winner is a sensory event reported
    with its time. Place states need hysteresis (winner activity + ``margin`` during
    ``hold_time``); event states (sound, floor colour, still, moving) win at their onset.
    """

    def __init__(self, params: StateLayerParams | None = None, n_place: int = 0) -> None:
        self.params = params or StateLayerParams()
        if int(n_place) != n_place or n_place < 0:
            raise ValueError(f"n_place must be an integer >= 0, got {n_place!r}")
        self._n_place0 = int(n_place)
        self.reset()

    @property
    def activity(self) -> dict[int, float]:
        """State id -> activity at the last step: every place state's, and the winner's (an
        event state's level, or a context state's: the most active of its units)."""
        got = self._activity
        if got is None:
            ids, pa, winner, own = self._activity_of
            got = dict(zip(ids.tolist(), pa.tolist()))
            if own is not None:
                got[winner] = own
            self._activity = got
        return got

    @activity.setter
    def activity(self, value: dict[int, float]) -> None:
        self._activity = value

    # ---------------------------------------------------------------- registry
    def reset(self, *, keep_states: bool = False) -> None:
        """Restart the competition (and, unless ``keep_states``, forget every state id)."""
        if not keep_states or not hasattr(self, "_keys"):
            self._keys: list[StateKey] = []
            self._ids: dict[StateKey, int] = {}
            self._place_ids = np.zeros(0, dtype=int)
            self._mean = np.zeros(0)
            self._var = np.ones(0)
            self._evidence = np.zeros(0)
            self._add_places(self._n_place0)
            cp = self.params.contexts
            self.contexts: ContextStates | None = None if cp is None else ContextStates(cp)
            self._clone_of: dict[int, int] = {}           # state id -> context id
            self._clone_ids: dict[int, int] = {}           # context id -> state id
        else:
            self._mean[:] = 0.0
            self._var[:] = 1.0
            self._evidence[:] = 0.0
            if self.contexts is not None:
                self.contexts.reset()  # the way in is unknown after a kidnap
        self.t = 0.0
        self.winner: int | None = None
        self.since = 0.0
        self._context: int | None = None
        self._candidate: int | None = None   # a place winning, not yet held context_time
        self._prev_sound = False
        self._prev_colour: int | None = None
        self._prev_moving: bool | None = None
        self._onset_t: dict[int, float] = {}
        self._pool = (0.0, 1.0)
        self.place_activity = np.zeros(self._place_ids.size)
        self.activity = {}

    def recruit(self, kind: str, index: int | None = None, context: int | None = None) -> int:
        """Id of the state ``(kind, index, context)``, registering it if new."""
        key = self._make_key(kind, index, context)
        if key.kind == "place" and key.index >= self._place_ids.size:  # type: ignore[operator]
            self._add_places(key.index + 1 - self._place_ids.size)  # type: ignore[operator]
            return self._ids[key]
        return self._register(key)

    def bind_context(self, state: int) -> None:
        """Make ``state`` (a place or colour) the context of the next conjunctive events.

        For an agent that stops on purpose: it stops *for* a place it planned to reach, and
        the stop is bound to that place even when noisy place cells crown another one at the
        moment it stops (top-down: the expectation names the state)."""
        if self.key(state).kind not in _CONTEXT_KINDS:
            raise ValueError(f"only a place or colour can be a context, got "
                             f"{self.describe(state)}")
        self._context, self._candidate = int(state), None

    def find(self, kind: str, index: int | None = None, context: int | None = None) -> int:
        """Id of an existing state; ``ValueError`` if it was never seen."""
        key = self._make_key(kind, index, context)
        if key not in self._ids:
            raise ValueError(f"unknown state {key}: never seen by this state layer")
        return self._ids[key]

    def key(self, state: int) -> StateKey:
        """The :class:`StateKey` of a state id; ``ValueError`` for an unknown id."""
        if isinstance(state, bool) or not isinstance(state, (int, np.integer)):
            raise ValueError(f"state id must be an integer, got {state!r}")
        if not 0 <= state < len(self._keys):
            raise ValueError(f"unknown state id {state} (this layer has {len(self._keys)} states)")
        return self._keys[int(state)]

    def describe(self, state: int) -> str:
        """Human-readable name: ``place 3``, ``colour 2``, ``sound``, ``still@place 3``."""
        k = self.key(state)
        name = k.kind if k.index is None else f"{k.kind} {k.index}"
        if state in self._clone_of:
            name += f"|{self._clone_of[state]}"
        if k.context is not None:
            name += "@" + self.describe(k.context)
        return name

    @property
    def states(self) -> list[StateKey]:
        """Every state's key; the position is its id."""
        return list(self._keys)

    @property
    def n_states(self) -> int:
        """Number of states registered so far."""
        return len(self._keys)

    def _make_key(self, kind: str, index: int | None, context: int | None) -> StateKey:
        if kind not in _KINDS:
            raise ValueError(f"unknown state kind {kind!r}; choose from {_KINDS}")
        if kind in ("place", "colour"):
            if isinstance(index, bool) or not isinstance(index, (int, np.integer)) or index < 0:
                raise ValueError(f"a {kind} state needs an integer index >= 0, got {index!r}")
            index = int(index)
        elif index is not None:
            raise ValueError(f"a {kind} state takes no index, got {index!r}")
        if context is not None:
            if kind not in self.params.conjunctive:
                raise ValueError(f"{kind} states are not conjunctive (params.conjunctive)")
            self.key(context)
            context = int(context)
        return StateKey(kind, index, context)

    def _register(self, key: StateKey) -> int:
        sid = self._ids.get(key)
        if sid is None:
            sid = self._ids[key] = len(self._keys)
            self._keys.append(key)
        return sid

    def _add_places(self, n: int) -> None:
        start = self._place_ids.size
        ids = [self._register(StateKey("place", start + i, None)) for i in range(n)]
        self._place_ids = np.concatenate([self._place_ids, np.array(ids, dtype=int)])
        self._mean = np.concatenate([self._mean, np.zeros(n)])
        self._var = np.concatenate([self._var, np.ones(n)])
        self._evidence = np.concatenate([self._evidence, np.zeros(n)])
        if hasattr(self, "place_activity"):
            self.place_activity = np.concatenate([self.place_activity, np.zeros(n)])

    def clone(self, state: int) -> int | None:
        """The context id (in :attr:`contexts`) of a context state; None for any other."""
        self.key(state)
        return self._clone_of.get(int(state))

    def _units(self, state: int) -> list[int]:
        """The place units a place state stands for (several once places were merged)."""
        key = self._keys[state]
        if key.kind != "place":
            return []
        if self.contexts is None or state not in self._clone_of:
            return [key.index]  # type: ignore[list-item]
        return [int(u) for u in self.contexts.members(key.index)]

    def _context_state(self, unit: int) -> int:
        """Place unit ``unit`` won: the id of its context state (learning the way in)."""
        ctx = self.contexts
        cid = ctx.observe(int(unit), self.t)  # type: ignore[union-attr]
        sid = self._clone_ids.get(cid)
        if sid is None:
            # a context born of a split or a merge keeps the state id of the oldest context
            # it replaced, so what the map and the timing learned about it carries over
            older = [c for c in self._clone_ids if ctx.resolve(c) == cid]  # type: ignore[union-attr]
            if older:
                sid = self._clone_ids[min(older)]
            else:
                sid = len(self._keys)
                self._keys.append(StateKey("place", int(ctx.same(int(unit))), None))  # type: ignore[union-attr]
            self._clone_ids[cid] = sid
            self._clone_of[sid] = cid
        return sid

    # ---------------------------------------------------------------- competition
    def _event_state(self, kind: str) -> int:
        ctx = self._context if kind in self.params.conjunctive else None
        return self._register(StateKey(kind, None, ctx))

    def step(self, place: ArrayLike | None = None, *, colour: int | None = None,
             sound: bool = False, moving: bool | None = None, dt: float) -> StateEvent:
        """One tick of the competition.

        place: place-cell activities (1-D, may grow between ticks; None = no place cells).
        colour: floor colour id (0 or None = plain floor). sound: the reward sound is heard.
        moving: proprioception (True moving, False still, None = not sensed). dt: seconds
        since the previous tick (> 0).
        """
        dt = check_positive("dt", dt)
        snd = bool(_flag("sound", sound))
        mov = _flag("moving", moving)
        col = _colour(colour)
        pa = self._places(place, dt)
        self.t = self.t + dt if self.winner is not None else 0.0
        self.place_activity = pa
        p = self.params

        if (self._candidate is not None and self._candidate == self.winner
                and self.t - self.since >= p.context_time - 1e-9):
            self._context, self._candidate = self._candidate, None
        onsets: list[str] = []
        if snd and not self._prev_sound:
            onsets.append("sound")
        if col is not None and col != self._prev_colour:
            onsets.append("colour")
        resumed = False
        if self._prev_moving is not None and mov is not None and mov != self._prev_moving:
            onsets.append("moving" if mov else "still")
            resumed = mov
        self._prev_sound, self._prev_colour, self._prev_moving = snd, col, mov
        onsets = [k for k in onsets if k in p.events]

        new: int | None = None
        if self.winner is None:  # first tick: the strongest input wins outright
            proprio = None if mov is None else ("moving" if mov else "still")
            if snd and "sound" in p.events:
                new = self._event_state("sound")
            elif col is not None and "colour" in p.events:
                new = self._register(StateKey("colour", col, None))
            elif pa.size:
                new = int(self._place_ids[int(np.argmax(pa))])
            elif proprio in p.events:
                new = self._event_state(proprio)  # type: ignore[arg-type]
            else:
                raise ValueError("nothing to compete: give place activities, a floor colour, "
                                 "the sound flag or the moving flag")
        elif onsets:
            kind = min(onsets, key=p.priority.index)
            new = (self._register(StateKey("colour", col, None)) if kind == "colour"
                   else self._event_state(kind))
            if new == self.winner:
                new = None
        elif resumed and "moving" not in p.events:  # leaving still@s: back to s at once
            k = self._keys[self.winner]
            if k.kind == "still" and k.context is not None:
                new = k.context
        elif (self.winner is not None and self._keys[self.winner].kind == "colour"
              and col != self._keys[self.winner].index and pa.size):
            # the robot left the coloured floor: the most active place takes over at once
            # (waiting for it to beat a silent colour by the margin could take minutes)
            new = int(self._place_ids[int(np.argmax(pa))])
        elif (col is not None and self.winner is not None
              and self._keys[self.winner].kind not in ("place", "colour")
              and self._event_level(self.winner, snd, col, mov) == 0.0):
            # an event state ended (the sound stopped, a transient faded) on coloured floor:
            # the colour, still perceived, takes the win back at once (not a place by level)
            new = self._register(StateKey("colour", col, None))
        if new is None and self.winner is not None and pa.size:
            wk = self._keys[self.winner]
            units = self._units(self.winner)
            w_act = ((pa.item(units[0]) if len(units) == 1 else max(pa.item(u) for u in units))
                     if wk.kind == "place" else self._event_level(self.winner, snd, col, mov))
            beating = pa > w_act + p.margin
            for u in units:  # (empty unless the winner is a place)
                beating[u] = False
            self._evidence = np.where(beating, self._evidence + dt, 0.0)
            ready = self._evidence >= p.hold_time - 1e-9
            if np.count_nonzero(ready):
                new = int(self._place_ids[int(np.argmax(np.where(ready, pa, -np.inf)))])

        if new is not None and self.contexts is not None:
            nk = self._keys[new]
            if nk.kind == "place" and new not in self._clone_of:
                new = self._context_state(nk.index)  # type: ignore[arg-type]
        previous = None
        changed = new is not None and new != self.winner
        if changed:
            previous, self.winner, self.since = self.winner, new, self.t
            self._evidence[:] = 0.0
            self._onset_t[new] = self.t
            kind = self._keys[new].kind
            if kind == "colour" or (kind == "place" and (p.context_time <= 0
                                                         or self._context is None)):
                self._context, self._candidate = new, None
            elif kind == "place":
                self._candidate = new   # becomes the context once it has held the win
            else:
                self._candidate = None  # an event state took over: the candidate never held
        # the activities by state id, built when :attr:`activity` is read (most ticks nobody
        # does): the place units' and, when it is not a plain place, the winner's level
        if self._keys[self.winner].kind != "place":
            own = self._event_level(self.winner, snd, col, mov)
        elif self.winner in self._clone_of:
            own = max(pa.item(u) for u in self._units(self.winner))
        else:
            own = None
        self._activity, self._activity_of = None, (self._place_ids, pa, self.winner, own)
        novel = not (pa.size and float(np.maximum.reduce(pa)) >= p.recruit_threshold)
        return StateEvent(self.t, int(self.winner), bool(changed), previous, self.since, novel)
