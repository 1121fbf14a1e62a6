"""Input validation shared by every module: each failure names the problem."""

from __future__ import annotations

import dataclasses
import math
import numbers
import operator
import os
import types
import typing
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np


def as_array(name: str, value: Any) -> np.ndarray:
    """``np.asarray(value)``, or a ``ValueError`` naming ``name`` when it is no array at all
    (ragged nested lists, objects numpy cannot read)."""
    try:
        return np.asarray(value)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be an array of numbers, got {type(value).__name__} "
                         f"that numpy cannot read as one ({exc})") from None


def check_finite(name: str, value: Any, *, keep_float32: bool = False) -> np.ndarray:
    """Return ``value`` as a float array, or raise ``ValueError`` if it holds NaN or inf.

    With ``keep_float32`` a float32 array is returned as is (no float64 copy of a large
    recording); anything else becomes float64.
    """
    if type(value) is np.ndarray and value.dtype == np.float64:
        arr = value  # already what the conversions below would return (the per-tick case)
    else:
        arr = as_array(name, value)
    if arr.dtype != np.float64 and not (keep_float32 and arr.dtype == np.float32):
        if arr.dtype.kind == "c":   # a cast to float drops the imaginary part, silently
            raise ValueError(f"{name} must hold real numbers, got complex values "
                             f"(dtype {arr.dtype})")
        try:
            arr = np.asarray(arr, dtype=float)
        except (TypeError, ValueError) as exc:  # the same type (scikit-learn's convention)
            raise type(exc)(f"{name} must hold real numbers, got dtype {arr.dtype} "
                            f"({exc})") from None
    # one reduction on the hot path: a NaN or inf anywhere makes the sum non-finite
    if not math.isfinite(float(np.add.reduce(arr, axis=None))):
        bad = int(np.size(arr) - np.count_nonzero(np.isfinite(arr)))
        if bad:  # (a finite sum can only overflow when every value is finite)
            raise ValueError(f"{name} contains {bad} non-finite value(s) (NaN or inf)")
    return arr


def _number(name: str, value: Any) -> float:
    """``float(value)``, or a ``ValueError`` naming ``name``: a bool or a string (``"5"``,
    which ``float`` reads) is no number either."""
    if isinstance(value, bool | np.bool_ | str | bytes):
        raise ValueError(f"{name} must be a number, got {value!r}")
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None


def check_positive(name: str, value: float, *, allow_zero: bool = False) -> float:
    """Raise ``ValueError`` unless ``value`` is a finite number > 0 (or >= 0)."""
    if type(value) is float and 0.0 < value < math.inf:  # the usual case (every tick)
        return value
    v = _number(name, value)
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        rel = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"{name} must be finite and {rel}, got {value!r}")
    return v


def check_range(name: str, value: float, lo: float, hi: float, *,
                closed: str = "both") -> float:
    """Raise ``ValueError`` unless ``value`` lies in the interval.

    ``closed`` says which ends belong to it: ``both``, ``left``, ``right`` or ``neither``.
    """
    v = _number(name, value)
    ok_lo = v >= lo if closed in ("both", "left") else v > lo
    ok_hi = v <= hi if closed in ("both", "right") else v < hi
    if not (math.isfinite(v) and ok_lo and ok_hi):
        lb = "[" if closed in ("both", "left") else "("
        rb = "]" if closed in ("both", "right") else ")"
        raise ValueError(f"{name} must lie in {lb}{lo}, {hi}{rb}, got {value!r}")
    return v


def check_shape(name: str, arr: np.ndarray, shape: tuple[int | None, ...]) -> np.ndarray:
    """Raise ``ValueError`` unless ``arr`` has dims matching ``shape`` (None = any size)."""
    a = np.asarray(arr)
    if a.ndim != len(shape) or any(s is not None and s != d for s, d in zip(shape, a.shape)):
        want = "(" + ", ".join("*" if s is None else str(s) for s in shape) + (
            ",)" if len(shape) == 1 else ")")
        raise ValueError(f"{name} must have shape {want}, got {a.shape}")
    return a


def check_int(name: str, value: Any, *, lo: int | None = None, hi: int | None = None) -> int:
    """Return ``value`` as an ``int``, or raise ``ValueError`` naming it.

    Integers (Python or numpy) only: ``10.5``, ``10.0``, ``"10"`` and ``True`` are refused, so a
    computed float never silently becomes a size. ``lo`` / ``hi`` bound it (inclusive).
    """
    if isinstance(value, bool | np.bool_):
        raise ValueError(f"{name} must be an integer, got {value!r} (a bool)")
    try:
        v = operator.index(value)
    except TypeError:
        raise ValueError(f"{name} must be an integer, got {value!r} "
                         f"({type(value).__name__})") from None
    if (lo is not None and v < lo) or (hi is not None and v > hi):
        rng = (f">= {lo}" if hi is None else f"<= {hi}" if lo is None
               else f"in [{lo}, {hi}]")
        raise ValueError(f"{name} must be an integer {rng}, got {value!r}")
    return v


def check_seed(name: str, value: Any) -> int:
    """A seed for ``numpy.random.default_rng``: an integer in [0, 2**63)."""
    return check_int(name, value, lo=0, hi=2**63 - 1)


def check_path(name: str, value: Any) -> Path:
    """``value`` (a ``str`` or ``os.PathLike``) as a ``Path``; an empty string is refused, since
    ``Path("")`` is the current folder (an unset variable would write into the user's)."""
    if not isinstance(value, str | os.PathLike):
        raise TypeError(f"{name} must be a path (str or os.PathLike), got "
                        f"{type(value).__name__}")
    if not os.fspath(value):
        raise ValueError(f"{name} must not be an empty path (use '.' for the current folder)")
    return Path(value)


def check_choice(name: str, value: Any, choices: Iterable[Any]) -> Any:
    """Raise ``ValueError`` unless ``value`` is one of ``choices`` (compared with ==, same type)."""
    options = tuple(choices)
    for c in options:
        if type(value) is type(c) and value == c:
            return value
    listed = ", ".join(repr(c) for c in options)
    raise ValueError(f"{name} must be one of {listed}; got {value!r}")


def check_real(name: str, value: Any) -> float:
    """Return ``value`` as a finite ``float``; bools, strings, NaN and inf are refused."""
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real):
        raise ValueError(f"{name} must be a real number, got {value!r} "
                         f"({type(value).__name__})")
    v = float(value)
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return v


def is_wall_side(value: Any) -> bool:
    """Is ``value`` a wall side, the integer -1 (right) or +1 (left)? (``True`` and ``1.0``
    equal 1 but are no side.)"""
    return isinstance(value, int | np.integer) and not isinstance(value, bool | np.bool_) \
        and value in (-1, 1)


def check_wall_side(name: str, value: Any, *, none_ok: bool = False) -> int | None:
    """``value`` as a wall side (:func:`is_wall_side`; None too with ``none_ok``), or a
    ``ValueError`` naming ``name``: the one refusal of every place that takes a side."""
    if (value is None and none_ok) or is_wall_side(value):
        return None if value is None else int(value)
    allowed = "-1 (right wall), +1 (left wall) or None" if none_ok else \
        "-1 (right wall) or +1 (left wall)"
    raise ValueError(f"{name} must be {allowed}, got {value!r}")


def check_array(name: str, value: Any, *, shape: tuple[int | None, ...] | None = None,
                dtype: str = "float", finite: bool = True,
                max_abs: float | None = None) -> np.ndarray:
    """Check a loaded or given array: its kind (``float``: real numbers; ``int``: integers;
    ``bool``), its ``shape`` (None = any size), (numbers) finiteness, and ``|value| <= max_abs``.
    Returns a copy of type float64 / int64 / bool."""
    a = np.asarray(value)
    kind = a.dtype.kind
    if dtype == "float":
        if kind not in "fiu":
            raise ValueError(f"{name} must hold real numbers, got dtype {a.dtype}")
        a = a.astype(np.float64)
    elif dtype == "int":
        if kind not in "iu":
            raise ValueError(f"{name} must hold integers, got dtype {a.dtype}")
        a = a.astype(np.int64)
    elif dtype == "bool":
        if kind != "b":
            raise ValueError(f"{name} must hold booleans, got dtype {a.dtype}")
        a = a.copy()
    else:  # pragma: no cover - programming error
        raise ValueError(f"unknown dtype kind {dtype!r}")
    if shape is not None:
        check_shape(name, a, shape)
    if finite and dtype == "float" and not np.isfinite(a).all():
        bad = int(a.size - np.count_nonzero(np.isfinite(a)))
        raise ValueError(f"{name} contains {bad} non-finite value(s) (NaN or inf)")
    if max_abs is not None and a.size and dtype != "bool" and np.abs(a).max() > max_abs:
        raise ValueError(f"{name} holds a value of magnitude {np.abs(a).max():.3g}, beyond "
                         f"{max_abs:g}: no fit produces it")
    return a


def _hint_ok(value: Any, hint: Any) -> bool:
    """Does ``value`` fit the type hint? Unknown hints accept anything."""
    origin = typing.get_origin(hint)
    if hint is Any:
        return True
    if hint is type(None):
        return value is None
    if origin in (typing.Union, types.UnionType):
        return any(_hint_ok(value, h) for h in typing.get_args(hint))
    if origin is typing.Literal:
        return any(type(value) is type(c) and value == c for c in typing.get_args(hint))
    if hint is bool:
        return isinstance(value, bool | np.bool_)
    if hint is int:
        return isinstance(value, numbers.Integral) and not isinstance(value, bool | np.bool_)
    if hint is float:
        return (isinstance(value, numbers.Real) and not isinstance(value, bool | np.bool_)
                and math.isfinite(float(value)))
    if hint is str:
        return isinstance(value, str)
    if origin is tuple:
        args = typing.get_args(hint)
        if not isinstance(value, tuple):
            return False
        if len(args) == 2 and args[1] is Ellipsis:
            return all(_hint_ok(v, args[0]) for v in value)
        return len(args) == len(value) and all(_hint_ok(v, h) for h, v in zip(args, value))
    if isinstance(hint, type) and dataclasses.is_dataclass(hint):
        return isinstance(value, hint)
    return True


def _describe(hint: Any) -> str:
    origin = typing.get_origin(hint)
    if hint is type(None):
        return "None"
    if origin in (typing.Union, types.UnionType):
        return " or ".join(_describe(h) for h in typing.get_args(hint))
    if origin is typing.Literal:
        return "one of " + ", ".join(repr(c) for c in typing.get_args(hint))
    if origin is tuple:
        args = typing.get_args(hint)
        if len(args) == 2 and args[1] is Ellipsis:
            return f"a tuple of {_describe(args[0])}"
        return "a tuple (" + ", ".join(_describe(a) for a in args) + ")"
    names = {bool: "a bool", int: "an integer", float: "a finite real number", str: "a string"}
    return names.get(hint, getattr(hint, "__name__", str(hint)))


def check_fields(obj: Any) -> None:
    """Check every field of the dataclass ``obj`` against its annotated type.

    ``int`` fields take integers only (``10.5``, ``True`` refused), ``float`` fields finite real
    numbers, ``bool`` fields bools, ``str`` fields strings, ``Literal`` fields one of their
    values, nested parameter dataclasses their class; a field named ``seed`` must be an integer
    >= 0 (or None where allowed). The error names the class, the field, the value and what is
    allowed. Call it first in ``__post_init__``; range checks come after.
    """
    cls = type(obj)
    hints = _HINTS.get(cls)
    if hints is None:
        hints = typing.get_type_hints(cls)
        _HINTS[cls] = hints
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        hint = hints.get(f.name, Any)
        if not _hint_ok(value, hint):
            raise ValueError(f"{cls.__name__}.{f.name} must be {_describe(hint)}, "
                             f"got {value!r} ({type(value).__name__})")
        if f.name == "seed" and value is not None:
            check_seed(f"{cls.__name__}.seed", value)


_HINTS: dict[type, dict[str, Any]] = {}


def check_observation(obs: Any, n_sensors: int, last_t: float) -> tuple[np.ndarray, float]:
    """The per-tick check of a robot's observation; returns ``(ir, t)``.

    ``obs`` must carry ``ir`` (``n_sensors`` readings in [0, 1]), ``t`` (a finite time, not
    earlier than ``last_t``: a clock running backwards is refused), ``odometry``
    (3 finite numbers), ``floor`` (an integer colour id >= 0), ``sound`` and ``moving`` (bools).
    Cheap: float comparisons over the readings (NaN fails them too), a few scalar tests.
    """
    try:
        ir, t, odo = obs.ir, obs.t, obs.odometry
        floor, sound, moving = obs.floor, obs.sound, obs.moving
    except AttributeError as exc:
        raise ValueError(f"obs must be an Observation (ir, t, odometry, floor, sound, moving), "
                         f"got {type(obs).__name__} ({exc})") from None
    try:
        ir = np.asarray(ir, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"obs.ir must be {n_sensors} sensor readings, got {ir!r:.80}") from None
    if ir.shape != (n_sensors,):
        raise ValueError(f"obs.ir must have shape ({n_sensors},), got {ir.shape} ({ir!r:.80})")
    # a handful of numbers: plain float min, max and sum beat array reductions (a NaN, which
    # min and max may pass over, makes the sum NaN)
    vals = ir.tolist()
    if vals and not (min(vals) >= 0.0 and max(vals) <= 1.0 and sum(vals) == sum(vals)):
        raise ValueError(f"obs.ir readings must be finite and in [0, 1], got {ir}")
    real = type(t) is float or (isinstance(t, numbers.Real) and not isinstance(t, bool))
    if not real or not math.isfinite(t):
        raise ValueError(f"obs.t must be a finite time in s, got {t!r}")
    if not t >= last_t:
        raise ValueError(f"obs.t = {t!r} is earlier than the previous tick's {last_t!r}: "
                         "the clock must not run backwards")
    try:
        odo = np.asarray(odo, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"obs.odometry must be (dx, dy, dtheta), got {odo!r:.80}") from None
    if odo.shape != (3,) or not all(map(math.isfinite, odo.tolist())):
        raise ValueError(f"obs.odometry must be 3 finite numbers (dx, dy, dtheta), got {odo!r:.80}")
    if (type(floor) is not int and (isinstance(floor, bool | np.bool_)
                                    or not isinstance(floor, numbers.Integral))) or floor < 0:
        raise ValueError(f"obs.floor must be an integer colour id >= 0, got {floor!r}")
    for name, v in (("sound", sound), ("moving", moving)):
        if v is not True and v is not False and not isinstance(v, np.bool_):
            raise ValueError(f"obs.{name} must be True or False, got {v!r}")
    return ir, float(t)
