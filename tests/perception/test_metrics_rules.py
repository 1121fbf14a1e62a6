"""The place-cell metrics' rules on hand-worked cases: place fields on a small grid (edges,
points on an inner edge and outside the extent, one-sample bins, unvisited bins NaN without a
warning), ICANN09 localization exactly at its threshold, sample count and concentration, the
spatial order (weak units last, ties kept in order), the winner and centroid decoders and
their accuracy within one step, walls crossing or touching the line between two locations,
the binary cell's threshold against a brute-force search, balanced accuracy, the recovery
after kidnapping exactly at hold and horizon, and every refusal word for word."""

from __future__ import annotations

import re
import warnings
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from hippo.perception import metrics as M


def _strict(f: Callable[..., Any], *args: Any, **kw: Any) -> Any:
    """``f(*args, **kw)`` with every warning an error (0/0 must stay silent)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return f(*args, **kw)


def _raises(call: Callable[[], Any], text: str, exc: type[Exception] = ValueError) -> None:
    with pytest.raises(exc, match=f"^{re.escape(text)}$"):
        call()


# ------------------------------------------------------------------------------ place fields
def test_place_fields_grid_by_hand():
    # extent (0, 40, 0, 20), 4 x 2 bins of 10: xe = 0, 10, 20, 30, 40; ye = 0, 10, 20.
    # p1 lies on the inner edge x = 10 (goes up, to bin 1), p6 on y = 10 (to row 1); p3 and
    # p4 lie outside the extent (clipped to the edge bins)
    xy = np.array([[5, 5], [10, 5], [15, 15], [-4, 25], [45, -3], [12, 3], [25, 10]], float)
    Y = np.column_stack([np.arange(1.0, 8.0), 10 * np.arange(1.0, 8.0)])
    fields, occ, xe, ye = _strict(M.place_fields_grid, xy, Y, bins=(4, 2),
                                  extent=(0.0, 40.0, 0.0, 20.0))
    assert xe.tolist() == [0, 10, 20, 30, 40] and ye.tolist() == [0, 10, 20]
    assert occ.dtype == np.float64 and occ.tolist() == [[1, 2, 0, 1], [1, 1, 1, 0]]
    # row 0: p0 (1); p1, p5 (2 and 6: mean 4); none; p4 (5). row 1: p3 (4); p2 (3); p6 (7)
    want = np.array([[1, 4, np.nan, 5], [4, 3, 7, np.nan]])
    assert fields.shape == (2, 2, 4) and fields.dtype == np.float64
    np.testing.assert_array_equal(fields[0], want)
    np.testing.assert_array_equal(fields[1], 10 * want)


def test_place_fields_grid_default_extent_and_bins():
    # the default extent spans the data (x in [2, 8], y in [-1, 3]); the largest point lies
    # just inside the last bin
    xy = np.array([[2.0, -1.0], [8.0, 3.0], [5.0, 1.5]])
    _, occ, xe, ye = _strict(M.place_fields_grid, xy, np.ones(3), bins=(3, 2))
    assert xe[0] == 2.0 and 8.0 < xe[-1] <= 8.0 + 1e-8 and xe.size == 4
    assert ye[0] == -1.0 and 3.0 < ye[-1] <= 3.0 + 1e-8 and ye.size == 3
    assert occ.tolist() == [[1, 0, 0], [0, 1, 1]]
    _, occ30, xe30, _ = M.place_fields_grid(xy, np.ones(3))
    assert occ30.shape == (30, 30) and xe30.size == 31


def test_place_fields_locations_by_hand():
    # locations 2 and 3 have one sample each, 1 and 4 none (NaN, silently)
    F = _strict(M.place_fields_locations, np.array([0, 0, 2, 3]),
                np.array([[1.0], [3.0], [5.0], [7.0]]), 5)
    np.testing.assert_array_equal(F[:, 0], [2.0, np.nan, 5.0, 7.0, np.nan])
    _raises(lambda: M.place_fields_locations(np.array([0, 3]), np.zeros((2, 1)), 3),
            "labels must lie in [0, 3), got 0..3")


# ------------------------------------------------------------------------------ localization
def _line_nb() -> np.ndarray:
    """Three locations on a line, as 0/1 integers (cast to bool)."""
    return np.array([[1, 1, 0], [1, 1, 1], [0, 1, 1]])


def test_localized_units_on_their_edges():
    labels = np.repeat([0, 1, 2], 3)
    Y = np.zeros((9, 4))
    Y[:3, 0] = 4.5                       # exactly the threshold, exactly min_samples = 3
    Y[[0, 1, 7, 8], 1] = 5.0             # labels 0, 0, 2, 2: preferred 0, concentration 2/4
    Y[4, 2] = 6.0                        # one sample only
    Y[:, 3] = -1.0                       # never active
    res = M.localized_units(Y, labels, _line_nb())
    assert res.localized.tolist() == [True, True, False, False] and res.count == 2
    assert res.peak.tolist() == [4.5, 5.0, 6.0, -1.0]
    assert res.preferred.tolist() == [0, 0, 1, -1]
    assert res.concentration.tolist() == [1.0, 0.5, 1.0, 0.0]
    assert res.n_active.tolist() == [3, 4, 1, 0] and res.n_active.dtype.kind == "i"
    # one step past: a higher concentration or sample count is required
    assert not M.localized_units(Y, labels, _line_nb(), min_concentration=0.51).localized[1]
    assert not M.localized_units(Y, labels, _line_nb(), min_samples=4).localized[0]
    assert M.localized_units(Y, labels, _line_nb(), min_samples=1).localized[2]
    # an empty recording: no peak, nothing active
    empty = M.localized_units(np.zeros((0, 2)), np.zeros(0, int), _line_nb())
    assert empty.peak.tolist() == [-np.inf, -np.inf] and empty.preferred.tolist() == [-1, -1]
    assert empty.n_active.tolist() == [0, 0] and empty.count == 0


def test_localized_units_refusals():
    labels = np.repeat([0, 1, 2], 3)
    _raises(lambda: M.localized_units(np.zeros((9, 1)), labels, np.ones((3, 2), bool)),
            "neighbors must be a square boolean matrix, got (3, 2)")
    _raises(lambda: M.localized_units(np.zeros((9, 1)), labels, np.ones(3, bool)),
            "neighbors must be a square boolean matrix, got (3,)")
    _raises(lambda: M.localized_units(np.zeros((9, 1)), labels, np.ones((2, 2), bool)),
            "labels must lie in [0, 2), got 0..2")
    _raises(lambda: M.localized_units(np.zeros((8, 1)), labels, _line_nb()),
            "Y has 8 rows, expected 9")
    _raises(lambda: M.localized_units(np.zeros((9, 1)), labels, _line_nb(), threshold=np.nan),
            "threshold must be finite, got nan")


def test_spatial_order_by_hand():
    # location 2 is never visited (NaN fields); keys: strong units their peak location,
    # weak ones 4 + it
    labels = np.array([0, 0, 1, 1, 3, 3])
    Y = np.column_stack([
        [0, 0, 1, 1, 5, 5],          # strong at 3: key 3
        [0, 0, 4.5, 4.5, 0, 0],      # exactly the threshold at 1: key 1
        [-3, -3, -1, -1, -2, -2],    # weak, best at 1 (not the unvisited 2): key 5
        [1, 1, 0, 0, 0, 0],          # weak at 0: key 4
        [6, 6, 0, 0, 0, 0],          # strong at 0: key 0
    ]).astype(float)
    assert M.spatial_order(Y, labels, 4).tolist() == [4, 1, 0, 3, 2]
    # ties keep the units' order (a stable sort): 40 units, keys drawn with repeats
    rng = np.random.default_rng(0)
    peak_at = rng.integers(0, 3, 40)
    strong = rng.random(40) < 0.5
    labels = np.repeat([0, 1, 2], 2)
    Y = np.zeros((6, 40))
    Y[2 * peak_at, np.arange(40)] = np.where(strong, 6.0, 1.0)
    Y[2 * peak_at + 1, np.arange(40)] = np.where(strong, 6.0, 1.0)
    key = np.where(strong, peak_at, 3 + peak_at)
    want = sorted(range(40), key=lambda j: key[j])          # Python's sort is stable
    assert M.spatial_order(Y, labels, 3).tolist() == want


# ------------------------------------------------------------------------------ decoding
def test_winner_decoder_by_hand():
    # unit 0 wins at locations 1, 1, 2 (-> 1), unit 1 wins once at 3 (-> 3), unit 2 never
    # wins: the most frequent location, 1
    Y = np.array([[5, 0, 0], [5, 0, 0], [5, 0, 0], [0, 5, 0]], float)
    assert M.fit_winner_decoder(Y, np.array([1, 1, 2, 3]), 4).tolist() == [1, 3, 1]
    assert M.fit_winner_decoder(np.zeros((0, 2)), np.zeros(0, int), 3).tolist() == [0, 0]
    _raises(lambda: M.fit_winner_decoder(Y, np.array([1, 1, 2, 4]), 4),
            "labels must lie in [0, 4), got 1..4")
    _raises(lambda: M.fit_winner_decoder(Y[:3], np.array([1, 1, 2, 3]), 4),
            "Y has 3 rows, expected 4")


def test_centroid_decoder_by_hand():
    Y = np.array([[1.0, 2.0], [3.0, 4.0], [5.0, 5.0]])
    C = _strict(M.fit_centroid_decoder, Y, np.array([0, 0, 2]), 3)   # location 1 unvisited
    np.testing.assert_array_equal(C, [[2.0, 3.0], [np.nan, np.nan], [5.0, 5.0]])
    _raises(lambda: M.fit_centroid_decoder(Y[:2], np.array([0, 0, 2]), 3),
            "Y has 2 rows, expected 3")
    _raises(lambda: M.decode_nearest_centroid(Y, np.full((2, 2), np.nan)),
            "no location has a centroid (the training data visited none)")
    _raises(lambda: M.decode_nearest_centroid(Y, np.zeros((5, 3))),
            "centroids must be (locations, 2) for 2 units, got shape (5, 3)")


def test_decoding_accuracy_by_hand():
    # locations 0-1-2-3 on a path; the mapping sends unit 0 to 0 and unit 1 to 3
    nb = np.eye(4, dtype=bool) | np.eye(4, k=1, dtype=bool) | np.eye(4, k=-1, dtype=bool)
    Y = np.array([[1, 0], [0, 1], [1, 0], [0, 1]], float)
    lab = np.array([0, 3, 1, 2])
    # predicted 0, 3, 0, 3: exact 2 of 4; each prediction one step from its label at most
    assert M.decoding_accuracy(Y, lab, np.array([0, 3]), nb) == (0.5, 1.0)
    assert M.decoding_accuracy(Y, lab, np.array([0, 3])) == (0.5, 0.5)
    # a mapping naming location 4 when neighbors covers 4 (0..3): refused; 3 is the last
    _raises(lambda: M.decoding_accuracy(Y, lab, np.array([0, 4]), nb),
            "the decoder names location 4; neighbors covers 4 locations")
    _raises(lambda: M.decoding_accuracy(Y, lab, np.array([0, 3]), np.ones((4, 5), bool)),
            "neighbors must be a square boolean matrix, got bool (4, 5)")
    _raises(lambda: M.decoding_accuracy(Y, lab, np.array([0, 3]), np.ones(4, bool)),
            "neighbors must be a square boolean matrix, got bool (4,)")
    _raises(lambda: M.decoding_accuracy(Y[:3], lab, np.array([0, 3]), nb),
            "Y has 3 rows, expected 4")
    # centroids without neighbours: the labels must name one of the 4 centroids
    C = np.array([[1.0, 0.0], [0.5, 0.5], [0.4, 0.6], [0.0, 1.0]])
    assert M.decoding_accuracy(Y, lab, C) == (0.5, 0.5)
    _raises(lambda: M.decoding_accuracy(Y, np.array([0, 4, 1, 2]), C),
            "labels must lie in [0, 4), got 0..4")
    # no samples: NaN, silently
    for nbs in (None, nb):
        ex, near = _strict(M.decoding_accuracy, np.zeros((0, 2)), np.zeros(0, int),
                           np.array([0, 3]), nbs)
        assert np.isnan(ex) and np.isnan(near)


def test_walls_crossing_or_touching_the_line():
    # two locations p = (3, 2), q = (13, 2); each wall alone, shifted off the origin
    loc = np.array([[3.0, 2.0], [13.0, 2.0]])
    walls = {
        (8, -3, 8, 7): True,        # crosses the line
        (8, 7, 8, 2): True,         # its end touches the line
        (13, 2, 13, 7): True,       # starts at q
        (3, -4, 3, 2): True,        # ends at p
        (7, -1, 9, 6): True,        # crosses at an angle
        (5, 2, 7, 2): False,        # along the line (collinear): not a crossing
        (8, 3, 8, 7): False,        # above the line
        (15, -3, 15, 7): False,     # beyond q
        (1, 5, 16, 9): False,       # above, slanted
    }
    for w, blocked in walls.items():
        nb = M.location_neighbors(loc, walls=np.array([w], float))
        assert nb.tolist() == [[True, not blocked], [not blocked, True]], w
    # a slanted line p = (3, 2), q = (13, 12) and the other diagonal of its square: they
    # cross at (8, 7); a wall below the line, parallel to it, does not
    diag = np.array([[3.0, 2.0], [13.0, 12.0]])
    for w, blocked in (((3, 12, 13, 2), True), ((9, 2, 13, 4), False), ((8, 2, 14, 8), False)):
        nb = M.location_neighbors(diag, walls=np.array([w], float))
        assert nb[0, 1] == nb[1, 0] == (not blocked), w
    # two walls at once, one blocking
    nb = M.location_neighbors(loc, walls=np.array([[8, 3, 8, 7], [8, -3, 8, 7]], float))
    assert not nb[0, 1] and not nb[1, 0]


def test_location_neighbors_radius():
    # x = 0, 1, 3, 7: nearest-neighbour distances 1, 1, 2, 4, median 1.5, radius 2.25
    loc = np.column_stack([[0.0, 1.0, 3.0, 7.0], np.zeros(4)])
    path = np.eye(4, dtype=bool)
    path[0, 1] = path[1, 0] = path[1, 2] = path[2, 1] = True
    assert M.location_neighbors(loc).tolist() == path.tolist()
    assert M.location_neighbors(loc, radius=2.0).tolist() == path.tolist()   # 2 <= 2
    assert M.location_neighbors(loc, radius=1.99).sum() == 4 + 2
    assert M.location_neighbors(loc, radius=0.5).tolist() == np.eye(4, dtype=bool).tolist()
    one = M.location_neighbors(np.array([[1.0, 2.0]]))
    assert one.dtype == bool and one.tolist() == [[True]]
    _raises(lambda: M.location_neighbors(np.zeros(3)), "locations must be (L, 2), got (3,)")
    _raises(lambda: M.location_neighbors(np.array([[np.nan, 0.0]])),
            "locations contains 1 non-finite value(s) (NaN or inf)")
    _raises(lambda: M.location_neighbors(loc, walls=np.array([[0.0, 0.0, np.inf, 1.0]])),
            "walls contains 1 non-finite value(s) (NaN or inf)")
    _raises(lambda: M.location_neighbors(loc, radius=0), "radius must be finite and > 0, got 0")
    _raises(lambda: M.location_neighbors(loc, radius=np.nan), "radius must be finite, got nan")
    _raises(lambda: M.place_fields_grid(loc, np.ones(4), bins=0),
            "bins must be an integer in [1, 1000], got 0")
    _raises(lambda: M.place_fields_grid(np.ones((3, 3)), np.ones(3)),
            "xy must be (T, 2), got (3, 3)")
    _raises(lambda: M.place_fields_grid(loc, np.ones(3)), "Y has 3 rows, expected 4")
    _raises(lambda: M.place_fields_grid(np.array([[np.nan, 0.0]]), np.ones(1)),
            "xy contains 1 non-finite value(s) (NaN or inf)")


# ------------------------------------------------------------------------------ binary cells
def _brute_threshold(y: np.ndarray, truth: np.ndarray) -> tuple[float, float]:
    """The first threshold (ascending: below all values, between distinct values, above all)
    maximising the balanced accuracy of ``y > thr``, each counted directly."""
    u = np.unique(y)
    cands = [u[0] - 0.5, *((u[:-1] + u[1:]) / 2), u[-1] + 0.5]
    pos, neg = truth.sum(), (~truth).sum()
    best = (np.nan, -np.inf)
    for t in cands:
        p = y > t
        b = 0.5 * ((p & truth).sum() / pos + (~p & ~truth).sum() / neg)
        if b > best[1]:
            best = (float(t), float(b))
    return best


def test_best_threshold_against_a_brute_force_search():
    rng = np.random.default_rng(0)
    for _ in range(60):
        n = int(rng.integers(2, 9))
        y = rng.integers(0, 5, n).astype(float)           # integers: ties, exact midpoints
        truth = rng.random(n) < rng.uniform(0.2, 0.8)
        if truth.all() or not truth.any():
            continue
        assert M._best_threshold(y, truth) == _brute_threshold(y, truth), (y, truth)
    # anti-correlated: no cut beats predicting everyone positive (the first, below all)
    assert M._best_threshold(np.array([1.0, 2, 3, 4]), np.array([1, 1, 0, 0], bool)) == \
        (0.5, 0.5)


def test_fit_binary_cell_by_hand():
    Y = np.array([[1.0, 1.0], [2.0, 2.0], [3.0, 3.0], [4.0, 4.0]])
    cell = M.fit_binary_cell(Y, np.array([0, 0, 1, 1]))    # 0/1 integers as classes
    # two identical units: the first is kept; the cut between 2 and 3
    assert (cell.unit, cell.threshold, cell.polarity, cell.train_balanced_accuracy) == \
        (0, 2.5, 1, 1.0)
    neg = M.fit_binary_cell(Y, np.array([True, True, False, False]))
    assert (neg.unit, neg.threshold, neg.polarity) == (0, 2.5, -1)
    assert neg.predict(Y).tolist() == [True, True, False, False]
    # units restricts the search: unit 1 is imperfect, but the only one allowed
    Z = np.column_stack([[1.0, 2, 3, 4], [1.0, 3, 2, 4]])
    one = M.fit_binary_cell(Z, np.array([False, False, True, True]), units=[1])
    assert one.unit == 1 and one.train_balanced_accuracy == 0.75
    # mask (0/1 integers, cast to bool) drops the last sample, which would spoil the cut
    y = np.array([[1.0], [2.0], [3.0], [4.0], [10.0]])
    m = M.fit_binary_cell(y, np.array([0, 0, 1, 1, 0], bool), mask=[1, 1, 1, 1, 0])
    assert (m.threshold, m.polarity, m.train_balanced_accuracy) == (2.5, 1, 1.0)
    _raises(lambda: M.fit_binary_cell(Y, np.array([True, False, True])),
            "truth must have shape (4,), got (3,)")
    _raises(lambda: M.fit_binary_cell(Y, np.array([True, False, True, False]),
                                      mask=[True, False, True, False]),
            "truth needs both classes among the selected training samples")


def test_binary_cell_predict_is_strict():
    Y = np.array([[1.0], [2.0], [3.0]])
    assert M.BinaryCell(0, 2.0, 1, 1.0).predict(Y).tolist() == [False, False, True]
    assert M.BinaryCell(0, 2.0, -1, 1.0).predict(Y).tolist() == [True, False, False]


def test_balanced_accuracy_by_hand():
    # TPR 1/3, TNR 1: 2/3
    assert M.balanced_accuracy(np.array([1, 0, 0, 0]), np.array([1, 1, 1, 0])) == \
        0.5 * (1 / 3 + 1.0)
    # exactly one positive: TPR 1, TNR 1/2
    assert M.balanced_accuracy(np.array([1, 0, 1]), np.array([1, 0, 0])) == 0.75
    for truth in (np.ones(3, bool), np.zeros(3, bool)):      # one class only: NaN, silently
        assert np.isnan(_strict(M.balanced_accuracy, np.ones(3, bool), truth))
    _raises(lambda: M.balanced_accuracy(np.ones(3, bool), np.ones(4, bool)),
            "pred (3,) and truth (4,) differ in shape")
    msg = "pred must hold booleans (or integers 0 and 1), got dtype "
    _raises(lambda: M.balanced_accuracy(np.array([0.5, 1.0, 0.0]), np.ones(3, bool)),
            msg + "float64 with values 0.0..1.0")
    _raises(lambda: M.balanced_accuracy(np.array([], float), np.ones(0, bool)), msg + "float64")
    _raises(lambda: M.balanced_accuracy(np.array(["a", "b"]), np.ones(2, bool)), msg + "<U1")
    _raises(lambda: M.balanced_accuracy(np.ones(2, bool), np.array([-1, 2])),
            "truth must hold booleans (or integers 0 and 1), got dtype int64 with values -1..2")


# ------------------------------------------------------------------------------ kidnapping
def test_recovery_stops_at_the_next_event():
    correct = np.r_[np.zeros(10, bool), np.ones(20, bool)]
    # event 2: the search stops at event 5 before the read-out is right: NaN; event 5:
    # right from tick 10 on, r = 5; event 20: right at once
    np.testing.assert_array_equal(M.recovery_times(correct, [2, 5, 20], hold=3),
                                  [np.nan, 5, 0])
    np.testing.assert_array_equal(M.recovery_times(correct, [2, 5], hold=3), [np.nan, 5])
    # the same tick twice (sorted, allowed): the first search is empty
    np.testing.assert_array_equal(M.recovery_times(correct, [5, 5], hold=3), [np.nan, 5])
    assert M.recovery_times(correct, [0], hold=3).tolist() == [10.0]
    # events too close for a window of hold ticks: no recovery, even if right throughout
    np.testing.assert_array_equal(M.recovery_times(np.ones(20, bool), [5, 7], hold=5),
                                  [np.nan, 0])


def test_recovery_hold_default_and_horizon_edges():
    # right on ticks 10..14 (5 ticks), wrong on 15, right from 16: hold 5 (the default)
    # recovers at 10; hold 6 at 16
    correct = np.ones(40, bool)
    correct[:10] = False
    correct[15] = False
    assert M.recovery_times(correct, [0]).tolist() == [10.0]
    assert M.recovery_times(correct, [0], hold=6).tolist() == [16.0]
    # horizon: recovery at r = 10 with hold 3 needs ticks up to 12, so a horizon of 13
    # ticks and no fewer
    c = np.r_[np.zeros(10, bool), np.ones(5, bool), np.zeros(5, bool), np.ones(20, bool)]
    assert M.recovery_times(c, [0], hold=3, horizon=13).tolist() == [10.0]
    assert np.isnan(M.recovery_times(c, [0], hold=3, horizon=12)[0])
    # per event: event 15 recovers at r = 5 (ticks 20..22), so 8 ticks and no fewer
    np.testing.assert_array_equal(M.recovery_times(c, [0, 15], hold=3, horizon=[13, 7]),
                                  [10, np.nan])
    np.testing.assert_array_equal(M.recovery_times(c, [0, 15], hold=3, horizon=[13, 8]),
                                  [10, 5])
    # a shorter list: its last value serves the later events
    np.testing.assert_array_equal(M.recovery_times(c, [0, 15], hold=3, horizon=[13]), [10, 5])
    np.testing.assert_array_equal(M.recovery_times(c, [0, 15], hold=3, horizon=[12]),
                                  [np.nan, 5])


def test_recovery_refusals():
    ok = np.ones(50, bool)
    _raises(lambda: M.recovery_times(ok, [10], hold=0), "hold must be an integer >= 1, got 0")
    _raises(lambda: M.recovery_times(np.zeros(50), [10]),
            "correct must be a 1-D boolean series, got float64 (50,)")
    _raises(lambda: M.recovery_times(ok, np.array([30, 10])),
            "events must be sorted tick indices in [0, 50), got array([30, 10])")
    _raises(lambda: M.recovery_times(ok, np.array([-1])),
            "events must be sorted tick indices in [0, 50), got array([-1])")


def test_recovery_refuses_a_horizon_that_is_no_number_of_ticks():
    c = np.ones(20, dtype=bool)
    msg = "horizon must be a number of ticks >= 0, or one per event (the last repeated), got "
    for bad in (-1, [3, -1], [], 2.5, [np.nan], True, [[3]]):
        with pytest.raises(ValueError, match="^" + re.escape(msg + f"{bad!r}"[:80]) + "$"):
            M.recovery_times(c, [0, 5], horizon=bad)
    # 0 ticks: no search at all (NaN), an integer array one per event
    assert np.isnan(M.recovery_times(c, [0], horizon=0)[0])
    np.testing.assert_array_equal(M.recovery_times(c, [0, 5], horizon=np.array([5, 5])),
                                  [0.0, 0.0])
