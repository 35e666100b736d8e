import numpy as np
import pytest

from conftest import DATA, grid_disk
from qcremesh.geometry.distance import (
    hausdorff_distance,
    point_mesh_distance,
    point_polyline_distance,
    point_segment_distance,
    point_triangle_distance,
    polyline_hausdorff_distance,
)
from qcremesh.mesh.io import read_mesh
from qcremesh.mesh.topology import boundary_edges


def reference_point_triangle(P, A, B, C):
    """Independent reference: the projection onto the plane if its barycentric
    coordinates (least squares) are non-negative, else the nearest point on the edges."""
    out = np.empty(len(P))
    for i in range(len(P)):
        p, a, b, c = P[i], A[i], B[i], C[i]
        M = np.column_stack([b - a, c - a])
        (v, w), *_ = np.linalg.lstsq(M, p - a, rcond=None)
        best = np.inf
        if v >= 0 and w >= 0 and v + w <= 1 and np.linalg.matrix_rank(M, tol=1e-9) == 2:
            best = np.linalg.norm(p - a - M @ [v, w])
        for x, y in ((a, b), (b, c), (c, a)):
            t = np.clip((p - x) @ (y - x) / max((y - x) @ (y - x), 1e-300), 0, 1)
            best = min(best, np.linalg.norm(p - x - t * (y - x)))
        out[i] = best
    return out


def bumpy_mesh(k=14, jitter=0.35):
    uv, F = grid_disk(k, jitter)
    z = 0.15 * np.sin(5 * uv[:, 0]) * np.cos(4 * uv[:, 1])
    return np.column_stack([uv, z]), F


def brute_force(P, V, F):
    """Nearest face by measuring every face, (k,), and the distance."""
    k, m = len(P), len(F)
    d, _, _ = point_triangle_distance(np.repeat(P, m, 0), *(np.tile(V[F[:, c]], (k, 1)) for c in range(3)))
    d = d.reshape(k, m)
    return d.min(1), d


def on_face(Q, V, F, face):
    """Distance from points to the given faces (0 when Q lies on them)."""
    return point_triangle_distance(Q, V[F[face, 0]], V[F[face, 1]], V[F[face, 2]])[0]


def test_point_triangle_regions():
    A, B, C = [0.0, 0, 0], [2.0, 0, 0], [0.0, 2, 0]
    P = np.array([[0.5, 0.5, 1], [-1, -1, 0], [3, -1, 0], [-1, 3, 2], [1, -1, 0], [2, 2, 0], [-1, 1, 0]])
    d, Q, b = point_triangle_distance(P, A, B, C)
    np.testing.assert_allclose(d, [1, np.sqrt(2), np.sqrt(2), np.sqrt(6), 1, np.sqrt(2), 1])
    expected = [[0.5, 0.5, 0], [0, 0, 0], [2, 0, 0], [0, 2, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    np.testing.assert_allclose(Q, expected)
    np.testing.assert_allclose(b.sum(1), 1)
    np.testing.assert_allclose(b @ np.array([A, B, C]), Q, atol=1e-15)
    assert (b >= 0).all()


@pytest.mark.parametrize("dim", [2, 3])
def test_point_triangle_against_reference(dim):
    rng = np.random.default_rng(dim)
    n = 3000
    A, B, C = (rng.normal(size=(n, dim)) for _ in range(3))
    # skinny, needle, collinear and repeated-vertex triangles
    C[:300] = A[:300] + rng.uniform(0, 1, (300, 1)) * (B[:300] - A[:300]) + 1e-7 * rng.normal(size=(300, dim))
    C[300:400] = A[300:400] + 0.3 * (B[300:400] - A[300:400])
    B[400:500] = A[400:500]
    A[500:550] = B[500:550] = C[500:550]
    P = rng.normal(size=(n, dim)) * 1.5
    d, Q, b = point_triangle_distance(P, A, B, C)
    np.testing.assert_allclose(d, reference_point_triangle(P, A, B, C), rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(P - Q, axis=1), d, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(b[:, :1] * A + b[:, 1:2] * B + b[:, 2:] * C, Q, atol=1e-12)
    assert (b >= -1e-12).all() and np.allclose(b.sum(1), 1)


def test_point_triangle_planar_inside_is_exactly_zero():
    rng = np.random.default_rng(0)
    A, B, C = [0.0, 0.0], [1.0, 0.0], [0.3, 1e-4]
    w = rng.dirichlet([1, 1, 1], 1000)
    P = w @ np.array([A, B, C])
    d, Q, b = point_triangle_distance(P, A, B, C)
    assert (d == 0).all() and (Q == P).all()
    np.testing.assert_allclose(b, w, atol=1e-8)


def test_point_segment_distance():
    P = [[0.5, 1.0], [-2.0, 0.0], [3.0, 4.0], [1.0, 1.0]]
    d, Q, t = point_segment_distance(P, [[0, 0]] * 3 + [[1, 1]], [[1, 0]] * 3 + [[1, 1]])
    np.testing.assert_allclose(d, [1, 2, np.hypot(2, 4), 0])
    np.testing.assert_allclose(t, [0.5, 0, 1, 0])
    np.testing.assert_allclose(Q, [[0.5, 0], [0, 0], [1, 0], [1, 1]])


def test_distance_to_plane_is_height():
    uv, F = grid_disk(20, jitter=0.3)
    V = np.column_stack([uv, np.zeros(len(uv))])
    rng = np.random.default_rng(1)
    P = np.column_stack([rng.uniform(0, 1, (2000, 2)), rng.uniform(-0.5, 0.5, 2000)])
    d, face, Q = point_mesh_distance(P, V, F)
    np.testing.assert_allclose(d, np.abs(P[:, 2]), atol=1e-14)
    np.testing.assert_allclose(Q, P * [1, 1, 0], atol=1e-14)
    np.testing.assert_allclose(on_face(Q, V, F, face), 0, atol=1e-14)
    assert face.dtype == np.int64


def test_point_mesh_distance_matches_brute_force_near_bumpy_surface():
    V, F = bumpy_mesh()
    rng = np.random.default_rng(2)
    f = rng.integers(0, len(F), 1000)
    P = (V[F[f]] * rng.dirichlet([1, 1, 1], 1000)[:, :, None]).sum(1)
    P += rng.normal(size=P.shape) * np.r_[np.full(800, 0.02), np.full(200, 0.5)][:, None]
    d, face, Q = point_mesh_distance(P, V, F)
    dmin, D = brute_force(P, V, F)
    np.testing.assert_allclose(d, dmin, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(D[np.arange(len(P)), face], dmin, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(np.linalg.norm(P - Q, axis=1), d, rtol=1e-10, atol=1e-14)
    np.testing.assert_allclose(on_face(Q, V, F, face), 0, atol=1e-12)


def test_point_mesh_distance_mixed_sizes_and_needles():
    # A CAD tessellation: large faces next to tiny ones, long needles and fans.
    V, F = read_mesh(DATA / "featuretype.STL")
    rng = np.random.default_rng(3)
    diag = np.linalg.norm(V.max(0) - V.min(0))
    f = rng.integers(0, len(F), 250)
    P = (V[F[f]] * rng.dirichlet([1, 1, 1], 250)[:, :, None]).sum(1)
    P += rng.normal(size=P.shape) * diag * np.r_[np.full(200, 0.005), np.full(50, 0.2)][:, None]
    d, face, Q = point_mesh_distance(P, V, F)
    dmin, _ = brute_force(P, V, F)
    np.testing.assert_allclose(d, dmin, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(on_face(Q, V, F, face), 0, atol=1e-12 * diag)


def test_point_mesh_distance_planar_mesh_outside_points():
    uv, F = grid_disk(10, jitter=0.3)
    rng = np.random.default_rng(4)
    P = rng.uniform(-0.5, 1.5, (1000, 2))
    d, face, Q = point_mesh_distance(P, uv, F)
    dmin, _ = brute_force(P, uv, F)
    np.testing.assert_allclose(d, dmin, atol=1e-15)
    outside = (P < 0).any(1) | (P > 1).any(1)
    assert (d[~outside] == 0).all()
    np.testing.assert_allclose(Q[outside], np.clip(P[outside], 0, 1), atol=1e-14)


def test_point_polyline_distance_matches_brute_force():
    V, F = bumpy_mesh(10)
    E = boundary_edges(F)
    rng = np.random.default_rng(5)
    P = rng.uniform(-0.3, 1.3, (1000, 3))
    d, seg, Q = point_polyline_distance(P, V, E)
    A, B = (np.tile(V[E[:, c]], (len(P), 1)) for c in range(2))
    D = point_segment_distance(np.repeat(P, len(E), 0), A, B)[0]
    np.testing.assert_allclose(d, D.reshape(len(P), len(E)).min(1), rtol=1e-12)
    t = point_segment_distance(Q, V[E[seg, 0]], V[E[seg, 1]])[0]
    np.testing.assert_allclose(t, 0, atol=1e-14)


def test_hausdorff_of_parallel_planes_and_of_a_mesh_with_itself():
    uv, F = grid_disk(12, jitter=0.3)
    V = np.column_stack([uv, np.zeros(len(uv))])
    h, mean = hausdorff_distance(V, F, V + [0, 0, 0.1], F)
    assert h == pytest.approx(0.1) and mean == pytest.approx(0.1)
    W, G = bumpy_mesh()
    assert hausdorff_distance(W, G, W, G) == pytest.approx((0, 0), abs=1e-15)


def test_hausdorff_is_symmetric_and_exact_for_a_half_plane():
    # B = [0, 0.5] x [0, 1] inside A = [0, 1]^2: d(A -> B) = max(x - 0.5, 0), d(B -> A) = 0
    g = np.linspace(0, 1, 11)
    uv = np.stack(np.meshgrid(g, g), -1).reshape(-1, 2)
    i, j = np.meshgrid(np.arange(10), np.arange(10))
    a = (j * 11 + i).ravel()
    F = np.concatenate([np.column_stack([a, a + 1, a + 12]), np.column_stack([a, a + 12, a + 11])])
    V = np.column_stack([uv, np.zeros(len(uv))])
    FB = F[V[F].mean(1)[:, 0] < 0.5]
    h, mean = hausdorff_distance(V, F, V, FB)
    assert h == pytest.approx(0.5)
    assert mean == pytest.approx((0.125 + 0) / 2)  # the quadrature is exact on linear pieces
    assert hausdorff_distance(V, FB, V, F) == pytest.approx((h, mean))


def test_polyline_hausdorff_of_nested_squares():
    sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    E = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
    big = (sq - 0.5) * 1.1 + 0.5
    h, mean = polyline_hausdorff_distance(sq, E, big, E)
    assert h == pytest.approx(0.05 * np.sqrt(2))
    assert 0.05 < mean < 0.05 * np.sqrt(2)
    assert polyline_hausdorff_distance(sq, E, sq, E) == (0.0, 0.0)
