"""Candidate positions of an output vertex on the input surface, and the radius ratios
of the faces around it there: what the two pattern searches of the relaxation share
(:mod:`qcremesh.remeshing.min_quality`, :mod:`qcremesh.remeshing.regularize`).
"""

from __future__ import annotations

import numpy as np

from ..geometry.distance import point_segment_distance
from ..geometry.locate import interpolate_barycentric
from ..geometry.quality import corner_normals_up, surface_side_quality
from ..geometry.vectors import cross, norm
from .onsurface import closest_point_near, csr_rows, independent_first

__all__ = [
    "DIRECTIONS",
    "StarQuality",
    "boundary_candidates",
    "boundary_deviation",
    "input_up",
    "mean_edge_length",
    "star_radius_ratios",
    "tangent_candidates",
]

# Directions of the tangent plane the candidates are offset in.
DIRECTIONS = 8


def input_up(T, face, input_normals):
    """Normal of the input surface under output faces ``T``: the sum of the input face
    normals at their three vertices (``face`` is the input face each output vertex lies
    on, -1 on a boundary that slides; on a cut, which is fixed, the face beside it), (f,
    3). Faces with a vertex at -1 get zero and are never taken as turned over: along a
    jagged scan border the input's normals are too irregular to judge by (judged by the
    normals under their other vertices: camel_b min q 0.339 -> 0.140 at its face count,
    hand.ply 3 faces through others). So do faces over a fold of the input
    (:func:`~qcremesh.geometry.quality.corner_normals_up`): a face across the two walls of
    a narrow pocket has no side, and taken as turned over it blocked every move of its
    vertices (human_face at half its face count, seed 1: min q 0.079, now 0.485)."""
    under = np.take(face, T)
    up = corner_normals_up(np.take(input_normals, under, axis=0))
    up[(under < 0).any(1)] = 0.0
    return up


def mean_edge_length(X, A, verts):
    """Mean length of the edges at each vertex, (p,)."""
    ring, owner = csr_rows(A, verts)
    return np.bincount(owner, norm(X[ring] - X[verts[owner]])) / np.bincount(owner)


def tangent_candidates(X, out, verts, reach, face, surface, steps):
    """Candidate positions of interior vertices: offsets of ``steps`` times ``reach`` in
    8 directions of the tangent plane of each vertex (the normal of its star), snapped
    onto the input surface near the vertex's face (``out`` the output's connectivity and
    ``surface`` the input, as :mod:`qcremesh.remeshing.meshes` holds them).

    Returns
    -------
    Xc : (p, c, 3) float
    uvc : (p, c, 2) float
        Surface and disk positions, c = 8 len(steps) per vertex.
    fc : (p, c) int64
        The input faces under them.
    """
    angles = 2 * np.pi * np.arange(DIRECTIONS) / DIRECTIONS
    star, owner = csr_rows(out.VF, verts)
    T = np.take(X, np.take(out.F, star, axis=0), axis=0)
    normal = np.stack(
        [np.bincount(owner, c, len(verts)) for c in cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]).T], axis=1
    )
    normal /= np.maximum(norm(normal), 1e-300)[:, None]
    t1 = cross(normal, np.eye(3)[np.argmin(np.abs(normal), axis=1)])
    # (a star whose faces' normals cancel, folded onto itself, has none: no offsets)
    t1 /= np.maximum(norm(t1), 1e-300)[:, None]
    t2 = cross(normal, t1)
    offsets = (np.cos(angles)[:, None, None] * t1 + np.sin(angles)[:, None, None] * t2)[:, None]
    offsets = offsets * (steps[None, :, None, None] * reach[:, None])
    offsets = offsets.reshape(-1, len(verts), 3).transpose(1, 0, 2)  # (p, c, 3)
    c = offsets.shape[1]
    f, cp, b = closest_point_near(
        (X[verts][:, None] + offsets).reshape(-1, 3), np.repeat(face[verts], c), surface.V, surface.F,
        surface.vertex_faces,
    )
    uvc = interpolate_barycentric(surface.F, f, b, surface.disk_uv).reshape(-1, c, 2)
    return cp.reshape(-1, c, 3), uvc, f.reshape(-1, c)


def boundary_candidates(s, i, reach, curve, steps):
    """Candidate positions of boundary vertices, slid along the input boundary by
    ``steps`` times ``reach`` either way, each kept between its two boundary neighbours
    (no closer than a tenth of the way to either).

    Parameters
    ----------
    s : (b,) float
        Arc length of the output boundary loop's vertices along ``curve``, increasing.
    i : (p,) int
        Positions in the loop of the vertices to move.
    reach : (p,) float
    curve : BoundaryCurve
    steps : (t,) float

    Returns
    -------
    Xc : (p, c, 3) float
    uvc : (p, c, 2) float
        Surface and disk positions, c = 2 t per vertex.
    sc : (p, c) float
        Their arc lengths.
    """
    s_prev, s_next = s[i - 1] - (i == 0) * curve.perimeter, s[(i + 1) % len(s)]
    s_next = s_next + (i == len(s) - 1) * curve.perimeter
    shift = np.concatenate([steps, -steps])[None, :] * reach[:, None]
    lo, hi = 0.9 * s_prev + 0.1 * s_next, 0.1 * s_prev + 0.9 * s_next
    sc = np.clip(s[i][:, None] + shift, lo[:, None], hi[:, None])
    uvc, Xc = curve.at(sc.ravel())
    c = sc.shape[1]
    return Xc.reshape(-1, c, 3), uvc.reshape(-1, c, 2), sc


def boundary_deviation(s, i, Xc, sc, X_loop, curve):
    """How far the output boundary strays from the input boundary around boundary
    vertices at candidate positions: the largest distance from the input boundary's
    vertices between a vertex's two boundary neighbours to the output boundary path
    through them and the candidate, (p, c) (0 where no input vertex lies between).

    Parameters
    ----------
    s : (b,) float
        Arc length of the output boundary loop's vertices along ``curve``, increasing.
    i : (p,) int
        Positions in the loop of the vertices.
    Xc : (p, c, 3) float
    sc : (p, c) float
        Candidate surface positions and their arc lengths.
    X_loop : (b, 3) float
        Surface positions of the output boundary loop.
    curve : BoundaryCurve
    """
    b, per = len(s), curve.perimeter
    s_prev = s[i - 1] - (i == 0) * per
    s_next = s[(i + 1) % b] + (i == b - 1) * per
    # the input boundary's vertices over three turns, so every span is one run of them
    knots = np.concatenate([curve.s[:-1] - per, curve.s[:-1], curve.s[:-1] + per])
    points = np.tile(curve.points, (3, 1))
    lo = np.searchsorted(knots, s_prev, side="right")
    count = np.searchsorted(knots, s_next, side="left") - lo
    owner = np.repeat(np.arange(len(i)), count)
    at = np.repeat(lo, count) + np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    P, arc = points[at], knots[at]
    c = Xc.shape[1]
    before = arc[:, None] < sc[owner]
    ends = np.where(before[..., None], X_loop[(i - 1) % b][owner][:, None], X_loop[(i + 1) % b][owner][:, None])
    dist = point_segment_distance(
        np.repeat(P, c, axis=0), ends.reshape(-1, 3), Xc[owner].reshape(-1, 3)
    )[0].reshape(-1, c)
    out = np.zeros((len(i), c))
    np.maximum.at(out, owner, dist)
    return out


def star_radius_ratios(X, uv, Fo, VF, verts, Xc, uvc, face, input_normals):
    """Radius ratio of every face around each vertex, for candidate positions of the
    vertex.

    With the vertex at a candidate position, each face of its star has edge lengths
    a, b, c and twice the area 2A = |n| with n its normal, and radius ratio
    q = 4 (2A)^2 / ((a + b + c) a b c). A candidate that folds a face in the disk
    (non-positive signed area) or leaves it turned over on the surface (its normal more
    than 90 degrees from the input's normal under it, see :func:`input_up`) gets -1 for
    that face.

    Parameters
    ----------
    X : (k, 3) float
    uv : (k, 2) float
    Fo : (l, 3) int
    VF : (k, l) CSR
        Vertex-face incidence of ``Fo``.
    verts : (p,) int
        Vertices to score, no two on a common face.
    Xc : (p, c, 3) float
    uvc : (p, c, 2) float
        Candidate surface and disk positions of every vertex.
    face : (k,) int
        Input face each output vertex lies on.
    input_normals : (m, 3) float
        Unit normals of the input faces.

    Returns
    -------
    q : (t, c) float
        For the t faces of the stars, star after star.
    starts : (p,) int
        Row of ``q`` where each vertex's star starts.
    """
    star, owner = csr_rows(VF, verts)
    T = Fo[star]
    corner = np.argmax(T == verts[owner][:, None], axis=1)
    P, U = np.take(X, T, axis=0), np.take(uv, T, axis=0)
    surface_up = input_up(T, face, input_normals)
    c = Xc.shape[1]
    P = np.repeat(P[:, None], c, axis=1)
    U = np.repeat(U[:, None], c, axis=1)
    rows, cols = np.arange(len(star))[:, None], np.arange(c)[None, :]
    P[rows, cols, corner[:, None]] = Xc[owner]
    U[rows, cols, corner[:, None]] = uvc[owner]
    e = np.roll(P, -1, axis=2) - P
    length = norm(e)
    normal = cross(P[:, :, 1] - P[:, :, 0], P[:, :, 2] - P[:, :, 0])
    dbl = norm(normal)
    den = length.sum(2) * length.prod(2)
    q = np.divide(4 * dbl**2, den, out=np.zeros_like(den), where=den > 0)
    a, b = U[:, :, 1] - U[:, :, 0], U[:, :, 2] - U[:, :, 0]
    valid = (a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0] > 0) & ((normal * surface_up[:, None]).sum(2) >= 0)
    starts = np.r_[0, np.cumsum(np.bincount(owner, minlength=len(verts)))[:-1]]
    return np.where(valid, q, -1.0), starts


class StarQuality:
    """The radius ratio of every output face, negated where the face is turned over on
    the surface (:func:`surface_side_quality`), and the smallest of them around every
    vertex, kept up to date as vertices move.

    Attributes
    ----------
    q : (l,) float
        Per face.
    qv : (k,) float
        Per vertex: the smallest ``q`` of its star.
    """

    def __init__(self, X, Fo, VF, face, input_normals):
        self.Fo, self.VF, self.input_normals = Fo, VF, input_normals
        self.q = surface_side_quality(X, Fo, input_up(Fo, face, input_normals))
        self.qv = np.minimum.reduceat(self.q[VF.indices], VF.indptr[:-1])

    def worst_independent(self, A, active):
        """The ``active`` vertices (bool mask) whose star is worse than that of every
        active neighbour (ties by index): no two of them share a face, so they can move
        at once. Increasing indices."""
        act = np.flatnonzero(active)
        act = act[np.lexsort((act, self.qv[act]))]
        return np.sort(act[independent_first(A, act)])

    def update(self, X, face, moved):
        """After the vertices ``moved`` moved: their faces and the stars around them."""
        touched = np.unique(csr_rows(self.VF, moved)[0])
        self.q[touched] = surface_side_quality(
            X, self.Fo[touched], input_up(self.Fo[touched], face, self.input_normals)
        )
        around = np.unique(self.Fo[touched])
        star, owner = csr_rows(self.VF, around)
        self.qv[around] = np.minimum.reduceat(self.q[star], np.r_[0, np.cumsum(np.bincount(owner))[:-1]])
