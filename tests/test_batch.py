import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from conftest import DATA, grid_disk, strip_disk
from qcremesh.cli.batch import output_paths, remesh_file, remesh_files
from qcremesh.cli.main import main
from qcremesh.mesh.io import read_mesh, write_mesh


@pytest.fixture
def inputs(tmp_path):
    """Two small disks and a file that is not a mesh."""
    folder = tmp_path / "in"
    folder.mkdir()
    shutil.copy(DATA / "fran_cut.ply", folder / "fran.ply")
    uv, F = grid_disk(12, jitter=0.3)
    write_mesh(folder / "grid.obj", np.column_stack([uv, np.sin(3 * uv[:, 0]) * 0.2]), F)
    (folder / "junk.off").write_text("not a mesh\n")
    return [folder / "fran.ply", folder / "junk.off", folder / "grid.obj"]


def test_batch_cli_remeshes_each_file_as_remesh_does(tmp_path, inputs, capsys):
    out = tmp_path / "out"
    args = ["batch", *map(str, inputs), "-o", str(out), "--faces-ratio", "0.5", "--seed", "3"]
    assert main(args + ["--jobs", "2", "--json", str(tmp_path / "r.json")]) == 1  # one file failed
    captured = capsys.readouterr()
    lines = captured.out.splitlines()
    assert len(lines) == 3 and lines[-1].startswith("2 of 3 files remeshed in ")
    assert lines[-1].endswith(f"; failed: {inputs[1]}")
    assert captured.err.strip().endswith(f"{inputs[1]}: error: cannot read (no OFF header)")
    assert sorted(p.name for p in out.iterdir()) == ["fran.ply", "grid.obj"]
    records = {r["input"]: r for r in json.loads((tmp_path / "r.json").read_text())}
    assert records[str(inputs[1])] == {"input": str(inputs[1]), "output": None, "error": f"{inputs[1]}: cannot read (no OFF header)"}
    for path in (inputs[0], inputs[2]):
        # the same bytes as qcremesh remesh of the file, in this process
        faces = round(0.5 * len(read_mesh(path)[1]))
        single = tmp_path / f"single{path.suffix}"
        assert main(["remesh", str(path), "-o", str(single), "--faces", str(faces), "--seed", "3"]) == 0
        assert (out / path.name).read_bytes() == single.read_bytes()
        record = records[str(path)]
        assert record["output"] == str(out / path.name) and record["faces_in"] == 2 * faces
        assert abs(record["faces"] - faces) <= 0.05 * faces and record["q_min"] > 0.3
        assert f"{path} -> {out / path.name}: {record['faces']:,} faces, mean q {record['q_mean']:.4f}" in captured.out


def test_batch_cli_warns_of_an_output_that_leaves_the_surface(tmp_path, capsys):
    """A strip 24 long remeshed whole (its crowded ends lost, 1.6 mean edge lengths off)
    gets the remesh CLI's warning on its line."""
    path = tmp_path / "strip.obj"
    write_mesh(path, *strip_disk(24))
    assert main(["batch", str(path), "-o", str(tmp_path / "out"), "--faces", "1000", "--whole"]) == 0
    assert capsys.readouterr().err.strip() == (
        f"[1/1] {path}: warning: the output lies up to 1.6 times its mean edge length from the input"
    )


def test_batch_cli_writes_a_report_per_file(tmp_path, inputs, capsys):
    """--report DIR: each file's report in DIR/<output stem>, named in its record; two
    outputs of one stem are refused before the work."""
    out, report = tmp_path / "out", tmp_path / "reports"
    args = ["batch", str(inputs[0]), str(inputs[2]), "-o", str(out), "--faces", "300", "--report", str(report)]
    assert main(args + ["--json", str(tmp_path / "r.json")]) == 0
    for stem in ("fran", "grid"):
        assert {"surfaces.png", "radius_ratio.png", "report.html"} <= {p.name for p in (report / stem).iterdir()}
    records = json.loads((tmp_path / "r.json").read_text())
    assert sorted(r["report"] for r in records) == [str(report / s / "report.html") for s in ("fran", "grid")]
    capsys.readouterr()
    twin = inputs[2].with_suffix(".ply")
    write_mesh(twin, *read_mesh(inputs[2]))
    assert main(["batch", str(inputs[2]), str(twin), "-o", str(tmp_path / "o2"), "--report", str(tmp_path / "r2")]) == 1
    assert capsys.readouterr().err.strip() == (
        f"qcremesh: error: the reports of {tmp_path / 'o2' / 'grid.obj'} and {tmp_path / 'o2' / 'grid.ply'} would "
        f"both be written to {tmp_path / 'r2' / 'grid'}"
    )
    assert not (tmp_path / "o2").exists() and not (tmp_path / "r2").exists()


def test_batch_cli_errors_before_the_work(tmp_path, inputs, capsys):
    out = tmp_path / "out"
    (tmp_path / "other").mkdir()
    twin = tmp_path / "other" / "fran.ply"
    shutil.copy(inputs[0], twin)
    assert main(["batch", str(inputs[0]), str(twin), "-o", str(out)]) == 1
    assert capsys.readouterr().err.strip() == (
        f"qcremesh: error: {inputs[0]} and {twin} would both be written to {out / 'fran.ply'}"
    )
    assert main(["batch", str(inputs[0]), str(tmp_path / "none.obj"), "-o", str(out)]) == 1
    assert capsys.readouterr().err.strip() == f"qcremesh: error: {tmp_path / 'none.obj'}: no such file"
    mat = tmp_path / "h.mat"
    mat.write_bytes(b"")
    assert main(["batch", str(mat), "-o", str(out)]) == 1
    assert capsys.readouterr().err.strip().endswith("cannot write .mat files (the extension names the format: "
                                                    ".obj, .ply, .off, .stl, .vtk, .vtu, ...) (give --format)")
    assert main(["batch", str(inputs[0]), "-o", str(out), "--faces-ratio", "0"]) == 1
    assert capsys.readouterr().err.strip() == "qcremesh: error: --faces-ratio must be positive"
    assert main(["batch", str(inputs[0]), "-o", str(out), "--jobs", "0"]) == 1
    assert capsys.readouterr().err.strip() == "qcremesh: error: --jobs must be at least 1"
    assert main(["batch", str(inputs[0]), "-o", str(out), "--creases", "200"]) == 1
    assert capsys.readouterr().err.strip() == "qcremesh: error: --creases must be between 0 and 180 degrees"
    assert not out.exists()
    with pytest.raises(SystemExit):  # argparse: not both
        main(["batch", str(inputs[0]), "-o", str(out), "--faces", "100", "--faces-ratio", "0.5"])
    with pytest.raises(SystemExit):
        main(["batch", str(inputs[0]), "-o", str(out), "--edge-length", "0.01", "--faces-ratio", "0.5"])
    capsys.readouterr()
    assert main(["batch", str(inputs[0]), "-o", str(out), "--edge-length", "-1"]) == 1
    assert capsys.readouterr().err.strip() == "qcremesh: error: --edge-length must be positive"


def test_batch_cli_format(tmp_path, inputs, capsys):
    assert main(["batch", str(inputs[2]), "-o", str(tmp_path / "out"), "--format", "ply", "--faces", "200"]) == 0
    V, F = read_mesh(tmp_path / "out" / "grid.ply")
    assert abs(len(F) - 200) <= 10


def test_output_paths():
    assert output_paths(["a/x.obj", "b/y.off"], "o") == [Path("o/x.obj"), Path("o/y.off")]
    assert [p.name for p in output_paths(["a/x.obj"], "o", ".ply")] == ["x.ply"]
    with pytest.raises(ValueError, match="would both be written to"):
        output_paths(["a/x.obj", "b/x.obj"], "o")


def test_remesh_file_options(tmp_path, inputs):
    record = remesh_file(inputs[0], tmp_path / "f.obj", faces=1000, seed=1, levels=1)
    assert abs(record["faces"] - 1000) <= 50 and record["faces_in"] == 4224
    with pytest.raises(ValueError, match="^give one of faces, faces_ratio and edge_length$"):
        remesh_file(inputs[0], tmp_path / "g.obj", faces=10, faces_ratio=0.5)
    with pytest.raises(ValueError, match="^give one of faces, faces_ratio and edge_length$"):
        remesh_file(inputs[0], tmp_path / "g.obj", faces_ratio=0.5, edge_length=0.01)
    record = remesh_file(inputs[0], tmp_path / "e.obj", edge_length=0.0088)
    assert abs(record["faces"] - 1007) <= 50
    with pytest.raises(ValueError, match=r"^no per-vertex array 'h' to take the sizing from \(the mesh has: uv\)$"):
        remesh_file(inputs[0], tmp_path / "g.obj", sizing="h")
    assert not (tmp_path / "g.obj").exists()
    with pytest.raises(ValueError, match="^jobs must be at least 1$"):
        list(remesh_files([(inputs[0], tmp_path / "g.obj")], jobs=0))


def test_remesh_file_in_a_dask_bag(tmp_path, inputs):
    """remesh_file as the task of a Dask bag run in worker processes: the records and the
    files are those of a run in this process."""
    bag = pytest.importorskip("dask.bag")
    pairs = [(str(inputs[0]), str(tmp_path / "a.ply")), (str(inputs[2]), str(tmp_path / "b.obj"))]
    records = bag.from_sequence(pairs, npartitions=2).starmap(remesh_file, faces_ratio=0.5, seed=2)
    records = records.compute(scheduler="processes", num_workers=2)
    for (input, output), record in zip(pairs, records):
        here = remesh_file(input, tmp_path / ("here" + output[-4:]), faces_ratio=0.5, seed=2)
        assert {k: v for k, v in record.items() if k not in ("output", "seconds")} == {
            k: v for k, v in here.items() if k not in ("output", "seconds")
        }
        assert (tmp_path / output).read_bytes() == (tmp_path / ("here" + output[-4:])).read_bytes()
