"""Progress bars: counted steps and timed long steps on stderr, silent on request."""

from __future__ import annotations

import time

from hippo.progress import Progress, progress, working


def test_progress_counts_steps_on_stderr(capsys):
    with Progress(4, "exploration", enabled=True) as bar:
        for _ in range(4):
            bar.update()
        assert bar.n == 4
    err = capsys.readouterr().err
    assert "exploration" in err and "4/4" in err and "100%" in err


def test_progress_is_silent_when_quiet(capsys, monkeypatch):
    monkeypatch.setenv("HIPPO_QUIET", "1")
    with Progress(3, "quiet") as bar:
        bar.update(3)
    assert list(progress(range(3), desc="quiet too")) == [0, 1, 2]
    with working("fitting"):
        pass
    assert capsys.readouterr().err == ""


def test_working_reports_elapsed_time_and_the_end(capsys):
    with working("fitting place cells", enabled=True, every=0.05):
        time.sleep(0.2)
    err = capsys.readouterr().err
    assert "fitting place cells (done): 00:00" in err


def test_working_ends_its_thread_on_an_error(capsys):
    import threading

    from tqdm._monitor import TMonitor

    before = set(threading.enumerate())
    try:
        with working("failing", enabled=True, every=0.05):
            raise KeyError("x")
    except KeyError:
        pass
    # (tqdm's own monitor thread starts with the first bar shown in the process: not ours)
    assert [t for t in threading.enumerate()
            if t not in before and not isinstance(t, TMonitor)] == []
    assert "failing (stopped)" in capsys.readouterr().err
