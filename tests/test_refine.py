import numpy as np
import pytest
from scipy.spatial import Delaunay

from conftest import cad_trough, grid_disk
from qcremesh.geometry.distance import point_mesh_distance
from qcremesh.geometry.intrinsic import intrinsic_delaunay, negative_cotangent_weights
from qcremesh.geometry.operators import doublearea, signed_doublearea
from qcremesh.geometry.quality import radius_ratio
from qcremesh.geometry.refine import local_edge_length, refine_boundary, split_edges, split_long_edges
from qcremesh.mesh.topology import (
    boundary_edges,
    edges,
    euler_characteristic,
    face_edge_lengths,
    needles_and_caps,
    nonmanifold_edges,
)


def scattered(n=3000, aspect=3.0, seed=2, height=None):
    """Delaunay triangulation of random points of an aspect:1 rectangle (its boundary:
    the convex hull, a few dozen edges), flat or lifted to a height field."""
    P = np.random.default_rng(seed).random((n, 2)) * [aspect, 1.0]
    F = Delaunay(P).simplices
    z = np.zeros(n) if height is None else height(P)
    return np.column_stack([P, z]), F


def test_local_edge_length_of_a_grid():
    uv, F = grid_disk(11)
    V = np.column_stack([uv, np.zeros(len(uv))])
    np.testing.assert_allclose(local_edge_length(V, F, [[0.5, 0.5, 0.0], [0.0, 0.0, 0.0]]), 0.1)


def test_split_edges_keeps_the_surface():
    """Boundary edges in thirds and the interior edges of one row in halves: the new
    vertices on their edges, the old ones first, the surface, its area and orientation
    as before."""
    uv, F = grid_disk(6)
    V = np.column_stack([uv, uv[:, 0] * uv[:, 1]])
    E = edges(F)
    B = np.sort(boundary_edges(F), axis=1)
    boundary = (E[:, None, :] == B[None]).all(2).any(1)
    row = ~boundary & (np.abs(V[E, 1].mean(1) - 0.5) < 0.05)
    count = np.where(boundary, 3, np.where(row, 2, 1))
    F2, P = split_edges(F, len(V), count)
    V2 = P @ V
    assert len(V2) == len(V) + (count - 1).sum() and len(boundary_edges(F2)) == 3 * len(B)
    np.testing.assert_array_equal(V2[: len(V)], V)
    expected = [(1 - t) * V[a] + t * V[b] for (a, b), k in zip(E, count) for t in np.arange(1, k) / k]
    np.testing.assert_allclose(V2[len(V):], expected, atol=1e-15)
    np.testing.assert_allclose(doublearea(V2[:, :2], F2).sum(), doublearea(uv, F).sum())
    assert (signed_doublearea(uv, F) > 0).all() and (signed_doublearea(V2[:, :2], F2) > 0).all()
    assert euler_characteristic(F2) == 1 and len(nonmanifold_edges(F2)) == 0


def test_split_long_edges_turns_cad_strips_into_ladders():
    """The needles of a CAD quarter cylinder (radius ratio 0.016), cut to pieces about as
    long as a strip is wide: every vertex on the facets, no edge longer than asked, and
    well-shaped triangles."""
    V, F = cad_trough()
    width = np.linalg.norm(V[1] - V[0])
    assert radius_ratio(V, F).max() < 0.02
    F2, P = split_long_edges(V, F, 1.25 * width)
    V2 = P @ V
    np.testing.assert_array_equal(V2[: len(V)], V)
    assert face_edge_lengths(V2, F2).max() <= 1.25 * width
    # (the chords of a facet lie inside the cylinder; its area is the facets')
    np.testing.assert_allclose(doublearea(V2, F2).sum(), doublearea(V, F).sum())
    assert point_mesh_distance(V2, V, F)[0].max() < 1e-12
    assert radius_ratio(V2, F2).min() > 0.6
    assert euler_characteristic(F2) == 1 and len(nonmanifold_edges(F2)) == 0


def test_split_long_edges_fills_a_large_flat_face():
    """A square of two triangles to edges of a tenth of its side: its border cut, then the
    inside halved and flipped until no edge is longer; Delaunay, with no needle."""
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float)
    F = np.array([[0, 1, 2], [0, 2, 3]])
    F2, P = split_long_edges(V, F, 0.1)
    V2 = P @ V
    assert face_edge_lengths(V2, F2).max() <= 0.1
    np.testing.assert_allclose(doublearea(V2, F2).sum(), 2.0)
    assert (signed_doublearea(V2[:, :2], F2) > 0).all()
    assert intrinsic_delaunay(V2, F2)[3] == 0 and radius_ratio(V2, F2).min() > 0.25
    with pytest.raises(ValueError, match="max_length must be positive, got 0"):
        split_long_edges(V, F, 0)


def test_refine_boundary_of_a_scattered_point_set():
    """The hull's edges, tens of times longer than those inside, cut to the inside's
    length, and the flat mesh flipped to the Delaunay triangulation of its points: no
    cap left, every interior edge's opposite angles summing to at most pi."""
    V, F = scattered()
    B = boundary_edges(F)
    ratio = np.linalg.norm(V[B[:, 0]] - V[B[:, 1]], axis=1) / local_edge_length(V, F, V[B].mean(1))
    assert ratio.max() > 20
    F2, P = refine_boundary(V, F)
    V2 = P @ V
    B2 = boundary_edges(F2)
    assert len(B2) > 5 * len(B)
    local = local_edge_length(V, F, V2[B2].mean(1))
    assert (np.linalg.norm(V2[B2[:, 0]] - V2[B2[:, 1]], axis=1) <= 4 * local).all()
    np.testing.assert_allclose(doublearea(V2, F2).sum(), doublearea(V, F).sum(), rtol=1e-12)
    assert (signed_doublearea(V2[:, :2], F2) > 0).all()
    assert euler_characteristic(F2) == 1 and len(nonmanifold_edges(F2)) == 0
    assert not needles_and_caps(V2, F2)[1].any()
    assert negative_cotangent_weights(V2, F2) == 0
    assert negative_cotangent_weights(V, F) == 0  # (the input was Delaunay too: its slivers are on the hull)


def test_refine_boundary_leaves_what_it_cannot_mend():
    # edges no longer than the others: nothing to do
    uv, F = grid_disk(8)
    assert refine_boundary(np.column_stack([uv, uv[:, 0] ** 2]), F) == (None, None)
    # a height field whose boundary faces span its dips and rises: fans would stay fans
    V, F = scattered(height=lambda P: 0.05 * np.sin(23 * P[:, 0] + 11 * P[:, 1]))
    assert refine_boundary(V, F) == (None, None)
