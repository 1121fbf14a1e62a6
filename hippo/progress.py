"""Progress bars for long steps, on tqdm (terminals, CI logs and Jupyter notebooks alike).

``Progress(total, desc)`` counts steps (``update``); ``working(desc)`` shows the elapsed time of
one long step that cannot count itself (a fit). Both write to stderr and are silent when the
environment variable ``HIPPO_QUIET`` is set (the test suite sets it) or with ``enabled=False``.
Outside a terminal (a CI log) the bars refresh at most every 10 s.
"""

from __future__ import annotations

import os
import sys
import threading
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from typing import TypeVar

from tqdm.auto import tqdm

T = TypeVar("T")


def _enabled(enabled: bool | None) -> bool:
    return (not os.environ.get("HIPPO_QUIET")) if enabled is None else bool(enabled)


def _interval(min_interval: float) -> float:
    return min_interval if sys.stderr.isatty() else max(min_interval, 10.0)


class Progress:
    """Progress over ``total`` steps; call :meth:`update` and :meth:`close` (or use ``with``)."""

    def __init__(self, total: int, desc: str = "", *, enabled: bool | None = None,
                 min_interval: float = 0.25) -> None:
        self.total = max(int(total), 1)
        self.desc = desc
        self.enabled = _enabled(enabled)
        self._bar = tqdm(total=self.total, desc=desc, disable=not self.enabled, file=sys.stderr,
                         mininterval=_interval(min_interval), dynamic_ncols=True, leave=True)

    @property
    def n(self) -> int:
        """Steps done so far."""
        return int(self._bar.n)

    def update(self, n: int = 1) -> None:
        """Count ``n`` more steps."""
        self._bar.update(n)

    def close(self) -> None:
        """End the bar (its last line stays)."""
        self._bar.close()

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


@contextmanager
def working(desc: str, *, enabled: bool | None = None, every: float = 0.5) -> Iterator[None]:
    """Show ``desc`` with the elapsed time while the ``with`` block runs (a step that cannot
    report its own progress, such as fitting the place cells)."""
    if not _enabled(enabled):
        yield
        return
    bar = tqdm(total=None, desc=desc, file=sys.stderr, bar_format="{desc}: {elapsed}",
               mininterval=_interval(every), leave=True)
    stop = threading.Event()

    def tick() -> None:
        while not stop.wait(_interval(every)):
            bar.refresh()

    thread = threading.Thread(target=tick, daemon=True)
    thread.start()
    end = "done"
    try:
        yield
    except BaseException:
        end = "stopped"
        raise
    finally:
        stop.set()
        thread.join()
        bar.set_description_str(f"{desc} ({end})", refresh=False)
        bar.close()
