"""The last stage of the relaxation: a search that raises the minimum radius ratio.

The vertices of the worst faces move, one independent set at a time, to the best of a
pattern of candidate positions on the surface (tangent offsets snapped onto it; boundary
vertices slide along the input boundary), where the best position maximizes the smallest
radius ratio of the faces around the vertex. Faces turned over on the surface count as
negative quality, so the search turns them back first.
"""

from __future__ import annotations

import numpy as np

from .onsurface import csr_rows
from .stars import (
    StarQuality,
    boundary_candidates,
    mean_edge_length,
    star_radius_ratios,
    tangent_candidates,
)

__all__ = ["QUALITY_FLOOR", "raise_min_quality"]


def _star_scores(X, uv, Fo, VF, verts, Xc, uvc, face, input_normals):
    """Smallest radius ratio over the faces around each vertex, for candidate positions of
    the vertex (see :func:`star_radius_ratios`), (p, c)."""
    q, starts = star_radius_ratios(X, uv, Fo, VF, verts, Xc, uvc, face, input_normals)
    return np.minimum.reduceat(q, starts, axis=0)


# The smallest radius ratio the remeshing aims at: the snapping keeps every face it
# touches above it, and held (snapped) vertices move only to mend a face below it.
QUALITY_FLOOR = 0.3
_STEPS = np.array([0.02, 0.06, 0.15, 0.3, 0.5])
# Rounds without a rise of the smallest radius ratio after which the search stops.
# Measured on the 7 disk meshes at both face counts: 75 gave the same meshes as no
# limit, and 30 the same minimum, mean and Hausdorff distance as 75, the 1st percentile
# within 0.001 (human_face at half its face count: 30 rounds of the first search instead
# of 75, 0.14 s less); 12 lowered the minimum there from 0.465 to 0.387.
_PATIENCE = 30


def raise_min_quality(
    X, uv, face, s, out, surface, pinned, held, curve, target, rounds, held_floor=QUALITY_FLOOR, guard=None
):
    """Pattern search that raises the smallest radius ratio of the faces around the
    vertices of the worst faces, in place.

    Each round takes the vertices whose star (faces around them) has a radius ratio below
    ``target``, keeps an independent set of them (a vertex whose star is worse than that
    of every such neighbour), and moves each to the best of a pattern of candidate
    positions if it raises the smallest radius ratio of its star. Interior candidates are
    offsets of 0.02 to 0.5 times the vertex's mean edge length in 8 directions of its
    tangent plane, snapped onto the surface near the current position; boundary
    candidates slide along the input boundary polyline by the same arc lengths, staying
    between their neighbours. Candidates that fold a face in the disk or leave it turned
    over on the surface are rejected. A vertex that found no better position is left
    alone until a neighbour moves. The search stops after ``rounds`` rounds, or 30 rounds
    after the smallest radius ratio last rose.

    Parameters
    ----------
    X : (k, 3) float
        Output vertices on the surface (updated).
    uv : (k, 2) float
        Their disk positions (updated).
    face : (k,) int
        Input face under each output vertex, -1 on the boundary (updated).
    s : (b,) float
        Arc length of the output boundary vertices along ``curve`` (updated).
    out : OutputMesh
        The output's connectivity (:class:`~qcremesh.remeshing.meshes.OutputMesh`).
    surface : InputSurface
        The input surface and its disk map (:class:`~qcremesh.remeshing.meshes.InputSurface`).
    pinned : (k,) bool
        Vertices that stay.
    held : (k,) bool
        Vertices that move only when a face around them has a radius ratio below
        ``held_floor`` (those snapped onto the input, which keep the output close to it).
    curve : BoundaryCurve
        The input boundary.
    target : float
        Radius ratio below which a star is improved.
    rounds : int
        Maximum number of rounds.
    held_floor : float
        See ``held``.
    guard : DistanceGuard, optional
        Refuses the candidates that take an input vertex it watches too far from the
        output (:class:`~qcremesh.remeshing.guard.DistanceGuard`).
    """
    k = len(X)
    Fo, A, VF, bnd = out.F, out.A, out.VF, out.loop
    where_bnd = np.full(k, -1)
    where_bnd[bnd] = np.arange(len(bnd))
    # Faces turned over on the surface (in pockets the disk map compresses, a face can be
    # counter-clockwise in the disk and still face into the surface) count as negative
    # quality, so the search turns them back first.
    input_normals = surface.normals
    quality = StarQuality(X, Fo, VF, face, input_normals)
    q, qv = quality.q, quality.qv
    stuck = np.zeros(k, dtype=bool)
    best, since = q.min(), 0
    for _ in range(rounds):
        active = (qv < target) & ~pinned & ~stuck & ~(held & (qv >= held_floor))
        if not active.any() or since >= _PATIENCE:
            break
        sel = quality.worst_independent(A, active)
        reach = np.zeros(k)
        reach[sel] = mean_edge_length(X, A, sel)
        on_bnd = where_bnd[sel] >= 0
        best_X, best_uv = X[sel].copy(), uv[sel].copy()
        best_face, best_s = face[sel].copy(), np.zeros(len(sel))
        gain = np.zeros(len(sel), dtype=bool)
        inner = sel[~on_bnd]
        if len(inner):
            Xc, uvc, fc = tangent_candidates(X, out, inner, reach[inner], face, surface, _STEPS)
            score = _star_scores(X, uv, Fo, VF, inner, Xc, uvc, face, input_normals)
            if guard is not None:
                score[guard.excluded(X, Fo, VF, inner, Xc)] = -np.inf
            j = np.argmax(score, axis=1)
            rows = np.arange(len(inner))
            better = score[rows, j] > qv[inner] + 1e-9
            best_X[~on_bnd] = np.where(better[:, None], Xc[rows, j], X[inner])
            best_uv[~on_bnd] = np.where(better[:, None], uvc[rows, j], uv[inner])
            best_face[~on_bnd] = np.where(better, fc[rows, j], face[inner])
            gain[~on_bnd] = better
        if on_bnd.any():
            outer = sel[on_bnd]
            i = where_bnd[outer]
            Xc, uvc, sc = boundary_candidates(s, i, reach[outer], curve, _STEPS)
            score = _star_scores(X, uv, Fo, VF, outer, Xc, uvc, face, input_normals)
            if guard is not None:
                score[guard.excluded(X, Fo, VF, outer, Xc)] = -np.inf
            j = np.argmax(score, axis=1)
            rows = np.arange(len(outer))
            better = score[rows, j] > qv[outer] + 1e-9
            best_X[on_bnd] = np.where(better[:, None], Xc[rows, j], X[outer])
            best_uv[on_bnd] = np.where(better[:, None], uvc[rows, j], uv[outer])
            best_s[on_bnd] = np.where(better, sc[rows, j], s[i])
            gain[on_bnd] = better
        X[sel], uv[sel], face[sel] = best_X, best_uv, best_face
        s[where_bnd[sel[on_bnd]]] = best_s[on_bnd]
        stuck[sel[~gain]] = True
        moved = sel[gain]
        if len(moved):
            stuck[csr_rows(A, moved)[0]] = False
            quality.update(X, face, moved)
            if guard is not None:
                guard.update(X, Fo, VF, moved)
        since = 0 if q.min() > best else since + 1
        best = max(best, q.min())
