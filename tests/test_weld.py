import numpy as np
import pytest

from conftest import grid_disk
from qcremesh.mesh.cut import coincident_pairs
from qcremesh.mesh.subdivide import upsample
from qcremesh.remeshing.cut_paths import split_pieces
from qcremesh.remeshing.weld import WELD_TOLERANCE, crack_hint, weld_levels, weld_tolerance


def cracked_grid():
    """A 6 x 6 grid disk whose faces right of x = 0.4 have their own copies of the
    vertices on that line: a crack from bottom to top, two pieces."""
    uv, F = grid_disk(6)
    V = np.column_stack([uv, np.zeros(len(uv))])
    on_line = np.flatnonzero(np.isclose(uv[:, 0], 0.4))
    right = V[F].mean(1)[:, 0] > 0.4
    copy = np.full(len(V), -1)
    copy[on_line] = len(V) + np.arange(len(on_line))
    G = F.copy()
    G[right] = np.where(copy[F[right]] >= 0, copy[F[right]], F[right])
    return np.r_[V, V[on_line]], G, on_line


def test_split_pieces_gives_each_piece_its_vertices_and_renumbered_faces():
    V, F, _ = cracked_grid()
    label = (V[F].mean(1)[:, 0] > 0.4).astype(np.int64)
    pieces = split_pieces(F, label, 2)
    assert len(pieces) == 2
    for k, (used, local) in enumerate(pieces):
        assert np.all(np.diff(used) > 0)  # sorted, each once
        np.testing.assert_array_equal(used[local], F[label == k])  # the faces, in their order


def test_coincident_pairs_and_the_crack_hint():
    """The crack's two sides are pairs of vertices at the same points; the hint counts
    them among the boundary vertices; a disk without one gets no hint."""
    V, F, on_line = cracked_grid()
    pairs = coincident_pairs(V, np.arange(len(V)))
    copies = len(V) - len(on_line) + np.arange(len(on_line))
    assert sorted(map(tuple, np.sort(pairs, axis=1).tolist())) == list(zip(on_line.tolist(), copies.tolist()))
    # the grid's 20 border vertices, the 4 inner ones of the crack and their 6 copies
    assert crack_hint(V, F) == (
        " (12 of its 30 boundary vertices lie at the same points as others: "
        "cracks between faces whose shared corners are not one vertex, or seams written twice; weld_seams=True "
        "(--weld-seams) merges them first)"
    )
    uv, G = grid_disk(6)
    assert crack_hint(np.column_stack([uv, np.zeros(len(uv))]), G) == ""


def test_weld_tolerance_is_a_fraction_of_the_mean_boundary_edge():
    uv, F = grid_disk(5)  # boundary edges 0.25 long
    assert weld_tolerance(np.column_stack([uv, np.zeros(len(uv))]), F) == pytest.approx(0.25 * WELD_TOLERANCE)


def merge_coincident(X, F, tol):
    """A join: vertices within ``tol`` of each other merged into the first."""
    pairs = coincident_pairs(X, np.arange(len(X)))
    target = np.arange(len(X))
    target[pairs.max(1)] = pairs.min(1)
    kept, inverse = np.unique(target, return_inverse=True)
    return X[kept], inverse[F], kept


def test_weld_levels_keeps_the_levels_that_join_into_the_topology_asked_for():
    """The cracked grid and its 1-to-4 split, both welded into one disk (Euler
    characteristic 1, one boundary loop): both levels kept. Where the coarse level does
    not join, the hierarchy starts above it; where the output level does not, None;
    asked for another topology, None too."""
    V, F, _ = cracked_grid()
    fine = upsample(V, F, 1)
    (X, G, kept), hierarchy = weld_levels([(V, F), fine], merge_coincident, 1, 1)
    assert len(hierarchy) == 2 and len(X) == 11 * 11 and len(G) == len(fine[1])
    assert [len(level[0]) for level in hierarchy] == [36, 121]

    def coarse_fails(X, F, tol):
        if len(X) == len(V):
            raise ValueError("no weld")
        return merge_coincident(X, F, tol)

    (_, G2, _), hierarchy = weld_levels([(V, F), fine], coarse_fails, 1, 1)
    assert len(hierarchy) == 1 and np.array_equal(hierarchy[0][1], G2)
    assert weld_levels([(V, F), fine], lambda X, F, tol: (X, F, np.arange(len(X))), 1, 1) is None  # two loops
    assert weld_levels([(V, F), fine], merge_coincident, 2, 0) is None


def test_weld_levels_refuses_faces_collapsed_or_back_to_back():
    """A tetrahedron asked for, with chi 2 and manifold edges, but joined into two faces
    on the same three vertices (back to back), or into faces with a corner twice (a
    closed piece asked for 4 faces came out as [[1, 1, 0], [1, 1, 2]]): no weld."""
    X = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    tetra = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
    level = (X, tetra[:3])  # (what the join closes: a disk)
    (_, G, _), _ = weld_levels([level], lambda X, F, tol: (X, tetra, np.arange(4)), 2, 0)
    np.testing.assert_array_equal(G, tetra)
    for faces in ([[0, 1, 2], [0, 2, 1]], [[1, 1, 0], [1, 1, 2]]):
        assert weld_levels([level], lambda X, F, tol: (X[:3], np.array(faces), np.arange(3)), 2, 0) is None
