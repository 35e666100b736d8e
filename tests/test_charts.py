import numpy as np
import pytest
from conftest import grid_cells, holed_plate, sphere_mesh, torus_mesh

import qcremesh as qc
from qcremesh.geometry.operators import doublearea
from qcremesh.geometry.quality import radius_ratio
from qcremesh.mesh.cut import cut_along_edges
from qcremesh.mesh.topology import boundary_loops, euler_characteristic, genus, nonmanifold_edges
from qcremesh.param.charts import chart_borders, disk_charts


def _is_disk(F):
    _, local = np.unique(F, return_inverse=True)
    local = local.reshape(-1, 3)
    return euler_characteristic(local) == 1 and len(boundary_loops(local)) == 1


def _charts_are_disks(V, F, labels):
    # each chart cut out along the borders (a vertex where it touches itself parted)
    F_cut, _ = cut_along_edges(F, chart_borders(F, labels), len(V))
    return all(_is_disk(F_cut[labels == c]) for c in range(labels.max() + 1))


@pytest.mark.parametrize(
    "mesh", [holed_plate(), torus_mesh(24), sphere_mesh(800)], ids=["plate of genus 3", "torus", "sphere"]
)
def test_disk_charts_split_a_surface_into_disks(mesh):
    V, F = mesh
    labels = disk_charts(V, F)
    assert labels.shape == (len(F),) and labels.dtype == np.int64
    count = labels.max() + 1
    assert count >= 2 and np.array_equal(np.unique(labels), np.arange(count))
    assert _charts_are_disks(V, F, labels)
    # the same charts every time
    assert np.array_equal(disk_charts(V, F), labels)


def test_disk_charts_adds_charts_where_one_seed_gives_no_disk():
    # one seed's cell is the whole torus: charts are added until each is a disk
    V, F = torus_mesh(24)
    labels = disk_charts(V, F, count=1)
    assert labels.max() + 1 >= 2
    assert _charts_are_disks(V, F, labels)


@pytest.mark.parametrize("mesh", [holed_plate(), torus_mesh(24)], ids=["plate of genus 3", "torus"])
def test_disk_charts_merge_small_charts(mesh):
    V, F = mesh
    count = disk_charts(V, F).max() + 1
    # charts of less than 0.9 of the mean area merged into a neighbour while the union
    # is a disk: fewer of them, all disks, and each one left that small has no neighbour
    # it could join so
    labels = disk_charts(V, F, min_share=0.9)
    assert labels.max() + 1 < count
    assert _charts_are_disks(V, F, labels)
    area = np.bincount(labels, doublearea(V, F))
    borders = np.sort(chart_borders(F, labels), axis=1)
    for c in np.flatnonzero(area < 0.9 * area.mean()):
        mine = np.isin(borders, np.unique(F[labels == c])).all(1)
        neighbours = set(labels[np.isin(F, borders[mine]).sum(1) >= 2]) - {c}
        assert neighbours and not any(_is_disk(F[(labels == c) | (labels == o)]) for o in neighbours)


def test_chart_borders_are_the_edges_between_charts():
    V, F = torus_mesh(12)
    labels = (F.min(1) >= len(V) // 2).astype(np.int64)
    borders = np.sort(chart_borders(F, labels), axis=1)
    # every border edge has one face of each chart, every other interior edge none
    for a, b in borders:
        around = labels[np.isin(F, [a, b]).sum(1) == 2]
        assert sorted(around) == [0, 1]
    assert len(np.unique(borders, axis=0)) == len(borders)


def test_remesh_splits_a_surface_of_higher_genus_into_charts():
    """A plate with three holes (genus 3): cut open into one disk, its map crowds the arcs
    along the handles (min q 0.09, Hausdorff distance 3.5 % of the diagonal at 4,000
    faces); remeshed in charts, each a disk, min q 0.31 and 1.4 %."""
    V, F = holed_plate()
    r = qc.remesh(V, F, 4000)
    assert abs(len(r.F) - 4000) <= 0.05 * 4000
    assert genus(r.F) == 3 and not len(nonmanifold_edges(r.F))
    assert len(r.stats["chart_piece_faces"]) >= 2 and sum(r.stats["chart_piece_faces"]) >= len(r.F)
    q = radius_ratio(r.V, r.F)
    assert q.min() >= 0.25 and q.mean() >= 0.95
    m = qc.mesh_quality(r.V, r.F, reference=(V, F))
    assert m["hausdorff"] <= 0.02


def test_remesh_in_charts_keeps_boundary_and_attributes():
    V, F = holed_plate()
    F = F[3:]
    r = qc.remesh(V, F, 4000, data={"x": V[:, 0].astype(np.float32)})
    assert genus(r.F) == 3 and len(boundary_loops(r.F)) == len(boundary_loops(F))
    assert "chart_piece_faces" in r.stats
    m = qc.mesh_quality(r.V, r.F, reference=(V, F))
    assert m["boundary_hausdorff"] < 1e-6
    assert r.data["x"].dtype == np.float32
    np.testing.assert_allclose(r.data["x"], r.V[:, 0], atol=1e-6)


@pytest.mark.parametrize("mesh", [holed_plate(), torus_mesh(24), sphere_mesh(800)], ids=["plate", "torus", "sphere"])
def test_disks_counted_at_once_are_those_counted_one_by_one(mesh):
    from qcremesh.param.charts import _Adjacency, _disks

    V, F = mesh
    adjacency = _Adjacency(V, F)
    rng = np.random.default_rng(0)
    labelings = [disk_charts(V, F), rng.integers(0, 5, len(F)), (V[F].mean(1)[:, 0] > 0).astype(np.int64)]
    for labels in labelings:
        labels = np.unique(labels, return_inverse=True)[1]
        charts = range(labels.max() + 1)
        np.testing.assert_array_equal(_disks(F, labels, adjacency), [_is_disk(F[labels == c]) for c in charts])
        # with ``pinched``, each chart as cut out along the borders
        F_cut, _ = cut_along_edges(F, chart_borders(F, labels), len(V))
        expected = [_is_disk(F_cut[labels == c]) for c in charts]
        np.testing.assert_array_equal(_disks(F, labels, adjacency, pinched=True), expected)


def test_a_chart_that_touches_itself_at_a_vertex_is_a_disk_once_cut_out():
    from qcremesh.param.charts import _Adjacency, _disks

    # 3 x 3 cells: the ring around the centre but for its corner (2, 2) is a C whose ends
    # touch at the vertex (2, 2); cut along its border, that vertex is two
    cells = np.array([(i, j) for i in range(3) for j in range(3)])
    V, F = grid_cells(cells)
    chart = np.where((cells == 1).all(1), 1, np.where((cells == 2).all(1), 2, 0))
    labels = np.r_[chart, chart]
    np.testing.assert_array_equal(_disks(F, labels, _Adjacency(V, F)), [False, True, True])
    np.testing.assert_array_equal(_disks(F, labels, _Adjacency(V, F), pinched=True), [True, True, True])
    # a ring of cells around one is not, either way
    cells = np.array([(i, j) for i in range(3) for j in range(3)])
    V, F = grid_cells(cells)
    centre = ((cells == 1).all(1)).astype(np.int64)
    for pinched in (False, True):
        np.testing.assert_array_equal(_disks(F, np.r_[centre, centre], _Adjacency(V, F), pinched), [False, True])


def test_charts_with_a_face_below_the_floor_are_weighed_against_the_cut_disk(monkeypatch):
    """Charts whose every face is at QUALITY_FLOOR or above are kept without cutting the
    surface open into one disk; charts with a face below it (here with the floor raised
    to 0.99) are weighed against the cut disk, the larger smallest radius ratio kept; and
    kept where the cut disk does not weld."""
    from qcremesh.remeshing import pipeline
    from qcremesh.remeshing.weld import WeldError

    V, F = holed_plate()
    made = {}

    def recorded(name, function):
        def call(*args, **kwargs):
            made[name] = function(*args, **kwargs)
            return made[name]

        return call

    monkeypatch.setattr(pipeline, "_remesh_charts", recorded("charts", pipeline._remesh_charts))
    monkeypatch.setattr(pipeline, "_remesh_cut_disk", recorded("cut", pipeline._remesh_cut_disk))
    r = qc.remesh(V, F, 2000)
    assert radius_ratio(r.V, r.F).min() >= pipeline.QUALITY_FLOOR and r is made["charts"] and "cut" not in made
    monkeypatch.setattr(pipeline, "QUALITY_FLOOR", 0.99)
    r = qc.remesh(V, F, 2000)
    least = {name: radius_ratio(made[name].V, made[name].F).min() for name in ("charts", "cut")}
    assert least["charts"] != least["cut"]
    assert r is made[max(least, key=least.get)]

    def refused(*args, **kwargs):
        raise WeldError("the remesh of the surface cut open does not weld back into its topology")

    monkeypatch.setattr(pipeline, "_remesh_cut_disk", refused)
    assert qc.remesh(V, F, 2000) is made["charts"]
