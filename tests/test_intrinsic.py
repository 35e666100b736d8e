"""The intrinsic Delaunay triangulation and its Laplacian, where the answers are known."""

import warnings

import numpy as np
from scipy.spatial import Delaunay

from conftest import DATA, grid_disk
from qcremesh.beltrami.coefficient import beltrami_coefficient, metric_beltrami_coefficient
from qcremesh.geometry.intrinsic import intrinsic_cotmatrix, intrinsic_delaunay, negative_cotangent_weights
from qcremesh.geometry.operators import cotmatrix, signed_doublearea
from qcremesh.mesh.io import read_mesh
from qcremesh.mesh.topology import face_edge_lengths
from qcremesh.param.tutte import tutte_embedding


def squeezed_triangulation(seed=1):
    """Points of the unit square triangulated by the Delaunay triangulation of the points
    squeezed 5 times along y: valid, but far from Delaunay; as a flat surface in space."""
    uv = np.random.default_rng(seed).uniform(0, 1, (300, 2))
    F = Delaunay(uv * [1, 0.2]).simplices.astype(np.int64)
    F[signed_doublearea(uv, F) < 0] = F[signed_doublearea(uv, F) < 0][:, ::-1]
    return uv, np.column_stack([uv, np.zeros(len(uv))]), F


def test_intrinsic_delaunay_of_a_flat_domain_is_its_delaunay_triangulation():
    """On a flat convex domain the intrinsic Delaunay triangulation is the Delaunay
    triangulation of the points: the flips recover Qhull's from the squeezed one (23 % of
    its interior edges not Delaunay), with the lengths of the sides in the plane and
    consistent twins; a Delaunay triangulation does not change."""
    uv, V, F = squeezed_triangulation()
    assert negative_cotangent_weights(V, F) > 0.2
    G, lengths, twin, flips = intrinsic_delaunay(V, F)
    assert flips > 0 and G.shape == F.shape
    assert {tuple(sorted(f)) for f in G} == {tuple(sorted(f)) for f in Delaunay(uv).simplices}
    np.testing.assert_allclose(lengths, face_edge_lengths(V, G), atol=1e-14)
    h = np.flatnonzero(twin >= 0)
    np.testing.assert_array_equal(twin[twin[h]], h)
    np.testing.assert_array_equal(G.ravel()[h], np.roll(G, -1, axis=1).ravel()[twin[h]])
    assert negative_cotangent_weights(V, G) == 0.0
    same, _, _, none = intrinsic_delaunay(V, G)
    assert none == 0 and np.array_equal(same, G)


def test_intrinsic_cotmatrix():
    """Of an embedded triangulation, the cotangent Laplacian from its side lengths alone;
    after the flips, no negative weight on an interior edge, and constants in its kernel."""
    _, V, F = squeezed_triangulation()
    L = intrinsic_cotmatrix(F, face_edge_lengths(V, F), len(V))
    np.testing.assert_allclose(L.toarray(), cotmatrix(V, F).toarray(), atol=1e-9)
    G, lengths, twin, _ = intrinsic_delaunay(V, F)
    L = intrinsic_cotmatrix(G, lengths, len(V)).tocoo()
    np.testing.assert_allclose(np.asarray(L.sum(axis=1)).ravel(), 0, atol=1e-9)
    inner = np.zeros((len(V), len(V)), dtype=bool)
    h = np.flatnonzero(twin >= 0)
    inner[G.ravel()[h], np.roll(G, -1, axis=1).ravel()[h]] = True
    off = (L.row != L.col) & inner[L.row, L.col]
    assert L.data[off].min() >= -1e-12


def test_metric_beltrami_coefficient_of_a_surface():
    """With the side lengths of a mesh in space, the coefficient of its Tutte embedding
    onto the surface (Eq. 19) from the lengths alone; the affine map z + 0.3 conj(z) has
    0.3 on every face."""
    V, F = read_mesh(DATA / "fran_cut.ply")
    T = tutte_embedding(F)
    mu = metric_beltrami_coefficient(T, F, face_edge_lengths(V, F))
    np.testing.assert_allclose(mu, beltrami_coefficient(T, F, V), atol=1e-12)
    uv, F = grid_disk(6, jitter=0.3)
    z = uv[:, 0] + 1j * uv[:, 1]
    w = z + 0.3 * np.conj(z)
    target = np.column_stack([w.real, w.imag, np.zeros(len(w))])
    np.testing.assert_allclose(metric_beltrami_coefficient(uv, F, face_edge_lengths(target, F)), 0.3, atol=1e-12)


def test_intrinsic_delaunay_leaves_two_faces_of_zero_area_without_a_warning():
    """Two collinear faces on one edge, one with an angle of pi opposite it and the other
    an angle of 0 (cotangents -inf and inf): no flip mends them, none is made, and no
    RuntimeWarning escapes (a boundary spike far off a scan took one to the CLI)."""
    V = np.array([[0.0, 0, 0], [2, 0, 0], [1, 0, 0], [3, 0, 0]])
    F = np.array([[0, 1, 2], [1, 0, 3]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        G, _, _, flips = intrinsic_delaunay(V, F)
    assert flips == 0 and np.array_equal(G, F)
