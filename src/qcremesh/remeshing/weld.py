"""The remeshes of the pieces of a cut surface joined back into one mesh: the two sides of
every cut welded into one vertex each, level by level of the multiresolution hierarchy,
and where a weld went wrong."""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..geometry.threads import query_workers
from ..mesh.cut import coincident_boundary_pairs, weld_cut
from ..mesh.topology import (
    boundary_edges,
    boundary_loops,
    duplicate_faces,
    euler_characteristic,
    nonmanifold_edges,
    nonmanifold_vertices,
    repeated_corner_faces,
)
from ..mesh.validate import TopologyError
from .result import RemeshResult

__all__ = [
    "WELD_TOLERANCE",
    "WeldError",
    "crack_hint",
    "join_pieces",
    "weld_defects",
    "weld_levels",
    "weld_tolerance",
]

# Distance, in mean boundary edge lengths, within which the boundary vertices of the two
# sides of a cut are one vertex when welded. They are the same arc length along the same
# polyline, but each side gets its point through its own disk map's boundary angles,
# which where the map crowds (arcs of 1e-6 rad) keep position to about 1e-9 of an edge:
# Hand1.off at half its face count with a curvature sizing field had two seam vertices
# 1.0x of 1e-9 edge from their twins, and its weld failed.
WELD_TOLERANCE = 1e-7


class WeldError(TopologyError):
    """The remesh of a surface cut open does not weld back into its topology."""


def weld_tolerance(X, F):
    """WELD_TOLERANCE of the mean boundary edge length of (X, F)."""
    border = boundary_edges(F)
    return WELD_TOLERANCE * np.linalg.norm(X[border[:, 0]] - X[border[:, 1]], axis=1).mean()


def weld_levels(levels, join, chi, loops):
    """Each level (X, F) of a remesh joined by ``join(X, F, tol)`` -> (X, F, kept) (a
    ValueError where it cannot; ``tol`` WELD_TOLERANCE of the level's mean boundary edge
    length) and kept where it then has Euler characteristic ``chi``, ``loops`` boundary
    loops, only manifold edges and faces of three distinct vertices, no two on the same
    three (a closed piece asked for 4 faces welded into two faces, each with two corners
    merged). Returns the output level's (X, F, kept) and the hierarchy, which starts
    above the last coarser level that does not join so, or whose join dropped faces
    (which then no longer split 1-to-4 into the next level's); None where the output
    level does not join."""

    def joined(X, Fo):
        try:
            Xw, Fw, kept = join(X, Fo, weld_tolerance(X, Fo))
        except ValueError:
            return None
        try:
            ok = (
                len(Fw) > 0
                and euler_characteristic(Fw) == chi
                and not len(nonmanifold_edges(Fw))
                and not repeated_corner_faces(Fw).any()
                and not len(duplicate_faces(Fw))
                and len(boundary_loops(Fw)) == loops
            )
        except ValueError:
            # (boundary edges not consistently oriented: two faces turned against each
            # other across a welded vertex)
            ok = False
        return (Xw, Fw, kept) if ok else None

    # the output level first: the coarser ones only where it joins
    output = joined(*levels[-1])
    if output is None:
        return None
    welded = [joined(X, Fo) for X, Fo in levels[:-1]] + [output]
    intact = [level is not None and len(level[1]) == len(f) for level, (_, f) in zip(welded, levels)]
    first = max([i + 1 for i, ok in enumerate(intact[:-1]) if not ok], default=0)
    hierarchy = [level[:2] for level in welded[first:]] if intact[-1] else [welded[-1][:2]]
    return welded[-1], hierarchy


def weld_defects(X, F, segments, labels=None):
    """Where the weld of a remeshed cut disk (X, F) along its cut (``segments``, (s, 2,
    3); ``labels`` as :func:`~qcremesh.mesh.cut.weld_cut` takes them) goes wrong: the points
    of the welded mesh at its non-manifold edges and vertices, and the centroids of the
    faces it folds onto others (and drops), (k, 3); none where it goes wrong otherwise or
    not at all."""
    try:
        Xw, Fw, _ = weld_cut(X, F, segments, weld_tolerance(X, F), labels)
    except ValueError:
        return np.zeros((0, 3))
    # each vertex's welded one: itself, or the mean of it and its twins, the nearest
    merged = cKDTree(Xw).query(X, workers=query_workers(len(X)))[1][F]
    _, group, size = np.unique(np.sort(merged, axis=1), axis=0, return_inverse=True, return_counts=True)
    folded = size[group.ravel()] > 1
    bad = np.union1d(np.unique(nonmanifold_edges(Fw)), nonmanifold_vertices(Fw)) if len(Fw) else []
    return np.concatenate([Xw[bad], X[F[folded]].mean(1)])


def crack_hint(V, F):
    """What an error says of boundary vertices at the same points as others: cracks
    between faces whose shared corners were written apart (a CAD part saved face by
    face), or seams written twice (a textured mesh), which
    :func:`qcremesh.mesh.cut.weld_seams` merges; "" where there are none."""
    twins = np.unique(coincident_boundary_pairs(V, F))
    if not len(twins):
        return ""
    border = np.unique(boundary_edges(F))
    return (
        f" ({len(twins)} of its {len(border)} boundary vertices lie at the same points as others: "
        "cracks between faces whose shared corners are not one vertex, or seams written twice; weld_seams=True "
        "(--weld-seams) merges them first)"
    )


def join_pieces(results, stats, faces_key):
    """The remeshes of several pieces (``results``) as one :class:`RemeshResult`.

    The levels are those all pieces have, from the output down (a piece with fewer
    levels than another starts the hierarchy at its own base mesh); the vertices are
    numbered level by level, every piece's coarser ones first. ``uv``, ``disk_levels``,
    ``mu`` and the stats are those of the largest piece remeshed (the one with the most
    output faces of those with ``disk_levels``; the others were kept as they were),
    joined with ``stats`` and ``stats[faces_key]`` (each piece's output faces), but the
    sharpest corner, its quality bound, the crowded share of the boundary and the draws,
    the worst piece's; the times are summed."""
    count = len(results)
    depth = min(len(r.levels) for r in results)
    levels = [[r.levels[len(r.levels) - depth + i] for r in results] for i in range(depth)]
    # Global numbering: level by level, piece by piece, the vertices new at that level.
    counts = np.array([[len(X) for X, _ in level] for level in levels])  # (depth, count)
    new = np.diff(np.vstack([np.zeros((1, count), dtype=np.int64), counts]), axis=0)
    start = np.cumsum(np.r_[0, new.ravel()])[:-1].reshape(depth, count)
    number = []
    for k in range(count):
        number.append(np.concatenate([start[i, k] + np.arange(new[i, k]) for i in range(depth)]))
    total = int(counts[-1].sum())
    joined = []
    for i, level in enumerate(levels):
        X = np.zeros((int(counts[i].sum()), 3))
        for k, (Xk, _) in enumerate(level):
            X[number[k][: len(Xk)]] = Xk
        joined.append((X, np.concatenate([number[k][Gk] for k, (_, Gk) in enumerate(level)])))
    out_data = {}
    for name in results[0].data:
        first = np.asarray(results[0].data[name])
        values = np.zeros((total,) + first.shape[1:], dtype=first.dtype)
        for k, r in enumerate(results):
            values[number[k]] = r.data[name]
        out_data[name] = values
    largest = max(range(count), key=lambda k: (len(results[k].disk_levels) > 0, len(results[k].F)))
    main = results[largest]
    stats = {**stats, **main.stats, faces_key: [len(r.F) for r in results]}
    # What the warnings read is the worst piece's.
    for name, worst in (("sharpest_corner_degrees", min), ("corner_quality_bound", min),
                        ("param_narrowest_share", max), ("draws", max)):
        values = [r.stats[name] for r in results if name in r.stats]
        if values:
            stats[name] = worst(values)
    times = {}
    for r in results:
        for name, t in r.times.items():
            times[name] = times.get(name, 0.0) + t
    V_out, F_out = joined[-1]
    return RemeshResult(V_out, F_out, main.uv, joined, out_data, main.disk_levels, main.mu, stats, times)
