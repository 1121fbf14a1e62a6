"""The state layer's vocabulary by hand (hippo.perception.state_params): the event inputs'
checks (a flag is True, False, None or a number 0 or 1; a colour an integer >= 0, 0 and None
the plain floor) on each edge and one step past, every refusal word for word, the text,
arrays and bools refused (a string "1" or "0" and a list [1] passed for a flag or colour
before: float() read them), the layer's step refusing them under the input's name, the
parameters' refusals word for word and their documented defaults, a state key's defaults and
the event's fields."""

from __future__ import annotations

import re
from dataclasses import FrozenInstanceError

import numpy as np
import pytest

from hippo.perception.state_params import (
    EVENT_KINDS,
    StateEvent,
    StateKey,
    StateLayerParams,
    _colour,
    _flag,
)
from hippo.perception.states import StateLayer


def refused(message: str):
    return pytest.raises(ValueError, match="^" + re.escape(message) + "$")


# ---------------------------------------------------------------------------- flags
@pytest.mark.parametrize("value", [None, True, False])
def test_none_and_the_two_bools_are_themselves(value):
    assert _flag("f", value) is value


@pytest.mark.parametrize("value, want", [(np.bool_(True), True), (np.bool_(False), False),
                                         (1, True), (0, False), (1.0, True), (0.0, False),
                                         (-0.0, False), (np.float64(1.0), True),
                                         (np.int8(0), False), (np.array(1.0), True)])
def test_numpy_bools_and_the_numbers_0_and_1_are_bools(value, want):
    got = _flag("f", value)
    assert got is want


@pytest.mark.parametrize("value", [2, -1, 0.5, 1.0000000000000002, 5e-324, 2.0])
def test_other_numbers_are_refused_word_for_word(value):
    with refused(f"moving must be a boolean (or 0/1), got {value!r}"):
        _flag("moving", value)


@pytest.mark.parametrize("value", ["1", "0", "True", b"1", [1], (0,), np.array([1.0]),
                                   [[0]], np.zeros((0,))])
def test_text_and_arrays_are_no_flags(value):
    with refused(f"sound must be a boolean (or 0/1), got {value!r}"):
        _flag("sound", value)


def test_a_non_finite_flag_is_refused_by_name():
    with refused("sound contains 1 non-finite value(s) (NaN or inf)"):
        _flag("sound", float("nan"))


# ---------------------------------------------------------------------------- colours
@pytest.mark.parametrize("value", [None, 0, 0.0, -0.0, np.int64(0), np.uint8(0)])
def test_none_and_zero_are_the_plain_floor(value):
    assert _colour(value) is None


@pytest.mark.parametrize("value, want", [(1, 1), (7, 7), (np.int64(3), 3), (2.0, 2),
                                         (np.float32(1.0), 1), (np.array(4), 4)])
def test_integral_colours_are_ints(value, want):
    got = _colour(value)
    assert got == want and type(got) is int


@pytest.mark.parametrize("value", [-1, np.int64(-1), -1.0, 0.5, 2.5, 1 + 2**-52, -5e-324])
def test_negative_or_fractional_colours_are_refused_word_for_word(value):
    with refused(f"colour must be an integer colour id >= 0, got {value!r}"):
        _colour(value)


@pytest.mark.parametrize("value", [True, False, np.bool_(True), "2", b"1", [2], (1,),
                                   np.array([3])])
def test_bools_text_and_arrays_are_no_colours(value):
    with refused(f"colour must be an integer colour id, got {value!r}"):
        _colour(value)


def test_an_infinite_colour_is_refused_by_name():
    with refused("colour contains 1 non-finite value(s) (NaN or inf)"):
        _colour(float("inf"))


def test_the_layer_refuses_text_for_its_event_inputs():
    layer = StateLayer(StateLayerParams(smoothing=0.0))
    with refused("sound must be a boolean (or 0/1), got '0'"):
        layer.step(None, sound="0", dt=0.2)
    with refused("moving must be a boolean (or 0/1), got [1]"):
        layer.step(None, moving=[1], dt=0.2)
    with refused("colour must be an integer colour id, got '1'"):
        layer.step(None, colour="1", dt=0.2)
    # nothing was stepped: the first good tick is the layer's first
    assert layer.step(None, sound=1, dt=0.2).t == 0.0


# ---------------------------------------------------------------------------- parameters
def test_the_documented_defaults():
    p = StateLayerParams()
    assert (p.margin, p.hold_time, p.normalize, p.place_scale) == (0.15, 0.6, "pooled", 2.0)
    assert (p.norm_tau, p.smoothing, p.recruit_threshold) == (300.0, 0.4, 0.3)
    assert p.events == p.priority == EVENT_KINDS == ("sound", "colour", "still", "moving")
    assert (p.conjunctive, p.transient, p.transient_time) == (("still", "moving"),
                                                              ("moving",), 1.0)
    assert (p.context_time, p.contexts) == (0.0, None)
    # hold_time "0.6 s = 3 ticks at dt = 0.2 s"
    assert p.hold_time == pytest.approx(3 * 0.2)
    with pytest.raises(FrozenInstanceError):
        p.margin = 0.2  # type: ignore[misc]


@pytest.mark.parametrize("priority", [("sound", "colour", "still"),
                                      ("sound", "colour", "still", "still"),
                                      ("sound", "colour", "still", "moving", "moving"), ()])
def test_the_priority_must_order_every_event_kind_once(priority):
    with refused(f"priority must order all of {EVENT_KINDS}, got {priority}"):
        StateLayerParams(priority=priority)


def test_any_order_of_the_four_kinds_is_a_priority():
    order = ("moving", "still", "colour", "sound")
    assert StateLayerParams(priority=order).priority == order


@pytest.mark.parametrize("name", ["events", "conjunctive", "transient"])
def test_unknown_event_kinds_are_listed_word_for_word(name):
    with refused(f"{name} lists unknown event kind(s) ['place', 'x']; choose from "
                 f"{EVENT_KINDS}"):
        StateLayerParams(**{name: ("sound", "place", "x")})
    assert getattr(StateLayerParams(**{name: ()}), name) == ()


@pytest.mark.parametrize("value", ["Pooled", "none", ""])
def test_normalize_is_one_of_three_words(value):
    with refused(f"normalize must be 'pooled', 'unit' or 'fixed', got {value!r}"):
        StateLayerParams(normalize=value)


def test_range_refusals_name_their_field():
    with refused("margin must lie in [0.0, 1.0], got 1.0000000000000002"):
        StateLayerParams(margin=1 + 2**-52)
    with refused("recruit_threshold must lie in [0.0, 1.0], got -5e-324"):
        StateLayerParams(recruit_threshold=-5e-324)
    with refused("transient_time must be finite and > 0, got 0.0"):
        StateLayerParams(transient_time=0.0)
    with refused("context_time must be finite and >= 0, got -5e-324"):
        StateLayerParams(context_time=-5e-324)
    assert StateLayerParams(margin=1.0, recruit_threshold=0.0, hold_time=0.0, smoothing=0.0,
                            context_time=0.0).margin == 1.0


# ---------------------------------------------------------------------------- keys, events
def test_a_key_defaults_to_no_index_and_no_context():
    assert StateKey("sound") == ("sound", None, None)
    assert StateKey("place", 3) == ("place", 3, None)
    k = StateKey("still", None, 4)
    assert (k.kind, k.index, k.context) == ("still", None, 4)


def test_an_event_holds_its_six_fields_and_is_frozen():
    e = StateEvent(1.5, 3, True, 2, 1.25, False)
    assert (e.t, e.winner, e.changed, e.previous, e.since, e.novel) == (1.5, 3, True, 2, 1.25,
                                                                        False)
    assert e == StateEvent(1.5, 3, True, 2, 1.25, False)
    assert e != StateEvent(1.5, 3, True, None, 1.25, False)
    with pytest.raises(FrozenInstanceError):
        e.winner = 4  # type: ignore[misc]
