"""Where a disk map crowds the boundary: arcs of the circle much shorter than the surface
boundary they carry.

A conformal map onto the disk shrinks a protrusion exponentially: along a strip w wide
the harmonic measure of the boundary falls as exp(-pi x / w) with the distance x from
where the map is centred, so the legs of a camel cut open along slits (camel_b.obj) get
arcs down to 5e-5 of their share of the boundary length. Landmarks spread in the disk
cannot follow that far (their Delaunay triangles there have their corners 1e-9 apart),
and the remesh gets slivers at the tips of the protrusions.
"""

from __future__ import annotations

import numpy as np

__all__ = ["crowded_arcs"]


def crowded_arcs(V, uv, bnd, ratio):
    """Runs of boundary vertices where the disk map's boundary arc per unit of boundary
    length falls below ``ratio`` times its mean.

    At each boundary vertex b the crowding is

        r_b = (dtheta_b / 2 pi) / (l_b / L),

    the share of the circle of its dual arc (half of each circle arc to its neighbours)
    over its share of the boundary length (half of each boundary edge; L the length of
    the boundary), 1 for a map that spreads the boundary uniformly.

    Parameters
    ----------
    V : (n, 3) float
    uv : (n, 2) float
        Disk map, boundary on the circle.
    bnd : (b,) int
        Boundary loop, in the order of increasing angle.
    ratio : float

    Returns
    -------
    start : (k,) int64
        Position in ``bnd`` of the first vertex of each run (the runs in order along the
        loop; one that wraps around past ``bnd[0]`` starts before its end).
    count : (k,) int64
        Number of vertices of each run (all of ``bnd`` when every vertex is crowded).
    crowding : (b,) float
        r at each boundary vertex.
    """
    theta = np.unwrap(np.arctan2(uv[bnd, 1], uv[bnd, 0]))
    arc = np.diff(np.r_[theta, theta[0] + 2 * np.pi])
    arc = (arc + np.roll(arc, 1)) / 2
    length = np.linalg.norm(V[np.roll(bnd, -1)] - V[bnd], axis=1)
    length = (length + np.roll(length, 1)) / 2
    crowding = (arc / (2 * np.pi)) / (length / length.sum())
    low = crowding < ratio
    if low.all():
        return np.zeros(1, dtype=np.int64), np.array([len(bnd)]), crowding
    start = np.flatnonzero(low & ~np.roll(low, 1))
    end = np.flatnonzero(low & ~np.roll(low, -1))
    # each run ends at the first end at or after its start, going round the loop
    end = end[np.searchsorted(end, start) % len(end)]
    return start, (end - start) % len(bnd) + 1, crowding
