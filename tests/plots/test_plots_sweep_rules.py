"""A sweep's summary figure, read back from the bars on hand-made rows.

numeric_metrics: the columns holding an int or a float (not a bool) in a row whose status is
"ok", bookkeeping and parameters left out, in the order the rows first show them.
plot_sweep_summary: one bar per combination of the parameters' values (as text, "" when a row
lacks one), its height the mean of the finite numbers of the ok rows and its error bar their
sample sd (ddof 1; 0 for one value), each value a black dot on the bar's x; the title names
the scenarios, the seeds as ranges and the failed cells; the figure max(4, 0.9 n + 2) wide.
"""

from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest
from matplotlib.colors import to_rgba
from matplotlib.container import BarContainer

from hippo.plots.sweep import BOOKKEEPING, _ranges, numeric_metrics, plot_sweep_summary


def row(seed: int, status: str = "ok", **kw: object) -> dict[str, object]:
    return {"cell": f"c{seed}", "scenario": "demo", "seed": seed, "status": status,
            "attempts": 1, "seconds": 2.5, "worker": "w", "error": "", **kw}


def test_bookkeeping_columns():
    assert BOOKKEEPING == {"cell", "scenario", "seed", "status", "attempts", "seconds",
                           "worker", "error"}


def test_numeric_metrics_in_table_order_from_ok_rows_only():
    rows = [row(0, "failed", early=1.0),
            row(1, gain=2, flag=True, text="x", b=1.5),
            row(2, a=3, b=float("nan"), c=None),
            {"status": "ok", "d": 4},
            {"d": 5.0, "e": 6.0}]                 # no status: not ok
    assert numeric_metrics(rows, ["gain"]) == ["b", "a", "d"]
    assert numeric_metrics(rows, []) == ["gain", "b", "a", "d"]
    assert numeric_metrics([], ["gain"]) == []


def test_an_unknown_metric_is_refused_naming_the_numeric_ones():
    rows = [row(0, gain=1, b=1.0, a=2.0)]
    with pytest.raises(ValueError, match="^" + re.escape(
            "metric 'z' is not a numeric metric of this sweep; choose from: b, a") + "$"):
        plot_sweep_summary(rows, ["gain"], metric="z")
    with pytest.raises(ValueError, match="^" + re.escape(
            "metric 'gain' is not a numeric metric of this sweep; choose from: (none)") + "$"):
        plot_sweep_summary([row(0, gain=1)], ["gain"], metric="gain")


def bars(ax) -> tuple[list[float], list[float]]:
    (bc,) = [c for c in ax.containers if isinstance(c, BarContainer)]
    heights = [p.get_height() for p in bc.patches]
    segs = bc.errorbar.lines[2][0].get_segments()
    # a bar of no value (nan) has an empty error segment
    return heights, [float(s[1][1] - s[0][1]) / 2 if len(s) else math.nan for s in segs]


def test_one_bar_per_combination_mean_and_sample_sd():
    rows = [row(0, gain=1, v=2.0), row(1, gain=1, v=4.0), row(2, gain=1, v=9.0),
            row(0, gain=2, v=5.0),
            row(1, gain=2, v=math.inf), row(2, gain=2, v=True),
            row(3, "failed", gain=2, v=100.0),
            row(0, gain=3, v=float("nan")), row(1, gain=3, w=1.0)]
    fig, ax = plot_sweep_summary(rows, ["gain"], metric="v")
    heights, err = bars(ax)
    # gain 1: mean 5, sd sqrt(((2-5)^2 + (4-5)^2 + (9-5)^2) / 2) = sqrt(13)
    assert heights[:2] == [5.0, 5.0] and math.isnan(heights[2])
    assert err[0] == pytest.approx(math.sqrt(13.0)) and err[1] == 0.0
    (bc,) = [c for c in ax.containers if isinstance(c, BarContainer)]
    assert all(p.get_facecolor() == to_rgba("#4c72b0", 0.85) for p in bc.patches)
    assert [p.get_x() + p.get_width() / 2 for p in bc.patches] == [0.0, 1.0, 2.0]
    assert [c.get_markersize() for c in bc.errorbar.lines[1]] == [6.0, 6.0]   # capsize 3
    dots = list(ax.lines)[-3:]
    assert [d.get_xdata().tolist() for d in dots] == [[0, 0, 0], [1], []]
    assert [d.get_ydata().tolist() for d in dots] == [[2.0, 4.0, 9.0], [5.0], []]
    assert all(d.get_marker() == "." and d.get_color() == "k" and d.get_markersize() == 4
               for d in dots)
    assert [t.get_text() for t in ax.get_xticklabels()] == ["gain=1", "gain=2", "gain=3"]
    assert list(ax.get_xticks()) == [0, 1, 2]
    assert ax.get_xticklabels()[0].get_fontsize() == 8
    assert ax.get_ylabel() == "v"
    assert ax.get_title() == "demo: mean ± sd over seeds 0-3 (1 failed cell left out)"
    assert ax.title.get_fontsize() == 9
    assert tuple(fig.get_size_inches()) == pytest.approx((4.7, 3.6))     # 0.9 * 3 + 2
    assert ax.get_position().bounds != pytest.approx((0.125, 0.11, 0.775, 0.77))  # tight


def test_the_default_metric_labels_and_the_width():
    rows = [row(s, a=k, b=f"v{s % 2}", m=float(s), n=1.0)
            for s, k in zip(range(6), [1, 2, 3, 4, 5, 6], strict=True)]
    rows.append({"status": "ok", "m": 3.0, "scenario": "other"})      # no a, no b, no seed
    fig, ax = plot_sweep_summary(rows, ["a", "b"])
    assert ax.get_ylabel() == "m"
    labels = [t.get_text() for t in ax.get_xticklabels()]
    assert labels == [f"a={k}\nb=v{s % 2}" for s, k in zip(range(6), range(1, 7), strict=True)] \
        + ["a=\nb="]
    assert tuple(fig.get_size_inches()) == pytest.approx((0.9 * 7 + 2.0, 3.6))
    assert ax.get_title() == "demo, other: mean ± sd over seeds 0-5"
    heights, _ = bars(ax)
    assert heights == [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 3.0]


def test_no_parameters_one_bar_called_all_and_failures_counted():
    rows = [row(0, m=1.0), row(2, m=3.0), row(5, "failed"), row(6, "error"), row(7, m=2.0)]
    fig, ax = plot_sweep_summary(rows, [])
    assert [t.get_text() for t in ax.get_xticklabels()] == ["all"]
    heights, err = bars(ax)
    assert heights == [2.0] and err == [pytest.approx(1.0)]     # sd of 1, 3, 2
    assert tuple(fig.get_size_inches()) == (4.0, 3.6)           # 0.9 + 2 < 4
    assert ax.get_title() == "demo: mean ± sd over seeds 0,2,5-7 (2 failed cells left out)"


def test_no_numeric_metric_at_all():
    rows = [row(0, "failed", m=1.0), row(1, "failed")]
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # no "mean of empty slice" for a bar of none
        _, ax = plot_sweep_summary(rows, ["gain"])
    assert ax.get_ylabel() == "(no numeric metric)"
    heights, _ = bars(ax)
    assert len(heights) == 1 and math.isnan(heights[0])
    assert [t.get_text() for t in ax.get_xticklabels()] == ["gain="]
    assert ax.get_title() == "demo: mean ± sd over seeds 0-1 (2 failed cells left out)"
    _, ax = plot_sweep_summary([{"status": "ok"}], [])
    assert ax.get_title() == ": mean ± sd over seeds -"


@pytest.mark.parametrize(("seeds", "text"), [
    ([], "-"), ([4], "4"), ([0, 1], "0-1"), ([0, 2], "0,2"), ([1, 2, 3, 7, 9, 10], "1-3,7,9-10"),
    ([5, 6, 8], "5-6,8"), ([3, 5, 6], "3,5-6")])
def test_seed_ranges(seeds: list[int], text: str):
    assert _ranges(seeds) == text


def test_the_dots_are_the_values_kept():
    rows = [row(0, g="x", v=1), row(1, g="x", v=np.float64(2.5))]
    _, ax = plot_sweep_summary(rows, ["g"], metric="v")
    assert list(ax.lines)[-1].get_ydata().tolist() == [1.0, 2.5]
    heights, err = bars(ax)
    assert heights == [1.75] and err == [pytest.approx(math.sqrt(1.125))]
