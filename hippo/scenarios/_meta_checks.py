"""Checks of a saved robot's meta (what ``--save`` wrote beside it): each field within the
bounds its command-line option has (:mod:`hippo.cli_args`), so that a hand-edited snapshot
(checksums recomputed) is refused on ``--load``, naming the field, before any work. Choices and
numbers go through :mod:`hippo._checks`; whole numbers are checked here, since a saved option
may come back from JSON as ``40.0``."""

from __future__ import annotations

import math
from typing import Any

from hippo._checks import check_choice, check_range, check_real


def field(key: str) -> str:
    """How an error names a meta field."""
    return f"the snapshot's meta {key}"


def finite(v: Any) -> bool:
    """A finite int or float (not a bool); an integer past the floats' range (JSON holds any)
    is not (math.isfinite would raise OverflowError on it)."""
    if not isinstance(v, int | float) or isinstance(v, bool):
        return False
    try:
        return math.isfinite(v)
    except OverflowError:
        return False


def bad_field(meta: dict, key: str, want: str) -> ValueError:
    return ValueError(f"{field(key)}={meta[key]!r} is not {want}")


def check_whole(meta: dict, key: str, bounds: tuple[int, int]) -> None:
    """``meta[key]`` is a whole number within ``bounds`` (JSON may write it as ``3.0``)."""
    v, (lo, hi) = meta[key], bounds
    if not finite(v) or v != int(v) or not lo <= v <= hi:
        raise bad_field(meta, key, f"a whole number in [{lo}, {hi}]")


def check_number(meta: dict, key: str, bounds: tuple[float, float]) -> None:
    """``meta[key]`` is a finite number within ``bounds``."""
    v = meta[key]
    if isinstance(v, int) and not isinstance(v, bool) and not finite(v):
        # past the floats' range: out of bounds (check_real's float() would overflow)
        raise ValueError(f"{field(key)} must lie in [{bounds[0]}, {bounds[1]}], got {v!r}")
    check_range(field(key), check_real(field(key), v), *bounds)


def check_option(meta: dict, key: str, choices: tuple[Any, ...]) -> None:
    """``meta[key]`` is one of ``choices`` (of the same type: ``1`` is not ``True``)."""
    check_choice(field(key), meta[key], choices)
