"""Quasi-conformal remeshing of a triangle mesh (Choi, Gu & Lui): the entry point.

:func:`remesh` checks the input and mends what can be mended without moving the surface
(:mod:`qcremesh.remeshing.mend`), computes the conformal parameterization of a disk onto the unit disk (Algorithm 1,
:mod:`qcremesh.param.disk`) and hands it to Algorithm 2
(:func:`qcremesh.remeshing.disk_remesh.remesh_disk`: landmarks, base mesh, subdivision,
Teichmueller map, projection, and the relaxation beyond the paper).

Beyond the paper, any manifold surface: one that is not a disk is cut open into one
along its edges (:mod:`qcremesh.mesh.cut`), remeshed with the two sides of every cut
alike and welded shut; several pieces are remeshed each.

Beyond the paper too, ``creases``: the edges where the surface turns by more than a
given angle (the edges of a CAD part's faces) kept as output edges, the disk cut along
them into pieces remeshed each and welded back.

Beyond the paper too, a ``sizing`` field (per input vertex, or ``"curvature"``, see
:mod:`qcremesh.adaptive.sizing`) grades the edge lengths: the landmarks spread the surface
area weighted by sizing^-2, and the relaxation keeps their grading.

The ablations of the paper are the ``method`` option: ``"uniform"`` (a regular mesh of the
disk projected as is, Fig. 7), ``"base"`` (the base mesh only), ``"subdivided"`` (Algorithm 2
without the Teichmueller map, Figs. 18-20 (c)) and ``"teichmuller"`` (all of it,
Figs. 18-20 (d), the default).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components as graph_components
from scipy.spatial import cKDTree

from ..adaptive.sizing import check_sizing, curvature_sizing, hole_sizing, point_sizing
from ..geometry.creases import check_crease_angle, sharp_edges
from ..geometry.operators import doublearea
from ..geometry.threads import query_workers
from ..mesh.cut import (
    cut_along_edges,
    cut_to_disk,
    edge_paths,
    paths_across,
    paths_to_boundary,
    weld_along_paths,
    weld_cut,
)
from ..mesh.topology import (
    boundary_edges,
    boundary_loop,
    boundary_loops,
    connected_components,
    euler_characteristic,
    genus,
    nonmanifold_edges,
    nonmanifold_vertices,
)
from ..mesh.validate import (
    DegenerateFaceError,
    MeshError,
    NonManifoldError,
    OrientationError,
    TopologyError,
    UnreferencedVertexError,
    as_mesh_arrays,
    check_not_soup,
)
from ..param.crowding import crowded_arcs
from ..param.disk import disk_conformal_map
from .disk_remesh import MIN_BASE_FACES, output_edge_length, planned_levels, remesh_disk
from .mend import refine_long_boundary, renumbered, repair_input, upsampled
from .result import RemeshResult, StageTimes

__all__ = ["METHODS", "RemeshResult", "remesh"]

METHODS = ("subdivided", "teichmuller", "base", "uniform")

# Where the remesh of a surface cut open does not weld back, it is done again with the
# edges around where the weld went wrong shortened to these ratios, in turn.
WELD_REFINE_RATIOS = (0.5, 0.25)

# Where it still does not, the cut's edges within this many output edges of where the weld
# went wrong are left out, if what is left still opens the surface into a disk.
TRIM_REACH = 3.0
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
# Fewest faces of a piece so cut off (else its path is not cut).
MIN_PIECE_FACES = 16
# Rounds of cuts across the pieces that a disk cut along its creases falls into, where
# their own maps crowd.
CREASE_ROUNDS = 3

# Distance, in mean boundary edge lengths, within which the boundary vertices of the two
# sides of a cut are one vertex when welded. They are the same arc length along the same
# polyline, but each side gets its point through its own disk map's boundary angles,
# which where the map crowds (arcs of 1e-6 rad) keep position to about 1e-9 of an edge:
# Hand1.off at half its face count with a curvature sizing field had two seam vertices
# 1.0x of 1e-9 edge from their twins, and its weld failed.
WELD_TOLERANCE = 1e-7

# A disk of fewer faces than a quarter of those asked for is split 1-to-4 until it has as
# many where the mean |mu| of its disk map is above this. A cube of 12 faces at 500 / 5,000
# faces (its cut disk's map 0.64): mean q 0.71 / 0.69, min q 0.013 / 0.000 -> 0.967 /
# 0.984, 0.68 / 0.66, and 7 s -> 0.2 s at 5,000. Where the map is near conformal it is not
# worth it: split, a hexagon of 6 faces (0.000), a cone over it (0.098) and a saddle of 32
# faces (0.138) at 200 and 2,000 faces lost up to 0.011 of mean q; closed meshes of 1,000
# to 10,000 faces at 8-20 times as many (cut disks' maps 0.04-0.10) moved by -0.0002 to
# +0.0013 (min q up by 0.00-0.08).
COARSE_MAP_MU = 0.3


def _weld_levels(levels, join, chi, loops):
    """Each level (X, F) of a remesh joined by ``join(X, F, tol)`` -> (X, F, kept) (a
    ValueError where it cannot; ``tol`` WELD_TOLERANCE of the level's mean boundary edge
    length) and kept where it then has Euler characteristic ``chi``, ``loops`` boundary
    loops and only manifold edges. Returns the output level's (X, F, kept) and the
    hierarchy, which starts above the last coarser level that does not join so, or whose
    join dropped faces (which then no longer split 1-to-4 into the next level's); None
    where the output level does not join."""

    def joined(X, Fo):
        try:
            Xw, Fw, kept = join(X, Fo, _weld_tolerance(X, Fo))
        except ValueError:
            return None
        ok = (
            len(Fw) > 0
            and euler_characteristic(Fw) == chi
            and len(boundary_loops(Fw)) == loops
            and not len(nonmanifold_edges(Fw))
        )
        return (Xw, Fw, kept) if ok else None

    # the output level first: the coarser ones only where it joins
    output = joined(*levels[-1])
    if output is None:
        return None
    welded = [joined(X, Fo) for X, Fo in levels[:-1]] + [output]
    intact = [level is not None and len(level[1]) == len(f) for level, (_, f) in zip(welded, levels)]
    first = max([i + 1 for i, ok in enumerate(intact[:-1]) if not ok], default=0)
    hierarchy = [level[:2] for level in welded[first:]] if intact[-1] else [welded[-1][:2]]
    return welded[-1], hierarchy


def _weld_tolerance(X, F):
    """WELD_TOLERANCE of the mean boundary edge length of (X, F)."""
    border = boundary_edges(F)
    return WELD_TOLERANCE * np.linalg.norm(X[border[:, 0]] - X[border[:, 1]], axis=1).mean()


def _weld_defects(X, F, segments):
    """Where the weld of a remeshed cut disk (X, F) along its cut (``segments``, (s, 2,
    3)) goes wrong: the points of the welded mesh at its non-manifold edges and vertices,
    and the centroids of the faces it folds onto others (and drops), (k, 3); none where
    it goes wrong otherwise or not at all."""
    try:
        Xw, Fw, _ = weld_cut(X, F, segments, _weld_tolerance(X, F))
    except ValueError:
        return np.zeros((0, 3))
    # each vertex's welded one: itself, or the mean of it and its twins, the nearest
    merged = cKDTree(Xw).query(X, workers=query_workers(len(X)))[1][F]
    _, group, size = np.unique(np.sort(merged, axis=1), axis=0, return_inverse=True, return_counts=True)
    folded = size[group.ravel()] > 1
    bad = np.union1d(np.unique(nonmanifold_edges(Fw)), nonmanifold_vertices(Fw)) if len(Fw) else []
    return np.concatenate([Xw[bad], X[F[folded]].mean(1)])


def _trimmed_cut(V, F, cut, where, reach):
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


def _split_pieces(F, label, count):
    """Each piece's vertices and faces: for piece k (``label`` (m,) the piece of each face,
    0..count-1), the vertices its faces use (sorted) and its faces renumbered over them,
    in their order in ``F``."""
    by_piece = np.split(F[np.argsort(label, kind="stable")], np.cumsum(np.bincount(label, minlength=count))[:-1])
    pieces = []
    for G in by_piece:
        used, local = np.unique(G, return_inverse=True)
        pieces.append((used, local.reshape(-1, 3)))
    return pieces


def _coincident_pairs(V, vertices):
    """The pairs of ``vertices`` at the same point (within 1e-9 of the bounding-box
    diagonal), as vertex indices, (p, 2) int."""
    vertices = np.asarray(vertices)
    tol = 1e-9 * np.linalg.norm(np.ptp(V, axis=0))
    return vertices[cKDTree(V[vertices]).query_pairs(tol, output_type="ndarray")]


def _crack_hint(V, F):
    """What an error says of boundary vertices at the same points as others: cracks
    between faces whose shared corners were written apart (a CAD part saved face by
    face); "" where there are none."""
    border = np.unique(boundary_edges(F))
    twins = np.unique(_coincident_pairs(V, border))
    if not len(twins):
        return ""
    return (
        f" ({len(twins)} of its {len(border)} boundary vertices lie at the same points as others: "
        "cracks between faces whose shared corners are not one vertex; merge them first)"
    )


def _remesh_cut(V, F, faces, sizing, data, repairs, options):
    """:func:`remesh` of a surface that is not a disk (closed, with holes, with handles):
    cut open into a disk (:func:`qcremesh.mesh.cut.cut_to_disk`), remeshed with a fixed
    boundary whose corners include the copies of the cut's ends and branch points (so that
    the two sides of each cut get the same vertices), with edges shortened around the
    holes shorter than a few edges (:func:`qcremesh.adaptive.sizing.hole_sizing`), and
    welded shut along the cut (:func:`qcremesh.mesh.cut.weld_cut`). Where the weld fails,
    the remesh is done again: without cutting the disk where its map crowds, with edges
    shortened around where the weld went wrong (WELD_REFINE_RATIOS), and last with the
    cut trimmed there (:func:`_trimmed_cut`). ``levels`` are welded
    each; ``uv``, ``disk_levels`` and ``mu`` stay those of the cut disk; ``repairs``, the
    stats of what :func:`~qcremesh.remeshing.mend.repair_input` mended first (the faces'
    orientation, which the cut needs to tell the two sides of a path), join the result's."""
    if options["relax"] == 0 or options["method"] == "uniform":
        raise ValueError(
            "a surface that is not a disk needs the relaxation (relax > 0) and a method other than 'uniform'"
        )
    try:
        F_cut, parent, cut = cut_to_disk(V, F, len(V))
    except ValueError as error:
        raise TopologyError(f"cannot cut the surface open into a disk: {error}{_crack_hint(V, F)}") from error
    edge = output_edge_length(V, F, faces)
    if isinstance(sizing, str):
        # on the surface, not on the cut disk: the two sides of a cut see the same
        # surface, and get the same sizing and so the same vertices
        sizing = curvature_sizing(V, F, edge)
    holes = hole_sizing(V, F, edge)
    if holes.min() < 1:
        sizing = holes if sizing is None else np.minimum(sizing, holes)
        repairs = dict(repairs, hole_sizing_min_ratio=float(holes.min()))
    chi, loops = euler_characteristic(F), len(boundary_loops(F))
    on_boundary = np.zeros(len(V), dtype=bool)
    on_boundary[boundary_edges(F).ravel()] = True

    def attempt(F_cut, parent, cut, sizing, **changed):
        """The disk F_cut (the surface cut along ``cut``) remeshed and welded shut:
        (result, the welded levels of :func:`_weld_levels` or None)."""
        # Corners: where the cut ends, branches or meets the boundary.
        degree = np.bincount(cut.ravel(), minlength=len(V))
        corner = (degree > 0) & ((degree != 2) | on_boundary)
        cut_corners = np.flatnonzero(corner[parent] & np.isin(np.arange(len(parent)), boundary_edges(F_cut)))
        result = remesh(
            V[parent], F_cut, faces, sizing=None if sizing is None else np.asarray(sizing)[parent],
            fixed_boundary=True, corners=cut_corners,
            data={k: np.asarray(v)[parent] for k, v in data.items()} if data else data, **dict(options, **changed),
        )
        segments = V[cut]
        return result, _weld_levels(result.levels, lambda X, Fo, tol: weld_cut(X, Fo, segments, tol), chi, loops)

    result, welded = attempt(F_cut, parent, cut, sizing)
    if welded is None and ("crowded_cuts" in result.stats or "crease_cuts" in result.stats):
        # The cut disk cut again where its map crowds or along its creases, whose seams
        # did not weld: once more without that.
        result, welded = attempt(F_cut, parent, cut, sizing, cut_crowded=False, creases=None)
    for ratio in WELD_REFINE_RATIOS:
        if welded is not None:
            break
        # A part of the surface thinner than about two output edges that the cut runs
        # along (a cow's tail, slit to its tip) collapses in the weld: shorter edges around
        # where it did, and once more.
        where = _weld_defects(*result.levels[-1], V[cut])
        if not len(where):
            break
        local = point_sizing(V, where, edge, ratio)
        sizing = local if sizing is None else np.minimum(sizing, local)
        repairs = dict(repairs, weld_sizing_min_ratio=ratio)
        result, welded = attempt(F_cut, parent, cut, sizing)
    if welded is None:
        # Still not: the cut without its part there (the slit then stops short of the
        # tail, which comes out coarse), where what is left still opens the surface.
        trimmed = _trimmed_cut(V, F, cut, _weld_defects(*result.levels[-1], V[cut]), TRIM_REACH * edge)
        if trimmed is not None:
            F_cut, parent, cut = trimmed
            repairs = dict(repairs, cut_trimmed=True)
            result, welded = attempt(F_cut, parent, cut, sizing)
    if welded is None:
        raise TopologyError(
            f"the remesh of the surface cut open does not weld back into its topology{_crack_hint(V, F)}"
        )
    # A coarse level can have a face across two copies of a branch point of the cut
    # (the corners of the disk where a handle's two loops meet), which the weld folds
    # away: the levels start above the last such one.
    (Vo, Fo, kept), levels = welded
    out_data = {k: np.asarray(v)[kept] for k, v in result.data.items()}
    stats = dict(repairs, **result.stats, cut_edges=len(cut))
    return RemeshResult(Vo, Fo, result.uv, levels, out_data, result.disk_levels, result.mu, stats, result.times)


def _crowded_ends(V, F, dm, edge):
    """The boundary vertices before and after each run that the disk map ``dm`` crowds
    (:func:`crowded_arcs` below CROWDED_RATIO over at least CROWDED_MIN_EDGES times
    ``edge`` of boundary), (p, 2)."""
    bnd = dm.boundary
    start, count, _ = crowded_arcs(V, dm.uv, bnd, CROWDED_RATIO)
    lengths = np.linalg.norm(V[np.roll(bnd, -1)] - V[bnd], axis=1)
    # (the run's length: its vertices' edges to the next, but the last's)
    along = np.r_[0.0, np.cumsum(np.r_[lengths, lengths])]
    long = (count < len(bnd) - 2) & (along[start + count - 1] - along[start] >= CROWDED_MIN_EDGES * edge)
    return np.column_stack([bnd[(start[long] - 1) % len(bnd)], bnd[(start[long] + count[long]) % len(bnd)]])


def _crowded_cuts(V, F, dm, faces):
    """Paths across the disk map ``dm``'s crowded boundary runs (:func:`_crowded_ends` for
    the output edge length of ``faces`` faces), each from the boundary vertex before a run
    to the one after it through interior vertices
    (:func:`qcremesh.mesh.cut.paths_across`); [] where there is none."""
    edge = output_edge_length(V, F, faces)
    return [p for p in paths_across(V, F, _crowded_ends(V, F, dm, edge)) if p is not None]


def _crease_cuts(V, F, sharp, paths, faces):
    """Paths to cut a disk along so that its ``sharp`` edges ((k, 2), from
    :func:`qcremesh.geometry.creases.sharp_edges`) become piece borders: those edges, the
    paths that join their parts with no boundary vertex to the boundary
    (:func:`qcremesh.mesh.cut.paths_to_boundary`), the crowded ``paths`` (from
    :func:`_crowded_cuts`) and, up to CREASE_ROUNDS times, the crowded cuts of each
    piece whose own disk map crowds more than CROWDED_SHARE_FIXED of its boundary (the
    ring between two creases round a plateau is a strip), split into paths that meet
    only at their ends (:func:`qcremesh.mesh.cut.edge_paths`, which end at the boundary
    and at branch points; a closed one starts and ends at the same vertex, which
    :func:`qcremesh.mesh.cut.weld_along_paths` takes). ``faces`` is the output's face
    count, shared among the pieces by area."""

    def edges_of(paths):
        return [np.column_stack([p[:-1], p[1:]]) for p in paths]

    cut = np.concatenate([sharp] + edges_of(paths_to_boundary(V, F, sharp) + paths))
    for _ in range(CREASE_ROUNDS):
        F_cut, parent = cut_along_edges(F, cut, len(V))
        count, label = connected_components(F_cut, len(parent))
        area = np.bincount(label, doublearea(V[parent], F_cut), count)
        more = []
        for k, (used, Fk) in enumerate(_split_pieces(F_cut, label, count)):
            Vk = V[parent[used]]
            try:
                dm = disk_conformal_map(Vk, Fk)
            except MeshError:
                continue
            if dm.narrowest_arcs > CROWDED_SHARE_FIXED * len(dm.boundary):
                share = max(faces * area[k] / area.sum(), 1.0)
                more += [parent[used][p] for p in _crowded_cuts(Vk, Fk, dm, share)]
        if not more:
            break
        cut = np.concatenate([cut] + edges_of(more))
    return edge_paths(cut, len(V), stops=boundary_edges(F).ravel())


def _remesh_along_paths(V, F, paths, faces, corners, sizing, data, stats, options, name="crowded"):
    """:func:`remesh` of a disk cut along ``paths`` (from :func:`_crowded_cuts`, where
    its map crowds parts of the boundary, or :func:`_crease_cuts`) into pieces, each
    remeshed on its own map with a share of the faces by area (counted times sizing^-2
    with a ``sizing`` field, (n,) or None), a fixed boundary whose corners are the
    paths' ends and the input vertices ``corners`` on it, and the boundary edge length planned for the whole (so that both
    sides of a path get the same vertices; in the metric of the sizing field, which each
    piece scales to a largest value of 1, so with the edge length scaled as the piece's
    field), all at the same levels, and welded along the paths
    (:func:`qcremesh.mesh.cut.weld_along_paths`, every level; a coarse level that does
    not weld into a disk is dropped). A path that would cut off a piece of fewer than
    MIN_PIECE_FACES faces is not cut; nor, for the crowded cuts (``name`` "crowded"), one
    that would cut off a piece without an interior vertex, or planned at fewer levels
    than one below the largest piece (:func:`~qcremesh.remeshing.disk_remesh.planned_levels`; every piece would take
    them: Hand1.off's cut disk at half its face count, two pieces of a few hundred faces
    at no level, took 11.9 s instead of 5.3 s, mean q 0.966 instead of 0.987). The
    creases' cuts keep such pieces (a mesa whose top is a sixth of its area lost its
    rim's crease to the level rule, Hausdorff 1.3 %; a step's steep band one face wide,
    a strip, lost both its creases), and a strip is split 1-to-4 first. Where a piece is
    then not a disk (a crease's closed loop whose join to the boundary went with a small
    piece), None.
    Joined as :func:`_join` with ``stats[name + "_cuts"]`` (the paths cut) and
    ``stats[name + "_piece_faces"]``; None where the output does not weld into a disk."""
    density = None if sizing is None else sizing.max() / sizing
    while True:
        if not paths:
            return None
        cut = np.concatenate([np.column_stack([p[:-1], p[1:]]) for p in paths])
        F_cut, parent = cut_along_edges(F, cut, len(V))
        count, label = connected_components(F_cut, len(parent))
        V_cut = V[parent]
        cut_density = None if density is None else density[parent]
        weight = doublearea(V_cut, F_cut)
        if cut_density is not None:
            weight = weight * (cut_density[F_cut] ** 2).mean(1)
        area = np.bincount(label, weight, count)
        edge = output_edge_length(V, F, faces, density)
        ends = np.isin(parent, np.concatenate([np.concatenate([p[[0, -1]] for p in paths]), corners]))
        on_boundary = np.zeros(len(parent), dtype=bool)
        on_boundary[boundary_edges(F_cut).ravel()] = True
        pieces, small, members, inner = [], [], [], []
        for k, (used, local) in enumerate(_split_pieces(F_cut, label, count)):
            members.append(parent[used])
            piece_data = {key: np.asarray(v)[parent][used] for key, v in data.items()} if data else data
            share = int(round(faces * area[k] / area.sum()))
            pieces.append((V_cut[used], local, share, np.flatnonzero(ends[used]), piece_data,
                           None if cut_density is None else cut_density[used]))
            inner.append(not on_boundary[used].all())
            if share < MIN_PIECE_FACES or (name == "crowded" and not inner[-1]):
                small.append(members[-1])
        # the levels each piece with an interior vertex plans (a strip is split first and
        # plans its own)
        planned = [
            planned_levels(Vk, Fk, share, options["levels"], dk) if has else None
            for (Vk, Fk, share, _, _, dk), has in zip(pieces, inner)
        ]
        if not small and name == "crowded":
            # Pieces planned at fewer levels than one below the largest's (which all
            # pieces would then take) are not cut off.
            most = planned[int(np.argmax([piece[2] for piece in pieces]))]
            small = [vertices for vertices, level in zip(members, planned) if level < most - 1]
        if not small:
            break
        # The paths that cut off a piece too small, without an interior vertex or (with
        # the level rule) planned at too few levels go.
        kept = [p for p in paths if not any(np.isin(p[[0, -1]], u).all() for u in small)]
        if len(kept) == len(paths):
            return None
        paths = kept
    if any(euler_characteristic(Fk) != 1 or len(boundary_loops(Fk)) != 1 for _, Fk, *_ in pieces):
        # (a crease's closed loop whose join to the boundary went with a small piece)
        return None
    # Every piece at the levels of the one that can have the fewest: from the fewest
    # planned, and those that had more remeshed again. (From the levels asked for,
    # Hand1.off's largest piece was remeshed at 2 levels and again at the 1 that a piece
    # of 619 faces planned: 20.0 -> 9.8 s at its face count.)
    results = [None] * len(pieces)
    levels = min((level for level in planned if level is not None), default=options["levels"])
    while True:
        for k, (Vk, Fk, share, corners, piece_data, dk) in enumerate(pieces):
            if results[k] is None or results[k].stats["levels"] > levels:
                # the piece's field scaled to a largest value of 1: its density to a least of 1
                scale = 1.0 if dk is None else dk.min()
                results[k] = remesh(
                    Vk, Fk, share, fixed_boundary=True, corners=corners, boundary_edge_length=edge / scale,
                    sizing=None if dk is None else 1.0 / dk, data=piece_data, **dict(options, levels=levels),
                )
        used = [r.stats["levels"] for r in results]
        if min(used) == max(used):
            break
        levels = min(used)
    joined = _join(results, dict(stats, **{f"{name}_cuts": len(paths)}), f"{name}_piece_faces")
    segments = [V[p] for p in paths]
    welded = _weld_levels(joined.levels, lambda X, Fo, tol: weld_along_paths(X, Fo, segments, tol), 1, 1)
    if welded is None:
        return None
    (Vo, Fo, kept), hierarchy = welded
    out_data = {k: np.asarray(v)[kept] for k, v in joined.data.items()}
    return RemeshResult(
        Vo, Fo, joined.uv, hierarchy, out_data, joined.disk_levels, joined.mu, joined.stats, joined.times
    )


def _remesh_pieces(V, F, label, count, faces, sizing, fixed_boundary, data, repairs, options):
    """:func:`remesh` of a mesh in several connected pieces (``label`` (m,), the piece of
    each face, 0..count-1): each piece remeshed on its own with a share of ``faces``
    proportional to its area (at least 4), and the results joined (:func:`_join`, with
    ``stats["pieces"]``). A piece's error names the piece."""
    area = np.bincount(label, doublearea(V, F), count)
    results = []
    for k, (used, local) in enumerate(_split_pieces(F, label, count)):
        share = max(int(round(faces * area[k] / area.sum())), 4)
        piece_sizing = sizing if sizing is None or isinstance(sizing, str) else np.asarray(sizing)[used]
        piece_data = {name: np.asarray(v)[used] for name, v in data.items()} if data else data
        try:
            results.append(
                remesh(
                    V[used], local, share, sizing=piece_sizing, fixed_boundary=fixed_boundary,
                    data=piece_data, **options,
                )
            )
        except MeshError as error:
            raise type(error)(f"piece {k + 1} of {count} ({len(local)} faces, {share} asked for): {error}") from error
    return _join(results, dict(repairs, pieces=count), "piece_faces")


def _join(results, stats, faces_key):
    """The remeshes of several pieces (``results``) as one :class:`RemeshResult`.

    The levels are those all pieces have, from the output down (a piece with fewer
    levels than another starts the hierarchy at its own base mesh); the vertices are
    numbered level by level, every piece's coarser ones first. ``uv``, ``disk_levels``,
    ``mu`` and the stats are those of the largest piece (the one with the most output
    faces), joined with ``stats`` and ``stats[faces_key]`` (each piece's output faces),
    but the sharpest corner, its quality bound, the crowded share of the
    boundary and the draws, the worst piece's; the times are summed."""
    count = len(results)
    depth = min(len(r.levels) for r in results)
    levels = [[r.levels[len(r.levels) - depth + i] for r in results] for i in range(depth)]
    # Global numbering: level by level, piece by piece, the vertices new at that level.
    counts = np.array([[len(X) for X, _ in level] for level in levels])  # (depth, count)
    new = np.diff(np.vstack([np.zeros((1, count), dtype=np.int64), counts]), axis=0)
    start = np.cumsum(np.r_[0, new.ravel()])[:-1].reshape(depth, count)
    number = []
    for k in range(count):
        number.append(np.concatenate([start[i, k] + np.arange(new[i, k]) for i in range(depth)]))
    total = int(counts[-1].sum())
    joined = []
    for i, level in enumerate(levels):
        X = np.zeros((int(counts[i].sum()), 3))
        for k, (Xk, _) in enumerate(level):
            X[number[k][: len(Xk)]] = Xk
        joined.append((X, np.concatenate([number[k][Gk] for k, (_, Gk) in enumerate(level)])))
    out_data = {}
    for name in results[0].data:
        first = np.asarray(results[0].data[name])
        values = np.zeros((total,) + first.shape[1:], dtype=first.dtype)
        for k, r in enumerate(results):
            values[number[k]] = r.data[name]
        out_data[name] = values
    largest = max(range(count), key=lambda k: len(results[k].F))
    main = results[largest]
    stats = {**stats, **main.stats, faces_key: [len(r.F) for r in results]}
    # What the warnings read is the worst piece's.
    for name, worst in (("sharpest_corner_degrees", min), ("corner_quality_bound", min),
                        ("param_narrowest_share", max), ("draws", max)):
        values = [r.stats[name] for r in results if name in r.stats]
        if values:
            stats[name] = worst(values)
    times = {}
    for r in results:
        for name, t in r.times.items():
            times[name] = times.get(name, 0.0) + t
    V_out, F_out = joined[-1]
    return RemeshResult(V_out, F_out, main.uv, joined, out_data, main.disk_levels, main.mu, stats, times)


def _remesh_not_disk(V, F, faces, sizing, fixed_boundary, corners, boundary_edge_length, data, stats, options):
    """:func:`remesh` of a mesh that the disk validation refused for its topology (after the
    repairs): several pieces remeshed each (:func:`_remesh_pieces`); a disk with every
    vertex on its boundary (a strip or fan of triangles, which the disk map cannot take)
    split 1-to-4 until it has an interior vertex and a quarter of the faces asked for,
    the same surface (with the
    ``boundary_edge_length`` given, as a piece of a disk cut along its creases can be);
    any other manifold surface cut open, remeshed and welded (:func:`_remesh_cut`). None
    for a mesh that is none of these (a triangle soup, a non-manifold one), whose
    validation error stands.

    Raises
    ------
    ValueError
        Where ``boundary_edge_length`` is given for a surface other than such a disk."""
    pieces, label = connected_components(F, len(V))
    loops = boundary_loops(F)
    strip = len(loops) == 1 and len(loops[0]) == len(V)
    if boundary_edge_length is not None and not (strip and pieces == 1):
        raise ValueError("boundary_edge_length is taken only on a disk")
    # (faces that share no vertex are a triangle soup, unless the repair split them apart)
    if pieces > 1 and (np.bincount(F.ravel()).max() > 1 or "split_vertices" in stats):
        if corners is not None and len(corners):
            raise ValueError("corners are taken only on a disk")
        return _remesh_pieces(V, F, label, pieces, faces, sizing, fixed_boundary, data, stats, options)
    if genus(F, len(V)) is None:
        return None
    if strip:
        # until it has an interior vertex, and a quarter of the faces asked for: the disk
        # map of a few large triangles is far from conformal (a 3:1 rectangle of two
        # triangles split once, 8 faces: mean q 0.85-0.86 at 200 and 2,000 faces; 0.95 /
        # 0.98 from 128 / 512)
        V_fine, F_fine, fine_data, fine_sizing = upsampled(
            V, F, data, sizing, lambda G: len(boundary_loop(G)) < len(np.unique(G)) and 4 * len(G) >= faces
        )
        result = remesh(
            V_fine, F_fine, faces, sizing=fine_sizing, fixed_boundary=fixed_boundary, corners=corners,
            boundary_edge_length=boundary_edge_length, data=fine_data, **options,
        )
        result.stats.update(stats, subdivided_input=True)
        return result
    if corners is not None and len(corners):
        raise ValueError("corners are taken only on a disk")
    return _remesh_cut(V, F, faces, sizing, data, stats, options)


def remesh(
    V,
    F,
    faces=None,
    *,
    levels=2,
    method="teichmuller",
    seed=0,
    corner_angle=45.0,
    cvt_iterations=10,
    relax=40,
    teichmuller_iterations=5,
    retries=2,
    sizing=None,
    fixed_boundary=False,
    corners=None,
    boundary_edge_length=None,
    cut_crowded=True,
    creases=None,
    data=None,
    progress=None,
):
    """Remesh a triangle mesh of manifold surfaces (disks, surfaces with holes, closed
    surfaces, handles; one piece or several) into a regular, semi-regular one.

    A surface that is not a disk is cut open into one along its edges
    (:func:`qcremesh.mesh.cut.cut_to_disk`: loops around its handles, paths from each
    hole to the longest boundary loop, a closed one of genus 0 slit between its two
    vertices farthest apart along its principal axis), remeshed with ``fixed_boundary``
    and the cut's ends and branch points as ``corners`` (so that the two sides of each
    cut get the same vertices) and closed again (:func:`_remesh_cut`); several pieces are
    remeshed each (:func:`_remesh_pieces`). A disk whose map crowds much of its boundary
    beyond what the landmarks resolve (long protrusions: a camel cut open along slits,
    a strip more than about 10 times as long as wide) is cut where it crowds into
    pieces remeshed on their own maps and welded back (:func:`_remesh_along_paths`;
    ``stats["crowded_cuts"]``, ``stats["crowded_piece_faces"]``), with the sizing field where
    there is one.

    Where the validation refuses the input for faces listed more than once (which make
    their edges non-manifold), faces turned against their neighbours, or for needles and
    caps (faces of zero area or within rounding of it), these are mended first, the
    surface kept: repeated faces kept once (``stats["duplicate_faces"]``), faces
    reversed to the majority's orientation
    (``stats["reoriented_faces"]``), needles merged and caps flipped away
    (``stats["repaired_needles"]``, ``stats["repaired_caps"]``).

    Parameters
    ----------
    V : (n, 3) or (n, 2) float
        Vertex positions; a planar mesh's (n, 2) get z = 0 (as
        :func:`qcremesh.mesh.io.read_mesh` gives them), and so does its output.
    F : (m, 3) int
        Manifold, consistently oriented surfaces (a disk passes
        :func:`qcremesh.mesh.validate.check_disk`).
    faces : int, optional
        Number of output faces wanted (the input's by default). The output has this many
        to within a few percent.
    levels : int
        Subdivision levels above the base mesh (the base mesh has about faces / 4^levels
        faces). Fewer are used where the base mesh would get under 100 faces or fewer
        interior landmarks than boundary ones, or where the first CVT's cells are far
        from equal on the surface (``MAX_CELL_SPREAD``; the level used is
        ``stats["levels"]``).
        Where the base mesh misses its face count by more than 2 % (landmarks left out
        near the boundary, or boundary corners added), its interior landmarks are drawn
        again with their number corrected (``stats["cvt_redrawn"]``).
    method : {"subdivided", "teichmuller", "base", "uniform"}
        The paper's pipeline (the default) or one of its ablations (see the module
        documentation). With ``relax``, ``"teichmuller"`` and ``"subdivided"`` differ only
        in where the relaxation starts (the Teichmueller map of the level below the
        output, or its linear subdivision); measured on the seven disk meshes of the
        benchmark, their outputs have the same quality to within the spread over CVT
        seeds.
    seed : int
        Seed of the CVT initialization; the output is a deterministic function of the
        input and the seed.
    corner_angle : float
        Boundary vertices where the boundary turns by more than this (degrees, at the
        scale of the output spacing) are kept as output vertices.
    cvt_iterations : int
        Maximum number of Lloyd iterations.
    relax : int
        Sweeps of tangential relaxation on the surface after the projection, followed by
        the search that raises the minimum radius ratio around the worst faces (see
        :mod:`qcremesh.remeshing.relax`; 0 leaves the paper's pipeline alone). The
        connectivity and the semi-regular structure are kept. With ``"subdivided"`` the
        sweeps go to the level below the output, whose relaxed subdivision then gets
        ``relax // 2`` more (with ``"teichmuller"``, the level below is first mapped
        by the Teichmueller map): measured on hand.ply, foot.off and human_face.obj this is
        twice as fast as relaxing the output alone and raises the mean radius ratio by
        0.005-0.007 (with ``relax // 4`` on the output; ``relax // 2`` raised it on 15 of
        the 16 benchmark runs of the disk meshes by up to 0.0023, human_brain's share of
        faces above 0.9 at half its count 97.1 -> 97.7 %, for about 10 % more relaxation
        time; twice as many coarse sweeps took human_face's Hausdorff distance 0.45 ->
        0.71 %).
    teichmuller_iterations : int
        Maximum number of QC iterations of the Teichmueller map (from the linear
        subdivision, the quality of the output changes little after the first few).
    retries : int
        Where the output's smallest radius ratio is below 0.3 after the relaxation (its
        search ends in a local optimum that depends on the landmarks) on at most 16
        faces (more come from the surface, not the draw), the landmarks are drawn again
        from another CVT initialization, up to this many times, and the draw with the
        largest smallest radius ratio is kept (``stats["draws"]`` is the number
        made). Only with ``relax`` and a method that draws landmarks.
    sizing : (n,) float or "curvature", optional
        Edge length wanted at each input vertex relative to the others (only the ratios
        count: the face count sets the scale), or ``"curvature"`` for
        :func:`qcremesh.adaptive.sizing.curvature_sizing` at the output's mean edge
        length (edges down to 0.6 of the rest where the surface bends at their scale).
        The landmarks spread the surface area weighted by sizing^-2 and the boundary
        ones, and the relaxation's boundary vertices, the boundary length weighted by
        sizing^-1; the interior keeps the grading of the landmarks' connectivity. Not
        with ``"uniform"``.
    fixed_boundary : bool
        The boundary landmarks spaced by arc length itself (not smoothed at their
        spacing), and the output's boundary vertices spaced evenly by arc length between
        the boundary corners (all around where there is none) and kept there through
        the relaxation (see :func:`qcremesh.remeshing.relax.relax_on_surface`): parts of
        the border that are the same polyline between corners get the same vertices
        (the two sides of a cut). Needs ``relax``.
    corners : (c,) int, optional
        Input boundary vertices kept as output vertices (boundary corners), besides those
        found by ``corner_angle``.
    boundary_edge_length : float, optional
        With ``fixed_boundary``: the length of the output's boundary edges. Each part of
        the boundary between corners gets its length over this (times 2^levels for the
        landmarks), rounded, instead of its share of the planned boundary count, so that
        two meshes remeshed apart that share a border polyline between corners, at the
        same levels (``stats["levels"]``), get the same vertices along it. With a
        ``sizing`` field, in its metric (lengths times 1 / sizing, the field scaled to a
        largest value of 1).
    cut_crowded : bool
        Cut a disk whose map crowds its boundary into pieces remeshed apart and welded
        back (:func:`_remesh_along_paths`); without, it is remeshed whole (the levels planned
        for the whole, the crowded parts less regular).
    creases : float, optional
        Keep the creases: the interior edges across which the surface turns by more than
        this many degrees (:func:`qcremesh.geometry.creases.sharp_edges`; the edges of a
        CAD tessellation's faces) become output edges. The disk is cut along them (and
        along shortest edge paths from the parts of them with no boundary vertex to the
        boundary, which are seams only) into pieces, remeshed as the crowded ones are
        and welded back (``stats["crease_edges"]``, ``stats["crease_cuts"]``,
        ``stats["crease_piece_faces"]``; ``stats["creases_kept"]`` False where every cut
        would leave a piece too small, a piece is not a disk or is refused, or the pieces
        did not weld back, and the disk was remeshed whole). Needs ``relax`` and a method
        other than ``"uniform"``. None (the default): not looked for.
    data : dict of str to (n,) or (n, d) array, optional
        Per-vertex attributes (normals, colours, scalars, UVs) to carry to the output.
    progress : callable, optional
        Called as ``progress(stage_name)`` when each stage starts.

    Returns
    -------
    RemeshResult
    """
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; choose one of {', '.join(METHODS)}")
    if levels < 0:
        raise ValueError("levels must be >= 0")
    if retries < 0:
        raise ValueError("retries must be >= 0")
    V, F = as_mesh_arrays(V, F)
    if V.ndim != 2 or V.shape[1] not in (2, 3):
        raise ValueError(f"V must be (n, 3) or (n, 2), got shape {V.shape}")
    if V.shape[1] == 2:
        V = np.column_stack([V, np.zeros(len(V))])
    faces = len(F) if faces is None else int(faces)
    if faces < 4:
        raise ValueError("faces must be at least 4")
    curvature = isinstance(sizing, str)
    if curvature:
        if sizing != "curvature":
            raise ValueError(f"unknown sizing {sizing!r}; give one value per input vertex or 'curvature'")
        sizing = None  # computed on the input as the disk map takes it
    elif sizing is not None:
        sizing = check_sizing(sizing, len(V))
    if (curvature or sizing is not None) and method == "uniform":
        raise ValueError("the 'uniform' method takes no sizing")
    if creases is not None:
        check_crease_angle(creases)
    if creases is not None and (relax == 0 or method == "uniform"):
        raise ValueError("keeping creases needs the relaxation (relax > 0) and a method other than 'uniform'")
    if fixed_boundary and (relax == 0 or method == "uniform"):
        raise ValueError("a fixed boundary needs the relaxation (relax > 0) and a method other than 'uniform'")
    if boundary_edge_length is not None and not (fixed_boundary and boundary_edge_length > 0):
        raise ValueError("boundary_edge_length must be positive and needs fixed_boundary")
    if corners is not None:
        corners = np.unique(np.asarray(corners, dtype=np.int64))
        if method == "uniform" and len(corners):
            raise ValueError("the 'uniform' method takes no corners")
    if method == "base":
        levels = 0
    while levels > 0 and faces / 4**levels < MIN_BASE_FACES:
        levels -= 1
    stats = {"levels": levels}
    clock = StageTimes(progress)

    options = dict(
        levels=levels, method=method, seed=seed, corner_angle=corner_angle, cvt_iterations=cvt_iterations,
        relax=relax, teichmuller_iterations=teichmuller_iterations, retries=retries, cut_crowded=cut_crowded,
        creases=creases, progress=progress,
    )
    clock.start("parameterize")
    given_faces = F
    try:
        try:
            dm = disk_conformal_map(V, F)
        except (OrientationError, DegenerateFaceError, NonManifoldError, UnreferencedVertexError) as error:
            repaired = repair_input(V, F, data, sizing, stats)
            if repaired is None:
                raise error
            V, F, data, sizing, kept = repaired
            if corners is not None:
                corners = renumbered(corners, kept)
            # (before the map: the caps that no flip mends can be those along such edges)
            if not fixed_boundary:
                V, F, data, sizing = refine_long_boundary(V, F, data, sizing, stats)
            dm = disk_conformal_map(V, F)
        else:
            if not fixed_boundary:
                V, F, data, sizing = refine_long_boundary(V, F, data, sizing, stats, dm.boundary)
                if "boundary_split_vertices" in stats:
                    dm = disk_conformal_map(V, F)
    except TopologyError:
        # A triangle soup is refused as one: repaired and cut into fans along its long
        # boundary edges (every edge), foot.off with every face's corners its own was
        # taken for thousands of pieces (stopped after 2 minutes). (The input, before the
        # repairs: two triangles that share one corner are two pieces once it is split.)
        check_not_soup(given_faces)
        # (a surface that is not a disk, whose repair did not cut them already)
        if not fixed_boundary and "boundary_split_vertices" not in stats:
            V, F, data, sizing = refine_long_boundary(V, F, data, sizing, stats)
        sizing = "curvature" if curvature else sizing
        result = _remesh_not_disk(
            V, F, faces, sizing, fixed_boundary, corners, boundary_edge_length, data, stats, options
        )
        if result is None:
            raise
        return result
    if 4 * len(F) < faces and dm.mean_abs_mu > COARSE_MAP_MU:
        # A few large faces whose disk map is far from conformal (a cube's of 12, cut
        # open: mean |mu| 0.64) split 1-to-4 until they are a quarter of the faces asked for.
        V, F, data, sizing = upsampled(V, F, data, sizing, lambda G: 4 * len(G) >= faces)
        dm = disk_conformal_map(V, F)
        stats["subdivided_input"] = True
    stats.update(
        param_mean_abs_mu=dm.mean_abs_mu, param_folded_faces=dm.folded_faces, param_repaired_faces=dm.repaired_faces
    )
    clock.stop("parameterize")
    bnd = dm.boundary
    corner_at = None
    if corners is not None:
        position = np.full(len(V), -1, dtype=np.int64)
        position[bnd] = np.arange(len(bnd))
        corner_at = position[corners[(corners >= 0) & (corners < len(V))]]
        if len(corner_at) != len(corners) or (corner_at < 0).any():
            raise ValueError("corners must be vertices of the boundary")
    crowded = dm.narrowest_arcs > (CROWDED_SHARE_FIXED if fixed_boundary else CROWDED_SHARE) * len(dm.boundary)
    if curvature:
        sizing = curvature_sizing(V, F, output_edge_length(V, F, faces))
    attempts = []
    if boundary_edge_length is None and relax > 0 and method != "uniform":
        # (the pieces themselves, with a boundary edge length, are not cut again)
        crowded_paths = _crowded_cuts(V, F, dm, faces) if cut_crowded and crowded else []
        if creases is not None:
            sharp = sharp_edges(V, F, creases)
            stats["crease_edges"] = len(sharp)
            if len(sharp):
                attempts.append(("crease", _crease_cuts(V, F, sharp, crowded_paths, faces)))
        if crowded_paths:
            attempts.append(("crowded", crowded_paths))
    # the boundary vertices at the same points as the paths' ends (their twins on the
    # other side of a cut that the caller welds) are corners too
    twins = _coincident_pairs(V, bnd) if fixed_boundary and attempts else None
    for name, paths in attempts:
        given = np.zeros(0, dtype=np.int64) if corners is None else corners
        if twins is not None:
            ends = np.concatenate([p[[0, -1]] for p in paths])
            given = np.union1d(given, twins[np.isin(twins, ends).any(axis=1)].ravel())
        try:
            result = _remesh_along_paths(V, F, paths, faces, given, sizing, data, stats, options, name)
        except ValueError:
            if name != "crease":
                raise
            # pieces that the remesh refuses (featuretype.STL welded at its cracks, a
            # CAD part of genus 9 with fillets a face wide: a piece's corner off its
            # boundary): remeshed without the creases, as where they do not weld
            result = None
        if result is not None:
            result.times["parameterize"] = result.times.get("parameterize", 0.0) + clock.times["parameterize"]
            return result
        if name == "crease":
            stats["creases_kept"] = False
    return remesh_disk(
        V, F, dm, faces, levels=levels, method=method, seed=seed, corner_angle=corner_angle,
        cvt_iterations=cvt_iterations, relax=relax, teichmuller_iterations=teichmuller_iterations, retries=retries,
        sizing=sizing, fixed_boundary=fixed_boundary, corner_at=corner_at, boundary_edge_length=boundary_edge_length,
        data=data, stats=stats, clock=clock,
    )
