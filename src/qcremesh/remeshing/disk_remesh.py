"""The paper's Algorithm 2 (Choi, Gu & Lui) on a disk whose conformal map is known, with
the projection back onto the surface.

1. Density: the area distortion rho of the parameterization (Eq. 14), which the landmarks
   follow by spreading the surface area itself.
2. Landmarks: boundary points spaced uniformly by surface arc length (sharp boundary
   corners included) and interior points from a CVT of the disk whose cells are taken on
   the surface, so that their images are uniform on the surface (see
   :mod:`qcremesh.adaptive.landmarks`).
3. Base mesh: the Delaunay triangulation of the landmarks.
4. Subdivision: ``levels`` times 1-to-4, new boundary vertices on the circle.
5. Teichmueller map: the landmark-matching Teichmueller map of the subdivided mesh, by
   the QC iteration started from the linear subdivision, with each face measured against
   an equilateral triangle (see :mod:`qcremesh.beltrami.teichmuller`). With the
   relaxation of step 7, which goes coarse to fine, the map is that of the level below
   the output, whose subdivision the relaxation finishes.
6. Projection: every vertex of the adaptive disk mesh is located in the parameterization
   and its position interpolated barycentrically on the input surface; boundary vertices
   are interpolated along the input boundary polyline (:mod:`qcremesh.remeshing.project`).
7. Beyond the paper, optional (``relax``): tangential relaxation on the surface and the
   searches that raise the minimum quality and the share of well-shaped faces
   (:mod:`qcremesh.remeshing.relax`).

:func:`qcremesh.remeshing.pipeline.remesh` checks and mends the input, computes the map
and takes surfaces that are not disks, or disks that its map crowds, apart into disks
before it comes here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ..adaptive.basemesh import (
    delaunay_disk_mesh,
    flip_for_surface_quality,
    flip_for_valence,
    hexagonal_disk_points,
    subdivide_disk_mesh,
    surface_quality,
)
from ..adaptive.landmarks import boundary_angles, boundary_landmarks, cvt_landmarks, interpolate_on_boundary
from ..adaptive.samples import area_samples
from ..beltrami.coefficient import coherent_mu
from ..beltrami.teichmuller import teichmuller_map
from ..geometry.distance import point_mesh_distance
from ..geometry.operators import doublearea, vertex_areas, vertex_normals
from ..geometry.quality import corner_radius_ratio_bound, radius_ratio, triangle_angles
from ..geometry.threads import query_workers
from ..geometry.vectors import norm
from ..mesh.subdivide import upsample
from ..mesh.topology import boundary_edges, boundary_loop, face_edge_lengths, vertex_face_incidence
from .min_quality import QUALITY_FLOOR
from .onsurface import star_distance
from .project import project_to_surface
from .relax import SNAP_REACH, relax_on_surface
from .result import RemeshResult, StageTimes

__all__ = [
    "MAX_REDRAWN_SLIVERS",
    "MIN_BASE_FACES",
    "levels_above_min_base",
    "output_edge_length",
    "planned_levels",
    "remesh_disk",
]

# Fewest base-mesh faces: below this the face count of the output, a multiple of
# 4^levels times the base mesh's, cannot come within a few percent of the request, so
# fewer levels are used.
MIN_BASE_FACES = 100

# The disk map is taken as far from conformal around an input vertex where its Beltrami
# coefficient, averaged as a complex number over the vertex's faces and then 3 times over
# its neighbours, has a modulus above NONCONFORMAL_MU: the average cancels the |mu| that
# the map has on skinny triangles of a conformal map (a jittered grid: mean |mu| 0.19,
# 0.4 % of the vertices above 0.3) and keeps a coherent stretch (a strip 8 times as long
# as wide, whose ends the map crowds: 12 %; camel_b.obj: 31 %; the scans: at most 0.1 %).
# Where more than NONCONFORMAL_SHARE of the vertices are, the base mesh's edges around
# them are flipped to raise the quality on the surface.
NONCONFORMAL_MU = 0.3
NONCONFORMAL_SHARE = 0.01
NONCONFORMAL_RINGS = 3

# The landmarks cannot follow the surface where its disk map's scale changes by a large
# factor across one base-mesh edge: a tube 40 long and of radius 1 at 1,700 faces gets base
# edges 2.4 long with two levels, across which the scale changes by e^2.4, and the surface
# areas of the CVT's cells have a coefficient of variation of 1.1 (mean radius ratio 0.89,
# a third of the faces due on its far half); 0.16 with one level (0.98). Above
# MAX_CELL_SPREAD, fewer levels are used. The disk meshes of ../shared/data at their face
# count and half of it: 0.16-0.29 (human_brain at half 0.26-0.285 over seeds 0-3); at a
# tenth of it, human_face 0.29 and human_brain 0.36, where one level fewer (none for
# human_brain) raised the mean radius ratio by 0.01-0.02 (seeds 0-1; 0.005-0.01 at a
# quarter of human_brain's count, 0.32) and min q and the Hausdorff distance mostly.
MAX_CELL_SPREAD = 0.28


# An output whose levels cannot follow the surface leaves parts of it out, farther than
# the snapping of the relaxation brings it: at a twentieth of human_face.obj's face count
# (1,700 faces), two levels leave 149 input vertices, 0.54 % of its area, more than an
# output edge from the output (up to 2.1 edges: the nostrils' and lips' pockets, which
# the disk map shrinks inside a base face and the landmarks, about 60, miss), Hausdorff
# distance 6.1 %; with no level, none (at most 0.50 edges, 1.4 %). Where more than
# FAR_SHARE of the input's area lies farther than FAR_REACHES times the snapping's reach
# (one mean output edge length by default) from the output, fewer levels are tried, as
# below the quality floor. human_face at 5-9 % of its face count: 0.48-1.28 % at two
# levels; at twice and four times its face count, where a vertex or two at a nostril
# stay 1.05 edges away, 0.0001-0.0003 %; the disk meshes of ../shared/data at their face
# count and half of it: none (at most 0.56 edges).
FAR_REACHES = 2.0
FAR_SHARE = 1e-3

# The landmarks are drawn again (``retries``) only where at most this many faces are
# below QUALITY_FLOOR: a few slivers come from the draw, many from the surface. Measured
# on the benchmark's runs: first draws with 3 and 8 such faces had none in the next;
# camel_b.obj at half its face count 15 -> 7 (its smallest radius ratio 0.006 -> 0.069);
# face-YH.off's pieces of 584, 105,036 and 53,008 faces, with 17, 59 and 136, had as many
# or more in both redraws (7-9 s each on the largest).
MAX_REDRAWN_SLIVERS = 16

# A base mesh more than this fraction away from its planned face count gets its interior
# landmarks drawn again, their number corrected.
COUNT_SLACK = 0.02

# The CVT of the landmarks samples the disk at the parameterization's vertices, subdivided
# until there are at least this many per landmark.
CVT_SAMPLES_PER_LANDMARK = 20

# Where the 99th percentile of the subdivided samples' face sides is longer than this fraction
# of the base mesh's planned edge, the samples are spread over the faces by area instead
# (adaptive.samples.area_samples). The disk meshes of ../shared/data at their face count
# and half of it: 0.16-0.65; a cone over a fan of 400 slivers: 1.06 and more.
SAMPLE_EDGE_RATIO = 0.8

# So they are too where more than SPARSE_AREA_SHARE of the surface's area lies in faces
# whose longest side, subdivided as the samples are, exceeds SPARSE_SAMPLE_RATIO of the
# base mesh's planned edge (fewer than about 4 samples per landmark's cell there): a
# graded mesh (a CAD or terrain tessellation, an adaptive decimation), whose vertices,
# subdivided until they are enough in all, leave its coarse part with a few samples per
# cell, the CVT's cells uneven on the surface (spread 0.37) and the landmarks planned at
# no level. Measured on random Delaunay disks with a bump, dense on a fifth of their
# area / along a ridge / on the bump and coarse elsewhere (80 % of the area in such
# faces), at their face count: mean q 0.965 / 0.971 / 0.968 -> 0.993 / 0.992 / 0.993,
# min q 0.67 -> 0.76-0.79, 3.1-3.3 s -> 0.8-1.3 s (at half their face count, where the
# 99th percentile above already takes them, the same). The meshes of ../shared/data:
# 0.00-0.19, and 0.33 on camel_b's pieces, none taken.
SPARSE_SAMPLE_RATIO = 0.5
SPARSE_AREA_SHARE = 0.5


def _share_left_out(V, F, Vo, Fo, beyond):
    """The share of the area of the input (V, F) around its vertices (a third of each
    face's) that stand farther than ``beyond`` mean output edge lengths from the output
    surface (Vo, Fo): measured first to the output vertices, then to the faces around
    the nearest (an upper bound of the distance, exact where the nearest face is among
    them), and, where that is still farther, to the whole surface."""
    h = norm(Vo[Fo[:, 1]] - Vo[Fo[:, 0]]).mean()
    tree = cKDTree(Vo)
    gap = tree.query(V, distance_upper_bound=beyond * h, workers=query_workers(len(V)))[0]
    far = np.flatnonzero(np.isinf(gap))
    if len(far) == 0:
        return 0.0
    nearest = tree.query(V[far], workers=query_workers(len(far)))[1]
    d, _ = star_distance(V[far], Vo, Fo, vertex_face_incidence(Fo, len(Vo)), nearest)
    unsure = np.flatnonzero(d > beyond * h)
    d[unsure] = point_mesh_distance(V[far[unsure]], Vo, Fo)[0]
    area = vertex_areas(V, F, len(V))
    return float(area[far[d > beyond * h]].sum() / area.sum())


def _plan(V, F, bnd, faces, levels, density=None):
    """Numbers of boundary and interior landmarks for ``faces`` output faces, the spacing
    of the boundary landmarks along the boundary, and the base mesh's face count wanted.
    With a ``density`` (n,), the inverse of a sizing field, areas are counted times
    density^2 and boundary lengths times density."""
    base_faces = max(faces / 4**levels, 4.0)
    h = output_edge_length(V, F, base_faces, density)
    lengths = np.linalg.norm(V[np.roll(bnd, -1)] - V[bnd], axis=1)
    perimeter = lengths.sum()
    sized = perimeter if density is None else (lengths * (density[bnd] + density[np.roll(bnd, -1)]) / 2).sum()
    nb = max(int(round(sized / h)), 3)
    ni = max(int(round((base_faces - nb + 2) / 2)), 0)
    return nb, ni, perimeter / nb, base_faces


def _levels_with_interior(V, F, bnd, faces, levels, density=None):
    """The most levels, up to ``levels``, at which the base mesh planned by :func:`_plan`
    has at least as many interior landmarks as boundary ones. A base mesh with fewer is
    mostly chords between boundary landmarks, which neither subdivision nor relaxation
    turns into a regular mesh (camel_b.obj, cut open along slits into a disk whose
    boundary is 28 times the square root of its area: 18 interior landmarks against 89 at
    half its face count, mean radius ratio 0.51); with fewer levels the base mesh gets an
    interior."""
    while levels > 0:
        nb, ni, _, _ = _plan(V, F, bnd, faces, levels, density)
        if ni >= nb:
            break
        levels -= 1
    return levels


def planned_levels(V, F, faces, levels, density=None):
    """The levels :func:`remesh_disk` plans for the disk (V, F) at ``faces`` faces (with a
    sizing field 1 / ``density``): fewer where the base mesh would get under
    MIN_BASE_FACES faces or more boundary landmarks than interior ones
    (:func:`_levels_with_interior`), before the CVT's test of its cells."""
    levels = levels_above_min_base(faces, levels)
    return _levels_with_interior(V, F, boundary_loop(F), faces, levels, density)


def levels_above_min_base(faces, levels):
    """The most levels, up to ``levels``, whose base mesh for ``faces`` output faces has
    at least MIN_BASE_FACES faces (or none)."""
    while levels > 0 and faces / 4**levels < MIN_BASE_FACES:
        levels -= 1
    return levels


def output_edge_length(V, F, faces, density=None):
    """The edge length of ``faces`` equilateral triangles of the surface's area (the mean
    output edge length planned); with a ``density`` (n,), the inverse of a sizing field,
    of its area counted times density^2 (the edge length where the density is 1, in its
    metric, as :func:`_plan` measures it)."""
    area = doublearea(V, F).sum() / 2 if density is None else (vertex_areas(V, F, len(V)) * density**2).sum()
    return np.sqrt(4 * area / (np.sqrt(3) * faces))


@dataclass
class _Landmarking:
    """What every draw of the landmarks at one number of levels shares: the plan, the
    boundary landmarks, and the samples of the disk with their points and areas on the
    surface for the CVT."""

    levels: int
    interior: int  # interior landmarks planned
    base_faces: float  # faces of the base mesh planned
    boundary_spacing: float  # of the boundary landmarks along the boundary
    theta: np.ndarray  # (b,) angles of the boundary landmarks
    corner: np.ndarray  # (b,) bool, the corners among them
    corner_faces: np.ndarray  # faces wanted at each corner
    corner_bound: np.ndarray  # the best smallest radius ratio of a fan filling each corner
    lattice_spacing: float = 0.0  # of the hexagonal lattice of "uniform"
    samples_uv: np.ndarray | None = None  # (s, 2) the CVT's samples of the disk
    samples_V: np.ndarray | None = None  # (s, 3) and their points on the surface
    cvt_mass: np.ndarray | None = None  # (s,) the surface area each spreads (times density^2)
    cvt_weight: np.ndarray | None = None  # (s,) the CVT's weight; None without a sizing field
    circle: np.ndarray | None = None  # (b, 2) the boundary landmarks in the disk
    circle_V: np.ndarray | None = None  # (b, 3) and on the surface


def _landmarking(
    V, F, dm, faces, levels, density, method, corner_angle, corner_at, fixed_boundary, boundary_edge_length, stats
):
    """The boundary landmarks and the CVT's samples of the disk (V, F) with disk map ``dm``
    at ``levels`` levels, for ``faces`` output faces (see :func:`remesh_disk`)."""
    bnd = dm.boundary
    nb, ni, boundary_spacing, base_faces = _plan(V, F, bnd, faces, levels, density)
    if method == "uniform":
        spacing = np.sqrt(4 * np.pi / (np.sqrt(3) * max(faces / 4**levels, 4.0)))
        nbu = max(int(round(2 * np.pi / spacing)), 3)
        theta = 2 * np.pi * np.arange(nbu) / nbu
        corner = np.zeros(nbu, dtype=bool)
        return _Landmarking(levels, ni, base_faces, boundary_spacing, theta, corner, np.zeros(0), np.zeros(0), spacing)
    theta, corner = boundary_landmarks(
        V, dm.uv, bnd, nb, corner_angle, None if density is None else density[bnd],
        corners=corner_at, smooth=not np.any(fixed_boundary),
        spacing=None if boundary_edge_length is None else boundary_edge_length * 2**levels,
    )
    stats["boundary_corners"] = int(corner.sum())
    corner_faces = corner_bound = np.zeros(0)
    if corner.any():
        # The sharpest corner kept bounds the smallest radius ratio of the output,
        # up to its boundary edges being chords (a ragged border can have teeth of
        # a few degrees).
        gap = np.abs(np.angle(np.exp(1j * (theta[corner][:, None] - boundary_angles(dm.uv, bnd)[None]))))
        at = bnd[np.argmin(gap, axis=1)]
        angle = np.bincount(F.ravel(), triangle_angles(V, F).ravel(), len(V))[at]
        # the faces a convex corner wants, one per 60 degrees (a reflex one, a
        # slit's end, none: camel_b's mean q moved by 0.001 either way over 4 seeds)
        corner_faces = np.where(angle < np.pi, np.maximum(np.round(angle / (np.pi / 3)), 1), 0)
        corner_bound = corner_radius_ratio_bound(angle)
        stats["sharpest_corner_degrees"] = float(np.degrees(angle.min()))
        stats["corner_quality_bound"] = float(corner_bound.min())
    samples_uv, samples_V, samples_F = dm.uv, V, F
    samples_density = density
    halvings = 0
    while len(samples_uv) < CVT_SAMPLES_PER_LANDMARK * (ni + nb):
        # the points on the surface and in the disk (and the density) subdivided together
        fields = [samples_V, samples_uv] + ([] if density is None else [samples_density])
        both, samples_F = upsample(np.column_stack(fields), samples_F, 1)
        samples_V, samples_uv = both[:, :3], both[:, 3:5]
        samples_density = None if density is None else both[:, 5]
        halvings += 1
    # (each subdivision halves every face's sides: the samples' face sides are the
    # input's, halved, each as often)
    sides = face_edge_lengths(V, F) / 2**halvings
    edge = output_edge_length(V, F, base_faces, density)
    area = doublearea(V, F) / 2
    sparse = area[sides.max(1) > SPARSE_SAMPLE_RATIO * edge].sum() / area.sum()
    if np.percentile(sides, 99) > SAMPLE_EDGE_RATIO * edge or sparse > SPARSE_AREA_SHARE:
        # A fan of slivers, subdivided, samples the surface along their long edges
        # only (in rings around the fan's centre, on which the landmarks then sit), and
        # a graded mesh its coarse part sparsely: the samples are spread over each input
        # face by area instead.
        fields = [dm.uv, V] + ([] if density is None else [density])
        values, surface_area = area_samples(F, area, CVT_SAMPLES_PER_LANDMARK * (ni + nb), fields)
        samples_uv, samples_V = values[0], values[1]
        samples_density = None if density is None else values[2]
    else:
        surface_area = vertex_areas(samples_V, samples_F, len(samples_uv))
    # The measure to spread and, as a CVT places its points with the square root
    # of its weight per unit area, the weight.
    cvt_mass, cvt_weight = surface_area, None
    if density is not None:
        cvt_mass, cvt_weight = surface_area * samples_density**2, surface_area * samples_density**4
    circle = np.column_stack([np.cos(theta), np.sin(theta)])
    circle_V = interpolate_on_boundary(boundary_angles(dm.uv, bnd), V[bnd], theta)
    return _Landmarking(
        levels, ni, base_faces, boundary_spacing, theta, corner, corner_faces, corner_bound, 0.0, samples_uv, samples_V,
        cvt_mass, cvt_weight, circle, circle_V,
    )


def _base_mesh(plan, count, method, cvt_iterations, cvt_seed, run, clock):
    """The CVT's interior landmarks (``count`` of them; the hexagonal lattice for
    ``"uniform"``) and their Delaunay base mesh with the boundary landmarks of ``plan``:
    (uv, F); the CVT's iterations and uniformity go to ``run``."""
    clock.start("landmarks")
    if method == "uniform":
        interior = hexagonal_disk_points(plan.lattice_spacing)
    else:
        cvt = cvt_landmarks(
            plan.samples_uv, plan.cvt_mass, plan.circle, count, weight=plan.cvt_weight, positions=plan.samples_V,
            fixed_positions=plan.circle_V, iterations=cvt_iterations, seed=cvt_seed,
        )
        interior = cvt.points
        run.update(cvt_iterations=cvt.iterations, cvt_uniformity=cvt.uniformity)
    clock.stop("landmarks")
    clock.start("base mesh")
    mesh = delaunay_disk_mesh(plan.theta, interior)
    clock.stop("base mesh")
    return mesh


def _adaptive_mesh(
    V, F, dm, plan, stretch, density, cvt_seed, first, method, cvt_iterations, teichmuller_iterations, relax, snap,
    fixed_boundary, clock,
):
    """The interior landmarks of one draw (``cvt_seed``) to the relaxed output: (disk
    positions, faces, hierarchy, surface positions or None, mu, stats); None when the
    ``first`` draw's CVT cells are too unequal for the levels of ``plan``."""
    run = {}
    levels, theta = plan.levels, plan.theta
    base_uv, base_F = _base_mesh(plan, plan.interior, method, cvt_iterations, cvt_seed, run, clock)
    if first and levels > 0 and run.get("cvt_uniformity", 0.0) > MAX_CELL_SPREAD:
        return None
    kept = len(base_uv) - len(theta)
    if method != "uniform" and kept > 0 and abs(len(base_F) - plan.base_faces) > COUNT_SLACK * plan.base_faces:
        # The base mesh left out the landmarks too close to the boundary (or the CVT
        # some with empty cells), or has more boundary landmarks than planned
        # (corners): a second CVT with the number of interior landmarks corrected in
        # proportion puts the face count back.
        wanted = max((plan.base_faces - len(theta) + 2) / 2, 0.0)
        count = int(round(wanted * plan.interior / kept))
        base_uv, base_F = _base_mesh(plan, count, method, cvt_iterations, cvt_seed, run, clock)
        run.update(cvt_redrawn=True)
    valence_flips = relax > 0 and method != "uniform"
    if stretch is not None or valence_flips:
        on_circle = np.arange(len(base_uv)) < len(theta)
        fields = [V, vertex_normals(V, F)] + ([stretch] if stretch is not None else [])
        base_X, base_up, *base_stretch = project_to_surface(dm.uv, F, dm.boundary, base_uv, on_circle, fields)
        base_up /= np.maximum(norm(base_up), 1e-300)[:, None]
    if stretch is not None:
        base_F, flips = flip_for_surface_quality(base_uv, base_F, base_X, base_stretch[0] > NONCONFORMAL_MU)
        run.update(base_flips=flips)
    if valence_flips:
        # Beyond the paper, with the relaxation: three faces at every boundary
        # landmark but the corners, and at a convex corner one per 60 degrees of
        # its angle (the open box cut along its creases at half its face count: a
        # right-angled corner with three faces, min q 0.335 -> 0.663).
        wanted = 3 * on_circle
        wanted[: len(theta)][plan.corner] = plan.corner_faces
        bound = np.ones(len(base_uv))
        bound[: len(theta)][plan.corner] = plan.corner_bound
        base_F, flips = flip_for_valence(base_uv, base_F, base_X, wanted, bound=bound)
        run.update(base_valence_flips=flips)
        turned = (surface_quality(base_X, base_F, base_up) < 0) & on_circle[base_F].all(1)
        if turned.any() and not (np.ndim(fixed_boundary) == 0 and fixed_boundary):
            # A face turned over on the surface though counter-clockwise in the disk:
            # three boundary landmarks around a reflex corner (of a piece's boundary
            # held along a crowded cut's path that steps across an input edge, say),
            # which no relaxation mends; flipped away. Not on a closed surface cut open
            # (its whole boundary held, True): there such an ear on one side of the cut
            # and one on the other are the same face turned both ways, which the weld
            # drops together. A surface with holes cut open holds its cut's sides only
            # (a mask), and its ears are flipped as a piece's are: its welds hold on
            # ../shared/data and the tests (sparing the ears whose landmarks all have
            # twins in the disk, the cut's sides, acted on camel_b's pieces too, whose
            # slits are such twins and are not welded: at half its face count min q
            # 0.234 -> 0.282 but q > 0.9 85.1 -> 84.7 %; not in).
            near = np.zeros(len(base_uv), dtype=bool)
            near[base_F[turned].ravel()] = True
            base_F, flips = flip_for_surface_quality(base_uv, base_F, base_X, near, up=base_up)
            run.update(base_turned_flips=flips)
    run.update(base_vertices=len(base_uv), base_faces=len(base_F))

    clock.start("subdivide")
    hierarchy = subdivide_disk_mesh(base_uv, base_F, levels)
    uv, Fo = hierarchy[-1]
    clock.stop("subdivide")

    mu = None
    # Where the relaxation starts on the level below the output (coarse to fine).
    coarse_uv = hierarchy[-2][0] if levels > 0 else None
    # With the relaxation, which takes the level below the output first, the
    # Teichmueller map is that level's (a quarter of the faces; the base mesh itself
    # for one level, which the map leaves as it is).
    mapped = -2 if relax > 0 else -1
    if method == "teichmuller" and levels + mapped >= 0:
        clock.start("teichmuller")
        # The source is the equilateral complex of the subdivided mesh and the QC
        # iteration starts from the linear subdivision, which already matches the
        # landmarks (see qcremesh.beltrami.teichmuller).
        map_uv, map_F = hierarchy[mapped]
        tm = teichmuller_map(
            map_uv,
            map_F,
            np.arange(len(base_uv)),
            base_uv,
            boundary=boundary_loop(map_F),
            initial=map_uv,
            reference="equilateral",
            max_iter=teichmuller_iterations,
            smooth=1,
        )
        # A face of a level and its four children of the linear subdivision have
        # the same coefficient (the equilateral frames of the children are the
        # parent's, up to half turns).
        mu = np.repeat(tm.mu, 4 ** (-1 - mapped))
        if mapped == -1:
            uv = tm.uv
        else:
            coarse_uv = tm.uv
        run.update(
            teichmuller_k=float(tm.k),
            teichmuller_iterations=int(tm.iterations),
            teichmuller_converged=bool(tm.converged),
            teichmuller_folded_faces=int(tm.folded_faces),
            teichmuller_guarded_faces=int(tm.guarded_faces),
        )
        clock.stop("teichmuller")

    Vo = None
    if relax > 0:
        clock.start("relax")
        pinned = np.zeros(len(uv), dtype=bool)
        pinned[: len(theta)] = plan.corner
        scale = plan.boundary_spacing
        sweeps = relax
        faces_hint = None
        if method in ("subdivided", "teichmuller") and levels > 0:
            # Coarse to fine: the level below the output takes the sweeps (a quarter of
            # the vertices, twice the reach per sweep), and its relaxed subdivision
            # half as many.
            coarse_F = hierarchy[-2][1]
            coarse_uv, _, coarse_faces = relax_on_surface(
                dm.uv, F, V, coarse_uv, coarse_F, iterations=relax, pinned=pinned[: len(coarse_uv)],
                boundary_scale=2 * scale, snap=snap, min_quality=0, regular_rounds=0, density=density,
                fixed_boundary=fixed_boundary, return_faces=True,
            )
            uv = subdivide_disk_mesh(coarse_uv, coarse_F, 1)[-1][0]
            # The coarse vertices keep their input faces; the new ones are found
            # from them.
            faces_hint = np.r_[coarse_faces, np.full(len(uv) - len(coarse_uv), -1)]
            sweeps = max(relax // 2, 1)
        elif valence_flips and levels == 0:
            # The output is the base mesh, whose connectivity no subdivision keeps:
            # relaxed, its edges are flipped towards six faces at every interior vertex
            # as well, and it is relaxed again (see flip_for_valence).
            uv, X, faces_hint = relax_on_surface(
                dm.uv, F, V, uv, Fo, iterations=relax, pinned=pinned, boundary_scale=scale, snap=snap, min_quality=0,
                regular_rounds=0, density=density, fixed_boundary=fixed_boundary, return_faces=True,
            )
            Fo, flips = flip_for_valence(uv, Fo, X, np.where(on_circle, wanted, 6), bound=bound, monotone=False)
            hierarchy = [(uv, Fo)]
            run.update(output_valence_flips=flips)
            sweeps = max(relax // 2, 1)
        uv, Vo = relax_on_surface(
            dm.uv, F, V, uv, Fo, iterations=sweeps, pinned=pinned, boundary_scale=scale, snap=snap, faces=faces_hint,
            density=density, fixed_boundary=fixed_boundary,
        )
        if valence_flips and levels == 0:
            q = radius_ratio(Vo, Fo)
            if q.min() < QUALITY_FLOOR:
                # Beyond the relaxation: the faces below the floor that a flip mends
                # (an ear of three boundary vertices on a straight border, where the
                # piece has no interior vertex: a quad of two faces asked for four had
                # one of radius ratio 1e-27).
                near = np.zeros(len(uv), dtype=bool)
                near[Fo[q < QUALITY_FLOOR].ravel()] = True
                Fo, flips = flip_for_surface_quality(uv, Fo, Vo, near)
                hierarchy = [(uv, Fo)]
                run.update(sliver_flips=flips)
        clock.stop("relax")
    return uv, Fo, hierarchy, Vo, mu, run


def remesh_disk(
    V, F, dm, faces, *, levels, method, seed, corner_angle, cvt_iterations, relax, teichmuller_iterations, retries,
    snap=SNAP_REACH, sizing=None, fixed_boundary=False, corner_at=None, boundary_edge_length=None, data=None,
    stats=None, clock=None,
):
    """The paper's Algorithm 2 on a disk whose conformal map is known: landmarks, base
    mesh, subdivision, Teichmueller map, relaxation on the surface and projection.

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
        A disk, as :func:`qcremesh.remeshing.pipeline.remesh` has checked and mended it.
    dm : DiskMap
        Its conformal map onto the unit disk (:func:`qcremesh.param.disk.disk_conformal_map`).
    faces : int
        Output faces wanted.
    levels, method, seed, corner_angle, cvt_iterations, relax, teichmuller_iterations, retries, snap
        As for :func:`qcremesh.remeshing.pipeline.remesh`; ``levels`` is already at most
        what keeps the base mesh at MIN_BASE_FACES (:func:`levels_above_min_base`).
    sizing : (n,) float, optional
        Relative edge lengths (the ``"curvature"`` field already computed).
    fixed_boundary, boundary_edge_length, data
        As for :func:`qcremesh.remeshing.pipeline.remesh`.
    corner_at : (c,) int, optional
        Positions along ``dm.boundary`` of the boundary corners given.
    stats : dict, optional
        Numbers of the run so far, added to (the returned result's).
    clock : StageTimes, optional
        Times of the stages so far, added to (the returned result's).

    Returns
    -------
    RemeshResult
    """
    stats = {} if stats is None else stats
    clock = StageTimes() if clock is None else clock
    bnd = dm.boundary
    density = None if sizing is None else 1.0 / sizing
    if density is not None:
        stats["sizing_min_ratio"] = float(sizing.min() / sizing.max())
    # Where the map is far from conformal, the base mesh's Delaunay triangles are
    # stretched on the surface.
    stretch = coherent_mu(F, dm.mu, len(V), NONCONFORMAL_RINGS)
    stats["param_nonconformal_share"] = float(np.mean(stretch > NONCONFORMAL_MU))
    stats["param_narrowest_share"] = dm.narrowest_arcs / len(dm.boundary)
    if method == "uniform" or stats["param_nonconformal_share"] <= NONCONFORMAL_SHARE:
        stretch = None

    # The smallest radius ratio after the relaxation depends chaotically on the landmarks.
    # With landmarks from disk cells it was below QUALITY_FLOOR in 3 of 24 draws (seeds 0-5
    # on hand.ply at both face counts, human_brain.ply and human_face.obj at half), each at
    # a narrow notch of a scan border; with surface cells, in none of 38 draws (seeds 0-9 of
    # human_face.obj at half its face count, 0-5 at its face count, 0-5 of fran_cut, venus
    # and foot and 0-3 of hand.ply at half; the lowest 0.310); hand.ply subdivided once
    # was (0.293, at a boundary corner) until the relaxation learnt to smooth the rings
    # around such faces together. camel_b.obj, cut along zero-width slits, never reaches
    # it. Below it, the landmarks are drawn again, up to ``retries`` times, and the best
    # draw is kept, while at most MAX_REDRAWN_SLIVERS faces are.
    draws = 1 + (retries if relax > 0 and method != "uniform" else 0)
    # Where the CVT's cells come out far from equal on the surface (above MAX_CELL_SPREAD),
    # fewer levels (more landmarks) are planned and the landmarks drawn again. Where the
    # best draw still has a face below QUALITY_FLOOR, or leaves more than FAR_SHARE of
    # the input farther than FAR_REACHES snapping reaches from the output, fewer levels
    # are planned too (where redraws are made, and not for a piece whose levels its
    # caller sets, with ``boundary_edge_length``), and the levels whose output follows
    # the surface, then with the largest smallest radius ratio, are kept: a part of the
    # disk narrower than the base mesh's spacing gets no landmark inside and its border
    # none along it (decimated-max.obj cut by a plane: a peninsula about 5 wide and 25
    # long at a spacing of 26 / 37, min q 0.045 / 0.124 at its face count / half, 0.415
    # / 0.373 with no level).
    try_fewer = draws > 1 and boundary_edge_length is None
    kept, tried, fallbacks = None, [], []
    while True:
        levels = _levels_with_interior(V, F, bnd, faces, levels, density)
        tried.append(levels)
        plan_stats = {"levels": levels}
        clock.start("landmarks")
        plan = _landmarking(
            V, F, dm, faces, levels, density, method, corner_angle, corner_at, fixed_boundary, boundary_edge_length,
            plan_stats,
        )
        clock.stop("landmarks")
        best = None
        for draw in range(draws):
            candidate = _adaptive_mesh(
                V, F, dm, plan, stretch, density, seed if draw == 0 else [seed, draw], draw == 0, method,
                cvt_iterations, teichmuller_iterations, relax, snap, fixed_boundary, clock,
            )
            if candidate is None:
                break
            _, Fo, _, Vo, _, _ = candidate
            q = radius_ratio(Vo, Fo) if Vo is not None else np.ones(1)
            if best is None or q.min() > best[0]:
                best = (q.min(), candidate)
            slivers = np.count_nonzero(q < QUALITY_FLOOR)
            if slivers == 0 or slivers > MAX_REDRAWN_SLIVERS:
                break
        # An output that follows the surface comes first, then the largest smallest radius
        # ratio.
        follows = levels == 0 or not try_fewer or snap == 0 or best is None or best[1][3] is None
        if not follows:
            _, Fo, _, Vo, _, _ = best[1]
            follows = _share_left_out(V, F, Vo, Fo, FAR_REACHES * snap) <= FAR_SHARE
        if best is not None and (kept is None or (follows, best[0]) > kept[0]):
            kept = ((follows, best[0]), best[1], dict(plan_stats, draws=draw + 1))
        if levels == 0 or (best is not None and ((best[0] >= QUALITY_FLOOR and follows) or not try_fewer)):
            break
        if best is None:
            fallbacks.append([levels, "the CVT's cells uneven on the surface"])
        elif not follows:
            fallbacks.append([levels, "part of the surface left beyond the snapping's reach"])
        else:
            fallbacks.append([levels, "a face left below a radius ratio of 0.3"])
        levels -= 1
    uv, Fo, hierarchy, Vo, mu, run = kept[1]
    stats.update(kept[2], levels_tried=tried, levels_fallbacks=fallbacks, **run)

    clock.start("project")
    on_circle = np.zeros(len(uv), dtype=bool)
    on_circle[boundary_edges(Fo).ravel()] = True
    names = sorted(data) if data else []
    # The relaxation already lifted the vertices; only the attributes are left then.
    fields = ([V] if Vo is None else []) + [data[k] for k in names]
    lifted = project_to_surface(dm.uv, F, bnd, uv, on_circle, fields) if fields else []
    if Vo is None:
        Vo = lifted.pop(0)
    out_data = dict(zip(names, lifted))
    levels_out = [(Vo[: len(u)], f) for u, f in hierarchy]
    clock.stop("project")
    return RemeshResult(Vo, Fo, uv, levels_out, out_data, hierarchy, mu, stats, clock.times)
