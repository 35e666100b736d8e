"""Combinatorial topology of triangle meshes: edges, boundary loops, components, Euler
characteristic, manifoldness and orientation.

Every function takes the face array ``F`` ((m, 3) int, 0-based) and works on index arrays
only; none of them loops over faces or vertices in Python.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components as _cc

__all__ = [
    "half_edges",
    "twin_half_edges",
    "edges",
    "edge_face_counts",
    "boundary_edges",
    "boundary_loops",
    "boundary_loop",
    "connected_components",
    "euler_characteristic",
    "genus",
    "nonmanifold_edges",
    "nonmanifold_vertices",
    "corner_fans",
    "split_nonmanifold_edges",
    "split_nonmanifold_vertices",
    "inconsistent_edges",
    "orient_faces",
    "unreferenced_vertices",
    "face_edge_lengths",
    "needles_and_caps",
    "degenerate_faces",
    "duplicate_faces",
    "repeated_corner_faces",
    "adjacency_matrix",
    "vertex_face_incidence",
    "unique_integers",
]


def unique_integers(a):
    """Sorted distinct values of an integer array, (k,).

    Same result as ``np.unique(a)``, by sorting: numpy 2.3 and later answer a bare
    ``np.unique`` of integers with a hash table, about 100 times slower than sorting on
    the millions of edge keys of a large mesh.
    """
    a = np.sort(np.asarray(a).ravel())
    return a[np.r_[True, a[1:] != a[:-1]]] if len(a) else a


def half_edges(F):
    """Directed edges of every face, (3m, 2): ``F[:, [0, 1]]``, then ``[1, 2]``, then ``[2, 0]``.

    Row ``k * m + f`` is the edge of face ``f`` opposite its corner ``(k + 2) % 3``.
    """
    F = np.asarray(F)
    return np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])


def _edge_keys(H, n):
    """One int64 per undirected edge: ``min * n + max``."""
    lo = np.minimum(H[:, 0], H[:, 1]).astype(np.int64)
    hi = np.maximum(H[:, 0], H[:, 1]).astype(np.int64)
    return lo * n + hi


def _keys_to_edges(keys, n):
    return np.column_stack([keys // n, keys % n])


def edges(F):
    """Undirected edges, each once, sorted, as (e, 2) with ``E[:, 0] < E[:, 1]``."""
    return edge_face_counts(F)[0]


def edge_face_counts(F):
    """Undirected edges and the number of faces that contain each.

    Returns
    -------
    E : (e, 2) int64
        Edges with ``E[:, 0] < E[:, 1]``, in lexicographic order.
    count : (e,) int64
        Faces incident to each edge: 1 on the boundary, 2 inside, more at a non-manifold edge.
    """
    F = np.asarray(F)
    n = int(F.max()) + 1
    keys, count = np.unique(_edge_keys(half_edges(F), n), return_counts=True)
    return _keys_to_edges(keys, n), count


def boundary_edges(F, twins=None):
    """Directed boundary edges (b, 2), oriented as in their face (interior on the left).

    ``twins``, the pairs of :func:`twin_half_edges` where already computed, spares their
    sort."""
    F = np.asarray(F)
    H = half_edges(F)
    i, j = _edge_pairs(_edge_keys(H, int(F.max()) + 1)) if twins is None else twins
    single = np.ones(len(H), dtype=bool)
    single[i] = single[j] = False
    return H[single]


def boundary_loops(F, twins=None):
    """Ordered boundary loops.

    Each loop follows the orientation of the faces (interior on the left, so the loop of a
    counter-clockwise disk parameterization runs counter-clockwise) and starts at its
    smallest vertex index. Loops are sorted longest first. Where the boundary touches
    itself at a vertex, the loops through it are split there (the j-th incoming boundary
    edge continues with the j-th outgoing one).

    Cycles are found by pointer jumping over the successor permutation of the boundary
    edges: O(b log b) vectorized work for b boundary edges.

    Parameters
    ----------
    F : (m, 3) int
    twins : tuple of (k,) int, optional
        The pairs of :func:`twin_half_edges`, where already computed.

    Returns
    -------
    list of (k,) int64 arrays

    Raises
    ------
    ValueError
        If the faces are not consistently oriented along the boundary (a boundary vertex
        with more incoming than outgoing boundary edges).
    """
    B = boundary_edges(F, twins)
    nb = len(B)
    if nb == 0:
        return []
    out_order = np.argsort(B[:, 0], kind="stable")
    in_order = np.argsort(B[:, 1], kind="stable")
    if not np.array_equal(B[out_order, 0], B[in_order, 1]):
        raise ValueError("boundary edges are not consistently oriented")
    succ = np.empty(nb, dtype=np.int64)
    succ[in_order] = out_order
    key = B[:, 0] * nb + np.arange(nb)
    label = key.copy()
    jump = succ.copy()
    for _ in range(int(np.ceil(np.log2(nb))) + 1):
        label = np.minimum(label, label[jump])
        jump = jump[jump]
    is_head = label == key
    # Distance to the last edge of each loop (the predecessor of its head).
    nxt = np.where(is_head[succ], np.arange(nb), succ)
    dist = (nxt != np.arange(nb)).astype(np.int64)
    for _ in range(int(np.ceil(np.log2(nb))) + 1):
        dist = dist + dist[nxt]
        nxt = nxt[nxt]
    order = np.lexsort((-dist, label))
    starts = np.flatnonzero(is_head[order])
    loops = np.split(B[order, 0], starts[1:])
    loops.sort(key=lambda loop: (-len(loop), int(loop[0])))
    return loops


def boundary_loop(F):
    """The longest boundary loop (see :func:`boundary_loops`); empty if there is none."""
    loops = boundary_loops(F)
    return loops[0] if loops else np.zeros(0, dtype=np.int64)


def adjacency_matrix(F, n=None):
    """Vertex adjacency of the edge graph, (n, n) CSR with ones on the edges.

    Parameters
    ----------
    F : (m, 3) int
    n : int, optional
        Number of vertices; ``F.max() + 1`` by default.
    """
    F = np.asarray(F)
    n = int(F.max()) + 1 if n is None else n
    # Every half-edge both ways; the conversion sums the repeats of an edge (a counting
    # sort, not the comparison sort of a list of unique edges: 0.6 -> 0.3 s at 1.7M faces).
    H = half_edges(F)
    A = sp.csr_matrix((np.ones(2 * len(H)), (np.r_[H[:, 0], H[:, 1]], np.r_[H[:, 1], H[:, 0]])), shape=(n, n))
    A.data[:] = 1.0
    return A


def vertex_face_incidence(F, n=None):
    """Vertex-face incidence, (n, m) CSR with a one where vertex i is a corner of face f;
    row i lists the faces around vertex i.

    Parameters
    ----------
    F : (m, 3) int
    n : int, optional
        Number of vertices; ``F.max() + 1`` by default.
    """
    F = np.asarray(F)
    n = int(F.max()) + 1 if n is None else n
    m = len(F)
    return sp.csr_matrix((np.ones(3 * m), (F.ravel(), np.repeat(np.arange(m), 3))), shape=(n, m))


def connected_components(F, n=None):
    """Connected components of the faces (two faces connect through a shared vertex).

    Returns
    -------
    count : int
        Number of components that contain at least one face.
    face_label : (m,) int64
        Component of each face, numbered 0..count-1 in order of first appearance.
    """
    F = np.asarray(F)
    n = int(F.max()) + 1 if n is None else n
    # Two edges of every face connect its three vertices; an edge listed twice (by both of
    # its faces) connects nothing more, so the edges need not be made unique (a sort of
    # every edge key less: 0.6 s at 1.7M faces).
    rows, cols = np.r_[F[:, 0], F[:, 1]], np.r_[F[:, 1], F[:, 2]]
    G = sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n))
    _, vlabel = _cc(G, directed=False)
    flabel = vlabel[F[:, 0]]
    _, first, inv = np.unique(flabel, return_index=True, return_inverse=True)
    rank = np.argsort(np.argsort(first))
    return len(first), rank[inv.ravel()].astype(np.int64)


def euler_characteristic(F):
    """V - E + F over the vertices referenced by ``F``."""
    F = np.asarray(F)
    return len(unique_integers(F)) - len(edges(F)) + len(F)


def genus(F, n=None):
    """Genus of ``F`` where it is one surface (connected, no non-manifold edge or vertex),
    None otherwise: (2 - chi - b) / 2 with b boundary loops (0 for a disk, a sphere and a
    disk with holes; 1 for a torus, with or without holes).

    On such a surface every boundary vertex has two boundary edges, so the loops are the
    connected components of the boundary edges, whatever the faces' orientation.
    """
    F = np.asarray(F)
    if not len(F) or connected_components(F, n)[0] != 1:
        return None
    if len(nonmanifold_edges(F)) or len(nonmanifold_vertices(F)):
        return None
    B = boundary_edges(F)
    loops = 0
    if len(B):
        m = int(F.max()) + 1
        G = sp.csr_matrix((np.ones(len(B)), (B[:, 0], B[:, 1])), shape=(m, m))
        loops = _cc(G, directed=False)[0] - (m - len(unique_integers(B)))
    return (2 - euler_characteristic(F) - loops) // 2


def nonmanifold_edges(F, twins=None):
    """Undirected edges shared by more than two faces, (k, 2), in lexicographic order.

    ``twins``, the pairs of :func:`twin_half_edges` where already computed, spares a sort:
    the half-edges of an edge in c faces make c - 1 pairs, consecutive there."""
    if twins is None:
        E, count = edge_face_counts(F)
        return E[count > 2]
    F = np.asarray(F)
    n = int(F.max()) + 1
    key = _edge_keys(half_edges(F)[twins[0]], n)
    return _keys_to_edges(unique_integers(key[1:][key[1:] == key[:-1]]), n)


def nonmanifold_vertices(F, twins=None):
    """Vertices whose incident faces form more than one fan (a pinch or bow-tie vertex).

    Around a vertex v, two incident faces are linked when they share an edge through v.
    The vertex is manifold when those links connect all its faces into one fan. The fans
    are counted for all vertices at once as connected components of a graph on the corners
    (face, vertex) pairs (:func:`corner_fans`). Vertices on non-manifold edges are reported
    by :func:`nonmanifold_edges` and are not repeated here unless they also pinch.
    ``twins``, the pairs of :func:`twin_half_edges` where already computed, spares their
    sort.

    Returns
    -------
    (k,) int64, sorted
    """
    F = np.asarray(F)
    m = len(F)
    corner_vertex = F.T.ravel()
    fans, fan = corner_fans(F, twins)
    # Every fan has the corners of one vertex: as many fans as vertices, none pinched.
    if fans == np.count_nonzero(np.bincount(corner_vertex)):
        return np.zeros(0, dtype=np.int64)
    pairs = unique_integers(corner_vertex.astype(np.int64) * (3 * m) + fan)
    # the (vertex, fan) pairs are sorted by vertex: a vertex with two or more is pinched
    v = pairs // (3 * m)
    return unique_integers(v[1:][v[1:] == v[:-1]])


def corner_fans(F, twins=None):
    """The fans of faces around the vertices, as a label per corner.

    Corner c = k * m + f is vertex ``F[f, k]`` of face f. Two corners of the same vertex
    are in one fan when their faces share an edge through it, one of the pairs ``twins``
    of half-edges (:func:`twin_half_edges` by default: every interior edge; a subset
    leaves the others open, as a cut does).

    Returns
    -------
    count : int
    fan : (3 m,) int
        The fan of each corner, 0..count-1.
    """
    F = np.asarray(F)
    m = len(F)
    # Half-edge h = k * m + f of half_edges(F) leaves the vertex of corner h and enters
    # that of corner next(h) = ((k + 1) % 3) * m + f.
    H = half_edges(F)
    i, j = _edge_pairs(_edge_keys(H, int(F.max()) + 1)) if twins is None else twins

    def entering(h):
        return (h // m + 1) % 3 * m + h % m

    # Corners of the same vertex across the shared edge are in the same fan.
    same_dir = H[i, 0] == H[j, 0]
    u1 = np.where(same_dir, j, entering(j))
    u2 = np.where(same_dir, entering(j), j)
    rows = np.r_[i, entering(i)]
    cols = np.r_[u1, u2]
    G = sp.coo_matrix((np.ones(len(rows), dtype=np.int8), (rows, cols)), shape=(3 * m, 3 * m))
    return _cc(G, directed=False)


def _edge_pairs(key):
    """Pairs (i, j) of positions in ``key`` with equal values, j the next one with that
    value after i (k positions with one value give k - 1 pairs). Sorts key * len + position
    where that fits in int64 (a value sort, several times faster than an argsort)."""
    key = np.asarray(key, dtype=np.int64)
    count = len(key)
    if count and int(key.max()) < np.iinfo(np.int64).max // max(count, 1) - 1:
        packed = np.sort(key * count + np.arange(count))
        ks, order = packed // count, packed % count
    else:
        order = np.argsort(key, kind="stable")
        ks = key[order]
    same = ks[1:] == ks[:-1]
    return order[:-1][same], order[1:][same]


def twin_half_edges(F):
    """The two half-edges of every interior edge, as rows (i, j) of :func:`half_edges`,
    (k,) and (k,) with i < j: on a manifold mesh each interior edge once, i in one of its
    faces and j in the other (row r is in face ``r % m``)."""
    F = np.asarray(F)
    return _edge_pairs(_edge_keys(half_edges(F), int(F.max()) + 1))


def split_nonmanifold_vertices(F):
    """Give each fan of faces around a vertex a vertex of its own (a pinched vertex, where
    two sheets touch, becomes one vertex per sheet; the surface does not move).

    Returns
    -------
    F : (m, 3) int64
        The faces over the new vertices, numbered in the order of the vertex each copies,
        its fans in order of their labels.
    parent : (n',) int64
        The vertex of the input each new vertex copies (sorted; vertices no face uses
        have none).
    """
    return _split_fans(np.asarray(F, dtype=np.int64))


def _split_fans(F, twins=None):
    """A vertex per fan of :func:`corner_fans` (F, twins): (F, parent)."""
    m = len(F)
    _, fan = corner_fans(F, twins)
    keys, corner = np.unique(F.T.ravel() * (3 * m) + fan, return_inverse=True)
    return corner.reshape(3, m).T.astype(np.int64), keys // (3 * m)


def split_nonmanifold_edges(V, F):
    """Detach the sheets of faces that meet at an edge of more than two faces.

    At each such edge the two faces that traverse it in opposite directions and turn the
    least from each other (the largest dot product of their unit normals) stay joined;
    then each fan of faces around a vertex, its faces linked across those pairs and the
    edges of two faces, gets a vertex of its own (the surface does not move). A fin on a
    surface comes off it along the edge. Where the other sheets meet the joined pair
    again around an end of the edge (one fan through them), the edge stays non-manifold.

    Returns
    -------
    F : (m, 3) int64
    parent : (n',) int64
        As :func:`split_nonmanifold_vertices` (which this also does).
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    m = len(F)
    H = half_edges(F)
    key = _edge_keys(H, int(F.max()) + 1)
    order = np.argsort(key, kind="stable")
    start = np.flatnonzero(np.r_[True, key[order][1:] != key[order][:-1]])
    size = np.diff(np.r_[start, len(key)])
    pairs = [(order[start[size == 2]], order[start[size == 2] + 1])]
    # every two half-edges of each edge of more faces, the best of them per edge
    group_start, group_size = start[size > 2], size[size > 2]
    member_group = np.repeat(np.arange(len(group_size)), group_size)
    member = _ranges(group_start, group_size)
    partner_group = np.repeat(member_group, group_size[member_group])
    first = np.repeat(member, group_size[member_group])
    second = _ranges(group_start[member_group], group_size[member_group])
    keep = first < second
    group, a, b = partner_group[keep], order[first[keep]], order[second[keep]]
    normal = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    score = np.where(H[a, 0] == H[b, 1], (normal[a % m] * normal[b % m]).sum(1), -np.inf)
    best = np.lexsort((-score, group))
    best = best[np.r_[True, group[best][1:] != group[best][:-1]]]
    best = best[np.isfinite(score[best])]
    pairs.append((a[best], b[best]))
    return _split_fans(F, tuple(np.concatenate(side) for side in zip(*pairs)))


def _ranges(start, count):
    """start[k], start[k] + 1, ..., start[k] + count[k] - 1 for every k, concatenated."""
    offset = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    return np.repeat(start, count) + offset


def inconsistent_edges(F, twins=None):
    """Interior edges whose two faces traverse them in the same direction, (k, 2).

    A consistently oriented mesh has none: each interior edge appears once as (a, b) and
    once as (b, a). For an edge-manifold mesh, ``twins``, the pairs of
    :func:`twin_half_edges` where already computed, spares a sort.
    """
    F = np.asarray(F)
    n = int(F.max()) + 1
    H = half_edges(F).astype(np.int64)
    if twins is None:
        directed, count = np.unique(H[:, 0] * n + H[:, 1], return_counts=True)
        bad = _keys_to_edges(directed[count > 1], n)
    else:
        i, j = twins
        bad = H[i[H[i, 0] == H[j, 0]]]
    return np.unique(_keys_to_edges(_edge_keys(bad, n), n), axis=0) if len(bad) else bad


def orient_faces(F):
    """Orient the faces of an orientable, edge-manifold mesh consistently: in each
    connected surface, the faces turned against the majority of their component are
    reversed.

    Faces sharing an edge agree when they traverse it in opposite directions. The
    orientations are solved for all faces at once as connected components of a graph on
    two copies of the faces (kept, reversed): agreeing neighbours link kept to kept and
    reversed to reversed, disagreeing ones kept to reversed.

    Parameters
    ----------
    F : (m, 3) int

    Returns
    -------
    F : (m, 3) int64
        The faces, some reversed.
    reversed : (m,) bool
        Which.

    Raises
    ------
    ValueError
        The mesh is not orientable (a Moebius strip).
    """
    F = np.asarray(F, dtype=np.int64)
    m = len(F)
    H = half_edges(F)
    i, j = twin_half_edges(F)
    f, g = i % m, j % m
    same = H[i, 0] == H[j, 0]  # traversed in the same direction: they disagree
    rows = np.concatenate([f, f + m])
    cols = np.concatenate([np.where(same, g + m, g), np.where(same, g, g + m)])
    graph = sp.coo_matrix((np.ones(len(rows), dtype=np.int8), (rows, cols)), shape=(2 * m, 2 * m))
    _, label = _cc(graph, directed=False)
    if np.any(label[:m] == label[m:]):
        raise ValueError("the mesh is not orientable")
    # Faces whose kept copy is in the same class as their component's first face's keep
    # its orientation; flip the others, or these if they are fewer.
    _, component = _cc(sp.coo_matrix((np.ones(len(f)), (f, g)), shape=(m, m)), directed=False)
    first = np.full(component.max() + 1, m)
    np.minimum.at(first, component, np.arange(m))
    flip = label[:m] != label[first[component]]
    flipped_share = np.bincount(component, flip) / np.bincount(component)
    flip ^= flipped_share[component] > 0.5
    F = F.copy()
    F[flip] = F[flip][:, ::-1]
    return F, flip


def unreferenced_vertices(F, n):
    """Vertices in ``0..n-1`` used by no face, (k,) int64."""
    used = np.zeros(n, dtype=bool)
    used[np.asarray(F).ravel()] = True
    return np.flatnonzero(~used)


# A face whose shortest edge is at most NEEDLE times its longest is a needle; one with an
# angle of at least CAP_ANGLE degrees a cap (its corner within 1e-3 of the opposite edge's
# length from that edge). Both are faces of zero area or within rounding of it: their
# cotangent weights are infinite or huge, and the Beltrami coefficient of a map onto them
# rounds to |mu| = 1 (a pymeshlab decimation of human_brain.ply made faces of relative
# area 1e-10, which a test on area alone passed and the disk map failed on). None of the
# disk meshes of ../shared/data has either.
NEEDLE = 1e-6
CAP_ANGLE = 179.8


def face_edge_lengths(V, F):
    """Lengths of the edges of every face, (m, 3): column k is the edge from corner k to
    corner k + 1 (the order of :func:`half_edges`)."""
    P = np.asarray(V, dtype=np.float64)[np.asarray(F)]
    return np.linalg.norm(np.roll(P, -1, axis=1) - P, axis=2)


def needles_and_caps(V, F):
    """The needles and the caps among the faces of a mesh (faces with a repeated corner
    are needles).

    Parameters
    ----------
    V : (n, d) float
    F : (m, 3) int

    Returns
    -------
    needle, cap : (m,) bool
        Faces whose shortest edge is at most ``NEEDLE`` times their longest; the others
        with an angle of at least ``CAP_ANGLE`` degrees.
    """
    L = face_edge_lengths(V, F)
    needle = L.min(1) <= NEEDLE * L.max(1)
    k = L.argmax(1)
    rows = np.arange(len(F))
    a, b, c = L[rows, k], L[rows, (k + 1) % 3], L[rows, (k + 2) % 3]
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = (b * b + c * c - a * a) / (2 * b * c)  # of the angle opposite the longest edge
    cap = ~needle & (cos <= np.cos(np.radians(CAP_ANGLE)))
    return needle, cap


def repeated_corner_faces(F):
    """Faces with a vertex at two of their corners, (m,) bool (left by merging vertices:
    no area, and an edge from a vertex to itself)."""
    F = np.asarray(F)
    return (F[:, 0] == F[:, 1]) | (F[:, 1] == F[:, 2]) | (F[:, 2] == F[:, 0])


def duplicate_faces(F):
    """Faces over the same three vertices as an earlier face, in either orientation,
    (k,) int64 face indices, increasing (a face listed twice makes its edges
    non-manifold)."""
    F = np.asarray(F)
    if not len(F):
        return np.zeros(0, dtype=np.int64)
    _, first = np.unique(np.sort(F, axis=1), axis=0, return_index=True)
    repeated = np.ones(len(F), dtype=bool)
    repeated[first] = False
    return np.flatnonzero(repeated)


def degenerate_faces(V, F):
    """Faces of zero area or within rounding of it: the needles and caps of
    :func:`needles_and_caps`.

    Parameters
    ----------
    V : (n, d) float
    F : (m, 3) int

    Returns
    -------
    (k,) int64 face indices
    """
    needle, cap = needles_and_caps(V, F)
    return np.flatnonzero(needle | cap)
