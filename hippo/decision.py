"""The brain's decisions: which transition to execute, and when a stop or a wait is over.

A :class:`Decider` belongs to one :class:`~hippo.brain.Brain` and reads its parts (state layer,
map, drives, planner, transition-cell readouts, heading estimate). It holds what the robot is
doing — the motor :class:`~hippo.types.Mode`, the transition being executed, the heading of
the last move — and changes it at sensory events and every tick:

- :meth:`Decider.choose` — at the current state, the outgoing transition with the highest
  drive activity (the planner), with motor continuity: a move that would turn a moving robot
  around is discounted (``turn_limit``, ``turn_discount``). With no active drive the robot
  explores along known moves (never by stopping); with an active drive and no reachable goal
  it explores with the wall follower.
- :meth:`Decider.check_wait` (:mod:`hippo.waits`) — an approach ends when the learned
  time-to-stop is over; a wait on the robot's own next event (``moving``) ends when the
  transition cells' ``delay_over`` rises (the learned delay), a wait on an external event (the
  sound) when the non-occurrence neuron fires. Either way the drives linked to the wait are
  inhibited until the robot reaches a place from which that stop is not one transition away.
- :meth:`Decider.recognise_stop` — soft recognition of a wanted stop's place (``coactive``,
  ``aliases``: :mod:`hippo.soft_recognition`).
- habituation — entering one place ``cycle_visits`` times within ``cycle_window`` s while a
  drive is active makes the robot explore for ``cycle_explore`` s.

Stopping where it was taught. The transition ``C -> still@C`` carries a delay (time from
entering ``C`` to stopping); the robot keeps its previous motion (mode ``APPROACH``) until that
delay is over and then stops, so a checkpoint wait starts where the teacher blocked the robot;
a stall or a turn on the spot on the way (stillness it did not choose) does not call it off.
"""

from __future__ import annotations

import math
from collections import deque
from typing import Any

import numpy as np

from hippo.runups import RunupRules
from hippo.soft_recognition import SoftRecognition
from hippo.types import Mode, StateKind, Transition, wrap_angle
from hippo.waits import WaitRules

__all__ = ["Decider"]


class Decider(WaitRules, SoftRecognition, RunupRules):
    """The decision rules of one brain (see the module docstring).

    ``brain``: the :class:`~hippo.brain.Brain` it decides for (this module does not import
    the brain: the brain builds its decider).
    """

    # class defaults: a decider restored from a snapshot saved before these existed
    _wait_since: float = 0.0
    _omitted_early: bool = False

    def __init__(self, brain: Any) -> None:
        self.b = brain
        self._visits: deque[tuple[float, int]] = deque()
        self._explore_until = -math.inf
        self._companions: dict[tuple[int, int], dict[int, tuple[int, float]]] = {}
        self.reset_episode()

    def reset_episode(self) -> None:
        t = self.b.t
        self.mode = Mode.EXPLORE
        self.current: Transition | None = None
        self.current_since = t
        self.heading: float | None = None         # heading of the last move (kept when lost)
        self._approach_t0 = t
        self._waiting_on: Transition | None = None
        self._wait_since = t                      # when the current wait began
        self._omitted_early = False               # its stop was 'omitted' before it could be
        self._inhibited: dict[str, int] = {}      # drive -> context state it was inhibited in
        self._inhibited_at: dict[str, tuple[float, float]] = {}  # ... and where (path int.)
        self._stopped_at: float | None = None   # odometer where the current stop began
        self._runup_fired = False               # the current approach is by run-up alone
        self._by_companion = False              # ... by a companion place (soft recognition)
        self._stop_by_runup = False             # ... and so is the current stop
        # the approach is timed from entering the stop's place (not from a soft recognition
        # or a run-up) and the run-up gate did not hold it: the stop's delay is a measurement
        self._entry_timed = False
        self.stop_untimed = False               # the last stop was not: learn no delay from it

    def lifted(self) -> None:
        self._visits.clear()
        self._explore_until = -math.inf
        # no re-anchoring is pending unless this lift keeps held drives (restore_inhibitions)
        self._reanchor, self._due_anchor = False, None

    def inhibitions(self) -> dict[str, int]:
        """Drive -> the context state it was inhibited in, for the drives a finished wait
        holds."""
        return dict(self._inhibited)

    def restore_inhibitions(self, kept: dict[str, int], where: tuple[float, float]) -> None:
        """Hold ``kept`` (from :meth:`inhibitions`) again, each to be released as after a wait
        that ended at ``where`` (path integration)."""
        self._inhibited.update(kept)
        for d in kept:
            self._inhibited_at[d] = (float(where[0]), float(where[1]))
        if kept:
            self.lifted_with_drives()

    def release_all(self) -> None:
        """Release every drive a finished wait inhibited."""
        for d in list(self._inhibited):
            self.b.drives.release(d)

    def _drive_active(self) -> bool:
        b = self.b
        return any(b.drives.level(n) >= b.p.planner.exploration_threshold
                   for n in b.drives.names)

    # -- at a sensory event -------------------------------------------------------------------
    def intended_source(self, new: int, kind: StateKind, prev: int | None, entered_at: float
                        ) -> tuple[int | None, float]:
        """The robot stopped for a stop it recognised softly while another place won: what it
        did is that transition, timed from the recognition."""
        w = self._waiting_on
        intended = (kind == StateKind.STILL and w is not None and w[1] == new
                    and self.mode == Mode.WAIT)
        if intended and prev is not None and w[0] != prev:  # type: ignore[index]
            return w[0], self._approach_t0  # type: ignore[index]
        return prev, entered_at

    def release_away_from(self, place: int) -> None:
        """Drives inhibited by a finished wait are released once the robot reaches a place from
        which that stop is not one transition away (it has left the checkpoint's region) and
        has moved ``release_distance`` cm (path integration) from where the wait ended."""
        b = self.b
        x, y = b.pi.pose[:2]
        for d, c in list(self._inhibited.items()):
            x0, y0 = self._inhibited_at.get(d, (x, y))
            if (c != place and not self.stops_at(place, c)
                    and math.hypot(x - x0, y - y0) >= b.p.release_distance):
                b.drives.release(d)
                del self._inhibited[d]
                self._inhibited_at.pop(d, None)

    def on_event(self, new: int, kind: StateKind, prev: int | None) -> None:
        """Decide after the brain entered ``new`` (coming from ``prev``)."""
        b = self.b
        if (kind in (StateKind.STILL, StateKind.MOVING) and self.mode == Mode.APPROACH
                and self.current is not None and new != self.current[1]):
            # a stall or a turn on the spot on the way to a stop (the robot did not choose to
            # stop: it approaches) does not call the stop off: it did, and the stop a run-up
            # gate held past its place at a corner never came (goal-arena tuning seed 23:
            # 4 of 7 passes with a stop; 21 of 21 with this rule)
            return
        if (kind == StateKind.PLACE and self.mode == Mode.APPROACH and self.current is not None
                and new != self.current[0]
                and not self.stops_at(new, b.layer.key(self.current[1]).context)):
            # on the way to a stop recognised softly (``coactive``): a place on the way that
            # does not know the stop does not cancel it
            return
        if (kind == StateKind.PLACE and self.mode == Mode.WAIT and self._waiting_on is not None
                and b.kind(self._waiting_on[1]) == StateKind.STILL
                and b.t - self._wait_since <= self.still_grace):
            # braking for a stop it chose: a place that wins before the robot's stillness is
            # perceived does not call the stop off (it did: the robot drove on through the
            # checkpoint, 3 of 6 failures in 2.2 h of deployment, tuning seed 0)
            return
        if kind == StateKind.MOVING:
            # resuming: keep the move chosen when the wait ended, else choose from the context
            if self.mode != Mode.MOVE or self.current is None:
                self.choose(b.layer.key(new).context, exclude_wait=True)
            return
        self._waiting_on = None
        if kind == StateKind.PLACE:
            self.passed_held_stop(new)
        came_from = b.kind(prev) if prev is not None else None
        if (kind == StateKind.PLACE and came_from is not None and came_from.is_context
                and self._cycling(new)):
            self._explore_until = b.t + b.p.cycle_explore
        if b.t < self._explore_until:
            self.mode, self.current = Mode.EXPLORE, None
            return
        self.choose()

    def stops_at(self, state: int, ctx: int | None) -> bool:
        """Is a stop in context ``ctx`` one transition away from ``state``?"""
        g, layer = self.b.graph, self.b.layer
        if ctx is None or not g.has_state(state):
            return False
        for _, s in g.outgoing(state):
            k = layer.key(s)
            if k.kind == StateKind.STILL and k.context == ctx:
                return True
        return False

    def _cycling(self, place: int) -> bool:
        """Habituation: has ``place`` been entered too often lately while a drive is active?"""
        b, v = self.b, self._visits
        v.append((b.t, place))
        while v and v[0][0] < b.t - b.p.cycle_window:
            v.popleft()
        return self._drive_active() and sum(1 for _, s in v if s == place) >= b.p.cycle_visits

    # -- choosing -----------------------------------------------------------------------------
    def choose(self, state: int | None = None, *, exclude_wait: bool = False) -> None:
        """Pick the transition to execute from ``state`` (default: the brain's state)."""
        b = self.b
        g = b.graph
        s = b.state if state is None else state
        keep_heading = self.mode in (Mode.MOVE, Mode.APPROACH) and self.heading is not None
        lost = Mode.MOVE if keep_heading else Mode.EXPLORE
        self.current = None
        self._runup_fired = self._by_companion = False
        if s is None or not g.has_state(s):
            self.mode = lost
            self.current_since = b.t
            return
        out = g.outgoing(s)
        exclude_wait = exclude_wait or b.entry_unseen   # no stop timed from an unseen entry
        if exclude_wait:
            out = [t for t in out if not g.action(t).is_wait]
        if not out:
            self.mode = lost
            return
        choice = b.planner.decide(g, b.drives, s, b.rng)
        tr = choice.transition
        if choice.explored:
            if self._drive_active():
                # a drive is active but no goal is reachable from here: leave this part of
                # the map by exploring (a random known move could circle in it forever)
                self.mode = Mode.EXPLORE
                return
            # no drive: explore along known transitions, by moving, never by stopping
            moves = [t for t in out if not g.action(t).is_wait]
            if not moves:
                self.mode = lost
                return
            tr = moves[int(b.rng.integers(len(moves)))]
        else:
            # motor continuity: a place can stand for two distant stretches of track (aliasing);
            # a move that would turn the robot around is discounted, so the robot keeps to the
            # stretch it is on rather than to the alias of it (also when it moves on after a
            # wait: it still faces the way it came)
            vals = np.array([self._activity(t) for t in out])
            if keep_heading or exclude_wait:
                for i, t in enumerate(out):
                    if self._turns(t):
                        vals[i] *= b.p.turn_discount
            if b.p.own_stops_only:
                # a stop is made for a drive that wants it: a stop whose wait serves no free,
                # active drive is no way through to another drive's goal (the map may hold a
                # short cut out of it that an aliased place drew)
                for i, t in enumerate(out):
                    if b.kind(t[1]) == StateKind.STILL and not self._stop_wanted(t[1]):
                        vals[i] = 0.0
                if vals.max() <= 0:
                    moves = [t for t in out if b.kind(t[1]) != StateKind.STILL]
                    if not moves:
                        self.mode = lost
                        return
                    pick = moves[int(b.rng.integers(len(moves)))]
                    vals = np.array([float(t == pick) for t in out])
            if tr not in out or vals[out.index(tr)] < vals.max():
                tr = out[int(np.argmax(vals))] if vals.max() > 0 else \
                    out[int(b.rng.integers(len(out)))]
            if b.p.hold_heading and keep_heading and not exclude_wait and self._turns(tr):
                self.mode, self.current_since = Mode.MOVE, b.t   # hold the heading
                return
        self.current, self.current_since = tr, b.t
        action = g.action(tr)
        if not action.is_wait:
            self.mode, h = Mode.MOVE, self._direction(tr)
            self.heading = float(b.pi.heading if h is None else h)
        elif b.kind(tr[1]) == StateKind.STILL and b.p.approach:
            if self._untimely(tr):   # an alias of a stop farther on: drive on, as it goes
                if not keep_heading:
                    return self.choose(state, exclude_wait=True)
                self.current, self.mode = None, Mode.MOVE
                return
            self.mode = Mode.APPROACH   # keep going until the learned time-to-stop is over
            self._entry_timed = True
            self._approach_t0 = b.entered_at
        else:
            self._wait_on(tr)

    def _direction(self, tr: Transition) -> float | None:
        """Heading of move ``tr``, None if it has none (a robot keeps its own then)."""
        return self.b.graph.direction(tr, self.b.p.min_heading_r)

    def _turns(self, tr: Transition) -> bool:
        """Would move ``tr`` turn the robot round (``turn_limit``)?"""
        h = self._direction(tr)
        return h is not None and abs(wrap_angle(h - self.b.pi.heading)) > self.b.p.turn_limit

    def _stop_wanted(self, still: int) -> bool:
        """Is a drive linked to a wait out of stop ``still`` free and active?"""
        b = self.b
        nxt = b.graph.outgoing(still) if b.graph.has_state(still) else []
        return any(self._wanted(n) and any(t in b.drives.links(n) for t in nxt)
                   for n in b.drives.names)

    def _activity(self, tr: Transition) -> float:
        act = self.b.planner.activity(self.b.graph, self.b.drives)
        return float(act.values[act.index.pos[tr]])

    # -- every tick ---------------------------------------------------------------------------
    def _wanted(self, name: str) -> bool:
        """Is drive ``name`` free (not held by a finished wait) and active?"""
        b = self.b
        return (not b.drives.is_inhibited(name)
                and b.drives.level(name) >= b.p.planner.exploration_threshold)
