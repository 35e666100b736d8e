import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from conftest import DATA, grid_disk
from qcremesh.beltrami.coefficient import beltrami_coefficient
from qcremesh.beltrami.solver import (
    beltrami_tensor,
    generalized_laplacian,
    generalized_laplacian_weights,
    linear_beltrami_solver,
)
from qcremesh.geometry import linsolve
from qcremesh.geometry.operators import cotmatrix, uniform_laplacian
from qcremesh.mesh.io import read_mesh
from qcremesh.mesh.topology import boundary_loop
from qcremesh.mesh.validate import InvalidIndexError
from qcremesh.param.tutte import tutte_embedding


def test_tensor_has_unit_determinant():
    mu = np.array([0, 0.3, -0.5j, 0.6 + 0.7j])
    a1, a2, a3 = beltrami_tensor(mu)
    np.testing.assert_allclose(a1 * a3 - a2**2, 1)
    np.testing.assert_allclose([a1[0], a2[0], a3[0]], [1, 0, 1])
    with pytest.raises(ValueError, match=r"\|mu\| < 1"):
        beltrami_tensor(np.array([1.0]))


def test_zero_mu_gives_cotmatrix():
    uv, F = grid_disk(6, jitter=0.3)
    L = generalized_laplacian(uv, F, np.zeros(len(F)))
    assert abs(L - cotmatrix(uv, F)).max() < 1e-12


def test_boolean_faces_are_refused():
    """Refused by name (numpy took them for a mask and raised that its size did not match)."""
    uv, F = grid_disk(6)
    with pytest.raises(InvalidIndexError, match="^face indices must be integers, got bool$"):
        generalized_laplacian(uv, F > 5, np.zeros(len(F)))


def test_surface_mu_gives_surface_cotmatrix():
    """With mu of the map Tutte disk -> surface (Eq. 19), Eq. 16 is the surface's own
    cotangent Laplacian: the reason Algorithm 1 yields a conformal map."""
    V, F = read_mesh(DATA / "fran_cut.ply")
    uv = tutte_embedding(F)
    L = generalized_laplacian(uv, F, beltrami_coefficient(uv, F, V))
    C = cotmatrix(V, F)
    assert abs(L - C).max() < 1e-9 * abs(C).max()


@pytest.mark.parametrize("mu", [0.0, 0.3, 0.5 - 0.4j])
def test_lbs_reproduces_affine_map(mu):
    uv, F = grid_disk(9, jitter=0.3)
    z = uv[:, 0] + 1j * uv[:, 1]
    a = 1.3 + 0.2j
    f = a * z + mu * a * np.conj(z)  # f_zbar / f_z = mu... with f_z = a, f_zbar = mu a
    b = boundary_loop(F)
    out = linear_beltrami_solver(uv, F, np.full(len(F), mu), b, f[b])
    np.testing.assert_allclose(out[:, 0] + 1j * out[:, 1], f, atol=1e-10)


def test_lbs_with_interior_landmarks_and_zero_mu_is_harmonic():
    uv, F = grid_disk(9, jitter=0.2)
    b = boundary_loop(F)
    land = np.r_[b, [40]]
    targets = np.r_[uv[b], [[0.6, 0.4]]]
    out = linear_beltrami_solver(uv, F, np.zeros(len(F)), land, targets)
    np.testing.assert_allclose(out[land], targets)
    L = cotmatrix(uv, F)
    free = np.setdiff1d(np.arange(len(uv)), land)
    np.testing.assert_allclose((L @ out)[free], 0, atol=1e-12)


def test_lbs_chops_large_mu():
    uv, F = grid_disk(6)
    b = boundary_loop(F)
    out = linear_beltrami_solver(uv, F, np.full(len(F), 1.5 + 0j), b, uv[b])
    assert np.all(np.isfinite(out))


@pytest.mark.parametrize("backend", ["superlu", "pardiso"])
def test_spd_solver_backends(backend):
    if backend == "pardiso" and linsolve._pypardiso is None:
        pytest.skip("pypardiso not installed")
    uv, F = grid_disk(8, jitter=0.2)
    L = cotmatrix(uv, F)
    b = boundary_loop(F)
    free = np.setdiff1d(np.arange(len(uv)), b)
    A = -L[free][:, free]
    solve = linsolve.spd_solver(A, backend)
    rhs = np.random.default_rng(0).normal(size=(len(free), 2)) @ np.array([1, 1j])
    x = solve(rhs)
    assert x.shape == rhs.shape and np.iscomplexobj(x)
    np.testing.assert_allclose(A @ x, rhs, atol=1e-10)
    np.testing.assert_allclose(A @ solve(rhs.real), rhs.real, atol=1e-10)
    with pytest.raises(ValueError, match="unknown solver backend"):
        linsolve.spd_solver(A, "magic")


@pytest.mark.parametrize("backend", ["superlu", "pardiso"])
def test_spd_solver_refactorize(backend):
    """Refactorizing with another matrix of the same pattern (uniform, then cotangent
    Laplacian of one mesh) solves with the new matrix; another pattern is factorized anew."""
    if backend == "pardiso" and linsolve._pypardiso is None:
        pytest.skip("pypardiso not installed")
    uv, F = grid_disk(30, jitter=0.2)
    b = boundary_loop(F)
    free = np.setdiff1d(np.arange(len(uv)), b)
    A1 = -uniform_laplacian(F)[free][:, free]
    A2 = -cotmatrix(uv, F)[free][:, free]
    rhs = np.random.default_rng(1).normal(size=(len(free), 3))
    solve = linsolve.spd_solver(A1, backend)
    np.testing.assert_allclose(A1 @ solve(rhs), rhs, atol=1e-10)
    assert solve.refactorize(A2) is solve
    np.testing.assert_allclose(A2 @ solve(rhs), rhs, atol=1e-10)
    if backend == "superlu":  # the fill-reducing ordering is kept, not lost
        fresh = spla.splu(sp.csc_matrix(A2), permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})
        assert solve._factor.lu.L.nnz <= 1.2 * fresh.L.nnz
    band = sp.diags([np.full(len(free) - 5, 0.1)] * 2, [5, -5])
    A3 = A2 + 0.5 * sp.eye(len(free)) + band
    np.testing.assert_allclose(A3 @ solve.refactorize(A3)(rhs), rhs, atol=1e-10)
    with pytest.raises(ValueError, match=r"refactorize needs a \(\d+, \d+\) matrix"):
        solve.refactorize(sp.eye(3))


def test_generalized_laplacian_weights_are_half_cotangents_for_mu_zero():
    """With mu = 0 the entry of an edge is half the cotangent of the angle opposite it."""
    uv = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    w = generalized_laplacian_weights(uv, np.array([[0, 1, 2]]), np.zeros(1, dtype=complex))
    np.testing.assert_allclose(w, [[0.5, 0.0, 0.5]], atol=1e-15)


def test_complement():
    np.testing.assert_array_equal(linsolve.complement(np.array([3, 0, 5]), 7), [1, 2, 4, 6])
