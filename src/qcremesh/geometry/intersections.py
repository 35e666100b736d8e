"""Self-intersections of a triangle mesh: faces that meet where its connectivity does
not join them.

A remesh whose vertices lie on the input surface can still pass through itself, where
the input comes close to itself (the walls of a narrow slit, two fingers touching) and
an output face bridges the gap. A valid output has no self-intersection that the input
does not have; :func:`self_intersections` counts them.

Two closed triangles in space are disjoint exactly when some axis separates their
projections: one of the two normals, one of the nine cross products of an edge of one
with an edge of the other, or, for coplanar triangles, one of the six in-plane normals
of the edges (the separating axis theorem for convex polytopes;
:func:`triangles_intersect` projects on all 17). Faces sharing one vertex v meet
elsewhere exactly when the sectors they span at v overlap: when the line where their
planes meet runs from v into both sectors, or, coplanar, when a ray of one sector lies
strictly inside the other (:func:`_sectors_overlap`), and cannot where the other two
corners of one lie strictly on one side of the plane of the other.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..mesh.topology import boundary_edges, inconsistent_edges, nonmanifold_edges, twin_half_edges
from ..mesh.validate import as_mesh_arrays, in_space
from .compiled import box_pairs_kernel
from .distance import face_grid
from .operators import vertex_normals
from .vectors import cross, norm

__all__ = ["triangles_intersect", "self_intersections"]

# Pairs tested at once (each takes 17 axes x 6 projections).
CHUNK = 100_000
# Planes closer to parallel than this angle (radians), and for faces without a common
# vertex also closer than this fraction of their size, are taken as one plane: where they
# would meet on a line lost in rounding, the faces are compared in the plane.
COPLANAR = 1e-10


def triangles_intersect(P, Q):
    """Whether the closed triangles ``P[i]`` and ``Q[i]`` share a point.

    They are disjoint exactly when the intervals of their projections on some axis a are
    disjoint, max_k a.P_k < min_k a.Q_k or the other way round, for a among the normals
    n_P, n_Q, the cross products e_i x f_j of their edges, and n x e_i, n x f_j with n
    the longer of the normals (which separate coplanar triangles). Touching counts as
    sharing a point. Triangles whose planes are parallel and apart within ``COPLANAR``
    (of a radian, and of their longest side) are compared on the in-plane axes alone, so
    that rounding cannot lift one off the other.

    Parameters
    ----------
    P, Q : (p, 3, 3) float
        Triangles, as their corners.

    Returns
    -------
    (p,) bool

    Examples
    --------
    >>> import numpy as np
    >>> P = np.array([[[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]])
    >>> triangles_intersect(P, P + [0.2, 0.2, -0.5] + [[0, 0, 0], [0, 0, 1], [0, 0, 0]])
    array([ True])
    >>> triangles_intersect(P, P + [0.0, 0.0, 0.1])
    array([False])
    """
    P = np.asarray(P, dtype=np.float64)
    Q = np.asarray(Q, dtype=np.float64)
    out = np.empty(len(P), dtype=bool)
    for start in range(0, len(P), CHUNK):
        part = slice(start, start + CHUNK)
        out[part] = _intersect(P[part], Q[part])
    return out


def _intersect(P, Q):
    origin = P[:, :1]  # rounding relative to the pair, not to the coordinates' offset
    P, Q = P - origin, Q - origin
    e = np.roll(P, -1, axis=1) - P  # (p, 3 edges, 3)
    f = np.roll(Q, -1, axis=1) - Q
    n_P = cross(e[:, 0], e[:, 1])
    n_Q = cross(f[:, 0], f[:, 1])
    flat = _coplanar(P, Q, n_P, n_Q)
    # The normals first: they separate most pairs, the other 15 axes the rest. Coplanar
    # pairs only in their plane, where rounding cannot lift one off the other.
    meet = flat | ~_separated(np.stack([n_P, n_Q], axis=1), P, Q)
    rest = np.flatnonzero(meet)
    e, f, n_P, n_Q = e[rest], f[rest], n_P[rest], n_Q[rest]
    # in the plane of the longer normal, so that a triangle flattened to a segment is
    # still separated from one in its plane
    n = np.where((norm(n_P) >= norm(n_Q))[:, None], n_P, n_Q)[:, None]
    edge_pairs = np.where(flat[rest, None, None], 0.0, cross(e[:, :, None], f[:, None, :]).reshape(-1, 9, 3))
    axes = np.concatenate([edge_pairs, cross(n, e), cross(n, f)], axis=1)
    meet[rest] = ~_separated(axes, P[rest], Q[rest])
    return meet


def _coplanar(P, Q, n_P, n_Q):
    """Pairs of triangles (translated so that P's first corner is the origin) whose
    planes are parallel and apart by at most ``COPLANAR`` of their longest side."""
    size = np.maximum(norm(P - P[:, :1]).max(1), norm(Q - P[:, :1]).max(1))
    parallel = norm(cross(n_P, n_Q)) <= COPLANAR * norm(n_P) * norm(n_Q)
    apart = np.abs(np.einsum("pkc,pc->pk", Q, n_P)).max(1)
    return parallel & (apart <= COPLANAR * size * norm(n_P))


def _separated(axes, P, Q):
    """Whether some axis (p, a, 3) separates the projections of P and Q (p, 3, 3)."""
    on_P = np.einsum("pac,pkc->pak", axes, P)
    on_Q = np.einsum("pac,pkc->pak", axes, Q)
    return ((on_P.max(2) < on_Q.min(2)) | (on_Q.max(2) < on_P.min(2))).any(1)


def _inside(r, u1, u2, n, strict=True):
    """Whether direction r (p, 3) lies strictly (or with ``strict`` False, possibly on a
    side) between u1 and u2 (p, 3), the sector of angle below 180 degrees they span in
    the plane of normal n = u1 x u2."""
    a, b = np.einsum("pc,pc->p", cross(u1, r), n), np.einsum("pc,pc->p", cross(r, u2), n)
    return (a > 0) & (b > 0) if strict else (a >= 0) & (b >= 0)


def _sectors_overlap(u1, u2, w1, w2):
    """Whether two triangles with a common vertex v meet elsewhere, from their edges at
    v: u1, u2 (p, 3) of one and w1, w2 of the other (normals n_u = u1 x u2 and
    n_w = w1 x w2). Not where their planes are apart and the other two corners of one lie
    strictly on one side of the plane of the other (it meets that plane at v alone).
    Otherwise near v each triangle is its sector, and the sectors meet beyond v exactly
    when the triangles do. Planes not parallel meet on a line through v, of direction
    d = n_u x n_w: the sectors overlap when d or -d lies in both (closed). In one plane,
    when a boundary ray or the bisector of one lies strictly inside the other."""
    n_u, n_w = cross(u1, u2), cross(w1, w2)
    d = cross(n_u, n_w)
    flat = norm(d) <= COPLANAR * norm(n_u) * norm(n_w)
    meet = flat | ~(_one_side(w1, w2, n_u) | _one_side(u1, u2, n_w))
    rest = np.flatnonzero(meet)
    u1, u2, w1, w2, n_u, n_w, d, flat = (x[rest] for x in (u1, u2, w1, w2, n_u, n_w, d, flat))
    along = (_inside(d, u1, u2, n_u, False) & _inside(d, w1, w2, n_w, False)) | (
        _inside(-d, u1, u2, n_u, False) & _inside(-d, w1, w2, n_w, False)
    )
    unit = [r / np.maximum(norm(r), 1e-300)[:, None] for r in (u1, u2, w1, w2)]
    in_w = [_inside(r, w1, w2, n_w) for r in (u1, u2, unit[0] + unit[1])]
    in_u = [_inside(r, u1, u2, n_u) for r in (w1, w2, unit[2] + unit[3])]
    meet[rest] = np.where(flat, np.any(in_w + in_u, axis=0), along)
    return meet


def _one_side(a, b, n):
    """Whether the points a and b (p, 3), relative to a point of a plane of normal n,
    both lie strictly on one side of it."""
    s, t = np.einsum("pc,pc->p", a, n), np.einsum("pc,pc->p", b, n)
    return ((s > 0) & (t > 0)) | ((s < 0) & (t < 0))


def _flat_fans(V, F):
    """The vertices whose faces, seen along the vertex normal N, turn once about it,
    every corner counter-clockwise, (n,) bool: every edge at the vertex is in two faces
    that run along it in opposite directions (so the faces around it close into fans),
    and the angles of its corners in the plane normal to N, atan2((a x b).N, a.b -
    (a.N)(b.N)) for the edges a, b of the corner, are all positive and sum to 2 pi (one
    fan, once around). Their faces cover the plane once around the vertex, so no two of
    them meet beyond it."""
    n = len(V)
    N = vertex_normals(V, F)
    turn, folded = np.zeros(n), np.zeros(n)
    for k in range(3):
        v = F[:, k]
        a, b = V[F[:, (k + 1) % 3]] - V[v], V[F[:, (k + 2) % 3]] - V[v]
        along_a, along_b = np.einsum("pc,pc->p", a, N[v]), np.einsum("pc,pc->p", b, N[v])
        angle = np.arctan2(np.einsum("pc,pc->p", cross(a, b), N[v]), np.einsum("pc,pc->p", a, b) - along_a * along_b)
        turn += np.bincount(v, angle, minlength=n)
        folded += np.bincount(v, angle <= 0, minlength=n)
    # each edge in two faces, one each way: not on the boundary, in more faces, or
    # traversed twice the same way
    twins = twin_half_edges(F)
    closed = np.ones(n, dtype=bool)
    for bad in (boundary_edges(F, twins), nonmanifold_edges(F, twins), inconsistent_edges(F, twins)):
        closed[bad.ravel()] = False
    # the angles of a closed fan sum to a whole number of turns
    return closed & (folded == 0) & (np.abs(turn - 2 * np.pi) < 1)


def _candidate_pairs(V, F, flat):
    """Pairs (i, j), i < j, of faces that may meet, every pair that does among them but
    those with only a vertex v in common where ``flat[v]`` (see :func:`_flat_fans`; the
    caller spares them): compiled (extra ``fast``), those whose bounding boxes meet and
    that have no edge in common nor only such a vertex
    (:func:`qcremesh.geometry.compiled.box_pairs_kernel`); else those whose
    bounding spheres (about the centroid, through the farthest corner) meet, the faces
    grouped by radius in octaves, each group in a k-d tree, so that a few large faces do
    not widen the search of the small ones."""
    kernel = box_pairs_kernel()
    if kernel is not None:
        V, F = np.ascontiguousarray(V), np.ascontiguousarray(F)
        return np.column_stack(kernel(V, F, *face_grid(V, F), flat))
    corners = V[F]
    centre = corners.mean(1)
    radius = norm(corners - centre[:, None]).max(1)
    smallest = max(float(radius.min()), 1e-300)
    octave = np.floor(np.log2(np.maximum(radius, smallest) / smallest)).astype(np.int64)
    groups = [np.flatnonzero(octave == k) for k in np.unique(octave)]
    trees = [cKDTree(centre[g]) for g in groups]
    reach = [float(radius[g].max()) for g in groups]
    found = []
    for a, (ga, ta) in enumerate(zip(groups, trees)):
        near = ta.query_pairs(2 * reach[a], output_type="ndarray")
        found.append(ga[near])
        for b in range(a + 1, len(groups)):
            near = ta.sparse_distance_matrix(trees[b], reach[a] + reach[b], output_type="ndarray")
            found.append(np.column_stack([ga[near["i"]], groups[b][near["j"]]]))
    pairs = np.sort(np.concatenate(found), axis=1)
    low, high = pairs[:, 0], pairs[:, 1]
    return pairs[norm(centre[low] - centre[high]) <= radius[low] + radius[high]]


def self_intersections(V, F):
    """Pairs of faces that meet where the mesh's connectivity does not join them.

    Faces with no common vertex are reported when they share a point
    (:func:`triangles_intersect`), touching included (the faces on the two sides of a
    slit of zero width, whose vertices are listed twice at one position, touch); faces
    with one common vertex when they meet away from it (their sectors at it overlap);
    faces over the same three vertices always. Faces with a common edge meet along it
    and are not tested (a fold of 180 degrees, which lays them on each other, is one of
    :func:`qcremesh.mesh.validate.foldover_edges`).

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int

    Returns
    -------
    (k, 2) int64
        Face index pairs (i, j), i < j, in lexicographic order.

    Examples
    --------
    A square and a triangle standing up through its middle:

    >>> import numpy as np
    >>> V = np.array([[0.0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0],
    ...               [1, 0.5, -1], [1, 1.5, -1], [1, 1, 1]])
    >>> F = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6]])
    >>> self_intersections(V, F).tolist()
    [[0, 2], [1, 2]]
    """
    V, F = as_mesh_arrays(V, F)
    V = in_space(V)
    flat = _flat_fans(V, F)
    pairs = _candidate_pairs(V, F, flat)
    A, B = F[pairs[:, 0]], F[pairs[:, 1]]
    same = A[:, :, None] == B[:, None, :]  # (p, 3 corners of A, 3 corners of B)
    shared = np.count_nonzero(same.reshape(-1, 9), axis=1)
    hit = shared == 3
    apart = np.flatnonzero(shared == 0)
    P, Q = V[A[apart]], V[B[apart]]
    boxes = (P.min(1) <= Q.max(1)).all(1) & (Q.min(1) <= P.max(1)).all(1)
    hit[apart[boxes]] = triangles_intersect(P[boxes], Q[boxes])
    one = np.flatnonzero(shared == 1)
    if len(one):
        # Rotate each face so that the common vertex is its first corner.
        k_A = same[one].any(2).argmax(1)
        k_B = same[one].any(1).argmax(1)
        rows = np.arange(len(one))[:, None]
        A1 = A[one][rows, (k_A[:, None] + np.arange(3)) % 3]
        B1 = B[one][rows, (k_B[:, None] + np.arange(3)) % 3]
        fan = ~flat[A1[:, 0]]
        one, A1, B1 = one[fan], A1[fan], B1[fan]
        v = V[A1[:, 0]]
        hit[one] = _sectors_overlap(V[A1[:, 1]] - v, V[A1[:, 2]] - v, V[B1[:, 1]] - v, V[B1[:, 2]] - v)
    pairs = pairs[hit]
    return pairs[np.lexsort(pairs.T[::-1])]
