import numpy as np
import pytest

from conftest import DATA, SHARED_DISKS, shared, star_disk, strip_disk
from qcremesh.geometry.operators import signed_doublearea
from qcremesh.mesh.io import read_mesh
from qcremesh.mesh.subdivide import upsample
from qcremesh.mesh.validate import TopologyError
from qcremesh.param.crowding import crowded_arcs
from qcremesh.param.disk import disk_conformal_map, harmonic_measure


def check_bijective_disk(result, F):
    assert result.folded_faces == 0
    assert np.all(signed_doublearea(result.uv, F) > 0)
    assert result.boundary_radius_error < 1e-9
    r = np.hypot(*result.uv.T)
    assert r.max() <= 1 + 1e-9
    theta = np.unwrap(np.angle(result.uv[result.boundary] @ np.array([1, 1j])))
    assert np.all(np.diff(theta) > 0) and theta[-1] - theta[0] < 2 * np.pi  # boundary in order


def test_human_face_target():
    V, F = read_mesh(DATA / "human_face.obj")
    result = disk_conformal_map(V, F)
    check_bijective_disk(result, F)
    assert result.mean_abs_mu <= 0.022 and result.narrowest_arcs == 0
    assert np.hypot(*result.uv[result.center]) < 1e-12
    assert np.abs(result.uv[result.boundary[0]] - [1, 0]).max() < 1e-12


@pytest.mark.parametrize("levels", [0, 1, 2])
def test_fran_subdivided_is_bijective(levels):
    V, F = upsample(*read_mesh(DATA / "fran_cut.ply"), levels)
    result = disk_conformal_map(V, F)
    check_bijective_disk(result, F)
    assert result.mean_abs_mu < 0.04 / 2**levels  # O(h): halves with each subdivision


def test_free_boundary_is_better_than_fixed_boundary():
    """The boundary is solved for: a harmonic map with arc-length boundary is ~5x worse."""
    from qcremesh.beltrami.coefficient import beltrami_coefficient
    from qcremesh.beltrami.solver import linear_beltrami_solver
    from qcremesh.param.tutte import map_vertices_to_circle

    V, F = read_mesh(DATA / "human_face.obj")
    result = disk_conformal_map(V, F)
    b = result.boundary
    fixed = linear_beltrami_solver(
        result.tutte, F, beltrami_coefficient(result.tutte, F, V), b, map_vertices_to_circle(V, b)
    )
    assert np.abs(beltrami_coefficient(fixed, F, V)).mean() > 4 * result.mean_abs_mu


def test_harmonic_measure_sums_to_one():
    from qcremesh.geometry.operators import cotmatrix

    V, F = read_mesh(DATA / "fran_cut.ply")
    result = disk_conformal_map(V, F)
    omega, _ = harmonic_measure(cotmatrix(V, F), result.boundary, result.center)
    assert abs(omega.sum() - 1) < 1e-10


def test_rejects_non_disk():
    V, F = read_mesh(DATA / "alex_3.ply")
    with pytest.raises(TopologyError, match="4 boundary loops, a disk has 1"):
        disk_conformal_map(V, F)


TARGETS = {"human_face.obj": 0.022, "hand.ply": 0.020, "human_brain.ply": 0.026}


@pytest.mark.parametrize("name", SHARED_DISKS)
@pytest.mark.parametrize("levels", [0, 1])
def test_shared_disks_bijective(name, levels):
    V, F = upsample(*read_mesh(shared(name)), levels)
    result = disk_conformal_map(V, F)
    check_bijective_disk(result, F)
    if levels == 0 and name in TARGETS:
        assert result.mean_abs_mu <= TARGETS[name]


@pytest.mark.parametrize("name", ["venus.off", "camel_b.obj", "foot.off", "human_face.obj"])
def test_shared_disks_subdivided_twice_bijective(name):
    V, F = upsample(*read_mesh(shared(name)), 2)
    check_bijective_disk(disk_conformal_map(V, F), F)


def test_fold_repair_is_reported():
    """camel_b's skinny triangles give negative cotangent weights that fold faces in the
    first solve; the repair unfolds them and says so."""
    V, F = read_mesh(shared("camel_b.obj"))
    result = disk_conformal_map(V, F)
    assert result.repaired_faces > 0
    check_bijective_disk(result, F)


def test_long_strip_stays_conformal_towards_its_ends():
    """The harmonic measure of the boundary of a strip 8 times as long as wide falls to
    about 1e-7 of the mean at its ends. Raised to 1e-3 of the mean there (as before), the
    map was far from conformal along the strip (mean |mu| 0.31); kept down to an arc of
    1e-6 rad, 0.17, and 0.13 from the middle of the strip (the torsion function is flat
    along it, and its maximum was at 4.4, or 5.2 on the intrinsic Delaunay triangulation,
    whose far end the map then crowds beyond the narrowest arc: 0.23); still bijective
    with the boundary in order."""
    V, F = strip_disk(8)
    result = disk_conformal_map(V, F)
    check_bijective_disk(result, F)
    assert abs(V[result.center, 0] - 4) < 0.25
    assert result.mean_abs_mu < 0.15
    assert 0 < result.narrowest_arcs < 0.1 * len(result.boundary)


def test_sheared_triangulation_gets_a_conformal_map():
    """A star meshed by pushing a disk mesh out along its rays (mean radius ratio 0.49,
    23 % of its interior edges not Delaunay): on its own triangulation the map had mean
    |mu| 0.32; on the intrinsic Delaunay one, 0.10, and bijective (the few needles it
    folds unfolded)."""
    V, F = star_disk()
    result = disk_conformal_map(V, F)
    check_bijective_disk(result, F)
    assert result.intrinsic_flips > 1000 and result.mean_abs_mu < 0.12 and result.repaired_faces > 0


def test_crowded_arcs_are_the_ends_of_a_strip():
    """A strip 12 times as long as wide: the boundary arc per unit length of its disk
    map falls exponentially towards the ends; below 0.1 of the
    mean, two runs of vertices, one around each end, and well above 1 in the middle,
    which gets most of the circle."""
    V, F = strip_disk(12)
    dm = disk_conformal_map(V, F)
    start, count, crowding = crowded_arcs(V, dm.uv, dm.boundary, 0.1)
    assert len(start) == 2 and (count == count[0]).all()
    x = V[dm.boundary, 0]
    low = crowding < 0.1
    runs = [dm.boundary[(s + np.arange(c)) % len(dm.boundary)] for s, c in zip(start, count)]
    assert np.array_equal(np.sort(np.concatenate(runs)), np.sort(dm.boundary[low]))
    assert all(len(np.unique(V[run, 0] < 6)) == 1 for run in runs)  # each run at one end
    assert crowding.max() > 5 and 3 < x[np.argmax(crowding)] < 9
    assert crowding[(x == 0) | (x == 12)].max() < 1e-3
