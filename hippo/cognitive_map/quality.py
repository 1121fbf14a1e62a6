"""How good a map's states are, measured the CSCG way (George et al., Nat. Commun. 2021).

A map's states are good when, knowing the state the robot is in, the next thing it will
perceive is predictable. CSCG reports the held-out next-observation prediction error in
bits per step; here the same is computed for any sequence of map states (learned places,
context-split states, ground-truth places) against the sequence of what comes next:

- :func:`next_state_bits` — fit ``P(next | state)`` on a training sequence (additive smoothing
  that backs off to the training marginal, so an unseen pair costs a finite number of bits),
  and return the mean ``−log2 P(next | state)`` over a held-out sequence;
- :func:`transitions_of` — the (state, next observation) pairs of an event sequence;
- :func:`states_per_place` — how many learned states each true place needs (the fewest that
  cover a given fraction of its visits): 1 is a clean map, more is a place split into several
  states (by direction, by context, or by drift).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Hashable, Sequence

import numpy as np

from hippo._checks import check_positive, check_range

__all__ = ["next_state_bits", "states_per_place", "transitions_of"]


def transitions_of(states: Sequence[Hashable],
                   observations: Sequence[Hashable] | None = None
                   ) -> tuple[list[Hashable], list[Hashable]]:
    """The pairs ``(state_k, observation_{k+1})`` of an event sequence.

    ``states[k]`` is the map state at event ``k``; ``observations[k]`` what was perceived at it
    (default: the states themselves, for a map whose states are its observations)."""
    obs = list(states) if observations is None else list(observations)
    if len(obs) != len(states):
        raise ValueError(f"states ({len(states)}) and observations ({len(obs)}) must have the "
                         f"same length")
    return list(states[:-1]), obs[1:]


def next_state_bits(train_states: Sequence[Hashable], train_next: Sequence[Hashable],
                    test_states: Sequence[Hashable], test_next: Sequence[Hashable], *,
                    prior: float = 1.0) -> float:
    r"""Held-out next-observation prediction error, bits per step.

    With counts :math:`c(s, n)` from the training pairs and the marginal
    :math:`m(n) = (c(n) + \tfrac12) / (N + \tfrac12 K)` over the :math:`K` symbols seen in
    training or test,

    .. math:: P(n \mid s) = \frac{c(s, n) + \text{prior}\; m(n)}{c(s) + \text{prior}},
              \qquad \text{bits} = -\frac{1}{T} \sum_{t} \log_2 P(n_t \mid s_t)

    over the :math:`T` test pairs (``prior`` pseudo-observations spread as the marginal). A
    state never seen in training predicts the marginal; a deterministic map whose test
    transitions were all seen in training often scores close to 0.
    """
    check_positive("prior", prior)
    for name, a, b in (("train", train_states, train_next), ("test", test_states, test_next)):
        if len(a) != len(b):
            raise ValueError(f"{name}_states ({len(a)}) and {name}_next ({len(b)}) must have "
                             f"the same length")
    if len(train_states) == 0 or len(test_states) == 0:
        raise ValueError("next_state_bits needs at least one training and one test pair")
    symbols = set(train_next) | set(test_next)
    k = len(symbols)
    marg = Counter(train_next)
    n_train = len(train_next)
    m = {s: (marg[s] + 0.5) / (n_train + 0.5 * k) for s in symbols}
    beta = prior
    pair = Counter(zip(train_states, train_next, strict=True))
    total = Counter(train_states)
    bits = [-np.log2((pair[(s, n)] + beta * m[n]) / (total[s] + beta))
            for s, n in zip(test_states, test_next, strict=True)]
    return float(np.mean(bits))


def states_per_place(states: Sequence[Hashable], places: Sequence[Hashable], *,
                     coverage: float = 0.9) -> dict[Hashable, int]:
    """For each true place, the fewest learned states that together hold ``coverage`` of the
    samples (ticks or events) the robot spent in it."""
    check_range("coverage", coverage, 0.0, 1.0, closed="right")
    if len(states) != len(places):
        raise ValueError(f"states ({len(states)}) and places ({len(places)}) must have the "
                         f"same length")
    by: dict[Hashable, Counter] = {}
    for s, p in zip(states, places, strict=True):
        by.setdefault(p, Counter())[s] += 1
    out = {}
    for p, c in by.items():
        counts = np.sort(np.fromiter(c.values(), dtype=float))[::-1]
        need = coverage * counts.sum()
        out[p] = int(np.searchsorted(np.cumsum(counts), need - 1e-9) + 1)
    return out
