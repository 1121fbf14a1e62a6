"""The parts' save/load rules by hand (hippo.perception.part_files), on a toy part: the keys a
part holds (missing, unknown, the prefix), each array's kind, shape, finiteness and magnitude
at MAX_ABS and one step past, the parameters' JSON (not a string, unreadable, not an object,
unknown names refused or dropped, lists as tuples, the class's own refusal), the format tag
(the same kind in another version, another kind, no text), and save/load on a file, each
refusal word for word."""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from hippo.io import CorruptFileError, load_npz, save_npz
from hippo.perception.part_files import (
    MAX_ABS,
    PartArrays,
    PartFile,
    check_format,
    params_from_json,
    params_json,
)


@dataclass(frozen=True)
class ToyParams:
    n: int = 2
    pair: tuple[float, ...] = (0.5, 1.5)
    name: str = "toy"

    def __post_init__(self) -> None:
        if not isinstance(self.n, int) or self.n < 1:
            raise ValueError(f"n must be >= 1, got {self.n!r}")


class Toy(PartFile):
    FILE_FORMAT = "hippo.perception.Toy/1"
    _PARAMS = ToyParams

    def __init__(self, params: ToyParams, w: np.ndarray) -> None:
        self.params, self.w = params, w

    def to_arrays(self, prefix: str = "") -> dict[str, np.ndarray]:
        return {prefix + "w": self.w.copy()}

    @classmethod
    def from_arrays(cls, params: Any, arrays: Mapping[str, Any], prefix: str = "",
                    scale: float = 1.0) -> Toy:
        own = PartArrays("Toy", arrays, prefix, ("w",))
        return cls(params, own.get("w", (params.n,)) * scale)


# -------------------------------------------------------------------------------- the keys
def test_a_part_holds_its_required_and_optional_keys():
    a = {"p_w": np.zeros(2), "p_b": np.ones(1)}
    own = PartArrays("Toy", a, "p_", ("w",), ("b", "c"))
    assert own.has("w") and own.has("b") and not own.has("c") and not own.has("p_w")
    assert own.prefix == "p_" and own.arrays is a
    # no prefix
    assert PartArrays("Toy", {"w": 1.0}, "", ("w",)).has("w")


def test_missing_keys_are_named_in_order():
    with pytest.raises(ValueError) as exc:
        PartArrays("SFA", {"p_b": 1.0}, "p_", ("z", "b", "a"))
    assert str(exc.value) == "the SFA state lacks array(s) p_z, p_a"
    # optional keys may be missing
    PartArrays("SFA", {"p_z": 1.0}, "p_", ("z",), ("y",))


def test_unknown_keys_are_named_sorted_with_what_the_part_holds():
    a = {"p_w": 1.0, "q": 2.0, "p_x": 3.0, "a": 4.0}
    with pytest.raises(ValueError) as exc:
        PartArrays("ICA", a, "p_", ("w",), ("v",))
    assert str(exc.value) == "the ICA state has unknown array(s) a, p_x, q (it holds p_v, p_w)"
    # a key of the right name without the prefix is unknown too
    with pytest.raises(ValueError) as exc:
        PartArrays("ICA", {"p_w": 1.0, "w": 1.0}, "p_", ("w",))
    assert str(exc.value) == "the ICA state has unknown array(s) w (it holds p_w)"


def test_a_long_list_of_unknown_keys_is_cut_at_200_characters():
    a = {"w": 1.0, **{f"k{i:03d}": 0.0 for i in range(100)}}
    with pytest.raises(ValueError) as exc:
        PartArrays("Toy", a, "", ("w",))
    listed = ", ".join(f"k{i:03d}" for i in range(100))[:200]
    assert str(exc.value) == f"the Toy state has unknown array(s) {listed} (it holds w)"


# ------------------------------------------------------------------------------- an array
def test_get_returns_a_float64_copy_of_the_right_shape():
    src = np.array([1, 2, 3], dtype=np.int32)
    own = PartArrays("Toy", {"p_w": src, "p_k": np.array([4, 5])}, "p_", ("w", "k"))
    got = own.get("w", (3,))
    assert got.dtype == np.float64 and got.tolist() == [1.0, 2.0, 3.0]
    got[0] = 9.0
    assert src[0] == 1
    k = own.get("k", (None,), dtype="int")
    assert k.dtype == np.int64 and k.tolist() == [4, 5]
    with pytest.raises(ValueError) as exc:
        own.get("w", (2,))
    assert str(exc.value) == "p_w must have shape (2,), got (3,)"
    with pytest.raises(ValueError) as exc:
        PartArrays("Toy", {"w": np.array(["a"])}, "", ("w",)).get("w", (1,))
    assert str(exc.value) == "w must hold real numbers, got dtype <U1"
    with pytest.raises(ValueError) as exc:
        PartArrays("Toy", {"w": np.array([0.0, np.nan])}, "", ("w",)).get("w", (2,))
    assert str(exc.value) == "w contains 1 non-finite value(s) (NaN or inf)"


def test_max_abs_on_its_edge_and_one_step_past():
    assert MAX_ABS == 1e12
    ok = PartArrays("Toy", {"w": np.array([-1e12, 1e12])}, "", ("w",)).get("w", (2,))
    assert ok.tolist() == [-1e12, 1e12]
    past = np.nextafter(1e12, 2e12)
    for v in (past, -past):
        with pytest.raises(ValueError) as exc:
            PartArrays("Toy", {"p_w": np.array([0.0, v])}, "p_", ("w",)).get("w", (2,))
        assert str(exc.value) == ("p_w holds a value of magnitude 1e+12, beyond 1e+12: no fit "
                                  "produces it")
    with pytest.raises(ValueError) as exc:
        PartArrays("Toy", {"k": np.array([2 * 10**12])}, "", ("k",)).get("k", (1,), "int")
    assert str(exc.value) == "k holds a value of magnitude 2e+12, beyond 1e+12: no fit produces it"


# ------------------------------------------------------------------------------ parameters
def test_parameters_round_trip_through_json_with_lists_as_tuples():
    p = ToyParams(n=3, pair=(0.25, 2.0, 4.0), name="x")
    text = params_json(p)
    assert text.dtype.kind == "U" and text.shape == ()
    assert json.loads(str(text)) == {"n": 3, "pair": [0.25, 2.0, 4.0], "name": "x"}
    back = params_from_json(ToyParams, text)
    assert back == p and type(back.pair) is tuple
    # missing names take the defaults
    assert params_from_json(ToyParams, np.array('{"n": 4}')) == ToyParams(n=4)


@pytest.mark.parametrize("value", [np.array(b'{"n": 2}'), np.array(['{"n": 2}']),
                                   np.array(3.0), np.array(['{"n": 2}', "{}"])])
def test_parameters_that_are_not_one_json_string_are_refused(value):
    with pytest.raises(CorruptFileError) as exc:
        params_from_json(ToyParams, value)
    assert str(exc.value) == "the parameters are not a JSON string"


def test_unreadable_and_non_object_parameters_are_refused():
    with pytest.raises(CorruptFileError) as exc:
        params_from_json(ToyParams, np.array('{"n": '))
    assert str(exc.value).startswith("unreadable parameters (Expecting value: line 1 column 7")
    deep = np.array("[" * 100_000 + "]" * 100_000)
    with pytest.raises(CorruptFileError) as exc:
        params_from_json(ToyParams, deep)
    assert str(exc.value).startswith("unreadable parameters (")
    with pytest.raises(CorruptFileError) as exc:
        params_from_json(ToyParams, np.array("[1, 2]"))
    assert str(exc.value) == "the parameters are not a JSON object: [1, 2]"
    with pytest.raises(CorruptFileError) as exc:
        params_from_json(ToyParams, np.array(json.dumps(list(range(100)))))
    assert str(exc.value) == ("the parameters are not a JSON object: "
                              + str(list(range(100)))[:80])


def test_unknown_parameters_are_refused_or_dropped():
    text = np.array('{"n": 2, "zeta": 1, "alpha": 2}')
    with pytest.raises(CorruptFileError) as exc:
        params_from_json(ToyParams, text)
    assert str(exc.value) == "unknown ToyParams parameter(s) alpha, zeta"
    assert params_from_json(ToyParams, text, ignore_unknown=True) == ToyParams(n=2)
    many = np.array(json.dumps({f"u{i:03d}": 0 for i in range(80)}))
    with pytest.raises(CorruptFileError) as exc:
        params_from_json(ToyParams, many)
    listed = ", ".join(f"u{i:03d}" for i in range(80))[:200]
    assert str(exc.value) == f"unknown ToyParams parameter(s) {listed}"


def test_the_classes_own_refusal_becomes_bad_parameters():
    with pytest.raises(CorruptFileError) as exc:
        params_from_json(ToyParams, np.array('{"n": 0}'))
    assert str(exc.value) == "bad parameters (n must be >= 1, got 0)"
    assert isinstance(exc.value.__cause__, ValueError)


# ------------------------------------------------------------------------------ the format
def test_the_format_tag():
    check_format(np.array("hippo.perception.Toy/1"), "hippo.perception.Toy/1", "a saved Toy")
    with pytest.raises(CorruptFileError) as exc:
        check_format(np.array("hippo.perception.Toy/2"), "hippo.perception.Toy/1", "a saved Toy")
    assert str(exc.value) == ("a saved Toy of format version 'hippo.perception.Toy/2': this "
                              "hippo reads 'hippo.perception.Toy/1'")
    with pytest.raises(CorruptFileError) as exc:
        check_format(np.array("hippo.perception.SFA/1"), "hippo.perception.Toy/1", "a saved Toy")
    assert str(exc.value) == ("not a saved Toy (format 'hippo.perception.SFA/1', expected "
                              "'hippo.perception.Toy/1')")


def test_the_version_is_the_text_after_the_last_slash():
    # a/b/2 is a/b in another version; a/c/1 is another kind, though it starts with a/
    with pytest.raises(CorruptFileError, match=r"^it of format version 'a/b/2'"):
        check_format(np.array("a/b/2"), "a/b/1", "it")
    with pytest.raises(CorruptFileError, match=r"^not it "):
        check_format(np.array("a/c/1"), "a/b/1", "it")
    # the kind without a version is the same kind, named with what was found
    with pytest.raises(CorruptFileError) as exc:
        check_format(np.array("a"), "a/1", "it")
    assert str(exc.value) == "it of format version 'a': this hippo reads 'a/1'"


def test_a_tag_that_is_no_text_or_too_long():
    with pytest.raises(CorruptFileError) as exc:
        check_format(np.array(7), "x/1", "it")
    assert str(exc.value) == "not it (format array(7), expected 'x/1')"
    with pytest.raises(CorruptFileError) as exc:
        check_format(np.array(["x/1"]), "x/1", "it")   # a 1-D array, not a 0-d string
    assert str(exc.value) == "not it (format array(['x/1'], dtype='<U3'), expected 'x/1')"
    long = np.arange(100)
    with pytest.raises(CorruptFileError) as exc:
        check_format(long, "x/1", "it")
    assert str(exc.value) == f"not it (format {repr(long)[:80]}, expected 'x/1')"
    with pytest.raises(CorruptFileError) as exc:
        check_format(np.array("y" * 100), "x/1", "it")
    assert str(exc.value) == f"not it (format {'y' * 80!r}, expected 'x/1')"


# ------------------------------------------------------------------------ save and load
def test_save_and_load_a_toy_part(tmp_path: Path):
    toy = Toy(ToyParams(n=3), np.array([1.0, -2.0, 3.5]))
    path = toy.save(tmp_path / "toy.npz")
    a = load_npz(path)
    assert sorted(a) == ["format", "params", "w"]
    assert str(a["format"]) == "hippo.perception.Toy/1"
    assert json.loads(str(a["params"])) == {"n": 3, "pair": [0.5, 1.5], "name": "toy"}
    back = Toy.load(path)
    assert back.params == toy.params and back.w.tolist() == [1.0, -2.0, 3.5]
    # keywords reach from_arrays
    assert Toy.load(path, scale=2.0).w.tolist() == [2.0, -4.0, 7.0]


def test_a_state_that_would_not_load_is_not_saved(tmp_path: Path):
    toy = Toy(ToyParams(n=3), np.array([1.0, 2.0]))
    with pytest.raises(ValueError) as exc:
        toy.save(tmp_path / "toy.npz")
    assert str(exc.value) == "w must have shape (3,), got (2,)"
    assert not (tmp_path / "toy.npz").exists()


def _write(path: Path, **arrays: Any) -> Path:
    base = {"format": np.array("hippo.perception.Toy/1"), "params": params_json(ToyParams()),
            "w": np.zeros(2)}
    return save_npz(path, {**base, **arrays})


@pytest.mark.parametrize(("arrays", "why"), [
    ({"format": np.array("hippo.perception.Toy/0")},
     "a saved Toy of format version 'hippo.perception.Toy/0': this hippo reads "
     "'hippo.perception.Toy/1'"),
    ({"format": np.array("hippo.perception.SFA/1")},
     "not a saved Toy (format 'hippo.perception.SFA/1', expected 'hippo.perception.Toy/1')"),
    ({"params": np.array('{"n": 2, "old": 1}')}, "unknown ToyParams parameter(s) old"),
    ({"params": np.array('{"n": -1}')}, "bad parameters (n must be >= 1, got -1)"),
    ({"w": np.zeros(3)}, "w must have shape (2,), got (3,)"),
    ({"extra": np.zeros(1)}, "the Toy state has unknown array(s) extra (it holds w)"),
])
def test_a_damaged_file_is_refused_naming_the_file(tmp_path: Path, arrays, why):
    path = _write(tmp_path / "toy.npz", **arrays)
    with pytest.raises(CorruptFileError) as exc:
        Toy.load(path)
    assert str(exc.value) == f"{path}: {why}"


def test_a_file_without_its_tag_or_parameters_is_refused(tmp_path: Path):
    path = save_npz(tmp_path / "bare.npz", {"w": np.zeros(2)})
    with pytest.raises(CorruptFileError) as exc:
        Toy.load(path)
    assert str(exc.value) == f"{path} lacks required array(s): format, params"


class Fragile(Toy):
    """A part whose loader fails with another kind of error."""

    @classmethod
    def from_arrays(cls, params: Any, arrays: Mapping[str, Any], prefix: str = "",
                    error: type[Exception] = KeyError) -> Toy:
        raise error("lost")


@pytest.mark.parametrize("error", [TypeError, KeyError, IndexError, OverflowError])
def test_every_kind_of_loading_error_names_the_file(tmp_path: Path, error):
    path = _write(tmp_path / "toy.npz")
    with pytest.raises(CorruptFileError) as exc:
        Fragile.load(path, error=error)
    assert str(exc.value) == f"{path}: {error('lost')}"
    assert isinstance(exc.value.__cause__, error)


def test_the_base_class_leaves_both_directions_to_the_part():
    with pytest.raises(NotImplementedError):
        PartFile().to_arrays()
    with pytest.raises(NotImplementedError):
        PartFile.from_arrays(ToyParams(), {})
