"""One sweep of tangential smoothing on the surface, the step the relaxation repeats.

Each vertex moved goes ``step`` of the way to the mean of its neighbours, less the
component of that displacement along its vertex normal, by at most a quarter of its mean
edge length, and is put back onto the input surface at the closest point among the input
faces around the one it was on (a local search, so it never jumps to another sheet of the
surface across a thin part); its disk coordinates follow by barycentric interpolation of
the parameterization on that face. Used by the relaxation
(:mod:`qcremesh.remeshing.relax`) and by the snapping, which drapes the rings around a
vertex it pulls after it (:mod:`qcremesh.remeshing.snap`).
"""

from __future__ import annotations

import numpy as np

from ..geometry.locate import interpolate_barycentric
from ..geometry.operators import vertex_normals
from ..geometry.vectors import norm
from .compiled import smooth_targets_kernel
from .onsurface import closest_point_near

__all__ = ["edge_lengths", "smooth_targets", "smoothing_sweep"]


def edge_lengths(X, E):
    """Lengths of the edges ``E`` (e, 2) of the vertices ``X``, (e,)."""
    return norm(np.take(X, E[:, 0], axis=0) - np.take(X, E[:, 1], axis=0))


def smooth_targets(X, verts, ring, Fo, VF, E, step):
    """Where one sweep of tangential smoothing sends the vertices ``verts``, before they
    are put back onto the surface, (p, 3):

        x_v + min(1, r_v / (4 |d_v|)) d_v,   d_v = step (I - n_v n_v^T) (mean_N(v) x - x_v),

    with n_v the area-weighted vertex normal and r_v the mean length of the edges at v.
    With Numba, :mod:`qcremesh.remeshing.compiled` computes the same to the last bit.

    Parameters
    ----------
    X : (k, 3) float
        Vertices.
    verts : (p,) int
        Those to move.
    ring : (p, k) CSR
        Their rows of the adjacency matrix, with sorted indices.
    Fo : (l, 3) int
        Faces.
    VF : (k, l) CSR
        Vertex-face incidence of ``Fo``.
    E : (e, 2) int
        The edges of ``Fo``, sorted.
    step : float
        Fraction of the way to the mean of the neighbours.

    Returns
    -------
    (p, 3) float
    """
    k = len(X)
    deg = np.diff(ring.indptr)
    normal = vertex_normals(X, Fo, VF)[verts]
    d = (ring @ X) / deg[:, None] - X[verts]
    d -= (d * normal).sum(1, keepdims=True) * normal
    length = edge_lengths(X, E)
    reach = (np.bincount(E[:, 0], length, k) + np.bincount(E[:, 1], length, k))[verts] / deg
    d *= step
    d *= np.minimum(1.0, 0.25 * reach / np.maximum(norm(d), 1e-300))[:, None]
    return X[verts] + d


def smoothing_sweep(X, uv, face, verts, ring, Fo, VF, E, V, F, disk_uv, vertex_faces, step):
    """One sweep of tangential smoothing of the vertices ``verts`` of an output mesh on the
    input surface.

    Parameters
    ----------
    X : (k, 3) float
        Output vertices, on the input surface.
    uv : (k, 2) float
        Their disk positions.
    face : (k,) int
        The input face under each (-1 where not known: the boundary).
    verts, ring, Fo, VF, E, step
        As for :func:`smooth_targets`.
    V : (n, 3) float
    F : (m, 3) int
        The input surface.
    disk_uv : (n, 2) float
        Its disk parameterization.
    vertex_faces : (n, m) CSR
        Vertex-face incidence of ``F``.

    Returns
    -------
    X, uv, face
        New arrays: the vertices ``verts`` moved, the others as they were.
    """
    targets = (smooth_targets_kernel() or smooth_targets)(X, verts, ring, Fo, VF, E, step)
    new_X, new_uv, new_face = X.copy(), uv.copy(), face.copy()
    f, cp, b = closest_point_near(targets, face[verts], V, F, vertex_faces)
    new_face[verts], new_X[verts] = f, cp
    new_uv[verts] = interpolate_barycentric(F, f, b, disk_uv)
    return new_X, new_uv, new_face
