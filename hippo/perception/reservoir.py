"""Leaky echo state reservoir with one leak rate per neuron (SMC09 eq. 1).

The update keeps the leak **inside** the non-linearity, exactly as SMC09/ICANN09 write it::

    x(t+1) = tanh((1 - a) ⊙ x(t) + a ⊙ (W_in u(t) + W_res x(t))),     x(0) = 0

(ReservoirPy and Oger integrate outside the tanh, ``x ← (1-a) x + a tanh(...)``: a different
system.) ``a`` is a vector, one leak rate per neuron; with ``a = 1`` the update is the standard
ESN ``x(t+1) = tanh(W_in u(t) + W_res x(t))``.

Weights (both fixed, never trained):

* ``W_res`` (N×N): i.i.d. N(0, 1), rescaled to the requested spectral radius (SMC09: 0.99,
  ICANN09: 0.9; the radius of the draw by Arnoldi from N = 256 on, :mod:`.spectral`).
* ``W_in`` (N×n_u): ternary, ``+w`` and ``-w`` with probability ``p`` each, else 0
  (SMC09: w = 2, p = 0.075; ICANN09: w = 0.2, p = 0.15).

Each matrix has its own random stream (children of ``numpy.random.SeedSequence(seed)``: child 0
draws ``W_res``, child 1 draws ``W_in``), so e.g. changing the number of inputs leaves ``W_res``
unchanged.

Two ways to drive it, with identical results (to float rounding):

* :meth:`Reservoir.run` harvests a whole sequence. It is batched: B input streams and/or B
  leak-rate vectors over the one shared ``W_res``, one matrix-matrix product per tick, so a
  leak-rate sweep costs about one run. On the CPU the tick loop is numpy (the default, and the
  fastest there: per-tick torch calls cost more than the product itself at this size); with
  ``device="cuda"`` it runs in torch on the GPU. torch is an optional dependency
  (``pip install "hippo[torch]"``), imported only for that backend.
* :meth:`Reservoir.step` advances one tick for the closed loop. It uses the weights folded into
  a single matrix, ``x ← tanh([u; x] · M)``, which costs one matrix-vector product per tick
  (~10-20 µs for 600 neurons).

Conventions: ``run(U)[t]`` is the state *after* feeding ``U[t]`` (``x(t+1)`` in eq. 1); it is
paired with ``U[t]`` to form the SFA input ``[u(t); x(t+1)]``.

The parameters (:class:`~hippo.perception.reservoir_params.ReservoirParams`) and the leak
specification (:func:`~hippo.perception.reservoir_params.expand_leak`) have their own module.

The weights are drawn from the parameters' seed, but a reservoir saves and loads them itself
(:meth:`Reservoir.to_arrays` / :meth:`Reservoir.from_arrays`, :meth:`Reservoir.save` /
:meth:`Reservoir.load`: :mod:`~hippo.perception.part_files`), so a saved model does not hang on
the random generator's stream, and one built :meth:`~Reservoir.from_weights` is saved too.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from hippo._checks import check_finite
from hippo._threads import blas_threads
from hippo.perception.backends import (
    _check_device,
    _import_torch,
    _loop_batched_np,
    _loop_shared_np,
    _np_dtype,
    _num_threads,
)
from hippo.perception.part_files import PartArrays, PartFile
from hippo.perception.reservoir_params import LeakSpec, ReservoirParams, expand_leak
from hippo.perception.spectral_radius import dense_spectral_radius, spectral_radius


def _host(a: Any) -> Any:
    """A torch tensor (on any device, even one that requires grad) as a numpy array; anything
    else as it is."""
    return a.detach().cpu().numpy() if hasattr(a, "detach") else a


@dataclass
class _StepMirror:
    """numpy copy of the folded weights used by :meth:`Reservoir.step`."""

    M: np.ndarray    # (n_u + N, N): [W_in^T ⊙ a ; W_res^T ⊙ a + diag(1 - a)]
    z: np.ndarray    # (n_u + N,): [u; x] work vector (its x part is the state)
    pre: np.ndarray  # (N,): pre-activation buffer


class Reservoir(PartFile):
    """Leaky ESN, SMC09 eq. 1: ``x(t+1) = tanh((1-a) x(t) + a (W_in u(t) + W_res x(t)))``.

    Its saved state (:meth:`to_arrays`, :meth:`save`) is ``W_in``, ``W_res`` and ``leak``; the
    float type and the device are chosen again at :meth:`load`, as at construction.

    Parameters
    ----------
    params:
        :class:`ReservoirParams` (defaults: SMC09).
    dtype:
        ``"float32"`` (default) or ``"float64"``, for both :meth:`run` and :meth:`step`.
    device:
        ``"cpu"`` (default: numpy) or ``"cuda[:N]"`` (torch on that GPU; needs the ``torch``
        extra) for :meth:`run`; :meth:`step` always runs on the CPU.

    Attributes
    ----------
    W_in : numpy (N, n_u)      ternary input weights
    W_res : numpy (N, N)       recurrent weights at the requested spectral radius
    leak : numpy (N,)          per-neuron leak rates ``a``
    state : numpy (N,)         current state of the online loop (:meth:`step`)
    """

    FILE_FORMAT = "hippo.perception.Reservoir/1"
    _PARAMS = ReservoirParams

    def __init__(self, params: ReservoirParams | None = None, *, dtype: str = "float32",
                 device: str = "cpu") -> None:
        self.params = params or ReservoirParams()
        p = self.params
        ss_res, ss_in = np.random.SeedSequence(int(p.seed)).spawn(2)
        W = np.random.default_rng(ss_res).standard_normal((p.n_neurons, p.n_neurons))
        W *= p.spectral_radius / spectral_radius(W)
        rng_in = np.random.default_rng(ss_in)
        W_in = rng_in.choice(np.array([-p.input_weight, 0.0, p.input_weight]),
                             p=[p.input_prob, 1.0 - 2.0 * p.input_prob, p.input_prob],
                             size=(p.n_neurons, p.n_inputs))
        self._setup(W_in, W, expand_leak(p.leak, p.n_neurons), dtype, device)

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_weights(cls, W_in: np.ndarray, W_res: np.ndarray, leak: LeakSpec, *,
                     spectral_radius: float | None = None, dtype: str = "float32",
                     device: str = "cpu") -> Reservoir:
        """A reservoir with the given weights (used by ``load``); nothing is rescaled.

        ``spectral_radius`` is only recorded in :attr:`params` (computed when not given).
        """
        W_in = check_finite("W_in", W_in)
        W_res = check_finite("W_res", W_res)
        if W_in.ndim != 2 or W_res.ndim != 2 or W_res.shape != (W_in.shape[0],) * 2:
            raise ValueError(f"W_in (N, n_u) and W_res (N, N) do not fit: {W_in.shape}, "
                             f"{W_res.shape}")
        n, n_u = W_in.shape
        leak_vec = expand_leak(leak, n)
        self = cls.__new__(cls)
        radius = (dense_spectral_radius(W_res) if spectral_radius is None
                  else float(spectral_radius))
        self.params = ReservoirParams(n_inputs=n_u, n_neurons=n, spectral_radius=max(radius, 1e-12),
                                      leak=float(leak_vec[0]) if np.all(leak_vec == leak_vec[0])
                                      else tuple(leak_vec.tolist()), input_weight=0.0,
                                      input_prob=0.0)
        self._setup(W_in, W_res, leak_vec, dtype, device)
        return self

    def to_arrays(self, prefix: str = "") -> dict[str, np.ndarray]:
        """The weights ``W_in`` (N, n_u), ``W_res`` (N, N), ``leak`` (N,) (float64 copies), each
        key led by ``prefix``."""
        return {f"{prefix}W_in": np.array(self.W_in), f"{prefix}W_res": np.array(self.W_res),
                f"{prefix}leak": np.array(self.leak)}

    @classmethod
    def from_arrays(cls, params: ReservoirParams, arrays: Mapping[str, Any], prefix: str = "",
                    *, dtype: str = "float32", device: str = "cpu") -> Reservoir:
        """A reservoir with the weights of :meth:`to_arrays` (keys led by ``prefix``), checked:
        every key present and known, shapes (N, n_u), (N, N), (N,) from ``params``, finite,
        the leak equal to ``params.leak`` and the spectral radius to ``params.spectral_radius``
        (to 1e-6 relative). Raises ``ValueError`` naming the key."""
        a = PartArrays("Reservoir", arrays, prefix, ("W_in", "W_res", "leak"))
        N, n_u = int(params.n_neurons), int(params.n_inputs)
        W_in, W_res, leak = a.get("W_in", (N, n_u)), a.get("W_res", (N, N)), a.get("leak", (N,))
        if not np.array_equal(leak, expand_leak(params.leak, N)):
            raise ValueError(f"{prefix}leak does not match the parameters' leak {params.leak}")
        rho, want = spectral_radius(W_res), float(params.spectral_radius)
        if not abs(rho - want) <= 1e-6 * max(1.0, want):
            raise ValueError(f"{prefix}W_res has spectral radius {rho:.6g}, its parameters say "
                             f"{want}")
        self = cls.__new__(cls)
        self.params = params
        self._setup(W_in, W_res, leak, dtype, device)
        return self

    def _setup(self, W_in: np.ndarray, W_res: np.ndarray, leak: np.ndarray, dtype: str,
               device: str) -> None:
        self.np_dtype = _np_dtype(dtype)
        self.dtype = self.np_dtype.__name__
        self.device = _check_device(device)
        self.W_in, self.W_res, self.leak = W_in, W_res, leak  # float64 from both callers
        self._W_in_run = np.ascontiguousarray(self.W_in, dtype=self.np_dtype)
        self._W_res_run = np.ascontiguousarray(self.W_res, dtype=self.np_dtype)
        a = self.leak
        M = np.vstack([self.W_in.T * a, self.W_res.T * a + np.diag(1.0 - a)])
        self._mirror = _StepMirror(M=np.ascontiguousarray(M, dtype=self.np_dtype),
                                   z=np.zeros(self.n_inputs + self.n_neurons, self.np_dtype),
                                   pre=np.zeros(self.n_neurons, self.np_dtype))

    @property
    def n_inputs(self) -> int:
        return self.W_in.shape[1]

    @property
    def n_neurons(self) -> int:
        return self.W_res.shape[0]

    @property
    def spectral_radius(self) -> float:
        """Largest absolute eigenvalue of ``W_res`` (computed, not the requested value)."""
        return dense_spectral_radius(self.W_res)

    # ------------------------------------------------------------------ offline harvest
    def run(self, U: Any, *, leak: LeakSpec | np.ndarray | None = None,
            x0: np.ndarray | None = None, threads: int | None = 1,
            backend: str = "auto") -> np.ndarray:
        """States for a whole input sequence (a numpy array of :attr:`np_dtype`).

        ``U`` is ``(T, n_u)`` (one stream) or ``(B, T, n_u)`` (B streams); an array-like (a torch
        tensor too). ``leak`` overrides the reservoir's own rates: a leak spec for all streams, or
        a ``(B, k)``/``(B, N)`` array of B leak configurations (a 2-D ``leak`` with a 2-D ``U``
        feeds the one stream to all B configurations: a leak sweep). ``x0`` is the initial state
        (default 0), ``(N,)`` or ``(B, N)``. ``threads`` is the BLAS (and torch) thread count for
        the tick loop (default 1: the per-tick products are small, and extra threads only pay off
        for a batch of leak configurations on idle cores; ``None`` leaves it as it is).
        ``backend``: ``"auto"`` runs the tick loop with numpy on the CPU and with torch on a CUDA
        :attr:`device`; ``"numpy"`` and ``"torch"`` force one. Returns ``(T, N)`` for one stream
        and one leak, else ``(B, T, N)``; row ``t`` is the state after feeding ``U[t]``.
        """
        if backend not in ("auto", "numpy", "torch"):
            raise ValueError(f"backend must be 'auto', 'numpy' or 'torch', got {backend!r}")
        if backend == "numpy" and self.device != "cpu":
            raise ValueError(f"backend='numpy' runs on the CPU, but device={self.device!r}")
        U = np.asarray(_host(U), dtype=self.np_dtype)
        if U.ndim not in (2, 3) or U.shape[-1] != self.n_inputs:
            raise ValueError(f"U must have shape (T, {self.n_inputs}) or (B, T, {self.n_inputs}),"
                             f" got {U.shape}")
        if not np.isfinite(U).all():
            raise ValueError("U (the input sequence) contains NaN or inf")
        batched = U.ndim == 3 or (leak is not None and np.ndim(leak) == 2)
        if U.ndim == 2:
            U = U[None]
        B_in = U.shape[0]
        N = self.n_neurons
        # ---- leak: (B_leak, N)
        if leak is None:
            A = self.leak[None, :]
        elif np.ndim(leak) == 2:
            A = np.stack([expand_leak(row, N) for row in leak])
        else:
            A = expand_leak(leak, N)[None, :]
        B = max(B_in, A.shape[0])
        if B_in not in (1, B) or A.shape[0] not in (1, B):
            raise ValueError(f"{B_in} input streams and {A.shape[0]} leak configurations "
                             "do not broadcast")
        A = A.astype(self.np_dtype)
        # ---- initial state
        x = np.zeros((B, N), dtype=self.np_dtype)
        if x0 is not None:
            x0 = check_finite("x0", _host(x0))
            if x0.shape not in ((N,), (1, N), (B, N)):
                raise ValueError(f"x0 must have shape ({N},) or ({B}, {N}), got {x0.shape}")
            x += x0  # (rounded to the reservoir's float type)
        if backend == "torch" or (backend == "auto" and self.device != "cpu"):
            states = self._run_torch(U, A, x, threads)
        else:
            states = self._run_numpy(U, A, x, threads)
        return states if batched else states[0]

    def _run_numpy(self, U: np.ndarray, A: np.ndarray, x: np.ndarray,
                   threads: int | None) -> np.ndarray:
        """The tick loop in numpy; returns (B, T, N)."""
        B, N = x.shape
        T = U.shape[1]
        # input drive W_in u(t) for all t at once: (T, B_in, N), on one thread so that the
        # states do not depend on the thread count (a small product: n_u = 8 columns)
        with blas_threads(1):
            drive = np.ascontiguousarray(np.matmul(U, self._W_in_run.T).transpose(1, 0, 2))
        with blas_threads(threads):
            if A.shape[0] == 1:
                # shared leak: fold (1-a) and a into one matrix -> one product per tick
                a = A[0]
                drive *= a
                M = self._W_res_run.T * a + np.diag(1 - a)
                states = np.empty((T, B, N), dtype=self.np_dtype)
                if T:
                    _loop_shared_np(drive, M, x, states)
                return (np.ascontiguousarray(states.transpose(1, 0, 2)) if B > 1
                        else states.reshape(1, T, N))
            # written straight in the (B, T, N) layout that is returned
            out = np.empty((B, T, N), dtype=self.np_dtype)
            if T:
                _loop_batched_np(drive, self._W_res_run, A, x, out)
            return out

    def _run_torch(self, U: np.ndarray, A: np.ndarray, x: np.ndarray,
                   threads: int | None) -> np.ndarray:
        """The same loop in torch on :attr:`device` (the CUDA backend); returns (B, T, N)."""
        torch = _import_torch()
        dev = torch.device(self.device)
        B, N = x.shape
        T = U.shape[1]
        cpu_threads = threads if dev.type == "cpu" else None
        with torch.inference_mode(), _num_threads(cpu_threads):
            Ut = torch.as_tensor(U, device=dev)
            At = torch.as_tensor(A, device=dev)
            xt = torch.as_tensor(x, device=dev)
            W_in = torch.as_tensor(self._W_in_run, device=dev)
            W_res = torch.as_tensor(self._W_res_run, device=dev)
            drive = torch.matmul(Ut, W_in.T).transpose(0, 1).contiguous()  # (T, B_in, N)
            states = torch.empty(T, B, N, dtype=Ut.dtype, device=dev)
            if At.shape[0] == 1:
                drive *= At
                a = At[0]
                M = W_res.T * a + torch.diag(1.0 - a)
                for t in range(T):
                    torch.tanh(torch.addmm(drive[t], xt, M), out=states[t])
                    xt = states[t]
            else:
                WT = W_res.T.contiguous()
                oma = 1.0 - At
                for t in range(T):
                    pre = torch.mm(xt, WT)
                    pre += drive[t]
                    pre *= At
                    pre.addcmul_(oma, xt)
                    torch.tanh(pre, out=states[t])
                    xt = states[t]
            return states.permute(1, 0, 2).cpu().numpy()

    # ------------------------------------------------------------------ online loop
    @property
    def state(self) -> np.ndarray:
        """Current state of the online loop (a copy)."""
        return self._mirror.z[self.n_inputs:].copy()

    def reset(self, x0: np.ndarray | None = None) -> None:
        """Set the online state to ``x0`` (default: zeros, as in eq. 1)."""
        m = self._mirror
        m.z[:] = 0
        if x0 is not None:
            x0 = check_finite("x0", x0)
            if x0.shape != (self.n_neurons,):
                raise ValueError(f"x0 must have shape ({self.n_neurons},), got {x0.shape}")
            m.z[self.n_inputs:] = x0

    def step(self, u: np.ndarray) -> np.ndarray:
        """Feed one input vector ``u(t)`` and return the new state ``x(t+1)`` (a view; copy it
        if you keep it)."""
        u = np.asarray(u, dtype=self.np_dtype)
        if u.shape != (self.n_inputs,):
            raise ValueError(f"u must have shape ({self.n_inputs},), got {u.shape}")
        if not np.isfinite(u).all():
            raise ValueError("u (the sensor vector) contains NaN or inf")
        m = self._mirror
        m.z[: self.n_inputs] = u
        return self._advance()

    def _advance(self) -> np.ndarray:
        """Update the state from the input already written into the work vector."""
        m = self._mirror
        np.dot(m.z, m.M, out=m.pre)
        np.tanh(m.pre, out=m.z[self.n_inputs:])
        return m.z[self.n_inputs:]

    def __repr__(self) -> str:
        a = np.unique(self.leak)
        leak = f"{a[0]:g}" if a.size == 1 else "/".join(f"{v:g}" for v in a[:4])
        return (f"Reservoir(N={self.n_neurons}, n_u={self.n_inputs}, leak={leak}, "
                f"rho={self.params.spectral_radius:g}, dtype={self.np_dtype.__name__}, "
                f"device={self.device})")
