"""Moving vertices on a triangle surface: closest points searched near a known face, the
boundary polyline parameterized by arc length, and a sparse-row gather they share.

Used by the relaxation (:mod:`qcremesh.remeshing.relax`), the snapping
(:mod:`qcremesh.remeshing.snap`) and the minimum-quality search
(:mod:`qcremesh.remeshing.min_quality`).
"""

from __future__ import annotations

import numpy as np

from ..adaptive.landmarks import boundary_angles, interpolate_on_boundary, smoothed_arc_length
from ..geometry.distance import point_face_distances, point_triangle_distance
from ..geometry.threads import map_row_chunks
from ..mesh.topology import boundary_loop
from .compiled import closest_point_near_kernel

__all__ = ["closest_point_near", "BoundaryCurve", "csr_rows", "independent_first", "nearest_per_owner"]


def closest_point_near(P, face, V, F, vertex_faces, rounds=4, workers=-1):
    """Closest points on a triangle mesh, searched among the faces around a given face.

    For each point, the candidates are the faces that share a vertex with its current
    face; the nearest candidate becomes the current face, and the search repeats (at most
    ``rounds`` times) until the face no longer changes. The points are independent, so
    large batches are split over ``workers`` threads (-1: every core; see
    :func:`~qcremesh.geometry.threads.map_row_chunks`), with the same result. With Numba
    installed the search runs compiled (:mod:`qcremesh.remeshing.compiled`), with the
    same result again.

    Parameters
    ----------
    P : (k, 3) float
    face : (k,) int
        Starting faces.
    V : (n, 3) float
    F : (m, 3) int
    vertex_faces : (n, m) sparse
        Vertex-face incidence.
    rounds : int
    workers : int

    Returns
    -------
    face : (k,) int64
    closest : (k, 3) float
    bary : (k, 3) float
        Barycentric coordinates of the closest point in ``face``.
    """
    P = np.asarray(P, dtype=np.float64)
    face = np.asarray(face, dtype=np.int64)
    search = closest_point_near_kernel() or _closest_point_near
    return map_row_chunks(search, [P, face], [V, F, vertex_faces, rounds], workers)


def _closest_point_near(P, face, V, F, vertex_faces, rounds):
    face = face.copy()
    closest = np.zeros_like(P)
    bary = np.zeros((len(P), 3))
    indptr, indices = vertex_faces.indptr, vertex_faces.indices
    # Most points stay over their face: accept the projection onto its plane when it
    # falls inside the face (that is then the closest point of the face, and of the
    # faces around it unless the surface folds back within a step).
    T = V[F[face]]
    e1, e2 = T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]
    r = P - T[:, 0]
    g11, g12, g22 = (e1 * e1).sum(1), (e1 * e2).sum(1), (e2 * e2).sum(1)
    r1, r2 = (r * e1).sum(1), (r * e2).sum(1)
    det = g11 * g22 - g12 * g12
    b1 = (g22 * r1 - g12 * r2) / det
    b2 = (g11 * r2 - g12 * r1) / det
    stay = (b1 >= 0) & (b2 >= 0) & (b1 + b2 <= 1)
    bary[stay] = np.column_stack([1 - b1 - b2, b1, b2])[stay]
    closest[stay] = T[stay, 0] + b1[stay, None] * e1[stay] + b2[stay, None] * e2[stay]
    active = np.flatnonzero(~stay)
    for _ in range(rounds):
        if len(active) == 0:
            break
        corners = F[face[active]].ravel()
        counts = indptr[corners + 1] - indptr[corners]
        owner = np.repeat(np.repeat(np.arange(len(active)), 3), counts)
        starts = np.repeat(indptr[corners], counts)
        offset = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
        cand = indices[starts + offset]
        T = V[F[cand]]
        dist, cp, b = point_triangle_distance(P[active][owner], T[:, 0], T[:, 1], T[:, 2])
        first = nearest_per_owner(dist, owner)
        new_face = cand[first]
        closest[active], bary[active] = cp[first], b[first]
        changed = new_face != face[active]
        face[active] = new_face
        active = active[changed]
    return face, closest, bary


def nearest_per_owner(dist, owner):
    """For candidates ``dist`` (c,) belonging to ``owner`` (c,) int, the index of the
    nearest candidate of each owner that has any, in increasing order of owner (ties:
    the first)."""
    if len(owner) and np.all(owner[1:] >= owner[:-1]) and not np.isnan(dist).any():
        # Grouped already (as csr_rows gives them): the first minimum of each group,
        # without a sort.
        starts = np.r_[0, np.flatnonzero(owner[1:] != owner[:-1]) + 1]
        least = np.minimum.reduceat(dist, starts)
        hit = np.flatnonzero(dist == np.repeat(least, np.diff(np.r_[starts, len(dist)])))
        return hit[np.r_[0, np.flatnonzero(np.diff(owner[hit])) + 1]]
    order = np.lexsort((dist, owner))
    return order[np.r_[0, np.flatnonzero(np.diff(owner[order])) + 1]]


def star_distance(P, X, Fo, VF, verts):
    """Distance from each point of ``P`` (p, 3) to the faces around the output vertex
    ``verts`` (p,) of the same row, and the nearest of those faces, (p,), (p,). With
    ``verts`` the nearest output vertices, the distance to the output surface: exact
    where the nearest face is around that vertex (as on a well-shaped mesh), an upper
    bound elsewhere.

    ``X`` (k, 3) and ``Fo`` (l, 3) are the output mesh, ``VF`` (k, l) CSR its
    vertex-face incidence."""
    if len(P) == 0:
        return np.zeros(0), np.zeros(0, dtype=np.int64)
    star, owner = csr_rows(VF, verts)
    d = point_face_distances(P, X, Fo, owner, star)
    first = nearest_per_owner(d, owner)
    return d[first], star[first]


def csr_rows(M, rows):
    """Column indices of the given rows of a CSR matrix, concatenated, and the position
    in ``rows`` each comes from."""
    counts = M.indptr[rows + 1] - M.indptr[rows]
    owner = np.repeat(np.arange(len(rows)), counts)
    offset = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    return M.indices[np.repeat(M.indptr[rows], counts) + offset], owner


def independent_first(A, verts):
    """The vertices of ``verts`` with no neighbour earlier in ``verts``.

    With ``verts`` in order of priority, the kept ones are pairwise non-adjacent, so
    moving all of them at once changes no face twice.

    Parameters
    ----------
    A : (k, k) CSR
        Vertex adjacency of the mesh.
    verts : (p,) int
        Distinct vertices, first the most urgent.

    Returns
    -------
    (p,) bool
    """
    rank = np.full(A.shape[0], len(verts))
    rank[verts] = np.arange(len(verts))
    ring, owner = csr_rows(A, verts)
    lowest = np.full(len(verts), len(verts))
    np.minimum.at(lowest, owner, rank[ring])
    return lowest > np.arange(len(verts))


class BoundaryCurve:
    """The input boundary polyline parameterized by its arc length s in
    [0, perimeter) smoothed at the scale ``width`` (see
    :func:`~qcremesh.adaptive.landmarks.smoothed_arc_length`), with its points on the
    surface and their images on the circle (linear in s on every edge, as the disk map
    is). With a ``density`` g per input vertex, s is measured in the metric of the sizing
    field 1 / g, so that points evenly spaced in s follow it."""

    def __init__(self, disk_uv, F, V, width, density=None):
        self.loop = boundary_loop(F)
        self.theta = boundary_angles(disk_uv, self.loop)
        self.theta_knots = np.r_[self.theta, self.theta[0] + 2 * np.pi]
        self.points = V[self.loop]
        self.s = smoothed_arc_length(self.points, width, None if density is None else np.asarray(density)[self.loop])
        self.perimeter = self.s[-1]

    def arc_length(self, theta):
        """Smoothed arc length of the boundary points at circle angles ``theta``, (k,)."""
        return np.interp(self.theta[0] + np.mod(theta - self.theta[0], 2 * np.pi), self.theta_knots, self.s)

    def edge_at(self, s):
        """Position in ``loop`` of the first vertex of the input boundary edge each arc
        length s lies on, (k,)."""
        edge = np.searchsorted(self.s, np.mod(s, self.perimeter), side="right") - 1
        return np.clip(edge, 0, len(self.loop) - 1)

    def at(self, s):
        """Disk positions (k, 2) and surface positions (k, 3) of the points at arc length s."""
        theta = np.interp(np.mod(s, self.perimeter), self.s, self.theta_knots)
        return np.column_stack([np.cos(theta), np.sin(theta)]), interpolate_on_boundary(self.theta, self.points, theta)
