"""Cutting a triangle mesh open into a disk along its edges, and welding it shut again."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components, depth_first_order, dijkstra, minimum_spanning_tree
from scipy.spatial import cKDTree

from .topology import (
    _edge_keys,
    _keys_to_edges,
    boundary_edges,
    boundary_loops,
    corner_fans,
    euler_characteristic,
    genus,
    half_edges,
    nonmanifold_edges,
    repeated_corner_faces,
    twin_half_edges,
    unique_integers,
)

__all__ = [
    "TWIN_LABEL_TOLERANCE",
    "boundary_is_seams",
    "cut_along_edges",
    "chord_across",
    "coincident_boundary_pairs",
    "coincident_pairs",
    "cut_to_disk",
    "edge_paths",
    "path_edges",
    "path_from_tree",
    "paths_across",
    "paths_to_boundary",
    "points_on_segments",
    "shortest_edge_path",
    "weld_along_paths",
    "weld_cut",
    "weld_seams",
]

# Two vertices at the same point are twins for weld_cut where their labels differ by less
# than this: twins lie at the same point up to about 1e-9 of an edge (the weld's tolerance
# is 1e-7), so their labels differ by about as much; two unrelated labels (two numbers
# uniform in [0, 1) each) come this close with a chance of about 4e-10.
TWIN_LABEL_TOLERANCE = 1e-5


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
    return path_from_tree(previous, target)


def paths_across(V, F, ends):
    """Shortest edge paths between pairs of boundary vertices through interior vertices,
    each through vertices of no earlier path (Dijkstra's algorithm, edges weighted by
    their length): on a disk, each such path cuts a piece off.

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
    ends : (p, 2) int
        Pairs of distinct boundary vertices.

    Returns
    -------
    list of (k,) int64 or None
        Each path's vertices from ``ends[i, 0]`` to ``ends[i, 1]``, or None where no path
        joins them (they are neighbours along the boundary, or the earlier paths block
        the way).
    """
    V = np.asarray(V, dtype=np.float64)
    n = len(V)
    H = half_edges(F)
    weight = np.linalg.norm(V[H[:, 0]] - V[H[:, 1]], axis=1)
    blocked = np.zeros(n, dtype=bool)
    blocked[boundary_edges(F).ravel()] = True
    paths = []
    for source, target in np.asarray(ends, dtype=np.int64).reshape(-1, 2):
        free = ~blocked
        free[[source, target]] = True
        # no edge along the boundary (between the two ends, or from one to the other)
        ok = free[H[:, 0]] & free[H[:, 1]] & ~(blocked[H[:, 0]] & blocked[H[:, 1]])
        G = sp.csr_matrix((weight[ok], (H[ok, 0], H[ok, 1])), shape=(n, n))
        _, previous = dijkstra(G, directed=True, indices=int(source), return_predecessors=True)
        if previous[target] < 0:
            paths.append(None)
            continue
        path = path_from_tree(previous, target)
        blocked[path] = True
        paths.append(path)
    return paths


def chord_across(F, loop, source, target):
    """The interior edge of a disk whose two ends lie on the boundary run from ``source``
    to ``target`` (both on the boundary ``loop``, the run in its order) and that cuts off
    the most of that run: (2,) int64, its ends in the loop's order, or None where the run
    has no such chord.

    Where a strip one triangle wide runs across a disk's boundary (a scan's border),
    no path through interior vertices (:func:`paths_across`) crosses it, but each of its
    rungs, an edge between its two sides, cuts the disk in two.

    Parameters
    ----------
    F : (m, 3) int
        A disk.
    loop : (b,) int
        Its boundary loop.
    source, target : int
        Vertices of ``loop``.
    """
    loop = np.asarray(loop, dtype=np.int64)
    b = len(loop)
    at = np.full(int(np.max(F)) + 1, -1)
    at[loop] = np.arange(b)
    run = (at[target] - at[source]) % b
    H = half_edges(F)
    i, _ = twin_half_edges(F)
    E = H[i]
    # where along the run each end lies, -1 off it
    along = np.where(at[E] >= 0, (at[E] - at[source]) % b, -1)
    along[along > run] = -1
    first, last = along.min(1), along.max(1)
    cut_off = np.where(first >= 0, last - first, 0)
    if cut_off.max(initial=0) < 2:
        return None
    best = np.argmax(cut_off)
    return E[best][np.argsort(along[best])]


def path_edges(paths):
    """The edges of vertex paths, each consecutive pair, (k, 2) int64 (the inverse of
    :func:`edge_paths`); (0, 2) for no path."""
    if not len(paths):
        return np.zeros((0, 2), dtype=np.int64)
    return np.concatenate([np.column_stack([p[:-1], p[1:]]) for p in paths]).astype(np.int64, copy=False)


def edge_paths(E, n, stops=None):
    """A set of edges split into the paths that run between its ends and branch points.

    Each path runs from a vertex of the set's degree other than 2, or one of ``stops``,
    through vertices of degree 2 to the next such; a closed loop without one is a path
    from its least vertex round to it again (first and last the same).

    Parameters
    ----------
    E : (k, 2) int
        Edges, either way round, each any number of times.
    n : int
        Number of vertices.
    stops : (s,) int or (n,) bool, optional
        Vertices where paths end even at degree 2 (the boundary).

    Returns
    -------
    list of (p_i,) int64
        Each path's vertices, the paths ordered by their first vertex.
    """
    keys = unique_integers(_edge_keys(np.asarray(E, dtype=np.int64).reshape(-1, 2), n))
    E = _keys_to_edges(keys, n)
    if not len(E):
        return []
    degree = np.bincount(E.ravel(), minlength=n)
    stop = degree != 2
    if stops is not None:
        stop[np.asarray(stops)] = True
    # Every edge's end at a stop gets a node of its own, so the paths come apart there;
    # the nodes are then renumbered 0.. over those used.
    ends = E.ravel().copy()
    at_stop = stop[ends]
    ends[at_stop] = n + np.flatnonzero(at_stop)
    nodes, local = np.unique(ends, return_inverse=True)
    local = local.reshape(-1, 2)
    vertex = np.where(nodes < n, nodes, E.ravel()[np.maximum(nodes - n, 0)])
    G = sp.csr_matrix((np.ones(len(local)), (local[:, 0], local[:, 1])), shape=(len(nodes),) * 2)
    count, label = connected_components(G, directed=False)
    # a path starts at one of its end nodes, a loop at its least vertex
    is_end = nodes >= n
    start = np.full(count, -1, dtype=np.int64)
    order = np.lexsort((vertex, ~is_end, label))
    first = np.r_[True, label[order][1:] != label[order][:-1]]
    start[label[order][first]] = order[first]
    paths = []
    for root in start[np.argsort(vertex[start], kind="stable")]:
        walk = vertex[depth_first_order(G, int(root), directed=False, return_predecessors=False)]
        paths.append(walk if is_end[root] else np.r_[walk, walk[0]])
    return paths


def paths_to_boundary(V, F, E):
    """Shortest edge paths that join each connected part of a set of interior edges that
    has no boundary vertex to the boundary or to a part already joined (Dijkstra's
    algorithm from all the part's vertices, edges weighted by their length; the parts
    in order of their least vertex). Cut along the edges and these paths, a disk falls
    into pieces that are disks each (the cut and the boundary then form one connected
    graph).

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
        A disk.
    E : (k, 2) int
        Edges of ``F``.

    Returns
    -------
    list of (p_i,) int64
        Each path's vertices, from the part to where it joins.
    """
    V = np.asarray(V, dtype=np.float64)
    n = len(V)
    E = np.asarray(E, dtype=np.int64).reshape(-1, 2)
    target = np.zeros(n, dtype=bool)
    target[boundary_edges(F).ravel()] = True
    if not len(E):
        return []
    G = sp.csr_matrix((np.ones(len(E)), (E[:, 0], E[:, 1])), shape=(n, n))
    _, part = connected_components(G, directed=False)
    used = np.unique(E)
    touches = np.zeros(n, dtype=bool)
    touches[part[used[target[used]]]] = True
    target[used[touches[part[used]]]] = True
    H = half_edges(F)
    M = sp.csr_matrix((np.linalg.norm(V[H[:, 0]] - V[H[:, 1]], axis=1), (H[:, 0], H[:, 1])), shape=(n, n))
    paths = []
    for k in np.unique(part[used][~touches[part[used]]]):
        members = used[part[used] == k]
        dist, previous, _ = dijkstra(M, directed=False, indices=members, return_predecessors=True, min_only=True)
        reached = np.flatnonzero(target & np.isfinite(dist))
        if not len(reached):
            raise ValueError("no path along the edges joins a part of the edges to the boundary")
        paths.append(path_from_tree(previous, reached[np.argmin(dist[reached])]))
        target[members] = True
        target[paths[-1]] = True
    return paths


def path_from_tree(previous, end):
    """The path from the root of a shortest-path tree to one of its vertices.

    One step per vertex of the path (a few hundred on a mesh of 100k vertices).

    Parameters
    ----------
    previous : (n,) int
        The predecessor of each vertex in the tree, negative at a root (the predecessors
        of :func:`scipy.sparse.csgraph.dijkstra`).
    end : int

    Returns
    -------
    path : (k,) int64
        The vertices from the root to ``end``, both included.
    """
    path = [int(end)]
    while previous[path[-1]] >= 0:
        path.append(int(previous[path[-1]]))
    return np.array(path[::-1], dtype=np.int64)


def cut_along_edges(F, cut, n=None):
    """Cut a mesh open along a set of its interior edges (libigl's ``cut_mesh``).

    Around every vertex, its faces fall into fans separated by the cut edges (and the
    boundary) (:func:`qcremesh.mesh.topology.corner_fans`); the fan with the vertex's
    first corner keeps the vertex, every other fan gets a copy of it. A path between two
    interior vertices becomes a slit (its ends stay one vertex each), a path from the
    boundary to the boundary two boundary arcs, a closed loop two loops.

    Parameters
    ----------
    F : (m, 3) int
    cut : (k, 2) int
        Interior edges of ``F``, either way round.
    n : int, optional
        Number of vertices (``F.max() + 1`` by default).

    Returns
    -------
    F_cut : (m, 3) int64
        The faces, on the vertices 0..n-1 and the copies n, n+1, ...
    parent : (n + c,) int64
        The vertex of ``F`` each vertex of ``F_cut`` is (itself or the one it copies).

    Raises
    ------
    ValueError
        Where a cut edge is not an edge of ``F`` or lies on its boundary.
    """
    F = np.asarray(F, dtype=np.int64)
    n = int(F.max()) + 1 if n is None else int(n)
    m = len(F)
    keys = _edge_keys(half_edges(F), n)
    cut_keys = unique_integers(_edge_keys(np.asarray(cut, dtype=np.int64).reshape(-1, 2), n))
    if np.isin(cut_keys, keys, invert=True).any():
        raise ValueError("the cut leaves the edges of the mesh")
    i, j = twin_half_edges(F)
    if np.isin(cut_keys, keys[i], invert=True).any():
        raise ValueError("the cut runs along the boundary")
    linked = np.isin(keys[i], cut_keys, invert=True)
    _, fan = corner_fans(F, (i[linked], j[linked]))
    corner_vertex = F.T.ravel()
    # the first corner of each fan (the fans are numbered in order of first corner)
    _, first = np.unique(fan, return_index=True)
    fan_vertex = corner_vertex[first]
    order = np.lexsort((first, fan_vertex))
    by_vertex = fan_vertex[order]
    keeps = np.r_[True, by_vertex[1:] != by_vertex[:-1]]
    number = np.empty(len(first), dtype=np.int64)
    number[order[keeps]] = by_vertex[keeps]
    copies = order[~keeps]
    number[copies] = n + np.arange(len(copies))
    return number[fan].reshape(3, m).T.copy(), np.r_[np.arange(n), fan_vertex[copies]]


def cut_to_disk(V, F, n=None):
    """Cut a connected manifold surface that is not a disk open into one.

    The cut is a set of edges:

    * the handles (genus g > 0): the 2g loops of a tree-cotree decomposition
      (Eppstein; Erickson & Whittlesey's greedy system of loops), on the surface with
      each boundary loop capped by a cone; each is a shortest path tree's two paths from
      a vertex near the centroid to the ends of an edge, the edges left out of the
      tree and of a maximum spanning tree of the dual weighted by the length of their
      loop; the cones' edges are kept out of the loops, the original boundary edges
      dropped from them (a loop through a cap becomes an arc from the boundary to the
      boundary), and dangling paths pruned;
    * then, where the surface has several boundary loops (the holes, and those the
      handles' cut made), one shortest edge path from each to the longest, through
      interior vertices that no other cut takes;
    * a closed surface of genus 0: the shortest edge path between its two vertices
      farthest apart along its principal axis (a slit); where that is one edge (a cube
      of 12 faces), the two edges through the third corner of a face beside it instead,
      as a slit along one edge does not open the surface.

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
    n : int, optional
        Number of vertices (``len(V)`` by default).

    Returns
    -------
    F_cut : (m, 3) int64
        A disk.
    parent : (n + c,) int64
        The vertex of ``F`` each vertex of ``F_cut`` is.
    cut : (k, 2) int64
        The edges cut, as vertices of ``F``.

    Raises
    ------
    ValueError
        Where no path of interior vertices joins a loop to the longest, or the cut does
        not give a disk.
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    n = len(V) if n is None else int(n)
    g = genus(F, n)
    if g is None:
        raise ValueError("not one manifold surface")
    cut = _handle_loops(V, F, n, g) if g > 0 else np.zeros((0, 2), dtype=np.int64)
    F_cut, parent = cut_along_edges(F, cut, n) if len(cut) else (F, np.arange(n))
    loops = boundary_loops(F_cut)
    if not loops:
        centred = V - V.mean(0)
        axis = np.linalg.svd(centred[:: max(1, n // 20000)], full_matrices=False)[2][0]
        along = centred @ axis
        path = shortest_edge_path(V, F, int(np.argmin(along)), int(np.argmax(along)))
        if len(path) == 2:
            beside = F[np.flatnonzero(np.isin(F, path).sum(1) == 2)[0]]
            path = np.array([path[0], beside[~np.isin(beside, path)][0], path[1]])
        paths = [path]
    else:
        paths = _paths_between_loops(V[parent], F_cut, len(parent), loops)
    more = path_edges(paths)
    if len(more):
        F_cut, again = cut_along_edges(F_cut, more, len(parent))
        cut = np.r_[cut, parent[more]]
        parent = parent[again]
    if len(boundary_loops(F_cut)) != 1 or euler_characteristic(F_cut) != 1:
        raise ValueError("the cut does not open the surface into a disk")
    return F_cut, parent, cut


def _handle_loops(V, F, n, g):
    """The edges of a system of 2 ``g`` loops cutting the handles (see :func:`cut_to_disk`)."""
    loops = boundary_loops(F)
    # Each boundary loop capped by a cone on a vertex of its own, n + k.
    cones = [np.column_stack([loop, np.roll(loop, -1), np.full(len(loop), n + k)]) for k, loop in enumerate(loops)]
    C = np.concatenate([F] + [c[:, ::-1] for c in cones]) if cones else F
    total = n + len(loops)
    P = np.r_[V, [V[loop].mean(0) for loop in loops]] if loops else V
    H = half_edges(C)
    keys = _edge_keys(H, total)
    edge_keys = unique_integers(keys)
    E = _keys_to_edges(edge_keys, total)
    length = np.linalg.norm(P[E[:, 0]] - P[E[:, 1]], axis=1)
    on_cone = E[:, 1] >= n
    border = _edge_keys(boundary_edges(F), total) if loops else np.zeros(0, dtype=np.int64)
    on_border = np.isin(edge_keys, border)
    # Shortest path tree from the vertex nearest the centroid; the cones only last (a
    # cone's vertex is then a leaf, which no tree path crosses).
    big = length.sum() + 1.0
    weight = length + big * on_cone + big * on_border
    G = sp.csr_matrix((weight, (E[:, 0], E[:, 1])), shape=(total, total))
    root = int(np.argmin(np.linalg.norm(V - V.mean(0), axis=1)))
    dist, previous = dijkstra(G, directed=False, indices=root, return_predecessors=True)
    child = np.flatnonzero(previous >= 0)
    tree_keys = _edge_keys(np.column_stack([child, previous[child]]), total)
    in_tree = np.isin(edge_keys, tree_keys)
    # Dual: faces joined across the edges out of the tree, a maximum spanning tree of the
    # length of the edges' loops (the cones' and borders' edges first).
    m = len(C)
    i, j = twin_half_edges(C)
    pair_keys = keys[i]
    index = np.searchsorted(edge_keys, pair_keys)
    out = ~in_tree[index]
    loop_length = dist[E[:, 0]] + dist[E[:, 1]] + length
    priority = np.where(on_cone | on_border, 0.0, loop_length.max() + 1.0 - loop_length) + 1.0
    D = sp.csr_matrix((priority[index[out]], (i[out] % m, j[out] % m)), shape=(m, m))
    cotree = minimum_spanning_tree(D).tocoo()
    cotree_keys = _edge_keys(np.column_stack([cotree.row, cotree.col]), m)
    face_pairs = _edge_keys(np.column_stack([i % m, j % m]), m)
    in_cotree = np.zeros(len(E), dtype=bool)
    in_cotree[index[np.isin(face_pairs, cotree_keys)]] = True
    left = np.flatnonzero(~in_tree & ~in_cotree)
    if len(left) != 2 * g:
        raise ValueError(f"the tree-cotree decomposition leaves {len(left)} edges, not {2 * g}")
    # Each loop: the tree paths from the root to the two ends of its edge, and the edge.
    paths = [path_from_tree(previous, end) for e in left for end in E[e]]
    cut = np.concatenate([E[left], path_edges(paths)])
    cut_keys = unique_integers(_edge_keys(cut, total))
    # out of the caps, off the border
    cut_keys = cut_keys[np.isin(cut_keys, border, invert=True)]
    cut = _keys_to_edges(cut_keys, total)
    cut = cut[cut[:, 1] < n]
    return _prune(cut, n, np.unique(np.concatenate(loops)) if loops else np.zeros(0, dtype=np.int64))


def _prune(cut, n, boundary):
    """Edges of ``cut`` left once its dangling paths (ending at an interior vertex of no
    other cut edge) are removed, repeatedly."""
    keep = np.ones(len(cut), dtype=bool)
    on_boundary = np.zeros(n, dtype=bool)
    on_boundary[boundary] = True
    while True:
        degree = np.bincount(cut[keep].ravel(), minlength=n)
        loose = (degree == 1) & ~on_boundary
        drop = keep & loose[cut].any(1)
        if not drop.any():
            return cut[keep]
        keep &= ~drop


def _paths_between_loops(V, F, n, loops):
    """Shortest edge paths joining the loops into a tree, grown from the first (the
    longest) as Prim's minimum spanning tree is: each the shortest path from a loop not
    yet joined to one that is, through interior vertices of the mesh on no other path.

    A band of surface between two holes narrower than their distances to the rest is
    where the shortest path between them runs, so it is cut across; joined each to the
    longest loop instead, the holes left the band as a channel of the cut disk, which its
    conformal map crowds (a plate with two holes of radius 0.3 0.15 apart: 20 faces below
    0.3 at 2,000 faces, Hausdorff distance 2 %).
    """
    H = half_edges(F)
    weight = np.linalg.norm(V[H[:, 0]] - V[H[:, 1]], axis=1)
    loop_of = np.full(n, -1, dtype=np.int64)
    for k, loop in enumerate(loops):
        loop_of[loop] = k
    start, stop = loop_of[H[:, 0]], loop_of[H[:, 1]]
    used = np.zeros(n, dtype=bool)
    joined = np.zeros(len(loops), dtype=bool)
    joined[0] = True
    paths = []
    for _ in range(1, len(loops)):
        # Edges from a loop not joined or a free interior vertex, to a free interior
        # vertex or a free vertex of a joined loop.
        interior_from = (start == -1) & ~used[H[:, 0]]
        from_loop = (start >= 0) & ~joined[start]
        to_ok = ((stop == -1) | joined[stop]) & ~used[H[:, 1]]
        ok = (interior_from | from_loop) & to_ok
        G = sp.csr_matrix((weight[ok], (H[ok, 0], H[ok, 1])), shape=(n, n))
        sources = np.concatenate([loops[k] for k in np.flatnonzero(~joined)])
        dist, previous = dijkstra(G, directed=True, indices=sources, return_predecessors=True, min_only=True)[:2]
        ends = np.concatenate([loops[k] for k in np.flatnonzero(joined)])
        ends = ends[~used[ends]]
        if not len(ends) or not np.isfinite(dist[ends]).any():
            sizes = ", ".join(str(len(loops[k])) for k in np.flatnonzero(~joined))
            raise ValueError(
                f"no path through interior vertices joins the boundary loops of {sizes} edges to the others"
            )
        path = path_from_tree(previous, ends[np.argmin(dist[ends])])
        joined[loop_of[path[0]]] = True
        used[path] = True
        paths.append(path)
    return paths


def coincident_pairs(V, vertices):
    """The pairs of ``vertices`` at the same point (within 1e-9 of the bounding-box
    diagonal), as vertex indices, (p, 2) int."""
    vertices = np.asarray(vertices)
    tol = 1e-9 * np.linalg.norm(np.ptp(V, axis=0))
    return vertices[cKDTree(V[vertices]).query_pairs(tol, output_type="ndarray")]


def coincident_boundary_pairs(V, F):
    """The pairs of boundary vertices of the mesh (V, F) at the same point
    (:func:`coincident_pairs`): cracks, seams written twice, slits, (p, 2) int."""
    return coincident_pairs(V, unique_integers(boundary_edges(F)))


def boundary_is_seams(V, F):
    """Whether the mesh (V, F) has a boundary and every boundary vertex lies at the same
    point as another (:func:`coincident_boundary_pairs`): a closed surface written with
    cracks or seams split (an STL file's faces written one by one and merged only where
    their corners agree), whose boundary is no border of the surface."""
    border = unique_integers(boundary_edges(F))
    return bool(len(border)) and len(np.unique(coincident_pairs(V, border))) == len(border)


def weld_seams(V, F):
    """Merge the boundary vertices of a mesh that lie at the same point as others (within
    1e-9 of its bounding-box diagonal, :func:`coincident_boundary_pairs`) into one: a surface
    written with its seams split, each vertex on a seam once for the faces on each side
    (as files of textured meshes often are, one vertex per texture coordinate), whose
    seams become boundary, is given back whole.

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int

    Returns
    -------
    V : (n', 3) float
        The vertices kept (a group merged into its first vertex, at their mean).
    F : (m', 3) int64
        The faces renumbered (two faces the merge folds onto each other both dropped,
        as :func:`weld_cut` does, and those with two corners merged).
    kept : (n',) int64
        The index in ``V`` of each vertex kept.
    merged : (n,) int64
        The vertex kept that each vertex of ``V`` became (-1 where none).

    Where boundaries meet at points rather than along seams (the tips of slits cut
    into a closed surface, camel_b.obj: one vertex), the merge leaves a vertex where
    sheets touch, or an edge of more than two faces, for the caller to mend or refuse.
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    pairs = coincident_boundary_pairs(V, F)
    if not len(pairs):
        return V, F, np.arange(len(V)), np.arange(len(V))
    X, G, kept, merged = _merge(V, F, pairs)
    collapsed = repeated_corner_faces(G)
    if collapsed.any():
        # two corners of a face merged (the fan of faces at a pole of a sphere written
        # with one vertex per face there): the face has no area left and goes
        X, G, again = _without_unused(X, G[~collapsed])
        new = np.full(len(kept), -1, dtype=np.int64)
        new[again] = np.arange(len(again))
        kept, merged = kept[again], np.where(merged >= 0, new[merged], -1)
    return X, G, kept, merged


def weld_cut(X, F, segments, tol, labels=None):
    """Close a disk mesh made by remeshing a surface cut open by :func:`cut_to_disk`: its
    boundary vertices on the cut (within ``tol`` of one of its edges) that lie within
    ``tol`` of each other (a vertex on one side of the cut and its twin on the other;
    the copies of a branch point of the cut) and, where ``labels`` are given, whose labels
    agree (within TWIN_LABEL_TOLERANCE), are merged, at their mean. The labels tell twins
    from other vertices at the same point: a tube whose two rims meet (a torus split along
    a seam, whose vertices there were written twice) is cut from a point of one rim to
    the same point of the other, and the copies of the one are not those of the other.
    Where both sides
    have an ear at the same place (a boundary vertex with one face, between two vertices
    that merge), the weld folds the two faces onto each other: both are dropped, as
    :func:`weld_along_paths` does.

    Parameters
    ----------
    X : (k, 3) float
    F : (l, 3) int
    segments : (s, 2, 3) float
        The cut's edges.
    tol : float
    labels : (k, c) float, optional
        Values per vertex of the surface (random numbers in [0, 1), say) carried to each
        vertex of the remesh, interpolated along the boundary of the cut disk: about the
        same at the twins on the two sides of the cut, which lie at the same point of the
        same edge, and unrelated at points of different edges.

    Returns
    -------
    X : (k', 3) float
        The vertices kept.
    F : (l, 3) int64
    kept : (k',) int64
        The index in ``X`` of each vertex kept.
    """
    X = np.asarray(X, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    segments = np.asarray(segments, dtype=np.float64).reshape(-1, 2, 3)
    border = unique_integers(boundary_edges(F))
    on_cut = border[points_on_segments(X[border], segments[:, 0], segments[:, 1], tol)]
    pairs = on_cut[cKDTree(X[on_cut]).query_pairs(tol, output_type="ndarray")]
    if labels is not None:
        labels = np.asarray(labels, dtype=np.float64).reshape(len(X), -1)
        pairs = pairs[np.all(np.abs(labels[pairs[:, 0]] - labels[pairs[:, 1]]) < TWIN_LABEL_TOLERANCE, axis=1)]
    return _merge(X, F, pairs)[:3]


def points_on_segments(Q, a, b, tol):
    """Which of points ``Q`` (q, 3) lie within ``tol`` of one of the segments a -> b
    ((s, 3) each), (q,) bool: each point against the segments whose midpoints are within
    half the longest segment (and ``tol``) of it (found from the smaller of the two sets:
    the seam of a large remesh has far fewer segments than the output has vertices)."""
    if not len(a) or not len(Q):
        return np.zeros(len(Q), dtype=bool)
    reach = np.linalg.norm(b - a, axis=1).max() / 2 + tol
    mid = (a + b) / 2
    if len(a) < len(Q):
        near = cKDTree(Q).query_ball_point(mid, reach)
        seg, point = _ball_pairs(near)
    else:
        point, seg = _ball_pairs(cKDTree(mid).query_ball_point(Q, reach))
    d = b[seg] - a[seg]
    t = np.clip(((Q[point] - a[seg]) * d).sum(1) / np.maximum((d * d).sum(1), 1e-300), 0.0, 1.0)
    on = np.zeros(len(Q), dtype=bool)
    on[point[np.linalg.norm(a[seg] + t[:, None] * d - Q[point], axis=1) <= tol]] = True
    return on


def _ball_pairs(near):
    """The (i, j) pairs of a ball query's lists (``near[i]`` holds the j), (p,), (p,)."""
    count = np.array([len(c) for c in near], dtype=np.int64)
    i = np.repeat(np.arange(len(near)), count)
    j = np.concatenate([np.asarray(c, dtype=np.int64) for c in near]) if count.sum() else np.zeros(0, np.int64)
    return i, j


def _merge(X, F, pairs):
    """Merge the vertices of each of ``pairs`` (p, 2) (and so the groups they link), each
    group into its first vertex at their mean, and drop the pairs of faces the merge
    folds onto each other; the vertices kept (those of a face), the faces renumbered,
    the index in ``X`` of each vertex kept and the kept vertex each vertex of ``X``
    became (-1 where none)."""
    linked = unique_integers(pairs)
    local = np.searchsorted(linked, pairs)
    G = sp.csr_matrix((np.ones(len(pairs)), (local[:, 0], local[:, 1])), shape=(len(linked),) * 2)
    groups, group = connected_components(G, directed=False)
    first = np.full(groups, len(X), dtype=np.int64)
    np.minimum.at(first, group, linked)
    total = np.zeros((groups, 3))
    np.add.at(total, group, X[linked])
    X = X.copy()
    X[first] = total / np.bincount(group, minlength=groups)[:, None]
    target = np.arange(len(X))
    target[linked] = first[group]
    F = target[F]
    # Two faces over the same vertices: ears of both sides at the same place (a boundary
    # vertex with one face between two vertices that merge with their twins), folded
    # onto each other; both go, and the vertex between them if it has no other face.
    _, face_group, size = np.unique(np.sort(F, axis=1), axis=0, return_inverse=True, return_counts=True)
    X, F, kept = _without_unused(X, F[size[face_group.ravel()] == 1])
    new = np.full(len(target), -1, dtype=np.int64)
    new[kept] = np.arange(len(kept))
    return X, F, kept, new[target]


def _without_unused(X, F):
    """The vertices of ``X`` that are corners of ``F``, the faces renumbered to them, and
    the index in ``X`` of each kept."""
    keep = np.zeros(len(X), dtype=bool)
    keep[F.ravel()] = True
    new = np.cumsum(keep) - 1
    return X[keep], new[F], np.flatnonzero(keep)


def weld_along_paths(X, F, paths, tol):
    """Join meshes remeshed apart along the paths that cut them apart: on each path, the
    chain of boundary vertices of one piece from one end of the path to the other, all
    on the path (within ``tol``), merged vertex by vertex with that of the other piece,
    at their mean.

    Unlike :func:`weld_cut`, vertices that lie at the same point but not along a path
    (the two sides of a zero-width slit that a path ends on) stay apart. Where two paths
    run between the same two points, a piece between them whose chain along one is a
    single edge has that edge's two vertices on the other path as well: of the chains
    found along a path, the longest are its own (where all have only the two ends, all
    of their copies merge). Where both pieces have an ear at the same place (a boundary
    vertex with one face, between two vertices of a chain), the weld folds the two faces
    onto each other: both are dropped, with their middle vertex. So are flaps of both
    sides over a longer run of a chain (faces with every corner on it, under an edge
    between two of its vertices that both sides have), with the chain's vertices inside
    the run.

    Parameters
    ----------
    X : (k, 3) float
    F : (l, 3) int
        The pieces, one mesh.
    paths : list of (p_i, 3) float
        Each path's points, end to end.
    tol : float

    Returns
    -------
    X : (k', 3) float
    F : (l', 3) int64
        The faces (l' < l where folded ears were dropped).
    kept : (k',) int64
        The index in ``X`` of each vertex kept.

    Raises
    ------
    ValueError
        Where a path does not have exactly two such chains with as many vertices at the
        same points.
    """
    X = np.asarray(X, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    loops = boundary_loops(F)
    pairs = []
    for P in paths:
        P = np.asarray(P, dtype=np.float64)
        chains = []
        for loop in loops:
            on = points_on_segments(X[loop], P[:-1], P[1:], tol)
            ends = [np.linalg.norm(X[loop] - P[i], axis=1) <= tol for i in (0, -1)]
            for i in np.flatnonzero(on & (ends[0] | ends[1])):
                # forward along the loop, on the path, to the other end
                other = ends[1] if ends[0][i] else ends[0]
                j, chain = i, [loop[i]]
                while len(chain) <= len(loop):
                    j = (j + 1) % len(loop)
                    if not on[j]:
                        break
                    chain.append(loop[j])
                    if other[j]:
                        chains.append(np.array(chain))
                        break
        # A piece between this path and another with the same ends has a chain along
        # the other one that has only the ends on this one: the longest chains are this
        # path's (where all are as long, their vertices are the same points: all merge).
        longest = max((len(c) for c in chains), default=0)
        if len(chains) > 2 and longest > 2:
            chains = [c for c in chains if len(c) == longest]
        if len(chains) < 2 or (len(chains) > 2 and longest > 2) or len(chains[0]) != len(chains[1]):
            sizes = " and ".join(str(len(c)) for c in chains) or "no"
            raise ValueError(f"a path has chains of {sizes} boundary vertices along it, not two alike")
        first = chains[0]
        for b in chains[1:]:
            # (the two sides of a path run along it in opposite directions)
            b = b[::-1] if np.abs(X[first] - X[b[::-1]]).max() <= tol else b
            if np.abs(X[first] - X[b]).max() > tol:
                raise ValueError("the two chains of boundary vertices along a path are not at the same points")
            pairs.append(np.column_stack([first, b]))
    Xw, Fw, kept, welded = _merge(X, F, np.concatenate(pairs) if pairs else np.zeros((0, 2), dtype=np.int64))
    over = nonmanifold_edges(Fw)
    if not len(over):
        return Xw, Fw, kept
    # Flaps of both sides over the same run of a chain: faces with every corner on the
    # chain, between the ends of an edge that both sides have across the run (a chord of
    # three or more chain edges, which then has four faces); all of them go, and the
    # chain vertices inside the run with them.
    chain_of = np.full(len(Xw), -1, dtype=np.int64)
    position = np.full(len(Xw), -1, dtype=np.int64)
    for c, pair in enumerate(pairs):
        on = welded[pair[:, 0]] >= 0
        chain_of[welded[pair[on, 0]]], position[welded[pair[on, 0]]] = c, np.flatnonzero(on)
    drop = np.zeros(len(Fw), dtype=bool)
    for u, w in over:
        if chain_of[u] < 0 or chain_of[u] != chain_of[w]:
            continue
        lo, hi = sorted((position[u], position[w]))
        on_run = (chain_of[Fw] == chain_of[u]) & (position[Fw] >= lo) & (position[Fw] <= hi)
        drop |= on_run.all(axis=1)
    Xw, Fw, still = _without_unused(Xw, Fw[~drop])
    return Xw, Fw, kept[still]
