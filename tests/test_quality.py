import json

import numpy as np
import pytest

from conftest import DATA
from qcremesh.geometry.quality import (
    corner_normals_up,
    corner_radius_ratio_bound,
    mesh_quality,
    min_angle,
    radius_ratio,
    surface_side_quality,
    triangle_angles,
    valence6_fraction,
    vertex_valence,
)
from qcremesh.mesh.io import read_mesh
from qcremesh.mesh.validate import InvalidIndexError


def regular_grid(k):
    """k x k vertices on [0, 1]^2, every square cut along the same diagonal."""
    g = np.linspace(0, 1, k)
    uv = np.stack(np.meshgrid(g, g), -1).reshape(-1, 2)
    i, j = np.meshgrid(np.arange(k - 1), np.arange(k - 1))
    a = (j * k + i).ravel()
    F = np.concatenate([np.column_stack([a, a + 1, a + k + 1]), np.column_stack([a, a + k + 1, a + k])])
    return uv, F


def random_rotation(seed):
    Q, _ = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return Q


def test_known_triangles():
    V = np.array([[0, 0], [1, 0], [0.5, np.sqrt(3) / 2], [0, 1], [3, 0], [0, 4], [2, 0]])
    F = np.array([[0, 1, 2], [0, 1, 3], [0, 4, 5], [0, 1, 6], [0, 0, 1]])
    q = radius_ratio(V, F)
    np.testing.assert_allclose(q, [1, 2 * (np.sqrt(2) - 1), 0.8, 0, 0], atol=1e-15)
    A = triangle_angles(V, F)
    np.testing.assert_allclose(A[0], np.pi / 3)
    np.testing.assert_allclose(A[1], [np.pi / 2, np.pi / 4, np.pi / 4])
    np.testing.assert_allclose(A[2], [np.pi / 2, np.arctan2(4, 3), np.arctan2(3, 4)])
    np.testing.assert_allclose(A[3], [0, np.pi, 0], atol=1e-15)  # collinear
    np.testing.assert_allclose(min_angle(V, F)[:4], [np.pi / 3, np.pi / 4, np.arctan2(3, 4), 0])


def test_invariant_under_rotation_and_embedding_in_space():
    rng = np.random.default_rng(0)
    uv = rng.normal(size=(30, 2))
    F = rng.choice(30, (50, 3), replace=True)
    F = F[(F[:, 0] != F[:, 1]) & (F[:, 1] != F[:, 2]) & (F[:, 2] != F[:, 0])]
    V = np.column_stack([uv, np.zeros(len(uv))]) @ random_rotation(1).T * 3.7
    np.testing.assert_allclose(radius_ratio(V, F), radius_ratio(uv, F), rtol=1e-9)
    np.testing.assert_allclose(triangle_angles(V, F), triangle_angles(uv, F), atol=1e-12)
    np.testing.assert_allclose(triangle_angles(V, F).sum(1), np.pi)
    l = np.linalg.norm(np.roll(V[F], -1, axis=1) - V[F], axis=2)
    a, b, c = l.T
    q = (b + c - a) * (c + a - b) * (a + b - c) / (a * b * c)
    np.testing.assert_allclose(radius_ratio(V, F), q, rtol=1e-8, atol=1e-12)
    assert ((0 <= radius_ratio(V, F)) & (radius_ratio(V, F) <= 1 + 1e-15)).all()


def test_needle_and_cap_are_accurate():
    # needle: 2A = 1e-9, a = 1, b = c = hypot(0.5, 1e-9); cap: the same with the apex at 0.
    h = 1e-9
    V = np.array([[0, 0], [1, 0], [0.5, h], [1e-12, h]])
    q = radius_ratio(V, [[0, 1, 2], [0, 1, 3]])
    b = np.hypot(0.5, h)
    np.testing.assert_allclose(q[0], 4 * h**2 / ((1 + 2 * b) * b * b), rtol=1e-9)
    c, d = np.hypot(1e-12, h), np.hypot(1 - 1e-12, h)
    np.testing.assert_allclose(q[1], 4 * h**2 / ((1 + c + d) * c * d), rtol=1e-6)
    angles = triangle_angles(V, [[0, 1, 2]])[0]
    np.testing.assert_allclose(angles[:2], np.arctan(2 * h), rtol=1e-12)


def test_valence_on_a_regular_grid():
    uv, F = regular_grid(6)
    val = vertex_valence(F)
    interior = ((uv > 0) & (uv < 1)).all(1)
    assert (val[interior] == 6).all()
    assert val.sum() == 2 * (3 * 5 * 5 + 2 * 5)  # twice the number of edges
    assert valence6_fraction(F) == 1.0
    np.testing.assert_array_equal(vertex_valence(F, n=40)[36:], 0)
    flipped = F.copy()
    flipped[0] = [0, 1, 6]
    flipped[25] = [1, 7, 6]  # the first square now cut along the other diagonal
    assert valence6_fraction(flipped) == pytest.approx(1 - 1 / 16)
    assert np.isnan(valence6_fraction([[0, 1, 2]]))


def test_mesh_quality_of_a_grid_and_against_a_reference():
    uv, F = regular_grid(11)
    V = np.column_stack([uv, np.zeros(len(uv))])
    r = mesh_quality(V, F)
    assert json.loads(json.dumps(r, allow_nan=False)) == r
    assert r["faces"] == 200 and r["vertices"] == 121
    assert r["q_mean"] == pytest.approx(2 * (np.sqrt(2) - 1)) == r["q_min"] == r["q_p01"]
    assert r["q_frac_above_0_9"] == 0 and r["frac_min_angle_below_30"] == 0
    assert r["min_angle_deg"] == pytest.approx(45) and r["mean_min_angle_deg"] == pytest.approx(45)
    assert r["valence6_fraction"] == 1.0
    assert (r["boundary_loops"], r["euler_characteristic"], r["manifold"]) == (1, 1, True)
    assert r["self_intersecting_faces"] == 0
    # 220 edges along the axes of 0.1, 100 diagonals of 0.1 sqrt(2)
    edge = (220 * 0.1 + 100 * 0.1 * np.sqrt(2)) / 320
    assert r["mean_edge_length"] == pytest.approx(edge)
    assert "hausdorff" not in r and "reference_self_intersecting_faces" not in r

    diag = np.sqrt(2)
    r = mesh_quality(V + [0.03, 0, 0.01], F, reference=(V, F))
    assert json.loads(json.dumps(r, allow_nan=False)) == r
    assert r["hausdorff"] == pytest.approx(np.hypot(0.03, 0.01) / diag)
    assert 0.01 / diag < r["mean_distance"] < r["hausdorff"]
    assert r["boundary_hausdorff"] == pytest.approx(np.hypot(0.03, 0.01) / diag)
    assert r["hausdorff_edges"] == pytest.approx(np.hypot(0.03, 0.01) / edge)
    # the grid with a small triangle standing up through one of its faces
    stand = np.array([[0.43, 0.425, -0.1], [0.47, 0.425, -0.1], [0.45, 0.415, 0.1]])
    crossed = (np.vstack([V, stand]), np.vstack([F, [121, 122, 123]]))
    r = mesh_quality(V, F, reference=crossed)
    assert (r["self_intersecting_faces"], r["reference_self_intersecting_faces"]) == (0, 2)
    r = mesh_quality(V, F, reference=(V, F))
    distances = [r["hausdorff"], r["mean_distance"], r["boundary_hausdorff"]]
    assert distances == pytest.approx([0, 0, 0], abs=1e-15)
    # a reference with fractional indices is refused by name (an IndexError of numpy before)
    with pytest.raises(InvalidIndexError, match="^face indices must be whole numbers"):
        mesh_quality(V, F, reference=(V, F + 0.5))


def test_mesh_quality_closed_and_nonmanifold():
    tet = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    T = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
    r = mesh_quality(tet, T, reference=(tet, T))
    assert (r["boundary_loops"], r["euler_characteristic"], r["manifold"]) == (0, 2, True)
    assert r["valence6_fraction"] == 0.0 and r["boundary_hausdorff"] == 0.0
    r = mesh_quality(tet, T, reference=(tet, T[:3]))
    assert r["boundary_hausdorff"] is None
    fin = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])  # three faces on edge (0, 1)
    V = np.array([[0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, -1, 0], [0.5, 0, 1]], float)
    r = mesh_quality(V, fin)
    assert r["manifold"] is False
    assert r["valence6_fraction"] is None
    bowtie = np.array([[0, 1, 2], [0, 3, 4]])  # two triangles pinched at vertex 0
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [-1, 0, 0], [-1, -1, 0]], float)
    r = mesh_quality(V, bowtie)
    assert r["manifold"] is False and r["boundary_loops"] == 1


def test_mesh_quality_of_a_real_mesh():
    V, F = read_mesh(DATA / "fran_cut.ply")
    r = mesh_quality(V, F)
    q = radius_ratio(V, F)
    assert r["q_min"] == q.min() > 0 and r["q_mean"] == pytest.approx(q.mean())
    assert r["q_min"] <= r["q_p01"] <= r["q_mean"] <= 1
    assert 0 < r["min_angle_deg"] <= r["mean_min_angle_deg"] <= 60
    assert (r["boundary_loops"], r["euler_characteristic"], r["manifold"]) == (1, 1, True)


def test_corner_radius_ratio_bound():
    """One triangle at a sharp corner: the isosceles one with that apex angle, measured
    by radius_ratio; 60 degrees: 1; 90 degrees: two isosceles triangles of 45 degrees.
    No triangle with a given angle does better."""
    a = np.radians([6.57, 20.0, 45.0])
    apex = np.array([0.0, 0.0, 0.0])
    V = np.concatenate([[apex], np.column_stack([np.cos(a / 2), np.sin(a / 2), 0 * a]),
                        np.column_stack([np.cos(a / 2), -np.sin(a / 2), 0 * a])])
    F = np.column_stack([np.zeros(3, int), [1, 2, 3], [4, 5, 6]])
    np.testing.assert_allclose(corner_radius_ratio_bound(a), radius_ratio(V, F), rtol=1e-12)
    np.testing.assert_allclose(corner_radius_ratio_bound(np.radians([60.0, 90.0])), [1.0, radius_ratio(
        np.array([[0, 0, 0], [1, 0, 0], [np.cos(np.pi / 4), np.sin(np.pi / 4), 0]]), np.array([[0, 1, 2]]))[0]])
    rng = np.random.default_rng(0)
    for angle in np.radians([5.0, 15.0, 40.0]):  # other triangles with that angle
        r = rng.uniform(0.05, 20.0, (200, 2))
        P = np.zeros((200, 3, 3))
        P[:, 1, 0] = r[:, 0]
        P[:, 2, :2] = r[:, 1:2] * [np.cos(angle), np.sin(angle)]
        q = radius_ratio(P.reshape(-1, 3), np.arange(600).reshape(-1, 3))
        assert q.max() <= corner_radius_ratio_bound(angle)[0] + 1e-12


def test_surface_side_quality_negates_faces_turned_over():
    """Two equilateral triangles in the plane z = 0, one counter-clockwise seen from +z
    and one clockwise: against the normal +z the second is turned over (-1), against a
    zero normal nothing is; the normals at three corners sum to the side of the surface,
    or to zero where one turns by more than about 100 degrees from the other two."""
    X = np.array([[0, 0, 0], [1, 0, 0], [0.5, 3**0.5 / 2, 0]], dtype=float)
    T = np.array([[0, 1, 2], [0, 2, 1]])
    z = np.tile([0.0, 0.0, 1.0], (2, 1))
    np.testing.assert_allclose(surface_side_quality(X, T, z), [1.0, -1.0])
    np.testing.assert_allclose(surface_side_quality(X, T, np.zeros((2, 3))), [1.0, 1.0])
    tilted = [[np.sin(np.radians(a)), 0.0, np.cos(np.radians(a))] for a in (80, 120)]
    up = corner_normals_up([[[0, 0, 1], [0, 0, 1], tilted[0]], [[0, 0, 1], [0, 0, 1], tilted[1]]])
    assert up[0, 2] > 2 and np.all(up[1] == 0)


def test_mesh_quality_counts_faces_turned_over_against_the_reference():
    """A grid whose vertex at (0.5, 0.5) is moved across its neighbour (0.6, 0.5), in its
    plane: the two faces of its star that now lie beyond that neighbour are turned over,
    folded flat onto the others; the grid against itself has none, and with every face
    reversed all are."""
    uv, F = regular_grid(11)
    V = np.column_stack([uv, np.zeros(len(uv))])
    moved = V.copy()
    centre = np.flatnonzero(np.all(np.isclose(uv, 0.5), axis=1))[0]
    moved[centre, 0] = 0.65
    turned = np.count_nonzero(
        np.cross(moved[F[:, 1]] - moved[F[:, 0]], moved[F[:, 2]] - moved[F[:, 0]])[:, 2] < 0
    )
    r = mesh_quality(moved, F, reference=(V, F))
    assert turned == 2 and r["turned_over_faces"] == 2 and r["reference_turned_over_faces"] == 0
    assert mesh_quality(V, F[:, ::-1], reference=(V, F))["turned_over_faces"] == len(F)
