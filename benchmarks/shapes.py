"""Synthetic surfaces for the benchmark's creases part and the tests: CAD-like parts (no CAD
disk is among the meshes of ../shared/data: its one CAD part has cracks at T-junctions),
and closed surfaces with a thin tail.

Each function returns (V, F): float64 (n, 3) vertices and int64 (m, 3) faces, turned
outwards, deterministic.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import Delaunay


def _grid_faces(n):
    """Faces of an n x n grid of vertices numbered row by row, two per cell."""
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel()
    return np.concatenate([np.column_stack([a, a + n, a + n + 1]), np.column_stack([a, a + n + 1, a + 1])])


def box(spacing, top):
    """The unit cube's surface, its six sides (``top``) or the five but the top (a disk),
    each a grid whose lines are at ``spacing`` (positions in [0, 1]) both ways."""
    t = np.asarray(spacing, dtype=np.float64)
    a, b = (x.ravel() for x in np.meshgrid(t, t, indexing="ij"))
    zero, one = np.zeros_like(a), np.ones_like(a)
    sides = [(a, b, zero, True), (a, zero, b, False), (a, one, b, True), (zero, a, b, True), (one, a, b, False)]
    if top:
        sides.append((a, b, one, False))
    G = _grid_faces(len(t))
    V = np.concatenate([np.column_stack(side[:3]) for side in sides])
    F = np.concatenate([(G[:, ::-1] if side[3] else G) + s * len(t) ** 2 for s, side in enumerate(sides)])
    # the grid points the sides share made one vertex
    _, first, inverse = np.unique(np.round(V, 12), axis=0, return_index=True, return_inverse=True)
    return V[first], inverse.ravel()[F]


def open_box():
    """A box open at the top whose grid lines crowd towards its edges (slivers along them,
    as a CAD tessellation has): 2,250 faces."""
    t = np.cumsum(np.r_[0.0, 1.4 ** np.abs(np.arange(-7, 8))])
    return box(t / t[-1], top=False)


def cube():
    """A closed cube of 8 x 8 squares a side: 768 faces."""
    return box(np.linspace(0.0, 1.0, 9), top=True)


def polar_disk(height):
    """The unit disk on 20 rings of 48 vertices round a centre, raised to ``height(r)``:
    1,872 faces."""
    r, k = np.linspace(0.0, 1.0, 21)[1:], 48
    R, A = np.meshgrid(r, np.linspace(0.0, 2 * np.pi, k, endpoint=False), indexing="ij")
    rings = np.column_stack([(R * np.cos(A)).ravel(), (R * np.sin(A)).ravel(), height(R).ravel()])
    V = np.vstack([[0.0, 0.0, float(height(np.zeros(1))[0])], rings])
    ring = np.arange(k)
    F = [np.column_stack([np.zeros(k, dtype=np.int64), 1 + ring, 1 + (ring + 1) % k])]
    for i in range(len(r) - 1):
        a0, a1 = 1 + i * k + ring, 1 + i * k + (ring + 1) % k
        F += [np.column_stack([a0, a0 + k, a1 + k]), np.column_stack([a0, a1 + k, a1])]
    return V, np.concatenate(F)


def plateau():
    """A disk raised by 0.25 inside a ring 0.1 wide: a crease at each side of the ring
    (turning by 68 degrees), neither touching the boundary."""
    return polar_disk(lambda r: np.clip((0.6 - r) * 2.5, 0.0, 0.25))


def mesa():
    """A flat top of radius 0.5 on a cone of slope 2: one closed crease round the top
    (63 degrees), a sixth of the area inside it."""
    return polar_disk(lambda r: np.where(r <= 0.5 + 1e-9, 0.25, 0.25 - 2 * (r - 0.5)))


SHAPES = {"open_box": open_box, "cube": cube, "plateau": plateau, "mesa": mesa}


def plate_with_two_holes(gap, radius):
    """A 4 x 2 plate, bent slightly (z = 0.05 sin x), with two round holes of ``radius``
    side by side at its middle, ``gap`` apart: the Delaunay triangulation of a grid of
    spacing 0.025 and of 0.025-spaced points on the holes' circles, the faces over the
    holes left out."""
    step = 0.025
    centres = np.array([[2 - radius - gap / 2, 1.0], [2 + radius + gap / 2, 1.0]])
    x, y = np.meshgrid(np.arange(161) * step, np.arange(81) * step)
    grid = np.column_stack([x.ravel(), y.ravel()])
    away = np.all(np.linalg.norm(grid[:, None] - centres[None], axis=2) > radius + step / 2, axis=1)
    m = int(2 * np.pi * radius / step)
    t = 2 * np.pi * np.arange(m) / m
    rims = [c + radius * np.column_stack([np.cos(t), np.sin(t)]) for c in centres]
    P = np.concatenate([grid[away]] + rims)
    F = Delaunay(P).simplices
    F = F[np.all(np.linalg.norm(P[F].mean(1)[:, None] - centres[None], axis=2) > radius, axis=1)]
    return np.column_stack([P, 0.05 * np.sin(P[:, 0])]), F.astype(np.int64)


def ball_with_tail(tail_radius, rings=120, sectors=48):
    """A closed surface of revolution about the z axis: the unit ball's sphere for z in
    [-1, 1] and a tail of radius ``tail_radius`` from it to z = 2.5, rounded over its
    last 0.2; ``rings`` circles of ``sectors`` vertices between the two poles."""
    z = np.linspace(-1.0, 2.5, rings + 2)[1:-1]
    r = np.maximum(np.sqrt(np.clip(1 - z**2, 0, None)), tail_radius * np.sqrt(np.clip((2.5 - z) / 0.2, 0, 1)))
    t = 2 * np.pi * np.arange(sectors) / sectors
    ring = np.column_stack([np.outer(r, np.cos(t)).ravel(), np.outer(r, np.sin(t)).ravel(), np.repeat(z, sectors)])
    V = np.vstack([[0.0, 0.0, -1.0], ring, [0.0, 0.0, 2.5]])
    i, j = np.meshgrid(np.arange(rings - 1), np.arange(sectors), indexing="ij")
    a, b = 1 + i * sectors + j, 1 + i * sectors + (j + 1) % sectors
    c, d = b + sectors, a + sectors
    j = np.arange(sectors)
    first, last = 1 + j, 1 + (rings - 1) * sectors + j
    caps = [
        np.column_stack([np.zeros(sectors, dtype=np.int64), 1 + (j + 1) % sectors, first]),
        np.column_stack([last, 1 + (rings - 1) * sectors + (j + 1) % sectors, np.full(sectors, len(V) - 1)]),
    ]
    sides = [np.column_stack([a.ravel(), b.ravel(), c.ravel()]), np.column_stack([a.ravel(), c.ravel(), d.ravel()])]
    return V, np.concatenate(caps[:1] + sides + caps[1:]).astype(np.int64)
