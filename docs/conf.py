"""Sphinx configuration: API reference from the docstrings (autodoc + napoleon), tutorials in
Markdown (MyST). Build with ``sphinx-build -W --keep-going -b html docs docs/_build/html``."""

from __future__ import annotations

import os
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # the docs describe the working tree, installed or not
os.environ.setdefault("HIPPO_QUIET", "1")
os.environ.setdefault("MPLBACKEND", "Agg")

import hippo  # noqa: E402

project = "hippo"
author = "the hippo developers"
copyright = "2026, the hippo developers"
release = version = hippo.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "myst_parser",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "**/*.png"]
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3

autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {"members": True, "show-inheritance": True, "ignore-module-all": True,
                           "member-order": "bysource"}
autodoc_typehints = "description"
autodoc_class_signature = "separated"
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_rtype = False
napoleon_use_ivar = True  # "Attributes" as fields: no second description of a property

html_theme = "furo"
html_title = f"hippo {release}"


# -- hippo's informal parameter lists --------------------------------------------------------
# Many docstrings (parameter dataclasses above all) list fields as ``name: text`` lines whose
# text continues on indented lines, or as a table of ````name````  text. Read as reST, that is
# a paragraph followed by an unexpected indent. This turns each such item into an entry of a
# definition list (the name as code, the text indented below it), which is what the author
# meant, leaving literal blocks and directives alone.
_ITEM = re.compile(r"^(?P<ind>\s*)(?P<name>[A-Za-z_]\w*(?:, [A-Za-z_]\w*)*):\s+(?P<text>\S.*)$")
_CODE_ITEM = re.compile(r"^(?P<ind>\s*)(?P<name>``[^`]+``)\s{2,}(?P<text>\S.*)$")


def _indent(line: str) -> int:
    return len(line) - len(line.lstrip())


def _fields(lines: list[str]) -> list[str]:
    out: list[str] = []
    literal_indent: int | None = None  # inside a literal block or directive body
    item_indent: int | None = None     # inside a list of converted items
    prev_blank = True
    for line in lines:
        blank = not line.strip()
        if literal_indent is not None:
            if blank or _indent(line) > literal_indent:
                out.append(line)
                prev_blank = blank
                continue
            literal_indent = None
        if item_indent is not None and not blank and _indent(line) > item_indent:
            out.append(" " * (item_indent + 4) + line.strip())  # continuation of the item
            continue
        m = None if blank else (_ITEM.match(line) or _CODE_ITEM.match(line))
        if m and (prev_blank or item_indent == len(m["ind"])):
            ind, name = m["ind"], m["name"]
            term = name if name.startswith("``") else f"``{name}``"
            out.extend([f"{ind}{term}", f"{ind}    {m['text']}"])
            item_indent = len(ind)
            prev_blank = False
            continue
        if item_indent is not None and not blank:
            out.append("")  # the list ends: a blank line before what follows
        item_indent = None
        out.append(line)
        if not blank and (line.rstrip().endswith("::") or line.lstrip().startswith(".. ")):
            literal_indent = _indent(line)
        prev_blank = blank
    return out


def _process_docstring(app, what, name, obj, options, lines):
    lines[:] = _fields(lines)


def setup(app):
    app.connect("autodoc-process-docstring", _process_docstring)
