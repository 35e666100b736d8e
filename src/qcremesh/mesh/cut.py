"""Cutting a triangle mesh open along a path of its edges."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components, dijkstra

from .topology import _edge_keys, half_edges, twin_half_edges

__all__ = ["cut_along_path", "shortest_edge_path", "weld_slit"]


def shortest_edge_path(V, F, source, target):
    """Vertices of the shortest path along the edges of a mesh from ``source`` to
    ``target`` (Dijkstra's algorithm, edges weighted by their length), (k,) int64, both
    ends included.

    Raises
    ------
    ValueError
        Where no path joins them.
    """
    V = np.asarray(V, dtype=np.float64)
    H = half_edges(F)
    weight = np.linalg.norm(V[H[:, 0]] - V[H[:, 1]], axis=1)
    G = sp.csr_matrix((weight, (H[:, 0], H[:, 1])), shape=(len(V), len(V)))
    _, previous = dijkstra(G, directed=False, indices=int(source), return_predecessors=True)
    if previous[target] < 0 and target != source:
        raise ValueError(f"no path along the edges joins vertices {source} and {target}")
    path = [int(target)]
    # (one step per vertex of the path, a few hundred on a mesh of 100k vertices)
    while path[-1] != source:
        path.append(int(previous[path[-1]]))
    return np.array(path[::-1], dtype=np.int64)


def cut_along_path(F, path, n=None):
    """Cut a mesh open along a simple path of its edges: every interior vertex of the path
    gets a copy, which the faces on one side of the path take, so that the path becomes
    two boundary arcs joined at its two ends.

    The faces around the interior vertices fall into two sides, connected through their
    shared edges but for the path's own; the side with the face that has the path's
    first edge counter-clockwise takes the copies. On a closed surface of genus 0, a path
    between two vertices cuts it into a disk (a slit sphere).

    Parameters
    ----------
    F : (m, 3) int
    path : (k,) int
        Distinct vertices, consecutive ones joined by an edge of ``F``, k >= 2; its two
        ends are not copied.
    n : int, optional
        Number of vertices (``F.max() + 1`` by default).

    Returns
    -------
    F_cut : (m, 3) int64
        The faces, on the vertices 0..n-1 and the copies n..n+k-3 of ``path[1:-1]``.
    parent : (n + k - 2,) int64
        The vertex of ``F`` each vertex of ``F_cut`` is (itself or the one it copies).

    Raises
    ------
    ValueError
        Where the path repeats a vertex, leaves the edges of ``F``, runs along the
        boundary, or does not split the faces around it into two sides.
    """
    F = np.asarray(F, dtype=np.int64)
    path = np.asarray(path, dtype=np.int64)
    n = int(F.max()) + 1 if n is None else int(n)
    if len(path) < 2 or len(np.unique(path)) != len(path):
        raise ValueError("the cut path must have at least 2 distinct vertices and repeat none")
    m = len(F)
    H = half_edges(F)
    keys = _edge_keys(H, n)
    path_keys = _edge_keys(np.column_stack([path[:-1], path[1:]]), n)
    on_path = np.isin(keys, path_keys)
    if len(np.unique(keys[on_path])) != len(path_keys):
        raise ValueError("the cut path leaves the edges of the mesh")
    i, j = twin_half_edges(F)
    if np.isin(path_keys, keys[i], invert=True).any():
        raise ValueError("the cut path runs along the boundary")
    inner = np.zeros(n, dtype=bool)
    inner[path[1:-1]] = True
    touching = inner[F].any(1)
    # The faces around the interior vertices, joined across the edges that are not the path's.
    fi, fj = i % m, j % m
    keep = touching[fi] & touching[fj] & ~on_path[i]
    G = sp.csr_matrix((np.ones(int(keep.sum())), (fi[keep], fj[keep])), shape=(m, m))
    _, label = connected_components(G, directed=False)
    sides = np.unique(label[touching])
    if len(path) > 2 and len(sides) != 2:
        raise ValueError(f"the cut path splits the faces around it into {len(sides)} sides, not 2")
    # The face with the path's first edge counter-clockwise (path[0] -> path[1]).
    first = np.flatnonzero((H[:, 0] == path[0]) & (H[:, 1] == path[1]))
    if len(first) != 1:
        raise ValueError("the cut path leaves the edges of the mesh")
    copy_side = touching & (label == label[first[0] % m])
    copy = np.full(n, -1, dtype=np.int64)
    copy[path[1:-1]] = n + np.arange(len(path) - 2)
    F_cut = F.copy()
    sub = F_cut[copy_side]
    F_cut[copy_side] = np.where(inner[sub], copy[sub], sub)
    parent = np.r_[np.arange(n), path[1:-1]]
    return F_cut, parent


def weld_slit(X, F, loop, ends, tol):
    """Close a disk mesh whose boundary runs along both sides of a slit: the boundary
    vertices between ``ends`` one way round the loop are merged with those the other way
    round, pairwise (the first after one end with the last before it), which must be
    within ``tol`` of each other.

    Parameters
    ----------
    X : (k, 3) float
    F : (l, 3) int
    loop : (b,) int
        The boundary loop of ``F``.
    ends : (2,) int
        Positions in ``loop`` of the slit's two ends.
    tol : float

    Returns
    -------
    X : (k', 3) float
        The vertices kept, a merged pair at its midpoint.
    F : (l, 3) int64
    kept : (k',) int64
        The index in ``X`` of each vertex kept.

    Raises
    ------
    ValueError
        Where the two sides differ in their number of vertices or lie farther apart.
    """
    X = np.asarray(X, dtype=np.float64)
    loop = np.roll(np.asarray(loop, dtype=np.int64), -int(ends[0]))
    other = (int(ends[1]) - int(ends[0])) % len(loop)
    side, twin = loop[1:other], loop[other + 1 :][::-1]
    if len(side) != len(twin):
        raise ValueError(f"the two sides of the slit have {len(side)} and {len(twin)} vertices")
    gap = np.linalg.norm(X[side] - X[twin], axis=1).max() if len(side) else 0.0
    if gap > tol:
        raise ValueError(f"the two sides of the slit are {gap:.3g} apart, more than {tol:.3g}")
    X = X.copy()
    X[side] = (X[side] + X[twin]) / 2
    target = np.arange(len(X))
    target[twin] = side
    keep = np.ones(len(X), dtype=bool)
    keep[twin] = False
    new = np.cumsum(keep) - 1
    return X[keep], new[target[np.asarray(F)]], np.flatnonzero(keep)
