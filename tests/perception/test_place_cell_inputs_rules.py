"""The place cells' input policy by hand (hippo.perception.place_cell_inputs), on a stand-in
that holds only the parameters: the recording's shape and kind, the range at its bounds and one
step past, the three out-of-range policies, the length a fit needs (with down-sampling and a
washout) and the constant-sensor refusal, each refusal word for word."""

from __future__ import annotations

import os
import warnings

import numpy as np
import pytest

from hippo.perception.place_cell_inputs import InputRangeWarning, SensorInputs
from hippo.perception.place_cell_params import RCSFAICAParams

FIT_HINT = ("; place cells are learned from sensor readings scaled to input_range: rescale U, "
            "or set input_range to its true range")
ERROR_HINT = ("; the model was fitted on readings in that range and would extrapolate (set "
              "out_of_range='clip' or 'warn' to clip instead)")


class Inputs(SensorInputs):
    """The checks alone, reading ``params`` as RCSFAICA does."""

    def __init__(self, **kw: object) -> None:
        kw.setdefault("n_inputs", 3)
        kw.setdefault("n_reservoir", 5)
        self.params = RCSFAICAParams(**kw)


# ----------------------------------------------------------------------- shape and kind
def test_a_recording_in_range_passes_unchanged():
    U = np.array([[0.0, 0.5, 1.0], [0.25, 0.75, 0.125]])
    out = Inputs()._check_U(U)
    assert out.dtype == np.float64 and out.tolist() == U.tolist()
    # integers become floats; float32 stays float32 (no copy of a large recording)
    ints = Inputs()._check_U(np.array([[0, 1, 0]]))
    assert ints.dtype == np.float64 and ints.tolist() == [[0.0, 1.0, 0.0]]
    f32 = np.array([[0.5, 0.5, 0.5]], dtype=np.float32)
    assert Inputs()._check_U(f32) is f32
    # a list is read as an array
    assert Inputs()._check_U([[0.1, 0.2, 0.3]]).shape == (1, 3)


@pytest.mark.parametrize("shape", [(4,), (4, 2), (4, 4), (2, 4, 3), (3, 1), ()])
def test_a_recording_of_another_shape_is_refused_word_for_word(shape):
    with pytest.raises(ValueError) as exc:
        Inputs()._check_U(np.zeros(shape))
    assert str(exc.value) == f"sensor sequence U must have shape (T, 3), got {shape}"


@pytest.mark.parametrize(("U", "dtype"), [
    (np.array([[True, False, True]]), "bool"),
    (np.array([[1 + 0j, 0j, 0j]]), "complex128"),
    (np.array([["0", "1", "0"]]), "<U1"),
    (np.array([[0.0, 1.0, None]], dtype=object), "object"),
])
def test_readings_that_are_not_real_numbers_are_refused(U, dtype):
    with pytest.raises(ValueError) as exc:
        Inputs()._check_U(U)
    assert str(exc.value) == f"sensor sequence U must be real numbers, got dtype {dtype}"


def test_ragged_and_non_finite_recordings_are_refused_naming_u():
    with pytest.raises(ValueError) as exc:
        Inputs()._check_U([[0.0, 0.1, 0.2], [0.3]])
    assert str(exc.value).startswith("sensor sequence U must be an array of numbers, got list")
    for bad in (np.nan, np.inf, -np.inf):
        U = np.zeros((2, 3))
        U[1, 2] = bad
        with pytest.raises(ValueError) as exc:
            Inputs(input_range=None)._check_U(U)
        assert str(exc.value) == "sensor sequence U contains 1 non-finite value(s) (NaN or inf)"


# ------------------------------------------------------------------------------ the range
def test_readings_exactly_on_the_range_bounds_pass():
    U = np.array([[-2.0, 3.0, 0.0]])
    assert Inputs(input_range=(-2.0, 3.0))._check_U(U, fitting=True).tolist() == U.tolist()
    assert Inputs(input_range=(-2.0, 3.0))._check_U(U).tolist() == U.tolist()
    # no range: any finite reading
    big = np.array([[-1e9, 1e9, 0.0]])
    assert Inputs(input_range=None)._check_U(big, fitting=True).tolist() == big.tolist()
    # an empty recording has no reading outside any range
    assert Inputs()._check_U(np.zeros((0, 3))).shape == (0, 3)


def test_a_fit_refuses_readings_one_step_past_either_bound():
    low = np.array([[np.nextafter(0.0, -1.0), 0.5, 0.5]])
    high = np.array([[0.5, np.nextafter(1.0, 2.0), 0.5]])
    for U, lo, hi in ((low, f"{low.min():g}", "0.5"), (high, "0.5", f"{high.max():g}")):
        with pytest.raises(ValueError) as exc:
            Inputs()._check_U(U, fitting=True)
        assert str(exc.value) == (f"sensor sequence U holds readings outside input_range [0, 1] "
                                  f"(min {lo}, max {hi})" + FIT_HINT)
    with pytest.raises(ValueError) as exc:
        Inputs(input_range=(-2.5, 0.5), out_of_range="clip")._check_U(
            np.array([[-3.0, 0.0, 4.0]]), fitting=True)
    assert str(exc.value) == ("sensor sequence U holds readings outside input_range [-2.5, 0.5] "
                              "(min -3, max 4)" + FIT_HINT)


def test_out_of_range_error_refuses_with_its_hint():
    U = np.array([[-0.5, 0.5, 1.5]])
    with pytest.raises(ValueError) as exc:
        Inputs()._check_U(U)
    assert str(exc.value) == ("sensor sequence U holds readings outside input_range [0, 1] "
                              "(min -0.5, max 1.5)" + ERROR_HINT)
    with pytest.raises(ValueError) as exc:
        Inputs()._out_of_range(np.array([2.0]), "u is off")
    assert str(exc.value) == "u is off" + ERROR_HINT


def test_out_of_range_warn_clips_and_warns_word_for_word():
    U = np.array([[-0.5, 0.5, 1.5], [0.25, 2.0, 0.0]])
    with pytest.warns(InputRangeWarning) as rec:
        out = Inputs(out_of_range="warn")._check_U(U)
    assert out.tolist() == [[0.0, 0.5, 1.0], [0.25, 1.0, 0.0]]
    assert len(rec) == 1
    assert str(rec[0].message) == ("sensor sequence U holds readings outside input_range [0, 1] "
                                   "(min -0.5, max 2); clipped to the range")
    assert issubclass(InputRangeWarning, RuntimeWarning)


def test_the_warning_names_the_callers_line():
    # step's caller (two frames up from the policy) and transform's, features' or a leak
    # sweep's (three up, through the recording's check); not measurable under mutmut, whose
    # trampolines add frames
    def step_like(inputs: Inputs, u: np.ndarray) -> np.ndarray:
        return inputs._out_of_range(u, "u is off")

    def transform_like(inputs: Inputs, U: np.ndarray) -> np.ndarray:
        return inputs._check_U(U)

    inputs = Inputs(out_of_range="warn")
    with pytest.warns(InputRangeWarning) as rec:
        step_like(inputs, np.array([2.0, 0.0, 0.0]))
        transform_like(inputs, np.array([[2.0, 0.0, 0.0]]))
    assert str(rec[0].message) == "u is off; clipped to the range"
    if "MUTANT_UNDER_TEST" not in os.environ:
        assert [r.filename for r in rec] == [__file__, __file__]
        assert rec[0].lineno == rec[1].lineno - 1


def test_out_of_range_clip_clips_silently_to_the_range():
    U = np.array([[-4.0, 0.5, 7.0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = Inputs(out_of_range="clip", input_range=(-1.0, 2.0))._check_U(U)
        assert out.tolist() == [[-1.0, 0.5, 2.0]]
        one = Inputs(out_of_range="clip", input_range=(-1.0, 2.0))._out_of_range(
            np.array([3.0, -3.0, 0.0]), "ignored")
    assert one.tolist() == [2.0, -1.0, 0.0]


# ---------------------------------------------------------------------- what a fit needs
def _varied(T: int) -> np.ndarray:
    U = np.zeros((T, 3))
    U[:, 0] = np.linspace(0.0, 1.0, T) if T > 1 else 0.0
    U[0, 1] = 0.5   # a second sensor varies once
    return U


def _too_short(T: int, n: int, washout: int, ds: int, need: int) -> str:
    return (f"U has {T} ticks ({n} reservoir updates after a washout of {washout} and "
            f"down-sampling by {ds}); fitting needs at least min_fit_ticks={need} updates of "
            "exploration")


def test_the_fit_length_exactly_at_min_fit_ticks_and_one_tick_short():
    Inputs(min_fit_ticks=10)._check_trainable(_varied(10))
    with pytest.raises(ValueError) as exc:
        Inputs(min_fit_ticks=10)._check_trainable(_varied(9))
    assert str(exc.value) == _too_short(9, 9, 0, 1, 10)
    # the default is 100 updates
    Inputs()._check_trainable(_varied(100))
    with pytest.raises(ValueError) as exc:
        Inputs()._check_trainable(_varied(99))
    assert str(exc.value) == _too_short(99, 99, 0, 1, 100)


def test_the_washout_is_taken_off_the_updates():
    Inputs(min_fit_ticks=10, washout=5)._check_trainable(_varied(15))
    with pytest.raises(ValueError) as exc:
        Inputs(min_fit_ticks=10, washout=5)._check_trainable(_varied(14))
    assert str(exc.value) == _too_short(14, 9, 5, 1, 10)


def test_down_sampled_updates_are_the_whole_blocks_of_ticks():
    # the decimator updates at ticks 2, 5, 8, ...: T // 3 updates; 30 ticks give 10, 29 and 28
    # give 9 (a partial last block gives no update; ceil(28 / 3) = 10 was counted, and the fit
    # went on with 9)
    Inputs(min_fit_ticks=10, downsample=3)._check_trainable(_varied(30))
    for T in (29, 28):
        with pytest.raises(ValueError) as exc:
            Inputs(min_fit_ticks=10, downsample=3)._check_trainable(_varied(T))
        assert str(exc.value) == _too_short(T, 9, 0, 3, 10)
    # with a washout of 2: 36 // 3 - 2 = 10, 35 // 3 - 2 = 9
    Inputs(min_fit_ticks=10, downsample=3, washout=2)._check_trainable(_varied(36))
    with pytest.raises(ValueError) as exc:
        Inputs(min_fit_ticks=10, downsample=3, washout=2)._check_trainable(_varied(35))
    assert str(exc.value) == _too_short(35, 9, 2, 3, 10)


def test_a_recording_whose_every_sensor_is_constant_is_refused():
    U = np.full((20, 3), 0.5)
    U[:, 2] = 0.25
    with pytest.raises(ValueError) as exc:
        Inputs(min_fit_ticks=10)._check_trainable(U)
    assert str(exc.value) == ("every sensor in U is constant (values [0.25, 0.5]): stuck or "
                              "disconnected sensors carry no information about place")
    # the values shown: the first tick's distinct readings, sorted, at most four
    wide = Inputs(n_inputs=6, min_fit_ticks=10)
    U6 = np.tile([0.9, 0.1, 0.7, 0.3, 0.5, 0.1], (20, 1))
    with pytest.raises(ValueError) as exc:
        wide._check_trainable(U6)
    assert "(values [0.1, 0.3, 0.5, 0.7]):" in str(exc.value)


def test_a_spread_of_exactly_1e_9_is_constant_and_2e_9_is_not():
    U = np.zeros((20, 3))
    U[0, 1] = 1e-9
    with pytest.raises(ValueError) as exc:
        Inputs(min_fit_ticks=10)._check_trainable(U)
    # the values shown are the first tick's
    assert str(exc.value).startswith("every sensor in U is constant (values [0.0, 1e-09]):")
    U[0, 1] = 2e-9
    Inputs(min_fit_ticks=10)._check_trainable(U)
    # one varying sensor among constant ones is enough, wherever it is
    for j in range(3):
        V = np.full((20, 3), 0.5)
        V[7, j] = 0.75
        Inputs(min_fit_ticks=10)._check_trainable(V)


def test_teach_patrols_check_counts_the_updates_as_the_fit_does(monkeypatch):
    # the lesson refuses an exploration too short for the fit before any work: with
    # down-sampling by 3, a washout of 2 and min_fit_ticks 10 that is (10 + 2) * 3 = 36 ticks
    import hippo.tasks.lesson as lesson
    from hippo.perception.place_cells import RCSFAICA

    kw = dict(min_fit_ticks=10, downsample=3, washout=2)
    monkeypatch.setattr(lesson, "place_model", lambda units: RCSFAICA(**kw))
    lesson._check_learned(4, 36 * 0.2 / 60, 0.2, False)
    with pytest.raises(ValueError) as exc:
        lesson._check_learned(4, 35 * 0.2 / 60, 0.2, False)
    assert "gives 35 ticks of exploration; the place cells' fit needs at least 36 (7.2 s)" in str(
        exc.value)
    Inputs(n_inputs=8, n_reservoir=600, **kw)._check_trainable(np.tile(_varied(36), (1, 3))[:, :8])
    with pytest.raises(ValueError, match=r"^U has 35 ticks"):
        Inputs(n_inputs=8, n_reservoir=600, **kw)._check_trainable(
            np.tile(_varied(35), (1, 3))[:, :8])
