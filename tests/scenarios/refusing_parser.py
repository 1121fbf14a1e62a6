"""A parser whose ``error`` raises instead of exiting, for the scenario rules tests: a refusal
is read back as the exception's message, word for word."""

from __future__ import annotations

import argparse


class Refused(Exception):
    """What :class:`RefusingParser` raises where argparse would print and exit."""


class RefusingParser(argparse.ArgumentParser):
    def error(self, message: str) -> None:   # type: ignore[override]
        raise Refused(message)
