"""Checks of a saved robot's meta (what ``--save`` wrote beside it): each field within the
bounds its command-line option has, so that a hand-edited snapshot (checksums recomputed) is
refused on ``--load``, naming the field, before any work."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any


def finite(v: Any) -> bool:
    """A finite int or float (not a bool)."""
    return isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)


def bad_field(meta: dict, key: str, want: str) -> ValueError:
    return ValueError(f"the snapshot's meta {key}={meta[key]!r} is not {want}")


def check_whole(meta: dict, key: str, lo: int, hi: int) -> None:
    """``meta[key]`` is a whole number in ``[lo, hi]`` (JSON may write it as ``3.0``)."""
    v = meta[key]
    if not finite(v) or v != int(v) or not lo <= v <= hi:
        raise bad_field(meta, key, f"a whole number in [{lo}, {hi}]")


def check_number(meta: dict, key: str, lo: float, hi: float, unit: str = "") -> None:
    """``meta[key]`` is a finite number in ``[lo, hi]``."""
    if not finite(meta[key]) or not lo <= meta[key] <= hi:
        raise bad_field(meta, key, f"a number{' of ' + unit if unit else ''} in [{lo:g}, {hi:g}]")


def check_choice(meta: dict, key: str, choices: Sequence[Any]) -> None:
    """``meta[key]`` is one of ``choices``."""
    if meta[key] not in choices:
        raise bad_field(meta, key, f"one of {tuple(choices)}")
