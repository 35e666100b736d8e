"""Side-by-side benchmark of qcremesh against the tools users would pick instead.

    python benchmarks/run.py [--data DIR] [--out DIR] [--quick] [--parts ...] [--tools ...]

Eight parts; each tool runs in a process of its own (worker.py), kept for its jobs:

* param: disk parameterizations of every disk mesh (qcremesh's Algorithm 1, Tutte, libigl
  harmonic with arc-length boundary, libigl LSCM), with |mu| of the map disk -> surface,
  folded faces and time: the analogue of Table 1 of Choi, Gu & Lui.
* remesh: qcremesh.remesh, pymeshlab, pyacvd and gpytoolbox remesh_botsch at the input's
  face count and at half of it, on every mesh of the folder, measured by the project's
  quality module.
* ablation: qcremesh's methods uniform, base, subdivided and teichmuller (the paper's
  Fig. 7 and Figs. 18-20), with and without the relaxation, at the input's face count on
  foot, hand and human_face (the quick meshes in quick mode): what each stage adds.
* seeds: qcremesh on human_face (fran_cut in quick mode) with the CVT seeds 0-3 at half
  its face count: how much min q and the Hausdorff distance depend on the draw of
  landmarks.
* sizing: qcremesh with ``sizing="curvature"`` at both face counts on the eight disk
  meshes of ../shared/data (the quick meshes in quick mode), beside its default runs of
  the remesh part.
* snap: qcremesh with ``snap=0`` (no snapping onto the input vertices left far from the
  output) on the same meshes and face counts, beside its default runs.
* creases: every remesher and qcremesh with ``creases=60`` on synthetic CAD-like surfaces
  with creases (shapes.py: an open box, a closed cube, a plateau, a mesa; the open box only
  in quick mode) at both face counts.
* scaling: qcremesh's parameterization and remesh on one mesh subdivided 0, 1 and 2 times.

Writes results.md, results.json and PNG plots to --out; prints the tables.
"""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import io
import json
import os
import queue
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

import qcremesh
import report
import shapes
from qcremesh.mesh import topology
from worker import RESULT_MARK

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
MESH_SUFFIXES = {".obj", ".ply", ".off", ".stl", ".vtk", ".vtu", ".mat"}
QUICK_MESHES = ["fran_cut.ply", "venus.off"]
PARAM_TOOLS = ["qcremesh", "tutte", "igl_harmonic", "igl_lscm"]
REMESH_TOOLS = ["qcremesh", "pymeshlab", "pyacvd", "botsch"]
SCALING_LEVELS = [0, 1, 2]
ABLATION_MESHES = ["foot.off", "hand.ply", "human_face.obj"]
ABLATION_METHODS = ["uniform", "base", "subdivided", "teichmuller"]
ABLATION_RELAX = [0, 40]
SEED_MESHES = ["human_face.obj"]
SEEDS = [0, 1, 2, 3]
SIZING_MESHES = [
    "venus.off", "camel_b.obj", "fran_cut.ply", "foot.off", "hand.ply", "head_neck_cut.obj", "human_face.obj",
    "human_brain.ply",
]
CREASE_ANGLE = 60.0
QUICK_SHAPES = ["open_box"]


def parse_args(argv):
    p = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument(
        "--data", type=Path, default=ROOT.parent / "shared" / "data", help="folder of meshes"
    )
    p.add_argument(
        "--out", type=Path, help="results folder (default benchmarks/results, or results/quick)"
    )
    p.add_argument(
        "--quick",
        action="store_true",
        help=f"only {' and '.join(QUICK_MESHES)}, scaling on the first",
    )
    p.add_argument(
        "--parts",
        default="param,remesh,ablation,seeds,sizing,snap,creases,scaling",
        help="comma-separated subset of param,remesh,ablation,seeds,sizing,snap,creases,scaling",
    )
    p.add_argument("--tools", help="comma-separated subset of the tools (default: all)")
    p.add_argument(
        "--meshes", help="comma-separated file names in --data (default: all, or the quick ones)"
    )
    p.add_argument("--scaling-mesh", help="mesh subdivided for the scaling part (default hand.ply)")
    p.add_argument("--runs", type=int, default=3, help="timed runs per job at most")
    p.add_argument(
        "--budget", type=float, default=5.0, help="stop repeating once the runs add up to this (s)"
    )
    p.add_argument("--timeout", type=float, default=600.0, help="per job (s)")
    args = p.parse_args(argv)
    args.data = args.data.resolve()  # the workers run in benchmarks/
    args.parts = args.parts.split(",")
    args.tools = args.tools.split(",") if args.tools else None
    if args.out is None:
        args.out = HERE / "results" / ("quick" if args.quick else "")
    return args


def read_quietly(path):
    """qcremesh.read_mesh without the messages meshio prints on files it cannot read."""
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        return qcremesh.read_mesh(path)


def piece_genera(F, n):
    """Genus of each connected piece of the faces kept once (None for a piece that is not
    a manifold surface), as qcremesh's remesh takes them: none None, or no remesh."""
    F = np.delete(F, topology.duplicate_faces(F), axis=0)
    count, label = topology.connected_components(F, n)
    return [topology.genus(F[label == k]) for k in range(count)]


def same_points(W, V):
    """Whether two vertex arrays are the same points to 1e-6 of the bounding-box diagonal
    (one a copy in single precision: pyvista reads fran_cut.vtk's "float" points so)."""
    return W.shape == V.shape and np.abs(W - V).max() <= 1e-6 * np.linalg.norm(np.ptp(W, axis=0))


def inventory(folder, names):
    """Readable meshes of the folder, each once (a file with the same faces as an earlier
    one and the same vertices, to single precision, is skipped), whether each is a disk,
    and the genus of each piece. Returns (meshes, skipped)."""
    # MATLAB files last: a mesh that is also there in a common format goes by that name.
    if names:
        paths = [folder / name for name in names]
    else:
        paths = sorted(folder.iterdir(), key=lambda p: (p.suffix == ".mat", p.name))
    meshes, skipped, seen = [], [], {}
    for path in paths:
        if path.suffix.lower() not in MESH_SUFFIXES:
            continue
        try:
            V, F = read_quietly(path)
        except Exception as error:
            skipped.append({"mesh": path.name, "reason": f"cannot read: {error}"})
            continue
        digest = hashlib.sha1(F.tobytes()).hexdigest()
        twin = next(((W, name) for W, name in seen.get(digest, []) if same_points(W, V)), None)
        if twin is not None:
            W, name = twin
            reason = (
                f"same vertices and faces as {name}" if np.array_equal(W, V)
                else f"same faces as {name}, its vertices in single precision"
            )
            skipped.append({"mesh": path.name, "reason": reason})
            continue
        seen.setdefault(digest, []).append((V, path.name))
        try:
            qcremesh.check_disk(V, F)
            not_disk = None
        except qcremesh.MeshError as error:
            not_disk = str(error)
        meshes.append(
            {
                "mesh": path.name,
                "path": str(path),
                "vertices": len(V),
                "faces": len(F),
                "not_disk": not_disk,
                "genus": piece_genera(F, len(V)),
            }
        )
    meshes.sort(key=lambda m: m["faces"])
    return meshes, skipped


class Workers:
    """worker.py processes, one per tool and kind of job, each kept for all the jobs of
    its tool: the jobs of the tools still run one at a time, in the order given
    (interleaved across tools, so that a change of the host's load affects them alike),
    without a start, imports and warm-up of the tool per job (1-1.5 s each). A worker
    that dies or overruns the timeout is stopped, its job reported as failed, and the
    next job of its tool starts a new one."""

    def __init__(self, timeout):
        self.timeout = timeout
        self.running = {}  # key -> (process, queue of its output lines, its stderr file)

    def _start(self, key):
        err = tempfile.TemporaryFile(mode="w+")
        proc = subprocess.Popen(
            [sys.executable, str(HERE / "worker.py")],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=err,
            text=True,
            cwd=HERE,
        )
        lines = queue.Queue()
        threading.Thread(target=_pump, args=(proc.stdout, lines), daemon=True).start()
        self.running[key] = (proc, lines, err)

    def run(self, key, spec, fresh=False):
        """The row of job ``spec`` run by the worker of ``key``, or the failure; with
        ``fresh``, in a new process of its own (for a peak memory of this job alone)."""
        if fresh:
            self.stop(key)
        if key not in self.running:
            self._start(key)
        proc, lines, err = self.running[key]
        with contextlib.suppress(OSError):  # a worker that died is reported below
            proc.stdin.write(json.dumps(spec) + "\n")
            proc.stdin.flush()
        deadline = time.monotonic() + self.timeout
        while True:
            try:
                line = lines.get(timeout=max(deadline - time.monotonic(), 0.0))
            except queue.Empty:
                failure = f"timed out after {self.timeout:.0f} s"
                break
            if line is None:
                err.seek(0)
                last = (err.read().strip().splitlines() or ["no output"])[-1]
                failure = f"worker exited with status {proc.wait()}: {last}"
                break
            if line.startswith(RESULT_MARK):
                row = json.loads(line[len(RESULT_MARK) :])
                if fresh:
                    self.stop(key)
                return row
        self.stop(key, kill=True)
        return {"status": "failed", "reason": failure}

    def stop(self, key, kill=False):
        """End the worker of ``key``, if there is one: at the end of its input, or
        ``kill`` it."""
        if key in self.running:
            proc, _, err = self.running.pop(key)
            if kill:
                proc.kill()
            with contextlib.suppress(OSError):
                proc.stdin.close()
            proc.wait()
            err.close()

    def close(self):
        for key in list(self.running):
            self.stop(key)


def _pump(stream, lines):
    """Lines of a worker's output into ``lines``, then None at its end."""
    for line in stream:
        lines.put(line)
    lines.put(None)


def run_job(job, args, runs=None, fresh=False):
    """Run one job in the worker of its tool (at most ``runs`` timed runs, ``--runs`` by
    default; ``fresh``: in a new process); the row it reports, or the failure."""
    spec = dict(job, runs=runs or args.runs, budget=args.budget)
    t0 = time.perf_counter()
    row = args.workers.run((job["kind"], job["tool"]), spec, fresh)
    row.update(job)
    row["wall_s"] = time.perf_counter() - t0
    print(report.progress_line(row), file=sys.stderr, flush=True)
    return row


def selected(tools, args):
    return [t for t in tools if args.tools is None or t in args.tools]


def parameterization_jobs(meshes, args):
    for m in meshes:
        if m["not_disk"] is None:
            for tool in selected(PARAM_TOOLS, args):
                yield {
                    "kind": "param",
                    "tool": tool,
                    "mesh": m["path"],
                    "name": m["mesh"],
                    "faces_in": m["faces"],
                }


def remesh_job(m, tool, half, variant=None):
    """The job of remeshing mesh ``m`` with ``tool`` to its face count, or half of it."""
    job = {
        "kind": "remesh",
        "tool": tool,
        "mesh": m["path"],
        "name": m["mesh"],
        "faces_in": m["faces"],
        "half": half,
        "faces": m["faces"] // 2 if half else m["faces"],
    }
    if variant is not None:
        job["variant"] = variant
    return job


def previous_lengths(out):
    """The calibrated edge lengths of the last run written to ``out``, by (tool, mesh,
    input faces, wanted faces): where the mesh and the tool are the same, the calibration
    starts there and usually ends with its first run (the worker checks the face count
    anyway). Empty when there is no readable earlier run."""
    try:
        rows = json.loads((out / "results.json").read_text()).get("remesh", [])
    except (OSError, ValueError):
        return {}
    return {
        (r["tool"], r["name"], r["faces_in"], r["faces"]): r["param"]
        for r in rows
        if r.get("status") == "ok" and r.get("calibration_runs")
    }


def remesh_rows(meshes, args):
    """Every remesher on every mesh at its face count and at half; qcremesh remeshes
    manifold surfaces only (after dropping repeated faces), so the other meshes get a
    skipped row with the reason instead of a job."""
    rows = []
    lengths = previous_lengths(args.out)
    for m in meshes:
        for half in (False, True):
            for tool in selected(REMESH_TOOLS, args):
                job = remesh_job(m, tool, half)
                start = lengths.get((tool, m["mesh"], m["faces"], job["faces"]))
                if start is not None:
                    job["start"] = start
                if tool == "qcremesh" and None in m["genus"]:
                    reason = f"not manifold surfaces: {m['not_disk']}"
                    rows.append(dict(job, status="skipped", reason=reason))
                else:
                    rows.append(run_job(job, args))
    return rows


def variant_rows(meshes, names, half, variants, args):
    """qcremesh with each of ``variants`` (keyword arguments of remesh) on the disk meshes
    among ``names``, one timed run each (the quality is the point)."""
    if not selected(["qcremesh"], args):
        return []
    return [
        run_job(remesh_job(m, "qcremesh", half, variant), args, runs=1)
        for m in meshes
        if m["not_disk"] is None and m["mesh"] in names
        for variant in variants
    ]


def ablation_rows(meshes, args):
    """qcremesh's ablations with and without the relaxation, at the input's face count."""
    names = QUICK_MESHES if args.quick else ABLATION_MESHES
    variants = [{"method": method, "relax": relax} for relax in ABLATION_RELAX for method in ABLATION_METHODS]
    return variant_rows(meshes, names, False, variants, args)


def seed_rows(meshes, args):
    """qcremesh with each of SEEDS at half the input's face count (where the Hausdorff
    distance on human_face spreads most)."""
    names = QUICK_MESHES[:1] if args.quick else SEED_MESHES
    variants = [{"method": "teichmuller", "relax": 40, "seed": seed} for seed in SEEDS]
    return variant_rows(meshes, names, True, variants, args)


def sizing_rows(meshes, args):
    """qcremesh with the curvature sizing at the input's face count and at half of it."""
    names = QUICK_MESHES if args.quick else SIZING_MESHES
    variant = {"method": "teichmuller", "relax": 40, "sizing": "curvature"}
    return [row for half in (False, True) for row in variant_rows(meshes, names, half, [variant], args)]


def snap_rows(meshes, args):
    """qcremesh without the snapping at the input's face count and at half of it."""
    names = QUICK_MESHES if args.quick else SIZING_MESHES
    variant = {"method": "teichmuller", "relax": 40, "snap": 0.0}
    return [row for half in (False, True) for row in variant_rows(meshes, names, half, [variant], args)]


def crease_rows(args):
    """Every remesher, and qcremesh with ``creases=CREASE_ANGLE``, on the synthetic
    surfaces of shapes.py (written as OBJ files to a temporary folder for the workers) at
    their face count and at half of it."""
    rows = []
    names = QUICK_SHAPES if args.quick else list(shapes.SHAPES)
    variant = {"method": "teichmuller", "relax": 40, "creases": CREASE_ANGLE}
    with tempfile.TemporaryDirectory() as folder:
        for name in names:
            V, F = shapes.SHAPES[name]()
            path = Path(folder) / f"{name}.obj"
            qcremesh.write_mesh(path, V, F)
            m = {"mesh": name, "path": str(path), "faces": len(F)}
            for half in (False, True):
                for tool in selected(REMESH_TOOLS, args):
                    rows.append(run_job(remesh_job(m, tool, half), args))
                if selected(["qcremesh"], args):
                    rows.append(run_job(remesh_job(m, "qcremesh", half, variant), args))
    return rows


def scaling_rows(path, args):
    """qcremesh on the mesh subdivided 0, 1, 2 times; the remesh at the subdivided face
    count, not measured (the remesh part does that). A tool skipped at level 0 is not
    tried further."""
    rows = []
    if not selected(["qcremesh"], args):
        return rows
    for kind in ("param", "remesh"):
        for level in SCALING_LEVELS:
            job = {"kind": kind, "tool": "qcremesh", "mesh": str(path), "name": path.name}
            # The remesh part measures the output; here only time and memory count, the
            # peak memory of a process that ran nothing else.
            row = run_job(dict(job, subdivide=level, measure=kind == "param"), args, fresh=True)
            rows.append(row)
            if row["status"] == "skipped":
                break
    return rows


def main(argv=None):
    args = parse_args(argv)
    names = args.meshes.split(",") if args.meshes else None
    if args.quick and names is None:
        names = [n for n in QUICK_MESHES if (args.data / n).is_file()]
    if not args.data.is_dir() or names == []:
        sys.exit(f"run.py: no meshes to benchmark in {args.data}")
    meshes, skipped = inventory(args.data, names)
    scaling_name = args.scaling_mesh or (names[0] if args.quick else "hand.ply")

    args.workers = Workers(args.timeout)
    t0 = time.perf_counter()
    results = {
        "machine": report.machine(),
        "settings": report.settings(args),
        "meshes": meshes,
        "skipped_meshes": skipped,
    }
    if "param" in args.parts:
        results["param"] = [run_job(job, args) for job in parameterization_jobs(meshes, args)]
    if "remesh" in args.parts:
        results["remesh"] = remesh_rows(meshes, args)
    if "ablation" in args.parts:
        results["ablation"] = ablation_rows(meshes, args)
    if "seeds" in args.parts:
        results["seeds"] = seed_rows(meshes, args)
    if "sizing" in args.parts:
        results["sizing"] = sizing_rows(meshes, args)
    if "snap" in args.parts:
        results["snap"] = snap_rows(meshes, args)
    if "creases" in args.parts:
        results["creases"] = crease_rows(args)
    if "scaling" in args.parts and (args.data / scaling_name).is_file():
        results["scaling"] = scaling_rows(args.data / scaling_name, args)
        results["scaling_fit"] = report.fit_exponents(results["scaling"])
    args.workers.close()
    results["total_s"] = time.perf_counter() - t0
    results["machine"]["load_average_end"] = os.getloadavg()[0]

    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "results.json").write_text(json.dumps(results, indent=1) + "\n")
    markdown = report.markdown(results)
    (args.out / "results.md").write_text(markdown)
    report.plots(results, args.out)
    print(markdown)


if __name__ == "__main__":
    main()
