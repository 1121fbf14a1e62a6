"""`hippo run timing-demo --quick`: figures, metrics and arrays from the whole event pipeline."""

import json

import numpy as np

from hippo.cli import run_scenario
from hippo.io import load_npz


def test_timing_demo_quick(tmp_path):
    out = tmp_path / "timing"
    metrics = run_scenario("timing-demo", ["--quick", "--out", str(out), "--seed", "1"])
    for name in ("fig6_timing.png", "reproduction.png", "metrics.json", "run.npz"):
        assert (out / name).stat().st_size > 0
    saved = json.loads((out / "metrics.json").read_text())
    assert saved["delay_s"] == 7.0
    assert (saved["noise"], saved["jitter"]) == (0.3, 0.1)   # what the run was (fuzzing pass 3)
    # the place-preference chain was learned through the state layer: still@goal -> sound
    assert metrics["reward_transition_learned"]
    assert abs(metrics["reward_learned_delay_s"] - 7.0) < 0.2
    assert "still@colour 2 -> sound" in metrics["transitions_learned_s"]
    # rewarded trial: the prediction peaks before the sound, no non-occurrence
    assert 6.0 < metrics["rewarded_prediction_peak_s"] <= metrics["rewarded_sound_s"]
    assert not metrics["rewarded_non_occurrence"]
    # extinction: the non-occurrence neuron fires after the delay, within 2 s
    assert 0.0 < metrics["extinction_resume_after_delay_s"] < 2.0
    for d, rep in metrics["reproduction"].items():
        assert abs(rep["mean_error_pct"]) < 3.0, d
    arrays = load_npz(out / "run.npz", required=["rewarded_prediction", "delays_s"])
    assert np.array_equal(arrays["delays_s"], [2.0, 7.0, 20.0])
    assert arrays["extinction_prediction"].max() > 0.5


def test_the_longest_delays_give_no_warning_about_the_demos_own_trials(tmp_path):
    # --delays 100 ended the demo's probe and extinction trials after 200 s, beyond the
    # battery's 120 s, and DelayRangeWarning advised raising SpectralParams.mu_max
    import warnings

    from hippo.timing import DelayRangeWarning

    with warnings.catch_warnings():
        warnings.simplefilter("error", DelayRangeWarning)
        m = run_scenario("timing-demo", ["--quick", "--delays", "100", "--reproductions", "1",
                                         "--pairings", "2", "--out", str(tmp_path)])
    assert abs(m["reproduction"]["100"]["mean_error_pct"]) < 3.0
