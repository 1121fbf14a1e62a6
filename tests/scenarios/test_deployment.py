"""The long deployment end to end, quick: failures counted, health flat, and a run killed at a
random moment resumes to the same results as one never stopped."""

import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from hippo.cli import run_scenario

ARGS = ["--quick", "--hours", "0.4", "--segment-min", "5", "--seed", "4"]


def _without_memory(v):
    """The metrics but the process memory (which differs between processes)."""
    if isinstance(v, dict):
        return {k: _without_memory(x) for k, x in v.items() if k not in ("rss_mb", "wall_s")}
    if isinstance(v, list):
        return [_without_memory(x) for x in v]
    return v


def test_quick_deployment_counts_tasks_and_stays_healthy(tmp_path):
    m = run_scenario("deployment", [*ARGS, "--place-cells", "ground-truth",
                                    "--out", str(tmp_path)])
    segs = m["segments"]
    assert 1 < len(segs) <= 5 and m["hours"] >= 0.4  # the last one ends past 0.4 h
    # every lap of three checkpoints is three tasks; each segment ends at the quiet point
    assert m["tasks"] == sum(g["tasks"] for g in segs) >= 3 * int(m["laps"]) - 3
    assert m["laps"] > 5
    # with ground-truth cells the patrol does nearly all its tasks (one that never stops: 0)
    assert m["success_rate"] >= 0.9
    assert m["failures_total"] == sum(m["failures"].values())
    for k, w in enumerate(m["waits_s"]):   # the waits it makes are the waits it learned
        assert w["n"] > 0 and w["mean"] == pytest.approx(m["learned_waits_s"][k], rel=0.05)
    h0, h1 = m["health_start"], m["health_end"]
    assert h1["finite"] and h1["states"] <= h0["states"] + 5
    assert 0.0 <= h1["drive_min"] <= h1["drive_max"] <= 1.0
    assert not (tmp_path / "resume").exists()       # a finished run leaves no checkpoints
    assert (tmp_path / "deployment.png").stat().st_size > 0
    assert json.loads((tmp_path / "segments.json").read_text()) == segs


def test_a_killed_deployment_resumes_to_the_same_results(tmp_path):
    robot = tmp_path / "robot"
    whole = run_scenario("deployment", [*ARGS, "--save", str(robot),
                                        "--out", str(tmp_path / "whole")])
    # the killed run starts from the saved lesson (--load): the same robot, no re-learning
    out = tmp_path / "killed"
    env = {**os.environ, "OMP_NUM_THREADS": "1", "HIPPO_QUIET": "1"}
    cmd = [sys.executable, "-m", "hippo.cli", "run", "deployment", *ARGS, "--load", str(robot),
           "--out", str(out)]
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    rng = np.random.default_rng(0)
    try:  # kill it at a random moment after its second checkpoint
        deadline = time.monotonic() + 300
        while not (out / "resume" / "ckpt-000002").exists():
            assert proc.poll() is None and time.monotonic() < deadline
            time.sleep(0.01)
        time.sleep(rng.uniform(0.0, 0.5))
        proc.send_signal(signal.SIGKILL)
    finally:
        proc.wait()
    assert proc.returncode == -signal.SIGKILL, "the run ended before it could be killed"
    assert not (out / "metrics.json").exists()
    from hippo.resume import Checkpoints

    killed_wall = Checkpoints(out / "resume").load(dict)["run"]["wall_s"]
    t_resume = time.perf_counter()
    resumed = run_scenario("deployment", [*ARGS, "--load", str(robot), "--resume",
                                          "--out", str(out)])
    t_resume = time.perf_counter() - t_resume
    assert _without_memory(resumed) == _without_memory(whole)
    # its wall time counts the killed process's segments too (the wall time its last
    # checkpoint holds), and the resumed part at most for as long as that process ran: no
    # comparison of two clocks that the machine's load could reorder
    assert killed_wall > 0.0
    assert killed_wall < resumed["wall_s"] <= killed_wall + t_resume
    assert not (out / "resume").exists()


def test_resume_with_other_options_is_refused(tmp_path):
    from hippo.resume import Checkpoints

    Checkpoints(tmp_path / "resume").save({"meta": {"seed": 9}, "run": {}})
    with pytest.raises(SystemExit, match="other options") as e:
        run_scenario("deployment", [*ARGS, "--resume", "--out", str(tmp_path)])
    # the differing option is named, not the whole option dict dumped
    assert "seed: 9 there" in str(e.value)


def test_success_rate_is_the_share_of_passes_served_whatever_else_failed():
    # a maze run got stuck 57 times in 3 passes: the rate was 1 - 62/3 = -19.7
    from types import SimpleNamespace

    from hippo.scenarios.deployment import _metrics

    health = {"states": 10, "transitions": 20}
    seg = {"missed": 1, "misplaced": 4, "wait_off": 0, "stuck": 57, "tasks": 3, "laps": -0.75,
           "extra_stops": 0, "waits_s": [[5.0], []], "t1_h": 0.37, "health": health}
    m = _metrics({"waits": [5.0, 8.0]}, {"segments": [seg], "health0": health,
                                         "reproduced": 1.0, "learned": [5.0, 8.0]},
                 SimpleNamespace(t=1332.0), 1.0)
    assert m["success_rate"] == pytest.approx(2 / 3)
    assert m["failures_total"] == 62 and m["tasks_per_failure"] == pytest.approx(3 / 62)
    seg.update(missed=3, tasks=3)
    assert _metrics({"waits": [5.0, 8.0]}, {"segments": [seg], "health0": health,
                                            "reproduced": 1.0, "learned": [5.0, 8.0]},
                    SimpleNamespace(t=1332.0), 1.0)["success_rate"] == 0.0


def test_save_with_resume_is_refused_before_any_work(tmp_path, capsys):
    # the resumed run teaches no robot, so --save wrote nothing and the exit status was 0
    with pytest.raises(SystemExit) as e:
        run_scenario("deployment", [*ARGS, "--resume", "--save", str(tmp_path / "robot"),
                                    "--out", str(tmp_path / "out")])
    assert e.value.code == 2 and not (tmp_path / "out").exists()
    assert "argument --save: not allowed with --resume" in capsys.readouterr().err


def test_a_robot_taught_with_quick_stays_a_smoke_test_when_loaded_without_it():
    from hippo.runner import parse_scenario_args
    from hippo.scenarios.deployment import _meta

    args, _ = parse_scenario_args("deployment", ["--hours", "1"])
    assert _meta(args, 1.0, 24)["quick"] is False
    args.loaded = {"meta": {"quick": True}}   # what --load of a --quick lesson holds
    assert _meta(args, 1.0, 24)["quick"] is True


@pytest.mark.parametrize("scenario", ["deployment", "patrol", "place-preference"])
def test_learned_place_cell_options_are_refused_with_ground_truth_cells(scenario, capsys):
    # --units, --places and --reanchor shape learned cells only: with ground truth they were
    # dropped in silence (metrics.json said "place_units": 30, "reanchor": false)
    from hippo.runner import parse_scenario_args

    with pytest.raises(SystemExit) as e:
        parse_scenario_args(scenario, ["--place-cells", "ground-truth", "--units", "7",
                                       "--places", "9", "--reanchor"])
    assert e.value.code == 2
    assert "argument --units, --places, --reanchor: only for learned place cells" in \
        capsys.readouterr().err
    # left at their defaults (given or not) they are fine; learned cells take them
    parse_scenario_args(scenario, ["--place-cells", "ground-truth", "--no-reanchor"])
    parse_scenario_args(scenario, ["--units", "7", "--places", "9", "--reanchor"])
