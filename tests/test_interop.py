import numpy as np
import pytest

from conftest import DATA, grid_disk, holed_disk
from qcremesh.geometry.quality import mesh_quality, radius_ratio
from qcremesh.interop.meshio import from_meshio, remesh_meshio, to_meshio
from qcremesh.interop.pyvista import from_pyvista, remesh_pyvista, to_pyvista
from qcremesh.interop.trimesh import from_trimesh, remesh_trimesh, to_trimesh
from qcremesh.mesh.io import MeshReadError, read_mesh
from qcremesh.mesh.topology import boundary_loops
from qcremesh.remeshing.pipeline import remesh

trimesh = pytest.importorskip("trimesh")
pv = pytest.importorskip("pyvista")


@pytest.fixture(scope="module")
def fran():
    return read_mesh(DATA / "fran_cut.ply", return_data=True)


def bumpy_grid(n=12):
    uv, F = grid_disk(n)
    return np.column_stack([uv, 0.2 * np.sin(3 * uv[:, 0]) * uv[:, 1]]), F


def test_trimesh_round_trip_keeps_arrays_and_visuals():
    V, F = bumpy_grid()
    uv = V[:, :2].copy()
    mesh = to_trimesh(V, F, {"uv": uv, "height": V[:, 2]})
    assert isinstance(mesh.visual, trimesh.visual.TextureVisuals)
    V2, F2, data = from_trimesh(mesh)
    np.testing.assert_array_equal(V2, V)
    np.testing.assert_array_equal(F2, F)
    np.testing.assert_array_equal(data["uv"], uv)
    np.testing.assert_array_equal(data["height"], V[:, 2])
    colours = np.tile(np.array([10, 200, 30, 255], dtype=np.uint8), (len(V), 1))
    _, _, data = from_trimesh(to_trimesh(V, F, {"vertex_colors": colours}))
    np.testing.assert_array_equal(data["vertex_colors"], colours)


def test_remesh_trimesh_is_remesh_with_the_data_carried(fran):
    V, F, data = fran
    mesh = trimesh.Trimesh(V, F, visual=trimesh.visual.TextureVisuals(uv=data["uv"]), process=False)
    mesh.vertex_attributes["x"] = V[:, 0]
    out = remesh_trimesh(mesh, 2000, seed=2)
    direct = remesh(V, F, 2000, data={"uv": data["uv"], "x": V[:, 0]}, seed=2)
    assert isinstance(out, trimesh.Trimesh)
    np.testing.assert_array_equal(out.vertices, direct.V)
    np.testing.assert_array_equal(out.faces, direct.F)
    np.testing.assert_array_equal(out.visual.uv, direct.data["uv"])
    np.testing.assert_array_equal(out.vertex_attributes["x"], direct.data["x"])
    assert out.metadata["qcremesh"]["levels"] == direct.stats["levels"]
    assert out.is_watertight is False and out.is_winding_consistent


def test_remesh_trimesh_colours_stay_bytes():
    V, F = bumpy_grid()
    x = V[:, 0]
    colours = np.column_stack([255 * x, 255 * (1 - x), 0 * x, 255 + 0 * x]).round().astype(np.uint8)
    mesh = trimesh.Trimesh(V, F, vertex_colors=colours, process=False)
    out = remesh_trimesh(mesh, 300)
    got = out.visual.vertex_colors
    assert got.dtype == np.uint8 and got.shape == (len(out.vertices), 4)
    xo = out.vertices[:, 0]
    assert np.abs(got[:, 0] - 255 * xo).max() <= 3 and (got[:, 3] == 255).all()


def test_trimesh_refuses_what_is_not_one_mesh():
    V, F = bumpy_grid(4)
    scene = trimesh.Scene([trimesh.Trimesh(V, F, process=False)])
    with pytest.raises(TypeError, match=r"^expected a trimesh.Trimesh, got Scene: scene.to_mesh\(\) joins"):
        remesh_trimesh(scene)
    with pytest.raises(TypeError, match="carries the mesh's own per-vertex data"):
        remesh_trimesh(trimesh.Trimesh(V, F), data={})


def test_trimesh_closed_mesh():
    sphere = trimesh.creation.icosphere(subdivisions=3)
    out = remesh_trimesh(sphere, 1000, seed=0)
    assert out.is_watertight and out.is_winding_consistent and out.euler_number == 2
    assert abs(len(out.faces) - 1000) <= 50
    assert radius_ratio(out.vertices, out.faces).min() > 0.5
    assert np.abs(np.linalg.norm(out.vertices, axis=1) - 1).max() < 0.01


def test_pyvista_round_trip():
    V, F = bumpy_grid()
    mesh = to_pyvista(V, F, {"h": V[:, 2], "rgb": np.zeros((len(V), 3), dtype=np.uint8)})
    assert mesh.is_all_triangles and mesh.n_cells == len(F)
    V2, F2, data = from_pyvista(mesh)
    np.testing.assert_array_equal(V2, V)
    np.testing.assert_array_equal(F2, F)
    assert data["rgb"].dtype == np.uint8
    np.testing.assert_array_equal(data["h"], V[:, 2])


def test_remesh_pyvista_carries_point_data_and_active_arrays():
    # a plane of quads bent into a wave, with texture coordinates and normals as active arrays
    plane = pv.Plane(i_resolution=20, j_resolution=10)
    plane.points[:, 2] = 0.1 * np.sin(4 * plane.points[:, 0])
    plane.point_data.remove("Normals")
    plane = plane.compute_normals(point_normals=True, cell_normals=False)
    plane.point_data["elevation"] = plane.points[:, 0] * 2.0
    plane.point_data.active_scalars_name = "elevation"
    assert not plane.is_all_triangles
    out = remesh_pyvista(plane, 300, seed=1)
    assert isinstance(out, pv.PolyData) and out.is_all_triangles
    assert abs(out.n_cells - 300) <= 15
    np.testing.assert_allclose(out.point_data["elevation"], out.points[:, 0] * 2.0, atol=1e-9)
    assert out.point_data.active_scalars_name == "elevation"
    assert out.point_data.active_texture_coordinates_name == plane.point_data.active_texture_coordinates_name
    tc = out.active_texture_coordinates
    assert tc.min() >= -1e-12 and tc.max() <= 1 + 1e-12
    normals = out.point_data[plane.point_data.active_normals_name]
    np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-6)
    q = mesh_quality(out.points, out.faces.reshape(-1, 4)[:, 1:])
    assert q["q_mean"] > 0.95 and q["q_min"] > 0.5 and q["boundary_loops"] == 1


def test_remesh_pyvista_surface_with_holes_and_strips():
    V, F = holed_disk()
    out = remesh_pyvista(to_pyvista(V, F), 800, seed=0)
    assert mesh_quality(out.points, out.faces.reshape(-1, 4)[:, 1:])["boundary_loops"] == 3
    strips = pv.Sphere().strip()
    assert strips.n_strips > 0
    V, F, _ = from_pyvista(strips)
    assert len(F) == pv.Sphere().n_cells


def test_pyvista_refuses_what_is_not_a_surface():
    grid = pv.ImageData(dimensions=(3, 3, 3))
    with pytest.raises(TypeError, match=r"^expected a pyvista.PolyData, got ImageData: mesh.extract_surface\(\)"):
        remesh_pyvista(grid)
    with pytest.raises(ValueError, match="^the PolyData has no faces"):
        from_pyvista(pv.PolyData(np.random.default_rng(0).random((5, 3))))
    with pytest.raises(TypeError, match="carries the mesh's own point data"):
        remesh_pyvista(pv.Sphere(), data={})


def test_a_missing_library_is_named_with_its_install(monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "trimesh", None)  # as if not installed
    V, F = bumpy_grid(4)
    with pytest.raises(ImportError, match=r"^qcremesh.interop.trimesh needs trimesh: pip install trimesh$"):
        to_trimesh(V, F)


def seamed_grid():
    """A grid disk cut along x = 1/2 into two sheets whose vertices there are copies, with
    texture coordinates that differ across the cut (as trimesh loads a textured OBJ)."""
    V, F = bumpy_grid(13)
    seam = np.flatnonzero(np.isclose(V[:, 0], 0.5))
    right = V[F].mean(1)[:, 0] > 0.5
    copy = np.arange(len(V))
    copy[seam] = len(V) + np.arange(len(seam))
    F = np.where(right[:, None], copy[F], F)
    V = np.vstack([V, V[seam]])
    uv = V[:, :2].copy()
    uv[len(uv) - len(seam):, 0] += 1.0  # the right sheet's copies in another tile of the texture
    return V, F, uv


def test_remesh_trimesh_welds_texture_seams():
    V, F, uv = seamed_grid()
    mesh = trimesh.Trimesh(V, F, visual=trimesh.visual.TextureVisuals(uv=uv), process=False)
    mesh.vertex_attributes["x"] = V[:, 0]
    assert len(boundary_loops(mesh.faces)) == 2  # two sheets
    with pytest.warns(UserWarning, match=r"^remesh_trimesh merged the vertices at the same position \(a texture's seams\); uv"):
        out = remesh_trimesh(mesh, 600)
    assert len(boundary_loops(out.faces)) == 1 and not isinstance(out.visual, trimesh.visual.TextureVisuals)
    np.testing.assert_allclose(out.vertex_attributes["x"], out.vertices[:, 0], atol=1e-12)  # agrees across: kept
    kept = remesh_trimesh(mesh, 600, weld=False)
    assert len(boundary_loops(kept.faces)) == 2 and isinstance(kept.visual, trimesh.visual.TextureVisuals)


def test_meshio_round_trip():
    V, F = bumpy_grid()
    V2, F2, data = from_meshio(to_meshio(V, F, {"height": V[:, 2]}))
    np.testing.assert_array_equal(V2, V)
    np.testing.assert_array_equal(F2, F)
    np.testing.assert_array_equal(data["height"], V[:, 2])


def test_remesh_meshio_is_remesh_with_the_point_data_carried(fran):
    """The output is remesh's with the point data interpolated (colours as bytes stay
    bytes), the run's numbers in info; quads count as two triangles each."""
    import meshio

    V, F, data = fran
    colours = (255 * (V - V.min(0)) / np.ptp(V, axis=0)).round().astype(np.uint8)
    mesh = meshio.Mesh(V, [("triangle", F)], point_data={"uv": data["uv"], "rgb": colours})
    out = remesh_meshio(mesh, 2000, seed=2)
    direct = remesh(V, F, 2000, data={"uv": data["uv"], "rgb": colours}, seed=2)
    assert isinstance(out, meshio.Mesh) and [c.type for c in out.cells] == ["triangle"]
    np.testing.assert_array_equal(out.points, direct.V)
    np.testing.assert_array_equal(out.cells[0].data, direct.F)
    np.testing.assert_array_equal(out.point_data["uv"], direct.data["uv"])
    assert out.point_data["rgb"].dtype == np.uint8
    np.testing.assert_array_equal(out.point_data["rgb"], direct.data["rgb"])
    assert out.info["qcremesh"]["levels"] == direct.stats["levels"]
    g = np.arange(16).reshape(4, 4)
    quads = np.column_stack([g[:-1, :-1].ravel(), g[:-1, 1:].ravel(), g[1:, 1:].ravel(), g[1:, :-1].ravel()])
    plane = np.column_stack([np.stack(np.meshgrid(np.arange(4.0), np.arange(4.0)), -1).reshape(-1, 2), np.zeros(16)])
    V2, F2, _ = from_meshio(meshio.Mesh(plane, [("quad", quads)]))
    assert len(F2) == 18 and abs(len(remesh_meshio(meshio.Mesh(plane, [("quad", quads)])).cells[0].data) - 18) <= 2


def test_meshio_refuses_what_is_not_a_surface():
    import meshio

    with pytest.raises(TypeError, match="^expected a meshio.Mesh, got tuple$"):
        from_meshio((np.eye(3), [[0, 1, 2]]))
    tetra = meshio.Mesh(np.r_[np.eye(3), [[0, 0, 0]]], [("tetra", [[0, 1, 2, 3]])])
    with pytest.raises(MeshReadError, match=r"^meshio.Mesh: not a triangle mesh \(has tetra cells\)$"):
        remesh_meshio(tetra)
    with pytest.raises(MeshReadError, match="^meshio.Mesh: no triangles, quads or polygons$"):
        from_meshio(meshio.Mesh(np.eye(3), [("line", [[0, 1]])]))
    with pytest.raises(TypeError, match="^remesh_meshio carries the mesh's own point data"):
        remesh_meshio(to_meshio(*bumpy_grid()), data={})
