"""The ``hippo`` command never shows a traceback for a user's mistake.

Each mistake below must be answered before any work starts (the scenario's ``run`` is replaced
by a tripwire), with exit status 2 and one line on stderr that names the argument or value.
"""

from __future__ import annotations

import importlib
import subprocess
import sys
import time
from pathlib import Path

import pytest

from hippo import cli

ROOT = Path(__file__).resolve().parents[1]
A_FILE = str(ROOT / "pyproject.toml")

#: (argv, a word the one-line message must contain)
MISTAKES: list[tuple[list[str], str]] = [
    # the command itself
    (["bogus"], "bogus"),
    (["run"], "scenario"),
    (["run", "bogus"], "bogus"),
    (["list", "extra"], "extra"),
    (["run", "two-rooms", "--bogus", "1"], "--bogus"),
    (["run", "patrol", "--quick=1"], "--quick"),
    # options every scenario has
    (["run", "two-rooms", "--seed", "x"], "--seed"),
    (["run", "two-rooms", "--seed", "-1"], "--seed"),
    (["run", "maze", "--out", A_FILE], "--out"),
    (["run", "maze", "--out", A_FILE + "/below"], "--out"),
    # two rooms
    (["run", "two-rooms", "--ticks", "10"], "--ticks"),
    (["run", "two-rooms", "--ticks", "0"], "--ticks"),
    (["run", "two-rooms", "--ticks", "-5"], "--ticks"),
    (["run", "two-rooms", "--ticks", "many"], "--ticks"),
    (["run", "two-rooms", "--neurons", "0"], "--neurons"),
    (["run", "two-rooms", "--neurons", "1"], "--neurons"),   # 2 leak groups need 2 neurons
    (["run", "rooms", "--neurons", "2", "--leak", "0.1,0.2,0.3"], "--neurons"),
    (["run", "two-rooms", "--n-ica", "10"], "--n-ica"),
    (["run", "two-rooms", "--n-sfa", "0"], "--n-sfa"),
    (["run", "two-rooms", "--rho", "-1"], "--rho"),
    (["run", "two-rooms", "--rho", "2"], "--rho"),
    (["run", "two-rooms", "--seeds", "0"], "--seeds"),
    (["run", "two-rooms", "--sfa-cutoff", "bogus"], "--sfa-cutoff"),
    (["run", "two-rooms", "--sfa-cutoff", "0"], "--sfa-cutoff"),
    (["run", "two-rooms", "--leak", "0"], "--leak"),
    (["run", "two-rooms", "--leak", "0.1,x"], "--leak"),
    (["run", "two-rooms", "--ica-restarts", "0"], "--ica-restarts"),
    (["run", "two-rooms", "--ica-score", "bogus"], "--ica-score"),
    (["run", "two-rooms", "--ica-algorithm", "parallel"], "--ica-algorithm"),
    (["run", "two-rooms", "--hold", "-1"], "--hold"),
    # maze
    (["run", "maze", "--units", "0"], "--units"),
    (["run", "maze", "--downsample", "0"], "--downsample"),
    (["run", "maze", "--neurons", "-3"], "--neurons"),
    (["run", "maze", "--threshold", "nan"], "--threshold"),
    (["run", "maze", "--leak", "1.5"], "--leak"),
    (["run", "maze", "--ticks", "100"], "--ticks"),
    (["run", "maze", "--washout", "-1"], "--washout"),
    (["run", "maze", "--spectral-radius", "1"], "--spectral-radius"),
    (["run", "maze", "--washout", "soon"], "--washout"),
    (["run", "maze", "--ticks", "6000", "--washout", "150"], "--washout"),
    (["run", "maze", "--ticks", "6000"], "--ticks"),   # the automatic washout follows --ticks
    (["run", "maze", "--quick", "--downsample", "100"], "--downsample"),   # --quick's 60,000
    # place preference
    (["run", "place-preference", "--units", "0"], "--units"),
    (["run", "place-preference", "--explore-min", "0"], "--explore-min"),
    (["run", "place-preference", "--delay", "0"], "--delay"),
    (["run", "place-preference", "--delay", "inf"], "--delay"),
    (["run", "place-preference", "--trials", "0"], "--trials"),
    (["run", "place-preference", "--teach", "-1"], "--teach"),
    (["run", "place-preference", "--extinction", "-1"], "--extinction"),
    (["run", "place-preference", "--places", "0"], "--places"),
    (["run", "place-preference", "--places", "300"], "--places"),   # over max_prototypes 256
    (["run", "patrol", "--places", "257"], "--places"),
    (["run", "place-preference", "--trial-timeout", "0"], "--trial-timeout"),
    (["run", "place-preference", "--place-cells", "bogus"], "--place-cells"),
    (["run", "place-preference", "--explore-rho", "1.5"], "--explore-rho"),
    # patrol
    (["run", "patrol", "--waits", "1,2"], "--waits"),
    (["run", "patrol", "--waits", "1,10,10"], "--waits"),   # shorter than 2 s: not reproduced
    (["run", "patrol", "--heading-sectors", "0"], "--heading-sectors"),
    (["run", "deployment", "--heading-sectors", "2.5"], "--heading-sectors"),
    (["run", "patrol", "--waits", "a,b,c"], "--waits"),
    (["run", "patrol", "--loops", "0"], "--loops"),
    (["run", "place-preference", "--load", "/nonexistent/robot"], "--load"),
    (["run", "place-preference", "--load", "docs"], "--load"),
    (["run", "place-preference", "--load", "docs", "--save", "/tmp/x"], "--load"),
    (["run", "patrol", "--arena", "moon"], "--arena"),
    (["run", "patrol", "--checkpoints", "10,10"], "--checkpoints"),
    (["run", "patrol", "--checkpoints", "10,10;x,3"], "--checkpoints"),
    (["run", "patrol", "--checkpoints", "1,2;3,4;5,6;7,8;9,9"], "--checkpoints"),
    (["run", "patrol", "--arena", "two-rooms", "--checkpoints", "15,65;500,20"],
     "--checkpoints"),
    (["run", "patrol", "--arena", "two-rooms", "--checkpoints", "15,65;30,20"],
     "--checkpoints"),
    (["run", "patrol", "--arena", "two-rooms", "--checkpoints", "15,65;15,80"],
     "--checkpoints"),
    (["run", "patrol", "--arena", "goal-arena", "--waits", "5,6"], "--waits"),
    (["run", "patrol", "--checkpoints", "15,65;90,20", "--arena", "two-rooms", "--waits",
      "5,6,7"], "--waits"),
    (["run", "patrol", "--explore-min", "-1"], "--explore-min"),
    (["run", "patrol", "--route", "scenic"], "--route"),
    (["run", "patrol", "--route", "tour", "--checkpoints", "125,60;15,60"], "--checkpoints"),
    # timing demo
    (["run", "timing-demo", "--delay", "0"], "--delay"),
    (["run", "timing-demo", "--pairings", "0"], "--pairings"),
    (["run", "timing-demo", "--delays", "1,x"], "--delays"),
    (["run", "timing-demo", "--jitter", "1.5"], "--jitter"),
    (["run", "timing-demo", "--noise", "-1"], "--noise"),
    # demo and record
    (["run", "demo", "--arena", "bogus"], "--arena"),
    (["demo", "--ticks", "0"], "--ticks"),
    (["record", "bogus-arena"], "bogus-arena"),
    (["record", "two-rooms", "--ticks", "0"], "--ticks"),
    (["record", "two-rooms", "--out", str(ROOT)], "--out"),
    (["record", "two-rooms", "--rho", "3"], "--rho"),
    # rooms
    (["run", "rooms", "--n-rooms", "1"], "--n-rooms"),
    (["run", "rooms", "--ticks-per-room", "10"], "--ticks-per-room"),
    (["run", "rooms", "--sfa-cutoff", "2"], "--sfa-cutoff"),
    (["run", "rooms", "--units", "many"], "--units"),
    (["run", "rooms", "--units", "-1"], "--units"),
    (["run", "rooms", "--cache", A_FILE], "--cache"),
    (["run", "two-rooms", "--seeds", "x-y"], "--seeds"),
    # sweep
    (["sweep", "bogus"], "bogus"),
    (["sweep", "two-rooms", "--workers", "0"], "--workers"),
    (["sweep", "two-rooms", "--param", "bogus", "1"], "bogus"),
    (["sweep", "two-rooms", "--seeds", "x"], "--seeds"),
    # found by fuzzing: an empty item, a count meant as a seed, a grid past any machine, a
    # value a cell's scenario refuses (it had killed the Dask workers)
    (["run", "patrol", "--waits", "24.1,,11.6"], "--waits"),
    (["run", "patrol", "--checkpoints", "80,11;;140,56"], "--checkpoints"),
    (["run", "two-rooms", "--seeds", "987654"], "--seed 987654"),
    (["run", "two-rooms", "--seeds", "0-100000000000"], "--seeds"),
    (["sweep", "two-rooms", "--seeds", "-2"], "--seeds"),
    (["sweep", "demo", "--param", "rho", "0.5", "2", "--", "--quick"], "--rho 2"),
    # fifth fuzzing pass: an option --select alone reads, and what --units also takes
    (["run", "two-rooms", "--select-units", "12"], "only with --select"),
    (["run", "rooms", "--units", "abc"], "'auto'"),
    (["run", "two-rooms", "--select-criterion", "stability"], "--select-criterion: only"),
    (["run", "rooms", "--select-criterion", "stability"], "--select-criterion: only"),
    # sixth pass: two checkpoints on one spot were "waypoints must not all be one point"
    (["run", "patrol", "--checkpoints", "80,11;80,11"],
     "--checkpoints: checkpoints 1 and 2 are the same point (80, 11)"),
    (["run", "deployment", "--checkpoints", "80,11;140,56;80,11"],
     "--checkpoints: checkpoints 1 and 3 are the same point (80, 11)"),
]


@pytest.fixture(autouse=True)
def tripwire(monkeypatch):
    """Any scenario's ``run`` (and a recording) fails the test: no work may start."""
    def no_work(*args, **kwargs):
        raise AssertionError("work started before the arguments were checked")

    for module in cli.SCENARIOS.values():
        monkeypatch.setattr(importlib.import_module(module), "run", no_work)
    monkeypatch.setattr(importlib.import_module("hippo.sim.record"), "record", no_work)


def test_at_least_forty_mistakes_are_covered():
    assert len(MISTAKES) >= 40


@pytest.mark.parametrize(("argv", "word"), MISTAKES, ids=[" ".join(a) for a, _ in MISTAKES])
def test_a_mistake_is_one_line_and_exit_2_before_any_work(argv, word, capsys):
    t0 = time.perf_counter()
    with pytest.raises(SystemExit) as stop:
        cli.main(argv)
    elapsed = time.perf_counter() - t0
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.strip()]
    assert stop.value.code == 2, err
    assert len(lines) == 1, err
    assert "Traceback" not in err
    assert word in lines[0], lines[0]
    assert elapsed < 5.0  # answered at once (parsing only; a run takes minutes)


def test_a_failure_while_running_is_one_line_and_exit_1(monkeypatch, capsys, tmp_path):
    def broken(args):
        raise RuntimeError("the simulator\nbroke")

    monkeypatch.setattr(importlib.import_module(cli.SCENARIOS["demo"]), "run", broken)
    assert cli.main(["run", "demo", "--out", str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "the simulator broke" in err and "HIPPO_DEBUG" in err
    monkeypatch.setenv("HIPPO_DEBUG", "1")
    with pytest.raises(RuntimeError):  # the traceback, on request
        cli.main(["run", "demo", "--out", str(tmp_path)])


def test_list_and_help_are_readable(capsys):
    assert cli.main(["list"]) == 0
    out = capsys.readouterr().out
    for name, text in cli.DESCRIPTIONS.items():
        assert f"{name}" in out and text in out
    assert "hippo.scenarios" not in out  # descriptions, not module paths
    with pytest.raises(SystemExit) as stop:
        cli.main(["run", "place-preference", "--help"])
    assert stop.value.code == 0
    text = capsys.readouterr().out
    assert "``" not in text and ":class:" not in text   # no raw reST
    assert "(default: 7.0)" in text and "(default: learned)" in text


def test_exit_status_from_a_real_process():
    """The console entry point: status 2 and no traceback, in a fresh interpreter."""
    proc = subprocess.run([sys.executable, "-m", "hippo.cli", "run", "two-rooms", "--ticks",
                           "-5"], capture_output=True, text=True, cwd=ROOT, timeout=120,
                          env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr and proc.stderr.count("\n") == 1


#: fifth fuzzing pass: Path("") is the current folder, so each of these wrote into (and
#: removed an old metrics.json and stale temporary files from) the user's folder
EMPTY_PATHS = ([["run", name, "--out", ""] for name in cli.SCENARIOS]
               + [["run", name, "--cache", ""] for name in ("two-rooms", "maze", "rooms")]
               + [["run", "patrol", "--save", ""], ["run", "place-preference", "--load", ""],
                  ["sweep", "demo", "--out", "", "--", "--quick"]])


@pytest.mark.parametrize("argv", EMPTY_PATHS, ids=[" ".join(a) for a in EMPTY_PATHS])
def test_an_empty_path_is_refused_before_any_work(argv, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as stop:
        cli.main(argv)
    err = capsys.readouterr().err
    option = argv[argv.index("") - 1]
    assert stop.value.code == 2 and f"argument {option}: got an empty path" in err, err
    assert list(tmp_path.iterdir()) == []


def test_every_comma_separated_option_takes_one_trailing_comma():
    """Fifth fuzzing pass: --delays 2, and --select-units 2, were accepted but --leak 0.1, and
    --seeds 1, refused. One trailing comma is accepted everywhere; an empty item never."""
    from hippo.cli_args import seed_ranges
    from hippo.runner import parse_scenario_args

    def parsed(name, *argv):
        return parse_scenario_args(name, list(argv))[0]

    assert parsed("two-rooms", "--leak", "0.05,0.15,").leak == (0.05, 0.15)
    assert parsed("two-rooms", "--leak", "0.1,").leak == (0.1,)
    assert parsed("two-rooms", "--seeds", "1,").seeds == [1]   # a list of one seed
    assert parsed("two-rooms", "--seeds", "0-2,").seeds == [0, 1, 2]
    assert parsed("rooms", "--leak", "0.1,").leak == [0.1]
    assert parsed("timing-demo", "--delays", "2,").delays == [2.0]
    assert parsed("two-rooms", "--select", "--select-units", "12,").select_units == [12]
    assert seed_ranges("0-1,") == [0, 1]
    for name, option, bad in (("two-rooms", "--leak", "0.1,,"), ("two-rooms", "--leak", ","),
                              ("two-rooms", "--seeds", "1,,"), ("two-rooms", "--seeds", ","),
                              ("rooms", "--leak", "0.1,,0.2"), ("timing-demo", "--delays", "2,,")):
        with pytest.raises(SystemExit):
            parsed(name, option, bad)
    # the defaults still parse as before
    assert parsed("two-rooms").leak == (0.08, 0.15) and parsed("two-rooms").seeds == 1


def test_select_criterion_is_taken_with_select():
    """Fifth fuzzing pass: --select-criterion without --select was ignored in silence (now a
    usage error, in MISTAKES); with --select it is what selection uses."""
    from hippo.runner import parse_scenario_args

    for name in ("two-rooms", "rooms"):
        args = parse_scenario_args(name, ["--select", "--select-criterion", "stability"])[0]
        assert args.select and args.select_criterion == "stability"
        assert not parse_scenario_args(name, [])[0].select   # the default still parses
