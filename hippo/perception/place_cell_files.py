"""The place-cell estimator's file: one ``.npz`` (no pickle), written atomically, read
trusting nothing, composed of its parts' own states.

Each layer saves and loads its own state (:mod:`~hippo.perception.part_files`): the file holds
the estimator's format tag and parameters (JSON), the SFA's arrays under ``sfa_``
(:meth:`SFA.to_arrays <hippo.perception.sfa.SFA.to_arrays>`), the ICA's under ``ica_``, the
reservoir's ``W_in``, ``W_res``, ``leak`` as they are, and the estimator's own output statistics
``output_std``, ``output_peak``. (This is the layout files had before the parts saved
themselves: old files load unchanged.)

:func:`save_model` writes a fitted :class:`~hippo.perception.place_cells.RCSFAICA`;
:func:`load_model` checks the format tag and the parameters, hands each part its keys (each
part checks dtypes, shapes, finiteness and its own invariants against the parameters), and
checks what is left: no key belongs to no part, the output statistics fit.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from hippo.io import CorruptFileError, load_npz, save_npz
from hippo.perception.ica import FastICA
from hippo.perception.part_files import PartArrays, check_format, params_from_json, params_json
from hippo.perception.place_cell_params import RCSFAICAParams
from hippo.perception.reservoir import Reservoir
from hippo.perception.sfa import SFA

__all__ = ["FORMAT", "load_model", "save_model"]

FORMAT = "hippo.perception.RCSFAICA/1"
#: the estimator's own arrays; the reservoir's keep their names, SFA's and ICA's a prefix
_OWN = ("output_std", "output_peak")
_RESERVOIR = ("W_in", "W_res", "leak")


def save_model(model: Any, path: str | os.PathLike) -> Path:
    """Write the fitted ``model`` (an :class:`~hippo.perception.place_cells.RCSFAICA`) to ``path``
    (.npz, atomic, no pickle): its parts' states side by side."""
    model._check_fitted()
    arrays: dict[str, Any] = {"format": np.array(FORMAT), "params": params_json(model.params),
                              **model.sfa_.to_arrays("sfa_"), **model.ica_.to_arrays("ica_"),
                              "output_std": model.output_std_, "output_peak": model.output_peak_}
    if model.reservoir_ is not None:
        arrays.update(model.reservoir_.to_arrays())
    try:   # a file that would not load is never written (set_params after fit)
        _from_arrays(type(model), dict(arrays))
    except (ValueError, TypeError, KeyError, IndexError, OverflowError) as exc:
        raise ValueError(f"cannot save this {type(model).__name__}: its parameters no longer "
                         f"describe its fit ({exc}); set_params after fit changes the "
                         f"parameters, not the fitted model: fit again first") from None
    return save_npz(path, arrays)


def load_model(cls: type, path: str | os.PathLike) -> Any:
    """Read a model written by :func:`save_model` into a new ``cls`` (RCSFAICA).

    Nothing in the file is trusted: the format tag, the parameters (type- and range-checked
    like the constructor's), each part's arrays (checked by the part against the parameters:
    dtype, shape, finiteness, the reservoir's leak and spectral radius, SFA scales > 0, an
    orthonormal ICA rotation), no array that belongs to no part, output standard deviations
    > 0. A damaged file raises :class:`~hippo.io.CorruptFileError` (a ``ValueError``) naming
    the problem; nothing is half-loaded (the model is built only once every check passed).
    """
    a = load_npz(path, required=("format", "params"))  # the kind first, then each part's keys
    try:
        return _from_arrays(cls, a)
    except ValueError as exc:  # a part's or the estimator's check, naming the array
        raise CorruptFileError(f"{path}: {exc}") from exc
    except (TypeError, KeyError, IndexError, OverflowError) as exc:
        raise CorruptFileError(f"{path}: inconsistent model file ({exc})") from exc


def _split(a: dict[str, np.ndarray], use_reservoir: bool) -> dict[str, dict[str, np.ndarray]]:
    """The file's arrays by owner: ``sfa``, ``ica``, ``reservoir``, ``own``."""
    parts: dict[str, dict[str, np.ndarray]] = {"sfa": {}, "ica": {}, "reservoir": {}, "own": {}}
    for k, v in a.items():
        owner = ("sfa" if k.startswith("sfa_") else "ica" if k.startswith("ica_")
                 else "reservoir" if k in _RESERVOIR and use_reservoir else "own")
        parts[owner][k] = v
    return parts


def _from_arrays(cls: type, a: dict[str, np.ndarray]) -> Any:
    check_format(a.pop("format"), FORMAT, "an RCSFAICA model")
    p = params_from_json(RCSFAICAParams, a.pop("params"), ignore_unknown=True)
    parts = _split(a, p.use_reservoir)
    stray = sorted(set(parts["own"]) - set(_OWN))
    if stray:
        raise CorruptFileError(f"unknown array(s) {', '.join(stray)[:200]}: no part of the "
                               f"model owns them")
    reservoir = None
    if p.use_reservoir:
        reservoir = Reservoir.from_arrays(p.reservoir_params(), parts["reservoir"],
                                          dtype=p.dtype, device=p.device)
    sfa = SFA.from_arrays(p.sfa_params(), parts["sfa"], "sfa_", n_features_in=p.sfa_inputs)
    ica = FastICA.from_arrays(p.ica_params(), parts["ica"], "ica_", n_features_in=p.n_sfa)
    own = PartArrays("RCSFAICA", parts["own"], "", _OWN)
    output_std = own.get("output_std", (p.n_ica,))
    if not (output_std > 0).all():
        raise CorruptFileError(f"output_std must be > 0 everywhere, got min {output_std.min():g}")
    model = cls(p)
    model.reservoir_ = reservoir
    model.sfa_, model.ica_ = sfa, ica
    model.sfa_slowness_ = sfa.slowness_.copy()
    model.n_features_in_ = p.n_inputs
    model.output_std_, model.output_peak_ = output_std, own.get("output_peak", (p.n_ica,))
    model._compile()
    model.reset_state()
    return model
