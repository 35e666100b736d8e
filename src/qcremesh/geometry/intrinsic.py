"""The intrinsic Delaunay triangulation of a surface mesh and its cotangent Laplacian.

The cotangent Laplacian of a mesh with obtuse triangles has negative edge weights, and
its discrete harmonic functions are poor approximations of the smooth ones (the maximum
principle fails, harmonic maps fold or crowd). The intrinsic Delaunay triangulation of
the same surface (Bobenko & Springborn, "A discrete Laplace-Beltrami operator for
simplicial surfaces", Discrete Comput. Geom. 38, 2007) has the same vertices and the same
metric, flat on every triangle of the input; its edges are geodesics of the surface,
found by Lawson's flips on edge lengths alone: an edge whose two opposite angles sum to
more than pi is replaced by the other diagonal of its two triangles unfolded into the
plane. Its cotangent weights are all non-negative, and its Laplacian converges where the
input's does not.

Faces are kept as vertex triples with the lengths of their sides and, since two
vertices may be joined by several intrinsic edges, explicit twins of their half-edges:
half-edge ``3 f + k`` goes from ``F[f, k]`` to ``F[f, (k + 1) % 3]``, has length
``lengths[f, k]`` and twin ``twin[3 f + k]`` (-1 on the boundary).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..mesh.topology import face_edge_lengths, twin_half_edges
from .triangulation import best_ranked
from .vectors import aligned

__all__ = ["intrinsic_delaunay", "intrinsic_cotmatrix", "negative_cotangent_weights"]


def _half_edge_twins(F):
    """Twin of every half-edge ``3 f + k`` of a manifold mesh, -1 on the boundary, (3m,)."""
    m = len(F)
    i, j = twin_half_edges(F)
    # rows of half_edges are k * m + f; half-edge ids here are 3 f + k
    hi, hj = 3 * (i % m) + i // m, 3 * (j % m) + j // m
    twin = np.full(3 * m, -1, dtype=np.int64)
    twin[hi], twin[hj] = hj, hi
    return twin


def _cotangents(lengths):
    """Cotangent of the angle opposite every side, (m, 3): side k of a face is opposite
    its corner (k + 2) % 3. From the side lengths alone: cot = (b^2 + c^2 - a^2) / (4 A),
    with A by Heron's formula in its stable (Kahan) form."""
    a = lengths
    b, c = np.roll(a, -1, axis=1), np.roll(a, -2, axis=1)
    s = np.sort(a, axis=1)[:, ::-1]  # x >= y >= z
    x, y, z = s[:, 0], s[:, 1], s[:, 2]
    area = 0.25 * np.sqrt(np.maximum((x + (y + z)) * (z - (x - y)) * (z + (x - y)) * (x + (y - z)), 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        return (b * b + c * c - a * a) / (4 * area[:, None])


def negative_cotangent_weights(V, F):
    """Share of the interior edges of a mesh whose cotangent weight cot alpha + cot beta
    is negative (the two angles opposite the edge sum to more than pi: not Delaunay)."""
    F = np.asarray(F, dtype=np.int64)
    cot = _cotangents(face_edge_lengths(V, F)).ravel()
    twin = _half_edge_twins(F)
    h = np.flatnonzero(twin > np.arange(len(twin)))
    if len(h) == 0:
        return 0.0
    return float(np.mean(cot[h] + cot[twin[h]] < 0))


def intrinsic_delaunay(V, F, rounds=1000, flat=None):
    """Intrinsic Delaunay triangulation of a manifold triangle mesh by edge flips.

    Parameters
    ----------
    V : (n, d) float
    F : (m, 3) int
        Manifold, consistently oriented.
    rounds : int
        Maximum number of rounds of independent flips.
    flat : float, optional
        Flip only the edges whose two triangles lie in one plane, their normals within
        ``flat`` radians: the flips are then those of the mesh itself, which keep its
        surface, and the result is a triangulation of it in ``V`` (Delaunay where it is
        flat).

    Returns
    -------
    F : (m, 3) int64
        The intrinsic triangles (the same number, the same vertices; two triangles may
        share two edges).
    lengths : (m, 3) float
        ``lengths[f, k]``: intrinsic length of the side from ``F[f, k]`` to
        ``F[f, (k + 1) % 3]``.
    twin : (3m,) int64
        Twin of half-edge ``3 f + k``, -1 on the boundary.
    flips : int
    """
    F = np.array(F, dtype=np.int64)
    m = len(F)
    L = face_edge_lengths(V, F)
    twin = _half_edge_twins(F)
    flips = 0
    cot = _cotangents(L).ravel()
    # the edges to check, each by its half-edge of smaller id: at first all interior ones,
    # then those of the faces the last round changed
    h = np.flatnonzero(twin > np.arange(3 * m))
    for _ in range(rounds):
        # half-edge h is side h % 3 of its face; the angle opposite it is the cotangent of
        # that side; a tolerance keeps cocircular quads (a regular grid) as they are
        # (two faces of zero area, one with an angle of 0 opposite the edge and the other
        # with one of pi, give inf - inf: no flip mends them, and NaN is not > 0)
        with np.errstate(invalid="ignore"):
            excess = -(cot[h] + cot[twin[h]])
        if flat is not None:
            excess[~_flat_quads(V, F, h, twin[h], flat)] = 0.0
        bad = np.flatnonzero(excess > 1e-9)
        if len(bad) == 0:
            break
        h = h[bad][np.argsort(-excess[bad], kind="stable")]
        t = twin[h]
        f1, k1, f2, k2 = h // 3, h % 3, t // 3, t % 3
        # the two faces and the faces across their four outer sides: no two flips of a
        # round may touch one, so the outer twins can be relinked independently
        outer = [twin[3 * f + (k + r) % 3] // 3 for f, k in ((f1, k1), (f2, k2)) for r in (1, 2)]
        take = best_ranked([f1, f2] + [np.where(o >= 0, o, f1) for o in outer], m)
        # the candidates left out wait for a later round
        waiting = h[~take]
        h, t, f1, k1, f2, k2 = h[take], t[take], f1[take], k1[take], f2[take], k2[take]
        a, b, c = F[f1, k1], F[f1, (k1 + 1) % 3], F[f1, (k1 + 2) % 3]
        d = F[f2, (k2 + 2) % 3]
        l_ab, l_bc, l_ca = L[f1, k1], L[f1, (k1 + 1) % 3], L[f1, (k1 + 2) % 3]
        l_ad, l_db = L[f2, (k2 + 1) % 3], L[f2, (k2 + 2) % 3]
        t_bc, t_ca = twin[3 * f1 + (k1 + 1) % 3], twin[3 * f1 + (k1 + 2) % 3]
        t_ad, t_db = twin[3 * f2 + (k2 + 1) % 3], twin[3 * f2 + (k2 + 2) % 3]
        # unfold the quad: a at 0, b on the x axis, c above it, d below it
        cx = (l_ab**2 + l_ca**2 - l_bc**2) / (2 * l_ab)
        dx = (l_ab**2 + l_ad**2 - l_db**2) / (2 * l_ab)
        cy = np.sqrt(np.maximum(l_ca**2 - cx**2, 0.0))
        dy = -np.sqrt(np.maximum(l_ad**2 - dx**2, 0.0))
        l_cd = np.hypot(cx - dx, cy - dy)
        # new faces (c, a, d) and (d, b, c); sides 2 are the new edge d -> c and c -> d
        F[f1] = np.column_stack([c, a, d])
        F[f2] = np.column_stack([d, b, c])
        L[f1] = np.column_stack([l_ca, l_ad, l_cd])
        L[f2] = np.column_stack([l_db, l_bc, l_cd])
        for here, there in ((3 * f1, t_ca), (3 * f1 + 1, t_ad), (3 * f2, t_db), (3 * f2 + 1, t_bc)):
            twin[here] = there
            inside = there >= 0
            twin[there[inside]] = here[inside]
        twin[3 * f1 + 2], twin[3 * f2 + 2] = 3 * f2 + 2, 3 * f1 + 2
        cot.reshape(m, 3)[f1] = _cotangents(L[f1])
        cot.reshape(m, 3)[f2] = _cotangents(L[f2])
        flips += len(h)
        # a waiting candidate of a face rewritten in this round is another edge now: the
        # sides of those faces are checked again, each edge once
        changed = np.concatenate([3 * f1[:, None] + np.arange(3), 3 * f2[:, None] + np.arange(3)]).ravel()
        h = np.concatenate([waiting, changed])
        h = h[twin[h] >= 0]
        h = np.unique(np.minimum(h, twin[h]))
    return F, L, twin, flips


def _flat_quads(V, F, h, t, tolerance):
    """Whether the two faces of each half-edge h (its twin t) lie in one plane: their
    normals within ``tolerance`` radians."""
    f1, k1, f2, k2 = h // 3, h % 3, t // 3, t % 3
    a, b, c = V[F[f1, k1]], V[F[f1, (k1 + 1) % 3]], V[F[f1, (k1 + 2) % 3]]
    d = V[F[f2, (k2 + 2) % 3]]
    return aligned(np.cross(b - a, c - a), np.cross(a - b, d - b), tolerance)


def intrinsic_cotmatrix(F, lengths, n):
    """Cotangent Laplacian of an intrinsic triangulation, (n, n) symmetric CSR with a
    negative diagonal, in the convention of :func:`qcremesh.geometry.operators.cotmatrix`:
    L[i, j] = sum over the sides joining i and j of (cot alpha + cot beta) / 2.

    Parameters
    ----------
    F : (m, 3) int
    lengths : (m, 3) float
        Side lengths as returned by :func:`intrinsic_delaunay`.
    n : int
    """
    cot = _cotangents(lengths)
    i, j = F, np.roll(F, -1, axis=1)
    W = sp.csr_matrix(
        (np.concatenate([cot.ravel(), cot.ravel()]) / 2, (np.r_[i.ravel(), j.ravel()], np.r_[j.ravel(), i.ravel()])),
        shape=(n, n),
    )
    return (W - sp.diags(np.asarray(W.sum(axis=1)).ravel())).tocsr()
