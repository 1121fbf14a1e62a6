"""Where the reservoir runs (hippo.perception.backends): the float type, the device check and
torch's import error, each against the exact answer a user should get."""

from __future__ import annotations

import sys
import types

import numpy as np
import pytest

from hippo.perception import Reservoir, ReservoirParams
from hippo.perception.backends import _check_device, _import_torch, _np_dtype


def small() -> ReservoirParams:
    return ReservoirParams(n_neurons=6, n_inputs=3, seed=0)


class _TorchDtype:
    """What ``str(torch.float32)`` prints, without needing torch."""

    def __init__(self, name: str) -> None:
        self.name = name

    def __str__(self) -> str:
        return self.name


@pytest.mark.parametrize(("given", "want"), [
    ("float32", np.float32), ("float64", np.float64),
    (np.float32, np.float32), (np.dtype("float64"), np.float64),
    (_TorchDtype("torch.float32"), np.float32), (_TorchDtype("torch.float64"), np.float64),
])
def test_a_float_type_is_read_from_its_name_numpy_or_torch(given, want):
    assert _np_dtype(given) is want
    assert Reservoir(small(), dtype=given).np_dtype is want


@pytest.mark.parametrize("bad", ["float16", "int64", "torch.", "float32torch.", "xtorch.float32",
                                 "Float32"])
def test_other_float_types_are_refused_by_name(bad):
    with pytest.raises(ValueError, match=r"^dtype must be 'float32' or 'float64', got "):
        _np_dtype(_TorchDtype(bad))


def _torch_without_cuda(monkeypatch: pytest.MonkeyPatch) -> None:
    fake = types.ModuleType("torch")
    fake.__version__ = "9.9.9+cpu"
    fake.cuda = types.SimpleNamespace(is_available=lambda: False)
    monkeypatch.setitem(sys.modules, "torch", fake)


@pytest.mark.parametrize("device", ["cuda", "cuda:0", "cuda:3"])
def test_a_cuda_device_without_a_gpu_says_to_use_the_cpu(monkeypatch, device):
    _torch_without_cuda(monkeypatch)
    want = (f"device='{device}' but this torch build (9.9.9+cpu) sees no CUDA GPU; "
            "use device='cpu' (the numpy loop)")
    with pytest.raises(ValueError) as err:
        Reservoir(small(), device=device)
    assert str(err.value) == want


@pytest.mark.parametrize("device", ["gpu", "CUDA:0", "cudax", "cuda0", " cuda", "mps"])
def test_a_device_that_is_not_cpu_or_cuda_is_refused_before_torch_is_imported(monkeypatch,
                                                                                device):
    monkeypatch.setitem(sys.modules, "torch", None)  # importing torch would fail
    with pytest.raises(ValueError, match=r"^device must be 'cpu' or 'cuda\[:N\]', got "):
        _check_device(device)
    assert _check_device("cpu") == "cpu"


def test_without_torch_the_error_says_how_to_install_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "torch", None)  # as if torch were not installed
    with pytest.raises(ImportError) as err:
        _import_torch()
    assert str(err.value) == (
        "the torch backend of Reservoir needs PyTorch, an optional dependency: "
        "pip install 'hippo[torch]' (see the README for the build that matches your GPU)")
    with pytest.raises(ImportError, match=r"pip install 'hippo\[torch\]'"):
        Reservoir(small(), device="cuda")
