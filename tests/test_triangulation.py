import numpy as np
from scipy.spatial import Delaunay

from conftest import delaunay_excess
from qcremesh.geometry.operators import signed_doublearea
from qcremesh.geometry.triangulation import delaunay_flips, flip_edges, insert_points


def test_insert_points_splits_the_triangles_that_contain_them():
    """Points inserted into the two triangles of the unit square, several into one of
    them and one outside: each inside point adds two faces, all counter-clockwise, the
    square's area stays tiled, the point outside is left out."""
    uv = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.6, 0.2], [0.7, 0.1], [0.8, 0.3], [0.2, 0.7], [2.0, 2.0]])
    F = np.array([[0, 1, 2], [0, 2, 3]])
    G = insert_points(uv, F, np.arange(4, 9))
    assert len(G) == 2 + 2 * 4
    assert sorted(np.unique(G)) == list(range(8))
    assert np.all(signed_doublearea(uv, G) > 0)
    np.testing.assert_allclose(signed_doublearea(uv, G).sum() / 2, 1.0)


def test_flip_edges_stops_where_nothing_gains():
    """A criterion that gains nowhere flips nothing; one that gains on every edge flips a
    set of edges sharing no face in each round."""
    F = Delaunay(np.random.default_rng(0).uniform(0, 1, (50, 2))).simplices
    same, none = flip_edges(F, lambda F, f1, f2, a, b, c, d: -np.ones(len(a)), 10)
    assert none == 0 and np.array_equal(same, F)
    G, flips = flip_edges(F, lambda F, f1, f2, a, b, c, d: np.ones(len(a)), 1)
    changed = np.flatnonzero(np.any(G != F, axis=1))
    assert flips > 0 and len(changed) == 2 * flips


def test_flip_edges_vertex_disjoint_rounds():
    """With ``disjoint="vertices"`` no two edges flipped in one round share a vertex: the
    new edges (c, d) and the old ones (a, b) of a round touch each vertex at most once."""
    F = Delaunay(np.random.default_rng(0).uniform(0, 1, (50, 2))).simplices
    seen = []

    def everywhere(F, f1, f2, a, b, c, d):
        seen.append(np.column_stack([a, b, c, d]))
        return np.ones(len(a))

    G, flips = flip_edges(F, everywhere, 1, disjoint="vertices")
    changed = np.flatnonzero(np.any(G != F, axis=1))
    assert flips > 0 and len(changed) == 2 * flips
    # the flipped edges are the (a, b) whose faces changed; their four vertices are distinct
    quads = seen[0]
    old = {tuple(sorted(e)) for f in F[changed] for e in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0]))}
    new = {tuple(sorted(e)) for f in G[changed] for e in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0]))}
    flipped = quads[[tuple(sorted(q[:2])) in old - new for q in quads]]
    assert len(flipped) == flips and len(np.unique(flipped)) == 4 * flips


def test_delaunay_flips_recover_the_delaunay_triangulation():
    """Lawson's flips turn a valid but stretched triangulation (the Delaunay triangulation
    of the points squeezed 5 times along y) into Qhull's Delaunay triangulation of
    points in general position; a Delaunay triangulation stays as it is."""
    uv = np.random.default_rng(1).uniform(0, 1, (200, 2))
    F = Delaunay(uv * [1, 0.2]).simplices
    assert delaunay_excess(uv, F) > 0.5
    G = delaunay_flips(uv, F)
    assert np.all(signed_doublearea(uv, G) > 0)
    expected = Delaunay(uv).simplices
    assert sorted(map(tuple, np.sort(G, 1))) == sorted(map(tuple, np.sort(expected, 1)))
    np.testing.assert_array_equal(delaunay_flips(uv, G), G)
