"""Refinement of a mesh's boundary where its edges are far longer than those around them,
without moving its surface.

A triangulated point set (a terrain's TIN, a planar Delaunay mesh of scattered points)
has its convex hull for boundary: a few dozen edges, each tens of times longer than the
edges inside, with layers of slivers along them. Its disk map puts those few boundary
vertices on the circle and the rest inside the polygon they span, not the disk (a random
point set of a 3:1 rectangle, 40,000 faces, 25 boundary vertices: mean |mu| 0.20, and
its remesh has slivers). :func:`refine_boundary` cuts such edges into pieces as long as
the edges around them, each boundary face into the fan from its far corner, and then
flips the edges of the pieces of the surface that are flat, as Lawson's algorithm does
(:func:`~qcremesh.geometry.intrinsic.intrinsic_delaunay` with ``flat``), which turns the
fans into the Delaunay triangulation of the points there: the same surface, with a
boundary as fine as its inside.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from ..mesh.topology import _edge_keys, boundary_edges, half_edges, vertex_face_incidence
from .intrinsic import intrinsic_delaunay
from .vectors import aligned

__all__ = ["local_edge_length", "split_boundary_edges", "refine_boundary"]

# Edge flips that keep the surface: those of two faces whose normals are within this angle
# (radians), as on a planar mesh.
FLAT = 1e-6



def local_edge_length(V, F, points, neighbours=16):
    """The typical edge length of a mesh around given points: the median, over the
    ``neighbours`` vertices nearest each point, of each vertex's median edge length (over
    the edges it starts as a corner of its faces, which leaves out one of a boundary
    vertex's two boundary edges).

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
    points : (p, 3) float
    neighbours : int

    Returns
    -------
    (p,) float
    """
    return _typical_length(V, F, neighbours)(points)


def _typical_length(V, F, neighbours):
    """:func:`local_edge_length` of the mesh, as a function of the points (each vertex's
    median over the edges it starts, computed for the vertices near the points only)."""
    V = np.asarray(V, dtype=np.float64)
    H = half_edges(F)
    used = np.unique(H[:, 0])
    k = min(neighbours, len(used))
    tree = cKDTree(V[used])

    def at(points):
        points = np.asarray(points, dtype=np.float64)
        near = used[tree.query(points, k=k)[1].reshape(len(points), k)]
        around, slot = np.unique(near, return_inverse=True)
        start = H[np.isin(H[:, 0], around)]
        owner = np.searchsorted(around, start[:, 0])
        length = np.linalg.norm(V[start[:, 1]] - V[start[:, 0]], axis=1)
        order = np.lexsort((length, owner))
        count = np.bincount(owner, minlength=len(around))
        first = np.r_[0, np.cumsum(count)[:-1]]
        median = length[order][first + (count - 1) // 2]
        return np.median(median[slot.reshape(near.shape)], axis=1)

    return at


def split_boundary_edges(F, n, pieces):
    """Cut boundary edges into equal pieces, each boundary face into the fan from its
    corner opposite the edge.

    A face with several boundary edges to cut gets the one in most pieces; the fan's face
    that keeps another of them can take it in a further call.

    Parameters
    ----------
    F : (m, 3) int
        Consistently oriented.
    n : int
        Number of vertices.
    pieces : callable
        ``pieces(E)``: the number of pieces (>= 1) of each boundary edge of the (b, 2)
        array E.

    Returns
    -------
    F_new : (m', 3) int64
        Oriented as F; the new vertices are numbered from n, each edge's in order from
        its first end (``E[:, 0]``) on.
    P : (n', n) scipy.sparse.csr_matrix
        Each vertex as a combination of the old ones, ``P @ V`` the new positions (and
        ``P @ data`` any per-vertex data interpolated along the edges).
    """
    F = np.asarray(F, dtype=np.int64)
    m = len(F)
    B = boundary_edges(F)
    count = np.asarray(pieces(B), dtype=np.int64)
    sides = _edge_keys(half_edges(F), n)
    # the count of each side of each face (side j: F[j] -> F[j + 1]); 1 where not on the boundary
    order = np.argsort(_edge_keys(B, n))
    keys = _edge_keys(B, n)[order]
    at = np.minimum(np.searchsorted(keys, sides), len(keys) - 1)
    on = keys[at] == sides
    side = np.where(on, count[order][at], 1).reshape(3, m).T
    j = side.argmax(axis=1)
    k = side[np.arange(m), j]
    cut = np.flatnonzero(k > 1)
    if not len(cut):
        return F, sp.identity(n, format="csr")
    a, b, c = (F[cut, (j[cut] + r) % 3] for r in range(3))
    k = k[cut]
    first = n + np.r_[0, np.cumsum(k - 1)[:-1]]
    # vertex i (1 <= i < k) of the edge a -> b, at i / k from a
    edge = np.repeat(np.arange(len(cut)), k - 1)
    i = np.arange(len(edge)) - np.repeat(first - n, k - 1) + 1
    t = i / k[edge]
    new = len(edge)
    rows = np.r_[np.arange(n), np.repeat(n + np.arange(new), 2)]
    cols = np.r_[np.arange(n), np.column_stack([a[edge], b[edge]]).ravel()]
    vals = np.r_[np.ones(n), np.column_stack([1 - t, t]).ravel()]
    P = sp.csr_matrix((vals, (rows, cols)), shape=(n + new, n))
    # the fan: (p_i, p_i+1, c) for i = 0..k-1, p_0 = a, p_k = b
    face = np.repeat(np.arange(len(cut)), k)
    step = np.arange(len(face)) - np.repeat(np.r_[0, np.cumsum(k)[:-1]], k)

    def corner(s):
        return np.where(s == 0, a[face], np.where(s == k[face], b[face], first[face] + s - 1))

    fans = np.column_stack([corner(step), corner(step + 1), c[face]])
    keep = np.ones(m, dtype=bool)
    keep[cut] = False
    return np.concatenate([F[keep], fans]), P


def _flat_around(X, F, E):
    """Whether the face of each boundary edge of E (directed as in its face) and every
    face around its corners lie in one plane (normals within ``FLAT``): where the flips
    can turn its fan into well-shaped faces."""
    m = len(F)
    keys = _edge_keys(half_edges(F), len(X))
    order = np.argsort(keys)
    face = order[np.searchsorted(keys[order], _edge_keys(E, len(X)))] % m
    normal = np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]])
    around = vertex_face_incidence(F, len(X))[F[face].ravel()].tocoo()
    owner = around.row // 3
    n1, n2 = normal[face[owner]], normal[around.col]
    flat = aligned(n1, n2, FLAT)
    return np.bincount(owner, weights=~flat, minlength=len(E)) == 0


def refine_boundary(V, F, ratio=4.0, neighbours=16, rounds=3):
    """Cut the boundary edges longer than ``ratio`` times the typical edge length around
    them (:func:`local_edge_length`) into pieces no longer than it
    (:func:`split_boundary_edges`), where the surface around them is flat (``FLAT``),
    and flip the edges of the flat parts of the surface to Delaunay; see the module's
    notes. Where it is not flat (a terrain's boundary faces, which span the dips and rises
    of the ground between two far points of its hull), the fans would stay fans, which
    spoil the map as much as the long edges: those edges are left as they are.

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
        A consistently oriented manifold mesh.
    ratio : float
    neighbours : int
        Of :func:`local_edge_length`.
    rounds : int
        Calls of :func:`split_boundary_edges` (faces with two long boundary edges take
        one per call).

    Returns
    -------
    F_new : (m', 3) int64 or None
        None where no boundary edge is that long.
    P : (n', n) scipy.sparse.csr_matrix or None
        The vertices as combinations of the input's: ``P @ V`` their positions, ``P @
        data`` any per-vertex data.
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    B = boundary_edges(F)
    if not len(B):
        return None, None
    typical = _typical_length(V, F, neighbours)
    P = sp.identity(len(V), format="csr")
    X = V

    def pieces(E):
        length = np.linalg.norm(X[E[:, 0]] - X[E[:, 1]], axis=1)
        local = typical((X[E[:, 0]] + X[E[:, 1]]) / 2)
        long = length > ratio * local
        long[long] = _flat_around(X, F, E[long])
        return np.where(long, np.ceil(length / local), 1)

    if not (pieces(B) > 1).any():
        return None, None
    for _ in range(rounds):
        F_next, Q = split_boundary_edges(F, len(X), pieces)
        if Q.shape[0] == len(X):
            break
        F, P = F_next, (Q @ P).tocsr()
        X = P @ V
    if len(X) == len(V):
        return None, None
    F = intrinsic_delaunay(X, F, flat=FLAT)[0]
    return F, P
