"""Checkpoints' rules on hand-made folders: the pointer file, the numbering, what pruning
removes and keeps, and every refusal word for word (hippo.resume)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from hippo.io import CorruptFileError
from hippo.resume import Checkpoints


def _subdirs(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.is_dir())


def test_the_pointer_is_latest_json_naming_the_newest_folder(tmp_path):
    # the module docstring: a pointer file latest.json naming the newest complete checkpoint;
    # numbers start at 1 and are written with six digits (ckpt-%06d)
    ck = Checkpoints(tmp_path / "a" / "b")          # parents are made by save
    assert ck.pointer == tmp_path / "a" / "b" / "latest.json"
    first = ck.save({"k": 1})
    assert first == tmp_path / "a" / "b" / "ckpt-000001"
    # the pointer's text exactly: one JSON object and a newline
    assert ck.pointer.read_text() == '{"latest": "ckpt-000001"}\n'
    assert ck.latest() == first
    second = ck.save({"k": 2})
    assert second.name == "ckpt-000002"
    assert ck.pointer.read_text() == '{"latest": "ckpt-000002"}\n'
    assert _subdirs(ck.folder) == ["ckpt-000002"]   # the older one pruned after the move


def test_the_next_number_follows_the_pointer_not_the_folders(tmp_path):
    # a pointer on ckpt-000041 (folders of other numbers do not matter): the next is 42
    ck = Checkpoints(tmp_path)
    (tmp_path / "ckpt-000041").mkdir()
    (tmp_path / "latest.json").write_text('{"latest": "ckpt-000041"}')
    assert ck.save({"k": 42}).name == "ckpt-000042"
    assert _subdirs(tmp_path) == ["ckpt-000042"]
    assert ck.load(dict) == {"k": 42}


def test_the_millionth_checkpoint_is_still_a_checkpoint(tmp_path):
    # bug (fixed): 999999 + 1 is written with a seventh digit (%06d), ckpt-1000000, which the
    # pointer rule (exactly six digits) refused: the run's own newest checkpoint could not be
    # loaded, and pruning never removed it. The rule is now six digits or more.
    ck = Checkpoints(tmp_path)
    (tmp_path / "latest.json").write_text('{"latest": "ckpt-999999"}')
    (tmp_path / "ckpt-999999").mkdir()
    assert ck.save({"k": 10**6}).name == "ckpt-1000000"
    assert ck.load(dict) == {"k": 10**6}
    assert _subdirs(tmp_path) == ["ckpt-1000000"]
    assert ck.save({"k": 10**6 + 1}).name == "ckpt-1000001"
    assert _subdirs(tmp_path) == ["ckpt-1000001"]     # the seven-digit one pruned too


def test_a_stale_folder_under_the_next_name_is_replaced_whole(tmp_path):
    # a crash after writing part of ckpt-000002, before the pointer moved: save writes it anew
    ck = Checkpoints(tmp_path)
    ck.save({"k": 1})
    stale = tmp_path / "ckpt-000002"
    stale.mkdir()
    (stale / "junk.txt").write_text("left by a crash")
    assert ck.save({"k": 2}) == stale
    assert not (stale / "junk.txt").exists()
    assert ck.load(dict) == {"k": 2}


@pytest.mark.parametrize("doc, shown", [
    ([1, 2], "[1, 2]"),                                   # not an object
    ({"newest": "ckpt-000001"}, "{'newest': 'ckpt-000001'}"),   # no "latest"
    ({"latest": 1}, "{'latest': 1}"),                      # not a name
    ({"latest": "ckpt-1"}, "{'latest': 'ckpt-1'}"),        # too few digits
    ({"latest": "ckpt-00001"}, "{'latest': 'ckpt-00001'}"),       # five digits
    ({"latest": "xckpt-000001"}, "{'latest': 'xckpt-000001'}"),   # anchored at the start
    ({"latest": "ckpt-000001/.."}, "{'latest': 'ckpt-000001/..'}"),  # and at the end
    ({"latest": "CKPT-000001"}, "{'latest': 'CKPT-000001'}"),
    ({"latest": "ckpt-00000a"}, "{'latest': 'ckpt-00000a'}"),
])
def test_a_pointer_that_names_no_checkpoint_is_refused_word_for_word(tmp_path, doc, shown):
    ck = Checkpoints(tmp_path)
    ck.pointer.write_text(json.dumps(doc))
    want = f"{ck.pointer}: not a checkpoint pointer ({shown})"
    for call in (ck.latest, ck.load, lambda: ck.save({"k": 1})):
        with pytest.raises(CorruptFileError) as exc:
            call()
        assert str(exc.value) == want


def test_no_pointer_means_nothing_to_resume(tmp_path):
    ck = Checkpoints(tmp_path / "never")
    assert ck.latest() is None and ck.load() is None
    assert not ck.folder.exists()           # load on no folder makes none
    # checkpoint folders with no pointer: a crash before the first pointer; load removes them
    folder = tmp_path / "crashed"
    (folder / "ckpt-000001").mkdir(parents=True)
    assert Checkpoints(folder).load() is None
    assert _subdirs(folder) == []


def test_pruning_removes_only_checkpoint_folders(tmp_path):
    # only sub-folders named like a checkpoint go; other folders and files (even a file
    # named like a checkpoint) stay
    ck = Checkpoints(tmp_path)
    (tmp_path / "notes").mkdir()
    (tmp_path / "ckpt-000007").write_text("a file, not a checkpoint")
    (tmp_path / "ckpt-12").mkdir()                 # not a checkpoint name
    (tmp_path / "ckpt-000005").mkdir()             # a half-written one
    ck.save({"k": 1})
    assert _subdirs(tmp_path) == ["ckpt-000001", "ckpt-12", "notes"]
    assert (tmp_path / "ckpt-000007").read_text() == "a file, not a checkpoint"
    (tmp_path / "ckpt-000003").mkdir()             # another half-written one
    assert ck.load(dict) == {"k": 1}
    assert _subdirs(tmp_path) == ["ckpt-000001", "ckpt-12", "notes"]


def test_load_passes_the_expected_type_on(tmp_path):
    ck = Checkpoints(tmp_path)
    ck.save({"k": 1})
    assert ck.load(dict) == {"k": 1}
    with pytest.raises(CorruptFileError, match="list"):
        ck.load(list)


def test_clear_keeps_a_folder_that_holds_other_things(tmp_path):
    ck = Checkpoints(tmp_path / "resume")
    ck.save({"k": 1})
    ck.save({"k": 2})
    (ck.folder / "mine.txt").write_text("not the checkpoints'")
    ck.clear()
    assert ck.folder.is_dir() and sorted(p.name for p in ck.folder.iterdir()) == ["mine.txt"]
    assert ck.latest() is None
    (ck.folder / "mine.txt").unlink()
    ck.clear()                                     # nothing left to remove: the folder goes
    assert not ck.folder.exists()
    ck.clear()                                     # and clearing nothing is fine
    assert not ck.folder.exists()


def test_a_link_named_like_a_checkpoint_is_not_followed(tmp_path):
    # shutil.rmtree refuses a symbolic link; pruning ignores that error, so the link stays and
    # what it points to is never emptied (and saving and loading go on)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "precious.txt").write_text("keep me")
    folder = tmp_path / "resume"
    folder.mkdir()
    (folder / "ckpt-000009").symlink_to(elsewhere, target_is_directory=True)
    ck = Checkpoints(folder)
    assert ck.save({"k": 1}).name == "ckpt-000001"
    assert ck.load(dict) == {"k": 1}
    ck.clear()
    assert (elsewhere / "precious.txt").read_text() == "keep me"
    assert (folder / "ckpt-000009").is_symlink()
