"""Atomic writes: nothing half-written, no temporary file left behind, the user's permissions."""

import os
import stat
import time

import numpy as np
import pytest

from hippo import io


@pytest.fixture
def umask_027():
    old = os.umask(0o027)
    yield 0o027
    os.umask(old)


def _mode(p):
    return stat.S_IMODE(os.stat(p).st_mode)


def test_files_get_the_umask_permissions_not_mkstemps_0600(tmp_path, umask_027):
    p = io.save_npz(tmp_path / "a.npz", {"x": np.arange(3)})
    assert _mode(p) == 0o640
    os.umask(0o002)
    q = io.save_json(tmp_path / "b.json", {"a": 1})
    assert _mode(q) == 0o664
    r = io.atomic_write_text(tmp_path / "c.txt", "hi")
    assert _mode(r) == 0o664
    # a plain open() gives the same mode: the atomic write does not change what users see
    with open(tmp_path / "plain.txt", "w") as fh:
        fh.write("x")
    assert _mode(tmp_path / "plain.txt") == _mode(r)


def test_a_failed_write_keeps_the_old_file_and_leaves_no_temp(tmp_path):
    target = tmp_path / "m.json"
    io.save_json(target, {"v": 1})

    class Boom(Exception):
        pass

    def bad_write(fh):
        fh.write(b'{"v": 2, "half')
        raise Boom

    with pytest.raises(Boom):
        io._atomic_write(target, bad_write)
    assert io.load_json(target) == {"v": 1}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.json"]


def test_stale_temps_of_a_killed_write_are_removed_on_the_next_write(tmp_path):
    stale = tmp_path / ".run.npz.abc123.tmp"
    stale.write_bytes(b"half a zip")
    old = time.time() - 2 * io.STALE_AGE
    os.utime(stale, (old, old))
    young = tmp_path / ".other.json.xyz.tmp"  # another process may be writing it right now
    young.write_bytes(b"{")
    unrelated = tmp_path / "notes.tmp"  # not one of ours (no leading dot)
    unrelated.write_text("keep")
    io.save_json(tmp_path / "metrics.json", {"ok": True})
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == [".other.json.xyz.tmp", "metrics.json", "notes.tmp"]


def test_clean_stale_temps_reports_what_it_removed(tmp_path):
    a = tmp_path / ".x.tmp"
    a.write_text("")
    os.utime(a, (0, 0))
    assert io.clean_stale_temps(tmp_path) == [a]
    assert io.clean_stale_temps(tmp_path) == []
    assert io.clean_stale_temps(tmp_path / "missing") == []


def test_save_figure_is_atomic_and_readable(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.plot([0, 1], [1, 0])
    p = io.save_figure(fig, tmp_path / "f.png", dpi=50)
    plt.close(fig)
    assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [q.name for q in tmp_path.iterdir()] == ["f.png"]


def test_npz_refuses_objects_and_loads_without_pickle(tmp_path):
    with pytest.raises(TypeError, match="dtype object"):
        io.save_npz(tmp_path / "o.npz", {"x": np.array([{}, 1], dtype=object)})
    assert not (tmp_path / "o.npz").exists()
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(FileNotFoundError):
        io.load_npz(tmp_path / "none.npz")
    (tmp_path / "bad.npz").write_bytes(b"PK\x03\x04garbage")
    with pytest.raises(io.CorruptFileError):
        io.load_npz(tmp_path / "bad.npz")
    # random bytes: numpy takes them for a pickle and advises allow_pickle; hippo never does
    (tmp_path / "noise.npz").write_bytes(np.random.default_rng(0).bytes(3000))
    with pytest.raises(io.CorruptFileError, match="took it for pickled data") as e:
        io.load_npz(tmp_path / "noise.npz")
    assert "allow_pickle" not in str(e.value)


def test_json_is_strict_a_nan_or_infinity_is_written_as_null(tmp_path):
    import json

    def refuse(token):
        raise ValueError(f"non-standard JSON token {token}")

    obj = {"nan": float("nan"), "list": [1.5, np.float32(np.inf), -np.inf],
           "array": np.array([[0.25, np.nan]]), "ints": np.arange(2), "n": np.int64(7),
           "nested": ({"x": np.float64("nan")}, "text")}
    path = io.save_json(tmp_path / "m.json", obj)
    back = json.loads(path.read_text(), parse_constant=refuse)   # strict: no NaN token
    assert back == {"nan": None, "list": [1.5, None, None], "array": [[0.25, None]],
                    "ints": [0, 1], "n": 7, "nested": [{"x": None}, "text"]}
    assert io.load_json(path) == back


def test_writing_onto_a_folder_or_a_snapshot_onto_a_file_names_the_mistake(tmp_path):
    # found by trying inputs nobody listed: RCSFAICA.save(".") raised the OS's "Device or
    # resource busy" from os.replace, and save_snapshot onto a file pathlib's FileExistsError
    from hippo.snapshot import save_snapshot

    with pytest.raises(IsADirectoryError, match="is a folder: give a file name"):
        io.atomic_write_text(tmp_path, "x")
    a_file = tmp_path / "notes.txt"
    a_file.write_text("mine")
    with pytest.raises(NotADirectoryError, match="is a file: a snapshot is a folder"):
        save_snapshot({"a": 1}, a_file)
    assert a_file.read_text() == "mine" and sorted(p.name for p in tmp_path.iterdir()) == [
        "notes.txt"]
