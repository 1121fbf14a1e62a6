"""The package's shape: no import cycles, nothing imports a scenario, files stay small."""

from __future__ import annotations

import ast
from pathlib import Path

import networkx as nx

ROOT = Path(__file__).resolve().parents[1] / "hippo"


def _module(path: Path) -> str:
    parts = path.relative_to(ROOT.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(tree: ast.AST, known: set[str]) -> set[str]:
    """hippo modules imported anywhere in ``tree`` (also inside functions and under ``if
    TYPE_CHECKING:``: a type-only arrow is an arrow of the design too); ``from pkg import
    name`` counts as importing ``pkg.name`` when that is a module, else ``pkg``."""
    out: set[str] = set()

    def visit(node: ast.AST) -> None:
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names if a.name.startswith("hippo"))
        elif isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("hippo"):
            for a in node.names:
                sub = f"{node.module}.{a.name}"
                out.add(sub if sub in known else node.module)
        for child in ast.iter_child_nodes(node):
            visit(child)

    visit(tree)
    return out


def _graph() -> nx.DiGraph:
    files = {_module(p): p for p in ROOT.rglob("*.py")}
    g = nx.DiGraph()
    for mod, path in files.items():
        g.add_node(mod)
        for dep in _imports(ast.parse(path.read_text()), set(files)):
            # a package's __init__ re-exporting its modules is not an arrow back to it
            if dep != mod and not (mod.startswith(dep + ".") and dep in files):
                g.add_edge(mod, dep)
    return g


def test_no_import_cycles():
    cycles = list(nx.simple_cycles(_graph()))
    assert cycles == [], f"import cycles: {cycles}"


def test_nothing_imports_a_scenario_but_the_command_line():
    g = _graph()
    users = {m for m, d in g.edges if d.startswith("hippo.scenarios")
             and not m.startswith("hippo.scenarios")}
    assert users <= {"hippo.cli"}, users
    within = {(m, d) for m, d in g.edges if m.startswith("hippo.scenarios.")
              and d.startswith("hippo.scenarios.")
              and not d.rsplit(".", 1)[1].startswith("_")}  # private helpers are not scenarios
    assert within == set(), f"scenarios importing each other: {within}"


def test_the_low_layers_do_not_know_the_loop():
    """sim, perception, timing and cognitive_map never import the brain, the agent or tasks."""
    g = _graph()
    top = ("hippo.brain", "hippo.agent", "hippo.decision", "hippo.motor", "hippo.tasks",
           "hippo.places")
    low = [m for m in g if m.split(".")[1:2] and m.split(".")[1] in
           ("sim", "perception", "timing", "cognitive_map", "types")]
    bad = [(m, d) for m in low for d in g.successors(m) if d.startswith(top)]
    assert bad == []


def test_the_agent_stays_small():
    assert len((ROOT / "agent.py").read_text().splitlines()) <= 300


#: issue 13's "no file over ~400 lines": a file that grows past this is split, one idea each
MAX_LINES = 400


def test_no_module_is_over_400_lines():
    sizes = {p.relative_to(ROOT).as_posix(): len(p.read_text().splitlines())
             for p in ROOT.rglob("*.py")}
    assert len(sizes) > 50
    big = {name: n for name, n in sizes.items() if n > MAX_LINES}
    assert big == {}, f"modules over {MAX_LINES} lines (split them, one idea each): {big}"
