"""The deployment's figure, read back from its three panels on two or three hand-made segments.

Panel 1: the checkpoint passes summed up to each segment's end hour (a black line), and on a
twin axis each failure kind summed the same way as a step drawn after each point; panel 2 the
known states, transitions and map edges; panel 3 the memory in MB; the hours shared.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from hippo.plots.deployment import _KINDS, plot_deployment


def segment(t1: float, tasks: int, kinds: tuple[int, int, int, int], states: int,
            rss: float) -> dict:
    return {"t1_h": t1, "tasks": tasks, **dict(zip(_KINDS, kinds, strict=True)),
            "health": {"states": states, "transitions": 2 * states, "map_edges": states + 1,
                       "rss_mb": rss}}


def test_the_failure_kinds():
    assert _KINDS == ("missed", "misplaced", "wait_off", "stuck")


def test_no_segment_three_empty_panels_and_a_title():
    fig, axes = plot_deployment([])
    assert axes.shape == (3,) and len(fig.axes) == 3
    assert axes[0].get_title() == "deployment: no segment finished"
    assert all(len(ax.lines) == 0 for ax in axes)
    assert tuple(fig.get_size_inches()) == (7.0, 8.0)
    assert fig.get_layout_engine().__class__.__name__ == "ConstrainedLayoutEngine"
    assert axes[0].get_shared_x_axes().joined(axes[0], axes[2])
    plt.close(fig)


def test_cumulative_passes_and_failures_by_kind():
    segs = [segment(1.0, 3, (1, 0, 2, 0), 10, 100.0),
            segment(2.5, 4, (0, 1, 1, 0), 12, 120.0),
            segment(4.0, 0, (2, 0, 0, 5), 13, 90.5)]
    fig, axes = plot_deployment(segs)
    assert axes.shape == (3,) and len(fig.axes) == 4          # three panels and the twin
    hours = [1.0, 2.5, 4.0]
    ax = axes[0]
    (passes,) = ax.lines
    assert passes.get_xdata().tolist() == hours and passes.get_ydata().tolist() == [3, 7, 7]
    assert passes.get_color() == "k" and passes.get_linestyle() == "-"
    assert passes.get_label() == "checkpoint passes"
    (twin,) = [a for a in fig.axes if a not in set(axes)]
    assert twin.get_shared_x_axes().joined(twin, ax)
    got = {ln.get_label(): ln for ln in twin.lines}
    assert list(got) == ["missed", "misplaced", "wait_off", "stuck"]
    # the sums by hand: missed 1, 1, 3; misplaced 0, 1, 1; wait_off 2, 3, 3; stuck 0, 0, 5
    sums = {"missed": [1, 1, 3], "misplaced": [0, 1, 1], "wait_off": [2, 3, 3],
            "stuck": [0, 0, 5]}
    for kind, ln in got.items():
        assert ln.get_xdata().tolist() == hours and ln.get_ydata().tolist() == sums[kind]
        assert ln.get_drawstyle() == "steps-post"
    assert ax.get_ylabel() == "passes (cumulative)"
    assert twin.get_ylabel() == "failures (cumulative)"
    leg = twin.get_legend()
    assert [t.get_text() for t in leg.get_texts()] == list(_KINDS)
    assert leg._loc == 2 and leg.get_texts()[0].get_fontsize() == 8     # 2: upper left
    assert ax.get_legend() is None
    assert ax.get_title() == "deployment: tasks and failures"

    known = {ln.get_label(): ln for ln in axes[1].lines}
    assert list(known) == ["states", "transitions", "map_edges"]
    assert known["states"].get_ydata().tolist() == [10, 12, 13]
    assert known["transitions"].get_ydata().tolist() == [20, 24, 26]
    assert known["map_edges"].get_ydata().tolist() == [11, 13, 14]
    for ln in [*known.values(), *axes[2].lines]:
        assert ln.get_xdata().tolist() == hours
        assert (ln.get_marker(), ln.get_linestyle()) == (".", "-")
    assert axes[1].get_ylabel() == "count"
    leg1 = axes[1].get_legend()
    assert [t.get_text() for t in leg1.get_texts()] == ["states", "transitions", "map_edges"]
    assert leg1.get_texts()[0].get_fontsize() == 8
    (mem,) = axes[2].lines
    np.testing.assert_array_equal(mem.get_ydata(), [100.0, 120.0, 90.5])
    assert axes[2].get_ylabel() == "memory (MB)"
    assert axes[2].get_xlabel() == "simulated hours"
    assert axes[0].get_xlabel() == "" and axes[1].get_title() == ""
    assert tuple(fig.get_size_inches()) == (7.0, 8.0)
    plt.close(fig)
