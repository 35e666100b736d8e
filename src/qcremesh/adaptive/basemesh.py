"""Base mesh of the landmarks and its subdivision levels in the disk (Algorithm 2)."""

from __future__ import annotations

import numpy as np
from scipy.spatial import Delaunay

from ..geometry.operators import signed_doublearea
from ..geometry.quality import corner_normals_up, radius_ratio, surface_side_quality
from ..geometry.triangulation import delaunay_flips, flip_edges, insert_points
from ..mesh.subdivide import upsample
from ..mesh.topology import boundary_edges

__all__ = [
    "delaunay_disk_mesh",
    "flip_for_surface_quality",
    "surface_quality",
    "flip_for_valence",
    "subdivide_disk_mesh",
    "hexagonal_disk_points",
]

# Smallest radius ratio on the surface of the two faces a valence flip makes.
VALENCE_FLIP_QUALITY = 0.5


def delaunay_disk_mesh(theta, interior, margin=0.2):
    """Delaunay triangulation of boundary points on the unit circle and interior points.

    Every point of the circle is extreme, so the triangulation covers the inscribed
    polygon of the boundary points exactly and its boundary loop is that polygon.
    Interior points outside that polygon (between an edge and its arc) would become
    boundary vertices, and points just inside an edge would make a sliver with it: the
    points closer to the line of their sector's edge than ``margin`` times the edge's
    length, or beyond it, are left out. For the edge between the angles t_i and t_{i+1},
    a point at radius r and angle phi in that sector is kept when
    r cos(phi - (t_i + t_{i+1}) / 2) < cos(d / 2) - margin 2 sin(d / 2), d = t_{i+1} - t_i.

    Parameters
    ----------
    theta : (b,) float
        Increasing angles of the boundary points (b >= 3), within one turn.
    interior : (k, 2) float
        Points strictly inside the disk.
    margin : float

    Returns
    -------
    uv : (b + j, 2) float
        The boundary points first, in the order of ``theta``, then the interior points
        kept (j <= k), in their order.
    F : (m, 3) int64
        Counter-clockwise triangles.
    """
    theta = np.asarray(theta, dtype=np.float64)
    interior = np.asarray(interior, dtype=np.float64).reshape(-1, 2)
    phi = theta[0] + np.mod(np.arctan2(interior[:, 1], interior[:, 0]) - theta[0], 2 * np.pi)
    knots = np.r_[theta, theta[0] + 2 * np.pi]
    i = np.clip(np.searchsorted(knots, phi, side="right") - 1, 0, len(theta) - 1)
    d = knots[i + 1] - knots[i]
    height = np.hypot(interior[:, 0], interior[:, 1]) * np.cos(phi - (knots[i] + knots[i + 1]) / 2)
    interior = interior[height < np.cos(d / 2) - margin * 2 * np.sin(d / 2)]
    uv = np.concatenate([np.column_stack([np.cos(theta), np.sin(theta)]), interior])
    F = Delaunay(uv).simplices.astype(np.int64)
    cw = signed_doublearea(uv, F) < 0
    F[cw] = F[cw][:, ::-1]
    return _include_every_point(uv, F, len(theta))


def _include_every_point(uv, F, b):
    """Qhull leaves out points it cannot tell apart from a neighbour or from the line of
    two neighbours at its precision: points whose distances are below about 1e-7 of the
    disk's size, where the disk map crowds the surface (the boundary at the end of a long
    strip, the far end of a long tube, about 1e-9 from the centre). A boundary point left
    out is put back into the triangle on the chord that skips it (split into a fan from
    that triangle's third corner; one fan around the triangle where chords skip points on
    two or three of its edges). Interior points left out are inserted into the
    triangles that contain them (:func:`~qcremesh.geometry.triangulation.insert_points`)
    and the edges flipped until the triangulation is Delaunay again
    (:func:`~qcremesh.geometry.triangulation.delaunay_flips`, whose test on angles does
    not depend on the scale); one that no triangle contains (on a chord, at rounding) is
    dropped."""
    used = np.zeros(len(uv), dtype=bool)
    used[F.ravel()] = True
    if used.all():
        return uv, F
    on_hull = np.flatnonzero(used[:b])
    following = np.roll(on_hull, -1)
    gap = np.mod(following - on_hull, b) > 1
    first, last = on_hull[gap], following[gap]
    # The triangle on each chord (first, last): the one with that directed edge.
    n = len(uv)
    keys = (F * n + np.roll(F, -1, axis=1)).ravel()  # row f, column j: edge F[f, j] -> F[f, j + 1]
    order = np.argsort(keys)
    face = order[np.searchsorted(keys[order], first * n + last)] // 3
    chords = dict(zip(first.tolist(), last.tolist()))

    def path(p, q):
        """Along the triangle's edge p -> q: the boundary points its chord skips, then q."""
        if chords.get(p) != q:
            return np.array([q])
        return np.r_[np.arange(p + 1, q if q > p else q + b) % b, q]

    # Each triangle on a chord becomes a fan from its corner opposite the chord over the
    # points skipped (a triangle can have two or three such chords, where Qhull left out
    # runs of points on each: the fan then runs over all of them, around the triangle).
    fans = []
    for f in face[np.sort(np.unique(face, return_index=True)[1])]:
        c = F[f].tolist()
        j = next(j for j in range(3) if chords.get(c[j]) == c[(j + 1) % 3])
        k = c[(j + 2) % 3]
        around = np.concatenate([path(k, c[j]), path(c[j], c[(j + 1) % 3]), path(c[(j + 1) % 3], k)[:-1]])
        fans.append(np.column_stack([around[:-1], around[1:], np.full(len(around) - 1, k)]))
    F = np.concatenate([np.delete(F, np.unique(face), axis=0)] + fans)
    missing = np.flatnonzero(~used[b:]) + b
    if len(missing):
        F = delaunay_flips(uv, insert_points(uv, F, missing))
    # An interior point that no triangle takes (on a chord, at rounding) is dropped.
    kept = np.flatnonzero(np.isin(np.arange(n), F) | (np.arange(n) < b))
    if len(kept) == n:
        return uv, F
    renumber = np.full(n, -1)
    renumber[kept] = np.arange(len(kept))
    return uv[kept], renumber[F]


def flip_for_surface_quality(uv, F, X, flippable, rounds=50, up=None):
    """Flip interior edges of a disk mesh where that raises the smaller radius ratio of
    their two faces on the surface, keeping the mesh an embedding of the disk.

    Where the disk map is conformal, the Delaunay triangulation of the disk is the
    Delaunay triangulation of the surface too; where it is not, its triangles are
    stretched on the surface (a strip whose ends the map crowds, a surface cut along
    slits). An edge (a, b) with faces (a, b, c) and (b, a, d) becomes (c, d) when
    min(q(a, d, c), q(d, b, c)) > min(q(a, b, c), q(b, a, d)), q measured at the surface
    positions ``X`` (negated where a face is turned over on the surface, with ``up``),
    and both new faces are counter-clockwise in the disk. Each round flips, best gain
    first, edges that share no face, until none gains.

    Parameters
    ----------
    uv : (n, 2) float
    F : (m, 3) int
        Counter-clockwise triangles of the disk.
    X : (n, 3) float
        The vertices' points on the surface.
    flippable : (n,) bool
        An edge may flip only when a corner of its two faces is flippable.
    rounds : int
    up : (n, 3) float, optional
        Unit normals of the surface at the vertices' points: a face whose normal makes
        more than 90 degrees with their sum is turned over, and its radius ratio counts
        negated (:func:`qcremesh.geometry.quality.surface_side_quality`; not judged where
        the three normals disagree, :func:`~qcremesh.geometry.quality.corner_normals_up`).

    Returns
    -------
    F : (m, 3) int64
        The flipped triangles (the same number).
    flips : int
    """

    def gain(F, f1, f2, a, b, c, d):
        old, new, embedded = _flip_quality(uv, X, F, f1, f2, a, b, c, d, up)
        gain = new - old
        ok = (flippable[a] | flippable[b] | flippable[c] | flippable[d]) & (gain > 1e-6) & embedded
        return np.where(ok, gain, -1.0)

    return flip_edges(F, gain, rounds)


def surface_quality(X, F, up=None):
    """Radius ratio of faces ``F`` on a surface at the vertices' points ``X``, (m,),
    negated where a face is turned over against the unit normals ``up`` (n, 3) of the
    surface at its corners (see :func:`flip_for_surface_quality`)."""
    if up is None:
        return radius_ratio(X, F)
    return surface_side_quality(X, F, corner_normals_up(np.take(up, F, axis=0)))


def _flip_quality(uv, X, F, f1, f2, a, b, c, d, up=None):
    """For flips of edges (a, b) with faces f1 = (a, b, c), f2 = (b, a, d) to (c, d): the
    smaller radius ratio on the surface of the two faces before and after (negated where
    turned over, with ``up``: :func:`surface_quality`), and whether both new faces are
    counter-clockwise in the disk; (e,) each."""
    new1, new2 = np.column_stack([a, d, c]), np.column_stack([d, b, c])
    q = surface_quality(X, F, up)
    embedded = (signed_doublearea(uv, new1) > 0) & (signed_doublearea(uv, new2) > 0)
    return np.minimum(q[f1], q[f2]), np.minimum(surface_quality(X, new1, up), surface_quality(X, new2, up)), embedded


def flip_for_valence(uv, F, X, wanted, rounds=20, bound=None, monotone=True):
    """Flip edges of a disk mesh so that its vertices have the numbers of faces wanted:
    three at a boundary vertex, as a straight border of equilateral triangles has, as
    many as their angle asks for at the corners, six at an interior vertex.

    A Delaunay triangulation of landmarks on the circle gives many of them two faces (two
    right angles where the surface border is straight) or four; subdivision keeps the
    count, so the output has faces of radius ratio about 0.83 or less around them, which
    no relaxation mends (a star-shaped planar domain: mean radius ratio 0.963 at the
    border, 0.977 with these flips). An edge (a, b) with faces (a, b, c) and (b, a, d)
    becomes (c, d), which takes a face from a and b and gives one to c and d, when that
    lowers sum (3 / wanted)^2 (faces - wanted)^2 over the vertices with a wanted count
    (a face too many at a right-angled corner, which wants 2, turns its faces' angles
    from 45 to 30 degrees; at a straight border, from 60 to 45), keeps the
    interior valences within 5-7, and makes two faces counter-clockwise in the disk whose
    smaller radius ratio on the surface (at ``X``) is at least ``VALENCE_FLIP_QUALITY``
    and, with ``monotone``, at least that of the two faces replaced (without, for a mesh
    relaxed after the flips, which evens out the faces they skew). Where a flip takes a
    face from a vertex with more than it wants whose ``bound`` is below
    ``VALENCE_FLIP_QUALITY`` (a corner sharper than about 17 degrees), it needs only the
    latter (the tooth of a ragged border cut by a plane, 11 degrees at its tip, kept the
    three faces that made its output's slivers). Each round flips, best gain first, edges
    that share no vertex.

    The base mesh's interior vertices are left to its subdivision and Teichmueller map;
    where the base mesh is the output (no level), relaxed, about half of them have six
    faces, and flips towards six without ``monotone`` before a second relaxation (as an
    isotropic remesher flips) raise that to about two thirds (camel_b.obj at its face
    count: 0.50 -> 0.66, mean radius ratio 0.940 -> 0.953).

    Parameters
    ----------
    uv : (n, 2) float
    F : (m, 3) int
        Counter-clockwise triangles of the disk.
    X : (n, 3) float
        The vertices' points on the surface.
    wanted : (n,) bool or int
        The faces wanted at each vertex: 3 where True (a straight border), the count
        given where an int (a corner of angle a: about a / 60 degrees, 6 inside), none
        where False or 0.
    rounds : int
    bound : (n,) float, optional
        The largest radius ratio a face at each vertex can have on the surface (at a
        corner, :func:`qcremesh.geometry.quality.corner_radius_ratio_bound`); 1 by
        default.
    monotone : bool
        Whether a flip must also not lower the smaller radius ratio of the two faces.

    Returns
    -------
    F : (m, 3) int64
        The flipped triangles (the same number).
    flips : int
    """
    on = np.zeros(len(uv), dtype=bool)
    on[boundary_edges(F).ravel()] = True
    wanted = np.asarray(wanted)
    wanted = 3 * wanted.astype(np.int64) if wanted.dtype == bool else wanted.astype(np.int64)
    # A face more or less turns the faces' angles at a vertex of angle 60 w by about
    # 60 / w degrees: the squares weighed by (3 / w)^2, 1 on a straight border.
    weight = np.where(wanted > 0, (3.0 / np.maximum(wanted, 1)) ** 2, 0.0)
    bound = np.ones(len(uv)) if bound is None else np.asarray(bound, dtype=np.float64)

    def gain(F, f1, f2, a, b, c, d):
        count = np.bincount(F.ravel(), minlength=len(uv))
        excess = np.where(wanted > 0, count - wanted, 0)
        # w (faces - wanted)^2 of a and b with one face less, of c and d with one more
        drop = (
            weight[a] * (2 * excess[a] - 1)
            + weight[b] * (2 * excess[b] - 1)
            - weight[c] * (2 * excess[c] + 1)
            - weight[d] * (2 * excess[d] + 1)
        )
        # an interior vertex has as many neighbours as faces
        interior_ok = (on[a] | (count[a] > 5)) & (on[b] | (count[b] > 5)) & (on[c] | (count[c] < 7)) & (
            on[d] | (count[d] < 7)
        )
        old, new, embedded = _flip_quality(uv, X, F, f1, f2, a, b, c, d)
        # (a sharp corner's faces cannot reach VALENCE_FLIP_QUALITY)
        sharp = ((excess[a] > 0) & (bound[a] < VALENCE_FLIP_QUALITY)) | (
            (excess[b] > 0) & (bound[b] < VALENCE_FLIP_QUALITY)
        )
        floor = np.where(sharp, old, np.maximum(VALENCE_FLIP_QUALITY, old)) if monotone else VALENCE_FLIP_QUALITY
        ok = (drop > 0) & interior_ok & (new >= floor) & embedded
        return np.where(ok, drop + new, -1.0)

    return flip_edges(F, gain, rounds, disjoint="vertices")


def subdivide_disk_mesh(uv, F, levels):
    """Midpoint subdivision of a disk mesh, ``levels`` times, with the new boundary
    vertices moved onto the unit circle (along the bisector of their edge).

    Parameters
    ----------
    uv : (n, 2) float
        A mesh of the disk whose boundary vertices lie on the unit circle.
    F : (m, 3) int
    levels : int

    Returns
    -------
    list of (uv, F)
        Level 0 (the input) to level ``levels``; the vertices of each level are the first
        vertices of the next, and face ``f`` of a level is split into faces ``4f .. 4f+3``
        of the next (the semi-regular structure).
    """
    out = [(np.asarray(uv, dtype=np.float64), np.asarray(F, dtype=np.int64))]
    for _ in range(levels):
        uv, F = out[-1]
        n = len(uv)
        uv2, F2 = upsample(uv, F, 1)
        on_circle = np.zeros(len(uv2), dtype=bool)
        on_circle[boundary_edges(F2).ravel()] = True
        new = on_circle.copy()
        new[:n] = False
        uv2[new] /= np.linalg.norm(uv2[new], axis=1, keepdims=True)
        out.append((uv2, F2))
    return out


def hexagonal_disk_points(spacing):
    """Points of a hexagonal lattice with the given spacing inside the unit disk, at least
    half a spacing away from the circle (the interior of a uniform disk mesh).

    Returns
    -------
    (k, 2) float
    """
    rows = np.arange(-np.ceil(1 / spacing), np.ceil(1 / spacing) + 1)
    dy = spacing * np.sqrt(3) / 2
    j, i = np.meshgrid(rows, np.arange(-np.ceil(1 / dy), np.ceil(1 / dy) + 1))
    x = (j + 0.5 * (i % 2)) * spacing
    y = i * dy
    P = np.column_stack([x.ravel(), y.ravel()])
    return P[np.hypot(P[:, 0], P[:, 1]) < 1 - 0.5 * spacing]
