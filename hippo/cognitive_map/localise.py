"""Re-localisation in the map after a kidnap: trust the place state once the map recognises it.

After the robot is lifted and put down elsewhere, learned place cells keep the memory of where
it was (the reservoir's fading memory): measured on the goal arena (seed 0), the winning place
is 40-140 cm from the robot for 20-65 ticks of movement, and standing still does not help (the
cells need the sensor history of moving). A decision taken on that stale state executes a move
learned elsewhere (its heading runs into a wall, and the robot ends up far from any short
route). A fixed settling time is either too short or wastes the many lifts that settle fast.

The map itself says when the place code has settled: a sequence of sensory events that the
map knows. :class:`MapLocaliser` counts consecutive place changes ``A → B`` that are
transitions of the :class:`~hippo.cognitive_map.graph.TransitionGraph`; from the second one
on, the time spent in ``A`` must also match the transition's learned delay ``δ`` within
Weber's tolerance, ``|ln(d / δ)| ≤ ln(1 + delay_tolerance)`` (the first stay began at the lift,
so its duration means nothing). The robot is localised after ``n_known`` such events in a row,
or after ``max_time`` seconds whatever happened (a part of the world the map does not know
will never be recognised; the robot then goes on with what it perceives).

Measured (place preference, goal arena, learned place cells, 12 rewarded trials per seed,
gate with ``n_known=1`` against the fixed 6 s): the gate removes the worst detours, those that
start with a decision on a stale place (longest path 4.3x -> 3.2x the shortest on seed 0,
6.5x -> 3.2x on seed 101), but while it waits the robot keeps exploring, and a slow
recognition costs travel of its own (seed 3: new detours of 6.9x and 26.5x; seed 100: three
more trials over 1.5x). Over seeds 0, 3, 100, 101 the trials over 1.5x went from 12 to 16;
after a patrol kidnap recognition took 14-21 s (seeds 0-4). It is off by default in
:class:`~hippo.brain.BrainParams`. The 26.5x detour of seed 3 was a west-start trial in which
the robot crossed the goal zone while it waited; since a floor colour ends settling at once,
place preference uses the gate (tuning seeds 0-4: 43 of 60 rewarded paths <= 1.5x, against 30
of 58 with the fixed 6 s; held-out seeds 100-109: 90 of 120 against 71 of 119).

A place source that re-anchors itself after the lift
(:class:`~hippo.perception.relocate.SequenceRelocaliser`) says so (:meth:`MapLocaliser.anchor`):
the next place change then localises the robot, known to the map or not (:attr:`by_anchor`).
Patrol kidnap with it, tuning seeds 0-15: localised after 3.6 s median instead of 12.4 s
(figures and what it costs: :mod:`hippo.perception.relocate`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from hippo._checks import check_fields, check_positive, check_real
from hippo.cognitive_map.graph import TransitionGraph

__all__ = ["LocaliserParams", "MapLocaliser"]


@dataclass(frozen=True)
class LocaliserParams:
    """Parameters of :class:`MapLocaliser`.

    n_known: known place changes in a row that localise the robot (default 1).
    delay_tolerance: relative tolerance on a change's timing against the learned delay, from
        the second change on (default 0.5: within ×1.5 either way).
    max_time: seconds after the reset after which the robot counts as localised anyway
        (default 60).
    anchor_settle: seconds after a re-anchoring of the place code (:meth:`MapLocaliser.anchor`)
        from which a place change localises the robot (default 0: the switch the jump makes).
    """

    n_known: int = 1
    delay_tolerance: float = 0.5
    max_time: float = 60.0
    anchor_settle: float = 0.0

    def __post_init__(self) -> None:
        check_fields(self)
        if int(self.n_known) != self.n_known or self.n_known < 1:
            raise ValueError(f"n_known must be an integer >= 1, got {self.n_known!r}")
        check_positive("delay_tolerance", self.delay_tolerance)
        check_positive("max_time", self.max_time)
        check_positive("anchor_settle", self.anchor_settle, allow_zero=True)


class MapLocaliser:
    """Counts the place changes the map knows since a kidnap (see the module docstring).

    ``reset(t)`` at the lift; ``observe(state, t, graph)`` at every change of the place
    winner (after :meth:`anchor`, the next change localises); ``localised`` and
    ``ticks``/``events`` (what it took) are read at any time; ``check(t)`` applies the
    ``max_time`` limit between events.
    """

    def __init__(self, params: LocaliserParams | None = None) -> None:
        self.params = params or LocaliserParams()
        if not isinstance(self.params, LocaliserParams):
            raise TypeError(f"params must be LocaliserParams, got {self.params!r}")
        self.reset(0.0)

    def reset(self, t: float) -> None:
        """The robot was lifted at time ``t`` (s, finite): nothing it perceives is trusted yet."""
        self.t0 = check_real("t", t)
        self.localised = False
        self.events = 0               # place changes seen since the reset
        self.localised_at: float | None = None
        self._prev: int | None = None
        self._since: float = self.t0
        self._run = 0
        self._anchored_at: float | None = None
        self.by_anchor = False   # localised by a re-anchoring: the robot is inside the place

    def anchor(self, t: float) -> None:
        """The place code was re-anchored at time ``t`` (s) (:class:`hippo.perception.relocate.
        SequenceRelocaliser` matched the robot's readings to its exploration): the first place
        change from ``anchor_settle`` s after it on localises the robot, known to the map or
        not. That change is usually the jump's own switch to the place the robot is in, not an
        entry into it: :attr:`by_anchor` says so, and the brain then times nothing from it.
        """
        self._anchored_at = check_real("t", t)

    def check(self, t: float) -> bool:
        """Apply the ``max_time`` limit; returns :attr:`localised`."""
        if not self.localised and float(t) - self.t0 >= self.params.max_time - 1e-9:
            self._done(float(t))
        return self.localised

    def observe(self, state: int, t: float, graph: TransitionGraph) -> bool:
        """The place winner changed to ``state`` at time ``t``; returns :attr:`localised`."""
        t = float(t)
        if not math.isfinite(t) or t < self._since:
            raise ValueError(f"t must be a finite time not before the last event "
                             f"({self._since}), got {t!r}")
        if self.localised:
            return True
        prev, self._prev = self._prev, int(state)
        started, self._since = self._since, t
        self.events += 1
        anchored = getattr(self, "_anchored_at", None)
        if anchored is not None and t - anchored >= self.params.anchor_settle - 1e-9:
            self._done(t)
            self.by_anchor = True
            return True
        if prev is None or prev == state:
            return self.check(t)
        ok = (prev, int(state)) in graph
        if ok and self._run >= 1:
            delay = graph.delay((prev, int(state)))
            if delay is not None and delay > 0 and t - started > 0:
                ok = abs(math.log((t - started) / delay)) <= math.log1p(
                    self.params.delay_tolerance)
        self._run = self._run + 1 if ok else 0
        if self._run >= self.params.n_known:
            self._done(t)
        return self.check(t)

    def _done(self, t: float) -> None:
        self.localised, self.localised_at = True, t

    @property
    def time_to_localise(self) -> float | None:
        """Seconds from the reset to localisation (None while not localised)."""
        return None if self.localised_at is None else self.localised_at - self.t0
