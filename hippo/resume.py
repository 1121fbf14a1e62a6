"""Checkpoints a long run can resume from after a crash, with nothing lost and nothing mixed.

:class:`Checkpoints` keeps numbered snapshots (:func:`hippo.snapshot.save_snapshot`) in one
folder and a pointer file ``latest.json`` naming the newest complete one. A checkpoint is
written whole into a new sub-folder first; only then does the pointer move to it (an atomic
replace), and only then are older ones removed. A crash at any moment therefore leaves the
pointer on a complete checkpoint (or no pointer: start afresh); a half-written sub-folder is
never read, and the next save or load removes it::

    ckpt = Checkpoints(out / "resume")
    state = ckpt.load()                  # None: nothing to resume, start from the beginning
    ...
    ckpt.save({"agent": agent, "world": world, "done": k})   # after each finished piece
"""

from __future__ import annotations

import json
import os
import re
import shutil
from pathlib import Path
from typing import Any

from hippo.io import CorruptFileError, atomic_write_text, load_json
from hippo.snapshot import load_snapshot, save_snapshot

__all__ = ["Checkpoints"]

# six digits or more: the millionth checkpoint is ckpt-1000000 (%06d pads, never cuts)
_NAME = re.compile(r"^ckpt-(\d{6,})$")


class Checkpoints:
    """Numbered, resumable snapshots in ``folder`` (see the module docstring)."""

    def __init__(self, folder: str | os.PathLike) -> None:
        self.folder = Path(folder)

    @property
    def pointer(self) -> Path:
        return self.folder / "latest.json"

    def latest(self) -> Path | None:
        """The newest complete checkpoint, or None if there is none."""
        if not self.pointer.exists():
            return None
        doc = load_json(self.pointer)
        name = doc.get("latest") if isinstance(doc, dict) else None
        if not isinstance(name, str) or not _NAME.match(name):
            raise CorruptFileError(f"{self.pointer}: not a checkpoint pointer ({doc!r})")
        return self.folder / name

    def _number(self) -> int:
        last = self.latest()
        return int(_NAME.match(last.name).group(1)) if last is not None else 0  # type: ignore[union-attr]

    def _prune(self, keep: Path | None) -> None:
        """Remove every checkpoint folder but ``keep`` (older ones, half-written ones)."""
        if not self.folder.is_dir():
            return
        for p in self.folder.iterdir():
            if p.is_dir() and _NAME.match(p.name) and p != keep:
                shutil.rmtree(p, ignore_errors=True)

    def save(self, obj: Any) -> Path:
        """Write ``obj`` as the newest checkpoint; returns its folder."""
        self.folder.mkdir(parents=True, exist_ok=True)
        target = self.folder / f"ckpt-{self._number() + 1:06d}"
        if target.exists():  # left by a crash before the pointer moved
            shutil.rmtree(target)
        save_snapshot(obj, target)
        atomic_write_text(self.pointer, json.dumps({"latest": target.name}) + "\n")
        self._prune(target)
        return target

    def load(self, expect: type | None = None) -> Any:
        """The newest checkpoint's object, or None if there is none (half-written folders
        are removed). A damaged checkpoint raises :class:`~hippo.io.CorruptFileError`."""
        last = self.latest()
        self._prune(last)
        return None if last is None else load_snapshot(last, expect)

    def clear(self) -> None:
        """Remove every checkpoint and the pointer (the run finished)."""
        self._prune(None)
        if self.pointer.exists():
            self.pointer.unlink()
        if self.folder.is_dir() and not any(self.folder.iterdir()):
            self.folder.rmdir()
