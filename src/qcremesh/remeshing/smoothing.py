"""One sweep of tangential smoothing on the surface, the step the relaxation repeats.

Each vertex moved goes ``step`` of the way to the mean of its neighbours, less the
component of that displacement along its vertex normal, by at most a quarter of its mean
edge length, and is put back onto the input surface at the closest point among the input
faces around the one it was on (a local search, so it never jumps to another sheet of the
surface across a thin part); its disk coordinates follow by barycentric interpolation of
the parameterization on that face. A boundary vertex takes the component of the same
displacement along the boundary, as a step of its arc length. Used by the relaxation
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

__all__ = ["boundary_arc_steps", "edge_lengths", "smooth_targets", "smoothing_sweep"]


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


def smoothing_sweep(X, uv, face, verts, ring, out, surface, step):
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
    verts, ring, step
        As for :func:`smooth_targets`.
    out : OutputMesh
        The output's connectivity (:class:`~qcremesh.remeshing.meshes.OutputMesh`).
    surface : InputSurface
        The input surface and its disk map (:class:`~qcremesh.remeshing.meshes.InputSurface`).

    Returns
    -------
    X, uv, face
        New arrays: the vertices ``verts`` moved, the others as they were.
    """
    targets = (smooth_targets_kernel() or smooth_targets)(X, verts, ring, out.F, out.VF, out.E, step)
    new_X, new_uv, new_face = X.copy(), uv.copy(), face.copy()
    f, cp, b = closest_point_near(targets, face[verts], surface.V, surface.F, surface.vertex_faces)
    new_face[verts], new_X[verts] = f, cp
    new_uv[verts] = interpolate_barycentric(surface.F, f, b, surface.disk_uv)
    return new_X, new_uv, new_face


def boundary_arc_steps(X, loop, ring, s_prev, s, s_next):
    """Arc-length steps that move the vertices of a boundary loop towards the mean of all
    their neighbours along the boundary, (b,):

        delta_i = ((mean_N(i) x - x_i) . c_i) (s_next,i - s_prev,i) / |c_i|^2,
        c_i = x_next,i - x_prev,i,

    the component of the umbrella displacement along the chord between the vertex's two
    boundary neighbours, converted into arc length at the rate the chord spans it, and
    kept within half the way to either neighbour. The interior neighbours count as the
    boundary ones do, so the boundary spacing follows the size of the faces along it
    (the mean of the two boundary neighbours alone spaces the boundary evenly, which
    shears the boundary faces where the faces inside are larger or smaller).

    Parameters
    ----------
    X : (k, 3) float
        Vertices.
    loop : (b,) int
        The boundary loop, in order.
    ring : (b, k) CSR
        Its rows of the adjacency matrix.
    s_prev, s, s_next : (b,) float
        Arc-length positions of each loop vertex's previous neighbour, itself and its
        next neighbour along the loop (unwrapped: s_prev < s < s_next).

    Returns
    -------
    (b,) float
    """
    x = X[loop]
    umbrella = (ring @ X) / np.diff(ring.indptr)[:, None] - x
    chord = np.roll(x, -1, axis=0) - np.roll(x, 1, axis=0)
    along = (umbrella * chord).sum(1) / np.maximum((chord * chord).sum(1), 1e-300)
    return np.clip(along * (s_next - s_prev), (s_prev - s) / 2, (s_next - s) / 2)
