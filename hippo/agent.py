"""The closed loop: learned place cells drive HIREL's timed cognitive map.

One :meth:`Agent.step` per control tick, in the order of ``DESIGN.md``::

    PathIntegrator.step(odometry)     own pose estimate: headings for actions (never a place input)
    place source .step(obs)           place-cell activities: learned RC-SFA-ICA read out by
                                      radial-basis prototypes (default), or Gaussian fields on
                                      the true position (comparison only)
    StateLayer.step(...)              WTA over places + floor colour + sound + proprioception
    SpectralTiming.step(winner)       the new winner's battery restarts at each sensory event
    TransitionCells.step(battery)     learn A->B with its delay; predict the next states and when
    NonOccurrence.step(readouts)      a predicted event is overdue
    TransitionGraph / Drives          add A->B with its action (heading and distance measured by
                                      path integration between entering A and entering B, or
                                      "wait" for a proprioceptive event); a reward links its drive
                                      to the last transition
    Planner.decide(state)             the outgoing transition with the highest drive activity
    motor                             move along the heading with obstacle avoidance, stand still
                                      (wait), or explore (SMC09's wall follower)

Waiting (HIREL III). Stopping and resuming are proprioceptive events of the state layer:
``still@C`` (stopped in context ``C``) and ``moving@C`` (moving again). A checkpoint wait is the
transition ``still@C -> moving@C`` (action "wait", delay = the pause); the place-preference
reward is ``still@goal -> sound``. While the robot waits on a transition whose next event is its
own (``moving``), the wait ends when the transition cells' ``delay_over`` flag rises (the
learned delay, population-decoded from the batteries); when the next event is external (the
sound), it ends when the non-occurrence neuron fires. Either way the drive linked to the waited
transition is inhibited (held at 0) until the robot reaches another place, and the robot moves
on with the other choices of the place it stopped in.

Stopping where it was taught. The transition ``C -> still@C`` also carries a delay (time from
entering ``C`` to stopping); the robot keeps its previous motion until that delay is over and
then stops, so a checkpoint wait starts where the teacher blocked the robot, not at the edge of
the place field.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np

from hippo._checks import check_finite, check_observation, check_positive
from hippo.cognitive_map import Action, DriveParams, Drives, Planner, PlannerParams, TransitionGraph
from hippo.perception.prototypes import PlacePrototypes
from hippo.perception.states import StateLayer, StateLayerParams
from hippo.sim.controllers import (
    ObstacleAvoidance,
    WallFollower,
    WallFollowerParams,
    WallGuidedHeading,
)
from hippo.sim.odometry import PathIntegrator
from hippo.sim.robot import RobotParams, SensorModel, get_sensor_model
from hippo.sim.world import Observation, wrap_angle
from hippo.timing import (
    NonOccurrence,
    NonOccurrenceParams,
    SpectralParams,
    SpectralTiming,
    TransitionCells,
    TransitionParams,
)

Transition = tuple[int, int]

#: what the motor layer is doing
MODES = ("explore", "move", "approach", "wait")


class PlaceSource(Protocol):
    """Anything that turns an observation into place-cell activities."""

    kind: str
    n_units: int

    def step(self, obs: Observation) -> np.ndarray: ...

    def reset(self) -> None: ...

    def prime(self, sensors: np.ndarray) -> None: ...


class LearnedPlaceCells:
    """Place cells learned by RC-SFA-ICA from the robot's own distance sensors (the default).

    Wraps a fitted :class:`~hippo.perception.place_cells.RCSFAICA`; ``step`` feeds it the sensor
    readings only (never the pose or odometry). With ``prototypes`` (a fitted
    :class:`~hippo.perception.prototypes.PlacePrototypes`), the activities are those of
    radial-basis place cells over the whole ICA population vector instead of the ICA units
    themselves (less aliasing; see that module).
    """

    kind = "learned"

    def __init__(self, model: Any, prototypes: PlacePrototypes | None = None) -> None:
        if getattr(model, "ica_", None) is None:
            raise ValueError("LearnedPlaceCells needs a fitted RCSFAICA model")
        self.model = model
        self.prototypes = prototypes
        self.n_units = prototypes.n_units if prototypes is not None else int(model.params.n_ica)

    def step(self, obs: Observation) -> np.ndarray:
        y = self.model.step(obs.ir)
        return y if self.prototypes is None else self.prototypes.step(y)

    def reset(self) -> None:
        self.model.reset_state()

    def prime(self, sensors: np.ndarray) -> None:
        """Start the online loop from the state of a robot that has been sensing: reset, then
        run the reservoir through recent readings ``sensors`` (T, n_inputs). A zero reservoir
        state is far from where the robot's inputs hold it, and the slow features amplify it:
        measured on the patrol course, the ICA outputs then stay off their training range (and
        every prototype silent) for about 100 s."""
        self.model.reset_state()
        for u in np.asarray(sensors, dtype=float):
            self.model.step(u)  # the prototypes hold no state: nothing else to run


class GroundTruthPlaceCells:
    """Gaussian place fields on the true position — only to measure what perception costs.

    ``a_k = exp(-|p - c_k|² / (2 σ²))`` with centres ``c_k`` (cm) and width ``sigma``.
    """

    kind = "ground-truth"

    def __init__(self, centres: np.ndarray, sigma: float = 10.0) -> None:
        self.centres = check_finite("centres", centres).reshape(-1, 2)
        if len(self.centres) == 0:
            raise ValueError("GroundTruthPlaceCells needs at least one centre")
        self.sigma = check_positive("sigma", sigma)
        self.n_units = len(self.centres)

    def step(self, obs: Observation) -> np.ndarray:
        d2 = np.sum((self.centres - np.asarray(obs.pose[:2])) ** 2, axis=1)
        return np.exp(-d2 / (2 * self.sigma**2))

    def reset(self) -> None:
        pass

    def prime(self, sensors: np.ndarray) -> None:
        """Nothing to prime: the fields read the true position."""


@dataclass(frozen=True)
class AgentParams:
    """Parameters of the closed loop (dt and speed: the e-puck of SMC09).

    still_turn: rad/s of rotation under which a robot that does not translate counts as still
        (turning on the spot is movement for proprioception).
    move_timeout: a move is abandoned (the robot explores) after this × its learned delay + 5 s.
    explore_rho: side-switch probability of the exploring wall follower (0: a steady tour).
    approach: keep moving after entering a place until the learned ``C -> still@C`` delay is over
        before stopping (False: stop as soon as the stop is chosen).
    proprio_ticks: proprioception is debounced: the robot becomes still (or moving) after this
        many consecutive ticks of it, so a stall at a corner is not a stop.
    settle_time: after being lifted the robot explores this long (s) before it trusts its
        place state again (learned place cells need a few seconds to recover; SMC09 Fig. 7).
    stall_time, unstick_time: a move that leaves the robot stalled for ``stall_time`` s (its
        heading runs into a wall) hands over to the wall follower for ``unstick_time`` s.
    turn_discount: a move that would turn a moving robot around (> 100°) has its drive activity
        multiplied by this when transitions compete (motor continuity against aliasing).
    cycle_visits, cycle_window, cycle_explore: habituation. Entering the same place
        ``cycle_visits`` times within ``cycle_window`` s while a drive is active means the map
        is leading the robot in circles (noisy place states can make transitions point back
        and forth); it then explores for ``cycle_explore`` s.
    coactive: soft recognition of a wanted stop's place: while moving with an active drive
        whose stop is bound to place ``C``, the robot approaches that stop once ``C``'s activity
        reaches this fraction of the most active place's, as if it had entered ``C`` (0
        disables). Learned place cells split a stretch of track between prototypes that
        alternate from lap to lap; the taught one need not win on every pass.
    wall_tolerance: a move goes along the followed wall (the exploration's own motion, so the
        place cells see what they were trained on) while the move's heading is within this
        many radians of the robot's; beyond it the robot steers to the heading.
    """

    dt: float = 0.2
    speed: float = 5.08
    still_turn: float = 0.15
    move_timeout: float = 3.0
    explore_rho: float = 0.0
    approach: bool = True
    proprio_ticks: int = 2
    settle_time: float = 6.0
    stall_time: float = 1.0
    unstick_time: float = 4.0
    turn_discount: float = 0.5
    cycle_visits: int = 3
    cycle_window: float = 60.0
    cycle_explore: float = 20.0
    coactive: float = 0.6
    wall_tolerance: float = 2.0
    states: StateLayerParams = field(default_factory=StateLayerParams)
    spectral: SpectralParams = field(default_factory=SpectralParams)
    #: latency 0.4 s = one tick from decision to motion + one tick of proprioceptive debounce
    #: (``proprio_ticks - 1``): the robot's own end of a wait is then seen at the learned delay
    transitions: TransitionParams = field(default_factory=lambda: TransitionParams(latency=0.4))
    non_occurrence: NonOccurrenceParams = field(default_factory=NonOccurrenceParams)
    planner: PlannerParams = field(default_factory=lambda: PlannerParams(w=0.9, noise=0.01))

    def __post_init__(self) -> None:
        check_positive("dt", self.dt)
        check_positive("speed", self.speed)
        check_positive("still_turn", self.still_turn, allow_zero=True)
        check_positive("move_timeout", self.move_timeout)
        if self.proprio_ticks < 1:
            raise ValueError(f"proprio_ticks must be >= 1, got {self.proprio_ticks}")
        check_positive("settle_time", self.settle_time, allow_zero=True)
        check_positive("wall_tolerance", self.wall_tolerance)
        if not 0.0 <= self.coactive <= 1.0:
            raise ValueError(f"coactive must lie in [0, 1], got {self.coactive}")
        if not 0.0 <= self.explore_rho <= 1.0:
            raise ValueError(f"explore_rho must lie in [0, 1], got {self.explore_rho}")


class Agent:
    """HIREL's architecture on any place-cell source; one :meth:`step` per control tick.

    Parameters
    ----------
    places : a :class:`PlaceSource` (:class:`LearnedPlaceCells` in every scenario by default).
    drives : drive name -> :class:`DriveParams`. The drive ``"sound"`` is satisfied by the
        reward sound; others by :meth:`reward` (e.g. the teacher's end of a checkpoint block).
    params : :class:`AgentParams`.
    sensors, robot : the robot the motor layer drives.
    seed : seeds the agent's own random choices (planner noise, exploration).
    """

    def __init__(self, places: PlaceSource, *, drives: Mapping[str, DriveParams] | None = None,
                 params: AgentParams | None = None, sensors: str | SensorModel = "ir8",
                 robot: RobotParams | None = None, seed: int = 0) -> None:
        self.places = places
        self.p = params or AgentParams()
        self.robot = robot or RobotParams()
        self.sensors = get_sensor_model(sensors)
        self.rng = np.random.default_rng([seed, 7])
        self.layer = StateLayer(self.p.states, n_place=places.n_units)
        self.spectral = SpectralTiming(self.p.spectral)
        self.cells = TransitionCells(self.spectral, self.p.transitions)
        self.nonocc = NonOccurrence(self.p.non_occurrence)
        self.graph = TransitionGraph()
        self.drives = Drives(dict(drives if drives is not None else {"sound": DriveParams()}))
        self.planner = Planner(self.p.planner, seed=seed)
        self.explorer = WallFollower(WallFollowerParams(rho=self.p.explore_rho),
                                     sensors=self.sensors, robot=self.robot,
                                     rng=np.random.default_rng([seed, 8]))
        self.steer = WallGuidedHeading(sensors=self.sensors, robot=self.robot,
                                       tolerance=self.p.wall_tolerance,
                                       speed=self.p.speed, rng=np.random.default_rng([seed, 9]))
        self.avoid = ObstacleAvoidance(sensors=self.sensors, robot=self.robot)
        self.pi = PathIntegrator()
        self.t = 0.0
        self._moving = True
        self._flip = 0
        self._settle_until = -math.inf
        self._stalled = 0
        self._unstick_until = -math.inf
        self._visits: deque[tuple[float, int]] = deque()
        self._explore_until = -math.inf
        self._clear_view: np.ndarray | None = None
        self._reset_episode()

    # -- episode bookkeeping ------------------------------------------------------------------
    def _reset_episode(self) -> None:
        self.state: int | None = None
        self._entries: dict[int, tuple[float, tuple[float, float, float]]] = {}
        self._approach_t0 = self.t
        self.entered_at = self.t
        self._entry_pose = self.pi.pose
        self.current: Transition | None = None
        self.current_since = self.t
        self.mode = "explore"
        self._heading: float | None = None      # heading of the last move (kept when lost)
        self._waiting_on: Transition | None = None
        self._inhibited: dict[str, int] = {}    # drive -> context state it was inhibited in
        self._pending_rewards: list[str] = []
        self.last_transition: Transition | None = None
        self.non_occurrence: list[Transition] = []
        self.readouts: dict = {}

    def lifted(self, heading_change: float = 0.0) -> None:
        """The robot was picked up and put down elsewhere: no transition spans the jump, and
        the state competition starts afresh (the place cells keep their memory).

        ``heading_change`` (rad) is how much the robot was turned while carried; the heading
        estimate follows it (a robot's compass or head-direction system, not its place cells).
        """
        self.pi.heading = wrap_angle(self.pi.heading + heading_change)
        self.layer.reset(keep_states=True)
        self.nonocc.reset()
        for d in list(self._inhibited):
            self.drives.release(d)
        self._reset_episode()
        self._visits.clear()
        self._explore_until = -math.inf
        self._settle_until = self.t + self.p.settle_time

    def reward(self, drive: str) -> None:
        """An external satisfaction of ``drive``: linked to the next transition performed."""
        if drive not in self.drives:
            raise KeyError(f"unknown drive {drive!r}; known: {', '.join(self.drives.names)}")
        self._pending_rewards.append(drive)

    def describe(self, state: int | None) -> str:
        """Name of a state id (``place 3``, ``colour 1``, ``still@place 3``, ``sound``)."""
        return "none" if state is None else self.layer.describe(state)

    # -- the tick -----------------------------------------------------------------------------
    def step(self, obs: Observation) -> tuple[float, float]:
        """Perceive, learn, decide and act for one tick; returns wheel speeds (cm/s)."""
        p = self.p
        ir, self.t = check_observation(obs, self.sensors.n, getattr(self, "_last_t", -math.inf))
        self._last_t = self.t
        self.pi.step(obs.odometry)
        if self.avoid.boxed_in(obs) and self._clear_view is not None:
            # occluded: something is pressed against the robot (the teacher's block) and its
            # distance sensors see only that. They say nothing about the place, and feeding
            # them to the reservoir would corrupt its memory for minutes; the place cells keep
            # hearing the last clear view, as during any stop
            view = Observation(obs.t, obs.tick, self._clear_view, obs.floor, obs.sound,
                               obs.odometry, obs.moving, obs.pose, obs.speed)
            acts = self.places.step(view)
        else:
            self._clear_view = ir
            acts = self.places.step(obs)
        turning = abs(float(obs.odometry[2])) > p.still_turn * p.dt
        moving = bool(obs.moving or turning)
        if moving != self._moving:
            self._flip += 1
            if self._flip >= p.proprio_ticks:
                self._moving, self._flip = moving, 0
        else:
            self._flip = 0
        ev = self.layer.step(acts, colour=obs.floor, sound=obs.sound, moving=self._moving,
                             dt=p.dt)
        battery = self.spectral.step(ev.winner, p.dt)
        self.readouts = self.cells.step(battery, p.dt)  # learning never stops
        self.non_occurrence = self.nonocc.step(self.readouts, p.dt)
        if self.t < self._settle_until:
            self.mode = "explore"
            return self.explorer.act(obs)
        if self.state is None:  # (re)start: take the winner as it is, no transition
            self.state, self.entered_at, self._entry_pose = ev.winner, self.t, self.pi.pose
            self._entries[ev.winner] = (self.t, self.pi.pose)
            self._choose()
        elif ev.changed:
            self._on_event(ev.winner)
        self._recognise_stop()
        self._check_wait()
        self.drives.step(p.dt)
        return self._motor(obs)

    def _on_event(self, new: int) -> None:
        prev, t = self.state, self.t
        kind = self.layer.key(new).kind
        if kind == "moving" and (prev is None or self.layer.key(prev).kind != "still"):
            prev = None  # "moving" without a stop before it (e.g. after being lifted): no event
        entered_at, entry_pose = self.entered_at, self._entry_pose
        ctx = self.layer.key(new).context
        if (kind == "still" and prev is not None and ctx is not None and ctx != prev
                and self.layer.key(prev).kind == "place" and ctx in self._entries
                and t - entered_at < self.p.states.context_time):
            # the place that won just before the stop did not hold long enough to be its
            # context (state layer ``context_time``): the stop is bound to the place before,
            # and so is the transition into it (timed from entering that place)
            prev = ctx
            entered_at, entry_pose = self._entries[ctx]
        intended = (kind == "still" and self._waiting_on is not None
                    and self._waiting_on[1] == new and self.mode == "wait")
        if intended and prev is not None and self._waiting_on[0] != prev:  # type: ignore[index]
            # the robot stopped for a stop it recognised softly while another place won:
            # what it did is that transition, timed from the recognition
            prev = self._waiting_on[0]  # type: ignore[index]
            entered_at = self._approach_t0
        if prev is not None:
            delay = t - entered_at
            x0, y0, _ = entry_pose
            x1, y1, _ = self.pi.pose
            wait = self.layer.key(new).kind in ("still", "sound") or \
                self.layer.key(prev).kind == "still"
            dist = math.hypot(x1 - x0, y1 - y0)
            action = Action.wait() if wait or dist < 1e-6 else Action.move(
                math.atan2(y1 - y0, x1 - x0), dist)
            tr = self.graph.add_transition(prev, new, action, delay, time=t)
            self.graph.observe_position(new, (x1, y1))
            self.last_transition = tr
            if self.layer.key(new).kind == "sound" and "sound" in self.drives:
                self.drives.reward("sound", tr)
            for d in self._pending_rewards:
                self.drives.reward(d, tr)
            self._pending_rewards.clear()
        # drives inhibited by a finished wait are released once the robot reaches a place from
        # which that stop is not one transition away (it has left the checkpoint's region)
        if kind in ("place", "colour"):
            for d, c in list(self._inhibited.items()):
                if c != new and not self._stops_at(new, c):
                    self.drives.release(d)
                    del self._inhibited[d]
        approaching = self.mode == "approach" and self.current is not None
        self.state = new
        self.entered_at = t
        self._entry_pose = self.pi.pose
        if kind in ("place", "colour"):
            self._entries[new] = (t, self.pi.pose)
            if (approaching and kind == "place" and new != self.current[0]  # type: ignore[index]
                    and not self._stops_at(new, self.layer.key(
                        self.current[1]).context)):  # type: ignore[index]
                # on the way to a stop recognised softly (``coactive``): a place on the way
                # that does not know the stop does not cancel it
                return
        if kind == "moving":
            # resuming: keep the move chosen when the wait ended, else choose from the context
            if self.mode != "move" or self.current is None:
                ctx = self.layer.key(new).context
                self._choose(ctx, exclude_wait=True)
            return
        self._waiting_on = None
        came_from = self.layer.key(prev).kind if prev is not None else None
        if kind == "place" and came_from in ("place", "colour") and self._cycling(new):
            self._explore_until = t + self.p.cycle_explore
        if self.t < self._explore_until:
            self.mode, self.current = "explore", None
            return
        self._choose()

    def _recognise_stop(self) -> None:
        """Soft recognition of a wanted stop's place (``coactive``).

        Learned place cells often split one stretch of track between two prototypes that
        alternate from lap to lap; the place a stop was taught in then does not win on every
        pass. While moving with an active drive whose stop is bound to place ``C``, the robot
        approaches that stop when ``C``'s activity is close to the winner's (``coactive`` ×
        the most active place) and the map would choose that stop on entering ``C`` (its drive
        beats those of the moves out of ``C``)."""
        p = self.p
        if p.coactive <= 0 or self.mode != "move" or self.state is None:
            return
        acts = self.layer.place_activity
        if acts.size == 0:
            return
        top = float(acts.max())
        for name in self.drives.names:
            if (self.drives.is_inhibited(name)
                    or self.drives.level(name) < p.planner.exploration_threshold):
                continue
            for a, _ in self.drives.links(name):
                ka = self.layer.key(a)
                c = ka.context
                if ka.kind != "still" or c is None or c == self.state:
                    continue
                kc = self.layer.key(c)
                if kc.kind != "place" or kc.index >= acts.size:  # type: ignore[operator]
                    continue
                if (float(acts[kc.index]) < p.coactive * top  # type: ignore[index]
                        or not self.graph.has_state(c) or (c, a) not in self.graph):
                    continue
                # only if the map would choose that stop on entering C (drives compete)
                if max(self.graph.outgoing(c), key=self._activity) != (c, a):
                    continue
                self.current, self.current_since = (c, a), self.t
                self.mode, self._approach_t0 = "approach", self.t
                return

    def _stops_at(self, state: int, ctx: int | None) -> bool:
        """Is a stop in context ``ctx`` one transition away from ``state``?"""
        if ctx is None or not self.graph.has_state(state):
            return False
        for _, b in self.graph.outgoing(state):
            k = self.layer.key(b)
            if k.kind == "still" and k.context == ctx:
                return True
        return False

    def _cycling(self, place: int) -> bool:
        """Habituation: has ``place`` been entered too often lately while a drive is active?"""
        v = self._visits
        v.append((self.t, place))
        while v and v[0][0] < self.t - self.p.cycle_window:
            v.popleft()
        active = any(self.drives.level(n) >= self.p.planner.exploration_threshold
                     for n in self.drives.names)
        return active and sum(1 for _, s in v if s == place) >= self.p.cycle_visits

    def _choose(self, state: int | None = None, *, exclude_wait: bool = False) -> None:
        """Pick the transition to execute from ``state`` (default: the current one)."""
        s = self.state if state is None else state
        keep_heading = self.mode in ("move", "approach") and self._heading is not None
        self.current = None
        if s is None or not self.graph.has_state(s):
            self.mode = "move" if keep_heading else "explore"
            self.current_since = self.t
            return
        out = self.graph.outgoing(s)
        if exclude_wait:
            out = [t for t in out if not self.graph.action(t).is_wait]
        if not out:
            self.mode = "move" if keep_heading else "explore"
            return
        choice = self.planner.decide(self.graph, self.drives, s, self.rng)
        tr = choice.transition
        if choice.explored:
            if any(self.drives.level(n) >= self.p.planner.exploration_threshold
                   for n in self.drives.names):
                # a drive is active but no goal is reachable from here: leave this part of
                # the map by exploring (a random known move could circle in it forever)
                self.mode = "explore"
                return
            # no drive: explore along known transitions, by moving, never by stopping
            moves = [t for t in out if not self.graph.action(t).is_wait]
            if not moves:
                self.mode = "move" if keep_heading else "explore"
                return
            tr = moves[int(self.rng.integers(len(moves)))]
        else:
            # motor continuity: a place can stand for two distant stretches of track (aliasing);
            # a move that would turn the robot around is discounted, so the robot keeps to the
            # stretch it is on rather than to the alias of it (also when it moves on after a
            # wait: it still faces the way it came)
            vals = np.array([self._activity(t) for t in out])
            if keep_heading or exclude_wait:
                for i, t in enumerate(out):
                    a = self.graph.action(t)
                    if not a.is_wait and abs(wrap_angle(a.heading - self.pi.heading)) > 1.75:
                        vals[i] *= self.p.turn_discount
            if tr not in out or vals[out.index(tr)] < vals.max():
                tr = out[int(np.argmax(vals))] if vals.max() > 0 else \
                    out[int(self.rng.integers(len(out)))]
        self.current, self.current_since = tr, self.t
        action = self.graph.action(tr)
        if not action.is_wait:
            self.mode = "move"
            self._heading = float(action.heading)  # type: ignore[arg-type]
        elif self.layer.key(tr[1]).kind == "still" and self.p.approach:
            self.mode = "approach"   # keep going until the learned time-to-stop is over
            self._approach_t0 = self.entered_at
        else:
            self.mode = "wait"
            self._waiting_on = tr

    def _activity(self, tr: Transition) -> float:
        act = self.planner.activity(self.graph, self.drives)
        return float(act.values[act.index.pos[tr]])

    def _check_wait(self) -> None:
        if self.current is None:
            return
        ro = self.readouts.get(self.current)
        if self.mode == "approach":
            # stop when the learned time-to-stop is over, or before the robot would usually
            # have left the place (the timed prediction of the moves out of it)
            here = self.current[0] == self.state
            leaving = here and any(
                r.elapsed_fraction >= 0.8 for k, r in self.readouts.items()
                if k != self.current and r.strength >= self.p.transitions.min_strength
                and self.layer.key(k[1]).kind in ("place", "colour"))
            if here and ro is not None and ro.strength >= self.p.transitions.min_strength:
                over = ro.delay_over
            else:
                # a stop recognised softly, or bound to this place over a brief one: timed by
                # the map's delay since the place was recognised
                delay = self.graph.delay(self.current)
                lead = self.p.transitions.latency + 0.5 * self.p.dt
                over = delay is None or self.t - self._approach_t0 >= float(delay) - lead
            if over or leaving:
                ctx = self.layer.key(self.current[1]).context
                if ctx is not None:
                    self.layer.bind_context(ctx)  # it stops *for* this place
                self.mode, self._waiting_on = "wait", self.current
            return
        if self.mode != "wait" or self._waiting_on is None:
            return
        a, b = self._waiting_on
        own = self.layer.key(b).kind in ("moving", "place", "colour")
        over = (ro is not None and ro.delay_over) if own else (a, b) in self.non_occurrence
        if not over:
            return
        # the wait is over: inhibit the drives that chose it, then move on from the place
        ctx = self.layer.key(a).context if self.layer.key(a).kind == "still" else a
        for name in self.drives.names:
            if (a, b) in self.drives.links(name) and name not in self._inhibited:
                self.drives.inhibit(name)
                self._inhibited[name] = ctx if ctx is not None else a
        self._waiting_on = None
        self.mode = "explore"
        self._choose(ctx if ctx is not None else a, exclude_wait=True)

    # -- motor --------------------------------------------------------------------------------
    def _motor(self, obs: Observation) -> tuple[float, float]:
        if self.avoid.boxed_in(obs) or self.mode == "wait":
            return 0.0, 0.0
        if self.mode in ("move", "approach") and self._heading is not None:
            # a heading that runs into a wall leaves the robot stalled: wall-follow a while
            own_speed = math.hypot(obs.odometry[0], obs.odometry[1]) / self.p.dt  # odometry
            self._stalled = self._stalled + 1 if own_speed < 0.5 else 0
            if self._stalled * self.p.dt >= self.p.stall_time:
                self._unstick_until, self._stalled = self.t + self.p.unstick_time, 0
            if self.t < self._unstick_until:
                return self.explorer.act(obs)
            delay = self.graph.delay(self.current) if self.current is not None else None
            limit = self.p.move_timeout * float(delay or 5.0) + 5.0
            if self.t - self.current_since <= limit:
                return self.steer.act(obs, self.pi.heading, self._heading)
            self.mode, self.current = "explore", None
        return self.explorer.act(obs)

    # -- introspection ------------------------------------------------------------------------
    def snapshot(self) -> dict[str, Any]:
        """The per-tick signals a figure needs."""
        cur = self.current
        ro = self.readouts.get(cur) if cur is not None else None
        sound = [r.prediction for k, r in self.readouts.items()
                 if self.layer.key(k[1]).kind == "sound"]
        return {
            "sound_prediction": max(sound, default=0.0),
            "sound_non_occurrence": any(self.layer.key(k[1]).kind == "sound"
                                        for k in self.non_occurrence),
            "winner": -1 if self.state is None else self.state,
            "mode": MODES.index(self.mode),
            "transition_a": -1 if cur is None else cur[0],
            "transition_b": -1 if cur is None else cur[1],
            "prediction": 0.0 if ro is None else ro.prediction,
            "non_occurrence": bool(self.non_occurrence),
            "drives": [self.drives.level(n) for n in self.drives.names],
            "wait_drive": self._wait_drive(),
        }

    def _wait_drive(self) -> int:
        """Index of the drive the robot is waiting or stopping for (-1: none)."""
        cur = self._waiting_on if self.mode == "wait" else (
            self.current if self.mode == "approach" else None)
        if cur is None:
            return -1
        if self.layer.key(cur[1]).kind == "still":  # the stop itself: the wait after it
            nxt = self.graph.outgoing(cur[1]) if self.graph.has_state(cur[1]) else []
        else:
            nxt = [cur]
        for i, name in enumerate(self.drives.names):
            links = self.drives.links(name)
            if any(t in links for t in nxt):
                return i
        return -1
