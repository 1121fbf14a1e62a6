"""Odometric anchoring of taught stops: run-ups (the :class:`~hippo.decision.Decider`'s rules).

When the teacher's reward follows a stop, the distance the robot ran (path integration) from
the reward before is that stop's *run-up* (:meth:`hippo.brain.Brain.reward`). Learned place
fields drift by some 30 cm from lap to lap; the run between two checkpoints does not. The rules
here use it (parameters in :class:`~hippo.brain_params.BrainParams`):

- the gate (``runup_tolerance``, ``runup_window``): an approach does not end before the run-up;
- soft recognition (coactive or aliased places) is trusted only where the run-ups say the stop
  is due;
- the odometric stop (``runup_stop``, ``runup_hops``): a taught stop is made, next to its place
  in the map, by its run-up where its place neither wins nor is recognised softly;
- anchoring: only a wait where the anchor said moves it, and a run-up that two stops by place
  in a row show to be too long (a detour in the lesson) is replaced;
- re-anchoring after a lift: a robot carried in the middle of a task (a kidnap, a rescue) has
  no anchor; the first stop it passes without making it, because its drive is held, anchors
  the next run-up where that stop was due (entering its place plus the map's delay of the stop;
  a place that already wins when the robot is put down, or when the map recognises it, counts
  as entered then; one that a re-anchoring of the place code jumped into does not: the robot
  may be anywhere in it, or short of it). Until then soft recognition starts no approach
  (:mod:`hippo.soft_recognition`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from hippo.types import Mode, StateKind

__all__ = ["RunupRules"]


class RunupRules:
    """Run-up rules of a :class:`~hippo.decision.Decider` (mixed into it; reads its brain
    ``self.b``, its mode, current transition and approach start)."""

    b: Any
    mode: Mode
    current: Any
    current_since: float
    _approach_t0: float
    _stopped_at: float | None
    _stop_by_runup: bool
    _runup_fired: bool
    _entry_timed: bool
    _by_companion: bool
    # class defaults: a decider restored from a snapshot saved before these existed
    _reanchor: bool = False                     # carried, drives kept: no anchor yet
    _due_anchor: tuple[str, float] | None = None  # (drive, time) a passed stop was due

    # provided by the Decider and its WaitRules (annotations only: a method stub here would
    # shadow WaitRules.wait_drive wherever this class came first among the Decider's bases)
    wait_drive: Callable[[], int]
    _wanted: Callable[[str], bool]
    _taught_stops: Callable[[str], Any]

    def lifted_with_drives(self) -> None:
        """The robot was carried in the middle of a task with its held drives kept: the next
        held stop it passes re-anchors the run-ups (see the module docstring)."""
        self._reanchor, self._due_anchor = True, None

    def reanchoring(self) -> bool:
        """Carried with the held drives kept, and no anchor since (no wait, no held stop
        passed): the run-ups bound nothing yet."""
        return self._reanchor and self.b.wait_ended_at is None

    def passed_held_stop(self, place: int) -> None:
        """``place`` was just entered: if no anchor holds since a lift and a held drive's taught
        stop is bound to it, that stop is due after the map's delay of ``place -> still``."""
        b = self.b
        if not self.reanchoring():
            return
        for name in b.drives.names:
            if not b.drives.is_inhibited(name):
                continue
            for c, a in self._taught_stops(name):
                delay = b.graph.delay((c, a))
                if c == place and delay is not None:
                    self._due_anchor = (name, b.t + float(delay))
                    return

    def reanchor(self) -> None:
        """Every tick: a passed held stop that is now due anchors the run-ups, as if the robot
        had made it and its wait had just ended (unless a wait anchored them meanwhile)."""
        b = self.b
        due = self._due_anchor
        if due is None or b.t < due[1]:
            return
        self._due_anchor = None
        if self.reanchoring() and self.mode != Mode.WAIT:
            b.wait_ended_at, b.last_wait_drive = b.odometer, due[0]
            self._reanchor = False

    def _in_order(self, name: str) -> tuple[float, float] | None:
        """``(run-up, ran)`` of drive ``name`` if its run-up is taught and counts from the
        current anchor (the last wait was for the drive taught right before it): ``ran`` is
        the distance run since that wait; else None."""
        b = self.b
        runup = b.runups.get(name)
        if (runup is None or b.wait_ended_at is None
                or b.runup_after.get(name) != b.last_wait_drive):
            return None
        return runup, b.odometer - b.wait_ended_at

    def _correct_runup(self, name: str) -> None:
        """A taught run-up is an upper bound: a detour during the lesson makes it too long,
        never too short. Two stops for drive ``name`` in a row that the robot made by place
        (not by run-up), each after the drive taught before it and more than ``runup_window``
        cm short of the taught run-up, and within ``runup_window`` / 2 of each other, replace
        it by their mean."""
        b = self.b
        runup = b.runups.get(name)
        if (runup is None or self._stopped_at is None or self._stop_by_runup
                or b.wait_ended_at is None or b.runup_after.get(name) != b.last_wait_drive):
            return
        seen = self._stopped_at - b.wait_ended_at
        if seen >= runup - b.p.runup_window:
            b.runup_early.pop(name, None)
            return
        before = b.runup_early.get(name)
        if before is not None and abs(before - seen) <= b.p.runup_window / 2:
            b.runups[name] = (before + seen) / 2
            b.runup_early.pop(name)
        else:
            b.runup_early[name] = seen

    def _anchors(self, name: str) -> bool:
        """Does the robot's own wait for drive ``name``, just over, anchor the next run-up? Yes
        if no anchor holds, if ``name`` has no taught run-up, if the wait came where the anchor
        said (after the drive taught before it, within ``runup_window`` of its run-up), or if
        the anchor is stale (the robot ran the longest run-up and ``runup_window`` more since
        it). A stop that the anchor did not predict (a stop made again just after a wait, or
        for a drive out of the taught order) would shift every run-up after it."""
        b = self.b
        if b.wait_ended_at is None or b.last_wait_drive is None or name not in b.runups:
            return True
        anchored = self._in_order(name)
        if anchored is not None and abs(anchored[1] - anchored[0]) <= b.p.runup_window:
            return True
        return self._stale()

    def _stale(self) -> bool:
        """Is the anchor stale (or missing): has the robot run the longest taught run-up and
        ``runup_window`` more since its last wait? Past that, stops were missed, or the robot
        turned back, and the run since the wait no longer says where it is on the loop
        (tuning seed 5, 18 h: 434 cm after a wait, back and forth past a missed stop)."""
        b = self.b
        if b.wait_ended_at is None or not b.runups:
            return True
        return b.odometer - b.wait_ended_at > max(b.runups.values()) + b.p.runup_window

    def _runup_due(self) -> bool:
        """Odometric recognition of a taught stop (``BrainParams.runup_stop``): the robot's last
        wait was for the drive taught right before drive ``D``, ``D`` is active, and the robot
        has run ``D``'s run-up and ``runup_stop`` cm more without stopping for it (its place
        neither won nor was recognised softly, or an approach by place ran on): it stops for
        ``D`` now, whichever place wins. With the gate of :meth:`_before_runup` a stop then
        comes within [run-up - ``runup_tolerance``, run-up + ``runup_stop``] of the last wait;
        farther off (beyond ``runup_window``) neither rule applies."""
        b = self.b
        p = b.p
        if p.runup_stop < 0:
            return False
        for name in b.drives.names:
            if not self._runup_passed(name) or not self._wanted(name):
                continue
            for c, a in self._taught_stops(name):
                if self.mode != Mode.MOVE or not self._near_in_map(c, p.runup_hops):
                    return False
                # an approach that is over at once (:meth:`_past_runup`), timed as if C had
                # been entered the learned time-to-stop ago (the map's delay of C -> still@C
                # stays what it was)
                delay = b.graph.delay((c, a))
                self.current, self.current_since = (c, a), b.t
                self.mode = Mode.APPROACH
                self._entry_timed = False
                self._approach_t0 = b.t - float(delay or 0.0)
                self._runup_fired, self._by_companion = True, False
                return True
        return False

    def _near_in_map(self, c: int, hops: int) -> bool:
        """Is place ``c`` at most ``hops`` transitions from the place the robot is in (either
        way; a stop and the move on from it count as the place itself)?"""
        b = self.b
        here = b._ctx_now
        if here is None:
            return False
        layer = b.layer

        def ctx(s: int) -> int:
            k = layer.key(s)
            stop = k.kind in (StateKind.STILL, StateKind.MOVING)
            return k.context if stop and k.context is not None else s

        g = b.graph
        adj: dict[int, set[int]] = g.cached("context-adjacency",
                                            lambda: _context_adjacency(g, ctx))
        seen, front = {ctx(here)}, {ctx(here)}
        for _ in range(hops):
            front = {n for f in front for n in adj.get(f, ())} - seen
            seen |= front
        return c in seen

    def _past_runup(self) -> bool:
        """Has the robot, approaching a stop with a taught run-up from its last wait, run
        that run-up and ``runup_stop`` cm more (see :meth:`_runup_due`)?"""
        k = self.wait_drive()
        return self.b.p.runup_stop >= 0 and k >= 0 and self._runup_passed(self.b.drives.names[k])

    def _runup_passed(self, name: str) -> bool:
        """Has the robot run drive ``name``'s run-up and ``runup_stop`` cm more since the
        anchor it counts from (and not beyond ``runup_window``)?"""
        anchored = self._in_order(name)
        if anchored is None:
            return False
        runup, ran = anchored
        return runup + self.b.p.runup_stop <= ran < runup + self.b.p.runup_window

    def _not_due(self, name: str) -> bool:
        """Is the robot, by its run since its last wait, clearly not where drive ``name``'s
        stop is due? The stop is due the taught run-ups on from that wait: walking the taught
        order back from ``name`` (each drive's run-up counts from the drive taught before it)
        to the drive of the last wait, their sum ``s`` (one run-up in order, two after a stop
        missed, a lap right after a wait for ``name`` itself); and, when that walk closes a
        lap ``L`` (every drive of the loop has a run-up), again at ``s + k L`` (the stop
        missed, a lap later). "Clearly": farther than ``runup_window`` from every such point
        (before ``s``, or between two of them). No anchor, or the last wait's drive not in
        ``name``'s taught chain: no bound (and no lap: no bound past ``s``). Soft recognition
        asks this: a place coactive or aliased 10-150 cm after a wait stood in for a stop
        farther on, or for the same one again (6 misplaced stops in 6 h of deployment, tuning
        seed 1), and one coactive at checkpoint 1 for checkpoint 3, missed 100 cm before, made
        that stop there, and the robot set off the wrong way round from it (tuning seed 1,
        18 h)."""
        walk = self._walked(name)
        if walk is None:
            return False
        due, lap, ran, window = walk
        if ran < due - window:
            return True
        if not lap:   # no closed lap: no bound past the first point
            return False
        k = round((ran - due) / lap)
        return abs(ran - (due + k * lap)) > window

    def _untimely(self, stop: Any) -> bool:
        """Is the stop ``(C, still@C)`` that a place win would start an approach to taught only
        for wanted drives whose stop the run-ups say is clearly not due here
        (:meth:`_not_due`), while another wanted drive's stop is due a little way ahead
        (:meth:`_due_ahead`), and the anchor is not stale (:meth:`_stale`)? Then the win is
        an alias of a place farther on and the robot drives on (``BrainParams.due_first``):
        held-out seed 101, 18 h, the south corridor's stop for checkpoint 1 won in the north
        corridor 130 cm after checkpoint 2's wait, with checkpoint 3 due 20 cm on; the robot
        approached for checkpoint 1, drove past checkpoint 3 and stopped 160 cm early, and
        every run-up after counted from there (21 failures in half an hour)."""
        b = self.b
        if not b.p.due_first or self._stale():
            return False
        mine = [n for n in b.drives.names if self._wanted(n) and stop in self._taught_stops(n)]
        if not mine or not all(self._not_due(n) for n in mine):
            return False
        return any(self._wanted(n) and self._due_ahead(n) for n in b.drives.names
                   if n not in mine)

    def _due_ahead(self, name: str) -> bool:
        """Is drive ``name``'s stop due at most ``runup_window`` cm ahead of the robot (the next
        point of :meth:`_due_walk` at or past its run since the last wait)? A stop due behind
        it was missed; one ahead is still to come."""
        walk = self._walked(name)
        if walk is None:
            return False
        due, lap, ran, window = walk
        k = max(0, math.ceil((ran - due) / lap)) if lap else 0
        return 0.0 <= due + k * lap - ran <= window

    def _due(self, name: str) -> bool:
        """Do the run-ups say, positively, that drive ``name``'s stop is due here: an anchor
        holds, the last wait's drive is in ``name``'s taught chain, and the robot's run since
        that wait is within ``runup_window`` of a point where the stop is due (the walk's
        ``s``, or ``s + k L`` when it closed a lap; see :meth:`_not_due`, which without a
        closed lap sets no bound past ``s``)? Companion places are learned and used only
        then (:mod:`hippo.soft_recognition`)."""
        walk = self._walked(name)
        if walk is None:
            return False
        due, lap, ran, window = walk
        k = max(0, round((ran - due) / lap)) if lap else 0
        return abs(ran - (due + k * lap)) <= window

    def _walked(self, name: str) -> tuple[float, float, float, float] | None:
        """``(s, L, ran, window)``: :meth:`_due_walk`'s first point ``s``, its lap ``L`` (0
        unless it closed one longer than 2 ``runup_window``: then the stop is due again every
        ``L``), the run since the last wait and ``runup_window``; None: no bound."""
        walk = self._due_walk(name)
        if walk is None:
            return None
        due, lap, closed = walk
        b = self.b
        window = b.p.runup_window
        return due, (lap if closed and lap > 2 * window else 0.0), \
            b.odometer - b.wait_ended_at, window

    def _due_walk(self, name: str) -> tuple[float, float, bool] | None:
        """The walk of :meth:`_not_due`: ``(s, L, closed)``, the distance from the last wait at
        which drive ``name``'s stop is first due, the run-ups summed to where the walk
        stopped, and whether it closed a lap; None: no bound (no anchor, no window, or the
        last wait's drive not in ``name``'s taught chain)."""
        b = self.b
        if b.p.runup_window <= 0 or b.wait_ended_at is None or b.last_wait_drive is None:
            return None
        due, d, lap, closed = None, name, 0.0, False
        for _ in range(len(b.runups)):
            if d not in b.runups:
                break
            lap += b.runups[d]
            d = b.runup_after.get(d)
            if d == b.last_wait_drive and due is None:
                due = lap
            if d == name:
                closed = True
                break
        return None if due is None else (due, lap, closed)

    def _before_runup(self) -> bool:
        """Has the robot, approaching a stop with a taught run-up, run clearly less than it
        since its last wait (see ``BrainParams.runup_tolerance``)?"""
        b = self.b
        k = self.wait_drive()
        if b.p.runup_window <= 0 or k < 0 or b.wait_ended_at is None:
            return False
        runup = b.runups.get(b.drives.names[k])
        if runup is None:
            return False
        ran = b.odometer - b.wait_ended_at
        return runup - b.p.runup_window < ran < runup - b.p.runup_tolerance


def _context_adjacency(g: Any, ctx: Any) -> dict[int, set[int]]:
    """Undirected adjacency of the map's context states (a stop ``still@C`` and ``moving@C``
    stand for ``C``)."""
    adj: dict[int, set[int]] = {}
    for a, b in g.transitions:
        u, v = ctx(a), ctx(b)
        if u != v:
            adj.setdefault(u, set()).add(v)
            adj.setdefault(v, set()).add(u)
    return adj
