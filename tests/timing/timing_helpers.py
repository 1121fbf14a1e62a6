"""Shared trial runner for the timing tests: state A for a delay, then B (or nothing)."""

from __future__ import annotations

import numpy as np

from hippo.timing import NonOccurrence, SpectralTiming, TransitionCells

DT = 0.2


def make(seed: int = 0):
    timing = SpectralTiming()
    return timing, TransitionCells(timing), NonOccurrence(), np.random.default_rng(seed)


def tick(rng: np.random.Generator | None, jitter: float) -> float:
    if rng is None or jitter == 0:
        return DT
    return DT * (1.0 + rng.uniform(-jitter, jitter))


def trial(timing, cells, a: int, b: int, delay: float | None, *, rng=None, jitter=0.1,
          nonocc=None, self_end=False, t_max=None, other: int = 99):
    """Enter ``a`` (from ``other``), stay, then ``b`` comes at the tick nearest ``delay``.

    ``delay=None`` omits the event (extinction) until ``t_max``. ``self_end``: ``b`` comes one
    tick after ``delay_over`` of ``(a, b)`` rose (the agent's loop). Returns a dict with the
    elapsed times ``tau``, the predictions of ``(a, b)``, the delay-over flags, the ticks where
    the non-occurrence neuron fired, and ``end`` (time in ``a`` when ``b`` came, or None).
    """
    cells.step(timing.step(a, DT), DT)
    if nonocc is not None:
        nonocc.step(cells.readouts, DT)
    t_max = t_max if t_max is not None else 2.0 * (delay or 10.0) + 5.0
    tau, taus, preds, overs, fracs, fired, end = 0.0, [], [], [], [], [], None
    while tau < t_max:
        d = tick(rng, jitter)
        tau += d
        if self_end:
            come = cells.delay_over((a, b))  # decided at the previous tick, seen now
        else:
            come = delay is not None and tau >= delay - d / 2
        ro = cells.step(timing.step(b if come else a, d), d)
        if nonocc is not None and nonocc.step(ro, d):
            fired.append(tau)
        if come:
            end = tau
            break
        r = ro.get((a, b))
        taus.append(tau)
        preds.append(0.0 if r is None else r.prediction)
        overs.append(bool(r is not None and r.delay_over))
        fracs.append(0.0 if r is None else r.elapsed_fraction)
    for state in ((b, other) if end is not None else (other,)):  # then something else
        for _ in range(20):
            cells.step(timing.step(state, DT), DT)
            if nonocc is not None:
                nonocc.step(cells.readouts, DT)
    return {"tau": np.array(taus), "pred": np.array(preds), "over": np.array(overs),
            "frac": np.array(fracs),
            "fired": fired, "end": end}
