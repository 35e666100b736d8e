"""Midpoint (1-to-4) subdivision of triangle meshes."""

from __future__ import annotations

import numpy as np

from .topology import _edge_keys, half_edges

__all__ = ["upsample"]


def upsample(V, F, levels=1):
    """Split every triangle into four at its edge midpoints, ``levels`` times.

    A new vertex is added at the midpoint of every edge (numbered ``n + e`` in the order
    of the sorted undirected edges), and triangle (a, b, c) becomes (a, ab, ca),
    (ab, b, bc), (ca, bc, c) and (ab, bc, ca), which keeps the orientation. The geometry is
    unchanged: each new triangle is similar to its parent. The vertex positions are
    any per-vertex data that interpolates linearly (3D positions, disk coordinates).

    Parameters
    ----------
    V : (n, d) float
    F : (m, 3) int
    levels : int
        Number of subdivisions (0 returns copies of the input).

    Returns
    -------
    V : (n + e, d) float
        The first ``n`` rows are the input vertices.
    F : (4 m, 3) int64
        Row ``f`` of the input becomes rows ``4 f .. 4 f + 3`` of the output.
    """
    V = np.array(V, dtype=np.float64)
    F = np.array(F, dtype=np.int64)
    for _ in range(levels):
        n, m = len(V), len(F)
        key = _edge_keys(half_edges(F), n)
        ukey, inv = np.unique(key, return_inverse=True)
        lo, hi = ukey // n, ukey % n
        V = np.concatenate([V, 0.5 * (V[lo] + V[hi])])
        mid = (n + inv).reshape(3, m).T  # columns: ab, bc, ca
        a, b, c = F.T
        ab, bc, ca = mid.T
        F = np.stack(
            [
                np.column_stack([a, ab, ca]),
                np.column_stack([ab, b, bc]),
                np.column_stack([ca, bc, c]),
                np.column_stack([ab, bc, ca]),
            ],
            axis=1,
        ).reshape(-1, 3)
    return V, F
