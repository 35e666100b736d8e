import numpy as np
import pytest
from scipy.spatial import Delaunay

from conftest import grid_disk
from qcremesh.beltrami.teichmuller import circle_boundary_positions, teichmuller_map
from qcremesh.geometry.operators import doublearea, signed_doublearea
from qcremesh.mesh.subdivide import upsample
from qcremesh.mesh.topology import boundary_loop
from qcremesh.param.tutte import tutte_embedding


def disk_base(nb=16, ni=24, seed=0):
    """Delaunay mesh of nb points on the unit circle and ni random points inside."""
    rng = np.random.default_rng(seed)
    theta = 2 * np.pi * np.arange(nb) / nb
    r = 0.85 * np.sqrt(rng.uniform(0, 1, ni))
    a = rng.uniform(0, 2 * np.pi, ni)
    P = np.r_[np.c_[np.cos(theta), np.sin(theta)], np.c_[r * np.cos(a), r * np.sin(a)]]
    F = Delaunay(P).simplices.astype(np.int64)
    cw = signed_doublearea(P, F) < 0
    F[cw] = F[cw][:, ::-1]
    return P, F


def deform(P, amp=0.1):
    """A smooth self-map of the closed unit disk: a twist that fixes the circle, then a
    Moebius transformation of the disk."""
    z = P[:, 0] + 1j * P[:, 1]
    w = z * np.exp(3j * amp * (1 - abs(z) ** 2))
    b = amp * (1.2 + 0.6j)
    return (w - b) / (1 - np.conj(b) * w)


def subdivided_disk(levels=2, tutte=True):
    """The use case: a Delaunay base mesh subdivided (boundary midpoints back on the
    circle), its Tutte embedding as source, the base vertices as landmarks."""
    P, F0 = disk_base()
    V, F = upsample(P, F0, levels)
    bnd = boundary_loop(F)
    V[bnd] /= np.linalg.norm(V[bnd], axis=1)[:, None]
    uv = tutte_embedding(F, bnd) if tutte else V
    return uv, F, bnd, np.arange(len(P)), deform(P)


@pytest.fixture(scope="module")
def disk_case():
    uv, F, bnd, land, t = subdivided_disk()
    return uv, F, bnd, land, t, teichmuller_map(uv, F, land, t, boundary=bnd)


def test_disk_map_matches_landmarks_keeps_circle_and_unfolds(disk_case):
    uv, F, bnd, land, t, res = disk_case
    assert res.converged
    z = res.uv[:, 0] + 1j * res.uv[:, 1]
    assert np.max(np.abs(z[land] - t)) < 1e-10
    assert res.landmark_error < 1e-10
    np.testing.assert_allclose(np.abs(z[bnd]), 1, atol=1e-12)
    assert np.all(signed_doublearea(res.uv, F) > 0)
    assert res.folded_faces == 0
    # The harmonic map the iteration starts from folds faces next to landmarks.
    start = teichmuller_map(uv, F, land, t, boundary=bnd, max_iter=0)
    assert start.folded_faces > 0
    assert start.iterations == 0 and not start.converged


def test_disk_map_has_nearly_constant_modulus(disk_case):
    uv, F, bnd, land, t, res = disk_case
    modulus = np.abs(res.mu)
    area = doublearea(uv, F)
    assert res.k == pytest.approx(area @ modulus / area.sum())
    assert 0.2 < res.k < 0.8
    assert np.std(modulus) < 0.15 * res.k
    # Teichmueller: a smaller maximal distortion than the harmonic start.
    start = teichmuller_map(uv, F, land, t, boundary=bnd, max_iter=0)
    assert modulus.max() < 0.9 < np.abs(start.mu).max()
    assert np.std(np.abs(start.mu)) > 3 * np.std(modulus)


def test_history_decreases(disk_case):
    res = disk_case[-1]
    h = np.asarray(res.history)
    assert len(h) == res.iterations
    assert h[-1] < 1e-2
    assert np.mean(h[-10:]) < 0.1 * np.mean(h[:10])
    assert np.all(np.diff([np.mean(block) for block in np.array_split(h, 4)]) < 0)


@pytest.mark.parametrize("smooth", [0.0, 2.0])
def test_affine_targets_give_the_affine_map(smooth):
    uv, F = grid_disk(9, jitter=0.3)
    z = uv[:, 0] + 1j * uv[:, 1]
    a, mu0 = 1.2 + 0.3j, 0.3 - 0.2j
    f = a * z + mu0 * a * np.conj(z) + (0.1 - 0.4j)
    land = np.r_[boundary_loop(F), [20, 40, 58]]
    res = teichmuller_map(uv, F, land, f[land], smooth=smooth)
    assert res.converged and res.folded_faces == 0
    np.testing.assert_allclose(res.uv[:, 0] + 1j * res.uv[:, 1], f, atol=1e-10)
    np.testing.assert_allclose(res.mu, mu0, atol=1e-10)
    assert res.k == pytest.approx(abs(mu0), abs=1e-10)
    assert res.landmark_error < 1e-12


def test_identity_targets_give_the_identity():
    uv, F, bnd, land, _ = subdivided_disk(levels=1, tutte=False)
    res = teichmuller_map(uv, F, land, uv[land], boundary=bnd)
    assert res.converged and res.iterations == 1
    np.testing.assert_allclose(res.uv, uv, atol=1e-12)
    assert res.k < 1e-12


def test_circle_boundary_positions_interpolate_the_arcs():
    n = 12
    theta = 2 * np.pi * np.arange(n) / n
    uv = np.r_[np.c_[np.cos(theta), np.sin(theta)], [[0.0, 0.0]]]
    bnd = np.arange(n)
    # One boundary landmark: the whole circle is one arc, turned by 30 degrees.
    rot = np.exp(1j * np.pi / 6)
    v, p = circle_boundary_positions(uv, bnd, [n, 0], [0, rot])
    np.testing.assert_array_equal(v, np.arange(1, n))
    np.testing.assert_allclose(p, rot * np.exp(1j * theta[1:]), atol=1e-12)
    # Two landmarks, 0 and 9, sent to the angles 0 and pi/2: the eight vertices between
    # them split the quarter circle, the two after 9 the remaining three quarters.
    v, p = circle_boundary_positions(uv, bnd, [0, 9], [1, 1j])
    angle = np.mod(np.angle(p), 2 * np.pi)
    np.testing.assert_allclose(angle[:8], np.pi / 2 * np.arange(1, 9) / 9)
    np.testing.assert_allclose(angle[8:], np.pi / 2 + 1.5 * np.pi * np.arange(1, 3) / 3)
    # A clockwise loop turns clockwise.
    v, p = circle_boundary_positions(uv, bnd[::-1], [0], [1])
    np.testing.assert_array_equal(v, np.arange(n - 1, 0, -1))
    np.testing.assert_allclose(p, np.exp(-1j * theta[1:]), atol=1e-12)


def test_invalid_input():
    uv, F, bnd, land, t = subdivided_disk(levels=1, tutte=False)
    with pytest.raises(ValueError, match="distinct"):
        teichmuller_map(uv, F, [0, 0], [0, 0])
    with pytest.raises(ValueError, match="unit circle"):
        teichmuller_map(uv, F, land, 0.9 * t, boundary=bnd)
    interior = land[~np.isin(land, bnd)]
    with pytest.raises(ValueError, match="at least one landmark"):
        teichmuller_map(uv, F, interior, t[~np.isin(land, bnd)], boundary=bnd)
