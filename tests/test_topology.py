import numpy as np

from conftest import DATA, grid_disk
from qcremesh.mesh.io import read_mesh
from qcremesh.mesh import topology as t


def test_edges_and_counts():
    F = np.array([[0, 1, 2], [2, 1, 3]])
    E, c = t.edge_face_counts(F)
    np.testing.assert_array_equal(E, [[0, 1], [0, 2], [1, 2], [1, 3], [2, 3]])
    np.testing.assert_array_equal(c, [1, 1, 2, 1, 1])
    np.testing.assert_array_equal(t.edges(F), E)


def test_boundary_loop_of_grid_is_ccw_and_ordered():
    uv, F = grid_disk(6)
    (loop,) = t.boundary_loops(F)
    assert len(loop) == 20 and loop[0] == loop.min()
    z = uv[loop, 0] + 1j * uv[loop, 1]
    signed = 0.5 * np.sum((np.conj(z) * np.roll(z, -1)).imag)
    assert signed > 0  # counter-clockwise
    assert np.allclose(np.abs(np.diff(np.r_[z, z[0]])), 0.2)  # consecutive neighbours


def test_boundary_loops_with_holes():
    uv, F = grid_disk(9)
    centers = uv[F].mean(1)
    hole = lambda c, r: np.linalg.norm(centers - c, axis=1) < r
    F = F[~(hole([0.3, 0.3], 0.1) | hole([0.7, 0.7], 0.1))]
    loops = t.boundary_loops(F)
    assert len(loops) == 3
    assert sum(len(l) for l in loops) == len(t.boundary_edges(F))
    assert t.euler_characteristic(F) == -1


def test_components_and_euler():
    F = np.array([[0, 1, 2], [3, 4, 5], [3, 5, 6]])
    count, label = t.connected_components(F)
    assert count == 2
    np.testing.assert_array_equal(label, [0, 1, 1])
    assert t.euler_characteristic(F) == 2


def test_nonmanifold_edge_and_vertex():
    fin = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    np.testing.assert_array_equal(t.nonmanifold_edges(fin), [[0, 1]])
    bowtie = np.array([[0, 1, 2], [0, 3, 4]])
    np.testing.assert_array_equal(t.nonmanifold_vertices(bowtie), [0])
    uv, F = grid_disk(5)
    assert len(t.nonmanifold_vertices(F)) == 0 and len(t.nonmanifold_edges(F)) == 0


def test_split_nonmanifold_vertices_gives_each_fan_a_vertex():
    """Two grids touching at one corner (a bow tie): the corner gets a copy for each
    grid, in the order of the vertex it copies; nothing else changes."""
    uv, G = grid_disk(4)
    F = np.r_[G, G + 15]  # the second grid's corner 0 is the first's corner 15
    assert list(t.nonmanifold_vertices(F)) == [15]
    S, parent = t.split_nonmanifold_vertices(F)
    assert len(t.nonmanifold_vertices(S)) == 0 and len(parent) == 32
    np.testing.assert_array_equal(parent[S], F)
    np.testing.assert_array_equal(parent, np.r_[np.arange(16), 15, np.arange(16, 31)])
    assert t.connected_components(S)[0] == 2 and t.connected_components(F)[0] == 1


def test_split_nonmanifold_edges_detaches_the_sheet_that_turns_most():
    """Three faces on edge 0-1: the two in the plane, which traverse it in opposite
    directions, stay joined; the fin above them comes off with copies of 0 and 1. Where
    the fin meets the others again around both ends, the edge stays non-manifold."""
    V = np.array([[0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, -1, 0], [0.5, 0, 1]], dtype=float)
    F = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    S, parent = t.split_nonmanifold_edges(V, F)
    np.testing.assert_array_equal(parent, [0, 0, 1, 1, 2, 3, 4])
    np.testing.assert_array_equal(parent[S], F)
    np.testing.assert_array_equal(S, [[0, 2, 4], [2, 0, 5], [1, 3, 6]])
    assert not len(t.nonmanifold_edges(S)) and t.connected_components(S)[0] == 2
    # two faces could join the first: the one nearer its plane does
    below, flat = [[1, 0, 3], [1, 0, 4]], [0.5, -1, 0.1]
    for W, detached in ((np.r_[V[:3], [[0.5, -0.2, -1], flat]], 1), (np.r_[V[:3], [flat, [0.5, -0.2, -1]]], 2)):
        S, parent = t.split_nonmanifold_edges(W, np.r_[[[0, 1, 2]], below])
        assert t.connected_components(S)[0] == 2 and not len(t.nonmanifold_edges(S))
        assert not np.isin(S[detached], S[[0, 3 - detached]]).any()
    closed = np.r_[F, [[4, 0, 3], [1, 4, 3]]]
    S, parent = t.split_nonmanifold_edges(V, closed)
    np.testing.assert_array_equal(S, closed)
    np.testing.assert_array_equal(t.nonmanifold_edges(S), [[0, 1]])


def test_orientation_unreferenced_degenerate():
    F = np.array([[0, 1, 2], [1, 2, 3]])
    np.testing.assert_array_equal(t.inconsistent_edges(F), [[1, 2]])
    assert len(t.inconsistent_edges(np.array([[0, 1, 2], [2, 1, 3]]))) == 0
    np.testing.assert_array_equal(t.unreferenced_vertices(F, 6), [4, 5])
    V = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0]], float)
    np.testing.assert_array_equal(t.degenerate_faces(V, np.array([[0, 1, 2], [0, 1, 3], [0, 0, 3]])), [0, 2])


def test_checks_from_twin_half_edges_agree():
    """Given the twin half-edges, the edge checks and the boundary loops are those found
    without them: on a grid with holes, a fin of four faces on one edge, bow-ties and
    faces turned over (inconsistent_edges takes them on edge-manifold meshes)."""
    uv, F = grid_disk(9)
    centers = uv[F].mean(1)
    holed = F[np.linalg.norm(centers - 0.3, axis=1) > 0.15]
    turned = holed.copy()
    turned[[3, 40, 41]] = turned[[3, 40, 41], ::-1]
    fin = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4], [1, 0, 5], [2, 1, 6]])
    bowties = np.r_[holed, [[100, 101, 102], [100, 103, 104], [0, 101, 105]]]
    for F in (holed, turned, fin, bowties):
        twins = t.twin_half_edges(F)
        np.testing.assert_array_equal(t.nonmanifold_edges(F, twins), t.nonmanifold_edges(F))
        np.testing.assert_array_equal(t.nonmanifold_vertices(F, twins), t.nonmanifold_vertices(F))
        np.testing.assert_array_equal(t.boundary_edges(F, twins), t.boundary_edges(F))
    for F in (holed, turned):
        twins = t.twin_half_edges(F)
        np.testing.assert_array_equal(t.inconsistent_edges(F, twins), t.inconsistent_edges(F))
        for a, b in zip(t.boundary_loops(F, twins), t.boundary_loops(F)):
            np.testing.assert_array_equal(a, b)
    assert len(t.inconsistent_edges(turned)) > 0 and len(t.nonmanifold_edges(fin)) == 1


def test_adjacency_matrix():
    F = np.array([[0, 1, 2], [2, 1, 3]])
    A = t.adjacency_matrix(F).toarray()
    assert (A == A.T).all() and A.sum() == 10 and A[0, 3] == 0


def test_unique_integers_matches_numpy():
    a = np.random.default_rng(0).integers(0, 50, size=(40, 3))
    np.testing.assert_array_equal(t.unique_integers(a), np.unique(a))
    assert t.unique_integers(np.zeros(0, dtype=np.int64)).shape == (0,)


def test_edge_pairs_packed_and_argsort_paths_agree():
    """Positions of equal keys, paired with the next equal one; the fast packed sort and
    the argsort used when key * len would overflow give the same pairs."""
    key = np.array([5, 3, 5, 7, 3, 5])
    i, j = t._edge_pairs(key)
    assert sorted(zip(i.tolist(), j.tolist())) == [(0, 2), (1, 4), (2, 5)]
    big = key + 2**62
    i2, j2 = t._edge_pairs(big)
    assert sorted(zip(i2.tolist(), j2.tolist())) == [(0, 2), (1, 4), (2, 5)]


def test_twin_half_edges():
    """Two triangles sharing the edge (1, 2): that edge's two half-edges, one in each face."""
    F = np.array([[0, 1, 2], [2, 1, 3]])
    H = t.half_edges(F)
    i, j = t.twin_half_edges(F)
    assert len(i) == len(j) == 1
    assert sorted(H[i[0]]) == sorted(H[j[0]]) == [1, 2] and {i[0] % 2, j[0] % 2} == {0, 1}


def test_orient_faces_reverses_the_minority():
    """A grid with 30 % of its faces reversed: exactly those are turned back; with 70 %
    reversed, the others are (the majority's orientation wins)."""
    from conftest import grid_disk

    _, F = grid_disk(8)
    turned = np.random.default_rng(0).random(len(F)) < 0.3
    G = F.copy()
    G[turned] = G[turned][:, ::-1]
    H, reversed_ = t.orient_faces(G)
    np.testing.assert_array_equal(reversed_, turned)
    np.testing.assert_array_equal(H, F)
    H, reversed_ = t.orient_faces(np.where(turned[:, None], F, F[:, ::-1]))
    np.testing.assert_array_equal(reversed_, turned)
    np.testing.assert_array_equal(H, F[:, ::-1])


def test_adjacency_matrix_has_a_one_on_every_edge_both_ways():
    """On a scan with a boundary (its edges counted once or twice by the faces) and with
    more vertices than the faces use: ones exactly on the edges, in both directions, in
    canonical CSR form, the last vertex an empty row."""
    V, F = read_mesh(DATA / "human_face.obj")
    E = t.edges(F)
    A = t.adjacency_matrix(F, len(V) + 1)
    assert A.shape == (len(V) + 1, len(V) + 1) and A.has_canonical_format
    assert A.nnz == 2 * len(E) and np.all(A.data == 1.0)
    assert np.all(A[E[:, 0], E[:, 1]] == 1.0) and np.all(A[E[:, 1], E[:, 0]] == 1.0)
    assert A[len(V)].nnz == 0


def test_genus():
    from conftest import grid_disk, holed_disk, sphere_mesh, torus_mesh
    from qcremesh.mesh.topology import genus

    V, F = sphere_mesh(200)
    assert genus(F) == 0
    assert genus(torus_mesh()[1]) == 1
    assert genus(torus_mesh()[1][1:]) == 1  # a torus with a hole
    assert genus(grid_disk(5)[1]) == 0
    G = holed_disk()[1]
    assert genus(G) == 0 and genus(G[:, ::-1]) == 0  # whatever the orientation
    assert genus(np.concatenate([F, F + len(V)])) is None  # two pieces


def test_repeated_corner_faces():
    """A vertex at two corners, in any position, marks the face; three distinct do not."""
    F = np.array([[0, 1, 2], [3, 3, 4], [5, 6, 5], [7, 8, 8], [9, 9, 9]])
    np.testing.assert_array_equal(t.repeated_corner_faces(F), [False, True, True, True, True])
    assert t.repeated_corner_faces(np.zeros((0, 3), dtype=int)).shape == (0,)
