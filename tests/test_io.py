import os
import stat

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


def test_obj_bytes_are_deterministic(tmp_path):
    uv, F = grid_disk(5)
    V = np.column_stack([uv, uv[:, 0] ** 2])
    write_mesh(tmp_path / "a.obj", V, F, uv=uv)
    write_mesh(tmp_path / "b.obj", V, F, uv=uv)
    assert (tmp_path / "a.obj").read_bytes() == (tmp_path / "b.obj").read_bytes()


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


def test_read_errors(tmp_path):
    with pytest.raises(MeshReadError, match="no such file"):
        read_mesh(tmp_path / "missing.obj")
    pentagon = tmp_path / "pentagon.obj"
    pentagon.write_text("v 0 0 0\nv 1 0 0\nv 1.5 1 0\nv 0.5 1.5 0\nv -0.5 1 0\nf 1 2 3 4 5\n")
    with pytest.raises(MeshReadError, match="not a triangle mesh \\(has polygon cells\\)"):
        read_mesh(pentagon)
    junk = tmp_path / "junk.ply"
    junk.write_text("not a ply file\n")
    with pytest.raises(MeshReadError, match="cannot read"):
        read_mesh(junk)


def test_read_mat():
    path = SHARED / "alex_3.mat"
    if not path.is_file():
        pytest.skip("needs ../shared/data")
    V, F = read_mesh(path)
    V2, F2 = read_mesh(SHARED / "alex_3.ply")
    np.testing.assert_array_equal(F, F2)
    np.testing.assert_allclose(V, V2)
