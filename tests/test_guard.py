"""The distance guard of the last searches of the relaxation."""

import numpy as np

from qcremesh import remesh
from qcremesh.geometry.distance import point_mesh_distance, point_triangle_distance
from qcremesh.geometry.locate import locate_points
from qcremesh.geometry.quality import radius_ratio
from qcremesh.mesh.io import read_mesh
from qcremesh.mesh.topology import vertex_face_incidence
from qcremesh.remeshing.guard import DistanceGuard
from qcremesh.remeshing.meshes import input_surface, output_mesh
from qcremesh.remeshing.snap import _move_towards

from conftest import DATA


def pit():
    """A plane with a pit: the input (a vertex 1 deep at the origin, a ring of 6 at radius
    0.2 and one of 6 at radius 2, at z = 0) and an output star over it (its centre at
    (0.1, 0, -0.5), its ring the input's outer ring)."""
    angle = np.arange(6) * np.pi / 3
    ring = np.column_stack([np.cos(angle), np.sin(angle), np.zeros(6)])
    V = np.vstack([[0.0, 0.0, -1.0], 0.2 * ring, 2 * ring])
    inner, outer = 1 + np.arange(6), 7 + np.arange(6)
    fan = np.column_stack([np.zeros(6, dtype=int), inner, np.roll(inner, -1)])
    strip = np.vstack([np.column_stack([inner, outer, np.roll(outer, -1)]),
                       np.column_stack([inner, np.roll(outer, -1), np.roll(inner, -1)])])
    X = np.vstack([[0.1, 0.0, -0.5], 2 * ring])
    Fo = np.column_stack([np.zeros(6, dtype=int), 1 + np.arange(6), 1 + np.roll(np.arange(6), -1)])
    return V, np.vstack([fan, strip]), X, Fo


def test_a_move_out_of_the_pit_is_refused():
    """The pit's bottom, 0.51 from the output, is watched; the centre may stay or go a
    little deeper, not up into the plane (the bottom would be 1 away, beyond the limit
    0.6 and beyond where it is), nor down onto the bottom (the pit's rim would be 0.9
    away)."""
    V, F, X, Fo = pit()
    VF = vertex_face_incidence(Fo, len(X))
    guard = DistanceGuard(X, Fo, VF, V, 0.6)
    assert 0 in guard.points
    bottom = np.flatnonzero(guard.points == 0)[0]
    assert 0.45 < guard.distance[bottom] < 0.55
    Xc = np.array([[[0.0, 0.0, -1.0], [0.1, 0.0, -0.5], [1.0, 0.0, 0.0], [0.1, 0.0, -0.6]]])
    assert guard.excluded(X, Fo, VF, np.array([0]), Xc).tolist() == [[True, False, True, False]]
    # A guard that allows 1.2 takes every move.
    assert not DistanceGuard(X, Fo, VF, V, 1.2).excluded(X, Fo, VF, np.array([0]), Xc).any()


def test_a_patch_moved_out_of_the_pit_is_refused():
    """The whole star as one patch, moved already: lifted 0.4 (the bottom then 0.91 away,
    beyond the limit 0.6 and where it was) it is refused, unless its patch allows 1;
    shifted sideways by 0.05 it is taken."""
    V, F, X, Fo = pit()
    VF = vertex_face_incidence(Fo, len(X))
    guard = DistanceGuard(X, Fo, VF, V, 0.6)
    faces, patch = np.arange(len(Fo)), np.zeros(len(Fo), dtype=int)
    up = X + [0.0, 0.0, 0.4]
    assert guard.excluded_patches(up, Fo, faces, patch, np.array([0.0])).tolist() == [True]
    assert guard.excluded_patches(up, Fo, faces, patch, np.array([1.0])).tolist() == [False]
    aside = X + [0.05, 0.0, 0.0]
    assert guard.excluded_patches(aside, Fo, faces, patch, np.array([0.0])).tolist() == [False]


def test_update_measures_the_watched_points_again():
    """Moved into the plane anyway, the centre leaves the pit's bottom 1 from the output."""
    V, F, X, Fo = pit()
    VF = vertex_face_incidence(Fo, len(X))
    guard = DistanceGuard(X, Fo, VF, V, 0.6)
    X[0] = [0.0, 0.0, 0.0]
    guard.update(X, Fo, VF, np.array([0]))
    assert np.isclose(guard.distance[guard.points == 0][0], 1.0)


def test_the_last_search_keeps_the_snapped_pocket():
    """human_face.obj at half its face count, seed 2: the snapping brought the output
    within 0.54 % of the diagonal of the input, and the last minimum-quality search took
    a snapped vertex back out of a pocket under the left eye, to 1.28 %. Measured at the
    pocket (the input vertices within 5 mm of where it was): on session 43's host 0.42 %
    with the guard, 1.30 % without; the largest distance there is at a nostril instead
    (0.72 %, 0.55 % on session 42's host), which the draw of landmarks moves."""
    V, F = read_mesh(DATA / "human_face.obj")
    result = remesh(V, F, faces=len(F) // 2, seed=2)
    diag = np.linalg.norm(V.max(0) - V.min(0))
    pocket = np.linalg.norm(V - [-0.0419, 0.2728, 0.0729], axis=1) < 0.005
    assert point_mesh_distance(V[pocket], result.V, result.F)[0].max() < 0.006 * diag
    assert radius_ratio(result.V, result.F).min() >= 0.3


def test_nothing_to_watch_on_a_plane():
    """With the pit filled, no input vertex stands off the output: nothing is watched,
    no move is refused and an update changes nothing."""
    V, F, X, Fo = pit()
    V[0, 2] = 0.0
    X[0] = [0.1, 0.0, 0.0]
    VF = vertex_face_incidence(Fo, len(X))
    guard = DistanceGuard(X, Fo, VF, V, 0.6)
    assert len(guard.points) == len(guard.distance) == len(guard.face) == 0
    Xc = np.array([[[0.0, 0.0, 1.0], [0.5, 0.0, 0.0]]])
    assert not guard.excluded(X, Fo, VF, np.array([0]), Xc).any()
    guard.update(X, Fo, VF, np.array([0]))
    assert len(guard.points) == 0


def test_the_snapping_stops_short_of_exposing_the_pit():
    """The pit's centre vertex pulled towards the inner ring at (0.2, 0, 0), which is not
    far from the output (no allowance): all the way would leave the pit's bottom about
    0.9 from the output; with the limit 0.6 the vertex goes only part of the way, the
    bottom staying within 0.6; with the limit 10 it goes all the way."""
    V, F, X, Fo = pit()
    out, surface = output_mesh(Fo, len(X)), input_surface(V, F, V[:, :2])
    face = locate_points(surface.disk_uv, F, X[:, :2])[0]
    for limit, all_the_way in ((0.6, False), (10.0, True)):
        Xt, uv, ft = X.copy(), X[:, :2].copy(), face.copy()
        guard = DistanceGuard(Xt, Fo, out.VF, V, limit)
        moved, whole = _move_towards(Xt, uv, ft, out, surface, np.array([0]), np.array([1]), np.zeros(1), guard)
        assert moved[0] and whole[0] == all_the_way
        bottom = point_triangle_distance(V[[0] * len(Fo)], *Xt[Fo].transpose(1, 0, 2))[0].min()
        if all_the_way:
            np.testing.assert_array_equal(Xt[0], V[1])
            assert bottom > 0.85
        else:
            assert 0.51 < bottom <= 0.6
