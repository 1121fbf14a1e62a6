"""`hippo run two-rooms --quick`: runs end to end, writes its files, sane metric values."""

import json
import math

import numpy as np
import pytest

from hippo.cli import run_scenario
from hippo.perception import RCSFAICA


def test_two_rooms_quick(tmp_path):
    out = tmp_path / "two-rooms"
    m = run_scenario("two-rooms", ["--quick", "--out", str(out)])
    for name in ("metrics.json", "run.npz", "place_cells.npz", "fig5_room_cell_train.png",
                 "fig6_room_cell_test.png", "fig7_kidnapping.png", "fig8_corridor_cell_test.png"):
        assert (out / name).exists(), name
    saved = json.loads((out / "metrics.json").read_text())
    for key in ("room_cell_test_balanced_accuracy", "kidnap_recovery_ticks",
                "corridor_cell_test_balanced_accuracy", "leak_0.08_0.15", "leak_0.11_0.14"):
        assert key in m and key in saved
    # the defaults: the room cell from 2 SFA / 2 ICA units at leaks 0.08/0.15; the corridor
    # cell keeps SMC09's 4 units
    assert (m["n_sfa"], m["n_ica"], m["leak"], m["corridor_units"]) == (2, 2, [0.08, 0.15], 4)
    assert RCSFAICA.load(out / "place_cells.npz").params.n_ica == 2
    assert m["room_cell_is_slowest_unit"] in (0, 1)
    # seed 0, quick (8000 ticks, 120 neurons): room cell 0.70 (the 2-unit default was chosen
    # at full size, 600 neurons and 18,120 ticks; SMC09's 4 units reach 0.955 here, below),
    # ceiling 0.966, recovery 27 ticks, corridor cell 0.91; chance is 0.5
    assert 0.6 <= m["room_cell_test_balanced_accuracy"] <= 1.0
    assert 0.9 <= m["room_ceiling_balanced_accuracy"] <= 1.0
    assert 0.75 <= m["corridor_cell_test_balanced_accuracy"] <= 1.0
    assert math.isfinite(m["kidnap_recovery_ticks"]) and 0 <= m["kidnap_recovery_ticks"] <= 60
    assert m["kidnap_unrecovered"] == 0 and m["seeds"] == [0]
    assert [e["tick"] for e in m["kidnap_events"]] == [150, 400, 640, 980]


def test_two_rooms_quick_smc09_settings(tmp_path):
    # SMC09's fixed settings stay one option set away; seed 0, quick: room cell 0.955 (a
    # broken pipeline stays near chance, 0.5)
    m = run_scenario("two-rooms", ["--quick", "--out", str(tmp_path), "--no-figures",
                                   "--no-ceiling", "--n-sfa", "4", "--n-ica", "4",
                                   "--leak", "0.05,0.15"])
    assert (m["n_sfa"], m["n_ica"], m["leak"]) == (4, 4, [0.05, 0.15]) and "leak_0.05_0.15" in m
    assert 0.85 <= m["room_cell_test_balanced_accuracy"] <= 1.0


def test_two_rooms_ica_algorithm_option(tmp_path):
    # the ICA variant reaches the fitted model (saved with it) and the metrics
    m = run_scenario("two-rooms", ["--quick", "--out", str(tmp_path), "--no-figures",
                                   "--no-ceiling", "--ica-algorithm", "deflation",
                                   "--ica-score", "slowness", "--ica-restarts", "2"])
    assert m["ica_algorithm"] == "deflation" and m["ica_score"] == "slowness"
    model = RCSFAICA.load(tmp_path / "place_cells.npz")
    assert model.params.ica_algorithm == "deflation" and model.params.ica_score == "slowness"
    assert 0.5 <= m["room_cell_test_balanced_accuracy"] <= 1.0


def test_two_rooms_leak_option_and_sweep(tmp_path):
    out = tmp_path / "two-rooms"
    # SMC09's 4 units: the quick run's reservoir (120 neurons) is too small for the 2-unit
    # default (room cell 0.70 on seed 0, above)
    m = run_scenario("two-rooms", ["--quick", "--out", str(out), "--leak", "0.08,0.15",
                                   "--leak-sweep", "--ica-restarts", "1", "--n-sfa", "4",
                                   "--n-ica", "4"])
    assert m["leak"] == [0.08, 0.15] and "leak_0.08_0.15" in m
    assert (out / "leak_sweep.png").exists()
    rows = m["leak_sweep"]
    assert len(rows) == 16 and len({tuple(r["leak"]) for r in rows}) == 16
    # quick seed 0: the best pair reaches ~0.95 (a broken fit stays near 0.5)
    assert max(r["room_cell_test_balanced_accuracy"] for r in rows) >= 0.85
    for r in rows:
        assert 0.5 <= r["room_cell_test_balanced_accuracy"] <= 1.0
        assert r["meets_targets"] == (r["room_cell_test_balanced_accuracy"] >= 0.97
                                      and r["kidnap_recovery_ticks"] <= 15)
    assert m["leak_sweep_meeting_targets"] == [r["leak"] for r in rows if r["meets_targets"]]


def test_two_rooms_rejects_bad_leaks():
    import pytest

    for bad in ("0", "a,b", "0.1,1.5"):
        with pytest.raises(SystemExit):
            run_scenario("two-rooms", ["--quick", "--leak", bad])


def test_seeds_parser():
    import argparse

    import pytest

    from hippo.scenarios._common import parse_seeds, seed_list

    assert parse_seeds("3") == 3
    assert parse_seeds("100-103") == [100, 101, 102, 103]
    assert parse_seeds("0-2,15") == [0, 1, 2, 15]
    assert seed_list(argparse.Namespace(seed=5, seeds=2)) == [5, 6]
    assert seed_list(argparse.Namespace(seed=5, seeds=[9, 1])) == [9, 1]
    for bad in ("0", "3-1", "a", "1,1", "-2", "1001", "4294967296", "0-100000000000",
                "5,0-999"):
        with pytest.raises(argparse.ArgumentTypeError):
            parse_seeds(bad)
    # a bare number is a count: a large one is refused with the way to ask for one seed
    with pytest.raises(argparse.ArgumentTypeError, match="--seed 987654"):
        parse_seeds("987654")
    assert parse_seeds("1000") == 1000 and len(parse_seeds("0-999")) == 1000


def test_kidnapped_run_replays_the_clean_run_until_the_first_kidnap():
    import numpy as np

    from hippo.scenarios._two_rooms_recordings import kidnapped_recording
    from hippo.sim import arenas
    from hippo.sim.record import record

    arena = arenas.two_rooms()
    rec = record(arena, 1500, seed=4, progress=False)
    kid, events, kinds, moved = kidnapped_recording(arena, 1500, 1000, seed=4, rho=0.008)
    assert events == [1150, 1400] and kinds[0].startswith("away from") and moved[0]
    # put back where it was taken from
    assert kinds[1].startswith("back to")
    assert np.hypot(kid.x[1400] - rec.x[1149], kid.y[1400] - rec.y[1149]) < 2.0
    assert np.array_equal(kid.sensors[:1150], rec.sensors[:1150])
    assert not np.array_equal(kid.sensors[1150:], rec.sensors[1150:])
    room_before = arena.region_of(rec.x[1149], rec.y[1149])
    assert arena.region_of(kid.x[1151], kid.y[1151]) != room_before


def test_fault_curve_guard_helps(tmp_path):
    # SMC09's settings, as the README's fault figures (the quick reservoir is too small for the
    # 2-unit default)
    m = run_scenario("two-rooms", ["--quick", "--out", str(tmp_path), "--faults",
                                   "--ica-restarts", "1", "--no-figures", "--n-sfa", "4",
                                   "--n-ica", "4", "--leak", "0.05,0.15"])
    f = m["faults"]
    rows = f["rows"]
    assert {r["n_dead"] for r in rows} == {0, 1, 2, 3}
    assert {r["noise"] for r in rows} == {0.0, 0.01, 0.02, 0.05, 0.1}
    raw, guard = f["raw"]["dead"], f["guard"]["dead"]
    # with no fault the guard changes (almost) nothing; with one dead sensor it helps
    assert abs(raw["0"]["mean"] - guard["0"]["mean"]) < 0.02
    assert guard["1"]["mean"] > raw["1"]["mean"] + 0.05


@pytest.mark.slow
def test_two_rooms_select_quick(tmp_path):
    """--select: a leak pair and a unit count (2 or 4) chosen per seed without labels, with
    its rank correlation and the picked vs SMC09 comparison in metrics.json."""
    from hippo.scenarios._selection import CANDIDATES

    m = run_scenario("two-rooms", ["--quick", "--out", str(tmp_path), "--select",
                                   "--no-ceiling", "--no-figures"])
    sel = m["selection"]
    assert sel["criterion"] == "bimodal-stable" and sel["seeds"] == [0]
    assert tuple(sel["chosen"][0]) in CANDIDATES and sel["chosen_units"][0] in (2, 4)
    run = sel["runs"][0]
    assert len(run["scores"]) == len(run["labelled_accuracy"]) == 32
    c = int(np.argmin(run["scores"]))
    assert run["chosen"] == list(CANDIDATES[c % 16]) and run["chosen_units"] == (2, 4)[c // 16]
    assert -1 <= sel["spearman_mean"] <= 1
    # quick seed 0: every candidate's room cell is far above chance
    assert min(run["labelled_accuracy"]) > 0.6
    # the comparison is with SMC09's fixed settings (4 units, 0.05/0.15) as the scenario fits
    # them. (Not with the same candidate in the sweep: its features, harvested in a batch of
    # 16, differ by ~4e-7, and 4-unit symmetric FastICA can land in another optimum: quick
    # seed 0 gives 0.69 there against 0.96 for the plain fit.)
    smc = m["smc09"]["room_cell_test_balanced_accuracy"]["per_seed"]
    assert sel["paper_accuracy"] == smc
    assert 0.5 < run["paper_accuracy_in_sweep"] <= 1
    assert sel["picked_accuracy"] == [m["selected"]["room_cell_test_balanced_accuracy"]
                                      ["per_seed"][0]]
    assert sel["groups"][0]["picked_minus_paper"] == pytest.approx(
        sel["picked_accuracy"][0] - sel["paper_accuracy"][0])


def test_two_rooms_select_rejects_unknown_criterion():
    with pytest.raises(SystemExit):
        run_scenario("two-rooms", ["--quick", "--select", "--select-criterion", "labels"])


@pytest.mark.parametrize("units", ["0", "2,2", "x", "2,300"])
def test_two_rooms_select_units_are_checked_before_any_work(units, capsys):
    with pytest.raises(SystemExit):
        run_scenario("two-rooms", ["--quick", "--select", "--neurons", "100",
                                   "--select-units", units])
    assert "--select-units" in capsys.readouterr().err


def test_two_rooms_slow_pool(tmp_path):
    """--slow-pool: the models read the state and its running mean; a bad value, or with
    --faults / --leak-sweep (not wired), is refused before any work."""
    m = run_scenario("two-rooms", ["--quick", "--slow-pool", "100", "--no-figures",
                                   "--out", str(tmp_path)])
    assert m["slow_pool"] == 100.0
    assert 0.6 <= m["room_cell_test_balanced_accuracy"] <= 1.0
    for bad in (["--slow-pool", "0.5"], ["--slow-pool", "100", "--faults"],
                ["--slow-pool", "100", "--leak-sweep"]):
        with pytest.raises(SystemExit):
            run_scenario("two-rooms", ["--quick", *bad])


def _telegraph(rng, T, p):
    return 2.0 * (np.cumsum(rng.random(T) < p) % 2) - 1.0


def _smoothed(rng, T, tau):
    from scipy.signal import lfilter

    y = lfilter([1.0 / tau], [1.0, 1.0 / tau - 1.0], rng.standard_normal(T))
    return (y - y.mean()) / y.std()


def test_ica_on_the_two_slowest_features_recovers_the_slow_binary_source():
    """Known answer for the room cell's default model (2 SFA / 2 ICA units): a slow binary
    source ("room", ±1, switching every ~500 ticks) mixed into 10 channels with a slow Gaussian
    source, sparse bursts that occur only while the room is +1 (not independent of it, like a
    landmark of one room) and three fast sources. FastICA on the two slowest SFA outputs gives
    the room back (|r| 0.992) as the slowest unit (the choice that needs no labels); FastICA
    on four SFA outputs mixes the bursts in (|r| 0.971)."""
    from hippo.perception.ica import FastICA
    from hippo.perception.ica_params import ICAParams
    from hippo.perception.sfa import SFA, SFAParams
    from hippo.scenarios._two_rooms_report import _slowness

    rng = np.random.default_rng(0)
    T = 20000
    room = _telegraph(rng, T, 0.002)
    bursts = np.convolve((rng.random(T) < 0.02) & (room > 0), np.ones(40), "same")
    S = np.column_stack([room, _smoothed(rng, T, 150), (bursts - bursts.mean()) / bursts.std(),
                         *(_smoothed(rng, T, tau) for tau in (3, 5, 10))])
    X = S @ rng.standard_normal((S.shape[1], 10)) + 0.05 * rng.standard_normal((T, 10))
    r = {}
    for k in (2, 4):
        Y = SFA(SFAParams(n_components=k)).fit_transform(X)
        Z = FastICA(ICAParams(n_components=k, n_restarts=10, seed=0)).fit(Y).transform(Y)
        corr = np.abs([np.corrcoef(Z[:, j], room)[0, 1] for j in range(k)])
        r[k] = corr.max()
        if k == 2:
            assert int(np.argmin(_slowness(Z))) == int(np.argmax(corr))
    assert r[2] > 0.99
    assert r[4] < r[2] - 0.01


def test_slowness_ranks_a_slow_sine_before_a_fast_one():
    from hippo.scenarios._two_rooms_report import _slowness

    t = np.arange(5000)
    Y = np.c_[3 * np.sin(2 * np.pi * t / 50), 0.1 * np.sin(2 * np.pi * t / 1000)]
    # Δ of a unit-variance sine of period P is (2π/P)² (up to the discrete difference)
    np.testing.assert_allclose(_slowness(Y), (2 * np.pi / np.array([50, 1000])) ** 2, rtol=0.01)


def test_the_summary_says_when_a_kidnap_never_recovered(tmp_path, capsys):
    # "right again after 35 ticks" read as a success while one of three kidnaps never
    # recovered (the mean is over the recovered ones); quick seed 3 at --rho 0.6: room cell 0.62
    m = run_scenario("two-rooms", ["--quick", "--rho", "0.6", "--seed", "3", "--no-figures",
                                   "--no-ceiling", "--out", str(tmp_path)])
    out = capsys.readouterr().err   # the summary goes to stderr
    assert m["kidnap_unrecovered"] >= 1 and math.isfinite(m["kidnap_recovery_ticks"])
    assert f"{m['kidnap_unrecovered']} kidnap(s) never recovered" in out


@pytest.mark.parametrize("argv", [["--leak", "1,1"], ["--n-sfa", "1", "--n-ica", "1"]])
def test_a_room_cell_at_chance_reports_no_kidnapping_recovery(argv, tmp_path, capsys):
    # a memoryless cell (leak 1) or one unit flickering at chance (0.52, 0.50) was "right
    # again after 0 ticks" (targets 15): right for --hold ticks by luck
    from hippo.scenarios._two_rooms_report import RECOVERY_MIN_ACCURACY

    m = run_scenario("two-rooms", ["--quick", *argv, "--no-figures", "--no-ceiling",
                                   "--out", str(tmp_path)])
    assert m["room_cell_test_balanced_accuracy"] < RECOVERY_MIN_ACCURACY == 0.6
    assert math.isnan(m["kidnap_recovery_ticks"]) and m["kidnap_unrecovered"] == 0
    assert "too near chance" in m["kidnap_recovery_withheld_seeds"]["0"]
    # the raw recovery times stay in the seed's own row
    assert len(m["runs"]["paper"][0]["kidnap_recovery_ticks_each"]) == 4
    out = capsys.readouterr().err
    assert "recovery not reported (1 seed(s) left out" in out and "after 0 ticks" not in out


def test_a_seed_without_both_rooms_is_reported_unscored_and_the_others_kept(tmp_path, capsys):
    # quick, --rho 0.6: seed 2's training part stays in room A ("truth needs both classes"
    # ended the whole run, no metrics.json); seeds 0 and 1's test parts stay in one room (they
    # were left out of the mean in silence, "room cell 0.62" from 1 of 4 seeds)
    m = run_scenario("two-rooms", ["--quick", "--rho", "0.6", "--seeds", "0-3", "--no-figures",
                                   "--no-ceiling", "--out", str(tmp_path)])
    assert m["seeds_scored"] == 1 and m["room_cell_test_balanced_accuracy"] > 0.6
    assert m["unscored_seeds"] == {"0": "the test part visited only room A",
                                   "1": "the test part visited only room B",
                                   "2": "the training part visited only room A"}
    assert m["shown_seed"] == 0 and (tmp_path / "run.npz").exists()
    out = capsys.readouterr().err
    assert "(1 of 4 seeds scored)" in out
    assert "not scored: seed 2: the training part visited only room A" in out
    # every seed unscored: the metrics say why, and nothing is shown
    m = run_scenario("two-rooms", ["--quick", "--rho", "0.6", "--seed", "2", "--no-figures",
                                   "--out", str(tmp_path / "one")])
    assert m["seeds_scored"] == 0 and math.isnan(m["room_cell_test_balanced_accuracy"])
    assert (tmp_path / "one" / "metrics.json").exists()
    assert not (tmp_path / "one" / "run.npz").exists()
    assert "room cell not scored (0 of 1 seeds scored)" in capsys.readouterr().err
