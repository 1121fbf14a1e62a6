"""The user examples in ``scenarios/`` (scripts on the public API), loaded as modules."""

import importlib.util
from pathlib import Path
from types import ModuleType

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def load_example(name: str) -> ModuleType:
    """``scenarios/<name>.py`` as a module (its ``main`` is not run)."""
    spec = importlib.util.spec_from_file_location(name, SCENARIOS / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod
