"""Unit tests of the relaxation stages on planar surfaces, where the answers are known."""

import numpy as np

from conftest import grid_disk
from qcremesh.adaptive.basemesh import delaunay_disk_mesh, hexagonal_disk_points
from qcremesh.geometry.locate import locate_points
from qcremesh.geometry.quality import radius_ratio
from qcremesh.mesh.topology import adjacency_matrix, boundary_loop, vertex_face_incidence
from qcremesh.remeshing.onsurface import closest_point_near
from qcremesh.remeshing.relax import relax_on_surface
from qcremesh.remeshing.snap import snap_to_far_points


def plane(k):
    """A k x k grid of the unit square at z = 0, its vertices and their own 2D positions."""
    uv, F = grid_disk(k)
    return np.column_stack([uv, np.zeros(len(uv))]), F, uv


def test_closest_point_near_on_a_plane():
    """Points above a plane project straight down, from a start face a few faces away."""
    V, F, uv = plane(11)
    P = np.array([[0.33, 0.52, 0.2], [0.71, 0.18, -0.1]])
    start = locate_points(uv, F, np.array([[0.45, 0.45], [0.6, 0.3]]))[0]
    face, closest, bary = closest_point_near(P, start, V, F, vertex_faces=vertex_face_incidence(F, len(V)))
    np.testing.assert_allclose(closest, P * [1, 1, 0], atol=1e-12)
    np.testing.assert_allclose(np.einsum("kc,kcd->kd", bary, V[F[face]]), closest, atol=1e-12)


def flat_disk(spacing):
    """A triangulation of the unit disk at z = 0 (its own disk parameterization)."""
    k = int(round(2 * np.pi / spacing))
    uv, F = delaunay_disk_mesh(2 * np.pi * np.arange(k) / k, hexagonal_disk_points(spacing))
    return np.column_stack([uv, np.zeros(len(uv))]), F, uv


def test_snap_moves_the_nearest_vertex_onto_a_tip():
    """A coarse mesh of a plane with a tip the coarse mesh cuts across: the output vertex
    nearest the tip moves onto it and is pinned; the others stay."""
    V, F, uv_in = flat_disk(0.05)
    tip = np.argmin(np.linalg.norm(uv_in - [0.125, 0.07], axis=1))  # inside an output face
    V[tip, 2] = 0.3
    X, Fo, uv = flat_disk(0.25)
    face = locate_points(uv_in, F, uv)[0]
    X = np.einsum("kc,kcd->kd", locate_points(uv_in, F, uv)[1], V[F[face]])
    pinned = np.zeros(len(X), dtype=bool)
    before = X.copy()
    A, VF = adjacency_matrix(Fo, len(X)), vertex_face_incidence(Fo, len(X))
    vertex_faces = vertex_face_incidence(F, len(V))
    snap_to_far_points(X, uv, face, Fo, A, VF, boundary_loop(Fo), pinned, V, F, uv_in, vertex_faces, 1.0)
    moved = np.flatnonzero(np.any(X != before, axis=1))
    assert len(moved) == 1 and pinned[moved[0]] and pinned.sum() == 1
    np.testing.assert_array_equal(X[moved[0]], V[tip])
    assert radius_ratio(X, Fo).min() >= 0.3


def test_min_quality_search_repairs_slivers_on_a_plane():
    """On a planar surface a mesh with needles gets every face above the search's target
    without any smoothing sweep, and stays an embedding on the surface."""
    V, F, uv_in = flat_disk(0.04)
    X, Fo, uv = flat_disk(0.2)
    rng = np.random.default_rng(0)
    inner = np.setdiff1d(np.arange(len(uv)), boundary_loop(Fo))
    uv = uv.copy()
    uv[inner] += rng.uniform(-0.06, 0.06, (len(inner), 2))
    assert radius_ratio(np.column_stack([uv, np.zeros(len(uv))]), Fo).min() < 0.3
    new_uv, new_X = relax_on_surface(uv_in, F, V, uv, Fo, iterations=0, snap=0)
    q = radius_ratio(new_X, Fo)
    assert q.min() >= 0.6
    np.testing.assert_allclose(new_X[inner, :2], new_uv[inner], atol=1e-12)
