"""The timing demo's parts (:mod:`hippo.scenarios.timing_demo`) on stand-ins: its options on
their bounds and one past, the untimed trial ends' warning filter, one place-preference trial
through a stand-in pipeline (the ticks of each stage counted by hand, the sound at
``delay - dt / 2``, the non-occurrence's resume, the readouts traced), a learner probed
after its pairings, and the full width at half maximum, by hand."""

from __future__ import annotations

import argparse
import math
import warnings
from pathlib import Path
from types import SimpleNamespace
from typing import Any, ClassVar

import numpy as np
import pytest
from stand_ins import recording_progress

import hippo.scenarios.timing_demo as T
from hippo.seeds import Seeds
from hippo.timing import DelayRangeWarning
from hippo.types import StateKind


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser()
    T.add_arguments(p)
    return p


def test_constants():
    assert T.DT == 0.2 and T.GOAL_COLOUR == 2 and T.OTHER == 2
    assert T.HIREL_TABLE1 == {24.1: (22.3, 0.7), 19.1: (19.1, 0.3), 11.6: (15.3, 0.8)}
    assert T.FULL_DELAYS == (2.0, 3.5, 7.0, 11.6, 19.1, 24.1, 45.0, 60.0)
    assert T.QUICK_DELAYS == (2.0, 7.0, 20.0)


def test_the_options_defaults_and_bounds():
    a = _parser().parse_args([])
    assert (a.delay, a.pairings, a.delays, a.reproductions, a.jitter, a.noise) == (
        7.0, None, None, None, 0.1, 0.3)
    acts = {x.dest: x for x in _parser()._actions}
    for dest, ok, bad in (("delay", ("0.2", "100"), ("0.19", "100.01")),
                          ("pairings", ("1", "1000"), ("0", "1001")),
                          ("reproductions", ("1", "1000"), ("0", "1001")),
                          ("jitter", ("0", "0.99"), ("-0.01", "1")),
                          ("noise", ("0", "10"), ("-0.01", "10.01"))):
        f = acts[dest].type
        assert [float(f(v)) for v in ok] == [float(v) for v in ok]
        for v in bad:
            with pytest.raises(argparse.ArgumentTypeError):
                f(v)
    delays = acts["delays"].type
    assert delays("0.2,100") == [0.2, 100.0]
    assert delays(",".join(["1"] * 50)) == [1.0] * 50
    for bad in ("0.1", "100.5", ",".join(["1"] * 51)):
        with pytest.raises(argparse.ArgumentTypeError):
            delays(bad)
    with pytest.raises(argparse.ArgumentTypeError, match=r"\(s\)"):
        delays("0.1")


def test_untimed_trial_ends_silence_only_moves_into_other():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with T._untimed_trial_ends():
            warnings.warn("transition 0->2 came after 200 s", DelayRangeWarning, stacklevel=1)
            warnings.warn("transition 13->2 came after 200 s", DelayRangeWarning, stacklevel=1)
            for msg, cat in (("transition 0->1 came after 200 s", DelayRangeWarning),
                             ("transition 0->21 came after 200 s", DelayRangeWarning),
                             ("transition 0->2 came after 200 s", RuntimeWarning),
                             ("transition x->2 came after 200 s", DelayRangeWarning)):
                with pytest.raises(cat):
                    warnings.warn(msg, cat, stacklevel=1)
        with pytest.raises(DelayRangeWarning):     # the filter ends with the block
            warnings.warn("transition 0->2 came after 200 s", DelayRangeWarning, stacklevel=1)


def test_fwhm_by_hand():
    tau = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    assert T._fwhm(tau, np.array([0.0, 1.0, 4.0, 2.0, 0.0])) == 1.0    # 2 = half of 4: in
    assert T._fwhm(tau, np.array([0.0, 1.9, 4.0, 1.9, 0.0])) == 0.0
    assert T._fwhm(tau, np.array([2.0, 0.0, 4.0, 0.0, 3.0])) == 4.0    # first to last above
    assert math.isnan(T._fwhm(tau, np.zeros(5)))
    assert math.isnan(T._fwhm(tau, -np.ones(5)))
    assert math.isnan(T._fwhm(np.zeros(0), np.zeros(0)))


# ------------------------------------------------------------------------ one trial
STILL, SOUND_STATE, ELSE = 5, 7, 8


class _Pipe:
    """Winner STILL from the stop until the sound (or a move after the non-occurrence);
    readouts of (STILL, SOUND_STATE) predicting 10 tau while waiting."""

    def __init__(self, fire_at: float | None = None, blank_at: int | None = None) -> None:
        self.calls: list[tuple] = []
        self.fire_at, self.blank_at = fire_at, blank_at
        self.tau, self.waiting, self.n_wait = 0.0, False, 0
        kinds = {SOUND_STATE: StateKind.SOUND, ELSE: StateKind.PLACE}
        self.layer = SimpleNamespace(key=lambda b: SimpleNamespace(kind=kinds[b]))

    def tick(self, place: np.ndarray, colour: int, sound: bool, moving: bool, dt: float):
        self.calls.append((tuple(place), colour, sound, moving, dt))
        if not self.waiting and colour == T.GOAL_COLOUR and not moving:
            self.waiting, self.tau = True, 0.0
            return SimpleNamespace(winner=STILL), {}, False
        if not self.waiting:
            return SimpleNamespace(winner=1), {}, False
        self.tau += dt
        self.n_wait += 1
        if sound or moving:
            self.waiting = False
            return SimpleNamespace(winner=6), {}, False
        ro = SimpleNamespace(prediction=10.0 * self.tau, delay_over=self.tau > 0.5,
                             elapsed_fraction=self.tau / 2.0)
        readouts = ({} if self.n_wait == self.blank_at else
                    {(STILL, ELSE): SimpleNamespace(prediction=-1.0, delay_over=True,
                                                    elapsed_fraction=-1.0),
                     (STILL, SOUND_STATE): ro})
        omitted = self.fire_at is not None and self.tau >= self.fire_at
        return SimpleNamespace(winner=STILL), readouts, omitted


def _stages(calls: list[tuple]) -> list[tuple]:
    """Runs of equal (place, colour, moving) as (place, colour, moving, count)."""
    out: list[list] = []
    for place, colour, _, moving, _ in calls:
        if out and out[-1][:3] == [place, colour, moving]:
            out[-1][3] += 1
        else:
            out.append([place, colour, moving, 1])
    return [tuple(x) for x in out]


START, GOAL = (3.0, 0.0), (0.0, 3.0)


def test_a_rewarded_trial_without_jitter_or_noise():
    pipe = _Pipe(blank_at=2)
    tr = T._place_preference_trial(pipe, np.random.default_rng(0), 0.9, True, 0.0, 0.0)
    # 15 ticks of 0.2 to reach 3 s (14 make 2.8000000000000003), 5 to reach 1 s, the stop at
    # dt; the sound at tau >= 0.9 - 0.1 = 0.8 (the 4th tick); 1 s still, 3 s moving
    assert _stages(pipe.calls) == [(START, 0, True, 15), (GOAL, 2, True, 5),
                                   (GOAL, 2, False, 1 + 4 + 5), (START, 0, True, 15)]
    assert all(c[4] == 0.2 for c in pipe.calls)
    assert [c[2] for c in pipe.calls].count(True) == 1 and pipe.calls[24][2] is True
    assert tr.end == 0.8
    np.testing.assert_array_equal(tr.tau, [0.2, 0.4, 0.2 + 0.2 + 0.2])
    np.testing.assert_array_equal(tr.prediction, [2.0, 0.0, 10.0 * (0.2 + 0.2 + 0.2)])
    np.testing.assert_array_equal(tr.delay_over, [False, False, True])
    assert tr.delay_over.dtype == bool
    np.testing.assert_array_equal(tr.elapsed_fraction, [0.1, 0.0, (0.2 + 0.2 + 0.2) / 2])
    assert tr.fired == []


def test_an_extinction_trial_resumes_after_the_non_occurrence():
    pipe = _Pipe(fire_at=0.5)
    tr = T._place_preference_trial(pipe, np.random.default_rng(0), 0.9, False, 0.0, 0.0)
    assert tr.end is None
    # it fires at tau 0.6000000000000001 (3rd tick), moves on at the 4th, which ends the wait
    assert tr.fired == [0.2 + 0.2 + 0.2]
    np.testing.assert_array_equal(tr.tau, [0.2, 0.4, 0.2 + 0.2 + 0.2])
    waits = [c[3] for c in pipe.calls[21:25]]
    assert waits == [False, False, False, True]
    assert not any(c[2] for c in pipe.calls)       # no sound in extinction
    # then 1 s at the goal moving (no sound came), 3 s at the start
    # (the move that ended the wait is the first of them)
    assert _stages(pipe.calls)[-2:] == [(GOAL, 2, True, 1 + 5), (START, 0, True, 15)]
    assert len(pipe.calls) == 15 + 5 + 1 + 4 + 5 + 15


def test_a_wait_without_end_stops_at_three_delays():
    pipe = _Pipe()
    tr = T._place_preference_trial(pipe, np.random.default_rng(0), 0.2, False, 0.0, 0.0)
    # tau < 0.6: 0.2, 0.4, 0.6000000000000001 (three ticks), no end
    assert len(tr.tau) == 3 and tr.end is None and tr.fired == []


class _Rng:
    def __init__(self) -> None:
        self.uniform_args: list[tuple] = []

    def uniform(self, lo: float, hi: float) -> float:
        self.uniform_args.append((lo, hi))
        return 0.25

    def standard_normal(self, n: int) -> np.ndarray:
        return np.arange(1.0, n + 1.0)


def test_jitter_and_noise_are_drawn_as_the_rule_says():
    pipe, rng = _Pipe(), _Rng()
    T._place_preference_trial(pipe, rng, 1.0, True, 0.5, 0.1)
    assert set(rng.uniform_args) == {(-0.1, 0.1)}
    ticks = [c[4] for c in pipe.calls]
    # each tick 0.2 (1 + 0.25) = 0.25: 12 to 3 s, 4 to 1 s; the stop's tick is dt = 0.2
    assert ticks[:17] == [0.25] * 16 + [0.2]
    assert pipe.calls[0][0] == (3.5, 1.0) and pipe.calls[12][0] == (0.5, 4.0)
    assert _stages(pipe.calls)[0] == ((3.5, 1.0), 0, True, 12)
    assert _stages(pipe.calls)[-1] == ((3.5, 1.0), 0, True, 12)    # 12 x 0.25 is 3 exactly
    # the sound at tau >= 1 - 0.25 / 2: the 4th tick (1.0)
    assert [c[2] for c in pipe.calls].index(True) == 16 + 1 + 3


# ------------------------------------------------------------------------ a probed learner
def test_probe_teaches_pairings_trials_then_probes_for_two_delays(monkeypatch):
    calls: list[tuple] = []
    chain = SimpleNamespace(cells="cells")
    monkeypatch.setattr(T, "TimingChain", lambda: chain)

    def run_trial(c, a, b, d, **kw):
        assert c is chain
        calls.append((a, b, d, kw))
        return "probe" if d is None else "trial"

    monkeypatch.setattr(T, "run_trial", run_trial)
    args = argparse.Namespace(seed=5, jitter=0.3)
    probe, cells = T._probe(args, 3, 2, 4.0)
    assert (probe, cells) == ("probe", "cells")
    assert len(calls) == 4
    rngs = [kw.pop("rng") for *_, kw in calls[:3]]
    assert rngs[0] is rngs[1] is rngs[2]
    want = Seeds(5).generator("timing-trials", 2).random(3)
    np.testing.assert_array_equal(rngs[0].random(3), want)
    assert calls[:3] == [(0, 1, 4.0, {"dt": 0.2, "jitter": 0.3, "other": 2})] * 3
    assert calls[3] == (0, 1, None, {"dt": 0.2, "jitter": 0.0, "t_max": 8.0, "other": 2})


# ------------------------------------------------------------------------ run on stand-ins
def _trace(tau: list[float], pred: list[float], over: list[bool], fired: list[float],
           end: float | None) -> Any:
    from hippo.timing.trials import TrialTrace

    return TrialTrace(np.array(tau, dtype=float), np.array(pred, dtype=float),
                      np.array(over, dtype=bool), np.zeros(len(tau)), fired, end)


class _Cells:
    transitions: ClassVar[list[tuple[int, int]]] = [(0, 1), (1, 3), (2, 3)]
    delays: ClassVar[dict[tuple[int, int], float]] = {(0, 1): 2.0004, (1, 3): 7.1234, (2, 3): 6.5}

    def learned_delay(self, k: tuple[int, int]) -> float:
        return self.delays[k]


class _Layer:
    kinds: ClassVar[dict[int, StateKind]] = {0: StateKind.PLACE, 1: StateKind.STILL,
                                             2: StateKind.STILL, 3: StateKind.SOUND}

    def key(self, i: int) -> Any:
        return SimpleNamespace(kind=self.kinds[i])

    def describe(self, i: int) -> str:
        return f"s{i}"


class _TC:
    """A learner whose expectation is 1 on the grid's points 1000-2000 (of 0..5000)."""

    def __init__(self, d: float) -> None:
        self.d, self.params = d, SimpleNamespace(latency=0.4)

    def learned_delay(self, k: tuple[int, int]) -> float:
        assert k == (0, 1)
        return self.d + 0.5

    def expected(self, a: int, fine: np.ndarray) -> dict:
        assert a == 0 and len(fine) == 5001
        assert fine[0] == 0.01 and fine[-1] == 2.5 * self.d
        x = np.zeros(5001)
        x[1000:2001] = 1.0
        return {(0, 1): x}


def _run_timing(monkeypatch, tmp_path, argv: list[str], *, cells: Any = None,
                extinction_fired: list[float] | None = None, empty_rewarded: bool = False
                ) -> tuple[dict, dict]:
    seen: dict[str, Any] = {"trials": [], "probes": [], "reproduce": [], "figs": []}
    pipe = SimpleNamespace(cells=cells or _Cells(), layer=_Layer())
    monkeypatch.setattr(T, "_Pipeline", lambda: pipe)
    rewarded = _trace([0.2, 0.4, 0.6], [0.1, 0.9, 0.5], [False, False, True], [0.6], 7.0)
    extinction = _trace([0.2, 0.4], [0.2, 0.3], [False, True],
                        [9.5, 12.0] if extinction_fired is None else extinction_fired, None)

    def trial(p, rng, delay, rewarded_, noise, jitter):
        assert p is pipe
        seen["trials"].append((delay, rewarded_, noise, jitter))
        seen.setdefault("rng", rng)
        assert rng is seen["rng"]
        return rewarded if rewarded_ else extinction

    def probe(args, pairings, i, d):
        seen["probes"].append((pairings, i, d))
        if d == 2.0:
            return _trace([0.5, 1.0, 1.5], [0.1, 0.7, 0.3], [False, True, True], [], None), _TC(d)
        return _trace([1.0], [0.0], [False], [], None), _TC(d)

    def reproduce(d, seed, jitter):
        seen["reproduce"].append((d, seed, jitter))
        waits = {2.0: [1.0, 3.0], 7.0: [7.0, math.nan], 20.0: [30.0, 10.0]}.get(d, [d])
        return SimpleNamespace(waits=waits if seed % 1000 == 0 else [2.0 * d],
                               non_occurrence_lag=0.5 + seed % 1000)

    class _Fig:
        def __init__(self, name: str) -> None:
            self.name = name

        def savefig(self, path, dpi):
            seen["figs"].append((self.name, Path(path).name, dpi))

    def fig6(rw, ex, delay, by_delay, title):
        seen["fig6"] = (rw is rewarded, ex is extinction, delay, sorted(by_delay), title)
        return _Fig("fig6"), None

    def repro(delays, waits_all, reference, title):
        seen["repro"] = (list(delays), [list(w) for w in waits_all], reference, title)
        return _Fig("repro"), None

    monkeypatch.setattr(T, "Progress", recording_progress(seen))
    if empty_rewarded:
        rewarded = _trace([], [], [], [], 7.0)
    monkeypatch.setattr(T, "_place_preference_trial", trial)
    monkeypatch.setattr(T, "_probe", probe)
    monkeypatch.setattr(T, "reproduce", reproduce)
    monkeypatch.setattr(T, "plot_fig6", fig6)
    monkeypatch.setattr(T, "plot_reproduction", repro)
    monkeypatch.setattr(T, "plt", SimpleNamespace(close=lambda f: seen["figs"].append(
        ("closed", f.name))))
    monkeypatch.setattr(T, "save_npz", lambda path, arrays: seen.update(
        npz=(Path(path).name, arrays)))
    p = argparse.ArgumentParser()
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--quick", action="store_true")
    T.add_arguments(p)
    args = p.parse_args(argv)
    args.out = str(tmp_path / "out")
    return T.run(args), seen


def test_run_quick_on_stand_ins(monkeypatch, tmp_path, capsys):
    m, seen = _run_timing(monkeypatch, tmp_path, ["--quick", "--seed", "2"])
    # 3 pairings, then one rewarded and one extinction trial, delay 7, noise 0.3, jitter 0.1
    assert seen["trials"] == [(7.0, True, 0.3, 0.1)] * 4 + [(7.0, False, 0.3, 0.1)]
    np.testing.assert_array_equal(seen["rng"].random(2),
                                  Seeds(2).generator("timing-pipeline").random(2))
    assert seen["probes"] == [(3, 0, 2.0), (3, 1, 7.0), (3, 2, 20.0)]
    assert seen["progress"] == [6, "reproduction", 1, 1, 1, 1, 1, 1]
    assert seen["reproduce"] == [(2.0, 2000, 0.1), (2.0, 2001, 0.1), (7.0, 2000, 0.1),
                                 (7.0, 2001, 0.1), (20.0, 2000, 0.1), (20.0, 2001, 0.1)]
    assert m["delay_s"] == 7.0 and m["pairings"] == 3 and m["seed"] == 2
    assert (m["noise"], m["jitter"], m["quick"]) == (0.3, 0.1, True)
    assert m["transitions_learned_s"] == {"s0 -> s1": 2.0, "s1 -> s3": 7.123, "s2 -> s3": 6.5}
    assert m["reward_transition_learned"] is True
    assert m["reward_learned_delay_s"] == 7.1234      # the first transition into the sound
    assert m["rewarded_prediction_peak_s"] == 0.4 and m["rewarded_sound_s"] == 7.0
    assert m["rewarded_non_occurrence"] is True
    assert m["extinction_non_occurrence_s"] == 9.5
    assert m["extinction_resume_after_delay_s"] == 2.5
    two = m["by_delay"]["2"]
    assert two["learned_delay_s"] == 2.5 and two["prediction_peak_s"] == 1.0
    # the grid 0.01 .. 5 in 5000 steps: points 1000 to 2000 are 1000 steps of 4.99 / 5000
    assert two["prediction_fwhm_over_delay"] == pytest.approx(1000 * 4.99 / 5000 / 2.0)
    assert two["delay_over_seen_s"] == 1.0 + 0.4
    assert math.isnan(m["by_delay"]["7"]["delay_over_seen_s"])
    assert set(m["by_delay"]) == {"2", "7", "20"}
    # 2 s: waits 1, 3 (seed x000) and 4 (seed x001): mean 8/3, errors -50, 50, 100 %
    r2 = m["reproduction"]["2"]
    assert r2["mean_s"] == pytest.approx(8 / 3)
    assert r2["sd_s"] == pytest.approx(np.std([1.0, 3.0, 4.0]))
    assert r2["mean_error_pct"] == pytest.approx(100 / 3)
    assert r2["max_abs_error_pct"] == pytest.approx(100.0)
    assert r2["non_occurrence_after_s"] == 1.0        # lags 0.5 and 1.5
    # 7 s: 7, nan, 14: the nan left out
    r7 = m["reproduction"]["7"]
    assert r7["mean_s"] == 10.5 and r7["mean_error_pct"] == 50.0
    assert r7["max_abs_error_pct"] == 100.0
    # 20 s: 30, 10, 40: mean 80/3, errors 50, -50, 100: mean 100/3
    assert m["reproduction"]["20"]["mean_error_pct"] == pytest.approx(100 / 3)
    assert m["worst_mean_error_pct"] == 50.0
    assert seen["fig6"] == (True, True, 7.0, [2.0, 7.0, 20.0],
                            "Timed prediction of the reward (learned delay 7 s)")
    delays, waits_all, ref, title = seen["repro"]
    assert delays == [2.0, 7.0, 20.0] and waits_all[0] == [1.0, 3.0, 4.0]
    assert ref == T.HIREL_TABLE1 and title == "Learned vs reproduced waits (closed loop)"
    assert seen["figs"] == [("fig6", "fig6_timing.png", 110), ("closed", "fig6"),
                            ("repro", "reproduction.png", 110), ("closed", "repro")]
    name, arrays = seen["npz"]
    assert name == "run.npz"
    np.testing.assert_array_equal(arrays["rewarded_tau"], [0.2, 0.4, 0.6])
    np.testing.assert_array_equal(arrays["rewarded_prediction"], [0.1, 0.9, 0.5])
    np.testing.assert_array_equal(arrays["extinction_tau"], [0.2, 0.4])
    np.testing.assert_array_equal(arrays["extinction_prediction"], [0.2, 0.3])
    np.testing.assert_array_equal(arrays["extinction_fired_s"], [9.5, 12.0])
    np.testing.assert_array_equal(arrays["delays_s"], [2.0, 7.0, 20.0])
    np.testing.assert_allclose(arrays["reproduced_mean_s"], [8 / 3, 10.5, 80 / 3])
    np.testing.assert_allclose(arrays["reproduced_sd_s"],
                               [np.std([1.0, 3.0, 4.0]), 3.5, np.std([30.0, 10.0, 40.0])])
    np.testing.assert_array_equal(arrays["probe0_tau"], [0.5, 1.0, 1.5])
    np.testing.assert_array_equal(arrays["probe0_prediction"], [0.1, 0.7, 0.3])
    np.testing.assert_array_equal(arrays["probe2_tau"], [1.0])
    assert set(arrays) == {"rewarded_tau", "rewarded_prediction", "extinction_tau",
                           "extinction_prediction", "extinction_fired_s", "delays_s",
                           "reproduced_mean_s", "reproduced_sd_s", *(
                               f"probe{i}_{k}" for i in range(3)
                               for k in ("tau", "prediction"))}
    assert ("timing: the reward delay (7 s) learned as 7.12 s; in extinction the "
            "non-occurrence fired 2.5 s after the delay; reproduced delays 2, 7, 20 s within "
            "50.0 % (worst mean error)") in capsys.readouterr().err


def test_run_defaults_and_given_counts(monkeypatch, tmp_path):
    _, seen = _run_timing(monkeypatch, tmp_path, [])
    assert len(seen["trials"]) == 5 + 2
    assert [p[2] for p in seen["probes"]] == list(T.FULL_DELAYS)
    assert len(seen["reproduce"]) == 6 * 8 and seen["reproduce"][5] == (2.0, 5, 0.1)
    _, seen = _run_timing(monkeypatch, tmp_path, ["--quick", "--pairings", "1",
                                                  "--reproductions", "1", "--delays", "7,2",
                                                  "--delay", "3", "--noise", "0",
                                                  "--jitter", "0"])
    assert seen["trials"] == [(3.0, True, 0.0, 0.0)] * 2 + [(3.0, False, 0.0, 0.0)]
    assert seen["probes"] == [(1, 0, 7.0), (1, 1, 2.0)]
    assert seen["reproduce"] == [(7.0, 0, 0.0), (2.0, 0, 0.0)]


def test_run_with_no_reward_learned_and_no_give_up(monkeypatch, tmp_path, capsys):
    cells = SimpleNamespace(transitions=[(0, 1)], learned_delay=lambda k: 2.0)
    m, _ = _run_timing(monkeypatch, tmp_path, ["--quick"], cells=cells, extinction_fired=[],
                       empty_rewarded=True)
    assert math.isnan(m["rewarded_prediction_peak_s"])
    assert m["reward_transition_learned"] is False
    assert math.isnan(m["reward_learned_delay_s"])
    assert m["extinction_non_occurrence_s"] is None
    assert m["extinction_resume_after_delay_s"] is None
    assert "in extinction the non-occurrence fired never;" in capsys.readouterr().err


def test_the_pipeline_feeds_the_brain_one_tick():
    from hippo.timing import TransitionParams

    pipe = T._Pipeline()
    assert pipe.layer is pipe.brain.layer and pipe.cells is pipe.brain.cells
    assert pipe.brain.p.transitions == TransitionParams()
    asked = []

    def perceive(place, **kw):
        asked.append((place, kw))
        return SimpleNamespace(event="ev", timing=SimpleNamespace(readouts="ro", omitted=True))

    pipe.brain = SimpleNamespace(perceive=perceive)
    place = np.array([1.0, 2.0])
    assert pipe.tick(place, 2, True, False, 0.3) == ("ev", "ro", True)
    assert asked == [(place, {"colour": 2, "sound": True, "moving": False, "dt": 0.3})]


def test_a_sound_at_the_first_tick_leaves_an_empty_bool_trace():
    pipe = _Pipe()
    # delay 0.2: the sound at tau >= 0.1, the first tick of the wait: nothing traced
    tr = T._place_preference_trial(pipe, np.random.default_rng(0), 0.2, True, 0.0, 0.0)
    assert tr.end == 0.2 and tr.tau.size == 0 and tr.fired == []
    assert tr.delay_over.dtype == bool and tr.delay_over.shape == (0,)
