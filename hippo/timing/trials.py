"""Symbolic timed trials without a robot: state ``a`` for a delay, then ``b`` (or nothing).

Used by the timing demo, the precision benchmark and the tests; built on the public API only.

- :func:`run_trial` — one trial through a :class:`~hippo.timing.chain.TimingChain` (spectral
  timing -> transition cells -> non-occurrence, the same chain the brain steps), with jittered
  control ticks. The event ``b`` comes
  from a teacher at the tick nearest a given delay, is omitted (extinction), or comes when the
  system itself says the learned delay is over (``self_end``: the agent's loop, in which the
  decision read at one tick shows in the senses at the next).
- :class:`TrialTrace` — what happened: elapsed times, predictions of ``(a, b)``, delay-over
  flags, elapsed fractions, non-occurrence firings, and when ``b`` came.
- :func:`reproduce` -> :class:`Reproduction` — teach a delay, then let the system reproduce it
  in closed loop (HIREL's patrol, Table I) and time the non-occurrence of an omitted event.

Example::

    chain = TimingChain()
    rng = np.random.default_rng(0)
    for _ in range(3):
        run_trial(chain, 0, 1, 7.0, rng=rng)               # teach 0 -> 1 at 7 s
    rep = run_trial(chain, 0, 1, None, rng=rng, self_end=True)
    rep.end                                                # ~7.0: the reproduced wait
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from hippo._checks import check_positive, check_range, check_seed
from hippo.timing.chain import TimingChain
from hippo.timing.non_occurrence import NonOccurrence
from hippo.timing.spectral import SpectralTiming

__all__ = ["Reproduction", "TrialTrace", "reproduce", "run_trial"]


@dataclass(frozen=True, eq=False)
class TrialTrace:
    """One trial, tick by tick while ``a`` was the winner (the entry tick excluded).

    tau: elapsed time in ``a``; prediction, delay_over, elapsed_fraction: of ``(a, b)``.
    fired: elapsed times at which the non-occurrence neuron of ``(a, b)`` fired.
    end: elapsed time at which ``b`` came (None if it never did).
    """

    tau: np.ndarray
    prediction: np.ndarray
    delay_over: np.ndarray
    elapsed_fraction: np.ndarray
    fired: list[float]
    end: float | None


def run_trial(chain: TimingChain | SpectralTiming, *args: Any, dt: float = 0.2,
              jitter: float = 0.1, rng: np.random.Generator | None = None,
              self_end: bool = False, t_max: float | None = None, after: float = 4.0,
              other: int | None = None, nonocc: NonOccurrence | None = None) -> TrialTrace:
    """``run_trial(chain, a, b, delay, ...)``: enter ``a``, stay until ``b`` comes, then let
    ``b`` (and ``other``) last ``after`` s.

    ``chain``'s non-occurrence neurons (if it has them) watch the predictions: their firings
    for ``(a, b)`` are the trace's ``fired``. The modules may also be given one by one,
    ``run_trial(timing, cells, a, b, delay, ..., nonocc=None)``: they are stepped as the chain
    ``TimingChain.of(timing, cells, nonocc)``.

    delay: the teacher's delay (``b`` at the first tick with ``tau >= delay - tick/2``, i.e.
        the tick nearest the delay), or None for no teacher (extinction, or ``self_end``).
    jitter: each tick lasts ``dt * (1 + U(-jitter, jitter))`` (needs ``rng`` when > 0).
    self_end: ``b`` comes at the tick after the one where ``delay_over((a, b))`` rose.
    t_max: give up waiting after this long (default ``2 * delay + 5`` or 60 s).
    other: a state entered after ``b`` (or, if ``b`` never came, after ``a``); default: none.
    """
    if isinstance(chain, SpectralTiming):
        chain, args = TimingChain.of(chain, args[0], nonocc), args[1:]
    elif nonocc is not None:
        raise ValueError("nonocc goes with run_trial(timing, cells, ...): a chain has its own")
    if len(args) != 3:
        raise TypeError("run_trial(chain, a, b, delay, ...) takes a, b and delay")
    a, b, delay = args
    dt = check_positive("dt", dt)
    check_range("jitter", jitter, 0.0, 1.0, closed="left")
    if jitter > 0 and rng is None:
        raise ValueError("jitter > 0 needs rng, a numpy.random.Generator")
    if delay is not None:
        check_positive("delay", delay)
    if t_max is None:
        t_max = 2.0 * delay + 5.0 if delay is not None else 60.0
    t_max = check_positive("t_max", t_max)
    check_positive("after", after, allow_zero=True)
    cells = chain.cells
    if chain.state == a:
        raise ValueError(f"state {a} is already the winner: a trial starts by entering it "
                         "(end the previous trial in another state, e.g. with other=...)")

    def tick() -> float:
        return dt if jitter == 0 else dt * (1.0 + rng.uniform(-jitter, jitter))  # type: ignore[union-attr]

    def advance(state: int, d: float) -> dict:
        step = chain.step(state, d)
        return {"readouts": step.readouts, "fired": step.omitted}

    advance(a, dt)
    tau, end = 0.0, None
    taus, preds, overs, fracs, fired = [], [], [], [], []
    while tau < t_max:
        d = tick()
        tau += d
        if self_end:
            come = cells.delay_over((a, b))  # read at the previous tick, seen now
        else:
            come = delay is not None and tau >= delay - d / 2
        out = advance(b if come else a, d)
        if (a, b) in out["fired"]:
            fired.append(tau)
        if come:
            end = tau
            break
        r = out["readouts"].get((a, b))
        taus.append(tau)
        preds.append(0.0 if r is None else r.prediction)
        overs.append(bool(r is not None and r.delay_over))
        fracs.append(0.0 if r is None else r.elapsed_fraction)
    states = ([b] if end is not None else []) + ([other] if other is not None else [])
    for state in states:
        t = 0.0
        while t < after:
            d = tick()
            t += d
            advance(state, d)
    return TrialTrace(np.array(taus), np.array(preds), np.array(overs, dtype=bool),
                      np.array(fracs), fired, end)


@dataclass(frozen=True)
class Reproduction:
    """Closed-loop reproduction of one taught delay (see :func:`reproduce`).

    waits: the reproduced waits (s), one per closed-loop trial (nan if it never ended).
    learned: the delay stored after teaching (population readout of the weights, s).
    non_occurrence_lag: in a final trial without the event, how long after ``delay`` the
    non-occurrence neuron fired (s; nan if it did not).
    """

    delay: float
    waits: list[float]
    learned: float
    non_occurrence_lag: float


def reproduce(delay: float, *, seed: int = 0, teacher: int = 3, loops: int = 5,
              dt: float = 0.2, jitter: float = 0.1) -> Reproduction:
    """Teach ``0 -> 1`` at ``delay`` ``teacher`` times, then let the system end ``loops`` waits.

    Each closed-loop wait ends one tick after ``delay_over`` rises, and is learned again (the
    patrol's loop). A fresh learner per call; ``seed`` fixes the tick jitter.
    """
    rng = np.random.default_rng(check_seed("seed", seed))
    chain = TimingChain()
    kw = {"dt": dt, "jitter": jitter, "rng": rng, "other": 2}
    for _ in range(teacher):
        run_trial(chain, 0, 1, delay, **kw)
    learned = chain.cells.learned_delay((0, 1))
    waits = []
    for _ in range(loops):
        rep = run_trial(chain, 0, 1, None, self_end=True, t_max=3 * delay, **kw)
        waits.append(np.nan if rep.end is None else rep.end)
    ext = run_trial(chain, 0, 1, None, t_max=2 * delay + 5, **kw)
    lag = ext.fired[0] - delay if ext.fired else np.nan
    return Reproduction(delay, waits, learned, lag)
