"""Editing a planar triangulation: inserting points, and flipping edges by a criterion
until none gains (Lawson's flips to the Delaunay triangulation among them)."""

from __future__ import annotations

import numpy as np

from ..mesh.topology import half_edges, twin_half_edges
from .locate import locate_points
from .operators import signed_doublearea

__all__ = ["insert_points", "flip_edges", "delaunay_flips", "best_ranked"]


def insert_points(uv, F, points):
    """Insert vertices into a planar triangulation, each by splitting the triangle that
    contains it into three (in rounds of one point per triangle).

    Parameters
    ----------
    uv : (n, 2) float
        All the vertices.
    F : (m, 3) int
        Counter-clockwise triangles of some of them.
    points : (k,) int
        Vertices not in ``F`` to insert; those outside the triangulation are left out.

    Returns
    -------
    (m + 2 j, 3) int64
        Counter-clockwise triangles, with the j points inserted.
    """
    F = np.array(F, dtype=np.int64)
    while len(points):
        face, _, inside = locate_points(uv, F, uv[points])
        points, face = points[inside], face[inside]
        first = np.unique(face, return_index=True)[1]
        p, f = points[first], face[first]
        a, b, c = F[f].T
        F[f] = np.column_stack([a, b, p])
        F = np.concatenate([F, np.column_stack([b, c, p]), np.column_stack([c, a, p])])
        points = np.delete(points, first)
    return F


def best_ranked(owners, size):
    """Which candidates, in order of rank (0 best), rank first at every owner they touch:
    a set of candidates of which no two share an owner (faces or vertices a flip changes).

    Parameters
    ----------
    owners : list of (c,) int
        For each kind of owner, the owner of each candidate (indices below ``size``).
    size : int

    Returns
    -------
    (c,) bool
    """
    rank = np.arange(len(owners[0]))
    best = np.full(size, len(rank))
    for owner in owners:
        np.minimum.at(best, owner, rank)
    return np.logical_and.reduce([best[owner] == rank for owner in owners])


def flip_edges(F, gain_of, rounds, disjoint="faces"):
    """Flip interior edges where a criterion gains, in rounds of independent flips.

    Each round measures every interior edge (a, b), with faces f1 = (a, b, c) and
    f2 = (b, a, d), by ``gain_of``, and flips to (c, d), best gain first, the edges of
    positive gain that share no face (or, with ``disjoint="vertices"``, no vertex) with a
    better one; until none gains.

    Parameters
    ----------
    F : (m, 3) int
    gain_of : callable
        ``gain_of(F, f1, f2, a, b, c, d)``, all (e,) int arrays over the interior edges,
        returns their gains, (e,) float; a flip that must not happen gets a gain <= 0.
    rounds : int
        Maximum number of rounds.
    disjoint : {"faces", "vertices"}
        What the flips of one round must not share: faces, for a criterion on the two
        faces of an edge; vertices, for one on the vertices' valences (two flips at one
        vertex would both count its change).

    Returns
    -------
    F : (m, 3) int64
        The flipped triangles.
    flips : int
    """
    F = np.array(F, dtype=np.int64)
    m = len(F)
    flips = 0
    for _ in range(rounds):
        H = half_edges(F)
        opposite = np.concatenate([F[:, 2], F[:, 0], F[:, 1]])
        i, j = twin_half_edges(F)
        a, b, c, d = H[i, 0], H[i, 1], opposite[i], opposite[j]
        f1, f2 = i % m, j % m
        gain = gain_of(F, f1, f2, a, b, c, d)
        candidates = np.flatnonzero(gain > 0)
        if len(candidates) == 0:
            break
        candidates = candidates[np.argsort(-gain[candidates], kind="stable")]
        owners = (f1, f2) if disjoint == "faces" else (a, b, c, d)
        take = candidates[best_ranked([owner[candidates] for owner in owners], max(m, int(F.max()) + 1))]
        F[f1[take]] = np.column_stack([a, d, c])[take]
        F[f2[take]] = np.column_stack([d, b, c])[take]
        flips += len(take)
    return F, flips


def _angle(uv, apex, p, q):
    """Angle at ``apex`` between the directions to ``p`` and ``q``, from differences of
    coordinates (so at any scale)."""
    u, v = uv[p] - uv[apex], uv[q] - uv[apex]
    return np.arctan2(np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]), (u * v).sum(1))


def delaunay_flips(uv, F, rounds=1000):
    """Flip the edges of a planar triangulation until it is Delaunay (Lawson's algorithm).

    An interior edge (a, b) with faces (a, b, c) and (b, a, d) is flipped to (c, d) when
    its opposite angles sum to more than pi (d inside the circumcircle of (a, b, c)). The
    test is on angles measured from differences of coordinates, so it holds for triangles
    of any size, where the in-circle test of a lifting (Qhull's) loses the triangles
    below about 1e-7 of the extent of the point set.

    Parameters
    ----------
    uv : (n, 2) float
    F : (m, 3) int
        Counter-clockwise triangles.
    rounds : int
        Maximum number of rounds of independent flips.

    Returns
    -------
    (m, 3) int64
        Counter-clockwise triangles of the same vertices.
    """

    def excess(F, f1, f2, a, b, c, d):
        gain = _angle(uv, c, a, b) + _angle(uv, d, b, a) - np.pi
        valid = (signed_doublearea(uv, np.column_stack([a, d, c])) > 0) & (
            signed_doublearea(uv, np.column_stack([d, b, c])) > 0
        )
        return np.where(valid, gain - 1e-12, -1.0)

    return flip_edges(F, excess, rounds)[0]
