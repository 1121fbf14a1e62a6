"""`hippo run maze --quick`: runs end to end, writes its files, sane metric values."""

import json

from hippo.cli import run_scenario


def test_maze_quick(tmp_path):
    out = tmp_path / "maze"
    m = run_scenario("maze", ["--quick", "--out", str(out)])
    for name in ("metrics.json", "run.npz", "place_cells.npz", "fig3_activation_map.png",
                 "fig3_activation_map_ablation.png", "place_fields.png", "fig2a_sfa_units.png"):
        assert (out / name).exists(), name
    saved = json.loads((out / "metrics.json").read_text())
    for key in ("localized_units", "location_decoding_accuracy_test",
                "location_decoding_within_one_step_test", "ablation_localized_units",
                "ablation_location_decoding_accuracy_test"):
        assert key in m and key in saved
    # seed 0, quick (60,000 ticks, 100 neurons, 20 units, washout 1,150 of 2,000 training
    # updates): 2 localized units, decoding 0.21 exact / 0.36 within one step (chance ~0.05),
    # ceiling 0.83 / 0.93, ablation 0.13 within one step
    assert 1 <= m["localized_units"] <= m["units"]
    assert 0.1 <= m["location_decoding_accuracy_test"] <= m[
        "location_decoding_within_one_step_test"] <= 1.0
    assert m["location_decoding_within_one_step_test"] >= 0.25
    assert m["location_decoding_within_one_step_test"] > \
        m["ablation_location_decoding_within_one_step_test"] + 0.1
    ceiling = m["rc_sfa_ica"]["ceiling_location_decoding_within_one_step"]["mean"]
    assert 0.8 <= ceiling <= 1.0
    # the population read-out (nearest location centroid of all 20 units: 0.59 / 0.82) reads
    # what the winner misses, and stays below the supervised ceiling on the reservoir state
    assert "population_decoding_accuracy_test" in saved
    assert m["location_decoding_within_one_step_test"] + 0.2 < \
        m["population_decoding_within_one_step_test"] <= ceiling
    # the start from rest is left out of the fit (RCSFAICAParams.transient_updates)
    assert m["washout_updates"] == {"rc_sfa_ica": 1150, "no_reservoir_quadratic": 2}
