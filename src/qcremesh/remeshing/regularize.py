"""The last stage of the relaxation: a search that raises the share of well-shaped faces.

The smoothing sweeps leave faces a little off equilateral where the surface bends, along
the boundary and around the base mesh's irregular vertices, and the minimum-quality
search (:mod:`qcremesh.remeshing.min_quality`) only looks at the worst of them. This
search moves the vertices of every star with a face below a radius ratio of 0.9, one
independent set at a time, to the candidate position with the most faces of its star at
or above 0.9, ties going to the higher mean of the radius ratios capped at 0.9. The
candidates of an interior vertex are tangent offsets of 0.06, 0.15 and 0.3 times its mean
edge length in 8 directions, snapped onto the surface
(:func:`~qcremesh.remeshing.stars.tangent_candidates`); a boundary vertex slides along
the input boundary by the same lengths (corners stay), where that does not take the
output boundary farther from the input boundary's vertices between its two neighbours
(:func:`~qcremesh.remeshing.stars.boundary_deviation`). A move never lowers the star's
smallest radius ratio (below 0.9) or its mean radius ratio, and never folds a face in the
disk or turns one over on the surface; the vertices snapped onto the input and their
neighbours stay.

Measured at 20 rounds against none, on the seven disk meshes of ``../shared/data`` other
than camel_b at their face count and half of it: faces with q > 0.9 up on all 14 runs
(human_face 98.4 / 96.6 -> 98.6 / 97.1 %, human_brain 98.5 / 96.3 -> 98.8 / 97.1 %,
fran_cut 97.7 / 95.7 -> 98.3 / 96.8 %), mean radius ratio the same or higher (up to
1.5e-3), smallest the same or higher (head_neck_cut 0.667 -> 0.711, foot at half 0.661 ->
0.721); Hausdorff distance the same but on hand.ply (0.20 / 0.24 -> 0.22 / 0.26 %, at the
wrist), human_brain and venus at half (0.58 -> 0.62, 2.16 -> 2.25 %) and fran_cut (0.90 ->
0.91 %); 0.07 s on human_face.obj, 0.1 s on hand.ply, 0.2 s on human_brain.ply.

Tried: sliding the boundary vertices without the boundary condition raised the share
more (human_face 98.8 / 97.4 %, fran_cut 98.8 / 97.4 %) but took hand.ply's Hausdorff
distance at half to 0.30 % (an input boundary vertex at the wrist); moving the
neighbours of the snapped vertices as well, human_brain at half 0.68 %. Scoring the faces
above 0.9 alone, without holding the star's mean, raised the share more (human_face 98.9
/ 97.5 %, human_brain 99.1 / 97.8 %) by pushing faces just over 0.9 at the expense of
others: camel_b's mean radius ratio fell 0.919 -> 0.912 and its Hausdorff distance rose
1.69 -> 2.81 %. Five step lengths (0.02 and 0.5 as well) took longer for less; the
position at which each face of the star would be equilateral, averaged, as the only
direction gained half as much. Letting the neighbours of the snapped vertices move, and
the snapped vertices as well where their star stays within 0.2 of their mean edge length
of the input vertex that pulled them (or no farther than it is), raised the share on all
14 runs (seeds 0-1: human_brain at half 97.6 -> 98.2 %, human_face at half 97.3 -> 97.5
%, its smallest radius ratio 0.47 -> 0.54) but took the Hausdorff distance of human_brain
at its face count from 0.470 to 0.506 % (seeds 0-3, up on three) and of human_face at
seed 0 from 0.377 to 0.422 % (an output edge across the groove under the lower eyelid,
which no input vertex measures); the neighbours alone, 0.477 -> 0.510 % on human_brain at
its face count (seeds 0-1).
"""

from __future__ import annotations

import numpy as np

from .onsurface import csr_rows
from .stars import (
    StarQuality,
    boundary_candidates,
    boundary_deviation,
    mean_edge_length,
    star_radius_ratios,
    tangent_candidates,
)

__all__ = ["GOOD_QUALITY", "raise_regular_fraction"]

# Radius ratio from which a face counts as well shaped.
GOOD_QUALITY = 0.9
_STEPS = np.array([0.06, 0.15, 0.3])


def _best_candidates(X, uv, Fo, VF, verts, Xc, uvc, face, input_normals, excluded=None):
    """For candidate positions of independent vertices, the first of which is where the
    vertex is, some ``excluded`` ((p, c) bool): the index of the best (see the module
    documentation) and whether it is better than staying, (p,) each."""
    qc, starts = star_radius_ratios(X, uv, Fo, VF, verts, Xc, uvc, face, input_normals)
    size = np.diff(np.r_[starts, len(qc)])
    score = np.add.reduceat(
        (qc >= GOOD_QUALITY) + np.minimum(qc, GOOD_QUALITY) / np.repeat(size, size)[:, None], starts, axis=0
    )
    # No move lowers the star's smallest radius ratio (below 0.9) or its mean, or leaves a
    # face folded in the disk or turned over on the surface (-1); a star with such a face
    # is left to the minimum-quality search.
    lowest = np.minimum.reduceat(qc, starts, axis=0)
    total = np.add.reduceat(qc, starts, axis=0)
    score[(lowest < 0) | (lowest < np.minimum(lowest[:, :1], GOOD_QUALITY)) | (total < total[:, :1])] = -np.inf
    if excluded is not None:
        score[excluded] = -np.inf
    j = np.argmax(score, axis=1)
    return j, (score[np.arange(len(verts)), j] > score[:, 0] + 1e-6) & (lowest[:, 0] >= 0)


def _with_staying(here, candidates):
    """The candidates (p, c, ...) with each vertex's own position ``here`` (p, ...) first."""
    return np.concatenate([here[:, None], candidates], axis=1)


def raise_regular_fraction(X, uv, face, s, out, surface, movable, curve, rounds, guard=None):
    """Pattern search that raises the number of faces with a radius ratio of at least
    0.9, in place (see the module documentation).

    Each round takes the movable vertices with a face below 0.9 around them, keeps an
    independent set of them (worst star first), and moves each to the best of its
    candidate positions, if that is better than where it is: offsets in the tangent plane
    snapped onto the surface for interior vertices, slides along the input boundary for
    boundary vertices. A vertex that found none is left alone until a neighbour moves.
    The search stops after ``rounds`` rounds or when no vertex is left to try.

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
    movable : (k,) bool
        Vertices that may move.
    curve : BoundaryCurve
        The input boundary.
    rounds : int
        Maximum number of rounds.
    guard : DistanceGuard, optional
        Refuses the candidates that take an input vertex it watches too far from the
        output (:class:`~qcremesh.remeshing.guard.DistanceGuard`).
    """
    k = len(X)
    Fo, A, VF, bnd = out.F, out.A, out.VF, out.loop
    where_bnd = np.full(k, -1)
    where_bnd[bnd] = np.arange(len(bnd))
    input_normals = surface.normals
    quality = StarQuality(X, Fo, VF, face, input_normals)
    stuck = np.zeros(k, dtype=bool)
    for _ in range(rounds):
        active = (quality.qv < GOOD_QUALITY) & movable & ~stuck
        if not active.any():
            break
        sel = quality.worst_independent(A, active)
        reach = mean_edge_length(X, A, sel)
        on_bnd = where_bnd[sel] >= 0
        inner, outer = sel[~on_bnd], sel[on_bnd]
        better = np.zeros(len(sel), dtype=bool)
        if len(inner):
            Xc, uvc, fc = tangent_candidates(X, out, inner, reach[~on_bnd], face, surface, _STEPS)
            Xc, uvc, fc = _with_staying(X[inner], Xc), _with_staying(uv[inner], uvc), _with_staying(face[inner], fc)
            excluded = None if guard is None else guard.excluded(X, Fo, VF, inner, Xc)
            j, ok = _best_candidates(X, uv, Fo, VF, inner, Xc, uvc, face, input_normals, excluded)
            rows = np.flatnonzero(ok)
            X[inner[rows]], uv[inner[rows]], face[inner[rows]] = Xc[rows, j[rows]], uvc[rows, j[rows]], fc[rows, j[rows]]
            better[~on_bnd] = ok
        if len(outer):
            i = where_bnd[outer]
            Xc, uvc, sc = boundary_candidates(s, i, reach[on_bnd], curve, _STEPS)
            Xc, uvc, sc = _with_staying(X[outer], Xc), _with_staying(uv[outer], uvc), _with_staying(s[i], sc)
            # Nor does a slide take the output boundary farther from the input's.
            far = boundary_deviation(s, i, Xc, sc, X[bnd], curve)
            excluded = far > far[:, :1]
            if guard is not None:
                excluded |= guard.excluded(X, Fo, VF, outer, Xc)
            j, ok = _best_candidates(X, uv, Fo, VF, outer, Xc, uvc, face, input_normals, excluded)
            rows = np.flatnonzero(ok)
            X[outer[rows]], uv[outer[rows]], s[i[rows]] = Xc[rows, j[rows]], uvc[rows, j[rows]], sc[rows, j[rows]]
            better[on_bnd] = ok
        moved = sel[better]
        stuck[sel[~better]] = True
        if len(moved):
            stuck[csr_rows(A, moved)[0]] = False
            quality.update(X, face, moved)
            if guard is not None:
                guard.update(X, Fo, VF, moved)
