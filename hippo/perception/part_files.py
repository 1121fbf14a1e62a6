"""Each layer of RC-SFA-ICA saves and loads its own state (one ``.npz``, no pickle).

A part (:class:`~hippo.perception.reservoir.Reservoir`, :class:`~hippo.perception.sfa.SFA`,
:class:`~hippo.perception.ica.FastICA`) exports what its parameters cannot rebuild as named
arrays and restores itself from them, trusting nothing::

    part.to_arrays(prefix="")                   -> {prefix + key: array}  (copies)
    Part.from_arrays(params, arrays, prefix="") -> the fitted part, or ValueError naming the key
    part.save(path) / Part.load(path)           one .npz: "format", "params" (JSON), the arrays

``from_arrays`` refuses a missing or an unknown key, a wrong dtype or shape, NaN or inf, a
magnitude no fit produces (> 1e12), and whatever breaks the part's own invariants (an SFA scale
<= 0, an ICA rotation that is not orthonormal, a reservoir whose leak or spectral radius is not
its parameters'). ``load`` also checks the format tag (the kind of part and its version) and
the parameters (as their constructor does), and turns every refusal into
:class:`~hippo.io.CorruptFileError` (a ``ValueError``) naming the file.

The place-cell estimator's file (:mod:`~hippo.perception.place_cell_files`) is the parts'
arrays side by side, each part's keys under its prefix (``sfa_``, ``ica_``; the reservoir's
``W_in``, ``W_res``, ``leak`` as they are), so each part reads and checks its own keys.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Mapping
from dataclasses import asdict, fields
from pathlib import Path
from typing import Any, ClassVar, TypeVar

import numpy as np

from hippo._checks import check_array
from hippo.io import CorruptFileError, load_npz, save_npz

__all__ = ["MAX_ABS", "PartArrays", "PartFile", "check_format", "params_from_json",
           "params_json"]

#: no fitted array holds a larger magnitude; a loaded one that does is damaged
MAX_ABS = 1e12

P = TypeVar("P", bound="PartFile")


class PartArrays:
    """The arrays of one part (each key led by ``prefix``), read with checks that name the key.

    Construction refuses a missing ``required`` key and any key that is neither required nor
    ``optional`` (a file of another kind, or a damaged one).
    """

    def __init__(self, owner: str, arrays: Mapping[str, Any], prefix: str,
                 required: Iterable[str], optional: Iterable[str] = ()) -> None:
        self.arrays, self.prefix = arrays, prefix
        required = [prefix + k for k in required]
        known = {*required, *(prefix + k for k in optional)}
        missing = [k for k in required if k not in arrays]
        if missing:
            raise ValueError(f"the {owner} state lacks array(s) {', '.join(missing)}")
        extra = sorted(str(k) for k in arrays if k not in known)
        if extra:
            raise ValueError(f"the {owner} state has unknown array(s) {', '.join(extra)[:200]} "
                             f"(it holds {', '.join(sorted(known))})")

    def has(self, key: str) -> bool:
        return self.prefix + key in self.arrays

    def get(self, key: str, shape: tuple[int | None, ...], dtype: str = "float") -> np.ndarray:
        """The array ``prefix + key``: its kind, ``shape`` (None: any size), finite, at most
        :data:`MAX_ABS` in magnitude (a float64 / int64 copy)."""
        name = self.prefix + key
        return check_array(name, self.arrays[name], shape=shape, dtype=dtype, max_abs=MAX_ABS)


def params_json(params: Any) -> np.ndarray:
    """A parameter dataclass as a JSON string (a 0-d unicode array for an ``.npz``)."""
    return np.array(json.dumps(asdict(params)))


def params_from_json(cls: type, value: np.ndarray, *, ignore_unknown: bool = False) -> Any:
    """The parameter dataclass ``cls`` from a JSON string written by :func:`params_json`,
    checked as its constructor checks it. Lists become tuples (JSON has no tuples). Unknown
    names are refused, or dropped with ``ignore_unknown`` (a parameter a later version
    removed). Raises :class:`CorruptFileError` naming the problem."""
    if value.dtype.kind != "U" or value.shape != ():
        raise CorruptFileError("the parameters are not a JSON string")
    try:
        raw = json.loads(str(value))
    except (json.JSONDecodeError, RecursionError) as exc:
        raise CorruptFileError(f"unreadable parameters ({exc})") from exc
    if not isinstance(raw, dict):
        raise CorruptFileError(f"the parameters are not a JSON object: {str(raw)[:80]}")
    known = {f.name for f in fields(cls)}
    unknown = sorted(set(raw) - known)
    if unknown and not ignore_unknown:
        raise CorruptFileError(f"unknown {cls.__name__} parameter(s) {', '.join(unknown)[:200]}")
    raw = {k: tuple(v) if isinstance(v, list) else v for k, v in raw.items() if k in known}
    try:
        return cls(**raw)
    except (TypeError, ValueError, OverflowError) as exc:
        raise CorruptFileError(f"bad parameters ({exc})") from exc


def check_format(value: np.ndarray, expected: str, what: str) -> None:
    """Refuse a format tag other than ``expected`` (``what``: e.g. ``"a saved SFA"``); a tag of
    the same kind and another version is named as such."""
    tag = str(value)[:80] if value.dtype.kind == "U" and value.shape == () else None
    if tag == expected:
        return
    if tag is not None and tag.rsplit("/", 1)[0] == expected.rsplit("/", 1)[0]:
        raise CorruptFileError(f"{what} of format version {tag!r}: this hippo reads "
                               f"{expected!r}")
    shown = repr(tag) if tag is not None else f"{value!r:.80}"
    raise CorruptFileError(f"not {what} (format {shown}, expected {expected!r})")


class PartFile:
    """``save`` / ``load`` of a part, from its ``to_arrays`` and ``from_arrays``.

    A subclass sets ``FILE_FORMAT`` (``"hippo.perception.NAME/VERSION"``) and ``_PARAMS`` (its
    parameter dataclass, stored as ``self.params``), and implements ``to_arrays(prefix="")`` and
    the classmethod ``from_arrays(params, arrays, prefix="", **kw)``.
    """

    FILE_FORMAT: ClassVar[str]
    _PARAMS: ClassVar[type]
    params: Any

    def to_arrays(self, prefix: str = "") -> dict[str, np.ndarray]:  # pragma: no cover
        raise NotImplementedError

    @classmethod
    def from_arrays(cls: type[P], params: Any, arrays: Mapping[str, Any], prefix: str = "",
                    **kw: Any) -> P:  # pragma: no cover
        raise NotImplementedError

    def save(self, path: str | os.PathLike) -> Path:
        """Write the fitted part to ``path`` (.npz, atomic, no pickle): its format tag, its
        parameters as JSON, and :meth:`to_arrays`. A state that would not load (parameters
        changed by ``set_params`` after the fit) is refused with the loader's ``ValueError``
        and nothing is written."""
        arrays = self.to_arrays()
        type(self).from_arrays(self.params, arrays)
        return save_npz(path, {"format": np.array(self.FILE_FORMAT),
                               "params": params_json(self.params), **arrays})

    @classmethod
    def load(cls: type[P], path: str | os.PathLike, **kw: Any) -> P:
        """Read a part written by :meth:`save` (``kw`` go to :meth:`from_arrays`). Nothing is
        trusted: a damaged file, a file of another kind or version, bad parameters or arrays
        raise :class:`~hippo.io.CorruptFileError` naming the problem."""
        a = load_npz(path, required=("format", "params"))
        try:
            check_format(a.pop("format"), cls.FILE_FORMAT, f"a saved {cls.__name__}")
            params = params_from_json(cls._PARAMS, a.pop("params"))
            return cls.from_arrays(params, a, **kw)
        except (ValueError, TypeError, KeyError, IndexError, OverflowError) as exc:
            raise CorruptFileError(f"{path}: {exc}") from exc
