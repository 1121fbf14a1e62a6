"""The state layer's ids and keys: what it refuses, with the exact reason."""

from __future__ import annotations

import numpy as np
import pytest

from hippo.perception.states import StateLayer


def test_place_count_and_state_ids_are_checked():
    for bad in (2.5, -1):
        with pytest.raises(ValueError) as err:
            StateLayer(n_place=bad)
        assert str(err.value) == f"n_place must be an integer >= 0, got {bad!r}"
    layer = StateLayer(n_place=3)
    n = len(layer._keys)
    assert layer.key(np.int64(1)).kind == "place" and layer.key(1).index == 1
    for bad in (True, "1", 1.0):
        with pytest.raises(ValueError) as err:
            layer.key(bad)
        assert str(err.value) == f"state id must be an integer, got {bad!r}"
    for bad in (n, -1):                       # one past the last id, and negative
        with pytest.raises(ValueError, match="state"):
            layer.key(bad)


def test_recruited_keys_are_checked_with_the_reason():
    layer = StateLayer(n_place=2)
    for bad in (-1, True, 1.5, None):
        with pytest.raises(ValueError) as err:
            layer.recruit("colour", bad)
        assert str(err.value) == f"a colour state needs an integer index >= 0, got {bad!r}"
    with pytest.raises(ValueError) as err:
        layer.recruit("sound", 3)
    assert str(err.value) == "a sound state takes no index, got 3"
    assert layer.recruit("colour", np.int64(2)) == layer.find("colour", 2)
