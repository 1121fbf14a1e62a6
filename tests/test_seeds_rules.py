"""The run's named random streams (hippo/seeds.py): each name's key written out by hand (the
keys are fixed: a changed key changes every run that draws from it), every stream rebuilt
directly as ``default_rng(SeedSequence([seed, key], spawn_key=sub))``, and the refusals word
for word."""

from __future__ import annotations

import re

import numpy as np
import pytest

from hippo.seeds import STREAMS, Seeds

#: the keys hippo's scenarios have always used (hippo/seeds.py's docstring: 1-9 the old ones)
KEYS = {"recording": 1, "exploration": 3, "pauses": 4, "brain": 7, "motor-explore": 8,
        "motor-steer": 9, "fault-sets": 11, "sensor-faults": 13, "kidnaps": 23,
        "timing-trials": 29, "timing-pipeline": 31}


def refused(message: str):
    return pytest.raises(ValueError, match="^" + re.escape(message) + "$")


def test_every_stream_keeps_its_key():
    assert STREAMS == KEYS
    assert list(STREAMS) == list(KEYS)   # the order the unknown-name message lists


@pytest.mark.parametrize("seed", [0, 1, 12345, 2**63])
def test_each_stream_is_the_seed_sequence_of_the_seed_and_its_key(seed):
    s = Seeds(seed)
    assert s.seed == seed and type(s.seed) is int and s.world == seed
    for name, key in KEYS.items():
        q = s.sequence(name)
        assert q.entropy == [seed, key] and q.spawn_key == ()
        want = np.random.default_rng(np.random.SeedSequence([seed, key])).random(3)
        np.testing.assert_array_equal(s.generator(name).random(3), want)
        # the same numbers on every call: a fresh generator each time
        np.testing.assert_array_equal(s.generator(name).random(3), want)


def test_sub_streams_are_the_children_spawn_makes():
    s = Seeds(3)
    for sub in ((0,), (1,), (2, 5), (np.int64(4),)):
        q = s.sequence("sensor-faults", *sub)
        assert q.entropy == [3, 13] and q.spawn_key == tuple(int(i) for i in sub)
        assert all(type(i) is int for i in q.spawn_key)
        want = np.random.SeedSequence([3, 13], spawn_key=tuple(int(i) for i in sub))
        np.testing.assert_array_equal(s.generator("sensor-faults", *sub).random(3),
                                      np.random.default_rng(want).random(3))
    # sub-stream 1 is the second child of spawn(), and sub-stream 0 is not the stream itself
    child = np.random.SeedSequence([3, 13]).spawn(2)[1]
    np.testing.assert_array_equal(s.generator("sensor-faults", 1).random(3),
                                  np.random.default_rng(child).random(3))
    assert (s.generator("sensor-faults", 0).random() != s.generator("sensor-faults").random())


def test_a_seed_is_an_integer_at_least_0():
    for ok in (0, np.int64(9), np.uint32(2)):
        assert Seeds(ok).seed == int(ok) and type(Seeds(ok).seed) is int
    for bad in (-1, np.int64(-1), True, np.bool_(True), 1.0, "1", None):
        with refused(f"seed must be an integer >= 0, got {bad!r}"):
            Seeds(bad)   # type: ignore[arg-type]


def test_an_unknown_stream_and_bad_sub_streams_are_refused_word_for_word():
    s = Seeds(0)
    names = ("recording, exploration, pauses, brain, motor-explore, motor-steer, fault-sets, "
             "sensor-faults, kidnaps, timing-trials, timing-pipeline")
    with pytest.raises(KeyError) as e:
        s.sequence("teacher")
    assert e.value.args[0] == (f"unknown random stream 'teacher'; known: {names} (a new "
                               "consumer adds its name and key to hippo.seeds.STREAMS)")
    with pytest.raises(KeyError, match="unknown random stream 'Brain'"):
        s.generator("Brain")
    with refused("sub-stream indices must be integers >= 0, got [-1]"):
        s.sequence("kidnaps", -1)
    with refused("sub-stream indices must be integers >= 0, got [True, 1.5, -2]"):
        s.sequence("kidnaps", 0, True, 1.5, 2, -2)
    with refused("sub-stream indices must be integers >= 0, got ['1']"):
        s.generator("kidnaps", "1")   # type: ignore[arg-type]
    with refused("sub-stream indices must be integers >= 0, got [np.False_]"):
        s.sequence("kidnaps", np.bool_(False))   # type: ignore[arg-type]
