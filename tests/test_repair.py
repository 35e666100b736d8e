import numpy as np
import pytest

from conftest import grid_disk, split_vertex
from qcremesh.geometry.operators import doublearea
from qcremesh.geometry.quality import mesh_quality, radius_ratio
from qcremesh.geometry.repair import repair_degenerate_faces
from qcremesh.geometry.distance import point_mesh_distance
from qcremesh.mesh.topology import (
    boundary_loop,
    boundary_loops,
    needles_and_caps,
    nonmanifold_edges,
    nonmanifold_vertices,
)
from qcremesh.mesh.validate import (
    DegenerateFaceError,
    NonManifoldError,
    OrientationError,
    UnreferencedVertexError,
    check_disk,
    check_triangle_mesh,
)
from qcremesh.remeshing.pipeline import remesh


def test_needles_are_merged_and_the_surface_kept():
    """Three interior vertices split in two at the same point (six faces with an edge of
    zero length, which the validation refuses): the repair merges them back, the faces
    are those of the grid again."""
    uv, F = grid_disk(10, jitter=0.3)
    V = np.column_stack([uv, 0.2 * np.sin(3 * uv[:, 0])])
    W, G = V, F
    for v in (34, 45, 56):
        W, G = split_vertex(W, G, v)
    with pytest.raises(DegenerateFaceError, match="6 degenerate faces"):
        check_triangle_mesh(W, G)
    needle, cap = needles_and_caps(W, G)
    assert needle.sum() == 6 and cap.sum() == 0
    X, H, kept = repair_degenerate_faces(W, G)
    np.testing.assert_array_equal(kept, np.arange(len(V)))
    np.testing.assert_array_equal(X, V)
    assert sorted(map(tuple, np.sort(H, 1))) == sorted(map(tuple, np.sort(F, 1)))
    check_disk(X, H)


def test_caps_are_flipped_inside_and_deleted_on_the_boundary():
    """A flat face whose corner c lies on its edge ab: inside (a diamond a d b e), ab is
    flipped with the face beyond it and c gets a fan of four faces; on the boundary (a
    triangle a b e), the face goes and the boundary runs through c. The area stays."""
    V = np.array([[0, 0, 0], [2, 0, 0], [1, 0, 0], [1, -1, 0], [1, 1, 0.0]])  # a b c d e
    F = np.array([[0, 1, 2], [1, 0, 3], [0, 2, 4], [2, 1, 4]])
    assert needles_and_caps(V, F)[1].tolist() == [True, False, False, False]
    W, G, kept = repair_degenerate_faces(V, F)
    assert len(G) == 4 and (G == 2).any(1).sum() == 4
    assert not np.any(needles_and_caps(W, G)[1])
    np.testing.assert_allclose(doublearea(W, G).sum(), 4.0)
    check_disk(W, G)
    V = V[[0, 1, 2, 4]]  # a b c e
    F = np.array([[0, 1, 2], [0, 2, 3], [2, 1, 3]])
    W, G, kept = repair_degenerate_faces(V, F)
    assert len(G) == 2 and sorted(boundary_loop(G)) == [0, 1, 2, 3]
    np.testing.assert_allclose(doublearea(W, G).sum(), 2.0)


def test_remesh_repairs_its_input():
    """remesh takes a mesh with needles (which the validation refuses), carries the
    per-vertex data of the vertices kept, and counts what it repaired."""
    uv, F = grid_disk(24, jitter=0.3)
    V = np.column_stack([uv, 0.2 * np.sin(3 * uv[:, 0])])
    W, G = V, F
    for v in (100, 150, 300):
        W, G = split_vertex(W, G, v)
    r = remesh(W, G, faces=800, data={"height": W[:, 2]})
    assert r.stats["repaired_needles"] == 6 and r.stats["repaired_caps"] == 0
    check_disk(r.V, r.F)
    np.testing.assert_allclose(r.data["height"], r.V[:, 2], atol=1e-12)
    assert abs(len(r.F) - 800) <= 40 and radius_ratio(r.V, r.F).mean() >= 0.97


def test_remesh_orients_the_faces_of_its_input():
    """A bent grid with a third of its faces reversed (which the validation refuses): the
    faces are turned back to the majority's orientation first, and the output has the
    orientation of the unspoilt grid."""
    uv, F = grid_disk(16, jitter=0.3)
    V = np.column_stack([uv, 0.2 * np.sin(3 * uv[:, 0])])
    turned = np.random.default_rng(0).random(len(F)) < 0.3
    G = F.copy()
    G[turned] = G[turned][:, ::-1]
    with pytest.raises(OrientationError):
        check_triangle_mesh(V, G)
    r = remesh(V, G, faces=400)
    assert r.stats["reoriented_faces"] == turned.sum()
    check_disk(r.V, r.F)
    # the output's normals point the same way as the grid's (up, +z, mostly)
    normals = np.cross(r.V[r.F[:, 1]] - r.V[r.F[:, 0]], r.V[r.F[:, 2]] - r.V[r.F[:, 0]])
    grid_normals = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    assert np.sign(normals[:, 2].sum()) == np.sign(grid_normals[:, 2].sum())


def test_orient_faces_refuses_a_moebius_strip():
    """The faces of a Moebius strip cannot be oriented consistently."""
    from qcremesh.mesh.topology import orient_faces

    n = 12  # vertices 0..n-1 along one rail, n..2n-1 along the other, joined with a half twist
    quads = [[i, (i + 1) % n, n + (i + 1) % n, n + i] for i in range(n - 1)] + [[n - 1, n, 0, 2 * n - 1]]
    F = np.array([f for a, b, c, d in quads for f in ([a, b, c], [a, c, d])])
    with pytest.raises(ValueError, match="not orientable"):
        orient_faces(F)


def test_remesh_drops_vertices_no_face_uses():
    """A bent grid with two stray vertices far from it, one listed first (which the
    validation refuses): remesh drops them, carries the data of the others, and gives
    the output it gives without them; the distance is measured over the surface only."""
    uv, F = grid_disk(16, jitter=0.3)
    V = np.column_stack([uv, 0.2 * np.sin(3 * uv[:, 0])])
    stray = np.array([[50.0, 50.0, 50.0]])
    W = np.vstack([stray, V, -stray])
    G = F + 1
    with pytest.raises(UnreferencedVertexError):
        check_triangle_mesh(W, G)
    r = remesh(W, G, faces=400, data={"height": W[:, 2]})
    assert r.stats["unreferenced_vertices"] == 2
    plain = remesh(V, F, faces=400, data={"height": V[:, 2]})
    np.testing.assert_array_equal(r.V, plain.V)
    np.testing.assert_array_equal(r.F, plain.F)
    np.testing.assert_array_equal(r.data["height"], plain.data["height"])
    far = mesh_quality(r.V, r.F, reference=(W, G))
    assert far["hausdorff"] == mesh_quality(r.V, r.F, reference=(V, F))["hausdorff"]


def test_remesh_splits_vertices_where_sheets_touch():
    """Two bent grids touching at one corner (a vertex whose faces form two fans, which
    the validation refuses; range scans have them): remesh splits it, one copy per grid,
    and remeshes the two pieces."""
    uv, G = grid_disk(16, jitter=0.3)
    V = np.column_stack([uv, 0.2 * np.sin(3 * uv[:, 0])])
    corner = int(np.argmax(uv.sum(1)))  # (1, 1)
    W = np.r_[V, V[1:] + V[corner] - V[0]]
    second = G + len(V) - 1
    second[G == 0] = corner
    second[(G != 0)] = G[G != 0] + len(V) - 1
    F = np.r_[G, second]
    with pytest.raises(NonManifoldError):
        check_triangle_mesh(W, F)
    r = remesh(W, F, 800)
    assert r.stats["split_vertices"] == 1 and r.stats["pieces"] == 2
    assert not len(nonmanifold_vertices(r.F)) and len(boundary_loops(r.F)) == 2
    assert radius_ratio(r.V, r.F).mean() > 0.96


def test_remesh_detaches_a_fin_on_an_edge_of_three_faces():
    """A triangle standing on an interior edge of a bent grid (an edge of three faces,
    which the validation refuses; CAD exports and pyvista's airplane.ply have them): the
    remesh detaches it there and remeshes the grid and the fin as two pieces. Where the
    fin meets the others again around both ends of the edge, the validation's error stands."""
    uv, G = grid_disk(16, jitter=0.3)
    V = np.column_stack([uv, 0.2 * np.sin(3 * uv[:, 0])])
    a, b = G[np.argmin(np.linalg.norm(uv[G].mean(1) - 0.5, axis=1)), :2]
    W = np.r_[V, [(V[a] + V[b]) / 2 + [0, 0, 0.1]]]
    F = np.r_[G, [[a, b, len(V)]]]
    with pytest.raises(NonManifoldError, match=f"^1 non-manifold edge at vertices {min(a, b)}-{max(a, b)}$"):
        check_triangle_mesh(W, F)
    r = remesh(W, F, 800)
    assert r.stats["split_edges"] == 1 and r.stats["pieces"] == 2
    assert not len(nonmanifold_edges(r.F)) and not len(nonmanifold_vertices(r.F))
    assert len(boundary_loops(r.F)) == 2
    assert point_mesh_distance(r.V, W, F)[0].max() < 1e-9
    assert radius_ratio(r.V, r.F).mean() > 0.96
    # a fin whose faces close around a face below it, joined to it at both ends of the edge
    V = np.array([[0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, -1, 0], [0.5, 0, 1]], dtype=float)
    with pytest.raises(NonManifoldError, match="^1 non-manifold edge at vertices 0-1$"):
        remesh(V, np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4], [4, 0, 3], [1, 4, 3]]), 100)

