"""The benchmark harness (benchmarks/run.py) runs end to end, so it cannot rot.

Only the parameterization part, with qcremesh and Tutte: the other tools are installed in
the benchmark venv of `make bench`, not in the test venv. The bundled fran_cut.ply keeps
the test independent of ../shared/data.
"""

import json
import subprocess
import sys

from conftest import DATA, ROOT


def run_quick(out, parts, tools):
    """benchmarks/run.py --quick on the bundled meshes: its results.json, and what it
    printed."""
    command = [sys.executable, str(ROOT / "benchmarks" / "run.py"), "--quick", "--data", str(DATA)]
    command += ["--out", str(out), "--parts", parts, "--tools", tools]
    proc = subprocess.run(command, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    return json.loads((out / "results.json").read_text()), proc.stdout


def test_quick_parameterization_benchmark(tmp_path):
    results, stdout = run_quick(tmp_path, "param", "qcremesh,tutte")
    rows = {r["tool"]: r for r in results["param"]}
    assert set(rows) == {"qcremesh", "tutte"}
    for r in rows.values():
        assert r["status"] == "ok" and r["name"] == "fran_cut.ply" and r["faces_in"] == 4224
        assert r["folded"] == 0 and r["disk"]
        assert (
            1 <= r["time"]["runs"] <= 3
            and r["time"]["min"] <= r["time"]["median"] <= r["time"]["max"]
        )
        assert r["peak_rss_mb"] > 0
    assert rows["qcremesh"]["mu_mean"] < 0.05 < rows["tutte"]["mu_mean"]
    assert {"tutte", "lbs"} <= set(rows["qcremesh"]["stages"])
    assert results["machine"]["cpu"] and results["machine"]["packages"]["qcremesh"]

    markdown = (tmp_path / "results.md").read_text()
    assert "## Machine" in markdown and "| fran_cut.ply | 4,224 | qcremesh |" in markdown
    assert stdout == markdown + "\n"
    assert (tmp_path / "time_vs_faces.png").stat().st_size > 0


def test_quick_seed_benchmark(tmp_path):
    """The seeds part: qcremesh with the CVT seeds 0-3 on fran_cut at half its face
    count, with the number of landmark draws each run needed."""
    rows = run_quick(tmp_path, "seeds", "qcremesh")[0]["seeds"]
    assert [(r["half"], r["variant"]["seed"]) for r in rows] == [(True, s) for s in range(4)]
    for r in rows:
        assert r["status"] == "ok" and r["stages"]["draws"] >= 1
        assert r["quality"]["q_min"] >= 0.3
    assert "## Seeds" in (tmp_path / "results.md").read_text()


def test_calibration_starts_from_previous_run(tmp_path):
    """The edge lengths calibrated in the last run are the next run's first guesses, per
    tool, mesh and face count; rows that failed or were not calibrated give none."""
    sys.path.insert(0, str(ROOT / "benchmarks"))
    try:
        import run
    finally:
        sys.path.pop(0)
    assert run.previous_lengths(tmp_path) == {}
    (tmp_path / "results.json").write_text("{not json")
    assert run.previous_lengths(tmp_path) == {}
    base = {"name": "foot.off", "faces_in": 19974, "faces": 9987}
    rows = [
        dict(base, tool="pymeshlab", status="ok", calibration_runs=2, param=1.25),
        dict(base, tool="botsch", status="failed"),
        dict(base, tool="qcremesh", status="ok", calibration_runs=0, param=9987),
    ]
    (tmp_path / "results.json").write_text(json.dumps({"remesh": rows}))
    assert run.previous_lengths(tmp_path) == {("pymeshlab", "foot.off", 19974, 9987): 1.25}


def test_quick_sizing_benchmark(tmp_path):
    """The sizing part: qcremesh with the curvature sizing on fran_cut at both face
    counts, beside the default run of the remesh part."""
    results = run_quick(tmp_path, "remesh,sizing", "qcremesh")[0]
    rows = results["sizing"]
    assert [(r["half"], r["variant"]["sizing"]) for r in rows] == [(False, "curvature"), (True, "curvature")]
    assert all(r["status"] == "ok" and r["quality"]["q_min"] >= 0.3 for r in rows)
    markdown = (tmp_path / "results.md").read_text()
    row = next(line for line in markdown.splitlines() if line.startswith("| fran_cut.ply | 4,224 |") and " / " in line)
    default = next(r["quality"] for r in results["remesh"] if not r["half"])
    assert row.endswith(f" / {100 * default['hausdorff']:.2f} |")
