"""Stand-ins shared by the scenario rules tests: a parser whose ``error`` raises instead of
exiting (a refusal is read back as the exception's message, word for word), and a progress bar
that records what it was asked to show."""

from __future__ import annotations

import argparse
from typing import Any


class Refused(Exception):
    """What :class:`RefusingParser` raises where argparse would print and exit."""


class RefusingParser(argparse.ArgumentParser):
    def error(self, message: str) -> None:   # type: ignore[override]
        raise Refused(message)


def recording_progress(seen: dict[str, Any]) -> type:
    """A ``hippo.progress.Progress`` stand-in: ``seen["progress"]`` becomes ``[total, desc]``
    when one is made, then each ``update``'s step is appended."""

    class _Progress:
        def __init__(self, total: int, desc: str) -> None:
            seen["progress"] = [total, desc]

        def __enter__(self) -> _Progress:
            return self

        def __exit__(self, *exc: Any) -> None:
            pass

        def update(self, n: int = 1) -> None:
            seen["progress"].append(n)

    return _Progress
