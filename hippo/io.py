"""Open-format persistence: atomic ``.npz`` / JSON writes and checked loads (never pickle)."""

from __future__ import annotations

import io
import json
import math
import os
import tempfile
import time
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np


class CorruptFileError(ValueError):
    """A saved file is missing, truncated, not what it claims to be, or lacks required keys."""


#: a temporary file older than this (s) in a folder being written to is a leftover of a crash
STALE_AGE = 60.0


def _umask() -> int:
    """The process's umask (read by setting and restoring it; there is no getter)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def clean_stale_temps(folder: str | os.PathLike, *, max_age: float = STALE_AGE) -> list[Path]:
    """Remove the temporary files (``.NAME.*.tmp``) that a write killed mid-way left in
    ``folder``, if older than ``max_age`` seconds (a younger one may belong to a write in
    progress in another process). Returns the removed paths. Called by every atomic write."""
    folder = Path(folder)
    removed = []
    now = time.time()
    try:
        candidates = list(folder.glob(".*.tmp"))
    except OSError:
        return removed
    for p in candidates:
        try:
            if p.is_file() and now - p.stat().st_mtime > max_age:
                p.unlink()
                removed.append(p)
        except OSError:  # gone already, or not ours to remove
            continue
    return removed


def _atomic_write(path: Path, write) -> Path:
    """Write through a temporary file in the same folder, then ``os.replace`` it into place.

    The file gets the permissions a plain ``open(path, "w")`` would give (``0o666 & ~umask``;
    ``mkstemp`` alone would leave it ``0o600``); stale temporary files of killed writes in the
    folder are removed first.
    """
    path = Path(path)
    if path.is_dir():
        raise IsADirectoryError(f"{path} is a folder: give a file name to write to")
    path.parent.mkdir(parents=True, exist_ok=True)
    clean_stale_temps(path.parent)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        os.chmod(tmp, 0o666 & ~_umask())
        with os.fdopen(fd, "wb") as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
    return path


def atomic_write_text(path: str | os.PathLike, text: str, *, encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` atomically: a temp file in the same folder, then ``os.replace``.

    A crash or an exception while writing never leaves a half-written ``path`` behind.
    """
    data = text.encode(encoding)
    return _atomic_write(Path(path), lambda fh: fh.write(data))


def save_npz(path: str | os.PathLike, arrays: Mapping[str, Any], *, compress: bool = True) -> Path:
    """Write ``arrays`` to ``path`` atomically (a temp file renamed into place; no pickle).

    Object arrays are refused, so the file always loads with ``allow_pickle=False``.
    """
    clean = {}
    for k, v in arrays.items():
        a = np.asarray(v)
        if a.dtype == object:
            raise TypeError(f"array {k!r} has dtype object; store numbers or strings only")
        clean[k] = a
    saver = np.savez_compressed if compress else np.savez
    return _atomic_write(Path(path), lambda fh: saver(fh, **clean))


def load_npz(path: str | os.PathLike, required: Iterable[str] = ()) -> dict[str, np.ndarray]:
    """Load every array of an ``.npz`` file into a dict, with clear errors for bad files."""
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"no such file: {path}")
    if not path.is_file():
        raise CorruptFileError(f"{path} is not a file")
    try:
        data = np.load(path, allow_pickle=False)
        if not isinstance(data, np.lib.npyio.NpzFile):   # (a bare array is no context manager)
            raise ValueError("a single .npy array, not an .npz archive")
        with data:
            out = {k: data[k] for k in data.files}
    except Exception as exc:  # zip, zlib, header, dtype, size: any failure is a corrupt file
        why = repr(exc)
        if "pickle" in why:  # numpy's advice to allow pickles: hippo never loads one
            why = "neither a .npz archive nor a .npy array (numpy took it for pickled data)"
        raise CorruptFileError(f"{path} is not a readable .npz file ({why:.300})") from exc
    missing = [k for k in required if k not in out]
    if missing:
        raise CorruptFileError(f"{path} lacks required array(s): {', '.join(missing)}")
    return out


def _json_default(obj: Any) -> Any:
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"cannot write {type(obj).__name__} to JSON")


def _strict(obj: Any) -> Any:
    """``obj`` with every NaN or infinite number as ``None`` (JSON's null): strict JSON has no
    NaN, and other readers (``jq``, JavaScript's ``JSON.parse``) refuse the bare token."""
    if isinstance(obj, float | np.floating):
        return float(obj) if math.isfinite(obj) else None
    if isinstance(obj, np.ndarray):
        return _strict(obj.tolist()) if obj.dtype.kind in "fc" or obj.dtype == object \
            else obj.tolist()
    if isinstance(obj, dict):
        return {k: _strict(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_strict(v) for v in obj]
    return obj


def save_json(path: str | os.PathLike, obj: Any) -> Path:
    """Write ``obj`` as indented, strict JSON, atomically; numpy scalars and arrays are
    converted, and a NaN or infinite number is written as ``null`` (not measured)."""
    text = json.dumps(_strict(obj), indent=2, default=_json_default, allow_nan=False)
    return _atomic_write(Path(path), lambda fh: fh.write(text.encode()))


def load_json(path: str | os.PathLike) -> Any:
    """Read a JSON file, raising :class:`CorruptFileError` on malformed content."""
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"no such file: {path}")
    try:
        return json.loads(path.read_bytes().decode("utf-8"))
    except (ValueError, RecursionError) as exc:  # JSON, UTF-8, or absurdly nested
        raise CorruptFileError(f"{path} is not valid JSON ({exc!r:.300})") from exc


def save_figure(fig: Any, path: str | os.PathLike, **kwargs: Any) -> Path:
    """``fig.savefig(path, **kwargs)``, atomically (the format follows the file's suffix)."""
    path = Path(path)
    kwargs.setdefault("format", path.suffix.lstrip(".") or "png")
    buf = io.BytesIO()
    fig.savefig(buf, **kwargs)
    data = buf.getvalue()
    return _atomic_write(path, lambda fh: fh.write(data))
