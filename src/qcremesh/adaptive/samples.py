"""Samples of a triangle mesh spread by area, for the CVT of the landmarks where the
mesh's own vertices, subdivided, sample it unevenly (a fan of slivers)."""

from __future__ import annotations

import numpy as np

__all__ = ["area_samples"]

# The plastic number's reciprocals: the R2 sequence (i a1, i a2) mod 1 fills the unit
# square evenly at every length (Roberts' low-discrepancy sequence).
_PLASTIC = 1.3247179572447460
_R2 = np.array([1 / _PLASTIC, 1 / _PLASTIC**2])


def area_samples(F, area, count, fields):
    """About ``count`` points on the faces ``F``, as many on each face as its share of
    ``area``, at least one, spread within it by a low-discrepancy sequence, and the area
    each stands for.

    Face f gets n_f = ceil(count a_f / sum(a)) points, the next n_f points (u, v) of one
    R2 sequence in the unit square, folded into the triangle u + v <= 1 and taken as
    barycentric coordinates (1 - u - v, u, v) (an affine image of the triangle, so the
    points are even by area on every face, slivers included). Deterministic.

    Parameters
    ----------
    F : (m, 3) int
    area : (m,) float
        The area of each face (the measure to spread).
    count : int
    fields : list of (n, k) or (n,) float
        Per-vertex values (positions in the disk and on the surface, a density) to
        interpolate at the points.

    Returns
    -------
    values : list of (s, k) or (s,) float
        ``fields`` at the points.
    weight : (s,) float
        a_f / n_f for each point of face f: they sum to the faces' area.
    """
    F = np.asarray(F, dtype=np.int64)
    area = np.asarray(area, dtype=np.float64)
    per_face = np.maximum(np.ceil(count * area / area.sum()), 1).astype(np.int64)
    face = np.repeat(np.arange(len(F)), per_face)
    # one sequence through all faces: each face's run of it is even, and faces alike (a
    # fan) do not get their points at the same barycentric coordinates
    uv = np.mod(0.5 + np.arange(1, len(face) + 1)[:, None] * _R2, 1.0)
    folded = uv.sum(1) > 1
    uv[folded] = 1 - uv[folded]
    bary = np.column_stack([1 - uv.sum(1), uv])
    values = []
    for field in fields:
        field = np.asarray(field, dtype=np.float64)
        corners = field[F[face]]  # (s, 3) or (s, 3, k)
        values.append(np.einsum("sj,sj...->s...", bary, corners))
    return values, (area / per_face)[face]
