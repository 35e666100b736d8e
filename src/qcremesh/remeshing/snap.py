"""Snapping the output onto the input where it lies far from it.

Smoothing pulls vertices out of the deep narrow pockets of a surface (nostrils, sulci,
closed eyelids) that a disk map compresses, so the output spans them. The input vertices
left far from the output then pull the nearest free output vertex onto them, or as far
towards them as keeps its faces valid, over a few passes so that a pocket is followed
down one vertex at a time; a vertex that went only part of the way goes on in the later
passes and calls, as far as its faces then allow.

Measured with a reach of half an edge against one pass that moved vertices all the way or
not at all, from one edge length (Hausdorff distance in % of the diagonal at the input
face count / half of it): head_neck_cut 0.32 / 0.43 -> 0.24 / 0.34, human_face 1.45 /
1.48 -> 1.43 / 0.86, human_brain 0.67 / 0.97 -> 0.52 / 0.70, venus 3.20 / 3.29 -> 2.20 /
2.99; minimum radius ratio human_face 0.25 / 0.40 -> 0.37 / 0.35, human_brain 0.58 / 0.60
-> 0.49 / 0.39. Letting the vertices that went part of the way go on, against freezing
them there: human_face at seeds 0-3, 0.72 / 0.61 / 0.38 / 0.90 % -> 0.38 / 0.61 / 0.37 /
0.60 % at its face count, 0.67 / 0.84 / 0.72 / 1.03 % -> 0.69 / 0.62 / 0.48 / 0.79 % at
half of it (smallest radius ratio at least 0.31); human_brain 0.55 / 0.70 -> 0.44 / 0.56
%; on the five other disk meshes the radius ratios and distances the same. A far point
whose vertex could not move at all turns to the next nearest vertex of the face in the
next pass (it pulled the same vertex again in vain): human_face at seed 1 and its face
count 0.98 -> 0.50 %, human_brain at half its face count at seeds 1 and 3 1.31 / 0.79 ->
0.76 / 0.69 %. A move that takes another input vertex farther from the output than the
reach, than it is and than the pulling vertex is, is refused
(:class:`~qcremesh.remeshing.guard.DistanceGuard`; camel_b over seeds 0-3, mean Hausdorff
distance at its face count / half 1.357 / 1.595 -> 1.267 / 1.529 %).

A vertex that cannot go all the way alone (its faces would fall below 0.3 or fold) goes
all the way with the free vertices within two edges of it draped after it by 20 sweeps of
tangential smoothing, where that keeps every face around them valid and the guard's
points within their limits; otherwise, as before, part of the way alone. Pulling one
vertex up a tip more than an edge high, or down a pocket as deep, makes faces that no
fraction of the way mends; the rings around it, smoothed with it held there, reshape
around the new height. Measured against moving alone (Hausdorff distance in % of the
diagonal, seeds 0-3 at the face count and half of it): human_brain mean 0.525 -> 0.493
(largest 0.646 -> 0.584; at seed 0 0.388 / 0.609 -> 0.375 / 0.545), human_face 0.578 ->
0.563 (seed 2 at its face count 0.492 -> 0.388), a Gaussian bump 0.4 high and 0.06 wide
on a unit square (8,198 faces; seeds 0, 1, 3) 1.38 -> 0.77 (seed 0 at half its face
count 4.02 -> 0.79: the coarse level of the relaxation had slid off its top, 2.4 output
edges high); a decimated hand.ply (10,586 faces) at half its face count 1.39 -> 1.07; the
other disk meshes of ``../shared/data`` at seed 0 the same. The mean radius ratio is
lower by up to 3e-4 on the scans (0.005 on the bump at half: 0.974 -> 0.969), the share
above 0.9 by up to 0.001, and the remesh takes 2-8 % longer (hand.ply 3.39 -> 3.56 s).
Draping only in the last pass kept little of it (the bump at half 4.02 %, human_face at
seed 2 0.49 %); one ring, or ten sweeps, did not reach the bump's top.
"""

from __future__ import annotations

import numpy as np
from scipy import sparse
from scipy.spatial import cKDTree

from ..geometry.locate import interpolate_barycentric
from ..geometry.operators import signed_doublearea
from ..geometry.quality import radius_ratio
from ..geometry.threads import query_workers
from ..geometry.vectors import norm
from .guard import DistanceGuard
from .min_quality import QUALITY_FLOOR
from .onsurface import closest_point_near, csr_rows, independent_first, star_distance
from .smoothing import smoothing_sweep

__all__ = ["snap_to_far_points"]

# Fractions of the way (in the disk) from an output vertex to the input vertex pulling it.
FRACTIONS = (1.0, 0.5, 0.25, 0.125)

# A vertex that cannot go all the way alone goes with the vertices within DRAPE_RINGS
# edges of it, draped after it by DRAPE_SWEEPS sweeps of smoothing.
DRAPE_RINGS = 2
DRAPE_SWEEPS = 20


def snap_to_far_points(X, uv, face, out, surface, A_in, pinned, snapped, partial, reach, passes=4):
    """Move output vertices onto (or towards) the input vertices farthest from the
    output surface: the bottoms of pockets and the tips the output cuts across.

    In each pass, the input vertices farther than ``reach`` from the output, and at least
    as far as their input neighbours, each pull the nearest interior vertex of their
    closest output face that has not moved all the way yet (the farthest first, no two
    neighbours at once), but for the vertices that could not move towards them at all in
    an earlier pass. The vertex goes the largest of the fractions 1, 1/2, 1/4, 1/8 of the
    way in the disk (lifted onto the surface) that keeps the disk mesh an embedding and
    its faces above a radius ratio of 0.3, and takes no input vertex watched by a
    :class:`~qcremesh.remeshing.guard.DistanceGuard` farther from the output than
    ``reach``, than it is and than the pulling vertex is. One that cannot go all the way
    alone then goes all the way with the free vertices within DRAPE_RINGS edges of it
    draped after it, where that keeps all their faces valid and the guard content (such
    vertices far enough apart for no face to move with two of them), and otherwise stays
    where it went alone. A vertex that moved is
    flagged in ``snapped``; one that went all the way (here or in an earlier call) stays,
    one that went part of the way is flagged in ``partial`` and may go on in a later pass
    or call.

    Parameters
    ----------
    X : (k, 3) float
        Output vertices on the surface (updated).
    uv : (k, 2) float
        Their disk positions (updated).
    face : (k,) int
        Input face under each output vertex (updated).
    out : OutputMesh
        The output's connectivity (:class:`~qcremesh.remeshing.meshes.OutputMesh`; the
        vertices of its boundary loop do not move).
    surface : InputSurface
        The input surface and its disk map (:class:`~qcremesh.remeshing.meshes.InputSurface`).
    A_in : (n, n) CSR
        Vertex adjacency of the input.
    pinned : (k,) bool
        Vertices that stay.
    snapped : (k,) bool
        Vertices snapped by an earlier call; set for those that move (updated).
    partial : (k,) bool
        Those of them that went only part of the way, which may move again (updated).
    reach : float
        Distance from the output beyond which an input vertex pulls (the relaxation
        takes half the mean output edge length).
    passes : int
        Maximum number of passes.
    """
    # Input vertices within reach of an output vertex are within reach of the output.
    # Only the others are measured, in every pass (one near a vertex that moves away is
    # not measured again: its other neighbours stay).
    Fo, A, VF, bnd, V = out.F, out.A, out.VF, out.loop, surface.V
    query = cKDTree(X).query(V, workers=query_workers(len(V)))
    candidates = np.flatnonzero(query[0] > reach)
    if len(candidates) == 0:
        return
    guard = DistanceGuard(X, Fo, VF, V, reach, query)
    dist = np.zeros(len(V))
    failed = np.zeros(0, dtype=np.int64)  # (far point, vertex) pairs that did not move, as far * k + vertex
    for _ in range(passes):
        if len(candidates) == 0:
            return
        P = V[candidates]
        dist[candidates], near_face = star_distance(P, X, Fo, VF, cKDTree(X).query(P)[1])
        keep = dist[candidates] > reach
        candidates, near_face = candidates[keep], near_face[keep]
        nbr_max = np.maximum.reduceat(dist[A_in.indices], A_in.indptr[:-1])
        bottom = dist[candidates] >= nbr_max[candidates]
        far, T = candidates[bottom], Fo[near_face[bottom]]
        fixed = pinned | (snapped & ~partial)
        fixed[bnd] = True
        dT = norm(X[T] - V[far][:, None])
        dT[fixed[T]] = np.inf
        dT[np.isin(far[:, None] * len(X) + T, failed)] = np.inf
        j = np.argmin(dT, axis=1)
        rows = np.flatnonzero(np.isfinite(dT[np.arange(len(far)), j]))
        far, target = far[rows], T[rows, j[rows]]
        order = np.argsort(-dist[far], kind="stable")
        far, target = far[order], target[order]
        _, first = np.unique(target, return_index=True)
        first = np.sort(first)  # farthest first
        far, target = far[first], target[first]
        free = independent_first(A, target)
        far, target = far[free], target[free]
        if len(far) == 0:
            return
        moved, whole = _move_towards(X, uv, face, out, surface, target, far, dist[far], guard)
        guard.update(X, Fo, VF, target[moved])
        short = np.flatnonzero(~whole)
        if len(short):
            fixed[target[whole]] = True
            draped = _drape_towards(
                X, uv, face, out, surface, target[short], far[short], dist[far[short]], fixed, guard
            )
            moved[short[draped]] = whole[short[draped]] = True
        failed = np.union1d(failed, far[~moved] * len(X) + target[~moved])
        snapped[target[moved]] = True
        partial[target[moved]] = ~whole[moved]


def _move_towards(X, uv, face, out, surface, target, far, allow, guard):
    """Move each output vertex ``target`` the largest fraction of the way to input vertex
    ``far`` that keeps its faces valid and takes no input vertex that ``guard`` watches
    farther from the output than the limit, than it is, or than ``far`` is (``allow``);
    which moved and which went all the way, (p,) bool each."""
    Fo, VF = out.F, out.VF
    V, F, disk_uv, vertex_faces = surface.V, surface.F, surface.disk_uv, surface.vertex_faces
    old_X, old_uv, old_face = X[target].copy(), uv[target].copy(), face[target].copy()
    star, owner = csr_rows(VF, target)
    moved = np.zeros(len(target), dtype=bool)
    whole = np.zeros(len(target), dtype=bool)
    flat = np.column_stack([disk_uv, np.zeros(len(disk_uv))])
    for t in FRACTIONS:
        todo = np.flatnonzero(~moved)
        if len(todo) == 0:
            break
        if t == 1.0:
            f = vertex_faces.indices[vertex_faces.indptr[far[todo]]]
            new_uv, new_X = disk_uv[far[todo]], V[far[todo]]
        else:
            goal = old_uv[todo] + t * (disk_uv[far[todo]] - old_uv[todo])
            # walk from the vertex's input face to the one containing the goal
            f, _, b = closest_point_near(np.column_stack([goal, np.zeros(len(goal))]), old_face[todo], flat, F,
                                         vertex_faces, rounds=64)
            new_uv = interpolate_barycentric(F, f, b, disk_uv)
            new_X = interpolate_barycentric(F, f, b, V)
        refused = guard.excluded(X, Fo, VF, target[todo], new_X[:, None], allow[todo])[:, 0]
        X[target[todo]], uv[target[todo]], face[target[todo]] = new_X, new_uv, f
        trying = ~moved[owner]
        faces = Fo[star[trying]]
        ok_face = (signed_doublearea(uv, faces) > 0) & (radius_ratio(X, faces) >= QUALITY_FLOOR)
        ok = np.bincount(owner[trying], weights=~ok_face, minlength=len(target)) == 0
        ok[moved] = False
        ok[todo[refused]] = False
        back = todo[~ok[todo]]
        X[target[back]], uv[target[back]], face[target[back]] = old_X[back], old_uv[back], old_face[back]
        if t == 1.0:
            whole = ok.copy()
        moved |= ok
    return moved, whole


def _balls(A, verts, rings):
    """The vertices within ``rings`` edges of each of ``verts`` (p,), as the pattern of a
    (p, k) CSR matrix."""
    k = A.shape[0]
    step = (A + sparse.identity(k, format="csr")).tocsr()
    ball = sparse.csr_matrix((np.ones(len(verts)), (np.arange(len(verts)), verts)), shape=(len(verts), k))
    for _ in range(rings):
        ball = ball @ step
        ball.data[:] = 1.0
    return ball


def _far_apart_first(A, verts, rings):
    """The vertices of ``verts`` (in order of priority) none of which is within ``2 rings``
    edges of an earlier one, (p,) bool."""
    ball = _balls(A, verts, rings)
    near = (ball @ ball.T).tocsr()
    near.setdiag(0)  # every ball holds its own vertex: the diagonal is stored already
    near.eliminate_zeros()
    return independent_first(near, np.arange(len(verts)))


def _drape_towards(X, uv, face, out, surface, target, far, allow, fixed, guard):
    """Move each output vertex ``target`` onto input vertex ``far`` with the free vertices
    within DRAPE_RINGS edges of it following: the vertex goes all the way, and DRAPE_SWEEPS
    sweeps of tangential smoothing of the others
    (:func:`~qcremesh.remeshing.smoothing.smoothing_sweep`) drape them after it. Where a
    face around them folds in the disk or falls below QUALITY_FLOOR, or ``guard`` sees a
    watched input vertex near them taken farther from the output than its limit, than it
    is and than ``far`` is (``allow``), they all go back. The vertices are taken in the
    order given, each more than 2 DRAPE_RINGS + 2 edges from an earlier one, so that no
    face moves with two of them; which were draped, (p,) bool."""
    Fo, A, VF = out.F, out.A, out.VF
    draped = np.zeros(len(target), dtype=bool)
    rows = np.flatnonzero(_far_apart_first(A, target, DRAPE_RINGS + 1))
    if len(rows) == 0:
        return draped
    t, p = target[rows], far[rows]
    region, verts = _balls(A, t, DRAPE_RINGS).nonzero()
    free = ~fixed[verts] & (verts != t[region])
    region, verts = region[free], verts[free]
    every, owner = np.r_[t, verts], np.r_[np.arange(len(t)), region]
    old = X[every].copy(), uv[every].copy(), face[every].copy()
    X[t], uv[t] = surface.V[p], surface.disk_uv[p]
    face[t] = surface.vertex_faces.indices[surface.vertex_faces.indptr[p]]
    ring = A[verts]
    for _ in range(DRAPE_SWEEPS):
        new_X, new_uv, new_face = smoothing_sweep(X, uv, face, verts, ring, out, surface, 0.5)
        X[verts], uv[verts], face[verts] = new_X[verts], new_uv[verts], new_face[verts]
    star, which = csr_rows(VF, every)
    star, first = np.unique(star, return_index=True)
    star_owner = owner[which[first]]
    faces = Fo[star]
    bad = (signed_doublearea(uv, faces) <= 0) | (radius_ratio(X, faces) < QUALITY_FLOOR)
    ok = np.bincount(star_owner, weights=bad, minlength=len(t)) == 0
    ok &= ~guard.excluded_patches(X, Fo, star, star_owner, allow[rows])
    back = ~ok[owner]
    X[every[back]], uv[every[back]], face[every[back]] = old[0][back], old[1][back], old[2][back]
    guard.update(X, Fo, VF, every[~back])
    draped[rows] = ok
    return draped
