"""Checkpoints a killed run resumes from: the newest complete one, never a half-written one."""

import json

import numpy as np
import pytest

from hippo.io import CorruptFileError
from hippo.resume import Checkpoints


def test_save_load_keeps_only_the_newest(tmp_path):
    ck = Checkpoints(tmp_path / "resume")
    assert ck.load() is None and ck.latest() is None
    ck.save({"k": 1, "w": np.arange(3.0)})
    second = ck.save({"k": 2, "w": np.arange(4.0)})
    back = ck.load(dict)
    assert back["k"] == 2 and np.array_equal(back["w"], np.arange(4.0))
    assert [p.name for p in ck.folder.iterdir() if p.is_dir()] == [second.name]
    assert ck.latest() == second


def test_a_half_written_checkpoint_is_never_read_and_is_removed(tmp_path):
    ck = Checkpoints(tmp_path / "resume")
    ck.save({"k": 1})
    # a crash while writing the next one: its folder exists, the pointer did not move
    half = ck.folder / "ckpt-000002"
    half.mkdir()
    (half / "state.json").write_text("{")
    assert ck.load(dict) == {"k": 1}
    assert not half.exists()
    # and the next save takes its number cleanly
    assert ck.save({"k": 2}).name == "ckpt-000002" and ck.load(dict) == {"k": 2}


def test_a_damaged_pointer_or_checkpoint_is_refused(tmp_path):
    ck = Checkpoints(tmp_path / "resume")
    ck.save({"k": 1})
    ck.pointer.write_text(json.dumps({"latest": "../../etc"}))
    with pytest.raises(CorruptFileError, match="not a checkpoint pointer"):
        ck.load()
    ck.pointer.write_text(json.dumps({"latest": "ckpt-000001"}))
    (ck.folder / "ckpt-000001" / "arrays.npz").write_bytes(b"garbage")
    with pytest.raises(CorruptFileError):
        ck.load()


def test_clear_removes_everything(tmp_path):
    ck = Checkpoints(tmp_path / "resume")
    ck.save({"k": 1})
    ck.clear()
    assert not ck.folder.exists() and ck.load() is None
