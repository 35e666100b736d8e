import numpy as np
import pytest
from scipy.spatial import Delaunay

from conftest import grid_disk
from qcremesh.adaptive.basemesh import delaunay_disk_mesh, hexagonal_disk_points, subdivide_disk_mesh
from qcremesh.beltrami.coefficient import beltrami_coefficient
from qcremesh.beltrami.teichmuller import circle_boundary_positions, equilateral_coefficient, teichmuller_map
from qcremesh.geometry.quality import radius_ratio
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


@pytest.mark.parametrize("smooth", [0, 2])
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


def test_equilateral_coefficient():
    w = np.exp(2j * np.pi / 3 * np.arange(3))
    F = np.array([[0, 1, 2]])
    for p in [w, w[::-1]]:  # counter-clockwise and clockwise equilateral faces
        assert abs(equilateral_coefficient(np.c_[p.real, p.imag] * 2 + 1, F)[0]) < 1e-14
    # The face R^{-1}(w), R = z + 0.3 conj(z) inverted: mu of the map onto w.
    z = (w - 0.3 * np.conj(w)) / (1 - 0.09)
    uv = np.c_[z.real, z.imag]
    mu = equilateral_coefficient(uv, F)
    np.testing.assert_allclose(mu, 0.3, atol=1e-14)
    np.testing.assert_allclose(mu, beltrami_coefficient(uv, F, w), atol=1e-14)


@pytest.fixture(scope="module")
def warm_case():
    """The remeshing use: a Delaunay base mesh of jittered hexagonal points subdivided,
    its base vertices already on their targets, mapped from the equilateral reference."""
    rng = np.random.default_rng(0)
    P = hexagonal_disk_points(0.3)
    P = P[np.linalg.norm(P, axis=1) < 0.85]
    P = P + rng.uniform(-0.06, 0.06, P.shape)
    base, base_F = delaunay_disk_mesh(2 * np.pi * np.arange(20) / 20, P)
    uv, F = subdivide_disk_mesh(base, base_F, 2)[-1]
    bnd, land = boundary_loop(F), np.arange(len(base))
    res = teichmuller_map(
        uv, F, land, uv[land], boundary=bnd, initial=uv, reference="equilateral", max_iter=8, smooth=1
    )
    return uv, F, bnd, land, res


def test_warm_start_matches_landmarks_keeps_circle_and_unfolds(warm_case):
    uv, F, bnd, land, res = warm_case
    np.testing.assert_allclose(res.uv[land], uv[land], atol=1e-12)
    assert res.landmark_error < 1e-12
    np.testing.assert_allclose(np.linalg.norm(res.uv[bnd], axis=1), 1, atol=1e-12)
    assert res.folded_faces == 0 and np.all(signed_doublearea(res.uv, F) > 0)
    assert res.iterations == len(res.history) <= 8
    # k is the mean over the faces of |mu_T|, the distortion from equilateral.
    mu = equilateral_coefficient(res.uv, F)
    np.testing.assert_allclose(np.abs(res.mu), np.abs(mu), atol=1e-10)
    assert res.k == pytest.approx(np.abs(mu).mean())


def test_warm_start_improves_the_triangles(warm_case):
    uv, F, bnd, land, res = warm_case
    q0, q = radius_ratio(uv, F), radius_ratio(res.uv, F)
    assert q.mean() > q0.mean() + 0.005
    # Faces are guarded before |mu_T| exceeds 0.45 (a radius ratio of about 0.45).
    assert q.min() > 0.4
    assert 0 < res.guarded_faces < 0.2 * len(F)


def test_equilateral_reference_converges_on_a_regular_case():
    """A hexagonal patch of equilateral triangles, its boundary on the circle: the
    interior landmark at its own place gives a T-map that converges, with small k."""
    uv, F, bnd, land, _ = subdivided_disk(levels=1, tutte=False)
    tutte = tutte_embedding(F, bnd)
    res = teichmuller_map(tutte, F, land, tutte[land], boundary=bnd, reference="equilateral", max_iter=100)
    assert res.converged and res.folded_faces == 0
    assert res.history[-1] < 1e-2
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
