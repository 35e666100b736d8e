"""Compiled twins of the closest-point search of :mod:`qcremesh.remeshing.onsurface` and of
the smoothing step of :mod:`qcremesh.remeshing.relax`, used when Numba is installed (the
optional extra ``fast``).

The relaxation, the snapping and the minimum-quality search call
:func:`~qcremesh.remeshing.onsurface.closest_point_near` hundreds of times on batches of a
few to tens of thousands of points; in NumPy each call builds arrays of candidate faces
and runs the exact point-triangle distance on them, so on human_face.obj a third of the
remeshing time went there. This is the same search point by point, with the same
arithmetic in the same order (the plane projection of the first test, the distance of
:func:`qcremesh.geometry.distance.point_triangle_distance`, the first nearest candidate on
ties), so it returns the same faces, points and coordinates to the last bit (a test
compares them, and the remeshed meshes are the same bytes). Measured: the 50 relaxation
sweeps' searches take 0.04 s instead of 0.28 s on human_face.obj and 0.19 s instead of
0.81 s on hand.ply; the whole remesh at the input's face count 1.31 s instead of 1.73 s
and 3.2 s instead of 5.0 s (against remesh_botsch's 1.4-1.7 s and 3.5-4.7 s run beside it).

The smoothing step (where a sweep sends each vertex: the mean of its neighbours, less the
normal component, clamped to a quarter of its mean edge length) takes the vertex normals,
the neighbour sums and the edge lengths of the whole mesh in NumPy, each a pass over
every face or edge; compiled, each vertex gathers its own, with the same additions in
the same order (the faces around a vertex in the order of the incidence matrix, the
neighbours in the order of the adjacency row, the edge lengths to the higher-numbered
neighbours before the lower, as the two counts over the sorted edge list add them), so
again the same bits. Measured: the step of hand.ply's 53k vertices takes 6 ms instead of
29 ms (human_face.obj's 17k, 1.6 ms instead of 7.4 ms); the 60 sweeps of its remesh at
its face count, with their closest-point searches, 0.46 s instead of 0.78 s.
"""

from __future__ import annotations

import numpy as np

from ..geometry.compiled import numba_compile, point_triangle_kernel

__all__ = ["closest_point_near_kernel", "smooth_targets_kernel"]

# Numba is the optional extra "fast"; it is imported, and the functions compiled (or
# loaded from its cache), at the first search, not with qcremesh (0.3 s).
_state = None  # None: not tried yet; True: compiled; False: Numba cannot be imported
_point_triangle = None  # the compiled point-triangle distance, which the search calls


def _closest_point_near(P, face, V, F, indptr, indices, rounds):
    """The search of qcremesh.remeshing.onsurface._closest_point_near point by point, with
    the vertex-face incidence as its CSR arrays."""
    k = P.shape[0]
    face = face.copy()
    closest = np.zeros((k, 3))
    bary = np.zeros((k, 3))
    for i in range(k):
        f = face[i]
        p0, p1, p2 = P[i, 0], P[i, 1], P[i, 2]
        # The projection onto the plane of the current face, accepted when inside it.
        a, b, c = F[f, 0], F[f, 1], F[f, 2]
        e10, e11, e12 = V[b, 0] - V[a, 0], V[b, 1] - V[a, 1], V[b, 2] - V[a, 2]
        e20, e21, e22 = V[c, 0] - V[a, 0], V[c, 1] - V[a, 1], V[c, 2] - V[a, 2]
        r0, r1, r2 = p0 - V[a, 0], p1 - V[a, 1], p2 - V[a, 2]
        g11 = e10 * e10 + e11 * e11 + e12 * e12
        g12 = e10 * e20 + e11 * e21 + e12 * e22
        g22 = e20 * e20 + e21 * e21 + e22 * e22
        s1 = r0 * e10 + r1 * e11 + r2 * e12
        s2 = r0 * e20 + r1 * e21 + r2 * e22
        det = g11 * g22 - g12 * g12
        b1 = (g22 * s1 - g12 * s2) / det
        b2 = (g11 * s2 - g12 * s1) / det
        if b1 >= 0 and b2 >= 0 and b1 + b2 <= 1:
            bary[i, 0], bary[i, 1], bary[i, 2] = 1 - b1 - b2, b1, b2
            closest[i, 0] = V[a, 0] + b1 * e10 + b2 * e20
            closest[i, 1] = V[a, 1] + b1 * e11 + b2 * e21
            closest[i, 2] = V[a, 2] + b1 * e12 + b2 * e22
            continue
        for _ in range(rounds):
            best, best_face = np.inf, f
            for corner in range(3):
                v = F[f, corner]
                for j in range(indptr[v], indptr[v + 1]):
                    g = indices[j]
                    d, q0, q1, q2, l0, l1, l2 = _point_triangle(p0, p1, p2, V, F[g, 0], F[g, 1], F[g, 2])
                    if d < best:
                        best, best_face = d, g
                        closest[i, 0], closest[i, 1], closest[i, 2] = q0, q1, q2
                        bary[i, 0], bary[i, 1], bary[i, 2] = l0, l1, l2
            if best_face == f:
                break
            f = best_face
        face[i] = f
    return face, closest, bary


def _smooth_targets(X, verts, ring_indptr, ring_indices, vf_indptr, vf_indices, Fo, step):
    """The smoothing step of qcremesh.remeshing.smoothing.smooth_targets vertex by vertex,
    with the adjacency rows of ``verts`` and the vertex-face incidence as CSR arrays."""
    p = verts.shape[0]
    out = np.empty((p, 3))
    for r in range(p):
        v = verts[r]
        # the area-weighted normal: the cross products of the faces around v, summed
        n0, n1, n2 = 0.0, 0.0, 0.0
        for j in range(vf_indptr[v], vf_indptr[v + 1]):
            f = vf_indices[j]
            a, b, c = Fo[f, 0], Fo[f, 1], Fo[f, 2]
            p0, p1, p2 = X[b, 0] - X[a, 0], X[b, 1] - X[a, 1], X[b, 2] - X[a, 2]
            q0, q1, q2 = X[c, 0] - X[a, 0], X[c, 1] - X[a, 1], X[c, 2] - X[a, 2]
            n0 += p1 * q2 - p2 * q1
            n1 += p2 * q0 - p0 * q2
            n2 += p0 * q1 - p1 * q0
        length = max(np.sqrt(n0 * n0 + n1 * n1 + n2 * n2), 1e-300)
        n0, n1, n2 = n0 / length, n1 / length, n2 / length
        # the neighbours' sum, and the edge lengths to them (higher-numbered ones first)
        s0, s1, s2 = 0.0, 0.0, 0.0
        above, below = 0.0, 0.0
        for j in range(ring_indptr[r], ring_indptr[r + 1]):
            u = ring_indices[j]
            s0 += X[u, 0]
            s1 += X[u, 1]
            s2 += X[u, 2]
            e0, e1, e2 = X[v, 0] - X[u, 0], X[v, 1] - X[u, 1], X[v, 2] - X[u, 2]
            edge = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
            if u > v:
                above += edge
            else:
                below += edge
        deg = ring_indptr[r + 1] - ring_indptr[r]
        d0, d1, d2 = s0 / deg - X[v, 0], s1 / deg - X[v, 1], s2 / deg - X[v, 2]
        dn = d0 * n0 + d1 * n1 + d2 * n2
        d0, d1, d2 = d0 - dn * n0, d1 - dn * n1, d2 - dn * n2
        reach = (above + below) / deg
        d0, d1, d2 = d0 * step, d1 * step, d2 * step
        scale = min(1.0, 0.25 * reach / max(np.sqrt(d0 * d0 + d1 * d1 + d2 * d2), 1e-300))
        out[r, 0], out[r, 1], out[r, 2] = X[v, 0] + d0 * scale, X[v, 1] + d1 * scale, X[v, 2] + d2 * scale
    return out


def closest_point_near_kernel():
    """The compiled search, ``search(P, face, V, F, vertex_faces, rounds) -> (face,
    closest, bary)`` on one chunk of points, as
    :func:`~qcremesh.remeshing.onsurface.closest_point_near`; None where Numba cannot be
    imported (not installed, or built for another NumPy), and the NumPy search is to be
    used. The functions are compiled (or loaded from Numba's cache) at the first
    search; Numba compiles under a lock, so threads may make it."""
    return _search if _compiled() else None


def smooth_targets_kernel():
    """The compiled smoothing step, ``targets(X, verts, ring, Fo, VF, E, step) -> (p,
    3)``, as :func:`qcremesh.remeshing.smoothing.smooth_targets` (``ring`` with sorted
    indices, ``E`` the sorted edge list it takes its edge lengths from); None where Numba
    cannot be imported."""
    return _targets if _compiled() else None


def _compiled():
    """Whether the kernels are compiled, compiling them (or loading them from Numba's
    cache) at the first call."""
    global _state, _point_triangle, _closest_point_near, _smooth_targets
    if _state is None:
        kernel = point_triangle_kernel()
        _state = kernel is not None
        if _state:
            _point_triangle = kernel
            _closest_point_near = numba_compile(_closest_point_near)
            _smooth_targets = numba_compile(_smooth_targets)
    return _state


def _search(P, face, V, F, vertex_faces, rounds):
    """The compiled search on arrays it can take without a copy where they already are
    (the incidence's index arrays keep their integer type: Numba compiles one version
    per type)."""
    return _closest_point_near(
        np.ascontiguousarray(P, dtype=np.float64),
        np.ascontiguousarray(face, dtype=np.int64),
        np.ascontiguousarray(V, dtype=np.float64),
        np.ascontiguousarray(F, dtype=np.int64),
        vertex_faces.indptr,
        vertex_faces.indices,
        int(rounds),
    )


def _targets(X, verts, ring, Fo, VF, E, step):
    """The compiled smoothing step on the arrays it takes (``E`` is implied: the edges of
    ``Fo``)."""
    return _smooth_targets(
        np.ascontiguousarray(X, dtype=np.float64),
        np.ascontiguousarray(verts, dtype=np.int64),
        ring.indptr,
        ring.indices,
        VF.indptr,
        VF.indices,
        np.ascontiguousarray(Fo, dtype=np.int64),
        float(step),
    )
