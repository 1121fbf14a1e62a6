import numpy as np
import pytest

from hippo.io import CorruptFileError
from hippo.perception.prototypes import PlacePrototypes, PrototypeParams


def _clusters(seed=0):
    rng = np.random.default_rng(seed)
    centres = np.array([[0.0, 0.0, 0.0], [5.0, 0.0, 0.0], [0.0, 5.0, 0.0], [0.0, 0.0, 5.0]])
    Y = np.concatenate([c + 0.3 * rng.standard_normal((200, 3)) for c in centres])
    return centres, Y


def test_recovers_cluster_centres_and_activity_equation():
    centres, Y = _clusters()
    p = PlacePrototypes(PrototypeParams(n_prototypes=4, seed=1)).fit(Y)
    for c in centres:
        assert np.min(np.linalg.norm(p.centres_ - c, axis=1)) < 0.1
    y = np.array([0.2, -0.1, 0.4])
    expect = np.exp(-np.sum((p.centres_ - y) ** 2, axis=1) / (2 * p.sigma_**2))
    np.testing.assert_allclose(p.transform(y[None])[0], expect, rtol=1e-12)
    np.testing.assert_allclose(p.transform(p.centres_).diagonal(), 1.0)
    # sigma is the median distance of a sample to its nearest centre (about 0.3 * sqrt(3))
    assert 0.3 < p.sigma_ < 0.7


def test_each_cluster_has_its_own_winner():
    _centres, Y = _clusters()
    p = PlacePrototypes(PrototypeParams(n_prototypes=4)).fit(Y)
    winners = np.argmax(p.transform(Y), axis=1).reshape(4, 200)
    assert len({int(np.bincount(w).argmax()) for w in winners}) == 4
    assert all(np.mean(w == np.bincount(w).argmax()) > 0.99 for w in winners)


def test_online_recruitment_of_a_novel_place():
    _, Y = _clusters()
    p = PlacePrototypes(PrototypeParams(n_prototypes=4, recruit_threshold=0.2)).fit(Y)
    assert p.step(Y[0]).size == 4
    a = p.step(np.array([9.0, 9.0, 9.0]))
    assert a.size == 5 and a[-1] == 1.0 and p.n_units == 5
    assert np.argmax(p.step(np.array([9.1, 9.0, 8.9]))) == 4  # the new cell wins nearby


@pytest.mark.parametrize("d", [3, 24])
def test_one_output_step_is_the_transform_of_one_row_bit_for_bit(d):
    """The closed loop's tick (1-D operations, centre norms kept) gives exactly the numbers of
    transform() on a block of one row, for a few dims and many outputs."""
    rng = np.random.default_rng(d)
    Y = rng.standard_normal((400, d)) * 2.0
    p = PlacePrototypes(PrototypeParams(n_prototypes=16, seed=0)).fit(Y)
    for y in np.concatenate([Y[:100], rng.standard_normal((100, d)) * 4.0]):
        np.testing.assert_array_equal(p.step(y), p.transform(y[None])[0])


def test_same_seed_same_prototypes_and_round_trip(tmp_path):
    _, Y = _clusters(3)
    a = PlacePrototypes(PrototypeParams(n_prototypes=6, seed=5)).fit(Y)
    b = PlacePrototypes(PrototypeParams(n_prototypes=6, seed=5)).fit(Y)
    np.testing.assert_array_equal(a.centres_, b.centres_)
    back = PlacePrototypes.load(a.save(tmp_path / "p.npz"))
    np.testing.assert_array_equal(back.transform(Y), a.transform(Y))


def test_bad_input(tmp_path):
    with pytest.raises(ValueError, match="n_prototypes"):
        PrototypeParams(n_prototypes=0)
    with pytest.raises(ValueError, match="recruit_threshold"):
        PrototypeParams(recruit_threshold=1.5)
    with pytest.raises(RuntimeError, match="not fitted"):
        PlacePrototypes().transform(np.zeros((1, 3)))
    with pytest.raises(ValueError, match="non-finite"):
        PlacePrototypes(PrototypeParams(n_prototypes=2)).fit(np.array([[0.0, np.nan]] * 5))
    with pytest.raises(ValueError, match="at least"):
        PlacePrototypes(PrototypeParams(n_prototypes=10)).fit(np.zeros((3, 2)))
    bad = tmp_path / "bad.npz"
    bad.write_bytes(b"garbage")
    with pytest.raises(CorruptFileError):
        PlacePrototypes.load(bad)


def test_outputs_whose_squared_distances_overflow_are_refused_by_name():
    # scipy's kmeans2 crashed the interpreter on such data (k-means++ on NaN probabilities)
    Y = np.random.default_rng(0).normal(size=(500, 4)) * 1e155
    with pytest.raises(ValueError, match="overflow float64"):
        PlacePrototypes(PrototypeParams(n_prototypes=5, seed=0)).fit(Y)
    PlacePrototypes(PrototypeParams(n_prototypes=5, seed=0)).fit(Y * 1e-150)   # rescaled: fine
    with pytest.raises(ValueError, match=r"max_prototypes \(10\) must be >= n_prototypes \(20\)"):
        PrototypeParams(n_prototypes=20, max_prototypes=10)
