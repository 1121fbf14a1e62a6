"""When a stop or a wait is over, and which drives it served (a part of the brain's
:class:`~hippo.decision.Decider`).

- :meth:`WaitRules.check_wait` — an approach ends when the learned time-to-stop is over (or
  before the robot would usually have left the place, or past its run-up), unless the run-up
  gate holds it; a wait on the robot's own next event (``moving``) ends when the transition
  cells' ``delay_over`` rises (the learned delay), a wait on an external event (the sound)
  when the non-occurrence neuron fires. Either way the drives the wait served are inhibited
  until the robot reaches a place from which that stop is not one transition away, and the
  robot chooses its next move.
- :meth:`WaitRules.wait_drive`, :meth:`WaitRules._served_by` — the drive a stop serves: of the
  drives linked to its wait, the one whose run-up says the stop was due
  (:meth:`WaitRules._by_runup`).
- :meth:`WaitRules.untimed_stop` — a stop its learned time-to-stop did not time, which neither
  the map nor the transition cells learn from.

Mixed into :class:`~hippo.decision.Decider` (as :class:`~hippo.runups.RunupRules` and
:class:`~hippo.soft_recognition.SoftRecognition` are): it reads and changes the decider's
state and its brain's (``self.b``).
"""

from __future__ import annotations

from hippo.types import Mode, StateKind, Transition

__all__ = ["WaitRules"]


class WaitRules:
    """How :class:`~hippo.decision.Decider` ends stops and waits (see the module docstring)."""

    def check_wait(self) -> None:
        """End an approach (stop) or a wait when its time is over (see the module docstring)."""
        b = self.b
        p = b.p
        if self.current is None:
            return
        ro = b.readouts.get(self.current)
        if self.mode == Mode.APPROACH:
            # stop when the learned time-to-stop is over, or before the robot would usually
            # have left the place (the timed prediction of the moves out of it)
            here = self.current[0] == b.state
            leaving = here and any(
                r.elapsed_fraction >= p.leave_fraction for k, r in b.readouts.items()
                if k != self.current and r.strength >= p.transitions.min_strength
                and b.kind(k[1]).is_context)
            if here and ro is not None and ro.strength >= p.transitions.min_strength:
                over = ro.delay_over
            else:
                # a stop recognised softly, or bound to this place over a brief one: timed by
                # the map's delay since the place was recognised
                delay = b.graph.delay(self.current)
                lead = p.transitions.latency + p.stop_lead * p.dt
                over = delay is None or b.t - self._approach_t0 >= float(delay) - lead
            gated = self._before_runup()
            if over and gated:
                self._entry_timed = False   # held by the run-up gate: no longer the map's timing
            if (over or leaving or self._past_runup()) and not gated:
                self.stop_untimed = not (over and self._entry_timed)
                self.note_stop()  # companions: the place that won where it stops
                ctx = b.layer.key(self.current[1]).context
                if ctx is not None:
                    b.layer.bind_context(ctx)  # it stops *for* this place
                self._wait_on(self.current)
                self._stopped_at, self._stop_by_runup = b.odometer, self._runup_fired
            return
        if self.mode != Mode.WAIT or self._waiting_on is None:
            return
        a, s = self._waiting_on
        own = b.kind(s) in (StateKind.MOVING, StateKind.PLACE, StateKind.COLOUR)
        over = (ro is not None and ro.delay_over) if own else (a, s) in b.non_occurrence
        if b.kind(s) == StateKind.STILL:
            # a stop held past its learned time-to-stop (by the run-up gate, or recognised
            # late) is 'omitted' by the non-occurrence neurons about when the robot stops:
            # the robot's stillness is perceived only after the proprioceptive debounce, so
            # an omission before then waits for it (it ended the wait at once and the robot
            # stopped again 30 cm on: tuning seed 4, checkpoint 1)
            self._omitted_early |= over
            over = self._omitted_early and b.t - self._wait_since > self.still_grace
            if not over and b.t - self._wait_since > self.still_grace + p.stop_timeout:
                # the stillness it waits for has not come (the robot stands in another
                # stop's context, or cannot stop): give the stop up, serving no drive
                self.mode, self.current, self._waiting_on = Mode.EXPLORE, None, None
                return
        if not over:
            return
        # the wait is over: inhibit the drives that chose it, then move on from the place; a
        # predicted reward that did not come also weakens the drive's link to the wait (HIREL
        # eq. 4's decay term, Drives.extinguish: no change with the default extinction 0)
        ctx = b.layer.key(a).context if b.kind(a) == StateKind.STILL else a
        served = self._served_by((a, s))
        if served:
            self._correct_runup(served[0])
        if served and self._anchors(served[0]):  # the next run-up starts here
            b.wait_ended_at, b.last_wait_drive = b.odometer, served[0]
        for name in served:
            held = name in self._inhibited and b.drives.is_inhibited(name)  # a teacher releases
            if not held:
                if not own:
                    b.drives.extinguish(name, (a, s))
                b.drives.inhibit(name)
                self._inhibited[name] = ctx if ctx is not None else a
                self._inhibited_at[name] = b.pi.pose[:2]
        self._waiting_on = None
        self.mode = Mode.EXPLORE
        self.choose(ctx if ctx is not None else a, exclude_wait=True)

    def _served_by(self, wait: Transition) -> list[str]:
        """The drives a wait just over serves: those linked to it; where several are (one
        learned place stood for two checkpoints in the lesson), only the one whose run-up says
        this stop was due, counted along the taught order from the last wait, if it is one of
        them. Serving them all satisfied the later
        checkpoint's drive at the earlier one, and it never had a stop of its own (random
        checkpoints on patrol-course, tuning seeds 16 and 25)."""
        b = self.b
        return self._by_runup([name for name in b.drives.names if wait in b.drives.links(name)])

    def _by_runup(self, linked: list[str]) -> list[str]:
        """Of the drives ``linked`` to one stop's wait, the one the run-ups say the stop is
        due for (see :meth:`_served_by`); all of them if none is."""
        b = self.b
        if len(linked) < 2 or b.wait_ended_at is None or b.last_wait_drive is None:
            return linked
        # along the taught order from the last wait, adding up the run-ups: the stop whose
        # run-up ends here, the robot having passed the stops before it without making them
        ran, acc, name = b.odometer - b.wait_ended_at, 0.0, b.last_wait_drive
        for _ in b.drives.names:
            nxt = [d for d in b.drives.names if b.runup_after.get(d) == name and d in b.runups]
            if len(nxt) != 1:
                break
            name = nxt[0]
            acc += b.runups[name]
            if abs(ran - acc) <= b.p.runup_window:
                return [name] if name in linked else linked
            if acc > ran:
                break
        return linked

    def _wait_on(self, tr: Transition) -> None:
        """Wait for ``tr`` to happen (a stop's stillness, or the end of a wait)."""
        self.mode, self._waiting_on = Mode.WAIT, tr
        self._wait_since, self._omitted_early = self.b.t, False

    def untimed_stop(self, kind: StateKind) -> bool:
        """Is an event into a state of ``kind`` now the robot's own stop that its learned
        time-to-stop did not time (soft recognition, run-up, held by the run-up gate)? Such a
        stop is no measurement of the stop's delay, for the map nor for the transition cells:
        learning it would feed back (each stop off, the delay with it, the next stop further
        off; stops 30-50 cm late after 4.5 h, tuning seed 1; the cells' delay 7.4 -> 5.0 s
        over 5 h and the stops 20-30 cm early, tuning seed 0)."""
        return kind == StateKind.STILL and self.mode == Mode.WAIT and self.stop_untimed

    @property
    def still_grace(self) -> float:
        """How long (s) after a stop the robot's own stillness may take to be perceived: the
        proprioceptive debounce, one tick to the motor and one to spare."""
        p = self.b.p
        return (p.proprio_ticks + 2) * p.dt

    def wait_drive(self) -> int:
        """Index of the drive the robot is waiting or stopping for (-1: none): of the drives
        linked to the stop's wait, the one :meth:`_served_by` will serve."""
        b = self.b
        cur = self._waiting_on if self.mode == Mode.WAIT else (
            self.current if self.mode == Mode.APPROACH else None)
        if cur is None:
            return -1
        if b.kind(cur[1]) == StateKind.STILL:  # the stop itself: the wait after it
            nxt = b.graph.outgoing(cur[1]) if b.graph.has_state(cur[1]) else []
        else:
            nxt = [cur]
        linked = [n for n in b.drives.names if any(t in b.drives.links(n) for t in nxt)]
        return b.drives.names.index(self._by_runup(linked)[0]) if linked else -1
