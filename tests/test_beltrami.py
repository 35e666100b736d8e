import numpy as np
import pytest

from conftest import DATA, grid_disk
from qcremesh.beltrami.coefficient import (
    beltrami_coefficient,
    coherent_mu,
    complex_derivatives,
    compose_beltrami,
    face_to_vertex,
    mu_chop,
    vertex_to_face,
)
from qcremesh.mesh.io import read_mesh
from qcremesh.mesh.validate import InvalidIndexError
from qcremesh.param.tutte import tutte_embedding


@pytest.fixture
def mesh():
    return grid_disk(7, jitter=0.3)


def as_z(uv):
    return uv[:, 0] + 1j * uv[:, 1]


def test_affine_map_has_known_mu(mesh):
    uv, F = mesh
    z = as_z(uv)
    np.testing.assert_allclose(beltrami_coefficient(uv, F, z + 0.3 * np.conj(z)), 0.3, atol=1e-12)
    a, b = 1.5 - 0.5j, 0.2 + 0.4j
    np.testing.assert_allclose(beltrami_coefficient(uv, F, a * z + b * np.conj(z) + 7), b / a, atol=1e-12)
    f = a * z + b * np.conj(z)
    target = np.column_stack([f.real, f.imag])
    np.testing.assert_allclose(beltrami_coefficient(uv, F, target), b / a, atol=1e-12)


def test_fractional_face_indices_are_refused(mesh):
    """Refused by name (numpy's IndexError did not say which array was wrong)."""
    uv, F = mesh
    z = as_z(uv)
    with pytest.raises(InvalidIndexError, match="^face indices must be whole numbers"):
        beltrami_coefficient(uv, F + 0.5, z)


def test_conformal_map_has_zero_mu(mesh):
    uv, F = mesh
    z = as_z(uv)
    np.testing.assert_allclose(beltrami_coefficient(uv, F, (2 - 3j) * z + 1j), 0, atol=1e-12)
    # z -> z^2 is conformal; its PL interpolant has |mu| = O(h)
    mu = beltrami_coefficient(uv, F, (z + 1) ** 2)
    assert np.abs(mu).max() < 0.1


def test_fold_gives_modulus_above_one(mesh):
    uv, F = mesh
    z = as_z(uv)
    assert np.all(np.abs(beltrami_coefficient(uv, F, np.conj(z) + 0.2 * z)) > 1)


def test_surface_target_agrees_with_planar_formula(mesh):
    uv, F = mesh
    z = as_z(uv)
    f = 2 * z + (0.3 - 0.4j) * np.conj(z)
    V = np.column_stack([f.real, f.imag, np.zeros(len(f))])
    np.testing.assert_allclose(beltrami_coefficient(uv, F, V), beltrami_coefficient(uv, F, f), atol=1e-12)
    # a rigid motion of the target in R^3 leaves Eq. 19 unchanged
    R = np.linalg.qr(np.random.default_rng(1).normal(size=(3, 3)))[0]
    np.testing.assert_allclose(beltrami_coefficient(uv, F, V @ R.T + 5), beltrami_coefficient(uv, F, f), atol=1e-12)


def test_surface_target_is_below_one_on_real_mesh():
    V, F = read_mesh(DATA / "fran_cut.ply")
    mu = beltrami_coefficient(tutte_embedding(F), F, V)
    assert np.all(np.abs(mu) < 1)


def test_composition_of_affine_maps(mesh):
    uv, F = mesh
    z = as_z(uv)
    f = (1 + 0.5j) * z + 0.3 * np.conj(z)
    g = lambda w: (2 - 1j) * w + (0.1 + 0.6j) * np.conj(w)
    mu_f = beltrami_coefficient(uv, F, f)
    fz, _ = complex_derivatives(uv, F, f)
    fuv = np.column_stack([f.real, f.imag])
    mu_g = beltrami_coefficient(fuv, F, g(f))
    np.testing.assert_allclose(compose_beltrami(mu_f, fz, mu_g), beltrami_coefficient(uv, F, g(f)), atol=1e-12)
    # g with the coefficient of f^{-1} undoes the distortion: g o f is conformal (Algorithm 1)
    mu_finv = beltrami_coefficient(fuv, F, z)
    np.testing.assert_allclose(compose_beltrami(mu_f, fz, mu_finv), 0, atol=1e-12)


def test_mu_chop():
    mu = np.array([0.5, 1.2j, -3.0, np.nan, 0.0])
    out = mu_chop(mu, bound=1.0, value=0.9)
    np.testing.assert_allclose(out, [0.5, 0.9j, -0.9, 0.9, 0.0])
    assert mu[1] == 1.2j  # input untouched


def test_face_vertex_transfer():
    F = np.array([[0, 1, 2], [2, 1, 3]])
    np.testing.assert_allclose(face_to_vertex(F, np.array([1.0, 3.0])), [1, 2, 2, 3])
    np.testing.assert_allclose(vertex_to_face(F, np.array([0.0, 3, 6, 9])), [3, 6])


def test_coherent_mu_cancels_random_arguments_and_keeps_a_stretch():
    """A Beltrami coefficient of modulus 0.3 and random argument per face (what a
    conformal map has on skinny triangles) averages out around the vertices; the same
    modulus with one argument (a stretch) stays 0.3 everywhere."""
    _, F = grid_disk(20)
    n = F.max() + 1
    phase = np.random.default_rng(0).uniform(0, 2 * np.pi, len(F))
    assert coherent_mu(F, 0.3 * np.exp(1j * phase), n, 3).mean() < 0.06
    np.testing.assert_allclose(coherent_mu(F, np.full(len(F), 0.3 * np.exp(0.5j)), n, 3), 0.3)
