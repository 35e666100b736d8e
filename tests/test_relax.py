"""Unit tests of the relaxation stages on planar surfaces, where the answers are known."""

import numpy as np
import scipy.sparse as sp

from conftest import grid_disk
from qcremesh.adaptive.basemesh import delaunay_disk_mesh, hexagonal_disk_points
from qcremesh.geometry.distance import point_mesh_distance
from qcremesh.geometry.locate import interpolate_barycentric, locate_points
from qcremesh.geometry.operators import signed_doublearea
from qcremesh.geometry.quality import radius_ratio
from qcremesh.mesh.subdivide import upsample
from qcremesh.mesh.topology import adjacency_matrix, boundary_loop, edges, vertex_face_incidence
from qcremesh.remeshing.meshes import input_surface, output_mesh
from qcremesh.remeshing.min_quality import raise_min_quality
from qcremesh.remeshing.onsurface import BoundaryCurve, closest_point_near, nearest_per_owner
from qcremesh.remeshing import relax, snap
from qcremesh.remeshing.regularize import GOOD_QUALITY, raise_regular_fraction
from qcremesh.remeshing.relax import relax_on_surface
from qcremesh.remeshing.smoothing import boundary_arc_steps
from qcremesh.remeshing.snap import snap_to_far_points
from qcremesh.remeshing.stars import boundary_deviation


def plane(k):
    """A k x k grid of the unit square at z = 0, its vertices and their own 2D positions."""
    uv, F = grid_disk(k)
    return np.column_stack([uv, np.zeros(len(uv))]), F, uv


def test_the_meshes_of_a_grid():
    """The bundles the relaxation hands its stages, on a 5 x 5 grid: 16 boundary vertices
    in the loop, 56 edges (V - E + F = 1), the adjacency symmetric with each edge twice and
    the incidence each face thrice, the face normals +z, and each vertex's first face in
    vertex_faces one of its own."""
    V, F, uv = plane(5)
    out, surface = output_mesh(F, len(V)), input_surface(V, F, uv)
    assert len(out.loop) == 16 and len(out.E) == 56 and len(V) - len(out.E) + len(F) == 1
    assert (out.A != out.A.T).nnz == 0 and out.A.nnz == 2 * len(out.E) and out.VF.nnz == 3 * len(F)
    np.testing.assert_allclose(surface.normals, np.tile([0.0, 0.0, 1.0], (len(F), 1)))
    first = surface.vertex_faces.indices[surface.vertex_faces.indptr[:-1]]
    assert (F[first] == np.arange(len(V))[:, None]).any(1).all()


def test_closest_point_near_on_a_plane():
    """Points above a plane project straight down, from a start face a few faces away."""
    V, F, uv = plane(11)
    P = np.array([[0.33, 0.52, 0.2], [0.71, 0.18, -0.1]])
    start = locate_points(uv, F, np.array([[0.45, 0.45], [0.6, 0.3]]))[0]
    face, closest, bary = closest_point_near(P, start, V, F, vertex_faces=vertex_face_incidence(F, len(V)))
    np.testing.assert_allclose(closest, P * [1, 1, 0], atol=1e-12)
    np.testing.assert_allclose(np.einsum("kc,kcd->kd", bary, V[F[face]]), closest, atol=1e-12)


def flat_disk(spacing):
    """A triangulation of the unit disk at z = 0 (its own disk parameterization)."""
    k = int(round(2 * np.pi / spacing))
    uv, F = delaunay_disk_mesh(2 * np.pi * np.arange(k) / k, hexagonal_disk_points(spacing))
    return np.column_stack([uv, np.zeros(len(uv))]), F, uv


def _snap_setup(height, width=0.0, tip_uv=(0.125, 0.07)):
    """A coarse mesh of a plane (spacing 0.25) over a fine one (0.05) with a cone of
    ``height`` whose base has radius ``width`` (0: one raised vertex) inside a coarse
    face; the coarse vertices lifted onto it."""
    V, F, uv_in = flat_disk(0.05)
    tip = np.argmin(np.linalg.norm(uv_in - tip_uv, axis=1))
    V[tip, 2] = height
    if width > 0:
        V[:, 2] = height * np.maximum(0, 1 - np.linalg.norm(uv_in - uv_in[tip], axis=1) / width)
    X, Fo, uv = flat_disk(0.25)
    face, bary, _ = locate_points(uv_in, F, uv)
    X = np.einsum("kc,kcd->kd", bary, V[F[face]])
    return V, F, uv_in, tip, X, Fo, uv, face


def _snap(V, F, uv_in, X, Fo, uv, face, snapped=None, partial=None, passes=4):
    pinned = np.zeros(len(X), dtype=bool)
    snapped = np.zeros(len(X), dtype=bool) if snapped is None else snapped
    partial = np.zeros(len(X), dtype=bool) if partial is None else partial
    E = edges(Fo)
    mean_edge = np.linalg.norm(X[E[:, 0]] - X[E[:, 1]], axis=1).mean()
    snap_to_far_points(
        X, uv, face, output_mesh(Fo, len(X)), input_surface(V, F, uv_in), adjacency_matrix(F, len(V)), pinned,
        snapped, partial, mean_edge, passes,
    )
    assert not pinned.any() and not np.any(partial & ~snapped)
    return snapped


def test_snap_moves_the_nearest_vertex_onto_a_tip():
    """A tip the coarse mesh cuts across: the output vertex nearest the tip moves onto it
    and is flagged; the others stay."""
    V, F, uv_in, tip, X, Fo, uv, face = _snap_setup(0.3)
    before = X.copy()
    partial = np.zeros(len(X), dtype=bool)
    snapped = _snap(V, F, uv_in, X, Fo, uv, face, partial=partial)
    moved = np.flatnonzero(np.any(X != before, axis=1))
    assert len(moved) == 1 and snapped[moved[0]] and snapped.sum() == 1 and not partial.any()
    np.testing.assert_array_equal(X[moved[0]], V[tip])
    np.testing.assert_array_equal(uv[moved[0]], uv_in[tip])
    assert face[moved[0]] in np.flatnonzero((F == tip).any(axis=1))
    assert radius_ratio(X, Fo).min() >= 0.3


def test_snap_leaves_the_vertices_snapped_before():
    """A vertex flagged as snapped by an earlier call stays where it is (the tip pulls
    another vertex, or none)."""
    V, F, uv_in, tip, X, Fo, uv, face = _snap_setup(0.3)
    before = X.copy()
    (mover,) = np.flatnonzero(_snap(V, F, uv_in, X, Fo, uv, face))
    V, F, uv_in, tip, X, Fo, uv, face = _snap_setup(0.3)
    earlier = np.zeros(len(X), dtype=bool)
    earlier[mover] = True
    snapped = _snap(V, F, uv_in, X, Fo, uv, face, earlier.copy())
    np.testing.assert_array_equal(X[mover], before[mover])
    assert snapped[mover] and np.all(np.all(X == before, axis=1) | snapped)


def test_snap_falls_back_to_another_vertex_of_the_face(monkeypatch):
    """Where the vertex nearest a tip cannot move towards it at all (a neighbour pushed
    next to it leaves one of its faces near 0.3), nor with its rings draped after it (no
    sweeps here: it moves alone), the far point pulls another vertex of the output face
    closest to it, in a later pass, onto the tip."""
    monkeypatch.setattr(snap, "DRAPE_SWEEPS", 0)
    V, F, uv_in, tip, X, Fo, uv, face = _snap_setup(0.3)
    first = np.flatnonzero(_snap(V, F, uv_in, X.copy(), Fo, uv.copy(), face.copy()))
    np.testing.assert_array_equal(first, [47])
    uv[40] += [0.14, 0.07]
    X[40] = [*uv[40], 0.0]
    face[40] = locate_points(uv_in, F, uv[40:41])[0][0]
    before = X.copy()
    snapped = _snap(V, F, uv_in, X, Fo, uv, face)
    moved = np.flatnonzero(np.any(X != before, axis=1))
    np.testing.assert_array_equal(moved, [46])
    assert snapped.sum() == 1 and snapped[46]
    np.testing.assert_array_equal(X[46], V[tip])
    assert radius_ratio(X, Fo).min() >= 0.3


def test_snap_moves_part_of_the_way_up_a_cone_too_high(monkeypatch):
    """A cone so high that a vertex on its tip would leave a face below 0.3 (with no
    sweeps to drape its rings after it): the nearest vertex goes part of the way (a
    fraction of the disk segment, lifted onto the surface: up the cone), and every face
    stays above 0.3."""
    monkeypatch.setattr(snap, "DRAPE_SWEEPS", 0)
    V, F, uv_in, tip, X, Fo, uv, face = _snap_setup(1.0, width=0.3)
    before = X.copy()
    partial = np.zeros(len(X), dtype=bool)
    snapped = _snap(V, F, uv_in, X, Fo, uv, face, partial=partial)
    moved = np.flatnonzero(np.any(X != before, axis=1))
    assert len(moved) >= 1 and np.all(snapped[moved]) and snapped.sum() == len(moved)
    assert np.all(partial[moved])
    assert not np.any(np.all(X == V[tip], axis=1))
    assert np.all((X[moved, 2] > 0) & (X[moved, 2] < 1.0))
    d_before = np.linalg.norm(before[moved] - V[tip], axis=1)
    assert np.all(np.linalg.norm(X[moved] - V[tip], axis=1) < d_before)
    assert radius_ratio(X, Fo).min() >= 0.3
    # still on the surface: the lifted point of its disk position
    f, b, _ = locate_points(uv_in, F, uv[moved])
    np.testing.assert_allclose(X[moved], np.einsum("kc,kcd->kd", b, V[F[f]]), atol=1e-12)


def test_snap_moves_a_vertex_again_that_went_part_of_the_way(monkeypatch):
    """The flags of an earlier call: a vertex that went part of the way up the cone (no
    draping) may be pulled again (put back where it started, it goes up again), one that
    went all the way stays."""
    monkeypatch.setattr(snap, "DRAPE_SWEEPS", 0)
    V, F, uv_in, tip, X, Fo, uv, face = _snap_setup(1.0, width=0.3)
    start = X.copy(), uv.copy(), face.copy()
    partial = np.zeros(len(X), dtype=bool)
    snapped = _snap(V, F, uv_in, X, Fo, uv, face, partial=partial)
    (mover,) = np.flatnonzero(partial)
    after = X.copy(), uv.copy(), face.copy()
    for whole in (False, True):
        X, uv, face = (a.copy() for a in after)
        X[mover], uv[mover], face[mover] = (a[mover] for a in start)
        _snap(V, F, uv_in, X, Fo, uv, face, snapped.copy(), partial & (not whole))
        if whole:
            np.testing.assert_array_equal(X[mover], start[0][mover])
        else:
            assert np.linalg.norm(X[mover] - V[tip]) < np.linalg.norm(start[0][mover] - V[tip])
            assert radius_ratio(X, Fo).min() >= 0.3


def test_snap_drapes_the_rings_after_a_vertex_too_far_from_a_tip_alone():
    """The cone too high for one vertex: the nearest goes onto its tip all the same, the
    free vertices within two edges of it draped after it (on the surface, where their disk
    positions lift), the boundary where it was, every face above 0.3; the input is nearer
    the output than before everywhere on the cone."""
    V, F, uv_in, tip, X, Fo, uv, face = _snap_setup(1.0, width=0.3)
    before = X.copy()
    partial = np.zeros(len(X), dtype=bool)
    snapped = _snap(V, F, uv_in, X, Fo, uv, face, partial=partial)
    (mover,) = np.flatnonzero(snapped)
    np.testing.assert_array_equal(X[mover], V[tip])
    assert not partial.any()
    moved = np.flatnonzero(np.any(X != before, axis=1))
    A = adjacency_matrix(Fo, len(X))
    within = (A + A @ A)[mover].indices
    assert set(moved) <= set(within) | {mover} and len(moved) > 6
    assert not np.isin(moved, boundary_loop(Fo)).any()
    assert radius_ratio(X, Fo).min() >= 0.3
    cone = V[:, 2] > 0
    assert point_mesh_distance(V[cone], X, Fo)[0].max() < 0.5 * point_mesh_distance(V[cone], before, Fo)[0].max()
    f, b, _ = locate_points(uv_in, F, uv[moved])
    np.testing.assert_allclose(X[moved], np.einsum("kc,kcd->kd", b, V[F[f]]), atol=1e-12)


def test_min_quality_search_repairs_slivers_on_a_plane():
    """On a planar surface a mesh with needles gets every face above the search's target
    without any smoothing sweep, and stays an embedding on the surface."""
    V, F, uv_in = flat_disk(0.04)
    X, Fo, uv = flat_disk(0.2)
    rng = np.random.default_rng(0)
    inner = np.setdiff1d(np.arange(len(uv)), boundary_loop(Fo))
    uv = uv.copy()
    uv[inner] += rng.uniform(-0.06, 0.06, (len(inner), 2))
    assert radius_ratio(np.column_stack([uv, np.zeros(len(uv))]), Fo).min() < 0.3
    new_uv, new_X = relax_on_surface(uv_in, F, V, uv, Fo, iterations=0, snap=0)
    q = radius_ratio(new_X, Fo)
    assert q.min() >= 0.6
    np.testing.assert_allclose(new_X[inner, :2], new_uv[inner], atol=1e-12)


def test_faces_left_below_the_floor_get_their_rings_smoothed_together(monkeypatch):
    """Where the minimum-quality search ends with faces below 0.3 (here cut short at 2
    rounds on a badly jittered mesh of a plane), the rings around them are smoothed
    together and the search goes on: the smallest radius ratio gets above 0.3, where it
    stays below without that stage."""
    V, F, uv_in = flat_disk(0.04)
    X, Fo, uv = flat_disk(0.2)
    inner = np.setdiff1d(np.arange(len(uv)), boundary_loop(Fo))
    uv = uv.copy()
    uv[inner] += np.random.default_rng(2).uniform(-0.09, 0.09, (len(inner), 2))
    _, new_X = relax_on_surface(uv_in, F, V, uv, Fo, iterations=0, snap=0, rounds=2, regular_rounds=0)
    assert radius_ratio(new_X, Fo).min() >= 0.3
    monkeypatch.setattr(relax, "UNJAM_SWEEPS", 0)
    _, new_X = relax_on_surface(uv_in, F, V, uv, Fo, iterations=0, snap=0, rounds=2, regular_rounds=0)
    assert radius_ratio(new_X, Fo).min() < 0.3


def test_vertices_located_from_known_faces_land_where_the_search_puts_them(monkeypatch):
    """Located by a walk from the faces of a coarser level (and a neighbour's, for the
    midpoints; and from a face across the disk for a few), or from the nearest input
    vertex's where none is known, the vertices of a subdivided mesh of a paraboloid land
    where the search of the whole disk map puts them, and the faces returned contain
    them."""
    V, F, uv_in = flat_disk(0.04)
    V[:, 2] = (uv_in**2).sum(1)
    _, Fc, uv_c = flat_disk(0.2)
    kwargs = dict(iterations=0, snap=0, min_quality=0, regular_rounds=0, return_faces=True)
    uv_c, _, faces_c = relax_on_surface(uv_in, F, V, uv_c, Fc, **kwargs)
    bnd_c = boundary_loop(Fc)
    assert (faces_c[bnd_c] == -1).all() and (np.delete(faces_c, bnd_c) >= 0).all()
    uv, Fo = upsample(uv_c, Fc, 1)
    hint = np.r_[faces_c, np.full(len(uv) - len(uv_c), -1)]
    inner = np.flatnonzero(hint >= 0)
    hint[inner[::7]] = hint[inner[::7][::-1]]  # far from their own faces
    bnd = boundary_loop(Fo)
    face, bary, _ = locate_points(uv_in, F, np.delete(uv, bnd, axis=0))
    X_search = interpolate_barycentric(F, face, bary, V)
    searched = []
    monkeypatch.setattr(relax, "locate_points", lambda *a, **k: searched.append(len(a[2])) or locate_points(*a, **k))
    _, X_nearest, _ = relax_on_surface(uv_in, F, V, uv, Fo, **kwargs)
    assert searched == []  # every walk ended in its face
    _, X_walk, faces = relax_on_surface(uv_in, F, V, uv, Fo, faces=hint, **kwargs)
    np.testing.assert_allclose(np.delete(X_nearest, bnd, axis=0), X_search, atol=1e-12)
    np.testing.assert_allclose(np.delete(X_walk, bnd, axis=0), X_search, atol=1e-12)
    inside = faces >= 0
    assert inside.sum() == len(uv) - len(boundary_loop(Fo))
    a, b, c = np.moveaxis(uv_in[F[faces[inside]]], 1, 0)
    p = uv[inside]
    for e0, e1 in ((a, b), (b, c), (c, a)):  # p on the left of every side, up to rounding
        d, r = e1 - e0, p - e0
        assert (d[:, 0] * r[:, 1] - d[:, 1] * r[:, 0] >= -1e-15).all()


def test_regular_fraction_search_raises_the_share_of_good_faces_on_a_plane():
    """On a jittered mesh of a plane the search raises the number of faces with a radius
    ratio of at least 0.9 without lowering the smallest radius ratio or the mean; the
    vertices stay on the plane (their own disk positions), the boundary ones on the input
    boundary in their order, the mesh an embedding, and the vertices that may not move
    where they were."""
    V, F, uv_in = flat_disk(0.04)
    X, Fo, uv = flat_disk(0.2)
    bnd = boundary_loop(Fo)
    inner = np.setdiff1d(np.arange(len(uv)), bnd)
    uv = uv.copy()
    uv[inner] += np.random.default_rng(3).uniform(-0.03, 0.03, (len(inner), 2))
    face, bary, _ = locate_points(uv_in, F, uv)
    X = np.einsum("kc,kcd->kd", bary, V[F[face]])
    curve = BoundaryCurve(uv_in, F, V, 0.2)
    s = curve.arc_length(np.arctan2(uv[bnd, 1], uv[bnd, 0]))
    s = s[0] + np.mod(s - s[0], curve.perimeter)
    uv[bnd], X[bnd] = curve.at(s)
    face[bnd] = -1
    # every other boundary vertex jittered along the boundary
    s[::2] += np.random.default_rng(4).uniform(-0.05, 0.05, len(s[::2]))
    uv[bnd], X[bnd] = curve.at(s)
    q0 = radius_ratio(X, Fo)
    movable = np.ones(len(X), dtype=bool)
    movable[inner[::5]] = False
    movable[bnd[::7]] = False
    before, s_before = X.copy(), s.copy()
    raise_regular_fraction(X, uv, face, s, output_mesh(Fo, len(X)), input_surface(V, F, uv_in), movable, curve, 20)
    q = radius_ratio(X, Fo)
    assert (q >= GOOD_QUALITY).sum() > (q0 >= GOOD_QUALITY).sum() + 10
    assert q.min() >= min(q0.min(), GOOD_QUALITY) and q.sum() >= q0.sum()
    np.testing.assert_array_equal(X[~movable], before[~movable])
    np.testing.assert_allclose(X[inner, :2], uv[inner], atol=1e-12)
    slid = s != s_before
    assert slid.any() and (np.diff(s) > 0).all()
    np.testing.assert_allclose(X[bnd], curve.at(s)[1], atol=1e-12)
    assert (X[:, 2] == 0).all() and (signed_doublearea(uv, Fo) > 0).all()


def test_boundary_arc_steps_are_the_umbrella_along_the_boundary():
    """A boundary row on the x axis (x = 0..4, arc length s = x) under a row of
    equilateral apexes: a boundary vertex with the apexes beside it shifted by d along
    the row moves by the component along the row of the step to the mean of its four
    neighbours, d / 2; unshifted, by nothing; shifted by 3, by half the way to its
    neighbour (the clip)."""
    h = np.sqrt(3) / 2
    F = np.array([[i, i + 1, 5 + i] for i in range(4)] + [[i + 1, 6 + i, 5 + i] for i in range(3)])
    ring = adjacency_matrix(F, 9)
    loop = np.arange(5)
    s = np.arange(5.0)
    for d, step in ((0.0, 0.0), (0.2, 0.1), (3.0, 0.5)):
        X = np.column_stack([np.r_[s, np.arange(4) + 0.5 + d], np.r_[np.zeros(5), np.full(4, h)], np.zeros(9)])
        out = boundary_arc_steps(X, loop, ring[loop], s - 1, s, s + 1)
        np.testing.assert_allclose(out[1:4], step, atol=1e-12)


def test_boundary_step_is_the_even_one_where_the_umbrella_strays_farther(monkeypatch):
    """On the unit disk, a boundary vertex at angle 0 between neighbours at -0.4 and 0.4,
    pulled towards 0.35 by an interior neighbour: its umbrella step along the circle
    (0.053 rad at step 0.5) makes the output boundary stray farther from the circle than
    staying does (the sagitta over 0.453 rad instead of 0.4), which BOUNDARY_STRAY mean
    edge lengths allow; with none allowed, it takes the even step (none)."""
    V, F, uv_in = flat_disk(0.01)
    curve = BoundaryCurve(uv_in, F, V, 0.01)
    theta = np.array([-0.4, 0.0, 0.4, 2.0, 4.0])
    s = curve.arc_length(theta)
    s = s[0] + np.mod(s - s[0], curve.perimeter)
    X = np.vstack([curve.at(s)[1], [0.9 * np.cos(0.35), 0.9 * np.sin(0.35), 0.0]])
    E = np.array([[0, 1], [1, 2], [2, 3], [3, 4], [0, 4], [1, 5]])
    ring = sp.csr_matrix((np.ones(2 * len(E)), (np.r_[E[:, 0], E[:, 1]], np.r_[E[:, 1], E[:, 0]])), shape=(6, 6))
    bnd = np.arange(5)
    s_prev, s_next = np.roll(s, 1), np.roll(s, -1)
    s_prev[0] -= curve.perimeter
    s_next[-1] += curve.perimeter
    pinned = np.array([True, False, True, True, True])
    args = (X, E, bnd, ring[bnd], s_prev, s, s_next, pinned, curve, 0.5)
    umbrella = boundary_arc_steps(X, bnd, ring[bnd], s_prev, s, s_next)[1]
    assert 0.05 < 0.5 * umbrella < 0.06
    np.testing.assert_allclose(relax._boundary_steps(*args)[1], umbrella)
    monkeypatch.setattr(relax, "BOUNDARY_STRAY", 0.0)
    np.testing.assert_allclose(relax._boundary_steps(*args)[1], 0.0, atol=1e-12)


def test_boundary_deviation_is_the_sagitta_of_the_output_chords():
    """On the unit disk, a boundary vertex between neighbours at -a and a (angles on the
    circle): at angle 0 the output boundary strays from the input one by the sagitta of
    a chord over an arc a, 1 - cos(a / 2); slid next to a neighbour, by that of the chord
    over 2 a (less the slide), 1 - cos(a) (to the input polygon's own deviation from the circle)."""
    V, F, uv_in = flat_disk(0.01)
    curve = BoundaryCurve(uv_in, F, V, 0.01)
    a = 0.4
    theta = np.array([-a, 0.0, a, 2.0, 4.0])
    s = curve.arc_length(theta)
    s = s[0] + np.mod(s - s[0], curve.perimeter)
    _, X_loop = curve.at(s)
    sc = np.array([[s[1], s[0] + 1e-3 * (s[1] - s[0])]])
    Xc = curve.at(sc.ravel())[1].reshape(1, 2, 3)
    far = boundary_deviation(s, np.array([1]), Xc, sc, X_loop, curve)
    polygon = 1 - np.cos(np.pi / len(boundary_loop(F)))
    np.testing.assert_allclose(far[0], [1 - np.cos(a / 2), 1 - np.cos(a * (1 - 5e-4))], atol=polygon)


def test_held_vertex_moves_only_below_its_floor():
    """A held (snapped) vertex whose worst face is between 0.3 and 0.4 stays in the
    minimum-quality search by default and moves, lifting its star above 0.4, when the
    search lets held vertices mend faces below 0.4."""
    V, F, uv_in = flat_disk(0.04)
    _, Fo, uv0 = flat_disk(0.2)
    bnd = boundary_loop(Fo)
    curve = BoundaryCurve(uv_in, F, V, 0.2)
    A, VF = adjacency_matrix(Fo, len(uv0)), vertex_face_incidence(Fo, len(uv0))
    v = np.setdiff1d(np.arange(len(uv0)), bnd)[0]
    w = A[v].indices[0]
    uv0 = uv0.copy()
    t = 0.0
    while True:  # slide v towards a neighbour until its worst face is below 0.4
        t += 0.01
        uv = uv0.copy()
        uv[v] += t * (uv0[w] - uv0[v])
        X = np.column_stack([uv, np.zeros(len(uv))])
        if radius_ratio(X, Fo[VF[v].indices]).min() < 0.4:
            break
    assert radius_ratio(X, Fo[VF[v].indices]).min() > 0.3
    face, _, _ = locate_points(uv_in, F, uv)
    s = curve.arc_length(np.arctan2(uv[bnd, 1], uv[bnd, 0]))
    s = s[0] + np.mod(s - s[0], curve.perimeter)
    pinned = np.ones(len(uv), dtype=bool)
    pinned[v] = False
    held = ~pinned
    out, surface = output_mesh(Fo, len(X)), input_surface(V, F, uv_in)
    for floor, moves in ((0.3, False), (0.4, True)):
        Xt, uvt, facet, st = X.copy(), uv.copy(), face.copy(), s.copy()
        raise_min_quality(Xt, uvt, facet, st, out, surface, pinned, held, curve, 0.4, 5,
                          held_floor=floor)
        assert np.any(Xt[v] != X[v]) == moves
        if moves:
            assert radius_ratio(Xt, Fo[VF[v].indices]).min() >= 0.4


def test_tangent_candidates_of_a_folded_star_stay_at_the_vertex():
    """A vertex whose star is folded onto itself (its faces' normals sum to zero) has no
    tangent plane: its candidates stay where it is (they were NaN, with a warning)."""
    import warnings

    from qcremesh.remeshing.stars import tangent_candidates

    V, F, uv = plane(6)
    # an output vertex at the centre with two faces folded onto each other
    X = np.array([[0.5, 0.5, 0.0], [0.7, 0.5, 0.0], [0.5, 0.7, 0.0]])
    Fo = np.array([[0, 1, 2], [0, 2, 1]])
    face = locate_points(uv, F, X[:, :2])[0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Xc, uvc, fc = tangent_candidates(
            X, output_mesh(Fo, len(X)), np.array([0]), np.array([0.1]), face, input_surface(V, F, uv),
            np.array([0.5, 1.0]),
        )
    np.testing.assert_allclose(Xc[0], np.broadcast_to(X[0], Xc[0].shape), atol=1e-12)
    np.testing.assert_allclose(uvc[0], np.broadcast_to(X[0, :2], uvc[0].shape), atol=1e-12)


def test_nearest_per_owner_grouped_or_not():
    """The first nearest candidate of each owner, the same whether the candidates come
    grouped by owner (no sort) or shuffled; an owner with no candidate is skipped."""
    dist = np.array([0.5, 0.2, 0.2, 0.9, 0.1, 0.4, 0.4])
    owner = np.array([0, 0, 0, 1, 1, 3, 3])
    assert nearest_per_owner(dist, owner).tolist() == [1, 4, 5]
    order = np.random.default_rng(0).permutation(len(dist))
    d, o = dist[order], owner[order]
    first = nearest_per_owner(d, o)
    assert o[first].tolist() == [0, 1, 3]
    assert d[first].tolist() == [0.2, 0.1, 0.4]
    assert first[0] == np.flatnonzero((o == 0) & (d == 0.2))[0]
    assert first[2] == np.flatnonzero(o == 3)[0]
    with np.errstate(invalid="ignore"):
        assert nearest_per_owner(np.array([np.nan, 0.3, 0.7]), np.array([0, 0, 1])).tolist() == [1, 2]
