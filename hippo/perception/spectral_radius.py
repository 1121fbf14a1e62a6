"""Spectral radius of a reservoir's recurrent matrix, ``ρ(W) = max_i |λ_i(W)|``.

Drawing a reservoir rescales an i.i.d. N(0, 1) matrix to a set ``ρ`` (SMC09: 0.99). Every
eigenvalue from LAPACK (``numpy.linalg.eigvals``: balancing, Hessenberg reduction, then the
Hessenberg QR, about 10 N³ flops) costs 0.18 s of CPU at N = 600 (one core), a fifth of the
whole RC-SFA-ICA fit. Only the largest one is needed: ARPACK's implicitly restarted Arnoldi method
(Lehoucq, Sorensen & Yang 1998; ``scipy.sparse.linalg.eigs``, ``which="LM"``) finds it from
matrix-vector products (about 580 of them), 0.09 s at N = 600.

The Arnoldi answer equals LAPACK's to rounding (within 4e-14 relative on the N(0, 1) draws
checked, see ``tests/perception/test_spectral.py``), not bit for bit; the reservoir runs in
float32, where the rescaled weights of the 30 reported two-rooms seeds (0-9, 100-119) are the
same. LAPACK's own answer moves by a few ulps between 1 and 2 BLAS threads (at seed 118 that
changed one float32 weight); Arnoldi's does not (a fixed start vector, one BLAS thread). Arnoldi
can settle on a large eigenvalue that is not the largest when the Krylov space is small (with 20
vectors it did on 2 of 20 draws at N = 600); with ``_NCV`` = 100 vectors and the ``_K`` = 4
largest Ritz values converged it matched LAPACK on every draw checked (seeds 0-199 at N = 600,
0-99 at N = 400, 0-19 at N = 1200). Below ``_DENSE_BELOW``
neurons, and whenever ARPACK does not converge, the dense path is used.
"""

from __future__ import annotations

import numpy as np

from hippo._threads import blas_threads

#: below this size the dense eigenvalues cost about as much as Arnoldi (N = 400: 50 ms vs 45 ms)
_DENSE_BELOW = 512
#: Arnoldi: the Ritz values that must converge, and the Krylov space's dimension
_K, _NCV = 4, 100


def dense_spectral_radius(W: np.ndarray) -> float:
    """``max |λ|`` from all eigenvalues (LAPACK ``geev``)."""
    return float(np.max(np.abs(np.linalg.eigvals(W)))) if W.size else 0.0


def spectral_radius(W: np.ndarray) -> float:
    """``ρ(W) = max |λ_i(W)|`` of a square float64 matrix: Arnoldi for large ``W``, else
    (and as the fallback) every eigenvalue."""
    n = W.shape[0]
    if n < _DENSE_BELOW:
        return dense_spectral_radius(W)
    import scipy.sparse.linalg as sla

    try:
        with blas_threads(1):
            lam = sla.eigs(W, k=_K, which="LM", tol=0, ncv=min(_NCV, n - 1), v0=np.ones(n),
                           return_eigenvectors=False)
    except sla.ArpackNoConvergence:  # not seen on the draws checked
        return dense_spectral_radius(W)
    return float(np.max(np.abs(lam)))
