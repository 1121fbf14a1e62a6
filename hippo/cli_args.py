"""Command-line arguments that are checked before any work starts.

Each function here is an ``argparse`` ``type=``: it turns the text the user typed into a value
or raises :class:`argparse.ArgumentTypeError` with one line that says what was typed and what
is allowed (argparse adds the argument's name). :class:`Parser` prints that line alone (no
usage block, no traceback) and exits with status 2; :class:`HelpFormatter` shows every
option's default in ``--help``.

Example::

    parser = Parser(prog="hippo run two-rooms")
    parser.add_argument("--ticks", type=integer(100), default=18120, help="control ticks")
    parser.add_argument("--out", type=out_dir, default="out/two-rooms", help="output folder")
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any, NoReturn

#: exit status of a usage error (a bad argument) and of a failure while running
USAGE_ERROR, FAILURE = 2, 1


class Parser(argparse.ArgumentParser):
    """An ``ArgumentParser`` whose errors are one line on stderr and exit status 2."""

    def __init__(self, *args: object, **kwargs: object) -> None:
        kwargs.setdefault("formatter_class", HelpFormatter)
        super().__init__(*args, **kwargs)  # type: ignore[arg-type]

    def error(self, message: str) -> NoReturn:
        """One line (``prog: error: message (see --help)``), then exit with status 2."""
        line = " ".join(message.split())
        sys.stderr.write(f"{self.prog}: error: {line} (see {self.prog} --help)\n")
        raise SystemExit(USAGE_ERROR)


class HelpFormatter(argparse.RawDescriptionHelpFormatter):
    """Keeps the description's line breaks and shows each option's default."""

    def _get_help_string(self, action: argparse.Action) -> str:
        text = action.help or ""
        if (action.default is not argparse.SUPPRESS and action.default is not None
                and "%(default)" not in text and action.option_strings
                and not isinstance(action, (argparse._HelpAction, argparse._StoreTrueAction,
                                            argparse._StoreFalseAction))):
            text = f"{text} (default: %(default)s)" if text else "(default: %(default)s)"
        return text


def _fmt(v: float) -> str:
    return str(int(v)) if float(v).is_integer() and abs(v) < 1e15 else f"{v:g}"


def _bounds(lo: float | None, hi: float | None, *, lo_open: bool = False,
            hi_open: bool = False) -> str:
    lo_s = None if lo is None else f"{'>' if lo_open else '>='} {_fmt(lo)}"
    hi_s = None if hi is None else f"{'<' if hi_open else '<='} {_fmt(hi)}"
    if lo is not None and hi is not None:
        left, right = ("(" if lo_open else "["), (")" if hi_open else "]")
        return f"in {left}{_fmt(lo)}, {_fmt(hi)}{right}"
    return lo_s or hi_s or "any value"


def _within(v: float, lo: float | None, hi: float | None, lo_open: bool, hi_open: bool) -> bool:
    return (not (lo is not None and (v < lo or (lo_open and v == lo)))
            and not (hi is not None and (v > hi or (hi_open and v == hi))))


def integer(lo: int | None = None, hi: int | None = None) -> Callable[[str], int]:
    """An integer in ``[lo, hi]`` (either bound may be None)."""
    allowed = f"an integer {_bounds(lo, hi)}".replace("an integer any value", "an integer")

    def parse(text: str) -> int:
        try:
            v = int(text)   # int() itself takes spaces around and 1_000 (not _1, 1__0 or 1_)
        except ValueError:
            raise argparse.ArgumentTypeError(f"got {text!r}; needs {allowed}") from None
        if not _within(v, lo, hi, False, False):
            raise argparse.ArgumentTypeError(f"got {v}; needs {allowed}")
        return v

    parse.__name__ = "integer"
    return parse


def number(lo: float | None = None, hi: float | None = None, *, lo_open: bool = False,
           hi_open: bool = False, unit: str = "") -> Callable[[str], float]:
    """A finite number in ``[lo, hi]`` (``lo_open``/``hi_open`` exclude a bound)."""
    allowed = f"a number {_bounds(lo, hi, lo_open=lo_open, hi_open=hi_open)}"
    allowed = allowed.replace("a number any value", "a finite number") + (
        f" ({unit})" if unit else "")

    def parse(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"got {text!r}; needs {allowed}") from None
        if not math.isfinite(v) or not _within(v, lo, hi, lo_open, hi_open):
            raise argparse.ArgumentTypeError(f"got {text!r}; needs {allowed}")
        return v

    parse.__name__ = "number"
    return parse


def probability(text: str) -> float:
    """A probability in [0, 1]."""
    return number(0.0, 1.0)(text)


def numbers(count: int | tuple[int, int] | None = None, lo: float | None = None,
            hi: float | None = None, *, lo_open: bool = False, unit: str = ""
            ) -> Callable[[str], list[float]]:
    """``count`` numbers (or ``count[0]`` to ``count[1]``) separated by commas, in ``[lo, hi]``."""
    one = number(lo, hi, lo_open=lo_open)
    lo_n, hi_n = (count, count) if isinstance(count, int) else (count or (1, None))
    how_many = (f"{lo_n}" if lo_n == hi_n else
                f"{lo_n} or more" if hi_n is None else f"{lo_n} to {hi_n}")
    allowed = (f"{how_many} comma-separated numbers {_bounds(lo, hi, lo_open=lo_open)}"
               .replace("numbers any value", "finite numbers") + (f" ({unit})" if unit else ""))

    return _comma_list(one, allowed, "numbers",
                       lambda v: lo_n <= len(v) and (hi_n is None or len(v) <= hi_n))


def distinct_integers(lo: int | None = None, hi: int | None = None
                      ) -> Callable[[str], list[int]]:
    """One or more distinct integers separated by commas, each in ``[lo, hi]``."""
    one = integer(lo, hi)
    allowed = f"distinct comma-separated integers {_bounds(lo, hi)}"

    return _comma_list(one, allowed, "integers", lambda v: 0 < len(v) == len(set(v)))


#: the most runs one ``--seeds`` may ask for (a typo such as ``--seeds 987654`` would
#: otherwise start a run that never ends, or exhaust memory listing the seeds)
MAX_SEEDS = 1000
#: the largest seed (``--seed`` and ``--seeds`` alike)
MAX_SEED = 2**32 - 1


def plain_digits(text: str) -> bool:
    """Is ``text`` a whole number in plain ASCII digits (no sign, ``_``, spaces or other
    scripts' digits, all of which ``int()`` accepts)?"""
    return text.isascii() and text.isdigit()


def _seed(text: str) -> int:
    text = text.strip()
    if not plain_digits(text):
        raise ValueError(text)
    return int(text)


def seed_ranges(text: str) -> list[int]:
    """Explicit seeds as ranges and lists, ``100-119`` or ``0-9,15``: distinct, non-negative,
    at most :data:`MAX_SEEDS` of them (counted before any list is built). Seeds are plain ASCII
    digits: ``10_0`` or ``٣`` is refused, not read as another number. One trailing comma is
    allowed, as in every comma-separated option (``0-9,``)."""
    seeds: list[int] = []
    try:
        for part in _items(str(text), ",") or [""]:
            a, sep, b = part.strip().partition("-")
            lo = _seed(a)
            hi = _seed(b) if sep else lo
            if lo < 0 or hi < lo or hi > MAX_SEED:
                raise ValueError
            if len(seeds) + hi - lo + 1 > MAX_SEEDS:
                raise argparse.ArgumentTypeError(
                    f"{text!r} asks for more than {MAX_SEEDS} seeds; run such a grid in "
                    "parts (hippo sweep skips the cells already done)")
            seeds.extend(range(lo, hi + 1))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"seeds are integers in [0, {MAX_SEED}] in plain digits 0-9, as ranges and lists "
            f"(100-119, 0-9,15), got {text!r}") from None
    if len(set(seeds)) != len(seeds):
        raise argparse.ArgumentTypeError(f"{text!r} repeats a seed")
    return seeds


def _items(text: str, sep: str) -> list[str] | None:
    """``text`` split at ``sep`` (one trailing ``sep`` allowed); None if an item is empty
    (``'24.1,,11.6'``: a value left out is a mistake, not a shorter list)."""
    parts = text.split(sep)
    if len(parts) > 1 and not parts[-1].strip():
        parts = parts[:-1]
    return None if any(not p.strip() for p in parts) else parts


def _comma_list(one: Callable[[str], Any], allowed: str, name: str,
                ok: Callable[[list[Any]], bool]) -> Callable[[str], list[Any]]:
    """A parser of comma-separated values, each read by ``one``, the list accepted by ``ok``;
    any error says what is ``allowed``."""

    def parse(text: str) -> list[Any]:
        parts = _items(text, ",")
        try:
            values = None if parts is None else [one(p) for p in parts]
        except argparse.ArgumentTypeError:
            raise argparse.ArgumentTypeError(f"got {text!r}; needs {allowed}") from None
        if values is None or not ok(values):
            raise argparse.ArgumentTypeError(f"got {text!r}; needs {allowed}")
        return values

    parse.__name__ = name
    return parse


def points(count: tuple[int, int], unit: str = "") -> Callable[[str], list[tuple[float, float]]]:
    """Points ``'x,y;x,y;...'`` (``count[0]`` to ``count[1]`` of them), finite numbers."""
    allowed = (f"{count[0]} to {count[1]} points 'x,y' separated by ';'"
               + (f" ({unit})" if unit else ""))

    def parse(text: str) -> list[tuple[float, float]]:
        out = []
        parts = _items(text, ";")
        if parts is None:
            why = ("no points" if not text.replace(";", "").strip()
                   else "an empty point between two ';'")
            raise argparse.ArgumentTypeError(f"got {text!r} ({why}); needs {allowed}")
        for part in parts:
            xy = part.split(",")
            try:
                x, y = (float(v) for v in xy)
            except ValueError:
                raise argparse.ArgumentTypeError(f"got {text!r}; needs {allowed}") from None
            if not (math.isfinite(x) and math.isfinite(y)):
                raise argparse.ArgumentTypeError(f"got {text!r}; needs finite numbers")
            out.append((x, y))
        if not count[0] <= len(out) <= count[1]:
            raise argparse.ArgumentTypeError(f"got {text!r}; needs {allowed}")
        return out

    parse.__name__ = "points"
    return parse


def snapshot_dir(text: str) -> Path:
    """A folder written by :func:`hippo.snapshot.save_snapshot` (its manifest is there)."""
    _not_empty(text)
    path = Path(text).expanduser()
    if not path.is_dir():
        raise argparse.ArgumentTypeError(f"{text!r} is not a folder")
    if not (path / "manifest.json").is_file():
        raise argparse.ArgumentTypeError(f"{text!r} holds no saved robot (no manifest.json; "
                                         "write one with --save)")
    return path


def sfa_cutoff(text: str) -> float | str:
    """The SFA whitening cutoff: a number in (0, 1), or ``auto``."""
    if text.strip() == "auto":
        return "auto"
    try:
        return number(0.0, 1.0, lo_open=True, hi_open=True)(text)
    except argparse.ArgumentTypeError:
        raise argparse.ArgumentTypeError(f"got {text!r}; needs a number in (0, 1), such as "
                                         "1e-8, or 'auto'") from None


def slow_pool(text: str) -> float:
    """A slow pool's time constant in ticks: 0 (off) or a number >= 1."""
    from hippo.perception.slow_pool import check_slow_pool  # the command line loads lazily
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"got {text!r}; needs 0 (off) or a time constant >= 1 tick") from None
    try:
        return check_slow_pool(value)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"got {text!r}: {exc}") from None


def _first_existing(path: Path) -> Path:
    while not path.exists() and path != path.parent:
        path = path.parent
    return path


def _not_empty(text: str, what: str = "a folder ('.': the current one)") -> None:
    """``Path("")`` is the current folder: ``--out ""`` (an unset variable) wrote there."""
    if not str(text):
        raise argparse.ArgumentTypeError(f"got an empty path; name {what}")


def out_dir(text: str) -> Path:
    """An output folder (not an empty path): existing, or one that can be created; writable."""
    _not_empty(text)
    path = Path(text).expanduser()
    if path.exists() and not path.is_dir():
        raise argparse.ArgumentTypeError(f"{text!r} is a file, not a folder")
    base = _first_existing(path.absolute())
    if not base.is_dir():
        raise argparse.ArgumentTypeError(f"cannot create {text!r}: {str(base)!r} is a file")
    if not os.access(base, os.W_OK | os.X_OK):
        raise argparse.ArgumentTypeError(f"cannot write to {text!r}: {str(base)!r} is not "
                                         "writable")
    return path


def out_file(text: str) -> Path:
    """An output file (not an empty path, not a folder) in a folder that exists or can be made."""
    _not_empty(text, "a file")
    path = Path(text).expanduser()
    if path.is_dir():
        raise argparse.ArgumentTypeError(f"{text!r} is a folder, not a file")
    if path.exists() and not os.access(path, os.W_OK):
        raise argparse.ArgumentTypeError(f"cannot write to {text!r}: the file is read-only")
    out_dir(str(path.parent))   # a bare name's parent is "."
    return path


#: the place sources a closed-loop task can run on (learned is the default everywhere)
PLACE_CELLS = ("learned", "ground-truth")
#: the closed-loop tasks' bounds on their options (the command line and a saved robot's meta
#: alike): exploration in simulated minutes, ICA units, place prototypes, a taught wait in s
#: (:data:`hippo.tasks.patrol_sets.MIN_WAIT_S` to ``MAX_WAIT_S``); prototypes up to
#: ``PrototypeParams.max_prototypes`` (256)
EXPLORE_MIN, UNITS, PLACES, WAIT_S = (5.0, 600.0), (1, 200), (1, 256), (2.0, 120.0)


class Given(argparse.Action):
    """Store the value and note that it was given (``<dest>_given``), so that an option a
    loaded snapshot fixes can be refused when it differs, not overridden in silence."""

    def __call__(self, parser, namespace, values, option_string=None) -> None:
        setattr(namespace, self.dest, values)
        setattr(namespace, f"{self.dest}_given", True)


def check_loaded_options(args: argparse.Namespace, parser: argparse.ArgumentParser,
                         meta: dict, keys: tuple[str, ...]) -> None:
    """With ``--load``, an option among ``keys`` given (set away from its default, or marked
    given by its action: ``--place-cells``) and other than the snapshot's ``meta`` value is
    refused (the snapshot's value is what runs): e.g. ``--seed 9`` for a robot made with
    seed 0 ran seed 0 in silence."""
    for key in keys:
        given = getattr(args, key, None)
        was_given = getattr(args, f"{key}_given", given != parser.get_default(key))
        if key in meta and was_given and given != meta[key]:
            opt = "--" + key.replace("_", "-")
            parser.error(f"argument {opt}: the loaded robot was made with {key} {meta[key]!r}; "
                         f"leave {opt} out with --load")


def loaded_robot_meta(meta: dict, places: Any) -> dict:
    """A saved robot's ``meta`` with what its place cells say of themselves: for learned ones
    ``units`` (the ICA units fitted; patrol snapshots before 2026-11-27 wrote the prototypes'
    count there) and ``places`` (the prototypes), and for any ``reanchor`` (whether they
    re-anchor after a lift); for :func:`check_loaded_options`."""
    meta = dict(meta)
    model = getattr(places, "model", None)
    if model is not None:
        meta["units"], meta["places"] = int(model.params.n_ica), int(places.n_units)
    meta["reanchor"] = getattr(places, "relocaliser", None) is not None
    return meta


#: the options that shape only learned place cells (ground-truth cells ignore them)
LEARNED_ONLY = ("units", "places", "reanchor")


def check_ground_truth_options(args: argparse.Namespace, parser: argparse.ArgumentParser,
                               place_cells: str | None = None) -> None:
    """With ground-truth place cells (``place_cells``, default ``args.place_cells``), an option
    of :data:`LEARNED_ONLY` set away from its default is refused, naming it: ground-truth cells
    ignore it, and ``--place-cells ground-truth --units 7`` ran in silence as if it were left
    out. A parser that lacks the option (default None) checks nothing for it."""
    if (place_cells or getattr(args, "place_cells", None)) != "ground-truth":
        return
    given = [key for key in LEARNED_ONLY if hasattr(args, key)
             and parser.get_default(key) is not None
             and getattr(args, key) != parser.get_default(key)]
    if given:
        opts = ", ".join("--" + key.replace("_", "-") for key in given)
        parser.error(f"argument {opts}: only for learned place cells; leave "
                     f"{'it' if len(given) == 1 else 'them'} out with --place-cells "
                     "ground-truth")


def add_place_cells(parser: argparse.ArgumentParser, *, reanchor: bool = False) -> None:
    """``--place-cells learned|ground-truth`` and ``--[no-]reanchor`` (default ``reanchor``):
    the options every closed-loop task shares."""
    parser.add_argument("--place-cells", choices=PLACE_CELLS, default="learned", action=Given,
                        help="learned from the robot's sensors, or Gaussian fields on the true "
                             "position (to measure what learning costs)")
    parser.add_argument("--reanchor", action=argparse.BooleanOptionalAction, default=reanchor,
                        help="after a lift, jump the learned place cells' reservoir to where "
                             "the robot's next readings match its exploration; it re-localises "
                             "in seconds, but the patrol kidnap chose a high-drive checkpoint "
                             "less often")
