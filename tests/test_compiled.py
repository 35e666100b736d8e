"""The compiled closest-point search, smoothing step and point-triangle distances (Numba,
extra "fast") against the NumPy ones."""

import sys

import numpy as np
import pytest
from scipy.spatial import Delaunay

from conftest import DATA
from qcremesh import read_mesh, remesh
from qcremesh.geometry import compiled as geometry_compiled
from qcremesh.geometry import distance
from qcremesh.geometry.compiled import pair_distances_kernel
from qcremesh.geometry.distance import point_mesh_distance, point_triangle_distance
from qcremesh.mesh.topology import adjacency_matrix, boundary_loop, edges, vertex_face_incidence
from qcremesh.remeshing import compiled, onsurface, smoothing
from qcremesh.remeshing.compiled import closest_point_near_kernel

pytest.importorskip("numba")


def test_compiled_search_is_the_numpy_search_to_the_last_bit():
    """On a real scan, from start faces up to several rings away (some points need all
    the rounds, some stop in their face at once, some are off the surface), the compiled
    search returns the same faces, closest points and barycentric coordinates."""
    V, F = read_mesh(DATA / "human_face.obj")
    vertex_faces = vertex_face_incidence(F, len(V))
    rng = np.random.default_rng(3)
    start = rng.integers(0, len(F), 5000)
    edge = np.linalg.norm(V[F[start, 0]] - V[F[start, 1]], axis=1)[:, None]
    P = V[F[start]].mean(1) + rng.normal(0.0, 1.0, (5000, 1)) * rng.normal(0.0, 1.0, (5000, 3)) * edge
    for rounds in (1, 4, 64):
        expected = onsurface._closest_point_near(P, start, V, F, vertex_faces, rounds)
        got = closest_point_near_kernel()(P, start, V, F, vertex_faces, rounds)
        for e, g in zip(expected, got):
            np.testing.assert_array_equal(g, e)
    assert (expected[0] != start).mean() > 0.5


def test_compiled_smoothing_step_is_the_numpy_one_to_the_last_bit():
    """On a real scan, its interior vertices moved by the relaxation's smoothing step at
    several step sizes (some clamped to a quarter of their edge length, some not): the
    compiled step gives the same targets."""
    V, F = read_mesh(DATA / "human_face.obj")
    A, E, VF = adjacency_matrix(F, len(V)), edges(F), vertex_face_incidence(F, len(V))
    verts = np.setdiff1d(np.arange(len(V)), boundary_loop(F))
    ring = A[verts]
    for step in (0.5, 1.0, 4.0):
        expected = smoothing.smooth_targets(V, verts, ring, F, VF, E, step)
        got = compiled.smooth_targets_kernel()(V, verts, ring, F, VF, E, step)
        np.testing.assert_array_equal(got, expected)
    moved = np.linalg.norm(got - V[verts], axis=1)
    reach = np.linalg.norm(V[E[:, 0]] - V[E[:, 1]], axis=1).mean()
    assert (moved > 0.2 * reach).any() and (moved < 0.1 * reach).any()


def test_remesh_is_the_same_with_and_without_the_compiled_search(monkeypatch):
    """The whole remeshing (relaxation, snapping, minimum-quality search) gives the same
    output bytes on either path."""
    V, F = read_mesh(DATA / "human_face.obj")
    fast = remesh(V, F, faces=3000)
    monkeypatch.setattr(compiled, "_state", False)
    plain = remesh(V, F, faces=3000)
    assert fast.V.tobytes() == plain.V.tobytes()
    assert fast.F.tobytes() == plain.F.tobytes()


def test_a_numba_that_cannot_be_imported_leaves_the_numpy_search(monkeypatch):
    """Numba failing to import (built for another NumPy, say): no compiled search, and
    closest_point_near gives the NumPy search's results."""
    V, F = read_mesh(DATA / "human_face.obj")
    vertex_faces = vertex_face_incidence(F, len(V))
    start = np.arange(0, len(F), 7)
    P = V[F[start]].mean(1) + 0.3 * (V[F[start, 1]] - V[F[start, 0]])
    monkeypatch.setattr(compiled, "_state", None)
    monkeypatch.setattr(geometry_compiled, "_state", None)
    monkeypatch.setitem(sys.modules, "numba", None)
    assert compiled.closest_point_near_kernel() is None
    assert compiled.smooth_targets_kernel() is None
    assert pair_distances_kernel() is None
    assert geometry_compiled.grid_nearest_kernel() is None
    got = onsurface.closest_point_near(P, start, V, F, vertex_faces)
    expected = onsurface._closest_point_near(P, start, V, F, vertex_faces, 4)
    for e, g in zip(expected, got):
        np.testing.assert_array_equal(g, e)


def test_compiled_pair_distances_are_the_numpy_ones_to_the_last_bit():
    """Points near and far from the faces of a real scan, on its vertices and edges, and
    faces made degenerate (a repeated corner, collinear corners): the compiled
    distances are those of point_triangle_distance, bit for bit."""
    V, F = read_mesh(DATA / "human_face.obj")
    F = F.astype(np.int64)
    F[:50, 2] = F[:50, 1]
    V = V.copy()
    V[F[50:100, 2]] = (V[F[50:100, 0]] + V[F[50:100, 1]]) / 2
    rng = np.random.default_rng(5)
    j = np.concatenate([np.arange(100), rng.integers(0, len(F), 20000)])
    edge = np.linalg.norm(V[F[j, 0]] - V[F[j, 1]], axis=1)[:, None]
    P = V[F[j]].mean(1) + rng.normal(0.0, 1.0, (len(j), 1)) * rng.normal(0.0, 1.0, (len(j), 3)) * edge
    P[:300] = V[F[j[:300], 0]]
    P[300:600] = (V[F[j[300:600], 0]] + V[F[j[300:600], 1]]) / 2
    i = rng.permutation(len(j))
    P = P[np.argsort(i)]
    expected = point_triangle_distance(P[i], V[F[j, 0]], V[F[j, 1]], V[F[j, 2]])[0]
    got = pair_distances_kernel()(P, V, F, i.astype(np.int64), j)
    np.testing.assert_array_equal(got, expected)
    assert np.isnan(got).sum() == 0 and (got == 0).sum() >= 300


def test_point_mesh_distance_is_the_same_without_the_compiled_distances(monkeypatch):
    """The nearest faces, distances and closest points of a remesh's samples on its input
    (the Hausdorff distance's search) do not depend on which distance code measures the
    candidates."""
    V, F = read_mesh(DATA / "human_face.obj")
    rng = np.random.default_rng(6)
    f = rng.integers(0, len(F), 20000)
    P = (V[F[f]] * rng.dirichlet([1, 1, 1], len(f))[:, :, None]).sum(1) + rng.normal(0.0, 0.3, (len(f), 3))
    fast = point_mesh_distance(P, V, F)
    monkeypatch.setattr(distance, "pair_distances_kernel", lambda: None)
    plain = point_mesh_distance(P, V, F)
    for a, b in zip(fast, plain):
        np.testing.assert_array_equal(a, b)


def test_grid_distances_are_the_search_of_balls_ones_to_the_last_bit(monkeypatch):
    """Points on a real scan's faces, vertices and edges, near it, and far from it (beyond
    the grid's shells, which the grid leaves uncertified to the search of balls): the
    distances of the grid search are those of the search of balls, compiled or not, bit
    for bit; so are a flat grid's (one cube thick) and a mesh with one face far larger
    than the rest."""
    V, F = read_mesh(DATA / "human_face.obj")
    diag = np.linalg.norm(np.ptp(V, axis=0))
    rng = np.random.default_rng(7)
    f = rng.integers(0, len(F), 20000)
    on = (V[F[f]] * rng.dirichlet([1, 1, 1], len(f))[:, :, None]).sum(1)
    P = np.r_[
        on,
        V[F[f[:2000], 0]],
        (V[F[f[:2000], 0]] + V[F[f[:2000], 1]]) / 2,
        on[:5000] + rng.normal(0.0, 0.003 * diag, (5000, 3)),
        on[:500] + rng.normal(0.0, 0.3 * diag, (500, 3)),
        rng.uniform(-5, 5, (100, 3)) * diag,
    ]
    grid = distance._distance_to_mesh(P, V, F)
    balls = distance._nearest_face(P, V, F)[0]
    np.testing.assert_array_equal(grid, balls)
    _, certified = geometry_compiled.grid_nearest_kernel()(
        P, V, F.astype(np.int64), *distance.face_grid(V, F.astype(np.int64)), distance.GRID_SHELLS
    )
    assert certified[:29000].all() and not certified[-100:].any()
    monkeypatch.setattr(distance, "pair_distances_kernel", lambda: None)
    np.testing.assert_array_equal(distance._nearest_face(P, V, F)[0], grid)
    monkeypatch.undo()
    g = np.linspace(0.0, 1.0, 30)
    uv = np.stack(np.meshgrid(g, g), -1).reshape(-1, 2)
    T = Delaunay(uv).simplices.astype(np.int64)
    flat = np.column_stack([uv, np.zeros(len(uv))])
    Q = rng.uniform(-0.5, 1.5, (3000, 3))
    np.testing.assert_array_equal(distance._distance_to_mesh(Q, flat, T), distance._nearest_face(Q, flat, T)[0])
    big = np.r_[flat, [[0.0, 0.0, 5.0], [50.0, 0.0, 5.0], [0.0, 50.0, 5.0]]]
    T2 = np.r_[T, [[len(flat), len(flat) + 1, len(flat) + 2]]]
    np.testing.assert_array_equal(distance._distance_to_mesh(Q, big, T2), distance._nearest_face(Q, big, T2)[0])


def test_point_face_distances_are_the_same_on_either_path(monkeypatch):
    """Pairs of points and faces of a real scan, in any order and with repeats: the
    distances of point_face_distances compiled and in NumPy are those of
    point_triangle_distance, bit for bit."""
    V, F = read_mesh(DATA / "human_face.obj")
    rng = np.random.default_rng(7)
    P = V[rng.integers(0, len(V), 3000)] + rng.normal(0.0, 1e-3, (3000, 3))
    i, j = rng.integers(0, len(P), 20000), rng.integers(0, len(F), 20000)
    expected = point_triangle_distance(P[i], *V[F[j]].transpose(1, 0, 2))[0]
    np.testing.assert_array_equal(distance.point_face_distances(P, V, F, i, j), expected)
    monkeypatch.setattr(geometry_compiled, "_state", False)
    assert pair_distances_kernel() is None
    np.testing.assert_array_equal(distance.point_face_distances(P, V, F, i, j), expected)
