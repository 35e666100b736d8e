"""Cutting a triangle mesh open along a path of its edges."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components, dijkstra

from .topology import _edge_keys, boundary_loops, half_edges, twin_half_edges

__all__ = ["cut_along_path", "cut_to_disk", "shortest_edge_path", "weld_cuts"]


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
    """Cut a mesh open along a simple path of its edges: every vertex of the path that the
    path splits the faces around into two fans (its interior vertices, and an end on the
    boundary) gets a copy, which the faces on one side of the path take, so that the path
    becomes two boundary arcs.

    The faces around the copied vertices fall into two sides, connected through their
    shared edges but for the path's own; the side with the face that has the path's
    first edge counter-clockwise takes the copies. On a closed surface of genus 0, a path
    between two vertices cuts it into a disk (a slit sphere; its two ends, interior
    vertices, stay one vertex each); a path between two boundary loops joins them into
    one.

    Parameters
    ----------
    F : (m, 3) int
    path : (k,) int
        Distinct vertices, consecutive ones joined by an interior edge of ``F``, k >= 2.
    n : int, optional
        Number of vertices (``F.max() + 1`` by default).

    Returns
    -------
    F_cut : (m, 3) int64
        The faces, on the vertices 0..n-1 and the copies n, n+1, ... of the copied
        vertices of ``path``, in its order.
    parent : (n + c,) int64
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
    single = np.ones(len(H), dtype=bool)
    single[i] = single[j] = False
    on_boundary = np.zeros(n, dtype=bool)
    on_boundary[H[single].ravel()] = True
    copied = np.r_[False, np.ones(len(path) - 2, dtype=bool), False] | on_boundary[path]
    cut = np.zeros(n, dtype=bool)
    cut[path[copied]] = True
    touching = cut[F].any(1)
    # The faces around the copied vertices, joined across the edges that are not the path's.
    fi, fj = i % m, j % m
    keep = touching[fi] & touching[fj] & ~on_path[i]
    G = sp.csr_matrix((np.ones(int(keep.sum())), (fi[keep], fj[keep])), shape=(m, m))
    _, label = connected_components(G, directed=False)
    sides = np.unique(label[touching])
    if copied.any() and len(sides) != 2:
        raise ValueError(f"the cut path splits the faces around it into {len(sides)} sides, not 2")
    # The face with the path's first edge counter-clockwise (path[0] -> path[1]).
    first = np.flatnonzero((H[:, 0] == path[0]) & (H[:, 1] == path[1]))
    if len(first) != 1:
        raise ValueError("the cut path leaves the edges of the mesh")
    copy_side = touching & (label == label[first[0] % m])
    copy = np.full(n, -1, dtype=np.int64)
    copy[path[copied]] = n + np.arange(int(copied.sum()))
    F_cut = F.copy()
    sub = F_cut[copy_side]
    F_cut[copy_side] = np.where(cut[sub], copy[sub], sub)
    parent = np.r_[np.arange(n), path[copied]]
    return F_cut, parent


def cut_to_disk(V, F, n=None):
    """Cut a connected manifold surface of genus 0 that is not a disk open into one.

    A closed surface is cut along the shortest edge path between its two vertices
    farthest apart along its principal axis (a slit); a surface with several boundary
    loops along one shortest edge path from each loop but the longest to the longest,
    through interior vertices that no other cut takes (:func:`cut_along_path`, which
    joins the two loops into one). Each cut adds one to the Euler characteristic, so the
    result, with one boundary loop and characteristic 1, is a disk.

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
    n : int, optional
        Number of vertices (``len(V)`` by default).

    Returns
    -------
    F_cut : (m, 3) int64
    parent : (n + c,) int64
        The vertex of ``F`` each vertex of ``F_cut`` is.
    paths : list of (k,) int64
        Each cut, as vertices of ``F`` from its first end (the principal axis's low end, a
        vertex of a shorter loop) to its last (the high end, a vertex of the longest loop).

    Raises
    ------
    ValueError
        Where no path of interior vertices joins a loop to the longest.
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    n = len(V) if n is None else int(n)
    loops = boundary_loops(F)
    if not loops:
        centred = V - V.mean(0)
        axis = np.linalg.svd(centred[:: max(1, n // 20000)], full_matrices=False)[2][0]
        along = centred @ axis
        paths = [shortest_edge_path(V, F, int(np.argmin(along)), int(np.argmax(along)))]
    else:
        paths = _paths_between_loops(V, F, n, loops)
    F_cut, parent = F, np.arange(n)
    for path in paths:
        F_cut, more = cut_along_path(F_cut, path, len(parent))
        parent = parent[more]
    return F_cut, parent, paths


def _paths_between_loops(V, F, n, loops):
    """Shortest edge paths from each loop but the first (the longest) to the first, whose
    interior vertices are interior vertices of the mesh and on no other path."""
    H = half_edges(F)
    weight = np.linalg.norm(V[H[:, 0]] - V[H[:, 1]], axis=1)
    loop_of = np.full(n, -1, dtype=np.int64)
    for k, loop in enumerate(loops):
        loop_of[loop] = k
    used = np.zeros(n, dtype=bool)
    paths = []
    for k in range(1, len(loops)):
        # Edges from loop k and through free interior vertices to a free vertex of loop 0.
        start, stop = loop_of[H[:, 0]], loop_of[H[:, 1]]
        free_from = ((start == -1) | (start == k)) & ~used[H[:, 0]]
        free_to = ((stop == -1) | (stop == 0)) & ~used[H[:, 1]]
        ok = free_from & free_to & ~((start == k) & (stop == k))
        G = sp.csr_matrix((weight[ok], (H[ok, 0], H[ok, 1])), shape=(n, n))
        dist, previous, source = dijkstra(
            G, directed=True, indices=loops[k], return_predecessors=True, min_only=True
        )
        ends = loops[0][~used[loops[0]]]
        if not len(ends) or not np.isfinite(dist[ends]).any():
            raise ValueError(f"no path of free interior vertices joins boundary loop {k} to the longest")
        end = int(ends[np.argmin(dist[ends])])
        path = [end]
        while path[-1] != source[end]:
            path.append(int(previous[path[-1]]))
        path = np.array(path[::-1], dtype=np.int64)
        used[path] = True
        paths.append(path)
    return paths


def weld_cuts(X, F, ends, tol):
    """Close a disk mesh cut open by :func:`cut_to_disk` again: along each cut, the
    boundary vertices on its two sides are merged pairwise, at their midpoint.

    The disk's boundary loop runs along each cut twice, in opposite directions: from a
    vertex at its last end (on the longest loop, or the slit's high end) along one side
    to a vertex at its first end, around what the cut joined (the shorter loop; nothing
    for a slit, whose first end is one vertex), and back along the other side to a vertex
    at its last end. The ends are found as the boundary vertices within ``tol`` of them.

    Parameters
    ----------
    X : (k, 3) float
    F : (l, 3) int
        A disk.
    ends : (c, 2, 3) float
        The first and last end of each cut (the points of ``paths[i][[0, -1]]``).
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
        Where the boundary has not one or two vertices at an end of a cut, or the two
        sides of a cut differ in their number of vertices or lie farther apart.
    """
    X = np.asarray(X, dtype=np.float64)
    loop = boundary_loops(F)[0]
    b = len(loop)
    side, twin = [], []
    for first, last in np.asarray(ends, dtype=np.float64):
        at_first = np.flatnonzero(np.linalg.norm(X[loop] - first, axis=1) <= tol)
        at_last = np.flatnonzero(np.linalg.norm(X[loop] - last, axis=1) <= tol)
        if not 1 <= len(at_first) <= 2 or len(at_first) != len(at_last):
            raise ValueError(
                f"the boundary has {len(at_first)} and {len(at_last)} vertices at the ends of a cut, not 1 or 2 each"
            )
        # One side runs from a vertex at the last end to the next vertex at the first,
        # the other from the vertex at the first end before the next one at the last.
        start = at_last[0]
        if len(at_last) == 2 and (at_last[1] - start) % b < ((at_first - start) % b).min():
            start = at_last[1]
        ahead = np.sort((at_first - start) % b)
        behind = np.sort((at_last - start) % b)[-1] if len(at_last) == 2 else b
        length = ahead[0]
        if behind - ahead[-1] != length:
            raise ValueError(f"the two sides of a cut have {length - 1} and {behind - ahead[-1] - 1} vertices")
        t = np.arange(length + 1)
        side.append(loop[(start + t) % b])
        twin.append(loop[(start + behind - t) % b])
    side, twin = np.concatenate(side), np.concatenate(twin)
    gap = np.linalg.norm(X[side] - X[twin], axis=1).max()
    if gap > tol:
        raise ValueError(f"the two sides of a cut are {gap:.3g} apart, more than {tol:.3g}")
    X = X.copy()
    X[side] = (X[side] + X[twin]) / 2
    target = np.arange(len(X))
    target[twin] = side
    keep = np.ones(len(X), dtype=bool)
    keep[twin[twin != side]] = False
    new = np.cumsum(keep) - 1
    return X[keep], new[target[np.asarray(F)]], np.flatnonzero(keep)
