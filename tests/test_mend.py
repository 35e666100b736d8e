import numpy as np
from scipy.spatial import Delaunay

from conftest import grid_disk
from qcremesh.mesh.topology import boundary_edges, duplicate_faces, inconsistent_edges
from qcremesh.remeshing.mend import refine_long_boundary, renumbered, repair_input, upsampled


def grid(k=6):
    uv, F = grid_disk(k)
    return np.column_stack([uv, uv[:, 0] * uv[:, 1]]), F


def test_repair_input_mends_repeats_unused_vertices_and_turned_faces_with_the_data():
    """A face listed twice, a vertex no face uses and a face turned against its
    neighbours: kept once, dropped, turned back; the data and sizing follow the vertices
    kept, and ``kept`` says which input vertex each one is."""
    V, F = grid()
    n = len(V)
    V2 = np.r_[V[:7], [[5.0, 5.0, 5.0]], V[7:]]  # an unused vertex at 7
    F2 = np.where(F >= 7, F + 1, F)
    F2 = np.r_[F2, F2[[3]]]
    F2[10] = F2[10, ::-1]
    colour = np.arange(n + 1, dtype=np.uint8)
    sizing = np.linspace(1.0, 2.0, n + 1)
    stats = {}
    W, G, data, s, kept = repair_input(V2, F2, {"c": colour}, sizing, stats)
    assert stats == {"duplicate_faces": 1, "unreferenced_vertices": 1, "reoriented_faces": 1}
    np.testing.assert_array_equal(kept, np.r_[0:7, 8 : n + 1])
    np.testing.assert_array_equal(W, V)
    assert len(G) == len(F) and not len(duplicate_faces(G)) and not len(inconsistent_edges(G))
    np.testing.assert_array_equal(data["c"], colour[kept])
    np.testing.assert_array_equal(s, sizing[kept])
    assert repair_input(V, F, None, None, {}) is None  # nothing to mend


def test_renumbered_maps_input_vertices_to_the_kept_ones():
    kept = np.array([0, 2, 3, 7])
    np.testing.assert_array_equal(renumbered([7, 0, 5, 3], kept), [3, 0, -1, 2])


def test_upsampled_splits_until_enough_and_carries_data_in_their_types():
    """Split 1-to-4 until at least 200 faces (50 -> 200): the input vertices first and
    unmoved, a colour interpolated and back in bytes, the sizing interpolated, the
    new vertices at the midpoints of the edges."""
    V, F = grid()
    colour = (255 * V[:, :1]).astype(np.uint8).repeat(3, axis=1)
    sizing = 1.0 + V[:, 0]
    W, G, data, s = upsampled(V, F, {"rgb": colour}, sizing, lambda G: len(G) >= 200)
    assert len(G) == 4 * len(F)
    np.testing.assert_array_equal(W[: len(V)], V)
    assert data["rgb"].dtype == np.uint8 and data["rgb"].shape == (len(W), 3)
    np.testing.assert_array_equal(data["rgb"][: len(V)], colour)
    np.testing.assert_allclose(s, 1.0 + W[:, 0])  # linear along the edges, as the positions
    assert np.abs(data["rgb"][:, 0].astype(float) - 255 * W[:, 0]).max() <= 1.0


def test_refine_long_boundary_cuts_only_edges_far_longer_than_those_around():
    """A flat 11 x 11 grid without the inner vertices of its bottom row: its Delaunay
    triangulation's bottom edge is 10 times as long as the others. It is cut into
    pieces as long as the edges around, the new vertices on it and the old ones
    unmoved; a grid disk is left as it is."""
    V, F = grid()
    stats = {}
    assert refine_long_boundary(V, F, None, None, stats)[1] is F and stats == {}
    g = np.linspace(0.0, 1.0, 11)
    P = np.stack(np.meshgrid(g, g), -1).reshape(-1, 2)
    P = P[(P[:, 1] > 0) | (P[:, 0] == 0) | (P[:, 0] == 1)]
    F = Delaunay(P).simplices
    a, b = P[F[:, 1]] - P[F[:, 0]], P[F[:, 2]] - P[F[:, 0]]
    F[a[:, 0] * b[:, 1] < a[:, 1] * b[:, 0]] = F[a[:, 0] * b[:, 1] < a[:, 1] * b[:, 0]][:, ::-1]
    V = np.column_stack([P, np.zeros(len(P))])
    W, G, _, _ = refine_long_boundary(V, F, None, None, stats)
    added = stats["boundary_split_vertices"]
    assert added > 0 and len(W) == len(V) + added
    np.testing.assert_array_equal(W[: len(V)], V)
    assert np.all(W[len(V) :, 1] == 0) and np.all((W[len(V) :, 0] > 0) & (W[len(V) :, 0] < 1))
    bottom = boundary_edges(G)
    bottom = bottom[(W[bottom, 1] == 0).all(1)]
    # (here back at the grid's spacing: the 9 missing vertices)
    assert added == 9 and np.abs(W[bottom[:, 0], 0] - W[bottom[:, 1], 0]).max() < 0.1 + 1e-12
