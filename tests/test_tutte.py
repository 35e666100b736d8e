import numpy as np
import pytest

from conftest import DATA, grid_disk
from qcremesh.geometry.operators import signed_doublearea, uniform_laplacian
from qcremesh.mesh.io import read_mesh
from qcremesh.mesh.topology import boundary_loop
from qcremesh.mesh.validate import InvalidIndexError
from qcremesh.param.tutte import map_vertices_to_circle, tutte_embedding


def test_map_vertices_to_circle():
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 3, 0], [0, 0, 0.0]])
    P = map_vertices_to_circle(V, [0, 1, 2])
    np.testing.assert_allclose(np.hypot(*P.T), 1)
    np.testing.assert_allclose(P[0], [1, 0])
    theta = np.angle(P[:, 0] + 1j * P[:, 1]) % (2 * np.pi)
    L = 1 + 3 + np.sqrt(10)
    np.testing.assert_allclose(theta, 2 * np.pi * np.array([0, 1, 4]) / L)
    Q = map_vertices_to_circle(None, [5, 6, 7, 8])
    np.testing.assert_allclose(Q, [[1, 0], [0, 1], [-1, 0], [0, -1]], atol=1e-15)


def test_tutte_embedding_of_real_mesh():
    V, F = read_mesh(DATA / "human_face.obj")
    uv = tutte_embedding(F)
    b = boundary_loop(F)
    np.testing.assert_allclose(np.hypot(*uv[b].T), 1, atol=1e-12)
    gaps = np.diff(np.unwrap(np.angle(uv[b, 0] + 1j * uv[b, 1])))
    np.testing.assert_allclose(gaps, 2 * np.pi / len(b))  # equal angles: fake metric
    assert np.all(signed_doublearea(uv, F) > 0)  # Tutte: bijective, orientation kept
    inner = np.setdiff1d(np.arange(len(V)), b)
    np.testing.assert_allclose((uniform_laplacian(F) @ uv)[inner], 0, atol=1e-10)


def test_tutte_embedding_takes_whole_number_floats_and_refuses_other_indices():
    """MATLAB's double indices give the same map; fractional indices (numpy's IndexError
    before) and booleans (a failed factorization before) are refused by name."""
    _, F = grid_disk(5)
    np.testing.assert_array_equal(tutte_embedding(F.astype(np.float64)), tutte_embedding(F))
    whole = r"^face indices must be whole numbers, got 96 that are not, e\.g\. 1\.5$"
    with pytest.raises(InvalidIndexError, match=whole):
        tutte_embedding(F + 0.5)
    with pytest.raises(InvalidIndexError, match=r"^face indices must be integers, got bool$"):
        tutte_embedding(F > 3)
