import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.csgraph import floyd_warshall

from conftest import grid_disk, sphere_mesh, torus_mesh
from qcremesh.geometry.distance import point_mesh_distance
from qcremesh.geometry.quality import radius_ratio
from qcremesh.mesh.cut import cut_along_path, shortest_edge_path, weld_slit
from qcremesh.mesh.topology import (
    boundary_edges,
    boundary_loop,
    edges,
    euler_characteristic,
    nonmanifold_edges,
    nonmanifold_vertices,
)
from qcremesh.mesh.validate import MeshError, check_disk
from qcremesh.remeshing.pipeline import remesh


def test_shortest_edge_path_follows_edges_and_is_shortest():
    uv, F = grid_disk(6)
    V = np.column_stack([uv, np.zeros(len(uv))])
    a, b = 0, len(V) - 1  # opposite corners of the square
    path = shortest_edge_path(V, F, a, b)
    assert path[0] == a and path[-1] == b
    E = {tuple(e) for e in edges(F)}
    assert all(tuple(sorted(p)) in E for p in zip(path[:-1], path[1:]))
    # as long as the shortest path by Floyd and Warshall's algorithm
    E = edges(F)
    length = np.linalg.norm(V[E[:, 0]] - V[E[:, 1]], axis=1)
    G = sp.csr_matrix((length, (E[:, 0], E[:, 1])), shape=(len(V), len(V)))
    shortest = floyd_warshall(G, directed=False)[a, b]
    assert np.isclose(np.linalg.norm(np.diff(V[path], axis=0), axis=1).sum(), shortest, rtol=1e-12)


def test_cut_along_path_opens_a_sphere_into_a_disk_and_weld_closes_it():
    V, F = sphere_mesh()
    path = shortest_edge_path(V, F, int(np.argmin(V[:, 2])), int(np.argmax(V[:, 2])))
    F_cut, parent = cut_along_path(F, path)
    assert len(F_cut) == len(F) and len(parent) == len(V) + len(path) - 2
    np.testing.assert_array_equal(parent[F_cut], F)  # the same faces, some on copies
    loop = check_disk(V[parent], F_cut)
    assert len(loop) == 2 * (len(path) - 1)
    ends = [np.flatnonzero(parent[loop] == path[0])[0], np.flatnonzero(parent[loop] == path[-1])[0]]
    X, F_back, kept = weld_slit(V[parent], F_cut, loop, ends, 1e-12)
    assert len(X) == len(V) and not len(boundary_edges(F_back)) and euler_characteristic(F_back) == 2
    np.testing.assert_array_equal(parent[kept][F_back], F)


def test_cut_and_weld_refuse_what_they_cannot_do():
    V, F = sphere_mesh(200)
    with pytest.raises(ValueError, match="^the cut path must have at least 2 distinct vertices and repeat none$"):
        cut_along_path(F, [F[0, 0], F[0, 1], F[0, 0]])
    far = int(np.argmax(np.linalg.norm(V - V[F[0, 0]], axis=1)))
    with pytest.raises(ValueError, match="^the cut path leaves the edges of the mesh$"):
        cut_along_path(F, [F[0, 0], far])
    uv, G = grid_disk(5)
    loop = boundary_loop(G)
    with pytest.raises(ValueError, match="^the cut path runs along the boundary$"):
        cut_along_path(G, loop[:3])
    with pytest.raises(ValueError, match=r"^the two sides of the slit have 1 and 2 vertices$"):
        weld_slit(np.zeros((5, 3)), G[:1], np.arange(5), [0, 2], 1e-9)
    with pytest.raises(ValueError, match=r"^the two sides of the slit are 1 apart, more than 1e-09$"):
        weld_slit(np.array([[0, 0, 0], [1, 0, 0], [0, 0, 0], [0, 0, 0.0]]), G[:1], np.arange(4), [0, 2], 1e-9)


def test_remesh_closes_a_closed_surface_of_genus_0():
    V, F = sphere_mesh(3000)
    r = remesh(V, F, 4000)
    assert abs(len(r.F) - 4000) <= 200
    assert not len(boundary_edges(r.F)) and euler_characteristic(r.F) == 2
    assert not len(nonmanifold_edges(r.F)) and not len(nonmanifold_vertices(r.F))
    assert len(np.unique(r.F)) == len(r.V)
    assert point_mesh_distance(r.V, V, F)[0].max() < 1e-9  # on the input surface
    # turned outwards, as the input
    volume = np.einsum("ij,ij->i", r.V[r.F[:, 0]], np.cross(r.V[r.F[:, 1]], r.V[r.F[:, 2]])).sum() / 6
    assert volume > 4
    q = radius_ratio(r.V, r.F)
    assert q.mean() > 0.97 and q.min() > 0.4
    # every level is closed too
    for X, G in r.levels:
        assert not len(boundary_edges(G)) and euler_characteristic(G) == 2 and len(np.unique(G)) == len(X)
    with pytest.raises(MeshError, match=r"^closed surface of genus 1 \(Euler characteristic 0\); remesh takes disks "
                       r"and closed surfaces of genus 0$"):
        remesh(*torus_mesh(), 500)
    with pytest.raises(ValueError, match=r"^a closed surface needs the relaxation \(relax > 0\) and a method other "
                       r"than 'uniform'$"):
        remesh(V, F, 2000, relax=0)


def test_remesh_orients_a_closed_surface_before_cutting_it():
    V, F = sphere_mesh(800)
    F = F.copy()
    F[:10] = F[:10, ::-1]  # ten faces turned against the others
    r = remesh(V, F, 1000)
    assert r.stats["reoriented_faces"] == 10
    assert not len(boundary_edges(r.F)) and euler_characteristic(r.F) == 2
    volume = np.einsum("ij,ij->i", r.V[r.F[:, 0]], np.cross(r.V[r.F[:, 1]], r.V[r.F[:, 2]])).sum() / 6
    assert volume > 3.5  # outwards, as the majority
