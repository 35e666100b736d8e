"""Tangential relaxation of a remeshed surface that keeps every vertex on the input
surface and the connectivity unchanged.

An optional last stage of :func:`qcremesh.remeshing.pipeline.remesh`, beyond the paper. Each
sweep (:func:`qcremesh.remeshing.smoothing.smoothing_sweep`) moves every interior vertex
towards the centroid of its neighbours, tangentially
(the component along the vertex normal is removed), by at most a quarter of its mean
edge length, and snaps it back onto the input surface at the closest point among the input faces
around the face it was on (a local search, so a vertex never jumps to another sheet of
the surface across a thin part). Its disk coordinates follow by barycentric interpolation
of the parameterization on that face. Boundary vertices slide along the input boundary
polyline: their arc-length position (measured on the boundary smoothed at the landmark
spacing, so narrow notches are skipped) moves by the component along the boundary of the
displacement to the mean of all their neighbours
(:func:`~qcremesh.remeshing.smoothing.boundary_arc_steps`), so that the boundary spacing
follows the faces along it, where that keeps the output boundary close to the input's
(BOUNDARY_STRAY), else, and with a sizing field, towards the mean of their two boundary
neighbours' (in the field's metric); boundary corners stay. A vertex whose move
would fold one of its faces in the disk stays where it is, so the disk mesh stays an
embedding and the surface mesh its orientation.

After the sweeps, input vertices left far from the output (pocket bottoms) pull output
vertices onto them (:mod:`qcremesh.remeshing.snap`), and a search raises the minimum
quality around the worst faces, which the sweeps leave where the surface bends sharply or
the boundary is jagged (:mod:`qcremesh.remeshing.min_quality`); then the snapping once
more, where the search has mended the faces that stopped it, and a short search. Where
faces stay below a radius ratio of 0.3, the vertices within 3 rings of them get 5 sweeps
of smoothing together, which frees a vertex that no move of its own can help, and the
search goes on (hand.ply subdivided once: 0.293 -> 0.496, where the landmarks had to be
drawn again before). Where faces are still below 0.4, the snapped vertices may move
again to mend them in a short search. Last, a search raises the share of faces with a
radius ratio of at least 0.9 (:mod:`qcremesh.remeshing.regularize`).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..adaptive.landmarks import interpolate_on_boundary
from ..geometry.locate import interpolate_barycentric, locate_points
from ..geometry.operators import signed_doublearea
from ..geometry.quality import radius_ratio
from ..geometry.threads import query_workers
from ..geometry.vectors import norm
from ..mesh.topology import adjacency_matrix, boundary_loop
from .guard import DistanceGuard
from .meshes import input_surface, output_mesh
from .min_quality import QUALITY_FLOOR, raise_min_quality
from .onsurface import BoundaryCurve, closest_point_near, csr_rows
from .regularize import raise_regular_fraction
from .smoothing import boundary_arc_steps, edge_lengths, smoothing_sweep
from .snap import snap_to_far_points
from .stars import boundary_deviation

__all__ = ["SNAP_REACH", "relax_on_surface"]

# The snapping's reach, in mean output edge lengths (see relax_on_surface).
SNAP_REACH = 0.5

# Where the minimum-quality search ends below QUALITY_FLOOR: sweeps of smoothing of the
# vertices within this many rings of the faces below it, before the search goes on.
UNJAM_RINGS = 3
UNJAM_SWEEPS = 5

# A point within this fraction of the longest side of a face from it lies in it (rounding
# at the edges; as locate_points).
LOCATE_RTOL = 1e-12

# Radius ratio below which the vertices snapped onto the input may move again, last.
# Measured: human_face at half its face count 0.308 -> 0.462 and at seed 1 and its face
# count 0.321 -> 0.512, with the Hausdorff distance the same (0.57, 0.92 %); the 12 other
# runs of the benchmark and 10 of 12 runs of human_face and human_brain at seeds 1-3 never
# get there. At 0.5: human_face at seed 2 and half its face count 0.439 -> 0.461 for a
# Hausdorff distance of 0.73 -> 0.80 %.
SNAPPED_FLOOR = 0.4

# A boundary vertex takes the umbrella's step along the boundary only where that leaves
# the output boundary no farther from the input boundary's vertices between its two
# neighbours than the even step would, or than this fraction of the mean output edge
# length. Measured (seed 0, at the face count / half): fran_cut's boundary Hausdorff
# distance 0.63 / 0.44 -> 0.35 / 0.34 % of the diagonal (0.21 / 0.43 with the even step
# everywhere), hand.ply 0.20 / 0.31 -> 0.18 / 0.21 %, human_face at half 0.15 -> 0.13 %, the
# mean radius ratio the same to 5e-4; 0.05 about the same; 1e-4 (the even step wherever
# it strays less) lost much of the umbrella's gain (fran_cut q > 0.9 99.3 -> 98.8 %).
BOUNDARY_STRAY = 0.1

# Most rounds of the walk that locates a vertex in the disk map from a face near it.
WALK_ROUNDS = 64


def _locate(disk_uv, F, vertex_faces, A, uv, inner, hint):
    """Input faces under the interior vertices ``inner`` and the barycentric coordinates of
    their disk positions in them, (p,) and (p, 3).

    A vertex whose input face is known (``hint``, (k,) int, -1 where not) or one of whose
    neighbours' is, is found by a walk in the disk map from that face
    (:func:`~qcremesh.remeshing.onsurface.closest_point_near`): a few faces away where the
    hint is the face of an endpoint of the edge the vertex subdivides. The others start
    from a face of the input vertex nearest to them in the disk. The walk ends in the
    face containing the point (the distance to the faces around the current one
    decreases on a planar triangulation); those whose walk stopped short of their face
    are located by :func:`~qcremesh.geometry.locate.locate_points` (which located all those
    with no face known nearby before: the level below the output, say; human_face.obj,
    both levels, 0.07 -> 0.04 s).
    """
    if len(inner) == 0:
        return np.zeros(0, dtype=np.int64), np.zeros((0, 3))
    start = hint[inner].copy()
    todo = np.flatnonzero(start < 0)
    if len(todo):
        ring, owner = csr_rows(A, inner[todo])
        known = hint[ring] >= 0
        ring, owner = ring[known], owner[known]
        _, first = np.unique(owner, return_index=True)
        start[todo[owner[first]]] = hint[ring[first]]
    todo = np.flatnonzero(start < 0)
    if len(todo):
        # no face known nearby: start from a face of the nearest input vertex in the disk
        used = np.flatnonzero(np.diff(vertex_faces.indptr))
        nearest = used[cKDTree(disk_uv[used]).query(uv[inner[todo]], workers=query_workers(len(todo)))[1]]
        start[todo] = vertex_faces.indices[vertex_faces.indptr[nearest]]
    P = np.column_stack([uv[inner], np.zeros(len(inner))])
    flat = np.column_stack([disk_uv, np.zeros(len(disk_uv))])
    face, closest, bary = closest_point_near(P, start, flat, F, vertex_faces, rounds=WALK_ROUNDS)
    corners = flat[F[face]]
    longest = norm(np.roll(corners, -1, axis=1) - corners).max(1)
    rest = np.flatnonzero(norm(closest - P) > LOCATE_RTOL * longest)
    if len(rest):
        face[rest], bary[rest], _ = locate_points(disk_uv, F, uv[inner[rest]], rtol=LOCATE_RTOL)
    return face, bary


def _evenly_between(s, fixed, perimeter):
    """Arc lengths ``s`` (b,) along a closed loop (increasing, period ``perimeter``) made
    evenly spaced between the ``fixed`` ones (b,) bool (around the whole loop from the
    first where none is), in loop order."""
    b = len(s)
    anchor = np.flatnonzero(fixed) if fixed.any() else np.array([0])
    # each position's anchor before it and the next one, with the loop closed
    knots = np.r_[anchor, anchor[0] + b]
    values = np.r_[s[anchor], s[anchor[0]] + perimeter]
    t = np.arange(b)
    before = t < anchor[0]
    return np.interp(np.where(before, t + b, t), knots, values) - before * perimeter


def _on_fixed_edges(on_circle, bnd, s, curve, fixed_boundary):
    """The output's boundary vertices (``bnd`` at arc lengths ``s`` along ``curve``) that
    lie on the input boundary edges the ``fixed_boundary`` of :func:`relax_on_surface`
    keeps: all of them where it is not an array, (k,) bool."""
    if np.ndim(fixed_boundary) == 0:
        return on_circle
    loop = curve.loop
    edge = curve.edge_at(s)
    held = np.zeros_like(on_circle)
    held[bnd] = fixed_boundary[loop[edge]] & fixed_boundary[np.roll(loop, -1)[edge]]
    return held


def _boundary_steps(X, E, bnd, ring, s_prev, s, s_next, pinned, curve, step):
    """Arc-length steps of the output boundary vertices ``bnd`` (at ``s`` along ``curve``,
    their neighbours at ``s_prev`` and ``s_next``) in a sweep of ``step``: the umbrella's
    (:func:`~qcremesh.remeshing.smoothing.boundary_arc_steps`), or the step to the mean
    of the two neighbours where the umbrella's takes the output boundary farther from the
    input boundary (:func:`~qcremesh.remeshing.stars.boundary_deviation`) than that one
    and than BOUNDARY_STRAY mean edge lengths, (b,) (the ``pinned`` ones' unchecked:
    they do not move)."""
    along = boundary_arc_steps(X, bnd, ring, s_prev, s, s_next)
    even = (s_prev + s_next) / 2 - s
    free = np.flatnonzero(~pinned)
    if not len(free):
        return along
    sc = np.column_stack([s + step * along, s + step * even])[free]
    Xc = curve.at(sc.ravel())[1].reshape(-1, 2, 3)
    stray = boundary_deviation(s, free, Xc, sc, X[bnd], curve)
    far = stray[:, 0] > np.maximum(stray[:, 1], BOUNDARY_STRAY * edge_lengths(X, E).mean())
    along[free[far]] = even[free[far]]
    return along


def _faces_beside(surface, loop, edge):
    """The input face of each input boundary edge (``loop[edge]``, ``loop[edge + 1]``),
    (k,): the one face both its ends are corners of."""
    VF = surface.vertex_faces
    common = (VF[loop[edge]].multiply(VF[np.roll(loop, -1)[edge]])).tocsr()
    return common.indices[common.indptr[:-1]].astype(np.int64)


def _undo_folds(new_X, new_uv, new_face, X, uv, face, Fo):
    """Keep the disk mesh an embedding: put back, in place, the old positions of the
    vertices around faces that the moves fold, until none is folded; which were put back,
    (k,) bool."""
    revert = np.zeros(len(X), dtype=bool)
    while True:
        bad = signed_doublearea(new_uv, Fo) <= 0
        grow = np.zeros(len(X), dtype=bool)
        grow[Fo[bad].ravel()] = True
        grow &= ~revert
        if not grow.any():
            return revert
        revert |= grow
        new_uv[grow], new_X[grow], new_face[grow] = uv[grow], X[grow], face[grow]


def relax_on_surface(
    disk_uv,
    F,
    V,
    uv,
    Fo,
    *,
    iterations=10,
    step=0.5,
    pinned=None,
    boundary_scale=None,
    snap=SNAP_REACH,
    min_quality=0.66,
    rounds=300,
    regular_rounds=20,
    faces=None,
    density=None,
    fixed_boundary=False,
    return_faces=False,
):
    """Move the vertices of a mesh of the disk so that its image on the surface gets more
    regular, without changing its connectivity.

    First ``iterations`` sweeps of tangential smoothing (see the module documentation).
    Then the snapping of :func:`qcremesh.remeshing.snap.snap_to_far_points`, at most
    ``rounds`` rounds of the search of
    :func:`qcremesh.remeshing.min_quality.raise_min_quality`, and, the faces mended, the
    snapping again and ``rounds // 12`` more rounds with the snapped vertices fixed
    (measured: Hausdorff distance on human_face 1.43 -> 0.76 % of the diagonal,
    human_brain 0.52 / 0.70 -> 0.46 / 0.60 % at its face count / half of it, hand.ply at
    half 0.33 -> 0.30 %; on the 7 disk meshes at both counts, 25 rounds there give the
    min q, mean q to 1e-4 and Hausdorff distance of 50; 10 rounds nearly so, hand.ply at
    half count 0.361 against 0.362). Then, where faces stay below 0.3, the rings around
    them are smoothed together and the search gets ``rounds // 12`` rounds more; where
    faces stay below 0.4, ``rounds // 12`` rounds more in which the snapped vertices may
    move to mend them. Last, ``regular_rounds`` rounds of
    :func:`qcremesh.remeshing.regularize.raise_regular_fraction`.

    Parameters
    ----------
    disk_uv : (n, 2) float
        Conformal parameterization of the input surface (boundary on the circle).
    F : (m, 3) int
        Input faces.
    V : (n, 3) float
        Input vertices.
    uv : (k, 2) float
        Disk positions of the output vertices (boundary ones on the circle).
    Fo : (l, 3) int
        Output faces, counter-clockwise in the disk.
    iterations : int
        Number of smoothing sweeps.
    step : float
        Fraction of the displacement applied per sweep, in (0, 1].
    pinned : (k,) bool, optional
        Vertices that must not move (e.g. boundary corners).
    boundary_scale : float, optional
        Scale at which the boundary is smoothed to measure the arc length along which the
        boundary vertices are spaced (notches narrower than it are skipped); the mean
        output boundary edge length by default.
    snap : float
        After the sweeps, the input vertices farther than ``snap`` mean output edge
        lengths from the output (the bottoms of pockets the output spans, which the
        smoothing pulls vertices out of) each pull the nearest output vertex onto them,
        or part of the way, where that keeps the faces around it valid; the minimum-quality
        search moves such a vertex again only to mend a face below 0.3. 0 skips this.
    min_quality : float
        Radius ratio below which the stars are optimized (0 skips that stage). Measured
        against 0.6 on the 14 benchmark runs of the 7 disk meshes (camel_b aside): the
        smallest radius ratio 0.60-0.61 -> 0.65-0.72 on 9 of them (venus at half its
        face count 0.609 -> 0.715) and 0.559 -> 0.561 on human_brain at half, the same on
        three, lower on human_face at its face count (0.565 -> 0.500); mean radius ratio
        and Hausdorff distance the same to 0.001 and 0.02 %; hand.ply 0.2-0.3 s longer.
        Over seeds 0-3 of human_face the Hausdorff distance moves both ways (at its face
        count 0.38 / 0.61 / 0.37 / 0.60 -> 0.38 / 0.60 / 0.45 / 0.64 %).
    rounds : int
        Maximum number of rounds of the minimum-quality search.
    regular_rounds : int
        Maximum number of rounds of the search that raises the share of faces with a
        radius ratio of at least 0.9 (:mod:`qcremesh.remeshing.regularize`), last, with
        the snapped vertices and their neighbours staying; 0 skips it.
    faces : (k,) int, optional
        Input face under each vertex where known, -1 elsewhere (the faces returned for
        the level this one subdivides, say): such a vertex, and a neighbour of it, are
        located in the disk map by a walk from that face instead of a search of the
        whole map (the output level of hand.ply at its face count, 53k vertices: 0.07 s
        instead of 0.17 s; human_face.obj 0.02 s instead of 0.09 s).
    density : (n,) float, optional
        Vertices wanted per unit length at each input vertex, relative to each other (the
        inverse of a sizing field): the boundary vertices are spaced evenly in its metric.
        The interior needs none: the connectivity of a mesh graded by the landmarks keeps
        its grading under the plain mean of the neighbours (a plane with edges wanted half
        as long on one side: 0.55 of the other's, radius ratio 0.981), while the mean
        weighted by the density, which grades by moving the vertices only along its
        gradient, overshoots (0.49) with skewed faces (0.947).
    fixed_boundary : bool or (n,) bool
        Space the boundary vertices evenly by arc length (unsmoothed, in the metric of
        ``density``) between the pinned ones (all around the loop where none is) and
        keep them there: parts of the border that are the same polyline between pinned
        vertices and get as many vertices get the same vertices (the two sides of a cut).
        An array over the input vertices keeps them only on the input boundary edges
        between two True vertices (the cuts of a piece cut off a disk), and the others
        slide as without.
    return_faces : bool
        Also return the input face under each vertex.

    Returns
    -------
    uv : (k, 2) float
        New disk positions.
    X : (k, 3) float
        Their positions on the surface.
    faces : (k,) int64
        With ``return_faces``: the input face under each vertex, -1 on the boundary
        (with a ``fixed_boundary`` of True, the face beside the input boundary edge
        under the vertex).
    """
    uv = np.array(uv, dtype=np.float64)
    k = len(uv)
    out = output_mesh(Fo, k)
    bnd = out.loop
    if boundary_scale is None:
        loop = boundary_loop(F)
        boundary_scale = np.linalg.norm(V[np.roll(loop, -1)] - V[loop], axis=1).sum() / len(bnd)
    # A fixed boundary is spaced by the arc length itself, which is the same both ways
    # along the polyline (the two sides of a slit get the same points).
    fixed = bool(np.any(fixed_boundary))
    curve = BoundaryCurve(disk_uv, F, V, 0.0 if fixed else boundary_scale, density)
    perimeter = curve.perimeter
    pinned = np.zeros(k, dtype=bool) if pinned is None else np.array(pinned, dtype=bool)
    on_circle = np.zeros(k, dtype=bool)
    on_circle[bnd] = True
    inner = np.flatnonzero(~on_circle)
    free = ~on_circle & ~pinned
    A, VF, E = out.A, out.VF, out.E
    surface = input_surface(V, F, disk_uv)
    vertex_faces = surface.vertex_faces

    hint = np.full(k, -1, dtype=np.int64) if faces is None else np.asarray(faces, dtype=np.int64)
    face = np.full(k, -1, dtype=np.int64)  # input face under each vertex; -1: boundary (but a cut)
    X = np.zeros((k, 3))
    face[inner], bary = _locate(disk_uv, F, vertex_faces, A, uv, inner, hint)
    X[inner] = interpolate_barycentric(F, face[inner], bary, V)
    theta = np.arctan2(uv[bnd, 1], uv[bnd, 0])
    X[bnd] = interpolate_on_boundary(curve.theta, curve.points, theta)
    s = curve.arc_length(theta)
    s = s[0] + np.mod(s - s[0], perimeter)  # increasing along the output loop
    if fixed:
        s = _evenly_between(s, pinned[bnd], perimeter)
        uv[bnd], X[bnd] = curve.at(s)
        pinned = pinned | _on_fixed_edges(on_circle, bnd, s, curve, fixed_boundary)
        if np.ndim(fixed_boundary) == 0:
            # A surface cut open (its cut, and the loops of its own boundary the cut
            # joins, all held): the boundary vertices, pinned, take the input face beside
            # the edge they lie on, so that the faces at the cut (whose two sides are
            # the same surface, not a scan's ragged border) are judged for turning over
            # too (stars.input_up; a closed CAD cylinder at 3,000 faces: 6 faces
            # through others, at the centre of a cap where its cut ends -> 0;
            # decimated-max at half its face count min q 0.543 -> 0.667; alex_3, whose
            # holes are ragged, Hand1.off and face-YH the same).
            face[bnd] = _faces_beside(surface, curve.loop, curve.edge_at(s))
    moved = np.flatnonzero(free)
    ring, ring_bnd = A[moved], A[bnd]
    for _ in range(iterations):
        new_X, new_uv, new_face = smoothing_sweep(X, uv, face, moved, ring, out, surface, step)
        # boundary: the umbrella's step along it in arc length, or, with a sizing field,
        # even spacing in its metric (the field's border rule shortens the boundary edges
        # where the boundary bends; following the faces instead took fran_cut's Hausdorff
        # distance with the curvature sizing from 0.68 to 0.94 %)
        s_prev, s_next = np.roll(s, 1), np.roll(s, -1)
        s_prev[0] -= perimeter
        s_next[-1] += perimeter
        if density is None:
            along = _boundary_steps(X, E, bnd, ring_bnd, s_prev, s, s_next, pinned[bnd], curve, step)
        else:
            along = (s_prev + s_next) / 2 - s
        s_new = np.where(pinned[bnd], s, s + step * along)
        new_uv[bnd], new_X[bnd] = curve.at(s_new)
        revert = _undo_folds(new_X, new_uv, new_face, X, uv, face, Fo)
        s_new[revert[bnd]] = s[revert[bnd]]
        uv, X, face, s = new_uv, new_X, new_face, s_new
    snapped, partial = np.zeros(k, dtype=bool), np.zeros(k, dtype=bool)
    A_in = adjacency_matrix(F, len(V)) if snap > 0 else None
    if snap > 0:
        snap_to_far_points(X, uv, face, out, surface, A_in, pinned, snapped, partial, snap * edge_lengths(X, E).mean())
    if min_quality > 0 and rounds > 0:
        raise_min_quality(X, uv, face, s, out, surface, pinned, snapped, curve, min_quality, rounds)
        if snap > 0:
            # The search has mended the faces that blocked some moves of the snapping
            # (a move must leave every face around the vertex above 0.3): snap again, and
            # polish around, the snapped vertices staying.
            snap_to_far_points(
                X, uv, face, out, surface, A_in, pinned, snapped, partial, snap * edge_lengths(X, E).mean()
            )
            raise_min_quality(
                X, uv, face, s, out, surface, pinned | snapped, snapped, curve, min_quality, max(rounds // 12, 1)
            )
        # Where the search ends below the floor, a vertex is wedged between neighbours
        # placed for where it is, and no move of one vertex helps (hand.ply subdivided
        # once: an interior vertex next to a boundary corner, 0.293); smoothing the
        # rings around the bad faces together frees it, and the search goes on.
        q = radius_ratio(X, Fo)
        if q.min() < QUALITY_FLOOR:
            near = np.zeros(k, dtype=bool)
            near[Fo[q < QUALITY_FLOOR].ravel()] = True
            for _ in range(UNJAM_RINGS):
                near |= (A @ near) > 0
            wedged = np.flatnonzero(near & free)
            ring = A[wedged]
            for _ in range(UNJAM_SWEEPS):
                new_X, new_uv, new_face = smoothing_sweep(X, uv, face, wedged, ring, out, surface, step)
                _undo_folds(new_X, new_uv, new_face, X, uv, face, Fo)
                uv, X, face = new_uv, new_X, new_face
            raise_min_quality(
                X, uv, face, s, out, surface, pinned, snapped, curve, min_quality, max(rounds // 12, 1)
            )
    last_search = min_quality > 0 and rounds > 0 and radius_ratio(X, Fo).min() < SNAPPED_FLOOR
    # The last two searches keep the input vertices the snapping reached within its reach
    # (the snapping guards its own moves the same way).
    guard = None
    if snap > 0 and (last_search or regular_rounds > 0):
        guard = DistanceGuard(X, Fo, VF, V, snap * edge_lengths(X, E).mean())
    if last_search:
        # The snapping leaves faces down to QUALITY_FLOOR around the vertices it moved into
        # pockets, and held there they stay; a short search in which they may move again to
        # mend a face below SNAPPED_FLOOR lifts the worst of them.
        raise_min_quality(
            X, uv, face, s, out, surface, pinned, snapped, curve, SNAPPED_FLOOR, max(rounds // 12, 1),
            held_floor=SNAPPED_FLOOR, guard=guard,
        )
    if regular_rounds > 0:
        # The snapped vertices and their neighbours, which shape the pockets the snapping
        # followed, stay.
        held = snapped | ((A @ snapped) > 0)
        raise_regular_fraction(X, uv, face, s, out, surface, ~pinned & ~held, curve, regular_rounds, guard=guard)
    return (uv, X, face) if return_faces else (uv, X)
