"""The place-cell estimator's file: one ``.npz`` (no pickle), written atomically, read
trusting nothing.

:func:`save_model` writes a fitted :class:`~hippo.perception.place_cells.RCSFAICA` (its
parameters as JSON, the SFA and ICA arrays, the output statistics, the reservoir's weights);
:func:`load_model` checks the format tag, the parameters, and every array's dtype, shape,
finiteness and consistency before it builds the model.
"""

from __future__ import annotations

import json
import os
from dataclasses import asdict, fields
from pathlib import Path
from typing import Any

import numpy as np

from hippo._checks import check_array
from hippo.io import CorruptFileError, load_npz, save_npz
from hippo.perception.ica import FastICA
from hippo.perception.place_cell_params import RCSFAICAParams
from hippo.perception.reservoir import Reservoir, expand_leak
from hippo.perception.sfa import SFA

__all__ = ["FORMAT", "load_model", "save_model"]

FORMAT = "hippo.perception.RCSFAICA/1"
#: no fitted array holds a larger magnitude; a loaded one that does is damaged
_MAX_ABS = 1e12
_REQUIRED = ("format", "params", "sfa_mean", "sfa_scale", "sfa_W", "sfa_slowness", "ica_mean",
             "ica_whitening", "ica_rotation", "output_std", "output_peak")


def save_model(model: Any, path: str | os.PathLike) -> Path:
    """Write the fitted ``model`` (an :class:`~hippo.perception.place_cells.RCSFAICA`) to ``path``
    (.npz, atomic, no pickle)."""
    model._check_fitted()
    arrays: dict[str, Any] = {
        "format": np.array(FORMAT),
        "params": np.array(json.dumps(asdict(model.params))),
        "sfa_mean": model.sfa_.mean_, "sfa_scale": model.sfa_.scale_, "sfa_W": model.sfa_.W_,
        "sfa_slowness": model.sfa_.slowness_, "sfa_cutoff": np.array(model.sfa_.cutoff_),
        "sfa_n_whitened": np.array(model.sfa_.n_whitened_),
        "ica_mean": model.ica_.mean_, "ica_whitening": model.ica_.whitening_,
        "ica_rotation": model.ica_.rotation_,
        "output_std": model.output_std_, "output_peak": model.output_peak_,
    }
    if model.params.sfa_expansion == "quadratic":
        arrays["sfa_pre_mean"] = model.sfa_.pre_mean_
        arrays["sfa_pre_scale"] = model.sfa_.pre_scale_
    if model.reservoir_ is not None:
        arrays.update(W_in=model.reservoir_.W_in, W_res=model.reservoir_.W_res,
                      leak=model.reservoir_.leak)
    return save_npz(path, arrays)

def load_model(cls: type, path: str | os.PathLike) -> Any:
    """Read a model written by :func:`save_model` into a new ``cls`` (RCSFAICA).

    Nothing in the file is trusted: the format tag, the parameters (type- and range-checked
    like the constructor's), and every array's dtype, shape (consistent with the
    parameters and with each other) and finiteness, the reservoir's leak and spectral radius
    against its parameters, scales and standard deviations > 0. A damaged file raises
    :class:`~hippo.io.CorruptFileError` (a ``ValueError``) naming the problem; nothing is
    half-loaded (the model is built only once every check passed).
    """
    a = load_npz(path, required=_REQUIRED)
    try:
        return _from_arrays(cls, a)
    except CorruptFileError as exc:
        raise CorruptFileError(f"{path}: {exc}") from exc
    except (ValueError, TypeError, KeyError, IndexError, OverflowError) as exc:
        raise CorruptFileError(f"{path}: inconsistent model file ({exc})") from exc

def _from_arrays(cls: type, a: dict[str, np.ndarray]) -> Any:
    fmt = a["format"]
    if fmt.dtype.kind != "U" or fmt.shape != () or str(fmt) != FORMAT:
        raise CorruptFileError(f"not an RCSFAICA model (format {str(fmt)[:80]!r})")
    if a["params"].dtype.kind != "U" or a["params"].shape != ():
        raise CorruptFileError("the parameters are not a JSON string")
    try:
        raw = json.loads(str(a["params"]))
    except json.JSONDecodeError as exc:
        raise CorruptFileError(f"unreadable parameters ({exc})") from exc
    if not isinstance(raw, dict):
        raise CorruptFileError(f"the parameters are not a JSON object: {str(raw)[:80]}")
    known = {f.name for f in fields(RCSFAICAParams)}
    if isinstance(raw.get("input_range"), list):
        raw["input_range"] = tuple(raw["input_range"])
    try:
        params = RCSFAICAParams(**{k: v for k, v in raw.items() if k in known})
    except (TypeError, ValueError) as exc:
        raise CorruptFileError(f"bad parameters ({exc})") from exc
    p = params

    def arr(key: str, shape: tuple[int | None, ...], dtype: str = "float") -> np.ndarray:
        if key not in a:
            raise CorruptFileError(f"lacks required array {key!r}")
        try:
            return check_array(key, a[key], shape=shape, dtype=dtype, max_abs=_MAX_ABS)
        except ValueError as exc:
            raise CorruptFileError(str(exc)) from None

    def positive(key: str, v: np.ndarray) -> np.ndarray:
        if not (v > 0).all():
            raise CorruptFileError(f"{key} must be > 0 everywhere, got min {v.min():g}")
        return v

    n_u, n_sfa, n_ica = p.n_inputs, p.n_sfa, p.n_ica
    reservoir = None
    if p.use_reservoir:
        N = p.n_reservoir
        W_in = arr("W_in", (N, n_u))
        W_res = arr("W_res", (N, N))
        leak = arr("leak", (N,))
        if not np.array_equal(leak, expand_leak(p.leak, N)):
            raise CorruptFileError(f"leak does not match the parameters' leak {p.leak}")
        radius = float(np.max(np.abs(np.linalg.eigvals(W_res)))) if N else 0.0
        if not abs(radius - p.spectral_radius) <= 1e-6 * max(1.0, p.spectral_radius):
            raise CorruptFileError(f"W_res has spectral radius {radius:.6g}, its parameters "
                                   f"say {p.spectral_radius}")
        reservoir = Reservoir.from_weights(W_in, W_res, leak,
                                           spectral_radius=p.spectral_radius,
                                           dtype=p.dtype, device=p.device)
    d_in = (n_u + (p.n_reservoir if p.use_reservoir else 0)) * (2 if p.slow_pool else 1)
    sfa = SFA(p.sfa_params())
    if p.sfa_expansion == "quadratic":
        sfa.pre_mean_ = arr("sfa_pre_mean", (d_in,))
        sfa.pre_scale_ = positive("sfa_pre_scale", arr("sfa_pre_scale", (d_in,)))
        d = d_in + d_in * (d_in + 1) // 2
    else:
        d = d_in
    sfa.n_features_in_ = d_in
    sfa.mean_ = arr("sfa_mean", (d,))
    sfa.scale_ = arr("sfa_scale", (d,))
    if not (sfa.scale_ > 1e-12 * (1.0 + np.abs(sfa.mean_))).all():
        raise CorruptFileError("sfa_scale must be > 0 everywhere (above 1e-12 of the "
                               "feature's mean, as fit leaves it)")
    sfa.W_ = arr("sfa_W", (d, n_sfa))
    sfa.slowness_ = arr("sfa_slowness", (n_sfa,))
    cutoff = arr("sfa_cutoff", ()) if "sfa_cutoff" in a else np.array(np.nan)
    sfa.cutoff_ = float(cutoff)
    if "sfa_n_whitened" in a:
        nw = int(arr("sfa_n_whitened", (), dtype="int"))
        if not n_sfa <= nw <= d:
            raise CorruptFileError(f"sfa_n_whitened={nw} must lie in [{n_sfa}, {d}]")
        sfa.n_whitened_ = nw
    else:
        sfa.n_whitened_ = -1
    ica = FastICA(p.ica_params())
    ica.mean_ = arr("ica_mean", (n_sfa,))
    ica.whitening_ = arr("ica_whitening", (n_sfa, n_ica))
    ica.rotation_ = arr("ica_rotation", (n_ica, n_ica))
    if not np.allclose(ica.rotation_ @ ica.rotation_.T, np.eye(n_ica), atol=1e-6):
        raise CorruptFileError("ica_rotation is not orthonormal (FastICA's unmixing is)")
    ica.components_ = ica.rotation_ @ ica.whitening_.T
    ica.n_features_in_ = n_sfa
    output_std = positive("output_std", arr("output_std", (n_ica,)))
    output_peak = arr("output_peak", (n_ica,))
    ica.output_std_ = output_std
    model = cls(params)
    model.reservoir_ = reservoir
    model.sfa_, model.ica_ = sfa, ica
    model.sfa_slowness_ = sfa.slowness_.copy()
    model.n_features_in_ = n_u
    model.output_std_, model.output_peak_ = output_std, output_peak
    model._compile()
    model.reset_state()
    return model
