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
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..geometry.locate import interpolate_barycentric
from ..geometry.operators import signed_doublearea
from ..geometry.quality import radius_ratio
from ..geometry.threads import query_workers
from ..geometry.vectors import norm
from .guard import DistanceGuard
from .min_quality import QUALITY_FLOOR
from .onsurface import closest_point_near, csr_rows, independent_first, star_distance

__all__ = ["snap_to_far_points"]

# Fractions of the way (in the disk) from an output vertex to the input vertex pulling it.
FRACTIONS = (1.0, 0.5, 0.25, 0.125)


def snap_to_far_points(
    X, uv, face, Fo, A, VF, bnd, pinned, snapped, partial, V, F, A_in, disk_uv, vertex_faces, reach, passes=4
):
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
    ``reach``, than it is and than the pulling vertex is. A vertex that moved is
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
    Fo : (l, 3) int
        Output faces.
    A : (k, k) CSR
        Vertex adjacency of ``Fo``.
    VF : (k, l) CSR
        Vertex-face incidence of ``Fo``.
    bnd : (b,) int
        Output boundary loop (its vertices do not move).
    pinned : (k,) bool
        Vertices that stay.
    snapped : (k,) bool
        Vertices snapped by an earlier call; set for those that move (updated).
    partial : (k,) bool
        Those of them that went only part of the way, which may move again (updated).
    V : (n, 3) float
    F : (m, 3) int
        The input surface.
    A_in : (n, n) CSR
        Vertex adjacency of ``F``.
    disk_uv : (n, 2) float
        Its disk parameterization.
    vertex_faces : (n, m) CSR
        Vertex-face incidence of ``F``.
    reach : float
        Distance from the output beyond which an input vertex pulls (the relaxation
        takes half the mean output edge length).
    passes : int
        Maximum number of passes.
    """
    # Input vertices within reach of an output vertex are within reach of the output.
    # Only the others are measured, in every pass (one near a vertex that moves away is
    # not measured again: its other neighbours stay).
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
        moved, whole = _move_towards(
            X, uv, face, Fo, VF, target, far, dist[far], guard, V, F, disk_uv, vertex_faces
        )
        guard.update(X, Fo, VF, target[moved])
        failed = np.union1d(failed, far[~moved] * len(X) + target[~moved])
        snapped[target[moved]] = True
        partial[target[moved]] = ~whole[moved]


def _move_towards(X, uv, face, Fo, VF, target, far, allow, guard, V, F, disk_uv, vertex_faces):
    """Move each output vertex ``target`` the largest fraction of the way to input vertex
    ``far`` that keeps its faces valid and takes no input vertex that ``guard`` watches
    farther from the output than the limit, than it is, or than ``far`` is (``allow``);
    which moved and which went all the way, (p,) bool each."""
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
