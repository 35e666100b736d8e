import re
import subprocess
import sys

import numpy as np
import pytest
from scipy.spatial import cKDTree

from conftest import (
    DATA,
    cad_trough,
    grid_disk,
    holed_disk,
    holed_plate,
    shapes,
    shared,
    sphere_mesh,
    split_vertex,
    star_disk,
    strip_disk,
    torus_mesh,
    tube_disk,
    uv_sphere,
)
from qcremesh.cli.main import _warn_departure, main
from qcremesh.geometry.quality import mesh_quality
from qcremesh.mesh.io import read_mesh, write_mesh
from qcremesh.mesh.subdivide import upsample
from qcremesh.mesh.topology import boundary_edges


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


def test_param_says_when_the_map_is_on_the_intrinsic_delaunay_triangulation(tmp_path, capsys):
    """A sheared star (see test_disk.py): the map is computed on the intrinsic Delaunay
    triangulation and the needles it folds are unfolded, which the summary says; the
    output keeps the input's faces. fran_cut's map is on its own triangulation."""
    path = tmp_path / "star.ply"
    write_mesh(path, *star_disk())
    assert main(["param", str(path), "-o", str(tmp_path / "d.obj")]) == 0
    text = capsys.readouterr().out
    assert "(on the intrinsic Delaunay triangulation, 2241 edge flips away)" in text
    assert "folded faces: 0 (5 folded by the solve, unfolded)" in text
    np.testing.assert_array_equal(read_mesh(tmp_path / "d.obj")[1], star_disk()[1])
    assert main(["param", str(DATA / "fran_cut.ply"), "-o", str(tmp_path / "f.obj")]) == 0
    assert "intrinsic" not in capsys.readouterr().out


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


def test_summary_into_a_closed_pipe_ends_quietly(tmp_path):
    """`qcremesh remesh ... | head` where the reader has gone: the output file is written,
    and no traceback follows (there was one, BrokenPipeError)."""
    out = tmp_path / "r.ply"
    command = [sys.executable, "-m", "qcremesh.cli.main", "remesh", str(DATA / "fran_cut.ply"), "-o", str(out)]
    proc = subprocess.Popen(command + ["--faces", "500"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.close()  # nobody reads the summary
    err = proc.stderr.read().decode()
    proc.wait()
    assert "Traceback" not in err and out.is_file()


def test_interrupt_ends_with_one_line_and_no_partial_file(tmp_path, capsys, monkeypatch):
    """Ctrl-C during the remesh: status 130, one line instead of a traceback, no file."""
    import qcremesh.remeshing.pipeline as pipeline

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(pipeline, "remesh", interrupted)
    assert main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(tmp_path / "r.ply")]) == 130
    assert capsys.readouterr().err == "qcremesh: interrupted; no partial output was written\n"
    assert list(tmp_path.iterdir()) == []


def test_param_rejects_non_obj_output(tmp_path, capsys):
    assert main(["param", str(DATA / "fran_cut.ply"), "-o", str(tmp_path / "x.ply")]) == 1
    assert "written as OBJ" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_param_rejects_a_plot_format_before_the_work(tmp_path, capsys):
    """A figure format matplotlib cannot save is told at once, and nothing is written
    (the map was written and a traceback followed)."""
    plot = tmp_path / "p.xyz"
    assert main(["param", str(DATA / "fran_cut.ply"), "-o", str(tmp_path / "d.obj"), "--plot", str(plot)]) == 1
    err = capsys.readouterr().err.strip()
    assert err == f"qcremesh: error: {plot}: cannot draw .xyz figures (png, pdf, svg, jpg, ...)"
    assert list(tmp_path.iterdir()) == []


def test_remesh_cli_with_report(tmp_path, capsys):
    out = tmp_path / "re.ply"
    report = tmp_path / "report"
    args = ["remesh", str(DATA / "fran_cut.ply"), "-o", str(out), "--faces", "2000", "--method", "subdivided"]
    assert main(args + ["--report", str(report)]) == 0
    text = capsys.readouterr().out
    assert "radius ratio 2 r_in / R_circ: mean" in text and "Hausdorff" in text and "time (s):" in text
    V, F = read_mesh(out)
    assert abs(len(F) - 2000) <= 100
    for name in ["surfaces.png", "radius_ratio.png", "disk_meshes.png", "summary.json", "report.html"]:
        assert (report / name).is_file()
    page = (report / "report.html").read_text()
    assert 'src="surfaces.png"' in page and 'src="radius_ratio.png"' in page and "q_mean" in page


def test_remesh_cli_report_without_matplotlib_is_refused_before_the_work(tmp_path, capsys, monkeypatch):
    import qcremesh.cli.report as report

    def missing():
        raise ImportError("plots need matplotlib: pip install 'qcremesh[plot]'")

    monkeypatch.setattr(report, "_pyplot", missing)
    out = tmp_path / "re.ply"
    assert main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(out), "--report", str(tmp_path / "r")]) == 1
    assert capsys.readouterr().err.strip() == "qcremesh: error: plots need matplotlib: pip install 'qcremesh[plot]'"
    assert list(tmp_path.iterdir()) == []


def test_remesh_cli_says_when_landmarks_were_drawn_again(tmp_path, capsys):
    assert main(["remesh", str(shared("camel_b.obj")), "-o", str(tmp_path / "c.ply"), "--faces", "1788"]) == 0
    text = capsys.readouterr().out
    assert ", drawn 3 times (the first draws left faces below 0.3)" in text
    assert (
        "\ncut into 5 pieces where the disk map crowds the boundary, remeshed each on its own map and welded back "
        "(1,280, 61, 197, 62, 173 faces; the numbers below are the largest's)\n"
    ) in text


def test_remesh_cli_says_why_fewer_levels_were_used(tmp_path, capsys):
    assert main(["remesh", str(DATA / "human_face.obj"), "-o", str(tmp_path / "f.ply"), "--faces", "1707"]) == 0
    assert (
        "\nsubdivision levels: 0, fewer than planned (at 2: part of the surface left beyond the snapping's reach; "
        "at 1: the CVT's cells uneven on the surface)\n"
    ) in capsys.readouterr().out


def test_remesh_cli_says_when_the_input_was_refined(tmp_path, capsys):
    path = tmp_path / "trough.obj"
    write_mesh(path, *cad_trough())
    assert main(["remesh", str(path), "-o", str(tmp_path / "t.ply"), "--faces", "3000"]) == 0
    found = re.search(
        r"\nthe input refined first, the surface kept \(a few large faces, or needles, beside the output's\): "
        r"([\d,]+) faces\n",
        capsys.readouterr().out,
    )
    assert found and int(found.group(1).replace(",", "")) > 10 * 78


def test_remesh_cli_warns_when_the_disk_map_is_far_from_conformal(tmp_path, capsys):
    """A strip 64 times as long as wide: its disk map crowds the ends beyond what the
    triangulation of the landmarks resolves; cut into pieces where it crowds, and the
    pieces with slivers again where their maps crowd, the pieces' maps still crowd their
    own ends (40 % of the boundary vertices of the most crowded piece get the narrowest
    arc). The output is written and a warning says why it is poor. fran_cut (none) gets
    no warning."""
    path = tmp_path / "strip.obj"
    write_mesh(path, *strip_disk(64))
    assert main(["remesh", str(path), "-o", str(tmp_path / "s.ply"), "--faces", "1000"]) == 0
    err = capsys.readouterr().err
    assert "qcremesh: warning: the disk map crowds 40 % of the boundary vertices to its narrowest arc" in err
    assert (tmp_path / "s.ply").is_file()
    assert main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(tmp_path / "f.ply"), "--faces", "1000"]) == 0
    assert "warning" not in capsys.readouterr().err


def test_cli_warns_when_the_disk_map_loses_precision(tmp_path, capsys):
    """A tube 50 long and of radius 1, closed at its far end: its disk map puts the far
    end within exp(-50) of the centre, below the precision of double numbers (faces of
    zero area, folds). Both commands write their output and warn; a tube 30 long (its far
    end within 2e-9 of the centre, resolved) gets no warning. Which of the lost faces fold
    is rounding noise (332 on an AMD EPYC, 225 on an Intel Xeon, with either sparse solver
    and the same packages); the count lies between one and
    the faces farther than 36 along the tube (exp(-36) = 2e-16), and both commands count
    the same map."""
    path = tmp_path / "tube.obj"
    V, F = tube_disk(50)
    write_mesh(path, V, F)
    lost = int((V[F, 2].mean(1) > 36).sum())
    warning = r"qcremesh: warning: the disk map has (\d+) folded or zero-area faces: it squeezes a part of"
    assert main(["param", str(path), "-o", str(tmp_path / "d.obj")]) == 0
    folded = int(re.search(warning, capsys.readouterr().err).group(1))
    assert 1 <= folded <= lost
    assert main(["remesh", str(path), "-o", str(tmp_path / "r.ply"), "--faces", "1000"]) == 0
    assert int(re.search(warning, capsys.readouterr().err).group(1)) == folded
    assert (tmp_path / "d.obj").is_file() and (tmp_path / "r.ply").is_file()
    write_mesh(path, *tube_disk(30))
    assert main(["remesh", str(path), "-o", str(tmp_path / "r.ply"), "--faces", "1000"]) == 0
    assert "warning" not in capsys.readouterr().err


def test_cli_warns_when_the_input_overlaps_itself(tmp_path, capsys):
    """A gently bent grid whose middle band was mirrored across itself: its connectivity
    is a sound disk, but it folds back onto itself at 58 of its 2465 interior edges
    (2.4 %). Both commands write their output and warn; human_face (2 such edges of 51k,
    at the walls of its narrowest slits) gets no warning."""
    uv, F = grid_disk(30, jitter=0.3)
    X = np.column_stack([uv, 0.1 * np.sin(3 * uv[:, 0])])
    band = (uv[:, 0] > 0.4) & (uv[:, 0] < 0.6)
    X[band, 0] = 1.0 - X[band, 0]
    path = tmp_path / "folded.obj"
    write_mesh(path, X, F)
    message = "qcremesh: warning: the input folds back onto itself at 58 of its 2465 interior edges"
    assert main(["param", str(path), "-o", str(tmp_path / "d.obj")]) == 0
    assert message in capsys.readouterr().err
    assert main(["remesh", str(path), "-o", str(tmp_path / "r.ply")]) == 0
    assert message in capsys.readouterr().err
    assert main(["param", str(DATA / "human_face.obj"), "-o", str(tmp_path / "f.obj")]) == 0
    assert "warning" not in capsys.readouterr().err


def test_remesh_cli_repairs_zero_area_faces(tmp_path, capsys):
    """A grid with two vertices split in two at the same point (four faces of zero area,
    which param refuses): remesh merges them back first and says so."""
    uv, F = grid_disk(20, jitter=0.3)
    V = np.column_stack([uv, 0.1 * uv[:, 0] ** 2])
    for v in (150, 250):
        V, F = split_vertex(V, F, v)
    path = tmp_path / "needles.obj"
    write_mesh(path, V, F)
    assert main(["param", str(path), "-o", str(tmp_path / "d.obj")]) == 1
    assert "4 degenerate faces (zero area or within rounding of it)" in capsys.readouterr().err
    assert main(["remesh", str(path), "-o", str(tmp_path / "r.ply"), "--faces", "600"]) == 0
    out = capsys.readouterr().out
    assert "repaired the input first: 4 needles (an edge of zero length) merged, 0 caps" in out


def test_remesh_cli_detaches_a_fin(tmp_path, capsys):
    """A triangle standing on an interior edge of a grid: remesh detaches it and says so."""
    uv, F = grid_disk(12)
    a, b = F[np.argmin(np.linalg.norm(uv[F].mean(1) - 0.5, axis=1)), :2]
    V = np.r_[np.column_stack([uv, np.zeros(len(uv))]), [[*(uv[a] + uv[b]) / 2, 0.1]]]
    path = tmp_path / "fin.obj"
    write_mesh(path, V, np.r_[F, [[a, b, len(uv)]]])
    assert main(["remesh", str(path), "-o", str(tmp_path / "r.obj"), "--faces", "400"]) == 0
    out = capsys.readouterr().out
    assert "repaired the input first: 1 edges of more than two faces: the sheets beyond the flattest two detached" in out


def test_remesh_cli_warns_of_a_face_count_far_from_the_asked(tmp_path, capsys):
    """Ten squares of two triangles apart at 20 faces: each piece is asked for at least 4."""
    square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float)
    path = tmp_path / "squares.obj"
    write_mesh(path, np.concatenate([square + [3 * i, 0, 0] for i in range(10)]),
               np.concatenate([np.array([[0, 1, 2], [0, 2, 3]]) + 4 * i for i in range(10)]))
    assert main(["remesh", str(path), "-o", str(tmp_path / "r.obj"), "--faces", "20"]) == 0
    assert "qcremesh: warning: 39 faces, 95 % off the 20 asked for" in capsys.readouterr().err
    assert main(["remesh", str(path), "-o", str(tmp_path / "r.obj"), "--faces", "200"]) == 0
    assert "asked for" not in capsys.readouterr().err


def test_remesh_cli_orients_the_input_and_warns_of_no_fold(tmp_path, capsys):
    """fran_cut with a fifth of its faces reversed: remesh turns them back, says so, and
    does not take the reversed faces for folds of the surface."""
    V, F = read_mesh(DATA / "fran_cut.ply")
    turned = np.random.default_rng(1).random(len(F)) < 0.2
    F[turned] = F[turned][:, ::-1]
    path = tmp_path / "turned.obj"
    write_mesh(path, V, F)
    assert main(["remesh", str(path), "-o", str(tmp_path / "r.obj"), "--faces", "2000"]) == 0
    captured = capsys.readouterr()
    assert f"repaired the input first: {turned.sum()} faces turned against their neighbours reversed" in captured.out
    assert "warning" not in captured.err


def test_remesh_cli_edge_length(tmp_path, capsys):
    """--edge-length L: as many faces as equilateral triangles of side L cover the area
    (fran_cut, 0.0088 in its units, about a seventeenth of its height: 1,007 of them)."""
    out = tmp_path / "e.ply"
    assert main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(out), "--edge-length", "0.0088"]) == 0
    V, F = read_mesh(out)
    assert abs(len(F) - 1007) <= 50
    captured = capsys.readouterr()
    assert "warning" not in captured.err
    edge = float(re.search(r"mean edge length ([\d.e-]+)\n", captured.out).group(1))
    assert edge == pytest.approx(0.0088, rel=0.03)


def test_remesh_cli_teichmuller_iterations(tmp_path, capsys):
    """5 QC iterations by default, which stop before the convergence test and say why no
    more are needed (the relaxation follows); without the relaxation, that more would
    converge; more run the map to it."""
    out = tmp_path / "t.ply"
    assert main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(out), "--faces", "2000"]) == 0
    assert re.search(r"Teichmueller map: k = [\d.]+ after 5 iterations \(stopped before converging: the relaxation "
                     r"finishes the mesh, and more iterations leave its radius ratios about as they are\), 0 folded "
                     r"faces", capsys.readouterr().out)
    assert main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(out), "--faces", "2000", "--relax", "0"]) == 0
    assert re.search(r"Teichmueller map: k = [\d.]+ after 5 iterations \(not converged: --teichmuller-iterations for "
                     r"more\), 0 folded faces", capsys.readouterr().out)
    assert main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(out), "--faces", "2000",
                 "--teichmuller-iterations", "100"]) == 0
    assert re.search(r"Teichmueller map: k = [\d.]+ after \d+ iterations, 0 folded faces", capsys.readouterr().out)
    assert main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(out), "--teichmuller-iterations", "0"]) == 1
    assert capsys.readouterr().err.strip() == "qcremesh: error: --teichmuller-iterations must be at least 1"


def test_remesh_cli_is_deterministic(tmp_path):
    args = ["remesh", str(DATA / "fran_cut.ply"), "--faces", "1500", "--method", "subdivided", "--seed", "7"]
    assert main(args + ["-o", str(tmp_path / "a.obj")]) == 0
    assert main(args + ["-o", str(tmp_path / "b.obj")]) == 0
    assert (tmp_path / "a.obj").read_bytes() == (tmp_path / "b.obj").read_bytes()


def test_remesh_cli_errors(tmp_path, capsys):
    out = tmp_path / "x.obj"
    assert main(["remesh", str(DATA / "featuretype.STL"), "-o", str(out), "--no-weld-seams"]) == 1
    err = capsys.readouterr().err.strip()
    # a CAD part saved face by face: cracks, boundary loops whose vertices coincide (merged
    # by default)
    assert err == (
        f"qcremesh: error: {DATA / 'featuretype.STL'}: the remesh of the surface cut open does not weld back "
        "into its topology (576 of its 576 boundary vertices lie at the same points as others: cracks between "
        "faces whose shared corners are not one vertex, or seams written twice; weld_seams=True (--weld-seams) "
        "merges them first)"
    )
    assert main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(out), "--faces", "2"]) == 1
    assert capsys.readouterr().err.strip() == "qcremesh: error: --faces must be at least 4"
    triangle = tmp_path / "one.obj"
    triangle.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    assert main(["remesh", str(triangle), "-o", str(out)]) == 1
    assert capsys.readouterr().err.strip() == (
        f"qcremesh: error: {triangle} has 1 face, and a remesh needs at least 4: give --faces"
    )
    triangle.unlink()
    assert main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(out), "--seed", "-1"]) == 1
    assert capsys.readouterr().err.strip() == "qcremesh: error: --seed must be >= 0"
    assert main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(out), "--snap", "-0.5"]) == 1
    assert capsys.readouterr().err.strip() == "qcremesh: error: --snap must be >= 0"
    # a face count no machine has the memory for is refused before the work
    assert main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(out), "--faces", str(10**13)]) == 1
    assert re.fullmatch(
        r"qcremesh: error: --faces asks for 10,000,000,000,000 faces, whose remesh would need about [\d,]+ GiB of "
        r"memory \(about 0\.9 KiB per face\), more than this machine's \d+ GiB",
        capsys.readouterr().err.strip(),
    )
    assert main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(out), "--edge-length", "1e-9"]) == 1
    assert capsys.readouterr().err.startswith("qcremesh: error: --edge-length asks for ")
    assert main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(out), "--edge-length", "0"]) == 1
    assert capsys.readouterr().err.strip() == "qcremesh: error: --edge-length must be positive"
    assert main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(out), "--edge-length", "1"]) == 1
    assert capsys.readouterr().err.strip() == (
        "qcremesh: error: --edge-length: edge_length 1 is too long for this surface: its area takes 0 "
        "equilateral triangles of that side, and a remesh needs at least 4"
    )
    with pytest.raises(SystemExit):  # argparse: not both
        main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(out), "--faces", "100", "--edge-length", "0.01"])
    capsys.readouterr()
    assert main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(tmp_path / "no" / "x.obj")]) == 1
    assert "does not exist" in capsys.readouterr().err
    # an output format it cannot write is told before the remesh (it was a traceback after it)
    assert main(["remesh", str(DATA / "fran_cut.ply"), "-o", str(tmp_path / "x.xyz")]) == 1
    assert capsys.readouterr().err.strip() == (
        f"qcremesh: error: {tmp_path / 'x.xyz'}: cannot write .xyz files "
        "(the extension names the format: .obj, .ply, .off, .stl, .vtk, .vtu, ...)"
    )
    assert list(tmp_path.iterdir()) == []


def test_quality_cli_json(capsys):
    import json

    assert main(["quality", str(DATA / "fran_cut.ply"), "--json", "--reference", str(DATA / "fran_cut.ply")]) == 0
    q = json.loads(capsys.readouterr().out)
    assert q["faces"] == 4224 and q["hausdorff"] < 1e-12 and 0 < q["q_min"] < q["q_mean"] < 1
    assert q["self_intersecting_faces"] == q["reference_self_intersecting_faces"] == 0
    assert main(["quality", str(DATA / "fran_cut.ply")]) == 0
    text = capsys.readouterr().out
    assert "radius ratio" in text and "manifold yes, self-intersecting faces 0\n" in text
    assert main(["quality", str(DATA / "human_face.obj"), "--reference", str(DATA / "human_face.obj")]) == 0
    assert "manifold yes, self-intersecting faces 406 (the reference: 406)\n" in capsys.readouterr().out


def test_quality_cli_against_a_reference_with_a_boundary_where_the_mesh_has_none(tmp_path, capsys):
    """A closed mesh measured against a disk: no boundary distance to tell (it was a
    TypeError on None)."""
    path = tmp_path / "sphere.obj"
    write_mesh(path, *sphere_mesh())
    assert main(["quality", str(path), "--reference", str(DATA / "fran_cut.ply")]) == 0
    line = capsys.readouterr().out.strip().splitlines()[-1].strip()
    assert line.startswith("distance to the reference (of its bounding-box diagonal): Hausdorff ")
    assert line.endswith(" mean edge lengths), mean 392.0933 %, no boundary Hausdorff (only one of the two has a boundary)")


def test_remesh_cli_warns_of_a_corner_too_sharp_for_good_triangles(tmp_path, capsys):
    """A flat triangle with an 8 degree corner: kept as a vertex, it bounds the radius
    ratio of the triangles there (0.26 at best, one isosceles triangle), which the warning
    says; the output is written."""
    half = np.radians(4.0)
    V = np.array([[0.0, 0.0, 0.0], [1.0, -np.tan(half), 0.0], [1.0, np.tan(half), 0.0]])
    V, F = upsample(V, np.array([[0, 1, 2]]), 5)
    path = tmp_path / "wedge.obj"
    write_mesh(path, V, F)
    assert main(["remesh", str(path), "-o", str(tmp_path / "w.ply"), "--faces", "500"]) == 0
    err = capsys.readouterr().err
    assert (
        "qcremesh: warning: the input boundary has a corner of 8.0 degrees, kept as a vertex: the triangles there "
        "are about as thin (a fan of triangles filling that angle has one with a radius ratio of at most 0.26)"
    ) in err
    assert (tmp_path / "w.ply").is_file()


def test_remesh_cli_sizing_from_a_vertex_array(tmp_path, capsys):
    V, F = read_mesh(DATA / "fran_cut.ply")
    # edges half as long on the lower half of the model
    z = (V[:, 2] - V[:, 2].min()) / np.ptp(V[:, 2])
    path = tmp_path / "sized.vtk"
    write_mesh(path, V, F, data={"size": np.clip(2 * z, 0.5, 1.0)})
    out = tmp_path / "r.ply"
    assert main(["remesh", str(path), "-o", str(out), "--faces", "3000", "--sizing", "size"]) == 0
    assert "sizing (size): edges planned down to 0.50 of the longest" in capsys.readouterr().out
    assert abs(len(read_mesh(out)[1]) - 3000) <= 150
    assert main(["remesh", str(path), "-o", str(tmp_path / "x.ply"), "--sizing", "width"]) == 1
    err = capsys.readouterr().err.strip()
    assert err == f"qcremesh: error: --sizing: {path} has no per-vertex array 'width' (it has: size)"
    args = ["remesh", str(path), "-o", str(tmp_path / "x.ply"), "--sizing", "curvature", "--method", "uniform"]
    assert main(args) == 1
    assert capsys.readouterr().err.strip() == (
        "qcremesh: error: --sizing does not go with --method uniform (a regular mesh of the disk)"
    )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.ply", "sized.vtk"]


def test_remesh_cli_points_at_creases_where_the_output_departs(tmp_path, capsys):
    """A plate 0.1 thick with three holes (genus 3, its rims and holes' edges turning by
    90 degrees) at 3,000 faces: some output faces pass through others, and the note
    after the warning counts its 390 such edges; with --creases given, no note. (The
    closed CAD cylinder of the test's first version, whose face turned over at a cap's
    centre where the cut that opens it ends, no longer does: the faces at a cut are
    judged for turning over.)"""
    path = tmp_path / "plate.obj"
    write_mesh(path, *holed_plate())
    out = tmp_path / "r.obj"
    assert main(["remesh", str(path), "-o", str(out), "--faces", "3000"]) == 0
    warning, note = capsys.readouterr().err.strip().splitlines()
    assert re.fullmatch(r"qcremesh: warning: \d+ output faces pass through others \(the input: 0\)", warning)
    assert note == (
        "qcremesh: note: 390 input edges turn by more than 60 degrees: where they are creases (a CAD part), "
        "--creases keeps them as output edges instead of rounding them off"
    )
    assert main(["remesh", str(path), "-o", str(out), "--faces", "3000", "--creases"]) == 0
    assert "note" not in capsys.readouterr().err


def test_remesh_cli_points_at_weld_seams_and_welds_them(tmp_path, capsys):
    """A sphere written with its seams twice: with --no-weld-seams, remeshed as the disk
    it is, with a note that counts its boundary vertices at the same points as others;
    with --weld-seams, closed, and the merge said among the repairs; by default too, its
    boundary being seams only and the file without per-vertex data, with a word on
    --no-weld-seams."""
    path = tmp_path / "sphere.obj"
    write_mesh(path, *uv_sphere(32, 16))
    out = tmp_path / "r.obj"
    assert main(["remesh", str(path), "-o", str(out), "--faces", "1000", "--no-weld-seams"]) == 0
    captured = capsys.readouterr()
    assert "boundary loops 1," in captured.out
    assert captured.err.strip() == (
        "qcremesh: note: 96 boundary vertices of the input lie at the same points as others: where they are seams "
        "written twice (a textured mesh), they stay boundary in the output, and --weld-seams merges them first"
    )
    assert main(["remesh", str(path), "-o", str(out), "--faces", "1000", "--weld-seams"]) == 0
    captured = capsys.readouterr()
    assert "boundary loops 0, Euler characteristic 2," in captured.out
    assert "79 boundary vertices at the same points as others merged (seams)" in captured.out
    assert captured.err == ""
    V, F = read_mesh(out)
    assert not len(boundary_edges(F))
    assert main(["remesh", str(path), "-o", str(out), "--faces", "1000"]) == 0
    captured = capsys.readouterr()
    assert "boundary loops 0, Euler characteristic 2," in captured.out
    assert (
        "79 boundary vertices at the same points as others merged (seams: by default, the whole boundary being "
        "seams or no two faces sharing a vertex; --no-weld-seams keeps them)" in captured.out
    )
    assert captured.err == ""


def test_remesh_cli_keeps_creases(tmp_path, capsys):
    path = tmp_path / "box.ply"
    write_mesh(path, *shapes.box(np.linspace(0.0, 1.0, 9), top=False))
    out = tmp_path / "r.obj"
    assert main(["remesh", str(path), "-o", str(out), "--creases"]) == 0  # 60 degrees
    text = capsys.readouterr().out
    assert (
        "creases: 64 edges turn by more than 60 degrees; cut along 8 paths into 5 pieces, remeshed each and "
        "welded back (" in text
    )
    assert "Hausdorff 0.000 %" in text
    assert main(["remesh", str(path), "-o", str(out), "--creases", "100"]) == 0
    assert "creases: no edge turns by more than 100 degrees" in capsys.readouterr().out
    # 60 faces: each side's piece would get 12, fewer than a piece may have
    assert main(["remesh", str(path), "-o", str(out), "--creases", "60", "--faces", "60"]) == 0
    assert capsys.readouterr().err.strip() == (
        "qcremesh: warning: the creases were not kept (the cuts along them leave pieces too small, or pieces the "
        "remesh refuses, or pieces that do not weld back): the surface was remeshed without them"
    )
    for args, message in [
        (["--creases", "0"], "--creases must be between 0 and 180 degrees"),
        (["--creases", "60", "--relax", "0"], "--creases needs the relaxation (--relax > 0) and a method other than uniform"),
    ]:
        assert main(["remesh", str(path), "-o", str(tmp_path / "x.obj"), *args]) == 1
        assert capsys.readouterr().err.strip() == f"qcremesh: error: {message}"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["box.ply", "r.obj"]


def test_remesh_cli_takes_closed_surfaces_holes_and_handles(tmp_path, capsys):
    path = tmp_path / "sphere.ply"
    write_mesh(path, *sphere_mesh(1500))
    assert main(["remesh", str(path), "-o", str(tmp_path / "r.obj"), "--faces", "2000"]) == 0
    assert "boundary loops 0, Euler characteristic 2, manifold yes" in capsys.readouterr().out
    V, F = holed_disk()
    write_mesh(tmp_path / "holes.ply", V, F)
    assert main(["remesh", str(tmp_path / "holes.ply"), "-o", str(tmp_path / "h.obj")]) == 0
    text = capsys.readouterr().out
    assert "boundary loops 3, Euler characteristic -1, manifold yes" in text
    assert re.search(r"\nnot a disk: cut open along \d+ edges, remeshed and welded shut\n", text)
    T, G = torus_mesh()
    write_mesh(tmp_path / "torus.ply", T, G)
    assert main(["remesh", str(tmp_path / "torus.ply"), "-o", str(tmp_path / "t.obj")]) == 0
    assert "boundary loops 0, Euler characteristic 0, manifold yes" in capsys.readouterr().out
    write_mesh(tmp_path / "two.ply", np.r_[V, T + 3], np.r_[F, G + len(V)])
    assert main(["remesh", str(tmp_path / "two.ply"), "-o", str(tmp_path / "two.obj"), "--faces", "2000"]) == 0
    text = capsys.readouterr().out
    assert "boundary loops 3, Euler characteristic -1, manifold yes" in text
    assert re.search(r"\n2 pieces, remeshed each \([\d,]+, [\d,]+ faces; the numbers below are the largest's\)\n", text)
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "h.obj", "holes.ply", "r.obj", "sphere.ply", "t.obj", "torus.ply", "two.obj", "two.ply"
    ]


def test_remesh_cli_splits_higher_genus_into_charts(tmp_path, capsys):
    path = tmp_path / "plate.ply"
    write_mesh(path, *holed_plate())
    assert main(["remesh", str(path), "-o", str(tmp_path / "r.ply"), "--faces", "4000"]) == 0
    text = capsys.readouterr().out
    assert "boundary loops 0, Euler characteristic -4, manifold yes" in text
    assert re.search(r"\nhigher genus: split into \d+ charts that are disks, remeshed each on its own map and welded "
                     r"back along \d+ borders \([\d, ]+ faces; the numbers below are the largest's\)\n", text)
    assert main(["remesh", str(path), "-o", str(tmp_path / "w.ply"), "--faces", "4000", "--whole"]) == 0
    text = capsys.readouterr().out
    assert "charts" not in text and re.search(r"\nnot a disk: cut open along \d+ edges", text)


def test_remesh_cli_whole_keeps_a_crowded_disk_in_one_piece(tmp_path, capsys):
    """A strip 16 times as long as wide: cut into three pieces where its map crowds by
    default (no warning then), remeshed in one piece with --whole, which the crowding
    warning then follows; its crowded ends are kept (0.27 mean edge lengths off; 1.8, and
    the warning that the output leaves the surface, with the boundary vertices spaced
    evenly along it)."""
    path = tmp_path / "strip.obj"
    write_mesh(path, *strip_disk(16))
    assert main(["remesh", str(path), "-o", str(tmp_path / "cut.ply"), "--faces", "1000"]) == 0
    captured = capsys.readouterr()
    assert "\ncut into 3 pieces where the disk map crowds the boundary" in captured.out
    assert "warning" not in captured.err
    assert main(["remesh", str(path), "-o", str(tmp_path / "whole.ply"), "--faces", "1000", "--whole"]) == 0
    captured = capsys.readouterr()
    assert "cut into" not in captured.out
    assert "qcremesh: warning: the disk map crowds 51 % of the boundary vertices to its narrowest arc" in captured.err
    assert "the output lies up to" not in captured.err


def test_departure_warnings_name_the_distance_and_the_crossing_faces(capsys):
    """Two triangles through each other against two flat ones: the output lies 2.07 from
    the input's far corner (2, 2, 0), 73 % of the diagonal and 2.0 mean edge lengths, and
    its 2 faces cross where the input's do not."""
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.2, 0.2, -0.5], [0.3, 0.2, 0.5], [0.25, 0.9, 0], [2, 2, 0]])
    quality = mesh_quality(V, np.array([[0, 1, 2], [3, 4, 5]]), reference=(V, np.array([[0, 1, 2], [1, 6, 2]])))
    _warn_departure(quality)
    err = capsys.readouterr().err
    assert (
        "qcremesh: warning: the output lies up to 73.08 % of the diagonal from the input, 2.0 times its mean edge "
        "length: it does not follow the surface there" in err
    )
    assert "qcremesh: warning: 2 output faces pass through others (the input: 0)" in err


def test_remesh_cli_says_where_the_weld_failed(tmp_path, capsys, monkeypatch):
    """A ball with a tail 0.06 across at 1,200 faces, its flaps with slivers not cut off
    and its edges only halved where the weld fails (test_cut's
    test_remesh_shortens_the_edges_where_the_weld_of_a_thin_tail_fails): the weld of its
    slit fails, with shorter edges too, and the slit is trimmed; the summary says each,
    in that order."""
    import qcremesh.remeshing.pipeline as pipeline
    from qcremesh.remeshing.cut_paths import CROWDED_MIN_EDGES

    monkeypatch.setattr(pipeline, "SLIVER_RUN_EDGES", CROWDED_MIN_EDGES)
    monkeypatch.setattr(pipeline, "WELD_REFINE_RATIOS", (0.5,))
    V, F = shapes.ball_with_tail(0.03, rings=118)
    path = tmp_path / "tail.obj"
    write_mesh(path, V, F)
    assert main(["remesh", str(path), "-o", str(tmp_path / "r.ply"), "--faces", "1200"]) == 0
    out = capsys.readouterr().out
    weld = out.index(
        "the first remesh did not weld back where the surface is thinner than about two edges: remeshed with "
        "edges down to 0.50 there"
    )
    trim = out.index(
        "the cut was shortened where the remesh did not weld back: the part of the surface there, thinner than "
        "about two edges, comes out coarse"
    )
    assert weld < trim
    assert "sizing (where the weld failed): edges planned down to" in out


def test_remesh_cli_says_when_it_cut_long_boundary_edges(tmp_path, capsys):
    from scipy.spatial import Delaunay

    P = np.random.default_rng(2).random((3000, 2)) * [3.0, 1.0]
    write_mesh(tmp_path / "points.obj", np.column_stack([P, np.zeros(len(P))]), Delaunay(P).simplices)
    assert main(["remesh", str(tmp_path / "points.obj"), "-o", str(tmp_path / "out.obj"), "--faces", "3000"]) == 0
    lines = [line for line in capsys.readouterr().out.splitlines() if line.startswith("boundary edges")]
    assert len(lines) == 1 and re.fullmatch(
        r"boundary edges more than 4 times as long as the edges around them \(a triangulated point set's hull\) "
        r"cut into pieces first: \d+ vertices added on them",
        lines[0],
    )


def test_remesh_cli_says_which_pieces_took_more_faces_or_were_kept(tmp_path, capsys, monkeypatch):
    """A small sphere beside a disk, remeshed at more than its share of 200 faces (which
    do not weld back); where no remesh of it welds, kept as in the input, with a
    warning."""
    import qcremesh.remeshing.pipeline as pipeline

    uv, F = grid_disk(10)
    S, G = sphere_mesh(200)
    path = tmp_path / "two.obj"
    write_mesh(path, np.r_[np.column_stack([uv, np.zeros(len(uv))]), 0.05 * S + [3, 0, 0]], np.r_[F, G + len(uv)])
    assert main(["remesh", str(path), "-o", str(tmp_path / "out.ply"), "--faces", "200"]) == 0
    captured = capsys.readouterr()
    assert (
        "\n1 of them remeshed at more than their share of the faces, which did not weld back or came out "
        "collapsed or away from the piece (parts a few output edges thin)\n" in captured.out
    )
    assert "kept as in the input" not in captured.err
    monkeypatch.setattr(pipeline, "weld_levels", lambda *args: None)
    assert main(["remesh", str(path), "-o", str(tmp_path / "out.ply"), "--faces", "200"]) == 0
    captured = capsys.readouterr()
    assert (
        "qcremesh: warning: piece 2 kept as in the input: no remesh of it at up to 4 times its face count welds "
        "back close to it (parts thinner than an output edge)\n" in captured.err
    )
    X, _ = read_mesh(tmp_path / "out.ply")
    assert cKDTree(X).query(0.05 * S + [3, 0, 0])[0].max() < 1e-6
