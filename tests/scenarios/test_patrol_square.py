"""The 40-line user example (``scenarios/patrol_square.py``): a patrol in a new arena."""

from user_examples import SCENARIOS, load_example

SCRIPT = SCENARIOS / "patrol_square.py"


def _load():
    return load_example("patrol_square")


def test_the_example_stays_short():
    lines = SCRIPT.read_text().split("\nfrom enum", 1)[1].split('\nif __name__')[0]
    code = [ln for ln in lines.splitlines() if ln.strip() and not ln.strip().startswith("#")]
    assert len(code) <= 40   # from "from enum import IntEnum" to the end of main()


def test_the_example_patrols_with_ground_truth_place_cells(tmp_path):
    # measured (seed 0, --quick, one lap): east 7.8 s, west 13.8 s (taught 8 and 14)
    waits = _load().main(seed=0, out=str(tmp_path), quick=True, place_cells="ground-truth")
    for name, w in waits.items():
        assert w["reproduced_s"], f"no stop at {name}"
        assert all(abs(r - w["taught_s"]) <= 0.03 * w["taught_s"] for r in w["reproduced_s"])
    assert (tmp_path / "run.npz").exists() and (tmp_path / "metrics.json").exists()

