"""Place-cell metrics on hand-made recordings with known answers."""

import numpy as np
import pytest

from hippo.perception import metrics as M


def _track(L=8, reps=30):
    """A robot shuttling along L locations on a line; unit j fires at location j."""
    labels = np.tile(np.r_[np.arange(L), np.arange(L - 2, 0, -1)], reps)
    Y = -0.3 * np.ones((labels.size, L))
    Y[np.arange(labels.size), labels] = 6.0
    locations = np.column_stack([np.arange(L) * 10.0, np.zeros(L)])
    return labels, Y, locations


def test_neighbors():
    _, _, loc = _track()
    nb = M.location_neighbors(loc)
    assert nb[0, 1] and nb[3, 2] and not nb[0, 2] and nb[4, 4]
    wall = np.array([[15.0, -5.0, 15.0, 5.0]])  # between locations 1 and 2
    nbw = M.location_neighbors(loc, walls=wall)
    assert nbw[0, 1] and not nbw[1, 2] and not nbw[2, 1] and nbw[2, 3]


def test_localized_units_and_aliasing():
    labels, Y, loc = _track()
    nb = M.location_neighbors(loc)
    res = M.localized_units(Y, labels, nb)
    assert res.count == 8
    np.testing.assert_array_equal(res.preferred, np.arange(8))
    # a unit firing at two distant locations is not localized; a weak unit neither
    Y2 = Y.copy()
    Y2[:, 0] = np.where(np.isin(labels, (0, 3, 6)), 6.0, -0.3)
    Y2[:, 1] = np.where(labels == 1, 3.0, -0.3)
    res2 = M.localized_units(Y2, labels, nb)
    assert not res2.localized[0] and not res2.localized[1] and res2.count == 6


def test_decoding_accuracy():
    labels, Y, loc = _track()
    nb = M.location_neighbors(loc)
    mapping = M.fit_winner_decoder(Y, labels, 8)
    np.testing.assert_array_equal(mapping, np.arange(8))
    assert M.decoding_accuracy(Y, labels, mapping, nb) == (1.0, 1.0)
    shifted = np.roll(Y, 1, axis=1)  # every unit now fires one location too far
    exact, near = M.decoding_accuracy(shifted, labels, mapping, nb)
    assert exact < 0.2 and near > 0.8


def test_centroid_decoder_reads_a_population_code_the_winner_cannot():
    # two ramp units code the position along the track together; neither is a place cell
    labels, _, loc = _track()
    x = labels / 7.0
    Y = np.column_stack([x, 1.0 - x])
    cent = M.fit_centroid_decoder(Y, labels, 9)
    np.testing.assert_allclose(cent[:8], np.column_stack([np.arange(8) / 7, 1 - np.arange(8) / 7]))
    assert np.isnan(cent[8]).all()  # location 8 was never visited: NaN, never decoded
    nb = M.location_neighbors(np.vstack([loc, [[500.0, 0.0]]]))
    assert M.decoding_accuracy(Y, labels, cent, nb) == (1.0, 1.0)
    winner = M.decoding_accuracy(Y, labels, M.fit_winner_decoder(Y, labels, 9), nb)
    assert winner[0] < 0.3  # the winner names only the two ends of the track
    # a sample halfway between locations 2 and 3 goes to the nearer centroid
    assert M.decode_nearest_centroid(np.array([[2.4 / 7, 1 - 2.4 / 7]]), cent)[0] == 2


def test_centroid_decoder_in_chunks_and_bad_input():
    rng = np.random.default_rng(0)
    labels = rng.integers(0, 5, 1000)
    Y = rng.normal(size=(1000, 3)) + labels[:, None]
    cent = M.fit_centroid_decoder(Y, labels, 5)
    np.testing.assert_array_equal(M.decode_nearest_centroid(Y, cent, chunk=7),
                                  M.decode_nearest_centroid(Y, cent))
    with pytest.raises(ValueError, match="centroids must be"):
        M.decode_nearest_centroid(Y, cent[:, :2])
    with pytest.raises(ValueError, match="no location has a centroid"):
        M.decode_nearest_centroid(Y, np.full((5, 3), np.nan))
    with pytest.raises(ValueError, match="labels"):
        M.fit_centroid_decoder(Y, labels, 4)


def test_place_fields():
    labels, Y, loc = _track()
    F = M.place_fields_locations(labels, Y, 9)
    assert np.isnan(F[8]).all() and F[3, 3] == 6.0
    xy = loc[labels]
    fields, occ, _, _ = M.place_fields_grid(xy, Y, bins=(8, 1))
    assert fields.shape == (8, 1, 8) and occ.sum() == labels.size
    order = M.spatial_order(Y[:, ::-1], labels, 8)
    np.testing.assert_array_equal(order, np.arange(8)[::-1])


def test_binary_cell_and_balanced_accuracy():
    rng = np.random.default_rng(0)
    truth = np.repeat([False, True, False, True], 250)
    Y = rng.standard_normal((1000, 3))
    Y[:, 2] = np.where(truth, -1.0, 1.0) + 0.1 * rng.standard_normal(1000)
    cell = M.fit_binary_cell(Y, truth)
    assert cell.unit == 2 and cell.polarity == -1 and cell.train_balanced_accuracy == 1.0
    assert M.balanced_accuracy(cell.predict(Y), truth) == 1.0
    assert M.balanced_accuracy(np.ones(4, bool), np.array([1, 1, 0, 0], bool)) == 0.5
    with pytest.raises(ValueError, match="both classes"):
        M.fit_binary_cell(Y, np.zeros(1000, bool))


def test_recovery_times():
    correct = np.ones(100, bool)
    correct[10:22] = False
    correct[50:53] = False
    correct[55] = False
    np.testing.assert_array_equal(M.recovery_times(correct, [10, 50], hold=5), [12, 6])
    never = np.zeros(30, bool)
    assert np.isnan(M.recovery_times(never, [5])[0])


def test_bad_input():
    with pytest.raises(ValueError, match="labels"):
        M.place_fields_locations(np.array([0.5, 1.0]), np.zeros((2, 1)), 3)
    with pytest.raises(ValueError, match="rows"):
        M.place_fields_locations(np.array([0, 1]), np.zeros((3, 1)), 3)
    with pytest.raises(ValueError, match="non-finite"):
        M.localized_units(np.array([[np.nan]]), np.array([0]), np.ones((1, 1), bool))


def _slow_classes(T=3000, d=12, seed=0):
    """A state X whose first feature is a slow square wave: the class is its sign."""
    rng = np.random.default_rng(seed)
    cls = ((np.arange(T) // 150) % 3).astype(int)          # three "rooms" visited in turn
    X = rng.normal(size=(T, d))
    X[:, 0] = cls == 0
    X[:, 1] = cls == 1
    return X, cls


def test_ridge_ceiling_exact_when_classes_are_linear():
    X, cls = _slow_classes()
    c = M.ridge_ceiling(X, cls, 3, folds=5, gap=20)
    assert c.balanced_accuracy == 1.0 and c.accuracy == 1.0
    assert np.array_equal(c.predicted, cls) and c.alpha.shape == (5,)


def test_ridge_ceiling_is_chance_without_information():
    X, cls = _slow_classes()
    X[:, :2] = np.random.default_rng(1).normal(size=(X.shape[0], 2))
    c = M.ridge_ceiling(X, cls, 3, folds=5, gap=20)
    assert abs(c.balanced_accuracy - 1 / 3) < 0.08


def test_ridge_ceiling_mask_and_errors():
    X, cls = _slow_classes()
    mask = cls != 2
    c = M.ridge_ceiling(X, np.where(mask, cls, -1), mask=mask, gap=20)
    assert c.balanced_accuracy == 1.0 and np.all(c.predicted[~mask] == -1)
    assert c.per_class_recall.shape == (2,)
    with pytest.raises(ValueError, match="folds"):
        M.ridge_ceiling(X, cls, folds=1)
    with pytest.raises(ValueError, match="labels"):
        M.ridge_ceiling(X, cls.astype(float))
    with pytest.raises(ValueError, match="gap"):
        M.ridge_ceiling(X[:100], cls[:100], 3, gap=20, folds=5)


def test_recovery_times_refuse_inputs_that_made_every_event_recover_at_once():
    from hippo.perception.metrics import recovery_times

    never = np.zeros(50, bool)
    assert np.isnan(recovery_times(never, [10, 20], hold=1)).all()
    for hold in (0, -3, 2.5, True):
        with pytest.raises(ValueError, match="hold"):
            recovery_times(never, [10, 20], hold=hold)
    with pytest.raises(ValueError, match="boolean"):
        recovery_times(np.full(50, np.nan), [10])
    for events in ([-5], [30, 10], [50], [1.5]):
        with pytest.raises(ValueError, match="events"):
            recovery_times(np.ones(50, bool), events)
    assert recovery_times(np.r_[np.zeros(25, bool), np.ones(25, bool)], [10, 30],
                          hold=5).tolist() == [15.0, 0.0]


def test_decoding_accuracy_checks_its_neighbours_labels_and_mapping():
    from hippo.perception import metrics as M

    rng = np.random.default_rng(0)
    Y, lab = rng.normal(size=(100, 5)), rng.integers(0, 4, 100)
    C = M.fit_centroid_decoder(Y, lab, 4)
    exact, near = M.decoding_accuracy(Y, lab, C, np.eye(4, dtype=bool))
    assert exact == near <= 1.0
    with pytest.raises(ValueError, match="square boolean"):
        M.decoding_accuracy(Y, lab, C, np.eye(4, dtype=int) * 5)   # gave 1.7 "within one step"
    with pytest.raises(ValueError, match="labels must lie in"):
        M.decoding_accuracy(Y, lab - 1, C, np.eye(4, dtype=bool))
    with pytest.raises(ValueError, match="labels must lie in"):
        M.decoding_accuracy(Y, lab, C, np.eye(2, dtype=bool))
    for mapping in ([0, 1, 2], [np.nan, 1, 2, 3, 0], [-1, 1, 2, 3, 0]):
        mapping = np.array(mapping)
        with pytest.raises(ValueError, match="one location"):
            M.decoding_accuracy(Y, lab, mapping)


def test_ridge_ceiling_refuses_arguments_it_used_to_trust():
    X, cls = _slow_classes(T=400)
    bad_calls = {
        "alphas": [dict(alphas=(np.nan,)), dict(alphas=(np.inf,)), dict(alphas=()),
                   dict(alphas=("a",)), dict(alphas=(0.0, 1.0)), dict(alphas=1.0)],
        "gap": [dict(gap=-5), dict(gap=2.5), dict(gap=True)],
        "folds": [dict(folds=2.5), dict(folds=1)],
        "n_classes": [dict(n_classes=2.5)],
        r"labels inside the mask must lie in \[0, n_classes=2\)": [dict(n_classes=2)],
        "classes .* at most one class per sample": [dict(n_classes=10**9)],
        "mask selects no samples": [dict(mask=np.zeros(400, bool))],
    }
    for match, calls in bad_calls.items():
        for kw in calls:
            with pytest.raises(ValueError, match=match):
                M.ridge_ceiling(X, cls, **{"n_classes": 3, "gap": 5, **kw})
    with pytest.raises(ValueError, match="at most one class per sample"):
        M.ridge_ceiling(X, cls * 10**6, gap=5)          # labels that imply 2 million classes
    c = M.ridge_ceiling(X, cls, 3, gap=5, alphas=np.array([1.0, 10.0]))  # an array is fine
    assert c.balanced_accuracy == 1.0 and set(c.alpha) <= {1.0, 10.0}


def test_place_metrics_refuse_bad_parameters():
    labels, Y, loc = _track()
    xy = np.column_stack([loc[labels, 0], np.zeros(labels.size)])
    for bins in (0, -3, 2.5, True, 10**5, (8, 0), (8, 1.5), (1, 2, 3)):
        with pytest.raises(ValueError, match="bins"):
            M.place_fields_grid(xy, Y, bins=bins)
    assert M.place_fields_grid(xy, Y, bins=np.int64(8))[1].shape == (8, 8)
    for radius in (-1, 0, np.nan, np.inf, "15"):
        with pytest.raises(ValueError, match="radius"):
            M.location_neighbors(loc, radius=radius)
    assert M.location_neighbors(loc, radius=15.0).sum() == 8 + 2 * 7
    nb = M.location_neighbors(loc)
    for threshold in (np.nan, np.inf, "4.5", None):
        with pytest.raises(ValueError, match="threshold"):
            M.localized_units(Y, labels, nb, threshold=threshold)
    truth = np.array([True, True, False, False])
    for name, pred, tr in (("pred", np.array([0.5, 1.0, 0.0, 0.0]), truth),
                           ("truth", np.ones(4, bool), np.array([-1, -2, 0, 0])),
                           ("truth", np.ones(4, bool), np.array([2, 2, 0, 0]))):
        with pytest.raises(ValueError, match=f"{name} must hold booleans"):
            M.balanced_accuracy(pred, tr)
    assert M.balanced_accuracy(np.array([1, 0, 0, 0]), np.array([1, 1, 0, 0])) == 0.75
