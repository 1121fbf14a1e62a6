"""The place sources (hippo.places): known answers worked out by hand.

LearnedPlaceCells is checked on hand-made stand-ins (a model, prototypes and a relocaliser that
record what they are asked and answer fixed values), GroundTruthPlaceCells on Gaussian fields
whose squared distances are worked out by hand: ``a_k = exp(-|p - c_k|^2 / (2 sigma^2))``.
Every refusal is compared word for word with its specification.
"""

from __future__ import annotations

import math
import re
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from hippo._estimator import NotFittedError
from hippo.perception.prototypes import PlacePrototypes, PrototypeParams
from hippo.perception.relocate import SequenceRelocaliser
from hippo.places import GroundTruthPlaceCells, LearnedPlaceCells, _fitted_units
from hippo.types import GroundTruth, Observation


class _Reservoir:
    def __init__(self) -> None:
        self.resets: list[Any] = []

    def reset(self, x: Any) -> None:
        self.resets.append(x)


class _Model:
    """A fitted RCSFAICA stand-in: ``step(u)`` returns ``10 u[:n_ica]`` and logs every call."""

    def __init__(self, n_ica: int = 3, *, std: Any = "none", downsample: int = 1,
                 slow_pool: Any = None, fitted: bool = True) -> None:
        self.ica_ = object() if fitted else None
        self.params = SimpleNamespace(n_ica=n_ica, downsample=downsample, slow_pool=slow_pool)
        if not isinstance(std, str):
            self.output_std_ = std
        self.reservoir_ = _Reservoir()
        self.log: list[Any] = []

    def step(self, u: np.ndarray) -> np.ndarray:
        self.log.append(("step", u))
        return 10.0 * np.asarray(u)[:self.params.n_ica]

    def reset_state(self) -> None:
        self.log.append("reset")


class _Protos:
    """Fitted prototypes stand-in: ``_step(y)`` returns ``y + 1`` (d = 3, 5 units)."""

    def __init__(self, d: int = 3) -> None:
        self.centres_ = np.zeros((5, d))
        self.n_units = 5
        self.checked = 0
        self.seen: list[np.ndarray] = []

    def _check_fitted(self) -> None:
        self.checked += 1

    def _step(self, y: np.ndarray) -> np.ndarray:
        self.seen.append(y)
        return y + 1.0


class _Relocaliser(SequenceRelocaliser):
    """Answers the queued states to ``observe`` and logs what it was shown."""

    def __init__(self, answers: list[Any]) -> None:
        super().__init__()
        self.answers = list(answers)
        self.shown: list[tuple[np.ndarray, bool]] = []

    def observe(self, u: np.ndarray, moving: bool) -> np.ndarray | None:
        self.shown.append((u, moving))
        return self.answers.pop(0)


def _obs(ir: list[float], moving: bool = True) -> Observation:
    return Observation(0.0, 0, np.array(ir), 0, False, np.zeros(3), moving)


# ---- _fitted_units and the constructor -------------------------------------------------

def test_the_fitted_width_is_the_output_scales_length_else_n_ica():
    assert _fitted_units(_Model(3, std=np.ones(4))) == 4      # changed by set_params since
    assert _fitted_units(_Model(3, std=None)) == 3
    assert _fitted_units(_Model(3)) == 3                        # no attribute at all
    assert LearnedPlaceCells(_Model(3, std=np.ones(4))).n_units == 4
    assert LearnedPlaceCells(_Model(2)).n_units == 2
    assert type(LearnedPlaceCells(_Model(2)).n_units) is int


def test_an_unfitted_model_is_refused():
    message = "LearnedPlaceCells needs a fitted RCSFAICA model"
    with pytest.raises(ValueError) as err:
        LearnedPlaceCells(_Model(fitted=False))
    assert str(err.value) == message
    with pytest.raises(ValueError, match=f"^{message}$"):
        LearnedPlaceCells(object())


def test_prototypes_are_checked_fitted_and_of_the_models_width():
    protos = _Protos(d=3)
    cells = LearnedPlaceCells(_Model(3), protos)
    assert protos.checked == 1 and cells.prototypes is protos and cells.n_units == 5
    with pytest.raises(ValueError) as err:
        LearnedPlaceCells(_Model(3), _Protos(d=2))
    assert str(err.value) == ("prototypes were fitted on 2-dimensional outputs; the model has "
                              "n_ica=3")
    # the width compared is the fitted one (output_std_), not params.n_ica
    with pytest.raises(ValueError, match=r"fitted on 3-dimensional outputs; the model has "
                                         r"n_ica=4$"):
        LearnedPlaceCells(_Model(3, std=np.ones(4)), _Protos(d=3))
    assert LearnedPlaceCells(_Model(2, std=np.ones(3)), _Protos(d=3)).n_units == 5
    # real prototypes, not fitted: their own refusal, before anything is read from them
    with pytest.raises(NotFittedError,
                       match=r"^PlacePrototypes is not fitted; call fit\(\) first$"):
        LearnedPlaceCells(_Model(3), PlacePrototypes(PrototypeParams(n_prototypes=2)))


def test_a_relocaliser_must_be_one():
    with pytest.raises(TypeError) as err:
        LearnedPlaceCells(_Model(), relocaliser="abc")  # type: ignore[arg-type]
    assert str(err.value) == "relocaliser must be a SequenceRelocaliser, got 'abc'"
    rel = _Relocaliser([])
    assert LearnedPlaceCells(_Model(), relocaliser=rel).relocaliser is rel
    assert LearnedPlaceCells(_Model()).relocaliser is None


@pytest.mark.parametrize(("downsample", "slow_pool", "refused"), [
    (1, None, False), (1, 0.0, False), (2, None, True), (3, None, True),
    (1, 20.0, True), (2, 20.0, True),
])
def test_re_anchoring_needs_no_down_sampling_and_no_slow_pool(downsample, slow_pool, refused):
    model = _Model(downsample=downsample, slow_pool=slow_pool)
    if refused:
        with pytest.raises(ValueError) as err:
            LearnedPlaceCells(model, relocaliser=_Relocaliser([]))
        assert str(err.value) == ("re-anchoring sets the reservoir state alone: it needs a "
                                  "model without down-sampling or a slow pool")
    else:
        LearnedPlaceCells(model, relocaliser=_Relocaliser([]))
    # without a relocaliser any model is taken
    assert LearnedPlaceCells(model).relocaliser is None


# ---- LearnedPlaceCells at work ----------------------------------------------------------

def test_step_feeds_the_readings_only_and_returns_the_models_output():
    model = _Model(2)
    cells = LearnedPlaceCells(model)
    truth = GroundTruth(0.0, 0, (50.0, 60.0, 0.0), 0.0)
    out = cells.step(_obs([0.1, 0.2, 0.3]), truth)
    np.testing.assert_array_equal(out, [1.0, 2.0])          # 10 u[:2]
    assert cells.anchored is False and len(model.log) == 1
    np.testing.assert_array_equal(model.log[0][1], [0.1, 0.2, 0.3])


def test_with_prototypes_the_activities_are_theirs():
    model, protos = _Model(3), _Protos(3)
    cells = LearnedPlaceCells(model, protos)
    out = cells.step(_obs([0.1, 0.2, 0.3]))
    np.testing.assert_allclose(protos.seen[0], [1.0, 2.0, 3.0])   # the model's output
    np.testing.assert_allclose(out, [2.0, 3.0, 4.0])              # ... + 1


def test_a_match_resets_the_reservoir_before_the_reading_and_marks_the_tick():
    state = np.array([7.0, 8.0])
    rel = _Relocaliser([None, state, None])
    model = _Model(2)
    cells = LearnedPlaceCells(model, relocaliser=rel)
    cells.step(_obs([0.5, 0.5]))          # not looking: the relocaliser is not asked
    assert rel.shown == [] and cells.anchored is False
    cells.lifted()
    assert rel.active
    cells.step(_obs([0.1, 0.2], moving=False))    # looking, no match yet
    assert cells.anchored is False and model.reservoir_.resets == []
    np.testing.assert_array_equal(rel.shown[0][0], [0.1, 0.2])
    assert rel.shown[0][1] is False
    out = cells.step(_obs([0.3, 0.4]))            # the match: jump, then this reading
    assert cells.anchored is True and model.reservoir_.resets == [state]
    assert rel.shown[1][1] is True
    np.testing.assert_allclose(out, [3.0, 4.0])
    assert model.log[-1][0] == "step"
    cells.step(_obs([0.3, 0.4]))                  # the next tick is anchored no more
    assert cells.anchored is False and model.reservoir_.resets == [state]


def test_reset_stops_the_relocaliser_and_lifted_starts_it():
    rel = _Relocaliser([])
    model = _Model()
    cells = LearnedPlaceCells(model, relocaliser=rel)
    cells.lifted()
    assert rel.active and rel.matched_after is None
    cells.reset()
    assert not rel.active and model.log == ["reset"]
    # without a relocaliser: reset resets the model, lifted does nothing
    bare = LearnedPlaceCells(model)
    bare.reset()
    bare.lifted()
    assert model.log == ["reset", "reset"]


def test_prime_resets_then_steps_through_every_reading_as_floats():
    model = _Model(2)
    cells = LearnedPlaceCells(model)
    cells.prime(np.array([[1, 0], [0, 1], [1, 1]]))   # integers: fed as floats
    assert model.log[0] == "reset" and len(model.log) == 4
    for (what, u), row in zip(model.log[1:], [[1, 0], [0, 1], [1, 1]], strict=True):
        assert what == "step" and u.dtype == np.float64
        np.testing.assert_array_equal(u, row)


# ---- GroundTruthPlaceCells --------------------------------------------------------------

def test_gaussian_fields_by_hand():
    """p = (3, 4): |p - c|^2 = 25, (3 - 10)^2 + 16 = 65, 9 + (4 + 4)^2 = 73; 2 sigma^2 = 50."""
    pc = GroundTruthPlaceCells(np.array([[0.0, 0.0], [10.0, 0.0], [0.0, -4.0]]), sigma=5.0)
    a = pc.step(None, GroundTruth(0.0, 0, (3.0, 4.0, 1.0), 0.0))
    np.testing.assert_allclose(a, [math.exp(-25 / 50), math.exp(-65 / 50), math.exp(-73 / 50)],
                               rtol=1e-15)
    assert pc.n_units == 3 and pc.sigma == 5.0 and pc.kind == "ground-truth"


def test_the_default_width_is_10_cm():
    """At 10 cm from the centre: exp(-100 / 200) = exp(-1/2)."""
    pc = GroundTruthPlaceCells([[0.0, 0.0]])
    assert pc.sigma == 10.0
    a = pc.step(None, SimpleNamespace(pose=(6.0, 8.0, 0.0)))
    np.testing.assert_allclose(a, [math.exp(-0.5)], rtol=1e-15)
    # the centres are kept as float64 values, lists accepted
    assert pc.centres.dtype == np.float64 and pc.centres.shape == (1, 2)


def test_without_the_truth_the_fields_refuse_word_for_word():
    pc = GroundTruthPlaceCells(np.zeros((1, 2)))
    with pytest.raises(ValueError) as err:
        pc.step(None)
    assert str(err.value) == ("GroundTruthPlaceCells read the true position: pass truth="
                              "world.truth (a GroundTruth) to step(), e.g. agent.step(obs, "
                              "world.truth)")


@pytest.mark.parametrize("shape", [(4, 3), (2,), (2, 2, 2), (3, 1), (2, 1, 2)])
def test_centres_must_be_n_by_2(shape):
    with pytest.raises(ValueError) as err:
        GroundTruthPlaceCells(np.zeros(shape))
    assert str(err.value) == (f"centres must be an (N, 2) array of (x, y) in cm, got shape "
                              f"{shape}")


def test_no_centre_non_finite_centres_and_a_bad_sigma_are_refused():
    with pytest.raises(ValueError) as err:
        GroundTruthPlaceCells(np.zeros((0, 2)))
    assert str(err.value) == "GroundTruthPlaceCells needs at least one centre"
    with pytest.raises(ValueError, match=re.escape("centres contains 1 non-finite value(s)")):
        GroundTruthPlaceCells(np.array([[0.0, np.nan]]))
    for bad in (0.0, -1.0, math.inf):
        with pytest.raises(ValueError, match=re.escape(f"sigma must be finite and > 0, got "
                                                       f"{bad!r}")):
            GroundTruthPlaceCells(np.zeros((1, 2)), sigma=bad)
    assert GroundTruthPlaceCells(np.zeros((1, 2)), sigma=1e-3).sigma == 1e-3


def test_the_fields_hold_no_state():
    pc = GroundTruthPlaceCells(np.array([[0.0, 0.0], [20.0, 0.0]]), sigma=4.0)
    truth = GroundTruth(0.0, 0, (20.0, 0.0, 0.0), 0.0)
    before = pc.step(None, truth)
    pc.reset()
    pc.prime(np.ones((3, 8)))
    np.testing.assert_array_equal(pc.step(None, truth), before)
    np.testing.assert_allclose(before, [math.exp(-400 / 32), 1.0], rtol=1e-15)
