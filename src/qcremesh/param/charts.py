"""Charts: a surface split along its edges into pieces that are each a topological disk.

A surface of higher genus cut open into one disk (:func:`qcremesh.mesh.cut.cut_to_disk`)
gives a disk whose boundary runs around every handle twice; its conformal map crowds
much of that boundary into arcs too short to resolve. Split into charts instead, each
with a boundary of its own, every chart's map is near its shape.

The charts are geodesic Voronoi cells on the edge graph: seeds spread by farthest-point
sampling, every vertex labelled with its nearest seed (Dijkstra's algorithm, edges
weighted by their length), every face with the label of two of its corners (or of the
corner nearest its seed). Where a chart is not a disk (it runs around a handle or a
hole, or touches itself at a vertex), a seed is added at its vertex farthest from its
seed and the cells are drawn again (where the seeds added stop making more charts, a
chart that touches itself at a vertex is taken for a disk, as it is once cut out along
the borders); once all are disks, the seeds move to the vertex of their chart farthest
from its border (a few rounds of Lloyd's iteration, which evens the charts out), the
charts are drawn again, still disks. The borders of cells on the edge graph are jagged;
they are evened out by a majority filter (a face takes the label that two of its three
neighbours share; dropped once a seed added makes no new chart, as the filter gave its
few faces back), and then each border between two branch points is replaced by the
shortest edge path between them through the two charts it separates, where both stay
disks. Last, charts of less than ``min_share`` of the mean area are merged into the
neighbour they share the longest border with, where the union is a disk.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components, dijkstra

from ..geometry.operators import doublearea
from ..mesh.cut import edge_paths, path_from_tree
from ..mesh.topology import (
    _edge_keys,
    boundary_loops,
    corner_fans,
    edges,
    euler_characteristic,
    half_edges,
    twin_half_edges,
    unique_integers,
)

__all__ = ["chart_borders", "disk_charts"]

# Rounds of added seeds that make no more charts after which a chart touching itself at a
# vertex counts as a disk: the cells of a marching-cubes gyroid of genus 28 (90,408
# faces) kept touching themselves, 4 of about 380 charts, as seeds came and went, and
# the split gave up after 200 rounds.
STALLED_ROUNDS = 5

# Passes over the borders replacing them by shortest paths (a border that one pass moved
# is judged again in the next as it then runs).
STRAIGHTENING_PASSES = 2


def _edge_graph(V, F):
    """The edge graph weighted by the edges' lengths, (n, n) symmetric CSR."""
    E = edges(F)
    weight = np.linalg.norm(V[E[:, 0]] - V[E[:, 1]], axis=1)
    rows, cols = np.r_[E[:, 0], E[:, 1]], np.r_[E[:, 1], E[:, 0]]
    return sp.csr_matrix((np.r_[weight, weight], (rows, cols)), shape=(len(V),) * 2)


def _is_disk(F):
    """Whether the faces ``F`` form one topological disk (Euler characteristic 1, one
    boundary loop, which a surface pinched at a vertex does not have)."""
    if not len(F):
        return False
    _, local = np.unique(F, return_inverse=True)
    local = local.reshape(-1, 3)
    try:
        return euler_characteristic(local) == 1 and len(boundary_loops(local)) == 1
    except ValueError:
        return False


class _Adjacency:
    """The faces across each interior edge of (V, F): faces ``a``, ``b`` (k,) and the
    edge's key and length; the half-edges ``half`` (3m, 2), the ``twin`` of each (-1 on
    the boundary) and the ``boundary`` vertices."""

    def __init__(self, V, F):
        m, n = len(F), len(V)
        i, j = twin_half_edges(F)
        self.a, self.b = i % m, j % m
        self.half = half_edges(F)
        self.twin = np.full(3 * m, -1, dtype=np.int64)
        self.twin[i], self.twin[j] = j, i
        self.boundary = unique_integers(self.half[self.twin < 0])
        self.key = _edge_keys(self.half[i], n)
        self.length = np.linalg.norm(V[self.key // n] - V[self.key % n], axis=1)
        self.m, self.n = m, n

    def border_half_edges(self, inside):
        """The half-edges of the faces where ``inside`` (m,) bool whose twin is not
        such a face (or on the boundary), (3m,) bool."""
        own = np.tile(inside, 3)
        return own & ((self.twin < 0) | ~inside[np.maximum(self.twin, 0) % self.m])

    def borders(self, labels):
        """Which interior edges separate two charts, (k,) bool."""
        return labels[self.a] != labels[self.b]

    def parts(self, keep, faces=None):
        """Connected parts of ``faces`` ((f,) int, every face where None) across the
        edges where ``keep`` (k,) bool: the part of each of them, (f,) int."""
        faces = np.arange(self.m) if faces is None else faces
        local = np.full(self.m, -1, dtype=np.int64)
        local[faces] = np.arange(len(faces))
        keep = keep & (local[self.a] >= 0) & (local[self.b] >= 0)
        A = sp.csr_matrix((np.ones(keep.sum()), (local[self.a[keep]], local[self.b[keep]])), shape=(len(faces),) * 2)
        return connected_components(A, directed=False)[1]


def _vertex_charts(F, labels):
    """Each pair of a vertex and a chart it is in, as vertex * count + chart, sorted, and
    the pair of each corner (corner k m + f is vertex ``F[f, k]`` of face f), (3m,)."""
    count = int(labels.max()) + 1
    return np.unique(F.T.ravel() * count + np.tile(labels, 3), return_inverse=True)


def _disks(F, labels, adjacency, pinched=False):
    """Which charts are topological disks, (count,) bool: Euler characteristic 1 and one
    boundary loop each, counted for all charts at once over the (vertex, chart) pairs (a
    chart that touches itself at a vertex has one vertex fewer, so its Euler
    characteristic is 0). With ``pinched``, over the fans of each vertex within a chart
    instead: such a chart is a disk once cut out along the borders, as the pieces of the
    remesh are."""
    count = int(labels.max()) + 1
    m = adjacency.m
    faces = np.bincount(labels, minlength=count)
    own = np.tile(labels, 3)
    twin = adjacency.twin
    inside = (twin >= 0) & (labels[np.maximum(twin, 0) % m] == own)
    border = np.flatnonzero(~inside)
    # the nodes: a vertex of each chart, or with ``pinched`` each fan of its faces there
    # (half-edge h = k m + f runs from corner h to corner ((k + 1) mod 3) m + f)
    ends = np.column_stack([border, (border // m + 1) % 3 * m + border % m])
    if pinched:
        linked = np.flatnonzero(inside & (np.arange(3 * m) < twin))
        nodes, node = corner_fans(F, (linked, twin[linked]))
    else:
        pairs, node = _vertex_charts(F, labels)
        nodes = len(pairs)
    node_chart = np.zeros(nodes, dtype=np.int64)
    node_chart[node] = own
    vertices = np.bincount(node_chart, minlength=count)
    border_count = np.bincount(own[border], minlength=count)
    chi = vertices - (3 * faces + border_count) // 2 + faces
    # the border's loops: components of its half-edges over the nodes they join
    ends = node[ends]
    G = sp.csr_matrix((np.ones(len(ends)), (ends[:, 0], ends[:, 1])), shape=(nodes, nodes))
    _, component = connected_components(G, directed=False)
    on_border = unique_integers(ends.ravel())
    first = np.unique(component[on_border], return_index=True)[1]
    loops = np.bincount(node_chart[on_border[first]], minlength=count)
    return (chi == 1) & (loops == 1) & (faces > 0)


def _face_labels(F, label, distance):
    """Each face's chart from its corners' ``label`` (n,): the label two or three of them
    share, else that of the corner nearest to its seed (``distance``, (n,))."""
    L = label[F]
    shared = np.where(L[:, 1] == L[:, 2], L[:, 1], L[:, 0])
    any_two = (L[:, 0] == L[:, 1]) | (L[:, 0] == L[:, 2]) | (L[:, 1] == L[:, 2])
    nearest = L[np.arange(len(F)), np.argmin(distance[F], axis=1)]
    return np.where(any_two, shared, nearest)


def _majority_filter(labels, adjacency, sweeps):
    """``labels`` with every face that has two neighbours of one other label given it,
    repeated up to ``sweeps`` times (until nothing changes)."""
    # each face's neighbours across its interior edges, -1 where fewer than three
    x, y = np.r_[adjacency.a, adjacency.b], np.r_[adjacency.b, adjacency.a]
    order = np.argsort(x, kind="stable")
    x, y = x[order], y[order]
    around = np.full((adjacency.m, 3), -1, dtype=np.int64)
    around[x, np.arange(len(x)) - np.searchsorted(x, x)] = y
    for _ in range(sweeps):
        L = np.where(around >= 0, labels[np.maximum(around, 0)], -1)
        pair01 = (L[:, 0] == L[:, 1]) & (L[:, 0] >= 0)
        pair02 = (L[:, 0] == L[:, 2]) & (L[:, 0] >= 0)
        pair12 = (L[:, 1] == L[:, 2]) & (L[:, 1] >= 0)
        new = np.where(pair01 | pair02, L[:, 0], np.where(pair12, L[:, 1], labels))
        if np.array_equal(new, labels):
            break
        labels = new
    return labels


def _largest_parts(labels, adjacency):
    """``labels`` with each chart kept to its largest edge-connected part, the faces of
    its other parts given the label of a neighbour (repeated until every chart is one
    part)."""
    labels = labels.copy()
    while True:
        part = adjacency.parts(~adjacency.borders(labels))
        size = np.bincount(part)
        order = np.lexsort((-size[part], labels))
        first = np.r_[True, labels[order][1:] != labels[order][:-1]]
        kept = np.zeros(len(size), dtype=bool)
        kept[part[order][first]] = True
        stray = ~kept[part]
        if not stray.any():
            return labels
        for x, y in ((adjacency.a, adjacency.b), (adjacency.b, adjacency.a)):
            take = stray[x] & ~stray[y]
            labels[x[take]] = labels[y[take]]


def _renumbered(labels):
    """Labels renumbered 0, 1, ... in order, and the old label of each."""
    present, labels = np.unique(labels, return_inverse=True)
    return labels.astype(np.int64), present


def _centres(G, F, labels, adjacency, count):
    """Each chart's interior vertex farthest from its border (between charts, or on the
    surface's boundary) along the edges, (count,) int (-1 for a chart without an
    interior vertex)."""
    keys = adjacency.key[adjacency.borders(labels)]
    border = unique_integers(np.r_[keys // adjacency.n, keys % adjacency.n, adjacency.boundary])
    distance = dijkstra(G, indices=border, min_only=True)
    chart = np.full(adjacency.n, -1, dtype=np.int64)
    chart[F.ravel()] = np.repeat(labels, 3)
    inner = np.ones(adjacency.n, dtype=bool)
    inner[border] = False
    v = np.flatnonzero(inner & (chart >= 0))
    v = v[np.lexsort((-distance[v], chart[v]))]
    first = np.r_[True, chart[v][1:] != chart[v][:-1]]
    centre = np.full(count, -1, dtype=np.int64)
    centre[chart[v][first]] = v[first]
    return centre


def _branch_points(F, labels, adjacency):
    """Where three or more charts meet, or a border meets the surface's boundary, (b,)
    int."""
    charts_at = np.bincount(_vertex_charts(F, labels)[0] // (int(labels.max()) + 1), minlength=adjacency.n)
    return unique_integers(np.r_[np.flatnonzero(charts_at >= 3), adjacency.boundary])


def _straightened(V, F, labels, G, adjacency):
    """``labels`` with each border between two charts that runs between two branch
    points (or the surface's boundary) replaced by the shortest edge path between its
    ends through the two charts, where that is shorter and leaves both disks."""
    n = adjacency.n
    cut = adjacency.borders(labels)
    keys = adjacency.key[cut]
    stops = _branch_points(F, labels, adjacency)
    order = np.argsort(adjacency.key)
    for path in edge_paths(np.column_stack([keys // n, keys % n]), n, stops):
        # (the paths of the borders as they were: one that moved is judged as it is now)
        if path[0] == path[-1] or len(path) < 3:
            continue
        first = _edge_keys(path[None, :2], n)[0]
        at = order[np.searchsorted(adjacency.key[order], first)]
        A, B = labels[adjacency.a[at]], labels[adjacency.b[at]]
        if A == B:
            continue
        in_union = (labels == A) | (labels == B)
        union = np.flatnonzero(in_union)
        allowed = np.zeros(n, dtype=bool)
        allowed[F[union].ravel()] = True
        allowed[adjacency.half[adjacency.border_half_edges(in_union)].ravel()] = False
        allowed[path[[0, -1]]] = True
        inside = np.flatnonzero(allowed)
        local = np.full(n, -1, dtype=np.int64)
        local[inside] = np.arange(len(inside))
        distance, previous = dijkstra(G[inside][:, inside], indices=local[path[0]], return_predecessors=True)
        end = local[path[-1]]
        length = np.linalg.norm(V[path[1:]] - V[path[:-1]], axis=1).sum()
        if not distance[end] < length * (1 - 1e-3):
            continue
        walk = inside[path_from_tree(previous, end)]
        crossing = np.isin(adjacency.key, _edge_keys(np.column_stack([walk[:-1], walk[1:]]), n))
        part = adjacency.parts(~crossing, union)
        if part.max() != 1:
            continue
        # the side with more of A's faces is A
        side_a = int(np.mean(labels[union][part == 1] == A) > np.mean(labels[union][part == 0] == A))
        new = labels.copy()
        new[union] = np.where(part == side_a, A, B)
        if _is_disk(F[new == A]) and _is_disk(F[new == B]):
            labels = new
    return labels


def _merged_small(V, F, labels, adjacency, min_share):
    """``labels`` with each chart of less than ``min_share`` of the mean area merged
    into the neighbour with which it shares the longest border, where the union is a
    disk (the smallest first, until none can be)."""
    area = doublearea(V, F)
    while True:
        count = labels.max() + 1
        chart_area = np.bincount(labels, area, count)
        merged = False
        for small in np.argsort(chart_area, kind="stable"):
            if chart_area[small] >= min_share * chart_area.mean():
                break
            cut = adjacency.borders(labels)
            touching = cut & ((labels[adjacency.a] == small) | (labels[adjacency.b] == small))
            other = np.where(labels[adjacency.a[touching]] == small, labels[adjacency.b[touching]],
                             labels[adjacency.a[touching]])
            shared = np.bincount(other, adjacency.length[touching], count)
            for neighbour in np.argsort(-shared, kind="stable"):
                if shared[neighbour] <= 0:
                    break
                new = np.where(labels == small, neighbour, labels)
                if _is_disk(F[new == neighbour]):
                    labels, merged = _renumbered(new)[0], True
                    break
            if merged:
                break
        if not merged:
            return labels


def disk_charts(V, F, count=2, *, lloyd=5, sweeps=20, min_share=0.3, max_rounds=200):
    """Split a connected manifold surface into charts along its edges, each chart a
    topological disk (see the module's notes).

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
        One connected, edge- and vertex-manifold surface.
    count : int
        Seeds to start from; more are added where a chart is not a disk.
    lloyd : int
        Rounds in which the seeds move to their charts' centres.
    sweeps : int
        Most sweeps of the majority filter on the charts' borders.
    min_share : float
        Charts of less area than this share of the mean are merged into a neighbour.
    max_rounds : int
        Most rounds of drawing the cells.

    Returns
    -------
    (m,) int64
        Each face's chart, 0, 1, ...

    Raises
    ------
    ValueError
        Where no such split is found in ``max_rounds`` rounds.
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    G = _edge_graph(V, F)
    adjacency = _Adjacency(V, F)
    seeds = [int(np.argmax(dijkstra(G, indices=int(F[0, 0]))))]
    distance = dijkstra(G, indices=seeds[0])
    while len(seeds) < count:
        seeds.append(int(np.argmax(distance)))
        distance = np.minimum(distance, dijkstra(G, indices=seeds[-1]))
    moved = 0
    previous, added = None, False
    counts, stalled, pinched = [], 0, False
    for _ in range(max_rounds):
        distance, _, source = dijkstra(G, indices=seeds, min_only=True, return_predecessors=True)
        chart_of_seed = np.full(adjacency.n, -1, dtype=np.int64)
        chart_of_seed[seeds] = np.arange(len(seeds))
        # (a vertex of no face is reached from no seed)
        labels = _face_labels(F, chart_of_seed[np.maximum(source, 0)], distance)
        labels = _largest_parts(_majority_filter(labels, adjacency, sweeps), adjacency)
        labels, present = _renumbered(labels)
        if added and np.array_equal(labels, previous):
            # The seeds added made no new chart: the filter gave their few faces back (a
            # tube one fan of slivers around, featuretype.STL's); no filter from here on.
            sweeps = 0
        previous, added = labels, False
        seeds = [seeds[c] for c in present]
        not_disks = np.flatnonzero(~_disks(F, labels, adjacency, pinched))
        # Rounds whose seeds added made no more charts than a round of the last few had
        # (they come and go): from STALLED_ROUNDS of them on, a chart that touches itself
        # at a vertex is taken for a disk (it is one once cut out along the borders).
        stalled = stalled + 1 if len(not_disks) and counts and len(present) <= max(counts) else 0
        counts = (counts + [len(present)])[-STALLED_ROUNDS:]
        if stalled >= STALLED_ROUNDS and not pinched:
            pinched = True
            not_disks = np.flatnonzero(~_disks(F, labels, adjacency, pinched))
        if len(not_disks):
            for c in not_disks:
                vertices = unique_integers(F[labels == c])
                seeds.append(int(vertices[np.argmax(distance[vertices])]))
            added = True
            continue
        if moved < lloyd:
            centre = _centres(G, F, labels, adjacency, len(seeds))
            seeds = [int(c) if c >= 0 else s for c, s in zip(centre, seeds)]
            moved += 1
            continue
        labels = _merged_small(V, F, labels, adjacency, min_share)
        for _ in range(STRAIGHTENING_PASSES):
            labels = _straightened(V, F, labels, G, adjacency)
        return _merged_small(V, F, labels, adjacency, min_share)
    raise ValueError(f"no split of the surface into disks found in {max_rounds} rounds")


def chart_borders(F, labels):
    """The interior edges between two charts, (k, 2) int64 (either way round)."""
    F = np.asarray(F, dtype=np.int64)
    i, j = twin_half_edges(F)
    m = len(F)
    across = labels[i % m] != labels[j % m]
    return half_edges(F)[i[across]]
