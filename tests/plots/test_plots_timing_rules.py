"""The timing figures, read back from their Axes on hand-made trial traces.

A trial panel draws the prediction from (0, 0) through the trace, dropped to 0 at the event
(when one came); the grey span "waiting (still)" from 0 to the event, else to the first
non-occurrence firing, else to the last tick; the learned delay dotted; the event and every
firing (only the first labelled) as lines; the first tick whose delay is over as a triangle;
x from 0 to max(last time, 1.5 delay). Panel c) draws each learned delay's prediction in
viridis at i / max(n - 1, 1), panel d) the same against time / delay, divided by its peak.
plot_reproduction: the mean and the population sd (ddof 0, nans left out) of each delay's
reproduced waits, and the error 100 (mean / delay - 1) % with sd 100 sd / delay.
"""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.colors import to_rgba
from matplotlib.container import ErrorbarContainer
from matplotlib.patches import Rectangle

from hippo.plots.timing import plot_fig6, plot_reproduction
from hippo.timing.trials import TrialTrace


def trace(tau: list[float], pred: list[float], *, over: list[bool] | None = None,
          fired: list[float] | None = None, end: float | None = None) -> TrialTrace:
    n = len(tau)
    return TrialTrace(np.array(tau, float), np.array(pred, float),
                      np.array(over if over is not None else [False] * n), np.zeros(n),
                      list(fired or []), end)


REWARDED = trace([1.0, 2.0, 3.0], [0.2, 0.6, 0.9], over=[False, True, True], end=3.5)
EXTINCTION = trace([1.0, 2.0, 3.0, 4.0, 5.0], [0.1, 0.5, 1.0, 0.4, 0.1],
                   fired=[3.7, 4.6], over=[False, False, False, True, True])
BY_DELAY = {4.0: trace([1.0, 2.0], [0.5, 2.0]), 2.0: trace([1.0, 3.0], [0.25, 0.5]),
            8.0: trace([], [])}


def labels(ax) -> list[str]:
    return ax.get_legend_handles_labels()[1]


def span(ax) -> Rectangle:
    (r,) = [p for p in ax.patches if isinstance(p, Rectangle) and p.get_label()[:1] != "_"]
    return r


def test_fig6_panels_and_titles():
    fig, axes = plot_fig6(REWARDED, EXTINCTION, 2.5, BY_DELAY, title="top")
    assert axes.shape == (2, 2) and len(fig.axes) == 4
    assert tuple(fig.get_size_inches()) == (11.0, 7.5)
    assert fig.get_layout_engine().__class__.__name__ == "ConstrainedLayoutEngine"
    assert fig.get_suptitle() == "top"
    assert [a.get_title(loc="left") for a in axes.ravel()] == [
        "a) rewarded trial: the sound comes, the prediction stops",
        "b) extinction trial: no sound, non-occurrence fires",
        "c) learned predictions for several delays (Weber: wider when longer)",
        "d) the same, rescaled: one shape (scalar property)"]
    assert all(a.title._text == "" and a._left_title.get_fontsize() == 10
               for a in axes.ravel())
    assert plot_fig6(REWARDED, EXTINCTION, 2.5, BY_DELAY)[0].get_suptitle() == ""


def test_a_rewarded_trial_panel():
    _, axes = plot_fig6(REWARDED, EXTINCTION, 2.5, BY_DELAY)
    ax = axes[0, 0]
    pred, delay, event, over = ax.lines
    assert pred.get_xdata().tolist() == [0.0, 1.0, 2.0, 3.0, 3.5]     # from 0, to the event
    assert pred.get_ydata().tolist() == [0.0, 0.2, 0.6, 0.9, 0.0]
    assert (pred.get_color(), pred.get_linewidth()) == ("C0", 2)
    assert list(delay.get_xdata()) == [2.5, 2.5] and delay.get_color() == "k"
    assert (delay.get_linestyle(), delay.get_linewidth()) == (":", 1)
    assert list(event.get_xdata()) == [3.5, 3.5] and event.get_color() == "C2"
    assert event.get_linewidth() == 2
    # the first tick whose delay is over: tau 2.0, prediction 0.6
    assert over.get_xdata().tolist() == [2.0] and over.get_ydata().tolist() == [0.6]
    assert (over.get_marker(), over.get_color(), over.get_markersize()) == ("v", "C1", 8)
    r = span(ax)
    assert (r.get_x(), r.get_width()) == (0.0, 3.5)
    assert r.get_facecolor() == to_rgba("0.9") and r.get_linewidth() == 0
    assert labels(ax) == ["waiting (still)", "prediction of the reward", "learned delay 2.5 s",
                          "sound at 3.5 s", "delay over at 2.0 s"]
    assert ax.get_xlim() == (0.0, 3.75)          # 1.5 x 2.5 > 3.5
    assert ax.get_ylim() == (-0.02, 1.05)
    assert ax.get_xlabel() == "time since the robot stopped (s)"
    assert ax.get_ylabel() == "activity"
    leg = ax.get_legend()
    assert leg._loc == 2 and leg.get_texts()[0].get_fontsize() == 7


def test_an_extinction_trial_panel():
    _, axes = plot_fig6(REWARDED, EXTINCTION, 2.5, BY_DELAY)
    ax = axes[0, 1]
    pred, _, f1, f2, over = ax.lines
    assert pred.get_xdata().tolist() == [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]   # no event, no drop
    assert pred.get_ydata().tolist() == [0.0, 0.1, 0.5, 1.0, 0.4, 0.1]
    assert list(f1.get_xdata()) == [3.7, 3.7] and list(f2.get_xdata()) == [4.6, 4.6]
    assert f1.get_color() == f2.get_color() == "C3" and f1.get_linewidth() == 2
    assert over.get_xdata().tolist() == [4.0]
    assert span(ax).get_width() == 3.7           # to the first firing
    assert labels(ax) == ["waiting (still)", "prediction of the reward", "learned delay 2.5 s",
                          "non-occurrence at 3.7 s", "delay over at 4.0 s"]
    assert ax.get_xlim() == (0.0, 5.0)           # 5 > 1.5 x 2.5


def test_a_panel_without_event_firing_or_delay_over_waits_to_the_last_tick():
    quiet = trace([0.5, 1.5], [0.3, 0.4])
    _, axes = plot_fig6(quiet, quiet, 4.0, BY_DELAY)
    ax = axes[0, 0]
    assert len(ax.lines) == 2                   # the prediction and the delay
    assert span(ax).get_width() == 1.5
    assert ax.get_xlim() == (0.0, 6.0)
    assert labels(ax) == ["waiting (still)", "prediction of the reward", "learned delay 4 s"]


def test_the_delays_side_by_side_and_rescaled():
    from matplotlib import colormaps

    _, axes = plot_fig6(REWARDED, EXTINCTION, 2.5, BY_DELAY)
    c, d = axes[1]
    cmap = colormaps["viridis"]
    colours = [cmap(0.0), cmap(0.5), cmap(1.0)]           # 2, 4, 8 s: i / 2
    curves = c.lines[0::2]
    marks = c.lines[1::2]
    assert [ln.get_label() for ln in curves] == ["2 s", "4 s", "8 s"]
    assert [ln.get_xdata().tolist() for ln in curves] == [[1.0, 3.0], [1.0, 2.0], []]
    assert [ln.get_ydata().tolist() for ln in curves] == [[0.25, 0.5], [0.5, 2.0], []]
    assert [ln.get_color() for ln in curves] == colours
    assert all(ln.get_linewidth() == 1.8 for ln in curves)
    assert [list(ln.get_xdata()) for ln in marks] == [[2.0, 2.0], [4.0, 4.0], [8.0, 8.0]]
    assert [ln.get_color() for ln in marks] == colours
    assert all(ln.get_linestyle() == ":" and ln.get_linewidth() == 1 for ln in marks)
    assert c.get_xlabel() == "time since entering the state (s)"
    assert c.get_ylabel() == "prediction"
    assert c.get_legend().get_title().get_text() == "learned delay"
    assert c.get_legend().get_texts()[0].get_fontsize() == 7
    # d): time / delay and prediction / peak (peak 0.5 and 2.0; none for the empty trace)
    *rescaled, unit = d.lines
    assert list(unit.get_xdata()) == [1.0, 1.0] and unit.get_color() == "k"
    assert (unit.get_linestyle(), unit.get_linewidth()) == (":", 1)
    assert [ln.get_xdata().tolist() for ln in rescaled] == [[0.5, 1.5], [0.25, 0.5], []]
    assert [ln.get_ydata().tolist() for ln in rescaled] == [[0.5, 1.0], [0.25, 1.0], []]
    assert [ln.get_color() for ln in rescaled] == colours
    assert [ln.get_label() for ln in rescaled] == ["2 s", "4 s", "8 s"]
    assert all(ln.get_linewidth() == 1.5 for ln in rescaled)
    assert d.get_xlim() == (0.0, 2.0)
    assert d.get_xlabel() == "elapsed time / learned delay"
    assert d.get_ylabel() == "prediction / peak"
    assert d.get_legend().get_texts()[0].get_fontsize() == 7


def test_an_extinction_trial_where_the_sound_came_after_all():
    late = trace([1.0, 2.0], [0.5, 0.7], end=2.4)
    _, axes = plot_fig6(REWARDED, late, 2.5, BY_DELAY)
    assert "sound at 2.4 s" in labels(axes[0, 1])


def test_two_delays_take_the_ends_of_the_colour_map():
    from matplotlib import colormaps

    _, axes = plot_fig6(REWARDED, EXTINCTION, 2.5, {3.0: trace([3.0], [0.5]),
                                                    1.0: trace([1.0], [0.5])})
    viridis = colormaps["viridis"]
    assert [ln.get_color() for ln in axes[1, 0].lines[0::2]] == [viridis(0.0), viridis(1.0)]


def test_the_figures_do_not_follow_the_users_style():
    """Title sizes, line widths, the colour map and the layout are the figure's own: a
    matplotlib style with other defaults changes nothing."""
    import matplotlib
    from matplotlib import colormaps

    style = {"font.size": 7.0, "lines.linewidth": 3.0, "image.cmap": "jet",
             "lines.linestyle": "--"}
    with matplotlib.rc_context(style):
        _, axes = plot_fig6(REWARDED, EXTINCTION, 2.5, BY_DELAY)
        fig2, (r1, r2) = plot_reproduction([2.0], [[2.0]])
    assert all(a._left_title.get_fontsize() == 10 for a in axes.ravel())
    assert [ln.get_linewidth() for ln in axes[1, 1].lines[:3]] == [1.5, 1.5, 1.5]
    assert axes[1, 0].lines[0].get_color() == colormaps["viridis"](0.0)
    assert fig2.get_layout_engine().__class__.__name__ == "ConstrainedLayoutEngine"
    assert r1.get_subplotspec().get_geometry() == (1, 2, 0, 0)
    assert r2.get_subplotspec().get_geometry() == (1, 2, 1, 1)
    zero = r2.lines[-1]
    assert list(zero.get_ydata()) == [0, 0]


def test_a_single_delay_takes_the_first_colour():
    from matplotlib import colormaps

    _, axes = plot_fig6(REWARDED, EXTINCTION, 2.5, {3.0: trace([3.0], [0.5])})
    assert axes[1, 0].lines[0].get_color() == colormaps["viridis"](0.0)


def errorbars(ax) -> list[tuple[list[float], list[float], list[float]]]:
    out = []
    for c in ax.containers:
        assert isinstance(c, ErrorbarContainer)
        line, _, (cols,) = c.lines
        half = [float(s[1][1] - s[0][1]) / 2 for s in cols.get_segments()]
        out.append((line.get_xdata().tolist(), line.get_ydata().tolist(), half))
    return out


def test_reproduced_waits_against_the_learned_delays():
    fig, axes = plot_reproduction([2.0, 8.0], [[1.0, 3.0, np.nan], [8.0, 8.0, 10.0, 6.0]],
                                  title="waits")
    ax, ax2 = axes
    assert len(fig.axes) == 2 and tuple(fig.get_size_inches()) == (10.0, 4.0)
    assert fig.get_suptitle() == "waits"
    # means 2 and 8, population sds 1 and 1.4142...
    (xs, ys, sd), = errorbars(ax)
    assert xs == [2.0, 8.0] and ys == [2.0, 8.0]
    assert sd == pytest.approx([1.0, np.sqrt(2.0)])
    (xs2, err, sd2), = errorbars(ax2)
    assert xs2 == [2.0, 8.0] and err == pytest.approx([0.0, 0.0])
    assert sd2 == pytest.approx([50.0, 100 * np.sqrt(2.0) / 8])
    perfect = ax.lines[0]
    assert list(perfect.get_xdata()) == pytest.approx([1.6, 10.0])
    assert list(perfect.get_ydata()) == pytest.approx([1.6, 10.0])
    assert (perfect.get_color(), perfect.get_linewidth()) == ("0.6", 1)
    assert labels(ax) == ["perfect", "hippo"]
    assert labels(ax2) == ["goal: 3 %", "hippo"]
    for a in (ax, ax2):
        assert a.containers[0].lines[0].get_marker() == "o"
        assert a.containers[0].lines[0].get_color() == "C0"
    goal = next(p for p in ax2.patches if p.get_label() == "goal: 3 %")
    assert (goal.get_y(), goal.get_height()) == (-3, 6)
    assert goal.get_facecolor() == to_rgba("C2", 0.15)
    zero = ax2.lines[-1]
    assert list(zero.get_ydata()) == [0, 0] and zero.get_color() == "0.6"
    assert zero.get_linewidth() == 1
    assert (ax.get_xscale(), ax.get_yscale(), ax2.get_xscale(), ax2.get_yscale()) == (
        "log", "log", "log", "linear")
    for a in (ax, ax2):
        assert list(a.get_xticks()) == [2.0, 8.0]
        assert a.xaxis.get_major_formatter().fmt == "%g"
        assert type(a.xaxis.get_minor_formatter()).__name__ == "NullFormatter"
        assert a.get_xlabel() == "learned delay (s)"
        assert a.get_legend().get_texts()[0].get_fontsize() == 8
    assert list(ax.get_yticks()) == [2.0, 8.0]
    assert ax.yaxis.get_major_formatter().fmt == "%g"
    assert type(ax.yaxis.get_minor_formatter()).__name__ == "NullFormatter"
    assert ax.get_ylabel() == "reproduced wait (s)" and ax2.get_ylabel() == "error (%)"


def test_the_reference_system_in_delay_order():
    _, (ax, ax2) = plot_reproduction([4.0], [[5.0]], reference={10.0: (11.0, 2.0),
                                                                  5.0: (4.0, 0.5)})
    assert ax.figure.get_suptitle() == ""
    hippo, ref = errorbars(ax)
    assert hippo == ([4.0], [5.0], [0.0])
    assert errorbars(ax2)[0][1] == pytest.approx([25.0])        # 100 (5 / 4 - 1) %
    assert ref[0] == [5.0, 10.0] and ref[1] == [4.0, 11.0] and ref[2] == [0.5, 2.0]
    _, ref2 = errorbars(ax2)
    assert ref2[1] == pytest.approx([-20.0, 10.0]) and ref2[2] == pytest.approx([10.0, 20.0])
    assert labels(ax)[-1] == "HIREL robot" and labels(ax2)[-1] == "HIREL robot"
    for a in (ax, ax2):
        line = a.containers[1].lines[0]
        assert (line.get_marker(), line.get_color()) == ("s", "C3")
    assert list(ax.lines[0].get_xdata()) == pytest.approx([3.2, 5.0])          # 0.8 x 4, 1.25 x 4
