"""Tangential relaxation of a remeshed surface that keeps every vertex on the input
surface and the connectivity unchanged.

An optional last stage of :func:`qcremesh.remeshing.pipeline.remesh`, beyond the paper. Each
sweep moves every interior vertex towards the centroid of its neighbours, tangentially
(the component along the vertex normal is removed), by at most a quarter of its mean
edge length, and snaps it back onto the input surface at the closest point among the input faces
around the face it was on (a local search, so a vertex never jumps to another sheet of
the surface across a thin part). Its disk coordinates follow by barycentric interpolation
of the parameterization on that face. Boundary vertices slide along the input boundary
polyline: their arc-length position becomes the mean of their two boundary neighbours';
boundary corners stay. A vertex whose move would fold one of its faces in the disk stays
where it is, so the disk mesh stays an embedding and the surface mesh its orientation.
"""

from __future__ import annotations

import numpy as np

from ..adaptive.landmarks import boundary_angles, interpolate_on_boundary
from ..geometry.distance import point_triangle_distance
from ..geometry.locate import interpolate_barycentric, locate_points
from ..geometry.operators import signed_doublearea
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


def _vertex_normals(X, Fo, k):
    N = np.cross(X[Fo[:, 1]] - X[Fo[:, 0]], X[Fo[:, 2]] - X[Fo[:, 0]])
    out = np.zeros((k, 3))
    for c in range(3):
        out += np.stack([np.bincount(Fo[:, c], weights=N[:, j], minlength=k) for j in range(3)], axis=1)
    return out / np.maximum(np.linalg.norm(out, axis=1, keepdims=True), 1e-300)


def relax_on_surface(disk_uv, F, V, uv, Fo, *, iterations=10, step=0.5, pinned=None):
    """Move the vertices of a mesh of the disk so that its image on the surface gets more
    regular, without changing its connectivity.

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
        Number of relaxation sweeps.
    step : float
        Fraction of the displacement applied per sweep, in (0, 1].
    pinned : (k,) bool, optional
        Vertices that must not move (e.g. boundary corners).

    Returns
    -------
    uv : (k, 2) float
        New disk positions.
    X : (k, 3) float
        Their positions on the surface.
    """
    uv = np.array(uv, dtype=np.float64)
    k = len(uv)
    bnd_in = boundary_loop(F)
    theta_in = boundary_angles(disk_uv, bnd_in)
    theta_knots = np.r_[theta_in, theta_in[0] + 2 * np.pi]
    seg = np.linalg.norm(V[np.roll(bnd_in, -1)] - V[bnd_in], axis=1)
    s_in = np.r_[0.0, np.cumsum(seg)]
    perimeter = s_in[-1]
    bnd = boundary_loop(Fo)
    pinned = np.zeros(k, dtype=bool) if pinned is None else np.asarray(pinned, dtype=bool)
    on_circle = np.zeros(k, dtype=bool)
    on_circle[bnd] = True
    inner = np.flatnonzero(~on_circle)
    free = ~on_circle & ~pinned
    A = adjacency_matrix(Fo, k)
    deg = np.asarray(A.sum(axis=1)).ravel()
    E = edges(Fo)
    vertex_faces = vertex_face_incidence(F, len(V))

    face = np.zeros(k, dtype=np.int64)
    X = np.zeros((k, 3))
    face[inner], bary, _ = locate_points(disk_uv, F, uv[inner])
    X[inner] = interpolate_barycentric(F, face[inner], bary, V)
    theta = np.arctan2(uv[bnd, 1], uv[bnd, 0])
    X[bnd] = interpolate_on_boundary(theta_in, V[bnd_in], theta)
    s = np.interp(theta_in[0] + np.mod(theta - theta_in[0], 2 * np.pi), theta_knots, s_in)
    s = s[0] + np.mod(s - s[0], perimeter)  # increasing along the output loop
    for _ in range(iterations):
        normal = _vertex_normals(X, Fo, k)
        d = (A @ X) / deg[:, None] - X
        d -= (d * normal).sum(1, keepdims=True) * normal
        length = np.linalg.norm(X[E[:, 0]] - X[E[:, 1]], axis=1)
        reach = (np.bincount(E[:, 0], length, k) + np.bincount(E[:, 1], length, k)) / deg
        d *= step
        d *= np.minimum(1.0, 0.25 * reach / np.maximum(np.linalg.norm(d, axis=1), 1e-300))[:, None]
        new_X, new_uv, new_face = X.copy(), uv.copy(), face.copy()
        moved = np.flatnonzero(free)
        f, cp, b = closest_point_near(X[moved] + d[moved], face[moved], V, F, vertex_faces)
        new_face[moved], new_X[moved] = f, cp
        new_uv[moved] = interpolate_barycentric(F, f, b, disk_uv)
        # boundary: 1D smoothing of arc length along the output boundary loop
        s_prev, s_next = np.roll(s, 1), np.roll(s, -1)
        s_prev[0] -= perimeter
        s_next[-1] += perimeter
        s_new = np.where(pinned[bnd], s, s + step * ((s_prev + s_next) / 2 - s))
        theta_new = np.interp(np.mod(s_new, perimeter), s_in, theta_knots)
        new_uv[bnd] = np.column_stack([np.cos(theta_new), np.sin(theta_new)])
        new_X[bnd] = interpolate_on_boundary(theta_in, V[bnd_in], theta_new)
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
    return uv, X
