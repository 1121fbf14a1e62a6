"""The rules of hippo.perception.spectral_radius on small hand-made and drawn matrices: which
path a size takes (exactly at ``_DENSE_BELOW`` and one below), the Arnoldi set-up the module
docstring gives (``_K`` = 4 Ritz values, ``_NCV`` = 100 vectors, a start vector of ones, one BLAS
thread), and a draw on which a Krylov space of scipy's default 20 vectors finds the wrong
eigenvalue."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
import scipy.sparse.linalg as sla
from threadpoolctl import threadpool_info

from hippo._threads import blas_threads
from hippo.perception import spectral_radius as spectral
from hippo.perception.spectral_radius import dense_spectral_radius, spectral_radius


def _draw(seed: int, n: int) -> np.ndarray:
    """W_res before scaling, drawn as ``Reservoir`` draws it (i.i.d. N(0, 1))."""
    ss_res, _ = np.random.SeedSequence(seed).spawn(2)
    return np.random.default_rng(ss_res).standard_normal((n, n))


def _spy(monkeypatch: pytest.MonkeyPatch) -> list[dict[str, Any]]:
    """Record every call of scipy's ``eigs`` (its arguments and the BLAS threads it ran on),
    passing it on to the real one."""
    calls: list[dict[str, Any]] = []
    real = sla.eigs

    def eigs(A: np.ndarray, **kw: Any) -> Any:
        threads = {i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"}
        calls.append(dict(kw, n=A.shape[0], threads=threads))
        return real(A, **kw)

    monkeypatch.setattr(sla, "eigs", eigs)
    return calls


def test_the_dense_path_ends_exactly_at_512_neurons(monkeypatch):
    calls = _spy(monkeypatch)
    assert spectral._DENSE_BELOW == 512
    # 511 < 512: every eigenvalue, the same number as LAPACK's own
    W = _draw(1, 511)
    assert spectral_radius(W) == float(np.max(np.abs(np.linalg.eigvals(W))))
    assert calls == []
    # 512 is not below 512: Arnoldi, once
    W = _draw(1, 512)
    r = spectral_radius(W)
    assert [c["n"] for c in calls] == [512]
    assert abs(r / dense_spectral_radius(W) - 1) < 1e-12


def test_arnoldi_runs_as_the_docstring_sets_it_up(monkeypatch):
    # _K = 4 Ritz values converged, _NCV = 100 Krylov vectors, the fixed start vector of ones
    # (no random start), the eigenvalues only, on one BLAS thread even when the caller allows 2
    calls = _spy(monkeypatch)
    W = _draw(0, 600)
    with blas_threads(2):
        r = spectral_radius(W)
    (c,) = calls
    assert c["k"] == 4 and c["ncv"] == 100 and c["which"] == "LM" and c["tol"] == 0
    np.testing.assert_array_equal(c["v0"], np.ones(600))
    assert c["return_eigenvectors"] is False
    assert c["threads"] == {1}
    # ρ is the largest modulus of what eigs gave
    with blas_threads(1):
        lam = sla.eigs(W, k=4, which="LM", tol=0, ncv=100, v0=np.ones(600),
                       return_eigenvectors=False)
    assert r == float(np.max(np.abs(lam)))


def test_a_draw_that_twenty_krylov_vectors_get_wrong_is_found_right():
    # seed 6 at N = 600: scipy's default Krylov space (ncv = max(2k + 1, 20) = 20) settles on
    # an eigenvalue 0.35 % below the largest (computed here with scipy directly); with
    # _NCV = 100 the radius is LAPACK's to rounding
    W = _draw(6, 600)
    dense = float(np.max(np.abs(np.linalg.eigvals(W))))
    with blas_threads(1):
        small = sla.eigs(W, k=4, which="LM", tol=0, ncv=20, v0=np.ones(600),
                         return_eigenvectors=False)
    assert float(np.max(np.abs(small))) < dense * (1 - 1e-3)      # the trap is real
    assert abs(spectral_radius(W) / dense - 1) < 1e-12


def test_hand_made_spectra_on_both_paths():
    # a diagonal matrix's eigenvalues are its diagonal: ρ = max |d_i| (here a negative one)
    d = np.linspace(-0.5, 0.4, 600)
    d[17] = -0.93
    assert spectral_radius(np.diag(d)) == pytest.approx(0.93, rel=1e-12)
    assert spectral_radius(np.diag(d[:40])) == pytest.approx(0.93, rel=1e-15)
    # a 2 x 2 rotation scaled by 0.5 has eigenvalues 0.5 e^{±iθ}: ρ = 0.5
    th = 0.7
    R = 0.5 * np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
    assert spectral_radius(R) == pytest.approx(0.5, rel=1e-15)
    # a nilpotent matrix: every eigenvalue is 0
    assert spectral_radius(np.triu(np.ones((5, 5)), 1)) == pytest.approx(0.0, abs=1e-12)
    # a 1 x 1 matrix is its eigenvalue; the empty matrix has radius 0
    assert spectral_radius(np.array([[-3.0]])) == 3.0
    assert dense_spectral_radius(np.zeros((0, 0))) == 0.0
