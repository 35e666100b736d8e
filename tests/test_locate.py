import numpy as np
import pytest

from conftest import DATA, grid_disk
from qcremesh.geometry.distance import point_triangle_distance
from qcremesh.geometry.locate import interpolate_barycentric, locate_points
from qcremesh.mesh.io import read_mesh
from qcremesh.param.disk import disk_conformal_map


def containing_faces(uv, F, P, tol=1e-12):
    """Brute force: (k, m) mask of the faces whose closed triangle contains each point."""
    A, B, C = (uv[F[:, c]][None] for c in range(3))
    X = P[:, None]

    def orient(a, b, c):
        (u0, u1), (w0, w1) = np.moveaxis(b - a, -1, 0), np.moveaxis(c - a, -1, 0)
        return u0 * w1 - u1 * w0

    total = orient(A, B, C)
    lam = np.stack([orient(X, B, C), orient(A, X, C), orient(A, B, X)]) / total
    return (lam >= -tol).all(0)


def sheared_strip(n=400, height=1e-3, shear=0.5):
    """Parallelograms between (i/n, 0) and (i/n + shear, height), each cut in two: needles
    of length about 0.5 and width about height / 200 (smallest angle about height / 100)."""
    x = np.arange(n + 1) / n
    bottom = np.column_stack([x, np.zeros(n + 1)])
    uv = np.concatenate([bottom, bottom + [shear, height]])
    i = np.arange(n)
    lower = np.column_stack([i, i + 1, i + n + 1])
    F = np.concatenate([lower, np.column_stack([i + 1, i + n + 2, i + n + 1])])
    return uv, F


def fan(n=2000):
    """A disk cut into n needles around its center (angle 2 pi / n at the center)."""
    t = 2 * np.pi * np.arange(n) / n
    uv = np.concatenate([[[0.0, 0.0]], np.column_stack([np.cos(t), np.sin(t)])])
    i = np.arange(n)
    return uv, np.column_stack([np.zeros(n, int), 1 + i, 1 + (i + 1) % n])


def check_inside(uv, F, P):
    face, bary, inside = locate_points(uv, F, P)
    assert inside.all() and face.dtype == np.int64
    np.testing.assert_allclose(bary.sum(1), 1, atol=1e-12)
    np.testing.assert_allclose(interpolate_barycentric(F, face, bary, uv), P, atol=1e-13)
    assert containing_faces(uv, F, P, tol=1e-9)[np.arange(len(P)), face].all()
    return face, bary


def test_jittered_grid():
    uv, F = grid_disk(30, jitter=0.4)
    P = np.random.default_rng(0).uniform(0, 1, (3000, 2))
    check_inside(uv, F, P)
    check_inside(uv, F, uv)  # the vertices themselves


@pytest.mark.parametrize("height", [1e-3, 1e-12])
def test_extremely_skinny_triangles(height):
    # smallest angles about 1e-5 and 1e-14 rad
    uv, F = sheared_strip(height=height)
    rng = np.random.default_rng(1)
    s, y = rng.uniform(0, 1, 1000), rng.uniform(0, height, 1000)
    check_inside(uv, F, np.column_stack([s + 0.5 * y / height, y]))
    uv, F = fan()
    r, t = np.sqrt(rng.uniform(0, 1, 1000)), rng.uniform(0, 2 * np.pi, 1000)
    P = np.column_stack([r * np.cos(t), r * np.sin(t)]) * np.cos(np.pi / 2000)  # inside the polygon
    check_inside(uv, F, P)


def test_points_outside_go_to_the_closest_point():
    uv, F = grid_disk(12, jitter=0.3)
    rng = np.random.default_rng(2)
    P = rng.uniform(-0.5, 1.5, (2000, 2))
    face, bary, inside = locate_points(uv, F, P)
    outside = (P < 0).any(1) | (P > 1).any(1)
    np.testing.assert_array_equal(inside, ~outside)
    assert (bary[outside] >= 0).all() and (bary[outside] <= 1).all()
    np.testing.assert_allclose(bary.sum(1), 1)
    Q = interpolate_barycentric(F, face, bary, uv)
    np.testing.assert_allclose(Q, np.clip(P, 0, 1), atol=1e-14)
    np.testing.assert_allclose(Q[~outside], P[~outside], atol=1e-14)
    # slightly outside a curved polygonal boundary
    uv, F = fan(200)
    P = 1.001 * uv[1:] + 0.0005 * np.roll(uv[1:], 1, axis=0)
    face, bary, inside = locate_points(uv, F, P)
    assert not inside.any()
    d = point_triangle_distance(P, *(uv[F[face, c]] for c in range(3)))[0]
    A, B, C = (np.tile(uv[F[:, c]], (len(P), 1)) for c in range(3))
    every = point_triangle_distance(np.repeat(P, len(F), 0), A, B, C)[0].reshape(len(P), len(F))
    np.testing.assert_allclose(d, every.min(1), rtol=1e-12)
    Q = interpolate_barycentric(F, face, bary, uv)
    np.testing.assert_allclose(np.linalg.norm(Q - P, axis=1), d, rtol=1e-12)


def test_interpolate_barycentric_linear_functions():
    uv, F = grid_disk(15, jitter=0.3)
    P = np.random.default_rng(3).uniform(0, 1, (500, 2))
    face, bary, _ = locate_points(uv, F, P)
    f = 2 * uv[:, 0] - 3 * uv[:, 1] + 0.5
    np.testing.assert_allclose(interpolate_barycentric(F, face, bary, f), 2 * P[:, 0] - 3 * P[:, 1] + 0.5)
    V = np.column_stack([uv, f, -f])
    out = interpolate_barycentric(F, face, bary, V)
    assert out.shape == (500, 4)
    np.testing.assert_allclose(out[:, 2], 2 * P[:, 0] - 3 * P[:, 1] + 0.5)


def test_disk_map_locates_its_own_vertices():
    V, F = read_mesh(DATA / "fran_cut.ply")
    uv = disk_conformal_map(V, F).uv
    face, bary, inside = locate_points(uv, F, uv)
    assert inside.all()
    assert (F[face] == np.arange(len(uv))[:, None]).any(1).all()
    np.testing.assert_allclose(interpolate_barycentric(F, face, bary, V), V, atol=1e-9)
    # and random points of the disk land in a face that contains them
    rng = np.random.default_rng(4)
    r, t = 0.99 * np.sqrt(rng.uniform(0, 1, 1000)), rng.uniform(0, 2 * np.pi, 1000)
    check_inside(uv, F, np.column_stack([r * np.cos(t), r * np.sin(t)]))


def test_empty_query():
    uv, F = grid_disk(4)
    face, bary, inside = locate_points(uv, F, np.zeros((0, 2)))
    assert face.shape == (0,) and bary.shape == (0, 3) and inside.shape == (0,)


@pytest.mark.parametrize("rtol", [0.0, 1e-6])
def test_rtol_decides_inside_on_the_boundary(rtol):
    uv, F = grid_disk(4)
    face, bary, inside = locate_points(uv, F, [[0.5, -1e-9]], rtol=rtol)
    assert inside[0] == (rtol > 0)
