"""A dependency-free progress bar on stderr (silent when ``HIPPO_QUIET`` is set)."""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Iterable, Iterator
from typing import TypeVar

T = TypeVar("T")


class Progress:
    """Progress over ``total`` steps; call :meth:`update` and :meth:`close` (or use ``with``)."""

    def __init__(self, total: int, desc: str = "", *, enabled: bool | None = None,
                 min_interval: float = 0.25) -> None:
        self.total = max(int(total), 1)
        self.desc = desc
        self.n = 0
        if enabled is None:
            enabled = not os.environ.get("HIPPO_QUIET")
        self.enabled = enabled
        self._tty = sys.stderr.isatty()
        self._t0 = time.perf_counter()
        self._last = 0.0
        self._min_interval = min_interval if self._tty else max(min_interval, 5.0)

    def update(self, n: int = 1) -> None:
        self.n += n
        if not self.enabled:
            return
        now = time.perf_counter()
        if now - self._last >= self._min_interval or self.n >= self.total:
            self._last = now
            self._render(now)

    def _render(self, now: float) -> None:
        frac = min(self.n / self.total, 1.0)
        elapsed = now - self._t0
        eta = elapsed / frac - elapsed if frac > 0 else float("nan")
        bar = "#" * int(frac * 24)
        line = (f"{self.desc:>14} [{bar:<24}] {100 * frac:5.1f}% "
                f"{self.n}/{self.total} {elapsed:6.1f}s eta {eta:5.1f}s")
        end = "\r" if self._tty and self.n < self.total else "\n"
        sys.stderr.write(line + end)
        sys.stderr.flush()

    def close(self) -> None:
        if self.enabled and self.n < self.total and self._tty:
            sys.stderr.write("\n")

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def progress(it: Iterable[T], total: int | None = None, desc: str = "") -> Iterator[T]:
    """Wrap an iterable with a :class:`Progress` bar."""
    if total is None:
        total = len(it)  # type: ignore[arg-type]
    with Progress(total, desc) as bar:
        for x in it:
            yield x
            bar.update()
