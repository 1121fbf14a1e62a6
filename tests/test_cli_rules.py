"""The ``hippo`` command by hand (hippo.cli): each subcommand handed its own arguments (the
scenario runner, the sweep and the recorder replaced by stand-ins that note what they got),
``hippo record``'s options at their bounds and one past, its files and messages, the list's
columns, the help, every refusal word for word with exit status 2, and a failure while running
as one line with exit status 1 (130 when interrupted)."""

from __future__ import annotations

import errno
import importlib
import sys
from pathlib import Path
from typing import Any

import pytest

import hippo.plots.sim
import hippo.sweep_cli
from hippo import cli, io
from hippo.sim import arenas

RECORD = importlib.import_module("hippo.sim.record")   # hippo.sim.record is also the function
NAMES = ", ".join(cli.SCENARIOS)


def _stop(capsys: pytest.CaptureFixture[str], argv: list[str]) -> tuple[int | str | None, str]:
    with pytest.raises(SystemExit) as e:
        cli.main(argv)
    return e.value.code, capsys.readouterr().err


@pytest.fixture
def runs(monkeypatch) -> list[tuple[str, list[str]]]:
    """``run_scenario`` replaced: the calls, in order."""
    calls: list[tuple[str, list[str]]] = []
    monkeypatch.setattr(cli, "run_scenario", lambda name, argv: calls.append((name, argv)))
    return calls


# ---------------------------------------------------------------------- commands and refusals
def test_run_hands_the_scenario_its_own_arguments(runs):
    assert cli.main(["run", "maze", "--quick", "--seed", "3"]) == 0
    assert cli.main(["run", "two-rooms"]) == 0
    assert runs == [("maze", ["--quick", "--seed", "3"]), ("two-rooms", [])]


def test_demo_is_run_demo(runs):
    assert cli.main(["demo", "--ticks", "5"]) == 0 and cli.main(["demo"]) == 0
    assert runs == [("demo", ["--ticks", "5"]), ("demo", [])]


def test_sweep_hands_over_its_arguments_and_status(monkeypatch):
    got: list[list[str]] = []

    def sweep_main(argv: list[str]) -> int:
        got.append(argv)
        return 7

    monkeypatch.setattr(hippo.sweep_cli, "sweep_main", sweep_main)
    assert cli.main(["sweep", "demo", "--seeds", "0-1", "--", "--quick"]) == 7
    assert got == [["demo", "--seeds", "0-1", "--", "--quick"]]


def test_the_arguments_default_to_the_command_line(monkeypatch, runs):
    monkeypatch.setattr(sys, "argv", ["hippo", "run", "maze", "--quick"])
    assert cli.main() == 0 and runs == [("maze", ["--quick"])]
    assert cli.main(("run", "demo")) == 0 and runs[-1] == ("demo", [])   # any sequence


def test_the_refusals_word_for_word(capsys, runs):
    assert _stop(capsys, ["run"]) == (2, f"hippo run: error: name a scenario: {NAMES} (see "
                                         "hippo run --help)\n")
    assert _stop(capsys, ["run", "bogus"]) == (
        2, f"hippo run: error: unknown scenario 'bogus'; choose from: {NAMES} (see hippo run "
           "--help)\n")
    assert _stop(capsys, ["bogus", "x"]) == (
        2, "hippo: error: unknown command 'bogus'; choose from: run, demo, record, sweep, list "
           "(see hippo --help)\n")
    assert _stop(capsys, ["list", "a", "b"]) == (
        2, "hippo: error: 'hippo list' takes no arguments, got 'a b' (see hippo --help)\n")
    assert runs == []


# --------------------------------------------------------------------------- list and help
@pytest.mark.parametrize("flag", ["-h", "--help"])
def test_list_help_is_its_usage_and_the_list(monkeypatch, capsys, flag):
    monkeypatch.setattr(cli, "SCENARIOS", {"ab": "m.ab"})
    monkeypatch.setattr(cli, "DESCRIPTIONS", {"ab": "two letters"})
    assert cli.main(["list", flag]) == 0
    assert capsys.readouterr().out == (
        "usage: hippo list   (the scenarios; hippo run NAME --help for the options)\n\n"
        "scenarios (hippo run NAME --help for the options of one):\n  ab  two letters\n")


def test_list_help_with_more_words_is_refused(capsys, runs):
    assert _stop(capsys, ["list", "-h", "x"]) == (
        2, "hippo: error: 'hippo list' takes no arguments, got '-h x' (see hippo --help)\n")


def test_the_list_in_two_columns(monkeypatch, capsys):
    monkeypatch.setattr(cli, "SCENARIOS", {"ab": "m.ab", "abcd": "m.abcd"})
    monkeypatch.setattr(cli, "DESCRIPTIONS", {"ab": "two letters"})
    assert cli.main(["list"]) == 0
    # the widest name (4) and two spaces make the column 6 wide; no description, no text
    assert capsys.readouterr().out == ("scenarios (hippo run NAME --help for the options of "
                                       "one):\n  ab    two letters\n  abcd  \n")


def test_the_top_help_and_the_list(capsys):
    outs = []
    for argv in ([], ["-h"], ["--help"]):
        assert cli.main(argv) == 0
        outs.append(capsys.readouterr().out)
    assert outs[0] == outs[1] == outs[2]
    text = outs[0]
    assert text.startswith("usage: hippo [-h] COMMAND ...\n\nhippocampus-inspired navigation "
                           "of a simulated robot: run its experiments, record runs\n")
    flat = " ".join(text.split())
    for line in ("run run a scenario: hippo run NAME [options] (see hippo list)",
                 "demo drive the robot in the two-rooms arena (same as run demo)",
                 "record record a wall-following run to .npz",
                 "sweep run a scenario over seeds x parameters on Dask distributed",
                 "list list the scenarios with what each does"):
        assert line in flat
    listing = text[text.index("\n\nscenarios (hippo run NAME"):]
    cli._list()
    assert listing == "\n\n" + capsys.readouterr().out


def test_run_help_is_the_usage_and_the_list(capsys, runs):
    for flag in ("-h", "--help"):
        assert cli.main(["run", flag]) == 0
        out = capsys.readouterr().out
        head = "usage: hippo run NAME [options]   (hippo run NAME --help for the options)\n\n"
        assert out.startswith(head)
        cli._list()
        assert out == head + capsys.readouterr().out
    assert runs == []


# ------------------------------------------------------------------------------- failures
@pytest.mark.parametrize("exc, line", [
    (RuntimeError("the simulator\n  broke"), "RuntimeError: the simulator broke"),
    (OSError(errno.ENOENT, "No such file or directory", "/x/run.npz"),
     "No such file or directory: /x/run.npz"),
    (OSError(errno.EACCES, "Permission denied"), "Permission denied"),
    (OSError("plain"), "OSError: plain"),
    (FileNotFoundError(errno.ENOENT, "No such file or directory", ""),
     "No such file or directory"),
    (ValueError(""), "ValueError"),          # no message: the kind alone, no dangling colon
    (ValueError(" \n"), "ValueError"),
    (AssertionError(), "AssertionError"),
])
def test_a_failure_is_one_line_and_status_1(monkeypatch, capsys, exc, line):
    def broken(name: str, argv: list[str]) -> None:
        raise exc

    monkeypatch.setattr(cli, "run_scenario", broken)
    monkeypatch.delenv("HIPPO_DEBUG", raising=False)
    assert cli.main(["run", "demo"]) == 1
    captured = capsys.readouterr()
    assert captured.err == f"hippo: error: {line} (HIPPO_DEBUG=1 shows where)\n"
    assert captured.out == ""
    monkeypatch.setenv("HIPPO_DEBUG", "")      # empty: as unset
    assert cli.main(["run", "demo"]) == 1
    monkeypatch.setenv("HIPPO_DEBUG", "1")
    with pytest.raises(type(exc)):
        cli.main(["run", "demo"])


def test_an_interruption_is_status_130(monkeypatch, capsys):
    def interrupted(name: str, argv: list[str]) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "run_scenario", interrupted)
    assert cli.main(["demo"]) == 130
    captured = capsys.readouterr()
    assert (captured.err, captured.out) == ("hippo: interrupted\n", "")


def test_a_usage_error_is_not_a_failure(monkeypatch, capsys):
    monkeypatch.setenv("HIPPO_DEBUG", "1")
    assert _stop(capsys, ["run"])[0] == 2     # SystemExit passes through main untouched


# ---------------------------------------------------------------------------- hippo record
class _Recording:
    def __init__(self, n: int) -> None:
        self.n = n
        self.saved: Path | None = None

    def __len__(self) -> int:
        return self.n

    def save(self, path: Path) -> Path:
        self.saved = path
        return path.with_name(path.name + ".saved")


@pytest.fixture
def recorder(monkeypatch) -> dict[str, Any]:
    """``record`` replaced: its arguments and the recording it returned."""
    seen: dict[str, Any] = {}

    def record(arena: Any, ticks: int, **kw: Any) -> _Recording:
        seen.update(arena=arena, ticks=ticks, **kw)
        seen["rec"] = _Recording(ticks * 2)
        return seen["rec"]

    monkeypatch.setattr(RECORD, "record", record)
    monkeypatch.setattr(arenas, "get", lambda name: ("arena", name))
    return seen


def test_record_hands_its_options_to_the_recorder(recorder, tmp_path, capsys):
    out = tmp_path / "a" / "b" / "run.npz"
    assert cli.main(["record", "maze-e1", "--ticks", "10000000", "--rho", "1", "--sensors",
                     "ray17", "--seed", "4294967295", "--out", str(out)]) == 0
    assert {k: v for k, v in recorder.items() if k != "rec"} == {
        "arena": ("arena", "maze-e1"), "ticks": 10_000_000, "seed": 2**32 - 1, "rho": 1.0,
        "sensors": "ray17"}
    assert recorder["rec"].saved == out and out.parent.is_dir()    # its folders made
    assert capsys.readouterr().err == f"wrote 20000000 ticks to {out}.saved\n"
    assert not out.with_suffix(".png").exists()


def test_record_defaults(recorder, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert cli.main(["record", "two-rooms"]) == 0
    assert {k: v for k, v in recorder.items() if k != "rec"} == {
        "arena": ("arena", "two-rooms"), "ticks": 18120, "seed": 0, "rho": 0.008,
        "sensors": "ir8"}
    assert recorder["rec"].saved == Path("run.npz")
    assert capsys.readouterr().err == "wrote 36240 ticks to run.npz.saved\n"
    assert cli.main(["record", "goal-arena", "--ticks", "1", "--rho", "0", "--seed", "0"]) == 0
    assert (recorder["ticks"], recorder["rho"], recorder["seed"]) == (1, 0.0, 0)


def test_record_writes_the_figure_when_asked(recorder, tmp_path, monkeypatch, capsys):
    drawn: list[Any] = []
    monkeypatch.setattr(hippo.plots.sim, "plot_trajectory",
                        lambda arena, rec: drawn.append((arena, rec)) or ("fig", "ax"))
    monkeypatch.setattr(io, "save_figure", lambda fig, path, dpi: drawn.append((fig, path, dpi)))
    out = tmp_path / "run.npz"
    assert cli.main(["record", "patrol-course", "--out", str(out), "--figure"]) == 0
    assert drawn == [(("arena", "patrol-course"), recorder["rec"]),
                     ("fig", tmp_path / "run.png", 120)]
    assert capsys.readouterr().err == (f"wrote 36240 ticks to {out}.saved\n"
                                       f"wrote {tmp_path / 'run.png'}\n")


@pytest.mark.parametrize("argv, says", [
    (["--ticks", "0"], "argument --ticks: got 0; needs an integer in [1, 10000000]"),
    (["--ticks", "10000001"], "argument --ticks: got 10000001; needs an integer in [1, 10000000]"),
    (["--seed", "-1"], "argument --seed: got -1; needs an integer in [0, 4294967295]"),
    (["--seed", "4294967296"],
     "argument --seed: got 4294967296; needs an integer in [0, 4294967295]"),
    (["--rho", "1.5"], "argument --rho: got '1.5'; needs a number in [0, 1]"),
    (["--sensors", "ir9"], "argument --sensors: invalid choice: 'ir9' (choose from 'ir8', "
                           "'ray17')"),
    (["--out", ""], "argument --out: got an empty path; name a file"),
    (["--figure=1"], "argument --figure: ignored explicit argument '1'"),
])
def test_record_refuses_word_for_word(recorder, capsys, argv, says):
    assert _stop(capsys, ["record", "two-rooms", *argv]) == (
        2, f"hippo record: error: {says} (see hippo record --help)\n")
    assert recorder == {}


def test_record_refuses_an_unknown_arena(recorder, capsys):
    names = ", ".join(f"'{n}'" for n in arenas.ARENAS)
    assert _stop(capsys, ["record", "moon"]) == (
        2, f"hippo record: error: argument ARENA: invalid choice: 'moon' (choose from {names}) "
           "(see hippo record --help)\n")
    assert _stop(capsys, ["record"])[1] == (
        "hippo record: error: the following arguments are required: ARENA (see hippo record "
        "--help)\n")


def test_record_help(capsys):
    with pytest.raises(SystemExit) as e:
        cli.main(["record", "--help"])
    assert e.value.code == 0
    text = " ".join(capsys.readouterr().out.split())
    assert text.startswith("usage: hippo record [-h] [--ticks TICKS] [--rho RHO] [--sensors "
                           "{ir8,ray17}] [--seed SEED] [--out OUT] [--figure] ARENA Record a "
                           "wall-following run (SMC09's explorer) to .npz: what the robot "
                           "sensed, and apart, where it truly was.")
    for line in (f"ARENA one of: {', '.join(arenas.ARENAS)}",
                 "--ticks TICKS control ticks of 0.2 s (default: 18120)",
                 "--rho RHO probability per tick of switching the followed wall "
                 "(default: 0.008)",
                 "--sensors {ir8,ray17} ir8: the e-puck of SMC09; ray17: ICANN09's 17 rays "
                 "(default: ir8)",
                 "--seed SEED random seed (default: 0)",
                 "--out OUT the .npz file to write (default: run.npz)",
                 "--figure also write a trajectory PNG"):
        assert line in text, line


def test_the_module_names_what_it_offers():
    assert cli.__all__ == ["DESCRIPTIONS", "SCENARIOS", "main", "parse_scenario_args",
                           "record_main", "run_scenario", "scenario_parser"]
