"""Security patrol (HIREL III-B) end to end, in --quick mode: the metrics CI checks."""

import numpy as np
import pytest

from hippo.cli import run_scenario


def _waits_within(m, rel):
    errs = [r["max_rel_error"] for r in m["checkpoints"] if r["max_rel_error"] is not None]
    return errs and all(e <= rel for e in errs)


def test_ground_truth_reproduces_untuned_waits(tmp_path):
    m = run_scenario("patrol", ["--quick", "--place-cells", "ground-truth", "--waits",
                                "8.3,15,5.7", "--seed", "3", "--out", str(tmp_path)])
    assert m["loop_completion"] == 1.0
    assert m["checkpoint_stops_made"] == m["checkpoint_stops_expected"] >= 6
    for r, taught in zip(m["checkpoints"], (8.3, 15.0, 5.7)):
        assert r["learned_wait_s"] == pytest.approx(taught, abs=0.35)
        # every reproduced wait within 3 % of the learned one (HIREL: up to 32 %)
        assert all(abs(w - r["learned_wait_s"]) <= 0.03 * r["learned_wait_s"]
                   for w in r["reproduced_waits_s"])
        assert r["sd_s"] <= 0.3
    # kidnapped before the checkpoint it served last (lowest drive), it heads on to another
    k = m["kidnap"]
    assert k["passed_the_low_drive"] and k["first_stop"]["drive"] != k["put_before"]
    assert k["drive_levels"][k["put_before"]] == min(k["drive_levels"].values())
    a = m["adaptation"]
    assert a["longer_block"]["after_s"] > a["longer_block"]["before_s"] + 3.0
    assert a["leash_restart"]["after_s"] < a["leash_restart"]["before_s"] - 3.0
    with np.load(tmp_path / "run.npz") as run:
        assert "block_start" in run["event_kind"] and "lead_start" in run["event_kind"]
    for name in ("map.png", "trajectories.png", "waits_table.png", "map.graphml"):
        assert (tmp_path / name).stat().st_size > 0


def test_learned_place_cells_patrol(tmp_path):
    m = run_scenario("patrol", ["--quick", "--seed", "2", "--out", str(tmp_path)])
    assert m["place_cells"] == "learned"
    assert m["loop_completion"] == 1.0
    assert m["reproduced_loop_fraction"] >= 0.95
    # with learned place cells not every checkpoint is recognised on every pass (measured over
    # seeds 0-19 in full runs: 86 %); the waits that are made are timed by the same mechanism
    assert m["checkpoint_stops_made"] >= 0.5 * m["checkpoint_stops_expected"]
    assert m["checkpoint_stops_expected"] >= 6
    assert _waits_within(m, 0.03)


def test_bad_waits_are_refused(tmp_path):
    with pytest.raises(SystemExit):
        run_scenario("patrol", ["--quick", "--waits", "3,nan,5", "--out", str(tmp_path)])
    with pytest.raises(SystemExit):
        run_scenario("patrol", ["--quick", "--waits", "3,4", "--out", str(tmp_path)])


def test_a_saved_lesson_patrols_bit_for_bit_like_the_run_that_saved_it(tmp_path):
    args = ["--quick", "--seed", "5", "--waits", "9,14,6"]
    whole = run_scenario("patrol", [*args, "--save", str(tmp_path / "robot"),
                                    "--out", str(tmp_path / "a")])
    # the course and the seed come from the snapshot: none given here
    loaded = run_scenario("patrol", ["--quick", "--load", str(tmp_path / "robot"),
                                     "--out", str(tmp_path / "b")])
    assert loaded["loaded_from"] == str(tmp_path / "robot")
    assert loaded["heading_sectors"] == whole["heading_sectors"] == 4   # learned: split in 4
    for k in whole:
        if k not in ("wall_s", "realtime_factor", "loaded_from"):
            assert loaded[k] == whole[k], k
    # a course that contradicts the saved one, or --save with --load, is one clear error
    for bad in (["--waits", "3,4,5"], ["--arena", "maze"], ["--save", str(tmp_path / "c")],
                ["--heading-sectors", "2"], ["--place-cells", "ground-truth"],
                ["--seed", "6"], ["--units", "30"], ["--route", "tour"], ["--reanchor"]):
        with pytest.raises(SystemExit):
            run_scenario("patrol", ["--quick", "--load", str(tmp_path / "robot"), *bad,
                                    "--out", str(tmp_path / "d")])
    # the robot's own unit count (--quick: 16 ICA units) is its value, not its 40 prototypes
    again = run_scenario("patrol", ["--quick", "--load", str(tmp_path / "robot"), "--units",
                                    "16", "--out", str(tmp_path / "e")])
    assert again["checkpoint_stops_made"] == whole["checkpoint_stops_made"]
    # a --quick robot loaded without --quick is still a smoke test, and says so
    full = run_scenario("patrol", ["--load", str(tmp_path / "robot"), "--loops", "1",
                                   "--out", str(tmp_path / "f")])
    assert full["quick"] is True
    with pytest.raises(SystemExit):   # not a patrol lesson
        run_scenario("patrol", ["--quick", "--load", str(tmp_path / "a"),
                                "--out", str(tmp_path / "d")])


def test_the_summary_gives_the_loops_beside_the_passes():
    from hippo.scenarios.patrol import loops_note

    done = {"loops_completed": 5.0, "loops": 5, "loop_completion": 1.0, "extra_stops": 0,
            "misplaced_stops": 0}
    assert loops_note(done) == " over 5.00 of 5 loops"
    back = {**done, "loops_completed": -0.05, "loop_completion": 0.0, "extra_stops": 32}
    note = loops_note(back)
    assert "-0.05 of 5 loops" in note and "32 extra" in note and "backwards" in note
    assert "not completed" in loops_note({**done, "loops_completed": 0.6,
                                          "loop_completion": 0.12})


def test_the_summary_names_a_route_out_and_back_as_a_known_limitation():
    from hippo.scenarios.patrol import route_note
    from hippo.sim import arenas
    from hippo.tasks import Route, patrol_route

    assert route_note(Route(arenas.loop_waypoints())) == ""
    out_and_back = Route.through(arenas.get("two-rooms"), [(15.0, 65.0), (100.0, 40.0)])
    assert out_and_back.winding == 0
    assert "out and back" in route_note(out_and_back)
    assert route_note(patrol_route("goal-arena", [(85.0, 15.0), (132.0, 76.0),
                                                  (45.0, 136.0)])) == ""


def test_learned_cells_re_anchor_after_the_kidnap_when_asked(tmp_path):
    """--reanchor: the kidnapped robot's place code jumps to where its readings match the
    exploration and the map trusts it sooner; by default it settles by itself."""
    on = run_scenario("patrol", ["--quick", "--seed", "1", "--reanchor",
                                 "--out", str(tmp_path / "on")])
    off = run_scenario("patrol", ["--quick", "--seed", "1", "--out", str(tmp_path / "off")])
    assert on["reanchor"] is True and off["reanchor"] is False
    k_on, k_off = on["kidnap"], off["kidnap"]
    assert k_on["relocalised_after_s"] is not None
    assert k_on["relocalised_after_s"] < k_off["relocalised_after_s"]
    assert k_on["passed_the_low_drive"]


def test_the_summary_says_a_wait_learned_off_the_taught_one_and_a_checkpoint_never_passed():
    # patrol-course, checkpoints 12,100;145,20;145,100;60,10, seed 333, ground truth: "stopped
    # at 18 of 18" hid a wait of 24.1 s learned as 15.6 s (a leash had cut the robot's own
    # stop there short; fixed) and a checkpoint the patrol's pass count never saw
    from hippo.scenarios.patrol import _wait_summary

    row = {"checkpoint": "checkpoint-1", "taught_block_s": 24.1, "taught_stop_s": 24.0,
           "learned_wait_s": 15.6, "passes": 3, "mean_s": 15.6, "sd_s": 0.0}
    assert _wait_summary(row) == ("checkpoint-1: wait 24.1 s, learned 15.6 s (-35 %), "
                                  "reproduced 15.6 ± 0.00 s")
    assert _wait_summary({**row, "learned_wait_s": 24.0, "mean_s": 24.0}) == (
        "checkpoint-1: wait 24.1 s, learned 24.0 s, reproduced 24.0 ± 0.00 s")
    assert _wait_summary({**row, "passes": 0}).endswith("never passed on the patrol")
    assert _wait_summary({**row, "learned_wait_s": None}) == (
        "checkpoint-1: wait 24.1 s, not learned")
    assert _wait_summary({**row, "taught_stop_s": None}) == (
        "checkpoint-1: wait 24.1 s, never taught")


def test_a_lesson_on_the_leash_lets_the_robots_own_stop_end_first(tmp_path):
    # checkpoints out of the loop's order on patrol-course: after checkpoint 2's lesson the
    # robot ran on to checkpoint 1 and stopped there by itself; the leash for checkpoint 3's
    # lesson pulled it away 11 s into that stop, and the stop's wait was learned as 15.6 s
    # instead of 24.1 s (ground truth, seed 333; it held at full size too)
    # (--route shortest: "auto" now takes the wall tour for these checkpoints, which passes
    # them in the loop's order, so that no lesson needs the leash)
    m = run_scenario("patrol", ["--quick", "--place-cells", "ground-truth", "--seed", "333",
                                "--checkpoints", "12,100;145,20;145,100;60,10",
                                "--route", "shortest", "--out", str(tmp_path)])
    rows = {r["checkpoint"]: r for r in m["checkpoints"]}
    assert rows["checkpoint-1"]["learned_wait_s"] == pytest.approx(24.1, rel=0.03)
    for r in rows.values():
        assert r["learned_wait_s"] == pytest.approx(r["taught_block_s"], rel=0.03)
