"""Where the reservoir runs: the float type (``float32``/``float64``), the device (``cpu``, or a
CUDA GPU through the optional torch extra), torch's import with a clear error when it is
missing, torch's thread count for a stretch of work, and the numpy tick loops of
:meth:`~hippo.perception.reservoir.Reservoir.run` (one shared leak, or a batch of leaks)."""

from __future__ import annotations

import sys
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np

__all__: list[str] = []


def _import_torch() -> Any:
    """torch, or a clear error saying how to install it (it is an optional dependency)."""
    try:
        import torch
    except ImportError as exc:  # pragma: no cover - depends on the installation
        raise ImportError("the torch backend of Reservoir needs PyTorch, an optional dependency: "
                          "pip install 'hippo[torch]' (see the README for the build that "
                          "matches your GPU)") from exc
    return torch


@contextmanager
def _num_threads(n: int | None) -> Iterator[None]:
    """Temporarily set torch's intra-op thread count (no-op for ``None`` or without torch)."""
    torch = sys.modules.get("torch")
    if n is None or torch is None or n == torch.get_num_threads():
        yield
        return
    old = torch.get_num_threads()
    torch.set_num_threads(n)
    try:
        yield
    finally:
        torch.set_num_threads(old)


def _np_dtype(dtype: Any) -> type[np.floating]:
    """numpy float type from ``"float32"``/``"float64"`` (a numpy type or dtype, or a torch dtype,
    is accepted)."""
    if isinstance(dtype, type) and issubclass(dtype, np.generic):
        dtype = np.dtype(dtype)  # np.float32 itself prints as "<class 'numpy.float32'>"
    name = str(dtype).removeprefix("torch.")
    if name not in ("float32", "float64"):
        raise ValueError(f"dtype must be 'float32' or 'float64', got {dtype!r}")
    return np.float32 if name == "float32" else np.float64


def _check_device(device: Any) -> str:
    """``"cpu"``, or a CUDA device that exists (which needs torch built with CUDA)."""
    name = str(device)
    if name == "cpu":
        return name
    if not (name == "cuda" or name.startswith("cuda:")):
        raise ValueError(f"device must be 'cpu' or 'cuda[:N]', got {device!r}")
    torch = _import_torch()
    if not torch.cuda.is_available():
        raise ValueError(f"device={name!r} but this torch build ({torch.__version__}) sees no "
                         "CUDA GPU; use device='cpu' (the numpy loop)")
    return name


def _loop_shared_np(drive: np.ndarray, M: np.ndarray, x: np.ndarray, states: np.ndarray) -> None:
    """``states[t] = tanh(drive[t] + states[t-1] @ M)``, shapes (T, B, N), (N, N), (B, N)."""
    pre = np.empty_like(x)
    for t in range(drive.shape[0]):
        np.matmul(x, M, out=pre)
        pre += drive[t]
        np.tanh(pre, out=states[t])
        x = states[t]


def _loop_batched_np(drive: np.ndarray, W: np.ndarray, A: np.ndarray, x: np.ndarray,
                     states: np.ndarray) -> None:
    """B leak configurations: ``tanh(A ⊙ (x @ W_resᵀ + drive[t]) + (1 - A) ⊙ x)``.

    ``drive`` is ``W_in u`` (T, B or 1, N), ``A`` (B, N), ``x`` (B, N), ``states`` (B, T, N). The
    states are kept as columns, ``W_res @ xᵀ`` (with OpenBLAS on 2 threads and B = 16, about
    12 % faster per tick than ``x @ W_resᵀ``), and written straight in the returned layout.
    """
    xT = np.ascontiguousarray(x.T)
    AT = np.ascontiguousarray(A.T)
    omaT = 1.0 - AT
    pre = np.empty_like(xT)
    tmp = np.empty_like(xT)
    for t in range(drive.shape[0]):
        np.matmul(W, xT, out=pre)
        pre += drive[t].T
        pre *= AT
        np.multiply(omaT, xT, out=tmp)
        pre += tmp
        np.tanh(pre, out=xT)
        states[:, t] = xT.T
