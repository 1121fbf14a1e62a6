"""Timing demo: HIREL Fig. 6 without the robot — timed predictions, rewards and extinction.

A symbolic place-preference task runs through the brain's neural chain
(:meth:`hippo.brain.Brain.perceive`: :class:`~hippo.perception.states.StateLayer` ->
:class:`~hippo.timing.SpectralTiming` -> :class:`~hippo.timing.TransitionCells` ->
:class:`~hippo.timing.NonOccurrence`, fed place activities directly): noisy place
cells, a coloured goal zone, the robot stopping there ("still" wins), and the reward sound
``--delay`` seconds later. After ``--pairings`` rewarded trials, one more rewarded trial and one
extinction trial (no sound; the robot resumes when the non-occurrence neuron fires) give
Fig. 6 a-b. Separate learners taught other delays give the predictions of Fig. 6 c-d, and a
closed-loop reproduction of each delay (HIREL Table I) gives ``reproduction.png``.

Outputs in ``--out``: ``fig6_timing.png``, ``reproduction.png``, ``metrics.json``, ``run.npz``.
"""

from __future__ import annotations

import argparse
import math
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from hippo.brain import Brain, BrainParams
from hippo.cli_args import integer, number, numbers
from hippo.io import save_npz
from hippo.plots.timing import plot_fig6, plot_reproduction
from hippo.progress import Progress
from hippo.scenarios._common import prepare_out, write_metrics
from hippo.seeds import Seeds
from hippo.timing import DelayRangeWarning, TransitionCells, TransitionParams
from hippo.timing.chain import TimingChain
from hippo.timing.trials import TrialTrace, reproduce, run_trial
from hippo.types import StateKind

DT = 0.2
GOAL_COLOUR = 2
HIREL_TABLE1 = {24.1: (22.3, 0.7), 19.1: (19.1, 0.3), 11.6: (15.3, 0.8)}
FULL_DELAYS = (2.0, 3.5, 7.0, 11.6, 19.1, 24.1, 45.0, 60.0)
QUICK_DELAYS = (2.0, 7.0, 20.0)
#: the state the symbolic trials enter after each trial (``other`` of :func:`run_trial`, as in
#: :func:`reproduce`): after a probe or an extinction trial of up to 2 x the delay + 5 s
OTHER = 2


@contextmanager
def _untimed_trial_ends() -> Iterator[None]:
    """No :class:`DelayRangeWarning` for a move into :data:`OTHER`: the end of the demo's own
    probe and extinction trials, which no learner times (``--delays 100`` ends them after
    200 s, beyond the battery's 120 s, and the warning advised raising ``mu_max``, which no
    option of the demo sets). A taught delay beyond the range would still be reported."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=rf"transition \d+->{OTHER} came after",
                                category=DelayRangeWarning)
        yield


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--delay", type=number(0.2, 100.0), default=7.0,
                        help="reward delay of the place-preference task, s (HIREL: 7)")
    parser.add_argument("--pairings", type=integer(1, 1000), default=None,
                        help="rewarded trials before the test trials (default 5, quick 3)")
    parser.add_argument("--delays", type=numbers((1, 50), 0.2, 100.0, unit="s"), default=None,
                        help="comma-separated delays for Fig. 6 c-d and the reproduction "
                        "(default 2,3.5,7,11.6,19.1,24.1,45,60; quick 2,7,20)")
    parser.add_argument("--reproductions", type=integer(1, 1000), default=None,
                        help="learners per delay for the reproduction (default 6, quick 2)")
    parser.add_argument("--jitter", type=number(0.0, 1.0, hi_open=True), default=0.1,
                        help="control tick jitter, fraction of dt = 0.2 s")
    parser.add_argument("--noise", type=number(0.0, 10.0), default=0.3,
                        help="noise on the place-cell activities (sd)")


class _Pipeline:
    """The brain's neural chain fed symbolic place activities, one tick a call."""

    def __init__(self) -> None:
        # the transition cells' default latency (no motor loop to compensate here)
        self.brain = Brain(params=BrainParams(transitions=TransitionParams()))
        self.layer, self.cells = self.brain.layer, self.brain.cells

    def tick(self, place: np.ndarray, colour: int, sound: bool, moving: bool, dt: float):
        seen = self.brain.perceive(place, colour=colour, sound=sound, moving=moving, dt=dt)
        return seen.event, seen.timing.readouts, seen.timing.omitted


def _place_preference_trial(pipe: _Pipeline, rng: np.random.Generator, delay: float,
                            rewarded: bool, noise: float, jitter: float) -> TrialTrace:
    """Start -> goal zone -> stop -> sound after ``delay`` (or not) -> back to the start."""
    start, goal = np.array([3.0, 0.0]), np.array([0.0, 3.0])

    def tick() -> float:
        return DT * (1.0 + rng.uniform(-jitter, jitter)) if jitter > 0 else DT

    def place(mean: np.ndarray) -> np.ndarray:
        return mean + noise * rng.standard_normal(mean.size)

    t = 0.0
    while t < 3.0:  # moving at the start place
        d = tick()
        t += d
        pipe.tick(place(start), 0, False, True, d)
    t = 0.0
    while t < 1.0:  # entering the coloured goal zone
        d = tick()
        t += d
        pipe.tick(place(goal), GOAL_COLOUR, False, True, d)
    ev, _, _ = pipe.tick(place(goal), GOAL_COLOUR, False, False, DT)  # stops: still@goal wins
    still = ev.winner
    tau, end, fired = 0.0, None, []
    taus, preds, overs, fracs = [], [], [], []
    resume = False
    while tau < 3.0 * delay:
        d = tick()
        tau += d
        sound = rewarded and tau >= delay - d / 2
        ev, readouts, omitted = pipe.tick(place(goal), GOAL_COLOUR, sound, resume, d)
        if ev.winner != still:  # the sound, or the robot moving on
            end = tau if sound else None
            break
        if omitted:
            fired.append(tau)
            resume = True  # the agent inhibits the drive: the robot moves on at the next tick
        r = next((ro for (_, b), ro in readouts.items()
                  if pipe.layer.key(b).kind == StateKind.SOUND), None)
        taus.append(tau)
        preds.append(0.0 if r is None else r.prediction)
        overs.append(bool(r is not None and r.delay_over))
        fracs.append(0.0 if r is None else r.elapsed_fraction)
    t = 0.0
    while t < 1.0:  # after the sound the robot stays a moment, then leaves
        d = tick()
        t += d
        pipe.tick(place(goal), GOAL_COLOUR, False, end is None, d)
    t = 0.0
    while t < 3.0:
        d = tick()
        t += d
        pipe.tick(place(start), 0, False, True, d)
    return TrialTrace(np.array(taus), np.array(preds), np.array(overs, dtype=bool),
                      np.array(fracs), fired, end)


def _probe(args: argparse.Namespace, pairings: int, i: int, d: float
           ) -> tuple[TrialTrace, TransitionCells]:
    """A learner taught ``d`` (``pairings`` trials), probed without the event for 2 x ``d``;
    returns the probe and the learner's transition cells."""
    chain = TimingChain()
    r = Seeds(args.seed).generator("timing-trials", i)
    for _ in range(pairings):
        run_trial(chain, 0, 1, d, dt=DT, jitter=args.jitter, rng=r, other=OTHER)
    probe = run_trial(chain, 0, 1, None, dt=DT, jitter=0.0, t_max=2.0 * d, other=OTHER)
    return probe, chain.cells


def _fwhm(tau: np.ndarray, x: np.ndarray) -> float:
    above = tau[x >= 0.5 * x.max()] if x.size and x.max() > 0 else np.zeros(0)
    return float(above[-1] - above[0]) if above.size else math.nan


def run(args: argparse.Namespace) -> dict[str, Any]:
    out = prepare_out(args.out)
    quick = bool(args.quick)
    pairings = args.pairings if args.pairings is not None else (3 if quick else 5)
    delays = args.delays or list(QUICK_DELAYS if quick else FULL_DELAYS)
    n_rep = args.reproductions if args.reproductions is not None else (2 if quick else 6)
    rng = Seeds(args.seed).generator("timing-pipeline")

    # --- Fig. 6 a-b: place preference through the whole pipeline
    pipe = _Pipeline()
    for _ in range(pairings):
        _place_preference_trial(pipe, rng, args.delay, True, args.noise, args.jitter)
    rewarded = _place_preference_trial(pipe, rng, args.delay, True, args.noise, args.jitter)
    extinction = _place_preference_trial(pipe, rng, args.delay, False, args.noise, args.jitter)
    cells, layer = pipe.cells, pipe.layer
    reward_keys = [k for k in cells.transitions if layer.key(k[1]).kind == StateKind.SOUND]
    learned = {layer.describe(a) + " -> " + layer.describe(b): round(cells.learned_delay((a, b)), 3)
               for a, b in cells.transitions}

    # --- Fig. 6 c-d: several learned delays (one learner each), probed without the event
    by_delay: dict[float, TrialTrace] = {}
    per_delay: dict[str, dict[str, float]] = {}
    for i, d in enumerate(delays):
        with _untimed_trial_ends():
            by_delay[d], tc = _probe(args, pairings, i, d)
        probe, fine = by_delay[d], np.linspace(0.01, 2.5 * d, 5001)
        over = np.flatnonzero(probe.delay_over)
        per_delay[f"{d:g}"] = {
            "learned_delay_s": tc.learned_delay((0, 1)),
            "prediction_peak_s": float(probe.tau[np.argmax(probe.prediction)]),
            "prediction_fwhm_over_delay": _fwhm(fine, tc.expected(0, fine)[(0, 1)]) / d,
            "delay_over_seen_s": (float(probe.tau[over[0]]) + tc.params.latency
                                  if over.size else math.nan),
        }

    # --- HIREL Table I: closed-loop reproduction of each delay
    reproduced: dict[str, dict[str, float]] = {}
    waits_all = []
    with Progress(len(delays) * n_rep, "reproduction") as bar:
        for d in delays:
            waits, lags = [], []
            for s in range(n_rep):
                with _untimed_trial_ends():
                    rep = reproduce(d, seed=args.seed * 1000 + s, jitter=args.jitter)
                waits += rep.waits
                lags.append(rep.non_occurrence_lag)
                bar.update()
            w = np.array(waits)
            waits_all.append(w)
            err = 100.0 * (w / d - 1.0)
            reproduced[f"{d:g}"] = {"mean_s": float(np.nanmean(w)), "sd_s": float(np.nanstd(w)),
                                    "mean_error_pct": float(np.nanmean(err)),
                                    "max_abs_error_pct": float(np.nanmax(np.abs(err))),
                                    "non_occurrence_after_s": float(np.nanmean(lags))}

    fig, _ = plot_fig6(rewarded, extinction, args.delay, by_delay,
                    title=f"Timed prediction of the reward (learned delay {args.delay:g} s)")
    fig.savefig(Path(out) / "fig6_timing.png", dpi=110)
    plt.close(fig)
    fig, _ = plot_reproduction(delays, waits_all,
                            reference={k: v for k, v in HIREL_TABLE1.items()},
                            title="Learned vs reproduced waits (closed loop)")
    fig.savefig(Path(out) / "reproduction.png", dpi=110)
    plt.close(fig)

    peak_i = int(np.argmax(rewarded.prediction)) if rewarded.prediction.size else 0
    metrics: dict[str, Any] = {
        "delay_s": args.delay,
        "pairings": pairings,
        "seed": args.seed,
        "noise": args.noise, "jitter": args.jitter,
        "quick": quick,
        "transitions_learned_s": learned,
        "reward_transition_learned": bool(reward_keys),
        "reward_learned_delay_s": (cells.learned_delay(reward_keys[0]) if reward_keys
                                   else math.nan),
        "rewarded_prediction_peak_s": (float(rewarded.tau[peak_i]) if rewarded.tau.size
                                       else math.nan),
        "rewarded_sound_s": rewarded.end,
        "rewarded_non_occurrence": bool(rewarded.fired),
        "extinction_non_occurrence_s": extinction.fired[0] if extinction.fired else None,
        "extinction_resume_after_delay_s": (extinction.fired[0] - args.delay
                                            if extinction.fired else None),
        "by_delay": per_delay,
        "reproduction": reproduced,
        "worst_mean_error_pct": max(abs(v["mean_error_pct"]) for v in reproduced.values()),
    }
    arrays = {
        "rewarded_tau": rewarded.tau, "rewarded_prediction": rewarded.prediction,
        "extinction_tau": extinction.tau, "extinction_prediction": extinction.prediction,
        "extinction_fired_s": np.array(extinction.fired),
        "delays_s": np.array(delays, dtype=float),
        "reproduced_mean_s": np.array([np.nanmean(w) for w in waits_all]),
        "reproduced_sd_s": np.array([np.nanstd(w) for w in waits_all]),
    }
    for i, d in enumerate(delays):
        arrays[f"probe{i}_tau"] = by_delay[d].tau
        arrays[f"probe{i}_prediction"] = by_delay[d].prediction
    save_npz(Path(out) / "run.npz", arrays)
    resume = metrics["extinction_resume_after_delay_s"]
    write_metrics(out, metrics, summary=(
        f"timing: the reward delay ({args.delay:g} s) learned as "
        f"{metrics['reward_learned_delay_s']:.2f} s; in extinction the non-occurrence fired "
        + ("never" if resume is None else f"{resume:.1f} s after the delay")
        + f"; reproduced delays {', '.join(f'{d:g}' for d in delays)} s within "
        f"{metrics['worst_mean_error_pct']:.1f} % (worst mean error)"))
    return metrics
