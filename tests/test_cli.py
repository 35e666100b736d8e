import subprocess
import sys

import numpy as np
import pytest

from conftest import DATA
from qcremesh.cli.main import main
from qcremesh.mesh.io import read_mesh


def test_param_writes_obj_with_disk_uv(tmp_path, capsys):
    out = tmp_path / "disk.obj"
    png = tmp_path / "disk.png"
    assert main(["param", str(DATA / "fran_cut.ply"), "-o", str(out), "--plot", str(png)]) == 0
    text = capsys.readouterr().out
    assert "2205 vertices, 4224 faces" in text
    assert "mean" in text and "folded faces: 0" in text and "time (s):" in text
    V, F = read_mesh(DATA / "fran_cut.ply")
    V2, F2, data = read_mesh(out, return_data=True)
    np.testing.assert_allclose(V2, V)
    np.testing.assert_array_equal(F2, F)
    np.testing.assert_allclose(np.hypot(*data["uv"].T).max(), 1)
    first_face = next(l for l in out.read_text().splitlines() if l.startswith("f "))
    a, b, c = F[0] + 1
    assert first_face == f"f {a}/{a} {b}/{b} {c}/{c}"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize(
    "mesh, message",
    [
        ("alex_3.ply", "alex_3.ply: 4 boundary loops, a disk has 1"),
        ("missing.obj", "missing.obj: no such file"),
    ],
)
def test_param_error_is_one_line_and_writes_nothing(tmp_path, mesh, message):
    out = tmp_path / "x.obj"
    proc = subprocess.run(
        [sys.executable, "-m", "qcremesh.cli.main", "param", str(DATA / mesh), "-o", str(out), "--plot", str(tmp_path / "p.png")],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 1
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("qcremesh: error: ") and lines[0].endswith(message)
    assert proc.stdout == ""
    assert list(tmp_path.iterdir()) == []


def test_param_rejects_non_obj_output(tmp_path, capsys):
    assert main(["param", str(DATA / "fran_cut.ply"), "-o", str(tmp_path / "x.ply")]) == 1
    assert "written as OBJ" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []
