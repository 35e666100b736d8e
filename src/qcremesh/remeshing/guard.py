"""Keeping the snapping and the last searches of the relaxation from moving the output off
the input vertices that the snapping reached.

The snapping (:mod:`qcremesh.remeshing.snap`) brings the output within reach of the input
vertices at the bottoms of pockets and on the tips it spans. The searches after it score
the shape of the faces only, and the last two moved vertices that kept such a vertex
within reach away from it: the short search in which snapped vertices may move again to
mend a face below 0.4 (:func:`qcremesh.remeshing.min_quality.raise_min_quality`;
human_face at half its face count, seed 2: an input vertex 0.54 % of the diagonal from
the output after the snapping, 1.28 % after it) and the search for well-shaped faces
(:mod:`qcremesh.remeshing.regularize`). The snapping itself did the same where it pulls
one vertex past another input vertex it covered: in camel_b's leg it moved the vertices
over a hoof's sole to other far points, taking sole vertices from 0.3-0.8 to 1.0-1.5
(its reach 1.07), and nothing pulled them back. :class:`DistanceGuard` watches the input
vertices that are not close to the output and refuses a candidate position of an output
vertex that takes one of them, near its star, farther from the star than a limit (the
snapping's reach), or farther than it is where it already is; in the snapping, or
farther than the input vertex pulling it. Where the snapping drapes the rings around a
vertex after it, all of them move at once, and the guard judges the patch of faces they
moved (:meth:`DistanceGuard.excluded_patches`).

Measured on an Intel Xeon on the eight disk meshes of ``../shared/data`` at their face
count and half of it, seeds 0-3, against no guard, mean (max) Hausdorff distance in % of
the diagonal: camel_b 1.357 (1.53) / 1.595 (1.75) -> 1.267 (1.53) / 1.529 (1.59),
human_face 0.492 (0.71) / 0.836 (1.28) -> 0.492 (0.71) / 0.664 (0.88), human_brain 0.471
(0.57) / 0.661 (0.78) -> 0.456 (0.57) / 0.596 (0.65), hand.ply at its face count 0.203 ->
0.199, the distances of the 9 other meshes and counts the same; the mean radius ratio and
the share of faces above 0.9 the same to 1e-3. The smallest radius ratio of human_face 0.457 / 0.462 -> 0.401 / 0.315:
a face below 0.4 that a vertex would have mended by leaving a pocket stays. With the
guard in the last two searches only: camel_b 1.357 / 1.595, human_face 0.492 / 0.646,
human_brain 0.456 / 0.654. Without the allowance of the pulling vertex's distance in the
snapping: camel_b at its face count 1.220, human_face at half 0.716. Time: human_face /
human_brain at half their face counts 0.85 / 2.48 s without the guard, 0.97 / 2.50 s
with it (1.28 / 3.60 s before the candidates that cannot take a point beyond the limit
were left unmeasured and the distances compiled, when the benchmark showed it).

Tried and not kept: guarding every search after the first snapping, and the output's side
as well (the centroids and edge midpoints of the faces around a moving vertex kept within
the limit of the input, or no farther than they are): human_face at its face count /
half, seeds 0-3, mean 0.49 / 0.84 -> 0.47 / 0.63 %, but 2.5 times the time of the whole
remesh on human_face (the distances of points off the input from its skinny faces) and
nothing gained elsewhere.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..geometry.distance import point_face_distances
from ..geometry.operators import vertex_normals
from ..geometry.threads import query_workers
from ..geometry.vectors import norm
from .onsurface import csr_rows, star_distance

__all__ = ["DistanceGuard"]

# Input vertices closer to the output than this fraction of the limit are not watched.
WATCH = 0.1


def _moved_stars(X, Fo, VF, verts, Xc):
    """The faces around each of ``verts`` (p,) with the vertex at each of its candidate
    positions ``Xc`` (p, c, 3): the faces (s,), the row of ``verts`` of each (s,), and
    the moved faces (s, c, 3) of the output vertices followed by the candidates,
    (k + p c, 3)."""
    star, owner = csr_rows(VF, verts)
    c = Xc.shape[1]
    T = np.repeat(Fo[star][:, None], c, axis=1)
    corner = np.argmax(Fo[star] == verts[owner][:, None], axis=1)
    T[np.arange(len(star))[:, None], np.arange(c)[None, :], corner[:, None]] = (
        len(X) + owner[:, None] * c + np.arange(c)[None, :]
    )
    return star, owner, T, np.concatenate([X, Xc.reshape(-1, 3)])


class DistanceGuard:
    """The input vertices farther than ``WATCH * limit`` from an output surface, their
    distances from it and their nearest output faces, kept up to date as output vertices
    move.

    Parameters
    ----------
    X : (k, 3) float
        Output vertices.
    Fo : (l, 3) int
        Output faces.
    VF : (k, l) CSR
        Vertex-face incidence of ``Fo``.
    V : (n, 3) float
        Input vertices.
    limit : float
        Distance from the output beyond which no move takes a watched input vertex (or,
        where it is already beyond, no farther than it is).
    query : tuple of (n,) float and (n,) int, optional
        The distance of each input vertex to its nearest output vertex and that vertex,
        ``cKDTree(X).query(V)``, where the caller has it already.

    Attributes
    ----------
    points : (w,) int
        The watched input vertices: those that stand farther than ``WATCH * limit / 2``
        off the tangent plane of their nearest output vertex and are farther than
        ``WATCH * limit`` from the faces around it.
    distance : (w,) float
        Their distances from the output, measured to the faces around their nearest
        output vertex (exact where the nearest face is among them, an upper bound
        elsewhere).
    face : (w,) int
        Their nearest output faces.
    """

    def __init__(self, X, Fo, VF, V, limit, query=None):
        self.V, self.limit = V, limit
        gap, nearest = cKDTree(X).query(V, workers=query_workers(len(V))) if query is None else query
        normal = vertex_normals(X, Fo)
        height = np.abs(((V - X[nearest]) * normal[nearest]).sum(1))
        # No farther from the output than from its nearest vertex.
        points = np.flatnonzero((height > WATCH * limit / 2) & (gap > WATCH * limit))
        distance, face = star_distance(V[points], X, Fo, VF, nearest[points])
        keep = distance > WATCH * limit
        self.points, self.distance, self.face = points[keep], distance[keep], face[keep]

    def _pairs(self, Fo, verts):
        """The watched points whose nearest face has a corner among ``verts``, and the
        row of ``verts`` of that corner, (r,), (r,)."""
        where = np.full(int(Fo.max()) + 1, -1)
        where[verts] = np.arange(len(verts))
        corners = where[Fo[self.face]]
        point, corner = np.nonzero(corners >= 0)
        return point, corners[point, corner]

    def excluded(self, X, Fo, VF, verts, Xc, allow=None):
        """Which candidate positions ``Xc`` (p, c, 3) of the output vertices ``verts``
        (p,), no two on a common face, take a watched point whose nearest face is around
        the vertex farther from the faces around it than the limit (and than it is, and
        than ``allow`` (p,) of the moving vertex), (p, c) bool. ``X`` holds the vertices
        where they are before the move: a point's distance from the star grows by no more
        than the vertex moves, so only the candidates that could take it beyond what is
        allowed are measured."""
        bad = np.zeros(Xc.shape[:2], dtype=bool)
        point, row = self._pairs(Fo, verts)
        allowed = np.maximum(self.limit, self.distance[point])
        if allow is not None:
            allowed = np.maximum(allowed, allow[row])
        step = norm(Xc[row] - X[verts[row]][:, None])
        measure = self.distance[point][:, None] + step > allowed[:, None]
        keep = np.flatnonzero(measure.any(axis=1))
        if len(keep) == 0:
            return bad
        point, row, allowed, measure = point[keep], row[keep], allowed[keep], measure[keep]
        star, owner, T, Y = _moved_stars(X, Fo, VF, verts[row], Xc[row])
        c = Xc.shape[1]
        Q = np.repeat(self.points[point[owner]], c)
        d = point_face_distances(self.V, Y, T.reshape(-1, 3), Q, np.arange(len(Q)))
        starts = np.r_[0, np.cumsum(np.bincount(owner, minlength=len(point)))[:-1]]
        d = np.minimum.reduceat(d.reshape(len(star), c), starts, axis=0)
        np.logical_or.at(bad, row, measure & (d > allowed[:, None] * (1 + 1e-9)))
        return bad

    def excluded_patches(self, X, Fo, faces, patch, allow):
        """Which patches of faces, moved already, take a watched point whose nearest face
        is among them farther from them than the limit (and than it is, and than ``allow``
        of the patch), (r,) bool.

        Parameters
        ----------
        X : (k, 3) float
            Output vertices, where the patches moved them.
        Fo : (l, 3) int
            Output faces.
        faces : (s,) int
            The faces of the patches, each in one patch.
        patch : (s,) int
            The patch of each, in [0, r).
        allow : (r,) float
        """
        r = len(allow)
        of_face = np.full(len(Fo), -1)
        of_face[faces] = patch
        point = np.flatnonzero(of_face[self.face] >= 0)
        bad = np.zeros(r, dtype=bool)
        if len(point) == 0:
            return bad
        which = of_face[self.face[point]]
        order = np.argsort(patch, kind="stable")
        count = np.bincount(patch, minlength=r)
        start = np.cumsum(count) - count
        # every watched point against every face of its patch
        n = count[which]
        i = np.repeat(np.arange(len(point)), n)
        j = faces[order][np.repeat(start[which], n) + np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)]
        d = point_face_distances(self.V[self.points[point]], X, Fo, i, j)
        d = np.minimum.reduceat(d, np.cumsum(n) - n)
        allowed = np.maximum(np.maximum(self.limit, self.distance[point]), allow[which])
        np.logical_or.at(bad, which, d > allowed * (1 + 1e-9))
        return bad

    def update(self, X, Fo, VF, moved):
        """After the output vertices ``moved`` (int array) moved: the distances and
        nearest faces of the watched points whose nearest face has one of them as a
        corner, measured to the faces around the three corners of that face."""
        point = np.unique(self._pairs(Fo, moved)[0])
        if len(point) == 0:
            return
        P = np.repeat(self.V[self.points[point]], 3, axis=0)
        d, f = star_distance(P, X, Fo, VF, Fo[self.face[point]].ravel())
        d, f = d.reshape(-1, 3), f.reshape(-1, 3)
        best = np.argmin(d, axis=1)
        rows = np.arange(len(point))
        self.distance[point] = d[rows, best]
        self.face[point] = f[rows, best]
