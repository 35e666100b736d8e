import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components as graph_components
from scipy.sparse.csgraph import floyd_warshall

from conftest import (
    DATA,
    cad_cylinder,
    grid_cells,
    grid_disk,
    holed_disk,
    shapes,
    shared,
    sphere_mesh,
    torus_mesh,
    uv_sphere,
)
from qcremesh.adaptive.sizing import curvature_sizing
from qcremesh.geometry.distance import point_mesh_distance
from qcremesh.geometry.operators import doublearea
from qcremesh.geometry.quality import mesh_quality, radius_ratio
from qcremesh.mesh.io import read_mesh
from qcremesh.mesh.cut import (
    boundary_is_seams,
    chord_across,
    coincident_boundary_pairs,
    cut_along_edges,
    cut_to_disk,
    edge_paths,
    path_edges,
    path_from_tree,
    paths_across,
    paths_to_boundary,
    points_on_segments,
    shortest_edge_path,
    weld_along_paths,
    weld_cut,
    weld_seams,
)
from qcremesh.mesh.topology import (
    boundary_edges,
    boundary_loop,
    boundary_loops,
    connected_components,
    edges,
    euler_characteristic,
    nonmanifold_edges,
    nonmanifold_vertices,
)
from qcremesh.mesh.validate import MeshError, TopologyError, check_disk
from qcremesh.remeshing.pipeline import remesh


def test_shortest_edge_path_follows_edges_and_is_shortest():
    uv, F = grid_disk(6)
    V = np.column_stack([uv, np.zeros(len(uv))])
    a, b = 0, len(V) - 1  # opposite corners of the square
    path = shortest_edge_path(V, F, a, b)
    assert path[0] == a and path[-1] == b
    E = {tuple(e) for e in edges(F)}
    assert all(tuple(sorted(p)) in E for p in zip(path[:-1], path[1:]))
    # as long as the shortest path by Floyd and Warshall's algorithm
    E = edges(F)
    length = np.linalg.norm(V[E[:, 0]] - V[E[:, 1]], axis=1)
    G = sp.csr_matrix((length, (E[:, 0], E[:, 1])), shape=(len(V), len(V)))
    shortest = floyd_warshall(G, directed=False)[a, b]
    assert np.isclose(np.linalg.norm(np.diff(V[path], axis=0), axis=1).sum(), shortest, rtol=1e-12)


def test_path_from_tree_walks_from_the_root_to_the_end():
    # a tree of 6 vertices rooted at 0: 0 - 1 - 2 - 3 and 1 - 4 - 5
    previous = np.array([-9999, 0, 1, 2, 1, 4])
    np.testing.assert_array_equal(path_from_tree(previous, 5), [0, 1, 4, 5])
    np.testing.assert_array_equal(path_from_tree(previous, 3), [0, 1, 2, 3])
    np.testing.assert_array_equal(path_from_tree(previous, 0), [0])
    assert path_from_tree(previous, 5).dtype == np.int64


def test_cut_along_edges_opens_a_sphere_into_a_disk_and_weld_closes_it():
    V, F = sphere_mesh()
    path = shortest_edge_path(V, F, int(np.argmin(V[:, 2])), int(np.argmax(V[:, 2])))
    F_cut, parent = cut_along_edges(F, path_edges([path]))
    # the path's interior vertices are copied, its two ends (one fan each) not
    assert len(F_cut) == len(F) and len(parent) == len(V) + len(path) - 2
    np.testing.assert_array_equal(np.sort(parent[len(V):]), np.sort(path[1:-1]))
    np.testing.assert_array_equal(parent[F_cut], F)  # the same faces, some on copies
    loop = check_disk(V[parent], F_cut)
    assert len(loop) == 2 * (len(path) - 1)
    X, F_back, kept = weld_cut(V[parent], F_cut, V[path_edges([path])], 1e-12)
    assert len(X) == len(V) and not len(boundary_edges(F_back)) and euler_characteristic(F_back) == 2
    np.testing.assert_array_equal(parent[kept][F_back], F)


def test_weld_cut_drops_ears_folded_onto_each_other():
    """A grid cut along a path, each side given an ear at the same place (a triangle of
    three consecutive vertices of the path, its middle one on that ear alone): welded,
    the two ears would be one face twice over an edge of four faces; both go, with the
    middle vertices, and the grid is whole again."""
    uv, F = grid_disk(9)
    V = np.column_stack([uv, np.zeros(len(uv))])
    a = int(np.flatnonzero(np.isclose(uv[:, 0], 0) & np.isclose(uv[:, 1], 0.5))[0])
    b = int(np.flatnonzero(np.isclose(uv[:, 0], 1) & np.isclose(uv[:, 1], 0.5))[0])
    (path,) = paths_across(V, F, [[a, b]])
    F_cut, parent = cut_along_edges(F, path_edges([path]), len(V))
    X = V[parent]
    # an ear on each side: a vertex at the midpoint of a path edge, with one face each
    i, j = path[3], path[4]
    mid = (V[i] + V[j]) / 2
    sides = [np.flatnonzero(parent == i), np.flatnonzero(parent == j)]
    ears = []
    for side in range(2):
        p, q = sides[0][side], sides[1][side]
        ears.append([p, q, len(X) + side] if side == 0 else [q, p, len(X) + side])
    X = np.r_[X, mid[None], mid[None]]
    G = np.r_[F_cut, ears]
    Xw, Gw, kept = weld_cut(X, G, np.stack([V[path[:-1]], V[path[1:]]], axis=1), 1e-9)
    assert len(Xw) == len(V) and len(Gw) == len(F)
    assert euler_characteristic(Gw) == 1 and len(boundary_loops(Gw)) == 1 and not len(nonmanifold_edges(Gw))


def test_cut_along_edges_splits_a_vertex_into_one_copy_per_fan():
    """A closed loop of edges around a grid's centre cuts the disk in two; a path from
    the boundary to the boundary too, copying its ends."""
    uv, F = grid_disk(7)
    ring = np.array([8, 9, 10, 11, 12, 19, 26, 33, 40, 39, 38, 37, 36, 29, 22, 15, 8])  # the square 1..5
    F_cut, parent = cut_along_edges(F, path_edges([ring]))
    assert len(parent) == len(uv) + 16 and len(boundary_loops(F_cut)) == 3
    assert connected_components(F_cut)[0] == 2
    across = np.arange(3, 46, 7)  # column 3, from the bottom border to the top
    F_cut, parent = cut_along_edges(F, path_edges([across]))
    assert len(parent) == len(uv) + len(across) and connected_components(F_cut)[0] == 2


def test_cut_to_disk_joins_the_loops_into_a_tree_and_weld_closes_them():
    V, F = holed_disk(holes=((0.3, 0.3, 0.12), (0.7, 0.6, 0.15), (0.3, 0.75, 0.1)))
    loops = boundary_loops(F)
    assert len(loops) == 4
    F_cut, parent, cut = cut_to_disk(V, F)
    np.testing.assert_array_equal(parent[F_cut], F)
    check_disk(V[parent], F_cut)  # one loop, Euler characteristic 1
    # three paths through interior vertices of no other, each between two loops, which
    # they join into a tree: the cut's vertices of degree 1 are on the loops
    degree = np.bincount(cut.ravel(), minlength=len(V))
    assert set(np.bincount(degree)[1:].nonzero()[0] + 1) == {1, 2}
    assert np.sum(degree == 1) == 6
    assert not np.isin(np.flatnonzero(degree == 2), np.concatenate(loops)).any()
    joins = [sorted(int(np.flatnonzero([v in loop for loop in loops])[0]) for v in path[[0, -1]]) for path in edge_paths(cut, len(V))]
    assert len(joins) == 3 and all(a != b for a, b in joins)
    tree = sp.csr_matrix((np.ones(3), np.array(joins).T), shape=(4, 4))
    assert graph_components(tree, directed=False)[0] == 1
    # every vertex of a cut is copied: both its ends split a fan of boundary faces
    assert len(parent) == len(V) + len(np.unique(cut))
    X, F_back, kept = weld_cut(V[parent], F_cut, V[cut], 1e-12)
    assert len(X) == len(V)
    np.testing.assert_array_equal(parent[kept][F_back], F)


def test_cut_to_disk_cuts_the_handles_of_a_torus():
    for V, F in [torus_mesh(), (torus_mesh()[0], torus_mesh()[1][1:])]:  # closed, and with a hole
        F_cut, parent, cut = cut_to_disk(V, F)
        check_disk(V[parent], F_cut)
        np.testing.assert_array_equal(parent[F_cut], F)
        X, F_back, kept = weld_cut(V[parent], F_cut, V[cut], 1e-12)
        assert len(X) == len(V) and euler_characteristic(F_back) == euler_characteristic(F)
        np.testing.assert_array_equal(parent[kept][F_back], F)
    # the closed torus: two loops through one vertex, or meeting along a shared path
    degree = np.bincount(cut_to_disk(*torus_mesh())[2].ravel())
    assert not np.any(degree == 1) and (np.sum(degree == 4) == 1 or np.sum(degree == 3) == 2)


def test_weld_cut_tells_twins_from_other_vertices_at_the_same_point_by_their_labels():
    """A torus split along its seam (the ring at angle 0 written twice): a tube whose two
    rims lie at the same points. Its cut runs from a point of one rim to the same point
    of the other, and by position alone the weld merges the copies of the two into one
    vertex (Euler characteristic -1, not the tube's 0); with labels carried by the copies,
    it gives the tube back."""
    V, F = torus_mesh(seam=True)
    assert len(boundary_loops(F)) == 2 and euler_characteristic(F) == 0
    F_cut, parent, cut = cut_to_disk(V, F)
    ends = V[edge_paths(cut, len(V))[0][[0, -1]]]
    np.testing.assert_allclose(ends[0], ends[1], atol=1e-12)
    assert euler_characteristic(weld_cut(V[parent], F_cut, V[cut], 1e-12)[1]) == -1
    labels = np.random.default_rng(0).random((len(V), 2))[parent]
    X, F_back, kept = weld_cut(V[parent], F_cut, V[cut], 1e-12, labels)
    assert len(X) == len(V) and euler_characteristic(F_back) == 0 and len(boundary_loops(F_back)) == 2
    np.testing.assert_array_equal(parent[kept][F_back], F)


def test_torus_split_along_its_seam_remeshes_into_a_tube():
    """The tube of the test above remeshed, its seams kept (weld_seams=False), at its face
    count and half of it: it did not weld (WeldError), and now keeps its topology, the two
    rims at the same points."""
    V, F = torus_mesh(48, seam=True)
    for faces in (len(F), len(F) // 2):
        r = remesh(V, F, faces, weld_seams=False)
        assert euler_characteristic(r.F) == 0 and len(boundary_loops(r.F)) == 2
        assert not len(nonmanifold_edges(r.F)) and not len(nonmanifold_vertices(r.F))
        assert abs(len(r.F) - faces) <= 0.05 * faces
        rims = r.V[np.concatenate(boundary_loops(r.F))]
        assert np.abs(rims[:, 1]).max() < 1e-9 and rims[:, 0].min() > 1.0  # both on the seam
        q = mesh_quality(r.V, r.F, reference=(V, F))
        assert q["q_mean"] > 0.97 and q["q_min"] > 0.5 and q["hausdorff"] < 0.01
        assert "qcremesh.cut_labels" not in r.data


def test_weld_seams_merges_the_vertices_of_seams_written_twice():
    """The torus whose ring at angle 0 is written twice: its 12 copies merged, it is the
    closed torus again. A sphere written as a grid in longitude and latitude: its
    meridian's copies and its poles' (one per face there) merged, the faces at the poles
    with two corners merged go, and it is a closed sphere with one vertex per pole."""
    V, F = torus_mesh(seam=True)
    X, G, kept, merged = weld_seams(V, F)
    assert len(X) == len(V) - 12 and not len(boundary_edges(G)) and euler_characteristic(G) == 0
    np.testing.assert_array_equal(G, merged[F])
    np.testing.assert_allclose(X, V[kept], atol=1e-12)  # (the mean of the copies, to rounding)
    np.testing.assert_array_equal(merged[kept], np.arange(len(kept)))
    V, F = uv_sphere(24, 12)
    X, G, kept, merged = weld_seams(V, F)
    assert len(X) == 24 * 11 + 2 and len(G) == 2 * 24 * 12 - 2 * 24
    assert not len(boundary_edges(G)) and euler_characteristic(G) == 2 and not len(nonmanifold_edges(G))
    assert not len(nonmanifold_vertices(G))
    uv, D = grid_disk(6)  # nothing at the same point: as it was
    P = np.column_stack([uv, np.zeros(len(uv))])
    X, G, kept, merged = weld_seams(P, D)
    np.testing.assert_array_equal(G, D)
    np.testing.assert_array_equal(kept, np.arange(len(P)))


def test_boundary_is_seams_where_every_boundary_vertex_has_a_twin():
    """The torus and the sphere written with their seams twice: every boundary vertex at
    the point of another. The sphere with the faces around a pole left out: a hole whose
    rim is boundary of its own. A disk, and a closed sphere: no seams."""
    assert boundary_is_seams(*torus_mesh(seam=True))
    V, F = uv_sphere(24, 12)
    assert boundary_is_seams(V, F)
    assert not boundary_is_seams(V, F[~np.isin(F, np.arange(0, len(V), 13)).any(1)])
    uv, D = grid_disk(6)
    assert not boundary_is_seams(np.column_stack([uv, np.zeros(len(uv))]), D)
    assert not boundary_is_seams(*sphere_mesh())


def test_remesh_welds_a_boundary_of_seams_only_when_nothing_rides_on_the_seams():
    """By default the torus written with its seam twice is remeshed closed (its boundary
    is seams only, as an STL file's cracks are), also with per-vertex data that agree
    across the seam; with data that differ there (a texture coordinate going once round),
    or with weld_seams=False, as the tube it is written as."""
    V, F = torus_mesh(48, seam=True)
    height = {"height": V[:, 2]}
    for data in (None, height):
        r = remesh(V, F, len(F), data=data)
        assert r.stats["welded_seams_by_default"] and r.stats["welded_seam_vertices"] == 24
        assert not len(boundary_edges(r.F)) and euler_characteristic(r.F) == 0
        q = mesh_quality(r.V, r.F, reference=(V, F))
        assert q["q_mean"] > 0.97 and q["q_min"] > 0.5 and q["hausdorff"] < 0.01
    np.testing.assert_allclose(r.data["height"], r.V[:, 2], atol=1e-3)
    u = np.zeros(len(V))
    u[np.unique(coincident_boundary_pairs(V, F)[:, 1])] = 1.0  # one copy of each seam vertex at 1
    for options in ({"data": dict(height, u=u)}, {"weld_seams": False}):
        r = remesh(V, F, len(F), **options)
        assert "welded_seam_vertices" not in r.stats and len(boundary_loops(r.F)) == 2


def test_remesh_with_weld_seams_remeshes_the_surface_whole():
    """With weld_seams=False, a sphere written with its seams twice is remeshed as the
    disk it is, the seams boundary; with weld_seams=True, as the closed sphere, its
    per-vertex data (the first copy's) carried over."""
    V, F = uv_sphere(32, 16)
    r = remesh(V, F, 1000, weld_seams=False)
    assert len(boundary_loops(r.F)) == 1 and "welded_seam_vertices" not in r.stats
    r = remesh(V, F, 1000, weld_seams=True, data={"height": V[:, 2]})
    assert r.stats["welded_seam_vertices"] == 17 + 2 * 32 - 2
    assert not len(boundary_edges(r.F)) and euler_characteristic(r.F) == 2
    assert not len(nonmanifold_edges(r.F)) and not len(nonmanifold_vertices(r.F))
    q = mesh_quality(r.V, r.F, reference=(V, F))
    assert q["q_mean"] > 0.98 and q["q_min"] > 0.6 and q["hausdorff"] < 0.005
    np.testing.assert_allclose(r.data["height"], r.V[:, 2], atol=0.01)


def test_faces_at_the_cut_of_a_closed_surface_are_judged_for_turning_over():
    """A closed CAD cylinder (its side two needles per facet, its caps fans) at 3,000
    faces: its cut ends at a cap's centre, where a face with a vertex on the cut turned
    over and 6 faces passed through others, as faces on a disk's boundary were not
    judged for turning over (right for a scan's ragged border, not for a cut). Now none."""
    V, F = cad_cylinder(height=4.0)
    r = remesh(V, F, 3000)
    assert euler_characteristic(r.F) == 2 and not len(boundary_edges(r.F))
    q = mesh_quality(r.V, r.F, reference=(V, F))
    assert q["self_intersecting_faces"] == 0 and q["q_min"] > 0.5 and q["q_mean"] > 0.98


def test_cut_refuses_what_it_cannot_do():
    V, F = sphere_mesh(200)
    far = int(np.argmax(np.linalg.norm(V - V[F[0, 0]], axis=1)))
    with pytest.raises(ValueError, match="^the cut leaves the edges of the mesh$"):
        cut_along_edges(F, [[F[0, 0], far]])
    uv, G = grid_disk(5)
    loop = boundary_loop(G)
    with pytest.raises(ValueError, match="^the cut runs along the boundary$"):
        cut_along_edges(G, path_edges([loop[:3]]))
    with pytest.raises(ValueError, match="^not one manifold surface$"):
        cut_to_disk(np.r_[V, V + 3], np.r_[F, F + len(V)])


def test_remesh_closes_a_closed_surface_of_genus_0():
    V, F = sphere_mesh(3000)
    r = remesh(V, F, 4000)
    assert abs(len(r.F) - 4000) <= 200
    assert not len(boundary_edges(r.F)) and euler_characteristic(r.F) == 2
    assert not len(nonmanifold_edges(r.F)) and not len(nonmanifold_vertices(r.F))
    assert len(np.unique(r.F)) == len(r.V)
    assert point_mesh_distance(r.V, V, F)[0].max() < 1e-9  # on the input surface
    # turned outwards, as the input
    volume = np.einsum("ij,ij->i", r.V[r.F[:, 0]], np.cross(r.V[r.F[:, 1]], r.V[r.F[:, 2]])).sum() / 6
    assert volume > 4
    q = radius_ratio(r.V, r.F)
    assert q.mean() > 0.97 and q.min() > 0.4
    # every level is closed too
    for X, G in r.levels:
        assert not len(boundary_edges(G)) and euler_characteristic(G) == 2 and len(np.unique(G)) == len(X)
    with pytest.raises(ValueError, match=r"^a surface that is not a disk needs the relaxation \(relax > 0\) and a "
                       r"method other than 'uniform'$"):
        remesh(V, F, 2000, relax=0)
    with pytest.raises(ValueError, match=r"^corners are taken only on a disk$"):
        remesh(V, F, 2000, corners=[0])


def test_remesh_of_coarse_tori_welds_at_the_count_asked():
    """Tori of 64 and 256 faces at 3,000 and 500: the inner equator of the first, a regular
    octagon cut open, turns by 45 degrees at each vertex, the corner threshold, which the
    two sides of the cut took either way (no weld); the second's cut disk got a boundary
    landmark at the end of its turn, 2 pi above the others, and its base mesh no interior
    landmark (88 faces). Measured: mean q 0.966 / 0.969, min q 0.67 / 0.78."""
    for k, faces in ((8, 3000), (16, 500)):
        V, F = torus_mesh(k)
        r = remesh(V, F, faces)
        assert abs(len(r.F) - faces) <= 0.05 * faces
        assert euler_characteristic(r.F) == 0 and not len(boundary_edges(r.F))
        q = radius_ratio(r.V, r.F)
        assert q.mean() > 0.95 and q.min() > 0.5


def cube_mesh():
    """The unit cube centred at 0 in 12 triangles, turned outwards."""
    V = np.array([[x, y, z] for z in (-0.5, 0.5) for y in (-0.5, 0.5) for x in (-0.5, 0.5)])
    F = np.array([[2, 1, 0], [1, 2, 3], [4, 2, 0], [2, 4, 6], [1, 4, 0], [4, 1, 5],
                  [6, 5, 7], [5, 6, 4], [3, 6, 7], [6, 3, 2], [5, 3, 7], [3, 5, 1]])
    return V, F


def test_cut_to_disk_slits_a_cube_along_two_edges():
    """The cube's two vertices farthest apart along its principal axis share an edge; a
    slit along one edge does not open the surface, the two edges around a face's third
    corner do."""
    V, F = cube_mesh()
    F_cut, parent, cut = cut_to_disk(V, F)
    assert len(cut) == 2 and len(boundary_loops(F_cut)) == 1 and euler_characteristic(F_cut) == 1
    assert len(parent) == 9 and np.bincount(parent).max() == 2


def test_remesh_of_a_cube_of_12_faces():
    """Its cut disk's map is far from conformal (mean |mu| 0.64): the faces are split until
    they are a quarter of those asked for. Measured at 500 / 5,000 faces: mean q 0.967 /
    0.984, min q 0.68 / 0.66 (without the split 0.71 / 0.69, 0.013 / 0.000)."""
    V, F = cube_mesh()
    for faces in (500, 5000):
        r = remesh(V, F, faces)
        assert abs(len(r.F) - faces) <= 0.05 * faces
        assert not len(boundary_edges(r.F)) and euler_characteristic(r.F) == 2
        assert r.stats["subdivided_input"]
        assert np.abs(r.V).max(axis=1).min() > 0.5 - 1e-12  # on the cube
        q = radius_ratio(r.V, r.F)
        assert q.mean() > 0.96 and q.min() > 0.6


def test_a_cube_welds_at_a_few_faces():
    """The cube cut open along two edges at 8 to 32 faces: the landmarks on the two sides
    of the cut are as many, although the disk map stretches one side so that it gets
    more than its share (they were added to that side alone, and no count from 4 to 32
    welded)."""
    V, F = cube_mesh()
    for faces in (8, 16, 32):
        r = remesh(V, F, faces)
        assert euler_characteristic(r.F) == 2 and not len(boundary_edges(r.F)) and not len(nonmanifold_edges(r.F))
        assert abs(len(r.F) - faces) <= 8
        assert np.allclose(np.abs(r.V).max(axis=1), 0.5)


def _disk_and_cubes(cubes):
    uv, F = grid_disk(10)
    V, G = cube_mesh()
    Vs = [np.column_stack([uv, np.zeros(len(uv))])] + [0.05 * V + [3 + k, 0, 0] for k in range(cubes)]
    Fs = [F] + [G + len(uv) + 8 * k for k in range(cubes)]
    return np.concatenate(Vs), np.concatenate(Fs)


def test_a_piece_that_is_refused_is_named(monkeypatch):
    import qcremesh.remeshing.pipeline as pipeline

    def no_cut(V, F, n=None):
        raise ValueError("no cut")

    monkeypatch.setattr(pipeline, "cut_to_disk", no_cut)
    with pytest.raises(TopologyError, match=r"^piece 2 of 2 \(12 faces, 4 asked for\): cannot cut the surface open "
                       r"into a disk: no cut$"):
        remesh(*_disk_and_cubes(1), 200)


def test_a_piece_too_small_for_its_share_gets_more_faces():
    """A small sphere (396 faces) beside a disk gets 4 of 200 faces, which do not weld
    back into a closed surface (it was refused): it is remeshed at twice as many, until
    it welds."""
    uv, F = grid_disk(10)
    S, G = sphere_mesh(200)
    V, F = np.r_[np.column_stack([uv, np.zeros(len(uv))]), 0.05 * S + [3, 0, 0]], np.r_[F, G + len(uv)]
    r = remesh(V, F, 200)
    assert r.stats["pieces_raised"] == 1 and "pieces_kept" not in r.stats
    disk, ball = r.stats["piece_faces"]
    assert ball >= 8 and disk + ball == len(r.F)
    B = r.F[disk:]
    assert euler_characteristic(B) == 2 and not len(boundary_edges(B)) and not len(nonmanifold_edges(B))
    assert point_mesh_distance(r.V[np.unique(B)], V, F)[0].max() < 1e-9


def test_a_piece_that_never_welds_is_kept(monkeypatch):
    """Where no remesh of a piece welds back at up to 4 times its face count, it is kept
    as it was (a part thinner than an output edge), unless all are."""
    import qcremesh.remeshing.pipeline as pipeline

    monkeypatch.setattr(pipeline, "weld_levels", lambda *args: None)
    V, F = _disk_and_cubes(1)
    r = remesh(V, F, 200, data={"x": V[:, 0]})
    assert r.stats["pieces_kept"] == [2] and "pieces_raised" not in r.stats
    disk, cube = r.stats["piece_faces"]
    assert cube == 12
    np.testing.assert_array_equal(np.sort(r.V[r.F[disk:]].reshape(-1, 3), axis=0),
                                  np.sort(V[F[-12:]].reshape(-1, 3), axis=0))
    np.testing.assert_allclose(r.data["x"], r.V[:, 0], atol=1e-12)
    assert len(r.uv) == len(r.V) - 8 and len(r.levels) == 1  # the disk's map; the kept piece has no levels
    C, G = cube_mesh()
    with pytest.raises(TopologyError, match=r"^none of the 2 pieces welds back into its topology at up to 4 times its "
                       r"face count$"):
        remesh(np.r_[C, C + 2], np.r_[G, G + 8], 200)


def test_a_piece_remeshed_away_from_itself_is_raised_then_kept(monkeypatch):
    """A remesh of a piece that welds into enough faces but stands farther from it than a
    quarter of its diagonal (the shape a leg of pyvista's ant lost; here the distance is
    reported so for the cube) is not taken: the piece is asked again at twice the faces
    while that is at most 4 times its own, and then kept as in the input; the disk beside
    it is remeshed as always. With the real distance, the cube is not kept at 400 faces;
    at 200, its share (4 faces) remeshed at up to 32 without its creases cuts its corners
    by about the limit, so whether it is kept depends on the host's rounding (on the AMD
    EPYC host of session 43: 0.0265 at 32 faces against a limit of 0.0217, kept)."""
    import qcremesh.remeshing.pipeline as pipeline

    real, asked = pipeline.hausdorff_distance, []

    def far_for_the_cube(VA, FA, VB, FB):
        if len(FA) == 12:
            asked.append(len(FB))
            return np.inf, np.inf
        return real(VA, FA, VB, FB)

    monkeypatch.setattr(pipeline, "hausdorff_distance", far_for_the_cube)
    V, F = _disk_and_cubes(1)
    r = remesh(V, F, 200)
    assert len(asked) >= 2 and asked == sorted(asked)
    assert r.stats["pieces_kept"] == [2] and "pieces_raised" not in r.stats
    disk, cube = r.stats["piece_faces"]
    assert cube == 12 and abs(disk - 196) <= 10
    monkeypatch.setattr(pipeline, "hausdorff_distance", real)
    assert "pieces_kept" not in remesh(V, F, 400).stats


def test_a_surface_whose_loops_are_all_short_welds():
    """A sphere with two holes of perimeter about 1.1 at 50 faces (edges of about 0.5):
    both loops, the longest too, get shorter edges around them, and the surface cut
    open between them welds back (it did not)."""
    V, F = sphere_mesh(1500)
    keep = np.abs(V[F].mean(1)[:, 2]) < np.cos(0.15)
    used, G = np.unique(F[keep], return_inverse=True)
    r = remesh(V[used], G.reshape(-1, 3), 50)
    assert len(boundary_loops(r.F)) == 2 and euler_characteristic(r.F) == 0 and not len(nonmanifold_edges(r.F))
    assert abs(len(r.F) - 50) <= 8


def test_remesh_of_a_torus_with_and_without_a_hole():
    """Measured at 2 x 48 x 24 faces: closed, mean q 0.982, min q 0.657; one face removed,
    0.964, 0.314."""
    V, F = torus_mesh(48)
    for G, chi, loops in [(F, 0, 0), (F[1:], -1, 1)]:
        r = remesh(V, G, len(G))
        assert abs(len(r.F) - len(G)) <= 0.05 * len(G)
        assert euler_characteristic(r.F) == chi and len(boundary_loops(r.F)) == loops
        assert not len(nonmanifold_edges(r.F)) and not len(nonmanifold_vertices(r.F))
        assert point_mesh_distance(r.V, V, G)[0].max() < 1e-9
        q = radius_ratio(r.V, r.F)
        assert q.mean() > 0.96 and q.min() > 0.3
        assert r.stats["cut_edges"] > 0
        for X, H in r.levels:
            assert euler_characteristic(H) == chi and len(np.unique(H)) == len(X)


def test_remesh_keeps_the_holes_of_a_disk_with_holes():
    V, F = holed_disk(60)
    r = remesh(V, F, 7000)
    assert abs(len(r.F) - 7000) <= 350
    assert len(boundary_loops(r.F)) == 3 and euler_characteristic(r.F) == -1
    assert not len(nonmanifold_edges(r.F)) and not len(nonmanifold_vertices(r.F))
    assert len(np.unique(r.F)) == len(r.V)
    assert point_mesh_distance(r.V, V, F)[0].max() < 1e-9
    # each output loop runs along an input loop, on its polyline
    for loop in boundary_loops(r.F):
        near = [np.abs(np.linalg.norm(r.V[loop][:, None] - V[h][None], axis=2).min(1)).max() for h in boundary_loops(F)]
        assert min(near) < 0.05
    edges_in = boundary_edges(F)
    for x in r.V[np.unique(boundary_edges(r.F))]:
        a, b = V[edges_in[:, 0]], V[edges_in[:, 1]]
        t = np.clip(((x - a) * (b - a)).sum(1) / ((b - a) ** 2).sum(1), 0, 1)
        assert np.linalg.norm(a + t[:, None] * (b - a) - x, axis=1).min() < 1e-9
    normal_in = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])[:, 2]
    normal_out = np.cross(r.V[r.F[:, 1]] - r.V[r.F[:, 0]], r.V[r.F[:, 2]] - r.V[r.F[:, 0]])[:, 2]
    assert (normal_in > 0).all() and (normal_out > 0).all()  # the bump is a graph, turned up as the input
    # (with the holes' borders held as the cut's sides are: mean q 0.984, q > 0.9 97.7 %)
    q = radius_ratio(r.V, r.F)
    assert q.mean() > 0.988 and q.min() > 0.4 and np.mean(q > 0.9) > 0.99
    assert r.stats["cut_edges"] > 0
    for X, G in r.levels:
        assert len(boundary_loops(G)) == 3 and euler_characteristic(G) == -1 and len(np.unique(G)) == len(X)


def test_remesh_of_a_face_scan_with_three_holes():
    """alex_3 (a face scan with the eyes and mouth open, four boundary loops) at half its
    face count: measured mean q 0.989, min q 0.669, q > 0.9 99.2 %, Hausdorff 0.23 %, along
    the boundary 0.23 % (remesh_botsch 0.970, 0.056, 0.16 %, 0; pymeshlab 0.962, 0.043,
    0.18 %, 0.11 %). Its holes' borders slide as a disk's: held, as the cut's sides are,
    q > 0.9 was 97.1 %."""
    V, F = read_mesh(DATA / "alex_3.ply")
    r = remesh(V, F, len(F) // 2)
    m = mesh_quality(r.V, r.F, reference=(V, F))
    assert abs(m["faces"] - len(F) // 2) <= 0.05 * len(F) // 2
    assert m["boundary_loops"] == 4 and m["euler_characteristic"] == -2 and m["manifold"]
    assert m["q_mean"] >= 0.97 and m["q_min"] >= 0.3 and m["q_frac_above_0_9"] >= 0.985
    assert m["hausdorff"] <= 0.003 and m["boundary_hausdorff"] <= 0.003


def test_remesh_keeps_the_corners_asked_for():
    uv, F = grid_disk(20, jitter=0.3)
    V = np.column_stack([uv, 0.2 * uv[:, 0] * uv[:, 1]])
    loop = boundary_loop(F)
    corners = loop[[3, 11, 30]]  # on straight sides, where no turn makes them corners
    r = remesh(V, F, 1200, corners=corners)
    assert np.linalg.norm(r.V[:, None] - V[corners][None], axis=2).min(0).max() < 1e-12
    plain = remesh(V, F, 1200)
    assert np.linalg.norm(plain.V[:, None] - V[corners][None], axis=2).min(0).max() > 1e-3
    with pytest.raises(ValueError, match=r"^corners must be vertices of the boundary$"):
        remesh(V, F, 1200, corners=[int(np.setdiff1d(np.arange(len(V)), loop)[0])])
    with pytest.raises(ValueError, match=r"^corners must be vertices of the boundary$"):
        remesh(V, F, 1200, corners=[len(V)])
    with pytest.raises(ValueError, match=r"^the 'uniform' method takes no corners$"):
        remesh(V, F, 1200, corners=corners, method="uniform")


def test_remesh_orients_a_closed_surface_before_cutting_it():
    V, F = sphere_mesh(800)
    F = F.copy()
    F[:10] = F[:10, ::-1]  # ten faces turned against the others
    r = remesh(V, F, 1000)
    assert r.stats["reoriented_faces"] == 10
    assert not len(boundary_edges(r.F)) and euler_characteristic(r.F) == 2
    volume = np.einsum("ij,ij->i", r.V[r.F[:, 0]], np.cross(r.V[r.F[:, 1]], r.V[r.F[:, 2]])).sum() / 6
    assert volume > 3.5  # outwards, as the majority


def test_paths_across_run_through_interior_vertices_and_apart():
    uv, F = grid_disk(12)
    V = np.column_stack([uv, np.zeros(len(uv))])
    boundary = np.unique(boundary_edges(F))
    left = [int(np.flatnonzero(np.isclose(uv[:, 0], 0) & np.isclose(uv[:, 1], y))[0]) for y in uv[:12, 0][[3, 8]]]
    right = [int(np.flatnonzero(np.isclose(uv[:, 0], 1) & np.isclose(uv[:, 1], y))[0]) for y in uv[:12, 0][[3, 8]]]
    bottom, top = 5, 11 * 12 + 5
    paths = paths_across(V, F, [[left[0], right[0]], [left[1], right[1]], [bottom, top]])
    for path, (a, b) in zip(paths[:2], zip(left, right)):
        assert path[0] == a and path[-1] == b
        assert not np.isin(path[1:-1], boundary).any()
    assert not np.isin(paths[0], paths[1]).any()
    # bottom to top must cross the first two paths
    assert paths[2] is None


def test_chord_across_cuts_off_the_most_of_the_run():
    """A 4 x 4 block with a strip one cell wide and 5 long on its side: no path through
    interior vertices crosses the strip, but each of its rungs cuts the block in two; the
    one chosen cuts off the most of the run of the boundary given."""
    V, F = grid_cells([(i, j) for i in range(4) for j in range(4)] + [(4 + i, 1) for i in range(5)])
    loop = boundary_loop(F)
    at = {tuple(p): k for k, p in enumerate(V[:, :2].astype(int))}
    source, target = at[5, 1], at[5, 2]
    assert paths_across(V, F, [[source, target]]) == [None]
    # the run from source to target goes round the strip's end (counter-clockwise)
    position = {v: k for k, v in enumerate(loop)}
    assert (position[at[9, 1]] - position[source]) % len(loop) < (position[target] - position[source]) % len(loop)
    assert chord_across(F, loop, source, target).tolist() == [source, target]
    # from one vertex further on: the next rung, not the diagonal beside it
    assert chord_across(F, loop, at[6, 1], target).tolist() == [at[6, 1], at[6, 2]]
    # along the block's straight side no interior edge joins two of its vertices
    assert chord_across(F, loop, at[0, 0], at[4, 0]) is None
    cut = cut_along_edges(F, np.array([[source, target]]), len(V))[0]
    assert connected_components(cut)[0] == 2


def test_path_edges_undo_edge_paths():
    """The consecutive pairs of each path, which edge_paths splits back into the paths
    (three meeting at a branch point, and a loop)."""
    paths = [np.array([0, 1, 2, 3]), np.array([3, 4]), np.array([3, 8]), np.array([5, 6, 7, 5])]
    E = path_edges(paths)
    np.testing.assert_array_equal(E, [[0, 1], [1, 2], [2, 3], [3, 4], [3, 8], [5, 6], [6, 7], [7, 5]])
    assert E.dtype == np.int64 and path_edges([]).shape == (0, 2)
    back = sorted(sorted(p.tolist()) for p in edge_paths(E, 9))
    assert back == [[0, 1, 2, 3], [3, 4], [3, 8], [5, 5, 6, 7]]


def test_edge_paths_end_at_branch_points_stops_and_ends():
    # a tail 0-1 into a triangle 1-2-3 (1 a branch point), a loop 4-5-6 of its own, given
    # in any order and direction, with an edge twice
    E = [[2, 1], [0, 1], [3, 2], [1, 3], [6, 4], [4, 5], [5, 6], [1, 0]]
    paths = edge_paths(E, 7)
    assert [p.tolist() for p in paths] == [[0, 1], [1, 2, 3, 1], [4, 5, 6, 4]]
    # a stop splits a path where it has degree 2
    assert [p.tolist() for p in edge_paths([[0, 1], [1, 2], [2, 3]], 4, stops=[2])] == [[0, 1, 2], [2, 3]]
    assert [p.tolist() for p in edge_paths([[0, 1], [1, 2], [2, 3]], 4, stops=np.array([0, 0, 1, 0], bool))] == [
        [0, 1, 2],
        [2, 3],
    ]
    assert edge_paths(np.zeros((0, 2), dtype=np.int64), 4) == []


def test_paths_to_boundary_join_each_free_part_once():
    uv, F = grid_disk(11)
    V = np.column_stack([uv, np.zeros(len(uv))])
    at = {tuple(np.round(p * 10).astype(int)): i for i, p in enumerate(uv)}
    # one part touching the boundary (left edge inwards), two free ones
    touching = [[at[0, 5], at[1, 5]]]
    near = [[at[4, 2], at[5, 2]]]  # 2 rows from the bottom
    far = [[at[5, 5], at[6, 5]]]
    paths = paths_to_boundary(V, F, touching + near + far)
    assert len(paths) == 2
    boundary = np.unique(boundary_edges(F))
    starts = [set(np.ravel(near)), set(np.ravel(far))]
    for path, start in zip(paths, starts):
        assert path[0] in start and np.isin(path[1:-1], boundary, invert=True).all()
    # the near part goes to the boundary, 2 edges down; the far one to the near part,
    # joined before it (0.4 to the boundary and to the touching part)
    assert path_length(V, paths[0]) == pytest.approx(0.2)
    assert path_length(V, paths[1]) == pytest.approx(0.3)
    assert paths_to_boundary(V, F, touching) == []


def path_length(V, path):
    return float(np.linalg.norm(np.diff(V[path], axis=0), axis=1).sum())


def test_weld_along_paths_joins_pieces_but_not_a_slit():
    """A grid cut across into two pieces is welded back into it; on a grid with a
    zero-width slit ending where the path starts, the slit's other side stays apart."""
    uv, F = grid_disk(9)
    V = np.column_stack([uv, np.zeros(len(uv))])
    a = int(np.flatnonzero(np.isclose(uv[:, 0], 0) & np.isclose(uv[:, 1], 0.5))[0])
    b = int(np.flatnonzero(np.isclose(uv[:, 0], 1) & np.isclose(uv[:, 1], 0.5))[0])
    (path,) = paths_across(V, F, [[a, b]])
    F_cut, parent = cut_along_edges(F, np.column_stack([path[:-1], path[1:]]), len(V))
    assert connected_components(F_cut, len(parent))[0] == 2
    X, G, kept = weld_along_paths(V[parent], F_cut, [V[path]], 1e-9)
    assert len(X) == len(V) and euler_characteristic(G) == 1 and len(boundary_loops(G)) == 1
    np.testing.assert_array_equal(np.sort(parent[kept]), np.arange(len(V)))
    # a second copy of the left end, as the other side of a slit, stays
    slit = np.r_[V[parent], V[a][None]]
    faces = np.r_[F_cut, [[len(parent), len(parent) + 1, len(parent) + 2]]]
    X2, G2, _ = weld_along_paths(np.r_[slit, V[a][None] + [[-0.1, 0, 0], [-0.1, -0.1, 0]]], faces, [V[path]], 1e-9)
    assert len(X2) == len(V) + 3 and connected_components(G2, len(X2))[0] == 2
    with pytest.raises(ValueError, match="a path has chains of no boundary vertices along it, not two alike"):
        weld_along_paths(V[parent], F_cut, [V[path] + 1.0], 1e-9)


def test_weld_along_paths_drops_flaps_of_both_sides_over_one_run():
    """Each side has faces with every corner on the chain under an edge across three
    chain edges (0-3, which then has four faces): all of them go with the chain's inner
    vertices, and the edge 0-3 joins the two sides' other faces."""
    chain = np.column_stack([np.arange(4.0), np.zeros(4), np.zeros(4)])
    X = np.concatenate([chain, [[1.5, 1, 0]], chain, [[1.5, -1, 0]]])
    above = [[0, 1, 2], [0, 2, 3], [0, 3, 4]]
    below = [[8, 7, 6], [8, 6, 5], [8, 5, 9]]
    Xw, Fw, kept = weld_along_paths(X, np.array(above + below), [chain[[0, -1]]], 1e-9)
    assert len(Fw) == 2 and len(Xw) == 4
    np.testing.assert_array_equal(np.sort(kept), [0, 3, 4, 9])
    assert not len(nonmanifold_edges(Fw)) and euler_characteristic(Fw) == 1
    # one side's flap alone stays: every edge has two faces at most
    below = [[8, 7, 9], [7, 6, 9], [6, 5, 9]]
    Xw, Fw, _ = weld_along_paths(X, np.array(above + below), [chain[[0, -1]]], 1e-9)
    assert len(Fw) == 6 and not len(nonmanifold_edges(Fw))


def test_weld_along_paths_takes_the_longest_chains_where_two_paths_share_their_ends():
    """Two paths from A to B, straight and bent at m: the piece between them is the face
    (A, B, m), whose edge A-B along the straight path has both ends on the bent one too.
    The chains along the bent path are that face's and the piece above's, A-m-B; the
    three pieces weld into one square."""
    A, B, m = [0.0, 0, 0], [1.0, 0, 0], [0.5, 0.3, 0]
    below = [A, [0.0, -1, 0], [1.0, -1, 0], B]
    lens = [A, B, m]
    above = [A, m, B, [1.0, 1, 0], [0.0, 1, 0]]
    X = np.array(below + lens + above)
    F = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [8, 9, 10], [8, 10, 11], [8, 11, 7]])
    straight, bent = np.array([A, B]), np.array([A, m, B])
    Xw, Fw, kept = weld_along_paths(X, F, [straight, bent], 1e-9)
    assert len(Xw) == 7 and len(Fw) == 6
    assert euler_characteristic(Fw) == 1 and len(boundary_loops(Fw)) == 1 and not len(nonmanifold_edges(Fw))
    assert np.isclose(doublearea(Xw, Fw).sum() / 2, 2.0)


def test_remeshes_apart_with_one_boundary_edge_length_weld():
    """The two halves of a disk remeshed apart, each with a share of the faces by area,
    the path's ends as corners and the same boundary edge length, get the same vertices
    along the path; with their own boundary counts they need not."""
    V, F = read_mesh(DATA / "fran_cut.ply")
    bnd = boundary_loops(F)[0]
    # (a boundary vertex in a face of boundary vertices alone has no path into the interior)
    path = next(p for i in range(10) for p in paths_across(V, F, [[bnd[i], bnd[i + len(bnd) // 2]]]) if p is not None)
    F_cut, parent = cut_along_edges(F, np.column_stack([path[:-1], path[1:]]), len(V))
    count, label = connected_components(F_cut, len(parent))
    edge = np.sqrt(4 * doublearea(V, F).sum() / 2 / (np.sqrt(3) * 4000))
    parts = []
    for k in range(count):
        used, local = np.unique(F_cut[label == k], return_inverse=True)
        share = int(round(4000 * doublearea(V[parent], F_cut[label == k]).sum() / doublearea(V, F).sum()))
        corners = np.flatnonzero(np.isin(parent[used], path[[0, -1]]))
        r = remesh(V[parent][used], local.reshape(-1, 3), share, fixed_boundary=True, corners=corners,
                   boundary_edge_length=edge, levels=0)
        parts.append(r)
    assert [r.stats["levels"] for r in parts] == [0, 0]
    X = np.r_[parts[0].V, parts[1].V]
    G = np.r_[parts[0].F, parts[1].F + len(parts[0].V)]
    welded, G, _ = weld_along_paths(X, G, [V[path]], 1e-9)
    assert euler_characteristic(G) == 1 and len(boundary_loops(G)) == 1 and not len(nonmanifold_edges(G))
    # about the path's length over the edge length, plus one (each part between corners
    # found along the path rounded on its own)
    along = np.linalg.norm(np.diff(V[path], axis=0), axis=1).sum() / edge
    assert abs(len(X) - len(welded) - (along + 1)) <= 2
    with pytest.raises(ValueError, match="boundary_edge_length must be positive and needs fixed_boundary"):
        remesh(V, F, boundary_edge_length=edge)


def test_cut_disk_cut_again_where_its_map_crowds():
    """Hand1.off (genus 1, one boundary loop) cut open into a disk whose map crowds 8.6 %
    of its boundary to the narrowest arc: the crowded part is cut off too (its path's ends
    and their twins on the other sides of the seams as corners), remeshed on its own map,
    welded along the path and then along the seams. At half its face count min q 0.034 ->
    0.462, Hausdorff 0.44 -> 0.36 % of the diagonal, mean q 0.985 -> 0.987."""
    V, F = read_mesh(shared("Hand1.off"))
    r = remesh(V, F, len(F) // 2)
    assert r.stats["crowded_cuts"] >= 1 and "cut_edges" in r.stats
    assert euler_characteristic(r.F) == -1 and len(boundary_loops(r.F)) == 1
    assert not len(nonmanifold_edges(r.F)) and not len(nonmanifold_vertices(r.F))
    assert abs(len(r.F) - len(F) // 2) <= 0.05 * (len(F) // 2)
    quality = mesh_quality(r.V, r.F, reference=(V, F))
    assert quality["q_min"] >= 0.3 and quality["q_mean"] >= 0.985 and quality["hausdorff"] <= 0.004


def test_pieces_with_slivers_cut_again_where_their_maps_crowd():
    """face-YH.off (a face scan in four pieces, the largest with two holes) at half its
    face count: its cut disk, cut where its map crowds, left in its largest piece a flap
    of the scan's border whose area that piece's own map crushed to 1e-10 of its share of
    the surface: no output vertex inside, a fan of slivers (136 faces below 0.3, min q
    0.002, Hausdorff distance 1.31 % of the diagonal). The pieces holding slivers are cut
    again where their own maps crowd, and that remesh kept for its larger min q: 32
    faces below 0.3, Hausdorff distance 0.23 %."""
    V, F = read_mesh(shared("face-YH.off"))
    r = remesh(V, F, len(F) // 2)
    assert r.stats["crowded_recut"] == 1
    assert len(boundary_loops(r.F)) == 6 and not len(nonmanifold_edges(r.F))
    assert abs(len(r.F) - len(F) // 2) <= 0.05 * (len(F) // 2)
    quality = mesh_quality(r.V, r.F, reference=(V, F))
    assert np.count_nonzero(radius_ratio(r.V, r.F) < 0.3) <= 40 and quality["hausdorff"] <= 0.004
    assert quality["q_mean"] >= 0.975


def _peninsula(hole, necks):
    """A 20 x 12 block of grid cells (with a 4 x 4 hole where ``hole``) and, from the
    middle of its right side, a chain of (length, width) bands of cells, bent (z = 0.3
    sin(x / 4) cos(y / 5)): a range map's border with a protrusion behind narrow necks."""
    cells = [(i, j) for i in range(20) for j in range(12) if not (hole and 6 <= i < 10 and 4 <= j < 8)]
    x = 20
    for length, width in necks:
        cells += [(x + i, 6 - width // 2 + j) for i in range(length) for j in range(width)]
        x += length
    V, F = grid_cells(cells)
    V[:, 2] = 0.3 * np.sin(V[:, 0] / 4) * np.cos(V[:, 1] / 5)
    return V, F


def test_disk_with_slivers_cut_where_its_map_crowds_a_protrusion():
    """A disk with a block 6 x 6 behind a neck 6 cells long and 2 wide, then 5 long and 1
    wide: its map crowds 2 of its 116 boundary vertices to the narrowest arc, too few to
    cut it at once, and the remesh of the whole has a fan of slivers over the neck (min q
    0.075, Hausdorff distance 4.5 % of the diagonal). Cut where its map crowds, the
    remesh is kept for its larger min q: 0.54, Hausdorff distance 1.3 %."""
    V, F = _peninsula(False, [(6, 2), (5, 1), (6, 6)])
    r = remesh(V, F, len(F))
    assert r.stats["crowded_after_slivers"] is True
    assert euler_characteristic(r.F) == 1 and len(boundary_loops(r.F)) == 1
    assert abs(len(r.F) - len(F)) <= 0.05 * len(F)
    quality = mesh_quality(r.V, r.F, reference=(V, F))
    assert quality["q_min"] >= 0.3 and quality["hausdorff"] <= 0.02


def test_crowded_run_behind_a_neck_without_interior_vertices_cut_at_a_chord():
    """The block of the test above with a hole (its cut disk has a fixed boundary, cut
    where its map crowds more than 5 % of it) and a chain of necks one and two cells wide
    between blocks, at half its face count: a crowded run whose ends no path through
    interior vertices joins is cut at a chord (a rung of a neck one cell wide; the piece
    beyond, a strip, split 1-to-4). Before: min q 0.157, Hausdorff distance 3.9 % of the
    diagonal; with the pieces holding slivers cut again, 0.35 and 1.2 %; with the ears
    of the pieces' base meshes turned over at reflex corners of their held boundaries
    flipped away, no piece has a sliver to cut again, and 0.35 and 0.04 %."""
    V, F = _peninsula(True, [(4, 2), (4, 1), (4, 4), (4, 1), (5, 5)])
    r = remesh(V, F, len(F) // 2)
    assert r.stats["crowded_cuts"] >= 2
    assert euler_characteristic(r.F) == 0 and len(boundary_loops(r.F)) == 2
    assert abs(len(r.F) - len(F) // 2) <= 0.05 * (len(F) // 2)
    quality = mesh_quality(r.V, r.F, reference=(V, F))
    assert quality["q_min"] >= 0.3 and quality["hausdorff"] <= 0.002


def test_ears_turned_over_at_reflex_corners_of_pieces_are_flipped():
    """The block with a hole and a block behind two necks, at half its face count: its
    cut disk is cut where its map crowds, and the base meshes of the pieces had ears of
    three boundary landmarks turned over on the surface around the reflex corners where
    the paths step across input edges (counter-clockwise in the disk, which is all their
    relaxation sees), folding the output over itself: min q 0.35, Hausdorff distance
    2.6 % of the diagonal. Flipped away, 0.71 and 0.03 %."""
    V, F = _peninsula(True, [(6, 2), (5, 1), (6, 6)])
    r = remesh(V, F, len(F) // 2)
    assert r.stats["crowded_cuts"] >= 1
    assert euler_characteristic(r.F) == 0 and len(boundary_loops(r.F)) == 2
    quality = mesh_quality(r.V, r.F, reference=(V, F))
    assert quality["q_min"] >= 0.6 and quality["hausdorff"] <= 0.002 and quality["self_intersecting_faces"] == 0


def test_rounds_of_recuts_remesh_each_piece_once(monkeypatch):
    """The rounds of cuts at slivers change only the pieces they cut: the others are
    taken from the round before, not remeshed again (the same output)."""
    import qcremesh.remeshing.pipeline as pipeline

    V, F = _peninsula(True, [(4, 2), (4, 1), (4, 4), (4, 1), (5, 5)])
    calls = []
    remesh_piece = pipeline.remesh

    def counted(Vk, Fk, faces, **options):
        if options.get("boundary_edge_length") is not None:
            calls.append((Vk.tobytes(), Fk.tobytes(), faces, options["levels"]))
        return remesh_piece(Vk, Fk, faces, **options)

    monkeypatch.setattr(pipeline, "remesh", counted)
    r = pipeline.remesh(V, F, len(F))
    assert r.stats["crowded_recut"] >= 1
    assert calls and len(calls) == len(set(calls))


def test_cut_disk_with_a_sizing_field_welds():
    """Hand1.off at half its face count with a curvature sizing field computed on the
    surface (as remesh(sizing="curvature") now does for a surface it cuts open): its cut
    disk, cut again where it crowds, had two seam vertices 1.0x of 1e-9 edge from their
    twins, and did not weld (the welding tolerance is now 1e-7 edge); remeshed whole,
    it had an ear on each side of a seam at the same place, which the weld folded onto
    each other (test_weld_cut_drops_ears_folded_onto_each_other)."""
    V, F = read_mesh(shared("Hand1.off"))
    edge = np.sqrt(4 * doublearea(V, F).sum() / 2 / (np.sqrt(3) * (len(F) // 2)))
    # the field of the curvature sizing when only shortening edges was its default
    sizing = curvature_sizing(V, F, edge, min_ratio=0.6, max_ratio=1.0, quantile=0.8, gradation=0.2)
    r = remesh(V, F, len(F) // 2, sizing=sizing)
    assert r.stats["crowded_cuts"] >= 1
    assert euler_characteristic(r.F) == -1 and len(boundary_loops(r.F)) == 1
    assert not len(nonmanifold_edges(r.F)) and not len(nonmanifold_vertices(r.F))
    assert abs(len(r.F) - len(F) // 2) <= 0.05 * (len(F) // 2)
    assert mesh_quality(r.V, r.F, reference=(V, F))["hausdorff"] <= 0.004


def test_cut_disk_remeshed_whole_where_its_crowded_pieces_do_not_weld(monkeypatch):
    """Where the seams of a cut disk cut again where it crowds do not weld (here: the first
    weld made to leave the mesh as it is), the cut disk is remeshed once more without
    that cutting (cut_crowded=False), and the output welds into the input's topology."""
    import qcremesh.remeshing.pipeline as pipeline

    V, F = read_mesh(shared("Hand1.off"))
    assert "crowded_cuts" in remesh(V, F, len(F) // 4).stats
    calls = []

    def weld_once_in_vain(X, G, segments, tol, labels=None):
        calls.append(len(G))
        if len(calls) == 1:
            return X, G, np.arange(len(X))
        return weld_cut(X, G, segments, tol, labels)

    monkeypatch.setattr(pipeline, "weld_cut", weld_once_in_vain)
    r = remesh(V, F, len(F) // 4)
    assert "crowded_cuts" not in r.stats and len(calls) >= 2
    assert euler_characteristic(r.F) == -1 and len(boundary_loops(r.F)) == 1 and not len(nonmanifold_edges(r.F))


def test_cut_to_disk_cuts_across_a_narrow_band_between_holes():
    """Two holes of radius 0.3, 0.15 apart, 0.7 from the plate's edge: the paths join the
    loops as a minimum spanning tree, so one runs straight across the band between the
    holes (joined each to the outer loop, the band stayed whole, a channel of the cut
    disk that its conformal map crowds)."""
    V, F = shapes.plate_with_two_holes(0.15, 0.3)
    loops = boundary_loops(F)
    F_cut, parent, cut = cut_to_disk(V, F)
    check_disk(V[parent], F_cut)
    for path in edge_paths(cut, len(V)):
        on = [int(np.flatnonzero([v in loop for loop in loops])[0]) for v in path[[0, -1]]]
        if sorted(on) == [1, 2]:
            across = np.linalg.norm(np.diff(V[path], axis=0), axis=1).sum()
            assert 0.15 <= across < 0.18
            break
    else:
        raise AssertionError("no path between the holes")


def test_remesh_of_a_plate_with_two_holes_close_together():
    """The plate above at 2,000 faces (edges about 0.08, half the band's width): min q
    0.048 with 20 faces below 0.3 and a Hausdorff distance of 2 % when the holes were
    joined each to the outer loop."""
    V, F = shapes.plate_with_two_holes(0.15, 0.3)
    r = remesh(V, F, 2000)
    assert len(boundary_loops(r.F)) == 3 and euler_characteristic(r.F) == -1
    m = mesh_quality(r.V, r.F, reference=(V, F))
    assert m["q_min"] > 0.5 and m["q_mean"] > 0.95 and m["hausdorff"] < 0.002


def test_remesh_shortens_the_edges_where_the_weld_of_a_thin_tail_fails(monkeypatch):
    """A ball with a tail 0.09 across (an output edge is about 0.17 at 1,000 faces),
    slit open along it to its tip: the tail's strip of the cut disk has no vertex inside,
    and the weld folds it (chi 4 for 2 in the cow of pymeshlab's samples). Remeshed
    again with edges a quarter as long around where the weld went wrong, it welds into a
    closed manifold surface of genus 0 (half as long did before the faces at a cut were
    judged for turning over, session 45, which leave the tail's strip folded at a half:
    mean q 0.973 -> 0.966, min q 0.693 -> 0.452, Hausdorff 3.8 -> 1.4 %). A tail 0.06 across at 1,200 faces welds with edges
    a quarter as long once the flap along the tail's slit, whose faces fall below 0.3, is
    cut off on its own map (SLIVER_RUN_EDGES; min q 0.041 -> 0.660, mean q 0.945 ->
    0.956). Without that cut, and with edges only halved (whether a quarter welds then
    depends on the host's rounding: it did not on session 42's host, it does on session
    43's, with the same packages, min q 0.047), the slit is trimmed where the weld went wrong,
    and the surface welds (its tail coarse). (At 1,500 faces it does not weld either
    way.) Without both, the error says so."""
    import qcremesh.remeshing.pipeline as pipeline
    from qcremesh.remeshing.cut_paths import CROWDED_MIN_EDGES

    def closed_genus_0(r):
        return (
            euler_characteristic(r.F) == 2 and not boundary_loops(r.F)
            and not len(nonmanifold_edges(r.F)) and not len(nonmanifold_vertices(r.F))
        )

    V, F = shapes.ball_with_tail(0.045, rings=118)
    r = remesh(V, F, 1000)
    assert r.stats["weld_sizing_min_ratio"] == 0.25 and "cut_trimmed" not in r.stats
    assert closed_genus_0(r) and radius_ratio(r.V, r.F).mean() > 0.94
    V, F = shapes.ball_with_tail(0.03, rings=118)
    r = remesh(V, F, 1200)
    assert r.stats["weld_sizing_min_ratio"] == 0.25 and r.stats["crowded_after_slivers"]
    assert "cut_trimmed" not in r.stats and closed_genus_0(r) and radius_ratio(r.V, r.F).min() > 0.6
    monkeypatch.setattr(pipeline, "SLIVER_RUN_EDGES", CROWDED_MIN_EDGES)
    monkeypatch.setattr(pipeline, "WELD_REFINE_RATIOS", (0.5,))
    r = remesh(V, F, 1200)
    assert r.stats["weld_sizing_min_ratio"] == 0.5 and r.stats["cut_trimmed"]
    assert closed_genus_0(r) and radius_ratio(r.V, r.F).mean() > 0.92
    monkeypatch.setattr(pipeline, "WELD_REFINE_RATIOS", ())
    monkeypatch.setattr(pipeline, "TRIM_REACH", 0.0)
    with pytest.raises(MeshError, match="^the remesh of the surface cut open does not weld back into its topology$"):
        remesh(V, F, 1200)


def test_points_on_segments_either_way_round():
    """Points on a segment, at its ends, off it by more than tol; the same answer whether
    the points or the segments are the fewer (the query runs from the smaller set)."""
    a = np.array([[0.0, 0, 0], [1, 0, 0], [5, 5, 5]])
    b = np.array([[1.0, 0, 0], [1, 1, 0], [6, 5, 5]])
    Q = np.array([[0.5, 0, 0], [1, 0.5, 1e-12], [1, 1, 0], [0.5, 1e-6, 0], [2, 0, 0], [5.5, 5, 5]])
    expected = np.array([True, True, True, False, False, True])
    assert (points_on_segments(Q, a, b, 1e-9) == expected).all()
    assert (points_on_segments(Q[:2], a, b, 1e-9) == expected[:2]).all()
    many = np.tile(a, (3, 1)), np.tile(b, (3, 1))
    assert (points_on_segments(Q[:2], *many, 1e-9) == expected[:2]).all()
    assert not points_on_segments(Q, a[:0], b[:0], 1e-9).any()
