"""The per-tick neural loop: one object, one :meth:`Brain.step` per control tick.

``Brain.step(observation) -> Tick`` runs, in the order of ``docs/architecture.md``::

    PathIntegrator.step(odometry)    own pose estimate: headings for actions (never a place input)
    places.step(obs)                 place-cell activities (learned RC-SFA-ICA by default)
    proprioception                   moving/still, debounced over ``proprio_ticks`` ticks
    StateLayer.step(...)             WTA over places + floor colour + sound + proprioception
    TimingChain.step(winner)         spectral batteries -> transition cells -> non-occurrence
    TransitionGraph / Drives         on a sensory event: add A->B with its action (heading and
                                     distance by path integration, or "wait"); a reward links
                                     its drive to the last transition
    Decider                          the transition to execute and the motor mode (see
                                     :mod:`hippo.decision`)
    Drives.step(dt)                  drives rise; inhibited ones are held at 0

The :class:`~hippo.ticks.Tick` it returns (:mod:`hippo.ticks`) is what the motor layer
(:mod:`hippo.motor`) needs and what a log records. :meth:`Brain.perceive` is the neural chain
alone (state layer and timing chain, no places, no decisions): the symbolic timing demo feeds
it place activities directly. The brain never sees the ground truth: only a ground-truth place
source (a comparison) receives it, through the explicit ``truth`` argument of
:meth:`Brain.step`.

Waiting (HIREL III). Stopping and resuming are proprioceptive events of the state layer:
``still@C`` (stopped in context ``C``) and ``moving@C``. A checkpoint wait is the transition
``still@C -> moving@C`` (action "wait", delay = the pause); the place-preference reward is
``still@goal -> sound``. How waits end, and how a stop is approached, is in
:mod:`hippo.decision`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from hippo._checks import check_finite, check_real
from hippo.brain_params import BrainParams
from hippo.cognitive_map import Action, DriveParams, Drives, Planner, TransitionGraph
from hippo.cognitive_map.localise import MapLocaliser
from hippo.decision import Decider
from hippo.head_direction import HeadingSectors
from hippo.perception.states import StateLayer
from hippo.places import PlaceSource
from hippo.seeds import Seeds
from hippo.sim.odometry import PathIntegrator
from hippo.ticks import Perception, Tick
from hippo.timing.chain import TimingChain
from hippo.types import GroundTruth, Mode, Observation, StateKind, Transition, wrap_angle

__all__ = ["Brain", "BrainParams", "Perception", "Tick"]


class Brain:
    """HIREL's architecture on any place source; one :meth:`step` per control tick.

    Parameters
    ----------
    places : a :class:`~hippo.places.PlaceSource` (None: only :meth:`perceive` is usable).
    drives : drive name -> :class:`DriveParams`. The drive ``"sound"`` is satisfied by the
        reward sound; others by :meth:`reward` (e.g. the teacher's end of a checkpoint block).
    params : :class:`BrainParams`.
    occlusion : an object whose ``boxed_in(obs) -> bool`` says that something is pressed
        against the robot and its distance sensors see only that (the teacher's block; the
        motor layer's :class:`~hippo.sim.controllers.ObstacleAvoidance`); the place cells then
        keep hearing the last clear view. Default: never. (An object, not a callable, so that
        a whole robot can be snapshotted.)
    seed : the run's seed; the brain's own random choices (planner noise, exploration of known
        moves) come from its stream ``"brain"`` (:mod:`hippo.seeds`), or from ``rng``.
    """

    #: direction-of-travel split of the place states (``BrainParams.heading_sectors`` > 1)
    sectors: HeadingSectors | None = None

    def __init__(self, places: PlaceSource | None = None, *,
                 drives: Mapping[str, DriveParams] | None = None,
                 params: BrainParams | None = None, occlusion: Any = None,
                 seed: int = 0, rng: np.random.Generator | None = None) -> None:
        self.places = places
        self.p = p = params or BrainParams()
        self.rng = rng if rng is not None else Seeds(seed).generator("brain")
        if p.heading_sectors > 1:
            self.sectors = HeadingSectors(p.heading_sectors)
        n_place = places.n_units if places is not None else 0
        self.layer = StateLayer(p.states, n_place=n_place * p.heading_sectors)
        self.timing = TimingChain(p.spectral, p.transitions, p.non_occurrence)
        self.graph = TransitionGraph()
        self.drives = Drives(dict(drives if drives is not None else {"sound": DriveParams()}))
        self.planner = Planner(p.planner, seed=seed)
        self.pi = PathIntegrator()
        self.odometer = 0.0  # distance run (cm, path integration)
        self.runups: dict[str, float] = {}  # drive -> run-up of its taught stop (cm)
        self.runup_after: dict[str, str] = {}  # drive -> the drive rewarded before it
        self.runup_early: dict[str, float] = {}  # drive -> a stop made well short of its run-up
        self.occlusion = occlusion
        self.t = 0.0
        self.decide = Decider(self)
        self._moving, self._flip = True, 0
        self._settle_until = -math.inf
        self.localiser = None if p.relocalise is None else MapLocaliser(p.relocalise)
        self._clear_view: np.ndarray | None = None
        self._reset_episode()

    # the neural parts under their usual names, and what the decider is doing
    spectral = property(lambda self: self.timing.spectral, doc="the SpectralTiming")
    cells = property(lambda self: self.timing.cells, doc="the TransitionCells")
    nonocc = property(lambda self: self.timing.nonocc, doc="the NonOccurrence neurons")
    mode = property(lambda self: self.decide.mode, doc="the motor Mode chosen")
    came_from = property(lambda self: self._ctx_before,
                         doc="the place (or colour) entered before the current one")
    current = property(lambda self: self.decide.current, doc="the transition executed")

    entry_unseen = False   # re-anchored inside this place: no stop until the next is entered
    def entered_since(self, state: int) -> float | None:
        """When the place (or colour) ``state`` was last entered in this episode (None: not
        since the last lift or reset)."""
        e = self._entries.get(state)
        return None if e is None else e[0]

    # -- episode bookkeeping ------------------------------------------------------------------
    def _reset_episode(self) -> None:
        self.state: int | None = None
        self.entry_unseen = False
        self._entries: dict[int, tuple[float, tuple[float, float, float]]] = {}
        # the context states (places, colours) entered last and the one before it
        self._ctx_now: int | None = None
        self._ctx_before: int | None = None
        self.wait_ended_at: float | None = None   # odometer when the last wait ended
        self._rewarded_at: float | None = None    # ... at the last reward
        self._rewarded_drive: str | None = None   # the drive of the last reward
        self.last_wait_drive: str | None = None   # the drive the last wait (or reward) was for
        self.entered_at = self.t
        self._entry_pose = self.pi.pose
        self._pending_rewards: list[str] = []
        self.last_transition: Transition | None = None
        self.non_occurrence: list[Transition] = []
        self.readouts: dict = {}
        self.decide.reset_episode()

    def lifted(self, heading_change: float = 0.0, *, keep_drives: bool = False,
               moved: bool = True) -> None:
        """The robot was picked up and put down elsewhere: no transition spans the jump, and
        the state competition starts afresh (the place cells keep their memory, or re-anchor).

        ``heading_change`` (rad) is how much the robot was turned while carried; the heading
        estimate follows it (a robot's compass or head-direction system, not its place cells).
        ``keep_drives``: a perturbation in the middle of a task (a kidnap, a rescue): a drive a
        finished wait inhibited stays so until the robot has moved ``release_distance`` from
        where it was put and left that stop's place (being carried satisfies no drive and renews
        none). False (default): a new trial, every drive released. ``moved`` False: put back
        where it was (nothing for the place cells to re-anchor).
        """
        turn = check_real("heading_change", heading_change)   # finite radians, checked first
        self.pi.heading = wrap_angle(self.pi.heading + turn)
        if self.sectors is not None:
            self.sectors.reset()
        getattr(self.places, "lifted", lambda: None)() if moved else None   # re-anchor?
        self.layer.reset(keep_states=True)
        self.nonocc.reset()
        kept = self.decide.inhibitions() if keep_drives else {}
        if not keep_drives:
            self.decide.release_all()
        self._reset_episode()
        self.decide.lifted()
        self.decide.restore_inhibitions(kept, self.pi.pose[:2])
        self._settle_until = self.t + self.p.settle_time
        if self.localiser is not None:
            self.localiser.reset(self.t)
            self._settle_until = math.inf   # until the map recognises where the robot is

    def reward(self, drive: str, *, runup: bool = True) -> None:
        """An external satisfaction of ``drive``: linked to the next transition performed
        (unless that is a wait already another drive's goal and ``drive`` has a goal of its
        own: a repeated lesson in an aliased place teaches only the run-up). ``runup`` False:
        the run since the reward before is no run-up (the teacher led the robot back from a
        detour), though this reward still anchors the next."""
        if drive not in self.drives:
            raise KeyError(f"unknown drive {drive!r}; known: {', '.join(self.drives.names)}")
        self._pending_rewards.append(drive)
        # the stop just rewarded is a taught one: its run-up is the run since the reward
        # before (the robot's own stops in between do not count), and it anchors the next (a
        # reward far from the run-up already taught, e.g. a block after hours, keeps it)
        ran = self.odometer - self._rewarded_at if runup and self._rewarded_at is not None else None
        taught = self.runups.get(drive)
        if (ran is not None and self._rewarded_drive is not None
                and (taught is None or abs(ran - taught) <= self.p.runup_window)):
            self.runups[drive] = ran
            self.runup_after[drive] = self._rewarded_drive
        self._rewarded_at = self.wait_ended_at = self.odometer
        self._rewarded_drive = self.last_wait_drive = drive

    def kind(self, state: int) -> StateKind:
        """What ``state`` stands for."""
        return StateKind(self.layer.key(state).kind)

    def describe(self, state: int | None) -> str:
        """Name of a state id (``place 3``, ``colour 1``, ``still@place 3``, ``sound``)."""
        return "none" if state is None else self.layer.describe(state)

    # -- the tick -----------------------------------------------------------------------------
    def perceive(self, place: np.ndarray | None, *, colour: int | None, sound: bool,
                 moving: bool, dt: float) -> Perception:
        """The neural chain for one tick: state layer -> timing chain (learning never stops)."""
        ev = self.layer.step(place, colour=colour, sound=sound, moving=moving, dt=dt)
        # the transition cells learn no delay from a stop the decider did not time (nor does
        # the map, _on_event)
        untimed = ev.changed and (self.decide.untimed_stop(self.kind(ev.winner))
                                  or self._lesson_on_another_goal(self.state, ev.winner))
        return Perception(ev, self.timing.step(ev.winner, dt, learn_event=not untimed))

    def step(self, obs: Observation, truth: GroundTruth | None = None) -> Tick:
        """Perceive, learn and decide for one tick. ``truth`` is read by a ground-truth place
        source only (the comparison that measures what perception costs)."""
        ir = check_finite("sensor readings", obs.ir)
        check_finite("odometry", obs.odometry)
        return self._step(obs, truth, ir)

    def _step(self, obs: Observation, truth: GroundTruth | None, ir: np.ndarray) -> Tick:
        """:meth:`step` on an observation already checked (:meth:`hippo.agent.Agent.step`
        checks each one whole, ``check_observation``); ``ir``: its readings as a float array."""
        p = self.p
        if self.places is None:
            raise ValueError("this Brain has no place source: use perceive(), or pass places")
        self.t = float(obs.t)
        dx, dy, dth = obs.odometry
        self.pi.advance(dx, dy, dth)
        self.odometer += math.hypot(dx, dy)
        if (self.occlusion is not None and self.occlusion.boxed_in(obs)
                and self._clear_view is not None):
            # occluded: the distance sensors see only what is pressed against the robot. They
            # say nothing about the place, and feeding them to the reservoir would corrupt its
            # memory for minutes; the place cells keep hearing the last clear view
            acts = self.places.step(obs.with_ir(self._clear_view), truth)
        else:
            self._clear_view = ir
            acts = self.places.step(obs, truth)
        if self.sectors is not None:
            acts = self.sectors.split(acts, self.pi.heading, math.hypot(dx, dy))
        if self.localiser is not None and getattr(self.places, "anchored", False):
            self.localiser.anchor(obs.t)   # the place code jumped to where the readings match
        turning = abs(float(dth)) > p.still_turn * p.dt
        moving = bool(obs.moving or turning)
        if moving != self._moving:
            self._flip += 1
            if self._flip >= p.proprio_ticks:
                self._moving, self._flip = moving, 0
        else:
            self._flip = 0
        seen = self.perceive(acts, colour=obs.floor, sound=obs.sound, moving=self._moving,
                             dt=p.dt)
        ev = seen.event
        self.readouts = seen.timing.readouts
        self.non_occurrence = seen.timing.omitted  # type: ignore[assignment]
        if (self.t < self._settle_until and ev.winner is not None
                and self.kind(ev.winner) == StateKind.COLOUR):
            self._settle_until = self.t  # a floor colour is sensed, not remembered: decide
        if self.t < self._settle_until and self.localiser is not None:
            if ev.changed and self.layer.key(ev.winner).kind == "place":
                self.localiser.observe(ev.winner, self.t, self.graph)
            if self.localiser.check(self.t):
                self._settle_until = self.t  # re-localised: decide from this tick on
        if self.t < self._settle_until:
            self.decide.mode = Mode.EXPLORE
            return self._tick(ev.changed, settling=True, novel=ev.novel)
        if self.state is None:  # (re)start: take the winner as it is, no transition
            self.state, self.entered_at, self._entry_pose = ev.winner, self.t, self.pi.pose
            self._entries[ev.winner] = (self.t, self.pi.pose)
            self._ctx_now, self._ctx_before = ev.winner, None
            self.entry_unseen = getattr(self.localiser, "by_anchor", False)   # re-anchored inside
            if self.kind(ev.winner) == StateKind.PLACE and not self.entry_unseen:
                self.decide.passed_held_stop(ev.winner)   # a held stop's place may win at once
            self.decide.choose()
        elif ev.changed:
            self._on_event(ev.winner)
        self.decide.reanchor()
        self.decide.recognise_stop()
        self.decide.check_wait()
        self.drives.step(p.dt)
        return self._tick(ev.changed, novel=ev.novel)

    def _tick(self, event: bool, *, settling: bool = False, novel: bool = False) -> Tick:
        d = self.decide
        limit = None
        if not settling and d.mode in (Mode.MOVE, Mode.APPROACH) and d.heading is not None:
            delay = self.graph.delay(d.current) if d.current is not None else None
            limit = self.p.move_timeout * float(delay or self.p.default_delay) + self.p.move_margin
        return Tick(self.t, self.state, bool(event), d.mode, d.current, d.heading,
                    self.pi.heading, d.current_since, limit, settling,
                    tuple(self.non_occurrence), bool(novel))

    def abandon(self) -> None:
        """The motor layer gave up the current move (it took too long): explore."""
        self.decide.mode, self.decide.current = Mode.EXPLORE, None

    def _on_event(self, new: int) -> None:
        """A sensory event: learn the transition just made (map, rewards), then decide."""
        prev, t = self.state, self.t
        kind = self.kind(new)
        if kind == StateKind.MOVING and (prev is None or self.kind(prev) != StateKind.STILL):
            prev = None  # "moving" without a stop before it (e.g. after being lifted): no event
        if self.entry_unseen:
            prev, self.entry_unseen = None, False   # a stay that began unseen times nothing
        entered_at, entry_pose = self.entered_at, self._entry_pose
        ctx = self.layer.key(new).context
        if (kind == StateKind.STILL and prev is not None and ctx is not None and ctx != prev
                and self.kind(prev) == StateKind.PLACE and ctx == self._ctx_before
                and ctx in self._entries and t - entered_at < self.p.states.context_time):
            # the place that won just before the stop did not hold long enough to be its
            # context (state layer ``context_time``): the stop is bound to the place before,
            # and so is the transition into it (timed from entering that place). Only the
            # place entered right before: a stop bound to a place last entered a lap ago (a
            # stop recognised softly) would be timed over the whole lap and spoil the map's
            # delay of that stop, which times soft stops (found in long deployments)
            prev = ctx
            entered_at, entry_pose = self._entries[ctx]
        prev, entered_at = self.decide.intended_source(new, kind, prev, entered_at)
        cur = self.decide.current
        if (kind.is_context and cur is not None and cur[0] == prev and cur[1] != new
                and cur in self.graph and self.graph.inferred(cur)):
            self.graph.remove_transition(cur)  # an inferred way back that led elsewhere
        if prev is not None:
            untimed = self.decide.untimed_stop(kind)  # no measurement of the stop's delay
            self._learn(prev, new, None if untimed else t - entered_at, entry_pose)
        if kind.is_context:
            self.decide.release_away_from(new)
        self.state = new
        self.entered_at = t
        self._entry_pose = self.pi.pose
        if kind.is_context:
            self._entries[new] = (t, self.pi.pose)
            self._ctx_now, self._ctx_before = new, self._ctx_now
        self.decide.on_event(new, kind, prev)

    def _learn(self, prev: int, new: int, delay: float | None,
               entry_pose: tuple[float, float, float]) -> None:
        """Add ``prev -> new`` to the map with its action and delay; pay pending rewards."""
        if self._lesson_on_another_goal(prev, new):
            for d in self._pending_rewards:
                self.drives.satisfy(d)
            self._pending_rewards.clear()
            return
        x0, y0, _ = entry_pose
        x1, y1, _ = self.pi.pose
        wait = self.kind(new) in (StateKind.STILL, StateKind.SOUND) or \
            self.kind(prev) == StateKind.STILL
        dist = math.hypot(x1 - x0, y1 - y0)
        action = Action.wait() if wait or dist < 1e-6 else Action.move(
            math.atan2(y1 - y0, x1 - x0), dist)
        if self.p.forget < 1.0 and self.graph.decay(self.p.forget):
            self.drives.prune(self.graph)
        tr = self.graph.add_transition(prev, new, action, delay, time=self.t)
        if (self.p.infer_reverse and not action.is_wait and self.graph.count(tr) == 1
                and self.kind(prev).is_context and self.kind(new).is_context):
            self.graph.infer_reverse(tr, time=self.t)
        self.graph.observe_position(new, (x1, y1))
        self.last_transition = tr
        if self.kind(new) == StateKind.SOUND and "sound" in self.drives:
            self.drives.reward("sound", tr)
        for d in self._pending_rewards:
            self.drives.reward(d, tr)
        self._pending_rewards.clear()

    def _lesson_on_another_goal(self, a: int | None, b: int) -> bool:
        """Does the wait ``a -> b`` end a lesson (a reward pending) on a stop that is already
        another drive's goal, while every drive rewarded has a goal of its own? Such a lesson
        (the patrol's last block at its first checkpoint, taught again for the run-up) stopped
        in a place aliased with another checkpoint's. It teaches the run-up (:meth:`reward`)
        and satisfies its drive, and nothing else: timing the wait or linking it would give
        the other checkpoint this one's wait (tuning seed 60: checkpoint 3 waited 24 s,
        checkpoint 1's, wherever its place won)."""
        if not self._pending_rewards or a is None or self.kind(a) != StateKind.STILL:
            return False
        served = self.drives.goals.get((a, b))
        return (served is not None and not any(d in served for d in self._pending_rewards)
                and all(self.drives.links(d) for d in self._pending_rewards))

    # -- introspection ------------------------------------------------------------------------
    def snapshot(self) -> dict[str, Any]:
        """The per-tick signals a figure needs."""
        cur = self.current
        ro = self.readouts.get(cur) if cur is not None else None
        sound = [r.prediction for k, r in self.readouts.items()
                 if self.kind(k[1]) == StateKind.SOUND]
        return {
            "sound_prediction": max(sound, default=0.0),
            "sound_non_occurrence": any(self.kind(k[1]) == StateKind.SOUND
                                        for k in self.non_occurrence),
            "winner": -1 if self.state is None else self.state,
            "mode": int(self.mode),
            "transition_a": -1 if cur is None else cur[0],
            "transition_b": -1 if cur is None else cur[1],
            "prediction": 0.0 if ro is None else ro.prediction,
            "non_occurrence": bool(self.non_occurrence),
            "drives": [self.drives.level(n) for n in self.drives.names],
            "wait_drive": self.decide.wait_drive(),
        }
