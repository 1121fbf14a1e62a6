"""Soft recognition of a wanted stop's place (the :class:`~hippo.decision.Decider`'s rules).

Learned place cells often split one stretch of track between two prototypes that alternate
from lap to lap; the place ``C`` a stop ``C -> still@C`` was taught in then does not win on
every pass. While moving with an active drive whose stop is bound to ``C``, the robot approaches
that stop as if it had entered ``C`` when

- ``C`` is *coactive*: its activity is close to the winner's (``BrainParams.coactive``), or
- the place just entered is an *alias* of ``C``: it came in ``C``'s timed sequence context
  (``BrainParams.aliases``, ``alias_tolerance``; :meth:`SoftRecognition.alias_of`),

- the place just entered is a *companion* of the stop: the robot has made that stop, where
  its run-ups said it was due, ``companions`` times while this place won, and no other place
  (``C`` included) won at more of those stops (``BrainParams.companions``;
  :meth:`SoftRecognition.note_stop`). It is timed from entering the companion by the mean
  time from entering it to those stops, and used only where the run-ups say the stop is due
  (:meth:`~hippo.runups.RunupRules._due`),

and the map would choose that stop on entering ``C`` (its drive beats those of the moves out
of ``C``), unless the robot's run since its last wait says the stop is not due here
(:meth:`~hippo.runups.RunupRules._not_due`), and not after a lift that kept the held
drives until the run-ups are re-anchored (:mod:`hippo.runups`). Parameters in
:class:`~hippo.brain_params.BrainParams`.

A companion binds the taught stop to a second place, the one that wins where the stop is
made, as a clone-structured graph (George et al. 2021) merges two observations that stand for
one hidden state: the taught place ``C`` may never win in the robot's own laps and be only
weakly coactive on some (checkpoint 1 missed 15 times in 18 h, tuning seed 3), while the
place that wins where it stops does win there.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from typing import Any

from hippo.types import Mode, StateKind

__all__ = ["SoftRecognition"]

#: a companion's time to its stop is the mean over its last stops, about this many
_MEAN_OVER = 20


class SoftRecognition:
    """Soft-recognition rules of a :class:`~hippo.decision.Decider` (mixed into it; reads its
    brain ``self.b`` and sets its mode, current transition and approach start)."""

    b: Any
    mode: Mode
    _runup_due: Any  # the run-up rules' (:class:`~hippo.runups.RunupRules`)
    _not_due: Any    # the same
    _due: Any        # the same
    reanchoring: Any  # the same
    current: Any
    current_since: float
    _approach_t0: float
    _entry_timed: bool
    _by_companion: bool = False  # the current approach is by a companion (class default:
    # a decider restored from a snapshot saved before companions existed)
    #: (C, still@C) -> {place W: (due stops made while W won, mean time from entering W)}
    _companions: dict[tuple[int, int], dict[int, tuple[int, float]]] | None = None

    # provided by the Decider and its WaitRules (annotations only, no stubs that could
    # shadow them)
    _wanted: Callable[[str], bool]
    _activity: Callable[[Any], float]
    wait_drive: Callable[[], int]

    def recognise_stop(self) -> None:
        """Approach a wanted stop whose place ``C`` is coactive, or whose alias was just
        entered (see the module docstring); not while the odometric stop of the run-up rules
        (``_runup_due``) is due, nor after a lift that kept the held drives (a kidnap, a
        rescue) until a held stop the robot passes re-anchors the run-ups: with no anchor a
        coactive place sets no bound, and one 15 cm before the checkpoint the robot was put
        before made another checkpoint's stop there (tuning seeds 48 and 68); nor inside a
        place the place code was re-anchored into (``Brain.entry_unseen``). An approach by
        an alias is timed from entering it."""
        b = self.b
        p = b.p
        # while moving from place to place: not standing (a teacher's block holds a robot that
        # means to move; a stop approached there waited for a stillness it already had, for
        # ever: a whole patrol, held-out seed 107) nor just starting off after a wait
        if (self.mode != Mode.MOVE or b.state is None or b.kind(b.state) != StateKind.PLACE
                or self._runup_due() or p.coactive <= 0
                or self.reanchoring() or b.entry_unseen):
            return
        acts = b.layer.place_activity
        if acts.size == 0:
            return
        top, here = float(acts.max()), b.state
        for name in b.drives.names:
            if not self._wanted(name):
                continue
            for c, a in self._taught_stops(name):
                kc = b.layer.key(c)
                if (c == b.state or kc.kind != StateKind.PLACE
                        or kc.index >= acts.size):  # type: ignore[operator]
                    continue
                alias = p.aliases and self.alias_of(here, c)
                soft = float(acts[kc.index]) >= p.coactive * top or alias  # type: ignore[index]
                t0 = None if soft else self._companion_start(here, (c, a), name)
                if not soft and t0 is None:
                    continue
                # only where the run-ups since the last wait say the stop is due
                if self._not_due(name):
                    break
                # only if the map would choose that stop on entering C (drives compete)
                if max(b.graph.outgoing(c), key=self._activity) != (c, a):
                    continue
                self.current, self.current_since = (c, a), b.t
                # timed from the recognition, or from entering the alias (as if it were C),
                # or by the companion's time to the stop from entering it
                self.mode = Mode.APPROACH
                self._approach_t0 = t0 if t0 is not None else b.entered_at if alias else b.t
                self._entry_timed, self._by_companion = bool(alias), t0 is not None
                return

    def _companion_start(self, here: int, stop: tuple[int, int], name: str) -> float | None:
        """If ``here``, the place the robot is in, is a companion of ``stop`` (``(C,
        still@C)``, for drive ``name``: it won at ``companions`` stops or more, and at no
        fewer than any other place, ``C`` included) whose time to the stop is not yet over,
        and the run-ups say the stop is due: the approach start that times the stop as the
        companion does (the map's delay of ``stop`` before the companion's stop time); else
        None."""
        b = self.b
        n = b.p.companions
        if n <= 0 or not self._companions:
            return None
        table = self._companions.get(stop, {})
        seen = table.get(here)
        delay = b.graph.delay(stop)
        if (seen is None or seen[0] < max(n, *(v[0] for v in table.values())) or delay is None
                or b.t - b.entered_at > seen[1] or not self._due(name)):
            return None
        return b.entered_at + seen[1] - float(delay)

    def note_stop(self) -> None:
        """The robot stops now for its current stop ``(C, still@C)``: if the run-ups say the
        stop is due here and the approach was not by a companion, count the stop for the
        place ``W`` that wins (``C`` itself included: a companion must have won at as many
        stops as ``C``) and average the time from entering ``W`` to it (over about the last
        ``_MEAN_OVER`` stops). Bounded: one entry per taught stop and place."""
        b = self.b
        w, stop = b.state, self.current
        if (b.p.companions <= 0 or stop is None or w is None or self._by_companion
                or b.kind(w) != StateKind.PLACE or b.kind(stop[1]) != StateKind.STILL):
            return
        k = self.wait_drive()
        if k < 0 or not self._due(b.drives.names[k]):
            return
        if self._companions is None:
            self._companions = {}
        table = self._companions.setdefault(stop, {})
        count, mean = table.get(w, (0, 0.0))
        count += 1
        table[w] = (count, mean + (b.t - b.entered_at - mean) / min(count, _MEAN_OVER))

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
