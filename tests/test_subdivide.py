import numpy as np

from conftest import DATA
from qcremesh.geometry.operators import doublearea
from qcremesh.mesh.io import read_mesh
from qcremesh.mesh.subdivide import upsample
from qcremesh.mesh.topology import boundary_loops, euler_characteristic, inconsistent_edges


def test_upsample_keeps_geometry_and_topology():
    V, F = read_mesh(DATA / "fran_cut.ply")
    V2, F2 = upsample(V, F, 2)
    assert len(F2) == 16 * len(F)
    np.testing.assert_array_equal(V2[: len(V)], V)
    np.testing.assert_allclose(doublearea(V2, F2).sum(), doublearea(V, F).sum())
    np.testing.assert_allclose(doublearea(V2, F2)[:4].sum() * 4, doublearea(V, F)[0])
    assert euler_characteristic(F2) == 1 and len(boundary_loops(F2)) == 1
    assert len(inconsistent_edges(F2)) == 0
    assert len(boundary_loops(F2)[0]) == 4 * len(boundary_loops(F)[0])
    V0, F0 = upsample(V, F, 0)
    np.testing.assert_array_equal(F0, F)
