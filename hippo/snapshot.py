"""Save a whole learning robot (or any part of it) and restore it bit for bit, in open formats.

:func:`save_snapshot` writes the complete state of an object graph — an :class:`~hippo.agent.Agent`
with its place cells, prototypes, state layer, timing batteries and weights, transition graph,
drives, planner and random generators, or any one of those parts — into a folder:

``state.json``   the object graph as standard JSON (no NaN tokens): each hippo object as its class
                 and attributes, containers and numbers as tagged JSON values, enum members
                 (``Mode``, ``StateKind``) as their class and value, shared objects and
                 arrays written once and referred to by number, random generators by their
                 bit-generator state, networkx graphs by their nodes and edges;
``arrays.npz``   every numpy array, by number (``allow_pickle=False``);
``manifest.json``  format, hippo version, the SHA-256 of the two files above, and the class.

Each file is written atomically (:mod:`hippo.io`), the manifest last, so a crash mid-save leaves the
previous snapshot loadable or a snapshot whose checksums do not match (refused on loading), never a
silently mixed one. :func:`load_snapshot` trusts nothing: it checks the checksums, accepts only the
tags below, builds only classes defined in the ``hippo`` package (never an arbitrary callable: no
pickle, no code from the file runs), checks every array against its recorded dtype and shape, and
raises :class:`~hippo.io.CorruptFileError` for anything else. Restoring sets the attributes
directly (``__init__`` is not run), so the restored object continues exactly where the saved one
stopped: same floats, same generator states, same shared references (a battery that two modules
share is still one battery).

Use the per-module formats (``RCSFAICA.save``, ``TransitionGraph.to_graphml``, ``Drives.save``) to
exchange one trained part with other tools; use a snapshot to stop and resume a robot.
"""

from __future__ import annotations

import collections
import enum
import hashlib
import json
import math
import os
import shutil
import types
from pathlib import Path
from typing import Any

import networkx as nx
import numpy as np

from hippo._snapshot_decoder import _ARRAY_DTYPES, _Decoder, _top_class
from hippo.io import CorruptFileError, atomic_write_text, load_json, load_npz, save_npz

SNAPSHOT_FORMAT = "hippo.snapshot/1"
_FILES = ("state.json", "arrays.npz", "manifest.json")


class SnapshotError(TypeError):
    """The object holds something a snapshot cannot store (named with its attribute path)."""


# ----------------------------------------------------------------------------- encoding
class _Encoder:
    def __init__(self) -> None:
        self.arrays: dict[str, np.ndarray] = {}
        self.memo: dict[int, int] = {}
        self.keep: list[Any] = []  # keeps encoded objects alive so their ids stay unique
        self.n_refs = 0

    def _ref(self, obj: Any) -> dict[str, Any] | None:
        r = self.memo.get(id(obj))
        return None if r is None else {"$ref": r}

    def _remember(self, obj: Any) -> int:
        r = self.n_refs
        self.n_refs += 1
        self.memo[id(obj)] = r
        self.keep.append(obj)
        return r

    def enc(self, obj: Any, path: str) -> Any:
        if isinstance(obj, enum.Enum):  # before str and int: an IntEnum is an int too
            _check_class(type(obj), path)
            return {"$enum": f"{type(obj).__module__}:{type(obj).__qualname__}",
                    "v": self.enc(obj.value, f"{path}.value")}
        if obj is None or isinstance(obj, bool | str):
            return obj
        if isinstance(obj, int) and not isinstance(obj, np.integer):
            return obj
        if isinstance(obj, float) and not isinstance(obj, np.floating):
            return obj if math.isfinite(obj) else {"$float": repr(obj)}
        if isinstance(obj, np.generic):
            if obj.dtype.kind not in _ARRAY_DTYPES:
                raise SnapshotError(f"{path}: numpy scalar of dtype {obj.dtype}")
            v = obj.item()
            if isinstance(v, float) and not math.isfinite(v):
                v = repr(v)
            return {"$np": obj.dtype.str, "v": v}
        seen = self._ref(obj)
        if seen is not None:
            return seen
        if isinstance(obj, np.ndarray):
            if obj.dtype.kind not in _ARRAY_DTYPES:
                raise SnapshotError(f"{path}: array of dtype {obj.dtype} (object arrays are not "
                                    "stored)")
            r = self._remember(obj)
            self.arrays[f"a{r}"] = np.array(obj, copy=True)
            return {"$array": r, "dtype": obj.dtype.str, "shape": list(obj.shape),
                    "writeable": bool(obj.flags.writeable)}
        if isinstance(obj, tuple) and type(obj) is not tuple:  # a NamedTuple
            _check_class(type(obj), path)
            return {"$namedtuple": f"{type(obj).__module__}:{type(obj).__qualname__}",
                    "items": [self.enc(v, f"{path}[{i}]") for i, v in enumerate(obj)]}
        if isinstance(obj, tuple):
            return {"$tuple": [self.enc(v, f"{path}[{i}]") for i, v in enumerate(obj)]}
        if isinstance(obj, list):
            r = self._remember(obj)
            return {"$list": [self.enc(v, f"{path}[{i}]") for i, v in enumerate(obj)], "id": r}
        if isinstance(obj, collections.deque):
            r = self._remember(obj)
            return {"$deque": [self.enc(v, f"{path}[{i}]") for i, v in enumerate(obj)],
                    "maxlen": obj.maxlen, "id": r}
        if isinstance(obj, frozenset | set):
            kind = "$frozenset" if isinstance(obj, frozenset) else "$set"
            r = self._remember(obj)
            items = [self.enc(v, f"{path}{{}}") for v in obj]
            items.sort(key=lambda e: json.dumps(e, sort_keys=True))  # a stable file
            return {kind: items, "id": r}
        if isinstance(obj, dict):
            r = self._remember(obj)
            return {"$dict": [[self.enc(k, f"{path}.key"), self.enc(v, f"{path}[{k!r}]")]
                              for k, v in obj.items()], "id": r}
        if isinstance(obj, Path):
            return {"$path": str(obj)}
        if isinstance(obj, np.random.Generator):
            r = self._remember(obj)
            st = obj.bit_generator.state
            return {"$rng": type(obj.bit_generator).__name__,
                    "state": self.enc(st, f"{path}.state"), "id": r}
        if isinstance(obj, nx.Graph):
            r = self._remember(obj)
            return {"$nx": type(obj).__name__, "id": r,
                    "graph": self.enc(dict(obj.graph), f"{path}.graph"),
                    "nodes": self.enc([(n, dict(d)) for n, d in obj.nodes(data=True)],
                                      f"{path}.nodes"),
                    "edges": self.enc([(u, v, dict(d)) for u, v, d in obj.edges(data=True)],
                                      f"{path}.edges")}
        if isinstance(obj, types.MethodType):  # a bound method of a hippo object (a callback)
            owner = obj.__self__
            _check_class(type(owner), path)
            return {"$method": obj.__func__.__name__, "self": self.enc(owner, f"{path}.self")}
        if isinstance(obj, np.dtype):
            return {"$dtype": obj.str}
        if isinstance(obj, type) and issubclass(obj, np.generic):
            return {"$nptype": np.dtype(obj).str}
        cls = type(obj)
        if isinstance(obj, type):
            _check_class(obj, path)
            return {"$class": f"{obj.__module__}:{obj.__qualname__}"}
        _check_class(cls, path)
        custom = getattr(cls, "__snapshot_state__", None)
        if custom is not None:  # the class says what its state is (e.g. World: no pymunk)
            r = self._remember(obj)
            try:
                st = obj.__snapshot_state__()
            except TypeError as exc:
                raise SnapshotError(f"{path}: {exc}") from None
            return {"$custom": f"{cls.__module__}:{cls.__qualname__}", "id": r,
                    "state": self.enc(st, f"{path}.state")}
        r = self._remember(obj)
        state = _attributes(obj)
        return {"$obj": f"{cls.__module__}:{cls.__qualname__}", "id": r,
                "state": {k: self.enc(v, f"{path}.{k}") for k, v in state.items()}}


def _check_class(cls: type, path: str) -> None:
    if not (cls.__module__ == "hippo" or cls.__module__.startswith("hippo.")):
        raise SnapshotError(f"{path}: cannot store a {cls.__module__}.{cls.__qualname__} "
                            "(only hippo objects, numpy arrays and generators, networkx "
                            "graphs and plain containers)")
    if "<locals>" in cls.__qualname__:
        raise SnapshotError(f"{path}: {cls.__qualname__} is defined inside a function")


def _attributes(obj: Any) -> dict[str, Any]:
    state: dict[str, Any] = {}
    for klass in type(obj).__mro__:
        for name in getattr(klass, "__slots__", ()):
            if name not in ("__dict__", "__weakref__") and hasattr(obj, name):
                state[name] = getattr(obj, name)
    state.update(getattr(obj, "__dict__", {}))
    return state


# ---------------------------------------------------------------------------- public API
def _sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def save_snapshot(obj: Any, folder: str | os.PathLike) -> Path:
    """Write the whole state of ``obj`` (a hippo object and everything it holds, or a dict,
    tuple or list of such parts, e.g. ``{"agent": agent, "world": world}``) to ``folder``.

    Raises :class:`SnapshotError` naming the attribute that cannot be stored (e.g. an open
    simulator or a lambda). Returns the folder.
    """
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise NotADirectoryError(f"{folder} is a file: a snapshot is a folder (give a new or "
                                 "an existing folder)")
    enc = _Encoder()
    tree = enc.enc(obj, type(obj).__name__)
    text = json.dumps(tree, allow_nan=False, separators=(",", ":"))
    created = not folder.exists()
    try:
        folder.mkdir(parents=True, exist_ok=True)
        save_npz(folder / "arrays.npz", enc.arrays)
        atomic_write_text(folder / "state.json", text)
        from hippo import __version__

        manifest = {"format": SNAPSHOT_FORMAT, "hippo": __version__,
                    "class": f"{type(obj).__module__}:{type(obj).__qualname__}",
                    "sha256": {n: _sha256(folder / n) for n in ("state.json", "arrays.npz")}}
        atomic_write_text(folder / "manifest.json", json.dumps(manifest, indent=2) + "\n")
    except BaseException:
        # interrupted (Ctrl-C, a full disk): a folder this call made goes again; an old
        # snapshot partly overwritten no longer matches its manifest and is refused on load
        if created:
            shutil.rmtree(folder, ignore_errors=True)
        raise
    return folder


def load_snapshot(folder: str | os.PathLike, expect: type | None = None) -> Any:
    """Restore the object saved by :func:`save_snapshot` in ``folder``.

    ``expect``: the class the snapshot must hold (checked before anything is built). A damaged,
    mixed or foreign snapshot raises :class:`~hippo.io.CorruptFileError`.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise FileNotFoundError(f"no snapshot folder {folder}")
    missing = [n for n in _FILES if not (folder / n).is_file()]
    if missing:
        raise CorruptFileError(f"{folder} is not a complete snapshot (missing {missing})")
    man = load_json(folder / "manifest.json")
    if not isinstance(man, dict) or man.get("format") != SNAPSHOT_FORMAT:
        raise CorruptFileError(f"{folder}/manifest.json is not a hippo snapshot manifest")
    sums = man.get("sha256")
    if not isinstance(sums, dict):
        raise CorruptFileError(f"{folder}/manifest.json lacks the checksums")
    for n in ("state.json", "arrays.npz"):
        if sums.get(n) != _sha256(folder / n):
            raise CorruptFileError(f"{folder}/{n} does not match its checksum (damaged, or "
                                   "written by another save)")
    cls = _top_class(man.get("class"))
    if expect is not None and not issubclass(cls, expect):
        raise CorruptFileError(f"{folder} holds a {cls.__qualname__}, not a {expect.__qualname__}")
    arrays = load_npz(folder / "arrays.npz")
    tree = load_json(folder / "state.json")
    try:
        obj = _Decoder(arrays).dec(tree)
    except CorruptFileError as exc:
        raise CorruptFileError(f"{folder}: {exc}") from exc
    except Exception as exc:  # any failure to rebuild from the file is a damaged snapshot
        raise CorruptFileError(f"{folder}: bad snapshot content ({exc!r:.200})") from exc
    if type(obj) is not cls:
        raise CorruptFileError(f"{folder}: the state holds a {type(obj).__qualname__}, the "
                               f"manifest says {cls.__qualname__}")
    return obj


def same_state(a: Any, b: Any) -> bool:
    """True when two object graphs hold the same state, bit for bit (NaN equals NaN)."""
    return (json.dumps(_Encoder().enc(a, "a"), sort_keys=True)
            == json.dumps(_Encoder().enc(b, "b"), sort_keys=True)
            and _arrays_equal(a, b))


def _arrays_equal(a: Any, b: Any) -> bool:
    ea, eb = _Encoder(), _Encoder()
    ea.enc(a, "a")
    eb.enc(b, "b")
    if ea.arrays.keys() != eb.arrays.keys():
        return False
    return all(x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes()
               for x, y in ((ea.arrays[k], eb.arrays[k]) for k in ea.arrays))


__all__ = ["SNAPSHOT_FORMAT", "SnapshotError", "load_snapshot", "same_state", "save_snapshot"]
