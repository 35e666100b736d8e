"""Compiled kernels (Numba, the optional extra ``fast``) of loops that NumPy would run
over many small gathers.

- The exact distance from a point to a triangle, written out for one pair at a time with
  the arithmetic of :func:`qcremesh.geometry.distance.point_triangle_distance` in the
  same order (the signed-area inside test, the three edges, the first nearest edge on
  ties), so the compiled and the NumPy code give the same numbers to the last bit (tests
  compare them). Two users: the nearest-face search of
  :func:`~qcremesh.geometry.distance.point_mesh_distance`, which measures a few
  candidate faces per point (:func:`pair_distances_kernel`), and the closest-point search
  on the surface of :mod:`qcremesh.remeshing.compiled` (:func:`point_triangle_kernel`).
- The search for the nearest face of many points in a uniform grid of the faces
  (:func:`grid_nearest_kernel`, with the same point-triangle distances), for the
  distances between two surfaces, which measure every sample of one against the other.
- The pairs of faces whose bounding boxes meet, from the same grid
  (:func:`box_pairs_kernel`), which :func:`qcremesh.geometry.intersections.
  self_intersections` then tests (the pairs of a search of bounding spheres without it:
  either holds every pair of faces that meet).
- The test that a guessed nearest point is the nearest (:func:`guess_is_nearest_kernel`),
  which spares Lloyd's iteration most of its nearest-generator searches; it certifies
  only what the search would answer, so the owners are the same with it and without.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "box_pairs_kernel",
    "face_grid_kernel",
    "grid_nearest_kernel",
    "guess_is_nearest_kernel",
    "numba_compile",
    "pair_distances_kernel",
    "point_triangle_kernel",
]

# Numba is imported, and the functions compiled (or loaded from its cache), at the first
# call that asks for them, not with qcremesh (0.3 s).
_state = None  # None: not tried yet; True: compiled; False: Numba cannot be imported


def _dot(a0, a1, a2, b0, b1, b2):
    return a0 * b0 + a1 * b1 + a2 * b2


def _cross(a0, a1, a2, b0, b1, b2):
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


def _edge(x0, x1, x2, e0, e1, e2):
    """Closest point of an edge (p + x + t e, t in [0, 1]) to p: (squared distance, t)."""
    ee = _dot(e0, e1, e2, e0, e1, e2)
    t = 0.0
    if ee > 0:
        t = min(max(-_dot(x0, x1, x2, e0, e1, e2) / ee, 0.0), 1.0)
    g0, g1, g2 = x0 + t * e0, x1 + t * e1, x2 + t * e2
    return _dot(g0, g1, g2, g0, g1, g2), t


def _point_triangle(p0, p1, p2, V, a, b, c):
    """Distance, closest point and barycentric coordinates of point p on triangle abc, by
    the arithmetic of qcremesh.geometry.distance._triangle."""
    # corners relative to p, and the edges ab, bc, ca
    xa0, xa1, xa2 = V[a, 0] - p0, V[a, 1] - p1, V[a, 2] - p2
    xb0, xb1, xb2 = V[b, 0] - p0, V[b, 1] - p1, V[b, 2] - p2
    xc0, xc1, xc2 = V[c, 0] - p0, V[c, 1] - p1, V[c, 2] - p2
    ea0, ea1, ea2 = V[b, 0] - V[a, 0], V[b, 1] - V[a, 1], V[b, 2] - V[a, 2]
    eb0, eb1, eb2 = V[c, 0] - V[b, 0], V[c, 1] - V[b, 1], V[c, 2] - V[b, 2]
    ec0, ec1, ec2 = V[a, 0] - V[c, 0], V[a, 1] - V[c, 1], V[a, 2] - V[c, 2]
    n0, n1, n2 = _cross(ec0, ec1, ec2, ea0, ea1, ea2)
    nn = _dot(n0, n1, n2, n0, n1, n2)
    l0 = _dot(*_cross(xb0, xb1, xb2, eb0, eb1, eb2), n0, n1, n2)
    l1 = _dot(*_cross(xc0, xc1, xc2, ec0, ec1, ec2), n0, n1, n2)
    l2 = _dot(*_cross(xa0, xa1, xa2, ea0, ea1, ea2), n0, n1, n2)
    if l0 >= 0 and l1 >= 0 and l2 >= 0 and nn > 0:
        h = _dot(xa0, xa1, xa2, n0, n1, n2) / nn
        return np.sqrt(h * h * nn), p0 + h * n0, p1 + h * n1, p2 + h * n2, l0 / nn, l1 / nn, l2 / nn
    da, ta = _edge(xa0, xa1, xa2, ea0, ea1, ea2)
    db, tb = _edge(xb0, xb1, xb2, eb0, eb1, eb2)
    dc, tc = _edge(xc0, xc1, xc2, ec0, ec1, ec2)
    if da <= db and da <= dc:
        s = 1 - ta
        return np.sqrt(da), p0 + xa0 + ta * ea0, p1 + xa1 + ta * ea1, p2 + xa2 + ta * ea2, s, ta, 0.0
    if db <= dc:
        s = 1 - tb
        return np.sqrt(db), p0 + xb0 + tb * eb0, p1 + xb1 + tb * eb1, p2 + xb2 + tb * eb2, 0.0, s, tb
    s = 1 - tc
    return np.sqrt(dc), p0 + xc0 + tc * ec0, p1 + xc1 + tc * ec1, p2 + xc2 + tc * ec2, tc, 0.0, s


def _pair_distances(P, V, F, i, j):
    """Distance from point ``P[i[k]]`` to face ``F[j[k]]`` for every k, (k,)."""
    out = np.empty(len(i))
    for k in range(len(i)):
        p, f = i[k], j[k]
        out[k] = _point_triangle(P[p, 0], P[p, 1], P[p, 2], V, F[f, 0], F[f, 1], F[f, 2])[0]
    return out


def _cube(x, lo, cell, dims):
    """Index of the cube of a uniform grid (corner ``lo``, side ``cell``, ``dims`` cubes)
    that holds coordinate x along one axis, the nearest one for x outside the grid."""
    return min(max(int(np.floor((x - lo) / cell)), 0), dims - 1)


def _face_cubes(V, F, f, lo, cell, dims, first, last):
    """The range of cubes of a uniform grid that face f's bounding box meets, along each
    axis, into ``first`` and ``last`` (3,)."""
    for a in range(3):
        first[a] = _cube(min(V[F[f, 0], a], V[F[f, 1], a], V[F[f, 2], a]), lo[a], cell, dims[a])
        last[a] = _cube(max(V[F[f, 0], a], V[F[f, 1], a], V[F[f, 2], a]), lo[a], cell, dims[a])


def _face_grid(V, F, lo, cell, dims):
    """The faces in each cube of a uniform grid (:func:`grid_nearest_kernel`): (start,
    members), every face in each cube its bounding box meets, in face order."""
    cells = dims[0] * dims[1] * dims[2]
    first, last = np.empty(3, dtype=np.int64), np.empty(3, dtype=np.int64)
    start = np.zeros(cells + 1, dtype=np.int64)
    for f in range(F.shape[0]):
        _face_cubes(V, F, f, lo, cell, dims, first, last)
        for x in range(first[0], last[0] + 1):
            for y in range(first[1], last[1] + 1):
                for z in range(first[2], last[2] + 1):
                    start[(x * dims[1] + y) * dims[2] + z + 1] += 1
    for c in range(cells):
        start[c + 1] += start[c]
    members = np.empty(start[cells], dtype=np.int64)
    fill = start[:-1].copy()
    for f in range(F.shape[0]):
        _face_cubes(V, F, f, lo, cell, dims, first, last)
        for x in range(first[0], last[0] + 1):
            for y in range(first[1], last[1] + 1):
                for z in range(first[2], last[2] + 1):
                    at = (x * dims[1] + y) * dims[2] + z
                    members[fill[at]] = f
                    fill[at] += 1
    return start, members


def _box_pairs(V, F, lo, cell, dims, start, members, flat):
    """The pairs of faces (i, j), i < j, whose bounding boxes meet and that have no edge
    in common nor only a vertex v with ``flat[v]``, each found once in the grid of
    :func:`_face_grid` (in the first cube that both boxes meet): (i, j) (k,) int64 each,
    in order of i, then of the cube."""
    m = F.shape[0]
    box_lo, box_hi = np.empty((m, 3)), np.empty((m, 3))
    first, last = np.empty((m, 3), dtype=np.int64), np.empty((m, 3), dtype=np.int64)
    for f in range(m):
        for a in range(3):
            box_lo[f, a] = min(V[F[f, 0], a], V[F[f, 1], a], V[F[f, 2], a])
            box_hi[f, a] = max(V[F[f, 0], a], V[F[f, 1], a], V[F[f, 2], a])
            first[f, a] = _cube(box_lo[f, a], lo[a], cell, dims[a])
            last[f, a] = _cube(box_hi[f, a], lo[a], cell, dims[a])
    out_i, out_j = np.empty(4 * m + 16, dtype=np.int64), np.empty(4 * m + 16, dtype=np.int64)
    k = 0
    for f in range(m):
        for x in range(first[f, 0], last[f, 0] + 1):
            for y in range(first[f, 1], last[f, 1] + 1):
                for z in range(first[f, 2], last[f, 2] + 1):
                    c = (x * dims[1] + y) * dims[2] + z
                    for at in range(start[c], start[c + 1]):
                        g = members[at]
                        if g <= f:
                            continue
                        if max(first[f, 0], first[g, 0]) != x or max(first[f, 1], first[g, 1]) != y:
                            continue
                        if max(first[f, 2], first[g, 2]) != z:
                            continue
                        apart = False
                        for a in range(3):
                            if box_hi[f, a] < box_lo[g, a] or box_hi[g, a] < box_lo[f, a]:
                                apart = True
                        if apart:
                            continue
                        shared, common = 0, -1
                        for p in range(3):
                            for q in range(3):
                                if F[f, p] == F[g, q]:
                                    shared += 1
                                    common = F[f, p]
                        if shared == 2 or (shared == 1 and flat[common]):
                            continue
                        if k == len(out_i):  # twice the room
                            grown_i, grown_j = np.empty(2 * k, dtype=np.int64), np.empty(2 * k, dtype=np.int64)
                            grown_i[:k], grown_j[:k] = out_i, out_j
                            out_i, out_j = grown_i, grown_j
                        out_i[k], out_j[k] = f, g
                        k += 1
    return out_i[:k].copy(), out_j[:k].copy()


def _grid_nearest(P, V, F, lo, cell, dims, start, members, shells):
    """The distance from every point ``P[i]`` (q, 3) to the nearest face of a uniform
    grid (:func:`grid_nearest_kernel`) and whether it is certified: (q,) float, (q,)
    bool."""
    q = P.shape[0]
    dist = np.full(q, np.inf)
    certified = np.zeros(q, dtype=np.bool_)
    c = np.empty(3, dtype=np.int64)
    done_lo, done_hi = np.empty(3, dtype=np.int64), np.empty(3, dtype=np.int64)
    box_lo, box_hi = np.empty(3, dtype=np.int64), np.empty(3, dtype=np.int64)
    largest = (2 * shells + 1) ** 3
    for i in range(q):
        for a in range(3):
            c[a] = _cube(P[i, a], lo[a], cell, dims[a])
            done_lo[a], done_hi[a] = c[a], c[a] - 1  # nothing searched yet
        best = np.inf
        r = 0
        while True:
            if best < np.inf:
                # the cubes that the ball of radius best around the point meets (a little
                # wider, for the rounding of the bounds)
                reach = best * (1.0 + 1e-9)
                for a in range(3):
                    box_lo[a] = _cube(P[i, a] - reach, lo[a], cell, dims[a])
                    box_hi[a] = _cube(P[i, a] + reach, lo[a], cell, dims[a])
                last = True
            else:
                # a shell of cubes further out, until one holds a face
                for a in range(3):
                    box_lo[a], box_hi[a] = max(c[a] - r, 0), min(c[a] + r, dims[a] - 1)
                last = False
                r += 1
            cubes = (box_hi[0] - box_lo[0] + 1) * (box_hi[1] - box_lo[1] + 1) * (box_hi[2] - box_lo[2] + 1)
            if cubes > largest:
                break
            for x in range(box_lo[0], box_hi[0] + 1):
                for y in range(box_lo[1], box_hi[1] + 1):
                    for z in range(box_lo[2], box_hi[2] + 1):
                        searched = done_lo[0] <= x <= done_hi[0] and done_lo[1] <= y <= done_hi[1]
                        if searched and done_lo[2] <= z <= done_hi[2]:
                            continue
                        at = (x * dims[1] + y) * dims[2] + z
                        for k in range(start[at], start[at + 1]):
                            f = members[k]
                            d = _point_triangle(P[i, 0], P[i, 1], P[i, 2], V, F[f, 0], F[f, 1], F[f, 2])[0]
                            if d < best:
                                best = d
            for a in range(3):
                done_lo[a], done_hi[a] = min(done_lo[a], box_lo[a]), max(done_hi[a], box_hi[a])
            if last:
                certified[i] = True
                break
        dist[i] = best
    return dist, certified


def _guess_is_nearest(Q, X, guess, neighbours, near2, far2):
    """Whether point ``X[guess[i]]`` is strictly the nearest point of X to ``Q[i]``, for
    every i, certified by :func:`guess_is_nearest_kernel`'s test: (q,) bool."""
    out = np.zeros(Q.shape[0], dtype=np.bool_)
    d = Q.shape[1]
    for i in range(Q.shape[0]):
        g = guess[i]
        own = 0.0
        for c in range(d):
            own += (Q[i, c] - X[g, c]) ** 2
        if own < near2[g]:
            out[i] = True
            continue
        if not own < far2[g]:
            continue
        nearest = True
        for n in range(neighbours.shape[1]):
            h = neighbours[g, n]
            other = 0.0
            for c in range(d):
                other += (Q[i, c] - X[h, c]) ** 2
            # (a margin far above rounding: the near-ties go to the search)
            if not own < other * (1.0 - 1e-12):
                nearest = False
                break
        out[i] = nearest
    return out


def numba_compile(func):
    """``func`` compiled by Numba with the options of every kernel of qcremesh: cached on
    disk, without the GIL (threads run it in parallel), and error_model="numpy" (a
    degenerate face divides by zero into inf or nan, as in NumPy). Numba resolves the
    functions ``func`` calls when it compiles it, at its first call."""
    import numba

    return numba.njit(cache=True, nogil=True, error_model="numpy")(func)


def _compile():
    """Compile the kernels at the first call; whether they are."""
    global _state, _dot, _cross, _edge, _point_triangle, _pair_distances, _guess_is_nearest
    global _cube, _face_cubes, _face_grid, _grid_nearest, _box_pairs
    if _state is None:
        try:
            import numba  # noqa: F401
        except ImportError:
            _state = False
        else:
            _dot, _cross, _edge = numba_compile(_dot), numba_compile(_cross), numba_compile(_edge)
            _point_triangle, _pair_distances = numba_compile(_point_triangle), numba_compile(_pair_distances)
            _guess_is_nearest = numba_compile(_guess_is_nearest)
            _cube, _face_cubes = numba_compile(_cube), numba_compile(_face_cubes)
            _face_grid, _grid_nearest = numba_compile(_face_grid), numba_compile(_grid_nearest)
            _box_pairs = numba_compile(_box_pairs)
            _state = True
    return _state


def point_triangle_kernel():
    """The compiled ``point_triangle(p0, p1, p2, V, a, b, c) -> (dist, q0, q1, q2, l0, l1,
    l2)``: distance, closest point and barycentric coordinates of the point (p0, p1, p2)
    on the triangle of the vertices ``a``, ``b``, ``c`` of ``V`` (n, 3), for use in other
    compiled functions; None where Numba cannot be imported."""
    return _point_triangle if _compile() else None


def pair_distances_kernel():
    """The compiled ``pair_distances(P, V, F, i, j) -> (k,)``, the distances from points
    ``P[i]`` (q, 3) to faces ``F[j]`` of the mesh (V (n, 3) float, F (m, 3) int64) for
    index arrays ``i``, ``j`` (k,) int64, as ``point_triangle_distance(P[i], *V[F[j]].
    transpose(1, 0, 2))[0]``; None where Numba cannot be imported."""
    return _pair_distances if _compile() else None


def face_grid_kernel():
    """The compiled ``face_grid(V, F, lo, cell, dims) -> (start, members)``: the grid of
    the faces that :func:`grid_nearest_kernel` searches (every face in each cube its
    bounding box meets, in face order); None where Numba cannot be imported."""
    return _face_grid if _compile() else None


def box_pairs_kernel():
    """The compiled ``box_pairs(V, F, lo, cell, dims, start, members, flat) -> (i, j)``:
    the pairs of faces (i < j, (k,) int64 each) of the mesh (V (n, 3) float, F (m, 3)
    int64) whose bounding boxes meet and that have no edge in common nor only a vertex v
    with ``flat[v]`` ((n,) bool), found in the grid of :func:`face_grid_kernel`, each
    once; None where Numba cannot be imported."""
    return _box_pairs if _compile() else None


def grid_nearest_kernel():
    """The compiled ``grid_nearest(P, V, F, lo, cell, dims, start, members, shells) ->
    (dist, certified)``: for every point of P (q, 3), the distance to the nearest face of
    the mesh (V (n, 3) float, F (m, 3) int64), searched in a uniform grid of cubes of
    side ``cell`` from the corner ``lo`` (3,), ``dims`` (3,) int64 cubes along the axes,
    cube (x, y, z) holding the faces ``members[start[i]:start[i + 1]]`` for i = (x
    dims[1] + y) dims[2] + z (every face in each cube its bounding box meets). Shells of
    cubes around the point's own (the nearest one, for a point outside the grid) are
    searched until one holds a face, then every cube the ball of the nearest distance
    found meets: the distance is then exact (``certified``). A point whose search would
    take more cubes than a box ``shells`` cubes from its own holds is not certified. None
    where Numba cannot be imported."""
    return _grid_nearest if _compile() else None


def guess_is_nearest_kernel():
    """The compiled ``guess_is_nearest(Q, X, guess, neighbours, near2, far2) -> (q,)
    bool``: True where ``X[guess[i]]`` is certified to be strictly the nearest point of
    X (g, d) to ``Q[i]`` (Q (q, d) float), False where it may not be. ``neighbours``
    (g, k) int64 are the k points of X nearest to each point (itself excluded), and
    ``near2`` and ``far2`` (g,) a little under the squares of half the distances to the
    nearest and to the farthest of them. A point closer to its guess than half the
    distance to some point of X is nearer to the guess than to any point of X at least
    that far (the triangle inequality): it is certified within ``near2``, and within
    ``far2`` when it is also strictly nearer to the guess than to each neighbour. None
    where Numba cannot be imported."""
    return _guess_is_nearest if _compile() else None
