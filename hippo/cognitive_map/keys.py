"""The map's keys: state ids and ``(a, b)`` transition keys, checked on the way in.

Every part of the cognitive map (the graph, the drives, the planner's inputs) keys a
transition by the tuple ``(a, b)`` of integer state ids, the same key as :mod:`hippo.timing`;
these two functions turn what a caller gives into that key or raise ``ValueError``.
"""

from __future__ import annotations

from collections.abc import Mapping, Set
from typing import Any

from hippo.types import Transition, check_state_id

__all__ = ["as_transition", "state_id"]


def state_id(value: Any, name: str = "state") -> int:
    """Return ``value`` as an ``int`` state id, or raise ``ValueError`` (the one rule of
    :func:`hippo.types.check_state_id`: an integer >= 0, no bools, no floats)."""
    return check_state_id(name, value)


def as_transition(t: Any) -> Transition:
    """Return ``t`` as an ``(a, b)`` tuple of ints, or raise ``ValueError``.

    A set or a mapping is no pair even with two ids (``{2, 1}`` unpacks as ``1, 2``, a dict
    as its keys), nor is a string (``"12"`` unpacks as two characters)."""
    if type(t) is not tuple and isinstance(t, str | bytes | Set | Mapping):
        raise ValueError(f"a transition is a pair (a, b) of state ids, got {t!r}")
    try:
        a, b = t
    except (TypeError, ValueError):
        raise ValueError(f"a transition is a pair (a, b) of state ids, got {t!r}") from None
    return state_id(a, "transition start state"), state_id(b, "transition end state")
