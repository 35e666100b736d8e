"""Where a disk is cut into pieces remeshed each and welded back: across the runs of its
boundary that its conformal map crowds beyond what the landmarks resolve (long
protrusions, strips), along its creases, and the cut of a surface trimmed where its weld
went wrong."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components as graph_components
from scipy.spatial import cKDTree

from ..geometry.operators import doublearea
from ..mesh.cut import chord_across, cut_along_edges, edge_paths, path_edges, paths_across, paths_to_boundary
from ..mesh.topology import boundary_edges, boundary_loops, connected_components, euler_characteristic
from ..mesh.validate import MeshError
from ..param.crowding import crowded_arcs
from ..param.disk import disk_conformal_map
from .disk_remesh import output_edge_length

__all__ = [
    "CROWDED_SHARE",
    "CROWDED_SHARE_FIXED",
    "crease_cuts",
    "crowded_cuts",
    "crowded_ends",
    "pieces_crowded_cuts",
    "split_pieces",
    "trimmed_cut",
]

# Where the disk map gives more than CROWDED_SHARE of the boundary vertices the narrowest
# arc (MIN_BOUNDARY_ARC of qcremesh.param.disk: crowded beyond what the landmarks
# resolve), each run of boundary vertices crowded below CROWDED_RATIO of the mean arc per
# unit length (crowded_arcs) over at least CROWDED_MIN_EDGES output edges is cut off and
# remeshed on its own map. Measured on strips 8-16 times as long as wide (test_remesh's
# strip_disk; 3, 23, 35, 44 and 51 % at the narrowest arc) at their face count, half of
# it and 1,000 faces: mean q 0.977 / 0.970 / 0.968 -> 0.962 / 0.943 / 0.948 on the
# strip 8 long, 0.964 / 0.960 -> 0.961 / 0.951 on the one 10 long, but 0.945 / 0.935 /
# 0.924 -> 0.969 / 0.951 / 0.951 on the one 12 long and 0.893 / 0.894 / 0.796 -> 0.968 /
# 0.956 / 0.953 on the one 16 long (min q 0.116 / 0.451 / 0.024 -> 0.540 / 0.668 /
# 0.685). camel_b.obj (35 %): its legs and neck, runs 18-40 edges long. The other disk
# meshes of ../shared/data have no vertex at the narrowest arc.
CROWDED_SHARE = 0.3
# With a fixed boundary (a surface cut open into a disk, whose two sides of each cut the
# caller welds; the boundary vertices at the same points as the paths' ends are corners
# too, so both sides keep the same vertices), above CROWDED_SHARE_FIXED: Hand1.off's cut
# disk, 8.6 % (at its face count / half: min q 0.028 / 0.034 -> 0.396 / 0.462, Hausdorff
# 0.33 / 0.44 -> 0.17 / 0.36 %); the cut disks of the torus, the holed disk, the sphere,
# decimated-max and alex_3 of the tests and the benchmark have at most 1.4 %.
CROWDED_SHARE_FIXED = 0.05
CROWDED_RATIO = 0.1
CROWDED_MIN_EDGES = 16
# Rounds of cuts across the pieces that a disk cut along its creases falls into, where
# their own maps crowd.
CREASE_ROUNDS = 3


def crowded_ends(V, F, dm, edge, min_edges=CROWDED_MIN_EDGES):
    """The boundary vertices before and after each run that the disk map ``dm`` crowds
    (:func:`crowded_arcs` below CROWDED_RATIO over at least ``min_edges`` times ``edge``
    of boundary), (p, 2)."""
    bnd = dm.boundary
    start, count, _ = crowded_arcs(V, dm.uv, bnd, CROWDED_RATIO)
    lengths = np.linalg.norm(V[np.roll(bnd, -1)] - V[bnd], axis=1)
    # (the run's length: its vertices' edges to the next, but the last's)
    along = np.r_[0.0, np.cumsum(np.r_[lengths, lengths])]
    long = (count < len(bnd) - 2) & (along[start + count - 1] - along[start] >= min_edges * edge)
    return np.column_stack([bnd[(start[long] - 1) % len(bnd)], bnd[(start[long] + count[long]) % len(bnd)]])


def crowded_cuts(V, F, dm, faces, min_edges=CROWDED_MIN_EDGES):
    """Paths across the disk map ``dm``'s crowded boundary runs (:func:`crowded_ends` for
    the output edge length of ``faces`` faces and ``min_edges``), each from the boundary
    vertex before a run to the one after it through interior vertices
    (:func:`qcremesh.mesh.cut.paths_across`), or, where no such path joins them (a neck
    one face wide), the chord that cuts off the most of the run
    (:func:`qcremesh.mesh.cut.chord_across`); [] where there is none."""
    edge = output_edge_length(V, F, faces)
    ends = crowded_ends(V, F, dm, edge, min_edges)
    paths = paths_across(V, F, ends)
    paths = [chord_across(F, dm.boundary, *e) if p is None else p for p, e in zip(paths, ends)]
    return [p for p in paths if p is not None]


def crease_cuts(V, F, sharp, paths, faces):
    """Paths to cut a disk along so that its ``sharp`` edges ((k, 2), from
    :func:`qcremesh.geometry.creases.sharp_edges`) become piece borders: those edges, the
    paths that join their parts with no boundary vertex to the boundary
    (:func:`qcremesh.mesh.cut.paths_to_boundary`), the crowded ``paths`` (from
    :func:`crowded_cuts`) and, up to CREASE_ROUNDS times, the crowded cuts of each
    piece whose own disk map crowds more than CROWDED_SHARE_FIXED of its boundary (the
    ring between two creases round a plateau is a strip), split into paths that meet
    only at their ends (:func:`qcremesh.mesh.cut.edge_paths`, which end at the boundary
    and at branch points; a closed one starts and ends at the same vertex, which
    :func:`qcremesh.mesh.cut.weld_along_paths` takes). ``faces`` is the output's face
    count, shared among the pieces by area."""

    cut = np.concatenate([sharp, path_edges(paths_to_boundary(V, F, sharp) + paths)])
    for _ in range(CREASE_ROUNDS):
        more = pieces_crowded_cuts(V, F, cut, faces, CROWDED_SHARE_FIXED)
        if not more:
            break
        cut = np.concatenate([cut, path_edges(more)])
    return edge_paths(cut, len(V), stops=boundary_edges(F).ravel())


def pieces_crowded_cuts(V, F, cut, faces, share=None, where=None):
    """The crowded cuts (:func:`crowded_cuts`) of the pieces that cutting the disk (V, F)
    along the edges ``cut`` (k, 2) makes, each on its own disk map with its share of the
    ``faces`` by area, as paths of vertices of (V, F): of the pieces whose map gives more
    than ``share`` of their boundary vertices the narrowest arc (every piece where None)
    and, with points ``where`` (p, 3), that hold the vertex nearest one of them; [] where
    there is none."""
    F_cut, parent = cut_along_edges(F, cut, len(V))
    count, label = connected_components(F_cut, len(parent))
    area = np.bincount(label, doublearea(V[parent], F_cut), count)
    chosen = np.ones(count, dtype=bool)
    if where is not None:
        piece = np.zeros(len(parent), dtype=np.int64)
        piece[F_cut.ravel()] = np.repeat(label, 3)
        chosen[:] = False
        chosen[piece[cKDTree(V[parent]).query(where)[1]]] = True
    more = []
    for k, (used, Fk) in enumerate(split_pieces(F_cut, label, count)):
        if not chosen[k]:
            continue
        Vk = V[parent[used]]
        try:
            dm = disk_conformal_map(Vk, Fk)
        except MeshError:
            continue
        if share is None or dm.narrowest_arcs > share * len(dm.boundary):
            more += [parent[used][p] for p in crowded_cuts(Vk, Fk, dm, max(faces * area[k] / area.sum(), 1.0))]
    return more


def trimmed_cut(V, F, cut, where, reach):
    """The cut (edges (k, 2) of the surface (V, F)) without its edges within ``reach`` of
    the points ``where``, the longest connected part of what is left: (F_cut, parent,
    edges) as :func:`qcremesh.mesh.cut.cut_to_disk` gives them; None where nothing is
    near or left, or what is left does not open the surface into a disk."""
    if not len(where) or not len(cut):
        return None
    near = cKDTree(where).query(V[cut].mean(1))[0] < reach
    rest = cut[~near]
    if not near.any() or not len(rest):
        return None
    graph = sp.coo_matrix((np.ones(len(rest)), (rest[:, 0], rest[:, 1])), shape=(len(V), len(V)))
    part = graph_components(graph, directed=False)[1][rest[:, 0]]
    length = np.bincount(part, np.linalg.norm(V[rest[:, 0]] - V[rest[:, 1]], axis=1))
    kept = rest[part == np.argmax(length)]
    try:
        F_cut, parent = cut_along_edges(F, kept, len(V))
    except ValueError:
        return None
    if len(boundary_loops(F_cut)) != 1 or euler_characteristic(F_cut) != 1:
        return None
    return F_cut, parent, kept


def split_pieces(F, label, count):
    """Each piece's vertices and faces: for piece k (``label`` (m,) the piece of each face,
    0..count-1), the vertices its faces use (sorted) and its faces renumbered over them,
    in their order in ``F``."""
    by_piece = np.split(F[np.argsort(label, kind="stable")], np.cumsum(np.bincount(label, minlength=count))[:-1])
    pieces = []
    for G in by_piece:
        used, local = np.unique(G, return_inverse=True)
        pieces.append((used, local.reshape(-1, 3)))
    return pieces
