import numpy as np
from scipy.spatial import Delaunay

from conftest import grid_disk
from qcremesh.geometry.intrinsic import negative_cotangent_weights
from qcremesh.geometry.operators import doublearea, signed_doublearea
from qcremesh.geometry.refine import local_edge_length, refine_boundary, split_boundary_edges
from qcremesh.mesh.topology import boundary_edges, euler_characteristic, needles_and_caps, nonmanifold_edges


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


def test_split_boundary_edges_keeps_the_surface():
    uv, F = grid_disk(6)
    V = np.column_stack([uv, uv[:, 0] * uv[:, 1]])
    B = boundary_edges(F)

    def thirds(E):
        return np.where(np.linalg.norm(X[E[:, 0]] - X[E[:, 1]], axis=1) > 0.15, 3, 1)

    X = V
    F1, P1 = split_boundary_edges(F, len(V), thirds)
    # the four corner faces have two boundary edges each, and take one per call
    assert len(P1 @ V) == len(V) + 2 * (len(B) - 4)
    X = P1 @ V
    F2, P2 = split_boundary_edges(F1, len(X), thirds)
    P = P2 @ P1
    V2 = P @ V
    assert len(V2) == len(V) + 2 * len(B) and len(boundary_edges(F2)) == 3 * len(B)
    np.testing.assert_array_equal(V2[: len(V)], V)
    # the new vertices at 1/3 and 2/3 of the edges, the area and orientation as before
    np.testing.assert_allclose(doublearea(V2, F2).sum(), doublearea(V, F).sum())
    assert (signed_doublearea(uv, F) > 0).all() and (signed_doublearea(V2[:, :2], F2) > 0).all()
    assert euler_characteristic(F2) == 1 and len(nonmanifold_edges(F2)) == 0
    ends = V[B]
    on_edge = [((V2[len(V):] - (1 - t) * e[0] - t * e[1]) ** 2).sum(1).min() for e in ends for t in (1 / 3, 2 / 3)]
    assert max(on_edge) < 1e-24


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
