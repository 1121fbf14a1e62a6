"""The closed loop's figures, read back from their Axes on hand-made logs and a stand-in robot.

state_centres: each state >= 0 drawn at the logged position nearest to the mean of its
positions (the first of equally near ones). plot_map: the learned map over a 40 x 20 arena,
the states at their centres, titled with the states that won of the layer's, and the
transitions between them of the map's. plot_trials: one path per trial of the phase, a cross
at its start, tab10's colours in trial order (the 11th takes the first again).
plot_wait_profiles: each trial's speed and prediction against the time since it stopped,
kept strictly between -8 s and delay + 12 s, rewarded trials (phase 2) left, extinction
(phase 3) right. The writers save their figures at 110 dpi and close them.
"""

from __future__ import annotations

import math
import struct
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.colors import to_rgba

import hippo.plots.agent as agent_plots
from hippo.cognitive_map import DriveParams, Drives, TransitionGraph
from hippo.plots.agent import (
    plot_map,
    plot_patrol,
    plot_place_preference,
    plot_trials,
    plot_wait_profiles,
    plot_waits_table,
    state_centres,
)
from hippo.sim.arena import Arena

ARENA = Arena("box", 40.0, 20.0, (((0.0, 0.0), (40.0, 0.0)),),
              locations=np.array([[5.0, 5.0]]),
              landmarks={"checkpoint-1": (1.0, 2.0), "checkpoint-2": (3.0, 4.0),
                         "checkpoint-3": (5.0, 6.0)})


def png_size(path: Path) -> tuple[int, int]:
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", data[16:24])


class Planner:
    def __init__(self) -> None:
        self.asked: list[tuple[Any, Any]] = []

    def activity(self, graph: TransitionGraph, drives: Drives) -> dict:
        self.asked.append((graph, drives))
        return {(0, 1): 1.0, (1, 0): 0.1}


def robot(transitions: bool = True) -> SimpleNamespace:
    g = TransitionGraph()
    if transitions:
        g.add_transition(0, 1, (0.0, 10.0))
        g.add_transition(1, 0, (math.pi, 10.0))
        g.add_transition(1, 5, (0.0, 10.0))        # 5 never won: not drawn
        g.add_transition(6, 0, (0.0, 10.0))        # nor 6
    d = Drives({"sound": DriveParams(learning_rate=1.0)})
    if transitions:
        d.link("sound", (0, 1))
    return SimpleNamespace(graph=g, drives=d, planner=Planner(),
                           layer=SimpleNamespace(n_states=9))


def log() -> dict[str, np.ndarray]:
    return {"winner": np.array([-1, 0, 0, 0, 1, -2]),
            "x": np.array([99.0, 0.0, 10.0, 4.0, 20.0, 99.0]),
            "y": np.array([99.0, 0.0, 0.0, 0.0, 10.0, 99.0])}


def test_state_centres_the_logged_position_nearest_the_mean():
    winner = np.array([-1, 0, 0, 0, 1, 2, 2, 0])
    x = np.array([50.0, 0.0, 10.0, 4.0, 7.0, 1.0, 3.0, 2.0])
    y = np.array([50.0, 0.0, 0.0, 0.0, 8.0, 5.0, 5.0, 0.0])
    got = state_centres(winner, x, y)
    # 0: mean (4, 0), at (4, 0); 1: its only point; 2: mean (2, 5), both 1 away: the first
    assert got == {0: (4.0, 0.0), 1: (7.0, 8.0), 2: (1.0, 5.0)}
    assert all(type(k) is int and all(type(v) is float for v in p) for k, p in got.items())
    # around a corner the mean (5, 5) lies off the path; the nearest logged point is taken
    corner = state_centres(np.zeros(3, int), np.array([0.0, 10.0, 5.0]),
                           np.array([10.0, 0.0, 5.5]))
    assert corner == {0: (5.0, 5.5)}
    assert state_centres(np.array([-1, -3]), np.zeros(2), np.zeros(2)) == {}
    # the same along y: mean (0, 14 / 3), nearest (0, 4), not the lowest point
    assert state_centres(np.zeros(3, int), np.zeros(3), np.array([0.0, 10.0, 4.0])) == {
        0: (0.0, 4.0)}
    # not the nearest to the origin nor to the first point: the nearest to the mean (6, 0)
    assert state_centres(np.zeros(3, int), np.array([0.0, 7.0, 11.0]), np.zeros(3)) == {
        0: (7.0, 0.0)}


def test_the_learned_map_over_the_arena():
    r = robot()
    fig, ax = plot_map(ARENA, r, log())
    assert tuple(fig.get_size_inches()) == pytest.approx((7.0, 7 * 20 / 40 + 0.8))
    assert fig.get_layout_engine().__class__.__name__ == "ConstrainedLayoutEngine"
    assert r.planner.asked == [(r.graph, r.drives)]
    assert ax.get_title() == ("learned map: 2 of 9 states (those that won, where the robot "
                              "was),\n2 of 4 transitions")
    assert ax.get_xlim() == (-2.0, 42.0) and ax.get_ylim() == (-2.0, 22.0)
    assert len(ax.lines) == 0                     # no locations drawn
    places = next(c for c in ax.collections if c.get_label() == "place")
    assert np.asarray(places.get_offsets()).tolist() == [[4.0, 0.0], [20.0, 10.0]]
    assert len(fig.axes) == 2                     # the map and the activity's colour bar
    (goal,) = [a for a in ax.texts if a.get_text() == "sound"]      # the robot's drives
    assert tuple(goal.xy) == pytest.approx((4.0 + 0.8 * 16.0, 8.0))
    assert plot_map(ARENA, r, log(), title="mine")[1].get_title() == "mine"


def test_an_empty_map_asks_no_activity():
    r = robot(transitions=False)
    fig, ax = plot_map(ARENA, r, log())
    assert r.planner.asked == [] and len(fig.axes) == 1
    assert ax.get_title() == ("learned map: 2 of 9 states (those that won, where the robot "
                              "was),\n0 of 0 transitions")


def trial_log() -> dict[str, np.ndarray]:
    # phase 2: trials 0-10, two ticks each; phase 1: trial 0 again (not drawn)
    n = 11
    trial = np.concatenate([np.repeat(np.arange(n), 2), [0, 0]])
    phase = np.concatenate([np.full(2 * n, 2), [1, 1]])
    x = np.arange(2 * n + 2, dtype=float)
    return {"trial": trial, "phase": phase, "x": x, "y": 100 + x}


def test_trials_one_path_and_a_start_cross_each():
    fig, ax = plot_trials(ARENA, trial_log(), 2, "paths")
    assert tuple(fig.get_size_inches()) == pytest.approx((6.0, 6 * 20 / 40 + 0.4))
    assert fig.get_layout_engine().__class__.__name__ == "ConstrainedLayoutEngine"
    assert ax.get_title() == "paths"
    lines = list(ax.lines)
    assert len(lines) == 22
    tab10 = plt.get_cmap("tab10")
    for i in range(11):
        path, start = lines[2 * i], lines[2 * i + 1]
        assert path.get_xdata().tolist() == [2 * i, 2 * i + 1]
        assert path.get_ydata().tolist() == [100 + 2 * i, 101 + 2 * i]
        assert path.get_linewidth() == 1 and path.get_marker() == "None"
        assert list(start.get_xdata()) == [2 * i] and list(start.get_ydata()) == [100 + 2 * i]
        assert (start.get_marker(), start.get_markersize(), start.get_markeredgewidth()) == (
            "x", 9, 2)
        assert path.get_color() == start.get_color() == tab10(i % 10)
    assert lines[20].get_color() == tab10(0)
    _, ax = plot_trials(ARENA, trial_log(), 1, "taught")
    assert ax.lines[0].get_xdata().tolist() == [22, 23]


def wait_log() -> dict[str, np.ndarray]:
    n = 100
    t = np.arange(n, dtype=float)
    trial = np.full(n, -1)
    phase = np.zeros(n, int)
    non = np.zeros(n, bool)
    trial[0:25], phase[0:25] = 0, 2
    phase[10] = 3                                  # trial 0's tick 10 is not a rewarded one
    trial[30:60], phase[30:60] = 1, 3
    trial[60:65], phase[60:65] = 2, 2
    trial[70:90], phase[70:90] = 3, 3
    non[[40, 45, 80]] = True
    non[12] = True                                 # a mark in a rewarded trial too
    return {"t": t, "trial": trial, "phase": phase, "speed": 2 * t, "sound_prediction": t / 100,
            "sound_non_occurrence": non}


TRIALS = [{"rewarded": True, "still_t": 8.0}, {"rewarded": False, "still_t": 38.0},
          {"rewarded": True}, {"rewarded": False, "still_t": 75.0}]


def test_wait_profiles_around_the_stop():
    fig, axes = plot_wait_profiles(wait_log(), TRIALS, 2.0)
    assert axes.shape == (2, 2) and tuple(fig.get_size_inches()) == (10.0, 5.5)
    assert fig.get_layout_engine().__class__.__name__ == "ConstrainedLayoutEngine"
    assert axes[0, 0].get_shared_x_axes().joined(axes[0, 0], axes[1, 1])
    # rewarded: trial 0, t 1..21 without 10 (tt strictly in (-8, 14)); t 0 is tt = -8
    t0 = [t for t in range(1, 22) if t != 10]
    speed = axes[0, 0].lines[0]
    assert speed.get_xdata().tolist() == [t - 8.0 for t in t0]
    assert speed.get_ydata().tolist() == [2.0 * t for t in t0]
    assert speed.get_linewidth() == 1
    pred = axes[1, 0].lines[0]
    assert pred.get_linewidth() == 1
    assert pred.get_xdata().tolist() == [t - 8.0 for t in t0]
    assert pred.get_ydata().tolist() == [t / 100 for t in t0]
    (mark,) = axes[1, 0].lines[1:-2]
    assert mark.get_xdata().tolist() == [4.0] and mark.get_ydata().tolist() == [0.12]
    # extinction: trial 1 (t 31..51) and trial 3 (t 70..88)
    s1, s3 = axes[0, 1].lines[:2]
    assert s1.get_xdata().tolist() == [t - 38.0 for t in range(31, 52)]
    assert s3.get_xdata().tolist() == [t - 75.0 for t in range(70, 89)]
    no1, no3 = axes[1, 1].lines[1:4:2]
    assert no1.get_xdata().tolist() == [2.0, 7.0] and no1.get_ydata().tolist() == [0.4, 0.45]
    assert no3.get_xdata().tolist() == [5.0] and no3.get_ydata().tolist() == [0.8]
    assert (no1.get_marker(), no1.get_color(), no1.get_markersize()) == ("v", "r", 7)
    assert no1.get_linestyle() == "None" and no1.get_label() == "non-occurrence"
    for ax in axes.ravel():
        zero, delay = ax.lines[-2:]
        assert list(zero.get_xdata()) == [0, 0] and zero.get_color() == "0.6"
        assert zero.get_linestyle() == ":"
        assert list(delay.get_xdata()) == [2.0, 2.0] and delay.get_color() == "tab:red"
        assert (delay.get_linestyle(), delay.get_linewidth()) == ("--", 1)
    assert [a.get_title() for a in axes[0]] == ["rewarded trials", "extinction trials"]
    assert [a.get_xlabel() for a in axes[1]] == [
        "time since the robot stopped in the goal zone (s)"] * 2
    assert axes[0, 0].get_ylabel() == "speed (cm/s)"
    assert axes[1, 0].get_ylabel() == "prediction of the sound"
    assert axes[0, 1].get_ylabel() == "" and axes[1, 1].get_ylabel() == ""
    assert axes[0, 0].get_legend() is None and axes[0, 1].get_legend() is None
    for ax in axes[1]:
        leg = ax.get_legend()
        assert [t.get_text() for t in leg.get_texts()] == ["non-occurrence"]     # one entry
        assert leg._loc == 1 and leg.get_texts()[0].get_fontsize() == 8
        (handle,) = leg.legend_handles                  # the mark's own handle, a triangle
        assert handle.get_marker() == "v" and handle.get_linestyle() == "None"
    _, axes = plot_wait_profiles(wait_log(), TRIALS[:1], 2.0)      # no trial on the right
    assert axes[1, 1].get_legend() is None


def test_the_waits_table():
    rows = [{"checkpoint": "cp1", "learned_wait_s": 4.0, "reproduced_waits_s": [3.0, 5.0, 4.5],
             "taught_block_s": 4.2},
            {"checkpoint": "cp2", "learned_wait_s": None, "reproduced_waits_s": [],
             "taught_block_s": 6.0},
            {"checkpoint": "cp3", "learned_wait_s": 2.0, "reproduced_waits_s": [1.0, 2.0],
             "taught_block_s": 2.5},
            {"checkpoint": "cp4", "learned_wait_s": 0.0, "reproduced_waits_s": [7.5],
             "taught_block_s": 7.0}]
    fig, ax = plot_waits_table(rows)
    assert tuple(fig.get_size_inches()) == (6.0, 3.6)
    assert fig.get_layout_engine().__class__.__name__ == "ConstrainedLayoutEngine"
    lines = list(ax.lines)
    assert len(lines) == 12
    learned, rep, block = lines[0::3], lines[1::3], lines[2::3]
    for k, ln in enumerate(learned):
        assert list(ln.get_xdata()) == [k - 0.25, k + 0.25]
        assert (ln.get_color(), ln.get_linestyle(), ln.get_linewidth()) == ("k", "-", 2)
    assert [ln.get_ydata()[0] for ln in learned][::2] == [4.0, 2.0]
    # None: no wait learned, blank; 0 s is a wait and drawn (it was blank, as None, before)
    assert math.isnan(learned[1].get_ydata()[0]) and list(learned[3].get_ydata()) == [0.0, 0.0]
    assert rep[0].get_xdata().tolist() == pytest.approx([-0.15, 0.0, 0.15])
    assert rep[0].get_ydata().tolist() == [3.0, 5.0, 4.5]
    assert rep[1].get_xdata().tolist() == [] and rep[1].get_ydata().tolist() == []
    assert rep[2].get_xdata().tolist() == pytest.approx([1.85, 2.15])
    assert rep[3].get_xdata().tolist() == pytest.approx([2.85])     # linspace(-.15, .15, 1)
    assert all((ln.get_marker(), ln.get_color(), ln.get_linestyle()) == ("o", "tab:blue",
                                                                        "None") for ln in rep)
    assert [(list(ln.get_xdata()), list(ln.get_ydata())) for ln in block] == [
        ([0], [4.2]), ([1], [6.0]), ([2], [2.5]), ([3], [7.0])]
    assert all((ln.get_marker(), ln.get_color(), ln.get_markersize()) == ("_", "r", 20)
               for ln in block)
    assert [ln.get_label()[:1] != "_" for ln in lines] == [True] * 3 + [False] * 9
    assert [t.get_text() for t in ax.get_xticklabels()] == ["cp1", "cp2", "cp3", "cp4"]
    assert list(ax.get_xticks()) == [0, 1, 2, 3]
    assert ax.get_ylabel() == "wait (s)"
    leg = ax.get_legend()
    assert [t.get_text() for t in leg.get_texts()] == ["learned", "reproduced",
                                                       "teacher's block"]
    assert leg.get_texts()[0].get_fontsize() == 8
    assert ax.get_title() == "checkpoint waits: learned vs reproduced"


def patrol_log() -> dict[str, np.ndarray]:
    return {"winner": np.array([0, 0, 1, 1, 0]), "phase": np.array([1, 1, 4, 4, 2]),
            "x": np.array([1.0, 2.0, 3.0, 4.0, 5.0]), "y": np.array([6.0, 7.0, 8.0, 9.0, 0.0])}


ROWS = [{"checkpoint": "cp1", "learned_wait_s": 4.0, "reproduced_waits_s": [4.0],
         "taught_block_s": 4.0}]


def test_the_writers_save_png_files_at_110_dpi_and_close_them(tmp_path: Path):
    paths = plot_place_preference(tmp_path, ARENA, robot(), {**wait_log(), **{
        "winner": np.zeros(100, int), "x": np.arange(100.0) % 40, "y": np.zeros(100)}},
        TRIALS, 2.0)
    assert paths == [tmp_path / "map.png", tmp_path / "trajectories.png",
                     tmp_path / "waits.png"]
    # 7 x 4.3, 6 x 3.4 and 10 x 5.5 inches at 110 dpi
    assert [png_size(p) for p in paths] == [(770, 473), (660, 374), (1100, 605)]
    assert plt.get_fignums() == []
    out = tmp_path / "patrol"
    out.mkdir()
    paths = plot_patrol(out, ARENA, robot(), patrol_log(), ROWS)
    assert paths == [out / "map.png", out / "trajectories.png", out / "waits_table.png"]
    assert [png_size(p) for p in paths] == [(770, 473), (770, 605), (660, 396)]
    assert plt.get_fignums() == []


def test_the_writers_figures(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    saved: list[tuple[Any, Path, dict]] = []

    def save(fig: Any, path: Path, **kw: Any) -> Path:
        saved.append((fig, path, kw))
        assert plt.fignum_exists(fig.number)     # saved before it is closed
        return path

    monkeypatch.setattr(agent_plots, "save_figure", save)
    plot_place_preference(tmp_path, ARENA, robot(), {**wait_log(), **{
        "winner": np.zeros(100, int), "x": np.zeros(100), "y": np.zeros(100)}}, TRIALS, 2.0)
    assert [p.name for _, p, _ in saved] == ["map.png", "trajectories.png", "waits.png"]
    assert all(kw == {"dpi": 110} for _, _, kw in saved)
    traj = saved[1][0].axes[0]
    assert traj.get_title() == "rewarded trials: paths to the goal"
    assert len(traj.lines) == 4                   # phase 2: trials 0 and 2, a path and a cross
    assert [fig.number for fig, _, _ in saved] and plt.get_fignums() == []
    saved.clear()
    plot_patrol(tmp_path, ARENA, robot(), patrol_log(), ROWS)
    assert [p.name for _, p, _ in saved] == ["map.png", "trajectories.png", "waits_table.png"]
    assert all(kw == {"dpi": 110} for _, _, kw in saved)
    fig_b = saved[1][0]
    (ax,) = fig_b.axes
    assert tuple(fig_b.get_size_inches()) == (7.0, 5.5)
    assert fig_b.get_layout_engine().__class__.__name__ == "ConstrainedLayoutEngine"
    taught, reproduced, *cps = ax.lines
    assert taught.get_xdata().tolist() == [1.0, 2.0] and taught.get_ydata().tolist() == [6, 7]
    assert (taught.get_color(), taught.get_linewidth(), taught.get_alpha()) == ("k", 1.2, 1.0)
    assert reproduced.get_xdata().tolist() == [3.0, 4.0]
    assert reproduced.get_color() == "tab:blue"
    assert (reproduced.get_linewidth(), reproduced.get_alpha()) == (0.6, 0.6)
    assert [(list(c.get_xdata()), list(c.get_ydata())) for c in cps] == [
        ([1.0], [2.0]), ([3.0], [4.0]), ([5.0], [6.0])]        # the arena's checkpoints
    assert all((c.get_marker(), c.get_color(), c.get_markersize()) == ("s", "tab:red", 9)
               for c in cps)
    assert [a.get_text() for a in ax.texts] == ["1", "2", "3"]
    for a, c in zip(ax.texts, [(1.0, 2.0), (3.0, 4.0), (5.0, 6.0)], strict=True):
        assert tuple(a.xy) == c and a.xyann == (5, 5) and a.anncoords == "offset points"
        assert a.get_color() == "tab:red"
    leg = ax.get_legend()
    assert [t.get_text() for t in leg.get_texts()] == ["taught (leash)", "reproduced"]
    assert leg._loc == 1 and leg.get_texts()[0].get_fontsize() == 8
    assert ax.get_title() == "patrol: taught and reproduced trajectories"
    assert ax.get_xlim() == (-2.0, 42.0) and len(ax.collections) == 1    # walls, no zones
    assert saved[2][0].axes[0].get_title() == "checkpoint waits: learned vs reproduced"
    saved.clear()
    plot_patrol(tmp_path, ARENA, robot(), patrol_log(), ROWS, checkpoints=[(9.0, 8.0)])
    ax = saved[1][0].axes[0]
    assert [(list(c.get_xdata()), list(c.get_ydata())) for c in ax.lines[2:]] == [
        ([9.0], [8.0])]
    assert [a.get_text() for a in ax.texts] == ["1"]
    assert to_rgba(ax.lines[2].get_color()) == to_rgba("tab:red")
