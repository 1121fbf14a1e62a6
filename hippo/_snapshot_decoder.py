"""Reading a snapshot's object graph back (:func:`hippo.snapshot.load_snapshot`): only the tags
:mod:`hippo.snapshot` writes, only classes of the hippo package, every array checked; anything
else is a :class:`~hippo.io.CorruptFileError`."""

from __future__ import annotations

import collections
import enum
import importlib
import math
import types
from pathlib import Path
from typing import Any

import networkx as nx
import numpy as np

from hippo.io import CorruptFileError

#: numpy kinds a snapshot stores: bool, ints, floats, complex, text; never object
_ARRAY_DTYPES = set("biufcUS")


class _Decoder:
    def __init__(self, arrays: dict[str, np.ndarray]) -> None:
        self.arrays = arrays
        self.memo: dict[int, Any] = {}

    def _put(self, tag: dict[str, Any], obj: Any) -> Any:
        r = tag.get("id", tag.get("$array"))
        if not isinstance(r, int) or isinstance(r, bool) or r in self.memo:
            raise CorruptFileError(f"bad or repeated object number {r!r}")
        self.memo[r] = obj
        return obj

    def dec(self, e: Any) -> Any:
        if e is None or isinstance(e, bool | int | str):
            return e
        if isinstance(e, float):
            if not math.isfinite(e):
                raise CorruptFileError("a bare non-finite number in state.json")
            return e
        if not isinstance(e, dict) or not e:
            raise CorruptFileError(f"unexpected JSON value {str(e)[:80]}")
        tag = next(iter(e))
        if tag == "$ref":
            r = e["$ref"]
            if not isinstance(r, int) or r not in self.memo:
                raise CorruptFileError(f"reference to unknown object {r!r}")
            return self.memo[r]
        if tag == "$float":
            if e["$float"] not in ("nan", "inf", "-inf"):
                raise CorruptFileError(f"bad non-finite float {e['$float']!r}")
            return float(e["$float"])
        if tag == "$np":
            dt = np.dtype(_text(e["$np"]))
            if dt.kind not in _ARRAY_DTYPES:
                raise CorruptFileError(f"numpy scalar of dtype {dt}")
            v = e["v"]
            if isinstance(v, str) and dt.kind in "fc":
                v = float(v) if v in ("nan", "inf", "-inf") else _bad(v)
            return dt.type(v)
        if tag == "$array":
            key = f"a{e['$array']}"
            if key not in self.arrays:
                raise CorruptFileError(f"arrays.npz lacks array {key}")
            a = self.arrays[key]
            if a.dtype.str != e.get("dtype") or list(a.shape) != e.get("shape"):
                raise CorruptFileError(f"array {key} is {a.dtype.str} {list(a.shape)}, the "
                                       f"state says {e.get('dtype')} {e.get('shape')}")
            a = np.array(a, copy=True)
            if e.get("writeable") is False:
                a.flags.writeable = False
            return self._put(e, a)
        if tag == "$tuple":
            return tuple(self.dec(v) for v in _list(e["$tuple"]))
        if tag == "$namedtuple":
            cls = _import_class(e["$namedtuple"])
            if not issubclass(cls, tuple):
                raise CorruptFileError(f"{cls.__qualname__} is not a named tuple")
            return tuple.__new__(cls, [self.dec(v) for v in _list(e["items"])])
        if tag == "$list":
            out: list[Any] = self._put(e, [])
            out.extend(self.dec(v) for v in _list(e["$list"]))
            return out
        if tag == "$deque":
            maxlen = e.get("maxlen")
            if maxlen is not None and (not isinstance(maxlen, int) or maxlen < 0):
                raise CorruptFileError(f"bad deque maxlen {maxlen!r}")
            dq: collections.deque = self._put(e, collections.deque(maxlen=maxlen))
            dq.extend(self.dec(v) for v in _list(e["$deque"]))
            return dq
        if tag in ("$set", "$frozenset"):
            items = [self.dec(v) for v in _list(e[tag])]
            return self._put(e, set(items) if tag == "$set" else frozenset(items))
        if tag == "$dict":
            d: dict[Any, Any] = self._put(e, {})
            for pair in _list(e["$dict"]):
                if not isinstance(pair, list) or len(pair) != 2:
                    raise CorruptFileError("a dict item must be [key, value]")
                d[self.dec(pair[0])] = self.dec(pair[1])
            return d
        if tag == "$path":
            return Path(_text(e["$path"]))
        if tag == "$rng":
            name = _text(e["$rng"])
            if name not in ("PCG64", "PCG64DXSM", "Philox", "SFC64", "MT19937"):
                raise CorruptFileError(f"unknown bit generator {name!r}")
            bg = getattr(np.random, name)()
            gen = self._put(e, np.random.Generator(bg))
            bg.state = self.dec(e["state"])
            return gen
        if tag == "$nx":
            kinds = {"Graph": nx.Graph, "DiGraph": nx.DiGraph, "MultiGraph": nx.MultiGraph,
                     "MultiDiGraph": nx.MultiDiGraph}
            if e["$nx"] not in kinds:
                raise CorruptFileError(f"unknown networkx graph kind {e['$nx']!r}")
            g = self._put(e, kinds[e["$nx"]]())
            g.graph.update(self.dec(e["graph"]))
            for n, d in self.dec(e["nodes"]):
                g.add_node(n, **d)
            for u, v, d in self.dec(e["edges"]):
                g.add_edge(u, v, **d)
            return g
        if tag == "$method":
            owner = self.dec(e["self"])
            name = _text(e["$method"])
            cls = type(owner)
            if not (cls.__module__ == "hippo" or cls.__module__.startswith("hippo.")):
                raise CorruptFileError(f"a method of a non-hippo object {cls.__qualname__}")
            func = getattr(cls, name, None)
            if not callable(func) or name.startswith("__"):
                raise CorruptFileError(f"{cls.__qualname__} has no method {name!r}")
            return types.MethodType(func, owner)
        if tag in ("$dtype", "$nptype"):
            dt = np.dtype(_text(e[tag]))
            if dt.kind not in _ARRAY_DTYPES:
                raise CorruptFileError(f"dtype {dt} is not stored")
            return dt if tag == "$dtype" else dt.type
        if tag == "$class":
            return _import_class(e["$class"])
        if tag == "$enum":  # (a snapshot of before enums were tagged holds their plain value)
            cls = _import_class(e["$enum"])
            if not issubclass(cls, enum.Enum):
                raise CorruptFileError(f"{cls.__qualname__} is not an enum")
            try:
                return cls(self.dec(e["v"]))
            except (ValueError, TypeError):
                raise CorruptFileError(f"{e['v']!r:.80} is not a {cls.__qualname__}") from None
        if tag == "$custom":
            cls = _import_class(e["$custom"])
            restore = getattr(cls, "__snapshot_restore__", None)
            if restore is None:
                raise CorruptFileError(f"{cls.__qualname__} has no snapshot restore")
            r = e.get("id")
            obj = restore(self.dec(e["state"]))
            e = {"id": r}
            return self._put(e, obj)
        if tag == "$obj":
            cls = _import_class(e["$obj"])
            obj = self._put(e, cls.__new__(cls))
            state = e.get("state")
            if not isinstance(state, dict):
                raise CorruptFileError(f"{cls.__qualname__}: attributes must be an object")
            for k, v in state.items():
                object.__setattr__(obj, k, self.dec(v))
            return obj
        raise CorruptFileError(f"unknown tag {tag!r} in state.json")


def _bad(v: Any) -> Any:
    raise CorruptFileError(f"bad number {v!r}")


def _text(v: Any) -> str:
    if not isinstance(v, str):
        raise CorruptFileError(f"expected text, got {v!r:.80}")
    return v


def _list(v: Any) -> list[Any]:
    if not isinstance(v, list):
        raise CorruptFileError(f"expected a list, got {v!r:.80}")
    return v


_PLAIN_TOPS = {"builtins:dict": dict, "builtins:tuple": tuple, "builtins:list": list}


def _top_class(spec: Any) -> type:
    """The class a snapshot holds: a hippo class, or a dict/tuple/list of parts."""
    return _PLAIN_TOPS.get(spec) or _import_class(spec)


def _import_class(spec: Any) -> type:
    """A class defined in the hippo package, by ``module:QualName``; nothing else."""
    spec = _text(spec)
    module, _, qual = spec.partition(":")
    if not (module == "hippo" or module.startswith("hippo.")) or not qual:
        raise CorruptFileError(f"refusing to build {spec!r}: only hippo classes are restored")
    try:
        obj: Any = importlib.import_module(module)
        for part in qual.split("."):
            obj = getattr(obj, part)
    except (ImportError, AttributeError) as exc:
        raise CorruptFileError(f"unknown class {spec!r} ({exc})") from exc
    if not isinstance(obj, type) or not (obj.__module__ == "hippo"
                                         or obj.__module__.startswith("hippo.")):
        raise CorruptFileError(f"{spec!r} is not a hippo class")
    return obj
