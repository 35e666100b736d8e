"""Refinement of a mesh where its edges are too long, without moving its surface.

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

A CAD tessellation, or a mesh of a few large faces remeshed to many, has edges far longer
than the output's everywhere, and needles along them. :func:`split_long_edges` cuts every
edge between two faces not in one plane into pieces of the length wanted, flips the flat
parts to Delaunay, and halves what is still too long (the inside of a large flat face)
until nothing is.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from ..mesh.topology import _edge_keys, boundary_edges, edges, half_edges, vertex_face_incidence
from .creases import dihedral_angles
from .intrinsic import intrinsic_delaunay
from .vectors import aligned

__all__ = ["local_edge_length", "refine_boundary", "split_edges", "split_long_edges"]

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


def refine_boundary(V, F, ratio=4.0, neighbours=16):
    """Cut the boundary edges longer than ``ratio`` times the typical edge length around
    them (:func:`local_edge_length`) into pieces no longer than it (:func:`split_edges`),
    where the surface around them is flat (``FLAT``), and flip the edges of the flat parts
    of the surface to Delaunay; see the module's notes. Where it is not flat (a terrain's
    boundary faces, which span the dips and rises of the ground between two far points of
    its hull), the fans would stay fans, which spoil the map as much as the long edges:
    those edges are left as they are.

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
        A consistently oriented manifold mesh.
    ratio : float
    neighbours : int
        Of :func:`local_edge_length`.

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
    length = np.linalg.norm(V[B[:, 0]] - V[B[:, 1]], axis=1)
    local = _typical_length(V, F, neighbours)((V[B[:, 0]] + V[B[:, 1]]) / 2)
    long = length > ratio * local
    long[long] = _flat_around(V, F, B[long])
    if not long.any():
        return None, None
    E = edges(F)
    count = np.ones(len(E))
    # (E is sorted, and so are its keys)
    count[np.searchsorted(_edge_keys(E, len(V)), _edge_keys(B[long], len(V)))] = np.ceil(length[long] / local[long])
    F, P = split_edges(F, len(V), count)
    F = intrinsic_delaunay(P @ V, F, flat=FLAT)[0]
    return F, P


def split_edges(F, n, count):
    """Cut edges into equal pieces, each face into fans from its corners over its cut sides.

    A face takes its side in most pieces first: the fan from the corner opposite it; the
    first and last faces of the fan keep the face's other two sides and take theirs in
    turn, so a face with three cut sides is three fans deep. The new faces are needles
    where a side is cut into many pieces (a flip to Delaunay makes them well shaped, see
    :func:`split_long_edges`).

    Parameters
    ----------
    F : (m, 3) int
        Consistently oriented.
    n : int
        Number of vertices.
    count : (e,) int
        The number of pieces (>= 1) of each edge of ``edges(F)``
        (:func:`qcremesh.mesh.topology.edges`: sorted, ``E[:, 0] < E[:, 1]``).

    Returns
    -------
    F_new : (m', 3) int64
        Oriented as F; the new vertices are numbered from n, each edge's in order from
        ``E[:, 0]`` on.
    P : (n', n) scipy.sparse.csr_matrix
        Each vertex as a combination of the old ones, ``P @ V`` the new positions (and
        ``P @ data`` any per-vertex data interpolated along the edges).
    """
    F = np.asarray(F, dtype=np.int64)
    E = edges(F)
    count = np.asarray(count, dtype=np.int64)
    cut = np.flatnonzero(count > 1)
    if not len(cut):
        return F, sp.identity(n, format="csr")
    lo, hi, k = E[cut, 0], E[cut, 1], count[cut]
    first = n + np.r_[0, np.cumsum(k - 1)[:-1]]
    # vertex i (1 <= i < k) of the edge lo -> hi, at i / k from lo
    edge = np.repeat(np.arange(len(cut)), k - 1)
    t = (np.arange(len(edge)) - np.repeat(first - n, k - 1) + 1) / k[edge]
    new = len(edge)
    rows = np.r_[np.arange(n), np.repeat(n + np.arange(new), 2)]
    cols = np.r_[np.arange(n), np.column_stack([lo[edge], hi[edge]]).ravel()]
    vals = np.r_[np.ones(n), np.column_stack([1 - t, t]).ravel()]
    P = sp.csr_matrix((vals, (rows, cols)), shape=(n + new, n))
    total = n + new
    keys = _edge_keys(np.column_stack([lo, hi]), total)  # sorted, as E is
    for _ in range(3):
        m = len(F)
        sides = _edge_keys(half_edges(F), total)
        at = np.minimum(np.searchsorted(keys, sides), len(keys) - 1)
        on = keys[at] == sides
        side = np.where(on, k[at], 1).reshape(3, m).T
        j = side.argmax(axis=1)
        todo = np.flatnonzero(side[np.arange(m), j] > 1)
        if not len(todo):
            break
        j = j[todo]
        which = at.reshape(3, m).T[todo, j]
        a, b, c = (F[todo, (j + r) % 3] for r in range(3))
        kf, start = k[which], first[which]
        forward = a == lo[which]
        face = np.repeat(np.arange(len(todo)), kf)
        step = np.arange(len(face)) - np.repeat(np.r_[0, np.cumsum(kf)[:-1]], kf)

        def corner(s):
            along = np.where(forward[face], s, kf[face] - s)
            return np.where(s == 0, a[face], np.where(s == kf[face], b[face], start[face] + along - 1))

        fans = np.column_stack([corner(step), corner(step + 1), c[face]])
        keep = np.ones(m, dtype=bool)
        keep[todo] = False
        F = np.concatenate([F[keep], fans])
    return F, P


def split_long_edges(V, F, max_length, max_rounds=32):
    """The surface on vertices no farther apart than ``max_length`` along any edge. The
    edges on the boundary and between faces not in one plane are cut into equal pieces no
    longer than it (:func:`split_edges`) and the edges of the flat parts of the surface
    flipped to Delaunay, as in :func:`refine_boundary` (each flat part is then the
    Delaunay triangulation of the points on its border); then, in rounds, every edge still
    longer is halved and the flat parts flipped again (the inside of a large flat face).
    The surface does not move.

    A CAD tessellation has strips of needles (a cylinder's two triangles per facet, each
    as long as the cylinder), which a disk map cannot make conformal and an output finer
    than them cannot follow; cut into pieces about as long as the strip is wide, with no
    point inside the strip (a strip's diagonal halved would put points beside its sides),
    they become ladders of well-shaped triangles.

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
        A consistently oriented manifold mesh.
    max_length : float
        Positive.
    max_rounds : int
        Rounds of halving at most.

    Returns
    -------
    F_new : (m', 3) int64
        F where no edge is longer than ``max_length``.
    P : (n', n) scipy.sparse.csr_matrix
        The vertices as combinations of the input's: ``P @ V`` their positions, ``P @
        data`` any per-vertex data.
    """
    if not max_length > 0:
        raise ValueError(f"max_length must be positive, got {max_length!r}")
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    P = sp.identity(len(V), format="csr")
    X = V
    for k in range(max_rounds):
        E = edges(F)
        length = np.linalg.norm(X[E[:, 1]] - X[E[:, 0]], axis=1)
        if k:
            count = np.where(length > max_length, 2, 1)
        else:
            count = np.where(_bent_edges(X, F, E), np.maximum(np.ceil(length / max_length), 1), 1)
        F_next, Q = split_edges(F, len(X), count)
        if Q.shape[0] == len(X) and k:
            break
        F, P = F_next, (Q @ P).tocsr()
        X = P @ V
        F = intrinsic_delaunay(X, F, flat=FLAT)[0]
    return F, P


def _bent_edges(X, F, E):
    """Whether each edge of the sorted undirected edges E of F (:func:`edges`) is on the
    boundary or between two faces that are not in one plane (turning by more than
    ``FLAT``, :func:`qcremesh.geometry.creases.dihedral_angles`)."""
    inner, turn = dihedral_angles(X, F)
    flat = inner[turn <= np.degrees(FLAT)]
    return ~np.isin(_edge_keys(E, len(X)), _edge_keys(flat, len(X)))
