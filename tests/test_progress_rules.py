"""The progress bars' rules: the total (at least 1, whole steps), when a bar shows (HIPPO_QUIET
unset or empty, or enabled given), the refresh interval (as asked on a terminal, at least 10 s
in a log), the wrapped iterable's total, and the timed step's last line, each checked against
the documented rule on tqdm's own attributes or on what reaches stderr."""

from __future__ import annotations

import io
import sys
from typing import Any, ClassVar

import pytest

import hippo.progress as progress_module
from hippo.progress import Progress, progress, working


class _Tty(io.StringIO):
    def isatty(self) -> bool:
        return True


class _Log(io.StringIO):
    def isatty(self) -> bool:
        return False


@pytest.mark.parametrize("total, kept", [(0, 1), (-3, 1), (1, 1), (2.9, 2), (7, 7)])
def test_the_total_is_whole_steps_and_at_least_one(total, kept):
    bar = Progress(total, enabled=False)
    assert bar.total == kept and bar._bar.total == kept
    assert bar.desc == ""                               # no description by default
    bar.close()


def test_quiet_unless_enabled(monkeypatch):
    monkeypatch.setenv("HIPPO_QUIET", "1")
    assert Progress(3).enabled is False and Progress(3)._bar.disable is True
    assert Progress(3, enabled=True).enabled is True
    assert Progress(3, enabled=True)._bar.disable is False
    monkeypatch.setenv("HIPPO_QUIET", "")           # empty: not quiet
    assert Progress(3).enabled is True
    monkeypatch.delenv("HIPPO_QUIET")
    assert Progress(3).enabled is True
    assert Progress(3, enabled=False).enabled is False
    assert Progress(3, enabled=0).enabled is False  # type: ignore[arg-type]
    assert Progress(3, enabled=1).enabled is True   # type: ignore[arg-type]


def test_the_refresh_interval_on_a_terminal_and_in_a_log(monkeypatch):
    monkeypatch.setattr(sys, "stderr", _Tty())
    assert Progress(3, enabled=True)._bar.mininterval == 0.25
    assert Progress(3, enabled=True, min_interval=0.5)._bar.mininterval == 0.5
    assert progress_module._interval(0.1) == 0.1
    monkeypatch.setattr(sys, "stderr", _Log())
    assert Progress(3, enabled=True)._bar.mininterval == 10.0
    assert Progress(3, enabled=True, min_interval=12.0)._bar.mininterval == 12.0
    assert progress_module._interval(10.0) == 10.0
    assert progress_module._interval(9.5) == 10.0


def test_a_bar_counts_its_steps_and_writes_its_description(monkeypatch):
    err = _Log()
    monkeypatch.setattr(sys, "stderr", err)
    with Progress(0, "nothing to do", enabled=True) as bar:
        assert bar.n == 0 and type(bar.n) is int
        bar.update()
        assert bar.n == 1
    text = err.getvalue()
    assert text.startswith("\rnothing to do: ") and "1/1" in text
    with Progress(5, "five", enabled=True) as bar:
        bar.update(2)
        bar.update(3)
        assert bar.n == 5 and bar.desc == "five"
    assert "5/5" in err.getvalue()
    assert bar._bar.leave is True and callable(bar._bar.dynamic_ncols)   # asked: True


class _Recorder:
    made: ClassVar[list[_Recorder]] = []

    def __init__(self, total: int, desc: str = "") -> None:
        self.total, self.desc, self.steps = total, desc, 0
        _Recorder.made.append(self)

    def update(self, n: int = 1) -> None:
        self.steps += n

    def __enter__(self) -> _Recorder:
        return self

    def __exit__(self, *exc: object) -> None:
        pass


def test_progress_wraps_an_iterable_with_its_length_or_the_given_total(monkeypatch):
    monkeypatch.setattr(progress_module, "Progress", _Recorder)
    _Recorder.made.clear()
    assert list(progress([4, 5, 6], desc="list")) == [4, 5, 6]
    assert list(progress((i for i in range(2)), total=9, desc="gen")) == [0, 1]
    assert list(progress("ab")) == ["a", "b"]
    a, b, c = _Recorder.made
    assert (a.total, a.desc, a.steps) == (3, "list", 3)
    assert (b.total, b.desc, b.steps) == (9, "gen", 2)
    assert (c.total, c.desc, c.steps) == (2, "", 2)     # no description by default


def test_working_shows_nothing_when_disabled(monkeypatch):
    err = _Log()
    monkeypatch.setattr(sys, "stderr", err)
    monkeypatch.setenv("HIPPO_QUIET", "1")
    ran = []
    with working("fit"):
        ran.append(1)
    with working("fit", enabled=False):
        ran.append(2)
    assert ran == [1, 2] and err.getvalue() == ""
    monkeypatch.delenv("HIPPO_QUIET")
    with working("fit quiet"):
        ran.append(3)
    assert "fit quiet (done): 00:00" in err.getvalue()


def test_working_ends_with_done_or_stopped(monkeypatch):
    err = _Tty()
    monkeypatch.setattr(sys, "stderr", err)
    with working("step", enabled=True, every=0.01):
        pass
    assert err.getvalue().rstrip("\n").endswith("step (done): 00:00")
    err2 = _Tty()
    monkeypatch.setattr(sys, "stderr", err2)
    with pytest.raises(KeyboardInterrupt), working("step", enabled=True, every=0.01):
        raise KeyboardInterrupt
    assert err2.getvalue().rstrip("\n").endswith("step (stopped): 00:00")


def test_working_refreshes_every_interval(monkeypatch):
    refreshes: list[Any] = []
    made: list[dict[str, Any]] = []
    real = progress_module.tqdm

    def tqdm(*args: Any, **kw: Any) -> Any:
        made.append(kw)
        bar = real(*args, **kw)
        bar.refresh = lambda *a, **k: refreshes.append(1)   # type: ignore[method-assign]
        return bar

    import time

    monkeypatch.setattr(progress_module, "tqdm", tqdm)
    monkeypatch.setattr(sys, "stderr", _Tty())
    start = time.monotonic()
    with working("step", enabled=True, every=0.02):
        time.sleep(0.3)
    elapsed = time.monotonic() - start
    # one refresh per interval waited: never more than elapsed / 0.02
    assert 3 <= len(refreshes) <= elapsed / 0.02 + 1
    kw = made[0]
    assert kw["total"] is None and kw["bar_format"] == "{desc}: {elapsed}"
    assert kw["mininterval"] == 0.02 and kw["leave"] is True and kw["desc"] == "step"
