"""Runs jobs of one tool, one at a time, in a process kept for that tool, and prints one
line of JSON per job.

    python worker.py < jobs    # one JSON job per line, e.g.
    {"kind": "param" | "remesh", "tool": ..., "mesh": PATH, "subdivide": 0, "faces": N,
     "runs": 3, "budget": 5}

Each result line starts with RESULT_MARK (a tool may print to standard output too). A
remesh job with ``"variant": {"method": ..., "relax": ...}`` runs that ablation of
qcremesh (``tools.qcremesh_variant``).

Remesh only: ``"start"`` is a first edge length for the tools calibrated by length;
``faces`` defaults to the face count of the (subdivided) input, and with
``"measure": false`` the output is not measured (time and memory only). Loading
and subdividing the mesh are not timed. The tool first runs once, untimed, on a small
mesh (:func:`warm_up`), then up to ``runs`` times, fewer when the runs so far add up to
``budget`` seconds, at least once; the wall time of each call is recorded. Peak memory
is the peak resident set of this process from the start of the job (the kernel's mark
is reset then; it includes Python, the libraries and the loaded mesh), read before
anything is measured. The measures then come from the same code for every tool:
``qcremesh.beltrami_coefficient`` for parameterizations and
``qcremesh.geometry.quality.mesh_quality`` for remeshers.
"""

from __future__ import annotations

import json
import sys
import time

import numpy as np

import qcremesh
import tools
from qcremesh.geometry.operators import signed_doublearea
from qcremesh.geometry.quality import mesh_quality
from qcremesh.mesh.subdivide import upsample
from qcremesh.mesh.topology import boundary_loop

# A calibrated face count within this fraction of the request is accepted.
FACE_TOLERANCE = 0.02
MAX_CALIBRATION_RUNS = 4


RESULT_MARK = "RESULT "


def memory_mb(field):
    """A memory figure of this process from /proc/self/status: VmRSS (resident now) or
    VmHWM (peak resident since the start or the last :func:`reset_peak_memory`)."""
    with open("/proc/self/status") as f:
        kb = next(line.split()[1] for line in f if line.startswith(field + ":"))
    return int(kb) / 1024


def reset_peak_memory():
    """Start VmHWM afresh from the present resident set (Linux: 5 written to
    /proc/self/clear_refs), so that a job's peak is not that of an earlier job."""
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")


def timed(call, *args):
    t0 = time.perf_counter()
    out = call(*args)
    return out, time.perf_counter() - t0


def repeat(call, args, times, runs, budget):
    """Call until there are ``runs`` times or they add up to ``budget``; the last output."""
    out = None
    while len(times) < runs and sum(times) < budget:
        out, t = timed(call, *args)
        times.append(t)
    return out


def small_disk(k=12):
    """A k x k grid of the unit square, two triangles per cell, bent into a bowl: the
    mesh of the warm-up run."""
    x, y = np.meshgrid(np.linspace(0.0, 1.0, k + 1), np.linspace(0.0, 1.0, k + 1))
    V = np.column_stack([x.ravel(), y.ravel(), 0.3 * ((x - 0.5) ** 2 + (y - 0.5) ** 2).ravel()])
    i, j = np.meshgrid(np.arange(k), np.arange(k))
    a = (j * (k + 1) + i).ravel()
    F = np.concatenate([np.column_stack([a, a + 1, a + k + 2]), np.column_stack([a, a + k + 2, a + k + 1])])
    return V, F


def warm_up(call):
    """Run ``call(V, F)`` once on :func:`small_disk`, untimed, so that no timed run pays
    for what a process does once: importing the tool's package, loading compiled code
    (Numba's cache, MKL), first allocations. A tool that cannot take the small mesh is
    left cold (its failure, if any, shows in the timed runs); one that is not installed
    is reported as such."""
    try:
        call(*small_disk())
    except tools.Unavailable:
        raise
    except Exception:  # a warm-up only: the timed runs report failures
        pass


def time_summary(times):
    return {
        "median": float(np.median(times)),
        "min": float(min(times)),
        "max": float(max(times)),
        "runs": len(times),
    }


def median_stages(stages):
    return {key: float(np.median([s[key] for s in stages])) for key in stages[0]}


def parameterization_measures(V, F, uv):
    """|mu| of the map disk -> surface and folded faces, relative to the orientation of
    the majority of the faces (a map may come out mirrored; it is mirrored back)."""
    area = signed_doublearea(uv, F)
    mirrored = bool(np.count_nonzero(area < 0) > np.count_nonzero(area > 0))
    if mirrored:
        uv = uv * np.array([-1.0, 1.0])
        area = -area
    mu = np.abs(qcremesh.beltrami_coefficient(uv, F, V))
    radius = np.hypot(*uv[boundary_loop(F)].T)
    return {
        "mu_mean": float(mu.mean()),
        "mu_median": float(np.median(mu)),
        "mu_max": float(mu.max()),
        "folded": int(np.count_nonzero(area <= 0)),
        "mirrored": mirrored,
        "disk": bool(np.max(np.abs(radius - 1.0)) < 1e-6),
    }


def run_parameterization(job, V, F):
    call = tools.PARAMETERIZATIONS[job["tool"]]
    stages = []

    def run():
        uv, stage = call(V, F)
        stages.append(stage)
        return uv

    warm_up(call)
    times = []
    uv = repeat(run, (), times, job["runs"], job["budget"])
    peak = memory_mb("VmHWM")
    result = {
        "time": time_summary(times),
        "peak_rss_mb": peak,
        **parameterization_measures(V, F, uv),
    }
    if stages[0]:
        result["stages"] = median_stages(stages)
    return result


def run_remesher(job, V, F):
    """Remesh to ``job["faces"]`` faces. A tool that takes an edge length is run with
    ``job["start"]`` (the length calibrated in the previous run) or else the length of
    equilateral triangles of that count, then corrected by sqrt(faces / wanted) until
    within FACE_TOLERANCE; the run with the final length is the first timed run."""
    if "variant" in job:
        tool = tools.qcremesh_variant(**job["variant"])
    else:
        tool = tools.REMESHERS[job["tool"]]
    wanted = job.get("faces", len(F))
    stages = []

    def run(param):
        out = tool.run(V, F, param)
        stages.append(out[2])
        return out

    warm_up(lambda V0, F0: tool.run(V0, F0, tool.initial(V0, F0, len(F0))))
    param = job.get("start") or tool.initial(V, F, wanted)
    calibration = 0
    while True:
        stages.clear()
        out, t = timed(run, param)
        calibration += 1
        faces = len(out[1])
        if (
            not tool.by_length
            or abs(faces - wanted) <= FACE_TOLERANCE * wanted
            or calibration == MAX_CALIBRATION_RUNS
        ):
            break
        param *= np.sqrt(faces / wanted)
    times = [t]
    U, G, _ = repeat(run, (param,), times, job["runs"], job["budget"]) or out
    peak = memory_mb("VmHWM")
    result = {
        "time": time_summary(times),
        "peak_rss_mb": peak,
        "param": param,
        "calibration_runs": calibration if tool.by_length else 0,
        "setting": tool.setting,
        "faces_out": len(G),
    }
    if job.get("measure", True):
        U = np.asarray(U, dtype=np.float64)
        result["quality"] = mesh_quality(U, np.asarray(G, dtype=np.int64), reference=(V, F))
    if stages[0]:
        result["stages"] = median_stages(stages)
    return result


def job_result(job):
    """The result row of one job."""
    reset_peak_memory()
    result = {}
    try:
        V, F = qcremesh.read_mesh(job["mesh"])
        V, F = upsample(V, F, job.get("subdivide", 0))
        result.update(vertices_in=len(V), faces_in=len(F), load_rss_mb=memory_mb("VmRSS"))
        if job["kind"] == "param":
            result.update(run_parameterization(job, V, F))
        else:
            result.update(run_remesher(job, V, F))
        result["status"] = "ok"
    except tools.Unavailable as reason:
        result.update(status="skipped", reason=str(reason))
    except Exception as error:  # a tool that cannot take this mesh: reported, not fatal
        result.update(status="failed", reason=f"{type(error).__name__}: {error}")
    return result


def main():
    for line in sys.stdin:
        if line.strip():
            print(RESULT_MARK + json.dumps(job_result(json.loads(line))), flush=True)


if __name__ == "__main__":
    main()
