"""The tutorials in docs/tutorials run as written (in a quick form: each line ending in
``# quick: VALUE`` takes VALUE instead)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

TUTORIALS = Path(__file__).resolve().parents[1] / "docs" / "tutorials"
_QUICK = re.compile(r"^(?P<lhs>\s*[A-Za-z_]\w*\s*=\s*)(?P<rhs>.+?)\s*#\s*quick:\s*(?P<q>.+)$")


def python_blocks(text: str) -> list[str]:
    """The ```python fenced blocks of a Markdown page, in order."""
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)


def quick(code: str) -> str:
    """Replace the right-hand side of ``NAME = value  # quick: other`` lines by ``other``."""
    return "\n".join(
        f"{m['lhs']}{m['q']}" if (m := _QUICK.match(line)) else line for line in code.splitlines())


def test_quick_substitution():
    assert quick("TICKS = 18_000  # quick: 600\nx = 1") == "TICKS = 600\nx = 1"
    assert python_blocks("a\n```python\nx = 1\n```\n```bash\nls\n```\n") == ["x = 1\n"]


@pytest.mark.parametrize("page", sorted(p.name for p in TUTORIALS.glob("*.md")))
def test_tutorial_runs(page, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # files the tutorial writes land in a temporary folder
    blocks = python_blocks((TUTORIALS / page).read_text())
    assert blocks, f"{page} has no python code"
    namespace: dict = {"__name__": "__tutorial__"}
    for k, block in enumerate(blocks):
        exec(compile(quick(block), f"{page}[block {k}]", "exec"), namespace)
