"""--cache: a cached recording is used only when it is whole and as long as asked; a damaged
or mismatched one is recorded again with a warning (it had been used: 'room cell nan')."""

import argparse

import pytest

from hippo.io import save_json
from hippo.scenarios._common import cached_recording
from hippo.sim import arenas
from hippo.sim.record import record


def _build(ticks, calls):
    def build():
        calls.append(ticks)
        return record(arenas.two_rooms(), ticks, seed=1, sensors="ir8", progress=False)
    return build


def test_a_cached_recording_is_read_back_when_it_matches(tmp_path):
    calls = []
    a = cached_recording(tmp_path, "k", _build(40, calls), 40)
    b = cached_recording(tmp_path, "k", _build(40, calls), 40)
    assert calls == [40] and len(b) == 40 and (b.sensors == a.sensors).all()


def test_a_short_or_damaged_cache_is_recorded_again(tmp_path):
    calls = []
    cached_recording(tmp_path, "k", _build(30, calls), 30)
    with pytest.warns(UserWarning, match="30 ticks, not 40"):
        rec = cached_recording(tmp_path, "k", _build(40, calls), 40)
    assert calls == [30, 40] and len(rec) == 40
    assert len(cached_recording(tmp_path, "k", _build(40, calls), 40)) == 40  # now kept
    (tmp_path / "k.npz").write_bytes(b"not a zip file")
    with pytest.warns(UserWarning, match="unusable"):
        rec = cached_recording(tmp_path, "k", _build(40, calls), 40)
    assert calls == [30, 40, 40] and len(rec) == 40


def test_a_damaged_kidnap_cache_is_recorded_again(tmp_path):
    from hippo.scenarios._two_rooms_recordings import _recordings

    args = argparse.Namespace(cache=str(tmp_path), rho=0.008)
    _, kid, events, kinds, moved = _recordings(args, arenas.two_rooms(), 1600, 600, 2)
    assert len(events) >= 2
    meta = next(tmp_path.glob("*_kid2.json"))
    again = _recordings(args, arenas.two_rooms(), 1600, 600, 2)   # read back, the same
    assert again[2:] == (events, kinds, moved) and (again[1].sensors == kid.sensors).all()
    for bad in ({"events": events, "kinds": kinds},                       # a key missing
                {"events": [10 ** 9], "kinds": kinds[:1], "moved": moved[:1]},  # past the end
                {"events": events, "kinds": kinds, "moved": moved[:-1]}):  # lengths differ
        save_json(meta, bad)
        with pytest.warns(UserWarning, match="kidnapped recording .* unusable"):
            out = _recordings(args, arenas.two_rooms(), 1600, 600, 2)
        assert out[2:] == (events, kinds, moved)


def test_a_new_run_in_a_folder_removes_the_last_runs_metrics(tmp_path):
    # a run that failed left the previous run's metrics.json looking like its own
    from hippo.scenarios._common import prepare_out

    (tmp_path / "metrics.json").write_text('{"seed": 0}')
    (tmp_path / "keep.png").write_bytes(b"")
    assert prepare_out(tmp_path) == tmp_path
    assert not (tmp_path / "metrics.json").exists() and (tmp_path / "keep.png").exists()


def test_the_closing_line_names_only_the_files_the_run_wrote(tmp_path, capsys):
    # it said "(metrics.json, figures, run.npz)" whatever was written: rooms writes no
    # run.npz, --no-figures no figure; a figure an earlier run left is not this run's
    from hippo.scenarios._common import prepare_out, write_metrics

    (tmp_path / "old.png").write_bytes(b"x")
    (tmp_path / "run.npz").write_bytes(b"x")
    out = prepare_out(tmp_path)
    (out / "place_cells.npz").write_bytes(b"y")
    write_metrics(out, {"quick": False})
    assert capsys.readouterr().err.strip().endswith("(metrics.json, place_cells.npz)")
    out = prepare_out(tmp_path)
    (out / "a.png").write_bytes(b"1")
    (out / "b.png").write_bytes(b"2")
    (out / "run.npz").write_bytes(b"new")
    write_metrics(out, {})
    assert capsys.readouterr().err.strip().endswith("(metrics.json, run.npz, 2 figures)")


def test_an_empty_output_or_cache_path_is_refused(tmp_path, monkeypatch):
    """Fifth fuzzing pass: Path("") is the current folder; the library helpers refuse an empty
    path as the command line does, before writing or removing anything."""
    from hippo.scenarios._common import prepare_out

    monkeypatch.chdir(tmp_path)
    (tmp_path / "metrics.json").write_text("{}")   # what prepare_out("") used to delete
    calls = []
    with pytest.raises(ValueError, match="out must not be an empty path"):
        prepare_out("")
    with pytest.raises(ValueError, match="cache must not be an empty path"):
        cached_recording("", "k", _build(20, calls), 20)
    with pytest.raises(TypeError, match="out must be a path"):
        prepare_out(None)
    assert calls == [] and [p.name for p in tmp_path.iterdir()] == ["metrics.json"]
    assert prepare_out(tmp_path / "out") == tmp_path / "out"   # a real folder still works
