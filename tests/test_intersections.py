import numpy as np
import pytest
from conftest import grid_disk

from qcremesh.geometry.intersections import _sectors_overlap, self_intersections, triangles_intersect
from qcremesh.mesh.validate import InvalidIndexError

TRIANGLE = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


def _segment_hits_triangle(a, b, T):
    """The segment a-b meets the triangle T (generic position: not in its plane)."""
    M = np.column_stack([b - a, T[0] - T[1], T[0] - T[2]])
    t, u, v = np.linalg.solve(M, T[0] - a)
    return 0 <= t <= 1 and u >= 0 and v >= 0 and u + v <= 1


def _reference_3d(P, Q):
    """Generic triangles meet exactly when an edge of one meets the other."""
    return any(_segment_hits_triangle(X[k], X[(k + 1) % 3], Y) for X, Y in ((P, Q), (Q, P)) for k in range(3))


def _orient(a, b, c):
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def _reference_2d(P, Q):
    """Planar triangles meet exactly when two of their edges cross or a corner of one is
    inside the other (generic position)."""

    def inside(p, T):
        s = [_orient(T[k], T[(k + 1) % 3], p) for k in range(3)]
        return all(x > 0 for x in s) or all(x < 0 for x in s)

    def cross(a, b, c, d):
        return _orient(a, b, c) * _orient(a, b, d) < 0 and _orient(c, d, a) * _orient(c, d, b) < 0

    edges = any(cross(P[i], P[(i + 1) % 3], Q[j], Q[(j + 1) % 3]) for i in range(3) for j in range(3))
    return edges or any(inside(p, Q) for p in P) or any(inside(q, P) for q in Q)


def test_triangles_intersect_matches_edge_tests_on_random_pairs():
    rng = np.random.default_rng(0)
    P = rng.uniform(0, 1, (3000, 3, 3))
    Q = rng.uniform(0, 1, (3000, 3, 3)) * 0.7 + rng.uniform(0, 0.3, (3000, 1, 3))
    want = np.array([_reference_3d(p, q) for p, q in zip(P, Q)])
    assert 0.2 < want.mean() < 0.8  # both answers are well represented
    np.testing.assert_array_equal(triangles_intersect(P, Q), want)
    np.testing.assert_array_equal(triangles_intersect(Q, P), want)


def test_triangles_intersect_coplanar_pairs():
    rng = np.random.default_rng(1)
    P = np.concatenate([rng.uniform(0, 1, (2000, 3, 2)), np.zeros((2000, 3, 1))], axis=2)
    Q = np.concatenate([rng.uniform(0.3, 1.3, (2000, 3, 2)), np.zeros((2000, 3, 1))], axis=2)
    want = np.array([_reference_2d(p[:, :2], q[:, :2]) for p, q in zip(P, Q)])
    assert 0.2 < want.mean() < 0.8
    np.testing.assert_array_equal(triangles_intersect(P, Q), want)
    # the same pairs tilted out of the plane z = 0 and moved away from the origin, which
    # lifts them off their common plane by rounding
    c, s = np.cos(0.7), np.sin(0.7)
    R = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    np.testing.assert_array_equal(triangles_intersect(P @ R.T + 1e3, Q @ R.T + 1e3), want)


def test_triangles_intersect_special_cases():
    e1, e2 = TRIANGLE[1], TRIANGLE[2]
    cases = {
        "parallel planes": (TRIANGLE + [0, 0, 0.1], False),
        # coplanar, beyond the long side (two faces of human_brain.ply that MeshLab's
        # self-intersection filter reports)
        "coplanar translate by e1 + e2": (TRIANGLE + e1 + e2, False),
        "coplanar overlapping": (TRIANGLE + [0.2, 0.2, 0], True),
        "touching corner to corner": (TRIANGLE + e1, True),
        "corner on the long side": (TRIANGLE + [0.5, 0.5, 0], True),
        "piercing the middle": (np.array([[0.2, 0.2, -1.0], [0.3, 0.2, 1.0], [0.2, 0.3, 1.0]]), True),
        "passing beside": (np.array([[0.8, 0.8, -1.0], [0.9, 0.8, 1.0], [0.8, 0.9, 1.0]]), False),
        "flattened to a segment across it": (np.array([[-1.0, 0.2, 0], [1.0, 0.2, 0], [0.0, 0.2, 0]]), True),
        "flattened to a segment beside it": (np.array([[-1.0, 1.5, 0], [1.0, 1.5, 0], [0.0, 1.5, 0]]), False),
    }
    for name, (Q, want) in cases.items():
        got = triangles_intersect(TRIANGLE[None], Q[None])[0], triangles_intersect(Q[None], TRIANGLE[None])[0]
        assert got == (want, want), name


def _shrunk(T, by=1e-6):
    centre = T.mean(1, keepdims=True)
    return centre + (1 - by) * (T - centre)


def test_sectors_overlap_matches_shrunk_triangles():
    # Two triangles with a common corner at the origin meet elsewhere when the same
    # triangles shrunk a little about their centroids (so no longer touching there) meet.
    rng = np.random.default_rng(2)
    u = rng.normal(size=(4000, 2, 3))
    w = rng.normal(size=(4000, 2, 3))
    want = triangles_intersect(
        _shrunk(np.concatenate([np.zeros((4000, 1, 3)), u], axis=1)),
        _shrunk(np.concatenate([np.zeros((4000, 1, 3)), w], axis=1)),
    )
    assert 0.1 < want.mean() < 0.9
    np.testing.assert_array_equal(_sectors_overlap(u[:, 0], u[:, 1], w[:, 0], w[:, 1]), want)


def _fan_pair(second):
    V = np.vstack([TRIANGLE, second])
    return V, np.array([[0, 1, 2], [0, 3, 4]])


def test_faces_with_a_common_vertex():
    through = np.array([[0.5, 0.5, -1.0], [0.5, 0.5, 1.0]])  # its sector crosses the other's
    assert self_intersections(*_fan_pair(through)).tolist() == [[0, 1]]
    assert self_intersections(*_fan_pair(np.array([[-1.0, 0, 1], [-1.0, 1, 1]]))).tolist() == []
    # in one plane: sectors of 0-90 and 45-135 degrees overlap, 0-90 and 100-170 do not
    assert self_intersections(*_fan_pair(np.array([[1.0, 1, 0], [-1.0, 1, 0]]))).tolist() == [[0, 1]]
    d1, d2 = (np.array([np.cos(a), np.sin(a), 0.0]) for a in np.radians([100, 170]))
    assert self_intersections(*_fan_pair(np.array([d1, d2]))).tolist() == []
    # the same sector twice, the second face longer
    assert self_intersections(*_fan_pair(2 * TRIANGLE[1:])).tolist() == [[0, 1]]


def test_no_self_intersection_on_flat_and_curved_grids():
    uv, F = grid_disk(30, jitter=0.3)
    assert len(self_intersections(uv, F)) == 0
    flat = np.column_stack([uv, np.zeros(len(uv))])
    assert len(self_intersections(flat + 1e5, F)) == 0
    # tilted, so that rounding lifts the vertices off the plane
    c, s = np.cos(0.7), np.sin(0.7)
    tilted = flat @ np.array([[1, 0, 0], [0, c, -s], [0, s, c]]).T + 1e3
    assert len(self_intersections(tilted, F)) == 0
    # a vertex dragged in the plane across its neighbours: its faces overlap theirs
    inner = np.argmin(np.linalg.norm(uv - 0.5, axis=1))
    dragged = flat.copy()
    dragged[inner, 0] += 3 / 29
    pairs = self_intersections(dragged @ np.array([[1, 0, 0], [0, c, -s], [0, s, c]]).T + 1e3, F)
    assert len(pairs) > 0
    assert (np.linalg.norm(uv[F[pairs.ravel()]].mean(1) - 0.5, axis=1) < 0.2).all()


def test_a_flap_pushed_through_the_surface():
    uv, F = grid_disk(12)
    V = np.column_stack([uv, np.zeros(len(uv))])
    # one more face over three new vertices, standing up through the middle of the grid
    V = np.vstack([V, [[0.43, 0.47, -0.2], [0.57, 0.47, -0.2], [0.5, 0.53, 0.3]]])
    F = np.vstack([F, [len(uv), len(uv) + 1, len(uv) + 2]])
    pairs = self_intersections(V, F)
    assert len(pairs) > 0 and (pairs[:, 1] == len(F) - 1).all()
    centre = V[F[pairs[:, 0]]].mean(1)
    assert (np.abs(centre[:, :2] - [0.5, 0.5]) < 0.15).all()
    # and a face listed twice lies on itself
    assert [0, len(F)] in self_intersections(V, np.vstack([F, F[:1]])).tolist()


def test_self_intersections_refuses_bad_faces():
    with pytest.raises(InvalidIndexError, match=r"face indices must lie in 0\.\.2, found 0\.\.3"):
        self_intersections(TRIANGLE, [[0, 1, 3]])


def test_candidate_searches_agree(monkeypatch):
    """The compiled search of bounding boxes in a grid and the search of bounding spheres
    in k-d trees (without Numba) give the same pairs, and so does testing the faces
    around every vertex (without sparing those of the vertices around which the faces
    turn once): on human_face.obj, whose lips pass through each other, and on a crumpled
    grid that folds over itself."""
    from conftest import DATA

    import qcremesh.geometry.intersections as intersections
    from qcremesh.mesh.io import read_mesh

    uv, F = grid_disk(40, jitter=0.3)
    u, v = uv.T
    crumpled = np.column_stack([u + 0.2 * np.sin(4 * np.pi * u), v, 0.01 * np.sin(7 * v) + 0.02 * np.cos(9 * u)])
    meshes = [read_mesh(DATA / "human_face.obj")[:2], (crumpled, F)]
    compiled = [self_intersections(V, F) for V, F in meshes]
    monkeypatch.setattr(intersections, "box_pairs_kernel", lambda: None)
    spheres = [self_intersections(V, F) for V, F in meshes]
    monkeypatch.setattr(intersections, "_flat_fans", lambda V, F: np.zeros(len(V), dtype=bool))
    every_fan = [self_intersections(V, F) for V, F in meshes]
    assert len(compiled[0]) == 408 and len(compiled[1]) > 100
    for a, b, c in zip(compiled, spheres, every_fan):
        np.testing.assert_array_equal(a, b)
        np.testing.assert_array_equal(a, c)


# A patch of pyacvd's remesh of alex_3.ply (data/, Apache-2.0) around one of its
# vertices (4 here), coordinates centred and rounded: faces 6 and 13 run along the edge
# 4-9 the same way, and 13 folds over the fan of vertex 4, through faces 5 and 10. Yet
# the corners around vertex 4 are all counter-clockwise seen along its normal and turn
# once.
FOLD_V = np.array(
    [
        [-0.625, 2.016, -2.694], [-0.021, 1.035, -3.815], [-0.077, 0.489, -2.303],
        [-0.646, 1.298, -0.91], [-0.023, -0.109, -0.303], [-0.323, -0.018, 1.516],
        [-0.024, -0.836, 2.822], [-0.792, 1.102, 0.767], [0.154, -0.759, 1.141],
        [0.166, -1.063, 2.312], [-0.561, -0.004, 3.383], [-0.539, -0.495, 5.434],
        [-1.355, 2.376, 1.342], [-1.002, 2.889, -1.592], [0.934, 0.431, -6.219],
        [0.528, -1.636, 2.147], [0.825, -2.594, 4.144], [0.811, -2.317, 3.005],
        [0.211, -1.722, 5.02], [0.45, -0.386, -2.62], [-1.152, 2.41, -0.253],
        [-1.116, 1.305, 2.443], [1.031, -0.512, -4.869], [0.319, 1.512, -5.356],
        [0.939, -0.963, -3.379], [0.959, -1.498, -1.613], [0.927, -1.951, 0.45],
    ]
)
FOLD_F = np.array(
    [
        [0, 2, 1], [3, 4, 2], [2, 0, 3], [4, 5, 6], [7, 5, 4], [4, 6, 8], [9, 8, 4],
        [4, 3, 7], [10, 6, 5], [5, 7, 10], [9, 8, 6], [6, 10, 11], [13, 3, 0],
        [15, 4, 9], [15, 16, 17], [18, 16, 15], [15, 19, 4], [9, 18, 15], [20, 7, 3],
        [3, 13, 20], [21, 10, 7], [7, 20, 12], [12, 21, 7], [19, 22, 14], [14, 23, 19],
        [1, 19, 23], [24, 22, 19], [19, 25, 24], [19, 1, 2], [19, 2, 4], [26, 25, 19],
        [26, 15, 17], [19, 15, 26], [9, 6, 18], [18, 6, 11],
    ]
)


def test_a_face_turned_and_folded_over_a_fan(monkeypatch):
    """The faces around a vertex are spared only where every edge there runs once each
    way, which the edge 4-9 does not: the pairs are those of testing every fan."""
    import qcremesh.geometry.intersections as intersections

    want = [[5, 13], [10, 13]]
    assert self_intersections(FOLD_V, FOLD_F).tolist() == want
    assert not intersections._flat_fans(FOLD_V, FOLD_F)[4]
    monkeypatch.setattr(intersections, "_flat_fans", lambda V, F: np.zeros(len(V), dtype=bool))
    assert self_intersections(FOLD_V, FOLD_F).tolist() == want
