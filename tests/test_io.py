import importlib.util
import os
import stat
from importlib.util import find_spec

import numpy as np
import pytest

from conftest import DATA, SHARED, grid_disk
from qcremesh.mesh.io import MeshReadError, read_mesh, write_mesh


def test_read_bundled_formats():
    V, F = read_mesh(DATA / "human_face.obj")
    assert V.shape == (17157, 3) and F.shape == (34144, 3)
    assert V.dtype == np.float64 and F.dtype == np.int64
    V, F, data = read_mesh(DATA / "fran_cut.ply", return_data=True)
    assert V.shape == (2205, 3) and F.shape == (4224, 3)
    assert data["uv"].shape == (2205, 2)
    V, F = read_mesh(DATA / "featuretype.STL")
    assert V.shape == (2010, 3) and F.shape == (3476, 3)


@pytest.mark.parametrize("ext", [".obj", ".ply", ".off", ".stl", ".vtk", ".vtu"])
def test_round_trip(tmp_path, ext, capfd):
    uv, F = grid_disk(6)
    V = np.column_stack([uv, uv[:, 0] * uv[:, 1]])
    path = tmp_path / f"m{ext}"
    write_mesh(path, V, F)
    assert capfd.readouterr() == ("", "")  # meshio warned on every PLY of 64-bit indices
    V2, F2 = read_mesh(path)
    if ext == ".stl":  # a triangle soup: compare the triangles' corner positions
        np.testing.assert_allclose(V2[F2], V[F], atol=1e-6)
    else:
        np.testing.assert_allclose(V2, V, atol=1e-6 if ext == ".stl" else 1e-12)
        np.testing.assert_array_equal(F2, F)


def test_obj_with_texture_coordinates(tmp_path):
    uv, F = grid_disk(4)
    V = np.column_stack([uv, np.zeros(len(uv))])
    path = tmp_path / "t.obj"
    write_mesh(path, V, F, uv=uv * 0.5)
    lines = path.read_text().splitlines()
    v = [l for l in lines if l.startswith("v ")]
    vt = [l for l in lines if l.startswith("vt ")]
    f = [l for l in lines if l.startswith("f ")]
    assert len(v) == len(V) and len(vt) == len(V) and len(f) == len(F)
    a, b, c = F[0] + 1
    assert f[0] == f"f {a}/{a} {b}/{b} {c}/{c}"
    assert np.allclose([float(x) for x in vt[1].split()[1:]], uv[1] * 0.5)
    V2, F2, data = read_mesh(path, return_data=True)
    np.testing.assert_array_equal(F2, F)
    np.testing.assert_allclose(data["uv"], uv * 0.5)


def test_obj_with_texture_seams_negative_indices_and_normals(tmp_path):
    """A square of four triangles around a centre vertex, written as a UV-mapped export
    is: corners ``v/vt/vn``, a texture seam (vertex 2 has two texture coordinates), the
    last face by negative indices. Positions and faces come through (meshio refused such
    files); the texture coordinates, having a seam, are not per-vertex data; the normals,
    one per vertex by value though named by different indices, are."""
    path = tmp_path / "seams.obj"
    path.write_text(
        "# square\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 0.1\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\nvt 0.9 0.9\n"
        "vn 0 0 1\nvn 0 0 1\ns off\ng square\n"
        "f 1/1/1 2/2/1 5/5/2\nf 2/2/1 3/3/2 5/5/1\nf 3/6/1 4/4/1 5/5/1\nf -2/-3/-2 -5/-6/-1 -1/-2/-1\n"
    )
    V, F, data = read_mesh(path, return_data=True)
    np.testing.assert_array_equal(V[4], [0.5, 0.5, 0.1])
    np.testing.assert_array_equal(F, [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    assert "uv" not in data
    np.testing.assert_array_equal(data["normals"], np.tile([0.0, 0.0, 1.0], (5, 1)))
    seamless = tmp_path / "seamless.obj"
    seamless.write_text(path.read_text().replace("f 3/6/1", "f 3/3/1"))
    _, _, data = read_mesh(seamless, return_data=True)
    np.testing.assert_array_equal(data["uv"], [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]])


def test_ply_with_other_elements(tmp_path, capfd):
    """A range map as MeshLab writes it, with a ``camera`` element before the vertices
    (meshio refuses such files, and printed its complaint): read through plyfile, a quad
    split as in OBJ, the vertex properties as data; nothing printed."""
    path = tmp_path / "range.ply"
    path.write_text(
        "ply\nformat ascii 1.0\nelement camera 1\nproperty float view_px\nproperty float focal\n"
        "element vertex 5\nproperty float x\nproperty float y\nproperty float z\nproperty float quality\n"
        "element face 3\nproperty list uchar int vertex_indices\nproperty int flags\nend_header\n"
        "0.5 2.0\n0 0 0 1\n1 0 0 2\n1 1 0 3\n0 1.5 0 4\n2 0.5 0 5\n"
        "4 0 1 2 3 0\n3 1 4 2 0\n3 0 2 3 7\n"
    )
    V, F, data = read_mesh(path, return_data=True)
    assert capfd.readouterr() == ("", "")
    np.testing.assert_array_equal(V[3], [0, 1.5, 0])
    np.testing.assert_array_equal(F, [[0, 1, 2], [0, 2, 3], [1, 4, 2], [0, 2, 3]])
    np.testing.assert_array_equal(data["quality"], [1, 2, 3, 4, 5])
    # a list of numbers per vertex (as some scanners write) is not per-vertex data
    listed = tmp_path / "listed.ply"
    listed.write_text(
        path.read_text()
        .replace("property float quality\n", "property float quality\nproperty list uchar int ids\n")
        .replace("0 0 0 1\n", "0 0 0 1 2 7 8\n")
        .replace("1 0 0 2\n", "1 0 0 2 0\n")
        .replace("1 1 0 3\n", "1 1 0 3 1 9\n")
        .replace("0 1.5 0 4\n", "0 1.5 0 4 0\n")
        .replace("2 0.5 0 5\n", "2 0.5 0 5 0\n")
    )
    V2, F2, data = read_mesh(listed, return_data=True)
    np.testing.assert_array_equal(V2, V)
    np.testing.assert_array_equal(F2, F)
    assert sorted(data) == ["quality"]
    broken = tmp_path / "broken.ply"
    broken.write_text(path.read_text().replace("4 0 1 2 3 0", "5 0 1 2 3 4 0"))
    with pytest.raises(MeshReadError, match="a face of 5 corners is not convex \\(or not flat\\): triangulate"):
        read_mesh(broken)


def test_ply_keeps_data_of_several_columns(tmp_path, capfd):
    """Per-vertex arrays of several columns, which meshio's PLY writer dropped with a
    printed warning, become one property per column: normals as nx, ny, nz."""
    uv, F = grid_disk(4)
    V = np.column_stack([uv, np.zeros(len(uv))])
    normals = np.tile([0.0, 0.0, 1.0], (len(V), 1))
    write_mesh(tmp_path / "n.ply", V, F, data={"normals": normals, "rgb": V * 0.5, "s": uv[:, 0]})
    assert capfd.readouterr() == ("", "")
    _, _, data = read_mesh(tmp_path / "n.ply", return_data=True)
    assert sorted(data) == ["nx", "ny", "nz", "rgb_0", "rgb_1", "rgb_2", "s"]
    np.testing.assert_array_equal(data["nz"], 1.0)
    np.testing.assert_allclose(data["rgb_1"], V[:, 1] * 0.5)


def test_obj_bytes_are_deterministic(tmp_path):
    uv, F = grid_disk(5)
    V = np.column_stack([uv, uv[:, 0] ** 2])
    write_mesh(tmp_path / "a.obj", V, F, uv=uv)
    write_mesh(tmp_path / "b.obj", V, F, uv=uv)
    assert (tmp_path / "a.obj").read_bytes() == (tmp_path / "b.obj").read_bytes()


def test_ply_bytes_are_deterministic_and_keep_the_data_types(tmp_path):
    """meshio's PLY writer put the time of day in the header; colours as bytes stay
    bytes, a mask becomes bytes, 64-bit integers 32-bit ones."""
    uv, F = grid_disk(5)
    V = np.column_stack([uv, uv[:, 0] ** 2])
    rgb = np.rint(127.5 * (uv + 1)).astype(np.uint8)
    data = {"red": rgb[:, 0], "green": rgb[:, 1], "inside": uv[:, 0] > 0, "label": np.arange(len(V)) - 3}
    write_mesh(tmp_path / "a.ply", V, F, uv=uv, data=data)
    write_mesh(tmp_path / "b.ply", V, F, uv=uv, data=data)
    assert (tmp_path / "a.ply").read_bytes() == (tmp_path / "b.ply").read_bytes()
    V2, F2, back = read_mesh(tmp_path / "a.ply", return_data=True)
    np.testing.assert_array_equal(V2, V)
    np.testing.assert_array_equal(F2, F)
    assert back["red"].dtype == np.uint8 and back["red"].max() == 255
    np.testing.assert_array_equal(back["green"], rgb[:, 1])
    assert back["inside"].dtype == np.uint8
    np.testing.assert_array_equal(back["inside"], uv[:, 0] > 0)
    assert back["label"].dtype == np.int32
    np.testing.assert_array_equal(back["label"], data["label"])
    np.testing.assert_array_equal(back["uv"], uv)


@pytest.mark.parametrize("text", [False, True])
def test_ply_of_every_property_type(tmp_path, text):
    """Binary PLY colours as ``uchar`` (meshio read 200 as -56) and the types meshio's
    binary reader refused (``char``, ``short``, ``ushort``) are read as written."""
    from plyfile import PlyData, PlyElement

    uv, F = grid_disk(4)
    types = {"red": "u1", "c": "i1", "s": "i2", "us": "u2", "ui": "u4", "f": "f4"}
    vertex = np.zeros(len(uv), dtype=[("x", "f4"), ("y", "f4"), ("z", "f4")] + list(types.items()))
    vertex["x"], vertex["y"] = uv.T
    values = {"red": 200, "c": -100, "s": -30000, "us": 60000, "ui": 4000000000, "f": 0.5}
    for name, value in values.items():
        vertex[name] = value
    face = np.empty(len(F), dtype=[("vertex_indices", "i4", (3,))])
    face["vertex_indices"] = F
    elements = [PlyElement.describe(vertex, "vertex"), PlyElement.describe(face, "face", len_types={"vertex_indices": "u1"})]
    PlyData(elements, text=text).write(str(tmp_path / "t.ply"))
    V, F2, data = read_mesh(tmp_path / "t.ply", return_data=True)
    np.testing.assert_array_equal(F2, F)
    np.testing.assert_allclose(V[:, :2], uv, atol=1e-7)
    for name, value in values.items():
        assert data[name].dtype == np.dtype(types[name]) and (data[name] == value).all(), name


def test_failed_write_leaves_no_file(tmp_path):
    uv, F = grid_disk(4)
    with pytest.raises(ValueError, match="cannot write .xyz files"):
        write_mesh(tmp_path / "m.xyz", np.column_stack([uv, 0 * uv[:, 0]]), F)
    assert list(tmp_path.iterdir()) == []


def test_written_files_get_the_usual_permissions(tmp_path):
    """The file written through a private temporary file gets the permissions the umask
    gives a new file (they were 0600 whatever the umask), and a file it replaces keeps
    its own."""
    uv, F = grid_disk(4)
    V = np.column_stack([uv, np.zeros(len(uv))])
    umask = os.umask(0o022)
    try:
        write_mesh(tmp_path / "new.ply", V, F)
        assert stat.S_IMODE((tmp_path / "new.ply").stat().st_mode) == 0o644
        os.umask(0o007)
        write_mesh(tmp_path / "group.obj", V, F)
        assert stat.S_IMODE((tmp_path / "group.obj").stat().st_mode) == 0o660
        (tmp_path / "new.ply").chmod(0o640)
        write_mesh(tmp_path / "new.ply", V, F)
        assert stat.S_IMODE((tmp_path / "new.ply").stat().st_mode) == 0o640
    finally:
        os.umask(umask)


def test_quads_are_split_along_their_shorter_diagonal(tmp_path):
    """Two quads, one whose diagonal 0-2 is the shorter (1.41 against 2.12), a kite whose
    diagonal 5-7 is (0.2 against 2); each becomes two triangles, in order, oriented as
    the quad."""
    path = tmp_path / "quads.obj"
    path.write_text(
        "v 0 0 0\nv 1.5 0 0\nv 1 1 0\nv 0 1.5 0\nv 2 0.5 0\nv 3 0.4 0\nv 4 0.5 0\nv 3 0.6 0\n"
        "f 1 2 3 4\nf 5 6 7 8\n"
    )
    V, F = read_mesh(path)
    np.testing.assert_array_equal(F, [[0, 1, 2], [0, 2, 3], [4, 5, 7], [5, 6, 7]])


def test_convex_polygons_become_fans_in_every_format(tmp_path):
    """A convex pentagon and a hexagon (OBJ, OFF, and VTK through meshio's polygon cells)
    become the fans from their first corners, in order; OFF read here also takes what
    meshio refused: counts on the header's line, comments, colours after a face, COFF."""
    P = np.array([[0, 0, 0], [1, 0, 0], [1.5, 1, 0], [0.5, 1.5, 0], [-0.5, 1, 0], [3, 0, 0], [4, 0, 0], [4.5, 1, 0], [4, 2, 0], [3, 2, 0], [2.5, 1, 0]], float)
    fans = [[0, 1, 2], [0, 2, 3], [0, 3, 4], [5, 6, 7], [5, 7, 8], [5, 8, 9], [5, 9, 10]]
    obj = tmp_path / "p.obj"
    obj.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in P) + "f 1 2 3 4 5\nf 6 7 8 9 10 11\n")
    off = tmp_path / "p.off"
    off.write_text(
        "COFF 11 2 0 # counts here\n" + "".join(f"{x} {y} {z} 255 0 0 255\n" for x, y, z in P)
        + "5 0 1 2 3 4 0.5 0.5 0.5\n# a hexagon\n6 5 6 7 8 9 10\n"
    )
    import meshio

    vtk = tmp_path / "p.vtk"
    meshio.write(vtk, meshio.Mesh(P, [("polygon", np.array([[0, 1, 2, 3, 4]])), ("polygon", np.array([[5, 6, 7, 8, 9, 10]]))]))
    for path in (obj, off, vtk):
        V, F = read_mesh(path)
        np.testing.assert_array_equal(V, P)
        np.testing.assert_array_equal(F, fans)


def test_off_reads_as_meshio_did():
    for name in ("venus.off", "foot.off", "face-YH.off"):
        path = SHARED / name
        if not path.is_file():
            pytest.skip("needs ../shared/data")
        import meshio

        m = meshio.read(path)
        V, F = read_mesh(path)
        np.testing.assert_array_equal(V, m.points)
        np.testing.assert_array_equal(F, m.cells[0].data)


def test_read_errors(tmp_path):
    with pytest.raises(MeshReadError, match="no such file"):
        read_mesh(tmp_path / "missing.obj")
    star = tmp_path / "star.obj"  # a pentagram's five points, in the order that crosses
    star.write_text("v 0 0 0\nv 1 0 0\nv 1.5 1 0\nv 0.5 1.5 0\nv -0.5 1 0\nf 1 3 5 2 4\n")
    with pytest.raises(MeshReadError, match="^" + str(star) + ": a face of 5 corners is not convex"):
        read_mesh(star)
    (tmp_path / "half.off").write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n")
    with pytest.raises(MeshReadError, match="fewer vertices or faces than its header says"):
        read_mesh(tmp_path / "half.off")
    junk = tmp_path / "junk.ply"
    junk.write_text("not a ply file\n")
    with pytest.raises(MeshReadError, match="cannot read"):
        read_mesh(junk)


def test_vtk_polygonal_data_through_pyvista(tmp_path, monkeypatch):
    """Legacy VTK files of POLYDATA (which meshio refuses, printing why and exiting) and
    .vtp files are read through pyvista, and .vtp written through it, texture coordinates
    as its active ones, data in their types, the same bytes each time; without pyvista,
    meshio's reason is kept and .vtp is refused before any work."""
    pytest.importorskip("pyvista")
    polydata = tmp_path / "tri.vtk"
    polydata.write_text(
        "# vtk DataFile Version 4.2\nvtk output\nASCII\nDATASET POLYDATA\nPOINTS 4 double\n"
        "0 0 0 1 0 0 1 1 0 0 1 0\nPOLYGONS 1 5\n4 0 1 2 3\n"
    )
    V, F = read_mesh(polydata)
    np.testing.assert_array_equal(V[:, :2], [[0, 0], [1, 0], [1, 1], [0, 1]])
    assert len(F) == 2
    uv, G = grid_disk(6)
    X = np.column_stack([uv, uv[:, 0] * uv[:, 1]])
    data = {"height": X[:, 2], "label": np.arange(len(X), dtype=np.uint8)}
    path = tmp_path / "grid.vtp"
    write_mesh(path, X, G, uv=uv[:, ::-1], data=data)
    first = path.read_bytes()
    W, H, back = read_mesh(path, return_data=True)
    np.testing.assert_array_equal(W, X)
    np.testing.assert_array_equal(H, G)
    np.testing.assert_array_equal(back["uv"], uv[:, ::-1])
    assert back["label"].dtype == np.uint8 and np.array_equal(back["label"], data["label"])
    write_mesh(path, X, G, uv=uv[:, ::-1], data=data)
    assert path.read_bytes() == first
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "pyvista" else find_spec(name))
    with pytest.raises(MeshReadError, match=r"^" + str(polydata) + r": cannot read \(Only VTK 'UNSTRUCTURED_GRID', "
                       r"'STRUCTURED_POINTS', 'STRUCTURED_GRID', 'RECTILINEAR_GRID' supported \(not POLYDATA\)\.\)$"):
        read_mesh(polydata)
    with pytest.raises(ValueError, match="^cannot write .vtp files without pyvista: pip install pyvista$"):
        write_mesh(tmp_path / "no.vtp", X, G)
    assert not (tmp_path / "no.vtp").exists()


def test_read_mat():
    path = SHARED / "alex_3.mat"
    if not path.is_file():
        pytest.skip("needs ../shared/data")
    V, F = read_mesh(path)
    V2, F2 = read_mesh(SHARED / "alex_3.ply")
    np.testing.assert_array_equal(F, F2)
    np.testing.assert_allclose(V, V2)


def test_a_format_whose_writer_lacks_a_module_is_refused_before_the_work(tmp_path, monkeypatch, capsys):
    """meshio's XDMF writer needs h5py: the check tries the writer on one triangle (the
    remesh was done first, and then its write failed)."""
    import sys

    from qcremesh.cli.main import main
    from qcremesh.mesh.io import check_writable

    monkeypatch.setitem(sys.modules, "h5py", None)  # as if not installed
    with pytest.raises(ValueError, match=r"^cannot write \.xdmf files \(.*h5py.*\)$"):
        check_writable(tmp_path / "out.xdmf")
    check_writable(tmp_path / "out.vtu")
    assert main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(tmp_path / "out.xdmf")]) == 1
    err = capsys.readouterr()
    assert err.out == "" and err.err.startswith(f"qcremesh: error: {tmp_path / 'out.xdmf'}: cannot write .xdmf files")
    assert list(tmp_path.iterdir()) == []
