"""Soft recognition of a wanted stop's place (the :class:`~hippo.decision.Decider`'s rules).

Learned place cells often split one stretch of track between two prototypes that alternate
from lap to lap; the place ``C`` a stop ``C -> still@C`` was taught in then does not win on
every pass. While moving with an active drive whose stop is bound to ``C``, the robot approaches
that stop as if it had entered ``C`` when

- ``C`` is *coactive*: its activity is close to the winner's (``BrainParams.coactive``), or
- the place just entered is an *alias* of ``C``: it came in ``C``'s timed sequence context
  (``BrainParams.aliases``, ``alias_tolerance``; :meth:`SoftRecognition.alias_of`),

and the map would choose that stop on entering ``C`` (its drive beats those of the moves out
of ``C``), unless the robot's run since its last wait says the stop is not due here
(:meth:`~hippo.runups.RunupRules._not_due`). Parameters in
:class:`~hippo.brain_params.BrainParams`.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

from hippo.types import Mode, StateKind

__all__ = ["SoftRecognition"]


class SoftRecognition:
    """Soft-recognition rules of a :class:`~hippo.decision.Decider` (mixed into it; reads its
    brain ``self.b`` and sets its mode, current transition and approach start)."""

    b: Any
    mode: Mode
    _runup_due: Any  # the run-up rules' (:class:`~hippo.runups.RunupRules`)
    _not_due: Any    # the same
    current: Any
    current_since: float
    _approach_t0: float
    _entry_timed: bool

    def _wanted(self, name: str) -> bool:  # provided by the Decider
        raise NotImplementedError

    def _activity(self, tr: Any) -> float:  # provided by the Decider
        raise NotImplementedError

    def recognise_stop(self) -> None:
        """Approach a wanted stop whose place ``C`` is coactive, or whose alias was just
        entered (see the module docstring); not while the odometric stop of the run-up rules
        (``_runup_due``) is due. An approach by an alias is timed from entering it."""
        b = self.b
        p = b.p
        if self.mode != Mode.MOVE or b.state is None or self._runup_due() or p.coactive <= 0:
            return
        acts = b.layer.place_activity
        if acts.size == 0:
            return
        top = float(acts.max())
        here = b.state if b.kind(b.state) == StateKind.PLACE else None
        for name in b.drives.names:
            if not self._wanted(name):
                continue
            for c, a in self._taught_stops(name):
                kc = b.layer.key(c)
                if (c == b.state or kc.kind != StateKind.PLACE
                        or kc.index >= acts.size):  # type: ignore[operator]
                    continue
                alias = p.aliases and here is not None and self.alias_of(here, c)
                if float(acts[kc.index]) < p.coactive * top and not alias:  # type: ignore[index]
                    continue
                # only where the run-ups since the last wait say the stop is due
                if self._not_due(name):
                    break
                # only if the map would choose that stop on entering C (drives compete)
                if max(b.graph.outgoing(c), key=self._activity) != (c, a):
                    continue
                self.current, self.current_since = (c, a), b.t
                # timed from the recognition, or from entering the alias (as if it were C)
                self.mode, self._approach_t0 = Mode.APPROACH, b.entered_at if alias else b.t
                self._entry_timed = bool(alias)
                return

    def _taught_stops(self, name: str) -> Iterator[tuple[int, int]]:
        """The stops ``C -> still@C`` in the map that drive ``name`` is linked to (through
        its wait ``still@C -> ...``), as ``(C, still@C)``."""
        b = self.b
        for a, _ in b.drives.links(name):
            ka = b.layer.key(a)
            c = ka.context
            if (ka.kind == StateKind.STILL and c is not None and b.graph.has_state(c)
                    and (c, a) in b.graph):
                yield c, a

    def alias_of(self, place: int, c: int) -> bool:
        """Does ``place``, just entered, stand in for place ``c`` this time: did the robot come
        from a place ``p`` after which the map has met ``c`` at least twice (``p -> c``), enter
        ``place`` instead, and enter it when ``c`` was due (the time in ``p`` within
        ``alias_tolerance`` of the map's delay of ``p -> c``, Weber's law)? Learned place cells
        code one stretch of track by one prototype on some laps and by another on others; the
        sequence context and the time since it tell such a stand-in from a place elsewhere
        that merely looks alike (the idea of clone-structured cognitive graphs, George et al.
        2021, turned round: two observations in one timed sequence context are one place)."""
        b = self.b
        p = b.came_from
        if place == c or p is None or p in (place, c) or b.state != place:
            return False
        g = b.graph
        if not ((p, c) in g and (p, place) in g and g.count((p, c)) >= 2):
            return False
        delay, since = g.delay((p, c)), b.entered_since(p)
        d = b.entered_at - since if since is not None else 0.0
        return (bool(delay) and d > 0
                and abs(math.log(d / float(delay))) <= math.log1p(b.p.alias_tolerance))
