import numpy as np
import pytest

from conftest import cad_cylinder, shapes
from qcremesh.geometry.creases import dihedral_angles, sharp_edges
from qcremesh.geometry.distance import hausdorff_distance
from qcremesh.geometry.quality import radius_ratio
from qcremesh.mesh.topology import boundary_loops, euler_characteristic, nonmanifold_edges
from qcremesh.remeshing.pipeline import remesh


def test_dihedral_angles_of_a_pair_folded_along_their_edge():
    # two triangles on the edge (0, 1) along x, the second turned down by 0, 45 and 90
    # degrees about it, and up by 45
    F = np.array([[0, 1, 2], [1, 0, 3]])
    for far, angle in [([0.5, -1, 0], 0.0), ([0.5, -1, -1], 45.0), ([0.5, 0, -1], 90.0), ([0.5, -1, 1], 45.0)]:
        V = np.array([[0, 0, 0], [1, 0, 0], [0.5, 1, 0], far], dtype=np.float64)
        E, turn = dihedral_angles(V, F)
        assert sorted(E[0]) == [0, 1] and turn == pytest.approx([angle])


def test_sharp_edges_are_the_box_edges():
    V, F = shapes.box(np.linspace(0.0, 1.0, 7), top=False)
    E = sharp_edges(V, F, 60.0)
    # the 4 bottom edges and the 4 vertical ones, 6 grid edges each
    assert len(E) == 48
    on_two_faces_of_the_cube = ((np.isclose(V[E], 0) | np.isclose(V[E], 1)).sum(2) >= 2).all()
    assert on_two_faces_of_the_cube
    assert len(sharp_edges(V, F, 100.0)) == 0
    with pytest.raises(ValueError, match="^the crease angle must be between 0 and 180 degrees, not 180.0$"):
        sharp_edges(V, F, 180.0)


def test_remesh_keeps_the_creases_of_an_open_box():
    # CAD-like: grid lines crowded towards the box's edges (slivers along them), 15
    # grid edges along each of the box's 8 edges
    V, F = shapes.open_box()
    diag = np.sqrt(3.0)
    for faces in (len(F), len(F) // 2):
        plain = remesh(V, F, faces)
        r = remesh(V, F, faces, creases=60.0)
        assert r.stats["crease_edges"] == 8 * 15 and len(r.stats["crease_piece_faces"]) == 5
        assert abs(len(r.F) - faces) <= 0.05 * faces
        assert euler_characteristic(r.F) == 1 and len(boundary_loops(r.F)) == 1 and not len(nonmanifold_edges(r.F))
        # every output vertex on a side; the box's 8 corners kept
        assert (np.isclose(r.V, 0, atol=1e-9) | np.isclose(r.V, 1, atol=1e-9)).any(1).all()
        for corner in [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1], [1, 1, 1]]:
            assert np.linalg.norm(r.V - corner, axis=1).min() < 1e-9
        # the creases are output edges: no output face cuts across one
        assert hausdorff_distance(V, F, r.V, r.F)[0] < 1e-6 * diag
        assert hausdorff_distance(V, F, plain.V, plain.F)[0] > 0.01 * diag
        q = radius_ratio(r.V, r.F)
        assert q.min() >= 0.6 and q.mean() >= 0.94


def test_remesh_keeps_the_creases_of_a_closed_cube():
    V, F = shapes.cube()
    r = remesh(V, F, creases=60.0)
    # (those of the cube's 12 * 8 crease edges that the cut into a disk follows are on its
    # border already)
    assert 0 < r.stats["crease_edges"] <= 12 * 8 and len(r.stats["crease_piece_faces"]) == 6
    assert euler_characteristic(r.F) == 2 and not boundary_loops(r.F) and not len(nonmanifold_edges(r.F))
    assert hausdorff_distance(V, F, r.V, r.F)[0] < 1e-6
    assert radius_ratio(r.V, r.F).min() >= 0.3


def test_creases_round_a_plateau_cut_the_ring_between_them_across():
    # the middle raised by 0.25 over a ring 0.1 wide, with a crease at each side of the
    # ring: neither touches the boundary, and the ring cut open is a strip 35 times as
    # long as wide, whose own map crowds
    V, F = shapes.plateau()
    r = remesh(V, F, creases=60.0)
    plain = remesh(V, F)
    assert r.stats["crease_edges"] == 2 * 48 and len(r.stats["crease_piece_faces"]) > 3
    assert euler_characteristic(r.F) == 1 and len(boundary_loops(r.F)) == 1
    assert hausdorff_distance(V, F, r.V, r.F)[0] < 0.2 * hausdorff_distance(V, F, plain.V, plain.F)[0]
    assert radius_ratio(r.V, r.F).min() >= 0.3


def test_a_crease_round_a_small_top_is_kept():
    # a mesa: the top (r < 0.5) a sixth of the area, one closed crease round it, joined
    # to the boundary by one seam; the top's piece is planned at fewer levels than the
    # rest, which does not drop a crease's cut as it does a crowded one's
    V, F = shapes.mesa()
    r = remesh(V, F, creases=60.0)
    plain = remesh(V, F)
    assert r.stats["crease_cuts"] == 2 and len(r.stats["crease_piece_faces"]) == 2
    assert hausdorff_distance(V, F, r.V, r.F)[0] < 0.2 * hausdorff_distance(V, F, plain.V, plain.F)[0]
    q = radius_ratio(r.V, r.F)
    assert q.min() >= 0.3 and q.mean() >= 0.95


def test_a_step_one_face_wide_keeps_both_creases():
    # a flat sheet with a steep band one grid column wide (x in [0.5, 0.55], rising 0.3):
    # cut along its two creases the band is a strip with no interior vertex, split
    # 1-to-4 before its remesh
    t = np.r_[np.linspace(0.0, 0.5, 11), np.linspace(0.55, 1.0, 10)]
    X, Y = np.meshgrid(t, np.linspace(0.0, 1.0, 21), indexing="ij")
    V = np.column_stack([X.ravel(), Y.ravel(), np.where(X >= 0.55 - 1e-9, 0.3, 0.0).ravel()])
    F = shapes._grid_faces(21)
    for faces in (len(F), len(F) // 2):
        r = remesh(V, F, faces, creases=60.0)
        assert r.stats["crease_cuts"] == 2 and len(r.stats["crease_piece_faces"]) == 3
        assert abs(len(r.F) - faces) <= 0.05 * faces
        assert euler_characteristic(r.F) == 1 and len(boundary_loops(r.F)) == 1
        assert hausdorff_distance(V, F, r.V, r.F)[0] < 1e-6
        q = radius_ratio(r.V, r.F)
        assert q.min() >= 0.6 and q.mean() >= 0.94


def test_a_cad_cup_keeps_its_rim():
    """A CAD cylinder open at the top: its rim's crease a closed loop, joined to the
    boundary by one seam; the side, cut along it, a strip of needles whose remesh falls
    back to fewer levels than planned. The levels it took, not those planned, have to be
    the cap's (the rim got 57 and 58 vertices on its two sides, and the creases were
    dropped: Hausdorff 1.6 % of the diagonal)."""
    V, F = cad_cylinder(lid=False)
    diag = np.linalg.norm(V.max(0) - V.min(0))
    for faces in (1000, 3000):
        r = remesh(V, F, faces, creases=60.0)
        assert r.stats["crease_cuts"] == 2 and len(r.stats["crease_piece_faces"]) == 2
        assert abs(len(r.F) - faces) <= 0.05 * faces
        assert euler_characteristic(r.F) == 1 and len(boundary_loops(r.F)) == 1 and not len(nonmanifold_edges(r.F))
        assert hausdorff_distance(V, F, r.V, r.F)[0] < 0.004 * diag
        q = radius_ratio(r.V, r.F)
        assert q.min() >= 0.6 and q.mean() >= 0.95


def test_creases_need_the_relaxation_and_an_angle_in_range():
    V, F = shapes.cube()
    with pytest.raises(ValueError, match=r"^keeping creases needs the relaxation \(relax > 0\) and a method other than 'uniform'$"):
        remesh(V, F, creases=60.0, relax=0)
    with pytest.raises(ValueError, match=r"^the crease angle must be between 0 and 180 degrees, not -1.0$"):
        remesh(V, F, creases=-1.0)
    assert "crease_edges" not in remesh(V, F).stats
