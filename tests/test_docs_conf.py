"""The docs' reading of hippo's informal ``name: text`` parameter lists (docs/conf.py)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

CONF = Path(__file__).resolve().parents[1] / "docs" / "conf.py"


@pytest.fixture(scope="module")
def fields():
    spec = importlib.util.spec_from_file_location("hippo_docs_conf", CONF)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod._fields


def test_items_become_a_definition_list(fields):
    doc = ["Parameters.", "", "w: weight per hop.", "noise: std of the noise,",
           "       relative to the best.", "After the list."]
    assert fields(doc) == ["Parameters.", "", "``w``", "    weight per hop.", "``noise``",
                           "    std of the noise,", "    relative to the best.", "",
                           "After the list."]


def test_literal_blocks_and_prose_are_left_alone(fields):
    doc = ["Example::", "", "    x: 1", "    y: 2", "", "A sentence with a colon: here."]
    assert fields(doc)[:5] == doc[:5]
    prose = ["Some text", "name: not an item (no blank line before it)"]
    assert fields(prose) == prose
