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

import numbers
import time
from dataclasses import replace

import numpy as np

from ..adaptive.landmarks import boundary_corners
from ..adaptive.sizing import check_sizing, curvature_sizing, hole_sizing, point_sizing
from ..geometry.creases import check_crease_angle, sharp_edges
from ..geometry.distance import hausdorff_distance
from ..geometry.operators import doublearea
from ..geometry.quality import radius_ratio
from ..mesh.cut import (
    boundary_is_seams,
    coincident_boundary_pairs,
    coincident_pairs,
    cut_along_edges,
    cut_to_disk,
    edge_paths,
    path_edges,
    weld_along_paths,
    weld_cut,
)
from ..mesh.cut import weld_seams as cut_weld_seams
from ..mesh.topology import (
    boundary_edges,
    boundary_loop,
    boundary_loops,
    connected_components,
    euler_characteristic,
    face_edge_lengths,
    genus,
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
    in_space,
    is_triangle_soup,
)
from ..param.charts import chart_borders, disk_charts
from ..param.disk import disk_conformal_map
from .cut_paths import (
    CROWDED_SHARE,
    CROWDED_SHARE_FIXED,
    crease_cuts,
    crowded_cuts,
    pieces_crowded_cuts,
    split_pieces,
    trimmed_cut,
)
from .disk_remesh import levels_above_min_base, output_edge_length, planned_levels, remesh_disk
from .min_quality import QUALITY_FLOOR
from .mend import refine_long_boundary, refined, renumbered, repair_input, upsampled
from .project import check_data
from .relax import SNAP_REACH
from .result import RemeshResult, StageTimes
from .seams import smooth_seams
from .weld import WeldError, crack_hint, join_pieces, weld_defects, weld_levels

__all__ = ["METHODS", "RemeshResult", "remesh"]

METHODS = ("subdivided", "teichmuller", "base", "uniform")

# Where the remesh of a surface cut open does not weld back, it is done again with the
# edges around where the weld went wrong shortened to these ratios, in turn.
WELD_REFINE_RATIOS = (0.5, 0.25)

# Where it still does not, the cut's edges within this many output edges of where the weld
# went wrong are left out, if what is left still opens the surface into a disk.
TRIM_REACH = 3.0

# The attribute that carries random labels (two numbers per input vertex, a fixed seed)
# through the remesh of a surface cut open, so that the weld tells the twins on the two
# sides of the cut from other vertices at the same point (weld_cut's labels).
LABEL_KEY = "qcremesh.cut_labels"

# A piece of a mesh in several whose remesh at its share of the faces does not weld back,
# or welds into fewer than half of them, or farther from it than PIECE_MAX_DISTANCE of its
# bounding-box diagonal, or into faces of a mean radius ratio below PIECE_MEAN_QUALITY,
# is remeshed at twice as many, while that is at most PIECE_FACE_RATIO times its own face
# count, and kept as it is where none welds close enough: pyvista's sample ant.ply, 15
# closed pieces, has flat plates 0.4 thick (at their share of its 912 faces, 19, welded
# into 16 faces of mean q 0.14; at 38, the weld folding most of them away, into 4; at
# 304, mean q 0.88) and legs of three spindles joined at necks far thinner than an
# output edge (at half its face count, one of 90 faces welded into 42 of mean q 0.68,
# 45 % of its diagonal from it: the ant's Hausdorff distance 13 %).
PIECE_FACE_RATIO = 4
PIECE_MEAN_QUALITY = 0.5
PIECE_MAX_DISTANCE = 0.25

# A surface of this genus or more is remeshed in charts (_remesh_charts), not cut open
# into one disk, whose map crowds the arcs along its handles. Marching-cubes surfaces (not
# in ../shared/data) at their face count / half, one cut disk -> charts: mean q, min q,
# Hausdorff distance in % of the diagonal:
# - a plate with 3 holes (32,056 faces): 0.981 / 0.957, 0.009 / 0.000, 2.51 / 4.60 ->
#   0.982 / 0.970, 0.213 / 0.321, 0.18 / 0.26;
# - with 4 holes: 0.981 / 0.973, 0.000 / 0.042, 2.93 / 1.56 -> 0.981 / 0.970, 0.024 /
#   0.328, 0.19 / 0.30;
# - with 6 holes: 0.973 / 0.965, 0.000 / 0.000, 2.17 / 2.62 -> 0.980 / 0.969, 0.266 /
#   0.308, 0.29 / 0.24;
# - three tori in a row (genus 3): 0.977 / 0.976, 0.005 / 0.009, 2.38 / 1.79 -> 0.969 /
#   0.965, 0.164 / 0.317, 0.22 / 0.28.
# A double torus (genus 2) stays cut open: 0.985 / 0.981, 0.064 / 0.361, 0.44 / 0.45
# against 0.977 / 0.964, 0.003 / 0.313, 0.18 / 0.31 in charts.
CHART_GENUS = 3
# Free sweeps of the smoothing across the charts' seams (see smooth_seams): their borders
# run along input edges, jagged at the output's scale on a marching-cubes grid, and the
# guarded sweeps alone, which take no face below the smaller of its radius ratio and 0.7,
# straighten them only in part. The plate with 3 holes at its face count, faces within
# 1.5 edges of the seams (29 % of the output), mean q 0.863 unsmoothed, 0.925 guarded, 0.968
# with the free sweeps first (0.9815 over the whole; min q 0.155 -> 0.213). On the seams
# of a cut disk they do not pay: alex_3's min q 0.658 / 0.658 -> 0.530 / 0.506.
CHART_FREE_SWEEPS = 20

# Fewest faces of a piece so cut off (else its path is not cut).
MIN_PIECE_FACES = 16
# Where the remesh of a disk whole has slivers and no crowded run is long enough to be cut
# off (CROWDED_MIN_EDGES), runs from SLIVER_RUN_EDGES output edges are, into pieces from
# SLIVER_PIECE_FACES faces (see _cut_at_slivers). A flap of a scan's border 0.02 wide and
# 0.2 long on a unit square (test_remesh's flap_disk), its tip crowded below what the
# landmarks resolve, at 1,000 / 2,000 / 4,000 faces: min q 0.150 / 0.152 / 0.178 -> 0.339 /
# 0.776 / 0.763, mean q 0.967 / 0.968 / 0.974 -> 0.970 / 0.976 / 0.978, Hausdorff distance
# 1.24 / 1.30 / 0.31 -> 0.37 % (the whole had no output vertex along the flap's middle).
# Every remesh of the benchmark (../shared/data at its face count and half of it, the
# synthetic CAD shapes with and without creases) keeps its bytes: none has slivers when
# remeshed whole but camel_b, which is cut where it crowds first, and face-YH.off, whose
# flaps lie in the pieces of a cut (cutting them off there with the short runs too, in
# _recut_at_slivers, took its 30 faces below 0.3 at half its face count to 134).
SLIVER_RUN_EDGES = 4
SLIVER_PIECE_FACES = 4
# Most rounds of cuts across the pieces that hold slivers (see _recut_at_slivers).
RECUT_ROUNDS = 3

# A disk that has more than COARSE_SHARE of its area in faces with an edge longer than
# LONG_EDGE_RATIO output edges where its map is far from conformal (|mu| above
# COARSE_MAP_MU) is refined first, the surface kept, where the refined disk's map is at
# most COARSE_GAIN times as far from conformal on the whole (mean |mu|): split 1-to-4 until
# it has a quarter of the faces asked for where every face has a radius ratio of at least
# WELL_SHAPED (its faces keep their shapes), else its edges longer than that cut
# (:func:`qcremesh.remeshing.mend.refined`: in equal pieces, the flat parts flipped to
# Delaunay), which 1-to-4 would leave needles. A cube of 12 faces at 500 / 5,000 faces
# (its cut disk's map 0.64): mean q 0.71 / 0.69, min q 0.013 / 0.000 -> 0.967 / 0.984, 0.68
# / 0.66 split 1-to-4, and 7 s -> 0.2 s at 5,000; with its edges cut instead, seeds 0-3 at
# 500 / 2,000 / 5,000, mean q 0.9627 / 0.9799 / 0.9866 -> 0.9612 / 0.9769 / 0.9855. A CAD
# tessellation's needles, seeds 0-3: a quarter cylinder of 78 faces, each as long as the
# cylinder, at 500 / 3,000 faces 0.851 / 0.950 split 1-to-4 -> 0.956 / 0.982 cut; a closed
# cylinder of 256, 0.941 / 0.985 -> 0.969 / 0.986 (mean min q 0.49 / 0.69 -> 0.68 / 0.61).
# The rule of before asked a mean |mu| above 0.3 and 90 % of the area in long faces (a
# disk coarser than the output nearly everywhere; those above refine as they did): a
# capsule 12 radii long tessellated as revolved shapes are (trimesh.creation.capsule's),
# whose cylinder is one band of needles with 83 % of its area (77 % in such faces; its
# cut disk's map 0.34, 163 faces folded), had mean q 0.60, min q 0.00001 and a Hausdorff
# distance of 5.4 % at its face count, 0.994 / 0.900 / 0.08 % refined (its map 0.019); 7
# radii long (24 %, map 0.154) 0.976 -> 0.990 (0.957 -> 0.992 numbered as trimesh does);
# trimesh's closed cylinder of 256 faces at its face count (map 0.68, 80 % of its area in
# such faces) 0.72 -> 0.95 (Hausdorff 19 -> 5.0 %, its creases not kept). 5 radii long
# (8 %, map 0.105) it is left: 0.986 (numbered as trimesh does 0.969 / 0.974 at its face
# count / half, 0.992 / 0.988 refined). camel_b.obj, whose map crowds at its slits, is
# left: it has 10 % of its area in such faces at its face count (and 9-14 % in three of
# its pieces cut where the map crowds at half), and refined there its map goes only from
# 0.39 to 0.35 (0.37 at half): with 2 % asked and no gain, over seeds
# 0-3 at its face count / half, mean q 0.9572 / 0.9379 -> 0.9569 / 0.9349, q > 0.9 84.3 ->
# 83.1 % at half; with 2 % and a gain of 0.5 asked, its outputs the same but 0.2 / 0.6 s
# longer (the finer maps made and not taken). At 15 %, one of its pieces at its face
# count (35 % of its area in such faces, its map 0.32 -> 0.23 refined: 0.72) is refined
# where a gain of 0.75 is asked: over seeds 0-3, min q 0.372 -> 0.429 but mean q 0.9572 ->
# 0.9564 and q > 0.9 90.6 -> 90.2 %; not at 0.7. The quarter cylinder above at 60 / 100
# faces (its map 0.51 -> 0.32 refined: 0.62) is refined as before. With a sizing field
# none is refined (camel_b.obj with the curvature sizing: a piece cut where its map
# crowds, refined against the mean edge length where its field asks for shorter ones,
# mean q 0.937 -> 0.894, min q 0.41 -> 0.005). Where the map is near conformal it is not worth it: split,
# a hexagon of 6 faces (0.000), a cone over it (0.098) and a saddle of 32 faces (0.138) at
# 200 and 2,000 faces lost up to 0.011 of mean q; closed meshes of 1,000 to 10,000 faces at
# 8-20 times as many (cut disks' maps 0.04-0.10) moved by -0.0002 to +0.0013 (min q up by
# 0.00-0.08).
COARSE_MAP_MU = 0.3
LONG_EDGE_RATIO = 2.0
COARSE_SHARE = 0.15
COARSE_GAIN = 0.7
WELL_SHAPED = 0.5


def _same_across_seams(V, F, data):
    """Whether every array of ``data`` has the same values at each two boundary vertices
    of (V, F) at the same point (:func:`qcremesh.mesh.cut.coincident_boundary_pairs`):
    nothing, such as texture coordinates or the normals of a crease, that the seams keep
    apart."""
    if not data:
        return True
    pairs = coincident_boundary_pairs(V, F)
    return all(np.array_equal(values[pairs[:, 0]], values[pairs[:, 1]]) for values in data.values())


def _remesh_cut(V, F, faces, sizing, data, repairs, options):
    """:func:`remesh` of a surface that is not a disk (closed, with holes, with handles),
    with edges shortened around the holes shorter than a few edges
    (:func:`qcremesh.adaptive.sizing.hole_sizing`): split into charts
    (:func:`_remesh_charts`) where its genus is CHART_GENUS or more, and otherwise, or
    where the charts do not weld or have a face below QUALITY_FLOOR, cut open into one
    disk (:func:`_remesh_cut_disk`); of the two, the one with the larger smallest radius
    ratio. (Charts do better where the one disk's map crowds along the handles: the
    plates with holes of the tests; not where they are many and small: featuretype.STL's
    43 charts, which weld where the pieces planned apart fill no gaps of landmarks, at its
    face count min q 0.004 and mean q 0.740, its cut disk 0.082 and 0.934.) ``repairs``,
    the stats of what :func:`~qcremesh.remeshing.mend.repair_input` mended first (the
    faces' orientation, which the cut needs to tell the two sides of a path), join the
    result's."""
    if options["relax"] == 0 or options["method"] == "uniform":
        raise ValueError(
            "a surface that is not a disk needs the relaxation (relax > 0) and a method other than 'uniform'"
        )
    edge = output_edge_length(V, F, faces)
    if isinstance(sizing, str):
        # on the surface, not on the cut disk: the two sides of a cut see the same
        # surface, and get the same sizing and so the same vertices
        sizing = curvature_sizing(V, F, edge)
    holes = hole_sizing(V, F, edge)
    if holes.min() < 1:
        sizing = holes if sizing is None else np.minimum(sizing, holes)
        repairs = dict(repairs, hole_sizing_min_ratio=float(holes.min()))
    charted = None
    if options["cut_crowded"] and (genus(F) or 0) >= CHART_GENUS:
        charted = _remesh_charts(V, F, faces, sizing, data, repairs, options)
        if charted is not None:
            least = radius_ratio(charted.V, charted.F).min()
            if least >= QUALITY_FLOOR:
                return charted
    try:
        cut = _remesh_cut_disk(V, F, faces, sizing, data, repairs, options, edge)
    except (TopologyError, WeldError):
        if charted is None:
            raise
        return charted
    return charted if charted is not None and least > radius_ratio(cut.V, cut.F).min() else cut


def _remesh_cut_disk(V, F, faces, sizing, data, repairs, options, edge):
    """The remesh of :func:`_remesh_cut` on the surface cut open into a disk
    (:func:`qcremesh.mesh.cut.cut_to_disk`; ``edge`` the planned output edge length),
    remeshed with the cut's sides held (``fixed_boundary`` True at the copies of the cut's
    vertices) and corners that include the copies of its ends and branch points (so that
    the two sides of each cut get the same vertices), and welded shut along the cut
    (:func:`qcremesh.mesh.cut.weld_cut`). Where the weld fails, the remesh is done again:
    without cutting the disk where its map crowds, with edges shortened around where the
    weld went wrong (WELD_REFINE_RATIOS), and last with the cut trimmed there
    (:func:`trimmed_cut`). ``levels`` are welded each; ``uv``, ``disk_levels`` and ``mu``
    stay those of the cut disk."""
    try:
        F_cut, parent, cut = cut_to_disk(V, F, len(V))
    except ValueError as error:
        raise TopologyError(f"cannot cut the surface open into a disk: {error}{crack_hint(V, F)}") from error
    chi, loops = euler_characteristic(F), len(boundary_loops(F))
    on_boundary = np.zeros(len(V), dtype=bool)
    on_boundary[boundary_edges(F).ravel()] = True

    def attempt(F_cut, parent, cut, sizing, **changed):
        """The disk F_cut (the surface cut along ``cut``) remeshed and welded shut:
        (result, the welded levels of :func:`weld_levels` or None, the labels of the output
        vertices that :func:`~qcremesh.mesh.cut.weld_cut` takes)."""
        # Corners: where the cut ends, branches or meets the boundary.
        degree = np.bincount(cut.ravel(), minlength=len(V))
        corner = (degree > 0) & ((degree != 2) | on_boundary)
        cut_corners = np.flatnonzero(corner[parent] & np.isin(np.arange(len(parent)), boundary_edges(F_cut)))
        cut_data = {k: np.asarray(v)[parent] for k, v in (data or {}).items()}
        cut_data[LABEL_KEY] = np.random.default_rng(0).random((len(V), 2))[parent]
        # The surface's own boundary loops slide along their borders as a disk's does:
        # held there too, evenly spaced by arc length between the corners, a hole's
        # faces were worse (alex_3.ply at half its face count: q > 0.9 97.1 -> 99.2 %,
        # mean q 0.982 -> 0.989; Hausdorff 0.21 -> 0.23 %). A closed surface, whose
        # boundary is all cut, keeps True: its boundary vertices then take the input
        # faces beside them (relax_on_surface), as a mask's held ones do not.
        held = True if loops == 0 else (degree > 0)[parent]
        result = remesh(
            V[parent], F_cut, faces, sizing=None if sizing is None else np.asarray(sizing)[parent],
            fixed_boundary=held, corners=cut_corners, data=cut_data, **dict(options, **changed),
        )
        labels = result.data.pop(LABEL_KEY)
        segments = V[cut]
        welded = weld_levels(
            result.levels, lambda X, Fo, tol: weld_cut(X, Fo, segments, tol, labels[: len(X)]), chi, loops
        )
        return result, welded, labels

    result, welded, labels = attempt(F_cut, parent, cut, sizing)
    if welded is None and ("crowded_cuts" in result.stats or "crease_cuts" in result.stats):
        # The cut disk cut again where its map crowds or along its creases, whose seams
        # did not weld: once more without that.
        result, welded, labels = attempt(F_cut, parent, cut, sizing, cut_crowded=False, creases=None)
    for ratio in WELD_REFINE_RATIOS:
        if welded is not None:
            break
        # A part of the surface thinner than about two output edges that the cut runs
        # along (a cow's tail, slit to its tip) collapses in the weld: shorter edges around
        # where it did, and once more.
        where = weld_defects(*result.levels[-1], V[cut], labels)
        if not len(where):
            break
        local = point_sizing(V, where, edge, ratio)
        sizing = local if sizing is None else np.minimum(sizing, local)
        repairs = dict(repairs, weld_sizing_min_ratio=ratio)
        result, welded, labels = attempt(F_cut, parent, cut, sizing)
    if welded is None:
        # Still not: the cut without its part there (the slit then stops short of the
        # tail, which comes out coarse), where what is left still opens the surface.
        trimmed = trimmed_cut(V, F, cut, weld_defects(*result.levels[-1], V[cut], labels), TRIM_REACH * edge)
        if trimmed is not None:
            F_cut, parent, cut = trimmed
            repairs = dict(repairs, cut_trimmed=True)
            result, welded, labels = attempt(F_cut, parent, cut, sizing)
    if welded is None:
        raise WeldError(f"the remesh of the surface cut open does not weld back into its topology{crack_hint(V, F)}")
    # A coarse level can have a face across two copies of a branch point of the cut
    # (the corners of the disk where a handle's two loops meet), which the weld folds
    # away: the levels start above the last such one.
    (Vo, Fo, kept), levels = welded
    out_data = {k: np.asarray(v)[kept] for k, v in result.data.items()}
    Vo, levels, out_data = _seams_smoothed(Vo, Fo, levels, out_data, V, F, cut, data, options, result.times)
    stats = dict(repairs, **result.stats, cut_edges=len(cut))
    return RemeshResult(Vo, Fo, result.uv, levels, out_data, result.disk_levels, result.mu, stats, result.times)


def _remesh_charts(V, F, faces, sizing, data, repairs, options):
    """:func:`remesh` (with the ``sizing`` field (n,) or None, ``repairs`` as for
    :func:`_remesh_cut`) of a surface of higher genus split into charts that are disks
    (:func:`qcremesh.param.charts.disk_charts`), each remeshed on its own map with its
    border fixed, the branch points of the borders for corners, and welded back
    (:func:`_remesh_along_paths`, the seams smoothed with CHART_FREE_SWEEPS free sweeps
    first); None where it cannot be split so, or a chart gets too few faces, or the
    charts do not weld back.

    The borders follow input edges and turn at every vertex of them, so no turn of a
    border is a corner (a corner kept on both sides of a jagged border took plate3's
    faces along the seams from mean q 0.952 to 0.910); the corners of the surface's own
    boundary are found on the whole surface (at the turning angle ``corner_angle``, at the
    scale of the output edge) and kept."""
    try:
        labels = disk_charts(V, F)
    except ValueError:
        return None
    edge = output_edge_length(V, F, faces)
    loops = boundary_loops(F)
    none = [np.zeros(0, dtype=np.int64)]
    corners = np.concatenate(
        [loop[boundary_corners(V, loop, options["corner_angle"], scale=edge)] for loop in loops] + none
    )
    # (the borders' paths end where they meet the boundary)
    paths = edge_paths(chart_borders(F, labels), len(V), np.concatenate(loops + none))
    return _remesh_along_paths(
        V, F, paths, faces, corners, sizing, data,
        dict(repairs, levels=options["levels"]), dict(options, corner_angle=180.0), name="chart",
        topology=(euler_characteristic(F), len(loops)),
    )


def _remesh_along_paths(
    V, F, paths, faces, corners, sizing, data, stats, options, name="crowded", min_levels=None, done=None, held=None,
    topology=(1, 1), min_piece_faces=MIN_PIECE_FACES, whole_levels=None,
):
    """:func:`remesh` of a disk cut along ``paths`` (from :func:`crowded_cuts`, where
    its map crowds parts of the boundary, or :func:`crease_cuts`) into pieces, each
    remeshed on its own map with a share of the faces by area (counted times sizing^-2
    with a ``sizing`` field, (n,) or None), its boundary fixed along the paths and on
    the boundary edges between two ``held`` vertices ((n,) bool: the disk's own boundary
    where that is a seam too; none where None), the rest of it sliding as a disk's
    does, the paths' ends and the input vertices ``corners`` on it for corners, and the
    boundary edge length planned for the whole (so that both sides of a path get the same vertices; in the
    metric of the sizing field, which each piece scales to a largest value of 1, so with
    the edge length scaled as the piece's field), all at the same levels, and welded along the paths
    (:func:`qcremesh.mesh.cut.weld_along_paths`, every level; a coarse level that does
    not weld into a disk, or into a surface of the Euler characteristic and boundary loops
    ``topology`` where that is given, is dropped). A path that would cut off a piece of fewer than
    ``min_piece_faces`` faces is not cut; nor, for the crowded cuts (``name`` "crowded"), one
    that would cut off a piece with an interior vertex planned at fewer levels than one
    below the largest piece (than ``min_levels`` where given; None where a piece then
    takes fewer; than ``whole_levels`` too where given, the levels of the remesh of the
    disk whole, which the pieces then lose nothing against)
    (:func:`~qcremesh.remeshing.disk_remesh.planned_levels`; every piece would take them:
    Hand1.off's cut disk at half its face count, two pieces of a few hundred faces at no
    level, took 11.9 s instead of 5.3 s, mean q 0.966 instead of 0.987). The
    creases' cuts keep such pieces (a mesa whose top is a sixth of its area lost its
    rim's crease to the level rule, Hausdorff 1.3 %; a step's steep band one face wide,
    a strip, lost both its creases), and a strip (a piece without an interior vertex, as
    a neck one face wide that a crowded cut crosses at a chord gives) is split 1-to-4
    first. Where a piece is
    then not a disk (a crease's closed loop whose join to the boundary went with a small
    piece), None.
    Joined as :func:`join_pieces` with ``stats[name + "_cuts"]`` (the paths cut) and
    ``stats[name + "_piece_faces"]``; None where the output does not weld into a disk (a
    surface of ``topology``). The seams of the crowded cuts and of charts (``name``
    "chart") are smoothed (:func:`_seams_smoothed`). ``done``, a dict, keeps each
    piece's remesh by its vertices, faces, share, corners and levels, and a piece found
    in it is not remeshed again (the rounds of :func:`_recut_at_slivers` change only the
    pieces they cut; its times are not counted again)."""
    density = None if sizing is None else sizing.max() / sizing
    while True:
        if not paths:
            return None
        cut = path_edges(paths)
        F_cut, parent = cut_along_edges(F, cut, len(V))
        count, label = connected_components(F_cut, len(parent))
        V_cut = V[parent]
        cut_density = None if density is None else density[parent]
        weight = doublearea(V_cut, F_cut)
        if cut_density is not None:
            weight = weight * (cut_density[F_cut] ** 2).mean(1)
        area = np.bincount(label, weight, count)
        edge = output_edge_length(V, F, faces, density)
        # the vertices whose boundary edges each piece keeps: the paths' and ``held``
        keeps = np.zeros(len(V), dtype=bool) if held is None else held.copy()
        keeps[np.concatenate(paths)] = True
        ends = np.isin(parent, np.concatenate([np.concatenate([p[[0, -1]] for p in paths]), corners]))
        on_boundary = np.zeros(len(parent), dtype=bool)
        on_boundary[boundary_edges(F_cut).ravel()] = True
        pieces, small, members, inner = [], [], [], []
        for k, (used, local) in enumerate(split_pieces(F_cut, label, count)):
            members.append(parent[used])
            piece_data = {key: np.asarray(v)[parent][used] for key, v in data.items()} if data else data
            share = int(round(faces * area[k] / area.sum()))
            pieces.append((V_cut[used], local, share, np.flatnonzero(ends[used]), piece_data,
                           None if cut_density is None else cut_density[used]))
            inner.append(not on_boundary[used].all())
            if share < min_piece_faces:
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
            least = planned[int(np.argmax([piece[2] for piece in pieces]))] - 1 if min_levels is None else min_levels
            if whole_levels is not None:
                least = min(least, whole_levels)
            small = [vertices for vertices, level in zip(members, planned) if level is not None and level < least]
        if not small:
            break
        # The paths that cut off a piece too small or (with the level rule) planned at too
        # few levels go.
        kept = [p for p in paths if not any(np.isin(p[[0, -1]], u).all() for u in small)]
        if len(kept) == len(paths):
            return None
        paths = _joined_paths(kept, boundary_edges(F))
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
        # the smallest first: with min_levels, a piece that takes fewer ends it soonest
        for k in np.argsort([piece[2] for piece in pieces], kind="stable"):
            Vk, Fk, share, corners, piece_data, dk = pieces[k]
            if results[k] is None or results[k].stats["levels"] > levels:
                key = (members[k].tobytes(), Fk.tobytes(), share, corners.tobytes(), levels)
                if done is not None and key in done:
                    results[k] = replace(done[key], times={})
                else:
                    # the piece's field scaled to a largest value of 1: its density to a least of 1
                    scale = 1.0 if dk is None else dk.min()
                    results[k] = remesh(
                        Vk, Fk, share, fixed_boundary=keeps[members[k]], corners=corners,
                        boundary_edge_length=edge / scale,
                        sizing=None if dk is None else 1.0 / dk, data=piece_data, **dict(options, levels=levels),
                    )
                    if done is not None:
                        done[key] = results[k]
                if min_levels is not None and results[k].stats["levels"] < min_levels:
                    return None
        used = [r.stats["levels"] for r in results]
        if min(used) == max(used):
            break
        levels = min(used)
    joined = join_pieces(results, dict(stats, **{f"{name}_cuts": len(paths)}), f"{name}_piece_faces")
    segments = [V[p] for p in paths]
    welded = weld_levels(joined.levels, lambda X, Fo, tol: weld_along_paths(X, Fo, segments, tol), *topology)
    if welded is None:
        return None
    (Vo, Fo, kept), hierarchy = welded
    out_data = {k: np.asarray(v)[kept] for k, v in joined.data.items()}
    if name in ("crowded", "chart"):
        Vo, hierarchy, out_data = _seams_smoothed(
            Vo, Fo, hierarchy, out_data, V, F, path_edges(paths), data, options, joined.times,
            CHART_FREE_SWEEPS if name == "chart" else 0,
        )
    return RemeshResult(
        Vo, Fo, joined.uv, hierarchy, out_data, joined.disk_levels, joined.mu, joined.stats, joined.times
    )


def _seams_smoothed(Vo, Fo, levels, out_data, V, F, seam, data, options, times, free_sweeps=0):
    """A remesh welded along the input edges ``seam`` with the vertices around them
    smoothed (:func:`~qcremesh.remeshing.seams.smooth_seams`, with ``free_sweeps``, the
    creases kept by ``options["creases"]`` held): its vertices, its ``levels`` (each a
    prefix of them) and its ``out_data`` at the new positions; the time is added to
    ``times["relax"]``."""
    started = time.perf_counter()
    held = None if options.get("creases") is None else sharp_edges(V, F, options["creases"])
    Vo, out_data = smooth_seams(Vo, Fo, V, F, seam, held, data, out_data, free_sweeps=free_sweeps)
    times["relax"] = times.get("relax", 0.0) + time.perf_counter() - started
    return Vo, [(Vo[: len(X)], f) for X, f in levels], out_data


def _joined_paths(paths, border):
    """The ``paths`` whose two ends each lie on the ``border`` edges or on another of
    them, dropped until every one does (a path of a second round of cuts that ends on
    one of the first, which went, would cut a slit)."""
    on_border = np.unique(border)
    while True:
        joined = [
            np.isin(p[[0, -1]], np.concatenate([on_border] + [q for j, q in enumerate(paths) if j != i])).all()
            for i, p in enumerate(paths)
        ]
        if all(joined):
            return paths
        paths = [p for p, ok in zip(paths, joined) if ok]


def _fewer_slivers(result, q, again):
    """``again`` (a RemeshResult or None) where it has fewer faces below QUALITY_FLOOR
    than ``result`` (whose radius ratios are ``q``), or as many and a larger smallest
    radius ratio, else ``result``, with the times of both; its radius ratios; and whether
    ``again`` was kept."""
    better = False
    if again is not None:
        q_again = radius_ratio(again.V, again.F)
        a, b = np.count_nonzero(q_again < QUALITY_FLOOR), np.count_nonzero(q < QUALITY_FLOOR)
        better = bool(a < b or (a == b and q_again.min() > q.min()))
    kept, other = (again, result) if better else (result, again)
    if other is not None:
        for stage, seconds in other.times.items():
            kept.times[stage] = kept.times.get(stage, 0.0) + seconds
    return kept, q_again if better else q, better


def _recut_at_slivers(V, F, paths, faces, corners_of, sizing, data, stats, options, result, done, held=None):
    """``result`` of :func:`_remesh_along_paths` along the crowded ``paths``, or, where it
    has faces below QUALITY_FLOOR, the pieces holding them are cut again where their own
    maps crowd (:func:`~qcremesh.remeshing.cut_paths.pieces_crowded_cuts`: cutting off a
    part changes the map of what is left) and the remesh along all the paths kept where
    it has fewer faces below the floor (or as many and a larger smallest radius ratio,
    :func:`_fewer_slivers`); and so on, up to RECUT_ROUNDS rounds, while each is kept
    (``stats["crowded_recut"]``, where tried: the rounds kept; the times are of all).
    face-YH.off at half its face count: a flap of its scan's border, 0.5 % of the area of
    the largest piece, that piece's map crushed to 1e-10 of its area on the surface, had
    no output vertex inside, a fan of slivers (min radius ratio 0.002, Hausdorff distance
    1.31 % of the diagonal); cut off, 0.012 and 0.23 % (a second round is not kept). A
    range scan's border (pymeshlab's sample face000.ply, the part above y = 60): a blob
    behind a neck one to two faces wide, cut off, left the neck crowded in what was left:
    three rounds at its face count, min q 0.025 -> 0.350, Hausdorff distance 2.96 -> 0.37
    %. ``corners_of(paths)`` gives the corners of the pieces along ``paths``; ``done`` the
    pieces remeshed so far and ``held`` the vertices held besides the paths' (see
    :func:`_remesh_along_paths`)."""
    cut = path_edges(paths)
    recuts = None
    q = radius_ratio(result.V, result.F)
    for _ in range(RECUT_ROUNDS):
        slivers = q < QUALITY_FLOOR
        if not slivers.any():
            break
        more = pieces_crowded_cuts(V, F, cut, faces, where=result.V[result.F[slivers]].mean(1))
        if not more:
            break
        more_cut = np.concatenate([cut, path_edges(more)])
        paths = edge_paths(more_cut, len(V), stops=boundary_edges(F).ravel())
        again = _remesh_along_paths(
            V, F, paths, faces, corners_of(paths), sizing, data, stats, options, min_levels=result.stats["levels"],
            done=done, held=held,
        )
        result, q, better = _fewer_slivers(result, q, again)
        recuts = (recuts or 0) + better
        if not better:
            break
        cut = more_cut
    if recuts is not None:
        result.stats["crowded_recut"] = recuts
    return result


def _cut_at_slivers(V, F, dm, faces, corners_of, sizing, data, stats, options, result, held=None):
    """``result``, the remesh of the disk (V, F) whole, or, where it has faces below
    QUALITY_FLOOR and its disk map ``dm`` crowds runs of its boundary (:func:`crowded_cuts`)
    though not enough of it to be cut at once (CROWDED_SHARE), the remesh along those
    cuts (:func:`_remesh_along_paths` and :func:`_recut_at_slivers`), where it has fewer
    faces below the floor (:func:`_fewer_slivers`; ``stats["crowded_after_slivers"]``
    says which, where tried; the times are of both). A scan's border with a protrusion
    behind a neck one or two faces wide: the map crushes what lies beyond, a fan of
    slivers there. Where no run is long enough for the crowded cuts, the runs from
    SLIVER_RUN_EDGES output edges are cut off, into pieces from SLIVER_PIECE_FACES faces
    (a flap of the border a few edges long); the pieces may take as few levels as the
    whole ended at. ``held`` as for :func:`_remesh_along_paths`."""
    q = radius_ratio(result.V, result.F)
    if q.min() >= QUALITY_FLOOR:
        return result
    paths, smallest = crowded_cuts(V, F, dm, faces), MIN_PIECE_FACES
    if not paths:
        paths, smallest = crowded_cuts(V, F, dm, faces, SLIVER_RUN_EDGES), SLIVER_PIECE_FACES
    if not paths:
        return result
    done = {}
    again = _remesh_along_paths(
        V, F, paths, faces, corners_of(paths), sizing, data, stats, options, done=done, held=held,
        min_piece_faces=smallest, whole_levels=result.stats["levels"],
    )
    if again is not None:
        again = _recut_at_slivers(V, F, paths, faces, corners_of, sizing, data, stats, options, again, done, held)
    kept, _, better = _fewer_slivers(result, q, again)
    kept.stats["crowded_after_slivers"] = better
    return kept


def _remesh_piece(V, F, share, sizing, fixed_boundary, data, options):
    """:func:`remesh` of one piece of a mesh in several at its ``share`` of the faces, or,
    where that does not weld back, or welds into fewer than half of them, or farther from
    the piece than PIECE_MAX_DISTANCE of its diagonal, or into faces of mean radius ratio
    below PIECE_MEAN_QUALITY, at twice as many, while that is at most PIECE_FACE_RATIO
    times its own face count: (the last remesh that welded into at least half the faces
    asked for and close enough, or None, and the faces it was asked for). Any other has
    lost the piece's shape (pyvista's ant.ply at half its face count: a leg of 88 faces
    welded into a tetrahedron at 32 asked for, and at no count up to 256, the Hausdorff
    distance of the whole 17 %)."""
    asked, welded = share, (None, share)
    limit = PIECE_MAX_DISTANCE * np.linalg.norm(V.max(axis=0) - V.min(axis=0))
    while True:
        try:
            result = remesh(V, F, asked, sizing=sizing, fixed_boundary=fixed_boundary, data=data, **options)
            if 2 * len(result.F) >= asked and hausdorff_distance(V, F, result.V, result.F)[0] <= limit:
                welded = result, asked
                if radius_ratio(result.V, result.F).mean() >= PIECE_MEAN_QUALITY:
                    return welded
        except WeldError:
            pass
        if 2 * asked > PIECE_FACE_RATIO * len(F):
            return welded
        asked *= 2


def _remesh_pieces(V, F, label, count, faces, sizing, fixed_boundary, data, repairs, options):
    """:func:`remesh` of a mesh in several connected pieces (``label`` (m,), the piece of
    each face, 0..count-1): each piece remeshed on its own with a share of ``faces``
    proportional to its area (at least 4), or more (:func:`_remesh_piece`;
    ``stats["pieces_raised"]``, how many), and the results joined (:func:`join_pieces`,
    with ``stats["pieces"]``). A piece none of whose remeshes welds back into enough faces
    close to it is kept as it is (``stats["pieces_kept"]``, their numbers from 1), unless
    all are. A piece's error
    names the piece."""
    area = np.bincount(label, doublearea(V, F), count)
    results, raised, kept = [], 0, []
    for k, (used, local) in enumerate(split_pieces(F, label, count)):
        share = max(int(round(faces * area[k] / area.sum())), 4)
        piece_sizing = sizing if sizing is None or isinstance(sizing, str) else np.asarray(sizing)[used]
        piece_data = {name: np.asarray(v)[used] for name, v in data.items()} if data else data
        try:
            result, asked = _remesh_piece(V[used], local, share, piece_sizing, fixed_boundary, piece_data, options)
        except MeshError as error:
            raise type(error)(f"piece {k + 1} of {count} ({len(local)} faces, {share} asked for): {error}") from error
        if result is None:
            kept.append(k + 1)
            result = RemeshResult(V[used], local, np.zeros((len(used), 2)), [(V[used], local)], piece_data or {})
        elif asked > share:
            raised += 1
        results.append(result)
    if len(kept) == count:
        raise WeldError(
            f"none of the {count} pieces welds back into its topology at up to {PIECE_FACE_RATIO} times its face count"
        )
    stats = dict(repairs, pieces=count)
    if raised:
        stats["pieces_raised"] = raised
    if kept:
        stats["pieces_kept"] = kept
    return join_pieces(results, stats, "piece_faces")


def _finer_input(V, F, dm, faces, data):
    """The disk (V, F) refined where it is coarser than the output and its map ``dm`` far
    from conformal (see COARSE_MAP_MU): its vertices, faces, per-vertex data and disk map,
    or None where such faces hold too little of its area or the finer map is not much
    nearer conformal (or the refined disk is not one the map takes: the sheared star of
    tests/test_remesh.py, a planar disk with 20 faces folded over others, cut along its
    edges had edges of three faces)."""
    area = doublearea(V, F)
    enough = COARSE_SHARE * area.sum()
    far = np.flatnonzero(np.abs(dm.mu) > COARSE_MAP_MU)
    if area[far].sum() <= enough:
        return None
    longest = LONG_EDGE_RATIO * output_edge_length(V, F, faces)
    coarse = far[face_edge_lengths(V, F[far]).max(axis=1) > longest]
    if area[coarse].sum() <= enough:
        return None
    if radius_ratio(V, F).min() >= WELL_SHAPED:
        V, F, data, _ = upsampled(V, F, data, None, lambda G: 4 * len(G) >= faces)
    else:
        V, F, data, _ = refined(V, F, data, None, longest)
    try:
        finer = disk_conformal_map(V, F)
    except MeshError:
        return None
    if finer.mean_abs_mu > COARSE_GAIN * dm.mean_abs_mu:
        return None
    return V, F, data, finer


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
        # (the levels and the rest of what the remesh of the split strip measured stand)
        result.stats = {**stats, **result.stats}
        result.stats["subdivided_input"] = result.stats.get("subdivided_input") or len(F_fine)
        return result
    if corners is not None and len(corners):
        raise ValueError("corners are taken only on a disk")
    return _remesh_cut(V, F, faces, sizing, data, stats, options)


def faces_for_edge_length(V, F, edge_length):
    """The number of equilateral triangles of side ``edge_length`` that cover the area A
    of the surface (V, F), round(4 A / (sqrt(3) edge_length^2)): :func:`remesh`'s face
    count for an ``edge_length``.

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
    edge_length : float
        Positive and finite, in the units of ``V``.

    Returns
    -------
    int
        At least 4 (ValueError where the area takes fewer).
    """
    length = float(edge_length)
    if not (np.isfinite(length) and length > 0):
        raise ValueError(f"edge_length must be positive and finite, got {edge_length!r}")
    count = round(2 * doublearea(V, F).sum() / (np.sqrt(3) * length**2))
    if count < 4:
        raise ValueError(
            f"edge_length {length:g} is too long for this surface: its area takes {count} equilateral "
            "triangles of that side, and a remesh needs at least 4"
        )
    return count


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
    snap=SNAP_REACH,
    teichmuller_iterations=5,
    retries=2,
    sizing=None,
    fixed_boundary=False,
    corners=None,
    boundary_edge_length=None,
    cut_crowded=True,
    creases=None,
    weld_seams=None,
    data=None,
    progress=None,
    edge_length=None,
):
    """Remesh a triangle mesh of manifold surfaces (disks, surfaces with holes, closed
    surfaces, handles; one piece or several) into a regular, semi-regular one.

    A surface that is not a disk is cut open into one along its edges
    (:func:`qcremesh.mesh.cut.cut_to_disk`: loops around its handles, paths from each
    hole to the longest boundary loop, a closed one of genus 0 slit between its two
    vertices farthest apart along its principal axis), remeshed with the cut's sides held
    (``fixed_boundary`` over the cut's vertices; the surface's own boundary loops slide as
    a disk's does) and the cut's ends and branch points as ``corners`` (so that the two
    sides of each cut get the same vertices) and closed again (:func:`_remesh_cut`);
    several pieces are remeshed each (:func:`_remesh_pieces`). A disk whose map crowds
    much of its boundary beyond what the landmarks resolve (long protrusions: a camel
    cut open along slits, a strip more than about 10 times as long as wide) is cut
    where it crowds into pieces remeshed on their own maps and welded back
    (:func:`_remesh_along_paths`; ``stats["crowded_cuts"]``,
    ``stats["crowded_piece_faces"]``), with the sizing field where there is one.

    Where the validation refuses the input for faces listed more than once (which make
    their edges non-manifold), faces turned against their neighbours, or for needles and
    caps (faces of zero area or within rounding of it), these are mended first, the
    surface kept: repeated faces kept once (``stats["duplicate_faces"]``), faces
    reversed to the majority's orientation
    (``stats["reoriented_faces"]``), needles merged and caps flipped away
    (``stats["repaired_needles"]``, ``stats["repaired_caps"]``). A disk with every vertex
    on its boundary, or with much of its area in faces far larger than the output's on
    which its map is far from conformal (a few large faces; a CAD tessellation's or a
    revolved shape's needles), is refined first where that brings the map nearer
    conformal, the surface kept (``stats["subdivided_input"]``, the faces it then has; see
    ``COARSE_MAP_MU``).

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
    edge_length : float, optional
        Mean output edge length wanted, in the units of ``V``, instead of ``faces``: the
        count of equilateral triangles of that side that cover the surface's area,
        4 A / (sqrt(3) edge_length^2) (with a sizing field, the edges are graded about
        it).
    levels : int
        Subdivision levels above the base mesh (the base mesh has about faces / 4^levels
        faces). Fewer are used where the base mesh would get under 100 faces or fewer
        interior landmarks than boundary ones, or where the first CVT's cells are far
        from equal on the surface (``MAX_CELL_SPREAD``); with ``retries``, fewer are
        tried where the best draw leaves a face below a radius ratio of 0.3 or more than
        0.1 % of the input's area farther than twice ``snap`` from the output
        (``FAR_SHARE``, ``FAR_REACHES``), and the output that follows the surface, then
        the one with the largest smallest radius ratio, is kept (the levels tried are
        ``stats["levels_tried"]``, those given up with the reason
        ``stats["levels_fallbacks"]``, the level used ``stats["levels"]``).
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
    snap : float
        After the sweeps, the input vertices farther than ``snap`` mean output edge lengths
        from the output (the bottoms of pockets and the tips it cuts across) pull output
        vertices onto them (see :mod:`qcremesh.remeshing.snap`); 0 leaves them, for a
        mesh a little more regular and farther from the input, sooner. Measured at 0
        against 0.5 on the 16 benchmark runs of the eight disk meshes (their face count /
        half; seed 0): Hausdorff distance human_face 0.36 / 0.65 -> 1.12 / 1.65 %,
        human_brain 0.38 / 0.55 -> 0.96 / 1.19 %, head_neck_cut 0.22 / 0.39 -> 0.32 / 0.50
        %, venus 1.53 / 2.29 -> 1.86 / 3.17 %; share of faces above 0.9 human_brain 99.0 /
        97.7 -> 99.4 / 99.1 %, human_face 99.1 / 98.0 -> 99.4 / 98.7 %; mean radius ratio
        up by at most 0.006 (camel_b at half); about a third less time (human_brain 5.0 /
        3.0 -> 3.1 / 1.9 s); foot and fran_cut, which have no input vertex that far, the
        same. Only with ``relax``.
    teichmuller_iterations : int
        Maximum number of QC iterations of the Teichmueller map (from the linear
        subdivision, the quality of the output changes little after the first few).
    retries : int
        Where the output's smallest radius ratio is below 0.3 after the relaxation (its
        search ends in a local optimum that depends on the landmarks) on at most 16
        faces (more come from the surface, not the draw), the landmarks are drawn again
        from another CVT initialization, up to this many times, and the draw with the
        largest smallest radius ratio is kept (``stats["draws"]`` is the number
        made). Where the best draw still has such a face, the same is done at one level
        fewer, down to none, and the levels with the largest smallest radius ratio kept
        (``stats["levels_tried"]``): a part of the disk narrower than the base mesh's
        spacing gets landmarks only at fewer levels. Only with ``relax``, ``retries``
        and a method that draws landmarks.
    sizing : (n,) float or "curvature", optional
        Edge length wanted at each input vertex relative to the others (only the ratios
        count: the face count sets the scale), or ``"curvature"`` for
        :func:`qcremesh.adaptive.sizing.curvature_sizing` at the output's mean edge
        length (edges from 0.4 to 2 times that length, scaled to even out how far the
        surface bends away from them).
        The landmarks spread the surface area weighted by sizing^-2 and the boundary
        ones, and the relaxation's boundary vertices, the boundary length weighted by
        sizing^-1; the interior keeps the grading of the landmarks' connectivity. Not
        with ``"uniform"``.
    fixed_boundary : bool or (n,) bool
        The boundary landmarks spaced by arc length itself (not smoothed at their
        spacing), and the output's boundary vertices spaced evenly by arc length between
        the boundary corners (all around where there is none) and kept there through
        the relaxation (see :func:`qcremesh.remeshing.relax.relax_on_surface`): parts of
        the border that are the same polyline between corners get the same vertices
        (the two sides of a cut). An array over the input vertices keeps them there
        only on the boundary edges between two True vertices (a piece cut off a disk:
        its cuts), the others sliding as without (all kept where the input is
        subdivided first). Needs ``relax``.
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
        back (:func:`_remesh_along_paths`), and split a surface of genus CHART_GENUS or
        more into charts (:func:`_remesh_charts`); without, it is remeshed whole (the
        levels planned for the whole, the crowded parts less regular), a surface of
        higher genus cut open into one disk.
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
    weld_seams : bool or None
        True: first merge the boundary vertices at the same points as others
        (:func:`qcremesh.mesh.cut.weld_seams`): a surface written with its seams split
        (a textured mesh, one vertex per texture coordinate), whose seams are otherwise
        boundary, in the output too, is remeshed whole
        (``stats["welded_seam_vertices"]``, the vertices merged away; the data and
        sizing of a group are those of its first vertex, so texture coordinates, which
        jump across a seam, come out wrong on the faces beside it; the corners
        renumbered; where boundaries meet at points, the vertex where sheets then touch
        is split as the input's own are). False: the seams stay boundary. None (the
        default): merged where the whole boundary is seams
        (:func:`qcremesh.mesh.cut.boundary_is_seams`: a CAD part written face by face,
        as STL files are) or the mesh is a triangle soup
        (:func:`qcremesh.mesh.validate.is_triangle_soup`), no ``fixed_boundary`` is
        given, and every array of ``data`` has the same values at the two sides of each
        seam (where texture coordinates or a crease's normals differ, the seams are
        there for them) (``stats["welded_seams_by_default"]``).
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
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
    V, F = as_mesh_arrays(V, F)
    V = in_space(V)
    data = check_data(data, len(V))
    if edge_length is not None:
        if faces is not None:
            raise ValueError("give faces or edge_length, not both")
        faces = faces_for_edge_length(V, F, edge_length)
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
    if not (isinstance(snap, numbers.Real) and np.isfinite(snap) and snap >= 0):
        raise ValueError(f"snap must be a reach >= 0 in output edge lengths, got {snap!r}")
    if creases is not None:
        check_crease_angle(creases)
    if creases is not None and (relax == 0 or method == "uniform"):
        raise ValueError("keeping creases needs the relaxation (relax > 0) and a method other than 'uniform'")
    seams = None
    if np.ndim(fixed_boundary):
        seams = np.asarray(fixed_boundary, dtype=bool)
        if seams.shape != (len(V),):
            raise ValueError(f"fixed_boundary must be a bool or one per vertex ({len(V)}), got shape {seams.shape}")
        fixed_boundary = True
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
    levels = levels_above_min_base(faces, levels)
    stats = {"levels": levels}
    if weld_seams is None:
        weld_seams = bool(
            seams is None and not fixed_boundary and (boundary_is_seams(V, F) or is_triangle_soup(F))
            and _same_across_seams(V, F, data)
        )
        if weld_seams:
            stats["welded_seams_by_default"] = True
    if weld_seams:
        if seams is not None:
            raise ValueError("weld_seams takes no fixed_boundary per vertex")
        V, F, kept, merged = cut_weld_seams(V, F)
        if len(kept) < len(merged):
            stats["welded_seam_vertices"] = len(merged) - len(kept)
            data = {k: np.asarray(v)[kept] for k, v in data.items()} if data else data
            sizing = sizing if sizing is None else sizing[kept]
            corners = corners if corners is None else np.unique(merged[corners][merged[corners] >= 0])
    clock = StageTimes(progress)

    options = dict(
        levels=levels, method=method, seed=seed, corner_angle=corner_angle, cvt_iterations=cvt_iterations,
        relax=relax, snap=snap, teichmuller_iterations=teichmuller_iterations, retries=retries,
        cut_crowded=cut_crowded, creases=creases, progress=progress,
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
            if seams is not None:
                seams = seams[kept]
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
    # (faces large or long beside the output's, see COARSE_MAP_MU; not measured against a
    # graded edge length)
    finer = _finer_input(V, F, dm, faces, data) if sizing is None else None
    if finer is not None:
        V, F, data, dm = finer
        stats["subdivided_input"] = len(F)
        seams = None
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
        crowded_paths = crowded_cuts(V, F, dm, faces) if cut_crowded and crowded else []
        if creases is not None:
            sharp = sharp_edges(V, F, creases)
            stats["crease_edges"] = len(sharp)
            if len(sharp):
                attempts.append(("crease", crease_cuts(V, F, sharp, crowded_paths, faces)))
        if crowded_paths:
            attempts.append(("crowded", crowded_paths))
    # the boundary vertices at the same points as the paths' ends (their twins on the
    # other side of a cut that the caller welds) are corners too
    twins = coincident_pairs(V, bnd) if fixed_boundary and attempts else None

    def corners_of(paths):
        given = np.zeros(0, dtype=np.int64) if corners is None else corners
        if twins is not None:
            ends = np.concatenate([p[[0, -1]] for p in paths])
            given = np.union1d(given, twins[np.isin(twins, ends).any(axis=1)].ravel())
        return given

    # the vertices whose boundary edges the pieces keep besides the paths': this disk's
    # own, where its boundary is held (a seam of a surface cut open)
    held = seams if seams is not None else np.full(len(V), bool(fixed_boundary))
    done = {}
    for name, paths in attempts:
        try:
            result = _remesh_along_paths(
                V, F, paths, faces, corners_of(paths), sizing, data, stats, options, name, done=done, held=held
            )
        except ValueError:
            if name != "crease":
                raise
            # pieces that the remesh refuses (featuretype.STL welded at its cracks, a
            # CAD part of genus 9 with fillets a face wide: a piece's corner off its
            # boundary): remeshed without the creases, as where they do not weld
            result = None
        if result is not None and name == "crowded":
            result = _recut_at_slivers(
                V, F, paths, faces, corners_of, sizing, data, stats, options, result, done, held
            )
        if result is not None:
            result.times["parameterize"] = result.times.get("parameterize", 0.0) + clock.times["parameterize"]
            return result
        if name == "crease":
            stats["creases_kept"] = False
    # (the numbers before the whole disk's remesh, for a remesh along crowded cuts)
    before = dict(stats)
    result = remesh_disk(
        V, F, dm, faces, levels=levels, method=method, seed=seed, corner_angle=corner_angle,
        cvt_iterations=cvt_iterations, relax=relax, snap=snap, teichmuller_iterations=teichmuller_iterations,
        retries=retries, sizing=sizing, fixed_boundary=fixed_boundary if seams is None else seams, corner_at=corner_at,
        boundary_edge_length=boundary_edge_length, data=data, stats=stats, clock=clock,
    )
    if attempts or boundary_edge_length is not None or relax == 0 or method == "uniform" or not cut_crowded:
        return result
    return _cut_at_slivers(V, F, dm, faces, corners_of, sizing, data, before, options, result, held)
