"""The input made ready for the disk map, the surface kept: what the validation refuses
and can be mended without moving the surface (repeated faces, unused vertices,
non-manifold edges and vertices, faces turned against their neighbours, needles and caps),
boundary edges far longer than those around them cut into pieces, and a surface of a few
faces split 1-to-4 or of long needles cut along their edges. Per-vertex data and a
sizing field follow the vertices."""

from __future__ import annotations

import numpy as np

from ..geometry.refine import refine_boundary, split_long_edges
from ..geometry.repair import repair_degenerate_faces
from ..mesh.subdivide import upsample
from ..mesh.topology import (
    boundary_edges,
    duplicate_faces,
    inconsistent_edges,
    needles_and_caps,
    nonmanifold_edges,
    nonmanifold_vertices,
    orient_faces,
    split_nonmanifold_edges,
    split_nonmanifold_vertices,
    unreferenced_vertices,
)
from ..mesh.validate import OrientationError
from .project import in_type

__all__ = ["LONG_BOUNDARY_RATIO", "refine_long_boundary", "refined", "renumbered", "repair_input", "upsampled"]

# Boundary edges more than this many times as long as the edges around them (the convex
# hull of a triangulated point set: 30-150 times) are cut into pieces where the surface
# around them is flat (:func:`qcremesh.geometry.refine.refine_boundary`). The disk meshes
# of ../shared/data: at most 3.7 times; their longest boundary edge is at most 3.7 times
# the median face side, which rules most inputs out before the local measure.
LONG_BOUNDARY_RATIO = 4.0


def refine_long_boundary(V, F, data, sizing, stats, loop=None):
    """The input with its boundary edges far longer than the edges around them cut into
    pieces, and its flat parts flipped to Delaunay
    (:func:`qcremesh.geometry.refine.refine_boundary`): vertices, faces, data and sizing
    (interpolated along the edges; data in their types), as they are where no edge is cut
    (``boundary_split_vertices`` in ``stats`` says one was). ``loop``, the boundary loop
    where known, spares finding the boundary edges."""
    B = boundary_edges(F) if loop is None else np.column_stack([loop, np.roll(loop, -1)])
    if not len(B):
        return V, F, data, sizing
    longest = np.linalg.norm(V[B[:, 1]] - V[B[:, 0]], axis=1).max()
    if longest <= LONG_BOUNDARY_RATIO * np.median(np.linalg.norm(V[F[:, 1]] - V[F[:, 0]], axis=1)):
        return V, F, data, sizing
    F_new, along = refine_boundary(V, F, LONG_BOUNDARY_RATIO)
    if F_new is None:
        return V, F, data, sizing
    stats["boundary_split_vertices"] = along.shape[0] - len(V)
    return (along @ V, F_new) + _interpolated(along, data, sizing)


def _interpolated(P, data, sizing):
    """Per-vertex data (in their types) and a sizing array (or None) at the vertices ``P
    @ V`` (P sparse, each new vertex a combination of the old ones)."""

    def carried(values):
        values = np.asarray(values)
        flat = np.asarray(values, dtype=np.float64).reshape(len(values), -1)
        return in_type((P @ flat).reshape((P.shape[0],) + values.shape[1:]), values.dtype)

    data = {k: carried(v) for k, v in data.items()} if data else data
    return data, None if sizing is None else P @ sizing


def refined(V, F, data, sizing, max_length):
    """The surface on vertices no farther apart than ``max_length`` along an edge
    (:func:`qcremesh.geometry.refine.split_long_edges`): vertices, faces, data and sizing
    interpolated along the edges (data in their types)."""
    F, P = split_long_edges(V, F, max_length)
    return (P @ V, F) + _interpolated(P, data, sizing)


def repair_input(V, F, data, sizing, stats):
    """The input made acceptable to the disk map where the validation refused it for
    what can be mended without moving the surface (more than 1e-3 of an edge): faces
    listed more than once are kept once, vertices no face uses dropped, sheets of faces
    that meet at an edge of more than two faces detached there
    (:func:`qcremesh.mesh.topology.split_nonmanifold_edges`) and vertices where two
    sheets touch split into one per sheet
    (:func:`qcremesh.mesh.topology.split_nonmanifold_vertices`), faces turned against
    their neighbours reversed (:func:`qcremesh.mesh.topology.orient_faces`, the
    majority's orientation kept), needles merged and caps flipped away
    (:func:`qcremesh.geometry.repair.repair_degenerate_faces`). Returns the new vertices,
    faces, per-vertex data and sizing field (of the vertices kept) and the input vertex
    each vertex is, counting what was done in ``stats``; None where nothing applies or
    a defect stands that this does not mend (an edge whose sheets meet again around its
    ends), which the validation then names."""
    n = len(V)
    repaired = False
    kept = np.arange(n)
    repeated = duplicate_faces(F)
    if len(repeated):
        F = np.delete(F, repeated, axis=0)
        stats["duplicate_faces"] = len(repeated)
        repaired = True
    unused = unreferenced_vertices(F, n)
    if len(unused):
        used = np.ones(n, dtype=bool)
        used[unused] = False
        kept = np.flatnonzero(used)
        V, F = V[kept], (np.cumsum(used) - 1)[F]
        stats["unreferenced_vertices"] = len(unused)
        repaired = True
    shared = nonmanifold_edges(F)
    if len(shared):
        F, copied = split_nonmanifold_edges(V, F)
        if len(nonmanifold_edges(F)):
            return None
        V, kept = V[copied], kept[copied]
        stats["split_edges"] = len(shared)
        repaired = True
    pinched = nonmanifold_vertices(F)
    if len(pinched):
        F, copied = split_nonmanifold_vertices(F)
        V, kept = V[copied], kept[copied]
        stats["split_vertices"] = len(pinched)
        repaired = True
    if len(inconsistent_edges(F)):
        try:
            F, turned = orient_faces(F)
        except ValueError as exc:
            raise OrientationError(
                "the surface is not orientable (as a Moebius strip): no orientation of its faces agrees across "
                "every edge"
            ) from exc
        stats["reoriented_faces"] = int(turned.sum())
        repaired = True
    needle, cap = needles_and_caps(V, F)
    if needle.any() or cap.any():
        V, F, merged = repair_degenerate_faces(V, F)
        kept = kept[merged]
        stats.update(repaired_needles=int(needle.sum()), repaired_caps=int(cap.sum()))
        repaired = True
    if not repaired:
        return None
    data = {k: np.asarray(v)[kept] for k, v in data.items()} if data else data
    sizing = sizing[kept] if sizing is not None else None
    return V, F, data, sizing, kept


def renumbered(vertices, kept):
    """``vertices`` as indices into ``kept`` (the input vertex of each vertex a repair kept,
    sorted), the first copy of each; -1 where gone."""
    vertices = np.asarray(vertices, dtype=np.int64)
    at = np.searchsorted(kept, vertices).clip(0, max(len(kept) - 1, 0))
    return np.where(kept[at] == vertices, at, -1)


def upsampled(V, F, data, sizing, enough):
    """The surface split 1-to-4 (:func:`qcremesh.mesh.subdivide.upsample`: the same
    surface, the input vertices first) until ``enough(F)``, with ``data`` and an array
    ``sizing`` interpolated along (data in their types): (V, F, data, sizing)."""
    fields = [V] + [np.reshape(v, (len(V), -1)) for v in (data or {}).values()]
    fields += [] if sizing is None or isinstance(sizing, str) else [np.reshape(sizing, (-1, 1))]
    X = np.column_stack(fields)
    while not enough(F):
        X, F = upsample(X, F, 1)
    parts = np.split(X, np.cumsum([f.shape[1] for f in fields])[:-1], axis=1)
    fine_data = {
        k: in_type(p.reshape((len(X),) + np.shape(v)[1:]), np.asarray(v).dtype)
        for (k, v), p in zip((data or {}).items(), parts[1:])
    }
    fine_sizing = parts[-1][:, 0] if len(parts) > 1 + len(fine_data) else sizing
    return parts[0], F, fine_data if data else data, fine_sizing
