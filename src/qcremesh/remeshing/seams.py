"""Smoothing across the seams of a remesh welded from pieces.

A surface that is not a disk is cut open along input edges, remeshed as a disk with its
boundary held and welded shut (:func:`qcremesh.remeshing.pipeline.remesh`); a disk whose
map crowds is cut into pieces remeshed on their own maps and welded back along the cuts.
Each piece relaxes on its own disk map, where the seam is boundary: its vertices stay
where the weld needs them, and the faces beside the seam keep the shape they had before
the relaxation. The cut follows input edges, jagged at the output's scale, so those faces
are sheared: within 1.5 output edges of the seam, mean radius ratio 0.94 / 0.93 on
alex_3 / decimated-max at their face counts (82 / 79 % above 0.9), against 0.99
elsewhere.

Once welded, the seam is inside the surface and no disk map spans it, so the vertices
around it are smoothed on the input surface itself: each sweep moves them tangentially
towards the mean of their neighbours
(:func:`~qcremesh.remeshing.smoothing.smooth_targets`) and puts them back onto the input
surface at the closest point among the input faces around the one each was on
(:func:`~qcremesh.remeshing.onsurface.closest_point_near`, a local search that does not
jump across a thin part), the seam vertices too. A vertex whose move turns a face
against the input surface under it (:func:`~qcremesh.remeshing.stars.input_up`, which
does not judge a face across a fold of the input), or takes a face below the smaller of
its radius ratio and SEAM_FLOOR, stays where it was in that sweep, and so do its neighbours; one
whose move takes an input vertex farther from the output than half the mean edge length
and than it is stays too (:class:`~qcremesh.remeshing.guard.DistanceGuard`). The corners
of the output faces nearest to input vertices more than a quarter of the mean edge length
from them (pocket bottoms and tips that the snapping reached) do not move at all: moving
them one by one under the guard still took camel_b's Hausdorff distance at half its face
count from 1.61 to 1.93 %.

The borders of charts (:func:`qcremesh.param.charts.disk_charts`) are jagged at the
output's scale on a marching-cubes grid, and the floor blocks most of the way to
straightening them: there ``free_sweeps`` come first, in which a face may take any shape
but turned over; the vertices of the faces that end them below the smaller of their
radius ratio and SEAM_FREE_FLOOR go back where they were (until no face does), and the
guarded sweeps follow (numbers at :data:`qcremesh.remeshing.pipeline.CHART_FREE_SWEEPS`).

Measured at the input's face count / half (seed 0), faces within 1.5 output edges of the
cut, mean radius ratio and share above 0.9, without -> with: alex_3 0.939 / 0.924 ->
0.980 / 0.957 (82 / 76 -> 96 / 90 %), decimated-max 0.934 / 0.941 -> 0.983 / 0.971
(79 / 83 -> 99 / 94 %), Hand1 0.940 / 0.919 -> 0.979 / 0.976 (83 / 75 -> 98 / 96 %);
the whole output's share above 0.9 alex_3 98.2 / 96.8 -> 98.4 / 97.1 %, decimated-max
98.3 / 97.6 -> 99.4 / 98.4 %, Hand1 99.1 / 98.2 -> 99.6 / 99.2 %, camel_b (its crowded
pieces' seams) 90.5 / 83.5 -> 90.9 / 84.7 %; the smallest radius ratio the same or
higher (alex_3 at its face count 0.517 -> 0.658, Hand1 0.396 -> 0.502), the Hausdorff
distances the same. With SEAM_FLOOR 0.5 the means were the same but alex_3's smallest
radius ratio at half fell from 0.658 to 0.527; 4 rings and 40 sweeps raised the faces
along the cut by 0.001-0.003 more for twice the time. Hand1 takes 0.6 / 0.7 s more at its
face count / half in the benchmark (8.21 / 4.49 -> 8.94 / 5.12 s; two seams: its cut
disk's crowded pieces, then the cut).
"""

from __future__ import annotations

import numpy as np

from ..geometry.distance import point_mesh_distance
from ..geometry.locate import interpolate_barycentric
from ..geometry.operators import face_normals
from ..geometry.quality import radius_ratio, surface_side_quality
from ..mesh.cut import points_on_segments
from ..mesh.topology import adjacency_matrix, boundary_edges, edges, vertex_face_incidence
from .compiled import smooth_targets_kernel
from .guard import DistanceGuard
from .onsurface import closest_point_near
from .project import in_type
from .smoothing import edge_lengths, smooth_targets
from .stars import input_up

__all__ = ["smooth_seams"]

# Rings of output vertices around the seam that move, sweeps, the fraction of the way to
# the neighbours' mean per sweep (as the relaxation's), and the radius ratio below which
# no face goes unless it was there already.
SEAM_RINGS = 3
SEAM_SWEEPS = 20
SEAM_STEP = 0.5
SEAM_FLOOR = 0.7
# Radius ratio below which no face ends the free sweeps unless it was there already.
SEAM_FREE_FLOOR = 0.3


def _on_edges(X, V, E):
    """Which of the points ``X`` lie on the input edges ``E`` (within 1e-9 of the
    input's bounding-box diagonal), (k,) bool."""
    E = np.asarray(E, dtype=np.int64).reshape(-1, 2)
    return points_on_segments(X, V[E[:, 0]], V[E[:, 1]], 1e-9 * np.linalg.norm(np.ptp(V, axis=0)))


def smooth_seams(
    X, Fo, V, F, seam, held=None, data=None, out_data=None, rings=SEAM_RINGS, sweeps=SEAM_SWEEPS, free_sweeps=0
):
    """Tangential smoothing, on the input surface, of the output vertices within
    ``rings`` edges of a seam.

    Parameters
    ----------
    X : (k, 3) float
        Output vertices, on the input surface.
    Fo : (l, 3) int
        Output faces, welded across the seam.
    V : (n, 3) float
    F : (m, 3) int
        The input surface (not cut).
    seam : (s, 2) int
        The input edges the pieces were cut along; output vertices on them (within
        1e-9 of the input's bounding-box diagonal) are the seam's.
    held : (h, 2) int, optional
        Input edges whose output vertices stay (kept creases), as the output's boundary
        always does.
    data : dict of (n, ...) arrays, optional
        Per-vertex attributes of the input.
    out_data : dict of (k, ...) arrays, optional
        The same of the output; at the moved vertices they are interpolated from
        ``data`` again (in their type, as
        :func:`~qcremesh.remeshing.project.project_to_surface` gives them).
    rings : int
    sweeps : int
    free_sweeps : int
        Sweeps first in which a face may get worse to any shape but turned over; the
        vertices of the faces that then end below the smaller of their radius ratio and
        SEAM_FREE_FLOOR go back where they were (and so on, until no face does), and the
        ``sweeps`` follow.

    Returns
    -------
    X : (k, 3) float
        New positions (the vertices that did not move as they were).
    out_data : dict of (k, ...) arrays
        The output attributes at the new positions (``{}`` where ``out_data`` is None).

    The moved vertices are those within ``rings`` of a seam vertex that are neither on
    the output's boundary nor on a ``held`` edge.
    """
    X = np.array(X, dtype=np.float64)
    Fo = np.asarray(Fo)
    k = len(X)
    out = {name: np.array(values) for name, values in (out_data or {}).items()}
    band = _on_edges(X, V, seam)
    if not band.any():
        return X, out
    A = adjacency_matrix(Fo, k).tocsr()
    A.sort_indices()
    for _ in range(rings):
        band = band | (A @ band.astype(np.float64) > 0)
    band[boundary_edges(Fo).ravel()] = False
    if held is not None:
        band &= ~_on_edges(X, V, held)
    VF = vertex_face_incidence(Fo, k).tocsr()
    E = edges(Fo)
    # the corners of the output faces nearest to the input vertices farther from them
    # than a quarter of an edge (pocket bottoms and tips the snapping reached) stay
    guard = DistanceGuard(X, Fo, VF, V, edge_lengths(X, E).mean() / 2)
    band[Fo[guard.face[guard.distance > guard.limit / 2]].ravel()] = False
    verts = np.flatnonzero(band)
    if len(verts) == 0:
        return X, out
    vertex_faces = vertex_face_incidence(F, len(V)).tocsr()
    ring = A[verts]
    # the faces that can change, and the input faces under their corners
    around = np.flatnonzero(np.asarray(VF[verts].sum(0)).ravel() > 0)
    corners = np.unique(Fo[around])
    face = np.full(k, -1, dtype=np.int64)
    face[corners] = point_mesh_distance(X[corners], V, F)[1]
    Fa = Fo[around]
    input_normals = face_normals(V, F)
    targets_of = smooth_targets_kernel() or smooth_targets
    bary = np.zeros((k, 3))
    moved = np.zeros(k, dtype=bool)

    def sweep(count, floor):
        nonlocal X, face, bary
        for _ in range(count):
            new_X, new_face, new_bary = X.copy(), face.copy(), bary.copy()
            new_face[verts], new_X[verts], new_bary[verts] = closest_point_near(
                targets_of(X, verts, ring, Fo, VF, E, SEAM_STEP), face[verts], V, F, vertex_faces
            )
            up = input_up(Fa, new_face, input_normals)
            old = surface_side_quality(X, Fa, up)
            back = np.zeros(k, dtype=bool)
            back[verts[guard.excluded(X, Fo, VF, verts, new_X[verts][:, None])[:, 0]]] = True
            new_X[back], new_face[back], new_bary[back] = X[back], face[back], bary[back]
            while True:
                new = surface_side_quality(new_X, Fa, up)
                bad = ((new < 0) & (old > 0)) | (np.abs(new) < np.minimum(np.abs(old), floor))
                grow = np.zeros(k, dtype=bool)
                grow[Fa[bad].ravel()] = True
                grow &= band & ~back
                if not grow.any():
                    break
                back |= grow
                new_X[grow], new_face[grow], new_bary[grow] = X[grow], face[grow], bary[grow]
            step = band & ~back
            if not step.any():
                break
            moved[step] = True
            X, face, bary = new_X, new_face, new_bary
            guard.update(X, Fo, VF, np.flatnonzero(step))

    if free_sweeps:
        start_X, start_face = X.copy(), face.copy()
        sweep(free_sweeps, 0.0)
        # the vertices of the faces that ended below the smaller of their radius ratio
        # and SEAM_FREE_FLOOR go back, until none is
        before = radius_ratio(start_X, Fa)
        while True:
            worse = radius_ratio(X, Fa) < np.minimum(before, SEAM_FREE_FLOOR)
            back = np.zeros(k, dtype=bool)
            back[Fa[worse].ravel()] = True
            back &= moved
            if not back.any():
                break
            X[back], face[back], moved[back] = start_X[back], start_face[back], False
            guard.update(X, Fo, VF, np.flatnonzero(back))
    sweep(sweeps, SEAM_FLOOR)
    changed = np.flatnonzero(moved)
    for name in out:
        source = np.asarray(data[name])
        out[name][changed] = in_type(
            interpolate_barycentric(F, face[changed], bary[changed], source.astype(np.float64)), source.dtype
        )
    return X, out
