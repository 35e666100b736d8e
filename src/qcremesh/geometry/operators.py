"""Discrete differential operators on triangle meshes: areas, per-face gradients and
Laplacians (cotangent and uniform), assembled from numpy index arrays."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..mesh.topology import adjacency_matrix, vertex_face_incidence
from .vectors import cross, norm

__all__ = [
    "doublearea",
    "signed_doublearea",
    "vertex_areas",
    "face_normals",
    "vertex_normals",
    "face_gradients",
    "cotmatrix",
    "uniform_laplacian",
]


def doublearea(V, F):
    """Twice the (unsigned) area of every face, (m,).

    Works for planar (n, 2) and spatial (n, 3) vertices.
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F)
    a = np.take(V, F[:, 1], axis=0) - np.take(V, F[:, 0], axis=0)
    b = np.take(V, F[:, 2], axis=0) - np.take(V, F[:, 0], axis=0)
    if V.shape[1] == 2:
        return np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    return norm(cross(a, b))


def signed_doublearea(uv, F):
    """Twice the signed area of every face of a planar mesh, (m,): positive when
    counter-clockwise, negative when the face is folded over.
    """
    uv = np.asarray(uv, dtype=np.float64)
    F = np.asarray(F)
    a = np.take(uv, F[:, 1], axis=0) - np.take(uv, F[:, 0], axis=0)
    b = np.take(uv, F[:, 2], axis=0) - np.take(uv, F[:, 0], axis=0)
    return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]


def vertex_areas(V, F, n=None):
    """Barycentric area of every vertex: a third of the area of each face around it (the
    diagonal of the barycentric mass matrix), (n,); they sum to the surface's area.
    """
    n = len(V) if n is None else n
    return np.bincount(np.asarray(F).ravel(), weights=np.repeat(doublearea(V, F) / 6, 3), minlength=n)


def face_normals(V, F):
    """Unit normals of the faces, (m, 3): (v1 - v0) x (v2 - v0), normalized (zero for a
    face of no area)."""
    normals = cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    return normals / np.maximum(norm(normals), 1e-300)[:, None]


def vertex_normals(V, F, incidence=None):
    """Unit area-weighted vertex normals: the sum of the cross products
    (v1 - v0) x (v2 - v0) of the faces around each vertex, normalized, (n, 3).

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
    incidence : (n, m) sparse, optional
        The vertex-face incidence of ``F``, where it is at hand (a caller that takes the
        normals of moving vertices many times).
    """
    F = np.asarray(F)
    incidence = vertex_face_incidence(F, len(V)) if incidence is None else incidence
    P0, P1, P2 = (np.take(V, F[:, c], axis=0) for c in range(3))
    out = incidence @ cross(P1 - P0, P2 - P0)
    return out / np.maximum(norm(out), 1e-300)[:, None]


def face_gradients(uv, F):
    """Per-face gradient weights of the linear hat functions on a planar mesh.

    On face (v0, v1, v2) with opposite edges e_k = v_{k+2} - v_{k+1} (indices mod 3),
    the hat function of corner k has gradient (-e_k.y, e_k.x) / (2 A), with A the signed
    area, so a function g linear on the face has

        dg/dx = -sum_k e_k.y * g_k / (2 A),    dg/dy = sum_k e_k.x * g_k / (2 A).

    Parameters
    ----------
    uv : (n, 2) float
    F : (m, 3) int

    Returns
    -------
    Dx, Dy : (m, 3) float
        ``(Dx * g[F]).sum(1)`` is dg/dx on each face, likewise for y.
    """
    uv = np.asarray(uv, dtype=np.float64)
    F = np.asarray(F)
    P = uv[F]
    e = np.roll(P, -2, axis=1) - np.roll(P, -1, axis=1)  # e[:, k] = P[k+2] - P[k+1]
    dbl = signed_doublearea(uv, F)[:, None]
    return -e[:, :, 1] / dbl, e[:, :, 0] / dbl


def cotmatrix(V, F):
    """Cotangent Laplacian, (n, n) symmetric CSR with a negative diagonal.

    L[i, j] = (cot alpha_ij + cot beta_ij) / 2 for an edge ij with opposite angles alpha
    and beta, and L[i, i] = -sum_j L[i, j]; so ``-u @ L @ u`` is twice the Dirichlet
    energy of the piecewise-linear function u. Same convention as ``igl.cotmatrix``.

    Parameters
    ----------
    V : (n, 2) or (n, 3) float
    F : (m, 3) int
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F)
    n = len(V)
    dbl = doublearea(V, F)
    rows, cols, vals = [], [], []
    for k in range(3):
        i, j, o = F[:, (k + 1) % 3], F[:, (k + 2) % 3], F[:, k]
        a, b = V[i] - V[o], V[j] - V[o]
        cot = (a * b).sum(1) / dbl
        rows += [i, j]
        cols += [j, i]
        vals += [cot / 2, cot / 2]
    rows = np.concatenate(rows)
    cols = np.concatenate(cols)
    vals = np.concatenate(vals)
    L = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
    return L - sp.diags(np.asarray(L.sum(axis=1)).ravel())


def uniform_laplacian(F, n=None):
    """Graph Laplacian with unit edge weights (the paper's fake metric, l = 1),
    (n, n) symmetric CSR with a negative diagonal: L = A - D.
    """
    A = adjacency_matrix(F, n)
    return (A - sp.diags(np.asarray(A.sum(axis=1)).ravel())).tocsr()
