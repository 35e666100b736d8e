"""Repair of needles and caps, faces of zero area or within rounding of it
(:func:`qcremesh.mesh.topology.needles_and_caps`).

Such a face has no shape for a conformal map to keep: its cotangent weights are infinite
or huge, and the Beltrami coefficient of the map onto it rounds to |mu| = 1, which the
disk map cannot take (a pymeshlab quadric decimation of human_brain.ply left 42 faces of
zero area, which the validation refuses, and faces of relative area 1e-10, which it
passes and the map failed on). There are two kinds. A *needle* has two corners at (almost)
the same point: the two are merged into one vertex, and the faces that become degenerate
go. A *cap* has a corner on (or almost on) its opposite edge: that edge is flipped with
the face beyond it, which splits the neighbour at the corner, or, on the boundary, the
face goes and the boundary runs through the corner. The surface moves by at most 1e-3 of
an edge.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..mesh.topology import (
    boundary_edges,
    face_edge_lengths,
    half_edges,
    needles_and_caps,
    repeated_corner_faces,
    twin_half_edges,
)
from .triangulation import flip_edges

__all__ = ["repair_degenerate_faces"]


def _merge_needles(V, F, needles):
    """Merge the two corners of the shortest edge of each needle (the smallest index
    stays), and drop the faces left with a repeated corner."""
    L = face_edge_lengths(V, F[needles])
    k = L.argmin(1)
    u, v = F[needles, k], F[needles, (k + 1) % 3]
    n = len(V)
    graph = coo_matrix((np.ones(len(u)), (u, v)), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    smallest = np.full(label.max() + 1, n)
    np.minimum.at(smallest, label, np.arange(n))
    F = smallest[label][F]
    return F[~repeated_corner_faces(F)]


def _flip_caps(V, F, caps):
    """Flip the longest edge of every interior cap with the face beyond it; delete the
    caps whose longest edge is on the boundary (their corner must not be on it)."""
    m = len(F)
    is_cap = np.zeros(m, dtype=bool)
    is_cap[caps] = True
    longest = face_edge_lengths(V, F).argmax(1)

    def gain(F, f1, f2, a, b, c, d):
        k1 = np.argmax(F[f1] == a[:, None], axis=1)  # edge (a, b) is edge k1 of f1
        k2 = np.argmax(F[f2] == b[:, None], axis=1)  # and (b, a) edge k2 of f2
        cap_on_edge = (is_cap[f1] & (longest[f1] == k1)) | (is_cap[f2] & (longest[f2] == k2))
        needle, cap = needles_and_caps(V, np.concatenate([np.column_stack([a, d, c]), np.column_stack([d, b, c])]))
        flat = needle | cap
        ok = cap_on_edge & ~flat[: len(a)] & ~flat[len(a) :]
        return np.where(ok, 1.0, -1.0)

    F, _ = flip_edges(F, gain, 1)
    # Caps left whose longest edge has no face beyond it.
    H = half_edges(F)
    i, j = twin_half_edges(F)
    paired = np.zeros(len(H), dtype=bool)
    paired[i] = paired[j] = True
    caps = np.flatnonzero(needles_and_caps(V, F)[1])
    longest = face_edge_lengths(V, F[caps]).argmax(1)
    on_boundary = ~paired[longest * len(F) + caps]
    corner = F[caps, (longest + 2) % 3]
    boundary_vertex = np.zeros(len(V), dtype=bool)
    boundary_vertex[boundary_edges(F).ravel()] = True
    drop = caps[on_boundary & ~boundary_vertex[corner]]
    return np.delete(F, drop, axis=0)


def repair_degenerate_faces(V, F, rounds=10):
    """Remove the needles and caps of a mesh (zero-area faces and faces within rounding of
    it) without moving its surface by more than 1e-3 of an edge: merge the corners of
    needles, flip (or, on the boundary, delete) caps.

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
        A consistently oriented manifold mesh.
    rounds : int
        Maximum number of rounds of merging and flipping.

    Returns
    -------
    V : (k, 3) float
        The vertices still used, in their order.
    F : (l, 3) int64
        The faces over them; some needles or caps may stay where no merge or flip applies
        (the mesh's checks then name those of zero area).
    kept : (k,) int64
        Index in the input of each vertex returned (to carry per-vertex data along).
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.array(F, dtype=np.int64)
    for _ in range(rounds):
        needle, cap = needles_and_caps(V, F)
        if not (needle.any() or cap.any()):
            break
        before = F.copy()
        if needle.any():
            F = _merge_needles(V, F, np.flatnonzero(needle))
        else:
            F = _flip_caps(V, F, np.flatnonzero(cap))
        if np.array_equal(before, F):
            break
    kept = np.unique(F)
    renumber = np.full(len(V), -1)
    renumber[kept] = np.arange(len(kept))
    return V[kept], renumber[F], kept
