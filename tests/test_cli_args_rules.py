"""The command line's checked arguments by hand (hippo.cli_args): every type's bounds exactly at
a bound and one step past it, its refusal word for word, the parser's one line and exit status
2, the help's defaults, the seeds' ranges and their count, the paths (empty, a file, a folder,
not writable), and the options a loaded robot or ground-truth cells fix."""

from __future__ import annotations

import argparse
import os
import types
from pathlib import Path
from typing import Any

import pytest

from hippo import cli_args
from hippo.cli_args import (
    FAILURE,
    MAX_SEED,
    MAX_SEEDS,
    USAGE_ERROR,
    Given,
    HelpFormatter,
    Parser,
    _bounds,
    _first_existing,
    _fmt,
    _items,
    _within,
    add_place_cells,
    check_ground_truth_options,
    check_loaded_options,
    distinct_integers,
    integer,
    loaded_robot_meta,
    number,
    numbers,
    out_dir,
    out_file,
    plain_digits,
    points,
    probability,
    seed_ranges,
    sfa_cutoff,
    slow_pool,
    snapshot_dir,
)


def refusal(parse: Any, text: str) -> str:
    """The ArgumentTypeError's message for ``text``."""
    with pytest.raises(argparse.ArgumentTypeError) as e:
        parse(text)
    return str(e.value)


# ------------------------------------------------------------------------------ the parser
def test_the_exit_statuses():
    assert (USAGE_ERROR, FAILURE) == (2, 1)


def test_an_error_is_one_line_with_the_programs_name_and_status_2(capsys):
    p = Parser(prog="hippo try")
    with pytest.raises(SystemExit) as e:
        p.error("two\n   lines   and  spaces\t")
    assert e.value.code == 2
    assert capsys.readouterr().err == ("hippo try: error: two lines and spaces "
                                       "(see hippo try --help)\n")


def test_a_bad_argument_is_the_parsers_one_line(capsys):
    p = Parser(prog="hippo x")
    p.add_argument("--n", type=integer(1, 3))
    assert p.parse_args(["--n", "3"]).n == 3
    with pytest.raises(SystemExit) as e:
        p.parse_args(["--n", "4"])
    assert e.value.code == 2
    assert capsys.readouterr().err == ("hippo x: error: argument --n: got 4; needs an integer "
                                       "in [1, 3] (see hippo x --help)\n")


def test_the_parser_uses_the_help_formatter_unless_told():
    assert Parser("hippo pos").prog == "hippo pos"      # argparse's own arguments, positional
    assert Parser(prog="p").formatter_class is HelpFormatter
    assert Parser(prog="p", formatter_class=argparse.HelpFormatter).formatter_class is (
        argparse.HelpFormatter)


def _help_strings(p: argparse.ArgumentParser) -> dict[str, str]:
    fmt = HelpFormatter("p")
    return {a.dest: fmt._get_help_string(a) for a in p._actions}


def test_the_help_shows_a_default_only_where_it_says_something():
    p = Parser(prog="p")
    p.add_argument("pos", help="a positional", nargs="?", default="here")
    p.add_argument("--ticks", type=int, default=5, help="ticks")
    p.add_argument("--bare", default=0.5)
    p.add_argument("--empty", default=2, help="")
    p.add_argument("--none", default=None, help="no default")
    p.add_argument("--own", default=3, help="own %(default)s")
    p.add_argument("--flag", action="store_true", help="a flag")
    p.add_argument("--off", action="store_false", help="off")
    p.add_argument("--hidden", default=argparse.SUPPRESS, help="hidden")
    p.add_argument("--falsy", default=0, help="zero")
    assert _help_strings(p) == {
        "help": "show this help message and exit", "pos": "a positional",
        "ticks": "ticks (default: %(default)s)", "bare": "(default: %(default)s)",
        "empty": "(default: %(default)s)", "none": "no default", "own": "own %(default)s",
        "flag": "a flag", "off": "off", "hidden": "hidden", "falsy": "zero (default: %(default)s)"}
    text = " ".join(p.format_help().split())
    assert "--ticks TICKS ticks (default: 5)" in text and "--own OWN own 3 --flag" in text
    assert "--falsy FALSY zero (default: 0)" in text


def test_the_help_keeps_the_descriptions_line_breaks():
    p = Parser(prog="p", description="first line\n  second, indented")
    assert "first line\n  second, indented\n" in p.format_help()


# ------------------------------------------------------------------------ numbers and bounds
@pytest.mark.parametrize("v, text", [
    (3, "3"), (3.0, "3"), (-2.0, "-2"), (0.5, "0.5"), (0.0, "0"), (2**32 - 1, "4294967295"),
    (999_999_999_999_999.0, "999999999999999"), (1e15, "1e+15"), (-1e15, "-1e+15"),
    (1e-8, "1e-08"), (0.125, "0.125"), (1 / 3, "0.333333")])
def test_a_bound_is_written_as_an_integer_when_it_is_one(v, text):
    assert _fmt(v) == text


@pytest.mark.parametrize("lo, hi, lo_open, hi_open, text", [
    (None, None, False, False, "any value"),
    (1, None, False, False, ">= 1"), (1, None, True, False, "> 1"),
    (None, 2.5, False, False, "<= 2.5"), (None, 2.5, False, True, "< 2.5"),
    (0, 1, False, False, "in [0, 1]"), (0, 1, True, False, "in (0, 1]"),
    (0, 1, False, True, "in [0, 1)"), (0, 1, True, True, "in (0, 1)"),
    (0, None, True, True, "> 0"), (None, 0, True, True, "< 0")])
def test_bounds_in_words(lo, hi, lo_open, hi_open, text):
    assert _bounds(lo, hi, lo_open=lo_open, hi_open=hi_open) == text


@pytest.mark.parametrize("v, lo, hi, lo_open, hi_open, ok", [
    (0, 0, 1, False, False, True), (1, 0, 1, False, False, True),
    (0, 0, 1, True, False, False), (1, 0, 1, False, True, False),
    (-1e-9, 0, 1, False, False, False), (1 + 1e-9, 0, 1, False, False, False),
    (5, None, None, True, True, True), (-5, None, 0, False, False, True),
    (5, 0, None, True, True, True), (0.5, 0, 1, True, True, True)])
def test_within_bounds(v, lo, hi, lo_open, hi_open, ok):
    assert _within(v, lo, hi, lo_open, hi_open) is ok


def test_an_integer_at_its_bounds_and_one_past():
    parse = integer(1, 5)
    assert parse.__name__ == "integer"
    assert [parse(t) for t in ("1", "5", " 3 ", "+2", "00004")] == [1, 5, 3, 2, 4]
    assert refusal(parse, "0") == "got 0; needs an integer in [1, 5]"
    assert refusal(parse, "6") == "got 6; needs an integer in [1, 5]"
    assert refusal(parse, "2.0") == "got '2.0'; needs an integer in [1, 5]"
    assert refusal(parse, "x") == "got 'x'; needs an integer in [1, 5]"
    assert integer(100)("1_000") == 1000           # digits grouped as Python writes them
    assert integer()(" 7\n") == 7
    for text in ("_5", "5_", "1__0", "1 0"):       # grouped otherwise: refused, not read as 5
        assert refusal(integer(), text) == f"got {text!r}; needs an integer"
    assert integer(100)("100") == 100
    assert refusal(integer(100), "99") == "got 99; needs an integer >= 100"
    assert refusal(integer(None, -1), "0") == "got 0; needs an integer <= -1"
    assert integer()("-12") == -12
    assert refusal(integer(), "many") == "got 'many'; needs an integer"


def test_a_number_at_its_bounds_and_one_past():
    parse = number(0.0, 2.0, unit="cm")
    assert parse.__name__ == "number"
    assert (parse("0"), parse("2"), parse("1.5")) == (0.0, 2.0, 1.5)
    assert refusal(parse, "-1e-9") == "got '-1e-9'; needs a number in [0, 2] (cm)"
    assert refusal(parse, "2.000001") == "got '2.000001'; needs a number in [0, 2] (cm)"
    assert refusal(parse, "two") == "got 'two'; needs a number in [0, 2] (cm)"
    shut = number(0.0, 2.0, lo_open=True, hi_open=True)
    assert shut("1e-300") == 1e-300
    assert refusal(shut, "0") == "got '0'; needs a number in (0, 2)"
    assert refusal(shut, "2") == "got '2'; needs a number in (0, 2)"
    free = number()
    assert free("-1e300") == -1e300
    for bad in ("nan", "inf", "-inf", "1e999"):
        assert refusal(free, bad) == f"got {bad!r}; needs a finite number"
    assert refusal(number(1), "inf") == "got 'inf'; needs a number >= 1"


def test_a_probability_is_a_number_in_0_1():
    assert (probability("0"), probability("1"), probability("0.008")) == (0.0, 1.0, 0.008)
    assert refusal(probability, "1.01") == "got '1.01'; needs a number in [0, 1]"
    assert refusal(probability, "-0.01") == "got '-0.01'; needs a number in [0, 1]"


def test_comma_separated_numbers_and_their_count():
    three = numbers(3, 0.0, 10.0, unit="s")
    assert three.__name__ == "numbers"
    assert three("1,2,10") == [1.0, 2.0, 10.0] and three("0, 5 ,6,") == [0.0, 5.0, 6.0]
    want = "needs 3 comma-separated numbers in [0, 10] (s)"
    for bad in ("1,2", "1,2,3,4", "1,2,11", "1,,2,3", "1,x,3", ""):
        assert refusal(three, bad) == f"got {bad!r}; {want}"
    some = numbers((2, 4), 2.0, 120.0)
    assert some("2,120") == [2.0, 120.0] and some("2,3,4,5") == [2.0, 3.0, 4.0, 5.0]
    for bad in ("5", "2,3,4,5,6", "1.99,5"):
        assert refusal(some, bad) == (
            f"got {bad!r}; needs 2 to 4 comma-separated numbers in [2, 120]")
    leak = numbers((1, None), 0.0, 1.0, lo_open=True)
    assert leak("1") == [1.0] and leak(",".join(["0.5"] * 40)) == [0.5] * 40
    assert refusal(leak, "0") == "got '0'; needs 1 or more comma-separated numbers in (0, 1]"
    assert numbers()("1,-2") == [1.0, -2.0]
    assert refusal(numbers(), "1,nan") == (
        "got '1,nan'; needs 1 or more comma-separated finite numbers")
    assert refusal(numbers(2), "1") == "got '1'; needs 2 comma-separated finite numbers"
    assert refusal(numbers(1, 0.0), "-1") == "got '-1'; needs 1 comma-separated numbers >= 0"


def test_distinct_integers():
    parse = distinct_integers(1, 500)
    assert parse.__name__ == "integers"
    assert parse("1,500") == [1, 500] and parse("7,") == [7] and parse("3,1") == [3, 1]
    want = "needs distinct comma-separated integers in [1, 500]"
    for bad in ("0", "501", "2,2", "1,x", "1,,2", ",", "1.5"):
        assert refusal(parse, bad) == f"got {bad!r}; {want}"
    assert distinct_integers()("-3,4") == [-3, 4]


# ---------------------------------------------------------------------------------- seeds
def test_plain_digits_only():
    assert plain_digits("0") and plain_digits("0123")
    for text in ("", "-1", "+1", "1_0", " 1", "1.0", "\u0663", "\u00b2"):
        assert not plain_digits(text), text


def test_seeds_as_ranges_and_lists():
    assert seed_ranges("0") == [0] and seed_ranges("3-5") == [3, 4, 5]
    assert seed_ranges("0-2,7, 9 - 10") == [0, 1, 2, 7, 9, 10]
    assert seed_ranges("5-5") == [5] and seed_ranges("0-1,") == [0, 1]
    assert seed_ranges(f"{MAX_SEED}") == [2**32 - 1]
    assert seed_ranges(f"{MAX_SEED - 1}-{MAX_SEED}") == [2**32 - 2, 2**32 - 1]


@pytest.mark.parametrize("text", ["", ",", "-1", "x", "1-", "-", "5-3", "1,,2", "1_0", "\u0663",
                                  "+1", "1.0", f"{2**32}", f"0-{2**32}", "1-2-3", "0,,"])
def test_a_bad_seed_is_refused_word_for_word(text):
    assert refusal(seed_ranges, text) == (
        "seeds are integers in [0, 4294967295] in plain digits 0-9, as ranges and lists "
        f"(100-119, 0-9,15), got {text!r}")


def test_at_most_a_thousand_seeds_counted_before_the_list():
    assert MAX_SEEDS == 1000 and MAX_SEED == 4294967295
    assert seed_ranges("0-999") == list(range(1000))
    assert seed_ranges("0-998,5000") == [*range(999), 5000]
    for text in ("0-1000", "0-998,5000,5001", f"0-{MAX_SEED}", "1,0-999"):
        assert refusal(seed_ranges, text) == (
            f"{text!r} asks for more than 1000 seeds; run such a grid in parts (hippo sweep "
            "skips the cells already done)")


def test_a_repeated_seed_is_refused():
    for text in ("1,1", "0-3,2", "4,2-4"):
        assert refusal(seed_ranges, text) == f"{text!r} repeats a seed"


def test_items_and_one_trailing_separator():
    assert _items("a,b", ",") == ["a", "b"] and _items("a,b,", ",") == ["a", "b"]
    assert _items("a, ", ",") == ["a"] and _items("a", ",") == ["a"]
    assert _items("x;y", ";") == ["x", "y"] and _items("x,y", ";") == ["x,y"]
    for text in ("", " ", ",", "a,,b", "a,,", ",a", "a, ,b"):
        assert _items(text, ",") is None, text


# --------------------------------------------------------------------------------- points
def test_points_and_their_count():
    parse = points((2, 3), "cm")
    assert parse.__name__ == "points"
    assert parse("1,2;3.5,-4") == [(1.0, 2.0), (3.5, -4.0)]
    assert parse(" 1 , 2 ; 3,4;5,6;") == [(1.0, 2.0), (3.0, 4.0), (5.0, 6.0)]
    want = "needs 2 to 3 points 'x,y' separated by ';' (cm)"
    for bad in ("1,2", "1,2;3,4;5,6;7,8", "1,2;3", "1,2;3,4,5", "1,2;a,b", "1;2"):
        assert refusal(parse, bad) == f"got {bad!r}; {want}"
    for bad in ("", "  ", ";", " ; "):
        assert refusal(parse, bad) == f"got {bad!r} (no points); {want}"
    for bad in ("1,2;;3,4", ";1,2", "1,2;;"):
        assert refusal(parse, bad) == f"got {bad!r} (an empty point between two ';'); {want}"
    for bad in ("1,2;nan,3", "inf,1;2,3", "1,2;3,-inf"):
        assert refusal(parse, bad) == f"got {bad!r}; needs finite numbers"
    assert refusal(points((1, 1)), "1,2;3,4") == (
        "got '1,2;3,4'; needs 1 to 1 points 'x,y' separated by ';'")


# ---------------------------------------------------------------------- cutoffs and pools
def test_the_sfa_cutoff():
    assert sfa_cutoff("auto") == "auto" and sfa_cutoff(" auto ") == "auto"
    assert sfa_cutoff("1e-8") == 1e-8 and sfa_cutoff("0.999") == 0.999
    for bad in ("0", "1", "-1e-8", "AUTO", "nan", "x"):
        assert refusal(sfa_cutoff, bad) == (
            f"got {bad!r}; needs a number in (0, 1), such as 1e-8, or 'auto'")


def test_the_slow_pool():
    assert (slow_pool("0"), slow_pool("1"), slow_pool("25.5")) == (0.0, 1.0, 25.5)
    for bad in ("0.5", "-1", "inf", "nan", "0.999"):
        assert refusal(slow_pool, bad) == (
            f"got {bad!r}: slow_pool must be 0 (off) or a time constant >= 1 tick, "
            f"got {float(bad)!r}")
    for bad in ("x", "", "1,2"):
        assert refusal(slow_pool, bad) == (
            f"got {bad!r}; needs 0 (off) or a time constant >= 1 tick")


# ---------------------------------------------------------------------------------- paths
def test_the_first_existing_folder_up_the_path(tmp_path):
    assert _first_existing(tmp_path / "a" / "b" / "c") == tmp_path
    assert _first_existing(tmp_path) == tmp_path
    f = tmp_path / "f"
    f.write_text("x")
    assert _first_existing(f / "below") == f
    assert _first_existing(Path("/no-such-root-folder-hippo/x")) == Path("/")


def test_an_output_folder(tmp_path):
    assert out_dir(str(tmp_path)) == tmp_path
    assert out_dir(str(tmp_path / "new" / "deeper")) == tmp_path / "new" / "deeper"
    assert not (tmp_path / "new").exists()      # checked, not created
    assert out_dir("~/x") == Path.home() / "x"
    assert out_dir(".") == Path(".")
    f = tmp_path / "f.txt"
    f.write_text("x")
    assert refusal(out_dir, str(f)) == f"{str(f)!r} is a file, not a folder"
    assert refusal(out_dir, str(f / "below")) == (
        f"cannot create {str(f / 'below')!r}: {str(f)!r} is a file")
    assert refusal(out_dir, "") == "got an empty path; name a folder ('.': the current one)"


def test_an_output_folder_that_cannot_be_written(tmp_path, monkeypatch):
    asked: list[tuple[str, int]] = []

    def access(path: Any, mode: int) -> bool:
        asked.append((str(path), mode))
        return False

    monkeypatch.setattr(cli_args.os, "access", access)
    target = tmp_path / "a" / "b"
    assert refusal(out_dir, str(target)) == (
        f"cannot write to {str(target)!r}: {str(tmp_path)!r} is not writable")
    assert asked == [(str(tmp_path), os.W_OK | os.X_OK)]


def test_an_output_file(tmp_path, monkeypatch):
    assert out_file(str(tmp_path / "run.npz")) == tmp_path / "run.npz"
    assert out_file(str(tmp_path / "a" / "run.npz")) == tmp_path / "a" / "run.npz"
    monkeypatch.chdir(tmp_path)
    assert out_file("run.npz") == Path("run.npz")      # its folder is the current one
    assert refusal(out_file, str(tmp_path)) == f"{str(tmp_path)!r} is a folder, not a file"
    assert refusal(out_file, "") == "got an empty path; name a file"
    f = tmp_path / "f"
    f.write_text("x")
    assert out_file(str(f)) == f                        # an existing file is overwritten
    assert refusal(out_file, str(f / "run.npz")) == f"{str(f)!r} is a file, not a folder"


def test_a_read_only_output_file(tmp_path, monkeypatch):
    f = tmp_path / "old.npz"
    f.write_text("x")
    monkeypatch.setattr(cli_args.os, "access", lambda path, mode: Path(path) != f)
    assert refusal(out_file, str(f)) == f"cannot write to {str(f)!r}: the file is read-only"
    assert out_file(str(tmp_path / "new.npz")) == tmp_path / "new.npz"


def test_a_snapshot_folder(tmp_path):
    assert refusal(snapshot_dir, "") == "got an empty path; name a folder ('.': the current one)"
    assert refusal(snapshot_dir, str(tmp_path / "none")) == (
        f"{str(tmp_path / 'none')!r} is not a folder")
    assert refusal(snapshot_dir, str(tmp_path)) == (
        f"{str(tmp_path)!r} holds no saved robot (no manifest.json; write one with --save)")
    (tmp_path / "manifest.json").mkdir()               # a folder of that name is no manifest
    assert refusal(snapshot_dir, str(tmp_path)).startswith(f"{str(tmp_path)!r} holds no")
    robot = tmp_path / "robot"
    robot.mkdir()
    (robot / "manifest.json").write_text("{}")
    assert snapshot_dir(str(robot)) == robot
    f = robot / "manifest.json"
    assert refusal(snapshot_dir, str(f)) == f"{str(f)!r} is not a folder"


# ----------------------------------------------------- options a loaded robot or its cells fix
def _task_parser() -> Parser:
    p = Parser(prog="hippo run task")
    add_place_cells(p)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--units", type=int, default=20)
    p.add_argument("--places", type=int, default=None)
    return p


def test_the_place_cells_options():
    p = _task_parser()
    a = p.parse_args([])
    assert (a.place_cells, a.reanchor) == ("learned", False)
    assert not hasattr(a, "place_cells_given")
    a = p.parse_args(["--place-cells", "learned", "--reanchor"])
    assert (a.place_cells, a.place_cells_given, a.reanchor) == ("learned", True, True)
    assert p.parse_args(["--no-reanchor"]).reanchor is False
    q = Parser(prog="q")
    add_place_cells(q, reanchor=True)
    assert q.parse_args([]).reanchor is True
    text = " ".join(p.format_help().split())
    assert ("--place-cells {learned,ground-truth} learned from the robot's sensors, or Gaussian "
            "fields on the true position (to measure what learning costs) (default: learned)"
            ) in text
    assert ("--reanchor, --no-reanchor after a lift, jump the learned place cells' reservoir to "
            "where the robot's next readings match its exploration; it re-localises in seconds, "
            "but the patrol kidnap chose a high-drive checkpoint less often") in text
    # the default said once, by the formatter (it was "(default off) (default: False)")
    for parser, default in ((q, "True"), (p, "False")):
        text = " ".join(parser.format_help().split()) + " --end"
        assert f"checkpoint less often (default: {default}) --" in text
        assert text.count("(default") == 2 and "(default: learned)" in text
    assert cli_args.PLACE_CELLS == ("learned", "ground-truth")


def test_given_stores_the_value_and_marks_it_given():
    p = argparse.ArgumentParser()
    p.add_argument("--x", action=Given, default=1, type=int)
    a = p.parse_args(["--x", "1"])
    assert a.x == 1 and a.x_given is True


def test_an_option_a_loaded_robot_fixes(capsys):
    p = _task_parser()
    meta = {"seed": 3, "units": 20, "place_cells": "learned"}
    keys = ("place_cells", "seed", "units", "places")
    for argv in ([], ["--seed", "3"], ["--units", "20"], ["--places", "9"]):
        check_loaded_options(p.parse_args(argv), p, meta, keys)   # same, or not in meta
    with pytest.raises(SystemExit) as e:
        check_loaded_options(p.parse_args(["--seed", "9"]), p, meta, keys)
    assert e.value.code == 2
    assert capsys.readouterr().err == (
        "hippo run task: error: argument --seed: the loaded robot was made with seed 3; leave "
        "--seed out with --load (see hippo run task --help)\n")
    # --place-cells learned is its default, but given by hand against a ground-truth robot
    with pytest.raises(SystemExit):
        check_loaded_options(p.parse_args(["--place-cells", "learned"]), p,
                             {"place_cells": "ground-truth"}, keys)
    assert "argument --place-cells: the loaded robot was made with place_cells 'ground-truth'; " \
           "leave --place-cells out with --load" in capsys.readouterr().err
    # left at its default: the snapshot's value runs, nothing to refuse
    check_loaded_options(p.parse_args([]), p, {"place_cells": "ground-truth", "seed": 4}, keys)
    # an option the parser lacks: never given, nothing to refuse
    check_loaded_options(p.parse_args([]), p, {"explore_min": 5.0}, ("explore_min",))
    # an option the keys do not name is not checked
    check_loaded_options(p.parse_args(["--seed", "9"]), p, meta, ("units",))


def test_a_loaded_robots_meta_from_its_place_cells():
    model = types.SimpleNamespace(params=types.SimpleNamespace(n_ica=12.0))
    learned = types.SimpleNamespace(model=model, n_units=40, relocaliser=object())
    meta = {"seed": 1, "units": 40}
    out = loaded_robot_meta(meta, learned)
    assert out == {"seed": 1, "units": 12, "places": 40, "reanchor": True}
    assert type(out["units"]) is int and meta == {"seed": 1, "units": 40}    # a copy
    truth = types.SimpleNamespace(relocaliser=None)
    assert loaded_robot_meta(meta, truth) == {"seed": 1, "units": 40, "reanchor": False}
    assert loaded_robot_meta({}, object()) == {"reanchor": False}


def test_options_only_learned_cells_read(capsys):
    p = _task_parser()
    p.add_argument("--extra", type=int, default=1)
    assert cli_args.LEARNED_ONLY == ("units", "places", "reanchor")
    for argv in (["--units", "7"], ["--reanchor"], ["--units", "20", "--extra", "3"],
                 ["--places", "5"], []):
        check_ground_truth_options(p.parse_args(argv), p)                  # learned cells
    gt = ["--place-cells", "ground-truth"]
    for argv in (gt, [*gt, "--units", "20", "--places", "5", "--no-reanchor", "--extra", "3"]):
        check_ground_truth_options(p.parse_args(argv), p)   # defaults; --places has none
    with pytest.raises(SystemExit) as e:
        check_ground_truth_options(p.parse_args([*gt, "--units", "7"]), p)
    assert e.value.code == 2
    assert capsys.readouterr().err == (
        "hippo run task: error: argument --units: only for learned place cells; leave it out "
        "with --place-cells ground-truth (see hippo run task --help)\n")
    with pytest.raises(SystemExit):
        check_ground_truth_options(p.parse_args([*gt, "--reanchor", "--units", "7"]), p)
    assert ("argument --units, --reanchor: only for learned place cells; leave them out with "
            "--place-cells ground-truth") in capsys.readouterr().err
    # the cells named by the caller (a loaded robot's) rather than by the arguments
    with pytest.raises(SystemExit):
        check_ground_truth_options(p.parse_args(["--units", "7"]), p, "ground-truth")
    check_ground_truth_options(p.parse_args([*gt, "--units", "7"]), p, "learned")
    # a parser without the options checks nothing for them
    bare = argparse.Namespace(place_cells="ground-truth", units=7)
    check_ground_truth_options(bare, Parser(prog="bare"))
    # arguments without --place-cells: learned cells, nothing to check
    check_ground_truth_options(argparse.Namespace(units=7), p)
