import numpy as np

from conftest import DATA, grid_disk
from qcremesh.geometry.operators import (
    cotmatrix,
    doublearea,
    face_gradients,
    face_normals,
    signed_doublearea,
    uniform_laplacian,
    vertex_areas,
)
from qcremesh.mesh.io import read_mesh
from qcremesh.mesh.topology import boundary_loop


def test_areas():
    uv = np.array([[0, 0], [2, 0], [0, 1]], float)
    F = np.array([[0, 1, 2], [0, 2, 1]])
    np.testing.assert_allclose(signed_doublearea(uv, F), [2, -2])
    np.testing.assert_allclose(doublearea(uv, F), [2, 2])
    np.testing.assert_allclose(doublearea(np.column_stack([uv, uv[:, 0]]), F[:1]), [2 * np.sqrt(2)])


def test_face_gradients_of_linear_function():
    uv, F = grid_disk(6, jitter=0.3)
    g = 3 * uv[:, 0] - 2 * uv[:, 1] + 1
    Dx, Dy = face_gradients(uv, F)
    np.testing.assert_allclose((Dx * g[F]).sum(1), 3)
    np.testing.assert_allclose((Dy * g[F]).sum(1), -2)


def test_cotmatrix_equilateral_and_linear_precision():
    V = np.array([[0, 0], [1, 0], [0.5, np.sqrt(3) / 2]])
    L = cotmatrix(V, np.array([[0, 1, 2]])).toarray()
    c = 0.5 / np.sqrt(3)
    np.testing.assert_allclose(L, [[-2 * c, c, c], [c, -2 * c, c], [c, c, -2 * c]])
    uv, F = grid_disk(7, jitter=0.3)
    L = cotmatrix(uv, F)
    inner = np.setdiff1d(np.arange(len(uv)), boundary_loop(F))
    np.testing.assert_allclose((L @ uv)[inner], 0, atol=1e-12)  # linear precision
    np.testing.assert_allclose(np.asarray(L.sum(1)).ravel(), 0, atol=1e-12)


def test_cotmatrix_dirichlet_energy_matches_area_on_surface():
    V, F = read_mesh(DATA / "fran_cut.ply")
    L = cotmatrix(V, F)
    assert abs(L - L.T).max() < 1e-12
    # -x^T L x = integral of |grad x|^2; summed over the coordinates of the embedding it
    # is the trace of the identity on the tangent plane (2) times the area
    energy = -sum(V[:, k] @ (L @ V[:, k]) for k in range(3))
    np.testing.assert_allclose(energy, doublearea(V, F).sum(), rtol=1e-10)


def test_uniform_laplacian():
    F = np.array([[0, 1, 2], [2, 1, 3]])
    L = uniform_laplacian(F).toarray()
    np.testing.assert_array_equal(np.diag(L), [-2, -3, -3, -2])
    assert L[0, 1] == 1 and L[0, 3] == 0


def test_vertex_areas_are_a_third_of_the_faces_around():
    """On a grid of the unit square every vertex gets a third of the area of the faces
    around it, and the areas sum to the square's."""
    uv, F = grid_disk(5)
    area = vertex_areas(uv, F)
    assert area.shape == (len(uv),)
    np.testing.assert_allclose(area.sum(), doublearea(uv, F).sum() / 2)
    for v in range(len(uv)):
        around = (F == v).any(axis=1)
        np.testing.assert_allclose(area[v], doublearea(uv, F[around]).sum() / 6)
    assert len(vertex_areas(uv, F, len(uv) + 2)) == len(uv) + 2


def test_vertex_normals_of_a_plane_and_a_sphere():
    from conftest import grid_disk, sphere_mesh
    from qcremesh.geometry.operators import vertex_normals
    from qcremesh.mesh.topology import vertex_face_incidence

    uv, F = grid_disk(6, jitter=0.3)
    V = np.column_stack([uv, np.zeros(len(uv))]) @ np.array([[1, 0, 0], [0, 0.6, 0.8], [0, -0.8, 0.6]])
    np.testing.assert_allclose(vertex_normals(V, F), np.tile([0, -0.8, 0.6], (len(V), 1)), atol=1e-12)
    V, F = sphere_mesh(500)
    N = vertex_normals(V, F)
    np.testing.assert_allclose(np.linalg.norm(N, axis=1), 1)
    assert (N * V).sum(1).min() > 0.95  # about radial, outwards
    np.testing.assert_array_equal(vertex_normals(V, F, vertex_face_incidence(F, len(V))), N)


def test_face_normals_are_unit_and_follow_the_corner_order():
    """A counter-clockwise triangle in the plane z = 0 has the normal +z, reversed -z, and
    a face of no area the zero vector."""
    V = np.array([[0, 0, 0], [2, 0, 0], [0, 3, 0], [4, 0, 0]], dtype=float)
    F = np.array([[0, 1, 2], [0, 2, 1], [0, 1, 3]])
    np.testing.assert_array_equal(face_normals(V, F), [[0, 0, 1], [0, 0, -1], [0, 0, 0]])
