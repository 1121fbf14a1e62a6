"""`hippo run two-rooms --quick`: runs end to end, writes its files, sane metric values."""

import json
import math

from hippo.cli import run_scenario


def test_two_rooms_quick(tmp_path):
    out = tmp_path / "two-rooms"
    m = run_scenario("two-rooms", ["--quick", "--out", str(out)])
    for name in ("metrics.json", "run.npz", "place_cells.npz", "fig5_room_cell_train.png",
                 "fig6_room_cell_test.png", "fig7_kidnapping.png", "fig8_corridor_cell_test.png"):
        assert (out / name).exists(), name
    saved = json.loads((out / "metrics.json").read_text())
    for key in ("room_cell_test_balanced_accuracy", "kidnap_recovery_ticks",
                "corridor_cell_test_balanced_accuracy", "leak_0.05_0.15", "leak_0.11_0.14"):
        assert key in m and key in saved
    assert 0.5 <= m["room_cell_test_balanced_accuracy"] <= 1.0
    assert 0.3 <= m["corridor_cell_test_balanced_accuracy"] <= 1.0
    assert math.isnan(m["kidnap_recovery_ticks"]) or 0 <= m["kidnap_recovery_ticks"] < 400
    assert [e["tick"] for e in m["kidnap_events"]] == [150, 400, 640, 980]


def test_two_rooms_leak_option_and_sweep(tmp_path):
    out = tmp_path / "two-rooms"
    m = run_scenario("two-rooms", ["--quick", "--out", str(out), "--leak", "0.08,0.15",
                                   "--leak-sweep", "--ica-restarts", "1"])
    assert m["leak"] == [0.08, 0.15] and "leak_0.08_0.15" in m
    assert (out / "leak_sweep.png").exists()
    rows = m["leak_sweep"]
    assert len(rows) == 16 and len({tuple(r["leak"]) for r in rows}) == 16
    for r in rows:
        assert 0.3 <= r["room_cell_test_balanced_accuracy"] <= 1.0
        assert r["meets_targets"] == (r["room_cell_test_balanced_accuracy"] >= 0.97
                                      and r["kidnap_recovery_ticks"] <= 15)
    assert m["leak_sweep_meeting_targets"] == [r["leak"] for r in rows if r["meets_targets"]]


def test_two_rooms_rejects_bad_leaks():
    import pytest

    for bad in ("0", "a,b", "0.1,1.5"):
        with pytest.raises(SystemExit):
            run_scenario("two-rooms", ["--quick", "--leak", bad])
