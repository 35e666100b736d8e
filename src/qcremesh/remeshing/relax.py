"""Tangential relaxation of a remeshed surface that keeps every vertex on the input
surface and the connectivity unchanged.

An optional last stage of :func:`qcremesh.remeshing.pipeline.remesh`, beyond the paper. Each
sweep moves every interior vertex towards the centroid of its neighbours, tangentially
(the component along the vertex normal is removed), by at most a quarter of its mean
edge length, and snaps it back onto the input surface at the closest point among the input faces
around the face it was on (a local search, so a vertex never jumps to another sheet of
the surface across a thin part). Its disk coordinates follow by barycentric interpolation
of the parameterization on that face. Boundary vertices slide along the input boundary
polyline: their arc-length position (measured on the boundary smoothed at the landmark
spacing, so narrow notches are skipped) becomes the mean of their two boundary neighbours';
boundary corners stay. A vertex whose move would fold one of its faces in the disk stays
where it is, so the disk mesh stays an embedding and the surface mesh its orientation.

Smoothing pulls vertices out of the deep narrow pockets of a surface (nostrils, sulci)
that a disk map compresses, so the output spans them: the input vertices left far from
the output then get the nearest output vertex moved onto them, where that keeps its
faces valid (measured: Hausdorff distance on human_face 2.75 -> 1.45 % of the diagonal,
human_brain 1.13 -> 0.67 %).

The sweeps regularize the mesh on average but leave the worst triangles where the surface
bends sharply or the boundary is jagged. A last stage then raises the minimum quality: the
vertices around the worst faces move, one independent set at a time, to the position
that maximizes the smallest radius ratio of their faces (see :func:`relax_on_surface`).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..adaptive.landmarks import boundary_angles, interpolate_on_boundary, smoothed_arc_length
from ..geometry.distance import point_mesh_distance, point_triangle_distance
from ..geometry.locate import interpolate_barycentric, locate_points
from ..geometry.operators import signed_doublearea
from ..geometry.quality import radius_ratio
from ..mesh.topology import adjacency_matrix, boundary_loop, edges, vertex_face_incidence

__all__ = ["relax_on_surface", "closest_point_near"]


def closest_point_near(P, face, V, F, vertex_faces, rounds=4):
    """Closest points on a triangle mesh, searched among the faces around a given face.

    For each point, the candidates are the faces that share a vertex with its current
    face; the nearest candidate becomes the current face, and the search repeats (at most
    ``rounds`` times) until the face no longer changes.

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

    Returns
    -------
    face : (k,) int64
    closest : (k, 3) float
    bary : (k, 3) float
        Barycentric coordinates of the closest point in ``face``.
    """
    face = np.asarray(face, dtype=np.int64).copy()
    closest = np.zeros_like(P, dtype=np.float64)
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
        order = np.lexsort((dist, owner))
        first = order[np.r_[0, np.flatnonzero(np.diff(owner[order])) + 1]]
        new_face = cand[first]
        closest[active], bary[active] = cp[first], b[first]
        changed = new_face != face[active]
        face[active] = new_face
        active = active[changed]
    return face, closest, bary


def _vertex_normals(X, Fo, VF):
    """Unit area-weighted vertex normals, (k, 3); ``VF`` is the (k, l) vertex-face
    incidence of ``Fo``."""
    out = VF @ np.cross(X[Fo[:, 1]] - X[Fo[:, 0]], X[Fo[:, 2]] - X[Fo[:, 0]])
    return out / np.maximum(np.linalg.norm(out, axis=1, keepdims=True), 1e-300)


def _rows(M, rows):
    """Column indices of the given rows of a CSR matrix, concatenated, and the position
    in ``rows`` each comes from."""
    counts = M.indptr[rows + 1] - M.indptr[rows]
    owner = np.repeat(np.arange(len(rows)), counts)
    offset = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    return M.indices[np.repeat(M.indptr[rows], counts) + offset], owner


class _BoundaryCurve:
    """The input boundary polyline parameterized by its arc length s in
    [0, perimeter) smoothed at the scale ``width`` (see
    :func:`~qcremesh.adaptive.landmarks.smoothed_arc_length`), with its points on the
    surface and their images on the circle (linear in s on every edge, as the disk map
    is)."""

    def __init__(self, disk_uv, F, V, width):
        self.loop = boundary_loop(F)
        self.theta = boundary_angles(disk_uv, self.loop)
        self.theta_knots = np.r_[self.theta, self.theta[0] + 2 * np.pi]
        self.points = V[self.loop]
        self.s = smoothed_arc_length(self.points, width)
        self.perimeter = self.s[-1]

    def arc_length(self, theta):
        """Smoothed arc length of the boundary points at circle angles ``theta``, (k,)."""
        return np.interp(self.theta[0] + np.mod(theta - self.theta[0], 2 * np.pi), self.theta_knots, self.s)

    def at(self, s):
        """Disk positions (k, 2) and surface positions (k, 3) of the points at arc length s."""
        theta = np.interp(np.mod(s, self.perimeter), self.s, self.theta_knots)
        return np.column_stack([np.cos(theta), np.sin(theta)]), interpolate_on_boundary(self.theta, self.points, theta)


def _surface_side(X, T, up):
    """Radius ratio of faces ``T`` of a mesh on a surface, negated where the face is
    turned over: its normal makes more than 90 degrees with ``up``, the normal of the
    input surface under it. (f,) for T (f, 3), up (f, 3)."""
    P = X[T]
    normal = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    return np.where((normal * up).sum(1) >= 0, 1.0, -1.0) * radius_ratio(X, T)


def _input_up(T, face, input_normals):
    """Normal of the input surface under interior output faces ``T``: the sum of the
    input face normals at their three vertices (``face`` is the input face each output
    vertex lies on, -1 on the boundary), (f, 3). Faces with a boundary vertex get zero
    and are never taken as turned over: along a jagged scan border the input's normals
    are too irregular to judge by."""
    up = input_normals[face[T]].sum(1)
    up[(face[T] < 0).any(1)] = 0.0
    return up


def _star_scores(X, uv, Fo, VF, verts, Xc, uvc, face, input_normals):
    """Smallest radius ratio over the faces around each vertex, for candidate positions of
    the vertex.

    With the vertex at a candidate position, each face of its star has edge lengths
    a, b, c and twice the area 2A = |n| with n its normal, and radius ratio
    q = 4 (2A)^2 / ((a + b + c) a b c). A candidate that folds a face in the disk
    (non-positive signed area) or leaves it turned over on the surface (its normal more
    than 90 degrees from the input's normal under it, see :func:`_input_up`) scores -1.

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
    (p, c) float
    """
    star, owner = _rows(VF, verts)
    T = Fo[star]
    corner = np.argmax(T == verts[owner][:, None], axis=1)
    P, U = X[T], uv[T]
    surface_up = _input_up(T, face, input_normals)
    c = Xc.shape[1]
    P = np.repeat(P[:, None], c, axis=1)
    U = np.repeat(U[:, None], c, axis=1)
    rows, cols = np.arange(len(star))[:, None], np.arange(c)[None, :]
    P[rows, cols, corner[:, None]] = Xc[owner]
    U[rows, cols, corner[:, None]] = uvc[owner]
    e = np.roll(P, -1, axis=2) - P
    length = np.linalg.norm(e, axis=3)
    normal = np.cross(P[:, :, 1] - P[:, :, 0], P[:, :, 2] - P[:, :, 0])
    dbl = np.linalg.norm(normal, axis=2)
    den = length.sum(2) * length.prod(2)
    q = np.divide(4 * dbl**2, den, out=np.zeros_like(den), where=den > 0)
    a, b = U[:, :, 1] - U[:, :, 0], U[:, :, 2] - U[:, :, 0]
    valid = (a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0] > 0) & ((normal * surface_up[:, None]).sum(2) >= 0)
    score = np.where(valid, q, -1.0)
    starts = np.r_[0, np.cumsum(np.bincount(owner, minlength=len(verts)))[:-1]]
    return np.minimum.reduceat(score, starts, axis=0)


_SNAP_MIN_QUALITY = 0.3


def _snap_to_far_points(X, uv, face, Fo, bnd, pinned, V, F, disk_uv, reach):
    """Move output vertices onto the input vertices farthest from the output surface (the
    bottoms of pockets and the tips the output cuts across): the input vertices farther
    than ``reach`` times the mean output edge length from the output, and at least as far
    as their neighbours, each pull the nearest interior vertex of their closest output
    face, where the move keeps the disk mesh an embedding and the vertex's faces above a
    radius ratio of 0.3. Updates ``X``, ``uv``, ``face`` and ``pinned`` (the snapped
    vertices are pinned) in place."""
    k = len(X)
    E = edges(Fo)
    h = np.linalg.norm(X[E[:, 0]] - X[E[:, 1]], axis=1).mean()
    # The distance to the nearest output vertex bounds the distance to the output from
    # above: only the input vertices farther than h from every output vertex can be
    # farther than h from the output.
    dist = cKDTree(X).query(V, workers=-1)[0]
    far = np.flatnonzero(dist > reach * h)
    if len(far) == 0:
        return
    near_face = np.zeros(len(V), dtype=np.int64)
    dist[:] = 0.0
    dist[far], near_face[far], _ = point_mesh_distance(V[far], X, Fo)
    # input vertices at least as far as all their neighbours, and farther than h
    A_in = adjacency_matrix(F, len(V))
    nbr_max = np.maximum.reduceat(dist[A_in.indices], A_in.indptr[:-1])
    far = far[(dist[far] >= nbr_max[far]) & (dist[far] > reach * h)]
    if len(far) == 0:
        return
    on_bnd = np.zeros(k, dtype=bool)
    on_bnd[bnd] = True
    T = Fo[near_face[far]]
    j = np.argmin(np.linalg.norm(X[T] - V[far][:, None], axis=2), axis=1)
    target = T[np.arange(len(far)), j]
    keep = ~on_bnd[target] & ~pinned[target]
    far, target = far[keep], target[keep]
    order = np.argsort(-dist[far])
    far, target = far[order], target[order]
    _, first = np.unique(target, return_index=True)
    first = np.sort(first)  # farthest first
    far, target = far[first], target[first]
    # no two moving vertices on one face: a vertex yields to a farther neighbour
    rank = np.full(k, len(target))
    rank[target] = np.arange(len(target))
    A = adjacency_matrix(Fo, k)
    ring, owner = _rows(A, target)
    lowest = np.full(len(target), len(target))
    np.minimum.at(lowest, owner, rank[ring])
    free = lowest > np.arange(len(target))
    far, target = far[free], target[free]
    VF = vertex_face_incidence(Fo, k)
    vf_in = vertex_face_incidence(F, len(V))
    old_X, old_uv = X[target].copy(), uv[target].copy()
    X[target], uv[target] = V[far], disk_uv[far]
    star, owner = _rows(VF, target)
    ok_face = (signed_doublearea(uv, Fo[star]) > 0) & (radius_ratio(X, Fo[star]) >= _SNAP_MIN_QUALITY)
    ok = np.bincount(owner, weights=~ok_face, minlength=len(target)) == 0
    X[target[~ok]], uv[target[~ok]] = old_X[~ok], old_uv[~ok]
    target, far = target[ok], far[ok]
    face[target] = vf_in.indices[vf_in.indptr[far]]
    pinned[target] = True


_STEPS = np.array([0.02, 0.06, 0.15, 0.3, 0.5])
_DIRECTIONS = 8


def _optimize_min_quality(X, uv, face, s, Fo, bnd, pinned, V, F, disk_uv, vertex_faces, curve, target, rounds):
    """Pattern search that raises the smallest radius ratio of the faces around the
    vertices of the worst faces (see :func:`relax_on_surface`). Updates ``X``, ``uv``,
    ``face`` and ``s`` in place."""
    k = len(X)
    VF = vertex_face_incidence(Fo, k)
    A = adjacency_matrix(Fo, k)
    where_bnd = np.full(k, -1)
    where_bnd[bnd] = np.arange(len(bnd))
    angles = 2 * np.pi * np.arange(_DIRECTIONS) / _DIRECTIONS
    # Faces turned over on the surface (in pockets the disk map compresses, a face can be
    # counter-clockwise in the disk and still face into the surface) count as negative
    # quality, so the search turns them back first.
    input_normals = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    input_normals /= np.maximum(np.linalg.norm(input_normals, axis=1, keepdims=True), 1e-300)
    q = _surface_side(X, Fo, _input_up(Fo, face, input_normals))
    qv = np.minimum.reduceat(q[VF.indices], VF.indptr[:-1])
    stuck = np.zeros(k, dtype=bool)
    for _ in range(rounds):
        active = (qv < target) & ~pinned & ~stuck
        if not active.any():
            break
        # An independent set: the active vertices whose star is worse than any active
        # neighbour's (ties by index), so no two moving vertices share a face.
        act = np.flatnonzero(active)
        rank = np.full(k, len(act))
        rank[act[np.lexsort((act, qv[act]))]] = np.arange(len(act))
        ring, owner = _rows(A, act)
        starts = np.r_[0, np.cumsum(np.diff(A.indptr)[act])[:-1]]
        sel = act[rank[act] < np.minimum.reduceat(rank[ring], starts)]
        ring, owner = _rows(A, sel)
        reach = np.zeros(k)
        reach[sel] = np.bincount(owner, np.linalg.norm(X[ring] - X[sel[owner]], axis=1)) / np.bincount(owner)
        on_bnd = where_bnd[sel] >= 0
        best_X, best_uv = X[sel].copy(), uv[sel].copy()
        best_face, best_s = face[sel].copy(), np.zeros(len(sel))
        gain = np.zeros(len(sel), dtype=bool)
        inner = sel[~on_bnd]
        if len(inner):
            star, owner = _rows(VF, inner)
            T = X[Fo[star]]
            normal = np.stack(
                [np.bincount(owner, c, len(inner)) for c in np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]).T], axis=1
            )
            normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
            t1 = np.cross(normal, np.eye(3)[np.argmin(np.abs(normal), axis=1)])
            t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
            t2 = np.cross(normal, t1)
            offsets = (np.cos(angles)[:, None, None] * t1 + np.sin(angles)[:, None, None] * t2)[:, None]
            offsets = offsets * (_STEPS[None, :, None, None] * reach[inner][:, None])
            offsets = offsets.reshape(-1, len(inner), 3).transpose(1, 0, 2)  # (p, c, 3)
            c = offsets.shape[1]
            f, cp, b = closest_point_near(
                (X[inner][:, None] + offsets).reshape(-1, 3), np.repeat(face[inner], c), V, F, vertex_faces
            )
            Xc = cp.reshape(-1, c, 3)
            uvc = interpolate_barycentric(F, f, b, disk_uv).reshape(-1, c, 2)
            score = _star_scores(X, uv, Fo, VF, inner, Xc, uvc, face, input_normals)
            j = np.argmax(score, axis=1)
            rows = np.arange(len(inner))
            better = score[rows, j] > qv[inner] + 1e-9
            best_X[~on_bnd] = np.where(better[:, None], Xc[rows, j], X[inner])
            best_uv[~on_bnd] = np.where(better[:, None], uvc[rows, j], uv[inner])
            best_face[~on_bnd] = np.where(better, f.reshape(-1, c)[rows, j], face[inner])
            gain[~on_bnd] = better
        if on_bnd.any():
            outer = sel[on_bnd]
            i = where_bnd[outer]
            s_prev, s_next = s[i - 1] - (i == 0) * curve.perimeter, s[(i + 1) % len(bnd)]
            s_next = s_next + (i == len(bnd) - 1) * curve.perimeter
            shift = np.concatenate([_STEPS, -_STEPS])[None, :] * reach[outer][:, None]
            lo, hi = 0.9 * s_prev + 0.1 * s_next, 0.1 * s_prev + 0.9 * s_next
            sc = np.clip(s[i][:, None] + shift, lo[:, None], hi[:, None])
            uvc, Xc = curve.at(sc.ravel())
            c = sc.shape[1]
            score = _star_scores(
                X, uv, Fo, VF, outer, Xc.reshape(-1, c, 3), uvc.reshape(-1, c, 2), face, input_normals
            )
            j = np.argmax(score, axis=1)
            rows = np.arange(len(outer))
            better = score[rows, j] > qv[outer] + 1e-9
            best_X[on_bnd] = np.where(better[:, None], Xc.reshape(-1, c, 3)[rows, j], X[outer])
            best_uv[on_bnd] = np.where(better[:, None], uvc.reshape(-1, c, 2)[rows, j], uv[outer])
            best_s[on_bnd] = np.where(better, sc[rows, j], s[i])
            gain[on_bnd] = better
        X[sel], uv[sel], face[sel] = best_X, best_uv, best_face
        s[where_bnd[sel[on_bnd]]] = best_s[on_bnd]
        stuck[sel[~gain]] = True
        moved = sel[gain]
        if len(moved):
            stuck[_rows(A, moved)[0]] = False
            touched = np.unique(_rows(VF, moved)[0])
            q[touched] = _surface_side(X, Fo[touched], _input_up(Fo[touched], face, input_normals))
            around = np.unique(Fo[touched])
            star, owner = _rows(VF, around)
            qv[around] = np.minimum.reduceat(q[star], np.r_[0, np.cumsum(np.bincount(owner))[:-1]])


def relax_on_surface(
    disk_uv,
    F,
    V,
    uv,
    Fo,
    *,
    iterations=10,
    step=0.5,
    pinned=None,
    boundary_scale=None,
    snap=1.0,
    min_quality=0.6,
    rounds=300,
):
    """Move the vertices of a mesh of the disk so that its image on the surface gets more
    regular, without changing its connectivity.

    First ``iterations`` sweeps of tangential smoothing (see the module documentation).
    Then at most ``rounds`` rounds of a search for the minimum quality: each round takes
    the vertices whose star (faces around them) has a radius ratio below
    ``min_quality``, keeps an independent set of them (a vertex whose star is worse than
    that of every such neighbour), and moves each to the best of a pattern of candidate
    positions if it raises the smallest radius ratio of its star. Interior candidates are
    offsets of 0.02 to 0.5 times the vertex's mean edge length in 8 directions of its
    tangent plane, snapped onto the surface near the current position; boundary
    candidates slide along the input boundary polyline by the same arc lengths, staying
    between their neighbours. Candidates that fold a face in the disk or flip its normal
    on the surface are rejected. A vertex that found no better position is left alone
    until a neighbour moves.

    Parameters
    ----------
    disk_uv : (n, 2) float
        Conformal parameterization of the input surface (boundary on the circle).
    F : (m, 3) int
        Input faces.
    V : (n, 3) float
        Input vertices.
    uv : (k, 2) float
        Disk positions of the output vertices (boundary ones on the circle).
    Fo : (l, 3) int
        Output faces, counter-clockwise in the disk.
    iterations : int
        Number of smoothing sweeps.
    step : float
        Fraction of the displacement applied per sweep, in (0, 1].
    pinned : (k,) bool, optional
        Vertices that must not move (e.g. boundary corners).
    boundary_scale : float, optional
        Scale at which the boundary is smoothed to measure the arc length along which the
        boundary vertices are spaced (notches narrower than it are skipped); the mean
        output boundary edge length by default.
    snap : float
        After the sweeps, the input vertices farther than ``snap`` mean output edge
        lengths from the output (the bottoms of pockets the output spans, which the
        smoothing pulls vertices out of) each get the nearest output vertex moved onto
        them where that keeps the faces around it valid; 0 skips this.
    min_quality : float
        Radius ratio below which the stars are optimized (0 skips that stage).
    rounds : int
        Maximum number of rounds of the minimum-quality search.

    Returns
    -------
    uv : (k, 2) float
        New disk positions.
    X : (k, 3) float
        Their positions on the surface.
    """
    uv = np.array(uv, dtype=np.float64)
    k = len(uv)
    bnd = boundary_loop(Fo)
    if boundary_scale is None:
        loop = boundary_loop(F)
        boundary_scale = np.linalg.norm(V[np.roll(loop, -1)] - V[loop], axis=1).sum() / len(bnd)
    curve = _BoundaryCurve(disk_uv, F, V, boundary_scale)
    perimeter = curve.perimeter
    pinned = np.zeros(k, dtype=bool) if pinned is None else np.array(pinned, dtype=bool)
    on_circle = np.zeros(k, dtype=bool)
    on_circle[bnd] = True
    inner = np.flatnonzero(~on_circle)
    free = ~on_circle & ~pinned
    A = adjacency_matrix(Fo, k)
    deg = np.asarray(A.sum(axis=1)).ravel()
    E = edges(Fo)
    vertex_faces = vertex_face_incidence(F, len(V))
    VF = vertex_face_incidence(Fo, k)

    face = np.full(k, -1, dtype=np.int64)  # input face under each vertex; -1: boundary
    X = np.zeros((k, 3))
    face[inner], bary, _ = locate_points(disk_uv, F, uv[inner])
    X[inner] = interpolate_barycentric(F, face[inner], bary, V)
    theta = np.arctan2(uv[bnd, 1], uv[bnd, 0])
    X[bnd] = interpolate_on_boundary(curve.theta, curve.points, theta)
    s = curve.arc_length(theta)
    s = s[0] + np.mod(s - s[0], perimeter)  # increasing along the output loop
    moved = np.flatnonzero(free)
    A_moved, deg_moved = A[moved], deg[moved]
    for _ in range(iterations):
        normal = _vertex_normals(X, Fo, VF)[moved]
        d = (A_moved @ X) / deg_moved[:, None] - X[moved]
        d -= (d * normal).sum(1, keepdims=True) * normal
        length = np.linalg.norm(X[E[:, 0]] - X[E[:, 1]], axis=1)
        reach = (np.bincount(E[:, 0], length, k) + np.bincount(E[:, 1], length, k))[moved] / deg_moved
        d *= step
        d *= np.minimum(1.0, 0.25 * reach / np.maximum(np.linalg.norm(d, axis=1), 1e-300))[:, None]
        new_X, new_uv, new_face = X.copy(), uv.copy(), face.copy()
        f, cp, b = closest_point_near(X[moved] + d, face[moved], V, F, vertex_faces)
        new_face[moved], new_X[moved] = f, cp
        new_uv[moved] = interpolate_barycentric(F, f, b, disk_uv)
        # boundary: 1D smoothing of arc length along the output boundary loop
        s_prev, s_next = np.roll(s, 1), np.roll(s, -1)
        s_prev[0] -= perimeter
        s_next[-1] += perimeter
        s_new = np.where(pinned[bnd], s, s + step * ((s_prev + s_next) / 2 - s))
        new_uv[bnd], new_X[bnd] = curve.at(s_new)
        # keep the disk mesh an embedding: undo the moves around faces that would fold
        revert = np.zeros(k, dtype=bool)
        while True:
            bad = signed_doublearea(new_uv, Fo) <= 0
            grow = np.zeros(k, dtype=bool)
            grow[Fo[bad].ravel()] = True
            grow &= ~revert
            if not grow.any():
                break
            revert |= grow
            new_uv[grow], new_X[grow], new_face[grow] = uv[grow], X[grow], face[grow]
            s_new[grow[bnd]] = s[grow[bnd]]
        uv, X, face, s = new_uv, new_X, new_face, s_new
    if snap > 0:
        _snap_to_far_points(X, uv, face, Fo, bnd, pinned, V, F, disk_uv, snap)
    if min_quality > 0 and rounds > 0:
        _optimize_min_quality(
            X, uv, face, s, Fo, bnd, pinned, V, F, disk_uv, vertex_faces, curve, min_quality, rounds
        )
    return uv, X
