"""Transition cells: which state comes next, and when (HIREL sec. II, eq. 1-3).

Public API
----------
- :class:`TransitionParams` — NLMS parameters, ``min_strength``, ``anticipation``, ``latency``.
- :class:`TransitionCells` — ``step(battery: BatteryState, dt) -> dict[(a, b), TransitionReadout]``
  (the transitions out of the current winner); ``reset(keep_weights=False)``.
  Queries: ``transitions`` (all keys), ``successors(a)``, ``prediction(key)``,
  ``learned_delay(key)``, ``strength(key)``, ``elapsed_fraction(key)``, ``delay_over(key)``,
  ``weights(key)``, ``expected(a, tau)`` (prediction of every successor of ``a`` over time),
  ``elapsed`` (population readout of the time spent in the current winner, s).
- :class:`TransitionReadout` — per transition and tick: ``prediction``, ``strength``,
  ``learned_delay`` (s), ``elapsed_fraction`` and the **delay-over** flag ``delay_over``.

A delay longer than the battery's longest cell (``SpectralParams.mu_max``, default 120 s) cannot
be timed: the event is still learned (its delay saturates near ``mu_max``) and a
:class:`DelayRangeWarning` reports it.

A transition is keyed by the tuple ``(a, b)`` of integer state ids everywhere (the cognitive map
uses the same key). Transitions are recruited when first experienced; learning never stops.

The delay-over moment
---------------------
``delay_over`` becomes True at the tick where
``elapsed_fraction >= 1 - (anticipation + latency) / T``,
where ``elapsed_fraction = readout(battery) / readout(W_ab)``: the population readout of the
elapsed time from the active battery divided by the population readout of the learned delay
``T`` from the transition's synapses (:meth:`SpectralTiming.readout`), and only for transitions
whose learned prediction is strong enough (``strength >= min_strength``). The anticipation of
half a control tick makes the decision land on the tick nearest to ``T`` (a decision taken at a
tick holds until the next one), which halves the quantisation error; the latency (one tick)
is the time the decision takes to show in the senses, so the robot is *seen* leaving at ``T``.
Typical use by an agent::

    layer, timing = StateLayer(), SpectralTiming()
    cells, nonocc = TransitionCells(timing), NonOccurrence()
    ev = layer.step(place=acts, colour=obs.floor, sound=obs.sound, moving=obs.moving, dt=0.2)
    readouts = cells.step(timing.step(ev.winner, 0.2), 0.2)
    wait = readouts.get((still_here, moving_here))
    if wait is not None and wait.delay_over:  # patrol: the learned wait is over, move on
        ...
    for key in nonocc.step(readouts, 0.2):    # extinction: predicted event did not come
        ...                                   # inhibit the drive that chose this transition
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from hippo._checks import check_positive
from hippo.timing.nlms import learning_modulation, nlms_update
from hippo.timing.spectral import BatteryState, SpectralTiming, check_state_id
from hippo.timing.transition_params import (
    DelayRangeWarning,
    Key,
    TransitionParams,
    TransitionReadout,
)

__all__ = ["DelayRangeWarning", "TransitionCells", "TransitionParams", "TransitionReadout"]

class TransitionCells:
    r"""Transition prediction cells learning ``A -> B`` with its timing (HIREL eq. 1-3).

    The cell of transition :math:`(a,b)` predicts state :math:`b` from the battery of state
    :math:`a`: :math:`X_{ab}(\tau) = \sum_j W_{ab,j} X^a_j(\tau)`. Its weights follow the NLMS
    rule of :mod:`hippo.timing.nlms` with :math:`X^{CS}` = the battery of :math:`a` and
    :math:`X^{US}` = the activity of state :math:`b` (1 when it is the winner, else 0):

    .. math:: \frac{dW_{ab,j}}{dt} = \alpha\,\eta_b\left[\frac{(X^{US}_b - X_{ab})\,X^a_j}
              {\sum_k (X^a_k)^2 + \sigma_1} - \lambda X^{US}_b W_{ab,j}\right],\quad
              \eta_b = |X^{US}_b - m^{US}_b| + \sigma_2,\quad
              m^{US}_b(t) = \gamma\,m^{US}_b(t-dt) + (1-\gamma)\,X^{US}_b(t).

    At the event :math:`a \to b` the CS is :math:`a`'s battery at that moment
    (``BatteryState.previous_activity``), so the cell associates :math:`b` with the time spent
    in :math:`a` (Hirel et al., sec. II and Fig. 1). Between events the cells of the winner's
    transitions see :math:`X^{US} = 0` and learn only as much as :math:`\eta` allows. After
    learning, entering :math:`a` makes :math:`X_{ab}` rise to a bell-shaped peak at the learned
    delay whose width grows with the delay (Weber). A never-experienced transition has no cell
    and predicts nothing.
    """

    #: skip the learning step on settled ticks (where it changes nothing); the tests turn it
    #: off to check that the numbers are the same
    _skip_settled = True
    #: the slot at which m^US is exactly one-hot (-1: it is not), and the (params, dt) whose
    #: NLMS step was checked stable (class defaults: a snapshot saved without them loads)
    _settled_at = -1
    _checked: tuple = (None, None)
    #: row -> (T, X(T)), the battery at a row's learned delay kept while T is the same
    _at_delay: dict | None = None
    #: (rows, W[rows]) just learned this tick: the readout that follows reads the same block
    _learned: tuple | None = None

    def __init__(self, timing: SpectralTiming, params: TransitionParams | None = None) -> None:
        if not isinstance(timing, SpectralTiming):
            raise ValueError(f"timing must be a SpectralTiming, got {type(timing).__name__}")
        self.timing = timing
        self.params = params or TransitionParams()
        self.reset()

    # ------------------------------------------------------------------ state
    def reset(self, *, keep_weights: bool = False) -> None:
        """Forget the current trial (and, unless ``keep_weights``, every learned transition)."""
        m = self.timing.n_cells
        if not keep_weights or not hasattr(self, "_w"):
            # one row per transition, grown by doubling: W (R, m), its learned delay and
            # strength, and the target state b of each row with that state's slot in m^US
            self._w = np.zeros((8, m))
            self._delay = np.full(8, math.nan)
            self._strength = np.zeros(8)
            self._target = np.zeros(8, dtype=np.intp)
            self._target_slot = np.zeros(8, dtype=np.intp)
            self._keys: list[Key] = []
            self._index: dict[Key, int] = {}
            self._out: dict[int, np.ndarray] = {}   # state a -> rows of the transitions a -> *
            self._slot: dict[int, int] = {}
        self._m = np.zeros(max(len(self._slot), 8))
        self._settled_at = -1
        self.state: int | None = None
        self.elapsed = math.nan
        self.readouts: dict[Key, TransitionReadout] = {}

    def _state_slot(self, s: int) -> int:
        slot = self._slot.get(s)
        if slot is None:
            slot = self._slot[s] = len(self._slot)
            if slot >= self._m.size:
                self._m = np.concatenate([self._m, np.zeros(self._m.size)])
        return slot

    def _recruit(self, key: Key) -> int:
        row = len(self._keys)
        if row >= self._w.shape[0]:
            grow = self._w.shape[0]
            self._w = np.concatenate([self._w, np.zeros_like(self._w)])
            self._delay = np.concatenate([self._delay, np.full(grow, math.nan)])
            self._strength, self._target, self._target_slot = (
                np.concatenate([x, np.zeros(grow, dtype=x.dtype)])
                for x in (self._strength, self._target, self._target_slot))
        self._keys.append(key)
        self._index[key] = row
        self._target[row] = key[1]
        self._target_slot[row] = self._state_slot(key[1])
        self._out[key[0]] = np.append(self._out.get(key[0], np.zeros(0, dtype=np.intp)), row)
        return row

    def _refresh(self, rows: np.ndarray | list[int]) -> None:
        r"""Re-read the learned delay and strength of ``rows`` after their weights changed.

        :math:`T_r = \mathrm{readout}(W_r)` (the population readout of the delay stored in the
        synapses) and :math:`s_r = \sum_j W_{r,j} X_j(T_r)` (the prediction at that delay; 0
        for a row whose weights are silent), for all rows at once (one row, the usual case
        between events, by the one-row readout: the same numbers).
        """
        if len(rows) == 1:
            r = int(rows[0])
            w = self._w[r]
            d = self.timing._readout(w)
            self._delay[r] = d
            if math.isnan(d):  # silent weights
                self._strength[r] = 0.0
                return
            memo = self._at_delay = self._at_delay if self._at_delay is not None else {}
            kept = memo.get(r)
            if kept is None or kept[0] != d:
                kept = memo[r] = (d, self.timing._tuning(d))
            self._strength[r] = float(np.einsum("rj,rj->r", w[None], kept[1][None])[0])
            return
        w = self._w.take(rows, axis=0)  # (W[rows]: a row gather by take is ~3 x faster)
        d = self.timing._readouts(w)
        ok = ~np.isnan(d)
        if ok.all():  # the usual case: no row to mask out
            s = np.einsum("rj,rj->r", w, self.timing._tuning(d))
        else:
            s = np.zeros(d.size)
            if ok.any():
                s[ok] = np.einsum("rj,rj->r", w[ok], self.timing._tuning(d[ok]))
        self._delay[rows] = d
        self._strength[rows] = s

    # ------------------------------------------------------------------ learning
    def _learn(self, rows: np.ndarray, cs: np.ndarray, winner: int, dt: float) -> None:
        r"""Eq. 1-2 on every transition out of the CS's state at once (``rows`` of W).

        :math:`X^{US}_b = [b = \text{winner}]`, :math:`\eta_b = |X^{US}_b - m^{US}_b| + \sigma_2`
        (``m^US`` already updated this tick), then one Euler step of eq. 1 on those rows. Rows
        with :math:`\eta_b = 0` do not change: only the others are written back and re-read.
        """
        p = self.params.nlms
        m, target, slot = self._m, self._target, self._target_slot
        # X^US and eq. 2 row by row on plain floats (a handful of rows: the same IEEE
        # operations as on arrays, without an array's overhead)
        rl = rows.tolist()
        us = [1.0 if target.item(r) == winner else 0.0 for r in rl]
        eta = [learning_modulation(u, m.item(slot.item(r)), p.sigma2) for u, r in zip(us, rl)]
        learning = [(i, r) for i, (r, e) in enumerate(zip(rl, eta)) if e > 0.0]
        if not learning:
            return
        w = nlms_update(self._w.take(rows, axis=0), cs, np.array(us), np.array(eta), p, dt)[0]
        for i, r in learning:  # (a row with eta = 0 is unchanged: w + dt * 0)
            self._w[r] = w[i]
        self._learned = (rows, w)
        self._refresh([r for _, r in learning])

    def step(self, battery: BatteryState, dt: float, *, learn_event: bool = True
             ) -> dict[Key, TransitionReadout]:
        """One tick: learn from the battery state, then read out the winner's transitions.

        ``battery`` is what :meth:`SpectralTiming.step` returned this tick. Returns the
        readouts of the transitions out of the current winner (also in ``self.readouts``).
        ``learn_event=False``: an event this tick is no measurement of its delay (a stop the
        agent timed by other means): it is recruited, but no weight out of the state left
        learns from it.
        """
        if not isinstance(battery, BatteryState):
            raise ValueError(f"battery must be a BatteryState, got {type(battery).__name__}")
        params, checked_dt = self._checked
        if params is not self.params or checked_dt != dt:  # a new dt or new parameters
            dt = self._check_dt(dt)
        p = self.params.nlms
        winner = check_state_id("battery.state", battery.state)
        if battery.activity.shape != self.timing.mu.shape:  # (n_cells,)
            raise ValueError(f"battery.activity must have shape ({self.timing.n_cells},), "
                             f"got {battery.activity.shape}")
        # eq. 3 for every known state: X^US_b(t) = 1 for the winner, 0 otherwise. Between
        # events m^US settles to exactly one-hot at the winner; from then on the update
        # changes nothing (gamma * 1 + (1 - gamma) == 1 and gamma * 0 == 0) until the winner
        # changes, and, with sigma2 = 0, eta_b = |X^US_b - m^US_b| = 0 on every row: nothing
        # learns (most ticks)
        slot = self._state_slot(winner)
        if slot != self._settled_at or p.gamma + (1.0 - p.gamma) != 1.0:
            m = self._m
            m *= p.gamma
            m[slot] += 1.0 - p.gamma
            m[m < 1e-12] = 0.0
            self._settled_at = slot if m[slot] == 1.0 and np.count_nonzero(m) == 1 else -1
        settled = self._skip_settled and p.sigma2 == 0.0 and self._settled_at == slot
        if battery.changed and battery.previous is not None:
            a = check_state_id("battery.previous", battery.previous)
            self._state_slot(a)
            if battery.previous_activity is None:
                raise ValueError("battery.previous_activity is missing at an event")
            if battery.previous_tau > self.timing.params.mu_max:
                warnings.warn(
                    f"transition {a}->{winner} came after {battery.previous_tau:.4g} s, beyond "
                    f"the battery's longest cell (mu_max={self.timing.params.mu_max:g} s): its "
                    "delay is learned as saturated near mu_max. Harmless for a stay no task "
                    "times (a long visit while exploring); to time delays that long, raise "
                    "SpectralParams.mu_max", DelayRangeWarning, stacklevel=2)
            if winner != a and (a, winner) not in self._index:
                self._recruit((a, winner))
            rows = self._out.get(a)
            if rows is not None and learn_event:
                self._learn(rows, battery.previous_activity, winner, dt)
        else:
            # between events X^US = 0 on every row out of the winner, so eta = m^US + sigma2:
            # with sigma2 = 0 no row learns unless the target of one was active lately
            rows = self._out.get(winner)
            if rows is not None and not settled:
                self._learn(rows, battery.activity, winner, dt)
        self.state = winner
        self.readouts = self._read(winner, battery.activity)
        return self.readouts

    def _check_dt(self, dt: float) -> float:
        """``dt`` > 0 and the NLMS step stable with it (checked once per dt and parameters)."""
        dt = check_positive("dt", dt)
        p = self.params.nlms
        step = p.alpha * dt * (p.gamma + p.sigma2)  # eta <= gamma + sigma2 for US in {0, 1}
        if step >= 2.0:
            raise ValueError(f"NLMS step alpha*dt*eta = {step:.3g} >= 2 is unstable; "
                             "lower nlms.alpha or dt")
        self._checked = (self.params, dt)
        return dt

    # ------------------------------------------------------------------ readout
    def _read(self, a: int, activity: np.ndarray) -> dict[Key, TransitionReadout]:
        """Read out every transition out of ``a`` at once.

        ``X_ab = W_ab . X^a`` for all rows in one product; then, per row,
        ``elapsed_fraction = tau_hat / T_ab`` and
        ``delay_over = [s_ab >= min_strength] and [tau_hat / T_ab >= 1 - lead / T_ab]``,
        ``tau_hat`` the population readout of the battery (inf when it is silent). Those are a
        few scalars per row, taken as plain floats (the same IEEE operations as array ones,
        without an array's overhead on a handful of rows). Rows that learned this tick are read
        from the block the learning step made (the numbers a gather of them gives).
        """
        rows, (kept, self._learned) = self._out.get(a), (self._learned, None)
        if rows is None:
            self.elapsed = math.nan
            return {}
        if activity is self.timing.activity:  # the battery of this tick (the usual case)
            elapsed = self.timing.elapsed_readout()
        else:
            elapsed = self.timing._readout(activity)
        if math.isnan(elapsed):  # a silent battery: longer than any cell can time
            elapsed = math.inf
        self.elapsed = elapsed
        preds = ((kept[1] if kept is not None and kept[0] is rows else self._w.take(rows, axis=0))
                 @ activity).tolist()
        lead = self.params.anticipation + self.params.latency
        strong = self.params.min_strength
        keys, delay, strength, out = self._keys, self._delay, self._strength, {}
        for r, x in zip(rows.tolist(), preds):
            d, s = delay.item(r), strength.item(r)
            frac = elapsed / d  # a row whose weights are silent has T = nan: never over
            out[keys[r]] = TransitionReadout(keys[r], x, s, d, frac,
                                             s >= strong and frac >= 1.0 - lead / d)
        return out

    def _check_key(self, key: Key) -> Key:
        if not isinstance(key, tuple) or len(key) != 2:
            raise ValueError(f"a transition key is a tuple (a, b) of state ids, got {key!r}")
        a = check_state_id("transition source", key[0])
        b = check_state_id("transition target", key[1])
        for s in (a, b):
            if s not in self._slot:
                raise ValueError(f"unknown state id {s}: these transition cells never saw it")
        return (a, b)

    @property
    def transitions(self) -> list[Key]:
        """Every transition learned so far, in order of recruitment."""
        return list(self._keys)

    def successors(self, a: int) -> list[int]:
        """States ``b`` with a learned transition ``(a, b)``."""
        a = check_state_id("state", a)
        if a not in self._slot:
            raise ValueError(f"unknown state id {a}: these transition cells never saw it")
        return [self._keys[r][1] for r in self._out.get(a, ())]

    def weights(self, key: Key) -> np.ndarray:
        """Copy of the weights of transition ``key`` (zeros if never experienced)."""
        key = self._check_key(key)
        r = self._index.get(key)
        return np.zeros(self.timing.n_cells) if r is None else self._w[r].copy()

    def learned_delay(self, key: Key) -> float:
        """Delay stored in the transition's weights, seconds (nan if never experienced)."""
        key = self._check_key(key)
        r = self._index.get(key)
        return math.nan if r is None else float(self._delay[r])

    def strength(self, key: Key) -> float:
        """Prediction the transition gives at its learned delay (0 if never experienced)."""
        key = self._check_key(key)
        r = self._index.get(key)
        return 0.0 if r is None else float(self._strength[r])

    def prediction(self, key: Key) -> float:
        """Current activity of the transition cell (0 unless its source is the winner)."""
        key = self._check_key(key)
        ro = self.readouts.get(key)
        return 0.0 if ro is None else ro.prediction

    def elapsed_fraction(self, key: Key) -> float:
        """Elapsed time in the source state / learned delay (0 unless the source is the winner)."""
        key = self._check_key(key)
        ro = self.readouts.get(key)
        return 0.0 if ro is None or math.isnan(ro.elapsed_fraction) else ro.elapsed_fraction

    def delay_over(self, key: Key) -> bool:
        """True once the learned delay of ``key`` is over while its source state is the winner."""
        key = self._check_key(key)
        ro = self.readouts.get(key)
        return bool(ro is not None and ro.delay_over)

    def expected(self, a: int, tau: np.ndarray) -> dict[Key, np.ndarray]:
        """Prediction of every successor of ``a`` at elapsed times ``tau`` (no learning)."""
        a = check_state_id("state", a)
        if a not in self._slot:
            raise ValueError(f"unknown state id {a}: these transition cells never saw it")
        x = self.timing.tuning(np.asarray(tau, dtype=float))
        return {self._keys[r]: x @ self._w[r] for r in self._out.get(a, ())}
