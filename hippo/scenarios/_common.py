"""Helpers every scenario uses: the output folder and the metrics file."""

from __future__ import annotations

import argparse
import math
import sys
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from hippo._checks import check_path
from hippo.cli_args import MAX_SEEDS, numbers, out_dir, plain_digits, seed_ranges
from hippo.io import CorruptFileError, clean_stale_temps, save_json
from hippo.sim.record import Recording


def prepare_out(out: str | Path) -> Path:
    """Create the output folder and return it as a Path; temporary files that a run killed
    mid-write left in it are removed (:func:`hippo.io.clean_stale_temps`), and so is an earlier
    run's ``metrics.json``: a run that fails leaves none, not another run's."""
    path = check_path("out", out)
    path.mkdir(parents=True, exist_ok=True)
    clean_stale_temps(path)
    (path / "metrics.json").unlink(missing_ok=True)
    _BEFORE[path.resolve()] = _files(path)
    return path


#: the files each output folder held when :func:`prepare_out` prepared it, so that the
#: closing line names only what the run wrote (not a figure an earlier run left)
_BEFORE: dict[Path, dict[str, tuple[int, int, int]]] = {}


def _files(path: Path) -> dict[str, tuple[int, int, int]]:
    """The files directly in ``path``, each with its inode, modification time and size."""
    out = {}
    for p in path.iterdir():
        if p.is_file():
            st = p.stat()
            out[p.name] = (st.st_ino, st.st_mtime_ns, st.st_size)
    return out


def written_files(out: str | Path) -> str:
    """What the run wrote into ``out`` since :func:`prepare_out` (every file there if it was
    not prepared so): ``metrics.json``, the other files by name, the PNGs counted as figures."""
    path = Path(out)
    before = _BEFORE.get(path.resolve(), {})
    new = sorted(n for n, v in _files(path).items() if before.get(n) != v)
    names = ["metrics.json"] + [n for n in new if n != "metrics.json" and not n.endswith(".png")]
    figures = sum(n.endswith(".png") for n in new)
    if figures:
        names.append(f"{figures} figure{'s' if figures > 1 else ''}")
    return ", ".join(names)


def write_metrics(out: Path, metrics: dict[str, Any], *, announce: bool = True,
                  summary: str | None = None) -> Path:
    """Write ``out/metrics.json`` atomically and tell the user where the results are (and,
    with ``summary``, the headline numbers)."""
    path = save_json(Path(out) / "metrics.json", metrics)
    if announce:
        if summary:
            print(summary, file=sys.stderr)
        if metrics.get("quick"):
            print("--quick: a smoke test with shortened settings; its numbers are not results",
                  file=sys.stderr)
        print(f"results written to {Path(out).resolve()} ({written_files(out)})",
              file=sys.stderr)
    return path


def smoke_test(args: argparse.Namespace, loaded: dict | None = None) -> bool:
    """Whether a run is a smoke test: ``--quick``, or a robot loaded with ``--load`` (``loaded``,
    default ``args.loaded``) that was taught with ``--quick``, as its snapshot's meta records:
    a robot taught briefly stays a smoke test when loaded without ``--quick``."""
    if loaded is None:
        loaded = getattr(args, "loaded", None)
    meta = (loaded or {}).get("meta") or {}
    return bool(getattr(args, "quick", False)) or bool(meta.get("quick"))


def sfa_cutoff(text: str) -> float | str:
    """Parse ``--sfa-cutoff``: a number, or ``auto``."""
    return text if text == "auto" else float(text)


def check_leak_groups(args: argparse.Namespace, parser: argparse.ArgumentParser) -> None:
    """``--neurons`` must hold one group of neurons per ``--leak`` rate."""
    if args.neurons < len(args.leak):
        parser.error(f"argument --neurons: {args.neurons} neuron(s) cannot hold the "
                     f"{len(args.leak)} groups of --leak (one group of neurons per leak rate)")


def check_sfa_inputs(parser: argparse.ArgumentParser, option: str, k: int, neurons: int,
                     slow_pool: float = 0.0, what: str = "") -> None:
    """``k`` SFA units (``option``, ``what`` says where ``k`` came from) need as many SFA
    inputs: the reservoir's ``neurons`` and the 8 sensors, twice that with a slow pool
    (:mod:`hippo.perception.slow_pool` appends its running mean); refused before any work."""
    n_in = (int(neurons) + 8) * (2 if slow_pool else 1)
    if k > n_in:
        parser.error(f"argument {option}: {k}{what} exceeds the {n_in} inputs of SFA "
                     f"({neurons} neurons + 8 sensors"
                     + (", twice that with the slow pool" if slow_pool else "") + ")")


def mean_sd(values: list[float]) -> tuple[float, float]:
    """Mean and sample sd over seeds of the finite values (sd 0 for one value, nan for none)."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return math.nan, math.nan
    return float(v.mean()), float(v.std(ddof=1)) if v.size > 1 else 0.0


#: the project's evaluation convention: settings are chosen on TUNING_SEEDS only, headline
#: figures are reported on HELD_OUT_SEEDS (never looked at while choosing)
TUNING_SEEDS = tuple(range(0, 10))
HELD_OUT_SEEDS = tuple(range(100, 120))


def parse_seeds(text: str) -> list[int] | int:
    """Parse ``--seeds``: a count ``N`` (the seeds ``--seed`` … ``--seed + N - 1``, returned as
    an int) or explicit seeds as ranges and lists, ``100-119`` or ``0-9,15`` (a list); at most
    :data:`~hippo.cli_args.MAX_SEEDS` runs either way."""
    s = str(text).strip()
    if plain_digits(s):
        n = int(s)
        if n < 1:
            raise argparse.ArgumentTypeError(f"--seeds must be >= 1 or a list, got {text!r}")
        if n > MAX_SEEDS:
            raise argparse.ArgumentTypeError(
                f"--seeds {s} is a count of runs (at most {MAX_SEEDS}); for the one seed {s} "
                f"give --seed {s}, or --seeds {s}-{s}")
        return n
    try:
        return seed_ranges(s)
    except argparse.ArgumentTypeError as e:
        # only a malformed list is "a count or seeds ..."; too many or repeated seeds are
        # said as such ("--seeds takes a count (5) or '1,1' repeats a seed" read as nonsense)
        why = str(e)
        raise argparse.ArgumentTypeError(f"--seeds takes a count (5) or {why}"
                                         if why.startswith("seeds are ") else
                                         f"--seeds: {why}") from None


def seed_list(args: argparse.Namespace) -> list[int]:
    """The seeds a scenario runs: ``--seeds`` as a list, or ``--seed`` … for a count."""
    spec = getattr(args, "seeds", 1)
    if isinstance(spec, int):
        return [int(args.seed) + i for i in range(spec)]
    return list(spec)


def add_seeds_argument(parser: argparse.ArgumentParser, what: str) -> None:
    """``--seeds``: a count or explicit seeds (see :func:`parse_seeds`)."""
    parser.add_argument("--seeds", type=parse_seeds, default=1,
                        help=f"{what}: a count N (seeds --seed ... --seed+N-1) or seeds as "
                             "ranges and lists, e.g. 100-119 or 0-9,15 (tuning seeds 0-9, "
                             "held-out seeds 100-119)")


def add_cache_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--cache", type=out_dir, default=None,
                        help="folder to keep and reuse recordings in (.npz), keyed by their "
                             "settings; default: record afresh")


def cached_recording(cache: str | Path | None, key: str, build: Callable[[], Recording],
                     ticks: int | None = None) -> Recording:
    """``build()`` once per ``key``: with a ``cache`` folder the recording is kept there as
    ``key.npz`` (atomic write) and read back on later calls. A cached file that is damaged,
    or not ``ticks`` long, is recorded again (with a warning), never used."""
    if cache is None:
        return build()
    path = check_path("cache", cache) / f"{key}.npz"
    if path.exists():
        try:
            rec = Recording.load(path)
        except CorruptFileError as exc:
            why = str(exc)
        else:
            if ticks is None or len(rec) == ticks:
                return rec
            why = f"{len(rec)} ticks, not {ticks}"
        warnings.warn(f"the cached recording {path} is unusable ({why}): recording it again",
                      stacklevel=2)
    rec = build()
    path.parent.mkdir(parents=True, exist_ok=True)
    rec.save(path)
    return rec


def only_with(args: argparse.Namespace, parser: argparse.ArgumentParser, dest: str,
              needs: str, why: str) -> None:
    """Refuse the option ``dest`` (a :class:`~hippo.cli_args.Given` one) typed without the
    flag ``needs``, which it only serves (``why``): ignored, it would do nothing in silence."""
    if getattr(args, f"{dest}_given", False) and not getattr(args, needs):
        parser.error(f"argument --{dest.replace('_', '-')}: only with --{needs} ({why}); "
                     f"add --{needs} or leave it out")


#: one or more leak rates in (0, 1], read as every comma-separated option is
_LEAK_RATES = numbers((1, None), 0.0, 1.0, lo_open=True)


def parse_leak(text: str) -> tuple[float, ...]:
    """``"0.05,0.15"`` -> ``(0.05, 0.15)``: one leak rate or one per group of neurons, each in
    (0, 1] (one trailing comma allowed, as in ``--delays`` and ``--seeds``)."""
    return tuple(_LEAK_RATES(text))
